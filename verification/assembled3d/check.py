#!/usr/bin/env python3
"""The assembled stiffness in 3D (3 x 3 blocks) and the Cholesky factor of a 3D consistent mass.

1. The same run with INTERNAL FORCE=ASSEMBLED (f = K u with K assembled once in 3 x 3 blocks)
   and with INTERNAL FORCE=ELEMENT (the loop over the material laws): a distorted block of
   C3D8, C3D20, C3D20R and C3D27 (nu = 0.3), clamped at x = 0 and on rollers at z = 0, set
   moving in x and z; lumped (HRZ) mass, undamped (the fused step) and with mass-proportional
   damping, and a consistent mass (CG). Every displacement field and the energies must agree to
   round-off (1e-12 relative), omega_max too (the stable step from K or the element loop).
2. Bits: the assembled runs (C3D8 lumped, undamped and damped; C3D20 consistent with CG and
   with CHOLESKY) on 2 and 3 ranks and continued from a checkpoint on 2 ranks, bit for bit.
3. AUTO: a linear 3D model takes the assembled K and says so in the log (the bytes of its
   3 x 3 blocks against the memory available); with ICTUS_MEMORY_LIMIT_MB below twice those
   bytes it takes the element loop, says why, and gives the bits of INTERNAL FORCE=ELEMENT.
4. MASS SOLVER=CHOLESKY with a consistent mass in 3D (one factor for the clamped components,
   a second for the roller component) equals the CG run to the CG's tolerance.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

E, NU, RHO = 1000.0, 0.3, 1.0
SIZES = {"C3D8": (4, 3, 3), "C3D20": (3, 2, 2), "C3D20R": (3, 2, 2), "C3D27": (2, 2, 2)}


def deck(etype, force="AUTO", mass="HRZ", solver="", damping=False, extra="", t_end=0.4):
    """A distorted block [0, 2] x [0, 1] x [0, 1] of `etype`, clamped at x = 0, on rollers at
    z = 0 (u_z = 0), moving at v = (0.1, 0, -0.05) from t = 0."""
    nx, ny, nz = SIZES[etype]
    mesh = vcheck.box_mesh(type="C3D20" if etype == "C3D20R" else etype, nx=nx, ny=ny, nz=nz,
                           lx=2.0, ly=1.0, lz=1.0, distort=0.08)
    if etype == "C3D20R":
        mesh = mesh.replace("TYPE=C3D20", "TYPE=C3D20R")
    step = "*DYNAMIC, EXPLICIT, INTERNAL FORCE=" + force + (", MASS SOLVER=" + solver
                                                            if solver else "")
    return ("*HEADING\nassembled K in 3D\n*ANALYSIS, TYPE=3D\n"
            + vcheck.material_block(e=E, nu=NU, rho=RHO) + mesh
            + "*BOUNDARY\nX0, 1, 3\nZ0, 3, 3\n*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 1, 0.1\n"
            + "BODY, 3, -0.05\n*MASS, TYPE=" + mass + "\n"
            + ("*DAMPING, ALPHA=20.0\n" if damping else "")
            + "*STEP\n" + step + "\n0, " + repr(t_end) + "\n*OUTPUT, FIELD, EVERY=20\n"
            + extra + "*END STEP\n")


def run(args, name, text, np_=None, env=None):
    path = os.path.join(args.work, name + ".inp")
    with open(path, "w") as f:
        f.write(text)
    out = path.replace(".inp", ".h5")
    _, log = vcheck.run_ictus(args, path, out, np=np_, env=env)
    return path, out, log


def fields(out):
    r = vcheck.Results(out)
    return [r.field(s, "displacement") for s in r.field_steps()], r


def agree(chk, label, a, b, rtol=1e-12):
    ua, ra = fields(a)
    ub, rb = fields(b)
    scale = max(float(np.max(np.abs(u))) for u in ua)
    err = max(float(np.max(np.abs(x - y))) for x, y in zip(ua, ub)) / scale
    chk.true(len(ua) == len(ub) and len(ua) > 2, f"{label}: the same {len(ua)} snapshots")
    chk.below(err, rtol, f"{label}: max |u_A - u_E| / max |u| over all snapshots")
    ea, eb = ra.history("energy/strain"), rb.history("energy/strain")
    chk.below(float(np.max(np.abs(ea - eb)) / np.max(np.abs(ea))), rtol,
              f"{label}: strain energy history")
    chk.close(float(ra.attr("omega_max")), float(rb.attr("omega_max")), 1e-12,
              f"{label}: omega_max from K and from the element loop")


def same_physics(args, chk):
    for etype in SIZES:
        for tag, kw in (("lumped", {}), ("damped", {"damping": True}),
                        ("consistent CG", {"mass": "CONSISTENT", "solver": "CG"})):
            if tag != "lumped" and etype not in ("C3D8", "C3D20"):
                continue
            base = f"{etype.lower()}_{tag.split()[0]}"
            _, a, log = run(args, base + "_asm", deck(etype, force="ASSEMBLED", **kw))
            chk.true("internal force: assembled stiffness, f = K u (3 x 3 blocks" in log,
                     f"{etype} {tag}: ASSEMBLED logs the 3 x 3 blocks")
            _, b, _ = run(args, base + "_elem", deck(etype, force="ELEMENT", **kw))
            # the consistent mass: both runs stop their CG at the same tolerance, on
            # right-hand sides that differ by round-off
            agree(chk, f"{etype} {tag}, ASSEMBLED vs ELEMENT", a, b,
                  1e-12 if tag != "consistent CG" else 1e-9)


def bits(args, chk):
    every = "*RESTART, WRITE, EVERY=40\n"
    for label, etype, kw in (("C3D8 lumped", "C3D8", {}),
                             ("C3D8 damped", "C3D8", {"damping": True}),
                             ("C3D20 consistent CG", "C3D20", {"mass": "CONSISTENT",
                                                               "solver": "CG"}),
                             ("C3D20 consistent CHOLESKY", "C3D20", {"mass": "CONSISTENT",
                                                                     "solver": "CHOLESKY"})):
        name = "bits_" + label.lower().replace(" ", "_")
        path, out, _ = run(args, name, deck(etype, force="ASSEMBLED", extra=every, **kw))
        vcheck.check_ranks_and_restart(args, chk, path, out, ranks=(2, 3),
                                       label=f"{label} assembled: ")


def auto_choice(args, chk):
    _, a, log = run(args, "auto_c3d8", deck("C3D8"))
    chk.true("AUTO: the assembled K, whose 3 x 3 blocks take" in log,
             "AUTO in 3D: the assembled K, logged with its bytes")
    line = next(ln for ln in log.splitlines() if "internal force:" in ln)
    mb = float(line.split("blocks take ")[1].split(" MB")[0])
    limit = f"{mb / 1.5:.6f}"
    _, b, log = run(args, "auto_c3d8_short", deck("C3D8"), env={"ICTUS_MEMORY_LIMIT_MB": limit})
    chk.true("AUTO: the element loop, as the assembled K would take" in log,
             f"AUTO in 3D with {limit} MB available: the element loop, logged with the reason")
    _, c, _ = run(args, "auto_c3d8_elem", deck("C3D8", force="ELEMENT"))
    chk.true(vcheck.same_bits(b, c), "AUTO short of memory: the bits of INTERNAL FORCE=ELEMENT")
    chk.true(vcheck.same_bits(a, os.path.join(args.work, "c3d8_lumped_asm.h5")),
             "AUTO with memory: the bits of INTERNAL FORCE=ASSEMBLED")


def cholesky(args, chk):
    for etype in ("C3D8", "C3D20", "C3D27"):
        kw = {"mass": "CONSISTENT", "extra": "", "force": "ASSEMBLED"}
        _, a, log = run(args, f"chol_{etype.lower()}", deck(etype, solver="CHOLESKY", **kw))
        chk.true("2 factor(s) for 3 components" in log,
                 f"{etype} CHOLESKY: one factor for x and y, one for z (rollers)")
        _, b, _ = run(args, f"cg_{etype.lower()}", deck(etype, solver="CG", **kw))
        ua, _ = fields(a)
        ub, _ = fields(b)
        scale = max(float(np.max(np.abs(u))) for u in ua)
        err = max(float(np.max(np.abs(x - y))) for x, y in zip(ua, ub)) / scale
        chk.below(err, 1e-9, f"{etype} consistent mass: CHOLESKY vs CG, max |du| / max |u|")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("assembled3d")
    same_physics(args, chk)
    auto_choice(args, chk)
    cholesky(args, chk)
    bits(args, chk)
    chk.finish()


if __name__ == "__main__":
    main()
