#!/usr/bin/env python3
"""Contact patch test (doc/reference.md §4): two stacked elastic blocks pressed together must
carry a uniform stress and a uniform contact pressure.

Lower block [0, W] x [0, H1], upper block [0, W] x [H1, H1 + H2], W = 1, H1 = H2 = 0.5,
plane strain, E = 1000, nu = 0.3, rho = 1, touching at y = H1, frictionless TWO HALF PASS
penalty eps = 1e4 (first surface: the lower block's top). Bottom on rollers (u_y = 0), its
left corner fixed in x; the upper block's top displaced by u_y = -delta (delta = 1e-3, a
constant *BOUNDARY value; there is no pressure card) with its left corner fixed in x (the
exact u_x = eps_xx x vanishes there, so both blocks expand alike and stay matching).

Exact static solution of the penalty problem: sigma_xx = 0 (free sides), sigma_yy = -p,
plane strain sigma_zz = nu sigma_yy, so eps_yy = -p (1 - nu^2)/E in both blocks; the penalty
interface closes by gp = p/eps. Compatibility: delta = p (H1 + H2)(1 - nu^2)/E + p/eps:
    p = delta / ((H1 + H2)(1 - nu^2)/E + 1/eps).
The static state of the predictor-corrector scheme (doc/theory.md §4) differs from it: at
rest v_{n-1/2} = v_{n+1/2} = 0, but v_pre = dt M^-1 f_int/(1 + h) (h = alpha dt/2) is not
zero at the interface nodes, whose internal force balances the contact force; contact is
evaluated on u_pre = u + dt v_pre, i.e. on a gap closed further by
dt^2 p (l_s/m_s + l_m/m_m)/(1 + h) = (r/eps) p/(1 + h). So
    p_pc = delta / ((H1 + H2)(1 - nu^2)/E + (1 - r/(1 + h))/eps),
    r = eps dt^2 (l_s/m_s + l_m/m_m) (the ratio the run prints),
uniform only when l_A/m_A is the same at every interface node: NURBS row sum
(l/m = 1/(rho int N_0 dy) = 6/(rho H1) for 2 spans) and Q8 with TYPE=ALPHA, ALPHA=1/5
(corner 1/20, midside 1/5 of the element mass: l/m = 10/(3 rho h_y)); Q8 HRZ (corner
6/(rho h_y), midside 3/(rho h_y)) gives a non-uniform pressure (printed as a regression
number: 2.5 %). The gates use p_pc (it tends to p as dt -> 0; +3.7 % here).
The static state is reached by dynamic relaxation: *DAMPING ALPHA = 2 omega_1 with omega_1 =
pi c'/(H1 + H2), c' = sqrt(E/((1 - nu^2) rho)), the fixed-fixed axial column mode (near
critical damping), run to t = 10 (the slowest modes then have decayed below 1e-12).

Matching meshes (Q8 4 x 2 on 4 x 2, ALPHA = 1/5; NURBS p = 2, 4 x 2 spans each, row sum):
every contact-point pressure and the resultant against p_pc to 1e-10 (relative).
Non-matching (Q8 4 x 2 below, 5 x 2 above): doc/reference.md §4 gates max |p_q - p|/p < 5 % and
resultant error < 1e-8; the measured values are printed as regression numbers.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402
import impact  # noqa: E402

W, H1, H2, NU, EPS, DELTA = 1.0, 0.5, 0.5, 0.3, 1.0e4, 1.0e-3
E, RHO = impact.E, impact.RHO
P = DELTA / ((H1 + H2) * (1 - NU ** 2) / E + 1 / EPS)
OMEGA1 = np.pi * np.sqrt(E / ((1 - NU ** 2) * RHO)) / (H1 + H2)
T_END = 10.0


def deck(kind, n_upper, q8_mass="ALPHA, ALPHA=0.2"):
    out = [impact.header(f"contact patch test, {kind}, 4 vs {n_upper}", "PLANE STRAIN", NU)]
    if kind == "Q8":
        lo, nxt, ne = impact.q8_bar("LO", 0.0, W, H1, 4, ny=2)
        up, _, _ = impact.q8_bar("UP", 0.0, W, H2, n_upper, first_node=nxt, first_element=ne,
                                 ny=2, y0=H1)
        pins = "LO_CORNER_LL, 1, 1\nUP_CORNER_UL, 1, 1\n"
        mass = q8_mass
    else:
        lo, nlo = impact.iga_block("LO", 0.0, 0.0, W, H1, 4, 2)
        up, _ = impact.iga_block("UP", 0.0, H1, W, H2, n_upper, 2)
        # control points: LO first (direction 1 fastest), then UP; pins at (0, 0), (0, H1 + H2)
        ul = nlo + (n_upper + 2) * (2 + 2 - 1) + 1
        pins = f"1, 1, 1\n{ul}, 1, 1\n"
        mass = "ROW SUM"
    out += [lo, up, "*BOUNDARY\nLO_BOTTOM, 2, 2\n", pins, f"UP_TOP, 2, 2, {-DELTA!r}\n",
            f"*CONTACT PAIR, NAME=PATCH, PENALTY={EPS!r}\nLO_TOP, UP_BOTTOM\n",
            f"*DAMPING, ALPHA={2 * OMEGA1!r}\n", f"*MASS, TYPE={mass}\n",
            impact.step(T_END, field_every=1000000)]
    return "".join(out)


def ell_over_m(kind, q8_mass):
    """l_A/m_A of every interface node (uniform along the side; both blocks alike)."""
    hy = H1 / 2
    if kind == "IGA":      # row sum: 1/(rho int N_0 dy), int N_0 = (H/2)/3
        return 6.0 / (RHO * H1)
    if q8_mass.startswith("ALPHA"):   # corner 1/20, midside 1/5 of rho h_x h_y
        return 10.0 / (3.0 * RHO * hy)
    return None            # HRZ: corner 6/(rho h_y), midside 3/(rho h_y): not uniform


def run(args, kind, n_upper, q8_mass="ALPHA, ALPHA=0.2"):
    tag = "hrz" if q8_mass == "HRZ" else ""
    path = os.path.join(args.work, f"patch_{kind}_{n_upper}{tag}.inp")
    with open(path, "w") as fd:
        fd.write(deck(kind, n_upper, q8_mass))
    out = path.replace(".inp", ".h5")
    _, log = vcheck.run_ictus(args, path, out)
    r = vcheck.Results(out)
    dt = float(r.history("dt")[0])
    lm = ell_over_m(kind, q8_mass)
    rr = EPS * dt ** 2 * 2 * lm if lm else impact.ratios(log)[0]
    h = OMEGA1 * dt            # alpha dt / 2 with alpha = 2 omega_1
    p_pc = DELTA / ((H1 + H2) * (1 - NU ** 2) / E + (1 - rr / (1 + h)) / EPS)
    steps = sorted(r.f["contact/patch"].keys())
    p = np.asarray(r.f[f"contact/patch/{steps[-1]}/pressure"])
    fy = float(r.history("contact/patch/force_first")[-1, 1])
    fy2 = float(r.history("contact/patch/force_second")[-1, 1])
    return p, fy, fy2, p_pc, rr, impact.ratios(log)[0]


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("contact_patch")
    print(f"  penalty-law contact pressure p = {P:.12g}")
    for kind in ("Q8", "IGA"):
        p, fy, fy2, pp, rr, r_log = run(args, kind, 4)
        print(f"  {kind}: r = eps dt^2 (l/m + l/m) = {rr:.6g} (printed {r_log:.4g}), static "
              f"state of the scheme p = {pp:.12g} ({pp / P - 1:+.4%} from the penalty law)")
        chk.close(r_log, rr, 1e-3, f"{kind}: printed r = eps dt^2 (l_s/m_s + l_m/m_m)")
        chk.below(float(np.max(np.abs(p - pp))) / pp, 1e-10,
                  f"{kind} matching: max |p_q - p|/p over {len(p)} contact points")
        chk.close(-fy, pp * W, 1e-10, f"{kind} matching: resultant on the lower block = p W")
        chk.close(fy2, pp * W, 1e-10, f"{kind} matching: resultant on the upper block = p W")
    p, fy, fy2, pp, rr, _ = run(args, "Q8", 4, "HRZ")
    print(f"  regression number, Q8 HRZ matching (l/m not uniform): max |p_q - p_mean|/p_mean = "
          f"{float(np.max(np.abs(p - p.mean())) / p.mean()):.6e}, resultant "
          f"{-fy:.12g}, balance |F_1 + F_2|/|F_1| = {abs(fy + fy2) / abs(fy):.3e}")
    p, fy, fy2, P_, rr, _ = run(args, "Q8", 5)
    dev = float(np.max(np.abs(p - P_))) / P_
    res = abs(-fy - P_ * W) / (P_ * W)
    bal = abs(fy + fy2) / (P_ * W)
    chk.below(dev, 0.05, "Q8 4 vs 5: max |p_q - p|/p (doc/reference.md §4 gate 5 %)")
    chk.below(res, 1e-8, "Q8 4 vs 5: resultant error |F - p W|/(p W) (gate 1e-8)")
    chk.below(bal, 1e-8, "Q8 4 vs 5: action = reaction |F_1 + F_2|/(p W)")
    print(f"  regression numbers, Q8 4 vs 5: max |p_q - p|/p = {dev:.6e}, resultant error "
          f"= {res:.6e}, |F_1 + F_2|/(p W) = {bal:.6e}")
    chk.finish()


if __name__ == "__main__":
    main()
