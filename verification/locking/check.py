#!/usr/bin/env python3
"""Volumetric locking and the mean dilatation (doc/theory.md §2.1).

A unit square in plane strain on rollers (u_x = 0 on x = 0, 1; u_y = 0 on y = 0, 1), nearly
incompressible: nu = 0.4999, E = 2 (1 + nu) so that mu = 1, rho = 1 (lambda = 5000 mu). The
field phi = (sin(pi x) cos(pi y), -cos(pi x) sin(pi y)) is divergence-free, meets the rollers
and their zero shear traction, and mu lap(phi) = -2 pi^2 mu phi: it is an exact eigenmode of
Navier's equations with omega = pi sqrt(2 mu/rho) = 4.4429 whatever lambda is. Started with
the velocity 0.01 phi (consistent mass; at the nodes, or at the Greville points of the control points), the kinetic
energy is first 0 at t = pi/(2 omega); the check finds that time in /history/energy/kinetic
(parabola through the three records around the smallest) and compares omega:
- with the mean dilatation (DILATATION=MEAN) Q4, Q8, Q9 and a quadratic NURBS patch, 8 x 8,
  reproduce omega within 2 %;
- the fully integrated Q4 (DILATATION=FULL) locks: no discrete field is divergence-free at
  all its Gauss points, so the mode draws on lambda and omega comes out more than 50 % high;
- the default (AUTO) takes the mean dilatation for nu >= 0.49: its run is bit-identical to
  DILATATION=MEAN.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

NU = 0.4999
E = 2 * (1 + NU)
OMEGA = math.pi * math.sqrt(2.0)
MATERIAL = f"*MATERIAL, NAME=MAT\n*ELASTIC\n{E!r}, {NU!r}\n*DENSITY\n1.0\n"
STEP = ("*MASS, TYPE=CONSISTENT\n*STEP\n*DYNAMIC, EXPLICIT\n0, 0.5\n*OUTPUT, HISTORY, EVERY=1\n"
        "*OUTPUT, FIELD, EVERY=100000\n*END STEP\n")


def phi(x, y):
    return (math.sin(math.pi * x) * math.cos(math.pi * y),
            -math.cos(math.pi * x) * math.sin(math.pi * y))


def velocities(points):
    lines = ["*INITIAL CONDITIONS, TYPE=VELOCITY"]
    for i, x, y in points:
        vx, vy = phi(x, y)
        lines += [f"{i}, 1, {0.01 * vx!r}", f"{i}, 2, {0.01 * vy!r}"]
    return "\n".join(lines) + "\n"


def fe_deck(etype, dil):
    mesh = vcheck.rect_mesh(type=etype, nx=8, ny=8, lx=1.0, ly=1.0)
    if dil:
        mesh = mesh.replace(f"*ELEMENT, TYPE={etype}", f"*ELEMENT, TYPE={etype}, DILATATION={dil}")
    return (f"*HEADING\nroller square {etype}\n" + MATERIAL + mesh + velocities(vcheck.mesh_points(mesh))
            + "*BOUNDARY\nLEFT, 1, 1\nRIGHT, 1, 1\nBOTTOM, 2, 2\nTOP, 2, 2\n" + STEP)


def nurbs_deck(spans=8):
    cards, pts = vcheck.square_patch("BODY", spans, extra=", DILATATION=MEAN")
    return ("*HEADING\nroller square NURBS\n" + MATERIAL + cards + velocities(pts)
            + "*NSET, NSET=L, PATCH=BODY, SIDE=XI0\n*NSET, NSET=R, PATCH=BODY, SIDE=XI1\n"
            + "*NSET, NSET=B, PATCH=BODY, SIDE=ETA0\n*NSET, NSET=T, PATCH=BODY, SIDE=ETA1\n"
            + "*BOUNDARY\nL, 1, 1\nR, 1, 1\nB, 2, 2\nT, 2, 2\n" + STEP)


def measured_omega(res):
    """omega from the first minimum of the kinetic energy (t = pi/(2 omega))."""
    t, ke = res.history("time"), res.history("energy/kinetic")
    k = 1
    while k + 1 < len(ke) and not (ke[k] <= ke[k - 1] and ke[k] <= ke[k + 1]):
        k += 1
    a, b, _ = np.polyfit(t[k - 1:k + 2] - t[k], ke[k - 1:k + 2], 2)
    return math.pi / (2 * (t[k] - b / (2 * a)))


def run(args, name, text):
    path = os.path.join(args.work, name + ".inp")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(args.work, name + ".h5")
    vcheck.run_ictus(args, path, out)
    return out


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("locking")
    for et in ("Q4", "Q8", "Q9"):
        out = run(args, f"{et}_mean", fe_deck(et, "MEAN"))
        chk.close(measured_omega(vcheck.Results(out)), OMEGA, 0.02,
                  f"{et}, mean dilatation: omega of the isochoric mode")
    out = run(args, "nurbs_mean", nurbs_deck())
    chk.close(measured_omega(vcheck.Results(out)), OMEGA, 0.02,
              "NURBS p = 2, mean dilatation: omega of the isochoric mode")
    out = run(args, "Q4_full", fe_deck("Q4", "FULL"))
    w = measured_omega(vcheck.Results(out))
    print(f"  (fully integrated Q4: omega = {w:.4f}, {w / OMEGA:.2f} times the exact value)")
    chk.true(w > 1.5 * OMEGA, "Q4, full integration locks: omega more than 50 % high")
    auto = run(args, "Q4_auto", fe_deck("Q4", None))
    chk.true(vcheck.same_bits(auto, os.path.join(args.work, "Q4_mean.h5")),
             "Q4, nu = 0.4999, default: the mean dilatation (bit-identical to DILATATION=MEAN)")
    chk.finish()


if __name__ == "__main__":
    main()
