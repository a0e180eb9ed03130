#!/usr/bin/env python3
"""Multi-patch NURBS bodies with exact circular boundaries (doc/iga.md §1.1), written as ictus
deck cards: biquadratic patches of one span each, merged by *PATCH, MERGE=YES, refined by
*REFINE, and a Q8 mesh of the same maps for comparison.

    disc.py --kind disc [--n 16] [--m 8] [options] > disc.inp      full disc, 5 patches
    disc.py --kind ring [--n 16] [--m 4] [options] > ring.inp      ring, 4 patches
    disc.py --kind halfdisc --n 32 [--centre upper] [options] > half.inp
                                                    half-disc x >= 0, 4 patches (Hertz)
    disc.py --kind disc --q8 [...]                  the same maps as a Q8 mesh

Full disc (radius R = --radius, centre (0, --y0)): a square centre patch C of half-side
c = --inner * R (n x n spans) and four ring patches E, N, W, S between the square's sides and
the 90-degree arcs at -45..45, 45..135, ... degrees (direction 1 radial with m spans, direction
2 counter-clockwise with n spans). Each arc is the exact rational quadratic arc (middle weight
cos 45 degrees); the inner sides are straight; the middle row of a ring patch is the mean of its
inner and outer rows in homogeneous coordinates, so the map is linear in the radial direction.
Every patch corner has an angle below 180 degrees: no point with det J = 0.

Ring (inner radius --inner * R): four quarter-annulus patches, direction 1 radial (m spans),
direction 2 along the arcs (n spans).

Half-disc x >= 0 for the Hertz problem (R = 4 by default, contact point A on the arc at
-90 degrees): the half x >= 0 of the full disc: the rectangle [0, c] x [-c, c] (n/2 x n spans),
the ring patch E (m x n) and the halves of N and S (m x n/2). With c = R/2 and m = n/2 the
symmetry cut has 2n spans of length R/n. --centre upper (default) puts the centre at (0, R), so
A is the origin and the body lies above it; --centre lower mirrors it to the centre (0, -R).
A is a 90-degree patch corner of S. A half-disc of three conforming quadrilateral patches
necessarily has a patch corner of 180 degrees on the boundary (a point with det J = 0, as the
single patch has at G1 and G2), which is why this layout has four (doc/iga.md §1.1).

Names (NAME = --name, default DISC): patches NAME_C, NAME_E, NAME_N, NAME_W, NAME_S (ring:
NAME_E, NAME_N, NAME_W, NAME_S); *ELSET NAME of all of them (so NAME is also the node set of
the whole body); *SURFACE NAME_ARC (the outer arc; half-disc: the arc A -> B), one data line per
patch side; half-disc: *NSET NAME_SYM (the cut x = 0); ring: *SURFACE NAME_INNER (the inner
arc). With --q8 the same names are an ELSET, node sets and TYPE=ELEMENT surfaces.

Deck contents (unless --body-only): plane strain, material E, nu, rho (defaults 1000, 0.2, 1),
the body, initial velocity (--vx, --vy), optionally a rigid wall y = 0 (--wall PENALTY, the
allowed side facing the body: use --y0 > R for a disc above it), *MASS TYPE=--mass and a step
(--dt, 0 = automatic; --t-end; --field-every). The first line records the command.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import halfdisc  # noqa: E402

S2 = math.sqrt(0.5)


def rot(p, a):
    """Point p = (x, y) rotated by a radians about the origin."""
    c, s = math.cos(a), math.sin(a)
    return (c * p[0] - s * p[1], s * p[0] + c * p[1])


def arc(r, a0, a1):
    """Control points (x, y, w) of the circular arc of radius r from angle a0 to a1 (< pi)."""
    h = 0.5 * (a1 - a0)
    m = 0.5 * (a0 + a1)
    return [(r * math.cos(a0), r * math.sin(a0), 1.0),
            (r / math.cos(h) * math.cos(m), r / math.cos(h) * math.sin(m), math.cos(h)),
            (r * math.cos(a1), r * math.sin(a1), 1.0)]


def line(p, q):
    """Control points of the straight segment p -> q (uniform parameter)."""
    return [(p[0], p[1], 1.0), (0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 1.0),
            (q[0], q[1], 1.0)]


def ruled(inner, outer):
    """3 x 3 net, direction 1 from `inner` to `outer` (fastest), direction 2 along them; the
    middle row is the homogeneous mean, so the map is linear in direction 1."""
    net = []
    for a, b in zip(inner, outer):
        w = 0.5 * (a[2] + b[2])
        mid = ((a[2] * a[0] + b[2] * b[0]) / (2 * w), (a[2] * a[1] + b[2] * b[1]) / (2 * w), w)
        net += [a, mid, b]
    return net


def square(x0, x1, y0, y1):
    """3 x 3 net of the rectangle [x0, x1] x [y0, y1], direction 1 along x."""
    return [(x, y, 1.0) for y in (y0, 0.5 * (y0 + y1), y1) for x in (x0, 0.5 * (x0 + x1), x1)]


def ring_patch(r0, r1, a0, a1, inner_line):
    """Ring patch between angles a0 < a1: outer arc of radius r1; inner arc of radius r0, or
    (inner_line) the chord of the square of half-side r0 facing the arc."""
    if inner_line:
        # the side of the square facing the arc (its normal at the multiple of 90 degrees
        # nearest the middle of the arc), cut to the rays a0 and a1
        face = round(0.5 * (a0 + a1) / (0.5 * math.pi)) * 0.5 * math.pi
        p = rot((r0, r0 * math.tan(a0 - face)), face)
        q = rot((r0, r0 * math.tan(a1 - face)), face)
        inner = line(p, q)
    else:
        inner = arc(r0, a0, a1)
    return ruled(inner, arc(r1, a0, a1))


def patches(kind, radius, inner, n, m):
    """The patches [(suffix, net, (k1, k2))] and sides {"ARC": [(suffix, side)], ...}."""
    c = inner * radius
    d = math.pi / 180.0
    if kind == "disc":
        out = [("C", square(-c, c, -c, c), (n, n))]
        for k, s in enumerate("ENWS"):
            out.append((s, ring_patch(c, radius, (90 * k - 45) * d, (90 * k + 45) * d, True),
                        (m, n)))
        return out, {"ARC": [(s, "XI1") for s in "ENWS"]}
    if kind == "ring":
        out = [(s, ring_patch(c, radius, 90 * k * d, 90 * (k + 1) * d, False), (m, n))
               for k, s in enumerate("ENWS")]
        return out, {"ARC": [(s, "XI1") for s in "ENWS"], "INNER": [(s, "XI0") for s in "ENWS"]}
    if kind == "halfdisc":
        out = [("S", ring_patch(c, radius, -90 * d, -45 * d, True), (m, n // 2)),
               ("C", square(0.0, c, -c, c), (n // 2, n)),
               ("E", ring_patch(c, radius, -45 * d, 45 * d, True), (m, n)),
               ("N", ring_patch(c, radius, 45 * d, 90 * d, True), (m, n // 2))]
        return out, {"ARC": [("S", "XI1"), ("E", "XI1"), ("N", "XI1")],
                     "SYM": [("S", "ETA0"), ("C", "XI0"), ("N", "ETA1")]}
    raise ValueError(kind)


def placed(kind, a):
    """Patches and sides moved to their place: the disc and ring centred at (0, y0); the
    half-disc centred at (0, R) (upper) or mirrored to (0, -R) (lower; direction 2 reversed
    to keep det J > 0, which exchanges ETA0 and ETA1)."""
    pts, sides = patches(kind, a.radius, a.inner, a.n, a.m)
    eps = 1e-14 * a.radius      # cos 90 degrees and the like: exactly 0
    pts = [(s, [(0.0 if abs(x) < eps else x, 0.0 if abs(y) < eps else y, w) for x, y, w in net],
            k) for s, net, k in pts]
    if kind != "halfdisc":
        return [(s, [(x, y + a.y0, w) for x, y, w in net], k) for s, net, k in pts], sides
    if a.centre == "upper":
        return [(s, [(x, y + a.radius, w) for x, y, w in net], k) for s, net, k in pts], sides
    out = []
    for s, net, k in pts:
        rows = [net[3 * j:3 * j + 3] for j in range(3)][::-1]
        out.append((s, [(x, -y - a.radius, w) for row in rows for x, y, w in row], k))
    swap = {"ETA0": "ETA1", "ETA1": "ETA0", "XI0": "XI0", "XI1": "XI1"}
    return out, {key: [(s, swap[side]) for s, side in v] for key, v in sides.items()}


def iga_cards(kind, a):
    pts, sides = placed(kind, a)
    name = a.name
    out = []
    for s, net, (k1, k2) in pts:
        out.append(f"*PATCH, NAME={name}_{s}, MATERIAL={a.material}, DEGREE=2,2, SIZE=3,3, "
                   "MERGE=YES\n*KNOTS, DIRECTION=1\n0 0 0 1 1 1\n*KNOTS, DIRECTION=2\n"
                   "0 0 0 1 1 1\n*CONTROL POINTS\n")
        out += [f"{x:.17g}, {y:.17g}, {w:.17g}\n" for x, y, w in net]
        if k1 > 1 or k2 > 1:
            out.append(f"*REFINE, PATCH={name}_{s}, SUBDIVIDE={k1},{k2}\n")
    out.append(f"*ELSET, ELSET={name}\n" + ", ".join(f"{name}_{s}" for s, _, _ in pts) + "\n")
    for key, lst in sides.items():
        if key == "SYM":
            for s, side in lst:
                out.append(f"*NSET, NSET={name}_SYM_{s}, PATCH={name}_{s}, SIDE={side}\n")
            out.append(f"*NSET, NSET={name}_SYM\n" + ", ".join(f"{name}_SYM_{s}" for s, _ in lst)
                       + "\n")
        else:
            out.append(f"*SURFACE, NAME={name}_{key}\n")
            out += [f"PATCH={name}_{s}, SIDE={side}\n" for s, side in lst]
    return "".join(out)


def q8_cards(kind, a):
    """The same patch maps as Q8 elements (k1 x k2 per patch, node parameters uniform),
    nodes shared where they coincide."""
    pts, sides = placed(kind, a)
    name = a.name
    tol = 1e-9 * a.radius
    ids, nodes, elems, faces, sym = {}, [], [], {}, set()

    def node(x, y):
        key = (round(x / tol), round(y / tol))
        if key not in ids:
            ids[key] = len(nodes) + 1 + a.id_offset
            nodes.append((ids[key], x, y))
        return ids[key]

    for s, net, (k1, k2) in pts:
        m1, m2 = 2 * k1, 2 * k2
        grid = {}
        for j in range(m2 + 1):
            for i in range(m1 + 1):
                if i % 2 == 1 and j % 2 == 1:
                    continue
                x, y, _ = halfdisc.patch_map(net, i / m1, j / m2)
                grid[(i, j)] = node(x, y)
        for ey in range(k2):
            for ex in range(k1):
                i, j = 2 * ex, 2 * ey
                keys = [(i, j), (i + 2, j), (i + 2, j + 2), (i, j + 2),
                        (i + 1, j), (i + 2, j + 1), (i + 1, j + 2), (i, j + 1)]
                eid = len(elems) + 1 + a.id_offset
                elems.append((eid, [grid[q] for q in keys]))
                on = {"XI0": ex == 0, "XI1": ex == k1 - 1, "ETA0": ey == 0, "ETA1": ey == k2 - 1}
                for f, side in (("S1", "ETA0"), ("S2", "XI1"), ("S3", "ETA1"), ("S4", "XI0")):
                    if on[side]:
                        faces.setdefault((s, side), []).append((eid, f))
        for key, lst in sides.items():
            if key == "SYM" and any(s == p for p, _ in lst):
                side = dict(lst)[s]
                test = {"XI0": lambda i, j: i == 0, "XI1": lambda i, j: i == m1,
                        "ETA0": lambda i, j: j == 0, "ETA1": lambda i, j: j == m2}[side]
                sym |= {v for (i, j), v in grid.items() if test(i, j)}
    out = ["*NODE\n"] + [f"{i}, {x:.17g}, {y:.17g}\n" for i, x, y in nodes]
    out.append(f"*ELEMENT, TYPE=Q8, ELSET={name}, MATERIAL={a.material}\n")
    out += [f"{e}, " + ", ".join(map(str, c)) + "\n" for e, c in elems]
    for key, lst in sides.items():
        if key == "SYM":
            out.append(f"*NSET, NSET={name}_SYM\n" + halfdisc._lines(sorted(sym)))
        else:
            out.append(f"*SURFACE, NAME={name}_{key}, TYPE=ELEMENT\n")
            for s, side in lst:
                out += [f"{e}, {f}\n" for e, f in faces[(s, side)]]
    return "".join(out)


def body_cards(a):
    return q8_cards(a.kind, a) if a.q8 else iga_cards(a.kind, a)


def deck(a, command):
    what = {"disc": "full disc, 5 patches", "ring": "ring, 4 patches",
            "halfdisc": "half-disc x >= 0, 4 patches"}[a.kind]
    disc_kind = "Q8 mesh of the patch maps" if a.q8 else "merged NURBS patches"
    out = [f"** generated by: {command}\n",
           f"*HEADING\n{what} R = {a.radius:g} ({disc_kind}, n = {a.n}, m = {a.m}), "
           f"{a.mass} mass\n",
           "*ANALYSIS, TYPE=%s, THICKNESS=1\n" % ("PLANE STRESS" if a.plane_stress
                                                 else "PLANE STRAIN"),
           f"*MATERIAL, NAME={a.material}\n*ELASTIC\n{a.E!r}, {a.nu!r}\n*DENSITY\n{a.rho!r}\n",
           body_cards(a)]
    if a.kind == "halfdisc" and a.sym:
        out.append(f"*BOUNDARY\n{a.name}_SYM, 1, 1\n")
    if a.vx != 0.0 or a.vy != 0.0:
        out.append("*INITIAL CONDITIONS, TYPE=VELOCITY\n")
        if a.vx != 0.0:
            out.append(f"{a.name}, 1, {a.vx!r}\n")
        if a.vy != 0.0:
            out.append(f"{a.name}, 2, {a.vy!r}\n")
    if a.wall is not None:
        out.append(f"*RIGID WALL, NAME=WALL, POINT=0,0, NORMAL=0,1, PENALTY={a.wall:g}\n"
                   f"{a.name}_ARC\n")
    out.append(halfdisc.mass_and_step(a))
    return "".join(out)


def parser():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--kind", choices=["disc", "ring", "halfdisc"], default="disc")
    ap.add_argument("--q8", action="store_true", help="a Q8 mesh of the same patch maps")
    ap.add_argument("--radius", type=float, default=None, help="default 1 (half-disc: 4)")
    ap.add_argument("--inner", type=float, default=0.5,
                    help="square half-side (disc, half-disc) or inner radius (ring) / R")
    ap.add_argument("--n", type=int, default=16, help="spans along the square side / arc")
    ap.add_argument("--m", type=int, default=0, help="radial spans (0: n/2)")
    ap.add_argument("--y0", type=float, default=0.0, help="disc, ring: centre (0, y0)")
    ap.add_argument("--centre", choices=["upper", "lower"], default="upper")
    ap.add_argument("--name", default="DISC")
    ap.add_argument("--material", default="SOFT")
    ap.add_argument("--E", type=float, default=1000.0)
    ap.add_argument("--nu", type=float, default=0.2)
    ap.add_argument("--rho", type=float, default=1.0)
    ap.add_argument("--plane-stress", action="store_true")
    ap.add_argument("--no-sym", dest="sym", action="store_false")
    ap.add_argument("--vx", type=float, default=0.0)
    ap.add_argument("--vy", type=float, default=0.0)
    ap.add_argument("--mass", default="HRZ", choices=["CONSISTENT", "ROW SUM", "HRZ"])
    ap.add_argument("--wall", type=float, default=None, metavar="PENALTY")
    ap.add_argument("--dt", type=float, default=0.0, help="0: automatic")
    ap.add_argument("--t-end", type=float, default=1.0)
    ap.add_argument("--field-every", type=int, default=0)
    ap.add_argument("--body-only", action="store_true")
    ap.add_argument("--id-offset", type=int, default=0, help="Q8: added to node/element ids")
    return ap


def check_options(a):
    if a.radius is None:
        a.radius = 4.0 if a.kind == "halfdisc" else 1.0
    if a.m == 0:
        a.m = max(1, a.n // 2)
    bad = None
    if not (a.radius > 0 and math.isfinite(a.radius)):
        bad = "--radius must be > 0"
    elif not 0.0 < a.inner < (1.0 if a.kind == "ring" else S2):
        bad = "--inner must be in (0, 1) for a ring and in (0, 1/sqrt(2)) otherwise"
    elif a.n < 1 or a.m < 1:
        bad = "--n and --m must be >= 1"
    elif a.kind == "halfdisc" and a.n % 2:
        bad = "--n must be even for the half-disc (its N and S patches have n/2 spans)"
    elif a.dt < 0 or not a.t_end > 0:
        bad = "--dt must be >= 0 and --t-end > 0"
    elif not halfdisc.NAME.match(a.name + "_SYM_C"):
        bad = f"--name: {halfdisc.NAME_RULE}"
    if bad:
        raise SystemExit(f"disc.py: {bad}")


def options(**kw):
    """Default options, updated with kw (for use from Python, e.g. the verification cases)."""
    a = halfdisc.defaults_with(parser(), kw)
    check_options(a)
    return a


def main():
    halfdisc.run(parser(), check_options, body_cards, deck, "disc.py")


if __name__ == "__main__":
    main()
