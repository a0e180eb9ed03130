#!/usr/bin/env python3
"""A pressure that follows the deformed surface (*DLOAD, P with *STEP, NLGEOM=YES;
doc/theory.md §4a).

A free unit block (2 x 2 Q8, plane strain, E = 1000, nu = 0.3, rho = 1) spins about its centre
at omega = 2 (turning by about 1 rad over the run) with the pressure p = 5 on its face x = 1
(element faces S2). The internal forces sum to zero, so the total momentum changes by the
pressure's resultant: P_{n+1/2} - P_{n-1/2} = h_n F_n with the velocity step
h_n = (dt_{n-1} + dt_n)/2 (the stable step follows the state under NLGEOM, doc/theory.md §7.1;
dt_n = /history/dt, the step from t_n), and with the mean velocities of the field output
(v_n = (v_{n-1/2} + v_{n+1/2})/2)

    P_{n+1} - P_n = (h_n F_n + h_{n+1} F_{n+1})/2,    F_n = -p (dy, -dx)

with (dx, dy) the current chord of the loaded face from its first to its last node (the integral
of n dGamma over a chain of segments depends only on its end points). Checked at every step to
1e-10 of p dt; the same relation with the reference chord fails by far (the face has turned), so
the load follows the body. In small strain (NLGEOM=NO, no spin) the resultant is the constant
-p (1, 0) on the reference face and P_n = F t_n exactly (1e-12).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

P, OMEGA = 5.0, 2.0


def deck(nlgeom):
    mesh = vcheck.rect_mesh(type="Q8", nx=2, ny=2, lx=1.0, ly=1.0)
    nodes = [line.split(",") for line in mesh.split("*ELEMENT")[0].splitlines()[1:]]
    ic = ""
    if nlgeom:
        ic = "*INITIAL CONDITIONS, TYPE=VELOCITY\n"
        for n in nodes:
            i, x, y = int(n[0]), float(n[1]), float(n[2])
            ic += f"{i}, 1, {-OMEGA * (y - 0.5)!r}\n{i}, 2, {OMEGA * (x - 0.5)!r}\n"
    step = "*STEP, NLGEOM=YES\n" if nlgeom else "*STEP\n"
    return ("*HEADING\nfollower pressure on a spinning block\n"
            "*ANALYSIS, TYPE=PLANE STRAIN, THICKNESS=1\n"
            + vcheck.material_block(e=1000.0, nu=0.3, rho=1.0) + mesh
            + "*SURFACE, NAME=FACE, TYPE=ELEMENT\n2, S2\n4, S2\n" + ic
            + step + "*DYNAMIC, EXPLICIT\n0, 0.5\n*DLOAD\nFACE, P, 5.0\n"
            "*OUTPUT, HISTORY, EVERY=1\n*OUTPUT, FIELD, EVERY=1\n*END STEP\n")


def run(args, name, nlgeom):
    path = os.path.join(args.work, f"{name}.inp")
    with open(path, "w") as f:
        f.write(deck(nlgeom))
    out = os.path.join(args.work, f"{name}.h5")
    vcheck.run_ictus(args, path, out)
    res = vcheck.Results(out)
    m = res.model("mass")
    x0 = res.model("coordinates")
    a = int(np.nonzero((np.abs(x0[:, 0] - 1) < 1e-12) & (np.abs(x0[:, 1]) < 1e-12))[0][0])
    b = int(np.nonzero((np.abs(x0[:, 0] - 1) < 1e-12) & (np.abs(x0[:, 1] - 1) < 1e-12))[0][0])
    steps = res.field_steps()
    t = np.array([res.field_time(s) for s in steps])
    dt = res.history("dt")
    assert np.array_equal(res.history("time"), t)
    h = 0.5 * (np.concatenate([dt[:1], dt[:-1]]) + dt)
    mom = np.array([m @ res.field(s, "velocity") for s in steps])
    x = np.array([x0 + res.field(s, "displacement") for s in steps])
    return t, h, mom, x, a, b


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("loads_follower")
    t, h, mom, x, a, b = run(args, "spin", True)
    d = x[:, b] - x[:, a]
    f = -P * np.stack([d[:, 1], -d[:, 0]], axis=1)
    hf = h[:, None] * f
    err = np.max(np.abs(np.diff(mom, axis=0) - 0.5 * (hf[1:] + hf[:-1]))) / (P * h.max())
    chk.below(float(err), 1e-10, "NLGEOM: momentum changes by the pressure on the current face")
    f0 = np.tile([-P, 0.0], (len(t), 1))
    hf0 = h[:, None] * f0
    err0 = np.max(np.abs(np.diff(mom, axis=0) - 0.5 * (hf0[1:] + hf0[:-1]))) / (P * h.max())
    chk.true(err0 > 0.3, f"... and not by the pressure on the reference face ({err0:.3g})")
    turn = np.arctan2(d[-1, 1], d[-1, 0]) - np.pi / 2
    chk.true(abs(turn) > 0.5, f"the face has turned by {turn:.3f} rad")
    t, _, mom, x, a, b = run(args, "fixed", False)
    err = np.max(np.abs(mom - np.outer(t, [-P, 0.0]))) / (P * t[-1])
    chk.below(float(err), 1e-12, "small strain: P(t_n) = -p (1, 0) t_n on the reference face")
    chk.finish()


if __name__ == "__main__":
    main()
