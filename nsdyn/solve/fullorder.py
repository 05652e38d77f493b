"""Full-order runs on sparse operators: the factor-once generalized-alpha and the evaluations.

A full-order model in nodal coordinates (:mod:`nsdyn.models.isolated.fullorder`) is never
turned into the dense kernel tuple: its operators ``M``, ``K*``, ``C* = C + U diag(c) U^T``
(sparse + low rank), the influence ``Gamma`` and the rows ``R``, ``D`` drive the
``"operators"`` backend of :mod:`nsdyn.solve.sparse`, and a one-coordinate stand-in tuple
(``system.params(ground, stub=True)``) carries the friction law, the Baumgarte parameters and
the excitation.

The accelerations, normal forces and friction forces along a history (the metrics' inputs,
and the start of a run) solve the constrained equations at each output instant::

    M qdd = -K* q - C* qd - M Gamma u + R^T lam - D^T phi,
    R qdd + 2 alpha beta R qd + alpha^2 R q = 0,      phi = mu L s(D qd)

with ``qdd = A0 + G0 [lam; phi]`` (``M A0 = -K* q - C* qd - M Gamma u``, ``M G0 = [R^T,
-D^T]``, one sparse factorisation of ``M`` for all instants, in blocks of ``BLOCK`` rows):
the contact rows give ``lam = lam_c + Lam phi`` exactly, and since the velocity is given,
``phi = diag(mu s) (L_c + L_d phi)`` is linear in ``phi`` (``L = lam`` live, or the frozen
static normal forces). Open contacts (unilateral runs) and force excitations are not
supported here (the dense path runs them).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from nsdyn.models.isolated.excitation import ground_many
from nsdyn.models.isolated.fullorder import own_sparse
from nsdyn.models.isolated.params import KernelParams
from nsdyn.solve import _klowrank
from nsdyn.solve.checkpoint import CHUNK_S

__all__ = ["FullOps", "full_ops", "simulate_full", "warmup_operators"]

METHOD = "genalpha-lowrank"  # the sparse path's method (nsdyn.solve.sparse.METHOD)
DENSE_STEP_RANK = 0.5  # damped modes per dof above which the dense step is cheaper (dense_step)

K2 = 2.0 / np.pi


@dataclass(eq=False)
class FullOps:
    """Operators of a full-order model (``model``: a ``SparseModel``) with its influence
    ``Gamma`` (n, 2) and rows ``R`` (nc, n), ``D`` (ni, n)."""

    model: object
    Gamma: np.ndarray
    R: np.ndarray
    D: np.ndarray
    _m: dict = field(default_factory=dict, repr=False)

    def _mass(self):
        """(the accelerations' operators ``lin0, lr0``, G0, RGr^-1, Lam) — factored once."""
        if "lin0" not in self._m:
            import scipy.sparse as sp

            from nsdyn.solve.sparse import _sparse_lu, lu_arrays

            mo, R, D = self.model, self.R, self.D
            lu = _sparse_lu(sp.csc_array(mo.M))
            nc = R.shape[0]
            B = np.hstack([R.T, -D.T])
            G0 = lu.solve(B) if B.shape[1] else np.zeros((mo.n, 0))
            RGr_inv = np.linalg.inv(R @ G0[:, :nc]) if nc else np.zeros((0, 0))
            Lam = RGr_inv @ (-R @ G0[:, nc:]) if nc else np.zeros((0, D.shape[0]))
            W0 = sp.hstack([mo.K, mo.C], format="csr")
            W0.sort_indices()
            i64 = np.int64
            MG = np.ascontiguousarray(mo.M @ self.Gamma)
            lin0 = (W0.indptr.astype(i64), W0.indices.astype(i64), W0.data, MG, lu_arrays(lu))
            lr0 = (np.ascontiguousarray(mo.U), np.ascontiguousarray(mo.c, dtype=float))
            self._m.update(lin0=lin0, lr0=lr0, G0T=np.ascontiguousarray(G0.T), RGr_inv=RGr_inv,
                           Lam=Lam)  # fmt: skip
        m = self._m
        return m["lin0"], m["lr0"], m["G0T"], m["RGr_inv"], m["Lam"]

    def arrays(self) -> tuple:
        """The operators' arrays (M, K, C by their CSR parts; U, c, Gamma, R, D): what a
        run's checkpoint key (:func:`nsdyn.solve.checkpoint.run_key`) holds of the model
        beside the stand-in tuple."""
        mo = self.model
        parts = [getattr(A.tocsr(), k) for A in (mo.M, mo.K, mo.C)
                 for k in ("indptr", "indices", "data")]  # fmt: skip
        return (*parts, mo.U, mo.c, self.Gamma, self.R, self.D)

    def evaluate(self, P: tuple, t: np.ndarray, X: np.ndarray) -> tuple:
        """(QDD, LAM, TAU, MODES) at the rows of ``X`` (nt, 2n), times ``t`` (module text);
        ``P`` the stand-in kernel tuple (friction law, Baumgarte parameters, excitation)."""
        kp = KernelParams(P)
        if kp.force:
            raise ValueError("the sparse full-order path takes ground motions, not forces")
        n, nt = self.model.n, t.size
        R, D = self.R, self.D
        nc, ni = R.shape[0], D.shape[0]
        lin0, lr0, G0T, RGr_inv, Lam = self._mass()
        ab, bb = kp.alpha, kp.beta
        mu, lam0 = np.asarray(kp.mu, float), np.asarray(kp.lam_static, float)
        friction = kp.law == "arctan" and ni > 0 and bool(np.any(mu != 0.0))
        Ug = ground_many(np.ascontiguousarray(t, dtype=float), P)
        Ug[:, 1] += kp.g
        X = np.ascontiguousarray(X, dtype=float)
        QDD = np.empty((nt, n))
        _klowrank.accelerations_rows(X, Ug, lin0, lr0, QDD)  # A0, rows
        q, v = X[:, :n], X[:, n:]
        lam_c = -(QDD @ R.T + 2.0 * ab * bb * (v @ R.T) + ab * ab * (q @ R.T)) @ RGr_inv.T
        w = v @ D.T  # (nt, ni) slip velocities
        phi = np.zeros((nt, ni))
        if friction:
            s = mu * K2 * np.arctan(kp.eps * w)  # mu s, (nt, ni)
            if kp.frozen_normal or nc == 0:
                phi = s * lam0
            else:  # (I - diag(mu s) Ld) phi = diag(mu s) Lc, one small solve per instant
                Jm = np.eye(ni)[None] - s[:, :, None] * Lam[:ni][None]
                phi = np.linalg.solve(Jm, (s * lam_c[:, :ni])[:, :, None])[:, :, 0]
        lam = lam_c + phi @ Lam.T if nc else lam_c
        QDD += np.hstack([lam, phi]) @ G0T
        return QDD, lam, phi, np.where(w >= 0.0, 1, -1).astype(np.int64)


def dense_step(system) -> str:
    """Why ``genalpha-lowrank`` steps a full-order ``system`` on its dense copies rather than
    on the sparse operators (the reason's words), or "" (the sparse step). Dense when the
    copies exist (up to ``DENSE_MAX_DOF`` dofs) and the low-rank damping has more than
    ``DENSE_STEP_RANK`` n columns: per step the sparse path makes two passes over n x m
    arrays and three m x m products (4 n m + 6 m^2 flops for m damped modes), the dense one
    solves with a factorisation made once (2 n^2 per solve). With every mode damped (m ~ n,
    the modal damping up to ``MODAL_ALL_MAX_DOF`` dofs) the two steps cost about the same and
    the dense path's evaluations along a long record are the cheaper
    (``docs/guide/full-models-and-scale.md``). A damping matrix put in place of the model's
    own (e.g. the OpenSees export's) counts by its nonzeros: more than ``DENSE_STEP_RANK`` of
    its entries."""
    sp_model = getattr(system, "sparse", None)
    if sp_model is None or not isinstance(system.M, np.ndarray):
        return ""
    C = system.C
    if own_sparse(system) is None:  # a replaced damping matrix
        fill = np.count_nonzero(C) / C.size if isinstance(C, np.ndarray) else 0.0
        return f"dense: a damping matrix {fill:.0%} full" if fill > DENSE_STEP_RANK else ""
    m = sp_model.U.shape[1]
    return f"dense: modal damping of rank {m}" if m > DENSE_STEP_RANK * system.n else ""


def full_ops(system) -> FullOps:
    """The operators of ``system``: its sparse model when it has one and its damping is the
    model's own, else its (dense) matrices as sparse ones (cached on the system)."""
    from nsdyn.models.isolated.fullorder import SparseModel

    cached = system.info.get("_full_ops")
    if cached is not None and cached[0] is system.C:
        return cached[1]
    mo = own_sparse(system)
    if mo is None:
        if not isinstance(system.C, np.ndarray):
            raise ValueError(f"{system.name}: the damping was replaced by a non-matrix")
        mo = SparseModel.from_dense(system.M, system.C, system.K)
    ops = FullOps(mo, np.ascontiguousarray(system.Gamma, float), np.ascontiguousarray(system.R),
                  np.ascontiguousarray(system.D))  # fmt: skip
    system.info["_full_ops"] = (system.C, ops)
    return ops


_WARMED: list = []  # seconds the operators' kernels took to compile or load (once)


def warmup_operators(announce=None) -> float:
    """Compile (or load) the kernels of the sparse path (the ``"operators"`` step loop and the
    evaluations) on the two-dof problem of the warm-ups; seconds spent now (0.0 when done).
    ``announce(text)`` is called before a compilation (not when numba's cache has them)."""
    if _WARMED:
        return 0.0
    import time

    from nsdyn._numba_cache import compiling, dispatcher_cached

    entries = (_klowrank.run_steps_ops, _klowrank.accelerations_rows)
    if announce is not None and not all(dispatcher_cached(d) for d in entries):
        announce(f"compiling the {METHOD} integrator for sparse models (first run only)…")
    from nsdyn.models.isolated.fullorder import SparseModel
    from nsdyn.solve import _kcommon as ki
    from nsdyn.solve import sparse
    from nsdyn.solve.methods import _tiny_problem

    t0 = time.perf_counter()
    P, x0 = _tiny_problem()  # M = I, so the kernel tuple's M^-1 K, M^-1 C are K, C
    m = KernelParams(P).matrices()
    ops = FullOps(SparseModel.from_dense(np.eye(2), m["MiC"], m["MiK"]), m["Gamma"], m["R"],
                  m["D"])  # fmt: skip
    t = np.linspace(0.0, 0.02, 3)
    with compiling():
        _, _, X, _ = sparse.integrate(P, x0, t, 1e-3, uplift_mode=ki.UPLIFT_WARN, ops=ops)
        ops.evaluate(P, t, X)
    _WARMED.append(time.perf_counter() - t0)
    return _WARMED[0]


def simulate_full(
    system, motion, t_eval, *, x0=None, dt=None, uplift="raise", contact="detect",
    progress=None, reason="", result=None, rho_inf=None, max_steps=None, rtol=None, atol=None,
    checkpoint=None, chunk_s=CHUNK_S, **unused,
):  # fmt: skip
    """:func:`nsdyn.solve.transient.simulate` of a full-order ``system`` with
    ``genalpha-lowrank`` on its sparse operators, in chunks of ``chunk_s`` seconds as the
    dense path runs (each from the state the last one ended in, the factorisation made
    once): ``progress`` after each, and with ``checkpoint`` a file an interrupted run resumes
    from (the same run, bit for bit); ``result`` the result class to fill."""
    import time
    from pathlib import Path

    from nsdyn.models.isolated.metrics import response
    from nsdyn.solve import _kcommon as ki
    from nsdyn.solve import _kgenalpha, integrate, methods, sparse
    from nsdyn.solve.checkpoint import Carry, chunked, chunks, holding_signals, load, run_key, save
    from nsdyn.solve.resolution import result_notes
    from nsdyn.solve.transient import describe

    if unused:
        raise ValueError(f"{sparse.METHOD}, full-order model: unknown option(s) {sorted(unused)}")
    if getattr(system.isolation, "law", "none") not in ("arctan", "none"):  # (before dt: the
        why = system.dense_refusal()  # law refused once dt was given; dense methods too large)
        raise ValueError(why or f"method {sparse.METHOD!r}: friction law "
                         f"{system.isolation.law!r} is not supported (arctan or none); use "
                         "'radau', 'genalpha' or 'event' for the switch model")  # fmt: skip
    if dt is None or not dt > 0:
        raise ValueError(f"method {sparse.METHOD!r} needs a fixed step dt > 0 (e.g. dt=0.005)")
    if contact not in integrate.CONTACTS:
        raise ValueError(f"contact: expected one of {list(integrate.CONTACTS)}, got {contact!r}")
    n = system.n
    ops = full_ops(system)
    P = system.params(motion, stub=True)
    given_x0 = x0 is not None
    if x0 is None:
        x0, _ = system.static_equilibrium()
    x0 = np.ascontiguousarray(x0, dtype=float).reshape(-1)
    if x0.size != 2 * n:
        raise ValueError(f"x0: expected [q, qd] of length {2 * n}, got {x0.size}")
    t_eval = np.ascontiguousarray(t_eval, dtype=float)
    m = methods.METHODS[sparse.METHOD]
    upl = uplift if contact == "detect" else "warn"
    steps = integrate.DEFAULT_MAX_STEPS if max_steps is None else max_steps
    # (tolerances: the fixed step's Newton has its own; these are checked, not used)
    opts = methods.make_options(
        x0, m, integrate.SOLVE_RTOL, 0.0, dt, None, True, np.inf, steps, upl, rho_inf, None
    )
    rho = sparse.RHO_INF if rho_inf is None else float(rho_inf)
    coef = _kgenalpha.parameters(_kgenalpha.FAMILY_GENALPHA, rho)
    kp = KernelParams(P)
    law, eps = kp.law, kp.eps
    carry, ts, xs, k0 = Carry(), [t_eval[:1]], [x0[None, :]], 0
    ckpt = Path(checkpoint) if checkpoint else None
    if ckpt is not None:  # the stand-in P holds no matrix: the operators join the key
        options = dict(method=sparse.METHOD, dt=float(dt), uplift=uplift, contact=contact,
                       rho_inf=rho, max_steps=steps, model=ops.arrays(),
                       **chunked(chunk_s))  # fmt: skip
        run_id = run_key(P, x0 if given_x0 else None, t_eval, options)
        found = load(ckpt, run_id, t_eval) if ckpt.exists() else None
        if found is not None:
            t_done, x_done, carry = found
            ts, xs, k0 = [t_done], [x_done], t_done.size - 1
    compile_s = warmup_operators()
    wall, wall0 = 0.0, time.perf_counter()
    for te, a, b in chunks(t_eval, k0, chunk_s, carry.t_at):  # every chunk_s, off the grid too
        with holding_signals(ckpt is not None):  # (the chunk and its checkpoint first)
            # the scheme's own acceleration carried on: the chunks are one run (q̈ at each chunk's
            # start departed from it by O(dt²))
            acc = np.full(n, np.nan) if carry.acc is None else np.array(carry.acc, dtype=float)
            X = np.zeros((te.size, 2 * n))
            upl_t = np.full(system.n_contacts, np.nan)
            t0 = time.perf_counter()
            try:
                x_start = xs[-1][-1] if carry.x_at is None else carry.x_at
                stats, rinfo, X, upl_t = sparse.integrate(
                    P, x_start, te, float(dt), coef=coef, max_steps=opts.max_steps,
                    uplift_mode=opts.uplift_mode, X=X, upl_t=upl_t, ops=ops, acc=acc,
                )  # fmt: skip
            except FloatingPointError:
                stats, rinfo = np.zeros(ki.N_STATS, dtype=np.int64), np.zeros(ki.N_RINFO)
                stats[ki.S_STATUS] = ki.ST_LU_SINGULAR
                rinfo[ki.R_T], rinfo[ki.R_H] = float(te[0]), float(dt)
            chunk_wall = time.perf_counter() - t0
            sol = integrate._finish(m, opts, law, te, X, upl_t, stats, rinfo, [], None, chunk_wall,
                                    0.0, "raise", warn_uplift=contact == "detect",
                                    eps=eps)  # fmt: skip
            sol.acc_end = acc if stats[ki.S_STATUS] == ki.ST_SUCCESS else None
            k = min(b - a, sol.t.size - 1)  # the outputs reached (the last maybe the chunk's end)
            carry.take(sol, False, adaptive=False, n_out=k)
            wall += chunk_wall
            ts.append(t_eval[a : a + k])
            xs.append(sol.x[1 : 1 + k])
            if ckpt is not None:
                save(ckpt, np.concatenate(ts), np.concatenate(xs), run_id, carry)
            if progress is not None:
                progress(float(sol.t[-1]), float(t_eval[-1]), time.perf_counter() - wall0)
    t, x = np.concatenate(ts), np.concatenate(xs)
    evaluated = ops.evaluate(P, t, x)
    resp = response(system, t, x, P, evaluated=evaluated)
    res = result(
        system, t, x, resp, sparse.METHOD, carry.n_steps, wall, compile_s, carry.stats,
        sorted(set(carry.uplifts)), describe(motion), contact, method_reason=reason,
        law=getattr(system.isolation, "law", None),
    )  # fmt: skip
    res.notes = result_notes(res, P, evaluated[0], dt, motion)  # (unresolved peaks)
    return res
