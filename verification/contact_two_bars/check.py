#!/usr/bin/env python3
"""Two identical elastic bars at +-v0 (doc/reference.md §3.2, equivalent to §3.1): the interface
force is rho c A v0 for 2L/c, then both bars rebound at -+v0 without vibration.

Bars [-L, 0] (at +v0) and [0, L] (at -v0), L = 10, H = 0.1, E = 1000, rho = 1, plane stress
nu = 0, touching at t = 0; frictionless TWO HALF PASS penalty contact between the end faces
with eps_hat = eps h / E = 10 (h = 0.1: eps = 1e5). Q8 (HRZ, 100 x 1 elements) and a p = 2
NURBS patch per bar (row sum, 100 x 1 spans). Automatic time step (it keeps the
predictor-corrector ratio r <= 1/2; the printed r is checked). Gates of doc/reference.md §3.1.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402
import impact  # noqa: E402
from impact import C, RHO  # noqa: E402

L, H, V0, N = 10.0, 0.1, 1.0, 100
EPS_HAT = 10.0


def two_bar_deck(kind, eps_hat=EPS_HAT, mass_penalty="", dt=0.0, mass=None):
    """Deck of the two bars; `mass_penalty` e.g. ', MASS PENALTY=AUTO'."""
    h = L / N
    eps = eps_hat * impact.E / h
    out = [impact.header(f"two bars at +-v0, {kind}, eps_hat = {eps_hat:g}")]
    if kind == "Q8":
        a, nxt, ne = impact.q8_bar("A", -L, L, H, N)
        b, _, _ = impact.q8_bar("B", 0.0, L, H, N, first_node=nxt, first_element=ne)
        mass = mass or "HRZ"
    else:
        a, _ = impact.iga_block("A", -L, 0.0, L, H, N, 1)
        b, _ = impact.iga_block("B", 0.0, 0.0, L, H, N, 1)
        mass = mass or "ROW SUM"
    out += [a, b, f"*INITIAL CONDITIONS, TYPE=VELOCITY\nA, 1, {V0!r}\nB, 1, {-V0!r}\n",
            f"*CONTACT PAIR, NAME=BARS, PENALTY={eps:.17g}{mass_penalty}\nA_RIGHT, B_LEFT\n",
            f"*MASS, TYPE={mass}\n", impact.step(1.3 * 2 * L / C, dt)]
    return "".join(out)


def check_pulse(chk, r, label, dt):
    """The doc/reference.md §3.1 gates on a two-bar run; returns the pulse."""
    t = r.history("time")
    f = r.history("contact/bars/force_first")[:, 0]   # on bar A: -x
    p = impact.pulse(t, -f, dt)
    chk.close(p["plateau"], RHO * C * H * V0, 0.03, f"{label}: plateau force (middle 80 %) "
              "= rho c A v0")
    chk.close(p["duration"], 2 * L / C, 0.03, f"{label}: contact duration = 2L/c")
    chk.close(p["impulse"], 2 * RHO * H * L * V0, 0.01, f"{label}: impulse = 2 rho A L v0")
    ek = r.history("energy/kinetic")
    chk.true(ek[-1] >= 0.97 * ek[0], f"{label}: rebound kinetic energy {ek[-1] / ek[0]:.4f} "
             "of the initial (>= 0.97)")
    m = r.model("mass")
    worst = 0.0
    for s in r.field_steps():
        v = r.field(s, "velocity")
        worst = max(worst, abs(float(np.sum(m * v[:, 0]))) / (RHO * L * H * V0))
    chk.below(worst, 1e-10, f"{label}: total momentum / (m v0) at every snapshot")
    return p


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("contact_two_bars")
    for kind in ("Q8", "IGA"):
        path = os.path.join(args.work, f"two_bars_{kind}.inp")
        with open(path, "w") as fd:
            fd.write(two_bar_deck(kind))
        out = path.replace(".inp", ".h5")
        _, log = vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        dt = float(r.history("dt")[0])
        rs = impact.ratios(log)
        chk.below(max(rs), 0.5, f"{kind}: printed predictor-corrector ratio r (dt = {dt:.4g})")
        p = check_pulse(chk, r, kind, dt)
        print(f"  {kind}: plateau {p['plateau'] / (RHO * C * H * V0):.5f}, duration "
              f"{p['duration'] / (2 * L / C):.5f}, impulse {p['impulse'] / (2 * RHO * H * L * V0):.5f}"
              f" (ratios to exact), contact bursts {p['nbursts']}")
    chk.finish()


if __name__ == "__main__":
    main()
