"""Isolated systems without a frame: any linear superstructure from matrices, shear buildings.

The same constrained form as the frame's model ladder (:mod:`nsdyn.models.isolated.system`)::

    M qdd + C* qd + K* q = -M Gamma [u''_hor, u''_ver + g] + R^T lam - D^T tau
    K* = K + D^T diag(k_lam) D,   C* = C + D^T diag(c) D

with ``q`` relative to the ground, ``D`` the sliding rows (isolator slip ``D_i q``) and the
normal force of isolator i either

- **frozen** (``weight`` given): ``N_i`` fixed at its share of the weight, no contacts (``R``
  empty) and hence no uplift check — the textbook Coulomb oscillator ``F = mu N s(v)``; or
- a **constraint multiplier** (``contact_rows`` R given, one vertical gap per isolator): the
  vertical influence column ``Gamma[:, 1]`` carries gravity to the contacts, ``lam`` follows the
  dynamics and uplift (``lam <= 0``) is checked as for a frame.

Shear building (storey k between levels k-1 and k; level 0 the base slab on the isolators):
``M = diag(m_0..m_N)``, ``K = L^T K_fb L``, ``C = L^T C_fb L`` with ``(L q)_k = q_k - q_0`` and
``K_fb`` the fixed-base tridiagonal storey stiffness, ``C_fb = M_fb Phi diag(2 zeta_i w_i)
Phi^T M_fb`` (classical damping of the fixed-base modes, ``Phi^T M_fb Phi = I``).
"""

from __future__ import annotations

import warnings
from functools import partial

import numpy as np

from nsdyn._checks import InputWarning, NotedWarning, got_array
from nsdyn.models.isolated.system import IsolatedSystem, Isolation, _add_isolators

SYMMETRY_RTOL = 1e-10  # |A - A^T| allowed, relative to max |A|
PSD_RTOL = 1e-10  # eigenvalue allowed below zero, relative to the largest (K and C: >= 0)


class MatrixError(ValueError):
    """A system matrix or vector has the wrong shape or value; the message names it."""


def _floats(name: str, v, what: str) -> np.ndarray:
    """``v`` as a float array; text, bools and ragged or non-numeric entries are refused
    naming ``name`` (NumPy would read "1.0" as 1.0 and fail on "abc" without a name)."""
    try:
        a = np.asarray(v)
    except ValueError:  # ragged
        a = np.asarray(v, dtype=object)
    if a.dtype.kind not in "iuf":
        raise MatrixError(f"{name}: expected {what}, got {v!r}")
    return a.astype(float)


def _square(name: str, A, n: int | None) -> np.ndarray:
    try:
        A = np.array(A, dtype=float)
    except (TypeError, ValueError) as e:
        nested = isinstance(A, list | tuple) and all(isinstance(r, list | tuple) for r in A)
        rows = {len(r) for r in A} if nested else set()
        why = (
            f"rows of {', '.join(str(len(r)) for r in A)} entries"
            if len(rows) > 1
            else str(e).split(". ")[0]
        )  # (numpy's "setting an array element ...")
        raise MatrixError(f"{name}: expected a square matrix of numbers, got {why}") from None
    if A.ndim == 0 and n in (None, 1):
        A = A.reshape(1, 1)
    if A.ndim != 2 or A.shape[0] != A.shape[1] or A.size == 0:  # (0 x 0: a numpy error)
        raise MatrixError(f"{name}: expected a square matrix of one dof or more, got shape "
                          f"{A.shape}")  # fmt: skip
    if n is not None and A.shape != (n, n):
        raise MatrixError(f"{name}: expected shape ({n}, {n}) like M, got {A.shape}")
    bad = np.argwhere(~np.isfinite(A))
    if bad.size:
        i, j = bad[0]
        raise MatrixError(f"{name}: entry [{i}, {j}] is {A[i, j]}; expected finite numbers")
    scale = max(float(np.max(np.abs(A))), 1e-300)
    asym = float(np.max(np.abs(A - A.T)))
    if asym > SYMMETRY_RTOL * scale:
        i, j = np.unravel_index(np.argmax(np.abs(A - A.T)), A.shape)
        raise MatrixError(
            f"{name}: not symmetric ({name}[{i}, {j}] = {A[i, j]:.6g}, {name}[{j}, {i}] = "
            f"{A[j, i]:.6g}); expected {name} = {name}^T"
        )
    return 0.5 * (A + A.T)


def _definite(name: str, A: np.ndarray, strict: bool) -> None:
    w = np.linalg.eigvalsh(A)
    floor = PSD_RTOL * max(float(np.max(np.abs(w))), 1e-300)
    if (strict and not w[0] > floor) or w[0] < -floor:
        what = "positive definite" if strict else "positive semi-definite"
        raise MatrixError(f"{name}: expected {what}, smallest eigenvalue is {w[0]:.6g}")


def _rows(name: str, rows, n: int) -> np.ndarray:
    a = np.asarray(rows)
    if a.ndim == 0 and np.issubdtype(a.dtype, np.integer):  # one dof index (it read (1, 1))
        a = a.reshape(1)
    if a.ndim == 1 and (a.size == 0 or np.issubdtype(a.dtype, np.integer)):
        if a.size == 0:
            raise MatrixError(f"{name}: expected at least one dof index")
        if np.any(a < 0) or np.any(a >= n) or len(set(a.tolist())) != a.size:
            raise MatrixError(f"{name}: expected distinct dof indices in 0..{n - 1}, got {a}")
        return np.eye(n)[a]
    try:
        a = np.atleast_2d(np.asarray(rows, dtype=float))
    except (TypeError, ValueError):  # (text: numpy's message, naming no argument)
        a = np.full((1, 1), np.nan)
    if a.ndim != 2 or a.shape[1] != n or not np.all(np.isfinite(a)):
        got = got_array(a, (None, n)) if np.ndim(rows) == 2 else repr(rows)[:80]
        raise MatrixError(f"{name}: expected dof indices or finite rows of length {n}, got {got}")
    return a


def _label(name) -> None:
    """A system's name: non-empty text (it heads reports and names output files)."""
    if not isinstance(name, str) or not name.strip():
        raise TypeError(f"name: expected a label (non-empty text), got {name!r}")


def _influence(influence, n: int) -> np.ndarray:
    G = _floats("influence", influence, "numbers")
    if G.shape == (n,):
        G = np.column_stack([G, np.zeros(n)])
    if G.shape != (n, 2) or not np.all(np.isfinite(G)):
        got = got_array(influence, (n,) if np.ndim(influence) == 1 else (n, 2))
        raise MatrixError(f"influence: expected {n} finite values (horizontal) or shape "
                          f"({n}, 2) (horizontal, vertical), got {got}")  # fmt: skip
    return G


STOREY_PLAUSIBLE = 50.0  # [m] a storey higher than this: heights in mm? (noted)


def _levels(levels, heights, n: int) -> dict:
    out: dict = {}
    if levels is None:
        if heights is not None:
            raise MatrixError("heights: storey heights need levels (the dofs of each level)")
        return out
    lv = []
    for k, dofs in enumerate(levels):
        d = np.atleast_1d(np.asarray(dofs))
        if d.size == 0 or not np.issubdtype(d.dtype, np.integer) or d.min() < 0 or d.max() >= n:
            raise MatrixError(f"levels[{k}]: expected dof indices in 0..{n - 1}, got {dofs!r}")
        lv.append([int(i) for i in d])
    out["levels"] = lv
    if heights is not None:
        h = np.atleast_1d(_floats("heights", heights, "storey heights [m]"))
        if h.size == 1 and len(lv) > 2:
            h = np.full(len(lv) - 1, float(h[0]))
        if h.shape != (len(lv) - 1,) or not np.all(np.isfinite(h) & (h > 0)):
            raise MatrixError(
                f"heights: expected {len(lv) - 1} positive storey heights (one per pair of "
                f"consecutive levels) or one for all, got {heights!r}"
            )
        if h.max() > STOREY_PLAUSIBLE:  # (3000 for 3 m ran: drift ratios 1000x small, unsaid)
            warnings.warn(f"heights: a storey {h.max():.4g} m high, past the "
                          f"{STOREY_PLAUSIBLE:g} m of any building storey (2.5-6 m): storey "
                          "heights are in m; are they in mm?",
                          NotedWarning, stacklevel=4)  # fmt: skip
        out["heights"] = h
    return out


def system_from_matrices(
    M,
    C,
    K,
    *,
    iso_dofs,
    influence,
    isolation: Isolation,
    weight=None,
    contact_rows=None,
    levels=None,
    heights=None,
    name: str = "matrices",
) -> IsolatedSystem:
    """An isolated system from the matrices of any linear superstructure.

    Parameters
    ----------
    M, C, K : array_like, shape (n, n)  mass (positive definite), damping and stiffness
                                        (positive semi-definite), symmetric, relative to ground
    iso_dofs : ints or ndarray (ni, n)  the dofs whose displacement is the isolators' slip
                                        (or the sliding rows D themselves)
    influence : array_like, (n,) or (n, 2)   Gamma: ground-acceleration influence vectors
                                        (horizontal; vertical, which also carries gravity)
    isolation : Isolation               isolator springs k_lam and dampers c (added on the
                                        sliding rows), friction mu and law, per isolator
    weight : float or (ni,) floats      frozen normal forces [N]: one total split equally over
                                        the isolators, or one per isolator (no contacts)
    contact_rows : ndarray (ni, n)      vertical gap rows R (normal forces = multipliers)
    levels : list of dof lists          horizontal dofs of each level, base level first
                                        (floor accelerations, storey drifts; optional)
    heights : float or (n_levels-1,)    storey heights [m] for drift ratios (optional)
    """
    if not isinstance(isolation, Isolation):
        raise TypeError(f"isolation: expected an Isolation, got {type(isolation).__name__}")
    _label(name)
    M = _square("M", M, None)
    n = M.shape[0]
    C = _square("C", C, n)
    K = _square("K", K, n)
    _definite("M", M, strict=True)
    _definite("K", K, strict=False)
    _definite("C", C, strict=False)
    D = _rows("iso_dofs", iso_dofs, n)
    ni = D.shape[0]
    Gamma = _influence(influence, n)
    if not np.any(Gamma[:, 0]):  # the horizontal record would move nothing: runs at rest
        said = ("influence: all zero horizontally, so a horizontal ground motion does not load "
                "the system (a force load still does)")  # fmt: skip
        warnings.warn(said, InputWarning, stacklevel=2)
    if weight is not None and contact_rows is not None:
        raise MatrixError(
            "give either weight (frozen normal forces) or contact_rows (normal forces as "
            "constraint multipliers), not both"
        )
    iso = isolation
    normal = None
    if contact_rows is not None:
        R = _rows("contact_rows", contact_rows, n)
        if R.shape[0] != ni:
            raise MatrixError(
                f"contact_rows: expected one row per isolator ({ni}), got {R.shape[0]}"
            )
        if not np.any(R @ Gamma[:, 1]):
            raise MatrixError(
                "contact_rows: the vertical influence (influence[:, 1]) does not load the "
                "contacts, so gravity gives no normal force; pass influence of shape (n, 2)"
            )
    else:
        R = np.zeros((0, n))
        if weight is None:
            if iso.law != "none" and np.any(np.asarray(iso.mu) != 0):
                raise MatrixError(
                    "friction needs normal forces: pass weight= (frozen normal forces [N]) "
                    "or contact_rows= (vertical gaps; normal forces from the dynamics)"
                )
            normal = np.zeros(ni)
        else:
            w = np.atleast_1d(_floats("weight", weight, "normal forces [N]"))
            if w.size == 1:
                w = np.full(ni, float(w[0]) / ni)
            if w.shape != (ni,) or not np.all(np.isfinite(w) & (w > 0)):
                raise MatrixError(
                    f"weight: expected one positive total [N] or {ni} positive normal "
                    f"force{'s' * (ni != 1)} (one per isolator), got {weight!r}"
                )
            normal = w
        iso = iso.changed(frozen_normal=True)
    info = _levels(levels, heights, n)
    Ks, Cs = _add_isolators(K, C, D, iso, contacts=R.shape[0] > 0, frame=False)
    info["total_mass"] = float(Gamma[:, 0] @ M @ Gamma[:, 0])
    info["rebuild"] = partial(
        system_from_matrices,
        M,
        C,
        K,
        iso_dofs=D,
        influence=Gamma if contact_rows is not None else Gamma[:, 0],
        weight=weight,
        contact_rows=contact_rows,
        levels=levels,
        heights=heights,
        name=name,
    )
    system = IsolatedSystem(
        name,
        "matrices",
        M,
        Cs,
        Ks,
        Gamma,
        R,
        D,
        np.eye(n),
        iso,
        None,
        None,
        info,
        normal_force=normal,
    )
    if contact_rows is not None:  # each contact in compression at rest (cached for the runs)
        lam = system.static_equilibrium()[1]
        if lam.size and not np.all(lam > 0):
            k = int(np.argmin(lam))
            raise MatrixError(
                f"contact_rows: contact {k} carries no compression at rest (normal force "
                f"{lam[k]:.4g} N); check the rows' sign (R q is the gap, opening upwards; the "
                "normal force is compressive positive) and the vertical influence"
            )
    return system


def _storey_matrices(masses, stiffnesses, zeta) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M, C, K (N+1 square) of the shear building on a free base (see module docstring)."""
    m = np.asarray(masses, dtype=float)
    k = np.asarray(stiffnesses, dtype=float)
    N = k.size
    M = np.diag(m)
    if N == 0:
        return M, np.zeros((1, 1)), np.zeros((1, 1))
    Kfb = np.diag(k + np.append(k[1:], 0.0)) - np.diag(k[1:], 1) - np.diag(k[1:], -1)
    Mfb = np.diag(m[1:])
    w2, Phi = np.linalg.eigh(np.diag(m[1:] ** -0.5) @ Kfb @ np.diag(m[1:] ** -0.5))
    Phi = np.diag(m[1:] ** -0.5) @ Phi  # mass-normalised fixed-base modes
    A = Mfb @ Phi
    Cfb = A @ np.diag(2.0 * zeta * np.sqrt(w2)) @ A.T
    L = np.hstack([-np.ones((N, 1)), np.eye(N)])  # storey displacements relative to the base
    return M, L.T @ Cfb @ L, L.T @ Kfb @ L


def shear_building(
    masses,
    stiffnesses,
    damping_ratios,
    *,
    isolation: Isolation,
    heights=None,
    name: str | None = None,
) -> IsolatedSystem:
    """A shear building on one lumped friction isolator (the isolation layer).

    Parameters
    ----------
    masses : (N+1,) floats [kg]        level masses, the base slab (level 0, on the isolator)
                                       first; ``[m]`` alone is the single-mass oscillator
    stiffnesses : (N,) floats [N/m]    storey k joins levels k-1 and k
    damping_ratios : float or (N,)     fixed-base modal damping ratios (ignored for N = 0)
    isolation : Isolation              the isolation layer's totals: k_lam [N/m], c [N s/m],
                                       mu and the friction law
    heights : float or (N,) [m]        storey heights for interstorey drift ratios (optional)

    The normal force of the isolator is frozen at the total weight ``g sum(masses)`` (no
    vertical dofs, so no uplift check).
    """
    if not isinstance(isolation, Isolation):
        raise TypeError(
            f"isolation: expected an Isolation (nsdyn.Isolation(k_lam=..., mu=...)), got "
            f"{type(isolation).__name__}"
        )
    m = np.atleast_1d(_floats("masses", masses, "one or more positive level masses [kg]"))
    k = (np.atleast_1d(_floats("stiffnesses", stiffnesses, "storey stiffnesses [N/m]"))
         if np.size(stiffnesses) else np.zeros(0))  # fmt: skip
    if m.ndim != 1 or m.size == 0 or not np.all(np.isfinite(m) & (m > 0)):
        raise MatrixError(f"masses: expected one or more positive level masses, got {masses!r}")
    if k.shape != (m.size - 1,) or not np.all(np.isfinite(k) & (k > 0)):
        raise MatrixError(
            f"stiffnesses: expected len(masses) - 1 = {m.size - 1} positive storey stiffnesses "
            f"(storey k between levels k-1 and k; level 0 is the base slab), got {stiffnesses!r}"
        )
    z = np.atleast_1d(_floats("damping_ratios", damping_ratios, "ratios in [0, 1)"))
    N = k.size
    if N and z.size == 1:
        z = np.full(N, float(z[0]))
    if N and (z.shape != (N,) or not np.all(np.isfinite(z) & (z >= 0) & (z < 1))):
        per = " (one storey: one fixed-base mode)" if N == 1 else f" or {N} (one per mode)"
        raise MatrixError(  # [0, 1) as a frame's zeta: 1.5 is 1.5 % mistyped, not overdamping
            f"damping_ratios: expected one ratio in [0, 1) (0.05 for 5 %){per}, got "
            f"{damping_ratios!r}"
        )
    M, C, K = _storey_matrices(m, k, z[:N] if N else z)
    if name is not None:
        _label(name)
    name = name or (f"shear building ({N} storeys)" if N else "single mass on an isolator")
    s = system_from_matrices(
        M,
        C,
        K,
        iso_dofs=[0],
        influence=np.ones(m.size),
        isolation=isolation,
        weight=float(isolation.g * m.sum()),
        levels=[[i] for i in range(m.size)],
        heights=None if heights is None or N == 0 else heights,
        name=name,
    )
    s.fidelity = "shear"
    s.info["rebuild"] = partial(shear_building, m, k, damping_ratios, heights=heights, name=name)
    s.info["shear"] = {"masses": m, "stiffnesses": k, "damping_ratios": z[:N]}
    return s
