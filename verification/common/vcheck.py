"""Shared helpers of the verification cases: run ictus on a deck, read its results file,
compare numbers with expected values from physics, print one line per check and a closing
line, exit non-zero on any failure.

Every case is run by CTest as
    python3 <case>/check.py --ictus <path to ictus> --work <scratch dir>
"""
import argparse
import os
import subprocess
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "scripts", "mesh"))


def arguments():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ictus", required=True, help="the ictus executable")
    ap.add_argument("--work", required=True, help="scratch directory for decks and results")
    ap.add_argument("--mpiexec", default="", help="launcher prefix, e.g. 'mpirun -np 2'")
    ap.add_argument("--mpirun", default="mpirun",
                    help="MPI launcher for cases that choose the number of ranks themselves")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    return a


def run_ictus(args, deck, out=None, expect_status=0, extra=(), np=None, env=None):
    """Runs ictus on `deck` (on `np` MPI ranks when given; `env`: variables added to the
    environment), returns (status, output). Fails the case on a wrong exit status."""
    launcher = args.mpiexec.split() if args.mpiexec else []
    if np is not None:
        launcher = args.mpirun.split() + ["--oversubscribe", "-np", str(np)]
    cmd = launcher + [args.ictus, deck] + list(extra)
    if out:
        cmd += ["-o", out]
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       env=dict(os.environ, **env) if env else None)
    if p.returncode != expect_status:
        print(p.stdout)
        print(f"FAILED: {' '.join(cmd)} exited with {p.returncode}, expected {expect_status}")
        sys.exit(1)
    return p.returncode, p.stdout


def require_gmsh():
    """Exits with status 77 (CTest's skip) and a message when the gmsh Python module is
    missing."""
    try:
        import gmsh  # noqa: F401
    except ImportError:
        print("SKIPPED: the gmsh Python module is missing (Debian: apt-get install gmsh "
              "python3-gmsh; scripts/setup.sh installs it)")
        sys.exit(77)


class Results:
    """Read access to an ictus results file."""

    def __init__(self, path):
        self.f = h5py.File(path, "r")

    def attr(self, name):
        v = self.f.attrs[name]
        return v.decode() if isinstance(v, bytes) else v

    def history(self, name):
        return np.asarray(self.f["history/" + name])

    def field_steps(self):
        return sorted(self.f["fields"].keys())

    def field(self, step, name):
        return np.asarray(self.f[f"fields/{step}/{name}"])

    def field_time(self, step):
        return float(self.f[f"fields/{step}"].attrs["time"])

    def model(self, name):
        return np.asarray(self.f["model/" + name])


class Checker:
    def __init__(self, case):
        self.case, self.n, self.failed = case, 0, 0

    def close(self, got, want, rtol, label):
        self.n += 1
        err = abs(got - want) / (abs(want) if want != 0 else 1.0)
        ok = err <= rtol
        self.failed += not ok
        print(f"  {'ok  ' if ok else 'FAIL'} {label}: got {got:.6g}, expected {want:.6g}, "
              f"rel. error {err:.3g} (tolerance {rtol:.3g})")

    def below(self, got, limit, label):
        self.n += 1
        ok = got <= limit
        self.failed += not ok
        print(f"  {'ok  ' if ok else 'FAIL'} {label}: {got:.6g} (limit {limit:.6g})")

    def true(self, cond, label):
        self.n += 1
        self.failed += not cond
        print(f"  {'ok  ' if cond else 'FAIL'} {label}")

    def finish(self):
        verdict = "PASSED" if self.failed == 0 and self.n > 0 else "FAILED"
        print(f"VERIFICATION {self.case}: {verdict} ({self.n - self.failed} of {self.n} checks)")
        sys.exit(0 if verdict == "PASSED" else 1)


def material_block(name="MAT", e=1000.0, nu=0.2, rho=1.0):
    return f"*MATERIAL, NAME={name}\n*ELASTIC\n{e}, {nu}\n*DENSITY\n{rho}\n"


def mesh_points(mesh):
    """(id, x, y) of every node of the *NODE cards of a mesh text ((id, x, y, z) for the nodes
    of a 3D mesh)."""
    pts = []
    in_nodes = False
    for line in mesh.splitlines():
        if line.upper().startswith("*NODE"):
            in_nodes = True
            continue
        if line.startswith("*"):
            in_nodes = False
        elif in_nodes and line.strip():
            v = [s.strip() for s in line.split(",")]
            pts.append((int(v[0]), *(float(x) for x in v[1:])))
    return pts


def square_patch(name, spans, offset=0.0, extra=""):
    """A quadratic patch on the unit square shifted by `offset` (both directions): uniform
    knots, control points at the Greville abscissae (an affine map). Returns the cards
    (*PATCH with `extra` parameters, *KNOTS, *CONTROL POINTS) and the (id, x, y) of the
    control points, ids 1..n^2 in patch order."""
    knots = [0.0, 0.0] + [k / spans for k in range(spans + 1)] + [1.0, 1.0]
    n = spans + 2
    grev = [(knots[i + 1] + knots[i + 2]) / 2 for i in range(n)]
    cps, pts = [], []
    for j in range(n):
        for i in range(n):
            x, y = grev[i] + offset, grev[j] + offset
            cps.append(f"{x!r}, {y!r}, 1")
            pts.append((len(pts) + 1, x, y))
    kn = " ".join(repr(k) for k in knots)
    cards = (f"*PATCH, NAME={name}, MATERIAL=MAT, DEGREE=2,2, SIZE={n},{n}{extra}\n"
             f"*KNOTS, DIRECTION=1\n{kn}\n*KNOTS, DIRECTION=2\n{kn}\n*CONTROL POINTS\n"
             + "\n".join(cps) + "\n")
    return cards, pts


def rect_mesh(**kw):
    """The cards of a structured rectangle (scripts/mesh/rect.py) as a string."""
    import io
    import types
    import rect
    defaults = dict(type="Q8", x0=0.0, y0=0.0, first_node=1, first_element=1, elset="BODY",
                    material="MAT", prefix="", distort=0.0)
    defaults.update(kw)
    buf = io.StringIO()
    rect.write_mesh(types.SimpleNamespace(**defaults), buf)
    return buf.getvalue()


def box_mesh(**kw):
    """The cards of a structured box of hexahedra (scripts/mesh/box.py) as a string."""
    import io
    import types
    import box
    defaults = dict(type="C3D20", x0=0.0, y0=0.0, z0=0.0, first_node=1, first_element=1,
                    elset="BODY", material="MAT", prefix="", distort=0.0)
    defaults.update(kw)
    buf = io.StringIO()
    box.write_mesh(types.SimpleNamespace(**defaults), buf)
    return buf.getvalue()


def bar_wave_exact(x, t, v0, length, c):
    """The axial displacement of a bar [0, length] moving at -v0 and held at x = 0 from t = 0
    on, by characteristics (wave speed c), for t <= 2 length/c:
      t <= L/c:          u = -v0 min(t, x/c)
      L/c <= t <= 2L/c:  u = -v0 x/c for x <= 2L - ct, u = v0 (t - 2L/c) beyond."""
    if t <= length / c:
        return -v0 * np.minimum(t, x / c)
    return np.where(x <= 2 * length - c * t, -v0 * x / c, v0 * (t - 2 * length / c))


def check_bar_wave(chk, r, label, v0, length, c, lateral, mass, mass_text):
    """The checks of a bar wave's results r (vcheck.Results; the bar along x, held at x = 0,
    every field snapshot against bar_wave_exact): the mass-weighted RMS error of u_x over all
    snapshots (2 %: the O(h) error at the kink of the front), the free-end displacement at
    the last one (2 %), the largest lateral over axial displacement (below `lateral`), the
    energy balance (5e-3) and the total mass against `mass` (1e-12; `mass_text` says what it
    is). `label` starts every check's text."""
    x = r.model("coordinates")[:, 0]
    m = r.model("mass")
    worst = 0.0
    for step in r.field_steps():
        t = r.field_time(step)
        u = r.field(step, "displacement")[:, 0]
        scale = v0 * min(t, length / c) if t > 0 else 1.0
        err = np.sqrt(np.sum(m * (u - bar_wave_exact(x, t, v0, length, c)) ** 2) / np.sum(m))
        worst = max(worst, err / scale)
    chk.below(worst, 0.02, f"{label}mass-weighted RMS error of u over all snapshots / v0 t")
    last = r.field_steps()[-1]
    t = r.field_time(last)
    u = r.field(last, "displacement")
    tip = np.isclose(x, length)
    chk.close(float(np.mean(u[tip, 0])), float(bar_wave_exact(np.array([length]), t, v0,
              length, c)[0]), 0.02, f"{label}free-end displacement at t = {t:.4f}")
    lat = float(np.max(np.abs(u[:, 1:])) / np.max(np.abs(u[:, 0])))
    chk.below(lat, lateral, f"{label}lateral / axial motion (nu = 0)")
    etot = r.history("energy/total")
    chk.below(float(np.max(np.abs(etot - etot[0])) / etot[0]), 5e-3,
              f"{label}energy conservation max |E(t) - E(0)|/E(0)")
    chk.close(float(np.sum(m)), mass, 1e-12, f"{label}total mass {mass_text}")


def same_bits(a, b):
    """Whether every dataset under /history and /fields of two results files is equal, bit
    for bit (and there is at least one)."""
    fa, fb = h5py.File(a, "r"), h5py.File(b, "r")
    names = []
    for g in ("history", "fields"):
        fa[g].visititems(lambda n, o: names.append(g + "/" + n) if hasattr(o, "shape") else None)
    return len(names) > 0 and all(n in fb and np.array_equal(fa[n][()], fb[n][()]) for n in names)


def check_ranks_and_restart(args, chk, path, out, ranks=(2,), expect_status=0, label=""):
    """Runs deck `path` (whose 1-rank results are `out`, with a checkpoint next to them) on
    each number of ranks in `ranks`, and continues the 1-rank run on 2 ranks from its last
    checkpoint; each must give every history and field dataset of `out` bit for bit."""
    import shutil
    for n in ranks:
        o = out.replace(".h5", f"_np{n}.h5")
        run_ictus(args, path, o, np=n, expect_status=expect_status)
        chk.true(same_bits(out, o), f"{label}{n} ranks: every history and field dataset "
                 "bit-identical")
    o = out.replace(".h5", "_restart.h5")
    shutil.copy(out, o)
    run_ictus(args, path, o, np=2, expect_status=expect_status,
              extra=("--restart", out.replace(".h5", ".chk.h5")))
    chk.true(same_bits(out, o), f"{label}restart on 2 ranks from a checkpoint of the 1-rank "
             "run: bit-identical")


def processed_deck_reruns(args, out):
    """Runs the processed deck stored in the results file `out` (the root attribute `deck`
    with its bulk data under /deck, written back out by scripts/deck_from_results.py) and
    returns whether it gives the same history and fields bit for bit."""
    path = out.replace(".h5", "_processed.inp")
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts",
                          "deck_from_results.py")
    subprocess.run([sys.executable, script, out, "-o", path], check=True)
    again = out.replace(".h5", "_processed.h5")
    run_ictus(args, path, again)
    return same_bits(out, again)
