#!/usr/bin/python3
"""The performance benchmark of ictus (doc/performance.md).

    bench/benchmark.py [--quick] [--sizes 1e4,1e5,1e6] [--no-build] [--build-dir DIR]
                         [--work DIR] [--repeat R] [--steps N] [--no-mpi] [--cases LIST]
    bench/benchmark.py --suite real [--sizes 1e5,1e6] [...]   (bench/real.py: the runs users
                         make, timed through build/bin/ictus with their output)

Builds Release (scripts/setup.sh Release, unless --no-build), generates decks of growing size
in a scratch directory (square meshes of about `size` elements: Q8 with HRZ lumping or a
consistent mass, one p = 2 NURBS patch with row-sum lumping or a consistent mass (solved by
the default MASS SOLVER=AUTO, which takes the 1D factors along the lattice directions on these
meshes; *-consistent-cholesky: by the Cholesky factor; iga-corrector: applied by 2 corrector
passes; *-damped, asked for by --cases: the lumped case with mass-proportional damping), and
the same square cut into two stacked blocks pressed together by a *CONTACT PAIR), runs
build/bin/ictus-bench on each (and `mpirun -np 2` on the largest lumped meshes) and prints:

- per case and size: ns per element per step for the whole step and its phases (stiffness
  product K u, contact search and forces, mass solve, vector updates), the effective
  bandwidth of K u (bytes of the matrix and vectors it must move once / time), the STREAM
  triad bandwidth measured in the same run, and the ratios to it;
- the targets of doc/performance.md with the measured value and a verdict.
- warnings when the host's memory bandwidth moved during the run (host_checks).

The time step is the automatic one (0.9 * 2/omega_max, computed by ictus-bench) and the
bench starts from a rough velocity field, so a consistent-mass solve does the work it does in
a run. Timings are medians of --repeat sets (ictus-bench --repeat). Nothing is written but
the decks; no timing is asserted (the CTest smoke test only checks that the table appears).
"""
import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SCRIPTS = os.path.join(ROOT, "scripts")
E, NU, RHO = 1000.0, 0.3, 1.0
CASES = ["q8", "q8-consistent", "q8-contact", "iga", "iga-consistent", "iga-corrector",
         "iga-contact"]
# also accepted by --cases: the consistent mass solved by the conjugate gradient
EXTRA_CASES = ["q8-consistent-cg", "iga-consistent-cg", "q8-consistent-cholesky",
               "iga-consistent-cholesky", "q8-damped", "iga-damped", "q8-contact-mortar",
               "iga-contact-mortar"]
# *-contact-mortar: the contact case with ALGORITHM=MORTAR
# *-damped: the lumped case with mass-proportional damping (*DAMPING, ALPHA=DAMPING_ALPHA)
DAMPING_ALPHA = 1.0
# the consistent-mass solvers as ictus-bench reports them (MASS_SOLVER_* of src/solver/model.f90)
SOLVERS = {1: "CG", 2: "Cholesky", 3: "corrector", 4: "Kronecker"}
# Open MPI refuses to run as root without these (containers, CI)
MPI_ENV = dict(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


# ---------------------------------------------------------------- decks

def header(title, mass):
    return (f"*HEADING\n{title}\n*ANALYSIS, TYPE=PLANE STRAIN, THICKNESS=1\n"
            f"*MATERIAL, NAME=MAT\n*ELASTIC\n{E}, {NU}\n*DENSITY\n{RHO}\n"), f"*MASS, TYPE={mass}\n"


def step_cards(dt=0.0, t_end=1.0, solver=""):
    # dt = 0: ictus-bench takes the automatic step 0.9 * 2/omega_max; no output is asked for
    return (f"*STEP\n*DYNAMIC, EXPLICIT{solver}\n{dt!r}, {t_end!r}\n"
            "*OUTPUT, HISTORY, EVERY=100000000\n"
            "*OUTPUT, FIELD, EVERY=100000000\n*END STEP\n")


def q8_block(f, name, nx, ny, x0, y0, lx, ly, first_node, first_el):
    """Writes the *NODE and *ELEMENT cards of an nx x ny Q8 rectangle (numpy, fast) plus the
    node sets <name>_BOTTOM and <name>_LL. Returns (next node id, next element id, element
    ids of the bottom row, of the top row)."""
    mx, my = 2 * nx, 2 * ny
    jj, ii = np.meshgrid(np.arange(my + 1), np.arange(mx + 1), indexing="ij")
    keep = ~((ii % 2 == 1) & (jj % 2 == 1))
    idx = -np.ones((my + 1, mx + 1), dtype=np.int64)
    idx[keep] = first_node + np.arange(int(keep.sum()))
    xs = x0 + ii[keep] * (lx / mx)
    ys = y0 + jj[keep] * (ly / my)
    f.write("*NODE\n")
    np.savetxt(f, np.column_stack([idx[keep], xs, ys]), fmt="%d, %.15g, %.15g")
    ey, ex = np.meshgrid(np.arange(ny), np.arange(nx), indexing="ij")
    i, j = (2 * ex).ravel(), (2 * ey).ravel()
    conn = np.column_stack([idx[j, i], idx[j, i + 2], idx[j + 2, i + 2], idx[j + 2, i],
                            idx[j, i + 1], idx[j + 1, i + 2], idx[j + 2, i + 1], idx[j + 1, i]])
    eids = first_el + np.arange(nx * ny)
    f.write(f"*ELEMENT, TYPE=Q8, ELSET={name}, MATERIAL=MAT\n")
    np.savetxt(f, np.column_stack([eids, conn]), fmt="%d")
    f.write(f"*NSET, NSET={name}_BOTTOM\n")
    np.savetxt(f, idx[0, :].reshape(-1, 1), fmt="%d")
    f.write(f"*NSET, NSET={name}_LL\n{idx[0, 0]}\n")
    return int(idx.max()) + 1, int(eids[-1]) + 1, eids[:nx], eids[-nx:]


def iga_block(f, name, n1, n2, x0, y0, lx, ly):
    """A p = 2 NURBS patch of the rectangle refined to n1 x n2 spans, with node sets
    <name>_BOTTOM (side ETA0) and surfaces <name>_TOP/_BOTTOM (sides ETA1/ETA0)."""
    f.write(f"*PATCH, NAME={name}, MATERIAL=MAT, DEGREE=2,2, SIZE=3,3\n"
            "*KNOTS, DIRECTION=1\n0 0 0 1 1 1\n*KNOTS, DIRECTION=2\n0 0 0 1 1 1\n"
            "*CONTROL POINTS\n")
    for j in range(3):
        for i in range(3):
            f.write(f"{x0 + lx * i / 2!r}, {y0 + ly * j / 2!r}, 1.0\n")
    f.write(f"*REFINE, PATCH={name}, SUBDIVIDE={n1},{n2}\n"
            f"*NSET, NSET={name}_BOTTOM, PATCH={name}, SIDE=ETA0\n"
            f"*SURFACE, NAME={name}_TOP, PATCH={name}, SIDE=ETA1\n"
            f"*SURFACE, NAME={name}_BOTTOM, PATCH={name}, SIDE=ETA0\n")


def side(n):
    """Elements per side of a square mesh of about n elements (even: two blocks of n/2)."""
    return max(2, 2 * round(math.sqrt(n) / 2))


def write_deck(path, case, size, dt=0.0, t_end=1.0):
    """Writes the deck of `case` at about `size` elements (time step dt, 0: automatic);
    returns the number of elements."""
    n = side(size)
    h = 1.0 / n
    disc, _, rest = case.partition("-")
    consistent = rest.startswith("consistent") or rest == "corrector"
    solver = {"consistent-cg": ", MASS SOLVER=CG",
              "consistent-cholesky": ", MASS SOLVER=CHOLESKY",
              "corrector": ", MASS SOLVER=CORRECTOR, MASS PASSES=2"}.get(rest, "")
    contact = rest.startswith("contact")
    algorithm = ", ALGORITHM=MORTAR" if rest == "contact-mortar" else ""
    lumped = "HRZ" if disc == "q8" else "ROW SUM"
    head, mass = header(f"benchmark {case} {n} x {n}", "CONSISTENT" if consistent else lumped)
    if rest == "damped":
        mass += f"*DAMPING, ALPHA={DAMPING_ALPHA!r}\n"
    # contact: the upper block overlaps the lower one by 1 % of an element; penalty
    # eps = 0.1 E/h keeps the penalty ratio r = eps dt^2 (l_s/m_s + l_m/m_m) far below 1/2
    overlap = 0.01 * h
    eps = 0.1 * E / h
    with open(path, "w") as f:
        f.write(head)
        if disc == "q8" and not contact:
            q8_block(f, "BODY", n, n, 0.0, 0.0, 1.0, 1.0, 1, 1)
            f.write("*BOUNDARY\nBODY_BOTTOM, 2, 2\nBODY_LL, 1, 1\n")
        elif disc == "q8":
            nn, ne, _, top = q8_block(f, "LO", n, n // 2, 0.0, 0.0, 1.0, 0.5, 1, 1)
            _, _, bottom, _ = q8_block(f, "UP", n, n // 2, 0.0, 0.5 - overlap, 1.0, 0.5, nn, ne)
            f.write("*SURFACE, NAME=LO_TOP, TYPE=ELEMENT\n")
            np.savetxt(f, top.reshape(-1, 1), fmt="%d, S3")
            f.write("*SURFACE, NAME=UP_BOTTOM, TYPE=ELEMENT\n")
            np.savetxt(f, bottom.reshape(-1, 1), fmt="%d, S1")
            f.write("*BOUNDARY\nLO_BOTTOM, 2, 2\nLO_LL, 1, 1\n")
            f.write(f"*CONTACT PAIR, NAME=IFACE, PENALTY={eps!r}{algorithm}\nLO_TOP, UP_BOTTOM\n")
        elif not contact:
            iga_block(f, "BODY", n, n, 0.0, 0.0, 1.0, 1.0)
            f.write("*BOUNDARY\nBODY_BOTTOM, 2, 2\n1, 1, 1\n")
        else:
            iga_block(f, "LO", n, n // 2, 0.0, 0.0, 1.0, 0.5)
            iga_block(f, "UP", n, n // 2, 0.0, 0.5 - overlap, 1.0, 0.5)
            f.write("*BOUNDARY\nLO_BOTTOM, 2, 2\n1, 1, 1\n")
            f.write(f"*CONTACT PAIR, NAME=IFACE, PENALTY={eps!r}{algorithm}\nLO_TOP, UP_BOTTOM\n")
        f.write(mass)
        f.write(step_cards(dt, t_end, solver))
    return n * n


# ---------------------------------------------------------------- runs

def parse_bench(out):
    line = [ln for ln in out.splitlines() if ln.startswith("BENCH ")]
    if not line:
        raise RuntimeError("ictus-bench printed no BENCH line:\n" + out)
    d = {}
    for k, v in re.findall(r"(\w+)=\s*(\S+)", line[-1]):
        d[k] = v == "T" if v in ("T", "F") else float(v)
    return d


def run_bench(args, deck, nel, slow, ranks=1, steps=0, extra=()):
    # about 0.2-2 s per timed phase; a step with a factorised or CG consistent mass costs
    # several to tens of K u products (slow), a lumped or Kronecker one about one to three
    steps = steps or args.steps or (int(min(50, max(3, 5.0e5 / nel))) if slow else
                                    int(min(400, max(10, 2.0e7 / nel))))
    cmd = [os.path.join(args.build_dir, "bin", "ictus-bench"), deck, "--steps", str(steps),
           "--repeat", str(args.repeat), "--stream-mb", str(args.stream_mb)] + list(extra)
    env = dict(os.environ)
    if ranks > 1:
        env.update(MPI_ENV)
        cmd = [args.mpirun, "--oversubscribe", "-np", str(ranks)] + cmd
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({p.returncode}):\n{p.stdout}\n{p.stderr}")
    d = parse_bench(p.stdout)
    d["wall"] = time.time() - t0
    return d


def ns_el(d, key):
    return 1e9 * d[key] / d["nel"]


def row(case, ranks, d):
    gbs = d["bytes_kmv"] / d["t_kmv"] / 1e9
    stream = d["stream"] / 1e9
    cp = d["contact_points"]
    return [f"{case}{'' if ranks == 1 else ' np=2'}", f"{int(d['nel']):d}",
            f"{int(2 * d['nodes']):d}",
            f"{int(d['steps']):d}",
            f"{ns_el(d, 't_step'):.1f}",
            per_pass(d) if planned(d) else "-",
            f"{ns_el(d, 't_single'):.1f}" if planned(d) else "-",
            f"{ns_el(d, 't_sweep'):.1f}" if planned(d) else "-",
            f"{ns_el(d, 't_kmv'):.1f}",
            f"{ns_el(d, 't_kstep'):.1f}" if d.get("t_kstep", 0) > 0 else "-",
            f"{ns_el(d, 't_kread'):.1f}" if d.get("t_kread", 0) > 0 else "-",
            f"{ns_el(d, 't_elem'):.1f}" if d.get("t_elem", 0) > 0 else "-",
            f"{d['t_elem'] / d['t_kmv']:.1f}" if d.get("t_elem", 0) > 0 else "-",
            f"{ns_el(d, 't_contact'):.2f}" if cp else "-",
            f"{ns_el(d, 't_mass'):.1f}", f"{ns_el(d, 't_update'):.1f}",
            f"{gbs:.1f}", f"{stream:.1f}", f"{gbs / stream:.2f}",
            f"{d['t_kread'] / d['t_kmv']:.2f}" if d.get("t_kread", 0) > 0 else "-",
            f"{d['t_step'] / d['t_kmv']:.2f}",
            f"{d['t_mass'] / d['t_kmv']:.2f}" if d["consistent"] else "-",
            f"{d['mass_iter']:.1f}" if d["mass_iter"] > 0 else "-",
            f"{1e9 * d['t_contact'] / cp:.0f}" if cp else "-"]


def per_pass(d):
    """Steps per pass over K on the run's path; 'w' when the sweeps kept are of wide strips
    (SWEEP STEPS=AUTO timed them faster than the default strips)."""
    k = int(d.get("sweep", 1))
    return f"{k}w" if k > 1 and d.get("sweep_kib", 0) > 768 else f"{k}"


def planned(d):
    """Whether sweeps were planned (then the run times them against single steps)."""
    return d.get("sweep_plan", d.get("sweep", 1)) > 1


HEAD = ["case", "elements", "dofs", "steps", "step", "per pass", "1-step", "swept", "K u",
        "K u step", "K read", "elem f_int", "elem/K u", "contact", "mass", "update",
        "K u GB/s", "STREAM GB/s", "K u/STREAM", "K read/K u", "step/K u", "mass/K u",
        "it/solve", "contact ns/point"]


def print_table(rows, head=HEAD):
    w = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(head)]
    print("| " + " | ".join(h.rjust(w[i]) for i, h in enumerate(head)) + " |")
    print("|" + "|".join("-" * (x + 1) + ":" for x in w) + "|")
    for r in rows:
        print("| " + " | ".join(c.rjust(w[i]) for i, c in enumerate(r)) + " |")


def slope(xs, ys):
    lx, ly = np.log(np.asarray(xs, float)), np.log(np.asarray(ys, float))
    return float(np.polyfit(lx, ly, 1)[0])


def against(res, disc, name, runs):
    """The step of case disc-name against the lumped step `runs` of the same meshes:
    (its runs, the sizes both have, the worst of them, the ratio there)."""
    other = res.get(disc + "-" + name, {})
    common = sorted(set(other) & set(runs))
    if not common:
        return other, common, None, None
    worst = max(common, key=lambda s: other[s]["t_step"] / runs[s]["t_step"])
    return other, common, worst, other[worst]["t_step"] / runs[worst]["t_step"]


def verdicts(res, np2):
    """The targets of doc/performance.md: (target, measured, verdict) rows."""
    out = []

    def add(target, measured, ok):
        out.append((target, measured, "reported" if ok is None else "met" if ok else "MISSED"))

    for disc in ("q8", "iga"):
        runs = res.get(disc, {})
        if not runs:
            continue
        big = max(runs)
        d = runs[big]
        bw = d["bytes_kmv"] / d["t_kmv"] / d["stream"]
        add(f"{disc}: K u >= 70 % of STREAM triad (largest mesh, {int(d['nel'])} el.)",
            f"{100 * bw:.0f} %", bw >= 0.70)
        if d.get("t_kread", 0) > 0:
            add(f"{disc}: K u against one core merely reading K's arrays (largest mesh)",
                f"{100 * d['t_kread'] / d['t_kmv']:.0f} % of that rate", None)
        worst = max(runs.values(), key=lambda d: d["t_step"] / d["t_kmv"])
        r = worst["t_step"] / worst["t_kmv"]
        add(f"{disc}: lumped step <= 1.3 x K u (worst size, {int(worst['nel'])} el.)",
            f"{r:.2f} x", r <= 1.3)
        if all(planned(d) for d in runs.values()):
            worst = max(runs.values(), key=lambda d: d["t_single"] / d["t_kmv"])
            r = worst["t_single"] / worst["t_kmv"]
            add(f"{disc}: the same one step per pass (SWEEP STEPS=1; worst size, "
                f"{int(worst['nel'])} el.)", f"{r:.2f} x", None)
            worst = max(runs.values(), key=lambda d: d["t_sweep"] / d["t_kmv"])
            r = worst["t_sweep"] / worst["t_kmv"]
            add(f"{disc}: the same always in sweeps (SWEEP STEPS=6; worst size, "
                f"{int(worst['nel'])} el.)", f"{r:.2f} x", None)
        for name, target in (("consistent", True), ("consistent-cholesky", False)):
            cons, common, worst, r = against(res, disc, name, runs)
            if not common:
                continue
            how = SOLVERS.get(int(cons[worst].get("mass_solver", 0)), "?")
            add(f"{disc}: {name} step <= 2 x lumped step (worst size, "
                f"{int(runs[worst]['nel'])} el.; {how}, solve = "
                f"{cons[worst]['t_mass'] / cons[worst]['t_kmv']:.2f} K u)",
                f"{r:.2f} x", (r <= 2.0) if target else None)
            if target:
                # a consistent step does one K u per step and no sweep can share it (the
                # solve couples every node): its own K u over the lumped step is its floor
                # (the product it takes: column order, from K's upper blocks on one rank)
                ku = "t_kstep" if all(cons[s].get("t_kstep", 0) > 0 for s in common) \
                    else "t_kmv"
                worst = max(common, key=lambda s: cons[s][ku] / runs[s]["t_step"])
                r = cons[worst][ku] / runs[worst]["t_step"]
                add(f"{disc}: floor of any consistent step: its K u alone / lumped step (worst "
                    f"size, {int(runs[worst]['nel'])} el.)", f"{r:.2f} x", None)
                if ku == "t_kstep":
                    big = max(common)
                    r = cons[big]["t_kstep"] / cons[big]["t_kmv"]
                    add(f"{disc}: the consistent step's K u (column order, upper blocks) / "
                        f"K u (largest mesh, {int(cons[big]['nel'])} el.)", f"{r:.2f} x", None)
                elif all(cons[s].get("t_kread", 0) > 0 for s in common):
                    worst = max(common, key=lambda s: cons[s]["t_kread"] / runs[s]["t_step"])
                    r = cons[worst]["t_kread"] / runs[worst]["t_step"]
                    add(f"{disc}: the same by memory alone: reading K's arrays / lumped step "
                        f"(worst size, {int(runs[worst]['nel'])} el.)", f"{r:.2f} x", None)
            if all(planned(d) for d in runs.values()):
                worst = max(common, key=lambda s: cons[s]["t_step"] / runs[s]["t_single"])
                r = cons[worst]["t_step"] / runs[worst]["t_single"]
                add(f"{disc}: the same against the lumped step one step per pass "
                    f"(SWEEP STEPS=1; worst size, {int(runs[worst]['nel'])} el.)",
                    f"{r:.2f} x", None)
        for other in ("damped", "corrector"):
            runs_o, common, worst, r = against(res, disc, other, runs)
            if not common:
                continue
            nel = int(runs[worst]['nel'])
            what = (f"{disc}: damped step (*DAMPING) / undamped step, each on its run's path "
                    f"(worst size, {nel} el.)" if other == "damped" else
                    f"{disc}: consistent mass applied by 2 corrector passes (approximate "
                    f"inverse, doc/theory.md §5) / lumped step (worst size, {nel} el.; passes "
                    f"= {runs_o[worst]['t_mass'] / runs_o[worst]['t_kmv']:.2f} K u)")
            out.append((what, f"{r:.2f} x", "reported"))
        con = res.get(disc + "-contact", {})
        if len(con) >= 2:
            sizes = sorted(con)
            per = [con[s]["t_contact"] / con[s]["contact_points"] for s in sizes]
            grow = con[sizes[-1]]["contact_points"] / con[sizes[0]]["contact_points"]
            spread = max(per) / min(per)
            add(f"{disc}: contact cost per point flat within 30 % (surface grows "
                f"{grow:.1f} x)", f"max/min {spread:.2f} ({1e9 * min(per):.0f}-"
                f"{1e9 * max(per):.0f} ns/point)", spread <= 1.3)
        for c in (disc, disc + "-contact"):
            runs_c = res.get(c, {})
            if len(runs_c) >= 2:
                sizes = sorted(runs_c)
                s = slope([runs_c[k]["nel"] for k in sizes], [runs_c[k]["t_step"] for k in sizes])
                add(f"{c}: whole step linear in elements, log-log slope 1 +- 0.1 "
                    f"({int(runs_c[sizes[0]]['nel'])}-{int(runs_c[sizes[-1]]['nel'])} el.)",
                    f"{s:.3f}", abs(s - 1.0) <= 0.1)
                big = [k for k in sizes if k >= 5e4]
                if 2 <= len(big) < len(sizes):
                    s = slope([runs_c[k]["nel"] for k in big], [runs_c[k]["t_step"] for k in big])
                    out.append((f"{c}: the same, meshes beyond the caches only "
                                f"({int(runs_c[big[0]]['nel'])}-{int(runs_c[big[-1]]['nel'])} "
                                "el.)", f"{s:.3f}", "reported"))
    for c, (d1, d2) in np2.items():
        out.append((f"{c}: speed-up np = 2 / np = 1 of the whole step ({int(d1['nel'])} el.)",
                    f"{d1['t_step'] / d2['t_step']:.2f} x (K u {d1['t_kmv'] / d2['t_kmv']:.2f} x, "
                    f"STREAM {d2['stream'] / d1['stream']:.2f} x)", "reported"))
    return out


# same mesh, same K: the K u of these cases runs the same kernel on the same arrays
SAME_K = {"q8": "q8", "q8-consistent": "q8", "q8-consistent-cg": "q8", "q8-damped": "q8",
          "iga-damped": "iga",
          "q8-consistent-cholesky": "q8", "iga": "iga", "iga-consistent": "iga",
          "iga-corrector": "iga", "iga-consistent-cg": "iga", "iga-consistent-cholesky": "iga"}
STREAM_SPREAD, KU_SPREAD, NP2_STREAM = 1.15, 1.12, 1.5


def host_checks(res, np2):
    """Signs that the memory bandwidth of the host moved during the run (other guests of a
    shared host use the memory without showing in this machine's load average): lines to
    print, empty when none. Each compares figures that a steady host gives alike."""
    out = []
    streams = [d["stream"] for runs in res.values() for d in runs.values()]
    if len(streams) >= 2 and max(streams) > STREAM_SPREAD * min(streams):
        out.append(f"the np = 1 STREAM triad ranged over {min(streams) / 1e9:.1f}-"
                   f"{max(streams) / 1e9:.1f} GB/s (more than {STREAM_SPREAD:.2f} x)")
    groups = {}
    for case, runs in res.items():
        if case in SAME_K:
            for nel, d in runs.items():
                groups.setdefault((SAME_K[case], nel), []).append((case, d["t_kmv"] / d["nel"]))
    for (disc, nel), ts in sorted(groups.items()):
        lo, hi = min(ts, key=lambda x: x[1]), max(ts, key=lambda x: x[1])
        if hi[1] > KU_SPREAD * lo[1]:
            out.append(f"K u of the same {disc} mesh ({int(nel)} el.) took "
                       f"{1e9 * lo[1]:.1f} ns/el in {lo[0]} and {1e9 * hi[1]:.1f} in {hi[0]} "
                       f"(more than {KU_SPREAD:.2f} x)")
    for c, (d1, d2) in np2.items():
        if d2["stream"] < NP2_STREAM * d1["stream"]:
            out.append(f"the np = 2 STREAM triad of {c} was only "
                       f"{d2['stream'] / d1['stream']:.2f} x the np = 1 one (below "
                       f"{NP2_STREAM:.1f} x: the second core shared memory with something else)")
    return out


def loadavg():
    try:
        with open("/proc/loadavg") as f:
            return float(f.read().split()[0])
    except OSError:
        return 0.0


def build(args):
    env = dict(os.environ, BUILD_DIR=args.build_dir)
    print(f"benchmark: building Release in {args.build_dir} (scripts/setup.sh Release)", flush=True)
    subprocess.run(["bash", os.path.join(SCRIPTS, "setup.sh"), "Release"], check=True, env=env)


def build_type(build_dir):
    try:
        with open(os.path.join(build_dir, "CMakeCache.txt")) as f:
            m = re.search(r"^CMAKE_BUILD_TYPE:\w+=(\w*)", f.read(), re.M)
            return m.group(1) if m else ""
    except OSError:
        return ""


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--suite", choices=["kernels", "real"], default="kernels",
                    help="kernels: the square meshes of doc/performance.md §1-2 (default); "
                         "real: the runs users make (bench/real.py, doc/performance.md §6)")
    ap.add_argument("--quick", action="store_true",
                    help="sizes 1e4 and 1e5 (smoke run; --suite real: 1e4)")
    ap.add_argument("--sizes", help="comma-separated element counts (default 1e4,1e5,1e6; "
                    "--suite real: 1e5)")
    ap.add_argument("--no-build", action="store_true", help="use the existing build")
    ap.add_argument("--build-dir", default=os.environ.get("BUILD_DIR", os.path.join(ROOT, "build")))
    ap.add_argument("--work", help="scratch directory for the decks (default: a temporary one)")
    ap.add_argument("--repeat", type=int, default=3, help="timing sets per run (median)")
    ap.add_argument("--steps", type=int, default=0, help="steps per timing (default by size; "
                    "--suite real: steps of each ictus run, default 500 lumped, 100 others)")
    ap.add_argument("--stream-mb", type=int, default=768, help="STREAM triad arrays, MB in all")
    ap.add_argument("--no-mpi", action="store_true", help="skip the np = 2 runs")
    ap.add_argument("--cases", help="subset of " + ",".join(CASES + EXTRA_CASES) +
                    " (--suite real: of bench/real.py's CASES and EXTRA_CASES)")
    ap.add_argument("--alloc-check", action="store_true",
                    help="also count the heap allocations of ictus runs of 100 and 1000 steps")
    args = ap.parse_args()
    real = args.suite == "real"
    default_sizes = ("1e4" if real else "1e4,1e5") if args.quick else \
        ("1e5" if real else "1e4,1e5,1e6")
    try:
        sizes = [int(float(s)) for s in (args.sizes or default_sizes).split(",")]
    except ValueError:
        ap.error(f"--sizes: expected comma-separated element counts (e.g. 1e4,1e5), "
                 f"got {args.sizes}")
    if any(s < 4 for s in sizes):
        ap.error("--sizes: at least 4 elements per mesh")
    if args.repeat < 1:
        ap.error(f"--repeat: expected at least 1 timing set, got {args.repeat}")
    if args.steps < 0:
        ap.error(f"--steps: expected a positive number of steps (0: by size), got {args.steps}")
    if args.stream_mb < 1:
        ap.error(f"--stream-mb: expected a positive size in MB, got {args.stream_mb}")
    if real:
        import real as suite
        known, cases = suite.CASES + suite.EXTRA_CASES, suite.CASES
    else:
        known, cases = CASES + EXTRA_CASES, CASES
    if args.cases is not None:
        cases = [c for c in args.cases.split(",") if c]
    for c in cases:
        if c not in known:
            ap.error(f"unknown case {c}")
    args.build_dir = os.path.abspath(args.build_dir)
    if not args.no_build:
        build(args)
    bench = os.path.join(args.build_dir, "bin", "ictus-bench")
    if not os.access(bench, os.X_OK):
        sys.exit(f"benchmark: {bench} not found (build it, or drop --no-build)")
    bt = build_type(args.build_dir)
    if bt != "Release":
        print(f"benchmark: WARNING: {args.build_dir} is a {bt or 'unknown'} build; the figures "
              "are only meaningful for Release", flush=True)
    args.mpirun = shutil.which("mpirun")
    work = args.work or tempfile.mkdtemp(prefix="ictus-bench-")
    os.makedirs(work, exist_ok=True)
    print(f"benchmark: decks in {work}; sizes {sizes}; cases {cases}", flush=True)
    if real:
        suite.run_suite(args, work, sizes, cases)
        if not args.work:
            shutil.rmtree(work, ignore_errors=True)
        return
    load0 = loadavg()
    res, rows, np2 = {}, [], {}
    for case in cases:
        dt0 = None
        for size in sorted(sizes):
            deck = os.path.join(work, f"{case}-{size}.inp")
            t0 = time.time()
            # the smallest mesh takes the automatic step (omega_max by Lanczos in ictus-bench);
            # omega_max of these uniform meshes scales as 1/h, so the larger ones get
            # 0.99 dt0 h/h0 (a Lanczos run with a consistent mass would cost minutes at 1e6)
            dt = 0.0 if dt0 is None else 0.99 * dt0[0] * dt0[1] / side(size)
            nel = write_deck(deck, case, size, dt)
            tgen = time.time() - t0
            # the factor and the CG cost many K u per solve: fewer steps per timing
            d = run_bench(args, deck, nel, case.endswith(("-cholesky", "-cg")))
            if dt0 is None:
                dt0 = (d["dt"], side(size))
            res.setdefault(case, {})[nel] = d
            rows.append(row(case, 1, d))
            print(f"  {case:15s} {nel:8d} el.: step {ns_el(d, 't_step'):7.1f} ns/el, "
                  f"K u {ns_el(d, 't_kmv'):7.1f} ns/el (deck {tgen:.1f} s, run {d['wall']:.1f} s)",
                  flush=True)
            if ranks2(args, case, size, sizes):
                d2 = run_bench(args, deck, nel, False, ranks=2)
                np2[case] = (d, d2)
                rows.append(row(case, 2, d2))
                print(f"  {case:15s} {nel:8d} el., np = 2: step {ns_el(d2, 't_step'):7.1f} ns/el",
                      flush=True)
            if not args.work and size > 2e5:
                os.remove(deck)
    load1 = loadavg()
    print()
    print(f"load average (1 min) at the start {load0:.2f}, at the end {load1:.2f} on "
          f"{os.cpu_count()} CPUs (this benchmark adds about 1, 2 during the np = 2 runs)")
    if max(load0, load1) > 1.5:
        print("benchmark: WARNING: other processes were running; timings are not reliable")
    print("ns per element per step (medians of "
          f"{args.repeat}); bandwidths in GB/s; K u bytes = blocks (32 B + 4 B column index) "
          "+ row pointers + u read + K u written, once")
    print_table(rows)
    print()
    print("| target | measured | verdict |")
    print("|---|---:|---|")
    for t, m, v in verdicts(res, np2):
        print(f"| {t} | {m} | {v} |")
    checks = host_checks(res, np2)
    if checks:
        print()
        print("benchmark: WARNING: the host's memory bandwidth moved during this run; the verdicts "
              "near a threshold may fall either way (run again):")
        for line in checks:
            print("  - " + line)
    if args.alloc_check:
        alloc_check(args, work, cases)
    if not args.work:
        shutil.rmtree(work, ignore_errors=True)


def alloc_check(args, work, cases, n1=100, n2=1000):
    """Runs `ictus` (output off) for n1 and n2 steps on 20 x 20 meshes of each case with a
    malloc counter preloaded (scripts/malloc_count.c) and prints the allocations of the
    process: the time loop allocates nothing when the counts do not grow with the steps."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        print("alloc-check: no C compiler (cc), skipped")
        return
    so = os.path.join(work, "malloc_count.so")
    subprocess.run([cc, "-O2", "-shared", "-fPIC", "-o", so,
                    os.path.join(SCRIPTS, "malloc_count.c")], check=True)
    ictus = os.path.join(args.build_dir, "bin", "ictus")
    print()
    print(f"allocations of the ictus process (malloc + calloc + realloc; LD_PRELOAD "
          f"scripts/malloc_count.c), 20 x 20 meshes, output off, dt = 1e-4")
    print(f"| case | {n1} steps | {n2} steps | per extra step |")
    print("|---|---:|---:|---:|")
    for case in cases:
        counts = []
        for n in (n1, n2):
            deck = os.path.join(work, f"alloc-{case}-{n}.inp")
            write_deck(deck, case, 400, 1.0e-4, n * 1.0e-4)
            out = os.path.join(work, f"alloc-{case}-{n}.txt")
            if os.path.exists(out):
                os.remove(out)
            env = dict(os.environ, LD_PRELOAD=so, MALLOC_COUNT_OUT=out)
            p = subprocess.run([ictus, deck, "-o", deck.replace(".inp", ".h5")], env=env,
                               capture_output=True, text=True)
            if p.returncode != 0:
                raise RuntimeError(f"ictus {deck} failed:\n{p.stdout}\n{p.stderr}")
            with open(out) as f:
                line = [ln for ln in f if ln.startswith("ictus ")][-1]
            c = dict(kv.split("=") for kv in line.split()[2:])
            counts.append(int(c["malloc"]) + int(c["calloc"]) + int(c["realloc"]))
        print(f"| {case} | {counts[0]} | {counts[1]} | {(counts[1] - counts[0]) / (n2 - n1):.2f} |")


def ranks2(args, case, size, sizes):
    return (not args.no_mpi and args.mpirun is not None and size == max(sizes)
            and case in ("q8", "iga"))


if __name__ == "__main__":
    main()
