#!/usr/bin/env python3
"""Writes the *NODE, *ELEMENT and *NSET cards of a structured rectangular mesh.

    rect.py --type Q8 --nx 40 --ny 2 --lx 10 --ly 0.5 [--x0 0 --y0 0] [--first-node 1]
            [--first-element 1] [--elset BODY] [--material STEEL] [--distort 0.0] > mesh.inp

Node sets: LEFT, RIGHT, BOTTOM, TOP (edges), CORNER_LL/LR/UL/UR, plus the ELSET. Element
nodes follow deck-format.md (corners counter-clockwise, then midsides, then the centre).
--distort d moves every interior vertex node by a deterministic pseudo-random offset of up to
d times the element size (midside nodes stay at the middle of straight edges), for patch tests.
"""
import argparse
import math
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--type", choices=["Q4", "Q8", "Q9"], default="Q8")
    ap.add_argument("--nx", type=int, required=True)
    ap.add_argument("--ny", type=int, required=True)
    ap.add_argument("--lx", type=float, required=True)
    ap.add_argument("--ly", type=float, required=True)
    ap.add_argument("--x0", type=float, default=0.0)
    ap.add_argument("--y0", type=float, default=0.0)
    ap.add_argument("--first-node", type=int, default=1)
    ap.add_argument("--first-element", type=int, default=1)
    ap.add_argument("--elset", default="BODY")
    ap.add_argument("--material", default="MAT")
    ap.add_argument("--prefix", default="", help="prefix of the node set names")
    ap.add_argument("--distort", type=float, default=0.0)
    a = ap.parse_args()
    write_mesh(a, sys.stdout)


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
