#!/usr/bin/env python3
"""Static Hertz (doc/reference.md §7) by dynamic relaxation: one half-disc R = 4 (plane strain,
E = 1000, nu = 0.2) on a rigid frictionless wall, its top 45-degree arc moved down by 0.2,
mass-proportional damping ALPHA = 10, t = 3 (input/hertz/static_iga.inp, static_q8.inp:
IGA p = 2 and Q8, 24 x 24, spans along the contact arc graded by 1.12 from the contact point).
The load is what the prescribed displacement produces (about P = 93 for the full cylinder);
the Hertz ellipse is evaluated at that measured resultant.

Gates: relaxed (kinetic/strain energy < 1e-3, resultant constant to 1e-3 over the last 20 %);
at least 10 spans inside b; |p0^h - p0|/p0 < 5 %; |b^h - b| < one element (span) at b;
int p dx = P to 0.5 % (reference x, hertz_static.py); RMS(p - Hertz)/p0 < 3 %.
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(HERE, "..", "hertz"))
import vcheck  # noqa: E402
import hertz_cases  # noqa: E402
import hertz_static  # noqa: E402


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("hertz_static")
    for name in ("static_iga", "static_q8"):
        case = hertz_cases.find(name)
        chk.true(open(case.deck).read() == hertz_cases.deck_text(case),
                 f"{name}: input/hertz/{name}.inp is what its line-1 command writes")
        out = os.path.join(args.work, name + ".h5")
        vcheck.run_ictus(args, case.deck, out)
        s = hertz_static.analyse_static(out, case.args)
        print(f"  {name}: resultant P = {s['P_half']:.4f} (half), {s['P_full']:.4f} (full); "
              f"Hertz b = {s['b']:.4f}, p0 = {s['p0']:.3f}")
        chk.below(s["ek_rel"], 1e-3, f"{name}: kinetic/strain energy at the end (relaxed)")
        chk.below(s["drift"], 1e-3, f"{name}: resultant change over the last 20 % / P")
        chk.true(s["spans_in_b"] >= 10, f"{name}: {s['spans_in_b']} spans inside b (>= 10)")
        chk.close(s["p0h"], s["p0"], 0.05, f"{name}: p0^h against Hertz p0")
        chk.below(abs(s["bh"] - s["b"]), s["h_b"],
                  f"{name}: |b^h - b| (b^h = {s['bh']:.4f}, b = {s['b']:.4f}) below the span at b")
        chk.close(s["int_p"], s["P_half"], 0.005, f"{name}: int p dx against the resultant")
        chk.below(s["rms"], 0.03, f"{name}: RMS(p - Hertz)/p0 over |x| < b")
    chk.finish()


if __name__ == "__main__":
    main()
