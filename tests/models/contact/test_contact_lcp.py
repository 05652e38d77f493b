"""Lemke's method against brute-force enumeration of complementary bases (exact by definition:
an LCP solution is a complementary basis with a non-negative basic solution)."""

import itertools

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from nsdyn.models.contact._kgeom import solve_contacts
from nsdyn.models.contact._klcp import lemke

TOL = 1e-8


def brute_force(M, q):
    """All solutions of LCP(M, q) found by enumerating the 2^n complementary bases."""
    n = len(q)
    sols = []
    for basic in itertools.product((0, 1), repeat=n):
        S = [i for i in range(n) if basic[i]]
        z = np.zeros(n)
        if S:
            try:
                z[S] = np.linalg.solve(M[np.ix_(S, S)], -q[S])
            except np.linalg.LinAlgError:
                continue
        w = M @ z + q
        if z.min() >= -TOL and w.min() >= -TOL:
            if not any(np.allclose(z, y, atol=1e-7) for y in sols):  # degenerate bases
                sols.append(z)
    return sols


@st.composite
def p_matrix_lcp(draw):
    n = draw(st.integers(1, 5))
    vals = st.floats(-2, 2, allow_nan=False, allow_infinity=False)
    A = np.array(draw(st.lists(vals, min_size=n * n, max_size=n * n))).reshape(n, n)
    S = np.array(draw(st.lists(vals, min_size=n * n, max_size=n * n))).reshape(n, n)
    q = np.array(draw(st.lists(vals, min_size=n, max_size=n)))
    M = A @ A.T + 0.1 * np.eye(n) + (S - S.T)  # positive definite => P-matrix
    return M, q


@settings(max_examples=150, deadline=None)
@given(p_matrix_lcp())
def test_lemke_matches_unique_solution_of_p_matrix_lcp(data):
    M, q = data
    sols = brute_force(M, q)
    assert len(sols) == 1  # P-matrix: exactly one solution
    z, w, status = lemke(M, q)
    assert status == 0
    assert np.allclose(z, sols[0], atol=1e-7 * (1 + np.abs(sols[0]).max()))
    assert w.min() >= -1e-9 and abs(z @ w) < 1e-8 * (1 + np.abs(q).max() ** 2)


@st.composite
def contact_problem(draw):
    nc = draw(st.integers(1, 2))
    ang = draw(st.lists(st.floats(-1.2, 1.2), min_size=nc, max_size=nc))
    b = draw(st.lists(st.floats(-3, 3), min_size=2 * nc, max_size=2 * nc))
    mu = draw(st.lists(st.floats(0.0, 2.0), min_size=nc, max_size=nc))
    return nc, np.array(ang), np.array(b), np.array(mu)


@settings(max_examples=150, deadline=None)
@given(contact_problem())
def test_frictional_contact_lcp_solution_is_a_complementary_basis(data):
    """The frictional (copositive) contact LCP: Lemke's answer satisfies Signorini-Coulomb and
    a solution exists by enumeration whenever Lemke reports one."""
    nc, ang, b, mu = data
    verts = np.stack([0.5 * np.cos(ang) * np.sign(np.arange(nc) - 0.5), -np.ones(nc)], 1)
    Wn = np.stack([np.zeros(nc), np.ones(nc), verts[:, 0]], 1)
    Wt = np.stack([np.ones(nc), np.zeros(nc), -verts[:, 1]], 1)
    minv = np.array([1.0, 1.0, 3.0])
    idx = np.arange(nc)
    lamN, lamT, wN, slack, status = solve_contacts(Wn, Wt, minv, b[:nc], b[nc:], mu,
                                                   np.zeros(nc), idx)  # fmt: skip
    assert status == 0
    dv = minv * (Wn.T @ lamN + Wt.T @ lamT)
    gN = Wn @ dv + b[:nc]
    vT = Wt @ dv + b[nc:]
    s = 1e-7 * (1 + np.abs(b).max())
    assert lamN.min() >= -s and gN.min() >= -s and np.all(np.abs(lamN * gN) <= s)
    assert np.all(np.abs(lamT) <= mu * lamN + s)
    # sliding contacts: friction opposes the slip and is saturated
    sl = np.abs(vT) > 1e-6
    assert np.all(lamT[sl] * vT[sl] <= s)
    assert np.allclose(np.abs(lamT[sl]), (mu * lamN)[sl], atol=1e-6)
