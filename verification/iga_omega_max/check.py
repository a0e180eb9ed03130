#!/usr/bin/env python3
"""Largest natural frequency of a FREE biquadratic B-spline patch against doc/reference.md §6.2.

One NURBS patch, degree 2 x 2, square [0, 10]^2 with uniform open knot vectors refined to
10 x 10 spans (h = 1; all weights 1, control points at the Greville abscissae, so the map is
the identity up to scale), free edges, plane strain, E = 1000, nu = 0.2, rho = 1
(c_d = 33.333). Expected omega_max h/c_d (doc/reference.md §6.2, free-edge 10 x 10 patch):
consistent 5.857, row-sum 2.408 (gate 1 %). doc/reference.md gives no HRZ value: it is reported
(measured 2.296, Co_crit 0.871, slightly below row-sum). The automatic step must be
0.9 * 2/omega_max, and the total mass rho L^2.

The consistent mass applied by k corrector passes (MASS SOLVER=CORRECTOR, doc/theory.md §5) is
an approximate inverse that lies between the row-sum and the consistent inverse and grows with
k (Loewner order), so omega_max(row sum) <= omega_max(k = 1) <= (k = 2) <= (k = 4) <=
omega_max(consistent), each strictly here.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

CD = (1000.0 * (1 - 0.2) / ((1 + 0.2) * (1 - 2 * 0.2))) ** 0.5


def patch_deck(mass, nsub=10, length=10.0, dynamic="*DYNAMIC, EXPLICIT"):
    cps = "".join(f"{0.5 * length * i!r}, {0.5 * length * j!r}, 1.0\n"
                  for j in range(3) for i in range(3))
    return ("*HEADING\nfree biquadratic B-spline patch, 10 x 10 spans\n"
            "*ANALYSIS, TYPE=PLANE STRAIN, THICKNESS=1\n" + vcheck.material_block()
            + "*PATCH, NAME=SQ, MATERIAL=MAT, DEGREE=2,2, SIZE=3,3\n"
            + "*KNOTS, DIRECTION=1\n0 0 0 1 1 1\n*KNOTS, DIRECTION=2\n0 0 0 1 1 1\n"
            + "*CONTROL POINTS\n" + cps
            + f"*REFINE, PATCH=SQ, SUBDIVIDE={nsub},{nsub}\n"
            + f"*MASS, TYPE={mass}\n*STEP\n{dynamic}\n0, 1e-3\n*END STEP\n")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("iga_omega_max")
    got = {}
    for mass, want in (("CONSISTENT", 5.857), ("ROW SUM", 2.408), ("HRZ", None)):
        tag = mass.replace(" ", "_").lower()
        path = os.path.join(args.work, f"iga_omega_{tag}.inp")
        with open(path, "w") as f:
            f.write(patch_deck(mass))
        out = os.path.join(args.work, f"iga_omega_{tag}.h5")
        vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        w = float(r.attr("omega_max"))
        got[mass] = w / CD
        if want is not None:
            chk.close(w / CD, want, 0.01, f"{mass}: omega_max h / c_d")
        else:
            print(f"  info {mass}: omega_max h / c_d = {w / CD:.4f} (Co_crit = {2 * CD / w:.4f})")
        chk.close(float(r.attr("dt")), 0.9 * 2.0 / w, 1e-12, f"{mass}: automatic dt = 0.9 * 2/omega_max")
        chk.close(float(r.model("mass").sum()), 100.0, 1e-12, f"{mass}: total mass rho L^2")
    chk.true(got["ROW SUM"] < got["CONSISTENT"],
             "row-sum lumping lowers omega_max (doc/reference.md §6.2)")
    chain = [got["ROW SUM"]]
    for k in (1, 2, 4):
        path = os.path.join(args.work, f"iga_omega_corrector{k}.inp")
        with open(path, "w") as f:
            f.write(patch_deck("CONSISTENT", dynamic="*DYNAMIC, EXPLICIT, MASS SOLVER=CORRECTOR, "
                               f"MASS PASSES={k}"))
        out = os.path.join(args.work, f"iga_omega_corrector{k}.h5")
        vcheck.run_ictus(args, path, out)
        chain.append(float(vcheck.Results(out).attr("omega_max")) / CD)
        print(f"  info CORRECTOR, {k} passes: omega_max h / c_d = {chain[-1]:.4f}")
    chain.append(got["CONSISTENT"])
    chk.true(all(a < b for a, b in zip(chain, chain[1:])), "omega_max: row sum < corrector "
             "k = 1 < 2 < 4 < consistent (" + ", ".join(f"{w:.4f}" for w in chain) + ")")
    chk.finish()


if __name__ == "__main__":
    main()
