#!/usr/bin/python3
"""ParaView opens ictus sidecars and warps them by the displacement (doc/results.md, "The XDMF
sidecar"). Needs pvpython and xvfb-run (Debian: apt-get install python3-paraview xvfb xauth,
which scripts/setup.sh tries); without them it prints SKIPPED and exits 77 (CTest: skipped).

Runs the Hertz deck input/hertz/iga_hrz.inp (NURBS only) and the mixed deck
tests/scripts/xdmf_mixed.inp (a Q8 block and a NURBS patch) into --work, then runs
xdmf_paraview.py under pvpython three times:
  1. from the folder above --work, on the absolute paths of hertz.xdmf and mixed.xdmf, with
     the reader ParaView's OpenDataFile picks; renders the warped last step to
     --work/hertz.png and --work/mixed.png;
  2. from --work, on the bare names, with the legacy XDMF reader (XDMFReader);
  3. from --work, on ./hertz.xdmf, ./mixed.xdmf and the per-block sidecars
     ./mixed.q8.xdmf, ./mixed.iga.xdmf, with the reader OpenDataFile picks;
  4. from --work, on ./hertz.xdmf and ./mixed.xdmf, with Xdmf3ReaderT.
ParaView 5.11's Xdmf3 readers (the default) prefix the HDF5 name with the whole sidecar name
when that has no folder part (bare 'hertz.xdmf' -> 'hertz.xdmfhertz.h5'), whatever the sidecar
says; so the bare name is tried with the legacy reader and the default one gets './'.
Each time: the number of steps and the last time, the number of points and cells, 3
components of displacement and velocity, and the bounds after Warp By Vector equal what the
HDF5 file gives (geometry + displacement of the last snapshot).
Prints "N passed, N failed"; exit 1 on any failure.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

import numpy as np

import xdmf_common as xc

SKIP = 77
XVFB = ["xvfb-run", "-a", "-s", "-screen 0 1024x768x24 +extension GLX"]


def run_paraview(args, cwd):
    cmd = XVFB + ["pvpython", os.path.join(xc.HERE, "xdmf_paraview.py")] + args
    p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, timeout=600)
    results = [json.loads(line[len("RESULT "):]) for line in p.stdout.splitlines()
               if line.startswith("RESULT ")]
    if p.returncode != 0 or len(results) != len([a for a in args if a.endswith(".xdmf")]):
        print("\n".join(p.stdout.splitlines()[-30:]))
    return p.returncode, results


def expected(h5, block=None):
    blocks = [b for b in xc.blocks(h5) if block is None or b[0] == block]
    snaps = xc.snapshots(h5)
    bounds = xc.warped_bounds(h5) if block is None else None
    if block is not None:
        step = snaps[-1][0]
        x = blocks[0][2] + xc.field(h5, step, blocks[0][3] + "displacement")
        bounds = [x[:, 0].min(), x[:, 0].max(), x[:, 1].min(), x[:, 1].max()]
    return dict(steps=len(snaps), last_time=snaps[-1][1],
                points=sum(len(b[2]) for b in blocks), cells=sum(len(b[1]) for b in blocks),
                bounds=bounds)


def check_result(c, res, want, label):
    c.check(res["steps"] == want["steps"] and res["last_time"] == want["last_time"],
            f"{label}: {want['steps']} steps, last t = {want['last_time']:.6g}",
            f"got {res['steps']}, t = {res['last_time']!r}")
    c.check(res["points"] == want["points"] and res["cells"] == want["cells"],
            f"{label}: {want['points']} points, {want['cells']} cells",
            f"got {res['points']}, {res['cells']}")
    vectors = {k: v for k, v in res["components"].items() if k in ("displacement", "velocity")}
    c.check(vectors == {"displacement": 3, "velocity": 3},
            f"{label}: displacement and velocity have 3 components", str(res["components"]))
    b = np.array(res["warped_bounds"])
    err = np.abs(b[:4] - np.array(want["bounds"])).max()
    c.check(err <= 1e-12 * max(1.0, np.abs(want["bounds"]).max()) and not np.any(b[4:]),
            f"{label}: bounds after Warp By Vector = geometry + displacement of the last "
            "snapshot", f"{b.tolist()} vs {want['bounds']}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ictus", required=True)
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    missing = [t for t in ("pvpython", "xvfb-run") if shutil.which(t) is None]
    if missing:
        print(f"SKIPPED: {' and '.join(missing)} not found "
              "(apt-get install python3-paraview xvfb xauth)")
        sys.exit(SKIP)
    work = os.path.abspath(a.work)
    h5 = xc.run_decks(a.ictus, work)
    c = xc.Counter()
    wants = {"hertz.xdmf": expected(h5["hertz"]), "mixed.xdmf": expected(h5["mixed"]),
             "mixed.q8.xdmf": expected(h5["mixed"], "q8"),
             "mixed.iga.xdmf": expected(h5["mixed"], "iga")}
    main_files = ["hertz.xdmf", "mixed.xdmf"]
    runs = [("absolute path from elsewhere, default reader", os.path.dirname(work),
             ["--png", work] + [os.path.join(work, f) for f in main_files]),
            ("bare name from its folder, legacy reader", work,
             ["--reader", "legacy"] + main_files),
            ("./name from its folder, default reader", work,
             ["./" + f for f in wants]),
            ("./name from its folder, Xdmf3ReaderT", work,
             ["--reader", "xdmf3t"] + ["./" + f for f in main_files])]
    for how, cwd, args in runs:
        rc, results = run_paraview(args, cwd)
        files = [x for x in args if x.endswith(".xdmf")]
        c.check(rc == 0 and len(results) == len(files), f"pvpython ran ({how})",
                f"exit {rc}, {len(results)} of {len(files)} files")
        for res in results:
            name = os.path.basename(res["file"])
            check_result(c, res, wants[name], f"{name} ({how}; {res['reader']})")
            if "png" in res:
                ok = os.path.exists(res["png"]) and os.path.getsize(res["png"]) > 10000
                c.check(ok, f"{name}: rendered {res['png']}")
    c.finish()


if __name__ == "__main__":
    main()
