#!/usr/bin/env python3
"""Writes the *NODE, *ELEMENT and *NSET cards of a structured mesh of hexahedra on a box (3D
decks, *ANALYSIS, TYPE=3D).

    box.py --type C3D20 --nx 10 --ny 1 --nz 1 --lx 10 --ly 0.5 --lz 0.5 [--x0 0 --y0 0 --z0 0]
           [--first-node 1] [--first-element 1] [--elset BODY] [--material MAT] [--prefix P]
           [--distort 0.0] > mesh.inp

Types C3D8, C3D20 and C3D27, in the Abaqus node order (doc/elements3d.md §1): corners 1-4 on the
face z = z0 side of the element counter-clockwise seen from +z, 5-8 above them, then the edge
midsides 9-20, and for C3D27 the centre 21 and the face centres 22-27 (faces S1..S6). An
element's data line holds at most 16 values and ends with a comma where it goes on to the next
line (C3D20, C3D27), as Abaqus and gmsh write them. Elements run x fastest, then y, then z.

Node sets: X0, X1, Y0, Y1, Z0, Z1 (the nodes on the faces x = x0, x = x0 + lx, ...), plus the
ELSET. --distort d moves every interior vertex node by a deterministic pseudo-random offset of
up to d times the element size in each direction (midside, face and centre nodes stay at the
mean of the corners of their straight edge, face or element), for patch tests. Each element is
then the trilinear map of its corners; with d < 0.125 the corner offsets change every edge
vector of the map by less than a quarter of its length, which keeps every Jacobian positive.

Bad values (counts or ids < 1, lengths <= 0, non-finite numbers, bad names, d outside
[0, 0.125)) end the script with a one-line message and exit status 1, before anything is
written.
"""
import argparse
import math
import sys

from halfdisc import MAX_ID, add_mesh_options, check_first_ids, check_names, checker

MAX_DISTORT = 0.125                      # keeps every Jacobian positive (see above)
PER_LINE = 16                            # values per data line of an element

# parent coordinates of the nodes (Abaqus order), in {-1, 0, 1}^3
CORNERS = [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
           (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]
MIDSIDES = [(0, -1, -1), (1, 0, -1), (0, 1, -1), (-1, 0, -1),
            (0, -1, 1), (1, 0, 1), (0, 1, 1), (-1, 0, 1),
            (-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
CENTRES = [(0, 0, 0), (0, 0, -1), (0, 0, 1), (0, -1, 0), (1, 0, 0), (0, 1, 0), (-1, 0, 0)]
PARENT = {"C3D8": CORNERS, "C3D20": CORNERS + MIDSIDES, "C3D27": CORNERS + MIDSIDES + CENTRES}


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--type", choices=sorted(PARENT), default="C3D20")
    for d in "xyz":
        ap.add_argument(f"--n{d}", type=int, required=True, help=f"elements along {d} (>= 1)")
    for d in "xyz":
        ap.add_argument(f"--l{d}", type=float, required=True, help=f"length along {d} (> 0)")
    for d in "xyz":
        ap.add_argument(f"--{d}0", type=float, default=0.0)
    add_mesh_options(ap, MAX_DISTORT)
    a = ap.parse_args()
    check_options(a)
    write_mesh(a, sys.stdout)


check = checker("box.py")


def used(etype, i, j, k):
    """Whether point (i, j, k) of the fine grid is a node of a mesh of `etype` (C3D8: every
    point of the element grid; C3D20: no face or element centres; C3D27: every point)."""
    if etype == "C3D20":
        return (i % 2) + (j % 2) + (k % 2) <= 1
    return True


def node_count(a):
    """Nodes of the mesh."""
    if a.type == "C3D8":
        return (a.nx + 1) * (a.ny + 1) * (a.nz + 1)
    m = [2 * a.nx + 1, 2 * a.ny + 1, 2 * a.nz + 1]
    if a.type == "C3D27":
        return m[0] * m[1] * m[2]
    # the fine grid less the points with two or three odd indices
    odd = [a.nx, a.ny, a.nz]
    even = [a.nx + 1, a.ny + 1, a.nz + 1]
    return (m[0] * m[1] * m[2] - odd[0] * odd[1] * odd[2] - odd[0] * odd[1] * even[2]
            - odd[0] * even[1] * odd[2] - even[0] * odd[1] * odd[2])


def check_options(a):
    """Rejects the values that would give no mesh, an invalid one or a traceback."""
    for d in "xyz":
        n, length, x0 = getattr(a, f"n{d}"), getattr(a, f"l{d}"), getattr(a, f"{d}0")
        check(n >= 1, f"--n{d}", "a positive integer", n)
        check(math.isfinite(length) and length > 0.0, f"--l{d}", "a positive finite length",
              length)
        check(math.isfinite(x0), f"--{d}0", "a finite number", x0)
        m = n if a.type == "C3D8" else 2 * n
        xs = [x0 + i * (length / m) for i in range(m + 1)]
        check(all(map(math.isfinite, xs)) and all(p < q for p, q in zip(xs, xs[1:])),
              f"--l{d}", f"a length whose nodes stay finite and distinct from --{d}0 {x0!r}",
              length)
    check(node_count(a) <= MAX_ID, "--nx, --ny, --nz", f"at most {MAX_ID} nodes",
          (a.nx, a.ny, a.nz))
    check_first_ids(check, (("--first-node", a.first_node, node_count(a), "node"),
                            ("--first-element", a.first_element, a.nx * a.ny * a.nz,
                             "element")))
    check_names(check, a, "X0")
    check(0.0 <= a.distort < MAX_DISTORT, "--distort",
          f"a number in [0, {MAX_DISTORT:g}) (larger offsets can invert elements)", a.distort)


def pseudo_random(i, j, k, c):
    """A deterministic number in [-1, 1) of the grid point (i, j, k) and direction c."""
    s = math.sin(12.9898 * i + 78.233 * j + 37.719 * k + 4.1414 * c) * 43758.5453
    return 2.0 * (s - math.floor(s)) - 1.0


def grid(a):
    """The nodes: {(i, j, k): [x, y, z]} on the fine grid (the element grid for C3D8), with
    the ids in the order of the points (i fastest, then j, then k)."""
    s = 1 if a.type == "C3D8" else 2
    m = [s * a.nx, s * a.ny, s * a.nz]
    h = [a.lx / m[0], a.ly / m[1], a.lz / m[2]]
    x0 = [a.x0, a.y0, a.z0]
    ids, coords = {}, {}
    nid = a.first_node
    for k in range(m[2] + 1):
        for j in range(m[1] + 1):
            for i in range(m[0] + 1):
                if not used(a.type, i, j, k):
                    continue
                ids[(i, j, k)] = nid
                coords[(i, j, k)] = [x0[0] + i * h[0], x0[1] + j * h[1], x0[2] + k * h[2]]
                nid += 1
    if a.distort > 0.0:
        for p, x in coords.items():
            if any(q % s for q in p) or any(q in (0, mq) for q, mq in zip(p, m)):
                continue
            for c in range(3):
                x[c] += a.distort * s * h[c] * pseudo_random(*p, c)
        # the other nodes back to the mean of the corners of their edge, face or element
        for p, x in coords.items() if s == 2 else ():
            odd = [c for c in range(3) if p[c] % 2]
            if not odd:
                continue
            corners = [p]
            for c in odd:
                corners = [q[:c] + (q[c] + d,) + q[c + 1:] for q in corners for d in (-1, 1)]
            for c in range(3):
                x[c] = sum(coords[q][c] for q in corners) / len(corners)
    return ids, coords, m


def write_mesh(a, out):
    ids, coords, m = grid(a)
    out.write("*NODE\n")
    for key, n in ids.items():
        x = coords[key]
        out.write(f"{n}, {x[0]:.17g}, {x[1]:.17g}, {x[2]:.17g}\n")
    out.write(f"*ELEMENT, TYPE={a.type}, ELSET={a.elset}, MATERIAL={a.material}\n")
    eid = a.first_element
    half = 1 if a.type == "C3D8" else 2
    for ez in range(a.nz):
        for ey in range(a.ny):
            for ex in range(a.nx):
                base = (half * ex, half * ey, half * ez)
                # parent -1, 0, 1 is grid offset 0, half/2, half
                conn = [ids[tuple(b + (q + 1) * half // 2 for b, q in zip(base, xi))]
                        for xi in PARENT[a.type]]
                vals = [str(eid)] + [str(n) for n in conn]
                lines = [vals[k:k + PER_LINE] for k in range(0, len(vals), PER_LINE)]
                out.write(",\n".join(", ".join(v) for v in lines) + "\n")
                eid += 1
    p = a.prefix
    for c, d in enumerate("XYZ"):
        for side, value in (("0", 0), ("1", m[c])):
            nodes = [n for q, n in ids.items() if q[c] == value]
            out.write(f"*NSET, NSET={p}{d}{side}\n")
            for k in range(0, len(nodes), 16):
                out.write(", ".join(map(str, nodes[k:k + 16])) + "\n")


if __name__ == "__main__":
    main()
