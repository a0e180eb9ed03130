#!/usr/bin/env python3
"""Decks in Abaqus/CalculiX syntax (deck format 2) give the results of their native twins.

1. input/interop/block_ccx.inp (CalculiX style: CPE8, *SOLID SECTION, nodes "id, x, y, z",
   an empty dt field) and input/interop/block_native.inp (Q8, MATERIAL= on *ELEMENT,
   *ANALYSIS, TYPE=PLANE STRAIN, dt = 0) write the same results file bit for bit: every
   dataset and every attribute, the processed deck included (scripts/compare_results.py).
2. The free vibration of block_ccx.inp (clamped left edge, uniform initial velocity) keeps
   kinetic + strain energy constant to 1% (central differences conserve a discrete energy).
3. The other Abaqus names against their native meaning, on a distorted 8 x 4 block: CPE4 = Q4
   plane strain, CPS8R = Q8 with GAUSS=2 plane stress, CPS9 = Q9 plane stress; bit for bit.
"""
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

INPUT = os.path.join(vcheck.ROOT, "input", "interop")
COMPARE = os.path.join(vcheck.ROOT, "scripts", "compare_results.py")


def identical(a, b):
    p = subprocess.run([sys.executable, COMPARE, a, b], stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    print("    " + p.stdout.strip().replace("\n", "\n    "))
    return p.returncode == 0


def abaqus_style(native, abaqus_type):
    """A native rect.py mesh rewritten the Abaqus way: TYPE=<abaqus_type>, no MATERIAL= on
    *ELEMENT (a *SOLID SECTION instead), nodes "id, x, y, 0"."""
    out, in_nodes = [], False
    for line in native.splitlines():
        if line.startswith("*"):
            in_nodes = line.startswith("*NODE")
            if line.startswith("*ELEMENT"):
                line = f"*Element, type={abaqus_type}, elset=BODY"
        elif in_nodes:
            line += ", 0."
        out.append(line)
    return "\n".join(out) + "\n*Solid Section, elset=BODY, material=MAT\n"


def twin_decks(etype, abaqus_type, analysis, gauss):
    mesh = vcheck.rect_mesh(type=etype, nx=8, ny=4, lx=4.0, ly=2.0, distort=0.2)
    tail = ("*BOUNDARY\nLEFT, 1, 2\n*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 2, 1.0\n"
            "*STEP\n*DYNAMIC, EXPLICIT\n{dt}, 0.5\n*END STEP\n")
    native_mesh = mesh if gauss == 0 else mesh.replace("MATERIAL=MAT", f"MATERIAL=MAT, GAUSS={gauss}")
    native = ("*HEADING\ntwin\n" + f"*ANALYSIS, TYPE={analysis}\n" + vcheck.material_block()
              + native_mesh + tail.format(dt="0"))
    abaqus = ("*HEADING\ntwin\n" + vcheck.material_block() + abaqus_style(mesh, abaqus_type)
              + tail.format(dt=""))
    return native, abaqus


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("interop")
    out = {}
    for name in ("block_ccx", "block_native"):
        out[name] = os.path.join(args.work, name + ".h5")
        vcheck.run_ictus(args, os.path.join(INPUT, name + ".inp"), out[name])
    chk.true(identical(out["block_native"], out["block_ccx"]),
             "block_ccx.inp (CPE8, *SOLID SECTION, x y z, blank dt) = block_native.inp bit for bit")
    r = vcheck.Results(out["block_ccx"])
    e = r.history("energy/total")
    chk.below(float(np.max(np.abs(e - e[0])) / e[0]), 1e-2,
              "block_ccx.inp: free vibration, max |E_total - E_0| / E_0")
    chk.true(r.attr("analysis").lower().replace("_", " ").startswith("plane strain"),
             f"block_ccx.inp: CPE8 sets plane strain (analysis = {r.attr('analysis')})")

    for etype, abaqus_type, analysis, gauss in (("Q4", "CPE4", "PLANE STRAIN", 0),
                                                ("Q8", "CPS8R", "PLANE STRESS", 2),
                                                ("Q9", "CPS9", "PLANE STRESS", 0)):
        native, abaqus = twin_decks(etype, abaqus_type, analysis, gauss)
        h5 = []
        for tag, text in (("native", native), ("abaqus", abaqus)):
            path = os.path.join(args.work, f"{abaqus_type}_{tag}.inp")
            with open(path, "w") as f:
                f.write(text)
            h5.append(path[:-4] + ".h5")
            vcheck.run_ictus(args, path, h5[-1])
        chk.true(identical(*h5), f"{abaqus_type} = {etype}"
                 + (f" GAUSS={gauss}" if gauss else "") + f", {analysis.lower()}, bit for bit")
    chk.finish()


if __name__ == "__main__":
    main()
