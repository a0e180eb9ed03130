#!/usr/bin/env python3
"""MORTAR contact (doc/contact.md §4) on non-matching meshes and on the dynamic Hertz problem.

1. Contact patch test on non-matching meshes (doc/reference.md §4; the set-up of
   verification/contact_patch): lower block [0, W] x [0, H1] (first surface: its top, the
   slave), upper block [0, W] x [H1, H1 + H2], W = 1, H1 = H2 = 0.5, 2 rows each, plane strain,
   E = 1000, nu = 0.3, rho = 1, penalty eps = 1e4; rollers under the lower block, the left
   sides held in x (the exact u_x = eps_xx x vanishes there), the upper block's top displaced
   by -delta, dynamic relaxation to t = 10. Exact static state of the predictor-corrector
   penalty (contact_patch/check.py derives it):
       p_pc = delta / ((H1 + H2)(1 - nu^2)/E + (1 - r/(1 + h))/eps),
       r = eps dt^2 (l_s/m_s + l_m/m_m), h = alpha dt/2,
   with l/m uniform along each side: Q8 with TYPE=ALPHA, ALPHA=1/5 (10/(3 rho h_y)) and NURBS
   row sum (6/(rho H)). Meshes along the interface, lower vs upper: 8 vs 11 (1:1.375) and
   10 vs 21 (1:2.1), Q8 against Q8, NURBS against NURBS, Q8 against NURBS and NURBS against
   Q8. Gates: the pressure of every slave node and both resultants against p_pc and p_pc W
   to 1e-8; action = reaction to 1e-12.
   The other algorithms on Q8 8 vs 11: NODE TO SEGMENT fails the test (its master loads are
   the slave loads interpolated at the closest points, not the consistent loads: the
   pressures spread by more than 1 %); TWO HALF PASS passes it (each half-pass loads its own
   surface consistently; what it lacks is action = reaction on curved non-matching
   interfaces, part 2).
2. Momentum on non-matching meshes: the dynamic Hertz problem (scripts/mesh/hertz.py; NURBS
   p = 2, HRZ, V_rel = 4) with 8 x 8 spans above and 11 x 11 below, dt = 4e-4 (r = 0.82):
   under MORTAR force_first = -force_second at every record to 1e-13 of the largest force,
   and the total y momentum at the end equals the initial one to 1e-12 m V. The same deck
   with TWO HALF PASS is printed beside it (its forces differ by 17 % of the peak).
   MORTAR is bit-identical on 2 and 3 ranks and across a restart on 2 ranks.
3. The dynamic Hertz benchmark under MORTAR at the paper's settings (8 x 8, dt = 5e-4): IGA
   HRZ, IGA consistent and Q8 HRZ. F_max and t_c within 2 % of the converged values of the
   Hertz verification (doc/verification.md §5: F_max = 218, t_c = 0.762, from the refinement
   series of both discretisations); energy never above its start value by more than 1e-9
   and its loss below 2 %; the pressure oscillation index OI is printed beside TWO HALF
   PASS's on the same decks.
"""
import os
import re
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "common"))
sys.path.insert(0, os.path.join(HERE, "..", "hertz"))
sys.path.insert(0, os.path.join(HERE, "..", "..", "scripts", "mesh"))
import vcheck  # noqa: E402
import impact  # noqa: E402
import hertz  # noqa: E402
import hertz_compare  # noqa: E402

W, H1, H2, NU, EPS, DELTA = 1.0, 0.5, 0.5, 0.3, 1.0e4, 1.0e-3
E, RHO = impact.E, impact.RHO
OMEGA1 = np.pi * np.sqrt(E / ((1 - NU ** 2) * RHO)) / (H1 + H2)
T_END = 10.0
F_CONVERGED, TC_CONVERGED = 218.0, 0.762
LB, HB, V0 = 1.0, 0.1, 1.0          # the tied bar: half length, height, speed


def block(kind, name, y0, n, first_node, first_element):
    """One block of 2 rows; returns its cards, next node id, next element id, *MASS card."""
    if kind == "Q8":
        cards, nxt, ne = impact.q8_bar(name, 0.0, W, H1, n, first_node=first_node,
                                       first_element=first_element, ny=2, y0=y0)
        return cards, nxt, ne, f"*MASS, TYPE=ALPHA, ALPHA=0.2, ELSET={name}\n"
    cards, _ = impact.iga_block(name, 0.0, y0, W, H1, n, 2)
    return cards, first_node, first_element, f"*MASS, TYPE=ROW SUM, PATCH={name}\n"


def patch_deck(lo, n_lo, up, n_up, algorithm):
    """The patch test deck; algorithm "TIE": the blocks glued by *TIE (automatic penalty)
    and pulled apart (the top moved up by delta)."""
    out = [impact.header(f"mortar patch test, {lo} {n_lo} vs {up} {n_up}, {algorithm}",
                         "PLANE STRAIN", NU)]
    c1, nxt, ne, m1 = block(lo, "LO", 0.0, n_lo, 1, 1)
    c2, _, _, m2 = block(up, "UP", H1, n_up, nxt, ne)
    tie = algorithm == "TIE"
    out += [c1, c2, "*BOUNDARY\nLO_BOTTOM, 2, 2\nLO_LEFT, 1, 1\nUP_LEFT, 1, 1\n",
            f"UP_TOP, 2, 2, {(DELTA if tie else -DELTA)!r}\n",
            "*TIE, NAME=PATCH\n" if tie else
            f"*CONTACT PAIR, NAME=PATCH, PENALTY={EPS!r}, ALGORITHM={algorithm}\n",
            "LO_TOP, UP_BOTTOM\n",
            f"*DAMPING, ALPHA={2 * OMEGA1!r}\n", m1, m2, impact.step(T_END, field_every=1000000)]
    return "".join(out)


def ell_over_m(kind):
    """l_A/m_A of every interface node of a block of 2 rows of height H1/2."""
    return 6.0 / (RHO * H1) if kind == "IGA" else 10.0 / (3.0 * RHO * (H1 / 2))


def patch_run(args, chk, lo, n_lo, up, n_up, algorithm):
    tag = algorithm.replace(" ", "").lower()
    path = os.path.join(args.work, f"patch_{lo}{n_lo}_{up}{n_up}_{tag}.inp")
    with open(path, "w") as fd:
        fd.write(patch_deck(lo, n_lo, up, n_up, algorithm))
    out = path.replace(".inp", ".h5")
    _, log = vcheck.run_ictus(args, path, out)
    r = vcheck.Results(out)
    dt = float(r.history("dt")[0])
    eps = EPS
    if algorithm == "TIE":
        # the automatic tie penalty: contact ratio 0.9 at dt (doc/contact.md §4b)
        eps = 0.9 / (dt ** 2 * (ell_over_m(lo) + ell_over_m(up)))
        logged = float(re.search(r"tie patch: penalty (\S+)", log).group(1))
        chk.close(logged, eps, 1e-5, f"tie {lo} {n_lo} vs {up} {n_up}: the automatic penalty "
                  "puts r = 0.9 at dt")
    rr = eps * dt ** 2 * (ell_over_m(lo) + ell_over_m(up))
    p_pc = DELTA / ((H1 + H2) * (1 - NU ** 2) / E + (1 - rr / (1 + OMEGA1 * dt)) / eps)
    steps = sorted(r.f["contact/patch"].keys())
    p = np.asarray(r.f[f"contact/patch/{steps[-1]}/pressure"])
    f1 = float(r.history("contact/patch/force_first")[-1, 1])
    f2 = float(r.history("contact/patch/force_second")[-1, 1])
    return p, f1, f2, p_pc


def patch_tests(args, chk):
    for lo, n_lo, up, n_up in (("Q8", 8, "Q8", 11), ("Q8", 10, "Q8", 21), ("IGA", 8, "IGA", 11),
                               ("IGA", 10, "IGA", 21), ("Q8", 8, "IGA", 11),
                               ("IGA", 10, "Q8", 21)):
        label = f"patch test, MORTAR, {lo} {n_lo} vs {up} {n_up}"
        p, f1, f2, pp = patch_run(args, chk, lo, n_lo, up, n_up, "MORTAR")
        chk.below(float(np.max(np.abs(p - pp))) / pp, 1e-8,
                  f"{label}: max |p_A - p_pc|/p_pc over {len(p)} slave nodes")
        chk.close(-f1, pp * W, 1e-8, f"{label}: resultant on the lower block = p_pc W")
        chk.close(f2, pp * W, 1e-8, f"{label}: resultant on the upper block = p_pc W")
        chk.below(abs(f1 + f2) / (pp * W), 1e-12, f"{label}: action = reaction")
    for lo, n_lo, up, n_up in (("Q8", 8, "IGA", 11), ("IGA", 10, "Q8", 21)):
        label = f"tie patch test (tension), {lo} {n_lo} vs {up} {n_up}"
        p, f1, f2, pp = patch_run(args, chk, lo, n_lo, up, n_up, "TIE")
        out = os.path.join(args.work, f"patch_{lo}{n_lo}_{up}{n_up}_tie.h5")
        chk.true(vcheck.processed_deck_reruns(args, out),
                 f"{label}: the processed deck (*TIE) reruns bit for bit")
        chk.below(float(np.max(np.abs(p - pp))) / pp, 1e-8,
                  f"{label}: max ||P_A| - p_pc|/p_pc over {len(p)} slave nodes")
        chk.close(f1, pp * W, 1e-8, f"{label}: the lower block pulled up by p_pc W")
        chk.close(-f2, pp * W, 1e-8, f"{label}: the upper block pulled down by p_pc W")
    p, f1, f2, pp = patch_run(args, chk, "Q8", 8, "Q8", 11, "NODE TO SEGMENT")
    dev = float(np.max(np.abs(p[p > 0] - pp))) / pp
    print(f"  NODE TO SEGMENT, Q8 8 vs 11: max |p_A - p_pc|/p_pc over the nodes in contact = "
          f"{dev:.4e} ({np.count_nonzero(p == 0)} of {len(p)} nodes without pressure), "
          f"|F_1 + F_2|/(p W) = {abs(f1 + f2) / (pp * W):.2e}")
    chk.true(dev > 0.01, f"patch test, NODE TO SEGMENT, Q8 8 vs 11: fails (pressure spread "
             f"{dev:.3f} > 1 %)")
    p, f1, f2, pp = patch_run(args, chk, "Q8", 8, "Q8", 11, "TWO HALF PASS")
    dev = float(np.max(np.abs(p - pp))) / pp
    print(f"  TWO HALF PASS, Q8 8 vs 11: max |p_q - p_pc|/p_pc = {dev:.4e}, "
          f"|F_1 + F_2|/(p W) = {abs(f1 + f2) / (pp * W):.2e}")
    chk.below(dev, 1e-8, "patch test, TWO HALF PASS, Q8 8 vs 11: passes (flat interface)")


def hertz_deck(args, name, restart=False, **kw):
    a = hertz.options(**kw)
    hertz.check_options(a)
    text = hertz.deck(a, "verification/contact_mortar " + name)
    if restart:
        text = text.replace("*END STEP", "*RESTART, WRITE, EVERY=1000\n*END STEP")
    path = os.path.join(args.work, name + ".inp")
    with open(path, "w") as fd:
        fd.write(text)
    return path


def momentum(args, chk):
    res = {}
    for alg in ("MORTAR", "TWO HALF PASS"):
        name = "hertz_8_11_" + alg.replace(" ", "").lower()
        path = hertz_deck(args, name, kind="iga", subdivide=8, lower=11, mass="HRZ", dt=4e-4,
                          algorithm=alg, field_every=450, restart=alg == "MORTAR")
        out = path.replace(".inp", ".h5")
        vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        f1 = r.history("contact/hertz/force_first")
        f2 = r.history("contact/hertz/force_second")
        a = hertz_compare.analyse(out, 4.0)
        bal = float(np.max(np.abs(f1 + f2))) / float(np.max(np.abs(f1)))
        res[alg] = (bal, a["momentum_err"], a["f_max"])
        print(f"  Hertz 8 x 8 against 11 x 11, {alg}: max |F_1 + F_2| / max |F_1| = {bal:.3e}, "
              f"momentum change {a['momentum_err']:.2e} m V, F_max {a['f_max']:.2f}")
        if alg == "MORTAR":
            chk.below(bal, 1e-13, "Hertz 8 vs 11, MORTAR: force_first = -force_second at every "
                      "record")
            chk.below(a["momentum_err"], 1e-12, "Hertz 8 vs 11, MORTAR: total y momentum kept")
            vcheck.check_ranks_and_restart(args, chk, path, out, ranks=(2, 3),
                                           label="Hertz 8 vs 11, MORTAR: ")
            chk.true(vcheck.processed_deck_reruns(args, out),
                     "Hertz 8 vs 11, MORTAR: the processed deck reruns bit for bit")
    chk.true(res["TWO HALF PASS"][0] > 0.05, "Hertz 8 vs 11, TWO HALF PASS: the two forces "
             f"differ ({res['TWO HALF PASS'][0]:.3f} of the peak; what MORTAR removes)")


def hertz_benchmark(args, chk):
    rows = []
    for kind, mass in (("iga", "HRZ"), ("iga", "CONSISTENT"), ("q8", "HRZ")):
        oi = {}
        for alg in ("MORTAR", "TWO HALF PASS"):
            name = f"hertz_{kind}_{mass.lower()}_" + alg.replace(" ", "").lower()
            size = dict(n=8) if kind == "q8" else dict(subdivide=8)
            path = hertz_deck(args, name, kind=kind, mass=mass, dt=5e-4, algorithm=alg,
                              field_every=450, **size)
            out = path.replace(".inp", ".h5")
            vcheck.run_ictus(args, path, out)
            a = hertz_compare.analyse(out, 4.0)
            oi[alg] = a["oi"]
            if alg != "MORTAR":
                continue
            label = f"Hertz, MORTAR, {kind.upper()} {mass}"
            chk.close(a["f_max"], F_CONVERGED, 0.02, f"{label}: F_max against the converged 218")
            chk.close(a["t_c"], TC_CONVERGED, 0.02, f"{label}: t_c against the converged 0.762")
            e = vcheck.Results(out).history("energy/total")
            chk.below(float(np.max(e) - e[0]) / e[0], 1e-9, f"{label}: energy never rises")
            chk.below(a["energy_loss"], 0.02, f"{label}: energy loss")
            chk.below(a["momentum_err"], 1e-12, f"{label}: y momentum kept")
            rows.append((kind.upper(), mass, a["f_max"], a["t_c"], a["energy_loss"]))
        rows[-1] += (oi["MORTAR"], oi["TWO HALF PASS"])
    print("  | mesh | mass | F_max | t_c | energy loss | OI MORTAR | OI TWO HALF PASS |")
    for k, m, f, t, el, o1, o2 in rows:
        print(f"  | {k} 8x8 | {m} | {f:.2f} | {t:.4f} | {el:.4f} | {o1:.3f} | {o2:.3f} |")


def tie_wave_deck(right, n_right):
    """Bar [0, 2 L] x [0, HB] (plane stress, nu = 0): left half Q8 (20 x 2, HRZ, moving at
    V0 along x), right half at rest (Q8 or NURBS, n_right along x), glued at x = L by *TIE."""
    out = [impact.header(f"wave across a tie, Q8 20 | {right} {n_right}", "PLANE STRESS", 0.0)]
    c1, nxt, ne = impact.q8_bar("LB", 0.0, LB, HB, 20, ny=2)
    out.append(c1)
    if right == "Q8":
        c2, _, _ = impact.q8_bar("RB", LB, LB, HB, n_right, first_node=nxt, first_element=ne,
                                 ny=2)
        m2 = "*MASS, TYPE=HRZ, ELSET=RB\n"
    else:
        c2, _ = impact.iga_block("RB", LB, 0.0, LB, HB, n_right, 2)
        m2 = "*MASS, TYPE=ROW SUM, PATCH=RB\n"
    t_end = 0.9 * LB / (E / RHO) ** 0.5
    out += [c2, "*TIE, NAME=GLUE\nRB_LEFT, LB_RIGHT\n",
            f"*INITIAL CONDITIONS, TYPE=VELOCITY\nLB, 1, {V0!r}\n",
            "*MASS, TYPE=HRZ, ELSET=LB\n", m2, impact.step(t_end, field_every=40)]
    return "".join(out)


def tie_wave(args, chk):
    """A bar of two halves glued by a tie, the left one moving at V0 into the right one at
    rest: in 1D (nu = 0) the joint moves at V0/2 and the right half gains the momentum
    rho c (V0/2) A t until the wave reaches its end (t = L/c). Checked at every snapshot
    after the first tenth of that time (the right half: its own nodes, by id, those on the
    tie included)."""
    c = (E / RHO) ** 0.5
    for right, n in (("Q8", 20), ("IGA", 27)):
        path = os.path.join(args.work, f"tie_wave_{right}.inp")
        with open(path, "w") as fd:
            fd.write(tie_wave_deck(right, n))
        out = path.replace(".inp", ".h5")
        vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        ids = r.model("node_ids")
        mass = r.model("mass")
        if right == "Q8":
            _, first_right, _ = impact.q8_bar("LB", 0.0, LB, HB, 20, ny=2)
            rb = ids >= first_right
        else:
            rb = np.isin(ids, np.asarray(r.f["model/patches/rb/ids"]))
        worst = 0.0
        for step in r.field_steps():
            t = r.field_time(step)
            if t < 0.1 * LB / c:
                continue
            v = r.field(step, "velocity")[:, 0]
            p = float(mass[rb] @ v[rb])
            exact = RHO * c * 0.5 * V0 * HB * t
            worst = max(worst, abs(p / exact - 1.0))
        print(f"  wave across a tie, Q8 20 | {right} {n}: largest |P_right/P_exact - 1| = "
              f"{worst:.4f}")
        chk.below(worst, 0.03, f"wave across a tie, Q8 20 | {right} {n}: the right half's "
                  "momentum against rho c (V0/2) A t")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("contact_mortar")
    tie_wave(args, chk)
    patch_tests(args, chk)
    momentum(args, chk)
    hertz_benchmark(args, chk)
    chk.finish()


if __name__ == "__main__":
    main()
