#!/usr/bin/env python3
"""Output selection: *OUTPUT, FIELD, VARIABLES= and TIME INTERVAL=, *OUTPUT, HISTORY, NSET=.

1. Free translation. A free block of distorted Q8 elements (HRZ mass, no supports, no loads)
   starts with the uniform velocity v0 = (0.3, -0.7). A rigid translation strains nothing, so
   every node keeps v0 and moves by v0 t: the history of node set BODY must hold the mean
   velocity v0 and the mean displacement v0 t (to round-off) at every record, and the summed
   reaction 0 (nothing is constrained). A set asked for VARIABLES=V holds only its velocity.
   The field output with TIME INTERVAL=dt_out has its snapshots at the steps closest to the
   multiples k dt_out, n_k = nint(k dt_out/dt) with dt the root attribute, and at the last
   step N = ceil(t_end/dt).
2. Acceleration of a deforming free body (the right edge starts with v_x = 1; HRZ and
   consistent mass). With no loads the internal forces sum to zero, so the momentum balance
   gives sum_i m_i a_i = 0 (m_i = /model/mass, the row sums of the mass matrix). The central
   difference step (doc/theory.md §4) gives, with v_n the mean of the half-step velocities
   and a_n = (v_{n+1/2} - v_{n-1/2})/dt, the identities v_{n+1} - v_n = dt (a_n + a_{n+1})/2
   and u_{n+1} - u_n = dt v_n + dt^2/2 a_n, checked on snapshots at every step. The node-set
   history equals the means of the field over the set, and is bit for bit the same on 1 and
   2 MPI ranks.
3. A uniform strain state: a Q4 block with every node but the centre one held at
   u = (a x + b y, c x + d y); the stress is the plane-strain Hooke's law of that strain.
   VARIABLES=S writes the stress and nothing else (no displacement: the XDMF sidecar has no
   displacement attribute and meshio still reads it); VARIABLES=E,MISES the strain and the
   von Mises stress of the closed form; the default writes displacement, velocity, stress and
   von Mises stress, but neither strain nor PEEQ (an elastic law) nor acceleration.
"""
import math
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
import vcheck  # noqa: E402

V0 = (0.3, -0.7)
E, NU = 1000.0, 0.2


def write(args, name, text):
    path = os.path.join(args.work, name + ".inp")
    with open(path, "w") as f:
        f.write(text)
    return path


def run(args, name, text, np_=None):
    path = write(args, name, text)
    out = os.path.join(args.work, name + ".h5")
    vcheck.run_ictus(args, path, out, np=np_)
    return vcheck.Results(out), out


def translation(args, chk):
    dt_out = 0.037
    text = ("*HEADING\nfree translation\n" + vcheck.material_block(e=E, nu=NU)
            + vcheck.rect_mesh(type="Q8", nx=4, ny=2, lx=4.0, ly=2.0, distort=0.2)
            + f"*INITIAL CONDITIONS, TYPE=VELOCITY\nBODY, 1, {V0[0]}\nBODY, 2, {V0[1]}\n"
            + "*MASS, TYPE=HRZ\n*STEP\n*DYNAMIC, EXPLICIT\n0, 0.5\n*OUTPUT, HISTORY, EVERY=3\n"
            + "*OUTPUT, HISTORY, NSET=BODY\n*OUTPUT, HISTORY, NSET=LEFT, VARIABLES=V\n"
            + f"*OUTPUT, FIELD, TIME INTERVAL={dt_out}\n*END STEP\n")
    r, _ = run(args, "translation", text)
    t = r.history("time")
    u = r.history("nset/body/displacement")
    v = r.history("nset/body/velocity")
    rf = r.history("nset/body/reaction")
    chk.true(u.shape == (len(t), 2) and v.shape == (len(t), 2) and rf.shape == (len(t), 2),
             f"nset/body: displacement, velocity, reaction of shape (nt, 2), nt = {len(t)}")
    chk.below(float(np.max(np.abs(v - np.array(V0)))), 1e-12,
              "nset/body: the mean velocity stays v0 at every record")
    chk.below(float(np.max(np.abs(u - np.outer(t, V0)))), 1e-12,
              "nset/body: the mean displacement is v0 t at every record")
    chk.true(np.all(rf == 0.0), "nset/body: summed reaction 0 (no constrained dof)")
    chk.true(sorted(r.f["history/nset/left"].keys()) == ["velocity"],
             "nset/left with VARIABLES=V holds only its velocity")
    chk.below(float(np.max(np.abs(r.history("nset/left/velocity") - np.array(V0)))), 1e-12,
              "nset/left: the mean velocity stays v0")
    dt = float(r.attr("dt"))
    nlast = math.ceil(0.5 / dt * (1 - 1e-12))
    want = sorted({int(math.floor(k * dt_out / dt + 0.5)) for k in range(int(0.5 / dt_out) + 2)
                   if k * dt_out / dt + 0.5 < nlast} | {nlast})
    got = [int(s) for s in r.field_steps()]
    chk.true(got == want, f"TIME INTERVAL={dt_out}: snapshots at the steps nint(k dt_out/dt) "
             f"and the last ({got} vs {want})")
    chk.true(all(abs(r.field_time(s) - int(s) * dt) <= 1e-12 for s in r.field_steps()),
             "TIME INTERVAL: each snapshot's time is its step times dt")


def deforming(args, chk, mass, np_=None, tag=""):
    text = ("*HEADING\ndeforming free body\n" + vcheck.material_block(e=E, nu=NU)
            + vcheck.rect_mesh(type="Q8", nx=4, ny=2, lx=4.0, ly=2.0, distort=0.2)
            + "*INITIAL CONDITIONS, TYPE=VELOCITY\nRIGHT, 1, 1.0\nTOP, 2, -0.5\n"
            + f"*MASS, TYPE={mass}\n*STEP\n*DYNAMIC, EXPLICIT\n0, 0.1\n"
            + "*OUTPUT, HISTORY, EVERY=1\n*OUTPUT, HISTORY, NSET=RIGHT, VARIABLES=U,V\n"
            + "*OUTPUT, FIELD, EVERY=1, VARIABLES=U,V,A\n*END STEP\n")
    return run(args, f"deforming_{mass.lower()}{tag}", text, np_)


def acceleration(args, chk):
    for mass in ("HRZ", "CONSISTENT"):
        r, _ = deforming(args, chk, mass)
        m = r.model("mass")
        dt = float(r.attr("dt"))
        steps = r.field_steps()
        u = np.array([r.field(s, "displacement") for s in steps])
        v = np.array([r.field(s, "velocity") for s in steps])
        a = np.array([r.field(s, "acceleration") for s in steps])
        chk.true(set(r.f["fields/" + steps[1]].keys()) >= {"acceleration", "displacement",
                                                          "velocity"}
                 and "stress" not in r.f["fields/" + steps[1]],
                 f"{mass}: VARIABLES=U,V,A writes displacement, velocity, acceleration, no stress")
        amax = float(np.max(np.abs(a)))
        chk.true(amax > 1.0, f"{mass}: the body deforms (max |a| = {amax:.3g})")
        mom = np.abs(np.einsum("i,kid->kd", m, a)).max()
        scale = np.einsum("i,kid->k", m, np.abs(a)).max()
        chk.below(float(mom / scale), 1e-12, f"{mass}: momentum balance sum m_i a_i = 0 "
                  "(relative to sum m_i |a_i|)")
        dv = (v[1:] - v[:-1]) / dt - 0.5 * (a[1:] + a[:-1])
        chk.below(float(np.abs(dv).max() / amax), 1e-9,
                  f"{mass}: (v_(n+1) - v_n)/dt = (a_n + a_(n+1))/2 at every step")
        du = (u[1:] - u[:-1]) - dt * v[:-1] - 0.5 * dt * dt * a[:-1]
        chk.below(float(np.abs(du).max() / (dt * np.abs(v).max())), 1e-9,
                  f"{mass}: u_(n+1) - u_n = dt v_n + dt^2/2 a_n at every step")
        rows = set_rows(r, "RIGHT", args, mass)
        hu = r.history("nset/right/displacement")
        hv = r.history("nset/right/velocity")
        chk.below(float(np.abs(hu - u[:, rows].mean(axis=1)).max()), 1e-14,
                  f"{mass}: nset/right mean displacement = the mean of the field over the set")
        chk.below(float(np.abs(hv - v[:, rows].mean(axis=1)).max()), 1e-14,
                  f"{mass}: nset/right mean velocity = the mean of the field over the set")
        chk.true("reaction" not in r.f["history/nset/right"],
                 f"{mass}: nset/right with VARIABLES=U,V has no reaction")
    r1, _ = deforming(args, chk, "HRZ", tag="_np1")
    r2, _ = deforming(args, chk, "HRZ", np_=2, tag="_np2")
    same = all(np.array_equal(r1.history("nset/right/" + k), r2.history("nset/right/" + k))
               for k in ("displacement", "velocity"))
    same = same and all(np.array_equal(r1.field(s, "acceleration"), r2.field(s, "acceleration"))
                        for s in r1.field_steps())
    chk.true(same and int(r2.attr("ranks")) == 2,
             "node-set history and acceleration bit for bit the same on 1 and 2 ranks")


def set_rows(r, name, args, mass):
    """The 0-based rows of node set `name`: its ids from the deck."""
    with open(os.path.join(args.work, f"deforming_{mass.lower()}.inp")) as f:
        text = f.read()
    block = re.search(r"^\*NSET, NSET=" + name + r"\n((?:[^*].*\n)+)", text, re.M).group(1)
    ids = [int(x) for x in re.split(r"[,\s]+", block.strip()) if x]
    node_ids = list(r.model("node_ids"))
    return [node_ids.index(i) for i in ids]


def strain_state(args, chk):
    a, b, c, d = 1.0e-3, 0.4e-3, -0.2e-3, -0.6e-3
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    mu = E / (2 * (1 + NU))
    sxx = (lam + 2 * mu) * a + lam * d
    syy = lam * a + (lam + 2 * mu) * d
    sxy = mu * (b + c)
    szz = lam * (a + d)
    mises = math.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2)
                      + 3 * sxy ** 2)
    mesh = vcheck.rect_mesh(type="Q4", nx=4, ny=2, lx=4.0, ly=2.0, x0=-2.0, y0=-1.0)
    nodes = re.search(r"^\*NODE\n((?:[^*].*\n)+)", mesh, re.M).group(1).strip().splitlines()
    bc = ["*BOUNDARY"]
    for line in nodes:
        nid, x, y = (float(t) for t in line.split(","))
        if x == 0.0 and y == 0.0:
            continue  # the centre node is free: a uniform stress leaves it at rest
        bc += [f"{int(nid)}, 1, 1, {a * x + b * y!r}", f"{int(nid)}, 2, 2, {c * x + d * y!r}"]
    base = ("*HEADING\nuniform strain\n" + vcheck.material_block(e=E, nu=NU) + mesh
            + "\n".join(bc) + "\n*STEP\n*DYNAMIC, EXPLICIT\n0, 0.05\n")
    want_s = np.array([sxx, syy, sxy, szz])

    r, out = run(args, "strain_s", base + "*OUTPUT, FIELD, EVERY=5, VARIABLES=S\n*END STEP\n")
    last = r.field_steps()[-1]
    keys = set(r.f["fields/" + last].keys())
    chk.true(keys == {"stress", "nodal_stress"},
             f"VARIABLES=S: only stress and nodal_stress in a snapshot ({sorted(keys)})")
    s = r.field(last, "stress")
    chk.below(float(np.abs(s - want_s).max() / np.abs(want_s).max()), 1e-10,
              "VARIABLES=S: the stress is Hooke's law of the prescribed uniform strain")
    with open(out[:-3] + ".xdmf") as f:
        xdmf = f.read()
    chk.true("displacement" not in xdmf and "velocity" not in xdmf and "mises" not in xdmf,
             "VARIABLES=S: the sidecar points to no absent dataset")
    meshio_reads(chk, out[:-3] + ".xdmf", len(r.field_steps()))

    r, _ = run(args, "strain_e", base + "*OUTPUT, FIELD, EVERY=5, VARIABLES=E,MISES\n*END STEP\n")
    last = r.field_steps()[-1]
    keys = set(r.f["fields/" + last].keys())
    chk.true(keys == {"strain", "mises", "nodal_mises"},
             f"VARIABLES=E,MISES: strain, mises, nodal_mises ({sorted(keys)})")
    chk.below(float(np.abs(r.field(last, "strain") - [a, d, 0.5 * (b + c), 0.0]).max() / a),
              1e-10, "VARIABLES=E: the strain is the prescribed one (tensor shear, ezz = 0)")
    chk.close(float(r.field(last, "mises").max()), mises, 1e-10,
              "VARIABLES=MISES: the von Mises stress of the closed-form stress")

    r, out = run(args, "strain_default", base + "*OUTPUT, FIELD, EVERY=5\n*END STEP\n")
    keys = set(r.f["fields/" + r.field_steps()[-1]].keys())
    chk.true(keys == {"displacement", "velocity", "displacement_3d", "velocity_3d", "stress",
                      "mises", "nodal_stress", "nodal_mises"},
             f"default: displacement, velocity, stress, von Mises; no strain, PEEQ or "
             f"acceleration ({sorted(keys)})")
    with open(out[:-3] + ".xdmf") as f:
        xdmf = f.read()
    chk.true('Name="displacement"' in xdmf and 'Name="element_mises"' in xdmf
             and 'Name="peeq"' not in xdmf, "default: the sidecar shows displacement and "
             "element_mises, no peeq")


def meshio_reads(chk, xdmf, nsteps):
    try:
        import meshio
    except ImportError:
        chk.true(True, "meshio not installed: sidecar reading not checked")
        return
    with meshio.xdmf.TimeSeriesReader(xdmf) as rd:
        points, cells = rd.read_points_cells()
        n = rd.num_steps
        _, pd, _ = rd.read_data(n - 1)
    chk.true(n == nsteps and len(points) > 0 and len(cells) == 1 and "displacement" not in pd,
             f"meshio reads the VARIABLES=S sidecar: {n} steps, {len(points)} points, no "
             "displacement")


def main():
    args = vcheck.arguments()
    chk = vcheck.Checker("output_selection")
    translation(args, chk)
    acceleration(args, chk)
    strain_state(args, chk)
    chk.finish()


if __name__ == "__main__":
    main()
