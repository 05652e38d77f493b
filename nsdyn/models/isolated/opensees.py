"""Export the isolated frame's full FE model as a standalone openseespy script (and load OpenSees).

The exported model is the one ``nsdyn run SCENE --fidelity full`` integrates (seed 004 eqs
1-15; :mod:`nsdyn.models.isolated.system`)::

    M qdd + C* qd + K* q = -M Gamma [u''_hor, u''_ver + g] + R^T lam - D^T mu lam s(v)

mapped element by element (:mod:`nsdyn.models.isolated.opensees_script` lists the elements):

- K and M: the same Bernoulli-Euler members with the consistent mass (``-cMass``); OpenSees
  assembles exactly nsdyn's K and M, so the fixed-base frequencies agree to round-off.
- the contact R q = 0 (Baumgarte-stabilised constraint) becomes the bearing's axial spring
  ``k_v = K_VERTICAL`` (penalty), and the normal force lam its axial force;
- the arctan law mu lam (2/pi) arctan(eps v) becomes OpenSees' Coulomb friction with an
  elastic stick branch ``k_init = mu N_0 / STICK_DISP`` (N_0 the static normal force): both
  regularise Coulomb's law, one by a steep viscous branch, the other by a stiff spring;
- damping: nsdyn damps the fixed-interface modes (Craig-Bampton coordinates: C = 2 zeta omega
  on eta only), i.e. in nodal coordinates ``C = K Phi diag(2 zeta / omega^3) Phi^T K`` with
  Phi the fixed-base modes (eta = Omega^-2 Phi^T K_i: q): zero on rigid motion, so sliding is
  damped only by the isolators' dampers. OpenSees cannot hold that matrix. Default
  ``damping="modal"``: ``modalDampingQ`` on the modes psi_k (<= MODAL_F_MAX) of the *sliding*
  structure (frame + diaphragm + K_lam springs, y_base held, no friction), computed before the
  friction bearings are added, with ratios ``zeta_k = psi_k^T C psi_k / (2 omega_k)`` (nsdyn's
  C projected on them; C is diagonal in that basis to 1 %, and the near-rigid isolation mode
  gets ~1e-4). ``damping="stiffness"``: Rayleigh ``beta K`` on the members,
  ``beta = 2 zeta_1 / omega_1`` (mode 1 matches; mode j gets zeta_1 f_j / f_1, overdamped);
- time integration: Newmark average acceleration with the scene's ``dt`` (nsdyn: generalized-
  alpha, rho_inf = 0.8; both second order, the peaks differ by O(dt^2)).
"""

from __future__ import annotations

import copy
import inspect
import json
from pathlib import Path

import numpy as np
import scipy.linalg as sla

from nsdyn._checks import default_step
from nsdyn.models.isolated.opensees_script import HEADER, SCRIPT
from nsdyn.models.scenefile import SceneError, bundled_frame_said, scene_step

__all__ = [
    "DEFAULT_DT",
    "INSTALL_HINT",
    "K_VERTICAL",
    "OpenSeesUnavailable",
    "STICK_DISP",
    "export_opensees",
    "load_opensees",
    "load_script",
    "opensees_damping",
    "opensees_data",
    "script_text",
]

DEFAULT_DT = 0.005  # s, the fixed step of genalpha-lowrank on the full model (README)
STICK_DISP = 1e-4  # m, slip at which OpenSees' Coulomb bearing leaves its elastic stick branch
K_VERTICAL = 1e12  # N/m, axial (contact) stiffness of a bearing: penalty for R q = 0
K_ROTATION = 1.0  # N m/rad, rotational stiffness of a bearing (nsdyn: none; OpenSees needs one)
NEWMARK = (0.5, 0.25)  # gamma, beta: average acceleration (second order, no dissipation)
MODAL_F_MAX = 50.0  # Hz, modes of the sliding structure that carry the modal damping
DAMPINGS = ("modal", "stiffness")  # the export's damping mappings (module docstring)
NEWTON_TOL = 1e-8  # OpenSees' NormDispIncr test [m, rad]
INSTALL_HINT = 'pip install "nsdyn[opensees]"'


class OpenSeesUnavailable(ImportError):
    """openseespy is not installed (or does not import); the message names the install."""


def _preload_opensees_libraries():
    """Load the Linux wheel's bundled libraries globally (openseespylinux needs them first)."""
    import ctypes
    import importlib.util
    import os
    import sys

    if not sys.platform.startswith("linux"):
        return
    try:
        spec = importlib.util.find_spec("openseespylinux")
    except (ImportError, ValueError):
        spec = None
    if spec is None or not spec.origin:
        return
    lib = os.path.join(os.path.dirname(spec.origin), "lib")
    for name in ("libquadmath.so.0", "libgfortran.so.4", "libgomp.so.1", "libblas.so.3",
                 "liblapack.so.3"):  # fmt: skip
        path = os.path.join(lib, name)
        if os.path.exists(path):
            ctypes.CDLL(path, mode=ctypes.RTLD_GLOBAL)


def load_opensees():
    """``openseespy.opensees``, or :class:`OpenSeesUnavailable` naming the install command."""
    _preload_opensees_libraries()
    try:
        import openseespy.opensees as ops
    except ImportError as exc:
        raise OpenSeesUnavailable(
            f"OpenSees is not available ({exc}); install the extra: {INSTALL_HINT}"
        ) from None
    return ops


# ---- the model's data ----------------------------------------------------------------------


def _scene_system(scene, source: str, t_end=None):
    """(full system, motion, dt or None) of a scene file or loaded scene dict (isolated frames
    only); a ``t_end`` given replaces the scene's ``[motion] t_end`` (as ``nsdyn run
    --t-end`` does: the script ran to the scene's end and blamed the record)."""
    from nsdyn.models.isolated.scene import build_scene_run, load_scene
    from nsdyn.models.isolated.scene_structure import structure_kind
    from nsdyn.models.scenefile import read_toml, scene_kind

    raw = read_toml(scene) if isinstance(scene, str | Path) else copy.deepcopy(dict(scene))
    kind = scene_kind(raw, source)
    if kind == "building3d":  # (the message listed building3d as exported, and refused it)
        raise SceneError(
            f"{source}: scene.kind: export_opensees exports an isolated frame (kind "
            "'isolated'); a building3d scene or a 3D frame file is exported by nsdyn.models."
            "isolated.opensees3d_isolated.export_building_opensees (nsdyn export opensees "
            "takes either)"
        )
    if kind != "isolated":
        raise SceneError(
            f"{source}: scene.kind: OpenSees export is for the isolated frame (kind "
            f"'isolated') and the 3D building (kind 'building3d'), or a 3D frame file, got "
            f"{kind!r}"
        )
    mo = raw.get("motion") if isinstance(raw.get("motion"), dict) else {}
    if "force" in raw or mo.get("kind") == "harmonic":  # (before the scene's checks of its keys)
        raise SceneError(
            f"{source}: {'[force]' if 'force' in raw else '[motion]'}: OpenSees export needs a "
            "ground-motion record (motion.record = ...), not a harmonic motion or a force"
        )
    if isinstance(scene, str | Path):
        cfg = load_scene(scene, {"scene": {"fidelity": "full"}} if "structure" not in raw else None)
    else:
        cfg = raw
        cfg.setdefault("_source", source)
    if structure_kind(cfg, source) is not None:
        raise SceneError(
            f"{source}: [structure]: OpenSees export needs a frame ([scene] frame = ...); a "
            "shear building or a structure from matrices has no members to export"
        )
    cfg.setdefault("scene", {})["fidelity"] = "full"
    if t_end is not None:  # (a copy: a loaded scene given is not changed)
        cfg["motion"] = {k: v for k, v in cfg.get("motion", {}).items() if k != "t_end"}
    system, motion, _ = build_scene_run(cfg)
    dt = cfg.get("solver", {}).get("dt")
    return system, motion, None if dt is None else float(dt)


def _sliding_modes(full, f_max: float):
    """Frequencies [Hz] and M-normalised modes (in ``full``'s coordinates) of the sliding
    structure: frame, diaphragm and isolator springs, y_base = 0 (contacts), no friction."""
    Q = full.Q
    w2, psi = sla.eigh(Q.T @ full.K @ Q, Q.T @ full.M @ Q)
    f = np.sqrt(np.clip(w2, 0.0, None)) / (2.0 * np.pi)
    keep = f <= f_max
    return f[keep], Q @ psi[:, keep]


def modal_ratios(full, f_max: float = MODAL_F_MAX) -> tuple[np.ndarray, np.ndarray]:
    """(f, zeta) of the sliding structure's modes up to ``f_max``: nsdyn's superstructure
    damping projected on them, ``zeta_k = psi_k^T C_s psi_k / (2 omega_k)`` with
    ``C_s = C - D^T c D`` (the isolators' dampers stay separate elements)."""
    f, Psi = _sliding_modes(full, f_max)
    c = full.isolation.per_isolator("c", full.n_isolators)
    Cs = full.C - full.D.T @ np.diag(c) @ full.D
    w = 2.0 * np.pi * np.maximum(f, 1e-12)
    return f, np.einsum("ik,ij,jk->k", Psi, Cs, Psi) / (2.0 * w)


def opensees_data(
    system, motion, dt: float = DEFAULT_DT, *, damping: str = "modal", source: str = "<model>"
) -> dict:
    """The JSON-able data of the exported model: frame, isolators, damping, loads, record.

    ``system`` is an :class:`~nsdyn.models.isolated.system.IsolatedSystem` with a frame (any
    fidelity: its frame and isolation are exported as the full FE model); ``motion`` a
    :class:`~nsdyn.ground.GroundMotion`; ``dt`` the fixed time step [s]; ``damping`` one of
    :data:`DAMPINGS`.
    """
    from nsdyn.ground import GroundMotion
    from nsdyn.models.isolated.system import build_system
    from nsdyn.structure import fixed_base_modes

    frame = getattr(system, "frame", None)
    iso = getattr(system, "isolation", None)
    if frame is None or iso is None:
        raise SceneError(
            f"{source}: OpenSees export needs an isolated frame (a system built from a frame "
            "with isolation); got a structure without members or a fixed-base model"
        )
    if not isinstance(motion, GroundMotion):
        raise SceneError(
            f"{source}: motion: OpenSees export needs a ground-motion record (GroundMotion), "
            f"got {type(motion).__name__}"
        )
    if not (isinstance(dt, int | float) and np.isfinite(dt) and dt > 0):
        raise SceneError(f"{source}: solver.dt: expected a positive time step [s], got {dt!r}")
    scene_step(dt, motion, motion.duration, source)  # (dt = 1 s: x_iso 1.79 m, not 0.2765)
    if damping not in DAMPINGS:
        raise SceneError(f"{source}: damping: expected one of {list(DAMPINGS)}, got {damping!r}")
    if frame.column_joints is None:
        raise SceneError(f"{source}: frame {frame.name!r} has no regular column lines (drifts)")
    nb = len(frame.base_nodes)
    K, M = frame.assemble(lumped=False)
    f1, _ = fixed_base_modes(K, M, frame.boundary_dofs, n_modes=1)
    beta_k = 2.0 * float(frame.zeta[0]) / (2.0 * np.pi * float(f1[0]))
    inertia = -(M @ frame.influence())  # load per unit ground acceleration, (n_dof, 2)
    mu = iso.per_isolator("mu", nb) if iso.law != "none" else np.zeros(nb)
    full = build_system(frame, iso, fidelity="full")
    n0 = full.static_equilibrium()[1]
    f_modal, zeta_modal = modal_ratios(full) if damping == "modal" else (np.zeros(0),) * 2
    k_init = np.where(mu > 0, mu * n0 / STICK_DISP, iso.per_isolator("k_lam", nb))
    return {
        "name": str(frame.name),
        "nodes": np.asarray(frame.nodes, float).tolist(),
        "elements": np.asarray(frame.elements).tolist(),
        "E": frame.E.tolist(),
        "A": frame.A.tolist(),
        "I": frame.I.tolist(),
        "rho_A": frame.rho_A.tolist(),
        "node_mass": frame.node_mass.tolist(),
        "base_nodes": np.asarray(frame.base_nodes).tolist(),
        "column_joints": np.asarray(frame.column_joints).tolist(),
        "level_nodes": [np.asarray(n).tolist() for n in frame.level_nodes],
        "storey_heights": frame.storey_heights.tolist(),
        "diaphragm_EA": float(iso.diaphragm_EA),
        "diaphragm_EI": float(iso.diaphragm_EI),
        "mu": mu.tolist(),
        "k_lam": iso.per_isolator("k_lam", nb).tolist(),
        "c": iso.per_isolator("c", nb).tolist(),
        "k_init": k_init.tolist(),
        "static_normal_force": np.asarray(n0).tolist(),
        "k_vertical": K_VERTICAL,
        "k_rotation": K_ROTATION,
        "unilateral": iso.contact == "unilateral",
        "zeta_1": float(frame.zeta[0]),
        "f_1": float(f1[0]),
        "beta_k": beta_k,
        "damping": damping,
        "modal_f": f_modal.tolist(),
        "modal_zeta": zeta_modal.tolist(),
        "gravity": (inertia[:, 1] * iso.g).reshape(-1, 3).tolist(),
        "inertia_hor": inertia[:, 0].reshape(-1, 3).tolist(),
        "inertia_ver": inertia[:, 1].reshape(-1, 3).tolist(),
        "g": float(iso.g),
        "record": str(motion.name),
        "t0": float(motion.t0),
        "record_dt": float(motion.dt),
        "a_hor": motion.a_hor.tolist(),
        "a_ver": None if motion.a_ver is None else motion.a_ver.tolist(),
        "duration": float(motion.duration),
        "dt": float(dt),
        "newmark_gamma": NEWMARK[0],
        "newmark_beta": NEWMARK[1],
        "newton_tol": NEWTON_TOL,
        "law": iso.law,
        "frozen_normal": bool(iso.frozen_normal),
    }


def opensees_damping(system, data: dict):
    """A copy of ``system`` (a frame's full model) with the damping of the exported ``data``:
    ``beta K`` on the frame members (``T^T beta K T``) or the modal damping of the sliding
    structure's modes (``M Psi diag(2 zeta omega) Psi^T M``), plus the isolators' ``D^T c D``.

    nsdyn run with it and OpenSees then share the model but for the friction regularisation,
    the contact penalty and the integrator (the comparison of ``nsdyn bench opensees``)."""
    from dataclasses import replace

    c = system.isolation.per_isolator("c", system.n_isolators)
    C = system.D.T @ np.diag(c) @ system.D
    if data["damping"] == "modal":
        f, Psi = _sliding_modes(system, float(max(data["modal_f"])) * (1 + 1e-9))
        A = system.M @ Psi
        C = C + A @ np.diag(2.0 * np.asarray(data["modal_zeta"]) * 2.0 * np.pi * f) @ A.T
    else:
        K, _ = system.frame.assemble(sparse=False)
        C = C + system.T.T @ (data["beta_k"] * K) @ system.T
    return replace(system, C=C, info=dict(system.info))


def _damping_text(d: dict) -> str:
    if d["damping"] == "modal":
        z = ", ".join(f"{z:.4f}" for z in d["modal_zeta"][:5])
        return (
            f"Damping: modalDampingQ on the {len(d['modal_zeta'])} modes <= {max(d['modal_f']):.4g}"
            f" Hz of the sliding structure (no friction),\nratios nsdyn's damping projected on "
            f"them: {z}, ..."
        )
    return (
        f"Damping: beta K_init on the members, beta = 2 zeta_1/omega_1 = {d['beta_k']:.6g} s "
        f"(zeta_1 = {d['zeta_1']:g} at f_1 = {d['f_1']:.6g} Hz)."
    )


def _description(d: dict) -> str:
    return (
        f"Frame {d['name']}: {len(d['nodes'])} nodes, {len(d['elements'])} elasticBeamColumn "
        f"members (consistent mass, -cMass),\n{len(d['base_nodes'])} isolators: "
        f"flatSliderBearing (Coulomb mu = {d['mu']}, k_init = "
        f"{[f'{k:.4g}' for k in d['k_init']]} N/m,\naxial k_v = {d['k_vertical']:.3g} N/m) in "
        f"parallel with zeroLength Elastic(K_lam = {d['k_lam']} N/m, eta = c = {d['c']} N s/m).\n"
        f"{_damping_text(d)}\nRecord {d['record']!r}: "
        f"{len(d['a_hor'])} samples every {d['record_dt']:g} s"
        f"{', with vertical' if d['a_ver'] is not None else ''}; Newmark gamma = "
        f"{d['newmark_gamma']:g}, beta = {d['newmark_beta']:g}, dt = {d['dt']:g} s.\n"
        "The frame's nsdyn model is the law "
        f"{d['law']!r}; OpenSees' bearing is Coulomb with an elastic stick branch"
        f"{' and a live normal force (nsdyn: frozen)' if d['frozen_normal'] else ''}.\n"
    )


def script_text(data: dict, filename: str = "model.py") -> str:
    """The standalone script of ``data`` (:func:`opensees_data`)."""
    head = HEADER.format(name=data["name"], description=_description(data), filename=filename)
    preload = inspect.getsource(_preload_opensees_libraries)
    blob = json.dumps(data, separators=(",", ":"))
    return f"{head}\n{preload}\n\nDATA = json.loads({blob!r})\n{SCRIPT}"


def export_opensees(
    scene,
    path=None,
    *,
    motion=None,
    dt: float | None = None,
    t_end: float | None = None,
    damping: str = "modal",
) -> str:
    """Write (if ``path``) and return a standalone openseespy script of the full model.

    ``scene``: a scene TOML path, a loaded scene dict (:func:`~nsdyn.models.isolated.scene.
    load_scene`), None (the default scene, as the command line's), or an ``IsolatedSystem``
    built from a frame (then ``motion`` is required).
    ``dt`` overrides the scene's ``solver.dt`` (default :data:`DEFAULT_DT`); ``t_end`` cuts the
    record (in place of the scene's ``[motion] t_end``); ``damping`` is ``"modal"`` (default)
    or ``"stiffness"`` (module docstring). Bad input raises
    :class:`~nsdyn.models.scenefile.SceneError` naming the field (a ``scene`` of another type:
    TypeError).
    """
    from nsdyn.atomic import atomic_open

    if scene is None:
        from nsdyn.models.isolated.scene import load_scene

        scene = load_scene()
    if not isinstance(scene, str | Path | dict) and not hasattr(scene, "fidelity"):
        raise TypeError(f"scene: expected a scene file's path, a loaded scene (dict), None or an "
                        f"IsolatedSystem, got {type(scene).__name__}")  # fmt: skip
    if path is not None and Path(path).is_dir():
        raise SceneError(f"path: expected the script's file name, got the folder {path}")
    source = (str(scene) if isinstance(scene, str | Path)
              else scene.get("_source", "<default scene>") if isinstance(scene, dict)
              else "<scene>")  # fmt: skip
    if hasattr(scene, "fidelity") and hasattr(scene, "M"):
        if motion is None:
            raise SceneError(f"{source}: motion: a system needs a ground motion to export")
        system, step = scene, None
    else:
        if isinstance(scene, str | Path) and not Path(scene).is_file():
            said = bundled_frame_said(scene)
            if said and "frame3d" in said:  # (a 3D frame exports as itself)
                raise SceneError(f"{scene}: a bundled 3D frame, not a scene: export it with "
                                 f"export_opensees_3d (nsdyn export opensees {scene})")  # fmt: skip
            if said:  # (the default scene is the office frame's)
                raise SceneError(f"{said} (the default scene is the office frame's: nsdyn "
                                 "export opensees with no scene)")  # fmt: skip
            raise SceneError(f"{source}: no such scene file")
        system, rec, step = _scene_system(scene, source, t_end)
        motion = rec if motion is None else motion
    if t_end is not None:
        if not t_end > 0:
            raise SceneError(f"{source}: t_end: expected a positive end time [s], got {t_end!r}")
        try:  # an end time, as a run's t_end
            motion = motion.until(float(t_end))
        except ValueError as e:  # an end within the record's first step
            raise SceneError(f"{source}: {e}") from None
    if dt is None:  # the scene's; else every sample stepped on (a given step is checked)
        dt = step if step is not None else default_step(motion, DEFAULT_DT)
    data = opensees_data(system, motion, dt, damping=damping, source=source)
    text = script_text(data, Path(path).name if path is not None else "model.py")
    if path is not None:
        with atomic_open(path, "w") as fh:
            fh.write(text)
    return text


def load_script(path):
    """The exported script at ``path`` as a module (its ``DATA``, ``build``, ``run``, …),
    run from its source: no bytecode cache (``__pycache__``) is written beside it."""
    import types

    path = Path(path)
    module = types.ModuleType(f"_nsdyn_opensees_{abs(hash(str(path)))}")
    module.__file__ = str(path)
    exec(compile(path.read_bytes(), str(path), "exec"), module.__dict__)
    return module
