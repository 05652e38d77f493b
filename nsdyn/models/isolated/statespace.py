"""Linear models of the ladder as python-control state-space systems, and small demo systems.

The fixed-base frame is linear (seed 004 §6, Fig. 11), and so is the isolated frame without
friction (mu = 0). On the contact manifold q = Q z (eq 23) the latter reads

    Q^T M Q zdd + Q^T C* Q zd + Q^T K* Q z = -Q^T M Gamma_hor u''_hor ,

which :func:`linear_statespace` returns with input ``u''_hor`` and outputs chosen from the
relative displacements ``q`` or the full FE displacement field ``T q``.
"""

from __future__ import annotations

import numpy as np

from nsdyn.models.isolated.system import IsolatedSystem


def _mechanical_ss(Mz, Cz, Kz, Lz, Cout):
    import control

    n = Mz.shape[0]
    Mi = np.linalg.inv(Mz)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Mi @ Kz, -Mi @ Cz]])
    B = np.concatenate([np.zeros(n), -Mi @ Lz])[:, None]
    Cm = np.hstack([Cout, np.zeros((Cout.shape[0], n))])
    return control.ss(A, B, Cm, np.zeros((Cout.shape[0], 1)))


def linear_statespace(system: IsolatedSystem, outputs: np.ndarray | None = None):
    """State-space model of ``system`` with friction removed (mu = 0), input u''_hor.

    Parameters
    ----------
    outputs : ndarray, shape (n_out, n), optional
        Rows selecting outputs from q (default: identity, i.e. all q).

    Returns
    -------
    control.StateSpace with state [z, zd] (z = minimal coordinates).
    """
    Q = system.Q
    Mz = Q.T @ system.M @ Q
    Cz = Q.T @ system.C @ Q
    Kz = Q.T @ system.K @ Q
    Lz = Q.T @ system.M @ system.Gamma[:, 0]
    out = np.eye(system.n) if outputs is None else np.atleast_2d(outputs)
    return _mechanical_ss(Mz, Cz, Kz, Lz, out @ Q)


def fixed_base_statespace(system: IsolatedSystem, full_dofs: np.ndarray | None = None):
    """The fixed-base frame (fidelity "fixed") as a python-control system.

    Outputs are the relative displacements of the full FE dofs ``full_dofs`` (indices into the
    frame's dofs, 3 per node: x, y, rotation; default: all).
    """
    if system.fidelity != "fixed":
        raise ValueError(f"expected a fixed-base model, got fidelity {system.fidelity!r}")
    n = system.T.shape[0]
    if full_dofs is not None:
        d = np.asarray(full_dofs)
        if d.dtype.kind == "b" and d.shape == (n,):  # (a mask of the dofs)
            d = np.flatnonzero(d)
        if d.dtype.kind not in "iu" or d.ndim > 1 or d.size == 0 or d.min() < 0 or d.max() >= n:
            raise ValueError(f"full_dofs: expected indices of the frame's dofs, 0 to {n - 1} (or "
                             f"a mask of {n}), got {full_dofs!r}")  # fmt: skip
    T = system.T if full_dofs is None else system.T[d]
    return _mechanical_ss(system.M, system.C, system.K, system.Gamma[:, 0], T)


def demo_frame(storeys: int = 3, n_v: int = 2, n_h: int = 2):
    """A small one-bay steel frame (8 m bay, 4 m storeys, 20 t floors) for tests and docs."""
    from nsdyn.structure import Section, regular_frame

    col = Section(E=2.1e11, A=0.02, I=4e-4, rho_A=160.0)
    beam = Section(E=2.1e11, A=0.02, I=8e-4, rho_A=160.0)
    return regular_frame(
        "demo", [8.0], [4.0] * storeys, n_v, n_h, col, beam, floor_mass=2.0e4, zeta=[0.02, 0.03]
    )
