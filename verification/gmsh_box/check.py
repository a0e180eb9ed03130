#!/usr/bin/env python3
"""A 3D mesh exported by gmsh runs through *INCLUDE with only the material, section,
conditions and step added (deck format 2).

scripts/mesh/gmsh_box.py has the real gmsh (Debian python3-gmsh) mesh the bar
[0, 10] x [0, 0.5] x [0, 0.5] into hexahedra (100 x 1 x 1 C3D8, 50 x 1 x 1 C3D20 and
C3D27) and write gmsh's own
.inp export: the volume elements, the faces as surface elements (CPS4, CPS8, M3D9) and an
element set per physical group. The deck includes that file unchanged, holds the LEFT face
(u_x = 0 on the set of its surface elements' nodes) and sets the bar moving at -v0 along x
with nu = 0: the 1D bar wave, checked against the characteristics solution.
1. the export holds what ictus reads: one volume type and one surface type, an *ELSET per
   group;
2. the LEFT set is exactly the nodes of the plane x = 0 (held: u_x = 0 at every snapshot);
3. the bar wave (vcheck.check_bar_wave): mass-weighted RMS error of u and the free end within
   2 %, no lateral motion, energy kept, the mass rho L h^2 to 1e-12.
Without gmsh the case is skipped (exit status 77, a message says what to install).
"""
import os
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

L, H, E, RHO, V0 = 10.0, 0.5, 1000.0, 1.0, 0.1
C = np.sqrt(E / RHO)
# (volume type, gmsh_box options, surface type, elements along x, largest lateral / axial
# motion): C3D8 (equal nodal masses on the section) keeps the motion 1D exactly; the corner
# and midside masses of C3D20 make u_x vary over the section at the front (a little shear)
# (the prism of verification/solid3d's bar wave)
CASES = (("C3D8", ["--order", "1"], "CPS4", 100, 1e-12),
         ("C3D20", ["--order", "2"], "CPS8", 50, 0.02),
         ("C3D27", ["--order", "2", "--complete"], "M3D9", 50, 1e-12))


def main():
    args = vcheck.arguments()
    vcheck.require_gmsh()
    chk = vcheck.Checker("gmsh_box")
    for solid, opts, face, nx, lateral in CASES:
        mesh = os.path.join(args.work, f"box_{solid}_mesh.inp")
        subprocess.run([sys.executable, os.path.join(vcheck.ROOT, "scripts", "mesh",
                        "gmsh_box.py"), mesh, "--lx", str(L), "--ly", str(H), "--lz", str(H),
                        "--n", f"{nx},1,1"] + opts, check=True)
        with open(mesh) as f:
            text = f.read()
        types = sorted(set(t.upper() for t in re.findall(r"^\*ELEMENT, *type=(\w+)", text,
                                                        re.I | re.M)))
        sets = sorted(re.findall(r"^\*ELSET, *ELSET=(\w+)", text, re.I | re.M))
        chk.true(types == sorted([solid, face]), f"{solid}: the export has {solid} volume and "
                 f"{face} surface elements (got {types})")
        chk.true(sets == sorted(["BODY", "LEFT", "RIGHT", "FRONT", "BACK", "BOTTOM", "TOP"]),
                 f"{solid}: an *ELSET per physical group")
        deck = os.path.join(args.work, f"box_{solid}.inp")
        with open(deck, "w") as f:
            f.write(f"*HEADING\ngmsh box {solid}, bar wave\n*ANALYSIS, TYPE=3D\n"
                    + vcheck.material_block("M", E, 0.0, RHO)
                    + f"*INCLUDE, INPUT={os.path.basename(mesh)}\n"
                    "*SOLID SECTION, ELSET=BODY, MATERIAL=M\n"
                    "*BOUNDARY\nLEFT, 1, 1\n"
                    f"*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 1, {-V0}\n*MASS, TYPE=HRZ\n"
                    f"*STEP\n*DYNAMIC, EXPLICIT\n0, {1.5 * L / C}\n"
                    "*OUTPUT, FIELD, EVERY=50\n*END STEP\n")
        out = deck.replace(".inp", ".h5")
        vcheck.run_ictus(args, deck, out)
        r = vcheck.Results(out)
        x = r.model("coordinates")
        left = np.isclose(x[:, 0], 0.0)
        u = np.array([r.field(s, "displacement")[:, 0] for s in r.field_steps()])
        chk.true(left.sum() > 0 and np.all(u[:, left] == 0.0) and
                 np.all(np.abs(u[-1, ~left]) > 0), f"{solid}: the LEFT set holds the "
                 f"{left.sum()} nodes of x = 0 (u_x = 0 there, nowhere else)")
        vcheck.check_bar_wave(chk, r, f"{solid}: ", V0, L, C, lateral, RHO * L * H * H,
                              "rho L h^2")
    chk.finish()


if __name__ == "__main__":
    main()
