#!/usr/bin/env python3
"""The two internal forces agree: the element loop over the material law and the assembled K.

For a linear elastic law in small strain, f_int(u) = sum_e int B^T sigma(u) dV = K u exactly, so
`*DYNAMIC, EXPLICIT, INTERNAL FORCE=ELEMENT` (a loop over the elements that calls the law at
every quadrature point, doc/theory.md §4) must reproduce the run with the assembled stiffness
(`INTERNAL FORCE=AUTO` takes it for linear laws) to round-off. Checked on the linear Hertz decks
of the founding paper with contact (Q8 with HRZ mass, NURBS p = 2 with HRZ mass and with the
consistent mass): every history series (energies, contact forces, pressures, penetrations)
within 1e-12 of the largest value of the series, and the strain energy, which the element loop
takes from the law's energy density and the assembled operator from 1/2 u.K u, alike. The
element loop also gives the same bits on 1 and 2 ranks (each row summed over the same elements
in the same order).
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DECKS = ("q8_hrz", "iga_hrz", "iga_consistent")


def variant(name, force, work):
    """The shipped deck with INTERNAL FORCE=force on its *DYNAMIC card (AUTO: unchanged)."""
    src = os.path.join(HERE, "..", "..", "input", "hertz", name + ".inp")
    with open(src) as f:
        text = f.read()
    if force != "AUTO":
        text, n = re.subn(r"^\*DYNAMIC, EXPLICIT", f"*DYNAMIC, EXPLICIT, INTERNAL FORCE={force}",
                          text, flags=re.M)
        assert n == 1, name
    path = os.path.join(work, f"{name}_{force.lower()}.inp")
    with open(path, "w") as f:
        f.write(text)
    return path


def series(res):
    """Every history dataset of a results file, by path."""
    out = {}

    def visit(name, obj):
        if hasattr(obj, "shape") and name not in ("time", "dt"):
            out[name] = np.asarray(obj, dtype=float)
    res.f["history"].visititems(visit)
    return out


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("internal_force")
    for name in DECKS:
        runs = {}
        for force in ("AUTO", "ELEMENT"):
            deck = variant(name, force, args.work)
            out = deck.replace(".inp", ".h5")
            _, log = vcheck.run_ictus(args, deck, out)
            want = "element loop" if force == "ELEMENT" else "assembled stiffness"
            chk.true(f"internal force: {want}" in log, f"{name}, {force}: the log names the {want}")
            runs[force] = series(vcheck.Results(out))
        a, e = runs["AUTO"], runs["ELEMENT"]
        chk.true(sorted(a) == sorted(e) and len(a) > 0, f"{name}: the same history series")
        worst, where = 0.0, ""
        for key in a:
            scale = np.max(np.abs(a[key]))
            if scale == 0.0:
                continue
            d = np.max(np.abs(a[key] - e[key])) / scale
            if d > worst:
                worst, where = d, key
        chk.below(worst, 1e-12, f"{name}: element loop vs assembled K, largest difference over "
                  f"all series / the series' largest value (at {where or '-'})")
        active = [np.max(a[k]) for k in a if k.endswith("/active_points")]
        chk.true(len(active) > 0 and max(active) > 0, f"{name}: contact is active")
        chk.close(float(e["energy/strain"].max()), float(a["energy/strain"].max()), 1e-12,
                  f"{name}: largest strain energy, law energy density vs 1/2 u.K u")
    # the element loop on two ranks: the same bits
    deck = variant("q8_hrz", "ELEMENT", args.work)
    out2 = deck.replace(".inp", "_np2.h5")
    vcheck.run_ictus(args, deck, out2, np=2)
    one = series(vcheck.Results(deck.replace(".inp", ".h5")))
    two = series(vcheck.Results(out2))
    chk.true(all(np.array_equal(one[k], two[k]) for k in one),
             "q8_hrz, ELEMENT: every history series bit-identical on 1 and 2 ranks")
    chk.finish()


if __name__ == "__main__":
    main()
