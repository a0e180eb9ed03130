#!/usr/bin/env python3
"""Decks of the dynamic Hertz benchmark (doc/reference.md §1): two half-cylinders R = 4 touching at
the origin, plane strain, E = 1000, nu = 0.2, rho = 1, symmetry u_x = 0 on the cuts x = 0,
frictionless penalty contact (eps_N = 1e5, two-half-pass; --algorithm MORTAR or NODE TO SEGMENT),
dt = 5e-4, T = 0.9. --lower N: the lower body with N spans (iga) or elements (q8) per direction
(non-matching meshes).

    hertz.py --kind iga --mass HRZ [--subdivide 16] [--elevate 3] > deck.inp   (see input/hertz/)
    hertz.py --kind q8 --mass HRZ [--n 16] > deck.inp
    hertz.py --kind iga4 --mass HRZ [--subdivide 16] > deck.inp   (4 merged patches each,
        scripts/mesh/disc.py --kind halfdisc: no point with det J = 0; 16 spans on the cut)

--variant both (default): the upper body moves down at 2 and the lower one up at 2 (V_rel = 4);
--variant one: the upper body moves down at 2, the lower one is at rest (V_rel = 2).
--wall: one body (the upper one) against a rigid frictionless wall at y = 0 (doc/reference.md §1.3:
equivalent to two identical bodies at +-V).

Graded meshes (--grade-arc Q, --grade-depth Q; default 1 = uniform): the spans (IGA knots) or
elements (Q8 node parameters) of the parameter direction along the contact arc (A -> G1) and
of the direction along the cut (A -> B) grow geometrically by the ratio Q from the contact
point A, so the contact zone is fine and the degenerate corners G1, G2 (which set omega_max)
are coarse. IGA: the refined patch is written out (*KNOTS with interior knots and the control
points from knot insertion, Piegl & Tiller A5.1, in homogeneous coordinates); the geometry is
that of the 3 x 3 patch exactly. Q8: corner nodes at the graded parameters, midside nodes at
the mean parameter of their corners, all on the same map.

Static Hertz (--static D --alpha A, with --wall): no initial velocity; the top 45-degree arc
G2 -> B of the upper body (node set UPPER_TOP) is moved down by D (prescribed displacement,
constant in time) and mass-proportional damping ALPHA relaxes the body against the wall to the
static state (dynamic relaxation).

Bad values (counts < 1, degree < 2, a penalty, t_end or grading ratio <= 0, a negative dt,
alpha or field-every, mass passes outside [0, 50], D outside (0, 2R), non-finite numbers) end
the script with a one-line message and exit status 1, before anything is written.

Ids of two Q8 bodies: the lower body's node and element ids start at 100001 where the upper
body has at most 100000 nodes (n <= 181), else at 1 + the next power of ten above its count
(n = 707, 1.5 million nodes per body: 10000001; bench/benchmark.py --suite real).
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import halfdisc  # noqa: E402
import disc  # noqa: E402

LOWER_IDS = 100000   # Q8: id offset of the lower body (of meshes up to n = 181, lower_ids)
MAX_PASSES = 50      # upper end of *DYNAMIC, MASS PASSES= (deck_step.f90)


def parser():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--kind", choices=["iga", "iga4", "q8"], default="iga",
                    help="iga: one patch; iga4: 4 merged patches (disc.py), 2 x --subdivide "
                         "spans on the cut; q8: Q8 mesh")
    ap.add_argument("--mass", default="HRZ", choices=["CONSISTENT", "ROW SUM", "HRZ"])
    ap.add_argument("--mass-passes", type=int, default=0,
                    help="with --mass CONSISTENT: apply it by this many corrector passes "
                         "(MASS SOLVER=CORRECTOR); 0: the default solver (Cholesky factor)")
    ap.add_argument("--subdivide", type=int, default=16, help="IGA: spans per direction")
    ap.add_argument("--elevate", type=int, default=2)
    ap.add_argument("--n", type=int, default=16, help="Q8: elements per direction")
    ap.add_argument("--variant", choices=["both", "one"], default="both")
    ap.add_argument("--wall", action="store_true")
    ap.add_argument("--penalty", type=float, default=1.0e5)
    ap.add_argument("--algorithm", default="TWO HALF PASS",
                    choices=["TWO HALF PASS", "NODE TO SEGMENT", "MORTAR"])
    ap.add_argument("--lower", type=int, default=0,
                    help="spans (iga) or elements (q8) per direction of the lower body, for "
                         "non-matching meshes (0: as the upper body)")
    ap.add_argument("--dt", type=float, default=5.0e-4)
    ap.add_argument("--stability", choices=["STOP", "WARN"], default="STOP",
                    help="STABILITY= of the contact card (WARN: run even where the contact "
                         "ratio r exceeds 1 at the given dt)")
    ap.add_argument("--t-end", type=float, default=0.9)
    ap.add_argument("--field-every", type=int, default=100)
    ap.add_argument("--plane-stress", action="store_true")
    ap.add_argument("--grade-arc", type=float, default=1.0,
                    help="span growth ratio along the contact arc from A (1: uniform)")
    ap.add_argument("--grade-depth", type=float, default=1.0,
                    help="span growth ratio along the cut from A (1: uniform)")
    ap.add_argument("--static", type=float, default=None, metavar="D",
                    help="static Hertz: top arc moved down by D (needs --wall)")
    ap.add_argument("--alpha", type=float, default=0.0, help="*DAMPING, ALPHA= (static)")
    return ap


def check_options(a):
    """Rejects the values that would give an invalid deck or a traceback."""
    check, finite = halfdisc.checker("hertz.py"), math.isfinite
    check(a.subdivide >= 1, "--subdivide", "a positive integer (spans per direction)",
          a.subdivide)
    check(a.elevate >= 2, "--elevate", "a degree >= 2 (the patch is quadratic)", a.elevate)
    check(a.n >= 1, "--n", "a positive integer (Q8 elements per direction)", a.n)
    if a.kind == "iga4":
        check(a.subdivide % 2 == 0, "--subdivide", "an even number with --kind iga4 (the cut "
              "has as many spans, the patches beside the arc half of them)", a.subdivide)
        check(a.elevate == 2 and a.grade_arc == 1.0 and a.grade_depth == 1.0 and
              a.static is None, "--kind", "iga or q8 with --elevate, --grade-* or --static "
              "(iga4 is quadratic and uniform)", a.kind)
    if a.kind == "q8" and not a.wall:
        last = halfdisc.MAX_ID - halfdisc.q8_id_count(max(a.n, a.lower))
        check(lower_ids(a.n) <= last, "--n", f"a mesh whose lower body's ids stay <= "
              f"{halfdisc.MAX_ID}", a.n)
    check(0 <= a.mass_passes <= MAX_PASSES, "--mass-passes",
          f"an integer in [0, {MAX_PASSES}] (0: the default solver)", a.mass_passes)
    check(finite(a.penalty) and a.penalty > 0.0, "--penalty", "a positive finite penalty",
          a.penalty)
    halfdisc.check_step(check, a, "20 snapshots")
    check(a.lower >= 0, "--lower", "an integer >= 0 (0: as the upper body)", a.lower)
    if a.lower:
        check(a.kind in ("iga", "q8") and a.grade_arc == 1.0 and a.grade_depth == 1.0 and
              not a.wall, "--lower", "uniform iga or q8 meshes of two bodies", a.lower)
    spans = a.subdivide if a.kind == "iga" else a.n
    for opt, q in (("--grade-arc", a.grade_arc), ("--grade-depth", a.grade_depth)):
        check(finite(q) and q > 0.0, opt, "a positive finite ratio (1: uniform)", q)
        check(q == 1.0 or graded_ok(spans, q), opt,
              f"a ratio closer to 1, so that all {spans} spans keep a positive length", q)
    if a.static is not None:
        check(finite(a.static) and 0.0 < a.static < 8.0, "--static",
              "a displacement D in (0, 8) (down, less than the height 2R = 8 of the body)",
              a.static)
    check(finite(a.alpha) and a.alpha >= 0.0, "--alpha", "a finite damping >= 0", a.alpha)


def lower_ids(n):
    """The id offset of the lower Q8 body: LOWER_IDS, or the next power of ten above the
    upper body's count of ids when that exceeds it."""
    count = halfdisc.q8_id_count(n)
    return LOWER_IDS if count <= LOWER_IDS else 10 ** len(str(count))


def graded_ok(n, q):
    """True when the n spans of graded_knots(n, q) are all of positive length."""
    try:
        u = graded_knots(n, q)[2:-2]
    except (OverflowError, ZeroDivisionError):
        return False
    return all(map(math.isfinite, u)) and all(a < b for a, b in zip(u, u[1:]))


def graded_knots(n, q):
    """Open knot vector of degree 2 on [0, 1] with n spans growing by the ratio q from 0."""
    h = [q ** k for k in range(n)]
    tot = sum(h)
    u, acc = [0.0, 0.0, 0.0], 0.0
    for k in range(n - 1):
        acc += h[k]
        u.append(acc / tot)
    return u + [1.0, 1.0, 1.0]


def _insert(knots, pts, u, p=2):
    """Boehm knot insertion of u into a curve (Piegl & Tiller A5.1, once); pts homogeneous."""
    k = max(i for i in range(len(knots) - 1) if knots[i] <= u < knots[i + 1])
    new = []
    for i in range(len(pts) + 1):
        if i <= k - p:
            new.append(pts[i])
        elif i >= k + 1:
            new.append(pts[i - 1])
        else:
            a = (u - knots[i]) / (knots[i + p] - knots[i])
            new.append(tuple(a * x + (1.0 - a) * y for x, y in zip(pts[i], pts[i - 1])))
    return knots[:k + 1] + [u] + knots[k + 1:], new


def refine_net(net, knots1, knots2):
    """The 3 x 3 single-span net (x, y, w), direction 1 fastest, refined by knot insertion to
    the open degree-2 knot vectors knots1, knots2. Returns the net in the same order."""
    hom = [(w * x, w * y, w) for x, y, w in net]
    base = [0.0, 0.0, 0.0, 1.0, 1.0, 1.0]
    rows = [[hom[a + 3 * b] for a in range(3)] for b in range(3)]      # rows[b][a]
    for b in range(3):
        kv = list(base)
        for u in knots1[3:-3]:
            kv, rows[b] = _insert(kv, rows[b], u)
    n1 = len(rows[0])
    cols = [[rows[b][a] for b in range(3)] for a in range(n1)]        # cols[a][b]
    for a in range(n1):
        kv = list(base)
        for u in knots2[3:-3]:
            kv, cols[a] = _insert(kv, cols[a], u)
    n2 = len(cols[0])
    return [(cols[a][b][0] / cols[a][b][2], cols[a][b][1] / cols[a][b][2], cols[a][b][2])
            for b in range(n2) for a in range(n1)]


def _grades(a, centre):
    """(ratio of direction 1, ratio of direction 2): the arc direction is 1 for the upper body
    and 2 for the lower one (halfdisc.py orientations)."""
    return (a.grade_arc, a.grade_depth) if centre == "upper" else (a.grade_depth, a.grade_arc)


def graded_body_cards(a, centre, name, id_offset):
    """Body cards of a graded half-disc (IGA patch written out, or Q8 mesh), with the sets
    NAME_SYM, NAME_TOP and the surface NAME_ARC as halfdisc.body_cards names them."""
    net, sides = halfdisc.control_net(4.0, centre)
    sides = dict(sides, TOP="ETA1" if centre == "upper" else "XI1")
    q1, q2 = _grades(a, centre)
    out = []
    if a.kind == "iga":
        if a.elevate > 2:
            raise SystemExit("hertz.py: --elevate and grading cannot be combined")
        k1, k2 = graded_knots(a.subdivide, q1), graded_knots(a.subdivide, q2)
        fine = refine_net(net, k1, k2)
        n1, n2 = len(k1) - 3, len(k2) - 3
        out.append(f"*PATCH, NAME={name}, MATERIAL=SOFT, DEGREE=2,2, SIZE={n1},{n2}\n")
        for d, kv in ((1, k1), (2, k2)):
            out.append(f"*KNOTS, DIRECTION={d}\n" + halfdisc._lines(
                [f"{u:.17g}" for u in kv], 8))
        out.append("*CONTROL POINTS\n")
        out += [f"{x:.17g}, {y:.17g}, {w:.17g}\n" for x, y, w in fine]
        for key in ("SYM", "TOP"):
            out.append(f"*NSET, NSET={name}_{key}, PATCH={name}, SIDE={sides[key]}\n")
        out.append(f"*SURFACE, NAME={name}_ARC, PATCH={name}, SIDE={sides['ARC']}\n")
        return "".join(out)
    n = a.n
    g1, g2 = graded_knots(n, q1)[2:-2], graded_knots(n, q2)[2:-2]   # n + 1 corner parameters

    def par(g, i):
        return g[i // 2] if i % 2 == 0 else 0.5 * (g[i // 2] + g[i // 2 + 1])
    m = 2 * n
    nodes, nid = {}, 0
    for j in range(m + 1):
        for i in range(m + 1):
            if i % 2 == 1 and j % 2 == 1:
                continue
            nid += 1
            x, y, _ = halfdisc.patch_map(net, par(g1, i), par(g2, j))
            nodes[(i, j)] = (nid, x, y)
    elems = []
    for ey in range(n):
        for ex in range(n):
            i, j = 2 * ex, 2 * ey
            keys = [(i, j), (i + 2, j), (i + 2, j + 2), (i, j + 2),
                    (i + 1, j), (i + 2, j + 1), (i + 1, j + 2), (i, j + 1)]
            elems.append((len(elems) + 1, [nodes[k][0] for k in keys]))
    off = id_offset
    out.append("*NODE\n")
    out += [f"{i + off}, {x:.17g}, {y:.17g}\n" for i, x, y in nodes.values()]
    out.append(f"*ELEMENT, TYPE=Q8, ELSET={name}, MATERIAL=SOFT\n")
    out += [f"{e + off}, " + ", ".join(str(k + off) for k in c) + "\n" for e, c in elems]
    for key in ("SYM", "TOP"):
        ids = [k + off for k in halfdisc._side_nodes(nodes, sides[key], m)]
        out.append(f"*NSET, NSET={name}_{key}\n" + halfdisc._lines(ids))
    out.append(f"*SURFACE, NAME={name}_ARC, TYPE=ELEMENT\n")
    out += [f"{e + off}, {f}\n" for e, f in halfdisc._side_faces(n, sides["ARC"])]
    return "".join(out)


def _body(a, centre, name, id_offset):
    if a.kind == "iga4":
        # the cut of the 4-patch half-disc has 2n spans of R/n: as many as the single patch's
        # cut has with SUBDIVIDE = 2n (doc/iga.md §6)
        return disc.body_cards(disc.options(kind="halfdisc", n=a.subdivide // 2, centre=centre,
                                            name=name))
    if a.grade_arc != 1.0 or a.grade_depth != 1.0 or a.static is not None:
        return graded_body_cards(a, centre, name, id_offset)
    common = dict(kind=a.kind, subdivide=a.subdivide, elevate=a.elevate, n=a.n)
    if name == "LOWER" and a.lower:
        common.update(subdivide=a.lower, n=a.lower)
    return halfdisc.body_cards(halfdisc.options(centre=centre, name=name, id_offset=id_offset,
                                                **common))


def deck(a, command):
    if a.kind == "q8":
        kind = f"{a.n} x {a.n} Q8 elements"
    elif a.kind == "iga4":
        kind = f"4 merged NURBS patches, {a.subdivide} spans on the cut"
    else:
        kind = f"NURBS p = {max(2, a.elevate)}, {a.subdivide} x {a.subdivide} spans"
    if a.lower:
        kind += f" (lower body: {a.lower} x {a.lower})"
    if a.grade_arc != 1.0 or a.grade_depth != 1.0:
        kind += f" graded {a.grade_arc:g} (arc), {a.grade_depth:g} (cut)"
    static = a.static is not None
    if static and not a.wall:
        raise SystemExit("hertz.py: --static needs --wall")
    v_up, v_low = (-2.0, 2.0) if a.variant == "both" else (-2.0, 0.0)
    what = ("static, top moved by %g" % -a.static if static else
            "rigid wall" if a.wall else f"V_rel = {v_low - v_up:g}")
    out = [f"** generated by: {command}\n",
           "** Dynamic Hertz benchmark (doc/reference.md section 1): half-cylinders R = 4 "
           "touching at (0, 0).\n",
           "*HEADING\n",
           f"{'Static' if static else 'Dynamic'} Hertz, {kind}, {a.mass} mass"
           + (f" ({a.mass_passes} corrector passes)" if a.mass_passes > 0 else "") + f", {what}\n",
           "*ANALYSIS, TYPE=%s, THICKNESS=1\n" % ("PLANE STRESS" if a.plane_stress else "PLANE STRAIN"),
           "*MATERIAL, NAME=SOFT\n*ELASTIC\n1000.0, 0.2\n*DENSITY\n1.0\n"]
    out.append(_body(a, "upper", "UPPER", 0))
    bodies = ["UPPER"]
    if not a.wall:
        out.append(_body(a, "lower", "LOWER", lower_ids(a.n) if a.kind == "q8" else LOWER_IDS))
        bodies.append("LOWER")
    out.append("*BOUNDARY\n" + "".join(f"{b}_SYM, 1, 1\n" for b in bodies))
    if static:
        out.append(f"UPPER_TOP, 2, 2, {-a.static!r}\n")
    else:
        out.append("*INITIAL CONDITIONS, TYPE=VELOCITY\n")
        out.append(f"UPPER, 2, {v_up!r}\n")
        if not a.wall and v_low != 0.0:
            out.append(f"LOWER, 2, {v_low!r}\n")
    if a.wall:
        out.append(f"*RIGID WALL, NAME=WALL, POINT=0,0, NORMAL=0,1, PENALTY={a.penalty:g}"
                   + (", STABILITY=WARN" if a.stability == "WARN" else "") + "\nUPPER_ARC\n")
    else:
        out.append(f"*CONTACT PAIR, NAME=HERTZ, PENALTY={a.penalty:g}, ALGORITHM={a.algorithm}"
                   + (", STABILITY=WARN" if a.stability == "WARN" else "") + "\n"
                   "LOWER_ARC, UPPER_ARC\n")
    out.append(f"*MASS, TYPE={a.mass}\n")
    if a.alpha > 0.0:
        out.append(f"*DAMPING, ALPHA={a.alpha:g}\n")
    dynamic = "*DYNAMIC, EXPLICIT"
    if a.mass_passes > 0:
        if a.mass != "CONSISTENT":
            raise SystemExit("hertz.py: --mass-passes needs --mass CONSISTENT")
        dynamic += f", MASS SOLVER=CORRECTOR, MASS PASSES={a.mass_passes}"
    out.append(f"*STEP\n{dynamic}\n{a.dt!r}, {a.t_end!r}\n*OUTPUT, HISTORY, EVERY=1\n"
               f"*OUTPUT, FIELD, EVERY={a.field_every}\n*END STEP\n")
    return "".join(out)


def options(**kw):
    """Default options, updated with kw (for use from Python, e.g. the verification cases)."""
    return halfdisc.defaults_with(parser(), kw)


def main():
    a = parser().parse_args()
    check_options(a)
    sys.stdout.write(deck(a, halfdisc.command("hertz.py")))


if __name__ == "__main__":
    main()
