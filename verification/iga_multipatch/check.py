#!/usr/bin/env python3
"""Multi-patch NURBS bodies (*PATCH, MERGE=YES; doc/iga.md §1.1), from scripts/mesh/disc.py.

1. Mass and numbering. Full disc of 5 merged patches (R = 1, n = 32 spans along the square
   side, m = 16 radial), ring of 4 (inner radius 1/2), half-disc x >= 0 of 4 (R = 4): the sum
   of /model/mass is rho pi R^2, rho pi (R^2 - r^2) and rho pi R^2 / 2 to 1e-12 (HRZ, row sum
   and consistent mass: each conserves the element masses; the rest is the quadrature error of
   the rational map, 5e-14 here), every mass is positive, and the number of control points is
   that of the patches less those shared: (n+2)^2 + 4 (m+2)(n+2) - 4 (n+2) - 4 (m+2) + 4 for
   the disc (each ring patch shares its inner side with the centre and a radial side with
   each neighbour), 4 (m+2)(n+2) - 4 (m+2) for the ring, and for the half-disc the four patch
   sizes less the five shared sides plus the two triple points counted twice.

   One patch closed on itself (an annulus whose direction 2 is the full circle, so its sides
   ETA0 and ETA1 coincide): rho pi (R^2 - r^2) to 1e-12, and the two ends of the net are the
   same n1 nodes.

2. No seam. A bar [0, 10] x [0, 0.5] (plane stress, nu = 0, E = 1000, rho = 1, v = -1 along
   its axis, u_x = 0 at x = 0; verification/iga_bar_wave) made of two merged patches [0, 5]
   and [5, 10] of 50 x 1 spans each is the same discretisation as one patch whose knot 1/2 is
   double (C0 there: the same Bezier elements and the same space). The wave crossing the seam
   must therefore give the single patch's displacements at every snapshot, to round-off
   (1e-10 of the largest), with the free-end displacement of the characteristics solution
   within 2 % (no reflection at the seam).

3. Disc dropped on a rigid wall. The 5-patch disc R = 1 centred at (0, 1) (E = 1000, nu = 0.2,
   rho = 1, plane strain, HRZ), falling at 0.1 onto the frictionless *RIGID WALL y = 0 (penalty
   1e4 per unit length; the lowest point (0, 0) lies inside the arc of patch S, away from the
   seams). Contact ends before t = 0.6; the rebound velocity is the mean vertical velocity
   sum(m v_y) / sum(m) at t = 0.6. Reference: a Q8 disc on the same patch maps refined until
   it changes by less than 0.1 % (n = 32 and 48); the IGA disc (n = 32, m = 16) must be
   within 1 % of it. The IGA run on 2 MPI ranks, and the processed deck stored in its results
   file (which writes MERGE=YES and the *SURFACE side lines back), give the same histories and
   fields bit for bit, and so does a run continued from a checkpoint (*RESTART, WRITE).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402
import disc  # noqa: E402  (scripts/mesh, on the path through vcheck)

E, RHO, V0, L, H = 1000.0, 1.0, 1.0, 10.0, 0.5
S = np.sqrt(0.5)
C = (E / RHO) ** 0.5


def run(args, name, text, np_ranks=None):
    path = os.path.join(args.work, name + ".inp")
    with open(path, "w") as fd:
        fd.write(text)
    out = path.replace(".inp", ".h5")
    _, log = vcheck.run_ictus(args, path, out, np=np_ranks)
    return vcheck.Results(out), log


def disc_deck(**kw):
    a = disc.options(**kw)
    return disc.deck(a, "verification/iga_multipatch")


def check_mass(args, chk):
    n, m = 32, 16
    cases = [("disc", dict(kind="disc", n=n, m=m), RHO * np.pi,
              (n + 2) ** 2 + 4 * (m + 2) * (n + 2) - 4 * (n + 2) - 4 * (m + 2) + 4),
             ("ring", dict(kind="ring", n=n, m=8, inner=0.5), RHO * np.pi * 0.75,
              4 * (8 + 2) * (n + 2) - 4 * (8 + 2)),
             ("halfdisc", dict(kind="halfdisc", n=n, m=n // 2), RHO * np.pi * 8.0,
              2 * (m + 2) * (n // 2 + 2) + (n // 2 + 2) * (n + 2) + (m + 2) * (n + 2)
              - ((n // 2 + 2) + (n + 2) + (n // 2 + 2) + 2 * (m + 2)) + 2)]
    for label, kw, mass, ncp in cases:
        for scheme in ("HRZ", "ROW SUM", "CONSISTENT"):
            r, _ = run(args, f"mass_{label}_{scheme.replace(' ', '_')}",
                       disc_deck(mass=scheme, t_end=1e-4, **kw))
            mm = r.model("mass")
            chk.close(float(mm.sum()), mass, 1e-12, f"{label}, {scheme}: total mass")
            chk.true(bool(np.all(mm > 0)), f"{label}, {scheme}: all masses positive")
        chk.true(r.model("coordinates").shape[0] == ncp,
                 f"{label}: {r.model('coordinates').shape[0]} control points (expected {ncp})")


def closed_ring_deck():
    """One patch closed on itself: the annulus 1/2 <= r <= 1 with the full circle (9 control
    points, double knots at 1/4, 1/2, 3/4) along direction 2, so sides ETA0 and ETA1 are the
    same radial segment and are glued to each other."""
    circ = [(1, 0, 1), (1, 1, S), (0, 1, 1), (-1, 1, S), (-1, 0, 1), (-1, -1, S), (0, -1, 1),
            (1, -1, S), (1, 0, 1)]
    cps = "".join(f"{r * x!r}, {r * y!r}, {w!r}\n" for x, y, w in circ for r in (0.5, 0.75, 1.0))
    return ("*HEADING\nclosed ring, one patch\n*ANALYSIS, TYPE=PLANE STRAIN, THICKNESS=1\n"
            + vcheck.material_block(e=E, nu=0.2, rho=RHO)
            + "*PATCH, NAME=RING, MATERIAL=MAT, DEGREE=2,2, SIZE=3,9, MERGE=YES\n"
            + "*KNOTS, DIRECTION=1\n0 0 0 1 1 1\n*KNOTS, DIRECTION=2\n"
            + "0 0 0 0.25 0.25 0.5 0.5 0.75 0.75 1 1 1\n*CONTROL POINTS\n" + cps
            + "*REFINE, PATCH=RING, SUBDIVIDE=8,32\n*STEP\n*DYNAMIC, EXPLICIT\n0, 1e-4\n*END STEP\n")


def check_closed_ring(args, chk):
    r, _ = run(args, "closed_ring", closed_ring_deck())
    n1, n2 = (int(v) for v in r.f["model/patches/ring/size"][()])
    ids = np.asarray(r.f["model/patches/ring/ids"]).reshape(n2, n1)
    chk.close(float(r.model("mass").sum()), RHO * np.pi * 0.75, 1e-12,
              "closed ring (one patch glued to itself): total mass")
    chk.true(r.model("coordinates").shape[0] == n1 * n2 - n1 and
             np.array_equal(ids[0], ids[-1]), f"closed ring: {n1 * n2 - n1} control points, "
             "the first and last rows of the net are the same nodes")


def bar_deck(merged):
    head = ("*HEADING\nbar wave across a patch seam\n*ANALYSIS, TYPE=PLANE STRESS, THICKNESS=1\n"
            + vcheck.material_block(e=E, nu=0.0, rho=RHO))
    if merged:
        body = ""
        for name, x0 in (("BAR_A", 0.0), ("BAR_B", 0.5 * L)):
            cps = "".join(f"{x0 + 0.25 * L * i!r}, {0.5 * H * j!r}, 1.0\n"
                          for j in range(3) for i in range(3))
            body += (f"*PATCH, NAME={name}, MATERIAL=MAT, DEGREE=2,2, SIZE=3,3, MERGE=YES\n"
                     "*KNOTS, DIRECTION=1\n0 0 0 1 1 1\n*KNOTS, DIRECTION=2\n0 0 0 1 1 1\n"
                     f"*CONTROL POINTS\n{cps}*REFINE, PATCH={name}, SUBDIVIDE=50,1\n")
        body += "*ELSET, ELSET=BAR\nBAR_A, BAR_B\n*NSET, NSET=LEFT, PATCH=BAR_A, SIDE=XI0\n"
    else:
        cps = "".join(f"{0.25 * L * i!r}, {0.5 * H * j!r}, 1.0\n"
                      for j in range(3) for i in range(5))
        body = ("*PATCH, NAME=BAR, MATERIAL=MAT, DEGREE=2,2, SIZE=5,3\n"
                "*KNOTS, DIRECTION=1\n0 0 0 0.5 0.5 1 1 1\n*KNOTS, DIRECTION=2\n0 0 0 1 1 1\n"
                f"*CONTROL POINTS\n{cps}*REFINE, PATCH=BAR, SUBDIVIDE=50,1\n"
                "*NSET, NSET=LEFT, PATCH=BAR, SIDE=XI0\n")
    return (head + body + "*BOUNDARY\nLEFT, 1, 1\n*INITIAL CONDITIONS, TYPE=VELOCITY\n"
            + "BAR, 1, -1.0\n*MASS, TYPE=ROW SUM\n*STEP\n*DYNAMIC, EXPLICIT\n"
            + f"0, {1.5 * L / C!r}\n*OUTPUT, FIELD, EVERY=50\n*END STEP\n")


def check_seam(args, chk):
    rm, _ = run(args, "bar_merged", bar_deck(True))
    rs, _ = run(args, "bar_single", bar_deck(False))
    xm, xs = rm.model("coordinates"), rs.model("coordinates")
    chk.true(xm.shape == xs.shape, f"merged bar: {xm.shape[0]} control points, as the single "
             f"patch with a double knot ({xs.shape[0]})")
    # rows of the single patch in the order of the merged model's rows (same coordinates)
    km = np.lexsort((np.round(xm[:, 1], 9), np.round(xm[:, 0], 9)))
    ks = np.lexsort((np.round(xs[:, 1], 9), np.round(xs[:, 0], 9)))
    chk.below(float(np.max(np.abs(xm[km] - xs[ks]))), 1e-12, "the same control points")
    steps = rm.field_steps()
    chk.true(steps == rs.field_steps(), "the same snapshots")
    worst, umax = 0.0, 0.0
    for s in steps:
        um, us = rm.field(s, "displacement")[km], rs.field(s, "displacement")[ks]
        worst = max(worst, float(np.max(np.abs(um - us))))
        umax = max(umax, float(np.max(np.abs(us))))
    chk.below(worst / umax, 1e-10, "merged patches against the single C0 patch: largest "
              "displacement difference / largest displacement, all snapshots")
    s = steps[-1]
    t = rm.field_time(s)
    u = rm.field(s, "displacement")
    tip = float(np.mean(u[np.isclose(xm[:, 0], L), 0]))
    exact = V0 * (t - 2 * L / C) if t >= L / C else -V0 * t
    chk.close(tip, exact, 0.02, f"free-end displacement at t = {t:.4g} (characteristics)")


def drop_deck(q8, n):
    return disc_deck(kind="disc", q8=q8, n=n, m=n // 2, y0=1.0, vy=-0.1, wall=1e4, t_end=0.6,
                     field_every=0)


def rebound(r):
    mm = r.model("mass")
    v = r.field(r.field_steps()[-1], "velocity")
    return float(np.sum(mm * v[:, 1]) / np.sum(mm))


def check_drop(args, chk):
    q = {}
    for n in (32, 48):
        r, _ = run(args, f"drop_q8_{n}", drop_deck(True, n))
        q[n] = rebound(r)
        f = r.history("contact/wall/force_first")
        chk.true(bool(np.all(f[-20:] == 0.0)), f"Q8 n = {n}: the disc has left the wall")
    chk.close(q[32], q[48], 1e-3, "Q8 converged: rebound velocity, n = 32 against n = 48")
    r, _ = run(args, "drop_iga", drop_deck(False, 32))
    chk.true(bool(np.all(r.history("contact/wall/force_first")[-20:] == 0.0)),
             "IGA: the disc has left the wall")
    v = rebound(r)
    chk.close(v, q[48], 0.01, "IGA 5-patch disc: rebound velocity against the converged Q8")
    chk.close(float(r.model("mass").sum()), RHO * np.pi, 1e-12, "IGA drop: total mass rho pi R^2")
    print(f"  rebound velocity / v0: IGA {v / 0.1:.5f}, Q8 n = 32 {q[32] / 0.1:.5f}, "
          f"n = 48 {q[48] / 0.1:.5f}")
    chk.true(vcheck.processed_deck_reruns(args, os.path.join(args.work, "drop_iga.h5")),
             "IGA drop: the processed deck (MERGE=YES, *SURFACE side lines) reruns bit for bit")
    r2, _ = run(args, "drop_iga_np2", drop_deck(False, 32), np_ranks=2)
    chk.true(vcheck.same_bits(os.path.join(args.work, "drop_iga.h5"),
                              os.path.join(args.work, "drop_iga_np2.h5")),
             "IGA drop on 2 ranks: the same histories and fields bit for bit")


def check_restart(args, chk):
    """The drop (n = 16, to t = 0.3) with a checkpoint every 300 steps, continued from the
    checkpoint of step 300 in a copy of its results file: the same file bit for bit."""
    import shutil
    text = disc_deck(kind="disc", n=16, m=8, y0=1.0, vy=-0.1, wall=1e4, t_end=0.3)
    text = text.replace("*END STEP", "*RESTART, WRITE, EVERY=300\n*END STEP")
    run(args, "drop_restart", text)
    base = os.path.join(args.work, "drop_restart")
    shutil.copy(base + ".h5", base + "_again.h5")
    shutil.copy(base + ".chk.h5", base + "_again.chk.h5")
    _, log = vcheck.run_ictus(args, base + ".inp", base + "_again.h5",
                              extra=("--restart", base + "_again.chk.h5"))
    chk.true("continuing at step 300" in log and
             vcheck.same_bits(base + ".h5", base + "_again.h5"),
             "drop restarted from its checkpoint at step 300: the same results bit for bit")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("iga_multipatch")
    check_mass(args, chk)
    check_closed_ring(args, chk)
    check_seam(args, chk)
    check_drop(args, chk)
    check_restart(args, chk)
    chk.finish()


if __name__ == "__main__":
    main()
