#!/usr/bin/python3
"""Meshes a box with gmsh into hexahedra and writes gmsh's own Abaqus .inp export, for
*INCLUDE in a 3D deck.

    /usr/bin/python3 scripts/mesh/gmsh_box.py OUT.inp [--lx 8] [--ly 1] [--lz 1]
        [--n 16,2,2] [--order 1|2] [--complete]

The box [0, lx] x [0, ly] x [0, lz] is meshed by gmsh (Debian python3-gmsh) as a transfinite
volume of n1 x n2 x n3 hexahedra (every face recombined into quadrangles). --order 1 gives
C3D8; --order 2 C3D20 (serendipity) unless --complete asks for C3D27. Physical groups,
written by gmsh as element sets: BODY (the volume) and the faces LEFT (x = 0), RIGHT (x = lx),
FRONT (y = 0), BACK (y = ly), BOTTOM (z = 0), TOP (z = lz). gmsh writes the faces as surface
elements (CPS4, CPS8 or M3D9), which ictus reads in a 3D analysis as sets of boundary nodes,
as it reads the line elements of a 2D export; the deck adds the material, the section
(*SOLID SECTION, ELSET=BODY), the conditions and the step.

Exit status 0 when the file is written; 1 with a one-line message when gmsh (the Python
module) is missing or the arguments are bad.
"""
import argparse
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--lx", type=float, default=8.0)
    ap.add_argument("--ly", type=float, default=1.0)
    ap.add_argument("--lz", type=float, default=1.0)
    ap.add_argument("--n", default="16,2,2", help="elements along x, y, z")
    ap.add_argument("--order", type=int, default=1, choices=(1, 2))
    ap.add_argument("--complete", action="store_true", help="C3D27 instead of C3D20")
    a = ap.parse_args()
    try:
        n = [int(t) for t in a.n.split(",")]
        if len(n) != 3 or min(n) < 1:
            raise ValueError
    except ValueError:
        print(f"gmsh_box.py: bad --n {a.n!r} (expected three counts >= 1, e.g. 16,2,2)")
        sys.exit(1)
    if min(a.lx, a.ly, a.lz) <= 0:
        print("gmsh_box.py: the box's sides must be > 0")
        sys.exit(1)
    try:
        import gmsh
    except ImportError:
        print("gmsh_box.py: the gmsh Python module is missing (Debian: apt-get install gmsh "
              "python3-gmsh)")
        sys.exit(1)
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("box")
    vol = gmsh.model.occ.addBox(0, 0, 0, a.lx, a.ly, a.lz)
    gmsh.model.occ.synchronize()
    # the box's edges along each axis get that axis's count of elements
    for dim, tag in gmsh.model.getEntities(1):
        x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(dim, tag)
        axis = max(range(3), key=lambda k: [x1 - x0, y1 - y0, z1 - z0][k])
        gmsh.model.mesh.setTransfiniteCurve(tag, n[axis] + 1)
    faces = {}
    for dim, tag in gmsh.model.getEntities(2):
        gmsh.model.mesh.setTransfiniteSurface(tag)
        gmsh.model.mesh.setRecombine(2, tag)
        c = gmsh.model.occ.getCenterOfMass(dim, tag)
        for name, k, value in (("LEFT", 0, 0.0), ("RIGHT", 0, a.lx), ("FRONT", 1, 0.0),
                               ("BACK", 1, a.ly), ("BOTTOM", 2, 0.0), ("TOP", 2, a.lz)):
            if abs(c[k] - value) < 1e-6 * max(a.lx, a.ly, a.lz):
                faces[name] = tag
    gmsh.model.mesh.setTransfiniteVolume(vol)
    group = gmsh.model.addPhysicalGroup(3, [vol])
    gmsh.model.setPhysicalName(3, group, "BODY")
    for name, tag in faces.items():
        group = gmsh.model.addPhysicalGroup(2, [tag])
        gmsh.model.setPhysicalName(2, group, name)
    gmsh.option.setNumber("Mesh.ElementOrder", a.order)
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0 if a.complete else 1)
    gmsh.model.mesh.generate(3)
    gmsh.write(a.out)
    gmsh.finalize()


if __name__ == "__main__":
    main()
