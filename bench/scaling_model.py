#!/usr/bin/python3
"""The written scaling model of doc/scaling.md §3 as a table: the predicted step time of the
Hertz pair (NURBS p = 2, lumped mass, 2D) at 64, 512 and 4096 ranks, for 1e6 and 1e8 elements,
with and without contact and with history every step or off. Every input is a flag; the
defaults are the measured rates of doc/scaling.md §2 (this host, np = 2) and the stated
network model (InfiniBand HDR). Nothing here is measured: it is arithmetic on the inputs.

Per step, on one rank of p, for a model of N elements (two half-discs of n x n spans,
N = 2 n^2):
- element work: N/p x rate (ns per element-step, the per-rank rate measured with both cores
  of this host busy; history on: the step with its record);
- halo: one exchange of u per step (step_finish; inside sweeps one per step for the zone
  rows), to and from each of `nbr` neighbours: nbr alpha + bytes/beta, bytes = 2 x 16 B x
  ghost nodes, ghost nodes = depth x perimeter of a compact part of m = N/p elements in 2D
  (4 sqrt(m) element edges, depth p = 2 control points for NURBS p = 2);
- global reductions: `red` all-reduces of <= 3 doubles (history every step: three
  reproducible dot products, each an all-reduce of the maximum and one of 3 level sums),
  each 2 log2(p) alpha;
- contact gather: one all-reduce of 2 doubles per contact node (ncn = 2 (n + 2) control
  points on the two arcs): 2 log2(p) alpha + 2 (p - 1)/p x 16 ncn / beta;
- contact evaluation: every rank evaluates every contact point (ncp = 3 n): ncp x c_pt.
Peak memory per rank (--memory): base + rep x N + dist x N/p, rep the bytes per element that
every rank holds (the whole model_t and what is built from it), dist those that divide among
the ranks (K, the state vectors, the results' buffers), fitted to the peaks of §1.
"""
import argparse
import math


def predict(a, nel, p, contact, hist):
    n = math.sqrt(nel / 2)
    m = nel / p
    rate = a.rate_hist if hist else a.rate_off
    t = {"work": nel / p * rate * 1e-9}
    ghosts = a.depth * 4 * math.sqrt(m) if p > 1 else 0.0
    t["halo"] = (a.nbr * a.alpha + 2 * 16 * ghosts / a.beta) if p > 1 else 0.0
    lat = 2 * math.log2(p) * a.alpha if p > 1 else 0.0
    nred = (a.red_hist_contact if contact else a.red_hist) if hist else 0
    t["reductions"] = nred * lat
    ncn, ncp = 2 * (n + 2), 3 * n
    t["gather"] = (lat + 2 * (p - 1) / p * 16 * ncn / a.beta) if contact and p > 1 else 0.0
    t["contact"] = ncp * a.c_pt * 1e-9 if contact else 0.0
    t["total"] = sum(t.values())
    return t


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rate-off", type=float, default=23.1,
                    help="ns per element-step per rank, history off (measured, §2)")
    ap.add_argument("--rate-hist", type=float, default=66.3,
                    help="ns per element-step per rank, history every step (measured, §2)")
    ap.add_argument("--c-pt", type=float, default=150.0,
                    help="ns per contact point and step, every rank (measured, §2)")
    ap.add_argument("--alpha", type=float, default=1.5e-6, help="latency, s")
    ap.add_argument("--beta", type=float, default=25e9, help="link bandwidth, B/s")
    ap.add_argument("--nbr", type=int, default=6, help="halo neighbours of a 2D METIS part")
    ap.add_argument("--depth", type=float, default=2.0,
                    help="ghost layers (control points) across a part's edge")
    ap.add_argument("--red-hist", type=int, default=4,
                    help="all-reduces per recorded step without contact (2 repro_dot)")
    ap.add_argument("--red-hist-contact", type=int, default=6,
                    help="all-reduces per recorded step with contact (3 repro_dot)")
    ap.add_argument("--sizes", default="1e6,1e8")
    ap.add_argument("--memory", action="store_true", help="the peak memory per rank instead")
    ap.add_argument("--mem-base", type=float, default=38e6, help="bytes per rank (fitted)")
    ap.add_argument("--mem-rep", type=float, default=637.0,
                    help="replicated bytes per element (fitted)")
    ap.add_argument("--mem-dist", type=float, default=2982.0,
                    help="distributed bytes per element (fitted)")
    ap.add_argument("--ranks", default="1,64,512,4096")
    a = ap.parse_args()
    if a.memory:
        print("| elements | np | replicated GB | distributed GB | peak per rank GB |")
        print("|---:|---:|---:|---:|---:|")
        for nel in (float(s) for s in a.sizes.split(",")):
            for p in (int(x) for x in a.ranks.split(",")):
                rep, dist = a.mem_base + a.mem_rep * nel, a.mem_dist * nel / p
                print(f"| {nel:.0e} | {p} | {rep / 1e9:.3g} | {dist / 1e9:.3g} | "
                      f"{(rep + dist) / 1e9:.3g} |")
        return
    keys = ["work", "halo", "reductions", "gather", "contact", "total"]
    print("| elements | contact | history | np | " + " | ".join(
        f"{k} µs" for k in keys) + " | speed-up | efficiency |")
    print("|---:|---|---|---:|" + "---:|" * (len(keys) + 2))
    for nel in (float(s) for s in a.sizes.split(",")):
        for contact in (False, True):
            for hist in (False, True):
                t1 = predict(a, nel, 1, contact, hist)["total"]
                for p in (int(x) for x in a.ranks.split(",")):
                    t = predict(a, nel, p, contact, hist)
                    s = t1 / t["total"]
                    print(f"| {nel:.0e} | {'yes' if contact else 'no'} | "
                          f"{'every step' if hist else 'off'} | {p} | " +
                          " | ".join(f"{1e6 * t[k]:.3g}" for k in keys) +
                          f" | {s:.3g} | {s / p:.2f} |")


if __name__ == "__main__":
    main()
