#!/usr/bin/env python3
"""Runs the 3D Hertz sphere on a rigid wall (doc/reference.md §3.8, doc/contact.md §9.6) on a
list of meshes and prints F_max and t_c against quasi-static Hertz, the rebound velocity and
the momentum balance of each run.

    scripts/hertz_sphere.py --ictus build/bin/ictus --work /tmp/hs \\
        --mesh hex20:4:1.3 --mesh hex20:6:1.4 [--v 0.1] [--penalty 1e6]

A mesh is kind:n:grade of scripts/mesh/quarter_ball.py (kind hex8, hex20 or hex27; n
elements along an inner-block edge; grade the growth ratio away from the contact point).
The decks and results files are left in --work.
"""
import argparse
import os
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
E, NU, RHO, R = 1000.0, 0.3, 1.0, 1.0


def hertz(v):
    """Quasi-static Hertz impact of the whole sphere: F_max of the quarter model and t_c."""
    es = E / (1 - NU**2)
    m = 4.0 * np.pi * R**3 * RHO / 3.0
    delta = (15.0 * m * v**2 / (16.0 * es * np.sqrt(R)))**0.4
    return 4.0 / 3.0 * es * np.sqrt(R) * delta**1.5 / 4.0, 2.94328 * delta / v


def run(a, spec):
    kind, n, grade = spec.split(":")
    name = f"{kind}_n{n}_g{grade}_v{a.v:g}_p{a.penalty:g}"
    deck = os.path.join(a.work, name + ".inp")
    out = os.path.join(a.work, name + ".h5")
    with open(deck, "w") as f:
        subprocess.run([sys.executable, os.path.join(HERE, "mesh", "quarter_ball.py"), "--kind",
                        kind, "--n", n, "--grade", grade, "--v", repr(a.v), "--penalty",
                        repr(a.penalty), "--t-end", repr(a.t_end or 1.25 * hertz(a.v)[1]),
                        "--field-every", "0"], stdout=f, check=True)
    subprocess.run([a.ictus, deck, "-o", out], stdout=subprocess.DEVNULL, check=True)
    r = h5py.File(out, "r")
    t = r["history/time"][()]
    fz = r["history/contact/wall/force_first"][:, 2]
    dt = r["history/dt"][()]
    on = np.nonzero(fz > 0)[0]
    mass = r["model/mass"][()]
    last = sorted(r["fields"].keys())[-1]
    vz = float((mass * r[f"fields/{last}/velocity"][:, 2]).sum() / mass.sum())
    fh, th = hertz(a.v)
    tc = t[on[-1]] - t[on[0]]
    dmom = abs(mass.sum() * (vz + a.v) - (fz * dt).sum()) / (mass.sum() * a.v)
    print(f"| {kind} n = {n}, grade {grade} | {len(r['model/element_partition'])} | "
          f"{fz.max():.4f} ({fz.max() / fh - 1:+.1%}) | {tc:.4f} ({tc / th - 1:+.1%}) | "
          f"{vz / a.v:.4f} | {dmom:.1e} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ictus", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--mesh", action="append", required=True, help="kind:n:grade")
    ap.add_argument("--v", type=float, default=0.1)
    ap.add_argument("--penalty", type=float, default=1e6)
    ap.add_argument("--t-end", type=float, default=0.0, help="0: 1.25 t_c of Hertz")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    fh, th = hertz(a.v)
    print(f"v = {a.v:g}, penalty {a.penalty:g}; quasi-static Hertz: F_max {fh:.5f} (quarter), "
          f"t_c {th:.5f}\n")
    print("| mesh | elements | F_max | t_c | rebound / v | momentum vs impulse |")
    print("|---|---|---|---|---|---|")
    for spec in a.mesh:
        run(a, spec)


if __name__ == "__main__":
    main()
