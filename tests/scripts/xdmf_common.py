"""Shared by the XDMF reader tests (check_xdmf_meshio.py, check_xdmf_paraview.py): the two runs
they read and what the HDF5 file says each sidecar block should show.

  * hertz: input/hertz/iga_hrz.inp, NURBS only: one block ('iga'), one Uniform grid per step;
  * mixed: tests/scripts/xdmf_mixed.inp, one Q8 block and one NURBS patch: two blocks ('q8',
    'iga') per step in mixed.xdmf, and one sidecar per block (mixed.q8.xdmf, mixed.iga.xdmf).
"""
import os
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
DECKS = {"hertz": os.path.join(ROOT, "input", "hertz", "iga_hrz.inp"),
         "mixed": os.path.join(HERE, "xdmf_mixed.inp")}


class Counter:
    """Prints one line per check and the closing 'N passed, N failed' line."""

    def __init__(self):
        self.passed = self.failed = 0

    def check(self, cond, label, detail=""):
        if cond:
            self.passed += 1
            print(f"  ok   {label}")
        else:
            self.failed += 1
            print(f"  FAIL {label}" + (f": {detail}" if detail else ""))

    def finish(self):
        print(f"{self.passed} passed, {self.failed} failed")
        sys.exit(0 if self.failed == 0 and self.passed > 0 else 1)


def run_decks(ictus, work):
    """Runs both decks into `work`; returns {name: path of the .h5}."""
    os.makedirs(work, exist_ok=True)
    out = {}
    for name, deck in DECKS.items():
        h5 = os.path.join(work, name + ".h5")
        p = subprocess.run([ictus, deck, "-o", h5, "--quiet"], stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True)
        if p.returncode != 0:
            print(p.stdout)
            print(f"FAIL ictus {deck} exited with {p.returncode}")
            sys.exit(1)
        out[name] = h5
    return out


def blocks(h5path):
    """The sidecar blocks of a results file, in sidecar order: (name, connectivity, points,
    prefix of the field datasets)."""
    with h5py.File(h5path, "r") as f:
        out = []
        for t in sorted(f["model/elements"]):
            if t != "iga":
                out.append((t, f[f"model/elements/{t}/connectivity"][()],
                            f["model/coordinates"][()], ""))
        if "viz" in f:
            out.append(("iga", f["viz/iga/cells"][()], f["viz/iga/points"][()], "viz_"))
    return out


def snapshots(h5path):
    """[(step name, time)] of the field snapshots."""
    with h5py.File(h5path, "r") as f:
        return [(s, float(f["fields/" + s].attrs["time"])) for s in sorted(f["fields"])]


def field(h5path, step, name):
    with h5py.File(h5path, "r") as f:
        return f[f"fields/{step}/{name}"][()]


def warped_bounds(h5path):
    """Bounds (xmin, xmax, ymin, ymax) of every block's points moved by the last snapshot's
    displacement: what Warp By Vector gives at the last time."""
    step = snapshots(h5path)[-1][0]
    lo, hi = np.full(2, np.inf), np.full(2, -np.inf)
    for _, _, pts, prefix in blocks(h5path):
        x = pts + field(h5path, step, prefix + "displacement")
        lo, hi = np.minimum(lo, x.min(axis=0)), np.maximum(hi, x.max(axis=0))
    return [lo[0], hi[0], lo[1], hi[1]]
