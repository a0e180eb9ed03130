#!/usr/bin/python3
"""The bit-for-bit comparison cannot pass vacuously (scripts/compare_results.py and
scripts/bit_regression.py, doc/testing.md "Bit-identical results").

Three runs of the same deck (input/bar_wave/bar_q8.inp) into a.h5, b.h5 and c.h5:
  * a vs b: exit 0, IDENTICAL, and the comparison covered every dataset of the file (the
    count printed equals the count h5py finds, which is > 0);
  * a vs c after one bit of c is flipped (the lowest mantissa bit of one displacement
    component of the last snapshot): exit 1, naming that dataset and "1 of N elements";
  * a vs c after the bit is restored and the lowest bit of the root attribute `dt` flipped:
    exit 1, naming the attribute;
  * --ignore-attr dt then makes that pair identical again (exit 0).
Then bit_regression.py on that deck alone: the binary against itself, exit 0, and against a
stand-in "new" binary that runs ictus and then flips one bit of the results: exit 1 with the
deck's row DIFFERENT; and a stand-in that exits 2 where ictus exits 0: STATUS DIFFERS, exit 1.
Prints "N passed, N failed" and exits 1 on any failure.
"""
import argparse
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COMPARE = os.path.join(ROOT, "scripts", "compare_results.py")
REGRESSION = os.path.join(ROOT, "scripts", "bit_regression.py")
DECK = os.path.join(ROOT, "input", "bar_wave", "bar_q8.inp")

passed = failed = 0


def check(cond, label, output=""):
    global passed, failed
    if cond:
        passed += 1
        print(f"  ok   {label}")
    else:
        failed += 1
        print(f"  FAIL {label}")
        if output:
            print("       " + output.replace("\n", "\n       "))


def run(cmd, **kw):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kw)
    return p.returncode, p.stdout


def flip_last_bit(path, dataset, index):
    with h5py.File(path, "r+") as f:
        a = f[dataset][()]
        bits = a.view(np.uint64)
        bits[index] ^= np.uint64(1)
        f[dataset][...] = a


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ictus", required=True)
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    if os.path.exists(a.work):
        shutil.rmtree(a.work)
    os.makedirs(a.work)
    py = sys.executable
    files = {}
    for name in ("a", "b", "c"):
        files[name] = os.path.join(a.work, name + ".h5")
        status, out = run([a.ictus, DECK, "-o", files[name], "--quiet"])
        check(status == 0, f"ictus runs the deck into {name}.h5", out)

    with h5py.File(files["a"], "r") as f:
        n_datasets = []
        f.visititems(lambda k, o: n_datasets.append(k) if isinstance(o, h5py.Dataset) else None)
        last = sorted(f["fields"].keys())[-1]
    disp = f"fields/{last}/displacement"

    status, out = run([py, COMPARE, files["a"], files["b"]])
    check(status == 0 and out.startswith("IDENTICAL"), "two runs of the same deck: exit 0, "
          "IDENTICAL", out)
    check(f" {len(n_datasets)} datasets" in out and len(n_datasets) > 10,
          f"all {len(n_datasets)} datasets compared", out)

    status, out = run([py, COMPARE, files["a"], files["c"]])
    check(status == 0, "a third run is identical too before the change", out)
    flip_last_bit(files["c"], disp, (7, 1))
    status, out = run([py, COMPARE, files["a"], files["c"]])
    check(status == 1 and out.startswith("DIFFERENT"), "one bit of one dataset: exit 1", out)
    n = None
    with h5py.File(files["a"], "r") as f:
        n = f[disp].size
    check(f"/{disp}: data differs (1 of {n} elements differ, first at [7, 1]" in out,
          "the difference names the dataset, the element, and 1 element", out)
    check(out.count("\n    ") == 1, "and nothing else differs", out)

    flip_last_bit(files["c"], disp, (7, 1))
    with h5py.File(files["c"], "r+") as f:
        dt = np.float64(f.attrs["dt"])
        f.attrs["dt"] = np.array([dt]).view(np.uint64).__xor__(np.uint64(1)).view(np.float64)[0]
    status, out = run([py, COMPARE, files["a"], files["c"]])
    check(status == 1 and "/ @dt: attribute value differs" in out,
          "one bit of the root attribute dt: exit 1, named", out)
    status, out = run([py, COMPARE, files["a"], files["c"], "--ignore-attr", "dt"])
    check(status == 0 and "1 ignored" in out, "--ignore-attr dt: exit 0", out)

    # bit_regression.py on the one deck: against itself, against a changed "new" binary
    deck_filter = "^input/bar_wave/bar_q8.inp$"
    common = [py, REGRESSION, "--no-verification", "--filter", deck_filter, "--timeout", "60"]
    status, out = run(common + ["--old", a.ictus, "--new", a.ictus,
                                "--out", os.path.join(a.work, "same")])
    check(status == 0 and "| identical" in out and "BIT REGRESSION: IDENTICAL" in out,
          "bit_regression: ictus against itself: exit 0, identical", out)
    flip = os.path.join(a.work, "flip.sh")
    with open(flip, "w") as f:
        f.write(f"""#!/bin/bash
"{a.ictus}" "$@" || exit $?
out=$(printf '%s\\n' "$@" | grep '\\.h5$' | tail -1)
"{py}" -c "import sys, h5py, numpy as np
with h5py.File(sys.argv[1], 'r+') as f:
    d = f['history/energy/total']; x = d[()]; x.view(np.uint64)[3] ^= np.uint64(1); d[...] = x
" "$out"
""")
    os.chmod(flip, 0o755)
    status, out = run(common + ["--old", a.ictus, "--new", flip,
                                "--out", os.path.join(a.work, "flip")])
    check(status == 1 and "| DIFFERENT (1 difference)" in out
          and "/history/energy/total: data differs (1 of" in out
          and "BIT REGRESSION: DIFFERENT" in out,
          "bit_regression: one bit flipped by the new binary: exit 1, DIFFERENT", out)
    fail = os.path.join(a.work, "fail.sh")
    with open(fail, "w") as f:
        f.write(f'#!/bin/bash\n"{a.ictus}" "$@" || exit $?\nexit 2\n')
    os.chmod(fail, 0o755)
    status, out = run(common + ["--old", a.ictus, "--new", fail,
                                "--out", os.path.join(a.work, "fail")])
    check(status == 1 and "STATUS DIFFERS" in out,
          "bit_regression: new exits 2 where old exits 0: exit 1, STATUS DIFFERS", out)

    print(f"compare_results: {passed} passed, {failed} failed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
