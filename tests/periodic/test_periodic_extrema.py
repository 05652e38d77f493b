"""The periodic x_iso on the dense output, against a closed-form periodic solution.

Reference: the linear oscillator m x'' + c x' + k x = -m A sin(w t) has the steady state
x(t) = -X sin(w t - phi), X = m A / sqrt((k - m w^2)^2 + (c w)^2), tan phi = c w / (k - m w^2)
(any vibrations text, e.g. Chopra, Dynamics of Structures, eq. 3.2.2). x_iso is X.
"""

import math

import numpy as np
import pytest

from nsdyn import periodic as pr
from nsdyn.models.isolated.builders import system_from_matrices
from nsdyn.models.isolated.system import Isolation
from nsdyn.periodic.extrema import dense_half_range, dense_max

M, K = 1.0, (2 * math.pi) ** 2  # 1 Hz
C = 2 * 0.05 * math.sqrt(K * M)  # 5 % damping
A = 2.0  # m/s^2


def _linear():
    iso = Isolation(k_lam=0.0, c=0.0, mu=0.0, law="none")
    return system_from_matrices([[M]], [[C]], [[K]], iso_dofs=[0], influence=[1.0],
                                isolation=iso, weight=M * iso.g, levels=[[0]])  # fmt: skip


@pytest.mark.parametrize("f", [0.7, 2.9])
def test_x_iso_is_the_closed_form_amplitude(f):
    # 400 SDIRK3 steps per period: sampling alone misses the peak by up to X (w h)^2 / 8
    # (3e-5 X), the scheme's own error is O((w h)^3). The bound is the analysis of the module
    # nsdyn.periodic.extrema: 2 e_x + h e_v + h^2 e_a (errors of the samples against the exact
    # solution, measured here from the closed form) + X w^6 (h/2)^6 / 720 (interpolation).
    # At these two frequencies the peak falls between samples: the largest sample misses X
    # by more than the bound, so the test tells the dense output from the samples.
    w = 2 * math.pi * f
    X = M * A / math.hypot(K - M * w * w, C * w)
    phi = math.atan2(C * w, K - M * w * w)
    prob = pr.frame_problem(_linear(), A)
    disc = pr.Discretisation(method="sdirk3", n_min=400, dt_max=1e9)
    res = pr.shoot(prob, f, disc=disc)
    assert res.converged
    N = res.n_steps
    h = 1.0 / (f * N)
    t = np.linspace(0.0, 1.0 / f, N + 1)
    Xf = prob.to_full(res.X)
    x, v = Xf[:, 0], Xf[:, 1]
    a = (-M * A * np.sin(w * t) - C * v - K * x) / M  # the equation of motion at the samples
    ex = np.max(np.abs(x + X * np.sin(w * t - phi)))
    ev = np.max(np.abs(v + X * w * np.cos(w * t - phi)))
    ea = np.max(np.abs(a - X * w * w * np.sin(w * t - phi)))
    bound = 2 * ex + h * ev + h * h * ea + X * (w * h / 2) ** 6 / 720
    x_iso = prob.orbit_quantities(f, res.X)["x_iso"]
    assert abs(x_iso - X) <= bound
    assert abs(0.5 * (x.max() - x.min()) - X) > bound  # the samples alone would fail


def test_dense_max_of_a_sampled_sine():
    # sin on 12 samples per period, peak between two samples: exact data, so the error is the
    # interpolation's alone, <= (w h / 2)^6 / 720 = 2.6e-6 (module text)
    w, h = 2 * math.pi, 1.0 / 12
    t = 0.03 + h * np.arange(13)
    x, v, a = np.sin(w * t), w * np.cos(w * t), -w * w * np.sin(w * t)
    assert 1.0 - x.max() > 1e-2
    assert abs(dense_max(x, v, a, h) - 1.0) <= (w * h / 2) ** 6 / 720
    cols = np.column_stack([x, 2 * x])
    r = dense_half_range(cols, np.column_stack([v, 2 * v]), np.column_stack([a, 2 * a]), h)
    assert abs(r - 2.0) <= 2 * (w * h / 2) ** 6 / 720


@pytest.mark.parametrize("t_stop", [0.43, 0.5, 0.57])
def test_dense_max_of_a_slide_that_sticks_at_its_peak(t_stop):
    # x rises at v0 decelerating by d until it sticks at t_s = v0 / d (x'' jumps from -d to 0)
    # and stays: the peak is v0^2 / (2 d), reached at the stop inside the step [0.4, 0.6]; a
    # quintic through the kink overshoots, the speed bound of nsdyn.periodic.extrema caps it
    # at the stuck end value, exact to round-off
    d, h = 2.0, 0.2
    v0 = d * t_stop
    t = np.array([0.0, 0.2, 0.4, 0.6, 0.8])
    slip = t < t_stop
    x = np.where(slip, v0 * t - 0.5 * d * t**2, v0**2 / (2 * d))
    v = np.where(slip, v0 - d * t, 0.0)
    a = np.where(slip, -d, 0.0)
    assert abs(dense_max(x, v, a, h) - v0**2 / (2 * d)) <= 4 * np.finfo(float).eps


def test_no_speed_cap_where_the_acceleration_changes_sign():
    # x = c1 s + c2 s^2 + c3 s^3 (h = 1): a = 2 c2 + 6 c3 s is positive at s = 0 and negative
    # at s = 1, so the speed first grows above v(0) and the peak x(s*), v(s*) = 0, lies above
    # both x(0) + |v(0)| h and x(1) + |v(1)| h. A quintic Hermite reproduces a cubic, so the
    # dense peak is x(s*) to round-off: the root's error enters the value at second order only
    # (v = 0 there), each evaluation of a cubic with sum |c_i| = 1.1 on [0, 1] errs by at most
    # 6u sum |c_i| < 4 eps (and the Hermite coefficients by a few u on numbers <= 2): 16 eps.
    c1, c2, c3 = 0.1, 0.5, -0.5
    s = np.array([0.0, 1.0, 2.0])
    x, v, a = c1 * s + c2 * s**2 + c3 * s**3, c1 + 2 * c2 * s + 3 * c3 * s**2, 2 * c2 + 6 * c3 * s
    r = (2 * c2 + math.sqrt(4 * c2**2 - 12 * c3 * c1)) / (-6 * c3)  # v(r) = 0 in (0, 1)
    peak = c1 * r + c2 * r**2 + c3 * r**3
    assert peak > min(x[0] + abs(v[0]), x[1] + abs(v[1]))  # the speed bound does not hold
    assert abs(dense_max(x, v, a, 1.0) - peak) <= 16 * np.finfo(float).eps
