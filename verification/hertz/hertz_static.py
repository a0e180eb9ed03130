#!/usr/bin/env python3
"""Static Hertz (doc/reference.md §7) from a dynamic-relaxation run of input/hertz/static_*.inp:
one half-disc pressed onto a rigid wall (its top arc moved down, mass-proportional damping).

The contact points of the results file are Gauss points (3 per span or Q8 edge) in the
CURRENT configuration. Linear (small-strain) theory measures x and the pressure per length in
the reference configuration, so the reference position and length weight of every Gauss point
are rebuilt here from the same geometry as the deck (scripts/mesh/hertz.py): Gauss point q of
segment s at t_q = 1/2 + (-1, 0, 1) sqrt(3/5)/2, weight w_q = (5, 8, 5)/18,
    x_q = x_s(t_q),   dx_q = w_q |d x_s/dt (t_q)|  (x component: Hertz' x is horizontal).
The wall is flat, so the code's resultant is P_h = sum_q p_q w_q J_q (reference arc length J).

Reported: P_h (half model; the full-cylinder load is 2 P_h), the Hertz b, p0 at that load,
p0^h = max p_q, b^h = midpoint between the last loaded and the first unloaded Gauss point,
the contact length per element at the edge h_b, int p dx, and the RMS deviation of p_q from
the ellipse over |x| < b (relative to p0).
"""
import math
import os
import shlex
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "scripts", "mesh"))
import hertz_theory as ht  # noqa: E402
import hertz  # noqa: E402
import halfdisc  # noqa: E402

TQ = 0.5 + np.array([-1.0, 0.0, 1.0]) * math.sqrt(0.6) / 2
WQ = np.array([5.0, 8.0, 5.0]) / 18.0


def reference_gauss_points(args):
    """Reference x and horizontal length weights of the Gauss points on UPPER_ARC of the deck
    made by hertz.py `args` (a string), sorted by x."""
    a = hertz.parser().parse_args(shlex.split(args))
    net, _ = halfdisc.control_net(4.0, "upper")
    q_arc = a.grade_arc
    xs, ws = [], []
    if a.kind == "iga":
        k = hertz.graded_knots(a.subdivide, q_arc)[2:-2]
        for u0, u1 in zip(k[:-1], k[1:]):
            for t, w in zip(TQ, WQ):
                u, eps = u0 + t * (u1 - u0), 1e-7
                x = halfdisc.patch_map(net, u, 0.0)[0]
                xp = (halfdisc.patch_map(net, min(u + eps, 1.0), 0.0)[0]
                      - halfdisc.patch_map(net, max(u - eps, 0.0), 0.0)[0]) / (2 * eps)
                xs.append(x)
                ws.append(w * abs(xp) * (u1 - u0))
    else:
        g = hertz.graded_knots(a.n, q_arc)[2:-2]
        for g0, g1 in zip(g[:-1], g[1:]):
            pts = [halfdisc.patch_map(net, u, 0.0)[0] for u in (g0, 0.5 * (g0 + g1), g1)]
            for t, w in zip(TQ, WQ):
                n = np.array([(1 - t) * (1 - 2 * t), 4 * t * (1 - t), t * (2 * t - 1)])
                dn = np.array([4 * t - 3, 4 - 8 * t, 4 * t - 1])
                xs.append(float(n @ pts))
                ws.append(w * abs(float(dn @ pts)))
    xs, ws = np.array(xs), np.array(ws)
    o = np.argsort(xs)
    return xs[o], ws[o]


def analyse_static(path, args):
    with h5py.File(path, "r") as f:
        g = f["contact/wall"]
        last = sorted(g.keys())[-1]
        xc = np.asarray(g[last]["x"])[:, 0]
        p = np.asarray(g[last]["pressure"])
        force = np.asarray(f["history/contact/wall/force_first"])[:, 1]
        t = np.asarray(f["history/time"])
        ek = np.asarray(f["history/energy/kinetic"])
        es = np.asarray(f["history/energy/strain"])
    p = p[np.argsort(xc)]
    xr, wr = reference_gauss_points(args)
    ph = float(force[-1])
    p_full = 2.0 * ph
    b, p0 = ht.half_width(p_full), float(ht.peak_pressure(p_full))
    act = np.nonzero(p > 0.0)[0]
    k = int(act[-1])
    bh = 0.5 * (xr[k] + xr[k + 1])
    # element (span) length at the contact edge: the span holding Gauss point k
    s = k // 3
    h_b = float(xr[3 * s + 2] - xr[3 * s]) / float(TQ[2] - TQ[0])
    inside = np.abs(xr) < b
    i_late = t >= 0.8 * t[-1]
    res = dict(P_half=ph, P_full=p_full, b=b, p0=p0, p0h=float(np.max(p)), bh=bh, h_b=h_b,
               int_p=float(np.sum(p * wr)), spans_in_b=int(np.sum(xr[0::3] < b)),
               rms=float(np.sqrt(np.mean((p[inside] - ht.pressure(xr[inside], p_full)) ** 2))) / p0,
               drift=float(np.max(np.abs(force[i_late] - ph)) / ph),
               ek_rel=float(ek[-1] / max(es[-1], 1e-300)), x=xr, p=p)
    return res
