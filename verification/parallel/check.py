#!/usr/bin/env python3
"""The same deck on 1, 2, 3 and 4 MPI ranks gives the same bits.

ictus assembles the rows of each owned node from all elements holding it, in global element
order, and computes every global sum (conjugate gradients, power iteration, energies) with a
reproducible summation (doc/parallel.md). So the /history datasets, the field snapshots, the
nodal masses, omega_max and dt must be identical, not just close, for any number of ranks.
Cases: classic FE (Q8, HRZ and consistent mass, with damping), Q4 with a partition-cutting
Dirichlet boundary, NURBS (a refined biquadratic patch, consistent mass by the Cholesky factor
and by corrector passes, whose halo exchanges cut the partition), a rectangular Q8 grid and a
rectangular NURBS patch whose consistent mass is solved along the lattice directions
(MASS SOLVER=KRONECKER, taken by the default AUTO; the log must say so; the cases named
*_fused record every 25 steps, so that on one rank the steps in between fold the updates of
v and u into the solve, which must give the bits of the unfused steps the runs on several
ranks take, with a contact correction in between for two Q8 blocks), and the dynamic Hertz
problem with two-half-pass contact (NURBS HRZ, Q8 consistent) on partitions that cut right
through the contact zone (checked from /model/partition). The cases named *_sweep record
every 25 and 10 steps, so that the lumped-mass steps in between run as sweeps of several steps
over K (ictus_solver_sweep: zones around the partition boundaries and the contact nodes step
singly): they must give the same bits on any number of ranks, and the same bits as the run
with SWEEP STEPS=1 (one step per pass over K) and as the runs on 1 and 2 ranks with the
default SWEEP STEPS=AUTO, whose first windows alternate between sweeps and single steps
before the faster is kept (the log must say which); on the long strip q4_long_sweep AUTO on
one rank also times the plan of wide strips (the log must say so). q4_empty_rank (two Q4
elements) leaves a rank without nodes on 4 ranks, with the default SWEEP STEPS=AUTO timing sweeps. The cases named
*_damped_sweep add mass-proportional damping (with contact for the Hertz one, damped on the
upper body only, so that some ranks hold no damped node and must still join its sums): the damped
steps between records run in one pass over K and in sweeps, and must also give the bits of the
run that records every step, whose steps all take the unfused damped update (every field
snapshot, and the history rows of the records both runs make, the damping work included).
"""
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

sys.path.insert(0, os.path.join(vcheck.ROOT, "scripts", "mesh"))
import hertz  # noqa: E402

STEP = "*STEP\n*DYNAMIC, EXPLICIT\n0, 0.05\n*OUTPUT, FIELD, EVERY=20\n*END STEP\n"
SWEEP_STEP = ("*STEP\n*DYNAMIC, EXPLICIT, SWEEP STEPS=6\n0, 1.5\n*OUTPUT, HISTORY, EVERY=25\n"
              "*OUTPUT, FIELD, EVERY=40\n*END STEP\n")


def fe_deck(etype, mass, extra="", step=STEP, distort=0.2):
    return ("*HEADING\nparallel determinism\n" + vcheck.material_block()
            + vcheck.rect_mesh(type=etype, nx=12, ny=6, lx=3.0, ly=1.5, distort=distort)
            + "*BOUNDARY\nLEFT, 1, 2\nRIGHT, 1, 1, 0.01\n*INITIAL CONDITIONS, TYPE=VELOCITY\n"
            + "BODY, 2, -1.0\nTOP, 1, 0.5\n" + mass + "\n" + extra + step)


def iga_deck(step=STEP, rectangle=False):
    cps = []
    for j in range(3):
        for i in range(3):
            x, y = 1.5 * i, 0.75 * j + (0.0 if rectangle else 0.1 * i * j)
            cps.append(f"{x}, {y}, {1.0 if (i, j) != (1, 1) or rectangle else 0.8}")
    return ("*HEADING\nparallel determinism, NURBS\n" + vcheck.material_block()
            + "*PATCH, NAME=P, MATERIAL=MAT, DEGREE=2,2, SIZE=3,3\n*KNOTS, DIRECTION=1\n"
            + "0 0 0 1 1 1\n*KNOTS, DIRECTION=2\n0 0 0 1 1 1\n*CONTROL POINTS\n"
            + "\n".join(cps) + "\n*REFINE, PATCH=P, SUBDIVIDE=8,6\n"
            + "*NSET, NSET=FIX, PATCH=P, SIDE=XI0\n*BOUNDARY\nFIX, 1, 2\n"
            + "*INITIAL CONDITIONS, TYPE=VELOCITY\nP, 2, 1.0\n*MASS, TYPE=CONSISTENT\n" + step)


# record every 25 steps: the consistent-mass steps in between fold the updates of v and u
# into the solve on one rank (mass_step), which must give the bits of the unfused step that
# the runs on several ranks take
FUSED_STEP = SWEEP_STEP.replace(", SWEEP STEPS=6", "")


def q8_contact_deck():
    """Two stacked rectangular Q8 blocks, the upper one moving down onto the lower one:
    both lattices, so the consistent mass is solved along the lattice directions, with a
    contact correction (a consistent solve of its own) between predictor and update."""
    nx, ny = 8, 3
    up_first = (2 * nx + 1) * (ny + 1) + (nx + 1) * ny + 1
    return ("*HEADING\nparallel determinism, Q8 contact\n" + vcheck.material_block()
            + vcheck.rect_mesh(type="Q8", nx=nx, ny=ny, lx=2.0, ly=0.75, elset="LO",
                               prefix="LO_")
            + vcheck.rect_mesh(type="Q8", nx=nx, ny=ny, lx=2.0, ly=0.75, y0=0.76,
                               first_node=up_first, first_element=nx * ny + 1, elset="UP",
                               prefix="UP_")
            + "*SURFACE, NAME=LO_TOP, TYPE=ELEMENT\n"
            + "".join(f"{e}, S3\n" for e in range(nx * (ny - 1) + 1, nx * ny + 1))
            + "*SURFACE, NAME=UP_BOTTOM, TYPE=ELEMENT\n"
            + "".join(f"{e}, S1\n" for e in range(nx * ny + 1, nx * ny + nx + 1))
            + "*CONTACT PAIR, NAME=IFACE, PENALTY=2.0E4\nLO_TOP, UP_BOTTOM\n"
            + "*BOUNDARY\nLO_BOTTOM, 2, 2\nLO_CORNER_LL, 1, 1\n"
            + "*INITIAL CONDITIONS, TYPE=VELOCITY\nUP, 2, -1.0\n*MASS, TYPE=CONSISTENT\n"
            + FUSED_STEP.replace("0, 1.5", "0, 0.3"))


def long_deck():
    """A long Q4 strip (600 x 4 elements), lumped, recording every 25 steps: wide enough in
    the numbering direction for sweeps of two strips (and one wide strip)."""
    return ("*HEADING\nparallel determinism, long strip\n" + vcheck.material_block()
            + vcheck.rect_mesh(type="Q4", nx=600, ny=4, lx=60.0, ly=0.4)
            + "*BOUNDARY\nLEFT, 1, 2\n*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 2, -1.0\n"
            + "TOP, 1, 0.5\n*MASS, TYPE=ROW SUM\n" + SWEEP_STEP.replace("0, 1.5", "0, 1.2"))


def tiny_deck():
    """Two Q4 elements (6 nodes), lumped, recording every 25 steps with the default
    SWEEP STEPS=AUTO: on 4 ranks METIS leaves a rank without nodes, which must still take part
    in the sweeps' exchanges and the tuning's sums."""
    return ("*HEADING\nparallel determinism, a rank without nodes\n" + vcheck.material_block()
            + vcheck.rect_mesh(type="Q4", nx=2, ny=1, lx=2.0, ly=1.0)
            + "*BOUNDARY\nLEFT, 1, 2\n*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 2, -1.0\n"
            + "*MASS, TYPE=ROW SUM\n" + FUSED_STEP.replace("0, 1.5", "0, 3.0"))


def compare_unfused(chk, args, tag, text, ref):
    """The run recording the history every step (every step unfused) against ref, the run
    of `text` on one rank: the same bits in every field snapshot and in the history rows at
    the records ref made."""
    every = os.path.join(args.work, tag + "_every.inp")
    with open(every, "w") as f:
        f.write(re.sub(r"HISTORY, EVERY=\d+", "HISTORY, EVERY=1", text))
    out = os.path.join(args.work, tag + "_every.h5")
    # (every step records, so every step takes the unfused update of step_predict)
    vcheck.run_ictus(args, every, out, np=1)
    full = vcheck.Results(out)
    t_ref, t_full = ref.history("time"), full.history("time")
    rows = np.searchsorted(t_full, t_ref)
    same = bool(np.all(rows < len(t_full))) and np.array_equal(t_full[np.minimum(
        rows, len(t_full) - 1)], t_ref)
    names = []
    ref.f["history"].visit(lambda k: names.append(k) if hasattr(ref.f["history"][k], "shape")
                           else None)
    for k in names:
        if not same:
            break
        if not np.array_equal(ref.history(k), full.history(k)[rows]):
            same = False
            print(f"    differs: history/{k}")
    chk.true(same, f"{tag}: the history rows of its {len(t_ref)} records have the bits of "
             f"the run recording every step ({len(names)} datasets)")
    steps = ref.field_steps()
    same = steps == full.field_steps()
    for st in steps if same else []:
        for k in ref.f["fields/" + st].keys():
            if not np.array_equal(ref.field(st, k), full.field(st, k)):
                same = False
                print(f"    differs: fields/{st}/{k}")
    chk.true(same, f"{tag}: its {len(steps)} field snapshots have the bits of the run "
             "recording every step")
    w = ref.history("energy/external_work")
    chk.true(w[-1] < 0.0, f"{tag}: the damping does work (external_work {w[-1]:.4g})")


def compare(chk, tag, ref, other, n):
    a, b = ref.f, other.f
    names = []
    a.visit(lambda k: names.append(k) if hasattr(a[k], "shape") else None)
    # the partition itself is the one thing that depends on the number of ranks
    names = [k for k in names if k not in ("model/partition", "model/element_partition")]
    same = True
    for k in names:
        if k not in b or not np.array_equal(np.asarray(a[k]), np.asarray(b[k])):
            same = False
            print(f"    differs: {k}")
    chk.true(same, f"{tag}: np = {n} gives the same bits as np = 1 ({len(names)} datasets)")
    for attr in ("omega_max", "dt"):
        chk.true(a.attrs[attr] == b.attrs[attr], f"{tag}: np = {n} {attr} identical")
    chk.true(int(b.attrs["ranks"]) == n, f"{tag}: ranks attribute = {n}")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("parallel")
    cases = {"q8_hrz_damped": fe_deck("Q8", "*MASS, TYPE=HRZ", "*DAMPING, ALPHA=2.0\n"),
             "q8_consistent": fe_deck("Q8", "*MASS, TYPE=CONSISTENT"),
             "q8_consistent_cg": fe_deck("Q8", "*MASS, TYPE=CONSISTENT", step=STEP.replace(
                 "EXPLICIT", "EXPLICIT, MASS SOLVER=CG")),
             "q4_rowsum": fe_deck("Q4", "*MASS, TYPE=ROW SUM"),
             "iga_consistent": iga_deck(),
             "iga_corrector": iga_deck(STEP.replace("EXPLICIT", "EXPLICIT, MASS SOLVER=CORRECTOR")),
             # rectangular grid and patch: the consistent mass solved along the lattice
             # directions (MASS SOLVER=AUTO takes KRONECKER), on the gathered loads
             "q8_kronecker": fe_deck("Q8", "*MASS, TYPE=CONSISTENT", distort=0.0),
             "iga_kronecker": iga_deck(rectangle=True),
             "q8_kronecker_fused": fe_deck("Q8", "*MASS, TYPE=CONSISTENT", distort=0.0,
                                           step=FUSED_STEP),
             "iga_kronecker_fused": iga_deck(step=FUSED_STEP, rectangle=True),
             "q8_kronecker_contact_fused": q8_contact_deck(),
             "hertz_iga_hrz": hertz.deck(hertz.options(kind="iga", mass="HRZ", subdivide=8,
                                                       t_end=0.3, field_every=200), "test"),
             "hertz_q8_consistent": hertz.deck(hertz.options(kind="q8", mass="CONSISTENT", n=6,
                                                             dt=2e-4, t_end=0.2), "test"),
             "q4_rowsum_sweep": fe_deck("Q4", "*MASS, TYPE=ROW SUM", step=SWEEP_STEP),
             "q4_empty_rank": tiny_deck(),
             "q8_hrz_damped_sweep": fe_deck("Q8", "*MASS, TYPE=HRZ", "*DAMPING, ALPHA=2.0\n",
                                            step=SWEEP_STEP),
             # lines of 601 nodes: the default strips of a sweep are two, the wide ones one,
             # so SWEEP STEPS=AUTO times the wide plan as a third kind
             "q4_long_sweep": long_deck(),
             "hertz_iga_hrz_sweep": hertz.deck(hertz.options(
                 kind="iga", mass="HRZ", subdivide=8, t_end=0.3, field_every=200),
                 "test").replace("HISTORY, EVERY=1\n", "HISTORY, EVERY=10\n").replace(
                 "*DYNAMIC, EXPLICIT", "*DYNAMIC, EXPLICIT, SWEEP STEPS=6"),
             # damping on the upper body only: ranks that hold none of its nodes take the
             # damped step too (its global sum), with the undamped update
             "hertz_iga_hrz_damped_sweep": hertz.deck(hertz.options(
                 kind="iga", mass="HRZ", subdivide=8, t_end=0.3, field_every=200, alpha=3.0),
                 "test").replace("HISTORY, EVERY=1\n", "HISTORY, EVERY=10\n").replace(
                 "*DYNAMIC, EXPLICIT", "*DYNAMIC, EXPLICIT, SWEEP STEPS=6").replace(
                 "*DAMPING, ALPHA=3\n", "*DAMPING, ALPHA=3, PATCH=UPPER\n")}
    for tag, text in cases.items():
        path = os.path.join(args.work, tag + ".inp")
        with open(path, "w") as f:
            f.write(text)
        results = {}
        for n in (1, 2, 3, 4):
            out = os.path.join(args.work, f"{tag}_np{n}.h5")
            _, log = vcheck.run_ictus(args, path, out, np=n)
            results[n] = vcheck.Results(out)
            if tag.endswith("_sweep"):
                chk.true("sweeps: 6 steps per sweep" in log, f"{tag}: np = {n} runs sweeps "
                         "of 6 steps")
            if "_kronecker" in tag:
                chk.true("MASS SOLVER=KRONECKER" in log, f"{tag}: np = {n} solves the mass "
                         "along the lattice directions")
            if any(w in tag for w in ("consistent", "kronecker", "corrector")):
                # the product of a consistent step: K's upper blocks on one rank, the full
                # rows on several (the upper blocks on a part without ghosts), the same bits
                # (compared below)
                if n == 1:
                    ok = "summed in column order from the upper blocks of K (" in log
                else:
                    ok = ("summed in column order from the full rows of K" in log
                          or re.search(r"upper blocks of K on (\d of %d ranks .* the full rows "
                                       r"on the others|all %d ranks \(parts without ghosts)"
                                       % (n, n), log) is not None)
                what = "upper blocks" if n == 1 else "full rows (of parts with ghosts)"
                chk.true(ok, f"{tag}: np = {n} takes K u from the {what}")
            if tag.endswith("_fused"):
                fused = "update v and u inside the solve" in log
                chk.true(fused == (n == 1), f"{tag}: np = {n} "
                         + ("folds the updates into the solve" if n == 1 else
                            "solves on the gathered loads, updates apart"))
        for n in (2, 3, 4):
            compare(chk, tag, results[1], results[n], n)
        if tag.endswith("_sweep"):
            single = os.path.join(args.work, tag + "_single.inp")
            with open(single, "w") as f:
                f.write(text.replace("SWEEP STEPS=6", "SWEEP STEPS=1"))
            out = os.path.join(args.work, f"{tag}_single.h5")
            _, log = vcheck.run_ictus(args, single, out, np=1)
            chk.true("sweeps:" not in log, f"{tag}: SWEEP STEPS=1 runs one step per pass")
            compare(chk, tag + " vs SWEEP STEPS=1", vcheck.Results(out), results[1], 1)
            if "_damped" in tag:
                compare_unfused(chk, args, tag, text, results[1])
            auto = os.path.join(args.work, tag + "_auto.inp")
            with open(auto, "w") as f:
                f.write(text.replace(", SWEEP STEPS=6", ""))
            for n in (1, 2):
                out = os.path.join(args.work, f"{tag}_auto_np{n}.h5")
                _, log = vcheck.run_ictus(args, auto, out, np=n)
                chk.true("timed against single steps first" in log and
                         ("sweeps: kept" in log or "sweeps: dropped" in log),
                         f"{tag}: SWEEP STEPS=AUTO on np = {n} times sweeps against single "
                         "steps and keeps one")
                if tag == "q4_long_sweep" and n == 1:
                    # (on 2 ranks each rank's rows are narrow enough for one strip)
                    chk.true("and against wide strips" in log and "ms in one sweep of wide "
                             "strips" in log, f"{tag}: np = {n} times the wide strips too")
                compare(chk, f"{tag} with SWEEP STEPS=AUTO", results[1], vcheck.Results(out), n)
        if tag == "q8_kronecker_fused":
            # K's upper blocks do not fit in the memory given: the full rows, the same bits
            out = os.path.join(args.work, f"{tag}_no_upper.h5")
            _, log = vcheck.run_ictus(args, path, out, np=1,
                                      env={"ICTUS_MEMORY_LIMIT_MB": "0.001"})
            chk.true("full rows of K (its upper blocks would take more than half the memory "
                     "available)" in log, f"{tag}: K u from the full rows when memory is short")
            compare(chk, tag + " with the full rows", results[1], vcheck.Results(out), 1)
        if tag == "q4_empty_rank":
            owners = set(results[4].model("partition").tolist())
            chk.true(len(owners) < 4, f"{tag}: np = 4 leaves a rank without nodes (owners "
                     f"{sorted(owners)})")
        if tag == "hertz_iga_hrz_damped_sweep":
            chk.true("PATCH=UPPER" in text, f"{tag}: the damping acts on the upper body only")
            free = []
            for n in (2, 3, 4):
                x, owner = results[n].model("coordinates"), results[n].model("partition")
                free += [n for r in range(n) if not np.any((owner == r) & (x[:, 1] > 1e-9))]
            chk.true(len(free) > 0, f"{tag}: some rank holds no node of the damped body "
                     f"(np = {sorted(set(free))})")
        if tag.startswith("hertz"):
            x = results[4].model("coordinates")
            owner = results[4].model("partition")
            zone = (np.abs(x[:, 0]) < 1.5) & (np.abs(x[:, 1]) < 0.6)
            chk.true(len(set(owner[zone])) >= 2, f"{tag}: np = 4 partition cuts through the "
                     f"contact zone (ranks {sorted(set(owner[zone].tolist()))} there)")
            f = results[1].history("contact/hertz/force_first")
            chk.true(np.max(np.abs(f[:, 1])) > 50.0, f"{tag}: the bodies are in contact")
        if tag == "q8_kronecker_contact_fused":
            f = results[1].history("contact/iface/force_first")
            chk.true(np.max(np.abs(f[:, 1])) > 1.0, f"{tag}: the blocks are in contact "
                     f"(peak force {np.max(np.abs(f[:, 1])):.3g})")
    chk.finish()


if __name__ == "__main__":
    main()
