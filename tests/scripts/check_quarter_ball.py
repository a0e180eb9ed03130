#!/usr/bin/python3
"""The quarter-ball decks of scripts/mesh/quarter_ball.py (doc/user-guide.md §9, "3D meshes of
the Hertz sphere") describe the quarter-ball x >= cx, y >= cy, |r - c| <= R they claim to.

Reads the decks the script writes (its own deck parser below, nothing imported from the
script) and checks, with numpy and its own element and NURBS code:
  * NURBS (one patch, also the mirrored LOWER patch of --partner body and R = 2 at another
    centre): Cox-de Boor evaluation of the trivariate patch; volume by Gauss quadrature
    (8 x 8 x 8 points) per Bezier element of the patch after its *REFINE = pi R^3 / 3 to
    1e-12; 41 x 41 points of SIDE=ZETA1 at distance R from c to 1e-12; the control points of
    the node sets NAME_X0 and NAME_Y0 exactly on x = cx and y = cy; det J > 0 at every Gauss
    point and at the contact point c -+ R e_z (a patch corner), where the patch passes
    exactly; det J = 0 on the two degenerate sides (XI0: the x axis segment, ZETA0: the
    centre), which collapse to that line and point; the normal x_xi x x_eta of ZETA1 points
    away from c.
  * hexahedra (C3D8, C3D20, C3D27: shape functions from the Abaqus node order by a
    Vandermonde matrix of the element's monomials, not the script's formulas; element data
    lines of at most 16 entries, continued after a line's last comma): det J > 0 at
    the element's Gauss points and at its nodes; volume (Gauss, exact for these maps) ->
    pi R^3 / 3 at rate 2 (hex8: 1.9 to 2.1 from n = 2, 4, 8) and 4 (hex20, hex27: >= 3.8);
    every node of every face of NAME_SPH at radius R (1e-14 R); NAME_X0 and NAME_Y0 are
    exactly the nodes with x = cx and y = cy; every boundary face (a face of one element
    only) lies on x = cx, on y = cy or is listed in NAME_SPH, and every listed face is a
    boundary face; the outward normal of every boundary face (from its Abaqus corner order
    S1..S6, which runs clockwise seen from outside) points away from c on the sphere and
    along -e_x, -e_y on the planes; the contact point is a node of NAME_SPH. Also graded, and
    mirrored (--partner body, whose faces are S1).
  * the node order is gmsh's: a cube meshed by gmsh in C3D20 and in C3D27 and written in
    its Abaqus form has every node where this order puts it (C3D27: centre 21, face centres
    of S1..S6 22-27); skipped without gmsh's Python module;
  * the default deck's cards: *ANALYSIS, TYPE=3D, C3D20, the rigid wall at the contact point
    (0, 0, 0) with NORMAL=0,0,1 against BALL_SPH, u_x = 0 on BALL_X0, u_y = 0 on BALL_Y0,
    v_z = -0.1 (doc/reference.md §3.8);
  * the command line: the script run as a program writes the deck checked here (the checks
    call its option parsing and deck writer in this process, for speed); bad options end with
    "quarter_ball.py: OPTION: expected ..." and exit status 1, nothing on stdout.
Prints one line per check and "N passed, N failed"; exit 1 on any failure.
"""
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "scripts", "mesh", "quarter_ball.py")
sys.path.insert(0, os.path.dirname(SCRIPT))
import quarter_ball  # noqa: E402  (only to write the decks: nothing else is used)
NEN = {"C3D8": 8, "C3D20": 20, "C3D27": 27}
# Abaqus hexahedron: corners, the corners each edge node 9..20 lies between, faces S1..S6
CORNER_XI = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                      [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
EDGE_CORNERS = [1, 2, 2, 3, 3, 4, 4, 1, 5, 6, 6, 7, 7, 8, 8, 5, 1, 5, 2, 6, 3, 7, 4, 8]
FACE_CORNERS = {"S1": [1, 2, 3, 4], "S2": [5, 8, 7, 6], "S3": [1, 5, 6, 2],
                "S4": [2, 6, 7, 3], "S5": [3, 7, 8, 4], "S6": [4, 8, 5, 1]}


class Tally:
    """Counts checks, prints one line each and the closing line."""

    def __init__(self):
        self.counts = [0, 0]

    def __call__(self, ok, label, detail=""):
        self.counts[0 if ok else 1] += 1
        print(("  ok   " if ok else "  FAIL ") + label +
              ("" if ok or not detail else f": {detail}"))
        return ok

    def close(self):
        good, bad = self.counts
        print(f"{good} passed, {bad} failed")
        return 0 if bad == 0 and good > 0 else 1


# ---------------------------------------------------------------------------------------------
# deck reading
def read_deck(text):
    """Cards of a deck: [(KEYWORD, {PARAM: value}, [data lines])], comments dropped."""
    cards = []
    for line in text.splitlines():
        if not line.strip() or line.startswith("**"):
            continue
        if line.startswith("*"):
            head, params = line[1:].split(",")[0].strip().upper(), {}
            rest = line[1:][len(line[1:].split(",")[0]):]
            key = None
            for part in rest.split(","):
                if "=" in part:
                    key, val = (s.strip() for s in part.split("=", 1))
                    params[key.upper()] = val
                elif key is not None and part.strip():
                    params[key.upper()] += "," + part.strip()   # DEGREE=2,2,2
            cards.append((head, params, []))
        else:
            cards[-1][2].append(line)
    return cards


def fields(lines):
    return [t.strip() for ln in lines for t in ln.split(",") if t.strip()]


def model(text):
    """Nodes {id: xyz}, elements {elset: (type, ids, conn)}, node sets {name: [items]},
    surfaces {name: [data lines split]}, patches {name: card data}."""
    m = {"nodes": {}, "elements": {}, "nsets": {}, "surfaces": {}, "patches": {}}
    patch = None
    for head, par, data in read_deck(text):
        if head == "NODE":
            for ln in data:
                v = ln.split(",")
                m["nodes"][int(v[0])] = np.array([float(x) for x in v[1:]])
        elif head == "ELEMENT" and par["TYPE"] in NEN:   # goes on after a line's last comma
            size = NEN[par["TYPE"]] + 1
            vals = [int(x) for x in fields(data)]
            rows = [vals[k:k + size] for k in range(0, len(vals), size)]
            ends = [ln.rstrip().endswith(",") for ln in data]
            lines_ok = ends == ([True, False] * len(rows) if size > 16 else [False] * len(rows))
            m["elements"][par["ELSET"]] = (par["TYPE"], [r[0] for r in rows],
                                          [r[1:] for r in rows], lines_ok)
        elif head == "NSET":
            m["nsets"][par["NSET"]] = (("SIDE", par["PATCH"], par["SIDE"]) if "SIDE" in par
                                       else fields(data))
        elif head == "SURFACE":
            m["surfaces"][par["NAME"]] = (("SIDE", par["PATCH"], par["SIDE"]) if "SIDE" in par
                                          else [fields([ln]) for ln in data])
        elif head == "PATCH":
            patch = {"degree": [int(x) for x in par["DEGREE"].split(",")],
                     "size": [int(x) for x in par["SIZE"].split(",")], "knots": {},
                     "subdivide": [1, 1, 1]}
            m["patches"][par["NAME"]] = patch
        elif head == "KNOTS":
            patch["knots"][int(par["DIRECTION"])] = [float(x) for x in " ".join(data).split()]
        elif head == "CONTROL POINTS":
            patch["cp"] = np.array([[float(x) for x in ln.split(",")] for ln in data])
        elif head == "REFINE":
            m["patches"][par["PATCH"]]["subdivide"] = [int(x) for x in
                                                       par["SUBDIVIDE"].split(",")]
    return m


def node_set(m, name):
    """Items of a node set with set names expanded (ids, or (patch, side) pairs)."""
    items = m["nsets"][name]
    if isinstance(items, tuple):
        return [items[1:]]
    out = []
    for it in items:
        out += node_set(m, it) if it in m["nsets"] else [int(it)]
    return out


def deck_text(args):
    """The deck quarter_ball.py writes for the command-line arguments args (run in this
    process, through the script's own option parsing and checks, for speed)."""
    a = quarter_ball.parser().parse_args(args)
    quarter_ball.check_options(a)
    return quarter_ball.deck(a, "scripts/mesh/quarter_ball.py " + " ".join(args))


# ---------------------------------------------------------------------------------------------
# hexahedra
def node_xi(nen):
    """Natural coordinates of the nen nodes in Abaqus order (C3D27: the centre is node 21,
    the face centres of S1..S6 are 22-27, as gmsh's Abaqus export has them)."""
    edges = np.array([(CORNER_XI[a - 1] + CORNER_XI[b - 1]) / 2
                      for a, b in zip(EDGE_CORNERS[0::2], EDGE_CORNERS[1::2])])
    faces = np.array([CORNER_XI[[k - 1 for k in c]].mean(axis=0) for c in FACE_CORNERS.values()])
    return np.vstack([CORNER_XI, edges, np.zeros((1, 3)), faces])[:nen]


def monomials(nen):
    """Exponents of the element's polynomial space: trilinear (8), serendipity (20: at most one
    exponent 2), triquadratic (27)."""
    top = 1 if nen == 8 else 2
    e = [(a, b, c) for c in range(top + 1) for b in range(top + 1) for a in range(top + 1)]
    return np.array([t for t in e if nen != 20 or sum(x == 2 for x in t) <= 1])


def shape_grad(nen, pts):
    """dN/dxi (npts, nen, 3) from the Vandermonde matrix of the monomials at the nodes."""
    ex = monomials(nen)
    xi = node_xi(nen)
    vand = np.prod(xi[:, None, :] ** ex[None, :, :], axis=2)          # (node, monomial)
    coef = np.linalg.inv(vand)                                          # N = mono . coef
    out = np.zeros((len(pts), nen, 3))
    for d in range(3):
        lower = ex.copy()
        lower[:, d] = np.maximum(ex[:, d] - 1, 0)
        dmono = ex[:, d] * np.prod(pts[:, None, :] ** lower[None, :, :], axis=2)
        out[:, :, d] = dmono @ coef
    return out


def gauss(k):
    t, w = np.polynomial.legendre.leggauss(k)
    g = np.array(np.meshgrid(t, t, t, indexing="ij")).reshape(3, -1).T
    return g, np.prod(np.array(np.meshgrid(w, w, w, indexing="ij")).reshape(3, -1), axis=0)


def hex_volume(etype, xyz):
    """(volume, min det J at the Gauss points, min det J at the nodes) of elements xyz."""
    nen = NEN[etype]
    pts, w = gauss(3)        # exact for the volume of all three (degree <= 5 per variable)
    det = np.linalg.det(np.einsum("eni,gnj->egij", xyz, shape_grad(nen, pts)))
    own = gauss(2 if nen == 8 else 3)[0]
    det_own = np.linalg.det(np.einsum("eni,gnj->egij", xyz, shape_grad(nen, own)))
    det_nodes = np.linalg.det(np.einsum("eni,gnj->egij", xyz, shape_grad(nen, node_xi(nen))))
    return float((det * w).sum()), det_own.min(), det_nodes.min()


def face_nodes(nen):
    """{Sk: local indices of its nodes} (all whose natural coordinate is the face's)."""
    xi = node_xi(nen)
    out = {}
    for face, corners in FACE_CORNERS.items():
        centre = CORNER_XI[[k - 1 for k in corners]].mean(axis=0)
        d = int(np.nonzero(centre)[0][0])
        out[face] = np.nonzero(xi[:, d] == centre[d])[0]
    return out


def check_hex_body(t, m, name, c, radius, label):
    """Geometry checks of one hexahedral body; returns its volume."""
    etype, ids, conn, lines_ok = m["elements"][name]
    nen = NEN[etype]
    t(lines_ok, f"{label}: element data lines of at most 16 entries, continued after a comma")
    nid = np.array(sorted(m["nodes"]))
    pos = {n: k for k, n in enumerate(nid)}
    x = np.array([m["nodes"][n] for n in nid])
    cidx = np.array([[pos[n] for n in row] for row in conn])
    eidx = {e: k for k, e in enumerate(ids)}
    vol, det_gp, det_nodes = hex_volume(etype, x[cidx])
    t(det_gp > 0.0 and det_nodes > 0.0, f"{label}: det J > 0 at the Gauss points and nodes "
      f"(min {det_gp:.2e}, {det_nodes:.2e})")
    used = np.unique(cidx)
    mine = np.zeros(len(x), bool)
    mine[used] = True
    fn = face_nodes(nen)
    sph = [(eidx[int(e)], f) for e, f in m["surfaces"][name + "_SPH"]]
    on = np.unique(np.concatenate([cidx[e][fn[f]] for e, f in sph]))
    err = np.abs(np.linalg.norm(x[on] - c, axis=1) - radius).max()
    t(err <= 1e-14 * radius, f"{label}: {len(on)} nodes of {len(sph)} faces of {name}_SPH at "
      f"radius R to 1e-14 R: max |r - R| = {err:.1e}")
    for key, d in (("X0", 0), ("Y0", 1)):
        want = set(np.nonzero(mine & (x[:, d] == c[d]))[0])
        got = {pos[n] for n in node_set(m, f"{name}_{key}")}
        t(got == want, f"{label}: {name}_{key} = the {len(want)} nodes with "
          f"{'xy'[d]} = {c[d]:g} exactly", f"{len(got ^ want)} differ")
    # boundary faces: the faces of one element only (rows of sorted node indices)
    faces = list(FACE_CORNERS)
    rows = np.vstack([np.sort(cidx[:, fn[f]], axis=1) for f in faces])
    which = np.array([(e, k) for k in range(6) for e in range(len(cidx))])
    _, inv, cnt = np.unique(rows, axis=0, return_inverse=True, return_counts=True)
    bnd = np.nonzero(cnt[inv] == 1)[0]
    face_id = {(e, f): k * len(cidx) + e for k, f in enumerate(faces) for e in range(len(cidx))}
    listed = np.zeros(len(rows), bool)
    listed[[face_id[ef] for ef in sph]] = True
    plane = np.zeros(len(rows), bool)
    for d in (0, 1):
        plane |= np.all(x[rows, d] == c[d], axis=1)
    boundary = np.zeros(len(rows), bool)
    boundary[bnd] = True
    t(np.all(boundary[listed]) and np.all(boundary == (listed | plane)) and
      not np.any(listed & plane), f"{label}: the boundary faces are {listed.sum()} of "
      f"{name}_SPH and {(plane & boundary).sum()} on the symmetry planes",
      f"{(boundary & ~listed & ~plane).sum()} others, {(listed & ~boundary).sum()} listed "
      "inside")
    # Newell normal of the corner loop of each boundary face: the Abaqus order S1..S6 runs
    # clockwise seen from outside, so the outward normal is minus its right-hand normal
    corner = np.array([cidx[which[r, 0]][[k - 1 for k in FACE_CORNERS[faces[which[r, 1]]]]]
                       for r in bnd])
    p = x[corner]
    out = -sum(np.cross(p[:, k], p[:, (k + 1) % 4]) for k in range(4))
    sph_row, away = listed[bnd], np.einsum("fi,fi->f", out, p.mean(axis=1) - c)
    bad = np.count_nonzero(sph_row & (away <= 0.0))
    for d in (0, 1):
        rowd = np.all(p[:, :, d] == c[d], axis=1)
        side = np.linalg.norm(np.delete(out, d, axis=1), axis=1)
        bad += np.count_nonzero(rowd & ((out[:, d] >= 0.0) | (side > 1e-12 * np.abs(out[:, d]))))
    t(bad == 0, f"{label}: outward normals of all {len(bnd)} boundary faces (S1..S6 corner "
      "order): away from c on the sphere, -e_x / -e_y on the planes", f"{bad} wrong")
    return vol


def hex_case(t, kind, n, m_rad, extra=(), label=None):
    m = model(deck_text(["--kind", kind, "--n", str(n), "--m", str(m_rad)] + list(extra)))
    return check_hex_body(t, m, "BALL", np.array([0.0, 0.0, 1.0]), 1.0,
                          label or f"{kind} n = {n}, m = {m_rad}"), m


def check_hex(t):
    exact = math.pi / 3.0
    for kind, lo, hi in (("hex8", 1.9, 2.1), ("hex20", 3.8, 9.0), ("hex27", 3.8, 9.0)):
        errs = []
        for n in (2, 4, 8):
            vol, m = hex_case(t, kind, n, n)
            errs.append(abs(vol - exact))
        rates = [math.log2(a / b) for a, b in zip(errs, errs[1:])]
        t(all(lo <= r <= hi for r in rates), f"{kind}: volume error " +
          ", ".join(f"{e:.3e}" for e in errs) + " (n = 2, 4, 8): rates " +
          ", ".join(f"{r:.2f}" for r in rates) + f" in [{lo}, {hi}]")
    vol, m = hex_case(t, "hex20", 6, 5, ["--grade", "1.25"], "hex20 n = 6, m = 5, grade 1.25")
    t(abs(vol - exact) < 1e-3, f"hex20 graded: volume {vol:.9f} against pi/3 = {exact:.9f}")
    m = model(deck_text(["--kind", "hex27", "--n", "3", "--m", "2", "--partner", "body",
                         "--radius", "2"]))
    for name, cz in (("UPPER", 2.0), ("LOWER", -2.0)):
        c = np.array([0.0, 0.0, cz])
        vol = check_hex_body(t, m, name, c, 2.0, f"hex27 R = 2, {name}")
        t(abs(vol - 8 * math.pi / 3) < 1e-2, f"hex27 R = 2, {name}: volume {vol:.6f} ~ 8 pi/3")
        faces = {f for _, f in m["surfaces"][name + "_SPH"]}
        t(faces == ({"S2"} if name == "UPPER" else {"S1"}),
          f"hex27 R = 2, {name}: contact faces {sorted(faces)}")
    contact = [k for k, v in m["nodes"].items() if np.all(v == 0.0)]
    t(len(contact) == 2, "hex27 R = 2: the contact point (0, 0, 0) is a node of both bodies")


# ---------------------------------------------------------------------------------------------
# NURBS
def basis(knots, p, u):
    """B-spline basis N (len(u), n) and dN/du by the Cox-de Boor recursion (0/0 := 0); u at the
    last knot belongs to the last non-empty span."""
    kv = np.asarray(knots)
    u = np.asarray(u, dtype=float)
    last = np.nonzero(kv[:-1] < kv[1:])[0][-1]
    n0 = ((kv[:-1][None, :] <= u[:, None]) & (u[:, None] < kv[1:][None, :])).astype(float)
    n0[u == kv[-1], last] = 1.0
    nk = n0
    for k in range(1, p + 1):
        lower = nk
        left, right = np.zeros((len(u), lower.shape[1] - 1)), np.zeros((len(u), lower.shape[1] - 1))
        dleft, dright = np.zeros_like(left), np.zeros_like(right)
        for i in range(lower.shape[1] - 1):
            a = kv[i + k] - kv[i]
            b = kv[i + k + 1] - kv[i + 1]
            if a > 0:
                left[:, i] = (u - kv[i]) / a * lower[:, i]
                dleft[:, i] = k / a * lower[:, i]
            if b > 0:
                right[:, i] = (kv[i + k + 1] - u) / b * lower[:, i + 1]
                dright[:, i] = k / b * lower[:, i + 1]
        nk, dn = left + right, dleft - dright
    return nk, dn


def patch_eval(patch, u, v, w):
    """Points (len(u), len(v), len(w), 3) and Jacobians (..., 3, 3) of the NURBS patch on the
    tensor grid u x v x w."""
    n1, n2, n3 = patch["size"]
    p = patch["degree"]
    cp = patch["cp"].reshape(n3, n2, n1, 4)
    hom = np.concatenate([cp[..., :3] * cp[..., 3:], cp[..., 3:]], axis=-1)
    (b1, d1), (b2, d2), (b3, d3) = (basis(patch["knots"][k + 1], p[k], s)
                                    for k, s in enumerate((u, v, w)))
    def tensor(f1, f2, f3):
        return np.einsum("ai,bj,ck,kjil->abcl", f1, f2, f3, hom, optimize=True)
    a = tensor(b1, b2, b3)
    da = [tensor(d1, b2, b3), tensor(b1, d2, b3), tensor(b1, b2, d3)]
    x = a[..., :3] / a[..., 3:]
    jac = np.stack([(g[..., :3] - g[..., 3:] * x) / a[..., 3:] for g in da], axis=-1)
    return x, jac


def bezier_gauss(patch, k, ng):
    """Gauss points and weights per direction over the Bezier elements after *REFINE."""
    kv = np.unique(patch["knots"][k + 1])
    pts, wts = [], []
    t, w = np.polynomial.legendre.leggauss(ng)
    for a, b in zip(kv[:-1], kv[1:]):
        s = np.linspace(a, b, patch["subdivide"][k] + 1)
        for lo, hi in zip(s[:-1], s[1:]):
            pts.append(lo + (hi - lo) * (t + 1) / 2)
            wts.append((hi - lo) / 2 * w)
    return np.concatenate(pts), np.concatenate(wts), len(kv) - 1


def side_points(patch, side, count=41):
    """Tensor grid (u, v, w) of a side: the side's parameter fixed, count points on the others."""
    s = np.linspace(0.0, 1.0, count)
    grid = [s, s, s]
    d = {"XI": 0, "ETA": 1, "ZETA": 2}[side.rstrip("01")]
    grid[d] = np.array([float(side[-1])])
    return patch_eval(patch, *grid)


def side_cps(patch, side):
    """Control points (k, 4) of a side of the coarse patch."""
    n1, n2, n3 = patch["size"]
    cp = patch["cp"].reshape(n3, n2, n1, 4)
    d = {"XI": 2, "ETA": 1, "ZETA": 0}[side.rstrip("01")]
    return np.take(cp, 0 if side.endswith("0") else cp.shape[d] - 1, axis=d).reshape(-1, 4)


def check_nurbs_body(t, m, name, c, radius, down, label):
    patch = m["patches"][name]
    t(patch["degree"] == [2, 2, 2] and patch["size"] == [3, 5, 3] and len(patch["cp"]) == 45,
      f"{label}: quadratic patch of 3 x 5 x 3 control points")
    g = [bezier_gauss(patch, k, 8) for k in range(3)]
    x, jac = patch_eval(patch, g[0][0], g[1][0], g[2][0])
    det = np.linalg.det(jac)
    wt = np.einsum("a,b,c->abc", g[0][1], g[1][1], g[2][1])
    vol, exact = float((det * wt).sum()), math.pi * radius ** 3 / 3
    nel = "x".join(str(gk[2] * s) for gk, s in zip(g, patch["subdivide"]))
    t(abs(vol - exact) <= 1e-12 * exact, f"{label}: volume over {nel} Bezier elements "
      f"(8^3 Gauss points each) = pi R^3/3 to 1e-12: relative error "
      f"{abs(vol - exact) / exact:.1e}", f"{vol:.15f} against {exact:.15f}")
    t(det.min() > 0.0, f"{label}: det J > 0 at all {det.size} Gauss points (min "
      f"{det.min():.3g})")
    xs, js = side_points(patch, "ZETA1")
    err = np.abs(np.linalg.norm(xs - c, axis=-1) - radius).max()
    t(err <= 1e-12 * radius, f"{label}: 41 x 41 points of ZETA1 at distance R from c to "
      f"1e-12 R: max |r - R| = {err:.1e}")
    normal = np.cross(js[..., 0], js[..., 1])
    inner = np.einsum("...i,...i->...", normal, xs - c)[1:]   # xi = 0 (the x axis) excluded
    t(inner.min() > 0.0, f"{label}: x_xi x x_eta of ZETA1 points away from c")
    for key, d in (("X0", 0), ("Y0", 1)):
        sides = [s for _, s in node_set(m, f"{name}_{key}")]
        pts = np.vstack([side_cps(patch, s) for s in sides])
        t(np.all(pts[:, d] == c[d]), f"{label}: control points of {name}_{key} "
          f"({', '.join(sides)}) exactly on {'xy'[d]} = {c[d]:g}")
    surf = m["surfaces"][f"{name}_SPH"]
    t(surf == ("SIDE", name, "ZETA1"), f"{label}: {name}_SPH is SIDE=ZETA1")
    # degenerate sides: XI0 collapses to the x axis segment, ZETA0 to the centre; det J = 0
    for side, what in (("XI0", "the x axis segment"), ("ZETA0", "the centre")):
        xs, js = side_points(patch, side)
        dj = np.abs(np.linalg.det(js)).max()
        off = xs - c
        far = (np.abs(off[..., 1:]).max() if side == "XI0" else np.abs(off).max())
        t(dj <= 1e-12 * radius ** 3 and far <= 1e-15 * radius,
          f"{label}: {side} collapses to {what}, det J = 0 there",
          f"max |det J| {dj:.3g}, distance {far:.3g}")
    # the contact point is the corner XI1, ETA0 (ETA1 mirrored), ZETA1
    eta = 1.0 if down else 0.0
    xc, jc = patch_eval(patch, np.array([1.0]), np.array([eta]), np.array([1.0]))
    want = c + [0.0, 0.0, -radius if not down else radius]
    dc = float(np.linalg.det(jc[0, 0, 0]))
    t(np.abs(xc[0, 0, 0] - want).max() <= 1e-15 * radius and dc > 0.0,
      f"{label}: corner (1, {eta:g}, 1) is the contact point {want.tolist()}, det J = {dc:.4f}")


def check_nurbs(t):
    m = model(deck_text(["--kind", "nurbs", "--subdivide", "4"]))
    check_nurbs_body(t, m, "BALL", np.array([0.0, 0.0, 1.0]), 1.0, False, "nurbs R = 1")
    m = model(deck_text(["--kind", "nurbs", "--subdivide", "2", "--m", "3", "--radius", "2",
                         "--centre", "0.5,-0.25,3", "--partner", "body", "--elevate", "3"]))
    for name, cz, down in (("UPPER", 3.0, False), ("LOWER", -1.0, True)):
        check_nurbs_body(t, m, name, np.array([0.5, -0.25, cz]), 2.0, down,
                         f"nurbs R = 2, {name}")


# ---------------------------------------------------------------------------------------------
def check_cards(t):
    """The default deck's conditions: the wall touches the contact point (reference.md §9.7)."""
    cards = {head: (par, data) for head, par, data in read_deck(deck_text(["--n", "2"]))}
    par, data = cards["RIGID WALL"]
    t(par.get("POINT") == "0,0,0" and par.get("NORMAL") == "0,0,1" and data == ["BALL_SPH"],
      "default deck: *RIGID WALL, POINT=0,0,0, NORMAL=0,0,1 against BALL_SPH")
    t(cards["ANALYSIS"][0] == {"TYPE": "3D"} and cards["ELEMENT"][0]["TYPE"] == "C3D20",
      "default deck: *ANALYSIS, TYPE=3D and C3D20 elements")
    t(cards["BOUNDARY"][1] == ["BALL_X0, 1, 1", "BALL_Y0, 2, 2"] and
      cards["INITIAL CONDITIONS"][1] == ["BALL, 3, -0.1"],
      "default deck: u_x = 0 on BALL_X0, u_y = 0 on BALL_Y0, v_z = -0.1 on BALL")


def check_gmsh_order(t):
    """The node order agrees with gmsh's Abaqus export (a cube meshed with C3D20 and with C3D27
    elements): each exported node of every element sits where the trilinear map of the
    element's corners puts the natural coordinates node_xi gives it. Skipped without gmsh's
    Python module."""
    try:
        import gmsh
    except ImportError:
        print("  skip gmsh's C3D20 and C3D27 node order (no gmsh Python module)")
        return
    for incomplete, etype in ((1, "C3D20"), (0, "C3D27")):
        path = os.path.join(tempfile.mkdtemp(), "cube.inp")
        gmsh.initialize()
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
        gmsh.model.occ.synchronize()
        gmsh.model.mesh.setTransfiniteAutomatic()
        gmsh.option.setNumber("Mesh.RecombineAll", 1)
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", incomplete)
        gmsh.model.mesh.generate(3)
        gmsh.model.mesh.setOrder(2)
        gmsh.write(path)
        gmsh.finalize()
        with open(path) as f:
            m = model(f.read())
        _, _, conn, lines_ok = next(v for v in m["elements"].values() if v[0] == etype)
        x = np.array([[m["nodes"][n] for n in row] for row in conn])
        xi = node_xi(NEN[etype])
        trilinear = np.prod(1.0 + xi[:, None, :] * CORNER_XI[None, :, :], axis=2) / 8.0
        err = np.abs(np.einsum("nc,eci->eni", trilinear, x[:, :8]) - x).max()
        t(lines_ok and err < 1e-12, f"gmsh's Abaqus export of a cube in {len(conn)} {etype}: "
          "every node where this order puts it", f"max distance {err:.3g}")


def check_cli(t):
    args = ["--kind", "hex27", "--n", "2", "--partner", "body"]
    p = subprocess.run([sys.executable, SCRIPT] + args, stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True)
    t(p.returncode == 0 and p.stdout == deck_text(args) and not p.stderr,
      f"quarter_ball.py {' '.join(args)}: exit 0, the deck of the in-process run")
    for args, option in ((["--inner", "0.6"], "--inner"), (["--n", "0"], "--n"),
                         (["--kind", "nurbs", "--grade", "1.2"], "--grade"),
                         (["--grade", "0.1", "--n", "40"], "--grade"),
                         (["--radius", "nan"], "--radius"), (["--name", "1X"], "--name"),
                         (["--partner", "body", "--name", "B"], "--name")):
        p = subprocess.run([sys.executable, SCRIPT] + args, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True)
        msg = p.stderr.strip()
        t(p.returncode == 1 and not p.stdout and msg.count("\n") == 0 and
          msg.startswith(f"quarter_ball.py: {option}: expected"),
          f"refused: {' '.join(args)}", f"exit {p.returncode}, {msg!r}")


def main():
    t = Tally()
    check_nurbs(t)
    check_hex(t)
    check_cards(t)
    check_gmsh_order(t)
    check_cli(t)
    sys.exit(t.close())


if __name__ == "__main__":
    main()
