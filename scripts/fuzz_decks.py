#!/usr/bin/python3
"""Mutated input decks against ictus: bad input of any kind must end with exit status 0 or 1,
a message (an error names file:line), and no crash or backtrace.

Takes the decks of input/ and the good decks of the reader's unit test (tests/unit/io/decks;
their *INCLUDEs keep working: each mutant is
written next to its original, under a hidden name, and removed after the run), mutates 1-3
lines of each (delete, duplicate, swap or truncate lines; replace a line, a value or a number
with junk: empty, NaN, Inf, huge, negative, keywords, a NUL byte; drop a value; lower case)
and runs `ictus --check` (70 %) or a whole run (30 %, cut after --timeout seconds, which is
not a failure). A mutant is kept in --keep when ictus
  - exits with a status other than 0 or 1 (2: out of memory and METIS failures are the
    only documented ones, and these small decks never reach them),
  - prints a runtime backtrace or "Program received signal", or
  - exits 1 without an error message.
Exit status 1 when any was kept. A manual check, not a CTest (it takes minutes):

    /usr/bin/python3 scripts/fuzz_decks.py --count 500 --seed 4
"""
import argparse
import glob
import os
import random
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
JUNK = ["", "*", "**", ",", "=", "nan", "inf", "-inf", "1e400", "-1e-400", "0", "-1", "1.5",
        "999999999999", "2147483648", "abc", "*NODE", "*ELEMENT", "*END STEP", "*STEP", ",,,",
        "TYPE=", "NAME=", "\t", ",".join(str(k) for k in range(1, 21)), "é", "\x00"]
CRASH = re.compile(r"Backtrace|Program received signal|SIGSEGV|Error termination|"
                   r"Fortran runtime error|At line \d+ of file")


def mutate(lines, rng):
    i = rng.randrange(len(lines))
    kind = rng.randrange(9)
    if kind == 0:
        del lines[i]
    elif kind == 1:
        lines.insert(i, lines[rng.randrange(len(lines))])
    elif kind == 2:
        lines[i] = rng.choice(JUNK)
    elif kind == 3:
        toks = re.split(r"([,=])", lines[i])
        toks[rng.randrange(len(toks))] = rng.choice(JUNK)
        lines[i] = "".join(toks)
    elif kind == 4:
        del lines[i:]
    elif kind == 5:
        toks = lines[i].split(",")
        if len(toks) > 1:
            del toks[rng.randrange(len(toks))]
        lines[i] = ",".join(toks)
    elif kind == 6:
        nums = re.findall(r"-?\d+\.?\d*(?:[eE][-+]?\d+)?", lines[i])
        if nums:
            n = rng.choice(nums)
            lines[i] = lines[i].replace(n, rng.choice(
                ["0", "-" + n, n + "0000", "1e300", "-0", "1e-300",
                 str(rng.randint(-5, 100000))]), 1)
    elif kind == 7:
        lines[i] = lines[i].lower()
    else:
        j = rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ictus", default=os.path.join(ROOT, "build", "bin", "ictus"))
    ap.add_argument("--count", type=int, default=200, help="mutants to run")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds per whole run")
    ap.add_argument("--keep", default="/tmp/ictus-fuzz", help="where failing mutants go")
    args = ap.parse_args()
    rng = random.Random(args.seed)
    decks = sorted(d for d in glob.glob(os.path.join(ROOT, "input", "*", "*.inp"))
                   + glob.glob(os.path.join(ROOT, "tests", "unit", "io", "decks", "*.inp"))
                   if os.path.getsize(d) < 200000)
    os.makedirs(args.keep, exist_ok=True)
    out = os.path.join(args.keep, f"run_{args.seed}.h5")
    bad = 0
    for t in range(args.count):
        deck = rng.choice(decks)
        with open(deck, errors="replace") as f:
            lines = f.read().split("\n")
        for _ in range(rng.randint(1, 3)):
            if lines:
                mutate(lines, rng)
        path = os.path.join(os.path.dirname(deck), f".fuzz_{args.seed}_{t}.inp")
        with open(path, "w") as f:
            f.write("\n".join(lines))
        cmd = [args.ictus, path, "--quiet", "-o", out]
        if rng.random() < 0.7:
            cmd.append("--check")
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, errors="replace",
                               timeout=args.timeout)
            status, text = p.returncode, p.stdout + p.stderr
        except subprocess.TimeoutExpired:
            status, text = None, ""
        finally:
            os.remove(path)
        why = None
        if status not in (None, 0, 1):
            why = f"exit status {status}"
        elif CRASH.search(text):
            why = "a runtime error or backtrace"
        elif status == 1 and not re.search(r"error", text, re.I):
            why = "exit 1 without an error message"
        if why:
            bad += 1
            kept = os.path.join(args.keep, f"bad_{args.seed}_{t}.inp")
            with open(kept, "w") as f:
                f.write("\n".join(lines))
            print(f"FAIL {why}: {kept} (from {os.path.relpath(deck, ROOT)})")
            print("    " + text[-800:].replace("\n", "\n    "))
    print(f"fuzz_decks: {args.count} mutants of {len(decks)} decks (seed {args.seed}), "
          f"{bad} failing")
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
