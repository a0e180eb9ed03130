#!/usr/bin/env python3
"""1D wave in a bar (plane stress, nu = 0) against the exact solution by characteristics.

A bar [0, L] moving at -v0 along its axis is held at x = 0 from t = 0 on (doc/reference.md §3.1 with
a bilateral constraint, identical to the Signorini problem for t < 2L/c). The exact solution:
  t <= L/c:          u = -v0 min(t, x/c)
  L/c <= t <= 2L/c:  u = -v0 x/c for x <= 2L - ct, u = v0 (t - 2L/c) beyond.
Run to t = 1.5 L/c, checked at every field snapshot. Q8 elements (HRZ mass) and Q4 (HRZ).
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

E, RHO, V0, L, H = 1000.0, 1.0, 1.0, 10.0, 0.5
C = (E / RHO) ** 0.5


def deck(etype, nx):
    return ("*HEADING\nbar wave, plane stress, nu = 0\n*ANALYSIS, TYPE=PLANE STRESS, THICKNESS=1\n"
            + vcheck.material_block(e=E, nu=0.0, rho=RHO)
            + vcheck.rect_mesh(type=etype, nx=nx, ny=1, lx=L, ly=H)
            + "*BOUNDARY\nLEFT, 1, 1\n*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 1, -1.0\n"
            + "*MASS, TYPE=HRZ\n*STEP\n*DYNAMIC, EXPLICIT\n0, " + repr(1.5 * L / C)
            + "\n*OUTPUT, FIELD, EVERY=50\n*END STEP\n")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("bar_wave")
    for etype, nx in (("Q8", 100), ("Q4", 200)):
        path = os.path.join(args.work, f"bar_{etype}.inp")
        with open(path, "w") as f:
            f.write(deck(etype, nx))
        out = os.path.join(args.work, f"bar_{etype}.h5")
        vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        # Q4 (equal nodal masses) keeps the motion exactly 1D; Q8's corner/midside mass pattern
        # makes u_x vary over the height at the wave front, which couples in a little shear
        vcheck.check_bar_wave(chk, r, f"{etype}: ", V0, L, C, 1e-12 if etype == "Q4" else 0.02,
                              RHO * L * H, "rho L H")
    chk.finish()


if __name__ == "__main__":
    main()
