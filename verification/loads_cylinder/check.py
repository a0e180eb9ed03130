#!/usr/bin/env python3
"""A thick cylinder under inner pressure (*DLOAD, P), relaxed to its static state
(doc/reference.md §3.6: the Lamé solution).

Quarter annulus a = 1 <= r <= 2, plane strain, E = 1000, nu = 0.3, rho = 1, symmetry
conditions u_y = 0 on y = 0 and u_x = 0 on x = 0, inner pressure p = 1 (positive pushes into
the body) ramped by a SMOOTH STEP amplitude over [0, 0.5] and relaxed with *DAMPING, ALPHA=40
to t = 2.5. The static radial displacement (Lamé, plane strain):

    u_r(r) = p a^2 / (E (b^2 - a^2)) (1 + nu) ((1 - 2 nu) r + b^2 / r)

checked at every node within 0.5 % of u_r(a) for
- Q8 elements (4 radial x 8 circumferential, nodes on the circles), the pressure on the faces
  S4 of the inner elements;
- a NURBS patch of degree 2 (the exact circle: weights 1, 1/sqrt 2, 1 in the circumferential
  direction), elevated to 2, 2 and refined to 4 x 8 spans, the pressure on its side XI0
  (control points of a side are not on the body: the check takes the patch's points of the
  viewing samples on the body instead of control points).
The reactions on each symmetry line balance the pressure on the arc: sum R_x (x = 0) = -p a
and sum R_y (y = 0) = -p a, to 1e-6 (the integral of p n over the arc depends only on its end
points, so it is exact for the quadratic element edges and the NURBS side alike; what is left
is the residual of the relaxation). The processed deck of each (the echo of *AMPLITUDE and
*DLOAD) reruns bit for bit.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

A, B, E, NU, P = 1.0, 2.0, 1000.0, 0.3, 1.0
NR, NT = 4, 8


def u_lame(r):
    return P * A ** 2 / (E * (B ** 2 - A ** 2)) * (1 + NU) * ((1 - 2 * NU) * r + B ** 2 / r)


def common_tail():
    return ("*AMPLITUDE, NAME=RAMP, DEFINITION=SMOOTH STEP\n0, 0, 0.5, 1\n*DAMPING, ALPHA=40\n"
            "*STEP\n*DYNAMIC, EXPLICIT\n0, 2.5\n*DLOAD, AMPLITUDE=RAMP\nINNER, P, 1.0\n"
            "*OUTPUT, HISTORY, EVERY=100\n*OUTPUT, FIELD, EVERY=1000000, VARIABLES=U,V,S,MISES,RF\n*END STEP\n")


def q8_deck():
    ids, nodes = {}, []
    for j in range(2 * NT + 1):
        for i in range(2 * NR + 1):
            if i % 2 == 1 and j % 2 == 1:
                continue
            r = A + (B - A) * i / (2 * NR)
            th = 0.5 * math.pi * j / (2 * NT)
            ids[(i, j)] = len(nodes) + 1
            nodes.append(f"{len(nodes) + 1}, {r * math.cos(th)!r}, {r * math.sin(th)!r}")
    els, inner = [], []
    for j in range(NT):
        for i in range(NR):
            a, b = 2 * i, 2 * j
            c = [ids[(a, b)], ids[(a + 2, b)], ids[(a + 2, b + 2)], ids[(a, b + 2)],
                 ids[(a + 1, b)], ids[(a + 2, b + 1)], ids[(a + 1, b + 2)], ids[(a, b + 1)]]
            els.append(f"{len(els) + 1}, " + ", ".join(map(str, c)))
            if i == 0:
                inner.append(len(els))
    xsym = [n for (i, j), n in ids.items() if j == 2 * NT]
    ysym = [n for (i, j), n in ids.items() if j == 0]
    return ("*HEADING\nthick cylinder under inner pressure, Q8\n"
            "*ANALYSIS, TYPE=PLANE STRAIN, THICKNESS=1\n"
            + vcheck.material_block(e=E, nu=NU, rho=1.0)
            + "*NODE\n" + "\n".join(nodes) + "\n"
            + "*ELEMENT, TYPE=Q8, ELSET=CYL, MATERIAL=MAT\n" + "\n".join(els) + "\n"
            + "*NSET, NSET=XSYM\n" + ", ".join(map(str, xsym)) + "\n"
            + "*NSET, NSET=YSYM\n" + ", ".join(map(str, ysym)) + "\n"
            + "*SURFACE, NAME=INNER, TYPE=ELEMENT\n" + "".join(f"{e}, S4\n" for e in inner)
            + "*BOUNDARY\nXSYM, 1, 1\nYSYM, 2, 2\n" + common_tail())


def iga_deck():
    w = 1 / math.sqrt(2)
    cps = []
    for j, (cx, cy, wt) in enumerate(((1, 0, 1.0), (1, 1, w), (0, 1, 1.0))):
        for r in (A, B):
            cps.append(f"{r * cx!r}, {r * cy!r}, {wt!r}")
    return ("*HEADING\nthick cylinder under inner pressure, NURBS\n"
            "*ANALYSIS, TYPE=PLANE STRAIN, THICKNESS=1\n"
            + vcheck.material_block(e=E, nu=NU, rho=1.0)
            + "*PATCH, NAME=CYL, MATERIAL=MAT, DEGREE=1,2, SIZE=2,3\n"
            "*KNOTS, DIRECTION=1\n0 0 1 1\n*KNOTS, DIRECTION=2\n0 0 0 1 1 1\n"
            "*CONTROL POINTS\n" + "\n".join(cps) + "\n"
            + f"*ELEVATE, PATCH=CYL, DEGREE=2,2\n*REFINE, PATCH=CYL, SUBDIVIDE={NR},{NT}\n"
            "*NSET, NSET=XSYM, PATCH=CYL, SIDE=ETA1\n*NSET, NSET=YSYM, PATCH=CYL, SIDE=ETA0\n"
            "*SURFACE, NAME=INNER, PATCH=CYL, SIDE=XI0\n"
            "*BOUNDARY\nXSYM, 1, 1\nYSYM, 2, 2\n" + common_tail())


def check(args, chk, label, text, iga):
    path = os.path.join(args.work, f"{label}.inp")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(args.work, f"{label}.h5")
    vcheck.run_ictus(args, path, out)
    res = vcheck.Results(out)
    last = res.field_steps()[-1]
    if iga:
        x = np.asarray(res.f["viz/iga/points"])
        u = res.field(last, "viz_displacement")
    else:
        x = res.model("coordinates")
        u = res.field(last, "displacement")
    r = np.hypot(x[:, 0], x[:, 1])
    ur = (u[:, 0] * x[:, 0] + u[:, 1] * x[:, 1]) / r
    err = float(np.max(np.abs(ur - u_lame(r)))) / u_lame(A)
    chk.below(err, 5e-3, f"{label}: u_r = Lamé at every point, relative to u_r(a) = "
              f"{u_lame(A):.6g}")
    chk.below(float(np.max(np.abs(res.field(last, "velocity")))) / u_lame(A), 1e-2,
              f"{label}: relaxed (velocities small)")
    x0 = res.model("coordinates")
    rf = res.field(last, "reaction")
    xs, ys = np.abs(x0[:, 0]) < 1e-12, np.abs(x0[:, 1]) < 1e-12
    chk.close(float(rf[xs, 0].sum()), -P * A, 1e-6, f"{label}: sum R_x on x = 0 = -p a")
    chk.close(float(rf[ys, 1].sum()), -P * A, 1e-6, f"{label}: sum R_y on y = 0 = -p a")
    chk.true(vcheck.processed_deck_reruns(args, out), f"{label}: the processed deck reruns bit "
             "for bit")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("loads_cylinder")
    check(args, chk, "q8", q8_deck(), False)
    check(args, chk, "iga", iga_deck(), True)
    chk.finish()


if __name__ == "__main__":
    main()
