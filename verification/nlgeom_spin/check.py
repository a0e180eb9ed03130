#!/usr/bin/env python3
"""Objectivity in a run: a free body spun with NLGEOM keeps its shape (doc/theory.md §2, §4).

Square body [-0.5, 0.5]^2, plane strain, rho = 1, E = 1e6, nu = 0.3, no supports, initial velocity
of a rigid spin v = omega (-y, x), omega = 1, run to a quarter turn t = pi/2; Q8 elements (8 x 8,
HRZ mass) and one quadratic NURBS patch (8 x 8 spans, HRZ mass). Expected values:
- the centrifugal strain is of order rho omega^2 a^2 / E = 1e-6, so every distance between two
  nodes (control points: a NURBS body moves its control points with it) keeps its length to
  1e-5 relative, and the body has turned by omega t = pi/2;
- the discrete angular momentum sum m x(t_n) x v_n of central differences with a diagonal mass
  is conserved exactly (objective internal forces are torque-free), so it stays at its initial
  value to 1e-12 at every field snapshot; the linear momentum stays 0;
- with small-strain kinematics (NLGEOM=NO) the same run enlarges the body by
  sqrt(1 + (pi/2)^2) = 1.862: the failure this test exists for, checked here too;
- a soft square (E = 1, h = 0.25) whose corner node is thrown towards the centre at 5000
  crosses its element within a few steps of dt = 1e-4, faster than the stable step can follow
  (it is estimated every 10 steps): the element inverts, the run stops with exit 2, naming
  it, and the results written so far stay readable (verification/stable_step follows a
  gradual collapse instead).
"""
import math
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

OMEGA = 1.0
MATERIAL = "*MATERIAL, NAME=MAT\n*ELASTIC\n1e6, 0.3\n*DENSITY\n1.0\n"


def step(nlgeom):
    flag = ", NLGEOM=YES" if nlgeom else ""
    return (f"*MASS, TYPE=HRZ\n*STEP{flag}\n*DYNAMIC, EXPLICIT\n0, {math.pi / 2}\n"
            "*OUTPUT, HISTORY, EVERY=100\n*OUTPUT, FIELD, EVERY=2000\n*END STEP\n")


def spin_velocities(points):
    """*INITIAL CONDITIONS lines: v = omega (-y, x) at every (id, x, y)."""
    lines = ["*INITIAL CONDITIONS, TYPE=VELOCITY"]
    for i, x, y in points:
        lines.append(f"{i}, 1, {-OMEGA * y!r}")
        lines.append(f"{i}, 2, {OMEGA * x!r}")
    return "\n".join(lines) + "\n"


def q8_deck(nlgeom):
    mesh = vcheck.rect_mesh(type="Q8", nx=8, ny=8, lx=1.0, ly=1.0, x0=-0.5, y0=-0.5)
    return ("*HEADING\nspinning Q8 square\n" + MATERIAL + mesh
            + spin_velocities(vcheck.mesh_points(mesh))
            + step(nlgeom))


def nurbs_deck(nlgeom, spans=8):
    """One quadratic patch on the square: uniform knots, control points at the Greville
    abscissae (an affine map), ids 1..n^2 in patch order."""
    cards, pts = vcheck.square_patch("BODY", spans, offset=-0.5)
    return ("*HEADING\nspinning NURBS square\n" + MATERIAL + cards
            + spin_velocities(pts) + step(nlgeom))


def crush_deck():
    mesh = vcheck.rect_mesh(type="Q4", nx=4, ny=4, lx=1.0, ly=1.0, x0=-0.5, y0=-0.5)
    ic = ["*INITIAL CONDITIONS, TYPE=VELOCITY"]
    for i, x, y in vcheck.mesh_points(mesh):
        if x == -0.5 and y == -0.5:
            ic += [f"{i}, 1, 5000.0", f"{i}, 2, 5000.0"]
    return ("*HEADING\ncrushed square\n*MATERIAL, NAME=MAT\n*ELASTIC\n1.0, 0.3\n*DENSITY\n1.0\n"
            + mesh + "\n".join(ic) + "\n*MASS, TYPE=HRZ\n*STEP, NLGEOM=YES\n"
            "*DYNAMIC, EXPLICIT\n1e-4, 0.1\n*OUTPUT, HISTORY, EVERY=1\n*END STEP\n")


def run(args, name, text):
    path = os.path.join(args.work, name + ".inp")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(args.work, name + ".h5")
    _, log = vcheck.run_ictus(args, path, out)
    return vcheck.Results(out), log


def distances(x):
    d = x[:, None, :] - x[None, :, :]
    return np.sqrt((d ** 2).sum(axis=2))


def check_spin(chk, tag, res):
    x0 = res.model("coordinates")[:, :2]
    m = res.model("mass")
    steps = res.field_steps()
    l0 = None
    worst_l, worst_p = 0.0, 0.0
    for s in steps:
        x = x0 + res.field(s, "displacement")[:, :2]
        v = res.field(s, "velocity")[:, :2]
        lz = np.sum(m * (x[:, 0] * v[:, 1] - x[:, 1] * v[:, 0]))
        if l0 is None:
            l0 = lz
            i0 = OMEGA * np.sum(m * (x0 ** 2).sum(axis=1))
            chk.close(lz, i0, 1e-12, f"{tag}: initial angular momentum = omega sum m r^2")
        worst_l = max(worst_l, abs(lz - l0) / abs(l0))
        worst_p = max(worst_p, np.abs(m @ v).max() / (abs(l0)))
    chk.below(worst_l, 1e-12, f"{tag}: angular momentum conserved over {len(steps)} snapshots")
    chk.below(worst_p, 1e-12, f"{tag}: linear momentum stays 0")
    last = steps[-1]
    t = res.field_time(last)
    chk.close(t, math.pi / 2, 1e-3, f"{tag}: the run reaches a quarter turn")
    x = x0 + res.field(last, "displacement")[:, :2]
    d0, d1 = distances(x0), distances(x)
    mask = d0 > 0
    chk.below(np.max(np.abs(d1[mask] - d0[mask]) / d0[mask]), 1e-5,
              f"{tag}: every node-to-node distance kept to 1e-5 after a quarter turn")
    angle = np.arctan2(np.sum(m * (x0[:, 0] * x[:, 1] - x0[:, 1] * x[:, 0])),
                       np.sum(m * (x0 * x).sum(axis=1)))
    chk.close(angle, OMEGA * t, 1e-4, f"{tag}: turned by omega t")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("nlgeom_spin")
    for tag, deck in (("Q8", q8_deck), ("NURBS p = 2", nurbs_deck)):
        res, log = run(args, tag.split()[0].lower() + "_nlgeom", deck(True))
        chk.true("internal force: element loop" in log, f"{tag}: NLGEOM takes the element loop")
        check_spin(chk, tag, res)
        res, _ = run(args, tag.split()[0].lower() + "_small", deck(False))
        x0 = res.model("coordinates")[:, :2]
        x = x0 + res.field(res.field_steps()[-1], "displacement")[:, :2]
        growth = np.sqrt(((x ** 2).sum(axis=1)).max() / ((x0 ** 2).sum(axis=1)).max())
        chk.close(growth, math.sqrt(1 + (math.pi / 2) ** 2), 2e-3,
                  f"{tag}, small strain: the body grows by sqrt(1 + (pi/2)^2) = 1.862")
    path = os.path.join(args.work, "crush.inp")
    with open(path, "w") as f:
        f.write(crush_deck())
    out = os.path.join(args.work, "crush.h5")
    _, log = vcheck.run_ictus(args, path, out, expect_status=2)
    chk.true(re.search(r"Q4 element \d+ is inverted \(det F <= 0", log) is not None,
             "crushed square: exit 2 naming the inverted element")
    res = vcheck.Results(out)
    chk.true(res.attr("status").startswith("failed") and len(res.history("time")) > 0
             and res.history("time")[-1] < 1e-3,
             "crushed square: the results so far are readable, status failed before t = 1e-3")
    chk.finish()


if __name__ == "__main__":
    main()
