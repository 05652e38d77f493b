"""Numba kernel: the isolated frame's right-hand side for smooth friction, read from one flat array.

The same equations as :func:`nsdyn.models.isolated._kernel.evaluate` (seed 004, eqs 8-15) for
the laws without stick (arctan, none) and every contact closed, first-order ``x = [q, qd]``::

    qdd = a0 + sum_k MiR_k lam_k - sum_i MiD_i mu_i s_i lamf_i
    a0  = -M^-1 K* q - M^-1 C* qd - Gamma [u_hor, u_ver + g]
    G lam = -(R a0 + 2 alpha beta R qd + alpha^2 R q),  G = R M^-1 R^T - R M^-1 D^T diag(mu s)

(``lamf_i = lam_i``; with a frozen normal force ``lamf_i = lam0_i`` moves into ``a0`` and
``G = R M^-1 R^T``). ``R M^-1 R^T`` and ``R M^-1 D^T`` are formed once per run. The general
kernel carves views out of a scratch buffer and reads a 17-array tuple on every call; here the
matrices, scalars and scratch sit in one float64 array ``F`` at fixed offsets (:func:`pack_flat`),
which is what makes the call cheap (the Radau stages evaluate it ~7 times per step).

Where this form does not hold (a singular ``G``) :func:`feval_flat` says so and the caller
falls back to the general kernel (which takes the minimum-norm split).
"""

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka
from nsdyn._klinalg import lu_factor, lu_factor_flat, lu_solve_columns, lu_solve_flat
from nsdyn.models.isolated import _kernel as ks
from nsdyn.solve import _kcommon as ki

# header of F (floats; counts stored as floats)
H_N, H_NC, H_NI, H_OK, H_FROZEN, H_ARCTAN, H_EPS, H_ALPHA, H_BETA, H_G = range(10)
H_HARMONIC, H_NPTS = 10, 11  # 1.0 for a harmonic excitation; samples of a record
H_GPAR = 12  # the excitation parameters (ks.N_GPAR of them)
H_A0IN = H_GPAR + ks.N_GPAR  # 1.0: feval_flat finds a0's linear part already in F's scratch
N_HEAD = H_A0IN + 1


@njit(cache=True, error_model="numpy", inline="always")
def _offsets(n, nc, ni):
    """Offsets of the blocks of F: MiK^T, MiC^T (n, n: transposed), Gam (2, n), MiR (nc, n),
    R (nc, n), MiD (ni, n), D (ni, n), mu, lam0, RMiR (nc, nc), RMiD (nc, ni), the bands of
    R's and D's rows (nc + ni pairs [lo, hi): the row is zero outside); scratch a0 (n),
    G (nc, nc), s (ni) followed by G's row pivots (nc, at ``o_s + ni``); the end of these
    (the record's horizontal, then vertical samples follow); last, the offset of the bands."""
    o_mik = N_HEAD
    o_mic = o_mik + n * n
    o_gam = o_mic + n * n
    o_mir = o_gam + 2 * n
    o_r = o_mir + nc * n
    o_mid = o_r + nc * n
    o_d = o_mid + ni * n
    o_mu = o_d + ni * n
    o_lam0 = o_mu + ni
    o_rmir = o_lam0 + ni
    o_rmid = o_rmir + nc * nc
    o_band = o_rmid + nc * ni
    o_a0 = o_band + 2 * (nc + ni)
    o_g = o_a0 + n
    o_s = o_g + nc * nc
    end = o_s + ni + nc
    return (o_mik, o_mic, o_gam, o_mir, o_r, o_mid, o_d, o_mu, o_lam0, o_rmir, o_rmid, o_a0, o_g,
            o_s, end, o_band)  # fmt: skip


def pack_flat(P):
    """The flat array F of ``P`` (header, matrices, products, scratch). ``F[H_OK]`` is 1.0 when
    :func:`feval_flat` applies to the law of ``P`` (arctan or none), else 0.0.

    numpy, called from Python once per run (a kernel compiled for it took ~1.5 s of every
    first run). The products ``R M^-1 R^T``, ``R M^-1 D^T`` are summed over the columns in
    order, one product and one sum at a time, as the loop ``acc += R[k, c] * MiRt[c, j]`` of
    a kernel does (the same floats; a BLAS product may sum in another order)."""
    MiK, MiC, Gam = P[ks.I_MIK], P[ks.I_MIC], P[ks.I_GAM]
    R, MiRt, D, MiDt = P[ks.I_R], P[ks.I_MIRT], P[ks.I_D], P[ks.I_MIDT]
    fp, ip = P[ks.I_FPAR], P[ks.I_IPAR]
    n, nc, ni = MiK.shape[0], R.shape[0], D.shape[0]
    o = getattr(_offsets, "py_func", _offsets)(n, nc, ni)
    npts = P[ks.I_AH].shape[0]
    F = np.zeros(o[14] + 2 * npts)
    F[H_HARMONIC] = 1.0 if ip[ks.K_GROUND] == ks.GROUND_HARMONIC else 0.0
    F[H_NPTS] = npts
    F[H_GPAR : H_GPAR + ks.N_GPAR] = P[ks.I_GPAR][: ks.N_GPAR]
    F[o[14] : o[14] + npts] = P[ks.I_AH]
    F[o[14] + npts : o[14] + 2 * npts] = P[ks.I_AV]
    law = ip[ks.K_LAW]
    frozen = ip[ks.K_FROZEN] == 1
    F[H_N], F[H_NC], F[H_NI] = n, nc, ni
    ok = law == ks.LAW_ARCTAN or law == ks.LAW_NONE
    F[H_OK] = 1.0 if ok and (frozen or law == ks.LAW_NONE or ni <= nc) else 0.0
    F[H_FROZEN] = 1.0 if frozen else 0.0
    F[H_ARCTAN] = 1.0 if law == ks.LAW_ARCTAN else 0.0
    F[H_EPS], F[H_ALPHA] = fp[ks.F_EPS], fp[ks.F_ALPHA]
    F[H_BETA], F[H_G] = fp[ks.F_BETA], fp[ks.F_G]

    def put(k, block):
        F[o[k] : o[k] + block.size] = block.ravel()

    put(0, MiK.T)  # transposed: columns contiguous (feval_flat)
    put(1, MiC.T)
    put(2, Gam[:, :2].T)
    put(3, MiRt.T)
    put(4, R)
    put(5, MiDt.T)
    put(6, D)
    put(7, P[ks.I_MU][:ni])
    put(8, P[ks.I_LAM0][:ni])
    RMiR, RMiD = np.zeros((nc, nc)), np.zeros((nc, ni))
    for c in range(n):
        RMiR += np.multiply.outer(R[:, c], MiRt[c, :])
        RMiD += np.multiply.outer(R[:, c], MiDt[c, :])
    put(9, RMiR)
    put(10, RMiD)
    # the bands of R's and D's rows: a contact or isolator row of a frame touches a few dofs
    # (one, in Craig-Bampton coordinates), and the products with it skip the zeros outside
    # (the same sums: only exact zeros are left out)
    for k, row in enumerate([*R, *D]):
        nz = np.flatnonzero(row != 0.0)
        F[o[15] + 2 * k : o[15] + 2 * k + 2] = (nz[0], nz[-1] + 1) if nz.size else (0, 0)
    return F


@njit(cache=True, error_model="numpy", inline="always")
def _row_band(F, o_band, k):
    """The band [lo, hi) of row k of R (k < nc) or of D (row k - nc), from F's band block."""
    return int(F[o_band + 2 * k]), int(F[o_band + 2 * k + 1])


@njit(cache=True, error_model="numpy", inline="always")
def _ground(t, F, o):
    """Excitation channels at ``t`` as :func:`nsdyn.models.isolated._kernel.ground_accel`,
    from the parameters and samples in F (record samples from offset ``o``)."""
    g = H_GPAR
    if F[H_HARMONIC] != 0.0:
        return (
            F[g + ks.G_AH] * np.sin(2.0 * np.pi * F[g + ks.G_FH] * t + F[g + ks.G_PH]),
            F[g + ks.G_AV] * np.sin(2.0 * np.pi * F[g + ks.G_FV] * t + F[g + ks.G_PV]),
        )
    npts = int(F[H_NPTS])
    u = (t - F[g + ks.G_T0]) / F[g + ks.G_DT]
    if u < 0.0 or npts == 0:
        return 0.0, 0.0
    k = int(np.floor(u))
    if k >= npts - 1:
        if k == npts - 1 and u == k:
            return F[o + k], F[o + npts + k]
        return 0.0, 0.0
    w = u - k
    a = o + k
    return (1.0 - w) * F[a] + w * F[a + 1], (1.0 - w) * F[a + npts] + w * F[a + npts + 1]


@njit(cache=True, error_model="numpy", inline="always")
def usable(op, F):
    """True when :func:`feval_flat` applies now: a smooth law and every contact closed
    (``op``: the contact states ``P[I_OPEN]``)."""
    if F[H_OK] == 0.0:
        return False
    for k in range(op.shape[0]):
        if op[k] != 0:
            return False
    return True


@njit(cache=True, error_model="numpy", inline="always")
def _ground_into_a0(t, F, n, o):
    """a0 -= Gamma [u_hor, u_ver + g] at ``t`` (``o``: :func:`_offsets` for n dofs)."""
    o_gam, o_a0 = o[2], o[11]
    uh, uv = _ground(t, F, o[14])
    uv += F[H_G]
    for r in range(n):
        F[o_a0 + r] -= F[o_gam + r] * uh + F[o_gam + n + r] * uv


@njit(cache=True, error_model="numpy")
def evaluate_flat_many(t, X, F, A0, QDD, LAM, TAU, MODES, ok, K):
    """:func:`feval_flat` along a history (outputs as
    :func:`nsdyn.models.isolated._kernel.evaluate_many`), given its linear part
    ``A0 = -X_q MiK^T - X_v MiC^T`` (nt, n), which the caller forms with one matrix product
    (for the 435-dof frame the per-sample products were most of the post-processing): each
    row goes into F's ``a0`` and ``F[H_A0IN]`` tells :func:`feval_flat` so. ``ok[k]`` is
    False where ``G`` was singular (row k then holds scratch values: the caller fills it from
    the general kernel). A sample with a non-finite time or state gets NaN accelerations and
    forces and mode 0, with ``ok[k]`` True (nothing to ask the general kernel).

    :func:`feval_flat` is called through :func:`nsdyn._kaddress.call` as ``"flat.feval"``:
    directly (``K`` None) or by its address (``K`` from
    :func:`nsdyn.solve.compile_split.flat_calls`), so this kernel's code holds no copy of it
    (~1.2 s of a first run's compilation)."""
    n = int(F[H_N])
    o_a0 = _offsets(n, int(F[H_NC]), int(F[H_NI]))[11]
    out = np.empty(2 * n)
    F[H_A0IN] = 1.0
    for k in range(t.shape[0]):
        if not (np.isfinite(t[k]) and ki.all_finite(X[k])):
            ok[k] = True
            for arr in (QDD[k], LAM[k], TAU[k]):
                for r in range(arr.shape[0]):
                    arr[r] = np.nan
            for r in range(MODES.shape[1]):
                MODES[k, r] = 0
            continue
        for r in range(n):
            F[o_a0 + r] = A0[k, r]
        # straight into row k (no copies through scratch rows)
        args = (t[k], X[k], F, out, QDD[k], LAM[k], TAU[k], MODES[k])
        ok[k] = ka.call(K, "flat.feval", args, None)
    F[H_A0IN] = 0.0


@njit(cache=True, error_model="numpy", inline="always")
def _constrained(x, F, qdd, lam, tau, modes, n, nc, ni):
    """The rest of :func:`feval_flat` once ``a0`` (with the ground term) is in F: friction
    directions, the normal forces from ``G lam = -(R a0 + b)``, the accelerations (n dofs,
    nc contacts, ni isolators: the counts of F's header, which the caller has already read)."""
    (o_mik, o_mic, o_gam, o_mir, o_r, o_mid, o_d, o_mu, o_lam0, o_rmir, o_rmid, o_a0, o_g, o_s,
     o_rec, o_band) = _offsets(n, nc, ni)  # fmt: skip
    frozen = F[H_FROZEN] != 0.0
    arctan = F[H_ARCTAN] != 0.0
    eps = F[H_EPS]
    # friction directions s_i = (2/pi) arctan(eps D_i qd)
    for i in range(ni):
        si = 0.0
        if arctan:
            vi = 0.0
            lo, hi = _row_band(F, o_band, nc + i)
            for c in range(lo, hi):
                vi += F[o_d + i * n + c] * x[n + c]
            si = (2.0 / np.pi) * np.arctan(eps * vi)
        F[o_s + i] = si
        if frozen and si != 0.0 and F[o_mu + i] != 0.0:
            f = F[o_mu + i] * si * F[o_lam0 + i]
            for c in range(n):
                F[o_a0 + c] -= F[o_mid + i * n + c] * f
    # G lam = -(R a0 + b)
    ab2 = 2.0 * F[H_ALPHA] * F[H_BETA]
    aa = F[H_ALPHA] * F[H_ALPHA]
    for k in range(nc):
        ra = 0.0
        rq = 0.0
        rv = 0.0
        lo, hi = _row_band(F, o_band, k)
        for c in range(lo, hi):
            rk = F[o_r + k * n + c]
            ra += rk * F[o_a0 + c]
            rq += rk * x[c]
            rv += rk * x[n + c]
        lam[k] = -(ra + ab2 * rv + aa * rq)
        for j in range(nc):
            g = F[o_rmir + k * nc + j]
            if not frozen and j < ni:
                g -= F[o_rmid + k * ni + j] * F[o_mu + j] * F[o_s + j]
            F[o_g + k * nc + j] = g
    # G lam = -(R a0 + b) by LU with partial pivoting on G's block of F (pivots after s)
    if not lu_factor_flat(F, o_g, nc, o_s + ni, 1e-14):
        return False
    lu_solve_flat(F, o_g, o_s + ni, nc, lam, 0, 1, 1)
    # qdd = a0 + MiR lam - MiD diag(mu s) lamf;  tau_i = mu_i s_i lamf_i
    for r in range(n):
        qdd[r] = F[o_a0 + r]
    for k in range(nc):
        lk = lam[k]
        for r in range(n):
            qdd[r] += F[o_mir + k * n + r] * lk
    for i in range(ni):
        si = F[o_s + i]
        lf = F[o_lam0 + i] if frozen else (lam[i] if i < nc else 0.0)
        ti = F[o_mu + i] * si * lf if arctan else 0.0
        tau[i] = ti
        modes[i] = 1 if si >= 0 else -1
        if not frozen and ti != 0.0:
            for r in range(n):
                qdd[r] -= F[o_mid + i * n + r] * ti
    return True


@njit(cache=True, error_model="numpy")
def feval_flat(t, x, F, out, qdd, lam, tau, modes):
    """out = [qd, qdd] at (t, x): :func:`nsdyn.models.isolated._kernel.evaluate` for smooth
    laws and closed contacts from the flat array ``F`` (also lam, tau, modes, as there).

    With ``F[H_A0IN]`` set, the linear part of ``a0`` is taken as already in F's scratch
    (:func:`evaluate_flat_many` puts it there; the ground term is still added here).

    Returns False for a non-finite input (out NaN) or a singular ``G`` (outputs not set): the
    caller then asks the general kernel (:func:`nsdyn.solve._kcommon.feval`), which reports
    the first and takes the minimum-norm split for the second. ``P`` is not an argument on
    purpose: numba updates the reference count of each of its 17 arrays on every call,
    inlined or not.

    Compiled once and called; its pieces are inlined into it one level deep. numba types and
    lowers an ``inline="always"`` function again at every call site and, to inline it, copies
    its IR once per block together with the function's whole variable scope (blocks x
    variables): the three inlined copies of this function (Newton's stages, the step end, the
    error re-estimate) cost ~20 s of the default run's first compilation in a slow hour, and a
    middle layer (an inlined ``evaluate_flat`` holding the inlined :func:`_constrained`) made
    this function's own compilation 9-18 s instead of 4-6 s, both for no measurable run time.
    """
    n = qdd.shape[0]
    if not (np.isfinite(t) and ki.all_finite(x)):
        out[:] = np.nan
        return False
    nc = int(F[H_NC])
    ni = int(F[H_NI])
    o = _offsets(n, nc, ni)
    o_mik, o_mic, o_a0 = o[0], o[1], o[11]
    # a0 = -MiK q - MiC qd (- Gamma u, in _ground_into_a0) column by column: F holds MiK and
    # MiC transposed, so each column is contiguous and the row loop vectorises; each row's
    # sum is still formed in the order c = 0..n-1, the result is that of row-wise dot products
    if F[H_A0IN] == 0.0:  # else the caller put it there (evaluate_flat_many)
        a0 = F[o_a0 : o_a0 + n]
        for r in range(n):
            a0[r] = 0.0
        for c in range(n):
            xc = x[c]
            vc = x[n + c]
            kc = F[o_mik + c * n : o_mik + c * n + n]
            cc = F[o_mic + c * n : o_mic + c * n + n]
            for r in range(n):
                a0[r] -= kc[r] * xc + cc[r] * vc
    _ground_into_a0(t, F, n, o)
    if not _constrained(x, F, qdd, lam, tau, modes, n, nc, ni):
        return False
    for i in range(n):
        out[i] = x[n + i]
        out[n + i] = qdd[i]
    return True


@njit(cache=True, error_model="numpy")
def jac_flat(t, x, F, J, out, qdd, lam, tau, modes):
    """Analytic Jacobian of :func:`feval_flat` at (t, x) into J (2n x 2n); also lam, tau, modes.

    With ``a0`` the unconstrained accelerations (friction of a frozen normal force in it),
    ``B = M^-1 R^T - M^-1 D^T diag(mu s)`` (live normal forces; ``M^-1 R^T`` when frozen),
    ``G = R B``, ``lam = -G^-1 c``, ``c = R a0 + 2 alpha beta R qd + alpha^2 R q`` and
    ``qdd = a0 + B lam``, differentiating (``dB lam`` is ``W dqd``, ``dG lam = R W dqd``)::

        qdd_q  = A_q - B G^-1 R (A_q + alpha^2 I),              A_q = -M^-1 K*
        qdd_qd = A_v - B G^-1 R (A_v + 2 alpha beta I),         A_v = -M^-1 C* + W
        W = -sum_i M^-1 D_i^T mu_i lamf_i s'_i D_i,   s'_i = (2/pi) eps / (1 + (eps D_i qd)^2)

    the general kernel's ``(I - B G^-1 C) Jx - B G^-1 b_x`` in this form
    (:func:`nsdyn.models.isolated._kernel.jac`). ``out`` receives f(t, x) (scratch: the
    evaluation is :func:`feval_flat`, called, not a second inlined copy of the flat kernel).
    Returns False for a non-finite input (J NaN) or a singular ``G`` (J not set): the caller
    then asks the general kernel.
    """
    if not (np.isfinite(t) and ki.all_finite(x)):
        J[:, :] = np.nan
        return False
    return feval_flat(t, x, F, out, qdd, lam, tau, modes) and jac_flat_here(x, F, J, lam)


@njit(cache=True, error_model="numpy")
def jac_flat_here(x, F, J, lam):
    """:func:`jac_flat` at the state ``x`` where :func:`feval_flat` has just succeeded (it
    reads that evaluation's friction directions from F's scratch and its normal forces
    ``lam``). The default loop calls the two by address one after the other: this kernel's
    code then holds no copy of the flat right-hand side's (~1 s of its first compilation)."""
    n = x.shape[0] // 2
    nc = int(F[H_NC])
    ni = int(F[H_NI])
    (o_mik, o_mic, o_gam, o_mir, o_r, o_mid, o_d, o_mu, o_lam0, o_rmir, o_rmid, o_a0, o_g, o_s,
     o_rec, o_band) = _offsets(n, nc, ni)  # fmt: skip
    frozen = F[H_FROZEN] != 0.0
    eps = F[H_EPS]
    n2 = 2 * n
    for r in range(n):
        for c in range(n2):
            J[r, c] = 0.0
        J[r, n + r] = 1.0
        for c in range(n):
            J[n + r, c] = -F[o_mik + c * n + r]
            J[n + r, n + c] = -F[o_mic + c * n + r]
    if F[H_ARCTAN] != 0.0:
        for i in range(ni):
            lf = F[o_lam0 + i] if frozen else (lam[i] if i < nc else 0.0)
            cf = F[o_mu + i] * lf
            if cf == 0.0:
                continue
            vi = 0.0
            lo, hi = _row_band(F, o_band, nc + i)
            for c in range(lo, hi):
                vi += F[o_d + i * n + c] * x[n + c]
            z = eps * vi
            cf *= (2.0 / np.pi) * eps / (1.0 + z * z)
            for r in range(n):
                mr = F[o_mid + i * n + r] * cf
                for c in range(lo, hi):
                    J[n + r, n + c] -= mr * F[o_d + i * n + c]
    if nc == 0:
        return True
    # G, then Y = G^-1 R (A + shift) (nc x 2n) by the shared LU (pivot floor as feval_flat's)
    G = np.empty((nc, nc))
    Y = np.empty((nc, n2))
    piv = np.empty(nc, dtype=np.int64)
    Bm = np.empty((n, nc))
    ab2 = 2.0 * F[H_ALPHA] * F[H_BETA]
    aa = F[H_ALPHA] * F[H_ALPHA]
    for k in range(nc):
        for j in range(nc):
            g = F[o_rmir + k * nc + j]
            if not frozen and j < ni:
                g -= F[o_rmid + k * ni + j] * F[o_mu + j] * F[o_s + j]
            G[k, j] = g
        fk = 0.0
        if not frozen and k < ni:
            fk = F[o_mu + k] * F[o_s + k]
        for r in range(n):
            Bm[r, k] = F[o_mir + k * n + r] - fk * F[o_mid + k * n + r]
        rlo, rhi = _row_band(F, o_band, k)
        for c in range(n2):
            acc = 0.0
            for r in range(rlo, rhi):
                acc += F[o_r + k * n + r] * J[n + r, c]
            if c < n:
                acc += aa * F[o_r + k * n + c]
            else:
                acc += ab2 * F[o_r + k * n + c - n]
            Y[k, c] = acc
    if not lu_factor(G, piv, 1e-14):
        return False
    lu_solve_columns(G, piv, Y)
    for r in range(n):
        for c in range(n2):
            acc = 0.0
            for k in range(nc):
                acc += Bm[r, k] * Y[k, c]
            J[n + r, c] -= acc
    return True


@njit(cache=True, error_model="numpy", inline="always")
def finite_rows(A):
    """True when every entry of the 2-D ``A`` is finite."""
    for i in range(A.shape[0]):
        for j in range(A.shape[1]):
            if not np.isfinite(A[i, j]):
                return False
    return True


# the metrics' call of the flat right-hand side (:mod:`nsdyn._kaddress`): index 0 of their K
ka.slot("flat.feval", 0, feval_flat)
