#!/usr/bin/env python3
"""Restart: a run stopped at a wall-time limit and continued from its checkpoint, by the
cluster job logic (scripts/cluster/ictus-job.sh), on a different number of ranks, finishes
with a results file identical to an uninterrupted run; a leftover partial checkpoint does not
matter; a checkpoint of another deck is refused. The same identity holds for a damped
relaxation whose steps between records run as sweeps of several steps (the damping work
crosses the restart in the checkpoint).

Deck: the dynamic Hertz problem (NURBS, HRZ, 8 x 8 spans, contact), 1800 steps, with
*RESTART, WRITE, EVERY=200. Identity is checked dataset by dataset, to the bit (ictus keeps the
whole time-loop state in the checkpoint, including the conjugate-gradient warm starts and the
last contact results, and all its sums are reproducible on any number of ranks).
"""
import os
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

sys.path.insert(0, os.path.join(vcheck.ROOT, "scripts", "mesh"))
import hertz  # noqa: E402


def same_results(chk, ref, other, label):
    a, b = ref.f, other.f
    names = []
    a.visit(lambda k: names.append(k) if hasattr(a[k], "shape") else None)
    names = [k for k in names if k not in ("model/partition", "model/element_partition")]
    extra = []
    b.visit(lambda k: extra.append(k) if hasattr(b[k], "shape") and k not in a else None)
    bad = [k for k in names if k not in b or not np.array_equal(np.asarray(a[k]), np.asarray(b[k]))]
    for k in bad[:10]:
        print(f"    differs: {k}")
    chk.true(not bad and not extra, f"{label}: all {len(names)} datasets identical to the "
             f"uninterrupted run ({len(bad)} differ, {len(extra)} extra)")
    chk.true(other.attr("status") == "completed", f"{label}: status completed")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("restart")
    text = hertz.deck(hertz.options(kind="iga", mass="HRZ", subdivide=8, t_end=0.9,
                                    field_every=150), "verification/restart")
    text = text.replace("*END STEP", "*RESTART, WRITE, EVERY=200\n*END STEP")
    deck = os.path.join(args.work, "hertz.inp")
    with open(deck, "w") as f:
        f.write(text)
    ref_out = os.path.join(args.work, "ref.h5")
    _, log = vcheck.run_ictus(args, deck, ref_out, np=1)
    ref = vcheck.Results(ref_out)
    # a budget of a third of the uninterrupted run's time loop: a few segments in any build
    loop = float(re.search(r"wall time: ([0-9.eE+-]+) s", log).group(1))
    budget = f"{max(loop / 3.0, 0.01):.4f}"

    # the chained job: segments of a small wall-time budget on 2 ranks, continued on 3
    out = os.path.join(args.work, "chained.h5")
    for p in (out, out[:-3] + ".chk.h5"):
        if os.path.exists(p):
            os.remove(p)
    env = dict(os.environ, ICTUS=args.ictus, ICTUS_WALL=budget,
               ICTUS_LAUNCH=f"{args.mpirun} --oversubscribe -np 2")
    job = os.path.join(vcheck.ROOT, "scripts", "cluster", "ictus-job.sh")
    # first segment alone (it queues nothing: ICTUS_RESUBMIT=true only reports), then the rest
    env1 = dict(env, ICTUS_RESUBMIT="true")
    p = subprocess.run(["bash", job, deck, out], env=env1, text=True, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT)
    stopped = "wall-time limit reached" in p.stdout
    chk.true(p.returncode == 0 and stopped and os.path.exists(out[:-3] + ".chk.h5"),
             "first segment stops at the wall-time limit with a checkpoint")
    partial = vcheck.Results(out)
    chk.true(partial.attr("status").startswith("stopped at the wall-time limit"),
             "the stopped run's results say so and how to continue")
    partial.f.close()
    # a leftover partial checkpoint from a run killed while writing must not matter
    with open(out[:-3] + ".chk.h5.tmp", "wb") as f:
        f.write(b"\x89HDF\r\n\x1a\n truncated")
    env3 = dict(env, ICTUS_LAUNCH=f"{args.mpirun} --oversubscribe -np 3")
    p = subprocess.run(["bash", job, deck, out], env=env3, text=True, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT)
    segments = p.stdout.count("continues from")
    print(f"  (the chain ran {segments} more segment(s) on 3 ranks)")
    chk.true(p.returncode == 0 and "completed" in p.stdout, "the chain completes")
    chk.true(not os.path.exists(out[:-3] + ".chk.h5"), "the checkpoint is removed at the end")
    same_results(chk, ref, vcheck.Results(out), "chained run (np 2 then 3)")

    # damped sweeps across a restart: the static Hertz relaxation (Q8, *DAMPING, a rigid wall)
    # recording every 10 steps, so that the damped steps in between run as sweeps of 6 steps;
    # with a node-set history and field snapshots at a time interval, which the continued
    # run must cut back and carry on as well
    damped = open(os.path.join(vcheck.ROOT, "input", "hertz", "static_q8.inp")).read()
    for old, new in (("*DYNAMIC, EXPLICIT\n", "*DYNAMIC, EXPLICIT, SWEEP STEPS=6\n"),
                     ("HISTORY, EVERY=1\n", "HISTORY, EVERY=10\n*OUTPUT, HISTORY, NSET=UPPER_TOP\n"),
                     ("FIELD, EVERY=1000\n", "FIELD, TIME INTERVAL=0.35\n"),
                     ("*END STEP", "*RESTART, WRITE, EVERY=100\n*END STEP")):
        chk.true(damped.count(old) == 1, f"damped deck: {old.strip()!r} found once")
        damped = damped.replace(old, new)
    ddeck = os.path.join(args.work, "damped.inp")
    with open(ddeck, "w") as f:
        f.write(damped)
    dref_out = os.path.join(args.work, "damped_ref.h5")
    _, log = vcheck.run_ictus(args, ddeck, dref_out, np=1)
    chk.true("sweeps: 6 steps per sweep" in log, "damped relaxation runs sweeps of 6 steps")
    dloop = float(re.search(r"wall time: ([0-9.eE+-]+) s", log).group(1))
    dout = os.path.join(args.work, "damped.h5")
    for p in (dout, dout[:-3] + ".chk.h5"):
        if os.path.exists(p):
            os.remove(p)
    vcheck.run_ictus(args, ddeck, dout, np=1, extra=["--wall-time", f"{max(dloop / 3.0, 0.01):.4f}"],
                     expect_status=3)
    vcheck.run_ictus(args, ddeck, dout, np=1, extra=["--restart", dout[:-3] + ".chk.h5"])
    dref = vcheck.Results(dref_out)
    chk.true(dref.history("energy/external_work")[-1] < 0.0, "the damping does work")
    chk.true(dref.history("nset/upper_top/velocity").shape == dref.history("time").shape + (2,),
             "the node-set history has one record per history record")
    same_results(chk, dref, vcheck.Results(dout), "damped sweeps, stopped and restarted")

    # a checkpoint of another deck is refused (exit 1, message), nothing is overwritten
    vcheck.run_ictus(args, deck, os.path.join(args.work, "periodic.h5"), np=1,
                     extra=["--wall-time", budget], expect_status=3)
    other = text.replace("0.9\n", "0.8\n", 1)
    other_deck = os.path.join(args.work, "other.inp")
    with open(other_deck, "w") as f:
        f.write(other)
    _, log = vcheck.run_ictus(args, other_deck, os.path.join(args.work, "periodic.h5"),
                              extra=["--restart", os.path.join(args.work, "periodic.chk.h5")],
                              expect_status=1)
    chk.true("different deck" in log, "a checkpoint of another deck is refused")
    # ... also when only its bulk data differ (one control point moved by one ulp): the
    # checkpoint compares a digest of the data the record keeps in /deck (doc/parallel.md)
    head, tail = text.split("*CONTROL POINTS\n", 1)
    first, rest = tail.split("\n", 1)
    vals = [float(v) for v in first.split(",")]
    k = next(i for i, v in enumerate(vals) if v != 0.0)
    vals[k] = float(np.nextafter(vals[k], np.inf))
    moved_deck = os.path.join(args.work, "moved.inp")
    with open(moved_deck, "w") as f:
        f.write(head + "*CONTROL POINTS\n" + ", ".join(repr(v) for v in vals) + "\n" + rest)
    _, log = vcheck.run_ictus(args, moved_deck, os.path.join(args.work, "periodic.h5"),
                              extra=["--restart", os.path.join(args.work, "periodic.chk.h5")],
                              expect_status=1)
    chk.true("different deck" in log, "a checkpoint of a deck with one control point moved "
             "by one ulp is refused")
    # a file that is not a checkpoint, and a results path that cannot be written: exit 1
    junk = os.path.join(args.work, "junk.chk.h5")
    with open(junk, "w") as f:
        f.write("not HDF5\n")
    _, log = vcheck.run_ictus(args, deck, os.path.join(args.work, "periodic.h5"),
                              extra=["--restart", junk], expect_status=1)
    chk.true("cannot open the checkpoint" in log and "HDF5-DIAG" not in log,
             "a file that is not a checkpoint is refused with one clear message")
    _, log = vcheck.run_ictus(args, deck, os.path.join(args.work, "no", "such", "dir.h5"),
                              expect_status=1)
    chk.true("cannot create this results file" in log and "HDF5-DIAG" not in log,
             "an unwritable results path is refused with one clear message")
    chk.finish()


if __name__ == "__main__":
    main()
