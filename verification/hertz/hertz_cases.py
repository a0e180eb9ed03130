#!/usr/bin/env python3
"""The decks of the dynamic and static Hertz suite (input/hertz/<name>.inp), each made by
scripts/mesh/hertz.py with the arguments listed here (the command is line 1 of the deck).

    hertz_cases.py [--check]     # (re)writes input/hertz/*.inp; --check: only compare

Time steps: the paper's cases run at its dt = 5e-4 on 8 x 8 meshes (omega_max dt and the
contact ratio r in doc/verification.md §2). The refinement series keeps r (as printed by ictus)
near 1 for IGA, dt = 5e-4 * 8/n (16 x 16 reaches r = 1.006 and runs with STABILITY=WARN),
and omega_max dt <= 1.65; Q8 has a larger omega_max (its
degenerate-corner elements) and needs the smaller steps listed.
"""
import os
import shlex
import subprocess
import sys
from dataclasses import dataclass

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DECKS = os.path.join(ROOT, "input", "hertz")


@dataclass
class Case:
    name: str
    args: str
    v_rel: float = 4.0
    wall: bool = False
    groups: tuple = ()
    mesh_label: str = ""
    mass_label: str = "HRZ"

    @property
    def deck(self):
        return os.path.join(DECKS, self.name + ".inp")

    def command(self):
        return "scripts/mesh/hertz.py " + self.args


def _dyn(name, kind, n, mass, dt, groups, variant="both", passes=0, warn=False):
    mflag = {"HRZ": "HRZ", "ROW SUM": "'ROW SUM'", "CONSISTENT": "CONSISTENT"}[mass]
    size = f"--n {n}" if kind == "q8" else f"--subdivide {n}"
    args = f"--kind {kind} --mass {mflag} {size} --dt {dt:g} --field-every 50"
    if variant == "one":
        args += " --variant one"
    if warn:
        args += " --stability WARN"
    mass_label = mass.lower().replace("row sum", "row-sum")
    if passes:
        args += f" --mass-passes {passes}"
        mass_label += f", {passes} corrector passes"
    label = f"{'Q8' if kind == 'q8' else 'IGA p=2'} {n}x{n}"
    return Case(name, args, 4.0 if variant == "both" else 2.0, False, groups, label, mass_label)


# paper's setting: dt = 5e-4, T = 0.9, 8 x 8 meshes
PAPER = [
    _dyn("q8_hrz", "q8", 8, "HRZ", 5e-4, ("paper", "fig3", "conv_q8")),
    _dyn("iga_hrz", "iga", 8, "HRZ", 5e-4, ("paper", "fig3", "fig4", "conv_iga")),
    _dyn("iga_rowsum", "iga", 8, "ROW SUM", 5e-4, ("paper", "fig4")),
    _dyn("iga_consistent", "iga", 8, "CONSISTENT", 5e-4, ("paper", "fig4")),
    # beyond the paper: the consistent mass applied by 2 corrector passes (doc/theory.md §5.1)
    _dyn("iga_corrector", "iga", 8, "CONSISTENT", 5e-4, ("paper",), passes=2),
    _dyn("q8_hrz_one", "q8", 8, "HRZ", 5e-4, ("paper", "one"), variant="one"),
    _dyn("iga_hrz_one", "iga", 8, "HRZ", 5e-4, ("paper", "one"), variant="one"),
]
# refinement series (8 x 8 is the paper case above)
SERIES = [
    _dyn("iga_hrz_12", "iga", 12, "HRZ", 3.3e-4, ("series", "conv_iga")),
    # r = 1.006 at the start, just above the limit r = 1: run as before, with the warning
    _dyn("iga_hrz_16", "iga", 16, "HRZ", 2.5e-4, ("series", "conv_iga"), warn=True),
    _dyn("iga_hrz_24", "iga", 24, "HRZ", 1.5e-4, ("series", "conv_iga")),
    _dyn("q8_hrz_12", "q8", 12, "HRZ", 2.5e-4, ("series", "conv_q8")),
    _dyn("q8_hrz_16", "q8", 16, "HRZ", 1.5e-4, ("series", "conv_q8")),
    _dyn("q8_hrz_24", "q8", 24, "HRZ", 7e-5, ("series", "conv_q8")),
]
CASES = PAPER + SERIES

# static Hertz by dynamic relaxation (one half-disc on a rigid wall, top arc moved down)
STATIC = [
    Case("static_iga", "--kind iga --subdivide 24 --grade-arc 1.12 --wall --static 0.2 "
         "--alpha 10 --dt 0 --t-end 3 --field-every 1000", 0.0, True, ("static",),
         "IGA p=2 24x24 graded 1.12"),
    Case("static_q8", "--kind q8 --n 24 --grade-arc 1.12 --wall --static 0.2 "
         "--alpha 10 --dt 0 --t-end 3 --field-every 1000", 0.0, True, ("static",),
         "Q8 24x24 graded 1.12"),
]
ALL = CASES + STATIC


def find(name):
    for c in ALL:
        if c.name == name:
            return c
    raise KeyError(name)


def deck_text(case):
    cmd = [sys.executable, os.path.join(ROOT, "scripts", "mesh", "hertz.py")] + shlex.split(case.args)
    return subprocess.run(cmd, check=True, stdout=subprocess.PIPE, text=True, cwd=ROOT).stdout


def main():
    check = "--check" in sys.argv[1:]
    bad = 0
    for c in ALL:
        text = deck_text(c)
        if check:
            same = os.path.exists(c.deck) and open(c.deck).read() == text
            bad += not same
            print(f"{'ok  ' if same else 'DIFF'} {c.deck}")
        else:
            with open(c.deck, "w") as f:
                f.write(text)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
