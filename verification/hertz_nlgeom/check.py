#!/usr/bin/env python3
"""The small-strain limit of finite strain: the dynamic Hertz problem with NLGEOM=YES approaches
the linear run as the impact velocity falls (doc/theory.md §4).

The Hertz deck of the founding paper (scripts/mesh/hertz.py --kind iga --mass HRZ
--subdivide 8: two NURBS half-cylinders R = 4, E = 1000, nu = 0.2, rho = 1, penalty contact,
dt = 5e-4) at relative velocities V = 0.4, 0.04 and 0.004 (each body at V/2), run to
0.9 (4/V)^(1/5) (the Hertz contact time grows as V^(-1/5)), once in small strain and once with
*STEP, NLGEOM=YES. Finite and small strain differ by terms of the order of the strains and
rotations, which fall with V, on a force that itself grows with V. Expected:
- the difference of the peak contact forces falls at least linearly with V: each tenfold
  smaller V divides it by at least 10;
- its relative size falls too, and is below 0.2 % at V = 0.004.
"""
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
import vcheck  # noqa: E402

HERTZ = os.path.join(HERE, "..", "..", "scripts", "mesh", "hertz.py")


def deck(v, nlgeom):
    base = subprocess.run([sys.executable, HERTZ, "--kind", "iga", "--mass", "HRZ",
                           "--subdivide", "8"], check=True, capture_output=True,
                          text=True).stdout
    t_end = 0.9 * (4.0 / v) ** 0.2
    out = []
    for line in base.splitlines():
        if line == "UPPER, 2, -2.0":
            line = f"UPPER, 2, {-v / 2!r}"
        elif line == "LOWER, 2, 2.0":
            line = f"LOWER, 2, {v / 2!r}"
        elif line == "*STEP" and nlgeom:
            line = "*STEP, NLGEOM=YES"
        elif line == "0.0005, 0.9":
            line = f"0.0005, {t_end!r}"
        out.append(line)
    text = "\n".join(out) + "\n"
    assert f"{v / 2!r}" in text and f"{t_end!r}" in text
    return text


def peak(args, name, text):
    path = os.path.join(args.work, name + ".inp")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(args.work, name + ".h5")
    vcheck.run_ictus(args, path, out)
    return np.abs(vcheck.Results(out).history("contact/hertz/force_first")[:, 1]).max()


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("hertz_nlgeom")
    diff, rel = {}, {}
    for v in (0.4, 0.04, 0.004):
        lin = peak(args, f"v{v}_small", deck(v, False))
        fin = peak(args, f"v{v}_nlgeom", deck(v, True))
        diff[v], rel[v] = abs(fin - lin), abs(fin - lin) / lin
        print(f"  V = {v}: peak force small strain {lin:.6g}, NLGEOM {fin:.6g}, "
              f"difference {diff[v]:.3g} ({100 * rel[v]:.3g} %)")
    chk.below(diff[0.04] / diff[0.4], 0.1, "V 0.4 -> 0.04: the peak-force difference falls at "
              "least tenfold")
    chk.below(diff[0.004] / diff[0.04], 0.1, "V 0.04 -> 0.004: the peak-force difference falls "
              "at least tenfold")
    chk.true(rel[0.4] > rel[0.04] > rel[0.004], "the relative difference falls with V")
    chk.below(rel[0.004], 2e-3, "V = 0.004: NLGEOM within 0.2 % of small strain")
    chk.finish()


if __name__ == "__main__":
    main()
