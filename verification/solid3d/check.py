#!/usr/bin/env python3
"""3D runs of hexahedra (C3D8, C3D20, C3D20R, C3D27) without contact, against physics.

1. Bar wave: a prism [0, L] x [0, h] x [0, h] of C3D8 and one of C3D20 (HRZ mass, nu = 0)
   moving at -v0 along x is held at x = 0 (u_x = 0) from t = 0 on. The exact solution by
   characteristics (the 1D wave equation u_tt = c^2 u_xx, c = sqrt(E/rho)):
     t <= L/c:          u = -v0 min(t, x/c)
     L/c <= t <= 2L/c:  u = -v0 x/c for x <= 2L - ct, u = v0 (t - 2L/c) beyond
   (at t = L/c the wave reflected at the free end x = L starts back). Run to 1.5 L/c and
   checked at every snapshot; with nu = 0 the motion stays 1D.
2. Patch test at deck level: a block of distorted hexahedra whose boundary nodes are given the
   displacements u = A x of a linear field (*BOUNDARY, each node and dof with its value) and
   whose interior nodes start at rest at 0; mass-proportional damping (*DAMPING) relaxes the
   interior to the static solution, which is the linear field itself (a complete polynomial of
   degree 1 lies in the span of every one of these elements). Every element's stress must be
   sigma = lambda tr(eps) I + 2 mu eps of eps = (A + A^T)/2 to 1e-8, the interior nodes must
   be at A x.
3. omega_max of a free cube of one C3D8 (lumped mass m/8 per node): the largest eigenvalue of
   K x = omega^2 M x is the dilatational mode u = x - x_c, omega_max^2 = 4 E/((1 - 2 nu) rho h^2)
   (derived in doc/elements3d.md §6 and by tests/unit/elements/test_solid3d), as ictus
   estimates it for its stable step (the results attribute omega_max).
4. The quarter-ball of scripts/mesh/quarter_ball.py (C3D8, C3D20, C3D27; its rigid wall
   dropped): its total mass must be rho times the volume of its mesh (Gauss quadrature of
   det J here, from the deck's nodes and elements), and in free flight every node moves at
   -v e_z exactly.
5. Bit-identical results: the quarter-ball (C3D20, HRZ) with its bottom held (u_z = 0 on the
   nodes near the contact point) on 2 ranks and continued from a checkpoint on 2 ranks, the
   same with a consistent mass (MASS SOLVER=CG, AUTO in 3D) and with C3D27, and its processed
   deck re-run (vcheck.processed_deck_reruns).
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402
import quarter_ball  # noqa: E402  (scripts/mesh, on the path through vcheck)

E, RHO = 1000.0, 1.0
KIND = {"C3D8": "hex8", "C3D20": "hex20", "C3D20R": "hex20", "C3D27": "hex27"}


def material(e=E, nu=0.0, rho=RHO):
    return vcheck.material_block(e=e, nu=nu, rho=rho)


def parse_mesh(text):
    """Nodes {id: (x, y, z)} and elements [(type, [node ids])] of a deck text (elements
    continued over lines ending with a comma)."""
    nodes, elems = {}, []
    card, etype, pending = None, None, []
    for line in text.splitlines():
        s = line.strip()
        if not s or s.startswith("**"):
            continue
        if s.startswith("*"):
            card = s.split(",")[0].upper()
            m = re.search(r"TYPE=([A-Z0-9]+)", s.upper())
            etype = m.group(1) if m and card == "*ELEMENT" else None
            continue
        v = [t.strip() for t in s.split(",") if t.strip()]
        if card == "*NODE":
            nodes[int(v[0])] = tuple(float(x) for x in v[1:4])
        elif card == "*ELEMENT":
            pending += [int(x) for x in v]
            if not s.endswith(","):
                elems.append((etype, pending[1:]))
                pending = []
    return nodes, elems


def mesh_volume(nodes, elems, points):
    """Volume of the elements: the sum of det J w over the Gauss points, `points` per
    direction."""
    vol = 0.0
    t, w = np.polynomial.legendre.leggauss(points)
    for etype, conn in elems:
        pts = np.array([(a, b, c) for c in t for b in t for a in t])
        wts = np.array([wa * wb * wc for wc in w for wb in w for wa in w])
        xyz = np.array([nodes[k] for k in conn])
        jac = np.einsum("ni,gnj->gij", xyz, quarter_ball.shape_derivatives(KIND[etype], pts))
        vol += float(np.sum(np.linalg.det(jac) * wts))
    return vol


# ---------------------------------------------------------------------------------------------
# 1. Bar wave
# ---------------------------------------------------------------------------------------------

V0, L, H = 1.0, 10.0, 0.5
C = (E / RHO) ** 0.5


def bar_wave(args, chk):
    for etype, nx in (("C3D8", 100), ("C3D20", 50)):
        path = os.path.join(args.work, f"bar_{etype}.inp")
        with open(path, "w") as f:
            f.write("*HEADING\nbar wave in 3D, nu = 0\n*ANALYSIS, TYPE=3D\n" + material()
                    + vcheck.box_mesh(type=etype, nx=nx, ny=1, nz=1, lx=L, ly=H, lz=H)
                    + "*BOUNDARY\nX0, 1, 1\n*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 1, "
                    + repr(-V0) + "\n*MASS, TYPE=HRZ\n*STEP\n*DYNAMIC, EXPLICIT\n0, "
                    + repr(1.5 * L / C) + "\n*OUTPUT, FIELD, EVERY=50\n*END STEP\n")
        out = path.replace(".inp", ".h5")
        vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        chk.true(r.attr("analysis") == "3D" and int(r.attr("dimension")) == 3,
                 f"bar {etype}: results of a 3D analysis (dimension 3)")
        # C3D8 (equal nodal masses on the section) keeps the motion 1D exactly; the corner and
        # midside masses of C3D20 make u_x vary over the section at the front (a little shear)
        vcheck.check_bar_wave(chk, r, f"bar {etype}: ", V0, L, C,
                              1e-12 if etype == "C3D8" else 0.02, RHO * L * H * H, "rho L h^2")


# ---------------------------------------------------------------------------------------------
# 2. Patch test
# ---------------------------------------------------------------------------------------------

NU_P = 0.25
A_FIELD = np.array([[1.0e-3, 2.0e-4, -3.0e-4],
                    [5.0e-4, -2.0e-3, 1.0e-4],
                    [-2.0e-4, 3.0e-4, 1.5e-3]])


def patch_test(args, chk):
    lam = E * NU_P / ((1 + NU_P) * (1 - 2 * NU_P))
    mu = E / (2 * (1 + NU_P))
    eps = 0.5 * (A_FIELD + A_FIELD.T)
    sig = lam * np.trace(eps) * np.eye(3) + 2 * mu * eps
    # xx, yy, zz, xy, yz, zx
    sig6 = np.array([sig[0, 0], sig[1, 1], sig[2, 2], sig[0, 1], sig[1, 2], sig[2, 0]])
    for etype in ("C3D8", "C3D20", "C3D20R", "C3D27"):
        mesh = vcheck.box_mesh(type=etype.rstrip("R"), nx=3, ny=3, nz=3, lx=1.0, ly=1.2,
                               lz=0.9, distort=0.1)
        pts = {p[0]: np.array(p[1:]) for p in vcheck.mesh_points(mesh)}
        sets = dict(re.findall(r"\*NSET, NSET=(\w+)\n([\d,\s]+)", mesh))
        outer = sorted({int(n) for name in ("X0", "X1", "Y0", "Y1", "Z0", "Z1")
                        for n in sets[name].replace("\n", ",").split(",") if n.strip()})
        bc = "".join(f"{n}, {d + 1}, {d + 1}, {float((A_FIELD @ pts[n])[d])!r}\n"
                     for n in outer for d in range(3))
        path = os.path.join(args.work, f"patch_{etype}.inp")
        with open(path, "w") as f:
            f.write("*HEADING\npatch test, distorted hexahedra\n*ANALYSIS, TYPE=3D\n"
                    + material(nu=NU_P) + mesh.replace("TYPE=C3D20,", f"TYPE={etype},")
                    + "*BOUNDARY\n" + bc + "*DAMPING, ALPHA=150\n*STEP\n*DYNAMIC, EXPLICIT\n"
                    + "0, 1.0\n*OUTPUT, FIELD, VARIABLES=U,S\n*OUTPUT, HISTORY, EVERY=100\n"
                    + "*END STEP\n")
        out = path.replace(".inp", ".h5")
        vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        last = r.field_steps()[-1]
        s = r.field(last, "stress")
        err = float(np.max(np.abs(s - sig6[None, :])) / np.max(np.abs(sig6)))
        chk.below(err, 1e-8, f"patch {etype}: every element's stress is the exact uniform "
                  "stress (max error / max |sigma|)")
        x = r.model("coordinates")
        u = r.field(last, "displacement")
        uerr = float(np.max(np.abs(u - x @ A_FIELD.T)) / np.max(np.abs(x @ A_FIELD.T)))
        chk.below(uerr, 1e-8, f"patch {etype}: interior nodes at the linear field A x")


def pressure_faces(nx, ny, nz):
    """*SURFACE data lines of every boundary face of a box of nx x ny x nz elements
    (scripts/mesh/box.py numbering: x fastest): S6, S4 on x = x0, x1; S3, S5 on y; S1, S2 on z."""
    lines = []
    for ez in range(nz):
        for ey in range(ny):
            for ex in range(nx):
                e = 1 + ex + nx * (ey + ny * ez)
                for on, face in ((ex == 0, "S6"), (ex == nx - 1, "S4"), (ey == 0, "S3"),
                                 (ey == ny - 1, "S5"), (ez == 0, "S1"), (ez == nz - 1, "S2")):
                    if on:
                        lines.append(f"{e}, {face}\n")
    return "".join(lines)


def pressure_tests(args, chk):
    """*DLOAD, P on faces of hexahedra. (a) A free block of distorted elements under a
    uniform pressure p on its whole boundary, relaxed by damping: a self-equilibrated load
    whose static solution is the uniform stress sigma = -p I in every element. (b) The bar of
    1 held at x = 0, at rest, with the pressure p applied at t = 0 on its end x = L: the
    stress wave -p runs at c, the end moves at -p/(rho c), u(L, t) = -p c t/E for t < 2 L/c."""
    p = 2.0
    for etype in ("C3D8", "C3D20", "C3D27"):
        mesh = vcheck.box_mesh(type=etype, nx=3, ny=3, nz=3, lx=1.0, ly=1.2, lz=0.9,
                               distort=0.1)
        path = os.path.join(args.work, f"pressure_{etype}.inp")
        with open(path, "w") as f:
            f.write("*HEADING\nhydrostatic pressure on a free block\n*ANALYSIS, TYPE=3D\n"
                    + material(nu=NU_P) + mesh + "*SURFACE, NAME=OUTSIDE, TYPE=ELEMENT\n"
                    + pressure_faces(3, 3, 3) + f"*DLOAD\nOUTSIDE, P, {p!r}\n"
                    + "*DAMPING, ALPHA=100\n*STEP\n*DYNAMIC, EXPLICIT\n0, 1.0\n"
                    + "*OUTPUT, FIELD, VARIABLES=U,S\n*OUTPUT, HISTORY, EVERY=100\n*END STEP\n")
        out = path.replace(".inp", ".h5")
        vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        s = r.field(r.field_steps()[-1], "stress")
        err = float(np.max(np.abs(s - [-p, -p, -p, 0.0, 0.0, 0.0]))) / p
        chk.below(err, 1e-8, f"pressure {etype}: a free block under pressure p on its whole "
                  "boundary relaxes to sigma = -p I in every element")
    for etype, nx in (("C3D8", 100), ("C3D20", 50)):
        path = os.path.join(args.work, f"pressure_bar_{etype}.inp")
        with open(path, "w") as f:
            f.write("*HEADING\nbar under an end pressure\n*ANALYSIS, TYPE=3D\n" + material()
                    + vcheck.box_mesh(type=etype, nx=nx, ny=1, nz=1, lx=L, ly=H, lz=H)
                    + f"*SURFACE, NAME=END, TYPE=ELEMENT\n{nx}, S4\n*BOUNDARY\nX0, 1, 1\n"
                    + f"*DLOAD\nEND, P, {p!r}\n*STEP\n*DYNAMIC, EXPLICIT\n0, "
                    + repr(1.5 * L / C) + "\n*OUTPUT, FIELD, EVERY=50\n"
                    + "*RESTART, WRITE, EVERY=100\n*END STEP\n")
        out = path.replace(".inp", ".h5")
        vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        x = r.model("coordinates")[:, 0]
        last = r.field_steps()[-1]
        t = r.field_time(last)
        u = r.field(last, "displacement")
        tip = float(np.mean(u[np.isclose(x, L), 0]))
        chk.close(tip, -p * C * t / E, 0.02, f"pressure bar {etype}: end displacement "
                  f"-p c t/E at t = {t:.4f}")
        etot = r.history("energy/total")
        emax = float(np.max(r.history("energy/strain")))
        chk.below(float(np.max(np.abs(etot - etot[0]))) / emax, 5e-3,
                  f"pressure bar {etype}: energy balance (the work of the pressure in "
                  "external_work) / max strain energy")
        if etype == "C3D20":
            vcheck.check_ranks_and_restart(args, chk, path, out,
                                           label=f"pressure bar {etype}: ")


# ---------------------------------------------------------------------------------------------
# 3. omega_max of a free cube
# ---------------------------------------------------------------------------------------------

def free_cube(args, chk):
    nu = 0.3
    for h in (1.0, 2.5):
        path = os.path.join(args.work, f"cube_{h:g}.inp")
        with open(path, "w") as f:
            f.write("*HEADING\nfree cube, one C3D8\n*ANALYSIS, TYPE=3D\n" + material(nu=nu)
                    + vcheck.box_mesh(type="C3D8", nx=1, ny=1, nz=1, lx=h, ly=h, lz=h)
                    + "*MASS, TYPE=HRZ\n*STEP\n*DYNAMIC, EXPLICIT\n0, 1e-3\n*END STEP\n")
        out = path.replace(".inp", ".h5")
        vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        exact = (4.0 * E / ((1.0 - 2.0 * nu) * RHO * h * h)) ** 0.5
        chk.close(float(r.attr("omega_max")), exact, 1e-10,
                  f"free cube h = {h:g}: omega_max = sqrt(4E/((1 - 2 nu) rho h^2)) = {exact:g}")


# ---------------------------------------------------------------------------------------------
# 4. and 5. The quarter-ball
# ---------------------------------------------------------------------------------------------

def quarter_ball_deck(kind, n, mass="HRZ", t_end=0.05, hold=False, extra=""):
    """The deck of quarter_ball.py without its rigid wall; `hold`: u_z = 0 on the nodes
    within 0.05 R of the contact point (a bottom held instead of the wall)."""
    a = quarter_ball.parser().parse_args(["--kind", kind, "--n", str(n), "--mass", mass,
                                          "--t-end", repr(t_end)])
    quarter_ball.check_options(a)
    text = quarter_ball.deck(a, "quarter_ball.py --kind " + kind)
    text = re.sub(r"\*RIGID WALL[^\n]*\n[^\n]*\n", "", text)
    if hold:
        nodes, _ = parse_mesh(text)
        low = [i for i, x in nodes.items() if x[2] < 0.05]
        text = text.replace("*BOUNDARY\n", "*NSET, NSET=BOTTOM\n"
                            + ", ".join(map(str, low)) + "\n*BOUNDARY\nBOTTOM, 3, 3\n", 1)
    return text.replace("*END STEP", extra + "*END STEP")


def quarter_ball_mass(args, chk):
    for kind, n in (("hex8", 3), ("hex20", 2), ("hex27", 2)):
        text = quarter_ball_deck(kind, n)
        path = os.path.join(args.work, f"ball_{kind}.inp")
        with open(path, "w") as f:
            f.write(text)
        out = path.replace(".inp", ".h5")
        vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        nodes, elems = parse_mesh(text)
        mass = float(np.sum(r.model("mass")))
        # det J is a polynomial of degree 2 (C3D8) or 5 (C3D20, C3D27) in each parent
        # coordinate, so the 10 x 10 x 10 rule gives the volume of the mesh to round-off
        vol = mesh_volume(nodes, elems, 10)
        chk.close(mass, RHO * vol, 1e-12,
                  f"quarter-ball {kind}: total mass = rho x the volume of its mesh")
        # the flat faces of C3D8 cut the sphere (O(h^2)); C3D20 and C3D27 follow it (O(h^4))
        tol = 0.05 if kind == "hex8" else 0.005
        chk.close(vol, np.pi / 3.0, tol, f"quarter-ball {kind}: the mesh volume is near "
                  f"pi R^3/3 ({100 * tol:g} %)")
        last = r.field_steps()[-1]
        t = r.field_time(last)
        u = r.field(last, "displacement")
        v = 0.1
        chk.below(float(np.max(np.abs(u - [0.0, 0.0, -v * t]))) / (v * t), 1e-12,
                  f"quarter-ball {kind}: free flight, every node at u = -v t e_z")


def quarter_ball_bits(args, chk):
    every = "*RESTART, WRITE, EVERY=40\n*OUTPUT, FIELD, EVERY=40\n"
    for label, kind, mass in (("C3D20 HRZ", "hex20", "HRZ"),
                              ("C3D20 consistent (CG)", "hex20", "CONSISTENT"),
                              ("C3D27 HRZ", "hex27", "HRZ")):
        name = f"held_{kind}_{mass.lower()}"
        path = os.path.join(args.work, name + ".inp")
        with open(path, "w") as f:
            f.write(quarter_ball_deck(kind, 2, mass=mass, t_end=0.2, hold=True, extra=every))
        out = path.replace(".inp", ".h5")
        vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        etot = r.history("energy/total")
        chk.below(float(np.max(np.abs(etot - etot[0])) / etot[0]), 1e-2,
                  f"held ball {label}: energy conservation max |E(t) - E(0)|/E(0)")
        vcheck.check_ranks_and_restart(args, chk, path, out, label=f"held ball {label}: ")
        if mass == "HRZ" and kind == "hex20":
            chk.true(vcheck.processed_deck_reruns(args, out), f"held ball {label}: the "
                     "processed deck of the results file re-runs bit for bit")


# ---------------------------------------------------------------------------------------------
# 6. The XDMF sidecar in 3D
# ---------------------------------------------------------------------------------------------

# VTK's (and XDMF's) Hexahedron_27 after the corners and edges: the face centres of x-, x+, y-,
# y+, z-, z+ (corner lists in VTK numbering), then the centre
VTK_FACES = [(0, 3, 7, 4), (1, 2, 6, 5), (0, 1, 5, 4), (3, 2, 6, 7), (0, 1, 2, 3), (4, 5, 6, 7)]


def xdmf_3d(args, chk):
    import meshio
    for etype, cell in (("C3D20", "hexahedron20"), ("C3D27", "hexahedron27")):
        h5 = os.path.join(args.work, f"patch_{etype}.h5")
        with meshio.xdmf.TimeSeriesReader(h5.replace(".h5", ".xdmf")) as reader:
            points, cells = reader.read_points_cells()
            _, point_data, _ = reader.read_data(reader.num_steps - 1)
        r = vcheck.Results(h5)
        x = r.model("coordinates")
        conn = r.model(f"elements/{etype.lower()}/connectivity")
        chk.true(np.array_equal(points, x) and len(cells) == 1 and cells[0].type == cell,
                 f"xdmf {etype}: meshio reads the XYZ points and one block of {cell}")
        u = point_data["displacement"]
        chk.true(np.array_equal(u, r.field(r.field_steps()[-1], "displacement")),
                 f"xdmf {etype}: the displacement of the last step, 3 components")
        c = cells[0].data
        if etype == "C3D20":
            chk.true(np.array_equal(c, conn), "xdmf C3D20: Hexahedron_20 in the deck's order")
            continue
        # the box's face and centre nodes are the means of their corners: each must sit where
        # VTK's order puts it
        faces = np.stack([points[c[:, list(f)]].mean(axis=1) for f in VTK_FACES], axis=1)
        err = max(float(np.max(np.abs(points[c[:, 20:26]] - faces))),
                  float(np.max(np.abs(points[c[:, 26]] - points[c[:, :8]].mean(axis=1)))))
        chk.below(err, 1e-14, "xdmf C3D27: Hexahedron_27 face centres (x-, x+, y-, y+, z-, "
                  "z+) and centre where VTK puts them")
        chk.true(np.array_equal(c[:, :20], conn[:, :20]),
                 "xdmf C3D27: corners and edge midsides in the deck's order")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("solid3d")
    bar_wave(args, chk)
    patch_test(args, chk)
    pressure_tests(args, chk)
    free_cube(args, chk)
    quarter_ball_mass(args, chk)
    quarter_ball_bits(args, chk)
    xdmf_3d(args, chk)
    chk.finish()


if __name__ == "__main__":
    main()
