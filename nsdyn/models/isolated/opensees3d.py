"""Export a space frame (fixed base) as a standalone openseespy script with an eigen analysis.

The script rebuilds :class:`nsdyn.structure.Frame3D` element by element and prints the
lowest natural frequencies of the clamped structure, those that
:func:`nsdyn.structure.fixed_base_modes_3d` computes (``K_ii φ = ω² M_ii φ`` in the
diaphragm-constrained coordinates)::

    model       basic, -ndm 3 -ndf 6; node n -> tag n + 1
    member      elasticBeamColumn A E G' J' I_y I_z with geomTransf Linear vecxz (one
                transformation per distinct orientation vector: the same local axes as
                nsdyn.structure.elements3d, OpenSees' own convention)
    mass        consistent (default): -mass ρA -cMass, and G' J' = G J with
                J' = A ρI_p / ρA (OpenSees 3.7's consistent torsional inertia is ρA J'/A, so
                the pair keeps the torsional stiffness and puts nsdyn's ρI_p; for ρA = 0,
                J' = J); node masses in x, y, z. Lumped: massless members and nodal masses
                equal to the diagonal of nsdyn's HRZ-lumped M (translations, bending and
                torsional rotations: OpenSees' own lumped beam mass has no rotational part)
    diaphragm   a master node at (x_c, y_c, z_level) carrying (m, m, J) in (u_x, u_y, θ_z),
                its u_z, θ_x, θ_y fixed, rigidDiaphragm 3 master *slaves (u_x, u_y, θ_z of
                the slaves tied to U_x, U_y, Θ exactly as nsdyn's T), constraints
                Transformation
    base        fix 1 1 1 1 1 1
    eigen       ops.eigen(n) (ARPACK on the banded system; -fullGenLapack when n reaches
                the free dofs, or on request)

With these, OpenSees assembles nsdyn's K and M, so the frequencies agree to the
eigensolvers' round-off. The script also carries nsdyn's own frequencies for the same mass
choice and prints both.
"""

from __future__ import annotations

import inspect
import json
from pathlib import Path

import numpy as np

from nsdyn.models.isolated.opensees import _preload_opensees_libraries
from nsdyn.models.isolated.opensees_script import LOAD_OPENSEES
from nsdyn.structure import Frame3D, fixed_base_modes_3d, load_frame3d

__all__ = [
    "FRAME_BUILD",
    "MASSES",
    "export_opensees_3d",
    "frame_data_3d",
    "opensees_data_3d",
    "script_text_3d",
]

MASSES = ("consistent", "lumped")  # the exported element mass (module docstring)
N_MODES = 12  # default number of modes the script computes and nsdyn's reference lists

HEADER = '''"""OpenSees model of the space frame {name} (fixed base), exported by nsdyn.

{description}
Run with ``python {filename} [N]``: prints one JSON object with the N lowest frequencies
(default {n_modes}) next to nsdyn's for the same model.
"""

import ctypes
import importlib.util
import json
import math
import os
import sys

'''

FRAME_BUILD = r'''def build_frame(ops, d):
    """The space frame of ``d`` in a fresh domain: nodes (tag n + 1), members, node masses,
    diaphragm masters (tags after the nodes, in order) and their rigidDiaphragm ties."""
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for k, (x, y, z) in enumerate(d["nodes"]):
        ops.node(k + 1, x, y, z)
    for t, v in enumerate(d["transforms"]):
        ops.geomTransf("Linear", t + 1, *v)
    consistent = d["mass"] == "consistent"
    for k, (i, j) in enumerate(d["elements"]):
        extra = ["-mass", d["rho_A"][k], "-cMass"] if consistent and d["rho_A"][k] > 0 else []
        ops.element(
            "elasticBeamColumn", k + 1, i + 1, j + 1, d["A"][k], d["E"][k], d["G"][k],
            d["J"][k], d["I_y"][k], d["I_z"][k], d["transf"][k] + 1, *extra,
        )
    for k, m in enumerate(d["node_mass"]):
        if any(v > 0.0 for v in m):
            ops.mass(k + 1, *m)
    master = len(d["nodes"])
    for dia in d["diaphragms"]:
        master += 1
        x, y = dia["centre"]
        ops.node(master, x, y, dia["z"])
        ops.fix(master, 0, 0, 1, 1, 1, 0)
        ops.mass(master, dia["mass"], dia["mass"], 0.0, 0.0, 0.0, dia["inertia"])
        ops.rigidDiaphragm(3, master, *[n + 1 for n in dia["nodes"]])
'''
"""The scripts' ``build_frame(ops, d)``: the space frame of the data (shared by the fixed-base
and the isolated exports)."""

SCRIPT = (
    r"""

"""
    + LOAD_OPENSEES
    + "\n\n"
    + FRAME_BUILD
    + r'''

def build(ops):
    """The clamped space frame in OpenSees' domain (nodes, members, masses, diaphragms)."""
    build_frame(ops, DATA)
    for b in DATA["base_nodes"]:
        ops.fix(b + 1, 1, 1, 1, 1, 1, 1)
    ops.constraints("Transformation")
    ops.numberer("RCM")
    ops.system("BandGeneral")


def eigen_frequencies(n, solver=None):
    """The ``n`` lowest natural frequencies [Hz] of the clamped frame: ARPACK on the banded
    system, or LAPACK's dense solver when ``n`` reaches the free dofs (ARPACK finds fewer
    than N - 1 of N pairs)."""
    if solver is None:
        solver = "-genBandArpack" if n < DATA["n_free"] - 1 else "-fullGenLapack"
    ops = load_opensees()
    build(ops)
    lam = ops.eigen(solver, n)
    ops.wipe()
    return [math.sqrt(max(v, 0.0)) / (2.0 * math.pi) for v in lam]


if __name__ == "__main__":  # (N was int(sys.argv[1]): --help a ValueError, 20 of 15 free
    import argparse  # dofs padded the list with 0 Hz "modes")

    cli = argparse.ArgumentParser(description="The frame's lowest eigenfrequencies, OpenSees' "
                                  "beside nsdyn's.")
    cli.add_argument("N", nargs="?", type=int, default=DATA["n_modes"],
                     help=f"how many (default {DATA['n_modes']}, at most the {DATA['n_free']} "
                          "free dofs)")
    n = cli.parse_args().N
    if not 1 <= n <= DATA["n_free"]:
        cli.error(f"N: expected 1 to {DATA['n_free']} (the frame's free dofs), got {n}")
    f = eigen_frequencies(n)
    ref = DATA["nsdyn_f_hz"][:n]
    diff = [(a - b) / b for a, b in zip(f, ref)]
    print(json.dumps({"frame": DATA["name"], "mass": DATA["mass"], "opensees_f_hz": f,
                      "nsdyn_f_hz": ref, "families": DATA["nsdyn_families"][:n],
                      "relative_difference": diff}))
'''
)


def _transforms(vecxz: np.ndarray) -> tuple[list, np.ndarray]:
    uniq, inverse = np.unique(np.asarray(vecxz, float), axis=0, return_inverse=True)
    return uniq.tolist(), np.asarray(inverse).ravel()


def frame_data_3d(frame: Frame3D, mass: str = "consistent") -> dict:
    """The JSON-able frame part of an exported model: nodes, members (with their OpenSees
    section constants), node masses and diaphragms (``build_frame`` of the scripts).

    ``mass``: ``"consistent"`` (nsdyn's default) or ``"lumped"`` (HRZ; module docstring).
    """
    if not isinstance(frame, Frame3D):
        raise TypeError(f"expected a Frame3D, got {type(frame).__name__}")
    if mass not in MASSES:
        raise ValueError(f"mass: expected one of {list(MASSES)}, got {mass!r}")
    transforms, transf = _transforms(frame.vecxz)
    rho_A = np.asarray(frame.rho_A, float)
    if mass == "lumped":  # massless members; nsdyn's HRZ diagonal (with the node masses) on nodes
        _, Ml = frame.assemble(lumped=True)
        node_mass = Ml.diagonal().reshape(frame.n_nodes, 6)
        J_ops, G_ops, rho_ops = frame.J, frame.G, np.zeros_like(rho_A)
    else:
        node_mass = np.zeros((frame.n_nodes, 6))
        node_mass[:, :3] = frame.node_mass
        if np.any((rho_A == 0) & (frame.rho_Ip > 0)):
            e = int(np.argmax((rho_A == 0) & (frame.rho_Ip > 0)))
            raise ValueError(
                f"element {e}: torsional inertia rho_Ip without rho_A cannot be exported with "
                "OpenSees' consistent mass; use mass='lumped'"
            )
        massive = rho_A > 0
        J_ops = np.where(massive, frame.A * frame.rho_Ip / np.where(massive, rho_A, 1.0), frame.J)
        G_ops, rho_ops = frame.G * frame.J / J_ops, rho_A
    return {
        "name": str(frame.name),
        "mass": mass,
        "nodes": frame.nodes.tolist(),
        "elements": frame.elements.tolist(),
        "transforms": transforms,
        "transf": transf.tolist(),
        "A": frame.A.tolist(),
        "E": frame.E.tolist(),
        "G": np.asarray(G_ops, float).tolist(),
        "J": np.asarray(J_ops, float).tolist(),
        "I_y": frame.I_y.tolist(),
        "I_z": frame.I_z.tolist(),
        "rho_A": np.asarray(rho_ops, float).tolist(),
        "node_mass": node_mass.tolist(),
        "base_nodes": frame.base_nodes.tolist(),
        "diaphragms": [
            {
                "nodes": d.nodes.tolist(),
                "centre": d.centre.tolist(),
                "z": float(frame.nodes[d.nodes[0], 2]),
                "mass": float(d.mass),
                "inertia": float(d.inertia),
            }
            for d in frame.diaphragms
        ],
    }


def opensees_data_3d(frame: Frame3D, mass: str = "consistent", n_modes: int = N_MODES) -> dict:
    """The JSON-able data of the exported fixed-base model (see the module docstring).

    ``mass``: ``"consistent"`` (nsdyn's default) or ``"lumped"`` (HRZ); ``n_modes``: how
    many of nsdyn's fixed-base frequencies the script carries for comparison.
    """
    if not isinstance(frame, Frame3D):
        raise TypeError(f"expected a Frame3D, got {type(frame).__name__}")
    if mass not in MASSES:
        raise ValueError(f"mass: expected one of {list(MASSES)}, got {mass!r}")
    if not (isinstance(n_modes, int) and n_modes >= 1):
        raise ValueError(f"n_modes: expected a positive integer, got {n_modes!r}")
    base = set(frame.base_nodes.tolist())
    for k, d in enumerate(frame.diaphragms):
        if base & set(d.nodes.tolist()):
            raise ValueError(f"diaphragm {k} holds a base node: a clamped node cannot be a slave")
    data = frame_data_3d(frame, mass)
    modes = fixed_base_modes_3d(frame, n_modes=n_modes, lumped=mass == "lumped")
    data.update(
        n_free=int(frame.n_red - len(frame.boundary_reduced)),
        n_modes=int(len(modes.f_hz)),
        nsdyn_f_hz=modes.f_hz.tolist(),
        nsdyn_families=list(modes.family),
    )
    return data


def _description(d: dict) -> str:
    how = (
        "consistent mass (-cMass; G' J' = G J with J' = A rhoI_p / rhoA)"
        if d["mass"] == "consistent"
        else "lumped (HRZ) nodal masses, massless members"
    )
    return (
        f"{len(d['nodes'])} nodes, {len(d['elements'])} elasticBeamColumn members "
        f"({len(d['transforms'])} geomTransf Linear orientations), {how};\n"
        f"{len(d['diaphragms'])} rigid diaphragms (rigidDiaphragm 3, masters at the centres of "
        f"mass), {len(d['base_nodes'])} clamped base nodes.\n"
    )


def script_text_3d(data: dict, filename: str = "model.py") -> str:
    """The standalone script of ``data`` (:func:`opensees_data_3d`)."""
    head = HEADER.format(
        name=data["name"],
        description=_description(data),
        filename=filename,
        n_modes=data["n_modes"],
    )
    preload = inspect.getsource(_preload_opensees_libraries)
    blob = json.dumps(data, separators=(",", ":"))
    return f"{head}\n{preload}\n\nDATA = json.loads({blob!r})\n{SCRIPT}"


def export_opensees_3d(
    frame, path=None, *, mass: str = "consistent", n_modes: int = N_MODES
) -> str:
    """Write (if ``path``) and return the standalone script of a space frame, fixed base.

    ``frame``: a :class:`~nsdyn.structure.Frame3D`, a 3D frame file or a bundled name.
    """
    from nsdyn.atomic import atomic_open

    if not isinstance(frame, Frame3D):
        frame = load_frame3d(frame)
    data = opensees_data_3d(frame, mass=mass, n_modes=n_modes)
    text = script_text_3d(data, Path(path).name if path is not None else "model.py")
    if path is not None:
        with atomic_open(path, "w") as fh:
            fh.write(text)
    return text
