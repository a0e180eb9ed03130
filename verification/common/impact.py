"""Helpers of the contact verification cases: 1D-like bars (Q8 or p = 2 NURBS, plane stress,
nu = 0) and the analysis of a contact force history against the exact impact of doc/reference.md
§3.1-3.2 (plateau force, contact duration, impulse)."""
import re

import numpy as np

import vcheck

E, RHO = 1000.0, 1.0
C = (E / RHO) ** 0.5


def header(title, analysis="PLANE STRESS", nu=0.0):
    return (f"*HEADING\n{title}\n*ANALYSIS, TYPE={analysis}, THICKNESS=1\n"
            + vcheck.material_block(e=E, nu=nu, rho=RHO))


def q8_bar(name, x0, length, height, nx, first_node=1, first_element=1, ny=1, y0=0.0,
           etype="Q8"):
    """A rectangle of nx x ny elements; element set `name` (also a node set), node sets
    <name>_LEFT/RIGHT/TOP/BOTTOM/CORNER_*, surfaces <name>_LEFT/RIGHT/TOP/BOTTOM (element faces
    S4/S2/S3/S1). Returns (cards, next free node id, next free element id)."""
    cards = vcheck.rect_mesh(type=etype, nx=nx, ny=ny, lx=length, ly=height, x0=x0, y0=y0,
                             first_node=first_node, first_element=first_element, elset=name,
                             prefix=name + "_")
    ids = [int(line.split(",")[0]) for line in cards.split("*ELEMENT")[0].splitlines()[1:]]
    els = list(range(first_element, first_element + nx * ny))
    faces = {"LEFT": ([els[j * nx] for j in range(ny)], "S4"),
             "RIGHT": ([els[j * nx + nx - 1] for j in range(ny)], "S2"),
             "BOTTOM": (els[:nx], "S1"), "TOP": (els[-nx:], "S3")}
    for side, (elist, face) in faces.items():
        cards += f"*SURFACE, NAME={name}_{side}, TYPE=ELEMENT\n"
        cards += "".join(f"{e}, {face}\n" for e in elist)
    return cards, max(ids) + 1, first_element + nx * ny


def iga_block(name, x0, y0, length, height, n1, n2, p=2):
    """A rectangular NURBS patch of degree p (p + 1 control points per direction refined to
    n1 x n2 spans: control points at the Greville abscissae, so x is linear in xi), node sets
    and surfaces <name>_LEFT/RIGHT/BOTTOM/TOP (sides XI0/XI1/ETA0/ETA1). Returns the cards
    and the number of control points."""
    cps = "".join(f"{x0 + length * i / p!r}, {y0 + height * j / p!r}, 1.0\n"
                  for j in range(p + 1) for i in range(p + 1))
    knots = " ".join(["0"] * (p + 1) + ["1"] * (p + 1))
    cards = (f"*PATCH, NAME={name}, MATERIAL=MAT, DEGREE={p},{p}, SIZE={p + 1},{p + 1}\n"
             f"*KNOTS, DIRECTION=1\n{knots}\n*KNOTS, DIRECTION=2\n{knots}\n"
             "*CONTROL POINTS\n" + cps + f"*REFINE, PATCH={name}, SUBDIVIDE={n1},{n2}\n")
    for side, code in (("LEFT", "XI0"), ("RIGHT", "XI1"), ("BOTTOM", "ETA0"), ("TOP", "ETA1")):
        cards += f"*NSET, NSET={name}_{side}, PATCH={name}, SIDE={code}\n"
        cards += f"*SURFACE, NAME={name}_{side}, PATCH={name}, SIDE={code}\n"
    return cards, (n1 + p) * (n2 + p)


def step(t_end, dt=0.0, field_every=100):
    return (f"*STEP\n*DYNAMIC, EXPLICIT\n{dt!r}, {t_end!r}\n*OUTPUT, HISTORY, EVERY=1\n"
            f"*OUTPUT, FIELD, EVERY={field_every}\n*END STEP\n")


def ratios(log):
    """The contact stability ratios r printed by a run (at the start and at activation)."""
    return [float(x) for x in re.findall(
        r"stability ratio r = (?:dt\^2 eps \(l_s/m_s \+ l_m/m_m\) = )?([-+0-9.eE]+)", log)]


def pulse(t, f, dt):
    """Contact pulse of a force history f(t) recorded every step (the force of the last
    correction): start and end times, duration, impulse sum f dt, mean over the middle 80 %."""
    on = np.nonzero(np.abs(f) > 0.0)[0]
    if len(on) == 0:
        return dict(duration=0.0, impulse=0.0, plateau=0.0, t0=0.0, t1=0.0)
    t0, t1 = t[on[0]], t[on[-1]]
    dur = t1 - t0 + dt
    mid = (t >= t0 + 0.1 * dur) & (t <= t1 - 0.1 * dur)
    return dict(duration=dur, impulse=float(np.sum(f) * dt), plateau=float(np.mean(f[mid])),
                t0=t0, t1=t1, nbursts=int(np.sum(np.diff(on) > 1)) + 1)
