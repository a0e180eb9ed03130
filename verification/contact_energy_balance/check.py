#!/usr/bin/env python3
"""The exact discrete energy balance of the predictor-corrector contact step (doc/theory.md
§4b) on a bar hitting a rigid wall, from the displacements alone.

A Q4 bar (10 x 1 elements of 0.1 x 0.1, plane stress nu = 0, E = 1000, rho = 1, lumped mass
rho A/4 per element node) moves at -1 towards the *RIGID WALL x = 0 from x = 0.002; penalty
eps = 1e5, dt = 2.5e-4 (r = dt^2 eps l/m = 0.125), through the contact and the rebound. Every
step is written. This script builds the stiffness K (2 x 2 Gauss), the lumped masses M and the
wall forces (2 Gauss points on the end face, traction eps gp n) itself, and from the
displacement fields u_n alone (v_{n+1/2} = (u_{n+1} - u_n)/dt) checks:

* the strain energy recorded at t_n is 1/2 u_n.K u_n (K of this script);
* the step: M (v_{n+1/2} - v_{n-1/2})/dt = -K u_n + F_c(u_pre), with the contact force of the
  predicted u_pre = u_n + dt (v_{n-1/2} - dt M^-1 K u_n), at every dof and step;
* the exact balance T_{n+1/2} + 1/2 u_{n+1}.K u_n - sum_{k<=n} 1/2 (u_{k+1} - u_{k-1}).F_c^k
  = T_{1/2} at every step (T_{n+1/2} = 1/2 v_{n+1/2}.M v_{n+1/2}), to round-off;
* the kinetic energy recorded at t_n is 1/2 v_n.M v_n with v_n = (u_{n+1} - u_{n-1})/(2 dt),
  the mean of the corrected half-step velocities, to round-off (with the predictor's
  v_{n+1/2} it differs by up to tens of per cent in the contact steps);
* outside_points stays 0 (a wall has no surface ends).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

NX, L, H, E, RHO, V0, GAP, EPS, DT = 10, 1.0, 0.1, 1000.0, 1.0, 1.0, 0.002, 1.0e5, 2.5e-4
T_END = 0.08


def deck():
    return ("*HEADING\nbar on a rigid wall: discrete energy balance\n"
            "*ANALYSIS, TYPE=PLANE STRESS\n" + vcheck.material_block(e=E, nu=0.0, rho=RHO)
            + vcheck.rect_mesh(type="Q4", nx=NX, ny=1, lx=L, ly=H, x0=GAP)
            + "*SURFACE, NAME=END, TYPE=ELEMENT\n1, S4\n"
            + f"*RIGID WALL, NAME=WALL, POINT=0,0, NORMAL=1,0, PENALTY={EPS!r}\nEND\n"
            + f"*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 1, {-V0!r}\n"
            + f"*STEP\n*DYNAMIC, EXPLICIT\n{DT!r}, {T_END!r}\n*OUTPUT, HISTORY, EVERY=1\n"
            + "*OUTPUT, FIELD, EVERY=1\n*END STEP\n")


def mesh():
    """Node coordinates (row by row, as scripts/mesh/rect.py numbers them) and Q4 elements."""
    h = L / NX
    x = np.array([[GAP + i * h, j * H] for j in range(2) for i in range(NX + 1)])
    conn = [(i, i + 1, i + NX + 2, i + NX + 1) for i in range(NX)]
    return x, conn


def stiffness(x, conn):
    """K of plane-stress Q4 elements, nu = 0, 2 x 2 Gauss, dofs (2 node, 2 node + 1)."""
    d = E * np.diag([1.0, 1.0, 0.5])
    k = np.zeros((2 * len(x), 2 * len(x)))
    g = 1.0 / np.sqrt(3.0)
    for el in conn:
        xe = x[list(el)]
        ke = np.zeros((8, 8))
        for xi in (-g, g):
            for eta in (-g, g):
                dn = 0.25 * np.array([[-(1 - eta), (1 - eta), (1 + eta), -(1 + eta)],
                                      [-(1 - xi), -(1 + xi), (1 + xi), (1 - xi)]])
                jac = dn @ xe
                dx = np.linalg.solve(jac, dn)
                b = np.zeros((3, 8))
                b[0, 0::2] = dx[0]
                b[1, 1::2] = dx[1]
                b[2, 0::2] = dx[1]
                b[2, 1::2] = dx[0]
                ke += b.T @ d @ b * np.linalg.det(jac)
        idx = np.array([[2 * n, 2 * n + 1] for n in el]).ravel()
        k[np.ix_(idx, idx)] += ke
    return k


def masses(x, conn):
    m = np.zeros(len(x))
    for el in conn:
        xe = x[list(el)]
        area = 0.5 * abs(np.cross(xe[2] - xe[0], xe[3] - xe[1]))
        m[list(el)] += RHO * area / 4.0
    return np.repeat(m, 2)


def wall_force(x, conn, u):
    """Penalty forces of the wall x = 0 on face S4 of element 1 (node 4 -> node 1)."""
    a, b = conn[0][3], conn[0][0]
    f = np.zeros(2 * len(x))
    xa, xb = x[a] + u[2 * a:2 * a + 2], x[b] + u[2 * b:2 * b + 2]
    jac = np.linalg.norm(x[b] - x[a])
    for t in (0.5 - 0.5 / np.sqrt(3.0), 0.5 + 0.5 / np.sqrt(3.0)):
        xq = (1 - t) * xa + t * xb
        gp = max(0.0, -xq[0])
        f[2 * a] += (1 - t) * 0.5 * jac * EPS * gp
        f[2 * b] += t * 0.5 * jac * EPS * gp
    return f


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("contact_energy_balance")
    path = os.path.join(args.work, "bar_wall.inp")
    with open(path, "w") as fd:
        fd.write(deck())
    out = path.replace(".inp", ".h5")
    vcheck.run_ictus(args, path, out)
    r = vcheck.Results(out)
    x, conn = mesh()
    chk.below(np.max(np.abs(r.model("coordinates")[:, :2] - x)), 1e-15,
              "the mesh numbering this script assumes")
    k, m = stiffness(x, conn), masses(x, conn)
    chk.below(np.max(np.abs(r.model("mass") - m[0::2])), 1e-15, "lumped masses rho A/4")
    steps = r.field_steps()
    u = np.array([r.field(s, "displacement")[:, :2].ravel() for s in steps])
    nt = len(u)
    chk.true(nt == len(r.history("time")) and nt > 300, f"{nt} steps, all written")
    e_kin, e_strain = r.history("energy/kinetic"), r.history("energy/strain")
    e0 = 0.5 * np.sum(m[0::2]) * V0 ** 2
    chk.close(e_kin[0], e0, 1e-12, "kinetic energy at t = 0: 1/2 m v0^2")
    strain = np.array([0.5 * u[n] @ k @ u[n] for n in range(nt)])
    chk.below(np.max(np.abs(strain - e_strain)) / e0, 1e-12, "recorded strain energy = "
              "1/2 u.K u (K of this script), relative to E0")
    vh = np.diff(u, axis=0) / DT                      # v_{n+1/2}, n = 0 .. nt-2
    v_start = np.tile([-V0, 0.0], len(x))             # v_{-1/2} = v_0 (a_0 = 0)
    vh = np.vstack([v_start, vh])                     # vh[n] = v_{n-1/2}
    res, bal, fmax, w = 0.0, [], 0.0, 0.0
    t_half0 = 0.5 * vh[1] @ (m * vh[1])
    ncontact = 0
    for n in range(0, nt - 1):
        ku = k @ u[n]
        v_pre = vh[n] - DT * ku / m
        fc = wall_force(x, conn, u[n] + DT * v_pre)
        ncontact += int(np.any(fc != 0.0))
        fmax = max(fmax, np.max(np.abs(fc)))
        res = max(res, np.max(np.abs(m * (vh[n + 1] - vh[n]) / DT + ku - fc)))
        if n >= 1:
            w += 0.5 * (u[n + 1] - u[n - 1]) @ fc
            bal.append(0.5 * vh[n + 1] @ (m * vh[n + 1]) + 0.5 * u[n + 1] @ ku - w - t_half0)
    chk.true(ncontact > 100, f"the bar is in contact for {ncontact} steps")
    chk.below(res / fmax, 1e-9, "M (v_{n+1/2} - v_{n-1/2})/dt = -K u_n + F_c(u_pre) at every "
              "dof and step, relative to the largest contact force")
    chk.below(np.max(np.abs(bal)) / e0, 1e-11, "exact discrete balance T_{n+1/2} + "
              "1/2 u_{n+1}.K u_n - W_contact = T_{1/2} at every step, relative to E0")
    kin = np.array([0.5 * ((vh[n] + vh[n + 1]) / 2) @ (m * (vh[n] + vh[n + 1]) / 2)
                    for n in range(nt - 1)])
    chk.below(np.max(np.abs(kin - e_kin[:nt - 1])) / e0, 1e-11, "recorded kinetic energy = "
              "1/2 v_n.M v_n, v_n the mean of the corrected v_{n-1/2}, v_{n+1/2}, relative to E0")
    chk.true(np.all(r.history("contact/wall/outside_points") == 0), "outside_points = 0")
    chk.finish()


if __name__ == "__main__":
    main()
