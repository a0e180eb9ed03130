#!/usr/bin/env python3
"""Writes the *NODE, *ELEMENT and *NSET cards of a structured rectangular mesh.

    rect.py --type Q8 --nx 40 --ny 2 --lx 10 --ly 0.5 [--x0 0 --y0 0] [--first-node 1]
            [--first-element 1] [--elset BODY] [--material STEEL] [--distort 0.0] > mesh.inp

Node sets: LEFT, RIGHT, BOTTOM, TOP (edges), CORNER_LL/LR/UL/UR, plus the ELSET. Element
nodes follow doc/user-guide.md §4 (corners counter-clockwise, then midsides, then the centre).
--distort d moves every interior vertex node by a deterministic pseudo-random offset of up to
d times the element size (midside nodes stay at the middle of straight edges), for patch tests.
0 <= d < 0.25 keeps every element valid: each is the bilinear map of its corners, whose edges,
in units of the element size, are (1 + a, c) and (e, 1 + b) with |a|, |b|, |c|, |e| < 2d, so
the corner Jacobians exceed (1 - 2d)^2 - 4d^2 = 1 - 4d > 0 (d >= 0.25 can invert an element).

Bad values (counts or ids < 1, lengths <= 0, non-finite numbers, bad names, d outside
[0, 0.25)) end the script with a one-line message and exit status 1, before anything is written.
"""
import argparse
import math
import sys

from halfdisc import MAX_ID, add_mesh_options, check_first_ids, check_names

MAX_DISTORT = 0.25                       # keeps every Jacobian positive (see above)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--type", choices=["Q4", "Q8", "Q9"], default="Q8")
    ap.add_argument("--nx", type=int, required=True, help="elements along x (>= 1)")
    ap.add_argument("--ny", type=int, required=True, help="elements along y (>= 1)")
    ap.add_argument("--lx", type=float, required=True, help="length along x (> 0)")
    ap.add_argument("--ly", type=float, required=True, help="length along y (> 0)")
    ap.add_argument("--x0", type=float, default=0.0)
    ap.add_argument("--y0", type=float, default=0.0)
    add_mesh_options(ap, MAX_DISTORT)
    a = ap.parse_args()
    check_options(a)
    write_mesh(a, sys.stdout)


def check(ok, option, expected, value):
    """Unless ok, exits with status 1 and "rect.py: OPTION: expected EXPECTED, got VALUE"."""
    if not ok:
        sys.exit(f"rect.py: {option}: expected {expected}, got {value!r}")


def node_count(a):
    """Nodes of the mesh (the fine grid, less the centres for Q8)."""
    if a.type == "Q4":
        return (a.nx + 1) * (a.ny + 1)
    return (2 * a.nx + 1) * (2 * a.ny + 1) - (a.nx * a.ny if a.type == "Q8" else 0)


def grid_ok(x0, length, m):
    """True when the grid coordinates x0 + i * (length / m), i = 0..m, as write_mesh computes
    them, are finite and strictly increasing (no coincident nodes)."""
    h = length / m
    xs = [x0 + i * h for i in range(m + 1)]
    return all(map(math.isfinite, xs)) and all(p < q for p, q in zip(xs, xs[1:]))


def check_options(a):
    """Rejects the values that would give no mesh, an invalid one or a traceback."""
    check(a.nx >= 1, "--nx", "a positive integer", a.nx)
    check(a.ny >= 1, "--ny", "a positive integer", a.ny)
    check(node_count(a) <= MAX_ID, "--nx, --ny", f"at most {MAX_ID} nodes", (a.nx, a.ny))
    check_first_ids(check, (("--first-node", a.first_node, node_count(a), "node"),
                            ("--first-element", a.first_element, a.nx * a.ny, "element")))
    for opt, v in (("--lx", a.lx), ("--ly", a.ly)):
        check(math.isfinite(v) and v > 0.0, opt, "a positive finite length", v)
    for opt, v in (("--x0", a.x0), ("--y0", a.y0)):
        check(math.isfinite(v), opt, "a finite number", v)
    jac = (a.lx / a.nx) * (a.ly / a.ny) / 4   # Jacobian of an undistorted element
    check(sys.float_info.min <= jac and math.isfinite(a.lx * a.ly), "--lx, --ly",
          "lengths whose element Jacobians, (lx/nx)(ly/ny)/4, stay normal finite numbers",
          (a.lx, a.ly))
    m = 1 if a.type == "Q4" else 2
    check(grid_ok(a.x0, a.lx, m * a.nx), "--lx",
          f"a length whose nodes stay finite and distinct from --x0 {a.x0!r}", a.lx)
    check(grid_ok(a.y0, a.ly, m * a.ny), "--ly",
          f"a length whose nodes stay finite and distinct from --y0 {a.y0!r}", a.ly)
    check_names(check, a, "CORNER_LL")
    check(0.0 <= a.distort < MAX_DISTORT, "--distort",
          f"a number in [0, {MAX_DISTORT:g}) (larger offsets can invert elements)", a.distort)


def write_mesh(a, out):
    quad = a.type != "Q4"
    # grid of points with spacing h/2 when quadratic; node (i, j) on the fine grid
    mx, my = (2 * a.nx, 2 * a.ny) if quad else (a.nx, a.ny)
    hx, hy = a.lx / mx, a.ly / my
    ids = {}
    nid = a.first_node
    coords = {}
    for j in range(my + 1):
        for i in range(mx + 1):
            if a.type == "Q8" and i % 2 == 1 and j % 2 == 1:
                continue  # serendipity: no centre node
            ids[(i, j)] = nid
            coords[(i, j)] = [a.x0 + i * hx, a.y0 + j * hy]
            nid += 1
    if a.distort > 0.0:
        step = 2 if quad else 1
        for (i, j), xy in coords.items():
            if i % step or j % step or i in (0, mx) or j in (0, my):
                continue
            s = math.sin(12.9898 * i + 78.233 * j) * 43758.5453
            r1 = s - math.floor(s)
            s = math.sin(39.3468 * i + 11.135 * j) * 24634.6345
            r2 = s - math.floor(s)
            xy[0] += a.distort * step * hx * (2 * r1 - 1)
            xy[1] += a.distort * step * hy * (2 * r2 - 1)
        if quad:  # midside and centre nodes back to the middle of their straight edges
            for (i, j), xy in coords.items():
                if i % 2 == 0 and j % 2 == 0:
                    continue
                if i % 2 == 1 and j % 2 == 0:
                    xs = [coords[(i - 1, j)], coords[(i + 1, j)]]
                elif i % 2 == 0:
                    xs = [coords[(i, j - 1)], coords[(i, j + 1)]]
                else:
                    xs = [coords[(i - 1, j - 1)], coords[(i + 1, j - 1)], coords[(i + 1, j + 1)], coords[(i - 1, j + 1)]]
                xy[0] = sum(p[0] for p in xs) / len(xs)
                xy[1] = sum(p[1] for p in xs) / len(xs)
    out.write("*NODE\n")
    for key, n in ids.items():
        out.write(f"{n}, {coords[key][0]:.17g}, {coords[key][1]:.17g}\n")
    out.write(f"*ELEMENT, TYPE={a.type}, ELSET={a.elset}, MATERIAL={a.material}\n")
    eid = a.first_element
    s = 2 if quad else 1
    for ey in range(a.ny):
        for ex in range(a.nx):
            i, j = s * ex, s * ey
            c = [ids[(i, j)], ids[(i + s, j)], ids[(i + s, j + s)], ids[(i, j + s)]]
            if quad:
                c += [ids[(i + 1, j)], ids[(i + 2, j + 1)], ids[(i + 1, j + 2)], ids[(i, j + 1)]]
            if a.type == "Q9":
                c.append(ids[(i + 1, j + 1)])
            out.write(f"{eid}, " + ", ".join(map(str, c)) + "\n")
            eid += 1
    p = a.prefix
    sets = {
        "LEFT": [n for (i, j), n in ids.items() if i == 0],
        "RIGHT": [n for (i, j), n in ids.items() if i == mx],
        "BOTTOM": [n for (i, j), n in ids.items() if j == 0],
        "TOP": [n for (i, j), n in ids.items() if j == my],
        "CORNER_LL": [ids[(0, 0)]], "CORNER_LR": [ids[(mx, 0)]],
        "CORNER_UL": [ids[(0, my)]], "CORNER_UR": [ids[(mx, my)]],
    }
    for name, nodes in sets.items():
        out.write(f"*NSET, NSET={p}{name}\n")
        for k in range(0, len(nodes), 16):
            out.write(", ".join(map(str, nodes[k:k + 16])) + "\n")


if __name__ == "__main__":
    main()
