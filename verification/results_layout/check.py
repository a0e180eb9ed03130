#!/usr/bin/env python3
"""The results file holds every path of layout version 1 (doc/results.md) that applies without
contact, with the documented shapes and meanings, and the processed deck reads back as a deck.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

DECK = ("*HEADING\nlayout check\n*ANALYSIS, TYPE=PLANE STRAIN\n" + vcheck.material_block()
        + vcheck.rect_mesh(type="Q8", nx=4, ny=2, lx=2.0, ly=1.0)
        + "*BOUNDARY\nLEFT, 1, 2\n*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 1, 0.5\n"
        + "*STEP\n*DYNAMIC, EXPLICIT\n0, 0.05\n*OUTPUT, HISTORY, EVERY=2\n"
        + "*OUTPUT, FIELD, EVERY=10\n*END STEP\n")


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
    # the processed deck is a deck: run it again and get the same history
    again = os.path.join(args.work, "processed.inp")
    with open(again, "w") as fh:
        fh.write(r.attr("deck"))
    out2 = os.path.join(args.work, "processed.h5")
    vcheck.run_ictus(args, again, out2)
    r2 = vcheck.Results(out2)
    chk.true(np.array_equal(np.asarray(r2.f["history/energy/total"]), e["total"]),
             "the stored processed deck reproduces the run bit for bit")
    chk.true("processed deck" in log, "processed deck printed in the log")
    chk.finish()


if __name__ == "__main__":
    main()
