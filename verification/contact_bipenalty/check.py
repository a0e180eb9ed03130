#!/usr/bin/env python3
"""Bipenalty (doc/contact.md §6a) on the two-bar impact of doc/reference.md §3.2: a very stiff
penalty (eps_hat = eps h / E = 1e3) at the time step of the bulk.

The decks of verification/contact_two_bars (Q8 HRZ, 100 x 1 per bar, +-v0) with
eps_hat = 1e3. With MASS PENALTY=AUTO the automatic step is the bulk's 0.9 * 2/omega0_max
(the mass penalty keeps the predictor-corrector ratio r below 1/2), and the doc/reference.md
§3.1 gates hold. The same deck without the mass penalty, run at that same step, has r > 1: it is refused at input
(exit 1) with r and the largest stable penalty eps/r, both checked against r = dt^2 eps 76/(9 rho
h) of the mesh (doc/contact.md §6); with STABILITY=WARN it runs, and either blows up (exit 2,
"the solution blows up") or misses those gates. A
consistent mass with MASS PENALTY is refused (exit 1, message naming the card).
The omega_max statement (bipenalty keeps omega_max at the no-contact value, plain penalty
raises it) is checked by the unit test tests/unit/solver/test_contact_omega.
"""
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..",
                                "contact_two_bars"))
import vcheck  # noqa: E402
import impact  # noqa: E402
import check as two_bars  # noqa: E402
from impact import C, RHO  # noqa: E402


def plain_pair_line(path):
    """Line number of the *CONTACT PAIR card in a deck."""
    with open(path) as fd:
        for i, line in enumerate(fd, 1):
            if line.upper().startswith("*CONTACT PAIR"):
                return i
    return -1


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("contact_bipenalty")
    path = os.path.join(args.work, "bip.inp")
    with open(path, "w") as fd:
        fd.write(two_bars.two_bar_deck("Q8", 1e3, ", MASS PENALTY=AUTO"))
    out = path.replace(".inp", ".h5")
    _, log = vcheck.run_ictus(args, path, out)
    r = vcheck.Results(out)
    dt = float(r.history("dt")[0])
    dt_crit = float(re.search(r"critical time step 2/omega_max = ([-+0-9.eE]+)", log).group(1))
    chk.close(dt, 0.9 * dt_crit, 1e-6, "bipenalty: automatic dt = 0.9 * 2/omega0_max (bulk)")
    chk.below(max(impact.ratios(log)), 0.5, "bipenalty: printed ratio r")
    p = two_bars.check_pulse(chk, r, "bipenalty eps_hat = 1e3", dt)
    print(f"  bipenalty: dt {dt:.6g}, plateau {p['plateau'] / (RHO * C * two_bars.H):.5f}, "
          f"duration {p['duration'] / (2 * two_bars.L / C):.5f}, impulse "
          f"{p['impulse'] / (2 * RHO * two_bars.H * two_bars.L):.5f}, bursts {p['nbursts']}")
    # plain penalty at the same step: r > 1, refused at input (STABILITY=STOP, the default)
    path = os.path.join(args.work, "plain.inp")
    with open(path, "w") as fd:
        fd.write(two_bars.two_bar_deck("Q8", 1e3, "", dt=dt))
    pr = subprocess.run([args.ictus, path, "-o", path.replace(".inp", ".h5")],
                        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    # the ratio of doc/contact.md §6 from the mesh: the end corner node of a bar (one Q8 of
    # h x H, exact-diagonal HRZ: m = 3/76 rho h H, l = H/6) against the opposite corner,
    # r = dt^2 eps (2 l/m) = dt^2 eps 76/(9 rho h), with eps = eps_hat E/h
    h = two_bars.L / two_bars.N
    eps = 1e3 * impact.E / h
    r_exact = dt * dt * eps * 76.0 / (9.0 * RHO * h)
    m = re.search(r"(\S+): \*CONTACT PAIR bars: the contact stability ratio r = [^=]*= "
                  r"([-+0-9.eE]+) at dt = [-+0-9.eE]+ exceeds the limit r = 1.*largest stable "
                  r"penalty at this dt is about PENALTY=([-+0-9.eE]+)", pr.stdout)
    chk.true(pr.returncode == 1 and m is not None,
             "plain penalty at the bulk step: input error (exit 1) naming the pair, r and the "
             f"largest stable penalty (exit {pr.returncode})")
    if m:
        chk.true(m.group(1).endswith("plain.inp:" + str(plain_pair_line(path))),
                 f"the error names the *CONTACT PAIR line ({m.group(1)})")
        chk.close(float(m.group(2)), r_exact, 2e-3, f"printed r = dt^2 eps 76/(9 rho h) = "
                  f"{r_exact:.4g}")
        chk.close(float(m.group(3)), eps / r_exact, 2e-3, "largest stable penalty = eps/r")
    # with STABILITY=WARN the same deck runs, with the warning, and fails physically
    path = os.path.join(args.work, "plain_warn.inp")
    with open(path, "w") as fd:
        fd.write(two_bars.two_bar_deck("Q8", 1e3, ", STABILITY=WARN", dt=dt))
    pr = subprocess.run([args.ictus, path, "-o", path.replace(".inp", ".h5")],
                        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    chk.true("running anyway (STABILITY=WARN)" in pr.stdout and pr.returncode in (0, 2),
             f"STABILITY=WARN: runs with the warning (exit {pr.returncode})")
    if pr.returncode == 2:
        chk.true("the solution blows up" in pr.stdout,
                 "plain penalty at the bulk step: the run stops because the solution blows up")
    else:
        rr = vcheck.Results(path.replace(".inp", ".h5"))
        t = rr.history("time")
        q = impact.pulse(t, -rr.history("contact/bars/force_first")[:, 0], dt)
        ek = rr.history("energy/kinetic")
        bad = (abs(q["impulse"] / (2 * RHO * two_bars.H * two_bars.L) - 1) > 0.01
               or abs(q["duration"] / (2 * two_bars.L / C) - 1) > 0.03 or ek[-1] < 0.97 * ek[0]
               or ek[-1] > 1.03 * ek[0])
        chk.true(bad, f"plain penalty at the bulk step misses the doc/reference.md §3.1 gates "
                 f"(impulse {q['impulse'] / (2 * RHO * two_bars.H * two_bars.L):.4g}, duration "
                 f"{q['duration'] / (2 * two_bars.L / C):.4g}, kinetic energy {ek[-1] / ek[0]:.4g})")
    # consistent mass is refused
    path = os.path.join(args.work, "consistent.inp")
    with open(path, "w") as fd:
        fd.write(two_bars.two_bar_deck("Q8", 1e3, ", MASS PENALTY=AUTO", mass="CONSISTENT"))
    pc = subprocess.run([args.ictus, path], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                        text=True)
    chk.true(pc.returncode == 1 and "*CONTACT PAIR, NAME=BARS" in pc.stdout
             and "lumped mass" in pc.stdout,
             "MASS PENALTY with a consistent mass: input error naming the card (exit 1)")
    chk.finish()


if __name__ == "__main__":
    main()
