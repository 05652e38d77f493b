"""The text of an exported OpenSees script: the isolated frame rebuilt in openseespy, run, peaks.

The exported script is standalone (Python's standard library and openseespy only, no nsdyn, no
numpy). Its model is the FE model of :mod:`nsdyn.models.isolated.system` at ``fidelity="full"``
(seed 004 eqs 1-15) written in OpenSees elements::

    frame member      elasticBeamColumn(E, A, I, -mass rho_A -cMass), geomTransf Linear
                      (the Bernoulli-Euler stiffness and the consistent mass of nsdyn, exactly)
    base diaphragm    elasticBeamColumn(E = 1, A = EA, I = EI), no mass
    isolator i        flatSliderBearing (Coulomb mu_i, stick stiffness k_init, axial spring
                      k_v) || zeroLength(Elastic(K_lam, eta = c)) in x
    damping           modal (default): modalDampingQ on the modes <= 50 Hz of the sliding
                      structure (eigen before the friction is added), ratios = nsdyn's damping
                      projected on them; or "stiffness": Rayleigh beta K_init on the members,
                      beta = 2 zeta_1 / omega_1
    load              gravity -M r_y g (static, then held) and -M r_x u''_hor, -M r_y u''_ver
                      as nodal loads times Path series (OpenSees 3.7's elasticBeamColumn
                      doubles its element inertia load under UniformExcitation: measured, a
                      free member with -mass accelerates at -2 u''_g)
    integrator        Newmark average acceleration (gamma 1/2, beta 1/4), fixed dt, Krylov-
                      Newton (OpenSees' GeneralizedAlpha at rho_inf 0.8 did not converge here)

and the peaks it returns are nsdyn's (:mod:`nsdyn.models.isolated.metrics`): max |x_iso| of the
base nodes, max |u_x(j) - u_x(j-1)| / h over the column joints, and the absolute horizontal
acceleration u''_x + u''_g of every level node, levels above the base. ``SCRIPT`` holds the code;
:mod:`nsdyn.models.isolated.opensees` puts the model's data above it.
"""

from __future__ import annotations

__all__ = ["HEADER", "LOAD_OPENSEES", "SCRIPT"]

HEADER = '''"""OpenSees model of {name}, exported by nsdyn.

{description}
Run with ``python {filename}``: prints one JSON object with the peaks.
"""

import ctypes
import importlib.util
import json
import math
import os
import sys
import time

'''

LOAD_OPENSEES = r'''def load_opensees():
    """openseespy.opensees, its bundled libraries preloaded (the Linux wheel needs them)."""
    _preload_opensees_libraries()
    try:
        import openseespy.opensees as ops
    except ImportError as exc:
        raise SystemExit(
            f"openseespy is not importable ({exc}); install it: pip install openseespy"
        ) from None
    return ops
'''
"""The script's ``load_opensees()``, shared by the exported scripts."""

SCRIPT = (
    r"""
SLIDING_TAG = 1000000  # element tags of the bearings: SLIDING_TAG + isolator index


"""
    + LOAD_OPENSEES
    + r'''

def build(ops, fixed_base=False, damping=True):
    """The model in OpenSees' domain; ``fixed_base``: base nodes clamped, no isolators;
    ``damping``: with the superstructure's damping (modal: an eigen analysis of the sliding
    structure first)."""
    d = DATA
    ops.wipe()
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    for k, (x, y) in enumerate(d["nodes"]):
        ops.node(k + 1, x, y)
    for k, m in enumerate(d["node_mass"]):
        if m > 0.0:
            ops.mass(k + 1, m, m, 0.0)
    ops.geomTransf("Linear", 1)
    frame_tags = []
    for k, (i, j) in enumerate(d["elements"]):
        tag = k + 1
        ops.element(
            "elasticBeamColumn", tag, i + 1, j + 1, d["A"][k], d["E"][k], d["I"][k], 1,
            "-mass", d["rho_A"][k], "-cMass",
        )
        frame_tags.append(tag)
    base = [b + 1 for b in d["base_nodes"]]
    tag = len(d["elements"])
    modal = damping and d["damping"] == "modal" and not fixed_base
    if damping and not modal:
        ops.region(1, "-eleOnly", *frame_tags, "-rayleigh", 0.0, 0.0, d["beta_k"], 0.0)
    if fixed_base:
        for b in base:
            ops.fix(b, 1, 1, 1)
        return
    for a, b in zip(base[:-1], base[1:]):
        tag += 1
        ops.element("elasticBeamColumn", tag, a, b, d["diaphragm_EA"], 1.0, d["diaphragm_EI"], 1)
    ground0 = len(d["nodes"])
    for i, b in enumerate(base):
        g = ground0 + i + 1
        x, y = d["nodes"][b - 1]
        ops.node(g, x, y)
        ops.fix(g, 1, 1, 1)
        mat = 10 * (i + 1)
        if d["unilateral"]:
            ops.uniaxialMaterial("ENT", mat, d["k_vertical"])
        else:
            ops.uniaxialMaterial("Elastic", mat, d["k_vertical"])
        ops.uniaxialMaterial("Elastic", mat + 1, d["k_rotation"])
        ops.uniaxialMaterial("Elastic", mat + 2, d["k_lam"][i], d["c"][i])
        tag += 1
        ops.element("zeroLength", tag, g, b, "-mat", mat + 2, "-dir", 1)
        # the bearing's axial and rotational springs alone (friction added below)
        ops.element("zeroLength", SLIDING_TAG + i, g, b, "-mat", mat, mat + 1, "-dir", 2, 3)
    if modal:  # modes of the sliding structure (no friction), nsdyn's ratios projected on them
        ops.eigen(len(d["modal_zeta"]))
        ops.modalDampingQ(*d["modal_zeta"])  # on the residual only: the tangent stays banded
    for i, b in enumerate(base):
        if d["mu"][i] <= 0.0:
            continue
        g, mat = ground0 + i + 1, 10 * (i + 1)
        ops.remove("element", SLIDING_TAG + i)
        ops.frictionModel("Coulomb", i + 1, d["mu"][i])
        ops.element(
            "flatSliderBearing", SLIDING_TAG + i, g, b, i + 1, d["k_init"][i], "-P", mat,
            "-Mz", mat + 1, "-orient", 0.0, 1.0, 0.0, -1.0, 0.0, 0.0,
        )


def eigen_frequencies(n, fixed_base=False):
    """The ``n`` lowest natural frequencies [Hz] (isolators stuck: their initial stiffness)."""
    ops = load_opensees()
    build(ops, fixed_base, damping=False)
    lam = ops.eigen("-fullGenLapack", n)
    ops.wipe()
    return [math.sqrt(max(v, 0.0)) / (2.0 * math.pi) for v in lam]


def _ground(t, samples):
    """The record at time t (piecewise linear between samples, 0 outside)."""
    s = (t - DATA["t0"]) / DATA["record_dt"]
    k = int(math.floor(s))
    if k < 0 or k >= len(samples) - 1:
        return samples[-1] if k == len(samples) - 1 else 0.0
    w = s - k
    return (1.0 - w) * samples[k] + w * samples[k + 1]


def _gravity(ops):
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    for k, (fx, fy, mz) in enumerate(DATA["gravity"]):
        if fx or fy or mz:
            ops.load(k + 1, fx, fy, mz)
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", 1e-12, 20)
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


def run(t_end=None):
    """Gravity, then the record; returns the peaks (nsdyn's definitions) and the wall time."""
    d = DATA
    ops = load_opensees()
    build(ops)
    _gravity(ops)
    dt, hor, ver = d["dt"], d["a_hor"], d["a_ver"]
    for tag, samples, loads in ((2, hor, d["inertia_hor"]), (3, ver, d["inertia_ver"])):
        if samples is None:
            continue
        # the last sample once more: a Path series is zero past its end, and the last step's
        # time lands there by round-off (its load then dropped to zero at the record's end)
        ops.timeSeries("Path", tag, "-dt", d["record_dt"], "-values", *samples, samples[-1])
        ops.pattern("Plain", tag, tag)
        for k, (fx, fy, mz) in enumerate(loads):
            if fx or fy or mz:
                ops.load(k + 1, fx, fy, mz)
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system("BandGeneral")
    ops.test("NormDispIncr", d["newton_tol"], 30)
    ops.algorithm("KrylovNewton")  # the modal damping is not in the tangent: Krylov makes up
    ops.integrator("Newmark", d["newmark_gamma"], d["newmark_beta"])
    ops.analysis("Transient")
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
    joints = [[j + 1 for j in row] for row in d["column_joints"]]
    heights = d["storey_heights"]
    levels = [[n + 1 for n in row] for row in d["level_nodes"]]
    x_iso = 0.0
    idr = [0.0] * len(heights)
    acc = [0.0] * len(levels)
    t0 = time.perf_counter()
    for k in range(n_steps):
        if not _step(ops, dt):
            raise RuntimeError(f"OpenSees: no convergence at t = {(k + 1) * dt:.4f} s")
        t = d["t0"] + (k + 1) * dt
        for b in base:
            x_iso = max(x_iso, abs(ops.nodeDisp(b, 1)))
        ux = [[ops.nodeDisp(n, 1) for n in row] for row in joints]
        for s, h in enumerate(heights):
            for c in range(len(ux[s])):
                idr[s] = max(idr[s], abs(ux[s + 1][c] - ux[s][c]) / h)
        ag = _ground(t, hor)
        for lv, row in enumerate(levels):
            for n in row:
                acc[lv] = max(acc[lv], abs(ops.nodeAccel(n, 1) + ag))
    wall = time.perf_counter() - t0
    ops.wipe()
    return {
        "x_iso_max_m": x_iso,
        "idr_max": max(idr),
        "floor_acc_max_mps2": max(acc[1:]) if len(acc) > 1 else acc[0],
        "idr_by_storey": idr,
        "floor_acc_by_level_mps2": acc,
        "n_steps": n_steps,
        "dt": dt,
        "duration_s": n_steps * dt,
        "wall_s": wall,
    }


if __name__ == "__main__":  # (an unknown argument is refused, not ignored)
    import argparse

    cli = argparse.ArgumentParser(description="Run the exported OpenSees model; print peaks.")
    cli.add_argument("--t-end", type=float, default=None,
                     help="end the run here [s], on the record's clock")
    t_end = cli.parse_args().t_end
    if t_end is not None and not t_end - DATA["t0"] >= DATA["dt"] * (1 - 1e-9):
        cli.error(f"--t-end: expected an end at least one step ({DATA['dt']:g} s) after the "
                  f"record's start ({DATA['t0']:g} s), got {t_end!r}")  # (exit 2)
    print(json.dumps(run(t_end)))
'''
)
