#!/usr/bin/env python3
"""The results file holds every path of layout version 1 (doc/results.md) that applies without
contact, with the documented shapes and meanings, and the processed deck reads back as a deck:
scripts/deck_from_results.py writes it out (the `deck` attribute with the data lines of its
/deck groups), and running that deck gives the same results bit for bit and the same record
again. A second deck has what the first lacks: two element blocks, a NURBS patch, node and
element sets with ids, names and GENERATE, and coordinates with long decimal expansions.
"""
import os
import shutil
import subprocess
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
DECK_FROM_RESULTS = os.path.join(ROOT, "scripts", "deck_from_results.py")

DECK = ("*HEADING\nlayout check\n*ANALYSIS, TYPE=PLANE STRAIN\n" + vcheck.material_block()
        + vcheck.rect_mesh(type="Q8", nx=4, ny=2, lx=2.0, ly=1.0)
        + "*BOUNDARY\nLEFT, 1, 2\n*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 1, 0.5\n"
        + "*STEP\n*DYNAMIC, EXPLICIT\n0, 0.05\n*OUTPUT, HISTORY, EVERY=2\n"
        + "*OUTPUT, FIELD, EVERY=10\n*END STEP\n")

# two blocks (Q4 beside Q8, sharing no nodes), a patch above them, sets of every kind
MIXED = ("*HEADING\nrecord check\n*ANALYSIS, TYPE=PLANE STRESS, THICKNESS=0.1\n"
         + vcheck.material_block()
         + vcheck.rect_mesh(type="Q4", nx=3, ny=2, lx=1.0 / 3.0, ly=0.7, distort=0.2,
                            elset="LEFTB", prefix="A_")
         + vcheck.rect_mesh(type="Q8", nx=2, ny=2, lx=0.3, ly=0.7, x0=2.0 / 3.0,
                            first_node=101, first_element=101, elset="RIGHTB", prefix="B_",
                            distort=0.1)
         + "*PATCH, NAME=TOPP, MATERIAL=MAT, DEGREE=2,1, SIZE=3,2\n"
         + "*KNOTS, DIRECTION=1\n0, 0, 0, 1, 1, 1\n*KNOTS, DIRECTION=2\n0, 0, 1, 1\n"
         + "*CONTROL POINTS\n0, 1, 1\n0.5, 1.1, 0.7071067811865476\n1, 1, 1\n"
         + "0, 1.3, 1\n0.5, 1.4, 0.7071067811865476\n1, 1.3, 1\n"
         + "*REFINE, PATCH=TOPP, SUBDIVIDE=2,1\n"
         + "*NSET, NSET=FIXED\nA_LEFT, B_BOTTOM\n1, 2, 3\n"
         + "*NSET, NSET=SOME, GENERATE\n101, 121, 4\n"
         + "*ELSET, ELSET=ALL\nLEFTB, RIGHTB\n*ELSET, ELSET=FEW\n1, 5, 101\n"
         + "*BOUNDARY\nFIXED, 1, 2\n*INITIAL CONDITIONS, TYPE=VELOCITY\nALL, 1, 0.25\n"
         + "TOPP, 2, -0.5\nSOME, 2, 0.125\n"
         + "*STEP\n*DYNAMIC, EXPLICIT\n0, 0.02\n*OUTPUT, HISTORY, EVERY=1\n"
         + "*OUTPUT, FIELD, EVERY=5\n*END STEP\n")


def datasets(f, top):
    """{path: array} of every dataset below group `top` of an open results file."""
    out = {}
    f[top].visititems(lambda n, o: out.__setitem__(top + "/" + n, o[()])
                      if hasattr(o, "shape") else None)
    return out


def round_trip(args, chk, r, name, log_label):
    """Writes the deck of results r with scripts/deck_from_results.py, runs it and checks
    that the history, the fields, the record (the `deck` attribute) and its /deck data come
    out the same bits. Returns the text of the deck written."""
    again = os.path.join(args.work, name + "_processed.inp")
    p = subprocess.run([sys.executable, DECK_FROM_RESULTS, r.f.filename, "-o", again],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    chk.true(p.returncode == 0, f"{log_label}: deck_from_results.py runs"
             + (f" ({p.stdout.strip()})" if p.returncode else ""))
    out2 = os.path.join(args.work, name + "_processed.h5")
    vcheck.run_ictus(args, again, out2)
    r2 = vcheck.Results(out2)
    a, b = datasets(r.f, "history"), datasets(r2.f, "history")
    chk.true(a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a),
             f"{log_label}: the deck written out reproduces the history bit for bit")
    a, b = datasets(r.f, "fields"), datasets(r2.f, "fields")
    chk.true(len(a) > 0 and a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a),
             f"{log_label}: ... and every field snapshot")
    chk.true(r2.attr("deck") == r.attr("deck"), f"{log_label}: ... and the same record")
    a, b = datasets(r.f, "deck"), datasets(r2.f, "deck")
    chk.true(len(a) > 0 and a.keys() == b.keys()
             and all(a[k].dtype == b[k].dtype and np.array_equal(a[k], b[k]) for k in a),
             f"{log_label}: ... and the same /deck data ({len(a)} datasets)")
    return open(again).read()


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("results_layout")
    path = os.path.join(args.work, "layout.inp")
    with open(path, "w") as f:
        f.write(DECK)
    out = os.path.join(args.work, "layout.h5")
    _, log = vcheck.run_ictus(args, path, out)
    r = vcheck.Results(out)
    f = r.f
    for a in ("program", "version", "format_version", "title", "analysis", "ranks", "deck",
              "status"):
        chk.true(a in f.attrs, f"root attribute {a}")
    chk.true(r.attr("program") == "ictus", "program = ictus")
    chk.true(int(r.attr("format_version")) == 1, "format_version = 1")
    chk.true(r.attr("analysis") == "plane strain", "analysis = plane strain")
    chk.true(r.attr("title") == "layout check", "title from *HEADING")
    chk.true(int(r.attr("ranks")) == 1, "ranks = 1")
    chk.true(r.attr("status") == "completed", "status = completed")
    nn = (2 * 4 + 1) * (2 * 2 + 1) - 4 * 2  # Q8 nodes of a 4 x 2 mesh (no centre nodes)
    chk.true(f["model/coordinates"].shape == (nn, 2), "/model/coordinates (n, 2)")
    chk.true(f["model/weights"].shape == (nn,), "/model/weights (n)")
    chk.true(np.all(np.asarray(f["model/weights"]) == 1.0), "FE weights are 1")
    chk.true(f["model/mass"].shape == (nn,), "/model/mass (n)")
    chk.close(float(np.sum(f["model/mass"])), 2.0, 1e-12, "sum of nodal masses = rho * area")
    nt = f["history/time"].shape[0]
    for k in ("time", "dt", "energy/kinetic", "energy/strain", "energy/contact",
              "energy/external_work", "energy/total"):
        chk.true(f["history/" + k].shape == (nt,), f"/history/{k} ({nt})")
    t, dt = np.asarray(f["history/time"]), np.asarray(f["history/dt"])
    chk.close(float(t[1] - t[0]), float(2 * dt[0]), 1e-12, "history every 2 steps")
    chk.true(t[-1] >= 0.05 - 1e-12 and t[-1] - 0.05 < dt[-1], "last record at t_end")
    e = {k: np.asarray(f["history/energy/" + k]) for k in
         ("kinetic", "strain", "contact", "external_work", "total")}
    # the energies against values formed outside the history writer: at t = 0 the body moves
    # at v0 = 0.5 in x except the fixed LEFT nodes, with no strain, contact or external work,
    # so total = kinetic = 1/2 v0^2 (rho area - mass of LEFT); at every snapshot the kinetic
    # energy is 1/2 sum m |v|^2 of the velocity field (the mean velocity v_n of both)
    m = np.asarray(f["model/mass"])
    x = np.asarray(f["model/coordinates"])
    left = np.abs(x[:, 0]) < 1e-12
    chk.true(int(np.sum(left)) == 5, "LEFT holds the 5 nodes at x = 0")
    e0 = 0.5 * 0.5 ** 2 * (1.0 * 2.0 * 1.0 - float(np.sum(m[left])))
    chk.close(float(e["total"][0]), e0, 1e-12, "total at t = 0 = 1/2 v0^2 (rho area - m_LEFT)")
    chk.close(float(e["kinetic"][0]), e0, 1e-12, "kinetic at t = 0 = 1/2 v0^2 (rho area - m_LEFT)")
    chk.true(e["strain"][0] == 0.0 and e["contact"][0] == 0.0 and e["external_work"][0] == 0.0,
             "strain, contact and external work 0 at t = 0")
    steps = r.field_steps()
    worst = 0.0
    for s in steps:
        v = np.asarray(f["fields/" + s + "/velocity"])
        k = int(np.argmin(np.abs(t - r.field_time(s))))
        chk.true(abs(t[k] - r.field_time(s)) < 1e-12, f"/fields/{s} has a history record")
        worst = max(worst, abs(0.5 * float(np.sum(m * np.sum(v ** 2, axis=1))) - e["kinetic"][k])
                    / e0)
    chk.below(worst, 1e-12, "kinetic energy = 1/2 sum m |v|^2 of the velocity field at every "
              "snapshot, relative to E0")
    chk.true(len(steps) >= 2 and all(len(s) == 8 for s in steps), "/fields/<step> zero-padded to 8")
    for s in steps:
        g = f["fields/" + s]
        chk.true(int(g.attrs["step"]) == int(s) and "time" in g.attrs, f"/fields/{s} attributes")
        chk.true(g["displacement"].shape == (nn, 2) and g["velocity"].shape == (nn, 2),
                 f"/fields/{s} displacement and velocity (n, 2)")
    xdmf = out[:-3] + ".xdmf"
    chk.true(os.path.exists(xdmf) and "Quadrilateral_8" in open(xdmf).read(), "XDMF sidecar")
    # the record: every card and parameter line, marker lines for the bulk data
    deck = r.attr("deck")
    chk.true("*ELEMENT, TYPE=Q8, MATERIAL=MAT, ELSET=BODY, GAUSS=3\n"
             "** data: /deck/elements/1, 8 lines\n" in deck, "record: element marker line")
    chk.true(f"*NODE\n** data: /deck/nodes, {nn} lines\n" in deck, "record: node marker line")
    nodes = f["deck/nodes"]
    chk.true(np.array_equal(nodes["coordinates"][()], f["model/coordinates"][()]),
             "/deck/nodes/coordinates: the deck's coordinates, the same doubles as /model")
    chk.true(nodes["ids"].dtype.kind == "i" and np.array_equal(nodes["ids"][()],
                                                                f["model/node_ids"][()]),
             "/deck/nodes/ids: the node ids (integers)")
    # the processed deck is a deck: run it again and get the same results
    text = round_trip(args, chk, r, "layout", "Q8 deck")
    chk.true("** data:" not in text and "*NODE\n1, 0.0, 0.0\n" in text,
             "the deck written out has the data lines in place of the markers")
    chk.true("processed deck" in log, "processed deck printed in the log")
    # the second deck: blocks, a patch, sets of ids, names and GENERATE
    path = os.path.join(args.work, "mixed.inp")
    with open(path, "w") as fh:
        fh.write(MIXED)
    out = os.path.join(args.work, "mixed.h5")
    vcheck.run_ictus(args, path, out)
    rm = vcheck.Results(out)
    deck = rm.attr("deck")
    for marker in ("/deck/elements/1, 6 lines", "/deck/elements/2, 4 lines",
                   "/deck/control_points/1, 6 lines"):
        chk.true("** data: " + marker in deck, "record: " + marker)
    cp = rm.f["deck/control_points/1/control_points"][()]
    chk.true(cp.shape == (6, 3) and cp[1, 2] == 0.7071067811865476,
             "/deck/control_points/1: x, y, w rows as given")
    some = [k for k in rm.f["deck/sets"] if list(rm.f[f"deck/sets/{k}/ids"][()])
            == list(range(101, 122, 4))]
    chk.true(len(some) == 1, "*NSET GENERATE stored expanded")
    text = round_trip(args, chk, rm, "mixed", "mixed deck")
    chk.true("A_LEFT, B_BOTTOM" in text and "LEFTB, RIGHTB" in text,
             "set names stay text lines")
    # a record whose data group is missing: a one-line message, exit status 1
    broken = os.path.join(args.work, "broken.h5")
    shutil.copy(out, broken)
    with h5py.File(broken, "r+") as fh:
        del fh["deck/elements/2"]
    p = subprocess.run([sys.executable, DECK_FROM_RESULTS, broken], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True)
    chk.true(p.returncode == 1 and p.stdout == "" and "/deck/elements/2" in p.stderr
             and len(p.stderr.strip().splitlines()) == 1,
             "a missing data group: one line naming it, exit status 1: " + p.stderr.strip())
    chk.finish()


if __name__ == "__main__":
    main()
