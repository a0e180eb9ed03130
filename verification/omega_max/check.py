#!/usr/bin/env python3
"""Largest natural frequency of a free square Q8 mesh against doc/reference.md §6.2.

A 10 x 10 mesh of square Q8 elements (h = 1) with free edges, plane strain, E = 1000,
nu = 0.2, rho = 1 (c_d = 33.333). Expected omega_max h / c_d (Bloch analysis and a free
10 x 10 patch, doc/reference.md §6.2): consistent 8.051, HRZ with a 2x2 diagonal 8.731, HRZ with
the full 3x3 rule 7.568. ictus estimates omega_max by power iteration (stored as the root
attribute omega_max); gate: within 2%.
Also: a given dt above 2/omega_max is refused before the first step (exit 1, both numbers
named), and row-sum lumping of Q8 is refused (negative corner masses, doc/theory.md §3).
"""
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

CD = (1000.0 * (1 - 0.2) / ((1 + 0.2) * (1 - 2 * 0.2))) ** 0.5  # plane strain P-wave speed
CASES = [("CONSISTENT", "*MASS, TYPE=CONSISTENT", 8.051),
         ("HRZ 2X2", "*MASS, TYPE=HRZ, INTEGRATION=2X2", 8.731),
         ("HRZ FULL", "*MASS, TYPE=HRZ, INTEGRATION=FULL", 7.568)]


def deck(mass_card, dt="0", t_end="1e-3"):
    return ("*HEADING\nfree square Q8 mesh\n" + vcheck.material_block()
            + vcheck.rect_mesh(type="Q8", nx=10, ny=10, lx=10.0, ly=10.0)
            + mass_card + f"\n*STEP\n*DYNAMIC, EXPLICIT\n{dt}, {t_end}\n*END STEP\n")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("omega_max")
    chk.close(CD, 33.333, 1e-4, "plane-strain P-wave speed c_d")
    for name, card, want in CASES:
        tag = name.replace(" ", "_").lower()
        path = os.path.join(args.work, f"omega_{tag}.inp")
        with open(path, "w") as f:
            f.write(deck(card))
        out = os.path.join(args.work, f"omega_{tag}.h5")
        vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        chk.close(float(r.attr("omega_max")) / CD, want, 0.02, f"{name}: omega_max h / c_d")
        chk.close(float(r.attr("dt")), 0.9 * 2.0 / float(r.attr("omega_max")), 1e-12,
                  f"{name}: automatic dt = 0.9 * 2/omega_max")
    # a time step above the stable limit stops the run before the first step
    path = os.path.join(args.work, "omega_dt_too_big.inp")
    with open(path, "w") as f:
        f.write(deck("*MASS, TYPE=HRZ", dt="0.01", t_end="0.1"))
    _, log = vcheck.run_ictus(args, path, os.path.join(args.work, "too_big.h5"), expect_status=1)
    m = re.search(r"time step ([0-9.eE+-]+) exceeds the stable limit 2/omega_max = ([0-9.eE+-]+)", log)
    chk.true(m is not None and float(m.group(1)) == 0.01, "dt above 2/omega_max refused, naming both")
    chk.true(not os.path.exists(os.path.join(args.work, "too_big.h5")), "no results file left behind")
    # row-sum lumping of Q8 gives negative corner masses: refused, naming nodes
    path = os.path.join(args.work, "omega_rowsum.inp")
    with open(path, "w") as f:
        f.write(deck("*MASS, TYPE=ROW SUM"))
    _, log = vcheck.run_ictus(args, path, os.path.join(args.work, "rowsum.h5"), expect_status=1)
    chk.true("not positive at nodes 1," in log and "row-sum" in log, "row-sum on Q8 refused, naming nodes")
    chk.finish()


if __name__ == "__main__":
    main()
