#!/usr/bin/env python3
"""Short striker against a longer bar at rest (doc/reference.md §3.2, matched impedance): contact
lasts exactly 2 L1/c at the interface stress rho c v0/2, the striker ends at rest, the
target carries all the momentum (mean velocity v0 L1/L2) and the striker never touches it
again before the target's far-end reflection returns (t = 2 L2/c).

Striker [-L1, 0] at +v0 = 1, target [0, L2] at rest, L1 = 5, L2 = 2 L1 = 10, H = 0.05,
E = 1000, rho = 1, plane stress nu = 0, same Q8 mesh size h = 0.05 (HRZ), TWO HALF PASS
eps_hat = eps h / E = 10, automatic time step (r <= 1/2). Run to t = 1.5 L2/c < 2 L2/c.
Gates: duration 3 %, plateau (middle 80 %) 3 %, impulse rho A L1 v0 (all the striker's
momentum) 1 %, final striker |mean v| < 5 % v0, target mean velocity v0 L1/L2 within 5 %.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402
import impact  # noqa: E402
from impact import C, RHO  # noqa: E402

L1, L2, H, V0, HX, EPS_HAT = 5.0, 10.0, 0.05, 1.0, 0.05, 10.0


def deck():
    eps = EPS_HAT * impact.E / HX
    a, nxt, ne = impact.q8_bar("A", -L1, L1, H, int(round(L1 / HX)))
    b, _, _ = impact.q8_bar("B", 0.0, L2, H, int(round(L2 / HX)), first_node=nxt,
                            first_element=ne)
    return (impact.header("striker L1 against a bar L2 = 2 L1 at rest") + a + b
            + f"*INITIAL CONDITIONS, TYPE=VELOCITY\nA, 1, {V0!r}\n"
            + f"*CONTACT PAIR, NAME=HIT, PENALTY={eps:.17g}\nA_RIGHT, B_LEFT\n"
            + "*MASS, TYPE=HRZ\n" + impact.step(1.5 * L2 / C, field_every=50))


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("contact_striker")
    path = os.path.join(args.work, "striker.inp")
    with open(path, "w") as fd:
        fd.write(deck())
    out = path.replace(".inp", ".h5")
    _, log = vcheck.run_ictus(args, path, out)
    r = vcheck.Results(out)
    dt = float(r.history("dt")[0])
    chk.below(max(impact.ratios(log)), 0.5, f"printed ratio r (dt = {dt:.4g})")
    t = r.history("time")
    p = impact.pulse(t, -r.history("contact/hit/force_first")[:, 0], dt)
    chk.close(p["duration"], 2 * L1 / C, 0.03, "contact duration = 2 L1/c")
    chk.close(p["plateau"], 0.5 * RHO * C * H * V0, 0.03, "plateau force = rho c A v0/2")
    chk.close(p["impulse"], RHO * H * L1 * V0, 0.01, "impulse = rho A L1 v0")
    chk.true(p["nbursts"] == 1, f"one contact period only ({p['nbursts']})")
    x = r.model("coordinates")[:, 0]
    m = r.model("mass")
    v = r.field(r.field_steps()[-1], "velocity")[:, 0]
    s = x < 0.0
    vs = float(np.sum(m[s] * v[s]) / np.sum(m[s]))
    vt = float(np.sum(m[~s] * v[~s]) / np.sum(m[~s]))
    chk.below(abs(vs) / V0, 0.05, "striker at rest at the end: |mean v| / v0")
    chk.close(vt, V0 * L1 / L2, 0.05, "target mean velocity = v0 L1/L2")
    print(f"  duration {p['duration'] / (2 * L1 / C):.5f}, plateau "
          f"{p['plateau'] / (0.5 * RHO * C * H * V0):.5f}, impulse "
          f"{p['impulse'] / (RHO * H * L1 * V0):.5f} (ratios to exact); striker v/v0 {vs:.5f},"
          f" target v/(v0 L1/L2) {vt / (V0 * L1 / L2):.5f}")
    chk.finish()


if __name__ == "__main__":
    main()
