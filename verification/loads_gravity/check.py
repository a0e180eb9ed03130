#!/usr/bin/env python3
"""A free block and a free NURBS patch under gravity (*DLOAD, GRAV), released from rest
(doc/theory.md §4a).

GRAV gives each node the force rho g d int N_A dV with d the normalised direction: here
g = 9.81 along (3, -4), so d = (0.6, -0.8). The forces sum to M g d (the shape functions are a
partition of unity, rational ones too), the lumped masses to M, and for the central-difference
scheme the mass-weighted mean displacement is then exactly g d t^2/2 at every step: checked to
1e-12 (relative) for each body, a Q8 block (the *DLOAD line names its element set) and a
biquadratic NURBS patch (by its patch name), with an empty element set (the whole model) in a
second run. No constrained dofs: the reaction field is 0. The total energy (kinetic + strain -
external work) stays within 2 % of the work done: the load applied at t = 0 excites the
highest modes, whose energy evaluated with the mean velocity oscillates by about
(omega dt/2)^2 around the conserved one (doc/theory.md §6). The processed deck (the echo of
the *DLOAD lines, an empty element set included) reruns bit for bit.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402
import impact  # noqa: E402

G, D = 9.81, np.array([0.6, -0.8])


def deck(whole):
    q8 = vcheck.rect_mesh(type="Q8", nx=4, ny=2, lx=2.0, ly=1.0, elset="BLOCK")
    patch, _ = impact.iga_block("PATCH", 3.0, 0.0, 2.0, 1.0, 4, 2)
    grav = ", GRAV, 9.81, 3, -4\n" if whole else "BLOCK, GRAV, 9.81, 3, -4\nPATCH, GRAV, 9.81, 3, -4\n"
    return ("*HEADING\nblock and patch falling under gravity\n"
            "*ANALYSIS, TYPE=PLANE STRAIN, THICKNESS=1\n"
            + vcheck.material_block(e=1000.0, nu=0.3, rho=2.0) + q8 + patch
            + "*DLOAD\n" + grav
            + "*STEP\n*DYNAMIC, EXPLICIT\n0, 0.05\n*OUTPUT, HISTORY, EVERY=1\n"
            "*OUTPUT, FIELD, EVERY=5, VARIABLES=U,V,S,MISES,RF\n*END STEP\n")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("loads_gravity")
    for whole in (False, True):
        name = "whole" if whole else "sets"
        path = os.path.join(args.work, f"{name}.inp")
        with open(path, "w") as f:
            f.write(deck(whole))
        out = os.path.join(args.work, f"{name}.h5")
        vcheck.run_ictus(args, path, out)
        res = vcheck.Results(out)
        m = res.model("mass")
        w = res.model("weights")
        x0 = res.model("coordinates")
        # the patch's control points follow the FE nodes in the numbering; the patch lies at x >= 3
        bodies = {"Q8 block": x0[:, 0] < 2.5, "NURBS patch": x0[:, 0] > 2.5}
        chk.true(np.all(w[x0[:, 0] < 2.5] == 1.0), "FE nodes have weight 1")
        for label, sel in bodies.items():
            err = 0.0
            for s in res.field_steps():
                t = res.field_time(s)
                u = res.field(s, "displacement")[sel]
                mean = m[sel] @ u / m[sel].sum()
                want = G * D * t ** 2 / 2
                err = max(err, float(np.max(np.abs(mean - want))) / (G * t ** 2 / 2 if t > 0 else 1))
            chk.below(err, 1e-12, f"{name}: {label}: mean displacement g d t^2/2 at every field step")
        last = res.field_steps()[-1]
        chk.true(not np.any(res.field(last, "reaction")), f"{name}: no constrained dofs, reaction 0")
        total = res.history("energy/total")
        work = res.history("energy/external_work")
        chk.below(float(np.max(np.abs(total - total[0])) / work[-1]), 0.02,
                  f"{name}: total energy constant (relative to the work of gravity)")
        chk.true(vcheck.processed_deck_reruns(args, out), f"{name}: the processed deck reruns "
                 "bit for bit")
    chk.finish()


if __name__ == "__main__":
    main()
