#!/usr/bin/python3
"""Runs every shipped deck and every verification case's decks with two ictus binaries and
compares the results files bit for bit (doc/testing.md, "Bit-identical results").

    /usr/bin/python3 scripts/bit_regression.py --old /path/to/old/ictus --new build/bin/ictus

The deck set:
  * input/**/*.inp that is a top-level deck: not an *INCLUDE fragment of another deck, and
    with a *STEP card. Each runs as `ictus deck -o <out>/<side>/input/<dir>/<name>.h5`
    (and, with --mpi-np N, also under `mpirun -np N` into <side>/mpi<N>/...).
  * every case registered in verification/CMakeLists.txt: its check.py runs as CTest runs
    it, with --work <out>/<side>/verify/<case> and --ictus pointing at a small logging shim
    in front of the binary. So the decks are generated exactly as the case generates them
    (inline, or with scripts/mesh/*.py), and the runs are exactly the case's runs: their
    rank counts (mpirun -np N), environment (ICTUS_MEMORY_LIMIT_MB), --restart and
    --wall-time chains (scripts/cluster/ictus-job.sh), --check runs and the runs expected to
    fail. The shim logs every ictus invocation with its exit status; the case's own
    checks run too, but their verdict is not used (a check that stops the case early shows
    up as runs and files missing on one side).

Verdicts, one table row per run (a --wall-time run and the --restart runs that continue it
into the same results file are one row, "(+ restarts)": how many segments it takes depends
on the clock):
  * `identical`: same exit status, and every results file the run left (results, its
    checkpoint, the XDMF sidecar) is identical by scripts/compare_results.py; `identical (its
    file is compared after a later run)` when a later run writes the same file. A run expected
    to fail counts as identical when both binaries give the same exit status (exit 1: no
    file on either side; exit 2: the partial results must be identical too).
  * `DIFFERENT`, `STATUS DIFFERS`, `MISSING` (a run one side did not make): failures.
  * `timing (status only)`: a run stopped by --wall-time (exit 3 on both sides) whose
    results nobody continued: where it stops depends on the clock, so only its exit status
    is compared. (A stopped run that is continued with --restart is compared through the
    continued, completed file.)
A results file written by several runs (a restart chain) is compared once, after the last.

Exit status 0 when every row is identical (or timing), 1 otherwise.
Needs numpy and h5py: run with /usr/bin/python3.
"""
import argparse
import concurrent.futures
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import compare_results  # noqa: E402

MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "OMPI_MCA_rmaps_base_oversubscribe": "1"}
# environment variables of ictus itself worth showing in a row's name (ictus-job.sh's own
# ICTUS, ICTUS_LAUNCH, ICTUS_WALL and ICTUS_RESUBMIT are not read by ictus)
SHOWN_ENV = ("ICTUS_MEMORY_LIMIT_MB",)
# verification cases that take long, skipped by --quick: verify/parallel runs 19 decks on
# 1-4 ranks (about 95 runs, 95 s per binary on 2 cores: with --jobs 2 the set takes 112 s
# instead of 255 s)
SLOW_CASES = ("parallel",)
COMPARED = []  # (results file, datasets) of every pair compared

# The shim logs an "S" line (rank 0, before the run: key, start time, ranks, folder, ictus
# variables, arguments) and an "E" line per rank after it (key, exit status, end time). Every
# rank writes its own E line because mpirun kills the other ranks as soon as one exits with a
# non-zero status (exit 3 at the wall-time limit), sometimes before they can write anything.
SHIM = r"""#!/bin/bash
# written by scripts/bit_regression.py: runs ictus, logs its arguments and exit status
key=${{PMIX_NAMESPACE:-$$}}  # the same on every rank of one mpirun
if [ "${{OMPI_COMM_WORLD_RANK:-0}}" = 0 ]; then
  line="S	$key	$(date +%s.%N)	${{OMPI_COMM_WORLD_SIZE:-0}}	$PWD"
  for e in {envs}; do line="$line	ENV:$e"; done
  for a in "$@"; do line="$line	$a"; done
  printf '%s\n' "$line" >> {log}
fi
timeout -k 5 {timeout} {real} "$@"
rc=$?
printf 'E\t%s\t%s\t%s\n' "$key" "$rc" "$(date +%s.%N)" >> {log}
exit $rc
"""


class Run:
    """One ictus invocation: exit status, time, rank count, arguments, results path."""

    def __init__(self, status, seconds, np, cwd, env, args):
        self.status, self.seconds, self.np, self.cwd, self.env, self.args = \
            status, seconds, np, cwd, env, args
        self.deck = next((a for a in args if a.endswith(".inp")), "")
        self.out = None
        for i, a in enumerate(args):
            if a in ("-o", "--output") and i + 1 < len(args):
                self.out = args[i + 1]
        if self.out is None and self.deck and "--check" not in args:
            self.out = re.sub(r"\.[^./]*$", "", self.deck) + ".h5"
        if self.out is not None and not os.path.isabs(self.out):
            self.out = os.path.normpath(os.path.join(cwd, self.out))

    def label(self, work):
        parts = [os.path.basename(self.deck) or "(no deck)"]
        if self.out:
            parts.append("-o " + os.path.relpath(self.out, work))
        parts += [a for a in self.args if a in ("--check", "--restart", "--wall-time")]
        if self.np:
            parts.append(f"np {self.np}")
        parts += [f"{k}={v}" for k, v in self.env.items()]
        return " ".join(parts)


class Chain:
    """Consecutive runs of one deck into one results file, each but the last stopped at
    its wall-time limit (exit 3) and continued with --restart: one logical run. How many
    segments it takes depends on the clock, so only the first run's arguments name it and
    only the last status counts."""

    def __init__(self, run):
        self.runs = [run]

    @property
    def first(self):
        return self.runs[0]

    @property
    def status(self):
        return self.runs[-1].status

    @property
    def seconds(self):
        return sum(r.seconds for r in self.runs)

    @property
    def out(self):
        return self.first.out

    def label(self, work):
        return self.first.label(work) + (" (+ restarts)" if len(self.runs) > 1 else "")

    def status_text(self):
        """The segments' statuses, repeats folded: "3x6,0"."""
        parts = []
        for r in self.runs:
            t = status_text(r.status)
            if parts and parts[-1][0] == t:
                parts[-1][1] += 1
            else:
                parts.append([t, 1])
        return ",".join(t if n == 1 else f"{t}x{n}" for t, n in parts)

    def stopped_by_clock(self):
        return self.status == 3 and any("--wall-time" in r.args for r in self.runs)


def chains(runs):
    out = []
    for r in runs:
        c = out[-1] if out else None
        if (c and c.status == 3 and "--restart" in r.args and r.deck == c.first.deck
                and r.out == c.out):
            c.runs.append(r)
        else:
            out.append(Chain(r))
    return out


def status_text(s):
    return {None: "none", 124: "timeout", 137: "killed"}.get(s, str(s))


def is_fragment(path, included):
    text = open(path, errors="replace").read()
    return os.path.abspath(path) in included or not re.search(r"^\*STEP\b", text, re.M | re.I)


def shipped_decks():
    """Top-level decks of input/: neither included by another deck nor without *STEP."""
    decks, included = [], set()
    for dirpath, _, files in os.walk(os.path.join(ROOT, "input")):
        for f in files:
            if f.lower().endswith(".inp"):
                p = os.path.join(dirpath, f)
                decks.append(p)
                for m in re.finditer(r"^\*INCLUDE\b.*INPUT\s*=\s*([^,\s]+)",
                                     open(p, errors="replace").read(), re.M | re.I):
                    included.add(os.path.abspath(os.path.join(dirpath, m.group(1))))
    return sorted(os.path.relpath(p, ROOT) for p in decks if not is_fragment(p, included))


def verification_cases():
    text = open(os.path.join(ROOT, "verification", "CMakeLists.txt")).read()
    text = re.sub(r"(?s)function\(.*?endfunction\(\)", "", text)
    return re.findall(r"^\s*ictus_add_verification\((\w+)", text, re.M)


class Runner:
    def __init__(self, a, out):
        self.a, self.out = a, out
        self.env = dict(os.environ, **MPI_ENV)
        self.lock = threading.Lock()
        self.children = set()
        self.check_status = {}

    def call(self, cmd, cwd, log, timeout):
        """Runs cmd in its own process group, output to log; returns (status, seconds)."""
        t0 = time.time()
        with open(log, "w") as f:
            p = subprocess.Popen(cmd, cwd=cwd, stdout=f, stderr=subprocess.STDOUT,
                                 stdin=subprocess.DEVNULL, env=self.env, start_new_session=True)
            with self.lock:
                self.children.add(p)
            try:
                status = p.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait()
                status = 124
                f.write(f"\nbit_regression: killed after {timeout} s\n")
            with self.lock:
                self.children.discard(p)
        return status, time.time() - t0

    def kill_all(self):
        with self.lock:
            for p in self.children:
                try:
                    os.killpg(p.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass

    def deck_task(self, side, binary, deck, np):
        sub = f"mpi{np}" if np else ""
        rel = os.path.splitext(deck)[0] + ".h5"
        res = os.path.join(self.out, side, sub, rel)
        os.makedirs(os.path.dirname(res), exist_ok=True)
        for p in (res, res[:-3] + ".chk.h5", res[:-3] + ".xdmf"):
            if os.path.exists(p):
                os.remove(p)
        launch = ["mpirun", "--oversubscribe", "-np", str(np)] if np else []
        status, secs = self.call(launch + [binary, os.path.join(ROOT, deck), "-o", res],
                                 os.path.dirname(os.path.join(ROOT, deck)), res[:-3] + ".log",
                                 self.a.timeout)
        run = Run(status, secs, np, ROOT, {}, [deck, "-o", res])
        return [run], secs

    def case_task(self, side, binary, case):
        work = os.path.join(self.out, side, "verify", case)
        if os.path.exists(work):
            shutil.rmtree(work)
        os.makedirs(work)
        shim_dir = os.path.join(self.out, side, "shim", case)
        os.makedirs(shim_dir, exist_ok=True)
        log = os.path.join(shim_dir, "runs.tsv")
        shim = os.path.join(shim_dir, "ictus")
        envs = " ".join(f'"{k}=${{{k}:-}}"' for k in SHOWN_ENV)
        with open(shim, "w") as f:
            f.write(SHIM.format(timeout=int(self.a.timeout), real=shlex.quote(binary),
                                log=shlex.quote(log), envs=envs))
        os.chmod(shim, 0o755)
        cmd = ["/usr/bin/python3", os.path.join(ROOT, "verification", case, "check.py"),
               "--ictus", shim, "--work", work, "--mpirun", "mpirun"]
        # the case as a whole: many runs, so a generous multiple of the per-run limit
        status, secs = self.call(cmd, work, os.path.join(shim_dir, "check.log"),
                                 self.a.timeout * 20)
        runs, latest, ends = [], {}, []
        # an E line belongs to the latest S line of its key before it (keys may be reused)
        for line in open(log).read().splitlines() if os.path.exists(log) else []:
            f = line.split("\t")
            if f[0] == "S":
                env = {}
                for e in f[5:]:
                    if e.startswith("ENV:") and "=" in e and not e.endswith("="):
                        k, v = e[4:].split("=", 1)
                        env[k] = v
                args = [e for e in f[5:] if not e.startswith("ENV:")]
                latest[f[1]] = len(runs)
                runs.append(Run(None, 0.0, int(f[3]), f[4], env, args))
                ends.append((float(f[2]), None))
            elif f[0] == "E" and f[1] in latest:
                i = latest[f[1]]
                st, prev = int(f[2]), runs[i].status
                # the ranks' statuses: the first non-zero one (mpirun kills the others, 137,
                # or they never write), else 0
                if prev is None or (prev == 0 and st != 0) or prev == 137:
                    runs[i].status = st
                    runs[i].seconds = float(f[3]) - ends[i][0]
        self.check_status[(side, case)] = status
        return runs, secs


def _compare_file(name, f, work_o, work_n, ignore, details):
    """Compares one results file (relative path) of the two sides: (verdict, failed)."""
    a, b = os.path.join(work_o, f), os.path.join(work_n, f)
    if not os.path.exists(a) and not os.path.exists(b):
        return "identical", False
    if os.path.exists(a) != os.path.exists(b):
        details.append(f"{name}: {f} only in {'old' if os.path.exists(a) else 'new'}")
        return f"DIFFERENT ({f} only on one side)", True
    diffs, counts = compare_results.compare_files(a, b, ignore)
    COMPARED.append((f, counts["datasets"]))
    if not diffs:
        return "identical", False
    buf = _Buf()
    compare_results.verdict(f"{name}: {f}", diffs, counts, out=buf)
    details.append(buf.text.rstrip())
    return f"DIFFERENT ({len(diffs)} difference{'s' if len(diffs) > 1 else ''})", True


def compare_unit(unit, old, new, ignore, details, scan=True):
    """Rows (name, old status, new status, verdict, failed, old s, new s) of one unit: one
    per logical run (Chain), then one per results file no run wrote (scan=True)."""
    rows = []
    (runs_o, work_o), (runs_n, work_n) = old, new
    co, cn = chains(runs_o), chains(runs_n)

    def rel(path, work):
        return os.path.relpath(path, work) if path else None

    # a results file is compared after the last run that writes it (exit 1 writes nothing)
    last_writer = {}
    for i, c in enumerate(co):
        if c.out and c.status != 1:
            last_writer[rel(c.out, work_o)] = i
    compared = set()
    for i in range(max(len(co), len(cn))):
        o = co[i] if i < len(co) else None
        n = cn[i] if i < len(cn) else None
        ref, wref = (o, work_o) if o else (n, work_n)
        name = unit if unit.startswith("input") and len(co) == 1 else \
            f"{unit} #{i + 1} {ref.label(wref)}"
        so = o.status_text() if o else "-"
        sn = n.status_text() if n else "-"
        t = ((o.seconds if o else 0.0), (n.seconds if n else 0.0))
        if o is None or n is None:
            rows.append((name, so, sn, "MISSING on " + ("new" if n is None else "old"), True)
                        + t)
            continue
        if o.label(work_o) != n.label(work_n):
            rows.append((name, so, sn, "MISSING (new ran: " + n.label(work_n) + ")", True) + t)
            continue
        if o.status != n.status:
            rows.append((name, so, sn, "STATUS DIFFERS", True) + t)
            continue
        out = rel(o.out, work_o)
        if not out or last_writer.get(out) != i:
            rows.append((name, so, sn, "identical" if not out or o.status == 1 else
                         "identical (its file is compared after a later run)", False) + t)
            continue
        chk = (out[:-3] if out.endswith(".h5") else out) + ".chk.h5"
        compared.update((out, chk))
        if o.stopped_by_clock():
            rows.append((name, so, sn, "timing (status only)", False) + t)
            continue
        verdict, failed = "identical", False
        for f in (out, chk):
            v, bad = _compare_file(name, f, work_o, work_n, ignore, details)
            if bad:
                verdict, failed = v, True
        rows.append((name, so, sn, verdict, failed) + t)
    if not scan:
        return rows
    # results files that no run of ictus wrote (left by the case itself)
    files = set(compare_results.results_files(work_o)) | set(compare_results.results_files(work_n))
    for f in sorted(files - compared):
        name = f"{unit} file {f}"
        verdict, failed = _compare_file(name, f, work_o, work_n, ignore, details)
        rows.append((name, "-", "-", verdict, failed, 0.0, 0.0))
    return rows


class _Buf:
    def __init__(self):
        self.text = ""

    def write(self, s):
        self.text += s


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--old", required=True, help="ictus binary of the reference commit")
    ap.add_argument("--new", required=True, help="ictus binary to check")
    ap.add_argument("--jobs", type=int, default=1, help="runs at a time (default 1)")
    ap.add_argument("--filter", default="", metavar="REGEX",
                    help="only units whose name (input/<dir>/<deck>.inp, verify/<case>) "
                         "matches REGEX (re.search)")
    ap.add_argument("--mpi-np", type=int, default=0, metavar="N",
                    help="also run every shipped deck under mpirun -np N")
    ap.add_argument("--timeout", type=float, default=600.0,
                    help="seconds per ictus run (default 600); a verification case as a "
                         "whole gets 20 times this")
    ap.add_argument("--out", default="", help="output folder (default: a new temporary one)")
    ap.add_argument("--keep", action="store_true",
                    help="keep the outputs (they are also kept when anything differs)")
    ap.add_argument("--ignore-attr", action="append", default=[], metavar="NAME",
                    help="also ignore attributes of this name (see compare_results.py)")
    ap.add_argument("--no-verification", action="store_true",
                    help="only the shipped decks of input/")
    ap.add_argument("--quick", action="store_true",
                    help="skip the slow verification cases: " + ", ".join(
                        "verify/" + c for c in SLOW_CASES))
    a = ap.parse_args()
    for b in (a.old, a.new):
        if not os.access(b, os.X_OK):
            ap.error(f"not an executable: {b}")
    old, new = os.path.abspath(a.old), os.path.abspath(a.new)
    out = os.path.abspath(a.out) if a.out else tempfile.mkdtemp(prefix="ictus-bits-")
    os.makedirs(out, exist_ok=True)
    runner = Runner(a, out)

    units = []  # (name, kind, arg)
    for d in shipped_decks():
        units.append((d, "deck", (d, 0)))
        if a.mpi_np:
            units.append((f"{d}@np{a.mpi_np}", "deck", (d, a.mpi_np)))
    if not a.no_verification:
        units += [(f"verify/{c}", "case", c) for c in verification_cases()
                  if not (a.quick and c in SLOW_CASES)]
    units = [u for u in units if re.search(a.filter, u[0])]
    if not units:
        ap.error("no deck matches the filter")
    n_decks = sum(u[1] == "deck" for u in units)
    print(f"bit_regression: {n_decks} shipped deck run(s), {len(units) - n_decks} verification "
          f"case(s); old {old}; new {new}; outputs in {out}; {a.jobs} job(s)", flush=True)

    tasks = [(u, side, binary) for u in units for side, binary in (("old", old), ("new", new))]
    # the verification cases first (the longest), so that short runs fill the gaps
    tasks.sort(key=lambda t: t[0][1] != "case")
    results = {}
    t_start = time.time()

    def work(task):
        (name, kind, arg), side, binary = task
        if kind == "deck":
            runs, secs = runner.deck_task(side, binary, *arg)
            wdir = os.path.join(out, side, f"mpi{arg[1]}" if arg[1] else "")
        else:
            runs, secs = runner.case_task(side, binary, arg)
            wdir = os.path.join(out, side, "verify", arg)
        return name, side, runs, wdir, secs

    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
            for name, side, runs, wdir, secs in pool.map(work, tasks):
                results[(name, side)] = (runs, wdir, secs)
                check = runner.check_status.get((side, name[len("verify/"):]))
                print(f"  ran {name} ({side}): {len(runs)} ictus run(s), {secs:.1f} s"
                      + ("" if check is None else f"; check.py exit {check} (not used)"),
                      flush=True)
    except KeyboardInterrupt:
        runner.kill_all()
        raise
    elapsed = time.time() - t_start

    rows, details = [], []
    ignore = set(a.ignore_attr)
    for name, kind, arg in units:
        ro, rn = results[(name, "old")], results[(name, "new")]
        # (a deck's output folder holds the other decks' files too: no scan there)
        rows += compare_unit(name, ro[:2], rn[:2], ignore, details, scan=kind == "case")

    head = ("deck", "old", "new", "verdict", "old s", "new s")
    table = [(r[0], r[1], r[2], r[3], f"{r[5]:.1f}", f"{r[6]:.1f}") for r in rows]
    width = [max(len(x[i]) for x in table + [head]) for i in range(len(head))]
    print()
    print("| " + " | ".join(h.ljust(w) for h, w in zip(head, width)) + " |")
    print("|" + "|".join("-" * (w + 2) for w in width) + "|")
    for row in table:
        print("| " + " | ".join(c.rjust(w) if i >= 4 else c.ljust(w)
                                for i, (c, w) in enumerate(zip(row, width))) + " |")
    bad = [r for r in rows if r[4]]
    timing = sum(r[3].startswith("timing") for r in rows)
    if details:
        print("\nDifferences:")
        for d in details:
            print(d)
    n_runs = sum(len(results[(u[0], "old")][0]) for u in units)
    print(f"\nbit_regression: {len(rows)} rows ({n_runs} ictus runs per binary in "
          f"{len(units)} units), {len(rows) - len(bad)} identical"
          + (f" ({timing} compared by exit status only: stopped by --wall-time)" if timing else "")
          + f", {len(bad)} differ; {len(COMPARED)} pairs of results files compared "
          f"({sum(n for _, n in COMPARED)} datasets); runs {elapsed:.0f} s + comparison "
          f"{time.time() - t_start - elapsed:.0f} s wall time with {a.jobs} job(s)")
    if a.keep or bad:
        print(f"bit_regression: outputs kept in {out}")
    else:
        shutil.rmtree(out, ignore_errors=True)
    print("BIT REGRESSION: " + ("IDENTICAL" if not bad else "DIFFERENT"))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
