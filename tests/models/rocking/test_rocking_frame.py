"""Rocking frame: p(gamma) and r(gamma) against a direct two-column + beam multibody model,
the column limit gamma -> 0 and seed 003 Tables 2-3."""

from __future__ import annotations

import math

import numpy as np
import pytest

from nsdyn.ground.pulses import one_sine
from nsdyn.models.rocking import RockingBlock, simulate_rocking
from nsdyn.models.rocking.block import housner_restitution
from nsdyn.models.rocking.frame import RockingFrame, frame_frequency_ratio, frame_restitution

G = 9.81


def _rot(phi, p):
    c, s = math.cos(phi), math.sin(phi)
    return np.array([c * p[0] - s * p[1], s * p[0] + c * p[1]])


class TwoColumnsAndBeam:
    """Direct planar multibody model: columns i = 0, 1 (mass m, 2B x 2H, centred at X_i) and a
    beam (mass m_b, half-depth h_b) as three free rigid bodies q = [x, y, phi] x 3, joined by
    pins: base corners (s B, -H) of the columns to the ground, top corners (-s B, H) to the
    beam. Constrained Lagrange equations M q'' = F + G^T lam, G q'' = -(G q')' q' and the
    impulse balance M dq' = G_new^T Lam, G_new q'+ = 0 at an impact."""

    def __init__(self, B, H, m, m_b, L=3.0, h_b=0.1):
        self.B, self.H, self.m, self.m_b, self.L, self.h_b = B, H, m, m_b, L, h_b
        self.X = (0.0, L)
        I_c = m * (B * B + H * H) / 3.0
        I_b = m_b * (L * L + 4 * h_b * h_b) / 12.0
        self.M = np.diag([m, m, I_c, m, m, I_c, m_b, m_b, I_b])

    def _pins(self, s):
        """(body a, point a, body b or None, point b / ground point) for side s."""
        B, H = self.B, self.H
        pins = []
        for i, X in enumerate(self.X):
            pins.append((i, (s * B, -H), None, (X + s * B, 0.0)))
            pins.append((i, (-s * B, H), 2, (X - s * B - self.L / 2, -self.h_b)))
        return pins

    def configuration(self, theta):
        s = 1.0 if theta >= 0 else -1.0
        q = np.zeros(9)
        for i, X in enumerate(self.X):
            piv = np.array([X + s * self.B, 0.0])
            q[3 * i : 3 * i + 2] = piv - _rot(-theta, (s * self.B, -self.H))
            q[3 * i + 2] = -theta
        top = q[0:2] + _rot(-theta, (-s * self.B, self.H))
        q[6:8] = top - np.array([self.X[0] - s * self.B - self.L / 2, -self.h_b])
        return q, s

    def jac(self, q, s):
        """Constraint Jacobian G (8, 9) and the velocity-product term (G' q') as a function."""
        rows = []
        for a, pa, b, pb in self._pins(s):
            for comp in range(2):
                row = np.zeros(9)
                row[3 * a + comp] = 1.0
                row[3 * a + 2] = _rot(q[3 * a + 2] + math.pi / 2, pa)[comp]
                if b is not None:
                    row[3 * b + comp] -= 1.0
                    row[3 * b + 2] -= _rot(q[3 * b + 2] + math.pi / 2, pb)[comp]
                rows.append(row)
        return np.array(rows)

    def gamma_term(self, q, qd, s):
        out = []
        for a, pa, b, pb in self._pins(s):
            v = -(qd[3 * a + 2] ** 2) * _rot(q[3 * a + 2], pa)
            if b is not None:
                v = v + qd[3 * b + 2] ** 2 * _rot(q[3 * b + 2], pb)
            out.extend(v)
        return np.array(out)

    def velocity(self, q, s, thetad):
        Gm = self.jac(q, s)
        _, _, vt = np.linalg.svd(Gm)
        n = vt[-1]
        return n * (-thetad / n[2])  # phi_0' = -theta'

    def theta_dd(self, theta, thetad, ug):
        q, s = self.configuration(theta)
        qd = self.velocity(q, s, thetad)
        Gm = self.jac(q, s)
        masses = np.diag(self.M)[[0, 3, 6]]
        F = np.zeros(9)
        for k, mk in enumerate(masses):
            F[3 * k] = -mk * ug
            F[3 * k + 1] = -mk * G
        K = np.block([[self.M, -Gm.T], [Gm, np.zeros((8, 8))]])
        rhs = np.r_[F, -self.gamma_term(q, qd, s)]
        sol = np.linalg.lstsq(K, rhs, rcond=None)[0]
        return -sol[2]

    def restitution(self):
        q, s = self.configuration(1e-300)
        qd_m = self.velocity(q, s, -1.0)  # rocking on s = +1, moving towards theta < 0
        Gn = self.jac(q, -s)
        K = np.block([[self.M, -Gn.T], [Gn, np.zeros((8, 8))]])
        sol = np.linalg.lstsq(K, np.r_[self.M @ qd_m, np.zeros(8)], rcond=None)[0]
        return -sol[2] / -1.0


@pytest.mark.parametrize("gamma", [0.0, 0.7, 5.0])
def test_frame_equation_matches_direct_multibody_model(gamma):
    """theta'' of the one-dof frame equation with p_f(gamma) equals theta'' of the direct
    two-column + beam model at several states and ground accelerations (independent
    derivation: constrained Lagrange equations of three free bodies)."""
    B, H, m = 0.2, 0.6, 2.0
    fr = RockingFrame(B=B, H=H, gamma=gamma)
    mb = TwoColumnsAndBeam(B, H, m, 2 * gamma * m)
    for theta, thetad, ug in [(0.05, 0.0, 0.0), (0.12, 0.4, -2.0), (-0.08, -0.3, 3.0)]:
        s = math.copysign(1.0, theta)
        phi = s * fr.alpha - theta
        expected = -(fr.p**2) * (math.sin(phi) + ug / G * math.cos(phi))
        assert mb.theta_dd(theta, thetad, ug) == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("gamma", [0.0, 0.3, 5.0])
def test_frame_restitution_matches_direct_impulse_balance(gamma):
    """r_f(gamma) (Makris-Vassiliou) equals the ratio theta'+ / theta'- of the direct model's
    impulse balance with the new pivots (independent derivation)."""
    B, H = 0.15, 0.6
    mb = TwoColumnsAndBeam(B, H, 1.0, 2 * gamma)
    assert mb.restitution() == pytest.approx(frame_restitution(math.atan2(B, H), gamma), rel=1e-9)


def test_gamma_zero_is_the_column():
    """gamma -> 0: the frame's r and p equal the free column's (Housner), and so do responses."""
    for alpha in (0.1, 0.25, 0.32):
        assert frame_restitution(alpha, 0.0) == pytest.approx(housner_restitution(alpha), rel=1e-14)
    assert frame_frequency_ratio(0.0) == 1.0
    fr = RockingFrame(width=0.3, height=1.2, gamma=1e-12)
    col = RockingBlock(width=0.3, height=1.2)
    assert fr.p == pytest.approx(col.p, rel=1e-11)
    exc = one_sine(0.4 * G, 12.57)
    a = simulate_rocking(fr, exc, t_end=4.0, dt_out=0)
    b = simulate_rocking(col, exc, t_end=4.0, dt_out=0)
    np.testing.assert_allclose(a.impacts[:10, 0], b.impacts[:10, 0], rtol=1e-8)


@pytest.mark.parametrize(
    "H2, B2, alpha_t, r_col, r_frame",
    [(1.2, 0.4, 0.32, 0.85, 0.80), (1.2, 0.3, 0.25, 0.91, 0.88), (2.0, 0.4, 0.20, 0.94, 0.92),
     (2.0, 0.2, 0.10, 0.99, 0.98)],
)  # fmt: skip
def test_seed003_tables_2_and_3(H2, B2, alpha_t, r_col, r_frame):
    """Seed 003 Tables 2-3 (gamma = 5): slenderness, column and frame restitution to the two
    decimals printed."""
    fr = RockingFrame(width=B2, height=H2, gamma=5.0)
    assert fr.alpha == pytest.approx(alpha_t, abs=0.0051)  # 0.245 prints as 0.25
    assert fr.column.restitution == pytest.approx(r_col, abs=0.005)
    assert fr.restitution == pytest.approx(r_frame, abs=0.005)
