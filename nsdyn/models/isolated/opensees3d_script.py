"""The text of an exported 3D building script: the space frame on its bearings in openseespy.

Standalone (Python's standard library and openseespy only). The model and its choices are
those of :mod:`nsdyn.models.isolated.opensees3d_isolated`; this module holds the code that
builds it (``build``), applies gravity (``gravity``: one static load step, held), runs the
record (``run``: UniformExcitation in X, Y, Z, Newmark average acceleration, KrylovNewton,
ten substeps then modified Newton where a step fails) and returns the peaks in nsdyn's
definitions:

- isolator displacement: max over time and bearings of the resultant |u_i| = √(u_x² + u_y²)
  of the base node relative to the ground;
- base shear: max of the resultant of Σ_i (bearing + rubber/damper forces) at the ground
  nodes (isolated) or of the column forces at the clamped base nodes (fixed base);
- storey drift ratios (:mod:`nsdyn.structure.storey3d`): each level's rigid floor motion
  (U_x, U_y, Θ) about its reference point (the diaphragm's master, else the least-squares
  fit of the level's nodes), δ_d(p) = (u_d(p; s + 1) − u_d(p; s)) / h_s at the centre of
  mass of the floor above and at the four plan corners;
- roof corner displacement: max resultant displacement of the top level's plan corners
  relative to the ground;
- the least and largest bearing axial force (N < 0: tension, an uplift nsdyn would stop at;
  for a TripleFrictionPendulum its axial spring's -k_v u_z, the element reporting minFv).

A TripleFrictionPendulum is checked after every step (``tfp_check``: its three pendulums add
up to the bearing's slip), the element reporting no failed internal iteration.

``python model.py [--out DIR] [--t-end S]`` prints them as one JSON object; ``--out`` also
writes OpenSees recorders (isolator displacements and forces, floor master displacements).
"""

from __future__ import annotations

from nsdyn.models.isolated.opensees3d import FRAME_BUILD
from nsdyn.models.isolated.opensees_script import LOAD_OPENSEES

__all__ = ["HEADER", "SCRIPT"]

HEADER = '''"""OpenSees model of the 3D building {name} ({kind}), exported by nsdyn.

{description}
Run with ``python {filename} [--out DIR] [--t-end S]``: prints one JSON object with the peaks.
"""

import argparse
import ctypes
import importlib.util
import json
import math
import os
import sys
import time

'''

SCRIPT = (
    r"""
GROUND_TAG = 1000000  # node tags of the ground under base node i: GROUND_TAG + i
BEARING_TAG = 2000000  # element tags of bearing i and of its rubber/damper
SPRING_TAG = 3000000
GRID_TAG = 4000000  # element tags of the grid base's beams


"""
    + LOAD_OPENSEES
    + "\n\n"
    + FRAME_BUILD
    + r'''

def _solver(ops):
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("UmfPack")


def master_tag(k):
    """Node tag of diaphragm k's master (build_frame numbers them after the nodes)."""
    return len(DATA["nodes"]) + 1 + k


def base_master_tag():
    """Node tag of the grid base's master (after the diaphragms' masters)."""
    return len(DATA["nodes"]) + len(DATA["diaphragms"]) + 1


def build(ops):
    """The model in OpenSees' domain: frame, beta K damping on its members, base."""
    d = DATA
    build_frame(ops, d)
    # stiffness-proportional damping on the members only: none on rigid motion or bearings
    ops.region(1, "-eleRange", 1, len(d["elements"]), "-rayleigh", 0.0, 0.0, d["beta_k"], 0.0)
    base = [b + 1 for b in d["base_nodes"]]
    if d["fixed_base"]:
        for b in base:
            ops.fix(b, 1, 1, 1, 1, 1, 1)
        return
    ops.uniaxialMaterial("Elastic", 1, d["k_vertical"])
    ops.uniaxialMaterial("Elastic", 2, d["k_rotation"])
    if d["base"] == "grid":
        # the grid base: massless beams between neighbouring feet on each grid line (vertical
        # bending and torsion EI = GJ = grid_EI, the columns clamped into them) and a rigid
        # diaphragm through the feet (master at the isolators' plan centroid)
        t = len(d["transforms"]) + 1
        ops.geomTransf("Linear", t, 0.0, 0.0, 1.0)
        ei = d["grid_EI"]
        for k, (i, j) in enumerate(d["grid_beams"]):
            ops.element("elasticBeamColumn", GRID_TAG + k, i + 1, j + 1, 1.0, 1.0, 1.0, ei, ei,
                        ei, t)
        m = base_master_tag()
        ops.node(m, *d["base_origin"])
        ops.fix(m, 0, 0, 1, 1, 1, 0)
        ops.rigidDiaphragm(3, m, *base)
    # flat slider and single pendulum: the element's own return mapping, 100 iterations (its
    # default 20 failed on a stiff portal under a circular orbit, "domain failed in update")
    mats = ["-P", 1, "-T", 2, "-My", 2, "-Mz", 2, "-orient", 0.0, 0.0, 1.0, 1.0, 0.0, 0.0,
            "-iter", 100, 1e-8]
    for i, (b, row) in enumerate(zip(base, d["bearings"])):
        g = GROUND_TAG + i
        ops.node(g, *d["nodes"][b - 1])
        ops.fix(g, 1, 1, 1, 1, 1, 1)
        if row["type"] == "tfp":
            # friction models 3i+1..3i+3: the inner pendulum (surfaces 2 = 3), surfaces 1, 4
            for k, (slow, fast, rate) in enumerate(row["frn"]):
                _friction(ops, 3 * i + 1 + k, slow, fast, rate)
            ops.element("TripleFrictionPendulum", BEARING_TAG + i, g, b, 3 * i + 1, 3 * i + 2,
                        3 * i + 3, 1, 2, 2, 2, *row["L"], *row["ubar"], row["N0"], row["uy"],
                        row["kvt"], row["min_fv"], d["tfp_tol"])
            continue
        _friction(ops, 3 * i + 1, row["mu_slow"], row["mu_fast"], row["rate"])
        if row["type"] == "flat":
            ops.element("flatSliderBearing", BEARING_TAG + i, g, b, 3 * i + 1, row["k_init"],
                        *mats)
        else:
            ops.element("singleFPBearing", BEARING_TAG + i, g, b, 3 * i + 1, row["radius"],
                        row["k_init"], *mats)
        if row["k_lam"] > 0.0 or row["c"] > 0.0:
            ops.uniaxialMaterial("Elastic", 100 + i, row["k_lam"], row["c"])
            ops.element("zeroLength", SPRING_TAG + i, g, b, "-mat", 100 + i, 100 + i,
                        "-dir", 1, 2)


def _friction(ops, tag, slow, fast, rate):
    """Coulomb(mu) for a constant coefficient, else VelDependent(mu_slow, mu_fast, rate)."""
    if fast == slow or rate == 0.0:
        ops.frictionModel("Coulomb", tag, slow)
    else:
        ops.frictionModel("VelDependent", tag, slow, fast, rate)


def tfp_check(ops, i, b, t):
    """TripleFrictionPendulum i's parts (its three series pendulums) must add up to the
    bearing's slip: the element does not report a failed internal iteration."""
    c = ops.eleResponse(BEARING_TAG + i, "compDisplacement")
    ex = c[0] + c[2] + c[4] - ops.nodeDisp(b, 1)
    ey = c[1] + c[3] + c[5] - ops.nodeDisp(b, 2)
    lim = DATA["tfp_check"] * DATA["bearings"][i]["uy"]
    if not math.hypot(ex, ey) <= lim:
        raise RuntimeError(
            f"OpenSees: TripleFrictionPendulum {i} lost its internal equilibrium at t = "
            f"{t:.4f} s (its parts miss the slip by {math.hypot(ex, ey):.3g} m > {lim:.3g} m)"
        )


def gravity(ops):
    """The weight -g M r_z in one static load step, then held (time reset to 0)."""
    if DATA["fixed_base"]:
        return
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    for k, f in enumerate(DATA["gravity"]):
        if any(f):
            ops.load(k + 1, *f)
    _solver(ops)
    ops.test("NormDispIncr", 1e-10, 30)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    if ops.analyze(1) != 0:
        raise RuntimeError("OpenSees: the static gravity step did not converge")
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()


def _step(ops, dt):
    """One step of dt; on failure, ten substeps, then modified Newton. True if it converged."""
    if ops.analyze(1, dt) == 0:
        return True
    if ops.analyze(10, dt / 10.0) == 0:
        return True
    ops.algorithm("ModifiedNewton", "-initial")
    ok = ops.analyze(10, dt / 10.0) == 0
    ops.algorithm("KrylovNewton")
    return ok


def floor_motions(ops):
    """(U_x, U_y, Θ) of every level about its reference point (base level first)."""
    d = DATA
    out = []
    for lv in d["levels"]:
        if lv["master"] is not None:
            m = master_tag(lv["master"])
            out.append((ops.nodeDisp(m, 1), ops.nodeDisp(m, 2), ops.nodeDisp(m, 6)))
            continue
        pts = [(d["nodes"][n], ops.nodeDisp(n + 1)) for n in lv["nodes"]]
        k = len(pts)
        cx = sum(p[0][0] for p in pts) / k
        cy = sum(p[0][1] for p in pts) / k
        ux = sum(u[0] for _, u in pts) / k
        uy = sum(u[1] for _, u in pts) / k
        jd = sum((x - cx) ** 2 + (y - cy) ** 2 for (x, y, _), _ in pts)
        if jd > 0:
            th = sum((x - cx) * u[1] - (y - cy) * u[0] for (x, y, _), u in pts) / jd
        else:
            th = sum(u[5] for _, u in pts) / k
        ex, ey = lv["c"][0] - cx, lv["c"][1] - cy
        out.append((ux - ey * th, uy + ex * th, th))
    return out


def _at(motion, c, p):
    ux, uy, th = motion
    return ux - (p[1] - c[1]) * th, uy + (p[0] - c[0]) * th


def _recorders(ops, out):
    d = DATA
    os.makedirs(out, exist_ok=True)
    masters = [master_tag(k) for k in range(len(d["diaphragms"]))]
    if masters:
        ops.recorder("Node", "-file", os.path.join(out, "floor_masters_disp.out"), "-time",
                     "-node", *masters, "-dof", 1, 2, 6, "disp")
    base = [b + 1 for b in d["base_nodes"]]
    ops.recorder("Node", "-file", os.path.join(out, "isolators_disp.out"), "-time",
                 "-node", *base, "-dof", 1, 2, 3, "disp")
    if not d["fixed_base"]:
        tags = [BEARING_TAG + i for i in range(len(base))]
        ops.recorder("Element", "-file", os.path.join(out, "isolators_force.out"), "-time",
                     "-ele", *tags, "basicForce")


def run(t_end=None, out=None):
    """Gravity, then the record; returns the peaks (nsdyn's definitions) and wall times."""
    d = DATA
    w0 = time.perf_counter()
    ops = load_opensees()
    build(ops)
    gravity(ops)
    for k, a in enumerate(d["accel"]):
        if a is None:
            continue
        # the last sample once more: a Path series is zero past its end, where the last
        # step's time lands by round-off
        ops.timeSeries("Path", 10 + k, "-dt", d["record_dt"], "-values", *a, a[-1])
        ops.pattern("UniformExcitation", 10 + k, k + 1, "-accel", 10 + k)
    _solver(ops)
    ops.test("NormDispIncr", d["newton_tol"], 30)
    ops.algorithm("KrylovNewton")
    ops.integrator("Newmark", d["newmark_gamma"], d["newmark_beta"])
    ops.analysis("Transient")
    if out:
        _recorders(ops, out)
    dt = d["dt"]
    # t_end on the record's clock, as nsdyn's (a duration before: t0 = 5 s ran it whole)
    duration = d["duration"] if t_end is None else min(float(t_end) - d["t0"], d["duration"])
    if t_end is not None and float(t_end) - d["t0"] > d["duration"] * (1 + 1e-9):  # (as export)
        print(f"note: --t-end {float(t_end):g} s is past the end of the record this script "
              f"holds ({d['t0'] + d['duration']:g} s); it runs {d['duration']:g} s",
              file=sys.stderr)  # fmt: skip
    if not duration >= dt * (1 - 1e-9):  # (-1 ran -200 steps to zero peaks; NaN: a traceback;
        # within one step: none, zero peaks and "Infinity")
        raise SystemExit(f"--t-end: expected a time after the record's start ({d['t0']:g} s), "
                         f"got {t_end}")
    n_steps = int(math.floor(duration / dt * (1 + 1e-9)))  # (round() ran past t_end)
    base = [b + 1 for b in d["base_nodes"]]
    nb, fixed = len(base), d["fixed_base"]
    springs = [i for i, r in enumerate(d["bearings"]) if r["k_lam"] > 0.0 or r["c"] > 0.0]
    tfps = {i for i, r in enumerate(d["bearings"]) if r["type"] == "tfp"}
    levels = d["levels"]
    heights = [b["z"] - a["z"] for a, b in zip(levels[:-1], levels[1:])]
    corners = d["corners"]
    u_iso = [0.0] * nb
    v_max = vx_max = vy_max = roof = 0.0
    n_min, n_max = math.inf, -math.inf
    cm_peak = [[0.0, 0.0] for _ in heights]
    corner_peak = [[0.0, 0.0] for _ in heights]
    w1 = time.perf_counter()
    for k in range(n_steps):
        if not _step(ops, dt):
            raise RuntimeError(f"OpenSees: no convergence at t = {(k + 1) * dt:.4f} s")
        for i, b in enumerate(base):
            u_iso[i] = max(u_iso[i], math.hypot(ops.nodeDisp(b, 1), ops.nodeDisp(b, 2)))
        vx = vy = 0.0
        if fixed:
            for e, end in d["base_elements"]:
                vx += ops.eleForce(e + 1, 1 + 6 * end)
                vy += ops.eleForce(e + 1, 2 + 6 * end)
        else:
            for i in range(nb):
                vx += ops.eleForce(BEARING_TAG + i, 1)
                vy += ops.eleForce(BEARING_TAG + i, 2)
                if i in tfps:  # (the element reports minFv in tension: its axial spring's)
                    tfp_check(ops, i, base[i], (k + 1) * dt)
                    n = -d["k_vertical"] * ops.nodeDisp(base[i], 3)
                else:
                    n = ops.eleForce(BEARING_TAG + i, 3)
                n_min, n_max = min(n_min, n), max(n_max, n)
            for i in springs:
                vx += ops.eleForce(SPRING_TAG + i, 1)
                vy += ops.eleForce(SPRING_TAG + i, 2)
        v_max = max(v_max, math.hypot(vx, vy))
        vx_max, vy_max = max(vx_max, abs(vx)), max(vy_max, abs(vy))
        mot = floor_motions(ops)
        for s, h in enumerate(heights):
            lo, hi = levels[s], levels[s + 1]
            for p, peak in [(hi["c"], cm_peak)] + [(q, corner_peak) for q in corners]:
                a, b = _at(mot[s], lo["c"], p), _at(mot[s + 1], hi["c"], p)
                peak[s][0] = max(peak[s][0], abs(b[0] - a[0]) / h)
                peak[s][1] = max(peak[s][1], abs(b[1] - a[1]) / h)
        for q in corners:
            roof = max(roof, math.hypot(*_at(mot[-1], levels[-1]["c"], q)))
    w2 = time.perf_counter()
    ops.wipe()
    caps = [r["d_cap"] for r in d["bearings"]]
    beyond = [i for i, (u, c) in enumerate(zip(u_iso, caps)) if c is not None and u > c]
    return {
        "frame": d["name"],
        "fixed_base": fixed,
        "peak_resultant_displacement_m": max(u_iso),
        "peak_resultant_displacement_per_isolator_m": u_iso,
        "peak_base_shear_N": v_max,
        "peak_base_shear_x_N": vx_max,
        "peak_base_shear_y_N": vy_max,
        "peak_drift_cm_x": max((p[0] for p in cm_peak), default=0.0),
        "peak_drift_cm_y": max((p[1] for p in cm_peak), default=0.0),
        "peak_drift_corner_x": max((p[0] for p in corner_peak), default=0.0),
        "peak_drift_corner_y": max((p[1] for p in corner_peak), default=0.0),
        "peak_roof_corner_displacement_m": roof,
        "min_normal_force_N": None if fixed else n_min,
        "max_normal_force_N": None if fixed else n_max,
        "beyond_d_cap": beyond,
        "n_steps": n_steps,
        "dt": dt,
        "duration_s": n_steps * dt,
        "setup_s": w1 - w0,
        "wall_s": w2 - w1,
    }


if __name__ == "__main__":
    cli = argparse.ArgumentParser(description="Run the exported OpenSees model; print peaks.")
    cli.add_argument("--out", default=None, help="directory for the OpenSees recorders")
    cli.add_argument("--t-end", type=float, default=None,
                     help="end the run here [s], on the record's clock")
    a = cli.parse_args()
    if a.t_end is not None and not a.t_end - DATA["t0"] >= DATA["dt"] * (1 - 1e-9):
        cli.error(f"--t-end: expected an end at least one step ({DATA['dt']:g} s) after the "
                  f"record's start ({DATA['t0']:g} s), got {a.t_end!r}")  # (exit 2)
    if a.out is not None:  # (a path under a file was os.makedirs' traceback)
        try:
            if not a.out or os.path.exists(a.out) and not os.path.isdir(a.out):
                raise NotADirectoryError
            os.makedirs(a.out, exist_ok=True)
        except OSError:
            cli.error(f"--out: expected a directory, got {a.out!r}")
    print(json.dumps(run(a.t_end, a.out)))
'''
)
