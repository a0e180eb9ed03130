#!/usr/bin/python3
"""meshio's XDMF time-series reader reads ictus sidecars, with the values of the HDF5 file
(doc/results.md, "The XDMF sidecar").

Runs the Hertz deck input/hertz/iga_hrz.inp (NURBS only: one block) and the mixed deck
tests/scripts/xdmf_mixed.inp (a Q8 block and a NURBS patch) into --work, then:
  * the sidecar's structure: one block -> one Uniform grid per step (no spatial collection),
    several -> a spatial collection per step; every vector attribute has 3 components;
  * /fields/<step>/[viz_]<field>_3d is the 2-component dataset bit for bit, with z = 0;
  * meshio.xdmf.TimeSeriesReader, run from another folder on the absolute path and from the
    sidecar's folder on its bare name, reads hertz.xdmf, mixed.q8.xdmf and mixed.iga.xdmf
    (meshio reads one mesh per file): points, cells, the times, and displacement and velocity
    of every step equal the HDF5 datasets exactly, with z = 0.
Prints "N passed, N failed"; exit 1 on any failure.
"""
import argparse
import os
import xml.etree.ElementTree as ET

import numpy as np

import xdmf_common as xc


def check_structure(c, xdmf, nblocks):
    c.check(os.path.exists(xdmf), f"{os.path.basename(xdmf)} written")
    if not os.path.exists(xdmf):
        return
    root = ET.parse(xdmf).getroot()
    series = root.find("Domain/Grid")
    c.check(series is not None and series.get("CollectionType") == "Temporal",
            f"{os.path.basename(xdmf)}: a temporal collection")
    steps = list(series.findall("Grid"))
    if nblocks == 1:
        c.check(all(g.get("GridType") == "Uniform" and g.find("Time") is not None
                    for g in steps), f"{os.path.basename(xdmf)}: one Uniform grid per step")
    else:
        c.check(all(g.get("CollectionType") == "Spatial" and len(g.findall("Grid")) == nblocks
                    for g in steps),
                f"{os.path.basename(xdmf)}: a spatial collection of {nblocks} grids per step")
    dims = [a.find("DataItem").get("Dimensions").split()[-1] for a in root.iter("Attribute")
            if a.get("AttributeType") == "Vector"]
    c.check(len(dims) > 0 and set(dims) == {"3"},
            f"{os.path.basename(xdmf)}: every vector attribute has 3 components")
    paths = [d.text.split(":")[0] for d in root.iter("DataItem")]
    c.check(all("/" not in p for p in paths),
            f"{os.path.basename(xdmf)}: the HDF5 file is named without a folder")


def check_padded(c, h5):
    bad = []
    for step, _ in xc.snapshots(h5):
        for _, _, _, prefix in xc.blocks(h5):
            for name in ("displacement", "velocity"):
                try:
                    a = xc.field(h5, step, prefix + name)
                    b = xc.field(h5, step, prefix + name + "_3d")
                except KeyError:
                    bad.append(f"{step}/{prefix}{name}_3d missing")
                    continue
                if not (b.shape == (a.shape[0], 3) and np.array_equal(b[:, :2], a)
                        and not np.any(b[:, 2])):
                    bad.append(f"{step}/{prefix}{name}")
    c.check(not bad, f"{os.path.basename(h5)}: every *_3d dataset is its 2-component "
            "dataset with z = 0", ", ".join(bad[:5]))


def check_meshio(c, xdmf, h5, block, cwd, name):
    """meshio reads the single-block sidecar `xdmf` (opened as `name` from folder `cwd`)."""
    import meshio
    label = f"meshio {name} (from {'its folder' if cwd == os.path.dirname(xdmf) else cwd})"
    bname, conn, pts, prefix = block
    here = os.getcwd()
    os.chdir(cwd)
    try:
        with meshio.xdmf.TimeSeriesReader(name) as r:
            points, cells = r.read_points_cells()
            c.check(np.array_equal(points, pts), f"{label}: points = the block's geometry")
            c.check(len(cells) == 1 and np.array_equal(cells[0].data, conn),
                    f"{label}: cells = the block's connectivity")
            snaps = xc.snapshots(h5)
            c.check(r.num_steps == len(snaps), f"{label}: {len(snaps)} steps")
            bad = []
            for k, (step, time) in enumerate(snaps):
                t, pd, _ = r.read_data(k)
                if t != time:
                    bad.append(f"time of {step}")
                for f in ("displacement", "velocity"):
                    want = xc.field(h5, step, prefix + f)
                    got = pd.get(f)
                    if got is None or got.shape != (len(want), 3) or \
                            not np.array_equal(got[:, :2], want) or np.any(got[:, 2]):
                        bad.append(f"{f} of {step}")
                if not prefix:
                    # finite-element blocks also show the von Mises stress at the nodes
                    want = xc.field(h5, step, "nodal_mises")
                    got = pd.get("mises")
                    if got is None or not np.array_equal(np.ravel(got), want):
                        bad.append(f"mises of {step}")
            c.check(not bad, f"{label}: time, displacement and velocity (and the nodal von "
                    "Mises stress of FE blocks) of every step equal the HDF5 datasets (z = 0)",
                    ", ".join(bad[:5]))
            bad = []
            for k, (step, _) in enumerate(snaps):
                _, _, cd = r.read_data(k)
                got = cd.get("element_mises")
                want = block_cells(h5, step, bname, len(conn), "mises")
                if got is None or not np.array_equal(np.ravel(got[0]), want):
                    bad.append(f"element_mises of {step}")
                got = cd.get("stress")
                want = block_cells(h5, step, bname, len(conn), "stress")
                if got is None or not np.array_equal(np.asarray(got[0]).reshape(want.shape),
                                                     want):
                    bad.append(f"stress of {step}")
            c.check(not bad, f"{label}: the cell fields element_mises and stress (4 components) "
                    "of every step are the per-element values of the block's elements (NURBS: "
                    "of the element of each viewing cell)", ", ".join(bad[:5]))
    except Exception as e:  # a reader error is a failed check, the others still run
        c.check(False, f"{label}: read", repr(e))
    finally:
        os.chdir(here)


def block_cells(h5, step, bname, ncells, name):
    """The per-element dataset `name` (model order) on the cells of block `bname`: the test
    decks have one FE type, whose elements come first in model order, then the NURBS spans,
    each shown on the same number of viewing cells."""
    import h5py
    vals = xc.field(h5, step, name)
    with h5py.File(h5, "r") as f:
        fe = [t for t in f["model/elements"] if t != "iga"]
        assert len(fe) <= 1
        nfe = len(f[f"model/elements/{fe[0]}/ids"]) if fe else 0
    if bname != "iga":
        return vals[:nfe]
    spans = vals[nfe:]
    return np.repeat(spans, ncells // len(spans), axis=0)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ictus", required=True)
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    work = os.path.abspath(a.work)
    h5 = xc.run_decks(a.ictus, work)
    c = xc.Counter()
    elsewhere = os.path.dirname(work)
    for run, path in h5.items():
        blocks = xc.blocks(path)
        xdmf = path[:-3] + ".xdmf"
        check_structure(c, xdmf, len(blocks))
        check_padded(c, path)
        if len(blocks) == 1:
            sidecars = [(xdmf, blocks[0])]
        else:
            sidecars = [(path[:-3] + f".{b[0]}.xdmf", b) for b in blocks]
            for x, b in sidecars:
                check_structure(c, x, 1)
        for x, b in sidecars:
            check_meshio(c, x, path, b, elsewhere, x)
            check_meshio(c, x, path, b, work, os.path.basename(x))
    check_cell_fields(c, a.ictus, work)
    c.finish()


def check_cell_fields(c, ictus, work):
    """A model of one FE block (input/hertz/q8_hrz.inp) also shows the per-element von Mises
    stress as a cell field; meshio reads it equal to the HDF5 dataset. The model is elastic, so
    by default its snapshots hold no PEEQ, and the sidecar shows none."""
    import meshio
    import subprocess
    deck = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "input",
                        "hertz", "q8_hrz.inp")
    out = os.path.join(work, "q8_hrz.h5")
    subprocess.run([ictus, deck, "-o", out, "--quiet"], check=True)
    with meshio.xdmf.TimeSeriesReader(out[:-3] + ".xdmf") as r:
        r.read_points_cells()
        bad = []
        for k, (step, _) in enumerate(xc.snapshots(out)):
            _, _, cd = r.read_data(k)
            got = cd.get("element_mises")
            if got is None or not np.array_equal(np.ravel(got[0]),
                                                 xc.field(out, step, "mises")):
                bad.append(f"element_mises of {step}")
            if "peeq" in cd:
                bad.append(f"peeq shown at {step}")
    c.check(not bad, "meshio q8_hrz.xdmf: the cell field element_mises of every step equals "
            "the HDF5 dataset, and no peeq is shown (an elastic model)", ", ".join(bad[:5]))


if __name__ == "__main__":
    main()
