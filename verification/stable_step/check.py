#!/usr/bin/env python3
"""The stable step follows the state under finite strain (doc/theory.md §7.1).

A free plane-strain square [-0.5, 0.5]^2 of 4 x 4 Q4 elements (distorted mesh, HRZ mass,
rho = 1) with NLGEOM=YES is crushed by the converging initial velocity v = -20 x (it would
reach zero size at t = 0.05), once as St. Venant-Kirchhoff (E = 1, nu = 0.3) and once as a
neo-Hookean (C10 = 0.2, D1 = 2). The deck gives dt0 = 1e-4. Expected, re-derived here from the
displacement fields (one every 50 steps; the step is estimated every 10):
- at every 2 x 2 Gauss point the factor s = sigma_min(F) / (c/c0) with the law's wave ratio
  c/c0 = sqrt(J M / M0): SVK M = M0 lam_max(b)^2/J + |sigma|, M0 = lambda + 2 mu; neo-Hooke
  M = K + 4/3 mu J^(-5/3) lam_max(b) + |sigma|, M0 = K + 4/3 mu (|sigma| the Frobenius norm of
  the Cauchy stress, written out here from the laws' closed forms), and the step recorded in
  /history/dt is dt0 min(1, min s) to 1e-9;
- the step falls by a factor of about 1000 on the way, and the run stops with exit 2 when it
  falls below dt0/1000, naming the element, with the results so far readable;
- with the step following the collapse the total energy stays at its start to 1e-4 while
  dt > dt0/100 (a fixed dt0 would have inverted the elements long before);
- with `*OUTPUT, FIELD, TIME INTERVAL=0.004` while the step changes, there is one snapshot per
  multiple k 0.004 reached, at the step time closest to it (from the step times of a history
  of every step) (the run fails before its end, so there is no end-of-run snapshot);
- the SVK run is bit-identical on 2 ranks, and continued on 2 ranks from a checkpoint of the
  1-rank run (the step and the one before it travel in the checkpoint).
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

DT0 = 1e-4
GP = [(-1 / np.sqrt(3), -1 / np.sqrt(3)), (1 / np.sqrt(3), -1 / np.sqrt(3)),
      (1 / np.sqrt(3), 1 / np.sqrt(3)), (-1 / np.sqrt(3), 1 / np.sqrt(3))]
LAWS = {
    "SVK": "*ELASTIC\n1.0, 0.3\n",
    "neo-Hooke": "*HYPERELASTIC, NEO HOOKE\n0.2, 2.0\n",
}


def deck(law, restart=False, interval=None):
    mesh = vcheck.rect_mesh(type="Q4", nx=4, ny=4, lx=1.0, ly=1.0, x0=-0.5, y0=-0.5,
                            distort=0.15)
    ic = ["*INITIAL CONDITIONS, TYPE=VELOCITY"]
    for i, x, y in vcheck.mesh_points(mesh):
        ic += [f"{i}, 1, {-20.0 * x!r}", f"{i}, 2, {-20.0 * y!r}"]
    return (f"*HEADING\ncrushed square, {law}\n*MATERIAL, NAME=MAT\n{LAWS[law]}*DENSITY\n1.0\n"
            + mesh + "\n".join(ic) + "\n*MASS, TYPE=HRZ\n*STEP, NLGEOM=YES\n"
            f"*DYNAMIC, EXPLICIT\n{DT0}, 0.1\n"
            + ("*OUTPUT, HISTORY, EVERY=10\n*OUTPUT, FIELD, EVERY=50\n" if interval is None else
               f"*OUTPUT, HISTORY, EVERY=1\n*OUTPUT, FIELD, TIME INTERVAL={interval}\n")
            + ("*RESTART, WRITE, EVERY=1000\n" if restart else "") + "*END STEP\n")


def cauchy(law, f):
    """The Cauchy stress of the law at the 3 x 3 deformation gradient f."""
    j = np.linalg.det(f)
    if law == "SVK":
        e, nu = 1.0, 0.3
        lam, mu = e * nu / ((1 + nu) * (1 - 2 * nu)), e / (2 * (1 + nu))
        green = 0.5 * (f.T @ f - np.eye(3))
        s = lam * np.trace(green) * np.eye(3) + 2 * mu * green
        return f @ s @ f.T / j
    c10, d1 = 0.2, 2.0
    bbar = j ** (-2 / 3) * f @ f.T
    return 2 * c10 / j * (bbar - np.trace(bbar) / 3 * np.eye(3)) + 2 / d1 * (j - 1) * np.eye(3)


def wave_ratio(law, f):
    j = np.linalg.det(f)
    lmax = np.linalg.eigvalsh(f @ f.T).max()
    sig = np.linalg.norm(cauchy(law, f))
    if law == "SVK":
        e, nu = 1.0, 0.3
        m0 = e * (1 - nu) / ((1 + nu) * (1 - 2 * nu))
        m = m0 * lmax ** 2 / j + sig
    else:
        mu, k = 0.4, 1.0
        m0 = k + 4 * mu / 3
        m = k + 4 * mu / 3 * j ** (-5 / 3) * lmax + sig
    return np.sqrt(j * m / m0)


def factor(law, x0, u, conn):
    """The smallest s = sigma_min(F) / (c/c0) over the Gauss points of the Q4 elements."""
    smin = np.inf
    for el in conn:
        xe, ue = x0[el], u[el]
        for xi, eta in GP:
            dn = 0.25 * np.array([[-(1 - eta), (1 - eta), (1 + eta), -(1 + eta)],
                                  [-(1 - xi), -(1 + xi), (1 + xi), (1 - xi)]])
            jac = dn @ xe
            dx = np.linalg.solve(jac, dn)
            f = np.eye(3)
            f[:2, :2] += (dx @ ue).T
            smin = min(smin, np.sqrt(np.linalg.eigvalsh(f.T @ f).min()) / wave_ratio(law, f))
    return smin


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("stable_step")
    for law in LAWS:
        path = os.path.join(args.work, f"crush_{law}.inp")
        with open(path, "w") as fh:
            fh.write(deck(law))
        out = os.path.join(args.work, f"crush_{law}.h5")
        _, log = vcheck.run_ictus(args, path, out, expect_status=2)
        chk.true(re.search(r"stable time step fell to \S+, below 1/1000 of the start-up step "
                           r"\S+, at Q4 element \d+", log) is not None,
                 f"{law}: exit 2 when dt falls below dt0/1000, naming the element")
        res = vcheck.Results(out)
        chk.true(res.attr("status").startswith("failed"), f"{law}: results readable, status failed")
        x0 = res.model("coordinates")[:, :2]
        conn = res.model("elements/q4/connectivity")
        t, dt = res.history("time"), res.history("dt")
        etot = res.history("energy/total")
        worst, nchecked = 0.0, 0
        for name in res.field_steps():
            k = int(np.argmin(abs(t - res.field_time(name))))
            u = res.field(name, "displacement")[:, :2]
            want = DT0 * min(1.0, factor(law, x0, u, conn))
            worst = max(worst, abs(dt[k] - want) / want)
            nchecked += 1
        chk.below(worst, 1e-9, f"{law}: /history/dt = dt0 min(1, min s) at all {nchecked} "
                  "snapshots")
        chk.below(dt.min() / DT0, 2e-3, f"{law}: the step fell by a factor of about 1000")
        keep = dt > DT0 / 100
        drift = abs(etot[keep] - etot[0]).max() / abs(etot[0])
        chk.below(drift, 1e-4, f"{law}: energy kept while dt > dt0/100 (t up to "
                  f"{t[keep].max():.5f} of 0.05)")
    check_interval(args, chk)
    check_bits(args, chk)
    chk.finish()


def check_interval(args, chk):
    path = os.path.join(args.work, "crush_interval.inp")
    with open(path, "w") as fh:
        fh.write(deck("SVK", interval=0.004))
    out = os.path.join(args.work, "crush_interval.h5")
    vcheck.run_ictus(args, path, out, expect_status=2)
    res = vcheck.Results(out)
    t = res.history("time")
    got = sorted(res.field_time(n) for n in res.field_steps())
    want = {float(t[np.argmin(abs(t - k * 0.004))]) for k in range(int(t[-1] / 0.004) + 1)}
    chk.true(got == sorted(want), f"TIME INTERVAL=0.004 with a changing step: {len(got)} "
             "snapshots, each at the step time closest to its multiple")


def check_bits(args, chk):
    path = os.path.join(args.work, "crush_bits.inp")
    with open(path, "w") as fh:
        fh.write(deck("SVK", restart=True))
    out = os.path.join(args.work, "crush_bits.h5")
    vcheck.run_ictus(args, path, out, expect_status=2)
    vcheck.check_ranks_and_restart(args, chk, path, out, expect_status=2, label="SVK: ")


if __name__ == "__main__":
    main()
