#!/usr/bin/env python3
"""The uniaxial-strain elastic-plastic wave (doc/reference.md, the J2 benchmark of doc/theory.md).

A bar of length 10 and height 0.5 in plane strain with rollers on top and bottom (u_y = 0: the
strain is uniaxial), E = 1000, nu = 0.3, rho = 1, J2 plasticity sigma_y = 5 + 100 epbar (table
`5, 0` / `105, 1`); the end x = 0 is held and the rest moves at -1 at t = 0 (a bar hitting a
rigid wall), small strain, Q4 elements of size 0.025. Closed forms (uniaxial strain):
- elastic modulus M = lambda + 2 mu = 1346.15, c_e = sqrt(M/rho) = 36.690; the Hugoniot elastic
  limit sigma_HEL = sigma_y (1 - nu)/(1 - 2 nu) = 8.75 at the strain eps_HEL = sigma_HEL/M;
- plastic modulus M_p = K + 4/3 mu H/(3 mu + H) = 874.23, c_p = sqrt(M_p/rho) = 29.567;
- the elastic precursor changes the velocity by sigma_HEL/(rho c_e) = 0.23848; behind the
  plastic front the bar is at rest, at the strain eps = eps_HEL + (sigma_final - sigma_HEL)/M_p
  with sigma_final = sigma_HEL + rho c_p (v0 - 0.23848) = 31.266.
At t = 0.2 (before the reflection from the far end at 10/c_e = 0.2726) the velocity and strain
plateaus behind each front are checked within 2 % (their means over the middle of each
plateau), the front positions (where the velocity is halfway between two plateaus) within two
element lengths of c_e t and c_p t, and the energy balance kinetic + strain + plastic work =
the initial kinetic energy (the held end does no work) within 0.5 %.
The history variables of the plasticity take part in the bit-identity of the runs: the same
run on 2 and 3 ranks, and one continued on 2 ranks from a checkpoint of the 1-rank run (which
carries the plastic strains), give every dataset of the results file bit for bit.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

E, NU, RHO, V0, SY, H = 1000.0, 0.3, 1.0, 1.0, 5.0, 100.0
LX, LY, NX, T = 10.0, 0.5, 400, 0.2


def closed_form():
    mu = E / (2 * (1 + NU))
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    m = lam + 2 * mu
    k = lam + 2 * mu / 3
    mp = k + 4 / 3 * mu * H / (3 * mu + H)
    c_e, c_p = math.sqrt(m / RHO), math.sqrt(mp / RHO)
    s_hel = SY * (1 - NU) / (1 - 2 * NU)
    dv = s_hel / (RHO * c_e)
    s_fin = s_hel + RHO * c_p * (V0 - dv)
    eps_hel = s_hel / m
    eps_fin = eps_hel + (s_fin - s_hel) / mp
    return c_e, c_p, dv, eps_hel, eps_fin, s_fin


def deck():
    mesh = vcheck.rect_mesh(type="Q4", nx=NX, ny=2, lx=LX, ly=LY)
    return ("*HEADING\nuniaxial-strain elastic-plastic wave\n"
            f"*MATERIAL, NAME=MAT\n*ELASTIC\n{E}, {NU}\n*PLASTIC\n{SY}, 0\n{SY + H}, 1\n"
            f"*DENSITY\n{RHO}\n" + mesh
            + "*BOUNDARY\nTOP, 2, 2\nBOTTOM, 2, 2\nLEFT, 1, 1\n"
            + f"*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 1, {-V0}\n*MASS, TYPE=HRZ\n"
            + f"*STEP\n*DYNAMIC, EXPLICIT\n0, {T}\n*OUTPUT, HISTORY, EVERY=1\n"
            + "*OUTPUT, FIELD, EVERY=200\n*RESTART, WRITE, EVERY=300\n*END STEP\n")


def plateau(x, y, a, b):
    """Mean of y over the middle 60 % of [a, b]."""
    lo, hi = a + 0.2 * (b - a), b - 0.2 * (b - a)
    sel = (x > lo) & (x < hi)
    return float(np.mean(y[sel]))


def crossing(x, y, level):
    """The first x at which y passes `level` (linear between samples)."""
    for i in range(len(x) - 1):
        if (y[i] - level) * (y[i + 1] - level) <= 0 and y[i] != y[i + 1]:
            return x[i] + (level - y[i]) * (x[i + 1] - x[i]) / (y[i + 1] - y[i])
    return float("nan")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("plastic_wave")
    c_e, c_p, dv, eps_hel, eps_fin, s_fin = closed_form()
    chk.close(s_fin, 31.266, 1e-4, "closed form: sigma_final = 31.266")
    path = os.path.join(args.work, "bar.inp")
    with open(path, "w") as f:
        f.write(deck())
    out = os.path.join(args.work, "bar.h5")
    _, log = vcheck.run_ictus(args, path, out)
    chk.true("internal force: element loop" in log, "J2 takes the element loop")
    res = vcheck.Results(out)
    last = res.field_steps()[-1]
    t = res.field_time(last)
    x0 = res.model("coordinates")
    on_axis = np.abs(x0[:, 1]) < 1e-12
    order = np.argsort(x0[on_axis, 0])
    x = x0[on_axis, 0][order]
    u = res.field(last, "displacement")[on_axis, 0][order]
    v = res.field(last, "velocity")[on_axis, 0][order]
    xe, xp = c_e * t, c_p * t
    h = LX / NX
    # velocities: at rest behind the plastic front, -v0 + dv in the precursor, -v0 ahead
    chk.below(abs(plateau(x, v, 0.0, xp)), 0.02 * V0, "at rest behind the plastic front")
    chk.close(plateau(x, v, xp, xe) + V0, dv, 0.02, "precursor velocity jump sigma_HEL/(rho c_e)")
    chk.close(plateau(x, v, xe, LX), -V0, 0.02, "ahead of the elastic front: -v0")
    # strains from the displacements (element midpoints)
    xm, eps = 0.5 * (x[1:] + x[:-1]), -np.diff(u) / np.diff(x)
    chk.close(plateau(xm, eps, 0.0, xp), eps_fin, 0.02,
              f"plastic plateau: strain {eps_fin:.5f} (sigma_final = {s_fin:.3f})")
    chk.close(plateau(xm, eps, xp, xe), eps_hel, 0.02,
              f"elastic precursor: strain eps_HEL = {eps_hel:.5f} (sigma_HEL = 8.75)")
    fe = crossing(x, v, -V0 + dv / 2)
    fp = crossing(x, v, (-V0 + dv) / 2)
    chk.below(abs(fe - xe), 2 * h, f"elastic front at {fe:.3f}, c_e t = {xe:.3f}")
    chk.below(abs(fp - xp), 2 * h, f"plastic front at {fp:.3f}, c_p t = {xp:.3f}")
    # the element stress output: sigma_xx on the plateaus, von Mises = sigma_y0 = 5 in the
    # precursor (at yield), equivalent plastic strain 0 there and > 0 behind the plastic front
    conn = res.model("elements/q4/connectivity")
    xc = x0[conn, 0].mean(axis=1)
    sxx = res.field(last, "stress")[:, 0]
    mises = res.field(last, "mises")
    peeq = res.field(last, "peeq")
    chk.close(-plateau(xc, sxx, 0.0, xp), s_fin, 0.02, "stress output: -sigma_xx = 31.266 behind "
              "the plastic front")
    chk.close(-plateau(xc, sxx, xp, xe), 8.75, 0.02, "stress output: -sigma_xx = sigma_HEL = 8.75 "
              "in the precursor")
    chk.close(plateau(xc, mises, xp, xe), SY, 0.02, "stress output: von Mises = sigma_y = 5 in the "
              "precursor")
    # behind the front: q = 3/2 (|sigma_xx| - K eps) (uniaxial strain), epbar = (q - 5)/100
    kb = E / (3 * (1 - 2 * NU))
    peeq_want = (1.5 * (s_fin - kb * eps_fin) - SY) / H
    chk.close(plateau(xc, peeq, 0.0, xp), peeq_want, 0.02,
              f"stress output: PEEQ = {peeq_want:.5f} behind the plastic front")
    chk.below(plateau(xc, peeq, xp, xe), 0.01 * peeq_want,
              "stress output: PEEQ ~ 0 in the precursor (the front's overshoot only)")
    kin = res.history("energy/kinetic")
    total = kin + res.history("energy/strain") + res.history("energy/plastic_work")
    chk.true(res.history("energy/plastic_work")[-1] > 0.1 * kin[0], "plastic work is done")
    chk.below(np.max(np.abs(total - kin[0])) / kin[0], 5e-3,
              "energy balance: kinetic + strain + plastic work = initial kinetic")
    chk.close(float(res.history("energy/total")[-1]), float(total[-1]), 1e-12,
              "the recorded total includes the plastic work")
    vcheck.check_ranks_and_restart(args, chk, path, out, ranks=(2, 3))
    chk.finish()


if __name__ == "__main__":
    main()
