#!/usr/bin/env python3
"""Energy conservation of a freely vibrating block, and conservation laws of the start-up.

A 4 x 2 block (E = 1000, nu = 0.2, rho = 1, plane strain) of distorted Q8 / Q9 / Q4 elements,
clamped on its left edge, starts with a uniform velocity v_y = 1 on all free nodes. No load
does work and the clamped nodes do not move, so kinetic + strain energy stays at its initial
value 1/2 v^T M v (doc/theory.md §6: central differences conserve a discrete energy; the
reported energy, with the mean velocity at t_n, oscillates by O((omega dt)^2) around it).
Checked for lumped (HRZ) and consistent mass with dt = 0.5 * 2/omega_max and dt/2, over ~20
periods of the fundamental mode: bounded (1%) and falling like dt^2; also with the automatic step (0.9 * 2/omega_max) with a wider bound,
and with mass-proportional damping, where kinetic + strain + dissipated work stays constant.
"""
import os
import sys

import re

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402


def deck(etype, mass, dt, t_end, damping="", dynamic=""):
    return ("*HEADING\nfree block\n" + vcheck.material_block()
            + vcheck.rect_mesh(type=etype, nx=8, ny=4, lx=4.0, ly=2.0, distort=0.2)
            + "*BOUNDARY\nLEFT, 1, 2\n*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 2, 1.0\n"
            + mass + "\n" + damping + f"*STEP\n*DYNAMIC, EXPLICIT{dynamic}\n{dt}, {t_end}\n"
            + "*OUTPUT, FIELD, EVERY=100000\n*END STEP\n")


def run(args, name, text, log=None):
    path = os.path.join(args.work, name + ".inp")
    with open(path, "w") as f:
        f.write(text)
    out = os.path.join(args.work, name + ".h5")
    _, output = vcheck.run_ictus(args, path, out)
    if log is not None:
        log.append(output)
    return vcheck.Results(out)


def mean_cg_iterations(output):
    """The mean CG iterations per consistent-mass solve from the log."""
    m = re.search(r"mean ([0-9.]+) CG iterations per solve \(relative residual ([^)]+)\)", output)
    return float(m.group(1)), float(m.group(2))


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("free_block")
    t_end = 2.0  # the fundamental period of this cantilever is about 0.1
    for etype in ("Q8", "Q9", "Q4"):
        for mass in ("*MASS, TYPE=HRZ", "*MASS, TYPE=CONSISTENT"):
            tag = f"{etype}_{mass.split('=')[1].lower()}"
            probe = run(args, tag + "_probe", deck(etype, mass, 0, 1e-6))
            dt = 0.5 * 2.0 / float(probe.attr("omega_max"))
            err = []
            for k, step in enumerate((dt, dt / 2)):
                r = run(args, f"{tag}_{k}", deck(etype, mass, step, t_end))
                m = r.model("mass")
                fixed = np.isclose(r.model("coordinates")[:, 0], 0.0)
                ek, es = r.history("energy/kinetic"), r.history("energy/strain")
                et = r.history("energy/total")
                err.append(float(np.max(np.abs(et - et[0])) / et[0]))
            if "HRZ" in mass:
                chk.close(float(ek[0]), 0.5 * np.sum(m[~fixed]), 1e-12,
                          f"{tag}: initial kinetic energy 1/2 m v^2")
            chk.below(err[0], 1e-2, f"{tag}: max |E(t) - E(0)| / E(0) at dt = 0.5 dt_crit")
            # the reported energy deviates from the conserved discrete energy by O(dt^2)
            chk.true(3.0 < err[0] / err[1] < 5.5,
                     f"{tag}: energy error falls like dt^2 when dt is halved (ratio "
                     f"{err[0] / err[1]:.2f}, expected about 4)")
            chk.true(float(np.max(es)) > 0.3 * et[0], f"{tag}: energy is exchanged (max strain "
                     f"energy {np.max(es):.3g} of {et[0]:.3g})")
    # MASS SOLVER=CG, MASS TOL= (relative residual of the CG): a looser tolerance takes fewer
    # iterations; the solve error, at most ~ tol per step, stays far below the O(dt^2) energy
    # error of the scheme, so the energy history agrees with the default (1e-12) run
    logs = []
    mass = "*MASS, TYPE=CONSISTENT"
    probe = run(args, "q8_tol_probe", deck("Q8", mass, 0, 1e-6))
    dt = 0.5 * 2.0 / float(probe.attr("omega_max"))
    tight = run(args, "q8_tol_default", deck("Q8", mass, dt, 0.5, dynamic=", MASS SOLVER=CG"),
                logs)
    loose = run(args, "q8_tol_1e-6", deck("Q8", mass, dt, 0.5,
                                           dynamic=", MASS SOLVER=CG, MASS TOL=1e-6"), logs)
    (it_tight, tol_tight), (it_loose, tol_loose) = (mean_cg_iterations(o) for o in logs)
    chk.close(tol_tight, 1e-12, 1e-12, "default MASS TOL is 1e-12 (log)")
    chk.close(tol_loose, 1e-6, 1e-12, "MASS TOL=1e-6 reaches the solver (log)")
    chk.true(it_loose < 0.8 * it_tight, f"MASS TOL=1e-6 takes fewer CG iterations per solve "
             f"({it_loose:.1f} against {it_tight:.1f})")
    et0, et1 = tight.history("energy/total"), loose.history("energy/total")
    chk.below(float(np.max(np.abs(et1 - et0)) / et0[0]), 1e-4,
              "MASS TOL=1e-6: energy history within 1e-4 E(0) of the default run")
    # the default MASS SOLVER=CHOLESKY (M factorised once) and the CG at 1e-12 solve the same
    # system by independent methods: the histories agree to the CG's residual
    chol = run(args, "q8_cholesky", deck("Q8", mass, dt, 0.5))
    ec = chol.history("energy/total")
    chk.below(float(np.max(np.abs(ec - et0)) / et0[0]), 1e-9,
              "Cholesky and CG (1e-12) consistent-mass runs: energy histories agree to 1e-9 E(0)")
    last = chol.field_steps()[-1]
    uc, ug = chol.field(last, "displacement"), tight.field(last, "displacement")
    chk.below(float(np.max(np.abs(uc - ug)) / np.max(np.abs(ug))), 1e-9,
              "Cholesky and CG (1e-12): final displacements agree to 1e-9")
    r = run(args, "q8_auto", deck("Q8", "*MASS, TYPE=HRZ", 0, t_end))
    et = r.history("energy/total")
    chk.below(float(np.max(np.abs(et - et[0])) / et[0]), 2e-2,
              "Q8 HRZ automatic dt: max |E(t) - E(0)| / E(0)")
    r = run(args, "q8_damped", deck("Q8", "*MASS, TYPE=HRZ", 0, t_end, "*DAMPING, ALPHA=5.0\n"))
    ek, es, w = (r.history("energy/" + k) for k in ("kinetic", "strain", "external_work"))
    et = r.history("energy/total")
    chk.below(float((ek[-1] + es[-1]) / et[0]), 0.01, "damped: energy decays (alpha t = 10)")
    chk.below(float(np.max(np.abs(et - et[0])) / et[0]), 2e-2,
              "damped: kinetic + strain - damping work stays at E(0)")
    chk.finish()


if __name__ == "__main__":
    main()
