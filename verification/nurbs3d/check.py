#!/usr/bin/env python3
"""3D runs of trivariate NURBS patches (doc/iga.md §11) without contact, against physics.

1. Mass of the exact quarter-ball of scripts/mesh/quarter_ball.py --kind nurbs (R = 1,
   rho = 1; its rigid wall dropped): the sum of /model/mass (the lumped masses, or the row
   sums of the consistent mass: every scheme keeps the element mass) must be rho pi R^3/3 to
   1e-12 with HRZ and ROW SUM. The geometry is exact; only the quadrature errs: det J is
   rational, so the (p + 1)^3 Gauss points of a span integrate it exactly only in the limit,
   with an error falling like h^(2p+2) (measured: p = 2 on 8 x 16 x 8 spans 3.5e-10, p = 3
   on the same spans 1.7e-13), hence p = 3 (*ELEVATE) on 8 x 16 x 8 spans. The consistent
   mass (its conjugate gradient does not converge in 500 iterations on the degenerate p = 3
   ball, doc/iga.md §11) is checked on p = 2, 2 x 4 x 2 spans: its row sums total the HRZ
   total to 1e-14, and rho pi R^3/3 to the quadrature error there (6.5e-8).
   The patch is degenerate (its side XI0 collapses to the x axis segment, ZETA0 to the
   centre, where det J = 0); the Gauss points lie inside the spans, so none of them sees
   det J = 0 (doc/iga.md §11). The coincident control points of those sides are merged
   into one node each (2111 nodes of 2541 control points).
2. Patch test: a block [0, 1] x [0, 1.2] x [0, 0.9] as one trivariate patch of degree 2 with
   non-uniform knot vectors, refined by *REFINE (SUBDIVIDE=2,1,2). Its control points sit at
   the Greville abscissae of the knots (the geometry is the identity map of a linear
   parametrisation, x_i(u) = L_i u_i, but the control points are unevenly spaced). The
   control points on the boundary are given u = A x (*BOUNDARY, each with its value), the
   interior ones start at rest at 0, and mass-proportional damping relaxes the interior to
   the static solution, which is the linear field (in the span of every NURBS basis with
   these weights). Every element's stress must be sigma = lambda tr(eps) I + 2 mu eps,
   eps = (A + A^T)/2, to 1e-10 of |sigma|, and the interior control points at A x. The same
   block given a rigid translation u = c or a small rotation u = W x (W antisymmetric) must
   have zero stress (1e-10 of E max |u|, the block being of size about 1).
3. Free flight: the quarter-ball moving at -v e_z with nothing held: every control point
   (and every viewing sample) at u = -v t e_z to 1e-12.
4. Bit-identical results: the quarter-ball with its bottom held (u_z = 0 on the control
   points within 0.05 R of the contact point) with HRZ and with a consistent mass (MASS
   SOLVER=CG), on 1 and 2 ranks and continued from a checkpoint on 2 ranks, and its
   processed deck re-run (vcheck.check_ranks_and_restart, vcheck.processed_deck_reruns).
5. The XDMF sidecar: meshio reads the viewing samples as one block of hexahedra with the
   3-component displacement of /fields/<step>/viz_displacement; every cell has a positive
   volume. A model of hexahedra (C3D8) and a patch side by side: both in free flight, mass
   2 rho, and meshio reads each block's own sidecar.
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402
import quarter_ball  # noqa: E402  (scripts/mesh, on the path through vcheck)

E, NU, RHO, V = 1000.0, 0.25, 1.0, 0.1


# ---------------------------------------------------------------------------------------------
# The quarter-ball
# ---------------------------------------------------------------------------------------------

def ball_deck(subdivide, elevate=2, mass="HRZ", t_end=0.01, hold=(), extra=""):
    """quarter_ball.py --kind nurbs without its rigid wall; `hold`: node ids given u_z = 0."""
    a = quarter_ball.parser().parse_args(
        ["--kind", "nurbs", "--subdivide", str(subdivide), "--elevate", str(elevate),
         "--mass", mass, "--t-end", repr(t_end), "--rho", repr(RHO), "--v", repr(V)])
    quarter_ball.check_options(a)
    text = quarter_ball.deck(a, "quarter_ball.py --kind nurbs")
    text = re.sub(r"\*RIGID WALL[^\n]*\n[^\n]*\n", "", text)
    if hold:
        text = text.replace("*BOUNDARY\n", "*NSET, NSET=BOTTOM\n"
                            + ",\n".join(", ".join(map(str, hold[i:i + 8]))
                                         for i in range(0, len(hold), 8))
                            + "\n*BOUNDARY\nBOTTOM, 3, 3\n", 1)
    return text.replace("*END STEP", extra + "*END STEP")


def run(args, name, text):
    path = os.path.join(args.work, name + ".inp")
    with open(path, "w") as f:
        f.write(text)
    out = path.replace(".inp", ".h5")
    vcheck.run_ictus(args, path, out)
    return path, out, vcheck.Results(out)


def ball_mass(args, chk):
    total = {}
    for mass in ("HRZ", "ROW SUM"):
        _, _, r = run(args, "mass_" + mass.replace(" ", "_").lower(),
                      ball_deck(8, elevate=3, mass=mass, t_end=3e-6))
        if mass == "HRZ":
            chk.true(r.attr("analysis") == "3D" and int(r.attr("dimension")) == 3
                     and list(r.model("patches/ball/degree")) == [3, 3, 3]
                     and list(r.model("patches/ball/size")) == [11, 21, 11]
                     and len(r.model("elements/iga/ids")) == 8 * 16 * 8,
                     "ball mass: 3D results of one patch of degree 3,3,3, 11 x 21 x 11 "
                     "control points, 8 x 16 x 8 elements")
            # the collapsed sides XI0 (21 x 11 points on 11 points of the x axis) and ZETA0
            # (11 x 21 points at the centre) merged: 2541 - (231 + 231 - 21) + 11 nodes
            chk.true(len(r.model("node_ids")) == 2111, "ball: the coincident control points "
                     "of the collapsed sides XI0 and ZETA0 are one node each (2111 nodes)")
        chk.close(float(np.sum(r.model("mass"))), RHO * np.pi / 3.0, 1e-12,
                  f"ball mass {mass}, p = 3 on 8 x 16 x 8 spans: sum of the nodal masses = "
                  "rho pi R^3/3")
    # the consistent mass on the coarse ball of p = 2 (its conjugate gradient converges there,
    # doc/iga.md §11): the row sums give the same total as HRZ, the element masses
    for mass in ("HRZ", "CONSISTENT"):
        _, _, r = run(args, "coarse_mass_" + mass.lower(), ball_deck(2, mass=mass, t_end=1e-4))
        total[mass] = float(np.sum(r.model("mass")))
    chk.close(total["CONSISTENT"], total["HRZ"], 1e-14, "ball mass p = 2 on 2 x 4 x 2 spans: "
              "the row sums of the consistent mass sum to the HRZ total")
    chk.close(total["CONSISTENT"], RHO * np.pi / 3.0, 1e-6, "ball mass p = 2 on 2 x 4 x 2 "
              "spans: rho pi R^3/3 up to the quadrature (6.5e-8 measured)")


def free_flight(args, chk):
    for mass in ("HRZ", "CONSISTENT"):
        _, _, r = run(args, "flight_" + mass.lower(),
                      ball_deck(2, mass=mass, t_end=0.05,
                                extra="*OUTPUT, FIELD, EVERY=20\n"))
        last = r.field_steps()[-1]
        t = r.field_time(last)
        for name in ("displacement", "viz_displacement"):
            u = r.field(last, name)
            where = "control point" if name == "displacement" else "viewing sample"
            chk.below(float(np.max(np.abs(u - [0.0, 0.0, -V * t]))) / (V * t), 1e-12,
                      f"free flight {mass}: every {where} at u = -v t e_z")
        etot = r.history("energy/total")
        chk.below(float(np.max(np.abs(etot - RHO * np.pi / 6.0 * V * V))) / etot[0], 1e-6,
                  f"free flight {mass}: kinetic energy m v^2/2 (m of the 2 x 4 x 2 spans, "
                  "quadrature 1e-7)")


def held_ball(args, chk):
    _, _, r = run(args, "held_probe", ball_deck(2, t_end=1e-4))
    x = r.model("coordinates")
    ids = r.model("node_ids")
    low = sorted(int(i) for i in ids[x[:, 2] < 0.05])
    every = "*RESTART, WRITE, EVERY=5\n*OUTPUT, FIELD, EVERY=5\n"
    for mass in ("HRZ", "CONSISTENT"):
        label = f"held ball {mass}: "
        path, out, r = run(args, "held_" + mass.lower(),
                           ball_deck(2, mass=mass, t_end=0.1, hold=low, extra=every))
        etot = r.history("energy/total")
        chk.below(float(np.max(np.abs(etot - etot[0])) / etot[0]), 1e-2,
                  label + "energy conservation max |E(t) - E(0)|/E(0)")
        chk.true(float(np.max(r.history("energy/strain"))) > 1e-3 * etot[0],
                 label + "the held bottom strains the ball")
        vcheck.check_ranks_and_restart(args, chk, path, out, label=label)
        if mass == "HRZ":
            chk.true(vcheck.processed_deck_reruns(args, out),
                     label + "the processed deck of the results file re-runs bit for bit")


# ---------------------------------------------------------------------------------------------
# The patch test
# ---------------------------------------------------------------------------------------------

P = 2
KNOTS = ([0, 0, 0, 0.3, 0.45, 1, 1, 1], [0, 0, 0, 0.6, 1, 1, 1], [0, 0, 0, 0.2, 0.5, 0.7, 1, 1, 1])
SUB = (2, 1, 2)
LENGTH = (1.0, 1.2, 0.9)
A_FIELD = np.array([[1.0e-3, 2.0e-4, -3.0e-4],
                    [5.0e-4, -2.0e-3, 1.0e-4],
                    [-2.0e-4, 3.0e-4, 1.5e-3]])


def subdivided(knots, k):
    """The knot vector after *REFINE, SUBDIVIDE=k: every non-empty span cut into k."""
    u = list(knots)
    new = []
    for a, b in zip(u[:-1], u[1:]):
        if b > a:
            new += [a + (b - a) * j / k for j in range(1, k)]
    return sorted(u + new)


def greville(knots):
    return np.array([np.mean(knots[i + 1:i + P + 1]) for i in range(len(knots) - P - 1)])


def lattice(knots3):
    """Control points (n, 3) of the block at the Greville abscissae, direction 1 fastest,
    and the mask of those on its boundary."""
    g = [greville(k) * length for k, length in zip(knots3, LENGTH)]
    pts, edge = [], []
    for k, z in enumerate(g[2]):
        for j, y in enumerate(g[1]):
            for i, x in enumerate(g[0]):
                pts.append((x, y, z))
                edge.append(i in (0, len(g[0]) - 1) or j in (0, len(g[1]) - 1)
                            or k in (0, len(g[2]) - 1))
    return np.array(pts), np.array(edge)


def block_deck(motion, title):
    """The block patch; the boundary control points of the refined patch get u = motion(x)."""
    coarse, _ = lattice(KNOTS)
    fine, edge = lattice([subdivided(k, s) for k, s in zip(KNOTS, SUB)])
    sizes = [len(k) - P - 1 for k in KNOTS]
    bc = "".join(f"{n + 1}, {d + 1}, {d + 1}, {float(motion(fine[n])[d])!r}\n"
                 for n in np.nonzero(edge)[0] for d in range(3))
    return ("*HEADING\n" + title + "\n*ANALYSIS, TYPE=3D\n"
            + vcheck.material_block(e=E, nu=NU, rho=RHO)
            + f"*PATCH, NAME=BLOCK, MATERIAL=MAT, DEGREE={P},{P},{P}, "
            + f"SIZE={sizes[0]},{sizes[1]},{sizes[2]}\n"
            + "".join(f"*KNOTS, DIRECTION={d + 1}\n" + ", ".join(map(repr, map(float, k)))
                      + "\n" for d, k in enumerate(KNOTS))
            + "*CONTROL POINTS\n"
            + "".join(f"{x!r}, {y!r}, {z!r}, 1.0\n" for x, y, z in coarse)
            + f"*REFINE, PATCH=BLOCK, SUBDIVIDE={SUB[0]},{SUB[1]},{SUB[2]}\n"
            + "*BOUNDARY\n" + bc + "*DAMPING, ALPHA=150\n*STEP\n*DYNAMIC, EXPLICIT\n0, 1.5\n"
            + "*OUTPUT, FIELD, VARIABLES=U,S\n*OUTPUT, HISTORY, EVERY=100\n*END STEP\n"), fine


def patch_test(args, chk):
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    mu = E / (2 * (1 + NU))
    eps = 0.5 * (A_FIELD + A_FIELD.T)
    sig = lam * np.trace(eps) * np.eye(3) + 2 * mu * eps
    sig6 = np.array([sig[0, 0], sig[1, 1], sig[2, 2], sig[0, 1], sig[1, 2], sig[2, 0]])
    text, fine = block_deck(lambda x: A_FIELD @ x, "patch test, trivariate NURBS block")
    _, _, r = run(args, "patch", text)
    x = r.model("coordinates")
    chk.below(float(np.max(np.abs(x - fine))), 1e-14,
              "patch: the refined control points at the Greville abscissae of the refined "
              "knots (knot insertion keeps the linear geometry)")
    last = r.field_steps()[-1]
    s = r.field(last, "stress")
    chk.true(s.shape == (6 * 2 * 8, 6), "patch: 6 x 2 x 8 elements, 6 stress components")
    err = float(np.max(np.abs(s - sig6[None, :])) / np.max(np.abs(sig6)))
    chk.below(err, 1e-10, "patch: every element's stress is the exact uniform stress "
              "(max error / max |sigma|)")
    u = r.field(last, "displacement")
    uerr = float(np.max(np.abs(u - x @ A_FIELD.T)) / np.max(np.abs(x @ A_FIELD.T)))
    chk.below(uerr, 1e-10, "patch: interior control points at the linear field A x")
    w = np.array([[0.0, -2.0e-6, 1.0e-6], [2.0e-6, 0.0, -3.0e-6], [-1.0e-6, 3.0e-6, 0.0]])
    c = np.array([1.0e-3, -2.0e-3, 5.0e-4])
    for label, motion in (("translation", lambda x: c + 0.0 * x),
                          ("small rotation", lambda x: w @ x)):
        text, fine = block_deck(motion, f"rigid {label} of a trivariate NURBS block")
        _, _, r = run(args, "rigid_" + label.replace(" ", "_"), text)
        s = r.field(r.field_steps()[-1], "stress")
        umax = max(float(np.max(np.abs(motion(x)))) for x in fine)
        chk.below(float(np.max(np.abs(s))) / (E * umax), 1e-10,
                  f"rigid {label}: zero stress in every element (max |sigma| / (E max |u|), "
                  "on a block of size about 1)")


# ---------------------------------------------------------------------------------------------
# The XDMF sidecar
# ---------------------------------------------------------------------------------------------

def hex_volume(p):
    """Volume of hexahedra p (n, 8, 3) in VTK order, by the 2 x 2 x 2 Gauss rule."""
    g = 1.0 / np.sqrt(3.0)
    corners = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                        [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
    vol = np.zeros(len(p))
    for q in np.array([[a, b, c] for a in (-g, g) for b in (-g, g) for c in (-g, g)]):
        dn = np.array([[corners[k, d] * np.prod([1 + corners[k, e] * q[e] for e in range(3)
                                                 if e != d]) / 8 for d in range(3)]
                       for k in range(8)])
        jac = np.einsum("cki,kj->cij", p, dn)
        vol += np.linalg.det(jac)
    return vol


def xdmf(args, chk):
    import meshio
    h5 = os.path.join(args.work, "flight_hrz.h5")
    with meshio.xdmf.TimeSeriesReader(h5.replace(".h5", ".xdmf")) as reader:
        points, cells = reader.read_points_cells()
        _, point_data, _ = reader.read_data(reader.num_steps - 1)
    r = vcheck.Results(h5)
    chk.true(points.shape[1] == 3 and np.array_equal(points, np.asarray(r.f["viz/iga/points"]))
             and len(cells) == 1 and cells[0].type == "hexahedron",
             "xdmf: meshio reads the viewing samples (XYZ) and one block of hexahedra")
    u = point_data["displacement"]
    chk.true(u.shape == (len(points), 3) and
             np.array_equal(u, r.field(r.field_steps()[-1], "viz_displacement")),
             "xdmf: the displacement of the last step at the samples, 3 components")
    # 2 x 4 x 2 elements of 5^3 samples and 4^3 cells each
    chk.true(len(cells[0].data) == 16 * 64 and len(points) == 16 * 125,
             "xdmf: (2 p + 1)^3 = 125 samples and 64 cells per element")
    vol = hex_volume(points[cells[0].data])
    chk.true(bool(np.all(vol > 0.0)), "xdmf: every cell has a positive volume (VTK order)")
    chk.close(float(np.sum(vol)), np.pi / 3.0, 2e-2, "xdmf: the cells fill the quarter-ball")


def mixed(args, chk):
    """Hexahedra and a trivariate patch in one 3D model: both in free flight, each shown as
    its own XDMF block."""
    import meshio
    cp = "".join(f"{i + 2.0!r}, {float(j)!r}, {float(k)!r}, 1.0\n"
                 for k in range(2) for j in range(2) for i in range(2))
    text = ("*HEADING\nhexahedra and a trivariate patch\n*ANALYSIS, TYPE=3D\n"
            + vcheck.material_block() + vcheck.box_mesh(type="C3D8", nx=2, ny=2, nz=2, lx=1,
                                                        ly=1, lz=1)
            + "*PATCH, NAME=BLOCK, MATERIAL=MAT, DEGREE=1,1,1, SIZE=2,2,2\n"
            + "".join(f"*KNOTS, DIRECTION={d}\n0, 0, 1, 1\n" for d in (1, 2, 3))
            + "*CONTROL POINTS\n" + cp
            + "*ELEVATE, PATCH=BLOCK, DEGREE=2,2,2\n*REFINE, PATCH=BLOCK, SUBDIVIDE=2,2,2\n"
            + f"*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 3, {-V!r}\nBLOCK, 3, {-V!r}\n"
            + "*MASS, TYPE=HRZ, INTEGRATION=2X2\n*STEP\n*DYNAMIC, EXPLICIT\n0, 0.01\n"
            + "*OUTPUT, FIELD, VARIABLES=U,V,S,MISES\n*END STEP\n")
    path, out, r = run(args, "mixed", text)
    last = r.field_steps()[-1]
    t = r.field_time(last)
    u = np.concatenate([r.field(last, "displacement"), r.field(last, "viz_displacement")])
    chk.below(float(np.max(np.abs(u - [0.0, 0.0, -V * t]))) / (V * t), 1e-12,
              "mixed: C3D8 and a patch in free flight, every node and sample at -v t e_z")
    chk.close(float(np.sum(r.model("mass"))), 2.0 * RHO, 1e-14,
              "mixed: total mass of the unit cube of C3D8 and the unit cube patch")
    blocks = {}
    for name in ("c3d8", "iga"):
        with meshio.xdmf.TimeSeriesReader(path.replace(".inp", f".{name}.xdmf")) as reader:
            points, cells = reader.read_points_cells()
            _, point_data, cell_data = reader.read_data(reader.num_steps - 1)
        blocks[name] = (len(points), [c.type for c in cells], point_data["displacement"].shape,
                        cell_data["stress"][0].shape)
    # the C3D8 block's points are all the model's nodes: 27 of the box, 4^3 control points
    chk.true(blocks == {"c3d8": (27 + 64, ["hexahedron"], (91, 3), (8, 6)),
                        "iga": (8 * 125, ["hexahedron"], (1000, 3), (8 * 64, 6))},
             "mixed: meshio reads the C3D8 block (the model's 91 nodes, 8 cells) and the "
             "patch's viewing block (8 elements of 125 samples, 64 cells each), with "
             "6-component cell stresses")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("nurbs3d")
    ball_mass(args, chk)
    patch_test(args, chk)
    free_flight(args, chk)
    held_ball(args, chk)
    xdmf(args, chk)
    mixed(args, chk)
    chk.finish()


if __name__ == "__main__":
    main()
