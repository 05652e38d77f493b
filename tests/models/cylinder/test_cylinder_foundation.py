"""Closed-form Winkler resultants over a circular segment, their Jacobian, and the statics.

Independent checks: numerical quadrature (scipy.integrate.quad over chords, with the kink as a
break point) of the defining integrals; central finite differences of the resultants; Winkler
statics (settlement mg/(πr²k)); the kern of a circle (uplift when the resultant reaches r/4,
Timoshenko & Goodier, eccentric load on a circular footing); the source study's design values
k = 9814.0 N/m³, c = 103.6 N s/m³ (seed 000, §4.4.3).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from nsdyn.models.cylinder.design import (
    design_foundation,
    rocking_frequency,
    static_settlement,
    uplift_onset,
)
from nsdyn.models.cylinder.foundation import (
    jacobian,
    resultants,
    segment_integrals,
    static_moment_tilt,
)
from nsdyn.models.cylinder.params import CylinderParams


def _chord_quad(f, r, lo=-1.0):
    """∫ over the disc part u > lo·r of f(u) × chord, and of its v² moment (numerical)."""
    a = max(lo, -1.0) * r
    ch = quad(lambda u: f(u) * 2 * math.sqrt(r * r - u * u), a, r, limit=200, epsabs=1e-13)[0]
    v2 = quad(lambda u: f(u) * 2 / 3 * (r * r - u * u) ** 1.5, a, r, limit=200, epsabs=1e-13)[0]
    return ch, v2


@pytest.mark.parametrize("d", [-1.0, -0.7, -0.1, 0.0, 0.35, 0.9, 0.999, 1.0])
def test_segment_integrals_match_quadrature(d):
    r = 1.3
    A, Su, Iuu, Ivv = segment_integrals(d * r, r)
    qa, qvv = _chord_quad(lambda u: 1.0, r, d)
    qs, _ = _chord_quad(lambda u: u, r, d)
    qi, _ = _chord_quad(lambda u: u * u, r, d)
    np.testing.assert_allclose([A, Su, Iuu, Ivv], [qa, qs, qi, qvv], rtol=1e-9, atol=1e-12)


def _quad_resultants(w, g, wd, gd, r, k, c):
    """F, m_a, m_b of p = kδ + cδ̇ over {δ > 0} by 2-D quadrature in polar coordinates."""

    def p_and_in(rad, phi):
        a, b = rad * math.cos(phi), rad * math.sin(phi)
        delta = -w - g[0] * a - g[1] * b
        if delta <= 0:
            return 0.0, a, b
        return k * delta + c * (-wd - gd[0] * a - gd[1] * b), a, b

    def integral(which):
        def inner(phi):
            def f(rad):
                pv, a, b = p_and_in(rad, phi)
                return pv * (1.0, a, b)[which] * rad

            # break point: where the chord crosses this ray
            gp = g[0] * math.cos(phi) + g[1] * math.sin(phi)
            pts = [-w / gp] if gp != 0 and 0 < -w / gp < r else None
            return quad(f, 0, r, points=pts, limit=200, epsabs=1e-12)[0]

        return quad(inner, 0, 2 * math.pi, limit=400, epsabs=1e-11)[0]

    return np.array([integral(0), integral(1), integral(2)])


@pytest.mark.parametrize(
    "w, g, wd, gd",
    [
        (-2e-4, (1e-4, -5e-5), 1e-3, (2e-3, 1e-3)),  # partial contact, tilted both ways
        (1e-4, (3e-4, 2e-4), -2e-3, (-1e-3, 4e-3)),  # most of the base lifted
        (-5e-4, (1e-4, 1e-4), 0.0, (0.0, 0.0)),  # full contact
    ],
)
def test_resultants_match_2d_quadrature(w, g, wd, gd):
    r, k, c = 1.0, 9814.0, 103.6
    res = resultants(w, g, wd, gd, r=r, k=k, c=c)
    got = np.array([res["F"], *res["m"]])
    ref = _quad_resultants(w, g, wd, gd, r, k, c)
    np.testing.assert_allclose(got, ref, rtol=1e-7, atol=1e-9 * abs(ref).max())


@pytest.mark.parametrize("bonded", [False, True])
def test_jacobian_matches_finite_differences(bonded):
    r, k, c = 1.0, 9814.0, 103.6
    x0 = np.array([-1e-4, 2e-4, -1e-4, 3e-3, -2e-3, 5e-3])  # partial contact when tensionless

    def f(x):
        res = resultants(x[0], x[1:3], x[3], x[4:6], r=r, k=k, c=c, bonded=bonded)
        return np.array([res["F"], *res["m"]])

    jac = jacobian(x0[0], x0[1:3], x0[3], x0[4:6], r=r, k=k, c=c, bonded=bonded)
    fd = np.empty((3, 6))
    for j in range(6):
        hj = 1e-6 * max(abs(x0[j]), 1e-4)
        e = np.zeros(6)
        e[j] = hj
        fd[:, j] = (f(x0 + e) - f(x0 - e)) / (2 * hj)
    np.testing.assert_allclose(jac, fd, rtol=1e-6, atol=1e-8 * np.abs(fd).max())


def test_design_reproduces_source_values():
    k, c = design_foundation(3.0, 0.10, r=1.0, H=4.0, m=1.0)
    assert k == pytest.approx(9814.0, abs=0.5)  # seed 000 §4.4.3: 9814.0 N/m³
    assert c == pytest.approx(103.6, abs=0.05)  # seed 000 §4.4.3: 103.6 N s/m³
    f, zeta = rocking_frequency(CylinderParams(k=k, c=c))
    assert f == pytest.approx(3.0, rel=1e-12) and zeta == pytest.approx(0.1, rel=1e-12)


def test_static_settlement_and_uplift_onset():
    p = CylinderParams(r=0.8, H=2.0, m=3.0, k=2e4, c=50.0)
    W = p.m * p.g
    dst = static_settlement(p)
    assert dst == pytest.approx(W / (math.pi * p.r**2 * p.k), rel=1e-14)
    th_u, M_u = uplift_onset(p)
    assert M_u == pytest.approx(W * p.r / 4, rel=1e-12)  # kern of the circle: r/4
    M, w = static_moment_tilt(p, np.array([0.0, 0.999 * th_u, th_u, 1.001 * th_u]))
    assert w[0] == pytest.approx(-dst, rel=1e-10)
    # resultant at r/4 in the base plane; its lever arm about the base centre is (r/4) cos θ
    assert M[2] == pytest.approx(W * p.r / 4 * math.cos(th_u), rel=1e-9)
    g_lo, g_hi = math.sin(0.999 * th_u), math.sin(1.001 * th_u)
    assert resultants(w[1], (g_lo, 0), r=p.r, k=p.k)["contact"] == "full"
    assert resultants(w[3], (g_hi, 0), r=p.r, k=p.k)["contact"] == "partial"


def test_static_moment_tilt_curve_matches_quadrature():
    """Tensionless M(θ) at vertical equilibrium vs the defining integrals done numerically."""
    from scipy.optimize import brentq

    p = CylinderParams()
    W = p.m * p.g
    th_u, _ = uplift_onset(p)
    thetas = th_u * np.array([0.5, 1.0, 2.0, 5.0, 20.0, 100.0])
    M, _ = static_moment_tilt(p, thetas)
    for th, Mi in zip(thetas, M, strict=True):
        s = math.sin(th)

        def force(w, s=s):
            return quad(
                lambda u: p.k * max(-w + s * u, 0) * 2 * math.sqrt(1 - u * u),
                -1, 1, points=[w / s] if abs(w / s) < 1 else None, limit=200, epsabs=1e-14,
            )[0]  # fmt: skip

        w = brentq(lambda w: force(w) - W, -2 * s - 1e-3, s, xtol=1e-16, rtol=1e-15)
        ma = quad(
            lambda u, w=w, s=s: u * p.k * max(-w + s * u, 0) * 2 * math.sqrt(1 - u * u),
            -1, 1, points=[w / s] if abs(w / s) < 1 else None, limit=200, epsabs=1e-14,
        )[0]  # fmt: skip
        assert Mi == pytest.approx(ma * math.cos(th), rel=1e-7)
    # bonded: linear in sin θ everywhere; tensionless softens after onset and stays below mgr
    Mb, _ = static_moment_tilt(p.with_(foundation="bonded"), thetas)
    np.testing.assert_allclose(Mb, p.k * p.I_base * np.sin(thetas) * np.cos(thetas), rtol=1e-9)
    assert np.all(M[2:] < Mb[2:]) and np.all(M < W * p.r)
