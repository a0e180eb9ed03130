#!/usr/bin/env python3
"""A run that becomes unstable stops with exit status 2, says where, and keeps its results.

A bar hits a rigid wall with a penalty 1000 times its element stiffness at the time step of
the bulk (0.9 * 2/omega_max without contact): the predictor-corrector penalty needs
r = dt^2 eps l_s/m_s <= 1 (doc/contact.md §6), here r is in the hundreds, so the contact mode
grows without bound (STABILITY=WARN on the wall: by default ictus refuses such a deck at
input, verification/contact_bipenalty checks that). ictus must detect the blow-up (energies non-finite or above 1000 times the
initial energy), stop with exit status 2 and a message naming the step, the time and the node,
print no backtrace, and leave a readable results file whose `status` says "failed: ..." with
the history written up to the failure.
"""
import os
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402


def deck(dt):
    return ("*HEADING\nunstable penalty\n*ANALYSIS, TYPE=PLANE STRESS\n"
            + vcheck.material_block(e=1000.0, nu=0.0)
            + vcheck.rect_mesh(type="Q4", nx=20, ny=1, lx=2.0, ly=0.1)
            + "*SURFACE, NAME=END, TYPE=ELEMENT\n1, S4\n"
            + "*RIGID WALL, NAME=WALL, POINT=0,0, NORMAL=1,0, PENALTY=1.0E7, STABILITY=WARN\nEND\n"
            + "*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 1, -1.0\n"
            + f"*STEP\n*DYNAMIC, EXPLICIT\n{dt!r}, 0.2\n*END STEP\n")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("runtime_failure")
    path = os.path.join(args.work, "unstable.inp")
    with open(path, "w") as f:
        f.write(deck(0.0))
    _, log = vcheck.run_ictus(args, path, extra=["--check"])
    dt_crit = float(re.search(r"critical time step 2/omega_max = ([-+0-9.eE]+)", log).group(1))
    with open(path, "w") as f:
        f.write(deck(0.9 * dt_crit))
    out = os.path.join(args.work, "unstable.h5")
    p = subprocess.run([args.ictus, path, "-o", out], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True)
    chk.true(p.returncode == 2, f"exit status 2 (got {p.returncode})")
    m = re.search(r"error: run-time failure: step (\d+), t = ([-+0-9.eE]+): (.*); worst at node "
                  r"(\d+)", p.stderr)
    chk.true(m is not None, "the message names the step, the time, the cause and the node")
    for bad in ("Backtrace", "Error termination", "SIGSEGV", "ERROR STOP"):
        chk.true(bad not in p.stderr + p.stdout, f"no '{bad}' in the output")
    r = vcheck.Results(out)
    chk.true(r.attr("status").startswith("failed: step"), "results status says failed")
    t = r.history("time")
    chk.true(len(t) > 1 and np.all(np.diff(t) > 0), f"history readable up to the failure "
             f"({len(t)} records)")
    if m:
        chk.true(abs(t[-1] - float(m.group(2))) <= 2 * 0.9 * dt_crit,
                 "the last history record is at the reported time")
    chk.finish()


if __name__ == "__main__":
    main()
