"""Radau IIA (order 5) collocation: the tableau, the Newton matrices and the simplified Newton.

Collocation at c = ((4 - sqrt 6)/10, (4 + sqrt 6)/10, 1) for ``xd = f(t, x)``::

    Z_i = h sum_j a_ij f(t + c_j h, x + Z_j),   x(t + h) = x + Z_3     (i, j = 1..3)

solved by simplified Newton with the eigen-split of the Radau matrix: ``W = T^-1 Z`` decouples
into one real and one complex system with the matrices ``(eig/h) I - J`` (Hairer & Wanner,
*Solving ODEs II*, sec. IV.8). The stepper around it is :mod:`nsdyn.solve._kradau`. The Newton
loop evaluates smooth laws through :func:`nsdyn.solve._kflat.feval_flat` and other laws through
a ``general`` kernel: :func:`general_called` (the general kernel called, for the run loop,
which rarely needs it), :func:`general_t` (:func:`general_table`, which calls the system
kernel by its address, itself called by its address: the event-driven runs, which always
need it) or :func:`flat_only` (none: the default run's
loop, which then never compiles the general kernel); each of Newton's kernels is a copy of
:func:`_newton` with its own (:func:`nsdyn._kaddress.specialised`). Newton itself is called,
not inlined. Inlining costs compile time at every call site (numba types and lowers the callee
again in each caller): inlining Newton and the general kernel into every stepper cost up to
twice the first-run compilation (calling them instead took it from 110 s to 52 s for ``radau``,
from 103 s to 84 s for ``event``) for ~4 ms of a 60 ms run; calling the flat kernel instead of
inlining it at its three sites, and the general one at the cold sites
(:func:`nsdyn.solve._kcommon.feval_called`), took the default run's first compilation from 157
s to 113 s in one slow hour, with no measurable change of run time.
Linking costs too: numba optimises and translates a kernel's code again in every caller it is
linked into, so the event loop's kernels reach the ~250-block system kernel through its address
(:func:`general_table`), compiled once, and its Newton, step and start-up reach
:func:`general_table` itself through its address too (:func:`general_t`).
"""

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn._klinalg import invert_diagonal, lu_solve_inverted
from nsdyn.solve import _kcommon as ki
from nsdyn.solve import _kflat as kf

S6 = 6.0**0.5
C = np.array([(4.0 - S6) / 10.0, (4.0 + S6) / 10.0, 1.0])
E = np.array([-13.0 - 7.0 * S6, -13.0 + 7.0 * S6, -1.0]) / 3.0
# eigenvalues of the inverse of the Radau IIA coefficient matrix (one real, one complex pair);
# the Newton matrices of the eigen-split are (eig/h) I - J
EIG_REAL = 3.0 + 3.0 ** (2.0 / 3.0) - 3.0 ** (1.0 / 3.0)
EIG_COMPLEX = complex(
    3.0 + 0.5 * (3.0 ** (1.0 / 3.0) - 3.0 ** (2.0 / 3.0)),
    -0.5 * (3.0 ** (5.0 / 6.0) + 3.0 ** (7.0 / 6.0)),
)
MU_REAL = EIG_REAL  # former name, still imported by the benchmarks
T = np.array(
    [
        [0.09443876248897524, -0.14125529502095421, 0.03002919410514742],
        [0.25021312296533332, 0.20412935229379994, -0.38294211275726192],
        [1.0, 1.0, 0.0],
    ]
)
TI = np.array(
    [
        [4.17871859155190428, 0.32768282076106237, 0.52337644549944951],
        [-4.17871859155190428, -0.32768282076106237, 0.47662355450055044],
        [0.50287263494578682, -2.57192694985560522, 0.59603920482822492],
    ]
)
# dense output: y(t + x h) = y + sum_k (Z^T PD)[:, k] x^(k+1)
PD = np.array(
    [
        [13.0 / 3.0 + 7.0 * S6 / 3.0, -23.0 / 3.0 - 22.0 * S6 / 3.0, 10.0 / 3.0 + 5.0 * S6],
        [13.0 / 3.0 - 7.0 * S6 / 3.0, -23.0 / 3.0 + 22.0 * S6 / 3.0, 10.0 / 3.0 - 5.0 * S6],
        [1.0 / 3.0, -8.0 / 3.0, 10.0 / 3.0],
    ]
)

NEWTON_MAXITER = 6  # simplified-Newton iterations per attempt

# ---- stepper state ``ctl`` (float64) -------------------------------------------------------
C_H = 0  # next step size to try
C_HOLD = 1  # previous accepted step (NaN: none) for the predictive controller
C_EOLD = 2  # previous error norm (NaN: none)
C_LUH = 3  # step size the LU factors belong to (0: invalid)
C_CURJ = 4  # 1 if J was evaluated at the current step start
C_HPREV = 5  # step of the dense output in Qd usable for the Newton predictor (0: none)
C_TNEW = 6  # out: end of the accepted step
C_HSTEP = 7  # out: size of the accepted step
C_NTOL = 8  # Newton tolerance
C_FACCON = 9  # rate/(1 - rate) of the last Newton iteration (RADAU5's FACCON)
N_CTL = 10


@njit(cache=True, error_model="numpy")
def _factor(h, J, LUr, pr, LUc, pc):
    """LU of the Newton matrices ``g I - J`` (g = eig_real/h and eig_complex/h), reduced to n x n.

    The state is [q, qd], so ``J = [[0, I], [Jq, Jv]]`` and ``(g I - J) [dq; dv] = [r1; r2]``
    gives ``dq = (r1 + dv)/g`` and ``(g I - Jv - Jq/g) dv = r2 + Jq r1/g``: only the n x n
    Schur complement is factored (8x fewer flops than the 2n x 2n matrix).

    U's diagonal is stored as its reciprocal (for :func:`_solve`): the back substitution then
    multiplies, and the complex one no longer divides (a complex division is three real ones
    and two branches; 13 of them per solve, two solves per Newton iteration, against 13 per
    factorisation here).
    """
    n = LUr.shape[0]
    gr = EIG_REAL / h
    gc = EIG_COMPLEX / h
    igr = 1.0 / gr
    igc = 1.0 / gc
    for i in range(n):
        for j in range(n):
            jq = J[n + i, j]
            jv = J[n + i, n + j]
            LUr[i, j] = -jv - jq * igr
            LUc[i, j] = -jv - jq * igc
        LUr[i, i] += gr
        LUc[i, i] += gc
    if not (ki.lu_factor(LUr, pr, 0.0) and ki.lu_factor(LUc, pc, 0.0)):
        return False
    invert_diagonal(LUr)
    invert_diagonal(LUc)
    return True


@njit(cache=True, error_model="numpy", inline="always")
def _solve(LU, piv, J, g, b):
    """Solve ``(g I - J) x = b`` in place (b of length 2n) with the factors of :func:`_factor`
    (U's diagonal inverted there; the n x n solve inlined, see ``lu_solve_inverted``)."""
    n = LU.shape[0]
    ig = 1.0 / g
    for i in range(n):
        acc = 0.0 * b[0]
        for j in range(n):
            acc += J[n + i, j] * b[j]
        b[n + i] += acc * ig
    lu_solve_inverted(LU, piv, b, n)
    for i in range(n):
        b[i] = (b[i] + b[n + i]) * ig


@ka.compiled_only
def _error_norm(err, Z, h, LUr, pr, J, luh, y, ynew, atol, rtol):
    """Scaled norm of the embedded error estimate ``(eig_real/h I - J)^-1 (err + E Z / h)``
    (err holds f(t, y) or the filtered estimate of a first try); the estimate is left in err."""
    ih = 1.0 / h
    for j in range(err.shape[0]):
        err[j] += (E[0] * Z[0, j] + E[1] * Z[1, j] + E[2] * Z[2, j]) * ih
    _solve(LUr, pr, J, EIG_REAL / luh, err)
    return ki.scaled_rms(err, y, ynew, atol, rtol)


@njit(cache=True, error_model="numpy")
def _predict_factor(h_abs, h_abs_old, en, en_old):
    if en == 0.0:
        return 1e10
    mult = 1.0
    if np.isfinite(en_old) and np.isfinite(h_abs_old):
        mult = h_abs / h_abs_old * (en_old / en) ** 0.25
    return min(1.0, mult) * en**-0.25


# what the stepper asks of the general right-hand side, through one ``general`` kernel; floats
# on purpose: numba types an integer constant argument as a literal and compiles the callee
# once per value (three copies of the general kernel's wrapper)
G_STAGES = 0.0  # the three collocation stages y + Z_i into the rows of F (ys scratch)
G_ONE = 1.0  # one evaluation at (t, y) into out
G_JAC = 2.0  # the Jacobian at (t, y) into J


@njit(cache=True, error_model="numpy", inline="always")
def _stages_called(P, t, y, h, Z, F, ys, qdd, lam, tau, modes):
    ok_all = True
    for i in range(3):
        for j in range(y.shape[0]):
            ys[j] = y[j] + Z[i, j]
        ok = ki.feval_called(t + C[i] * h, ys, P, F[i], qdd, lam, tau, modes)
        ok_all = ok_all and ok
    return ok_all


@njit(cache=True, error_model="numpy")
def general_called(kind, P, t, y, h, Z, F, ys, out, J, qdd, lam, tau, modes):
    """The general kernel for the stepper (``kind``: G_STAGES, G_ONE or G_JAC), called: for
    the run loop, which needs it only where the flat kernel does not apply. False for a
    singular constraint system (G_STAGES, G_ONE) or a non-finite state (G_JAC)."""
    if kind == G_JAC:
        return ki.jeval(t, y, P, J)
    if kind == G_ONE:
        return ki.feval_called(t, y, P, out, qdd, lam, tau, modes)
    return _stages_called(P, t, y, h, Z, F, ys, qdd, lam, tau, modes)


@ka.compiled_uncounted
def general_table(kind, P, t, y, h, Z, F, ys, out, J, qdd, lam, tau, modes):
    """:func:`general_called` with the system kernel and its Jacobian called by their
    addresses in the table of :mod:`nsdyn._kaddress` (:func:`nsdyn.solve._kcommon.feval_t`),
    for the event-driven loop: its step, start-up, detectors and handlers then share the one
    compiled system kernel instead of each optimising and translating a copy linked into it."""
    if kind == G_JAC:
        return ki.jeval_t(t, y, P, J)
    if kind == G_ONE:
        return ki.feval_t(t, y, P, out, qdd, lam, tau, modes)
    ok_all = True
    for i in range(3):
        for j in range(y.shape[0]):
            ys[j] = y[j] + Z[i, j]
        ok = ki.feval_t(t + C[i] * h, ys, P, F[i], qdd, lam, tau, modes)
        ok_all = ok_all and ok
    return ok_all


@njit(cache=True, error_model="numpy", inline="always")
def general_t(kind, P, t, y, h, Z, F, ys, out, J, qdd, lam, tau, modes):
    """:func:`general_table` by its address in the table of :mod:`nsdyn._kaddress` (row
    ``"event.general"``): the general kernel of the event loop's Newton, step and start-up,
    compiled once instead of linked into each of the three (where LLVM optimised and
    translated its code again)."""
    return ka.tcall("event.general", (kind, P, t, y, h, Z, F, ys, out, J, qdd, lam, tau, modes))


ka.tslot("event.general", general_table, "nsdyn.solve.compile_split:event_callees")


@njit(cache=True, error_model="numpy")
def flat_only(kind, P, t, y, h, Z, F, ys, out, J, qdd, lam, tau, modes):
    """No general kernel: every request fails, so a step that leaves the flat kernel's
    domain (a singular ``G``) stops the run with ST_SINGULAR and the caller runs it again
    with :func:`general_called`. A run loop given this kernel never compiles the general
    right-hand side or its Jacobian (~40 % of the default run's first compilation)."""
    return False


@njit(cache=True, error_model="numpy", inline="always")
def jeval(t, y, P, Fl, flat, general, K, J, ys, qdd, lam, tau, modes):
    """The Jacobian at (t, y) into J: the flat one when ``flat`` (``radau.jac``, directly or by
    its address in ``K``, see :mod:`nsdyn._kaddress`), else (or where it fails) the
    ``general`` kernel's (ys scratch). False when neither could form it."""
    ok = (
        flat
        and ka.call(K, "radau.feval", (t, y, Fl, ys, qdd, lam, tau, modes), general)
        and ka.call(K, "radau.jac", (y, Fl, J, lam), general)
    )
    if not ok:
        ok = general(G_JAC, P, t, y, 0.0, J, J, y, y, J, qdd, lam, tau, modes)
    return ok


# what each copy of :func:`_newton` calls (:func:`nsdyn._kaddress.specialised` binds them):
# the general kernel and the flat right-hand side
_GENERAL = general_called
_FEVAL_FLAT = kf.feval_flat


def _newton(
    P, t, y, h, ctl, stats, J, LUr, pr, LUc, pc, Z, W, F, dW, fr, fc, ys, iscale, qdd, lam, tau,
    modes, Fl, flat,
):  # fmt: skip
    """Simplified Newton on the collocation system; Z holds the start guess on entry.

    Convergence test as RADAU5: the error after an update is estimated as
    ``faccon * |dW|`` with ``faccon = rate/(1 - rate)``, carried over from the previous
    step for the first iteration (so a good predictor converges in one iteration); an
    iteration whose rate predicts no convergence within NEWTON_MAXITER stops (scipy).

    ``iscale`` holds the reciprocal error scales ``1 / (atol + |y| rtol)`` (the norm of dW
    multiplies: 78 divisions per iteration fewer).
    The arrays are those of the workspace (:func:`nsdyn.solve._kradau.workspace`), ``Fl`` the
    flat parameters of :func:`nsdyn.solve._kflat.pack_flat`, used when ``flat``; the general
    kernel ``_GENERAL`` (:func:`general_called`, :func:`general_table` or :func:`flat_only`)
    evaluates the stages otherwise. ``_FEVAL_FLAT``: :func:`nsdyn.solve._kflat.feval_flat`
    itself (linked), :func:`feval_flat_t` (by its address) or :func:`_no_flat`. Each kernel
    of Newton is a copy of this function with its own two (:func:`nsdyn._kaddress.specialised`).

    Returns (converged, n_iter, rate, nonfinite, singular, dW_norm).
    """
    n2 = y.shape[0]
    mr = EIG_REAL / h
    mc = EIG_COMPLEX / h
    for k in range(3):
        for j in range(n2):
            W[k, j] = TI[k, 0] * Z[0, j] + TI[k, 1] * Z[1, j] + TI[k, 2] * Z[2, j]
    tol = ctl[C_NTOL]
    faccon = max(ctl[C_FACCON], 2.220446049250313e-16) ** 0.8
    dw_old = -1.0
    rate = -1.0
    dw = 0.0
    converged = False
    nonfinite = False
    singular = False
    k = 0
    for k in range(NEWTON_MAXITER):
        ok = flat
        if flat:
            for i in range(3):
                for j in range(n2):
                    ys[j] = y[j] + Z[i, j]
                ok = ok and _FEVAL_FLAT(t + C[i] * h, ys, Fl, F[i], qdd, lam, tau, modes)
        if not ok:
            singular = not _GENERAL(G_STAGES, P, t, y, h, Z, F, ys, ys, J, qdd, lam, tau, modes)
        stats[ki.S_NFEV] += 3
        if not kf.finite_rows(F):
            nonfinite = True
            break
        if singular:
            break
        for j in range(n2):
            fr[j] = TI[0, 0] * F[0, j] + TI[0, 1] * F[1, j] + TI[0, 2] * F[2, j] - mr * W[0, j]
            re = TI[1, 0] * F[0, j] + TI[1, 1] * F[1, j] + TI[1, 2] * F[2, j]
            im = TI[2, 0] * F[0, j] + TI[2, 1] * F[1, j] + TI[2, 2] * F[2, j]
            fc[j] = complex(re, im) - mc * complex(W[1, j], W[2, j])
        _solve(LUr, pr, J, EIG_REAL / ctl[C_LUH], fr)
        _solve(LUc, pc, J, EIG_COMPLEX / ctl[C_LUH], fc)
        s = 0.0
        for j in range(n2):
            dW[0, j] = fr[j]
            dW[1, j] = fc[j].real
            dW[2, j] = fc[j].imag
            s += (fr[j] * iscale[j]) ** 2 + (fc[j].real * iscale[j]) ** 2
            s += (fc[j].imag * iscale[j]) ** 2
        dw = np.sqrt(s / (3 * n2))
        if not np.isfinite(dw):
            nonfinite = True
            break
        if dw_old >= 0.0:
            rate = dw / dw_old
        if rate >= 0.0:
            if rate >= 1.0 or rate ** (NEWTON_MAXITER - k) / (1.0 - rate) * dw > tol:
                break
            faccon = rate / (1.0 - rate)
        for i in range(3):
            for j in range(n2):
                W[i, j] += dW[i, j]
        for i in range(3):
            for j in range(n2):
                Z[i, j] = T[i, 0] * W[0, j] + T[i, 1] * W[1, j] + T[i, 2] * W[2, j]
        if faccon * dw < tol:
            converged = True
            break
        dw_old = dw
    ctl[C_FACCON] = faccon
    return converged, k + 1, rate, nonfinite, singular, dw


# the Radau loop's callees by address (:mod:`nsdyn._kaddress`): their indices in ``K``
K_FEVAL, K_JAC, K_FACTOR, K_NEWTON, K_START = range(5)


@njit(cache=True, error_model="numpy", inline="always")
def feval_flat_t(t, x, F, out, qdd, lam, tau, modes):
    """:func:`nsdyn.solve._kflat.feval_flat` by its address in the table of
    :mod:`nsdyn._kaddress` (row ``"radau.feval"``, filled by
    :func:`nsdyn.solve.compile_split.radau_calls`): the default loop's Newton then holds no copy
    of the flat right-hand side, which the loop calls by address too (linked, its code went
    through LLVM again in Newton's: ~1 s of one core in a first run)."""
    return ka.tcall("radau.feval", (t, x, F, out, qdd, lam, tau, modes))


ka.tslot("radau.feval", kf.feval_flat, "nsdyn.solve.compile_split:radau_callees")


@njit(cache=True, error_model="numpy", inline="always")
def _no_flat(t, x, F, out, qdd, lam, tau, modes):
    """No flat right-hand side (Newton for a law the flat kernels do not serve)."""
    return False


# Newton's kernels: copies of _newton, each with its general kernel and flat right-hand side
newton = njit(cache=True, error_model="numpy")(
    ka.specialised(_newton, "newton", _GENERAL=general_called, _FEVAL_FLAT=kf.feval_flat)
)
"""Newton with :func:`general_called` and the flat right-hand side linked (the general
kernel's loop, :func:`nsdyn.solve._kradau.radau_general`)."""

newton_general = ka.compiled_uncounted(
    ka.specialised(_newton, "newton_general", _GENERAL=general_t, _FEVAL_FLAT=_no_flat)
)
"""Newton for a law the flat kernels do not serve (``flat`` False at every call): the event
loop's step calls it by address; no flat right-hand side is compiled with it."""

newton_flat = ka.compiled_uncounted(
    ka.specialised(_newton, "newton_flat", _GENERAL=flat_only, _FEVAL_FLAT=feval_flat_t)
)
"""Newton with :func:`flat_only` and :func:`feval_flat_t` (the default loop's, called by
address: a kernel with a kernel argument would have the argument's dispatcher in its
declared type)."""

newton_table = ka.compiled_uncounted(
    ka.specialised(_newton, "newton_table", _GENERAL=general_t, _FEVAL_FLAT=kf.feval_flat)
)
"""Newton with :func:`general_t` (:func:`general_table` by its address) and the flat
right-hand side linked (the event loop's step calls it by address, for a law the flat
kernels serve)."""

# Newton called directly (``K`` None, :func:`nsdyn._kaddress.call`): the copy for the caller's
# general kernel
NEWTON_FOR = {general_called: newton, general_t: newton_table, flat_only: newton_flat}
