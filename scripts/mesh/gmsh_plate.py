#!/usr/bin/python3
"""Meshes a plate with a hole (or a grid of holes) with gmsh and writes it in Abaqus .inp
form, for *INCLUDE.

    /usr/bin/python3 scripts/mesh/gmsh_plate.py OUT.inp [--lx 4] [--ly 2] [--radius 0.5]
        [--size 0.25] [--order 2] [--complete] [--node-sets] [--holes NX,NY] [--refine K]

The plate [0, lx] x [0, ly] has a circular hole of the given radius at its centre, or with
--holes NX,NY a grid of NX x NY such holes, centred in the cells of an NX x NY grid of the
plate (bench/benchmark.py --suite real meshes a plate with 4 x 2 holes). gmsh
(Debian python3-gmsh) meshes it with quadrilaterals: Frontal-Delaunay triangles recombined
into quadrangles, then every element split into quadrangles (Mesh.SubdivisionAlgorithm = 1),
so that no triangle is left; --refine K then splits every element into four K times
(gmsh.model.mesh.refine: the same mesh with elements of half the size; gmsh's meshing of
this plate takes about 5 s for 1e5 elements, but minutes for 1e6). --order 2 (the default)
gives quadratic elements, 8-node serendipity ones (CPS8 in the file) unless --complete asks
for 9-node ones; --order 1 gives CPS4.

Physical groups, written by gmsh as element sets: PLATE (the surface), LEFT (x = 0), RIGHT
(x = lx), BOTTOM (y = 0), TOP (y = ly) and HOLE (the circles). The curves are written as line
elements (T3D2, or T3D3 at order 2), which ictus reads as sets of boundary nodes; the surface
as CPS elements, plane stress. --node-sets also writes an *NSET per group
(Mesh.SaveGroupsOfNodes, what CalculiX users ask for), beside the *ELSET of the same name:
ictus takes the pair as one set. Nothing else is needed from gmsh: the deck adds the materials,
the section, the conditions and the step (doc/user-guide.md, "Coming from Abaqus, CalculiX
and gmsh").

Exit status 0 when the file is written; 1 with a one-line message when gmsh (the Python
module) is missing or the arguments are bad.
"""
import argparse
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--lx", type=float, default=4.0)
    ap.add_argument("--ly", type=float, default=2.0)
    ap.add_argument("--radius", type=float, default=0.5)
    ap.add_argument("--size", type=float, default=0.25, help="target element size")
    ap.add_argument("--order", type=int, choices=(1, 2), default=2)
    ap.add_argument("--complete", action="store_true", help="9-node quadrilaterals")
    ap.add_argument("--node-sets", action="store_true", help="an *NSET per physical group too")
    ap.add_argument("--holes", default="1,1", help="NX,NY: a grid of holes (default 1,1)")
    ap.add_argument("--refine", type=int, default=0,
                    help="split every element into four this many times")
    a = ap.parse_args()
    try:
        nx, ny = (int(k) for k in a.holes.split(","))
    except ValueError:
        nx = ny = 0
    if a.refine < 0:
        sys.exit(f"gmsh_plate.py: --refine: expected an integer >= 0, got {a.refine}")
    if nx < 1 or ny < 1:
        sys.exit(f"gmsh_plate.py: --holes: expected NX,NY, two positive integers, got {a.holes}")
    cx, cy = a.lx / nx, a.ly / ny
    if not (a.lx > 0 and a.ly > 0 and a.size > 0 and 0 < a.radius < 0.5 * min(cx, cy)):
        sys.exit("gmsh_plate.py: expected lx, ly, size > 0 and 0 < radius < min(lx/NX, ly/NY) / 2")
    try:
        import gmsh
    except ImportError:
        sys.exit("gmsh_plate.py: the gmsh Python module is missing (Debian: apt-get install "
                 "gmsh python3-gmsh)")

    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("plate")
    occ = gmsh.model.occ
    rect = occ.addRectangle(0, 0, 0, a.lx, a.ly)
    holes = [(2, occ.addDisk((i + 0.5) * cx, (j + 0.5) * cy, 0, a.radius, a.radius))
             for j in range(ny) for i in range(nx)]
    occ.cut([(2, rect)], holes)
    occ.synchronize()
    surfaces = [tag for _, tag in gmsh.model.getEntities(2)]
    groups = {"LEFT": [], "RIGHT": [], "BOTTOM": [], "TOP": [], "HOLE": []}
    eps = 1e-9 * max(a.lx, a.ly)
    for _, tag in gmsh.model.getEntities(1):
        x, y, _ = occ.getCenterOfMass(1, tag)
        if abs(x) < eps:
            groups["LEFT"].append(tag)
        elif abs(x - a.lx) < eps:
            groups["RIGHT"].append(tag)
        elif abs(y) < eps:
            groups["BOTTOM"].append(tag)
        elif abs(y - a.ly) < eps:
            groups["TOP"].append(tag)
        else:
            groups["HOLE"].append(tag)
    for name, tags in groups.items():
        gmsh.model.setPhysicalName(1, gmsh.model.addPhysicalGroup(1, tags), name)
    gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, surfaces), "PLATE")

    # Frontal-Delaunay (6) and recombination; the Frontal-Delaunay for quads (8) of the
    # Debian gmsh 4.8 crashes on this geometry.
    gmsh.option.setNumber("Mesh.Algorithm", 6)
    gmsh.option.setNumber("Mesh.RecombineAll", 1)
    gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 1)
    gmsh.option.setNumber("Mesh.MeshSizeMax", 2 * a.size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.5 * a.size)
    # with --refine: meshed linear, split, then made quadratic (gmsh 4.8 drops the
    # 8-node quadrangles it is asked to split)
    gmsh.option.setNumber("Mesh.ElementOrder", 1 if a.refine else a.order)
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0 if a.complete else 1)
    gmsh.option.setNumber("Mesh.SaveGroupsOfNodes", 1 if a.node_sets else 0)
    gmsh.model.mesh.generate(2)
    for _ in range(a.refine):
        gmsh.model.mesh.refine()
    if a.refine and a.order > 1:
        gmsh.model.mesh.setOrder(a.order)
    gmsh.write(a.out)
    gmsh.finalize()


if __name__ == "__main__":
    main()
