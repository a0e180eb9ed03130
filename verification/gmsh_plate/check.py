#!/usr/bin/env python3
"""A mesh exported by gmsh runs through *INCLUDE with only the material, section, conditions
and step added (deck format 2).

scripts/mesh/gmsh_plate.py has the real gmsh (Debian python3-gmsh) mesh a 4 x 2 plate with a
central hole of radius 0.5 into 8-node quadrilaterals and write gmsh's own .inp export: CPS8
elements for the surface, T3D3 line elements for the edges, an element set per physical group.
input/interop/plate_gmsh.inp includes that file unchanged and runs:
1. the export holds what ictus reads: CPS8 and T3D3 elements only, an *ELSET per group;
2. the total mass is rho times the area lx ly - pi r^2 (the quadratic elements follow the
   circle: to 1e-4);
3. every node of the LEFT edge stays fixed in x and y (the T3D3 set read as a node set);
4. the free vibration keeps kinetic + strain energy constant to 1%;
5. the other exports of the script run too: 9-node quadrilaterals (gmsh writes them as M3D9,
   read as Q9, plane stress) and linear ones (CPS4 with T3D2 edges), with their mass;
6. with Mesh.SaveGroupsOfNodes (--node-sets) gmsh adds an *NSET beside each *ELSET of the
   same name: the run is bit for bit the run without them (but for the title and the
   processed deck, which hold the path of the mesh file, gmsh's *Heading).
Without gmsh the case is skipped (exit status 77, a message says what to install).
"""
import os
import re
import shutil
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

LX, LY, R, RHO = 4.0, 2.0, 0.5, 1.0


def main():
    args = vcheck.arguments()
    vcheck.require_gmsh()
    chk = vcheck.Checker("gmsh_plate")
    mesh = os.path.join(args.work, "plate_gmsh_mesh.inp")
    subprocess.run([sys.executable, os.path.join(vcheck.ROOT, "scripts", "mesh", "gmsh_plate.py"),
                    mesh, "--lx", str(LX), "--ly", str(LY), "--radius", str(R)], check=True)
    deck = os.path.join(args.work, "plate_gmsh.inp")
    shutil.copy(os.path.join(vcheck.ROOT, "input", "interop", "plate_gmsh.inp"), deck)
    with open(mesh) as f:
        text = f.read()
    types = sorted(set(t.upper() for t in re.findall(r"^\*ELEMENT, *type=(\w+)", text, re.I | re.M)))
    sets = re.findall(r"^\*ELSET, *ELSET=(\w+)", text, re.I | re.M)
    print(f"  gmsh export: element types {types}, element sets {sets}")
    chk.true(types == ["CPS8", "T3D3"], "the export has CPS8 surface and T3D3 line elements")
    chk.true(sorted(sets) == sorted(["PLATE", "LEFT", "RIGHT", "BOTTOM", "TOP", "HOLE"]),
             "an *ELSET per physical group")

    out = os.path.join(args.work, "plate_gmsh.h5")
    vcheck.run_ictus(args, deck, out)
    r = vcheck.Results(out)
    chk.close(float(np.sum(r.model("mass"))), RHO * (LX * LY - np.pi * R * R), 1e-4,
              "total mass = rho (lx ly - pi r^2)")
    x = r.model("coordinates")
    left = np.abs(x[:, 0]) < 1e-9 * LX
    last = r.field_steps()[-1]
    u = r.field(last, "displacement")
    chk.true(bool(left.any()) and bool(np.all(u[left] == 0.0)) and bool(np.any(u[~left] != 0.0)),
             f"the {int(left.sum())} nodes at x = 0 (LEFT, T3D3 elements) stay fixed, the others move")
    e = r.history("energy/total")
    chk.below(float(np.max(np.abs(e - e[0])) / e[0]), 1e-2,
              "free vibration, max |E_total - E_0| / E_0")

    sub = os.path.join(args.work, "node_sets")
    os.makedirs(sub, exist_ok=True)
    subprocess.run([sys.executable, os.path.join(vcheck.ROOT, "scripts", "mesh", "gmsh_plate.py"),
                    os.path.join(sub, "plate_gmsh_mesh.inp"), "--lx", str(LX), "--ly", str(LY),
                    "--radius", str(R), "--node-sets"], check=True)
    with open(os.path.join(sub, "plate_gmsh_mesh.inp")) as f:
        nsets = re.findall(r"^\*NSET, *NSET=(\w+)", f.read(), re.I | re.M)
    shutil.copy(deck, sub)
    vcheck.run_ictus(args, os.path.join(sub, "plate_gmsh.inp"), os.path.join(sub, "plate_gmsh.h5"))
    cmp = subprocess.run([sys.executable, os.path.join(vcheck.ROOT, "scripts", "compare_results.py"),
                          out, os.path.join(sub, "plate_gmsh.h5"), "--ignore-attr", "title",
                          "--ignore-attr", "deck"], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True)
    print("    " + cmp.stdout.strip())
    chk.true(sorted(nsets) == sorted(sets) and cmp.returncode == 0,
             f"--node-sets: *NSET {sorted(nsets)} beside the *ELSETs; results identical")

    for opts, want, rtol, note in ((["--complete"], ["M3D9", "T3D3"], 1e-4, ""),
                                   (["--order", "1"], ["CPS4", "T3D2"], 1e-2,
                                    " (straight edges cut the circle)")):
        sub = os.path.join(args.work, "_".join(want).lower())
        os.makedirs(sub, exist_ok=True)
        subprocess.run([sys.executable, os.path.join(vcheck.ROOT, "scripts", "mesh",
                                                     "gmsh_plate.py"),
                        os.path.join(sub, "plate_gmsh_mesh.inp")] + opts, check=True)
        with open(os.path.join(sub, "plate_gmsh_mesh.inp")) as f:
            found = sorted(set(t.upper() for t in re.findall(r"^\*ELEMENT, *type=(\w+)",
                                                             f.read(), re.I | re.M)))
        shutil.copy(deck, sub)
        vcheck.run_ictus(args, os.path.join(sub, "plate_gmsh.inp"),
                         os.path.join(sub, "plate_gmsh.h5"))
        m = float(np.sum(vcheck.Results(os.path.join(sub, "plate_gmsh.h5")).model("mass")))
        chk.true(found == want, f"gmsh_plate.py {' '.join(opts)}: the export has {found}")
        chk.close(m, RHO * (LX * LY - np.pi * R * R), rtol,
                  f"gmsh_plate.py {' '.join(opts)}: total mass{note}")
    chk.finish()


if __name__ == "__main__":
    main()
