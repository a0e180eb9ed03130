#!/usr/bin/env python3
"""A free bar under a suddenly applied end force (*CLOAD), and the same bar held at one end
and relaxed under a smoothly ramped force (doc/theory.md §4a, doc/reference.md §3.5).

Bar: length 10, height 1, plane stress, nu = 0 (uniaxial stress), E = 1000, rho = 1, 100 x 1
Q4 elements; the force F = 1 is split over the two nodes of the end x = 10.
1. Free bar, F applied at t = 0 (no amplitude):
   - Newton on the whole bar: the total momentum is F t, and the mass-weighted mean
     displacement is u_mean(t) = F t^2 / (2 m), m = rho L H = 10. For the central-difference
     scheme this is exact (sum_i m_i a_i = F at every step, v_{-1/2} = -dt/2 a_0), so it is
     checked to 1e-12 at every field step;
   - the stress wave: behind the front sigma_xx = F/A = 1 (mean over the middle of the loaded
     part, within 3 %) and the front (sigma_xx = 1/2) at x = L - c t, c = sqrt(E/rho), within
     two element lengths;
   - the external work: the history's external_work equals the trapezoidal sum of F . v over
     the end nodes, recomputed here from the velocity field written at every step
     (v_n = (v_{n-1/2} + v_{n+1/2})/2), to 1e-10; the total energy stays within 1 % of the
     work done;
   - no constrained dofs: the reaction field is 0;
   - bit-identical results on 2 and 3 ranks and after a restart on 2 ranks from a checkpoint of
     the 1-rank run.
2. Bar held at x = 0 (u_x = 0 on the end, u_y = 0 at one corner), F ramped by a SMOOTH STEP
   amplitude over t in [0, 2] and relaxed with *DAMPING: at t = 6 the end displacement is
   F L/(E A) = 0.01 and the reactions sum to -F (to 1e-4), the other dofs' reactions are 0.
   Here the *CLOAD names the two end nodes by their ids.
3. The held bar under the sudden force, undamped, with the lumped (HRZ) and the consistent
   mass: the reactions are R = (M a)_c - (f_ext - f_int)_c, so summed with the loads they give
   1^T M a (the internal forces sum to zero): the momentum P = sum of the row-sum masses times
   the velocities obeys P_{n+1/2} - P_{n-1/2} = dt (F + sum R_n), and with the mean velocities
   of the fields P_{n+1} - P_n = dt (F + (sum R_n + sum R_{n+1})/2), checked at every step to
   1e-9 of F dt (for the consistent mass this needs the coupling M_cf a_f in R). The
   consistent-mass run on 2 ranks gives the same bits.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

E, RHO, L, H, NX, F = 1000.0, 1.0, 10.0, 1.0, 100, 1.0
C = math.sqrt(E / RHO)
T1 = 0.2


def header(title):
    return (f"*HEADING\n{title}\n*ANALYSIS, TYPE=PLANE STRESS, THICKNESS=1\n"
            + vcheck.material_block(e=E, nu=0.0, rho=RHO)
            + vcheck.rect_mesh(type="Q4", nx=NX, ny=1, lx=L, ly=H))


def free_deck():
    return (header("free bar under a suddenly applied end force")
            + f"*STEP\n*DYNAMIC, EXPLICIT\n0, {T1}\n*CLOAD\nRIGHT, 1, {F / 2}\n"
            "*OUTPUT, HISTORY, EVERY=1\n*OUTPUT, FIELD, EVERY=1, VARIABLES=U,V,S,MISES,RF\n*RESTART, WRITE, EVERY=30\n"
            "*END STEP\n")


def held_deck():
    return (header("held bar relaxed under a ramped end force")
            + "*AMPLITUDE, NAME=RAMP, DEFINITION=SMOOTH STEP\n0, 0, 2, 1\n"
            + "*BOUNDARY\nLEFT, 1, 1\nCORNER_LL, 2, 2\n*DAMPING, ALPHA=8\n"
            + f"*STEP\n*DYNAMIC, EXPLICIT\n0, 6\n*CLOAD, AMPLITUDE=RAMP\n"
            + f"{NX + 1}, 1, {F / 2}\n{2 * NX + 2}, 1, {F / 2}\n"
            "*OUTPUT, HISTORY, EVERY=100\n*OUTPUT, FIELD, EVERY=100000, VARIABLES=U,V,S,MISES,RF\n*END STEP\n")


def dynamic_held_deck(mass):
    return (header(f"held bar under a sudden end force, {mass} mass")
            + f"*BOUNDARY\nLEFT, 1, 1\nCORNER_LL, 2, 2\n*MASS, TYPE={mass}\n"
            + f"*STEP\n*DYNAMIC, EXPLICIT\n0, 0.5\n*CLOAD\nRIGHT, 1, {F / 2}\n"
            "*OUTPUT, HISTORY, EVERY=1\n*OUTPUT, FIELD, EVERY=1, VARIABLES=U,V,S,MISES,RF\n*END STEP\n")


def check_momentum(args, chk):
    for mass in ("HRZ", "CONSISTENT"):
        path = os.path.join(args.work, f"held_{mass.lower()}.inp")
        with open(path, "w") as f:
            f.write(dynamic_held_deck(mass))
        out = os.path.join(args.work, f"held_{mass.lower()}.h5")
        vcheck.run_ictus(args, path, out)
        res = vcheck.Results(out)
        m = res.model("mass")
        steps = res.field_steps()
        t = np.array([res.field_time(s) for s in steps])
        p = np.array([m @ res.field(s, "velocity")[:, 0] for s in steps])
        r = np.array([res.field(s, "reaction")[:, 0].sum() for s in steps])
        dt = t[1] - t[0]
        err = np.max(np.abs(np.diff(p) - dt * (F + 0.5 * (r[1:] + r[:-1])))) / (F * dt)
        chk.below(float(err), 1e-9, f"{mass}: momentum change = impulse of F and the reactions")
        chk.true(float(np.max(np.abs(r))) > 0.5 * F, f"{mass}: the wave reaches the held end "
                 f"(largest |sum R| = {float(np.max(np.abs(r))):.3g})")
    o = out.replace(".h5", "_np2.h5")
    vcheck.run_ictus(args, path, o, np=2)
    chk.true(vcheck.same_bits(out, o), "CONSISTENT: 2 ranks bit-identical")


def check_free(args, chk):
    path = os.path.join(args.work, "free.inp")
    with open(path, "w") as f:
        f.write(free_deck())
    out = os.path.join(args.work, "free.h5")
    vcheck.run_ictus(args, path, out)
    res = vcheck.Results(out)
    m = res.model("mass")
    x0 = res.model("coordinates")
    chk.close(float(m.sum()), RHO * L * H, 1e-12, "total mass rho L H")
    steps = res.field_steps()
    t = np.array([res.field_time(s) for s in steps])
    umean = np.array([m @ res.field(s, "displacement")[:, 0] for s in steps]) / m.sum()
    want = F * t ** 2 / (2 * m.sum())
    err = np.max(np.abs(umean - want)) / np.max(want)
    chk.below(err, 1e-12, "mean displacement F t^2/(2m) at every step (exact for the scheme)")
    # stress wave at the last step
    last = steps[-1]
    tl = t[-1]
    conn = res.model("elements/q4/connectivity")
    xc = x0[conn, 0].mean(axis=1)
    sxx = res.field(last, "stress")[:, 0]
    front = L - C * tl
    sel = (xc > front + 0.2 * (L - front)) & (xc < L - 0.2 * (L - front))
    chk.close(float(np.mean(sxx[sel])), F / H, 0.03, "sigma_xx = F/A behind the front")
    order = np.argsort(xc)
    xs, ss = xc[order], sxx[order]
    k = np.nonzero(ss > 0.5 * F / H)[0][0]
    xf = xs[k - 1] + (0.5 * F / H - ss[k - 1]) * (xs[k] - xs[k - 1]) / (ss[k] - ss[k - 1])
    chk.below(abs(xf - front), 2 * L / NX, f"front at {xf:.3f}, L - c t = {front:.3f}")
    # external work: trapezoidal sum of F . v_n over the loaded nodes, from the fields
    right = np.abs(x0[:, 0] - L) < 1e-12
    p = np.array([F / 2 * res.field(s, "velocity")[right, 0].sum() for s in steps])
    w = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(t) * (p[1:] + p[:-1]))])
    wh = res.history("energy/external_work")
    th = res.history("time")
    chk.true(np.array_equal(th, t), "history and fields at the same times")
    chk.below(float(np.max(np.abs(wh - w)) / abs(w[-1])), 1e-10,
              "external_work = trapezoidal sum of F . v_n from the velocity fields")
    chk.close(float(wh[-1]), F * float(np.mean(res.field(last, "displacement")[right, 0])),
              0.05, "external work ~ F u_end")
    total = res.history("energy/total")
    chk.below(float(np.max(np.abs(total - total[0])) / wh[-1]), 0.01,
              "total energy (kinetic + strain - external work) constant within 1 % of the work")
    chk.true(all(not np.any(res.field(s, "reaction")) for s in steps),
             "no constrained dofs: the reaction field is 0")
    vcheck.check_ranks_and_restart(args, chk, path, out, ranks=(2, 3))


def check_held(args, chk):
    path = os.path.join(args.work, "held.inp")
    with open(path, "w") as f:
        f.write(held_deck())
    out = os.path.join(args.work, "held.h5")
    vcheck.run_ictus(args, path, out)
    res = vcheck.Results(out)
    x0 = res.model("coordinates")
    last = res.field_steps()[-1]
    u = res.field(last, "displacement")
    r = res.field(last, "reaction")
    right = np.abs(x0[:, 0] - L) < 1e-12
    left = np.abs(x0[:, 0]) < 1e-12
    chk.close(float(np.mean(u[right, 0])), F * L / (E * H), 1e-4, "static end displacement F L/(E A)")
    chk.close(float(r[:, 0].sum()), -F, 1e-4, "reactions sum to -F")
    chk.below(float(np.max(np.abs(r[~left, 0]))), 0.0, "x reactions only on the held end")
    chk.below(abs(float(r[:, 1].sum())), 1e-6, "no y reaction (uniaxial)")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("loads_bar")
    check_free(args, chk)
    check_held(args, chk)
    check_momentum(args, chk)
    chk.finish()


if __name__ == "__main__":
    main()
