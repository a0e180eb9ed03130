#!/usr/bin/env python3
"""Runs the Hertz suite of input/hertz/ and writes its table and figures (doc/verification.md).

    /usr/bin/python3 scripts/hertz_suite.py --ictus build/bin/ictus --out results/hertz \
        [--groups paper series static] [--table verification/hertz/results_table.md] \
        [--figures doc/figures] [--reuse]

groups: paper (the paper's cases at dt = 5e-4, 8 x 8), series (refinement), static, or fig3
(only the two runs of the paper's Fig. 3); also fig4 (the three NURBS lumpings), one (the upper
body moving, the lower at rest), conv_q8 and conv_iga (the HRZ refinement of each
discretisation). --reuse skips runs whose results file is newer than
the deck. The table (markdown) is printed and, with --table, written; the figures are PNGs in
--figures.
"""
import argparse
import os
import re
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "verification", "hertz"))
import hertz_cases as hcases  # noqa: E402
import hertz_compare as hc  # noqa: E402
import hertz_static as hs  # noqa: E402
import hertz_theory as ht  # noqa: E402


def run_case(ictus, case, out, reuse):
    h5 = os.path.join(out, case.name + ".h5")
    log = os.path.join(out, case.name + ".log")
    if reuse and os.path.exists(h5) and os.path.getmtime(h5) > os.path.getmtime(case.deck) \
            and os.path.exists(log):
        return h5, open(log).read()
    t0 = time.time()
    p = subprocess.run([ictus, case.deck, "-o", h5], stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    with open(log, "w") as f:
        f.write(p.stdout)
    if p.returncode != 0:
        sys.stdout.write(p.stdout[-3000:])
        raise SystemExit(f"hertz_suite: {case.name} failed with status {p.returncode}")
    print(f"  ran {case.name} in {time.time() - t0:.1f} s", file=sys.stderr)
    return h5, p.stdout


def log_numbers(text):
    """omega_max, dt and the contact ratio r (at the start) from the ictus log."""
    om = re.search(r"omega_max = ([0-9.Ee+-]+)", text)
    r = re.search(r"stability ratio r = [^=]*= ([0-9.Ee+-]+)", text)
    dt = re.search(r"step: dt = ([0-9.Ee+-]+)", text)
    return dict(omega=float(om.group(1)) if om else float("nan"),
                r=float(r.group(1)) if r else float("nan"),
                dt_run=float(dt.group(1)) if dt else float("nan"))


def smooth_peak(res, window=0.02):
    """Peak of the force averaged over a moving window (removes the contact chatter)."""
    r = res["run"]
    k = max(1, int(round(window / res["dt"])))
    f = np.convolve(r.force, np.ones(k) / k, mode="same")
    return float(np.max(f))


def dynamic_table(rows):
    head = ("| case | mesh | mass | Δt | ω_max Δt | r | F_max | t(F_max) | F_max/F_qs "
            "| F̄_max/F_qs | t_c | t_c/t_c,qs | p_max/p0,qs | OI | OI_max | impulse "
            "| I/m(V+V_reb)−1 | V_reb/V_w | momentum | ΔE/E0 |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n")
    out = []
    for c, res, ln in rows:
        out.append(
            f"| {c.name} | {c.mesh_label} | {c.mass_label} | {res['dt']:.3g} "
            f"| {ln['omega'] * res['dt']:.2f} | {ln['r']:.2f} | {res['f_max']:.1f} "
            f"| {res['t_peak']:.3f} | {res['f_max'] / res['f_qs']:.3f} "
            f"| {res['f_smooth'] / res['f_qs']:.3f} | {res['t_c']:.4f} "
            f"| {res['t_c'] / res['tc_qs']:.3f} | {res['p_max'] / res['p0_qs']:.2f} "
            f"| {res['oi']:.3f} | {res['oi_max']:.2f} | {res['impulse']:.2f} "
            f"| {res['impulse_err']:+.1e} | {res['restitution']:.3f} | {res['momentum_err']:.1e} "
            f"| {res['energy_loss']:.4f} |")
    return head + "\n".join(out) + "\n"


def static_table(rows):
    head = ("| case | mesh | Δt (auto) | P (half) | P full | b | b^h | h at b | spans in b "
            "| p0 | p0^h | p0^h/p0 − 1 | ∫p dx / P − 1 | RMS(p − Hertz)/p0 |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n")
    out = []
    for c, s, ln in rows:
        out.append(f"| {c.name} | {c.mesh_label} | {ln['dt_run']:.3g} | {s['P_half']:.3f} "
                   f"| {s['P_full']:.3f} | {s['b']:.4f} | {s['bh']:.4f} | {s['h_b']:.4f} "
                   f"| {s['spans_in_b']} | {s['p0']:.3f} | {s['p0h']:.3f} "
                   f"| {s['p0h'] / s['p0'] - 1:+.4f} | {s['int_p'] / s['P_half'] - 1:+.4f} "
                   f"| {s['rms']:.4f} |")
    return head + "\n".join(out) + "\n"


def figures(dyn, stat, outdir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    os.makedirs(outdir, exist_ok=True)
    by = {c.name: (c, res) for c, res, _ in dyn}
    q1, q17 = ht.benchmark(4.0, 1.0), ht.benchmark(4.0, 1.7)
    tt = np.linspace(0.0, 0.9, 901)
    made = []

    def history_figure(names, title, fname):
        if not all(n in by for n in names):
            return
        fig, ax = plt.subplots(2, 1, figsize=(8, 8), sharex=True)
        for n in names:
            c, res = by[n]
            r = res["run"]
            ax[0].plot(r.t, r.force, lw=0.8, label=f"{c.mesh_label}, {c.mass_label}")
            ax[1].plot(r.t, r.pmax, lw=0.8, label=f"{c.mesh_label}, {c.mass_label}")
        for q, st, lab in ((q1, "k--", "quasi-static Hertz, C = 1"),
                           (q17, "k:", "quasi-static Hertz, C = 1.7")):
            pf = q.force_at(tt)
            ax[0].plot(tt, pf / 2, st, lw=1.2, label=lab)
            ax[1].plot(tt, ht.peak_pressure(pf), st, lw=1.2, label=lab)
        ax[0].set_ylabel("contact force per half model")
        ax[1].set_ylabel("maximal contact pressure")
        ax[1].set_xlabel("time")
        ax[1].set_ylim(0, 2.2 * float(ht.peak_pressure(q17.p_max)))
        ax[0].set_title(title)
        for a in ax:
            a.grid(alpha=0.3)
            a.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(outdir, fname), dpi=110)
        plt.close(fig)
        made.append(fname)

    history_figure(["q8_hrz", "iga_hrz"], "Dynamic Hertz, V_rel = 4, dt = 5e-4: FEA Q8 vs IGA, HRZ",
                   "hertz_fig3_fea_vs_iga.png")
    history_figure(["iga_hrz", "iga_rowsum", "iga_consistent"],
                   "Dynamic Hertz, IGA p = 2, 8 x 8, dt = 5e-4: mass matrices", "hertz_fig4_iga_mass.png")
    history_figure(["q8_hrz_24", "iga_hrz_24"], "Dynamic Hertz, finest meshes (24 x 24)",
                   "hertz_fine_fea_vs_iga.png")

    # pressure distribution at the snapshot nearest the peak force
    names = [n for n in ("q8_hrz", "iga_hrz", "iga_consistent", "q8_hrz_24", "iga_hrz_24")
             if n in by]
    if names:
        fig, axs = plt.subplots(1, len(names), figsize=(4 * len(names), 4), sharey=True)
        axs = np.atleast_1d(axs)
        for a, n in zip(axs, names):
            c, res = by[n]
            r = res["run"]
            steps = np.array(sorted(r.snap))
            k_peak = int(np.argmax(r.force))
            s = int(steps[np.argmin(np.abs(steps - k_peak))])
            x, p = r.pressure_at(s)
            pf = 2.0 * r.force[s]
            xe = np.linspace(0, 1.1 * ht.half_width(pf), 300)
            a.plot(xe, ht.pressure(xe, pf), "k-", lw=1.2, label="Hertz at the current force")
            a.plot(x, p, "o-", ms=3, lw=0.8, label="ictus (Gauss points)")
            a.set_title(f"{c.mesh_label} {c.mass_label}\nt = {r.t[s]:.3f}, F = {r.force[s]:.1f}",
                        fontsize=9)
            a.set_xlim(0, 2.0)
            a.set_xlabel("x (current)")
            a.grid(alpha=0.3)
        axs[0].set_ylabel("contact pressure")
        axs[0].legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(outdir, "hertz_pressure_at_peak.png"), dpi=110)
        plt.close(fig)
        made.append("hertz_pressure_at_peak.png")

    # convergence
    series = {"IGA p=2 HRZ": [n for n in ("iga_hrz", "iga_hrz_12", "iga_hrz_16", "iga_hrz_24")
                              if n in by],
              "Q8 HRZ": [n for n in ("q8_hrz", "q8_hrz_12", "q8_hrz_16", "q8_hrz_24") if n in by]}
    if any(len(v) > 1 for v in series.values()):
        fig, ax = plt.subplots(1, 3, figsize=(14, 4))
        for lab, names in series.items():
            if not names:
                continue
            nn = [int(re.search(r"(\d+)x", by[n][0].mesh_label).group(1)) for n in names]
            fm = [by[n][1]["f_max"] for n in names]
            fs = [by[n][1]["f_smooth"] for n in names]
            tc = [by[n][1]["t_c"] for n in names]
            oi = [by[n][1]["oi"] for n in names]
            col = "C0" if lab.startswith("IGA") else "C1"
            ax[0].plot(nn, fm, "o-", color=col, label=f"{lab}: F_max")
            ax[0].plot(nn, fs, "s--", color=col, label=f"{lab}: F_max (0.02 moving mean)")
            ax[1].plot(nn, tc, "o-", color=col, label=lab)
            ax[2].plot(nn, oi, "o-", color=col, label=lab)
        for a, q, qq, yl in ((ax[0], q1.p_max / 2, q17.p_max / 2, "peak force (half model)"),
                             (ax[1], q1.t_c, q17.t_c, "contact duration")):
            a.axhline(q, color="k", ls="--", lw=1, label="quasi-static C = 1")
            a.axhline(qq, color="k", ls=":", lw=1, label="quasi-static C = 1.7")
            a.set_ylabel(yl)
        ax[2].set_ylabel("oscillation index OI")
        for a in ax:
            a.set_xlabel("spans / elements per direction n")
            a.grid(alpha=0.3)
            a.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(outdir, "hertz_convergence.png"), dpi=110)
        plt.close(fig)
        made.append("hertz_convergence.png")

    if stat:
        fig, axs = plt.subplots(1, len(stat), figsize=(5 * len(stat), 4), sharey=True)
        axs = np.atleast_1d(axs)
        for a, (c, s, _) in zip(axs, stat):
            xe = np.linspace(0, 1.2 * s["b"], 300)
            a.plot(xe, ht.pressure(xe, s["P_full"]), "k-", lw=1.2,
                   label=f"Hertz, P = {s['P_full']:.2f} (full)")
            a.plot(s["x"], s["p"], "o", ms=3, label="ictus (Gauss points)")
            a.axvline(s["bh"], color="C1", ls=":", lw=1, label="b^h")
            a.set_xlim(0, 1.4 * s["b"])
            a.set_title(f"static Hertz, {c.mesh_label}", fontsize=9)
            a.set_xlabel("x (reference)")
            a.grid(alpha=0.3)
            a.legend(fontsize=8)
        axs[0].set_ylabel("contact pressure")
        fig.tight_layout()
        fig.savefig(os.path.join(outdir, "hertz_static.png"), dpi=110)
        plt.close(fig)
        made.append("hertz_static.png")
    return made


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ictus", default=os.path.join(ROOT, "build", "bin", "ictus"))
    ap.add_argument("--out", default=os.path.join(ROOT, "results", "hertz"))
    ap.add_argument("--groups", nargs="*", default=["paper", "series", "static"])
    ap.add_argument("--table", default=None)
    ap.add_argument("--figures", default=None)
    ap.add_argument("--reuse", action="store_true")
    a = ap.parse_args()
    known = sorted({g for c in hcases.ALL for g in c.groups})
    bad = [g for g in a.groups if g not in known]
    if bad or not a.groups:
        sys.exit(f"hertz_suite: --groups: expected one or more of {', '.join(known)}, got "
                 f"{' '.join(bad) if bad else 'none'}")
    if not (os.path.isfile(a.ictus) and os.access(a.ictus, os.X_OK)):
        sys.exit(f"hertz_suite: --ictus: {a.ictus} is not an executable (build it with "
                 "scripts/setup.sh, or give its path)")
    for d in [a.out] + ([a.figures] if a.figures else []):
        try:
            os.makedirs(d, exist_ok=True)
        except OSError as e:
            sys.exit(f"hertz_suite: cannot create the directory {d}: {e.strerror}")
    if a.table:
        try:
            open(a.table, "a").close()
        except OSError as e:
            sys.exit(f"hertz_suite: --table: cannot write {a.table}: {e.strerror}")
    want = set(a.groups)
    dyn, stat = [], []
    for c in hcases.ALL:
        if not want.intersection(c.groups):
            continue
        h5, log = run_case(a.ictus, c, a.out, a.reuse)
        ln = log_numbers(log)
        if "static" in c.groups:
            s = hs.analyse_static(h5, c.args)
            stat.append((c, s, ln))
        else:
            res = hc.analyse(h5, c.v_rel, c.wall)
            res["f_smooth"] = smooth_peak(res)
            dyn.append((c, res, ln))
    text = ["# Hertz suite: ictus against Hertz theory\n\n",
            "Written by `scripts/hertz_suite.py` (doc/verification.md explains every column). "
            "Forces per half model (full cylinder / 2).\n\n"]
    if dyn:
        text.append(hc.reference_block(sorted({c.v_rel for c, _, _ in dyn}, reverse=True)))
        for v in sorted({c.v_rel for c, _, _ in dyn}, reverse=True):
            text.append(f"\n## Dynamic, V_rel = {v:g}\n\n")
            text.append(dynamic_table([x for x in dyn if x[0].v_rel == v]))
    if stat:
        text.append("\n## Static Hertz (dynamic relaxation, one half-disc on a rigid wall)\n\n")
        text.append(static_table(stat))
    out = "".join(text)
    sys.stdout.write(out)
    if a.table:
        with open(a.table, "w") as f:
            f.write(out)
    if a.figures:
        made = figures(dyn, stat, a.figures)
        print("figures: " + ", ".join(os.path.join(a.figures, m) for m in made))


if __name__ == "__main__":
    main()
