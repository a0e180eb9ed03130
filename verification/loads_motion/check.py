#!/usr/bin/env python3
"""Prescribed motion (*BOUNDARY with AMPLITUDE= and TYPE=, doc/theory.md §4a).

A bar (length 10, height 1, 20 x 1 Q4, plane stress, nu = 0, E = 1000, rho = 1) at dt = 1e-3:
- its end x = 0 moves with the velocity v(t) = 2 A_v(t) in x (TYPE=VELOCITY, a TABULAR
  amplitude with points at multiples of dt: 0 at t = 0, 1 at 0.01 and 0.03, -0.5 at 0.05,
  0 from 0.08 on). The step sets v_{n+1/2} = v_p(t_{n+1/2}), the midpoint rule, exact for a
  velocity linear between steps: the displacement of the end equals the integral
  2 int_0^t A_v, computed here in closed form, to round-off (1e-12 of its largest value);
- its end x = 10 follows u(t) = 0.01 A_u(t) in x (TYPE=DISPLACEMENT, TABULAR
  0, 0 / 0.04, 1 / 0.1, -1): u_{n+1} = u_p(t_{n+1}) exactly, checked at every step to 1e-15 of
  the amplitude;
- energy balance: the work of the reactions of the moving ends enters the external work, so
  kinetic + strain - external work stays at 0 within 1 % of the largest energy;
- both ends' y dofs are free; the reaction field is non-zero only on the x dofs of the ends.
The same run on 2 ranks gives the same bits, and so does the run continued on 2 ranks from a
checkpoint of the 1-rank run (the prescribed dofs' velocities and the power of the last step
are part of it) and the run of the processed deck (the echo of the cards).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

DT, T_END = 1e-3, 0.12
AV = [(0.0, 0.0), (0.01, 1.0), (0.03, 1.0), (0.05, -0.5), (0.08, 0.0)]
AU = [(0.0, 0.0), (0.04, 1.0), (0.1, -1.0)]


def table(pts):
    return "\n".join(f"{t!r}, {a!r}" for t, a in pts) + "\n"


def deck():
    return ("*HEADING\nprescribed velocity and displacement histories\n"
            "*ANALYSIS, TYPE=PLANE STRESS, THICKNESS=1\n"
            + vcheck.material_block(e=1000.0, nu=0.0, rho=1.0)
            + vcheck.rect_mesh(type="Q4", nx=20, ny=1, lx=10.0, ly=1.0)
            + "*AMPLITUDE, NAME=AV\n" + table(AV)
            + "*AMPLITUDE, NAME=AU, DEFINITION=TABULAR\n" + table(AU)
            + f"*STEP\n*DYNAMIC, EXPLICIT\n{DT!r}, {T_END!r}\n"
            "*BOUNDARY, AMPLITUDE=AV, TYPE=VELOCITY\nLEFT, 1, 1, 2.0\n"
            "*BOUNDARY, AMPLITUDE=AU, TYPE=DISPLACEMENT\nRIGHT, 1, 1, 0.01\n"
            "*OUTPUT, HISTORY, EVERY=1\n*OUTPUT, FIELD, EVERY=1, VARIABLES=U,V,S,MISES,RF\n*RESTART, WRITE, EVERY=50\n"
            "*END STEP\n")


def amp(pts, t):
    """The TABULAR amplitude, as the code evaluates it."""
    if t <= pts[0][0]:
        return pts[0][1]
    if t >= pts[-1][0]:
        return pts[-1][1]
    for (t0, a0), (t1, a1) in zip(pts[:-1], pts[1:]):
        if t0 <= t < t1:
            return a0 + (a1 - a0) * ((t - t0) / (t1 - t0))


def integral(pts, t):
    """int_0^t of the TABULAR amplitude (piecewise linear, constant after the last point)."""
    s = 0.0
    for (t0, a0), (t1, a1) in zip(pts[:-1], pts[1:]):
        if t <= t0:
            break
        te = min(t, t1)
        s += (te - t0) * (a0 + 0.5 * (a1 - a0) * (te - t0) / (t1 - t0))
    if t > pts[-1][0]:
        s += (t - pts[-1][0]) * pts[-1][1]
    return s


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("loads_motion")
    path = os.path.join(args.work, "motion.inp")
    with open(path, "w") as f:
        f.write(deck())
    out = os.path.join(args.work, "motion.h5")
    vcheck.run_ictus(args, path, out)
    res = vcheck.Results(out)
    x0 = res.model("coordinates")
    left = np.abs(x0[:, 0]) < 1e-12
    right = np.abs(x0[:, 0] - 10.0) < 1e-12
    ev, eu = 0.0, 0.0
    ul_max = max(abs(2.0 * integral(AV, t)) for t in np.linspace(0, T_END, 500))
    for s in res.field_steps():
        t = res.field_time(s)
        u = res.field(s, "displacement")
        ev = max(ev, float(np.max(np.abs(u[left, 0] - 2.0 * integral(AV, t)))))
        eu = max(eu, float(np.max(np.abs(u[right, 0] - 0.01 * amp(AU, t)))))
    chk.below(ev / ul_max, 1e-12, "TYPE=VELOCITY: u(t_n) = 2 int_0^t_n A_v at every step")
    chk.below(eu / 0.01, 1e-15, "TYPE=DISPLACEMENT: u(t_n) = 0.01 A_u(t_n) at every step")
    last = res.field_steps()[-1]
    chk.close(float(res.field(last, "displacement")[left, 0][0]), 2.0 * integral(AV, T_END),
              1e-12, "end displacement of the moving end")
    kin, strain = res.history("energy/kinetic"), res.history("energy/strain")
    total = res.history("energy/total")
    emax = float(np.max(kin + strain))
    chk.true(emax > 0.1, f"the motion puts energy into the bar ({emax:.4g})")
    chk.below(float(np.max(np.abs(total - total[0]))) / emax, 0.01,
              "kinetic + strain - external work (with the reactions' work) constant")
    r = np.array([res.field(s, "reaction") for s in res.field_steps()])
    ends = left | right
    chk.true(not np.any(r[:, ~ends, :]) and not np.any(r[:, :, 1]),
             "reactions only on the prescribed x dofs")
    chk.true(np.any(r[:, left, 0]) and np.any(r[:, right, 0]), "the moving ends take reactions")
    vcheck.check_ranks_and_restart(args, chk, path, out)
    chk.true(vcheck.processed_deck_reruns(args, out), "the processed deck reruns bit for bit")
    chk.finish()


if __name__ == "__main__":
    main()
