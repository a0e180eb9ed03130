#!/usr/bin/env python3
"""Mass of the half-disc R = 4 of doc/iga.md §10.4, IGA and Q8 from the same deck family
(scripts/mesh/halfdisc.py), rho = 1: sum of /model/mass (row sums of the consistent mass, or
the lumped masses; every scheme conserves the element mass) against the exact area.

IGA (exact geometry): sum m = rho * pi R^2/2 = 8 pi rho up to quadrature only. The NURBS
Jacobian is rational, so (p+1)^2 Gauss points per span integrate it exactly only in the
limit; the error falls like h^(2p+2): 4.1e-12 (p = 2, 16 x 16 spans), 7e-14 (p = 2, 32 x 32),
below 1e-15 (p = 3, 16 x 16). Gate 1e-12 with p = 2 on 32 x 32 spans and p = 3 (*ELEVATE) on
16 x 16.

Q8 (nodes on the NURBS map at the Q8 node parameters, n x n elements): the body is bounded by
the straight cut and by parabolic arcs through three nodes on the circle. By Archimedes, the
parabola through the end nodes and the node at its parameter midpoint cuts off 4/3 of the
triangle of those three points, so an arc edge of angle theta whose middle node sits at angle
delta from the bisector loses exactly
    D = R^2 [ (theta - sin theta)/2 - (4/3) sin(theta/2) (cos delta - cos(theta/2)) ]
          ~ R^2 (theta^5/960 + theta delta^2/3)
of area. Gate: sum m = rho (8 pi - sum D) to 1e-12 (the Q8 area integrals are exact: det J is
a polynomial of degree 3 per direction). The measured geometric error (sum m - 8 pi)/8 pi is
printed and must be within 1 % of the leading-order -R^2 sum(theta^5/960 + theta delta^2/3)/(8 pi);
n = 16 gives -1.279e-7, falling as n^-4 (n = 8: -2.04e-6, n = 32: -8.0e-9).

Finally the committed decks input/halfdisc/*.inp must regenerate identically from the command
on their first line, and run to their end (free flight, t = 0.9) with that mass (IGA p = 2
on 16 x 16 spans: 1e-11, its quadrature error being 4.1e-12) and constant total energy
(1e-10: round-off over several thousand steps).
"""
import glob
import math
import os
import shlex
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import numpy as np  # noqa: E402
import vcheck  # noqa: E402
import halfdisc  # noqa: E402  (scripts/mesh, on the path through vcheck)

R, RHO = 4.0, 1.0
EXACT = RHO * math.pi * R * R / 2.0


def run(args, name, **kw):
    a = halfdisc.options(radius=R, rho=RHO, vy=-2.0, t_end=2e-3, **kw)
    path = os.path.join(args.work, name + ".inp")
    with open(path, "w") as f:
        f.write(halfdisc.deck(a, "verification/iga_halfdisc_mass/check.py"))
    out = os.path.join(args.work, name + ".h5")
    vcheck.run_ictus(args, path, out)
    return vcheck.Results(out)


def archimedes_deficit(net, n, centre):
    """Sum of D over the Q8 arc edges (every boundary edge except the straight cut), exact and
    to leading order."""
    m = 2 * n
    sides = halfdisc.control_net(R, centre)[1]
    total, lead = 0.0, 0.0
    cy = R if centre == "upper" else -R
    for side in ("XI0", "XI1", "ETA0", "ETA1"):
        if side == sides["SYM"]:
            continue
        for e in range(n):
            pts = []
            for s in (2 * e, 2 * e + 1, 2 * e + 2):
                uv = {"XI0": (0, s), "XI1": (m, s), "ETA0": (s, 0), "ETA1": (s, m)}[side]
                x, y, _ = halfdisc.patch_map(net, uv[0] / m, uv[1] / m)
                pts.append(math.atan2(y - cy, x))
            theta = abs(pts[2] - pts[0])
            delta = pts[1] - 0.5 * (pts[0] + pts[2])
            total += R * R * ((theta - math.sin(theta)) / 2
                              - 4.0 / 3.0 * math.sin(theta / 2) * (math.cos(delta) - math.cos(theta / 2)))
            lead += R * R * (theta ** 5 / 960 + theta * delta ** 2 / 3)
    return total, lead


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("iga_halfdisc_mass")
    for name, kw in (("iga_p2", dict(kind="iga", subdivide=32, mass="CONSISTENT")),
                     ("iga_p2_hrz", dict(kind="iga", subdivide=32, mass="HRZ")),
                     ("iga_p3", dict(kind="iga", elevate=3, subdivide=16, mass="ROW SUM")),
                     ("iga_p3_lower", dict(kind="iga", elevate=3, subdivide=16, mass="HRZ",
                                           centre="lower"))):
        r = run(args, name, **kw)
        m = r.model("mass")
        chk.close(float(m.sum()), EXACT, 1e-12, f"{name} ({kw['mass']}): sum of nodal masses = 8 pi rho")
        chk.true(bool((m > 0).all()), f"{name}: all control-point masses positive")
    for centre in ("upper", "lower"):
        n = 16
        r = run(args, f"q8_{centre}", kind="q8", n=n, mass="HRZ", centre=centre)
        net = halfdisc.control_net(R, centre)[0]
        d, lead = archimedes_deficit(net, n, centre)
        total = float(r.model("mass").sum())
        chk.close(total, RHO * (EXACT / RHO - d), 1e-12,
                  f"Q8 {n}x{n} ({centre}): sum m = rho (8 pi - Archimedes deficit of the arcs)")
        err = (total - EXACT) / EXACT
        print(f"  info Q8 {n}x{n} ({centre}): geometric mass error (sum m - 8 pi rho)/(8 pi rho)"
              f" = {err:.4g}; exact -sum D/(8 pi) = {-d / EXACT:.4g}, leading order "
              f"{-lead / EXACT:.4g}")
        chk.close(err, -lead / EXACT, 0.01,
                  f"Q8 {n}x{n} ({centre}): relative mass error ~ -R^2 sum(theta^5/960 + theta delta^2/3)/(8 pi)")
    committed_decks(args, chk)
    chk.finish()


def committed_decks(args, chk):
    """input/halfdisc/*.inp: each regenerates identically from the command on its first line,
    and runs to its end (t = 0.9, free flight) with the mass of its discretisation and
    energy conserved."""
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    decks = sorted(glob.glob(os.path.join(root, "input", "halfdisc", "*.inp")))
    chk.true(len(decks) >= 3, "input/halfdisc holds the IGA p = 2, p = 3 and Q8 decks")
    for path in decks:
        name = os.path.basename(path)
        with open(path) as f:
            text = f.read()
        first = text.splitlines()[0]
        prefix = "** generated by: "
        chk.true(first.startswith(prefix + "scripts/mesh/halfdisc.py"), f"{name}: command on line 1")
        cmd = shlex.split(first[len(prefix):])
        p = subprocess.run([sys.executable, os.path.join(root, cmd[0])] + cmd[1:],
                           stdout=subprocess.PIPE, text=True, cwd=root)
        chk.true(p.returncode == 0 and p.stdout == text, f"{name}: regenerates identically")
        out = os.path.join(args.work, name.replace(".inp", ".h5"))
        vcheck.run_ictus(args, path, out)
        r = vcheck.Results(out)
        total = float(r.model("mass").sum())
        a = halfdisc.parser().parse_args(cmd[1:])
        if a.kind == "iga":
            # quadrature error of the rational Jacobian: 4.1e-12 for p = 2 on 16 x 16 spans
            chk.close(total, a.rho * EXACT / RHO, 1e-11, f"{name}: sum m = 8 pi rho")
        else:
            d = archimedes_deficit(halfdisc.control_net(a.radius, a.centre)[0], a.n, a.centre)[0]
            chk.close(total, a.rho * (EXACT / RHO - d), 1e-12, f"{name}: sum m = rho (8 pi - D)")
        etot = r.history("energy/total")
        chk.below(float(np.max(np.abs(etot - etot[0])) / etot[0]), 1e-10,
                  f"{name}: energy conserved in free flight to t = {r.history('time')[-1]:.3f}")


if __name__ == "__main__":
    main()
