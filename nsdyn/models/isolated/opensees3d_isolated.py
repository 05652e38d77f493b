"""Export a space frame on its bearings (or fixed-base) with a three-component record to OpenSees.

The model is the building of ``nsdyn run`` on a 3D building scene: the space frame of
:mod:`nsdyn.models.isolated.opensees3d` (the same members, local axes, consistent mass and
rigid diaphragms) on one bearing under every base node, relative to the ground,

    M ü + C u̇ + K u + Σ_i F_i(u_i, u̇_i, N_i) = −M r_z g − M (r_x a_x + r_y a_y + r_z a_z),

written in OpenSees elements (:mod:`nsdyn.models.isolated.opensees3d_script` holds the code)::

    ground node i     fixed, at base node i (tag GROUND_TAG + i)
    base              "grid" (default, as nsdyn's cb rung): massless elasticBeamColumn
                      between neighbouring feet on each grid line, vertical bending and torsion
                      EI = GJ = GRID_EI (the plane ladder's base diaphragm), the columns clamped
                      into them, and rigidDiaphragm 3 through the feet (master at the
                      isolators' plan centroid); "pinned": each foot on its own bearing
    flat slider       flatSliderBearing(frictionModel, k_init, -P Elastic(k_v), -T/-My/-Mz
                      Elastic(K_ROTATION)), -orient 0 0 1 1 0 0 (local x up, shear y = X,
                      z = Y), in parallel with zeroLength Elastic(K_lam, eta = c) in X and Y
    friction pendulum singleFPBearing(frictionModel, R, k_init, ...) (restoring N u / R), the
                      rubber and damper as above when the bearing has them
    triple pendulum   TripleFrictionPendulum (Dao et al. 2013; global X, Y shear, Z up) with
                      friction models (inner pair, surface 1, surface 4), -P Elastic(k_v),
                      rotations Elastic(K_ROTATION), W = N_0, uy = u_y, kvt = TFP_KVT,
                      minFv = TFP_MIN_FV N_0, tol = TFP_TOL (mapping below)
    friction model    Coulomb(mu) for a constant coefficient; VelDependent(mu_slow, mu_fast,
                      rate): mu(v) = mu_fast - (mu_fast - mu_slow) exp(-rate |v|), nsdyn's
                      kinetic law with the same parameters in the same order
    gravity           nodal loads -g M r_z, one static load step, then held (loadConst)
    ground motion     UniformExcitation in X, Y, Z (Path series of the record's samples)
    damping           Rayleigh beta K on the members only (region -eleRange), beta =
                      2 zeta_1 / omega_1 with nsdyn's first fixed-base mode: zero on rigid
                      motion (the sliding is damped by the bearings' dampers alone, as in
                      nsdyn's building rungs), mode j of the superstructure gets
                      zeta_1 f_j / f_1 (nsdyn's rungs: frame.zeta on the modes in order).
                      OpenSees' modal damping needs its eigen analysis, which ARPACK did not
                      finish on the office building floating on soft springs (over 250 s, the
                      floor beams' cluster of local modes near 4 Hz)
    integrator        Newmark average acceleration (gamma 1/2, beta 1/4), fixed dt,
                      KrylovNewton, NormDispIncr NEWTON_TOL

Bidirectional friction. The flat slider and single pendulum elements use a circular yield surface
|f| <= mu N with an elastic branch of stiffness ``k_init`` (a penalty on stick): the export
chooses ``k_init_i = mu_slow,i N_0,i / STICK_DISP`` (STICK_DISP = 0.1 mm, N_0 the static
normal force of the rigid-plate distribution), so a stuck bearing creeps elastically by at
most mu N / k_init = 0.1 mm (for N = N_0) before it slides; nsdyn's switch law sticks
exactly. OpenSees has no separate static coefficient: it breaks away at mu(0) N = mu_slow N,
not at nsdyn's mu_static N (reported when they differ). Not exported: the rim stop at d_cap
(the script reports a peak beyond d_cap) and uplift (a bilateral axial spring; the script
reports the least axial force, negative = tension).

Triple pendulum. OpenSees' element is the series model of a symmetric bearing: three
bidirectional elastic-plastic pendulums (the element's source) with post-yield radii 2 L1,
L2 - L1, L3 - L1, friction models 1, 2, 3 and circular gaps 2 (L1 Ubar3/L3 + Ubar1),
Ubar2 (1 - L1/L2), Ubar3 (1 - L1/L3), each with elastic stiffness E = 3 mu_1 / uy (per unit
normal force; three in series: mu_1 / uy, nsdyn's kappa_e). nsdyn's series elements
(:mod:`nsdyn.models.isolated.tfp`: R1 - R2, R2, R3, R4 - R3 with capacities d1 (1 - R2/R1),
d2 + d1 R2/R1, d3 + d4 R3/R4, d4 (1 - R3/R4)) are these for

    L1 = R2 = R3,  L2 = R1,  L3 = R4,  Ubar1 = d3,  Ubar2 = d1,  Ubar3 = d4,
    friction models (mu2 = mu3, mu1, mu4),  uy = u_y,

when the inner pair is one pendulum: R2 = R3, mu2 = mu3 (and their mu_fast), and d2 + d1
R2/R1 = d3 + d4 R3/R4 (e.g. d2 = d3 and d1/R1 = d4/R4); otherwise the export refuses naming
the field (:func:`tfp_element_args`). Velocity-dependent friction maps with its rate scaled to
the surface speeds the element uses (0.5, L2/(L2 - L1), L3/(L3 - L1) x its pendulums' speeds,
nsdyn's law takes the element's slip speed): rates a, a (R1 - R2)/R1, a (R4 - R3)/R4. The two
models differ only by the elastic part: OpenSees' pendulum e slides by its play P_e (R̄_e -
1/E) where nsdyn's slides by P_e R̄_e, at most (1/E) Σ_e max(d̄_e/R̄_e, phi) in displacement
(tests/models/isolated/test_tfp_opensees.py). The element does not report a failed internal
iteration (a first sliding step of several uy from rest lost its equilibrium silently): the
script checks every step that its pendulums add up to the bearing's slip (within TFP_CHECK
uy) and stops with the time otherwise. In tension the element keeps minFv and kvt (a free
uplift); the script reports the axial spring's -k_v u_z as the normal force.

``fixed_base=True`` writes the same frame clamped at the base, no gravity, the same beta K:
the model of :func:`nsdyn.models.isolated.fixed3d.fixed_response_3d` when that is given the
ratios beta omega_k / 2 of stiffness-proportional damping (:func:`rayleigh_zeta`).
"""

from __future__ import annotations

import inspect
import json
import math
from pathlib import Path

import numpy as np

from nsdyn._checks import default_step
from nsdyn.models.isolated.opensees import (
    K_ROTATION,
    K_VERTICAL,
    NEWMARK,
    NEWTON_TOL,
    STICK_DISP,
    _preload_opensees_libraries,
    load_opensees,
)
from nsdyn.models.isolated.opensees3d import frame_data_3d
from nsdyn.models.isolated.opensees3d_script import HEADER, SCRIPT
from nsdyn.models.scenefile import SceneError, scene_step

__all__ = [
    "DEFAULT_DT",
    "building_data",
    "export_building_opensees",
    "rayleigh_beta",
    "rayleigh_zeta",
    "script_text_building",
    "tfp_element_args",
]

DEFAULT_DT = 0.005  # s, Newmark's fixed step (the planar export's)
BASES = ("grid", "pinned")  # nsdyn's cb rung bases
GRID_EI = 1e11  # N m², the grid beams' EI and GJ (the plane ladder's base diaphragm EI)
TFP_SAME = 1e-9  # relative tolerance of the triple pendulum's inner symmetry (R2 = R3, ...)
TFP_MIN_FV = 1e-3  # TripleFrictionPendulum's minFv (the friction's normal force in tension) / N_0
TFP_KVT = 1e3  # N/m, TripleFrictionPendulum's vertical stiffness in tension (kvt): free uplift
TFP_TOL = 1e-6  # TripleFrictionPendulum's relative tolerance of its internal equilibrium
TFP_CHECK = 1e-2  # the script's check: |sum of the element's parts - u| <= TFP_CHECK * uy


def rayleigh_beta(frame) -> tuple[float, float]:
    """(beta [s], f_1 [Hz]): ``beta = 2 zeta_1 / omega_1`` of the first fixed-base mode."""
    from nsdyn.structure import fixed_base_modes_3d

    f1 = float(fixed_base_modes_3d(frame, n_modes=1).f_hz[0])
    return 2.0 * float(frame.zeta[0]) / (2.0 * math.pi * f1), f1


def rayleigh_zeta(frame, f_hz) -> np.ndarray:
    """Modal ratios ``beta omega_k / 2`` of the export's beta K at the frequencies f_hz."""
    beta, _ = rayleigh_beta(frame)
    return beta * np.pi * np.asarray(f_hz, float)


def tfp_element_args(b, where: str = "bearing") -> dict:
    """OpenSees' TripleFrictionPendulum parameters of a :class:`~nsdyn.models.isolated.tfp.
    TripleBearing` (module docstring, "triple pendulum"): ``L`` = [L1, L2, L3] [m], ``ubar`` =
    [Ubar1, Ubar2, Ubar3] [m], ``frn`` = three (mu_slow, mu_fast, rate) and ``uy`` [m].
    A bearing the element cannot represent is a one-line :class:`SceneError` naming the field
    (``where`` its prefix): the element has one inner pendulum, so R2 = R3, mu2 = mu3 (and
    their mu_fast) and equal inner series capacities d2 + d1 R2/R1 = d3 + d4 R3/R4."""
    R1, R2, R3, R4 = (float(getattr(b, f"R{j}")) for j in range(1, 5))
    d1, d2, d3, d4 = (float(getattr(b, f"d{j}")) for j in range(1, 5))
    mu = [float(getattr(b, f"mu{j}")) for j in range(1, 5)]
    fast = b.fast()
    rate = float(b.rate)

    def same(a, c):
        return abs(a - c) <= TFP_SAME * max(abs(a), abs(c))

    for field, a, c, what in (
        ("R3", R3, R2, "one inner radius: R3 = R2"),
        ("mu3", mu[2], mu[1], "one inner friction: mu3 = mu2"),
        ("mu_fast3", fast[2], fast[1], "one inner friction law: mu_fast3 = mu_fast2"),
        ("d3", d3 + d4 * R3 / R4, d2 + d1 * R2 / R1,
         "one inner capacity: d3 + d4 R3/R4 = d2 + d1 R2/R1 (e.g. d2 = d3, d1/R1 = d4/R4)"),
    ):  # fmt: skip
        if not same(a, c):
            raise SceneError(f"{where}.{field}: OpenSees' TripleFrictionPendulum has {what}; "
                             f"got {a:g} against {c:g}")  # fmt: skip
    return {
        "L": [R2, R1, R4],
        "ubar": [d3, d1, d4],
        "frn": [[mu[1], fast[1], rate], [mu[0], fast[0], rate * (R1 - R2) / R1],
                [mu[3], fast[3], rate * (R4 - R3) / R4]],
        "uy": float(b.u_y),
    }  # fmt: skip


def tfp_single(b, W: float, mass: float | None = None):
    """openseespy, with node 2 (mass ``mass``, rotations held) on one TripleFrictionPendulum of
    ``b`` (:func:`tfp_element_args`, constant friction at the slow coefficients) over the
    fixed node 1, carrying the weight W [N] (a static step, then held at time 0). The model of
    the single-bearing cross-checks; the analysis objects are left for the caller. The
    element's elastic stage is undamped: ``b.zeta_e`` must be 0 (the same model)."""
    if b.zeta_e != 0.0:
        raise SceneError(f"{b.where}.zeta_e: OpenSees' TripleFrictionPendulum has an undamped "
                         f"elastic stage; expected zeta_e = 0, got {b.zeta_e:g}")  # fmt: skip
    ops = load_opensees()
    a = tfp_element_args(b)
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    ops.node(1, 0.0, 0.0, 0.0)
    m = [] if mass is None else ["-mass", mass, mass, mass, 0.0, 0.0, 0.0]
    ops.node(2, 0.0, 0.0, 0.0, *m)
    ops.fix(1, 1, 1, 1, 1, 1, 1)
    ops.fix(2, 0, 0, 0, 1, 1, 1)
    for k, (slow, _, _) in enumerate(a["frn"]):
        ops.frictionModel("Coulomb", k + 1, slow)
    ops.uniaxialMaterial("Elastic", 1, K_VERTICAL)
    ops.uniaxialMaterial("Elastic", 2, K_ROTATION)
    ops.element("TripleFrictionPendulum", 1, 1, 2, 1, 2, 3, 1, 2, 2, 2, *a["L"], *a["ubar"], W,
                a["uy"], TFP_KVT, TFP_MIN_FV * W, TFP_TOL)  # fmt: skip
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 0.0, 0.0, -W, 0.0, 0.0, 0.0)
    tfp_solver(ops)
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    if ops.analyze(1) != 0:
        raise RuntimeError("OpenSees: the weight's static step did not converge")
    ops.loadConst("-time", 0.0)
    ops.wipeAnalysis()
    return ops


def tfp_solver(ops) -> None:
    """The single bearing's solution objects (Newton on a banded system, displacement test)."""
    ops.constraints("Transformation")
    ops.numberer("Plain")
    ops.system("BandGen")
    ops.test("NormDispIncr", 1e-10, 50)
    ops.algorithm("Newton")


def tfp_slip_mismatch(ops) -> float:
    """|Σ parts − u| [m] of element 1: its three pendulums' slips against node 2's (the element
    does not report a failed internal iteration; the export's script checks the same)."""
    c = ops.eleResponse(1, "compDisplacement")
    return math.hypot(c[0] + c[2] + c[4] - ops.nodeDisp(2, 1),
                      c[1] + c[3] + c[5] - ops.nodeDisp(2, 2))  # fmt: skip


def _bearing_rows(frame, bearings, source: str):
    """(rows, deck) of the bearings under the base nodes (one per base node)."""
    from nsdyn.models.isolated import bearings as B
    from nsdyn.models.isolated.building3d import building_deck
    from nsdyn.models.isolated.tfp import TripleBearing

    nb = len(frame.base_nodes)
    bl = (bearings,) * nb if isinstance(bearings, B.Bearing) else tuple(bearings)
    for b in bl:
        if not isinstance(b, B.Bearing) or getattr(b, "friction", None) is None:
            raise SceneError(
                f"{source}: bearing: OpenSees export maps a flat slider (flatSliderBearing), "
                "a single friction pendulum (singleFPBearing) or a triple friction pendulum "
                f"(TripleFrictionPendulum); got {type(b).__name__}"
            )
    try:
        deck = building_deck(frame, bl)
    except ValueError as e:
        raise SceneError(f"{source}: {e}") from None
    n0 = deck.static_normal()
    rows = []
    for i, b in enumerate(bl):
        f = b.friction
        mu0 = float(f.mu_slow)
        if not mu0 > 0:  # (named as the scene writes it: mu, or mu_slow beside mu_fast)
            key = "mu_slow" if f.mu_fast is not None else "mu"
            raise SceneError(f"{source}: {b.where}.{key}: OpenSees' bearings need mu > 0")
        if b.area is not None:  # (it would be dropped: a script of another model)
            raise SceneError(f"{source}: {b.where}.area: pressure-dependent friction has no "
                             "counterpart in the exported bearings (their friction does not "
                             "follow the contact pressure); expected no area")  # fmt: skip
        row = {
            "type": "flat" if math.isinf(b.radius) else "fps",
            "radius": None if math.isinf(b.radius) else float(b.radius),
            "mu_slow": mu0, "mu_fast": float(f.fast), "rate": float(f.rate),
            "mu_static": float(f.static),
            "k_lam": float(b.k_lam), "c": float(b.c),
            "d_cap": None if math.isinf(b.d_cap) else float(b.d_cap),
            "N0": float(n0[i]), "k_init": mu0 * float(n0[i]) / STICK_DISP,
        }  # fmt: skip
        if isinstance(b, TripleBearing):
            if b.zeta_e != 0.0:  # (dropped, the script would run another bearing)
                raise SceneError(f"{source}: {b.where}.zeta_e: OpenSees' TripleFrictionPendulum "
                                 "has an undamped elastic stage; expected zeta_e = 0 for an "
                                 f"export, got {b.zeta_e:g}")  # fmt: skip
            row.update(tfp_element_args(b, f"{source}: {b.where}"))
            row.update({"type": "tfp", "radius": None, "k_init": None,
                        "min_fv": TFP_MIN_FV * float(n0[i]), "kvt": TFP_KVT})  # fmt: skip
        rows.append(row)
    return rows, deck


def _grid_beams(frame) -> list:
    """[i, j] pairs of neighbouring base nodes on each grid line (equal x, then equal y)."""
    xy = frame.nodes[frame.base_nodes, :2]
    tol = 1e-6 * max(float(np.ptp(xy)), 1.0)
    out = []
    for along, across in ((1, 0), (0, 1)):
        keys = np.round(xy[:, across] / tol).astype(np.int64)
        for k in np.unique(keys):
            idx = np.flatnonzero(keys == k)
            idx = idx[np.argsort(xy[idx, along])]
            out += [[int(frame.base_nodes[a]), int(frame.base_nodes[b])]
                    for a, b in zip(idx[:-1], idx[1:], strict=True)]  # fmt: skip
    return out


def _levels(frame) -> list:
    """Per level (base first): its elevation, reference point and master index or fit nodes."""
    from nsdyn.structure import floor_motions

    z, nodes = frame.levels()
    _, c, _ = floor_motions(frame, np.zeros(frame.n_dof))
    owner = {int(n): k for k, d in enumerate(frame.diaphragms) for n in d.nodes}
    out = []
    for h, ns, cc in zip(z, nodes, c, strict=True):
        ks = {owner[int(n)] for n in ns if int(n) in owner}
        out.append({"z": float(h), "c": [float(v) for v in cc],
                    "master": min(ks) if ks else None,
                    "nodes": [int(n) for n in ns]})  # fmt: skip
    return out


def _gravity(frame, g: float) -> list:
    """Nodal loads -g M r_z (consistent element mass and the node masses), (n_nodes, 6)."""
    _, M = frame.assemble(lumped=False)
    rz = np.zeros(frame.n_dof)
    rz[2::6] = 1.0
    return (-g * (M @ rz)).reshape(frame.n_nodes, 6).tolist()


def _need_record3(motion, source: str) -> None:
    """SceneError unless ``motion`` is a three-component record (an orbit has no samples)."""
    if not hasattr(motion, "dt") or getattr(motion, "ax", None) is None:
        what = "a planar record" if hasattr(motion, "dt") else "an orbit"
        raise SceneError(f"{source}: motion: OpenSees export needs a three-component record "
                         f"(kind = 'record3'), not {what}")  # fmt: skip


def building_data(
    frame,
    bearings,
    motion,
    dt: float = DEFAULT_DT,
    *,
    fixed_base: bool = False,
    base: str = "grid",
    g: float | None = None,
    source: str = "<model>",
) -> dict:
    """The JSON-able data of the exported building (module docstring).

    ``frame``: a :class:`~nsdyn.structure.Frame3D`; ``bearings``: one
    :class:`~nsdyn.models.isolated.Bearing` for all base nodes or one each (ignored with
    ``fixed_base``); ``motion``: a three-component record (``t0, dt, ax, ay, az``);
    ``dt``: Newmark's step [s]; ``base``: "grid" or "pinned" (module docstring).
    """
    from nsdyn.ground.excitation import G_EARTH

    g = G_EARTH if g is None else float(g)
    if not (isinstance(dt, int | float) and math.isfinite(dt) and dt > 0):
        raise SceneError(f"{source}: solver.dt: expected a positive time step [s], got {dt!r}")
    _need_record3(motion, source)
    data = frame_data_3d(frame, "consistent")
    if base not in BASES:
        raise SceneError(f"{source}: structure.base: expected one of {list(BASES)}, got {base!r}")
    rows, deck = ([], None) if fixed_base else _bearing_rows(frame, bearings, source)
    ax = np.asarray(motion.ax, float)
    comp = [ax, motion.ay, getattr(motion, "az", None)]
    duration = (len(ax) - 1) * float(motion.dt)
    scene_step(dt, motion, duration, source)
    lo, hi = frame.nodes[:, :2].min(axis=0), frame.nodes[:, :2].max(axis=0)
    base_elems = []
    for e, (i, j) in enumerate(frame.elements.tolist()):
        for end, n in enumerate((i, j)):
            if n in set(frame.base_nodes.tolist()):
                base_elems.append([e, end])
    beta, f1 = rayleigh_beta(frame)
    data.update({
        "fixed_base": bool(fixed_base),
        "gravity": _gravity(frame, g) if not fixed_base else None,
        "g": g,
        "bearings": rows,
        "k_vertical": K_VERTICAL, "k_rotation": K_ROTATION, "base": base,
        "grid_EI": GRID_EI, "grid_beams": _grid_beams(frame) if base == "grid" else [],
        "base_origin": [*frame.nodes[frame.base_nodes, :2].mean(axis=0).tolist(),
                        float(frame.nodes[frame.base_nodes, 2].min())],
        "beta_k": beta, "f_1": f1, "zeta_1": float(frame.zeta[0]),
        "levels": _levels(frame),
        "corners": [[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]],
        "base_elements": base_elems,
        "record": str(getattr(motion, "name", "record")),
        "t0": float(getattr(motion, "t0", 0.0) or 0.0),
        "record_dt": float(motion.dt),
        "accel": [None if a is None else np.asarray(a, float).tolist() for a in comp],
        "duration": duration,
        "dt": float(dt),
        "newmark_gamma": NEWMARK[0], "newmark_beta": NEWMARK[1], "newton_tol": NEWTON_TOL,
        "tfp_tol": TFP_TOL, "tfp_check": TFP_CHECK,
        "deck": None if deck is None else {
            "m": float(deck.info["m"]), "J": float(deck.info["J"]), "h": float(deck.info["h"]),
            "origin": [float(v) for v in deck.info["origin"]],
        },
    })  # fmt: skip
    return data


def _description(d: dict) -> str:
    head = (
        f"{len(d['nodes'])} nodes, {len(d['elements'])} elasticBeamColumn members (consistent "
        f"mass), {len(d['diaphragms'])} rigid diaphragms;\n"
    )
    if d["fixed_base"]:
        base = f"{len(d['base_nodes'])} clamped base nodes.\n"
    else:
        kinds = sorted({b["type"] for b in d["bearings"]})
        elems = " and ".join(
            {"flat": "flatSliderBearing", "fps": "singleFPBearing",
             "tfp": "TripleFrictionPendulum"}[k] for k in kinds
        )  # fmt: skip
        k0 = [b["k_init"] for b in d["bearings"] if b["k_init"] is not None]
        static = [b for b in d["bearings"] if b["mu_static"] > max(b["mu_slow"], b["mu_fast"])]
        base = (
            f"{len(d['bearings'])} bearings ({elems})"
            + (f", k_init {min(k0):.4g}..{max(k0):.4g} N/m (mu N0 / k_init = {STICK_DISP:g} m)"
               if k0 else "")
            + ";\n"
            + ("OpenSees breaks away at mu_slow N, nsdyn at mu_static N.\n" if static else "")
        )  # fmt: skip
    return (
        head + base + f"Record {d['record']!r}: {len(d['accel'][0])} samples every "
        f"{d['record_dt']:g} s; Newmark average acceleration, dt = {d['dt']:g} s.\n"
    )


def script_text_building(data: dict, filename: str = "model.py") -> str:
    """The standalone script of ``data`` (:func:`building_data`)."""
    kind = "fixed base" if data["fixed_base"] else "on its bearings"
    head = HEADER.format(name=data["name"], kind=kind, description=_description(data),
                         filename=filename)  # fmt: skip
    preload = inspect.getsource(_preload_opensees_libraries)
    blob = json.dumps(data, separators=(",", ":"))
    return f"{head}\n{preload}\n\nDATA = json.loads({blob!r})\n{SCRIPT}"


def _from_scene(scene, source: str, t_end=None, fixed_base=None):
    """(frame, bearing or None, motion, dt or None, fixed) of a building3d scene file; a
    ``t_end`` given replaces the scene's ``[motion] t_end``, and with ``fixed_base`` the
    scene needs no ``[bearing]``."""
    import copy

    from nsdyn.models.isolated.bearings import BearingError, bearing_from_config
    from nsdyn.models.isolated.building3d_scene import build_motion, build_system
    from nsdyn.models.scenefile import read_toml

    cfg = read_toml(scene) if isinstance(scene, str | Path) else copy.deepcopy(dict(scene))
    fid = cfg.get("structure", {}).get("fidelity", "rigid")
    frame_only = copy.deepcopy(cfg)
    frame_only.setdefault("structure", {})["fidelity"] = "fixed"
    frame = build_system(frame_only, source)["frame"]
    if t_end is not None:
        cfg["motion"] = {k: v for k, v in cfg.get("motion", {}).items() if k != "t_end"}
    motion, _ = build_motion(cfg, source)
    fixed = fid == "fixed" if fixed_base is None else bool(fixed_base)
    bearing = None
    if not fixed:
        if "bearing" not in cfg:
            raise SceneError(f"{source}: bearing: missing; the building on isolators needs a "
                             "[bearing] table")  # fmt: skip
        try:
            bearing = bearing_from_config(cfg["bearing"], "bearing")
        except BearingError as e:
            raise SceneError(f"{source}: {e}") from None
    dt = cfg.get("solver", {}).get("dt")
    base = cfg.get("structure", {}).get("base", "grid")
    return frame, bearing, motion, dt, fixed, base


def export_building_opensees(
    scene,
    path=None,
    *,
    bearings=None,
    motion=None,
    dt: float | None = None,
    t_end: float | None = None,
    fixed_base: bool | None = None,
    base: str | None = None,
) -> str:
    """Write (if ``path``) and return the standalone script of a 3D building.

    ``scene``: a building3d scene file (fidelity "fixed" exports the fixed base, any other
    rung the building on its bearings) or a :class:`~nsdyn.structure.Frame3D` (then
    ``motion`` and, unless ``fixed_base``, ``bearings`` are required). ``dt`` overrides the
    step (default :data:`DEFAULT_DT`); ``t_end`` cuts the record [s]; ``base`` overrides the
    scene's ``structure.base`` ("grid" by default).
    """
    from nsdyn.atomic import atomic_open
    from nsdyn.structure import Frame3D

    source = str(scene) if isinstance(scene, str | Path) else "<building>"
    if isinstance(scene, Frame3D):
        if motion is None:
            raise SceneError(f"{source}: motion: a frame needs a three-component record")
        frame, step, fixed = scene, None, bool(fixed_base)
        base = base or "grid"
    else:
        if isinstance(scene, str | Path) and not Path(scene).is_file():
            raise SceneError(f"{source}: no such scene file")
        frame, bearing, rec, step, fixed, scene_base = _from_scene(scene, source, t_end,
                                                                   fixed_base)  # fmt: skip
        base = base or scene_base
        bearings = bearing if bearings is None else bearings
        motion = rec if motion is None else motion
    if not fixed and bearings is None:
        raise SceneError(f"{source}: bearing: the building on isolators needs its bearings")
    _need_record3(motion, source)  # (before t_end cuts it: an orbit has no until)
    if t_end is not None:
        if not (isinstance(t_end, int | float) and t_end > 0):
            raise SceneError(f"{source}: t_end: expected a positive end time [s], got {t_end!r}")
        try:  # an end time, as a run's t_end
            motion = motion.until(float(t_end))
        except ValueError as e:  # an end within the record's first step
            raise SceneError(f"{source}: {e}") from None
    if dt is None:  # the scene's; else every sample stepped on (a given step is checked)
        dt = step if step is not None else default_step(motion, DEFAULT_DT)
    data = building_data(frame, bearings, motion, dt, fixed_base=fixed,
                         base=base, source=source)  # fmt: skip
    text = script_text_building(data, Path(path).name if path is not None else "model.py")
    if path is not None:
        with atomic_open(path, "w") as fh:
            fh.write(text)
    return text
