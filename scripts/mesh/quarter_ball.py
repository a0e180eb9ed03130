#!/usr/bin/env python3
"""Writes ictus decks (format version 2, 3D) of the quarter-ball x >= cx, y >= cy, |r - c| <= R:
the quarter model of a sphere with the two symmetry planes x = cx and y = cy, for the dynamic
Hertz sphere of doc/reference.md §3.8 (sphere on a rigid wall; contact point c - R e_z at the
bottom, on the z axis through the centre c). A hexahedral mesh (cubed sphere) or one exact
NURBS patch. ictus runs both with the rigid wall and, for --partner body, the contact pair
(ALGORITHM=TWO HALF PASS; NODE TO SEGMENT and MORTAR are not yet in 3D): doc/contact.md §9,
verification/hertz_sphere and hertz_sphere_iga.

    quarter_ball.py --kind hex20 [--n 8] [--m 0] [--inner 0.5] [--grade 1] [options] > ball.inp
    quarter_ball.py --kind nurbs [--subdivide 8] [--m 0] [--elevate 2] [options] > ball.inp

Hexahedral meshes (--kind hex8, hex20, hex27; C3D8, C3D20, C3D27). Cubed sphere: the
quarter [0, a] x [0, a] x [-a, a] of a cube of half-side a = --inner * R around c
(n x n x 2n elements, n = --n) and four outer blocks between its faces x = a, y = a, z = -a,
z = a and the sphere (n x 2n, 2n x n, n x n, n x n elements across, m = --m radially;
m = 0 takes ceil(2n (1 - inner) / (inner + pi/4)), which makes the radial size about the
mean of the cube's a/n and the sphere's pi R/(4n)): 2n^3 + 6n^2 m elements. A point
a (u, v, w) of the cube surface (|u|, |v|, |w| <= 1, one of them 1) is joined by a straight
segment to its sphere point R d/|d|, d = (tan(pi u/4), tan(pi v/4), tan(pi w/4)) (the
equiangular cubed sphere: the sphere nodes are evenly spaced in angle along each block
edge); the node at fraction t of the segment is (1 - t) a (u, v, w) + t R d/|d|. There are
no degenerate elements: every block corner is a proper hexahedron corner, and the contact
point is the corner of the bottom block on the z axis. Nodes of the spherical face are on
the sphere to round-off, nodes of the symmetry sets exactly on their planes. For hex20 and
hex27 every node (corner, edge, face and centre) is the map evaluated at its parameters:
edge and face nodes lie on the curved geometry. --grade Q (default 1, uniform) makes the
element sizes grow by the ratio Q away from the contact point: along x and y from the axis
(n elements), along z from the bottom of the cube (2n elements) and along the radial
segments from the sphere inwards (m elements); mid nodes sit at the mean parameter of their
corners. The script checks det J > 0 at every Gauss point of every element (2 x 2 x 2 for
hex8, 3 x 3 x 3 otherwise) before writing.

Element node order (Abaqus): corners 1-4 at zeta = -1, counter-clockwise seen from +zeta
(xi from 1 to 2, eta from 1 to 4), 5-8 above them at zeta = +1; hex20 and hex27 add the edge
midsides 9 (1-2), 10 (2-3), 11 (3-4), 12 (4-1), 13 (5-6), 14 (6-7), 15 (7-8), 16 (8-5),
17 (1-5), 18 (2-6), 19 (3-7), 20 (4-8); hex27 adds the centre 21 and the face centres 22-27
in the face order S1..S6 below (the order gmsh's Abaqus export writes for C3D27). Faces:
S1 1-2-3-4, S2 5-8-7-6, S3 1-5-6-2, S4 2-6-7-3, S5 3-7-8-4, S6 4-8-5-1. The spherical faces
are the S2 faces of the outer layer (S1 in the lower body of --partner body, mirrored). An
element's data line holds at most 16 entries and ends with a comma where the element goes on
to the next line (C3D20, C3D27), as Abaqus and gmsh write them.

NURBS (--kind nurbs): ONE patch, exact geometry, quadratic in all three directions (the
lowest degree that is exact with these circles; direction 3 is linear, written as degree 2),
SIZE=3,5,3: 45 control points, direction 1 fastest. Spherical coordinates about the x
axis: direction 1 is the polar angle from the +x axis (theta = 0) to the plane x = cx
(theta = 90 degrees): the quarter circle (1, 0), (1, 1), (0, 1), weights 1, sqrt(1/2), 1;
direction 2 is the azimuth about the x axis in the plane x = cx, from -z through +y to +z:
two quarter circles (0, -1), (1, -1), (1, 0), (1, 1), (0, 1) in (y, z), weights 1, sqrt(1/2),
1, sqrt(1/2), 1, knots 0 0 0 1/2 1/2 1 1 1; direction 3 is the radius 0, R/2, R. The control
point (i, j, k) is c + r_k (cos_i, sin_i y_j, sin_i z_j) with weight w_i w_j (the tensor
product of the two circles is the unit sphere exactly). det J > 0 everywhere except on two
degenerate (collapsed) sides, where it vanishes:
  * SIDE=XI0 (theta = 0): the segment of the x axis from c to c + R e_x (a LINE; its 15
    control points are 5 copies each of c, c + R/2 e_x and c + R e_x);
  * SIDE=ZETA0 (r = 0): the centre c (a POINT; its 15 control points coincide).
The contact point (the corner of SIDE=XI1, ETA0 and ZETA1; ETA1 in the mirrored LOWER patch)
and the whole contact zone are regular: the x axis is 90 degrees from the contact point.
Coincident control points are separate control points in the deck (*PATCH, MERGE=YES glues no
side of zero length); a reader must tie them (or accept the stiff, small elements at the line
and the point, which lower the stable time step). --subdivide K writes *REFINE, SUBDIVIDE=K,K,M
(K spans per 90 degrees in both angular directions, M = --m radially, M = 0 takes K); --elevate
Q > 2 writes *ELEVATE first. Without collapsed sides an exact quarter-ball would take several
patches (an exact cubed sphere, as Cobb's, is of degree 4); that is not written.

Names (NAME = --name, default BALL): the ELSET (hex) or patch (nurbs) NAME, also the node set
of the whole body; *NSET NAME_X0, the nodes or control points on the plane x = cx (nurbs: the
sides XI1 and ZETA0, the collapsed centre), and NAME_Y0, those on y = cy (nurbs: ETA0, ETA1
and the collapsed sides XI0 and ZETA0, the x axis segment and the centre, which lie in that
plane), for nurbs lists of the side sets NAME_X0_<SIDE> and NAME_Y0_<SIDE>; *SURFACE NAME_SPH,
the whole spherical face (hex: TYPE=ELEMENT faces; nurbs: SIDE=ZETA1). With --partner body
the two bodies are UPPER (centre c) and LOWER (its mirror image in the plane z = cz - R,
touching UPPER at the contact point; its node and element ids follow those of UPPER).

Deck contents: *ANALYSIS, TYPE=3D, material E, nu, rho (defaults 1000, 0.3, 1: reference.md
§3.8), the body, u_x = 0 on NAME_X0 and u_y = 0 on NAME_Y0, initial velocity -v e_z (--v,
default 0.1; with --partner body UPPER at -v and LOWER at +v, the same as one body at v on a
wall), a frictionless rigid wall z = cz - R with NORMAL=0,0,1 against NAME_SPH (--partner
wall, the default) or a *CONTACT PAIR LOWER_SPH, UPPER_SPH (--partner body; --algorithm),
both with PENALTY=--penalty (default 1e5, as the 2D benchmark) and --stability, *MASS, TYPE=
--mass, and a step (--dt, 0 = automatic; --t-end, default 0.6 > t_c = 0.49; --field-every).
--body-only writes only the body cards. The first line of every full deck records the
command that made it.

Bad values (a radius, E, rho, penalty, t_end or grading ratio <= 0, nu outside (-1, 0.5),
--inner outside (0, 1/sqrt(3)) (the cube's corner must stay inside the sphere), counts < 1,
degree < 2, non-finite numbers, names the deck rejects, ids past 2^31 - 1, --grade with nurbs,
a grading that leaves an element without length or a Jacobian <= 0 at a Gauss point) end the
script with a one-line message and exit status 1, before anything is written.
"""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import halfdisc  # noqa: E402
import hertz  # noqa: E402

ABAQUS = {"hex8": "C3D8", "hex20": "C3D20", "hex27": "C3D27"}
# natural coordinates of the corners 1..8, the corner pairs of the edges 9..20 and the corner
# lists of the faces S1..S6 (Abaqus numbering)
CORNERS = [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
           (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]
EDGES = [(1, 2), (2, 3), (3, 4), (4, 1), (5, 6), (6, 7), (7, 8), (8, 5),
         (1, 5), (2, 6), (3, 7), (4, 8)]
FACES = [(1, 2, 3, 4), (5, 8, 7, 6), (1, 5, 6, 2), (2, 6, 7, 3), (3, 7, 8, 4), (4, 8, 5, 1)]
# node sets and surface of the NURBS patch by its sides (the lower body's reversed direction 2
# exchanges ETA0 and ETA1, which leaves these lists as they are)
NURBS_SIDES = {"X0": ["XI1", "ZETA0"], "Y0": ["ETA0", "ETA1", "XI0", "ZETA0"], "SPH": "ZETA1"}
# mirroring z -> -z maps the node (xi, eta, zeta) to (xi, eta, -zeta): S1 and S2 swap
MIRROR_FACE = {"S1": "S2", "S2": "S1", "S3": "S3", "S4": "S4", "S5": "S5", "S6": "S6"}


def natural(kind):
    """Natural coordinates (nen, 3) of the element nodes in Abaqus order."""
    c = np.array(CORNERS, dtype=float)
    if kind == "hex8":
        return c
    pts = [c, np.array([(c[a - 1] + c[b - 1]) / 2 for a, b in EDGES])]
    if kind == "hex27":   # the centre (21), then the face centres of S1..S6 (22-27)
        pts += [np.zeros((1, 3)), np.array([c[[k - 1 for k in f]].mean(axis=0) for f in FACES])]
    return np.vstack(pts)


def _lagrange(a, t):
    """1D factor of node coordinate a in {-1, 0, 1} at t, and its derivative (quadratic)."""
    if a == 0:
        return 1.0 - t * t, -2.0 * t
    return 0.5 * t * (t + a), t + 0.5 * a


def shape_derivatives(kind, pts):
    """dN/dxi (npts, nen, 3) of the Abaqus hexahedron `kind` at natural points pts (npts, 3)."""
    nat = natural(kind)
    out = np.zeros((len(pts), len(nat), 3))
    x = [pts[:, d] for d in range(3)]
    for n, a in enumerate(nat):
        if kind == "hex8" or (kind == "hex20" and np.all(a != 0)):
            lin = [0.5 * (1.0 + a[d] * x[d]) for d in range(3)]
            dlin = [0.5 * a[d] for d in range(3)]
            extra, dextra = 1.0, [0.0, 0.0, 0.0]
            if kind == "hex20":   # corner: (prod (1 + a x)) (a.x - 2) / 8
                extra = a[0] * x[0] + a[1] * x[1] + a[2] * x[2] - 2.0
                dextra = list(a)
            for d in range(3):
                others = lin[(d + 1) % 3] * lin[(d + 2) % 3]
                out[:, n, d] = dlin[d] * others * extra + lin[d] * others * dextra[d]
        elif kind == "hex20":     # edge node: (1 - x_d^2) times the linear factors of the others
            f = [_lagrange(0, x[d]) if a[d] == 0 else (0.5 * (1.0 + a[d] * x[d]), 0.5 * a[d])
                 for d in range(3)]
            for d in range(3):
                out[:, n, d] = f[d][1] * f[(d + 1) % 3][0] * f[(d + 2) % 3][0]
        else:                     # hex27: tensor product of 1D quadratic Lagrange factors
            f = [_lagrange(a[d], x[d]) for d in range(3)]
            for d in range(3):
                out[:, n, d] = f[d][1] * f[(d + 1) % 3][0] * f[(d + 2) % 3][0]
    return out


def jacobians(kind, xyz, conn):
    """det J (nel, ngp) at the Gauss points (2 x 2 x 2 for hex8, 3 x 3 x 3 otherwise)."""
    t = np.polynomial.legendre.leggauss(2 if kind == "hex8" else 3)[0]
    pts = np.array([(a, b, c) for c in t for b in t for a in t])
    jac = np.einsum("eni,gnj->egij", xyz[conn], shape_derivatives(kind, pts))
    return np.linalg.det(jac)


def _lattice(g, order):
    """Node parameters along one direction: the corners g, with their means between them when
    the elements are quadratic (order 2)."""
    g = np.asarray(g, dtype=float)
    if order == 1:
        return g
    out = np.empty(2 * len(g) - 1)
    out[0::2], out[1::2] = g, 0.5 * (g[:-1] + g[1:])
    return out


def radial_count(n, inner):
    """The automatic radial element count (see the docstring)."""
    return max(1, math.ceil(2 * n * (1.0 - inner) / (inner + math.pi / 4)))


def _tan_quarter(u):
    """tan(pi u / 4), exactly +-1 at u = +-1 and 0 at u = 0."""
    return np.where(np.abs(u) == 1.0, u, np.tan(0.25 * math.pi * u))


def hex_mesh(kind, radius, n, m, inner, grade):
    """Cubed-sphere mesh of the quarter-ball centred at the origin.
    Returns (xyz (nn, 3), conn (nel, nen) 0-based, sph [(element index, face)], x0 and y0
    (0-based node indices on x = 0 and y = 0))."""
    o = 1 if kind == "hex8" else 2
    gx = _lattice(hertz.graded_knots(n, grade)[2:-2], o)                         # [0, 1]
    gz = _lattice([2.0 * t - 1.0 for t in hertz.graded_knots(2 * n, grade)[2:-2]], o)
    gr = _lattice([1.0 - t for t in hertz.graded_knots(m, grade)[2:-2][::-1]], o)
    nx, nz = n * o, 2 * n * o                             # lattice sizes: i, j in 0..nx
    # blocks: element counts along (xi, eta, zeta) and the map of the block lattice (p, q, r)
    # to the global lattice (i, j, k, l) (l: radial index, 0 on the cube); all right-handed
    blocks = [((n, n, 2 * n), lambda p, q, r: (p, q, r, 0 * r)),          # inner cube
              ((n, n, m), lambda p, q, r: (q, p, 0 * r, r)),               # z = -a, outward -z
              ((n, n, m), lambda p, q, r: (p, q, nz + 0 * r, r)),          # z = +a
              ((n, 2 * n, m), lambda p, q, r: (nx + 0 * r, p, q, r)),      # x = +a
              ((2 * n, n, m), lambda p, q, r: (q, nx + 0 * r, p, r))]      # y = +a
    off = ((natural(kind) + 1) * o // 2).astype(int)
    keys, sph, first = [], [], 0
    for b, ((n1, n2, n3), to_global) in enumerate(blocks):
        e3, e2, e1 = np.meshgrid(range(n3), range(n2), range(n1), indexing="ij")
        e1, e2, e3 = e1.ravel(), e2.ravel(), e3.ravel()
        p, q, r = (e[:, None] * o + off[None, :, d] for d, e in enumerate((e1, e2, e3)))
        i, j, k, l = to_global(p, q, r)
        keys.append(((l * (nz + 1) + k) * (nx + 1) + j) * (nx + 1) + i)
        if b > 0:
            sph += [(first + e, "S2") for e in np.nonzero(e3 == m - 1)[0]]
        first += len(e1)
    uniq, conn = np.unique(np.concatenate(keys), return_inverse=True)
    conn = conn.reshape(-1, len(off))
    i, j = uniq % (nx + 1), (uniq // (nx + 1)) % (nx + 1)
    k, l = (uniq // (nx + 1) ** 2) % (nz + 1), uniq // ((nx + 1) ** 2 * (nz + 1))
    u = np.stack([gx[i], gx[j], gz[k]], axis=1)
    a = inner * radius
    d = _tan_quarter(u)
    norm = np.linalg.norm(d, axis=1)
    norm[norm == 0.0] = 1.0           # the centre (an inner node): d = 0, s unused
    s = radius * d / norm[:, None]
    t = gr[l][:, None]
    xyz = np.where(l[:, None] == 0, a * u, (1.0 - t) * (a * u) + t * s)
    return xyz, conn, sph, np.nonzero(i == 0)[0], np.nonzero(j == 0)[0]


def mirrored(kind, xyz, conn, sph):
    """The mesh mirrored z -> -z, with the element node order that keeps det J > 0."""
    nat = natural(kind)
    flip = [int(np.nonzero(np.all(nat == a * [1, 1, -1], axis=1))[0][0]) for a in nat]
    return xyz * [1.0, 1.0, -1.0], conn[:, flip], [(e, MIRROR_FACE[f]) for e, f in sph]


def nurbs_net(radius):
    """Control points (x, y, z, w) of the quarter-ball patch centred at the origin, direction 1
    (polar angle from +x) fastest, then 2 (azimuth from -z through +y to +z), then 3 (radius);
    and the knot vectors of the three directions."""
    s = math.sqrt(0.5)
    polar = [(1.0, 0.0, 1.0), (1.0, 1.0, s), (0.0, 1.0, 1.0)]                   # (cos, sin, w)
    azim = [(0.0, -1.0, 1.0), (1.0, -1.0, s), (1.0, 0.0, 1.0), (1.0, 1.0, s), (0.0, 1.0, 1.0)]
    net = [(r * c, r * sn * ey, r * sn * ez, 0.5 if wa == wp == s else wa * wp)
           for r in (0.0, 0.5 * radius, radius)
           for ey, ez, wa in azim for c, sn, wp in polar]
    knots = (halfdisc.KNOTS_P2, [0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0], halfdisc.KNOTS_P2)
    return net, knots


def nurbs_cards(a, name, centre, lower):
    net, knots = nurbs_net(a.radius)
    if lower:   # mirror z -> -z and reverse direction 2 (5 rows of 3 per radial layer)
        net = [net[15 * k + 3 * (4 - j) + i] for k in range(3) for j in range(5)
               for i in range(3)]
        net = [(x, y, -z, w) for x, y, z, w in net]
    cx, cy, cz = centre
    out = [f"*PATCH, NAME={name}, MATERIAL={a.material}, DEGREE=2,2,2, SIZE=3,5,3\n"]
    for d, kv in enumerate(knots, start=1):
        out.append(f"*KNOTS, DIRECTION={d}\n" + " ".join(f"{k:g}" for k in kv) + "\n")
    out.append("*CONTROL POINTS\n")
    out += [f"{x + cx + 0.0:.17g}, {y + cy + 0.0:.17g}, {z + cz + 0.0:.17g}, {w:.17g}\n"
            for x, y, z, w in net]     # + 0.0: no -0
    q = a.elevate
    if q > 2:
        out.append(f"*ELEVATE, PATCH={name}, DEGREE={q},{q},{q}\n")
    k, m = a.subdivide, a.m or a.subdivide
    if k > 1 or m > 1:
        out.append(f"*REFINE, PATCH={name}, SUBDIVIDE={k},{k},{m}\n")
    for key in ("X0", "Y0"):
        for s in NURBS_SIDES[key]:
            out.append(f"*NSET, NSET={name}_{key}_{s}, PATCH={name}, SIDE={s}\n")
        out.append(f"*NSET, NSET={name}_{key}\n" +
                   ", ".join(f"{name}_{key}_{s}" for s in NURBS_SIDES[key]) + "\n")
    out.append(f"*SURFACE, NAME={name}_SPH, PATCH={name}, SIDE={NURBS_SIDES['SPH']}\n")
    return "".join(out)


def element_line(ids):
    """An element's data: at most 16 entries a line, a comma at the end of a continued line."""
    return ",\n".join(", ".join(map(str, ids[k:k + 16])) for k in range(0, len(ids), 16)) + "\n"


def hex_cards(a, name, centre, mesh, node0, elem0):
    """Body cards of one hexahedral body; node and element ids start after node0, elem0."""
    xyz, conn, sph, x0, y0 = mesh
    xyz = xyz + np.asarray(centre) + 0.0      # + 0.0: no -0
    out = ["*NODE\n"]
    out += [f"{node0 + n + 1}, {x:.17g}, {y:.17g}, {z:.17g}\n" for n, (x, y, z) in enumerate(xyz)]
    out.append(f"*ELEMENT, TYPE={ABAQUS[a.kind]}, ELSET={name}, MATERIAL={a.material}\n")
    out += [element_line([elem0 + e + 1] + [node0 + k + 1 for k in c]) for e, c in enumerate(conn)]
    for key, nodes in (("X0", x0), ("Y0", y0)):
        out.append(f"*NSET, NSET={name}_{key}\n" + halfdisc._lines(node0 + nodes + 1))
    out.append(f"*SURFACE, NAME={name}_SPH, TYPE=ELEMENT\n")
    out += [f"{elem0 + e + 1}, {f}\n" for e, f in sph]
    return "".join(out)


def checked_mesh(a, lower):
    """The hexahedral mesh of the options (mirrored for the lower body), after the Jacobian
    check of every element as written (exit 1 if it fails)."""
    xyz, conn, sph, x0, y0 = hex_mesh(a.kind, a.radius, a.n, a.m or radial_count(a.n, a.inner),
                                      a.inner, a.grade)
    if lower:
        xyz, conn, sph = mirrored(a.kind, xyz, conn, sph)
    det = jacobians(a.kind, xyz, conn)
    halfdisc.checker("quarter_ball.py")(
        det.min() > 0.0, "--inner, --grade", "values that keep det J > 0 at every Gauss point",
        f"--inner {a.inner!r} --grade {a.grade!r}: min det J = {det.min():.3g}")
    return xyz, conn, sph, x0, y0


def bodies(a):
    """[(name, centre, lower)] of the deck's bodies."""
    cx, cy, cz = a.centre
    if a.partner == "wall":
        return [(a.name, a.centre, False)]
    return [("UPPER", a.centre, False), ("LOWER", (cx, cy, cz - 2.0 * a.radius), True)]


def body_cards(a):
    if a.kind == "nurbs":
        return "".join(nurbs_cards(a, name, c, low) for name, c, low in bodies(a))
    out = []
    for b, (name, c, low) in enumerate(bodies(a)):
        mesh = checked_mesh(a, low)
        out.append(hex_cards(a, name, c, mesh, b * len(mesh[0]), b * len(mesh[1])))
    return "".join(out)


def describe(a):
    if a.kind == "nurbs":
        k, m = a.subdivide, a.m or a.subdivide
        return (f"one NURBS patch p = {max(2, a.elevate)}, {k} x {2 * k} x {m} spans")
    m = a.m or radial_count(a.n, a.inner)
    kind = f"{ABAQUS[a.kind]} cubed sphere n = {a.n}, m = {m}, inner {a.inner:g}"
    return kind + (f", graded {a.grade:g}" if a.grade != 1.0 else "")


def deck(a, command):
    cx, cy, cz = a.centre
    names = [name for name, _, _ in bodies(a)]
    partner = "rigid wall" if a.partner == "wall" else "two bodies, V_rel = %g" % (2 * a.v)
    out = [f"** generated by: {command}\n",
           f"** Quarter-ball x >= {cx:g}, y >= {cy:g} of radius {a.radius:g}, centre "
           f"({cx:g}, {cy:g}, {cz:g}); contact point ({cx:g}, {cy:g}, {cz - a.radius:g}) on "
           f"surface {names[0]}_SPH;\n",
           f"** symmetry planes x = {cx:g} (node set {names[0]}_X0) and y = {cy:g} "
           f"({names[0]}_Y0). doc/reference.md section 3.8.\n",
           "*HEADING\n",
           f"Dynamic Hertz sphere R = {a.radius:g}, {describe(a)}, {a.mass} mass, {partner}\n",
           "*ANALYSIS, TYPE=3D\n",
           f"*MATERIAL, NAME={a.material}\n*ELASTIC\n{a.E!r}, {a.nu!r}\n*DENSITY\n{a.rho!r}\n",
           body_cards(a),
           "*BOUNDARY\n" + "".join(f"{b}_X0, 1, 1\n{b}_Y0, 2, 2\n" for b in names)]
    if a.v != 0.0:
        out.append("*INITIAL CONDITIONS, TYPE=VELOCITY\n" + f"{names[0]}, 3, {-a.v!r}\n" +
                   (f"{names[1]}, 3, {a.v!r}\n" if len(names) > 1 else ""))
    warn = ", STABILITY=WARN" if a.stability == "WARN" else ""
    if a.partner == "wall":
        out.append(f"*RIGID WALL, NAME=WALL, POINT={cx:g},{cy:g},{cz - a.radius:g}, "
                   f"NORMAL=0,0,1, PENALTY={a.penalty:g}{warn}\n{names[0]}_SPH\n")
    else:
        out.append(f"*CONTACT PAIR, NAME=HERTZ, PENALTY={a.penalty:g}, "
                   f"ALGORITHM={a.algorithm}{warn}\nLOWER_SPH, UPPER_SPH\n")
    out.append(halfdisc.mass_and_step(a))
    return "".join(out)


def centre_arg(text):
    """--centre "x,y,z" -> a tuple of three floats."""
    vals = tuple(float(v) for v in text.split(","))
    if len(vals) != 3:
        raise argparse.ArgumentTypeError("expected three numbers x,y,z")
    return vals


def parser():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--kind", choices=["hex8", "hex20", "hex27", "nurbs"], default="hex20")
    ap.add_argument("--radius", type=float, default=1.0)
    ap.add_argument("--centre", type=centre_arg, default=None, metavar="X,Y,Z",
                    help="the centre c (default 0,0,R: contact point at the origin)")
    ap.add_argument("--n", type=int, default=8, help="hex: elements along an inner-block edge")
    ap.add_argument("--m", type=int, default=0,
                    help="radial elements (hex) or spans (nurbs); 0: automatic")
    ap.add_argument("--inner", type=float, default=0.5, help="hex: cube half-side / R")
    ap.add_argument("--grade", type=float, default=1.0,
                    help="hex: element growth ratio away from the contact point (1: uniform)")
    ap.add_argument("--subdivide", type=int, default=8,
                    help="nurbs: spans per 90 degrees (*REFINE SUBDIVIDE=K,K,M)")
    ap.add_argument("--elevate", type=int, default=2, help="nurbs: *ELEVATE DEGREE=q,q,q if q > 2")
    ap.add_argument("--name", default="BALL")
    ap.add_argument("--material", default="SOFT")
    ap.add_argument("--E", type=float, default=1000.0)
    ap.add_argument("--nu", type=float, default=0.3)
    ap.add_argument("--rho", type=float, default=1.0)
    ap.add_argument("--v", type=float, default=0.1, help="speed toward the contact plane")
    ap.add_argument("--partner", choices=["wall", "body"], default="wall")
    ap.add_argument("--penalty", type=float, default=1.0e5)
    ap.add_argument("--algorithm", default="TWO HALF PASS",
                    choices=["TWO HALF PASS", "NODE TO SEGMENT", "MORTAR"])
    ap.add_argument("--stability", choices=["STOP", "WARN"], default="STOP")
    ap.add_argument("--mass", default="HRZ", choices=["CONSISTENT", "ROW SUM", "HRZ"])
    ap.add_argument("--dt", type=float, default=0.0, help="0: automatic")
    ap.add_argument("--t-end", type=float, default=0.6)
    ap.add_argument("--field-every", type=int, default=0, help="0: the program's default")
    ap.add_argument("--body-only", action="store_true")
    return ap


def lattice_count(kind, n, m):
    """Points of the node lattice of one hexahedral body: an upper bound of its node count."""
    o = 1 if kind == "hex8" else 2
    nx, nz = n * o + 1, 2 * n * o + 1
    return nx * nx * nz + m * o * (2 * nx * nz + 2 * nx * nx - nz - 4 * nx)


def check_options(a):
    """Rejects the values that would give no body, an invalid deck or a traceback."""
    check, finite = halfdisc.checker("quarter_ball.py"), math.isfinite
    check(finite(a.radius) and a.radius > 0.0, "--radius", "a positive finite length", a.radius)
    if a.centre is None:
        a.centre = (0.0, 0.0, a.radius)
    check(all(map(finite, a.centre)), "--centre", "three finite numbers x,y,z", a.centre)
    check(a.n >= 1, "--n", "a positive integer (elements along an inner-block edge)", a.n)
    check(a.m >= 0, "--m", "an integer >= 0 (0: automatic)", a.m)
    check(0.0 < a.inner < 1.0 / math.sqrt(3.0), "--inner", "a ratio in (0, 1/sqrt(3)) = "
          "(0, 0.577) (the cube's corner inside the sphere)", a.inner)
    check(finite(a.grade) and a.grade > 0.0, "--grade", "a positive finite ratio (1: uniform)",
          a.grade)
    check(a.subdivide >= 1, "--subdivide", "a positive integer (spans per 90 degrees)",
          a.subdivide)
    check(a.elevate >= 2, "--elevate", "a degree >= 2 (the patch is quadratic)", a.elevate)
    if a.kind == "nurbs":
        check(a.grade == 1.0, "--grade", "1 with --kind nurbs (refined uniformly by *REFINE)",
              a.grade)
    else:
        m = a.m or radial_count(a.n, a.inner)
        for count in (a.n, 2 * a.n, m):
            check(a.grade == 1.0 or hertz.graded_ok(count, a.grade), "--grade",
                  f"a ratio closer to 1, so that all {count} elements keep a positive length",
                  a.grade)
        count = lattice_count(a.kind, a.n, m) * (1 if a.partner == "wall" else 2)
        check(count <= halfdisc.MAX_ID, "--n, --m", f"a mesh of at most {halfdisc.MAX_ID} "
              f"nodes (ids are default Fortran integers)", (a.n, m))
    check(a.partner == "wall" or a.name == "BALL", "--name",
          "BALL with --partner body (the bodies are UPPER and LOWER)", a.name)
    # the body name also names the sets NAME_X0_ZETA0 (nurbs): 9 characters more
    check(halfdisc.NAME.match(a.name) and len(a.name) <= 55, "--name",
          f"a name of at most 55 characters ({halfdisc.NAME_RULE})", a.name)
    halfdisc.check_material(check, a)
    check(finite(a.v), "--v", "a finite speed", a.v)
    check(finite(a.penalty) and a.penalty > 0.0, "--penalty", "a positive finite penalty",
          a.penalty)
    halfdisc.check_step(check, a)


def main():
    halfdisc.run(parser(), check_options, body_cards, deck, "quarter_ball.py")


if __name__ == "__main__":
    main()
