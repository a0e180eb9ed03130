#!/usr/bin/python3
"""The benchmark of the runs users make (issue #31 item 1; doc/performance.md §6), run by
`bench/benchmark.py --suite real`.

Each case is a deck as a user writes it, run by build/bin/ictus for a fixed number of steps
(t_end = steps x the automatic dt) with the output of a run: a history record every step and
a field snapshot every 1 % of the user's run (TIME INTERVAL = T/100, T = 0.9 for the Hertz
decks as scripts/mesh/hertz.py writes them, 1.0 for the plate as input/interop/plate_gmsh.inp).
The same deck runs again with history every 1e8 steps (the share of the records), and
build/bin/ictus-bench on it gives the kernels of the step and the STREAM triad of the run.

Cases (both bodies of the Hertz problem count as elements):
- hertz-iga, hertz-q8: scripts/mesh/hertz.py, two half-discs R = 4, one NURBS p = 2 patch each
  (or Q8 of the same map), HRZ lumped mass, TWO HALF PASS contact (active from the first step);
- hertz-iga-consistent: the same NURBS deck with *MASS, TYPE=CONSISTENT (MASS SOLVER=AUTO: the
  Cholesky factor on these curved patches);
- hertz-iga-nlgeom: the NURBS deck with *STEP, NLGEOM=YES (St. Venant-Kirchhoff, element loop);
- plate-q4, plate-q8: a 4 x 2 plate with 4 x 2 holes of radius 0.25 meshed by gmsh
  (scripts/mesh/gmsh_plate.py: unstructured CPS4 or CPS8, plane stress), moving at v = 1
  onto a rigid wall under its bottom edge (*RIGID WALL, penalty 0.1 E/h: every bottom node in
  contact from the first step). Skipped, with a message, without gmsh's Python module.
- box-c3d8, box-c3d20: 3D, a box [0, 2] x [0, 1] x [0, 1] of 2n x n x n hexahedra
  (scripts/mesh/box.py), clamped at x = 0 and moving at v = 1 along z (a bending wave), HRZ
  lumped mass, the assembled stiffness in 3 x 3 blocks (INTERNAL FORCE=AUTO takes it);
  box-c3d8-element, box-c3d20-element: the same decks with INTERNAL FORCE=ELEMENT, the
  matrix-free step beside the assembled one.
EXTRA_CASES: hertz-q8-consistent, hertz-q8-nlgeom; plate-q4-sorted, plate-q8-sorted: the same
gmsh mesh with its nodes renumbered in rows along y (sort_nodes: the order of the kernel
suite's lattices; gmsh numbers the nodes that its splitting and the second order add after
the others, and ictus keeps a deck's numbering).

Per case and size: the time loop of the ictus runs, in ns per element per step, read from
the log's progress lines (between the first line after the sweep tuning and the last, so
that neither snapshot at its ends counts); the field snapshot from the time after the last
progress line; the peak memory of every ictus process (its high-water mark, ru_maxrss of
wait4, = VmHWM); the memory-bound floor: the bytes a step must move once over the STREAM
triad of the run (see floor_bytes). `real.py --peak FILE -- CMD...` runs CMD and writes its
peak (used for each rank of the np = 2 runs).
"""
import math
import os
import re
import shutil
import subprocess
import sys
import time

import numpy as np

import benchmark as bm

HERTZ = os.path.join(bm.SCRIPTS, "mesh", "hertz.py")
GMSH_PLATE = os.path.join(bm.SCRIPTS, "mesh", "gmsh_plate.py")
BOX = os.path.join(bm.SCRIPTS, "mesh", "box.py")
CASES = ["hertz-iga", "hertz-q8", "hertz-iga-consistent", "hertz-iga-nlgeom", "plate-q4",
         "plate-q8", "box-c3d8", "box-c3d8-element", "box-c3d20", "box-c3d20-element"]
EXTRA_CASES = ["hertz-q8-consistent", "hertz-q8-nlgeom", "plate-q4-sorted", "plate-q8-sorted"]
# the length of the user's run (its field snapshots every 1 % of it)
T_USER = {"hertz": 0.9, "plate": 1.0, "box": 1.0}
# the plate: lx x ly, 4 x 2 holes of radius 0.25, E, nu, rho; gmsh gives about
# PLATE_DENSITY / size^2 elements for --size (measured: 96916 at 0.0088); beyond PLATE_MESHED
# elements gmsh meshes a quarter (a sixteenth ...) and splits each element into four
# (gmsh_plate.py --refine: 1e5 elements take 5 s to mesh, 1e6 about 8 minutes)
PLATE = dict(lx=4.0, ly=2.0, holes="4,2", radius=0.25, E=1000.0, nu=0.3, rho=1.0, v=1.0)
PLATE_DENSITY, PLATE_MESHED = 7.5, 3.0e5
HIST_OFF = 100000000
# a case that could not run leaves a row of this reason
FAILED = "failed"


# ---------------------------------------------------------------- decks

def hertz_model(path, case, size):
    """The model of a Hertz case (all of hertz.py's deck up to *STEP) in path; returns the
    number of elements and whether the step is NLGEOM."""
    kind = "q8" if case.startswith("hertz-q8") else "iga"
    # -wall (bench/scaling.py): one half-disc on a rigid wall (hertz.py --wall)
    bodies = 1 if case.endswith("-wall") else 2
    n = max(2, round(math.sqrt(size / bodies)))
    mass = "CONSISTENT" if case.endswith("-consistent") else "HRZ"
    cmd = [sys.executable, HERTZ, "--kind", kind, "--mass", mass,
           "--n" if kind == "q8" else "--subdivide", str(n)] + (["--wall"] if bodies == 1 else [])
    text = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    with open(path, "w") as f:
        f.write(text[:text.index("\n*STEP\n") + 1])
    return bodies * n * n, case.endswith("-nlgeom")


def plate_model(path, case, size):
    """The plate with holes meshed by gmsh (its export included unchanged) on a rigid wall;
    returns the number of elements and False (small strain)."""
    mesh = path[:-len(".inp")] + "_mesh.inp"
    refine = 0
    while size / 4 ** refine > PLATE_MESHED:
        refine += 1
    h = math.sqrt(PLATE_DENSITY * 4 ** refine / size)
    subprocess.run([sys.executable, GMSH_PLATE, mesh, "--lx", str(PLATE["lx"]), "--ly",
                    str(PLATE["ly"]), "--holes", PLATE["holes"], "--radius",
                    str(PLATE["radius"]), "--size", repr(h), "--refine", str(refine),
                    "--order", "1" if case.startswith("plate-q4") else "2"], check=True)
    # the elements are about h/2^(refine + 1) (gmsh splits each recombined quadrangle into
    # four, --refine each element into four)
    el_size = 0.5 ** (refine + 1) * h
    if case.endswith("-sorted"):
        sort_nodes(mesh, el_size)
    nel, faces = bottom_faces(mesh)
    # penalty 0.1 E/h, as the contact cases of the kernel suite
    eps = 0.1 * PLATE["E"] / el_size
    with open(path, "w") as f:
        f.write(f"*HEADING\nbenchmark {case}: plate with holes (gmsh) on a rigid wall\n"
                f"*INCLUDE, INPUT={os.path.basename(mesh)}\n*MATERIAL, NAME=MAT\n*ELASTIC\n"
                f"{PLATE['E']!r}, {PLATE['nu']!r}\n*DENSITY\n{PLATE['rho']!r}\n"
                "*SOLID SECTION, ELSET=PLATE, MATERIAL=MAT\n1.\n"
                "*SURFACE, NAME=PLATE_BOTTOM, TYPE=ELEMENT\n")
        np.savetxt(f, faces, fmt="%d, S%d")
        f.write(f"*RIGID WALL, NAME=WALL, POINT=0,0, NORMAL=0,1, PENALTY={eps:.6g}\n"
                f"PLATE_BOTTOM\n*INITIAL CONDITIONS, TYPE=VELOCITY\nPLATE, 2, {-PLATE['v']!r}\n"
                "*MASS, TYPE=HRZ\n")
    return nel, False


def box_model(path, case, size):
    """The 3D box of 2n x n x n hexahedra (C3D8 or C3D20, scripts/mesh/box.py) clamped at
    x = 0 and moving at v = 1 along z; -element: INTERNAL FORCE=ELEMENT (written by
    step_deck). Returns the number of elements and False (small strain)."""
    etype = "C3D20" if "-c3d20" in case else "C3D8"
    n = max(1, round((size / 2) ** (1 / 3)))
    mesh = path[:-len(".inp")] + "_mesh.inp"
    with open(mesh, "w") as f:
        subprocess.run([sys.executable, BOX, "--type", etype, "--nx", str(2 * n), "--ny", str(n),
                        "--nz", str(n), "--lx", "2", "--ly", "1", "--lz", "1"], check=True,
                       stdout=f)
    with open(path, "w") as f:
        f.write(f"*HEADING\nbenchmark {case}: a clamped box of {etype}, bending\n"
                f"*ANALYSIS, TYPE=3D\n*INCLUDE, INPUT={os.path.basename(mesh)}\n"
                "*MATERIAL, NAME=MAT\n*ELASTIC\n1000.0, 0.3\n*DENSITY\n1.0\n"
                "*BOUNDARY\nX0, 1, 3\n*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 3, 1.0\n"
                "*MASS, TYPE=HRZ\n")
    return 2 * n ** 3, False


def sort_nodes(mesh, band):
    """Renumbers the nodes of a gmsh export (file rewritten) row by row: by y in rows of
    height band, by x within a row, as the lattices of the kernel suite are numbered; the
    element blocks follow (their ids and the element sets stay)."""
    with open(mesh) as f:
        lines = f.read().splitlines()
    heads = [i for i, ln in enumerate(lines) if ln.startswith("*")] + [len(lines)]
    blocks = [(heads[k], heads[k + 1]) for k in range(len(heads) - 1)]
    node = next((a, b) for a, b in blocks if lines[a].upper().startswith("*NODE"))
    xyz = np.array([ln.split(",") for ln in lines[node[0] + 1:node[1]]], dtype=float)
    ids = xyz[:, 0].astype(np.int64)
    order = np.lexsort((xyz[:, 1], np.floor(xyz[:, 2] / band)))
    new = np.zeros(ids.max() + 1, dtype=np.int64)
    new[ids[order]] = np.arange(1, len(ids) + 1)
    out = lines[:node[0] + 1] + [f"{k + 1}, {x!r}, {y!r}, {z!r}" for k, (x, y, z) in
                                 enumerate(xyz[order, 1:].tolist())]
    for a, b in blocks:
        if a == node[0]:
            continue
        out.append(lines[a])
        if lines[a].upper().startswith("*ELEMENT"):
            conn = np.array([ln.split(",") for ln in lines[a + 1:b]], dtype=np.int64)
            conn[:, 1:] = new[conn[:, 1:]]
            out += [", ".join(map(str, r)) for r in conn.tolist()]
        else:
            out += lines[a + 1:b]
    with open(mesh, "w") as f:
        f.write("\n".join(out) + "\n")


def bottom_faces(mesh):
    """(number of surface elements, rows (element id, face k)) of the faces on y = 0 of the
    CPS4/CPS8 elements of a gmsh export: face Sk runs from corner k to corner k + 1."""
    nodes, elems, block = {}, [], None
    with open(mesh) as f:
        for line in f:
            if line.startswith("*"):
                key = line.upper()
                block = "node" if key.startswith("*NODE") else \
                    "elem" if re.match(r"\*ELEMENT, *TYPE=CPS[48]\b", key) else None
            elif block == "node":
                v = line.split(",")
                nodes[int(v[0])] = float(v[2])
            elif block == "elem":
                elems.append([int(v) for v in line.split(",")[:5]])
    e = np.array(elems, dtype=np.int64)
    ids = np.fromiter(nodes.keys(), dtype=np.int64)
    y = np.zeros(ids.max() + 1)
    y[ids] = np.fromiter(nodes.values(), dtype=float)
    low = np.abs(y) < 1e-9 * PLATE["ly"]
    rows = [np.column_stack([e[on, 0], np.full(int(on.sum()), k + 1)])
            for k in range(4) for on in [low[e[:, 1 + k]] & low[e[:, 1 + (k + 1) % 4]]]]
    return len(e), np.concatenate(rows)


def step_deck(path, model, nlgeom, t_end, t_user, hist_every, force="AUTO"):
    """A deck that includes the model and runs to t_end with the automatic step, history
    every hist_every steps and a field snapshot every 1 % of the user's run t_user."""
    with open(path, "w") as f:
        f.write(f"*INCLUDE, INPUT={os.path.basename(model)}\n"
                f"*STEP{', NLGEOM=YES' if nlgeom else ''}\n"
                f"*DYNAMIC, EXPLICIT, INTERNAL FORCE={force}\n"
                f"0, {t_end!r}\n*OUTPUT, HISTORY, EVERY={hist_every}\n"
                f"*OUTPUT, FIELD, TIME INTERVAL={t_user / 100!r}\n*END STEP\n")


# ---------------------------------------------------------------- runs

def peak_main(argv):
    """real.py --peak FILE -- CMD...: runs CMD, writes its peak resident memory (bytes) to
    FILE.<rank> (the Open MPI rank, 0 outside mpirun), exits with its status."""
    out, cmd = argv[2], argv[4:]
    p = subprocess.Popen(cmd)
    _, status, ru = os.wait4(p.pid, 0)
    rank = os.environ.get("OMPI_COMM_WORLD_RANK", "0")
    with open(f"{out}.{rank}", "w") as f:
        f.write(f"{ru.ru_maxrss * 1024}\n")
    sys.exit(os.waitstatus_to_exitcode(status))


def run_ictus(args, deck, ranks=1, options=None):
    """Runs ictus on deck (ranks > 1: under mpirun) with options (default: -o the deck's
    .h5, removed after); returns (log, wall seconds of the process, peak resident bytes of
    each rank). Raises RuntimeError when it fails."""
    ictus = os.path.join(args.build_dir, "bin", "ictus")
    peak = deck[:-len(".inp")] + ".peak"
    options = ["-o", deck[:-len(".inp")] + ".h5"] if options is None else options
    cmd = [sys.executable, os.path.abspath(__file__), "--peak", peak, "--", ictus, deck] + \
        options
    env = dict(os.environ)
    if ranks > 1:
        env.update(bm.MPI_ENV)
        cmd = [args.mpirun, "--oversubscribe", "-np", str(ranks)] + cmd
    t0 = time.time()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       env=env)
    wall = time.time() - t0
    for suffix in (".h5", ".xdmf"):
        if os.path.exists(deck[:-len(".inp")] + suffix):
            os.remove(deck[:-len(".inp")] + suffix)
    if p.returncode != 0:
        lines = [ln for ln in p.stdout.splitlines() if "error" in ln.lower()] or \
            p.stdout.splitlines()[-3:] or [f"{p.returncode}"]
        raise RuntimeError(f"ictus {os.path.basename(deck)} failed ({p.returncode}): " +
                           " / ".join(lines[:3]))
    peaks = []
    for r in range(ranks):
        with open(f"{peak}.{r}") as f:
            peaks.append(int(f.read()))
        os.remove(f"{peak}.{r}")
    return p.stdout, wall, peaks


PROGRESS = re.compile(r"^step (\d+)/(\d+) .* elapsed (\S+) s", re.M)


def parse_log(log, interval):
    """From an ictus log: the time loop's seconds per step without snapshots, the seconds of
    the last snapshot, the steps, the set-up seconds, whether the SWEEP STEPS=AUTO tuning
    ended (None: no sweeps planned), and the stored bytes the log names (Cholesky factor,
    element-loop geometry). interval: the TIME INTERVAL of the snapshots
    (those due between the progress lines measured are taken off at the last one's cost)."""
    d = {}
    m = re.search(r"^wall time: (\S+) s for (\d+) steps", log, re.M)
    d["loop_wall"], d["steps"] = float(m.group(1)), int(m.group(2))
    d["dt"] = float(re.search(r"^step: dt = (\S+),", log, re.M).group(1))
    planned = re.search(r"^sweeps: \d+ steps per sweep", log, re.M)
    tuned = re.search(r"^sweeps: (kept|dropped)", log, re.M)
    d["tuned"] = None if planned is None else tuned is not None
    start = tuned.end() if tuned else 0
    prog = [(int(a), float(c)) for a, _, c in PROGRESS.findall(log[start:])]
    if len(prog) >= 2 and prog[-1][0] > prog[0][0]:
        (m0, e0), (m1, e1) = prog[0], prog[-1]
        # the snapshots at steps nint(k interval/dt), k >= 1 (schedule.f90), written after the
        # progress line of their step: those of steps m0 ... m1 - 1 lie between the lines
        inside = sum(1 for k in range(1, int(d["steps"] * d["dt"] / interval) + 2)
                     if m0 <= round(k * interval / d["dt"]) < m1)
        d["t_loop"] = (e1 - e0) / (m1 - m0)
        for _ in range(2):
            d["t_snap"] = max(0.0, d["loop_wall"] - e1 - (d["steps"] - m1) * d["t_loop"])
            d["t_loop"] = (e1 - e0 - inside * d["t_snap"]) / (m1 - m0)
        d["inside"] = inside
    else:
        # too few progress lines (a smoke run): the whole loop, its two snapshots included
        d["t_loop"], d["t_snap"] = d["loop_wall"] / d["steps"], float("nan")
    d["setup"] = sum(float(t) for name, t in
                     re.findall(r"^set-up: (.*) in (\S+) s$", log, re.M)
                     if name != "processed deck formed")
    for key, pattern in (("factor_mb", r"([\d.E+-]+) MB stored on every rank"),
                         ("geometry_mb", r"\(([\d.E+-]+) MB of stored geometry\)")):
        m = re.search(pattern, log)
        d[key] = float(m.group(1)) if m else 0.0
    return d


def floor_bytes(case, b, log):
    """The bytes one step must move once (the memory-bound floor is these over the STREAM
    triad), and what they are:
    - lumped, assembled K (hertz-*, plate-*): K u's bytes of doc/performance.md §1 (blocks
      32 B + 4 B column index, row pointers, u read and K u written): with history every step
      every step is a single step and reads K;
    - consistent (Cholesky): the product the step takes from K's upper blocks (diagonal and
      upper blocks, the same per-block and per-row bytes) plus the factor read twice (forward
      and backward) for one solve;
    - NLGEOM and -element (element loop): the stored shape derivatives and volume weights
      (the log's MB), the connectivity (4 B per node of an element) and u read, f written
      (16 B per node and component).
    - box-* (3D, 3 x 3 blocks): K u's bytes as in 2D with 72 B blocks and 3 components."""
    nrows = b["nodes"]
    nd = int(b.get("ndm", 2))
    nnzb = (b["bytes_kmv"] - 36.0 * nrows) / 36.0
    if case.endswith(("-nlgeom", "-element")):
        nen = {"c3d8": 8, "c3d20": 20, "q8": 8}.get(case.split("-")[1], 9)
        return (1e6 * log["geometry_mb"] + 4.0 * nen * b["nel"] + 16.0 * nd * nrows,
                "geometry + connectivity + u, f")
    if b["consistent"]:
        upper = 36.0 * (nnzb + nrows) / 2 + 36.0 * nrows
        return upper + 2e6 * log["factor_mb"], "K upper + 2 x factor"
    return b["bytes_kmv"], "K u"


def run_case(args, work, case, size, ranks=1):
    """Writes the decks of case at about size elements and runs them: ictus-bench (kernels,
    STREAM, dt), ictus with history every step, and (np = 1) ictus with history off.
    Returns the measurements (a dict) or, when the case cannot run, {"failed": reason}."""
    family = case.split("-")[0]
    tag = f"{case}-{size:g}"
    model = os.path.join(work, f"{tag}_model.inp")
    force = "ELEMENT" if case.endswith("-element") else "AUTO"
    t0 = time.time()
    if ranks == 1 or not os.path.exists(model):
        make = {"hertz": hertz_model, "plate": plate_model, "box": box_model}[family]
        nel, nlgeom = make(model, case, size)
        with open(model + ".info", "w") as f:
            f.write(f"{nel} {int(nlgeom)}\n")
    with open(model + ".info") as f:
        nel, nlgeom = (int(v) for v in f.read().split())
    tdeck = time.time() - t0
    slow = case.endswith(("-consistent", "-nlgeom", "-element"))
    steps = args.steps or (100 if slow else 500)
    t_user = T_USER[family]
    deck = os.path.join(work, f"{tag}.inp")
    # ictus-bench: the step's kernels without output, STREAM, and the automatic dt
    step_deck(deck, model, nlgeom, t_user, t_user, 1, force)
    try:
        b = bm.run_bench(args, deck, nel, slow, ranks, steps=max(8, min(40, round(2e6 / nel))),
                         extra=["--no-elem"])
    except RuntimeError as e:
        lines = str(e).splitlines()
        return {FAILED: ([ln for ln in lines if "error" in ln.lower()] + lines)[0][:300],
                "nel": nel}
    res = {"nel": nel, "bench": b, "deck_s": tdeck, "ranks": ranks}
    # the runs: history every step, then (np = 1) history off; t_end = steps x dt
    runs = [("on", 1)] + ([("off", HIST_OFF)] if ranks == 1 else [])
    for name, every in runs:
        step_deck(deck, model, nlgeom, steps * b["dt"], t_user, every, force)
        try:
            log, wall, peaks = run_ictus(args, deck, ranks)
        except RuntimeError as e:
            res[FAILED] = str(e)[:300]
            return res
        if args.work:
            with open(os.path.join(work, f"{tag}-{name}{'' if ranks == 1 else '-np2'}.log"),
                      "w") as f:
                f.write(log)
        d = parse_log(log, t_user / 100)
        d["wall"], d["peaks"] = wall, peaks
        res[name] = d
    return res


# ---------------------------------------------------------------- table

HEAD = ["case", "elements", "dofs", "steps", "dt", "step", "hist off", "record", "snapshot s",
        "fields", "output share", "1-step", "K u", "contact", "mass", "floor", "step/floor",
        "floor B/el", "floor bytes", "STREAM GB/s", "peak MB", "peak KB/el", "set-up s"]


def figures(res):
    """The derived figures of one case (ns per element per step unless said): the step as
    users get it (history every step, snapshots every 1 % of the user's run), its parts, the
    floor."""
    b, on, nel = res["bench"], res["on"], res["nel"]
    off = res.get("off")
    dt = on["dt"]
    family = res["case"].split("-")[0]
    # snapshots per step in the user's run of T_USER: 100 of them in T/dt steps
    per_step = 100.0 * dt / T_USER[family]
    f = {"loop": 1e9 * on["t_loop"] / nel,
         "fields": 1e9 * on["t_snap"] * per_step / nel if on["t_snap"] == on["t_snap"] else 0.0}
    f["step"] = f["loop"] + f["fields"]
    f["off"] = 1e9 * off["t_loop"] / nel if off else None
    fb, what = floor_bytes(res["case"], b, on)
    f["floor_bytes"], f["floor_what"] = fb, what
    f["floor"] = 1e9 * fb / b["stream"] / nel
    return f


def row(res):
    case = res["case"] + ("" if res.get("ranks", 1) == 1 else f" np={res['ranks']}")
    if FAILED in res and "on" not in res:
        return [case, f"{res['nel']}"] + [FAILED if i == 0 else "-" for i in range(len(HEAD) - 2)]
    b, on, nel = res["bench"], res["on"], res["nel"]
    f = figures(res)
    peak = max(on["peaks"])

    def ns(x, digits=1):
        return "-" if x is None else f"{x:.{digits}f}"
    return [case, f"{nel}", f"{int(b.get('ndm', 2) * b['nodes'])}", f"{on['steps']}",
            f"{on['dt']:.3g}",
            ns(f["step"]), ns(f["off"]) + ("" if res.get("off", {}).get("tuned") in
                                           (None, True) else "*"),
            ns(f["loop"] - f["off"]) if f["off"] else "-",
            f"{on['t_snap']:.2f}" if on["t_snap"] == on["t_snap"] else "-",
            ns(f["fields"], 2),
            f"{(f['step'] - f['off']) / f['step']:.2f}" if f["off"] else "-",
            ns(bm.ns_el(b, "t_single")), ns(bm.ns_el(b, "t_kmv")) if b["t_kmv"] > 0 else "-",
            ns(bm.ns_el(b, "t_contact")) if b["contact_points"] else "-",
            ns(bm.ns_el(b, "t_mass")) if b["consistent"] else "-",
            ns(f["floor"]), f"{f['step'] / f['floor']:.2f}",
            f"{f['floor_bytes'] / nel:.0f}", f["floor_what"], f"{b['stream'] / 1e9:.1f}",
            "/".join(f"{p / 1e6:.0f}" for p in on["peaks"]), f"{peak / 1e3 / nel:.2f}",
            f"{on['setup']:.1f}"]


def verdicts(res, np2):
    """The acceptance lines of issue #31 that this suite measures: (target, measured,
    verdict) rows; res[case][nel] the runs on one rank, np2[case][nel] on two."""
    out = []

    def add(target, measured, ok):
        out.append((target, measured, "reported" if ok is None else "met" if ok else "MISSED"))

    def ok(r):
        return r is not None and FAILED not in r

    for disc in ("iga", "q8"):
        runs = {n: r for n, r in res.get(f"hertz-{disc}", {}).items() if ok(r)}
        if not runs:
            continue
        big = max(runs)
        f = figures(runs[big])
        add(f"hertz-{disc}: whole step (history every step) <= 1.5 x its memory-bound floor "
            f"({big} el.)", f"{f['step'] / f['floor']:.2f} x", f["step"] <= 1.5 * f["floor"]
            if disc == "iga" and big >= 5e5 else None)
        for n, r in sorted(runs.items()):
            f = figures(r)
            add(f"hertz-{disc}: history every step <= 1.3 x history off ({n} el.)",
                f"{f['loop'] / f['off']:.2f} x", f["loop"] <= 1.3 * f["off"])
        cons = {n: r for n, r in res.get(f"hertz-{disc}-consistent", {}).items() if ok(r)}
        for n in sorted(set(cons) & set(runs)):
            r = figures(cons[n])["step"] / figures(runs[n])["step"]
            add(f"hertz-{disc}-consistent: step <= 2.5 x the lumped step ({n} el., "
                f"{bm.SOLVERS.get(int(cons[n]['bench']['mass_solver']), '?')})", f"{r:.2f} x",
                r <= 2.5 if disc == "iga" else None)
        nl = {n: r for n, r in res.get(f"hertz-{disc}-nlgeom", {}).items() if ok(r)}
        for n in sorted(set(nl) & set(runs)):
            r = figures(nl[n])["step"] / figures(runs[n])["step"]
            add(f"hertz-{disc}-nlgeom: step / the small-strain step ({n} el.)", f"{r:.2f} x",
                None)
    for etype in ("c3d8", "c3d20"):
        runs = {n: r for n, r in res.get(f"box-{etype}", {}).items() if ok(r)}
        for n, r in sorted(runs.items()):
            f = figures(r)
            add(f"box-{etype} (3D, assembled K): whole step <= 1.5 x its memory-bound floor "
                f"({n} el.)", f"{f['step'] / f['floor']:.2f} x",
                f["step"] <= 1.5 * f["floor"] if etype == "c3d8" and n >= 5e5 else None)
            add(f"box-{etype}: history off / floor ({n} el.)", f"{f['off'] / f['floor']:.2f} x",
                None)
        el = {n: r for n, r in res.get(f"box-{etype}-element", {}).items() if ok(r)}
        for n in sorted(set(el) & set(runs)):
            r = figures(el[n])["step"] / figures(runs[n])["step"]
            add(f"box-{etype}-element: the element-loop step / the assembled step ({n} el.)",
                f"{r:.2f} x", None)
    for case, runs in sorted(np2.items()):
        for n, r2 in runs.items():
            r1 = res[case][n]
            if not (ok(r1) and ok(r2)):
                continue
            ratio = max(r2["on"]["peaks"]) / max(r1["on"]["peaks"])
            add(f"{case}: peak memory per rank, np = 2 / np = 1 <= 0.6 ({n} el.)",
                f"{ratio:.2f} x", ratio <= 0.6 if n >= 5e5 else None)
    return out


def run_suite(args, work, sizes, cases):
    """Runs the cases at the sizes and prints the table and the verdicts."""
    try:
        import gmsh  # noqa: F401
        have_gmsh = True
    except ImportError:
        have_gmsh = False
    if not os.access(os.path.join(args.build_dir, "bin", "ictus"), os.X_OK):
        sys.exit(f"benchmark: {args.build_dir}/bin/ictus not found")
    load0, t_start = bm.loadavg(), time.time()
    res, np2, rows, notes = {}, {}, [], []
    for case in cases:
        if case.startswith("plate") and not have_gmsh:
            notes.append(f"{case}: skipped, the gmsh Python module is missing (Debian: "
                         "apt-get install gmsh python3-gmsh)")
            continue
        for size in sorted(sizes):
            t0 = time.time()
            r = run_case(args, work, case, size)
            r["case"] = case
            res.setdefault(case, {})[r["nel"]] = r
            rows.append(row(r))
            report(r, time.time() - t0)
            if ranks2(args, case, size, sizes) and FAILED not in r:
                t0 = time.time()
                r2 = run_case(args, work, case, size, ranks=2)
                r2["case"] = case
                np2.setdefault(case, {})[r["nel"]] = r2
                rows.append(row(r2))
                report(r2, time.time() - t0)
            for x in (r, np2.get(case, {}).get(r["nel"], {})):
                if FAILED in x:
                    notes.append(f"{case} ({x['nel']} el., np = {x.get('ranks', 1)}): "
                                 f"{x[FAILED]}")
            if not args.work and size > 2e5:
                # the decks of 1e6 elements take GBs: keep only those of the next case
                for f in os.listdir(work):
                    if f.startswith(f"{case}-{size:g}"):
                        os.remove(os.path.join(work, f))
    load1 = bm.loadavg()
    print()
    print(f"load average (1 min) at the start {load0:.2f}, at the end {load1:.2f} on "
          f"{os.cpu_count()} CPUs; the suite took {time.time() - t_start:.0f} s")
    print("ns per element per step; 'step': the ictus time loop with history every step "
          "and a field snapshot every 1 % of the user's run (T = 0.9 Hertz, 1.0 plate), "
          "'hist off' the same deck with history every 1e8 steps (* the SWEEP STEPS=AUTO "
          "tuning had not ended), 'record' their difference, 'fields' the snapshots per step "
          "of the user's run; '1-step', 'K u', 'contact', 'mass' from ictus-bench on the "
          "same deck (no output); 'floor' the bytes of 'floor bytes' once per step over the "
          "STREAM triad; 'peak' the high-water mark of each rank")
    bm.print_table(rows, HEAD)
    print()
    print("| target | measured | verdict |")
    print("|---|---:|---|")
    for t, m, v in verdicts(res, np2):
        print(f"| {t} | {m} | {v} |")
    for n in notes:
        print("benchmark: " + n)
    # the checks of the kernel suite on the ictus-bench runs: the spread of the np = 1
    # triads, the np = 2 triad against the np = 1 one
    checks = bm.host_checks(
        {c: {n: r["bench"] for n, r in runs.items() if "bench" in r} for c, runs in res.items()},
        {c: (res[c][n]["bench"], r["bench"]) for c, runs in np2.items() for n, r in runs.items()
         if "bench" in r})
    if max(load0, load1) > 1.5:
        checks.insert(0, f"the load average was {max(load0, load1):.2f} (other processes "
                      "were running)")
    if checks:
        print()
        print("benchmark: WARNING: the host's memory bandwidth or load moved during this run; "
              "each floor uses the triad of its own case (run again):")
        for line in checks:
            print("  - " + line)


def report(r, seconds):
    what = f"{r['case']}{'' if r.get('ranks', 1) == 1 else ' np=2'}"
    if FAILED in r and "on" not in r:
        print(f"  {what:22s} {r['nel']:8d} el.: {FAILED}: {r[FAILED]}", flush=True)
        return
    f = figures(r)
    print(f"  {what:22s} {r['nel']:8d} el.: step {f['step']:8.1f} ns/el, floor "
          f"{f['floor']:6.1f} (decks {r['deck_s']:.0f} s, all runs {seconds:.0f} s)", flush=True)


def ranks2(args, case, size, sizes):
    """The np = 2 runs: the lumped Hertz cases at the largest size."""
    return (not args.no_mpi and args.mpirun is not None and size == max(sizes)
            and case in ("hertz-iga", "hertz-q8"))


if __name__ == "__main__":
    if len(sys.argv) > 4 and sys.argv[1] == "--peak" and sys.argv[3] == "--":
        peak_main(sys.argv)
    sys.exit("real.py: run by bench/benchmark.py --suite real (or real.py --peak FILE -- CMD)")
