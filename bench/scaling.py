#!/usr/bin/python3
"""Strong and weak scaling of the Hertz step with contact on this machine (issue #31 item 5;
doc/scaling.md).

For each size (elements of the two half-discs together) and each number of ranks:
- build/bin/ictus-bench on the deck (no output): the STREAM triad of that many ranks at once,
  the step's kernels and the contact correction per step (t_contact: every rank evaluates
  every contact point, after an all-reduce of the contact nodes' coordinates);
- build/bin/ictus --check: the peak resident memory of every rank (model, K, M, contact; no
  stepper, no results);
- build/bin/ictus with history every step (as users run it) and with history every 1e8
  steps (the record's cost), fields every 1 % of the user's run as bench/real.py writes them:
  the time loop in ns per element-step from the log's progress lines (snapshots taken off),
  and the peak resident memory of every rank.
The decks are bench/real.py's (scripts/mesh/hertz.py: two half-discs, NURBS p = 2 or Q8,
HRZ lumped mass, TWO HALF PASS contact active from the first step).

The load average (1 minute) is printed beside every run: the host has 2 cores and other work
runs on it; a run that starts above --max-load waits up to --wait s for the load to fall
and is repeated once when the load at its end, less its own ranks' share, is above
--max-load.

    /usr/bin/python3 bench/scaling.py --sizes 1e5,2e5 --ranks 1,2
"""
import argparse
import math
import os
import shutil
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import benchmark as bm  # noqa: E402
import real  # noqa: E402


def quiet(args):
    """Waits (up to args.wait s) for the 1-minute load to fall below args.max_load; returns
    the load at the start."""
    t0 = time.time()
    while bm.loadavg() > args.max_load and time.time() - t0 < args.wait:
        time.sleep(5)
    return bm.loadavg()


def timed(args, what, fn, ranks):
    """fn() with the load before and after; repeated once when the load at the end is above
    args.max_load (less the part of the load that the run's own ranks add). Returns (result,
    load before, load after, tries)."""
    for tries in (1, 2):
        l0 = quiet(args)
        t0 = time.time()
        out = fn()
        l1 = bm.loadavg()
        # the 1-minute average at the end includes this run's own ranks: about
        # ranks (1 - exp(-wall/60)) of it
        own = ranks * (1.0 - math.exp(-(time.time() - t0) / 60.0))
        print(f"    {what}: load {l0:.2f} -> {l1:.2f} (own ranks ~{own:.2f})", flush=True)
        if l0 <= args.max_load and l1 - own <= args.max_load:
            break
    return out, l0, l1, tries


def run_one(args, work, kind, size, ranks):
    case = f"hertz-{kind}"
    model = os.path.join(work, f"{case}-{size:g}_model.inp")
    if not os.path.exists(model):
        nel, _ = real.hertz_model(model, case, size)
        with open(model + ".info", "w") as f:
            f.write(f"{nel}\n")
    with open(model + ".info") as f:
        nel = int(f.read().split()[0])
    deck = os.path.join(work, f"{case}-{size:g}-np{ranks}.inp")
    res = {"nel": nel, "ranks": ranks, "size": size, "loads": []}
    # kernels, STREAM and dt (no output)
    real.step_deck(deck, model, False, real.T_USER["hertz"], real.T_USER["hertz"], 1)
    b, l0, l1, _ = timed(args, f"{case} {nel} el. np={ranks} ictus-bench", lambda: bm.run_bench(
        args, deck, nel, False, ranks, steps=max(8, min(40, round(2e6 / nel)))), ranks)
    res["bench"], res["loads"] = b, [l0, l1]
    # --check: model, K, M and contact
    (_, _, pk), l0, l1, _ = timed(args, "ictus --check", lambda: real.run_ictus(
        args, deck, ranks, ["--check"]), ranks)
    res["check_peaks"] = pk
    res["loads"] += [l0, l1]
    for name, every in (("on", 1), ("off", real.HIST_OFF)):
        real.step_deck(deck, model, False, args.steps * b["dt"], real.T_USER["hertz"], every)
        (log, wall, pk), l0, l1, _ = timed(args, f"ictus history every {every}",
                                           lambda: real.run_ictus(args, deck, ranks), ranks)
        if args.keep_logs:
            with open(deck[:-4] + f"-{name}.log", "w") as f:
                f.write(log)
        d = real.parse_log(log, real.T_USER["hertz"] / 100)
        d["wall"], d["peaks"] = wall, pk
        res[name] = d
        res["loads"] += [l0, l1]
    return res


HEAD = ["case", "np", "elements", "contact pts", "STREAM GB/s", "step (hist)", "step (off)",
        "x np (hist)", "x np (off)", "K u", "contact us/step", "ns/contact pt",
        "check MB/rank", "run MB/rank", "load"]


def row(kind, r):
    b, nel, p = r["bench"], r["nel"], r["ranks"]
    on, off = 1e9 * r["on"]["t_loop"] / nel, 1e9 * r["off"]["t_loop"] / nel
    cp = int(b["contact_points"])
    return [f"hertz-{kind}", f"{p}", f"{nel}", f"{cp}", f"{b['stream'] / 1e9:.1f}",
            f"{on:.1f}", f"{off:.1f}", f"{on * p:.1f}", f"{off * p:.1f}",
            f"{1e9 * b['t_kmv'] / nel:.1f}", f"{1e6 * b['t_contact']:.1f}",
            f"{1e9 * b['t_contact'] / cp:.0f}" if cp else "-",
            "/".join(f"{x / 1e6:.0f}" for x in r["check_peaks"]),
            "/".join(f"{x / 1e6:.0f}" for x in r["on"]["peaks"]),
            f"{min(r['loads']):.2f}-{max(r['loads']):.2f}"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="1e5,2e5")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--kinds", default="iga",
                    help="iga, q8, iga-wall (one half-disc on a rigid wall: METIS splits it)")
    ap.add_argument("--steps", type=int, default=500, help="steps of each ictus run")
    ap.add_argument("--repeat", type=int, default=3, help="ictus-bench --repeat")
    ap.add_argument("--stream-mb", type=int, default=256)
    ap.add_argument("--build-dir", default=os.path.join(bm.ROOT, "build"))
    ap.add_argument("--mpirun", default=shutil.which("mpirun"))
    ap.add_argument("--work", help="keep the decks (and logs) here")
    ap.add_argument("--keep-logs", action="store_true")
    ap.add_argument("--max-load", type=float, default=1.5)
    ap.add_argument("--wait", type=float, default=120.0,
                    help="seconds to wait for the load to fall before a run")
    args = ap.parse_args()
    sizes = [float(s) for s in args.sizes.split(",")]
    ranks = [int(p) for p in args.ranks.split(",")]
    work = args.work or tempfile.mkdtemp(prefix="ictus-scaling-")
    os.makedirs(work, exist_ok=True)
    rows = []
    t0 = time.time()
    try:
        for kind in args.kinds.split(","):
            for size in sizes:
                for p in ranks:
                    r = run_one(args, work, kind, size, p)
                    rows.append(row(kind, r))
                    print("  " + " | ".join(rows[-1]), flush=True)
    finally:
        if not args.work:
            shutil.rmtree(work, ignore_errors=True)
    print()
    print(f"{os.cpu_count()} CPUs, {time.time() - t0:.0f} s. ns per element-step of the "
          "ictus time loop (snapshots taken off): 'hist' history every step, 'off' every 1e8 "
          "steps; 'x np' that times the ranks (constant = perfect scaling); 'K u' and "
          "'contact' from ictus-bench (no output), contact = the correction per step on one "
          "rank (every rank evaluates every point); peaks per rank (VmHWM); load: the 1-minute "
          "load average over the runs of the row")
    bm.print_table(rows, HEAD)


if __name__ == "__main__":
    main()
