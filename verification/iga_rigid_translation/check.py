#!/usr/bin/env python3
"""Energy balance of an IGA run: the free half-disc of doc/iga.md §10.4 (R = 4, rho = 1, no
boundary conditions) translating at a uniform initial velocity v = (1.5, -2) (doc/reference.md §5,
rigid translation). Exact: f_int = K u = 0 for u = v t, so the body keeps v, the strain energy
stays 0, and the kinetic energy is (1/2) m v^2 with m = 8 pi rho for consistent, row-sum and
HRZ mass alike (every scheme conserves the total mass, and the consistent M applied to a
uniform vector gives its row sums). Decks from scripts/mesh/halfdisc.py --no-sym: p = 2 on
32 x 32 spans and p = 3 (*ELEVATE) on 16 x 16 spans, so that sum m = 8 pi rho to 1e-12
(see verification/iga_halfdisc_mass).
Gates: kinetic energy at t = 0 and at the end = (1/2) 8 pi rho |v|^2 (1e-12); strain energy
below 1e-12 of the kinetic energy at all times; total energy constant (1e-12); at the last
snapshot every control point has u = v t and velocity v (1e-10).
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402
import halfdisc  # noqa: E402

R, RHO, V = 4.0, 1.0, np.array([1.5, -2.0])
KE = 0.5 * RHO * math.pi * R * R / 2.0 * float(V @ V)


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("iga_rigid_translation")
    for tag, kw in (("p2", dict(subdivide=32)), ("p3", dict(elevate=3, subdivide=16))):
        for mass in ("CONSISTENT", "ROW SUM", "HRZ"):
            name = f"{tag}_{mass.replace(' ', '_').lower()}"
            a = halfdisc.options(kind="iga", radius=R, rho=RHO, sym=False, vx=float(V[0]),
                                 vy=float(V[1]), mass=mass, t_end=0.02, field_every=10, **kw)
            path = os.path.join(args.work, name + ".inp")
            with open(path, "w") as f:
                f.write(halfdisc.deck(a, "verification/iga_rigid_translation/check.py"))
            out = os.path.join(args.work, name + ".h5")
            vcheck.run_ictus(args, path, out)
            r = vcheck.Results(out)
            label = f"{tag} {mass}"
            ek = r.history("energy/kinetic")
            es = r.history("energy/strain")
            et = r.history("energy/total")
            chk.close(float(ek[0]), KE, 1e-12, f"{label}: kinetic energy at t = 0 = (1/2) 8 pi rho v^2")
            chk.close(float(ek[-1]), KE, 1e-12, f"{label}: kinetic energy at the end")
            chk.below(float(np.max(np.abs(es))) / KE, 1e-12, f"{label}: max |strain energy| / E_kin")
            chk.below(float(np.max(np.abs(et - et[0]))) / KE, 1e-12, f"{label}: max |E(t) - E(0)| / E(0)")
            last = r.field_steps()[-1]
            t = r.field_time(last)
            u = r.field(last, "displacement")
            v = r.field(last, "velocity")
            chk.below(float(np.max(np.abs(u - t * V))) / (t * float(np.max(np.abs(V)))), 1e-10,
                      f"{label}: u = v t at every control point, t = {t:.4g}")
            chk.below(float(np.max(np.abs(v - V))) / float(np.max(np.abs(V))), 1e-10,
                      f"{label}: velocity stays v")
    chk.finish()


if __name__ == "__main__":
    main()
