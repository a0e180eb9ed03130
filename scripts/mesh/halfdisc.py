#!/usr/bin/env python3
"""Writes ictus decks of the half-disc x >= 0 of doc/iga.md §10.4: one NURBS patch (exact
geometry) or a Q8 mesh of the SAME map (nodes evaluated on the NURBS patch at the Q8 node
parameters), so both discretisations of one body exist.

    halfdisc.py --kind iga [--elevate 3] [--subdivide 16] [options] > halfdisc_iga.inp
    halfdisc.py --kind q8 [--n 16] [options] > halfdisc_q8.inp

Geometry (R = --radius, default 4). The doc/iga.md §10.4 table P[i][j] (i along the cut from A = (0, -R)
to B = (0, R), j from the cut to the arc) has det J < 0 in that (xi, eta) order, so:
  --centre upper  (centre (0, +R), the default): directions swapped (direction 1 = j, from the
                  cut to the arc; direction 2 = i, from A to B). The contact point A lands on
                  (0, 0), the bottom of the body. Sides: cut = XI0, arc through A = ETA0.
  --centre lower  (centre (0, -R)): the table mirrored y -> -y, in its own (i, j) order
                  (the mirror makes det J > 0). A lands on (0, 0), the top of the body.
                  Sides: cut = ETA0, arc through A = XI0 (as in doc/user-guide.md §5).
Either way det J > 0 everywhere except at the two 180-degree "virtual corners" on the arc at
+-45 degrees, where it vanishes (only reached by quadrature points in the limit).

Names (NAME = --name, default BODY): the patch (IGA) or ELSET (Q8) NAME, which is also the node
set of the whole body; *NSET NAME_SYM (the cut x = 0); *SURFACE NAME_ARC (the 45-degree arc
through the contact point A, i.e. the whole contact zone, doc/iga.md §10.4).

Deck contents: plane strain (--plane-stress for plane stress), material E, nu, rho (defaults
1000, 0.2, 1), the body, u_x = 0 on NAME_SYM (unless --no-sym), initial velocity
(--vx, --vy) on the whole body, *MASS TYPE=--mass, optionally a rigid wall at y = 0
(--wall PENALTY, the allowed side facing the body), and a step (--dt, 0 = automatic; --t-end;
--field-every). --body-only writes only the body cards (patch or mesh, sets, surface).
The first line of every full deck records the command that made it.

Bad values (a radius, E, rho, penalty or t_end <= 0, nu outside (-1, 0.5), dt < 0, counts
< 1, degree < 2, non-finite numbers, names the deck rejects, ids past 2^31 - 1) end the script
with a one-line message and exit status 1, before anything is written.
"""
import argparse
import math
import re
import sys

KNOTS_P2 = [0.0, 0.0, 0.0, 1.0, 1.0, 1.0]
MAX_ID = 2**31 - 1                       # ids are default Fortran integers (deck_lexer.f90)
NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_.-]{0,63}\Z")   # deck name rule (deck_card.f90)
NAME_RULE = "a letter or _, then letters, digits, _, - or ., at most 64 characters"


def table(radius):
    """The doc/iga.md §10.4 control net P[i][j] = (x, y, w), centred at the origin."""
    r, c, t, s = radius, math.cos(math.pi / 8), math.tan(math.pi / 8), math.sqrt(0.5)
    p = [[None] * 3 for _ in range(3)]
    p[0][0], p[1][0], p[2][0] = (0.0, -r, 1.0), (0.0, 0.0, 1.0), (0.0, r, 1.0)
    p[0][1], p[1][1], p[2][1] = (t * r, -r, c), (0.5 * r, 0.0, 1.0), (t * r, r, c)
    p[0][2], p[1][2], p[2][2] = (r * s, -r * s, 1.0), (2 * r * s, 0.0, s), (r * s, r * s, 1.0)
    return p


def control_net(radius=4.0, centre="upper"):
    """Control points (x, y, w) of the 3 x 3 biquadratic patch, direction 1 fastest, and the
    side names {"SYM": side of the cut, "ARC": side of the arc through the contact point}."""
    p = table(radius)
    net = []
    if centre == "upper":
        for i in range(3):          # direction 2 = table i
            for j in range(3):      # direction 1 = table j (fastest)
                x, y, w = p[i][j]
                net.append((x, y + radius, w))
        return net, {"SYM": "XI0", "ARC": "ETA0"}
    if centre == "lower":
        for j in range(3):          # direction 2 = table j
            for i in range(3):      # direction 1 = table i (fastest)
                x, y, w = p[i][j]
                net.append((x, -y - radius, w))
        return net, {"SYM": "ETA0", "ARC": "XI0"}
    raise ValueError("centre must be 'upper' or 'lower'")


def _bernstein2(u):
    return [(1 - u) ** 2, 2 * u * (1 - u), u * u], [-2 * (1 - u), 2 - 4 * u, 2 * u]


def patch_map(net, u, v):
    """Point (x, y) of the biquadratic single-span patch at (u, v) in [0, 1]^2, and det J."""
    bu, du = _bernstein2(u)
    bv, dv = _bernstein2(v)
    s = [0.0] * 9  # W, Wu, Wv, X, Xu, Xv, Y, Yu, Yv  (homogeneous sums)
    for b in range(3):
        for a in range(3):
            x, y, w = net[a + 3 * b]
            for k, f in enumerate((w, w * x, w * y)):
                s[3 * k] += f * bu[a] * bv[b]
                s[3 * k + 1] += f * du[a] * bv[b]
                s[3 * k + 2] += f * bu[a] * dv[b]
    w, wu, wv = s[0:3]
    x, y = s[3] / w, s[6] / w
    xu, xv = (s[4] - wu * x) / w, (s[5] - wv * x) / w
    yu, yv = (s[7] - wu * y) / w, (s[8] - wv * y) / w
    return x, y, xu * yv - xv * yu


def q8_mesh(net, n):
    """Q8 mesh of n x n elements on the patch map, uniform in the parameters.
    Returns (nodes {(i, j): (id, x, y)} on the (2n+1)^2 half-step grid without centre nodes,
    elements [(id, [8 node ids])], corners counter-clockwise then midsides)."""
    m = 2 * n
    nodes, nid = {}, 0
    for j in range(m + 1):
        for i in range(m + 1):
            if i % 2 == 1 and j % 2 == 1:
                continue
            nid += 1
            x, y, _ = patch_map(net, i / m, j / m)
            nodes[(i, j)] = (nid, x, y)
    elems = []
    for ey in range(n):
        for ex in range(n):
            i, j = 2 * ex, 2 * ey
            keys = [(i, j), (i + 2, j), (i + 2, j + 2), (i, j + 2),
                    (i + 1, j), (i + 2, j + 1), (i + 1, j + 2), (i, j + 1)]
            elems.append((len(elems) + 1, [nodes[k][0] for k in keys]))
    return nodes, elems


def _side_nodes(nodes, side, m):
    test = {"XI0": lambda i, j: i == 0, "XI1": lambda i, j: i == m,
            "ETA0": lambda i, j: j == 0, "ETA1": lambda i, j: j == m}[side]
    return [v[0] for (i, j), v in nodes.items() if test(i, j)]


def _side_faces(n, side):
    """(element id, face) along a parameter side of the n x n Q8 mesh."""
    if side == "ETA0":
        return [(ex + 1, "S1") for ex in range(n)]
    if side == "XI1":
        return [(n - 1 + ey * n + 1, "S2") for ey in range(n)]
    if side == "ETA1":
        return [((n - 1) * n + ex + 1, "S3") for ex in range(n)]
    return [(ey * n + 1, "S4") for ey in range(n)]


def _lines(values, per=16):
    vals = list(values)
    return "".join(", ".join(map(str, vals[k:k + per])) + "\n" for k in range(0, len(vals), per))


def body_cards(a):
    """The body: patch (with *ELEVATE/*REFINE) or Q8 mesh, the SYM node set, the ARC surface."""
    net, sides = control_net(a.radius, a.centre)
    name = a.name
    out = []
    if a.kind == "iga":
        out.append(f"*PATCH, NAME={name}, MATERIAL={a.material}, DEGREE=2,2, SIZE=3,3\n")
        for d in (1, 2):
            out.append(f"*KNOTS, DIRECTION={d}\n" + " ".join(f"{k:g}" for k in KNOTS_P2) + "\n")
        out.append("*CONTROL POINTS\n")
        out += [f"{x:.17g}, {y:.17g}, {w:.17g}\n" for x, y, w in net]
        if a.elevate > 2:
            out.append(f"*ELEVATE, PATCH={name}, DEGREE={a.elevate},{a.elevate}\n")
        if a.subdivide > 1:
            out.append(f"*REFINE, PATCH={name}, SUBDIVIDE={a.subdivide},{a.subdivide}\n")
        out.append(f"*NSET, NSET={name}_SYM, PATCH={name}, SIDE={sides['SYM']}\n")
        out.append(f"*SURFACE, NAME={name}_ARC, PATCH={name}, SIDE={sides['ARC']}\n")
    else:
        nodes, elems = q8_mesh(net, a.n)
        off = a.id_offset
        out.append("*NODE\n")
        out += [f"{nid + off}, {x:.17g}, {y:.17g}\n" for nid, x, y in nodes.values()]
        out.append(f"*ELEMENT, TYPE=Q8, ELSET={name}, MATERIAL={a.material}\n")
        out += [f"{eid + off}, " + ", ".join(str(n + off) for n in c) + "\n" for eid, c in elems]
        sym = [n + off for n in _side_nodes(nodes, sides["SYM"], 2 * a.n)]
        out.append(f"*NSET, NSET={name}_SYM\n" + _lines(sym))
        out.append(f"*SURFACE, NAME={name}_ARC, TYPE=ELEMENT\n")
        out += [f"{e + off}, {f}\n" for e, f in _side_faces(a.n, sides["ARC"])]
    return "".join(out)


def deck(a, command):
    if a.kind == "q8":
        kind = f"{a.n} x {a.n} Q8 elements"
    elif a.elevate > 2:
        kind = f"NURBS patch, p = {a.elevate} by *ELEVATE, {a.subdivide} x {a.subdivide} spans"
    else:
        kind = f"quadratic NURBS patch, {a.subdivide} x {a.subdivide} spans"
    centre = "(0, +R)" if a.centre == "upper" else "(0, -R)"
    out = [f"** generated by: {command}\n",
           "** Half-disc x >= 0 of doc/iga.md section 10.4 (R = %g, centre %s); "
           "contact point A = (0, 0)\n" % (a.radius, centre),
           f"** on surface {a.name}_ARC, symmetry cut x = 0 in node set {a.name}_SYM.\n",
           "*HEADING\n", f"Half-disc R = {a.radius:g}, {kind}, {a.mass} mass\n",
           "*ANALYSIS, TYPE=%s, THICKNESS=1\n" % ("PLANE STRESS" if a.plane_stress else "PLANE STRAIN"),
           f"*MATERIAL, NAME={a.material}\n*ELASTIC\n{a.E!r}, {a.nu!r}\n*DENSITY\n{a.rho!r}\n",
           body_cards(a)]
    if a.sym:
        out.append(f"*BOUNDARY\n{a.name}_SYM, 1, 1\n")
    if a.vx != 0.0 or a.vy != 0.0:
        out.append("*INITIAL CONDITIONS, TYPE=VELOCITY\n")
        if a.vx != 0.0:
            out.append(f"{a.name}, 1, {a.vx!r}\n")
        if a.vy != 0.0:
            out.append(f"{a.name}, 2, {a.vy!r}\n")
    if a.wall is not None:
        ny = 1.0 if a.centre == "upper" else -1.0
        out.append(f"*RIGID WALL, NAME=WALL, POINT=0,0, NORMAL=0,{ny:g}, PENALTY={a.wall:g}\n"
                   f"{a.name}_ARC\n")
    out.append(mass_and_step(a))
    return "".join(out)


def mass_and_step(a):
    """*MASS, TYPE=--mass and the explicit step (--dt, --t-end; history every step, fields every
    --field-every steps if > 0)."""
    field = f"*OUTPUT, FIELD, EVERY={a.field_every}\n" if a.field_every > 0 else ""
    return (f"*MASS, TYPE={a.mass}\n*STEP\n*DYNAMIC, EXPLICIT\n{a.dt!r}, {a.t_end!r}\n"
            f"*OUTPUT, HISTORY, EVERY=1\n{field}*END STEP\n")


def parser():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--kind", choices=["iga", "q8"], default="iga")
    ap.add_argument("--radius", type=float, default=4.0)
    ap.add_argument("--centre", choices=["upper", "lower"], default="upper",
                    help="upper: centre (0, +R); lower: centre (0, -R)")
    ap.add_argument("--subdivide", type=int, default=16, help="IGA: *REFINE SUBDIVIDE=k,k")
    ap.add_argument("--elevate", type=int, default=2, help="IGA: *ELEVATE DEGREE=q,q if q > 2")
    ap.add_argument("--n", type=int, default=16, help="Q8: n x n elements")
    ap.add_argument("--name", default="BODY")
    ap.add_argument("--material", default="SOFT")
    ap.add_argument("--E", type=float, default=1000.0)
    ap.add_argument("--nu", type=float, default=0.2)
    ap.add_argument("--rho", type=float, default=1.0)
    ap.add_argument("--plane-stress", action="store_true")
    ap.add_argument("--no-sym", dest="sym", action="store_false", help="no u_x = 0 on the cut")
    ap.add_argument("--vx", type=float, default=0.0)
    ap.add_argument("--vy", type=float, default=0.0)
    ap.add_argument("--mass", default="HRZ", choices=["CONSISTENT", "ROW SUM", "HRZ"])
    ap.add_argument("--wall", type=float, default=None, metavar="PENALTY",
                    help="add a rigid wall at y = 0 against NAME_ARC")
    ap.add_argument("--dt", type=float, default=0.0, help="0: automatic")
    ap.add_argument("--t-end", type=float, default=0.9)
    ap.add_argument("--field-every", type=int, default=0, help="0: the program's default")
    ap.add_argument("--body-only", action="store_true")
    ap.add_argument("--id-offset", type=int, default=0,
                    help="Q8: added to every node and element id (for two bodies in one deck)")
    return ap


def checker(prog):
    """check(ok, option, expected, value): unless ok, exits with status 1 and the one-line
    message "PROG: OPTION: expected EXPECTED, got VALUE"."""
    def check(ok, option, expected, value):
        if not ok:
            sys.exit(f"{prog}: {option}: expected {expected}, got {value!r}")
    return check


def add_mesh_options(ap, max_distort):
    """The options that the structured meshers (rect.py, box.py) share: first ids, names and
    the distortion of the vertices (a fraction of the element size below max_distort)."""
    ap.add_argument("--first-node", type=int, default=1, help="first node id (>= 1)")
    ap.add_argument("--first-element", type=int, default=1, help="first element id (>= 1)")
    ap.add_argument("--elset", default="BODY")
    ap.add_argument("--material", default="MAT")
    ap.add_argument("--prefix", default="", help="prefix of the node set names")
    ap.add_argument("--distort", type=float, default=0.0,
                    help=f"vertex offset, a fraction of the element size in [0, {max_distort:g})")


def check_first_ids(check, ids):
    """The first node or element ids of a mesher's options, [(option, first id, count,
    "node" or "element")]: each > 0, and the last of the count ids within MAX_ID."""
    for opt, first, count, what in ids:
        check(first >= 1, opt, f"a positive {what} id (deck ids are > 0)", first)
        check(first <= MAX_ID - count + 1, opt, f"at most {MAX_ID - count + 1}, so that the "
              f"last of the {count} {what} ids stays <= {MAX_ID}", first)


def check_names(check, a, set_name):
    """--elset, --material and --prefix of a mesher (set_name: a set it writes, which the
    prefix must keep a valid name)."""
    check(NAME.match(a.elset), "--elset", f"a name ({NAME_RULE})", a.elset)
    check(NAME.match(a.material), "--material", f"a name ({NAME_RULE})", a.material)
    check(NAME.match(a.prefix + set_name), "--prefix",
          f"a prefix giving valid set names such as {a.prefix}{set_name} ({NAME_RULE})",
          a.prefix)


def q8_id_count(n):
    """Nodes of the n x n Q8 mesh (more than its n^2 elements): the ids used per body."""
    return (2 * n + 1) ** 2 - n * n


def check_options(a):
    """Rejects the values that would give no body, an invalid deck or a traceback."""
    check, finite = checker("halfdisc.py"), math.isfinite
    check(finite(a.radius) and a.radius > 0.0, "--radius", "a positive finite length", a.radius)
    check(a.subdivide >= 1, "--subdivide", "a positive integer (spans per direction)",
          a.subdivide)
    check(a.elevate >= 2, "--elevate", "a degree >= 2 (the patch is quadratic)", a.elevate)
    check(a.n >= 1, "--n", "a positive integer (Q8 elements per direction)", a.n)
    h, d = a.radius / (a.n if a.kind == "q8" else a.subdivide), 2.0 * a.radius
    check(sys.float_info.min <= h * h and finite(d * d), "--radius", "a length whose "
          "Jacobians, from (R/spans)^2 to (2R)^2, stay normal finite numbers", a.radius)
    check(a.id_offset >= 0, "--id-offset", "an integer >= 0 (deck ids are > 0)", a.id_offset)
    if a.kind == "q8":
        last = MAX_ID - q8_id_count(a.n)
        check(a.id_offset <= last, "--id-offset", f"at most {last}, so that the last id of the "
              f"{a.n} x {a.n} mesh stays <= {MAX_ID}", a.id_offset)
    # the body name also names the sets NAME_SYM and NAME_ARC: 4 characters more
    check(NAME.match(a.name) and len(a.name) <= 60, "--name",
          f"a name of at most 60 characters ({NAME_RULE})", a.name)
    check_material(check, a)
    check(finite(a.vx), "--vx", "a finite velocity", a.vx)
    check(finite(a.vy), "--vy", "a finite velocity", a.vy)
    check(a.wall is None or (finite(a.wall) and a.wall > 0.0), "--wall",
          "a positive finite penalty", a.wall)
    check_step(check, a)


def check_material(check, a):
    """The options --material, --E, --nu, --rho, through check (see checker)."""
    finite = math.isfinite
    check(NAME.match(a.material), "--material", f"a name ({NAME_RULE})", a.material)
    check(finite(a.E) and a.E > 0.0, "--E", "a positive finite Young's modulus", a.E)
    check(-1.0 < a.nu < 0.5, "--nu", "a Poisson ratio in (-1, 0.5)", a.nu)
    check(finite(a.rho) and a.rho > 0.0, "--rho", "a positive finite density", a.rho)


def check_step(check, a, field_default="the program's default"):
    """The step options --dt, --t-end, --field-every (0 meaning field_default), through check."""
    finite = math.isfinite
    check(finite(a.dt) and a.dt >= 0.0, "--dt", "a finite time step >= 0 (0: automatic)", a.dt)
    check(finite(a.t_end) and a.t_end > 0.0, "--t-end", "a positive finite end time", a.t_end)
    check(a.field_every >= 0, "--field-every", f"an integer >= 0 (0: {field_default})",
          a.field_every)


def options(**kw):
    """Default options, updated with kw (for use from Python, e.g. the verification cases)."""
    return defaults_with(parser(), kw)


def defaults_with(ap, kw):
    """The defaults of argument parser `ap`, updated with the dict kw (unknown keys: KeyError)."""
    a = ap.parse_args([])
    for k, v in kw.items():
        if not hasattr(a, k):
            raise KeyError(k)
        setattr(a, k, v)
    return a


def command(script):
    """The command line that made a deck: scripts/mesh/SCRIPT and this run's arguments (quoted
    where they hold a blank)."""
    return f"scripts/mesh/{script} " + " ".join(f"'{s}'" if " " in s else s for s in sys.argv[1:])


def run(ap, check_options, body_cards, deck, script):
    """The main program of a mesh script: parses the command line with ap, checks the options,
    writes to stdout the body cards (--body-only) or the whole deck."""
    a = ap.parse_args()
    check_options(a)
    sys.stdout.write(body_cards(a) if a.body_only else deck(a, command(script)))


def main():
    run(parser(), check_options, body_cards, deck, "halfdisc.py")


if __name__ == "__main__":
    main()
