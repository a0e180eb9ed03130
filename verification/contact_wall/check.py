#!/usr/bin/env python3
"""Elastic bar hitting a rigid wall (Signorini, doc/reference.md §3.1): contact force rho c A v0 for
2L/c, impulse 2 rho A L v0, the bar leaves at +v0 with no residual vibration.

Bar [0, L], L = 10, H = 0.1, E = 1000, rho = 1, plane stress nu = 0, moving at -v0 = -1,
touching the *RIGID WALL x = 0 (normal +x) at t = 0, eps_hat = eps h / E = 10. Q8 (HRZ,
100 x 1) and p = 2 NURBS (row sum, 100 x 1 spans). Automatic time step (r <= 1/2, checked
from the printed ratio). Gates of doc/reference.md §3.1, plus the bar's final momentum
(+rho A L v0: the impulse is all passed on).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402
import impact  # noqa: E402
from impact import C, RHO  # noqa: E402

L, H, V0, N, EPS_HAT = 10.0, 0.1, 1.0, 100, 10.0


def deck(kind, normal="1,0"):
    eps = EPS_HAT * impact.E / (L / N)
    if kind == "Q8":
        bar, _, _ = impact.q8_bar("A", 0.0, L, H, N)
        mass = "HRZ"
    else:
        bar, _ = impact.iga_block("A", 0.0, 0.0, L, H, N, 1)
        mass = "ROW SUM"
    return (impact.header(f"bar against a rigid wall, {kind}") + bar
            + f"*INITIAL CONDITIONS, TYPE=VELOCITY\nA, 1, {-V0!r}\n"
            + f"*RIGID WALL, NAME=WALL, POINT=0,0, NORMAL={normal}, PENALTY={eps:.17g}\nA_LEFT\n"
            + f"*MASS, TYPE={mass}\n" + impact.step(1.3 * 2 * L / C))


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("contact_wall")
    forces = {}
    for kind in ("Q8", "IGA"):
        path = os.path.join(args.work, f"wall_{kind}.inp")
        with open(path, "w") as fd:
            fd.write(deck(kind))
        out = path.replace(".inp", ".h5")
        _, log = vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        dt = float(r.history("dt")[0])
        chk.below(max(impact.ratios(log)), 0.5, f"{kind}: printed ratio r (dt = {dt:.4g})")
        t = r.history("time")
        f = r.history("contact/wall/force_first")[:, 0]   # on the bar: +x
        forces[kind] = r.history("contact/wall/force_first")
        p = impact.pulse(t, f, dt)
        chk.close(p["plateau"], RHO * C * H * V0, 0.03, f"{kind}: plateau force = rho c A v0")
        chk.close(p["duration"], 2 * L / C, 0.03, f"{kind}: contact duration = 2L/c")
        chk.close(p["impulse"], 2 * RHO * H * L * V0, 0.01, f"{kind}: impulse = 2 rho A L v0")
        ek = r.history("energy/kinetic")
        chk.true(ek[-1] >= 0.97 * ek[0], f"{kind}: rebound kinetic energy {ek[-1] / ek[0]:.4f}"
                 " of the initial (>= 0.97)")
        m = r.model("mass")
        v = r.field(r.field_steps()[-1], "velocity")
        mom = float(np.sum(m * v[:, 0]))
        chk.close(mom + RHO * L * H * V0, p["impulse"], 1e-9, f"{kind}: momentum change = "
                  "impulse of the wall force")
        print(f"  {kind}: plateau {p['plateau'] / (RHO * C * H * V0):.5f}, duration "
              f"{p['duration'] / (2 * L / C):.5f}, impulse "
              f"{p['impulse'] / (2 * RHO * H * L * V0):.5f}, final momentum "
              f"{mom / (RHO * L * H * V0):.5f} (ratios to exact)")
    # A normal names a direction whatever its length: 1e-300 (whose square underflows) must
    # give the run of the unit normal, bit for bit
    path = os.path.join(args.work, "wall_Q8_tiny_normal.inp")
    with open(path, "w") as fd:
        fd.write(deck("Q8", normal="1e-300,0"))
    out = path.replace(".inp", ".h5")
    vcheck.run_ictus(args, path, out)
    f_tiny = vcheck.Results(out).history("contact/wall/force_first")
    chk.true(f_tiny.shape == forces["Q8"].shape and np.array_equal(f_tiny, forces["Q8"]),
             "Q8: NORMAL=1e-300,0 gives the forces of NORMAL=1,0 bit for bit")
    chk.finish()


if __name__ == "__main__":
    main()
