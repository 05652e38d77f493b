"""Response metrics of a transient run (seed 004 §5).

Physical displacements are recovered from the generalised coordinates only at the output
nodes (``u_out = T[out] q``; :func:`output_rows`: a frame's column joints and level nodes, or
the level dofs of a system built from matrices). With q relative to the ground:

- interstorey drift ratio of storey s: |u_x(level s) - u_x(level s-1)| / h_s, at each column
  line, maximum over time and columns;
- absolute horizontal floor acceleration of level l: |u''_x,rel + u''_g,hor|, maximum over
  time and the level's nodes (u''_g = 0 under a force excitation);
- storey drift |u_x(level s) - u_x(level s-1)| [m] (all models with levels); the drift
  ratio needs the storey heights (frames; shear buildings given heights) and is absent else;
- isolator displacement x_iso = D_i q; top drift relative to the base (eq 17):
  x_top - x_iso;
- normal forces lam (minimum over time = uplift margin).

The energy balance in the relative frame::

    E(t) - E(0) = W_in - W_visc - W_fric + W_con,     E = 1/2 qd^T M qd + 1/2 q^T K* q
    W_in   = -int qd^T M Gamma_e [e_hor, e_ver + g] dt  (excitation and gravity; a
             force b F(t) enters as Gamma_e[:, 0] = -M^-1 b, so W_in = int qd^T b F dt)
    W_visc =  int qd^T C* qd dt,   W_fric = int sum_i tau_i v_i dt,
    W_con  =  int qd^T R^T lam dt   (Baumgarte drift work, ~0; plus the kinetic energy
             change of the landings of a unilateral run, <= 0)

is integrated by the trapezoidal rule on the output grid; the closure error
|dE - (W_in - W_visc - W_fric + W_con)| is reported relative to the largest of |W_in|,
W_visc + |W_fric|, |dE| and the energy the run starts with above the static state (a free
vibration's scale).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from nsdyn._brief import brief_repr
from nsdyn._lazy import LazyModule, issparse
from nsdyn._tabular import FrozenArrays
from nsdyn.models.isolated import _kernel as ks
from nsdyn.models.isolated.excitation import ground_many
from nsdyn.models.isolated.friction import sticks
from nsdyn.models.isolated.params import KernelParams, with_open

sp = LazyModule("scipy.sparse")


@dataclass(repr=False, eq=False)
class Response(FrozenArrays):
    """Response histories and peak metrics of one run (read-only arrays: its summary's)."""

    __repr__ = brief_repr  # arrays by shape, not in full

    t: np.ndarray  # (nt,)
    x_iso: np.ndarray  # (nt, ni) isolator slip D_i q
    top_drift: np.ndarray  # (nt,) x_top - x_iso (eq 17), left column line; NaN without levels
    lam: np.ndarray  # (nt, nc) normal forces
    tau: np.ndarray  # (nt, ni) friction forces
    modes: np.ndarray  # (nt, ni) +1/-1 slip, 0 stick
    idr_by_storey: np.ndarray  # (n_storeys,) peak interstorey drift ratio; (0,) without heights
    floor_acc_by_level: np.ndarray  # (n_levels,) peak absolute floor acceleration, level 0 = base
    energy: dict = field(default_factory=dict)
    drift_by_storey: np.ndarray = field(default_factory=lambda: np.zeros(0))  # (n_storeys,) [m]

    @property
    def x_iso_max(self) -> float:
        """Peak isolator slip |D_i q| over the run and the isolators [m] (0 without any)."""
        return float(np.max(np.abs(self.x_iso))) if self.x_iso.size else 0.0

    @property
    def idr_max(self) -> float:
        """Peak drift ratio (NaN when the model has no storey heights)."""
        return float(np.max(self.idr_by_storey)) if self.idr_by_storey.size else float("nan")

    @property
    def floor_acc_max(self) -> float:
        """Peak absolute floor acceleration over the construction levels above the base
        (level 0, the isolation level, is kept in ``floor_acc_by_level`` only); NaN when the
        model has no levels."""
        a = self.floor_acc_by_level
        if not a.size:
            return float("nan")
        return float(np.max(a[1:] if a.size > 1 else a))

    @property
    def roof_drift_max(self) -> float:
        """Peak top-level displacement relative to the base (NaN without levels)."""
        d = self.top_drift
        return float(np.max(np.abs(d))) if d.size and np.all(np.isfinite(d)) else float("nan")

    @property
    def min_normal_force(self) -> float:
        """Least normal force λ over the run and the contacts [N] (NaN without contacts)."""
        # + 0.0: a contact held at zero reads 0, not -0 (a unilateral flight's λ = -0.0)
        return float(np.min(self.lam)) + 0.0 if self.lam.size else float("nan")

    @property
    def stick_fraction(self) -> float:
        """Share of output instants at which every isolator sticks."""
        if self.modes.size == 0:
            return 1.0
        return float(np.mean(np.all(self.modes == 0, axis=1)))

    def summary(self) -> dict:
        """Peak metrics; those the model cannot define (drift ratios without storey heights,
        floor quantities without levels, normal forces without contacts, the isolators' slip
        and stick share without isolators: a fixed base) are absent."""
        iso = self.modes.shape[-1] > 0
        out = {"x_iso_max_m": self.x_iso_max} if iso else {}
        if self.idr_by_storey.size:
            out["idr_max"] = self.idr_max
            out["idr_by_storey"] = self.idr_by_storey.tolist()
        if self.drift_by_storey.size:
            out["drift_by_storey_m"] = self.drift_by_storey.tolist()
        if self.floor_acc_by_level.size:
            out["floor_acc_max_mps2"] = self.floor_acc_max
            out["floor_acc_by_level_mps2"] = self.floor_acc_by_level.tolist()
        if np.isfinite(self.roof_drift_max):
            out["roof_drift_max_m"] = self.roof_drift_max
        if self.lam.shape[-1]:
            out["min_normal_force_N"] = self.min_normal_force
        if iso:
            out["stick_fraction"] = self.stick_fraction
        out["energy_closure"] = self.energy.get("closure", float("nan"))
        return out


def output_rows(system) -> dict:
    """Rows mapping q to the horizontal displacements the metrics need.

    ``joints`` (n_levels, n_lines, n): the column lines of a frame (one line per level for a
    model built from matrices) or None without levels; ``levels``: list of (n_nodes, n) per
    level (base level first); ``heights`` (n_storeys,) or None (no drift ratios).
    """
    if system.frame is not None:
        od = output_dofs(system.frame)
        T = system.T
        if od["joints_x"] is None:  # no column lines: floors, no drifts
            return {"joints": None, "levels": [T[d] for d in od["levels_x"]], "heights": None}
        if issparse(T):  # a large full-order model (nodal coordinates): sparse rows
            J = od["joints_x"]
            return {
                "joints": T[J.ravel()],
                "joint_shape": J.shape,
                "levels": [T[d] for d in od["levels_x"]],
                "heights": od["heights"],
            }
        return {
            "joints": T[od["joints_x"]],
            "levels": [T[d] for d in od["levels_x"]],
            "heights": od["heights"],
        }
    lv = system.info.get("levels")
    if not lv:
        return {"joints": None, "levels": [], "heights": None}
    eye = np.eye(system.n)
    rows = [eye[d] for d in lv]
    return {
        "joints": np.stack([r[:1] for r in rows]),  # first dof of each level
        "levels": rows,
        "heights": system.info.get("heights"),
    }


def output_dofs(frame) -> dict:
    """Full-model dof indices needed for the metrics (column joints and level nodes);
    ``joints_x`` None for a frame without regular column lines (a setback: no drift ratios)."""
    cj = None if frame.column_joints is None else np.asarray(frame.column_joints)
    return {
        "joints_x": None if cj is None else 3 * cj,  # (n_levels, n_columns)
        "levels_x": [3 * np.asarray(nodes) for nodes in frame.level_nodes],
        "heights": np.diff(np.asarray(frame.level_heights, dtype=float)),
    }


SPARSE_ROWS = 0.05  # output rows with fewer nonzeros than this fraction multiply as CSR


def as_product_rows(L):
    """``L`` (rows, n) as CSR when few of its entries are nonzero (a full model's rows pick
    single dofs: its dense rows made the metrics' products over a history 3x the run's
    integration at 1 593 dofs), else as given."""
    if isinstance(L, np.ndarray) and L.ndim == 2 and np.count_nonzero(L) < SPARSE_ROWS * L.size:
        return sp.csr_array(L)
    return L


def level_rows(od: dict):
    """All levels' output rows of ``od`` stacked (rows, n; CSR when sparse, see
    :func:`as_product_rows`), and the first row of each level."""
    stack = sp.vstack if issparse(od["levels"][0]) else np.concatenate
    starts = np.cumsum([0] + [rows.shape[0] for rows in od["levels"][:-1]])
    return as_product_rows(stack(od["levels"])), starts


def level_peaks(od: dict, q: np.ndarray, QDD: np.ndarray | None, ug_hor: np.ndarray) -> tuple:
    """Storey drifts, roof drift and floor accelerations of a history (``od`` from
    :func:`output_rows`, ``q`` and ``QDD`` (nt, n), ``ug_hor`` (nt, 1) the horizontal ground
    acceleration or zeros).

    Returns ``(drift_m, top_drift, acc)``: the largest |joint above - joint below| of each
    storey over time and column lines (empty without levels), the roof's drift history
    (NaN without levels) and the largest absolute horizontal acceleration of each level's
    nodes over time (empty without levels, or with ``QDD`` None: the drifts alone). One
    product for all joints and one for all level nodes, formed transposed
    (rows x nt): the reductions over time then run along contiguous rows, ~6x faster than over
    the columns of an (nt, rows) array for the default run's 8 001 outputs.
    """
    nt = q.shape[0]
    drift_m = np.zeros(0)
    top_drift = np.full(nt, np.nan)  # no levels: undefined (kept as a history for plots)
    if od["joints"] is not None:
        if "joint_shape" in od:  # sparse rows (n_lev * n_lin, n)
            n_lev, n_lin = od["joint_shape"]
            UT = od["joints"] @ q.T
        else:
            n_lev, n_lin = od["joints"].shape[:2]
            UT = as_product_rows(od["joints"].reshape(n_lev * n_lin, -1)) @ q.T  # level-major
        if n_lev > 1:
            dU = np.abs(UT[n_lin:] - UT[:-n_lin])  # the same line on adjacent levels
            drift_m = dU.max(axis=1).reshape(n_lev - 1, n_lin).max(axis=1)
        top_drift = UT[(n_lev - 1) * n_lin] - UT[0]
    acc = np.zeros(0)
    if od["levels"] and QDD is not None:
        L, starts = level_rows(od)
        AT = np.asarray(L @ QDD.T)
        AT += ug_hor.T
        peak = np.abs(AT, out=AT).max(axis=1)
        acc = np.maximum.reduceat(peak, starts)
    return drift_m, top_drift, acc


def _trapz(y, t):
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t))) if t.size > 1 else 0.0


STORED_ROUND_OFF = 1e-9  # relative round-off of a stored energy 1/2 q K q (n <= 1e6: n eps)


def energy_balance(system, t, X, P, LAM, TAU, G, impact_energy: float = 0.0) -> dict:
    """Energy terms of the relative-frame balance (see module docstring)."""
    n = system.n
    q, qd = X[:, :n], X[:, n:]
    kpar = KernelParams(P)
    ug = G.copy()
    ug[:, 1] += kpar.g
    M, K = system.M, system.K
    # the stored energy is needed at the ends only
    ends = [0.5 * float(v @ A @ v) for v, A in ((qd[-1], M), (q[-1], K), (qd[0], M), (q[0], K))]
    dE = ends[0] + ends[1] - ends[2] - ends[3]
    Gamma_e = kpar.matrices()["Gamma"]  # the packed load influence (ground or force)
    if Gamma_e.shape[0] != n:  # the stand-in tuple of a sparse full-order run: ground only
        Gamma_e = system.Gamma
    # the powers along the history from one (nt, n) product: qd C, qd M Gamma, qd R^T, qd D^T
    nc = system.R.shape[0]
    model = None  # a full-order model's operators, with its own damping (scipy's on use)
    if getattr(system, "sparse", None) is not None:
        from nsdyn.models.isolated.fullorder import own_sparse

        model = own_sparse(system)
    if model is not None and 2 * model.c.size < n:  # (fewer flops than its dense n² per output)
        CQ = np.asarray(model.damp(qd.T)).T  # (the dense product was 3x the run's steps)
        B = np.hstack([CQ, qd @ (M @ Gamma_e), qd @ system.R.T, qd @ system.D.T])
    elif isinstance(system.C, np.ndarray) and isinstance(M, np.ndarray):
        B = qd @ np.hstack([system.C, M @ Gamma_e, system.R.T, system.D.T])
    else:  # sparse / low-rank operators (C symmetric: qd C = (C qd^T)^T)
        CQ = np.asarray(system.C @ qd.T).T
        B = np.hstack([CQ, qd @ (M @ Gamma_e), qd @ system.R.T, qd @ system.D.T])
    p_visc = np.sum(B[:, :n] * qd, axis=1)
    p_in = -np.sum(B[:, n : n + 2] * ug, axis=1)
    p_con = np.sum(B[:, n + 2 : n + 2 + nc] * LAM, axis=1) if LAM.size else np.zeros(t.size)
    p_fric = np.sum(TAU * B[:, n + 2 + nc :], axis=1) if TAU.size else np.zeros(t.size)
    W_in, W_visc = _trapz(p_in, t), _trapz(p_visc, t)
    W_fric, W_con = _trapz(p_fric, t), _trapz(p_con, t) + impact_energy
    # the energy a run from a given state starts with, above the static equilibrium's (0 for a
    # run from rest): a free vibration's scale (its stored energy only changes by round-off)
    dq0 = q[0] - system.static_equilibrium()[0][:n]
    E0 = 0.5 * float(qd[0] @ M @ qd[0] + dq0 @ K @ dq0)
    # dE is a difference of the stored energies at the ends, with their round-off (n eps of
    # each, below STORED_ROUND_OFF of them for n <= 1e6): a run that moves by less (no
    # ground motion) is measured against that, not against its own round-off
    scale = max(abs(W_in), W_visc + abs(W_fric), abs(dE), E0, STORED_ROUND_OFF * max(ends), 1e-300)
    return {
        "input": W_in,
        "stored_change": dE,
        "viscous": W_visc,
        "friction": W_fric,
        "constraint": W_con,
        "closure": abs(dE - (W_in - W_visc - W_fric + W_con)) / scale,
    }


def evaluation_arrays(P: tuple, nt: int) -> tuple:
    """Empty accelerations (nt, n), normal forces (nt, nc), friction forces (nt, ni) and
    modes (nt, ni; int64) for the evaluations of ``nt`` states of ``P``."""
    n, nc, ni = P[ks.I_MIK].shape[0], P[ks.I_R].shape[0], P[ks.I_D].shape[0]
    return np.empty((nt, n)), np.empty((nt, nc)), np.empty((nt, ni)), np.empty((nt, ni), np.int64)


def evaluate_along(evaluate_many, P: tuple, t, X, open_contacts=None) -> tuple:
    """The accelerations, normal forces, friction forces and modes along the history ``X``
    by ``evaluate_many(t, X, P, QDD, LAM, TAU, MODES)`` (a kernel of the system kernel along
    a history): every contact closed, or with ``open_contacts`` (nt, nc; 1 open, a
    unilateral run) one call per contact pattern, with its own open set. ``t`` and ``X``
    C-contiguous float arrays."""
    out = evaluation_arrays(P, t.size)
    if open_contacts is None or not np.any(open_contacts):
        evaluate_many(t, X, P, *out)
        return out
    pats, which = np.unique(np.asarray(open_contacts, np.int64), axis=0, return_inverse=True)
    which = np.asarray(which).reshape(-1)
    for j, pat in enumerate(pats):
        sel = np.flatnonzero(which == j)
        part = evaluation_arrays(P, sel.size)
        evaluate_many(t[sel], np.ascontiguousarray(X[sel]), with_open(P, pat), *part)
        for a, b in zip(out, part, strict=True):
            a[sel] = b
    return out


def response(
    system, t, X, P, open_contacts=None, impact_energy: float = 0.0, *, evaluated=None
) -> Response:
    """Metrics of a history ``X`` (nt, 2n) of ``system`` computed with kernel tuple ``P``.

    ``P`` must use a law that decides the friction modes itself (arctan or switch); for an
    event-driven run pass the switch law. ``open_contacts`` (nt, nc), 1 where a contact is
    open (a unilateral run in flight: no normal force, no friction there);
    ``impact_energy`` the kinetic energy change of its landings [J]; ``evaluated``: the
    accelerations, normal forces, friction forces and modes along ``X`` when the caller has
    them (``nsdyn.solve.transient.flat_evaluations``), else the system kernel evaluates them.
    """
    t = np.ascontiguousarray(t, dtype=float)
    X = np.ascontiguousarray(X, dtype=float)
    n, nt = system.n, t.size
    if evaluated is None:
        evaluated = evaluate_along(ks.evaluate_many, P, t, X, open_contacts)
    QDD, LAM, TAU, MODES = evaluated
    G = ground_many(t, P)
    kpar = KernelParams(P)
    ug_hor = np.zeros((nt, 1)) if kpar.force else G[:, :1]  # ground acceleration (0: force)
    od = output_rows(system)
    q = X[:, :n]
    drift_m, top_drift, acc = level_peaks(od, q, QDD, ug_hor)
    if getattr(system, "fidelity", None) == "rigid":  # no storey deforms: 0, not round-off
        drift_m, top_drift = np.zeros_like(drift_m), np.zeros_like(top_drift)
    idr = np.zeros(0)
    if od["heights"] is not None and drift_m.size:
        # max_t,c(dU / h) = max_t,c(dU) / h exactly (h > 0; rounded division is monotonic)
        idr = drift_m / np.asarray(od["heights"], dtype=float)
    x_iso = q @ system.D.T
    # stick as nsdyn.models.isolated.friction defines it, for every law
    v = X[:, n:] @ system.D.T
    MODES = np.where(sticks(v, kpar.law, kpar.eps, kpar.eta, MODES), 0, MODES)
    energy = energy_balance(system, t, X, P, LAM, TAU, G, impact_energy)
    return Response(
        t=t,
        x_iso=x_iso,
        top_drift=top_drift,
        lam=LAM,
        tau=TAU,
        modes=MODES,
        idr_by_storey=idr,
        floor_acc_by_level=acc,
        energy=energy,
        drift_by_storey=drift_m,
    )
