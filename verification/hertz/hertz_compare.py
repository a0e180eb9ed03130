#!/usr/bin/env python3
"""Measures an ictus run of the dynamic Hertz benchmark against the quasi-static Hertz model
(hertz_theory.py, doc/reference.md §2.1, §2.4) and writes the comparison table.

    hertz_compare.py RESULTS_DIR [--cases name ...] [--table verification/hertz/results_table.md]

For every case of hertz_cases.CASES whose results file RESULTS_DIR/<name>.h5 exists it reports
(all forces per HALF model, i.e. full-cylinder force / 2, doc/reference.md §2.4):

* peak force F_max and its time, against the quasi-static C = 1 value and the C = 1.7 band;
* contact duration t_c = time of the last step with a contact force (contact starts at t = 0);
* peak contact pressure max_t max_q p_q, against Hertz p0 at the quasi-static peak force;
* impulse I = sum_n F_n dt (the momentum the contact transferred to the upper body);
* rebound velocity V_reb = (v_upper - v_lower)/2 at the end (centre-of-mass velocities from
  /model/mass and the last velocity field), and the coefficient of restitution V_reb/V_w;
* impulse check: I against m (V_w + V_reb), m = 8 pi rho the mass of one half-disc;
* total momentum (both bodies, x and y) at the end against its initial value;
* oscillation index OI: the RMS over the middle 80 % of the contact, [0.1 t_c, 0.9 t_c], of
  max_q p_q(t) / p0(2 F(t)) - 1, where p0(P) = sqrt(P E*/(pi R*)) is the Hertz peak pressure of
  the CURRENT simulated (full) force (doc/verification.md §3); and its largest value OI_max.
"""
import argparse
import math
import os
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import hertz_theory as ht  # noqa: E402

M_HALF = 0.5 * math.pi * ht.RHO * ht.R ** 2     # one half-disc, 8 pi


class Run:
    """The results file of one benchmark run, reduced to what the comparison needs."""

    def __init__(self, path):
        with h5py.File(path, "r") as f:
            self.t = np.asarray(f["history/time"])
            self.dt = np.asarray(f["history/dt"])
            pairs = list(f["history/contact"].keys())
            self.pair = pairs[0]
            g = f["history/contact/" + self.pair]
            f1, f2 = np.asarray(g["force_first"]), np.asarray(g["force_second"])
            self.wall = self.pair == "wall"
            if self.wall:                   # first surface = the upper body's arc, pushed up
                self.force = f1[:, 1].copy()
                self.force_mismatch = 0.0
            else:                           # first = LOWER_ARC (pushed down), second = UPPER_ARC
                self.force = 0.5 * (f2[:, 1] - f1[:, 1])
                big = max(float(np.max(np.abs(self.force))), 1e-300)
                # y only: mirror symmetry about y = 0 gives both bodies the same x force
                self.force_mismatch = float(np.max(np.abs(f1[:, 1] + f2[:, 1]))) / big
            self.pmax = np.asarray(g["max_pressure"])
            self.active = np.asarray(g["active_points"])
            self.energy = {k: np.asarray(f["history/energy/" + k]) for k in f["history/energy"]}
            self.mass = np.asarray(f["model/mass"])
            ids = np.asarray(f["model/node_ids"])
            if "model/patches/upper" in f:
                self.upper = np.isin(ids, np.asarray(f["model/patches/upper/ids"]))
            else:
                self.upper = ids < 100000
            steps = sorted(f["fields"].keys())
            self.field_steps = steps
            self.v_end = np.asarray(f[f"fields/{steps[-1]}/velocity"])
            self.v_start = np.asarray(f[f"fields/{steps[0]}/velocity"])
            self.t_end_field = float(f[f"fields/{steps[-1]}"].attrs["time"])
            self.snap = {}
            if "contact/" + self.pair in f:
                for s in f["contact/" + self.pair]:
                    grp = f[f"contact/{self.pair}/{s}"]
                    self.snap[int(s)] = (np.asarray(grp["x"]), np.asarray(grp["pressure"]))
            deck = f.attrs.get("deck", b"")
            self.deck = deck.decode() if isinstance(deck, bytes) else str(deck)

    def body_velocity(self, v, upper=True):
        sel = self.upper if upper else ~self.upper
        m = self.mass[sel]
        return v[sel].T @ m / np.sum(m)

    def pressure_at(self, step):
        """Contact-point x (distance from the symmetry line) and pressure at field step `step`,
        sorted by x, of the first surface."""
        x, p = self.snap[step]
        order = np.argsort(x[:, 0])
        return x[order, 0], p[order]


def analyse(path, v_rel, wall=False):
    """All comparison numbers of one run (a dict); v_rel the initial approach speed."""
    r = Run(path)
    v_w = 0.5 * v_rel
    qs1, qs17 = ht.benchmark(v_rel, 1.0), ht.benchmark(v_rel, 1.7)
    dt = float(r.dt[-1])
    on = np.nonzero(r.force > 0.0)[0]
    k_peak = int(np.argmax(r.force))
    res = dict(path=path, dt=dt, f_max=float(r.force[k_peak]), t_peak=float(r.t[k_peak]),
               f_qs=qs1.p_max / 2, f_qs17=qs17.p_max / 2, tc_qs=qs1.t_c, tc_qs17=qs17.t_c)
    res["t_c"] = float(r.t[on[-1]]) if len(on) else 0.0
    gaps = np.nonzero(np.diff(on) > 1)[0] if len(on) else []
    res["separations"] = int(len(gaps))        # contact lost and regained during the impact
    res["p_max"] = float(np.max(r.pmax))
    res["p0_qs"] = float(ht.peak_pressure(qs1.p_max))
    res["impulse"] = float(np.sum(r.force[1:] * r.dt[1:]))
    vu = r.body_velocity(r.v_end, True)
    if wall:
        res["v_reb"] = float(vu[1])
        res["momentum_err"] = 0.0
    else:
        vl = r.body_velocity(r.v_end, False)
        res["v_reb"] = float(0.5 * (vu[1] - vl[1]))
        # y only: the symmetry condition u_x = 0 on the cuts takes x reactions
        p_end = float(r.v_end[:, 1] @ r.mass)
        p_0 = float(r.v_start[:, 1] @ r.mass)
        res["momentum_err"] = abs(p_end - p_0) / (M_HALF * v_w)
    res["restitution"] = res["v_reb"] / v_w
    res["m_upper"] = float(np.sum(r.mass[r.upper]))
    res["impulse_expected"] = res["m_upper"] * (v_w + res["v_reb"])
    res["impulse_err"] = res["impulse"] / res["impulse_expected"] - 1.0
    res["force_mismatch"] = r.force_mismatch
    # oscillation index against Hertz p0 at the current force
    t_c = res["t_c"]
    mid = (r.t >= 0.1 * t_c) & (r.t <= 0.9 * t_c) & (r.force > 0.0)
    ratio = r.pmax[mid] / ht.peak_pressure(2.0 * r.force[mid]) - 1.0
    res["oi"] = float(np.sqrt(np.mean(ratio ** 2))) if len(ratio) else float("nan")
    res["oi_max"] = float(np.max(np.abs(ratio))) if len(ratio) else float("nan")
    res["oi_mean"] = float(np.mean(ratio)) if len(ratio) else float("nan")
    res["oi_median"] = float(np.median(ratio)) if len(ratio) else float("nan")
    e = r.energy["total"]
    res["energy_loss"] = float((e[0] - e[-1]) / e[0])
    res["run"] = r
    return res


def table_rows(results):
    """Markdown table of the comparison (one row per case)."""
    head = ("| case | mesh | mass | Δt | F_max | t(F_max) | F_max/F_qs | t_c | t_c/t_c,qs | p_max "
            "| p_max/p0,qs | OI | OI_max | impulse | I/m(V+V_reb)−1 | V_reb | e | momentum | ΔE/E0 |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n")
    rows = []
    for c, res in results:
        rows.append(
            f"| {c.name} | {c.mesh_label} | {c.mass_label} | {res['dt']:.3g} | {res['f_max']:.1f} "
            f"| {res['t_peak']:.3f} | {res['f_max'] / res['f_qs']:.3f} | {res['t_c']:.4f} "
            f"| {res['t_c'] / res['tc_qs']:.3f} | {res['p_max']:.1f} "
            f"| {res['p_max'] / res['p0_qs']:.3f} | {res['oi']:.3f} | {res['oi_max']:.3f} "
            f"| {res['impulse']:.2f} | {res['impulse_err']:+.1e} | {res['v_reb']:.3f} "
            f"| {res['restitution']:.3f} | {res['momentum_err']:.1e} | {res['energy_loss']:.4f} |")
    return head + "\n".join(rows) + "\n"


def reference_block(v_rels):
    out = ["Quasi-static Hertz reference (doc/reference.md §2.1; per half model = full/2):\n\n",
           "| V_rel | F_qs (C = 1) | F (C = 1.7) | t_c,qs (C = 1) | t_c (C = 1.7) | p0 at F_qs "
           "| b at F_qs |\n|---|---|---|---|---|---|---|\n"]
    for v in v_rels:
        a, b = ht.benchmark(v, 1.0), ht.benchmark(v, 1.7)
        out.append(f"| {v:g} | {a.p_max / 2:.2f} | {b.p_max / 2:.2f} | {a.t_c:.4f} | {b.t_c:.4f} "
                   f"| {float(ht.peak_pressure(a.p_max)):.2f} | {ht.half_width(a.p_max):.4f} |\n")
    return "".join(out)


def main():
    import hertz_cases
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", help="directory with <case>.h5")
    ap.add_argument("--cases", nargs="*", default=None)
    ap.add_argument("--table", default=None, help="write the markdown table here")
    a = ap.parse_args()
    cases = [c for c in hertz_cases.CASES if a.cases is None or c.name in a.cases]
    results = []
    for c in cases:
        path = os.path.join(a.results, c.name + ".h5")
        if not os.path.exists(path):
            continue
        results.append((c, analyse(path, c.v_rel, c.wall)))
    groups = sorted({c.v_rel for c, _ in results})
    text = ["# Dynamic Hertz benchmark: ictus against the quasi-static Hertz model\n\n",
            "Written by `verification/hertz/hertz_compare.py`; forces per half model. Columns: "
            "doc/verification.md §3.\n\n", reference_block(groups or [4.0]), "\n"]
    for v in groups:
        text.append(f"V_rel = {v:g}:\n\n")
        text.append(table_rows([(c, r) for c, r in results if c.v_rel == v]))
        text.append("\n")
    out = "".join(text)
    sys.stdout.write(out)
    if a.table:
        with open(a.table, "w") as f:
            f.write(out)


if __name__ == "__main__":
    main()
