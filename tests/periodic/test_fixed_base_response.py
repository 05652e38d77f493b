"""The fixed-base frame's steady harmonic response (:func:`nsdyn.periodic.fixed_base_response`).

What must hold: the batched receptance ``T (K - w^2 M + i w C)^-1 (-M Gamma)`` is the frequency
response of the python-control state-space model of the same frame
(:func:`nsdyn.models.isolated.statespace.fixed_base_statespace`, an independent evaluation
through ``(sI - A)^-1 B``) to the round-off of the two solves, times the amplitude; a sequence
of amplitudes (a list, an array) gives the list of each one's result, a number its result.
"""

import numpy as np
import pytest

from nsdyn.models.isolated.metrics import output_dofs
from nsdyn.models.isolated.statespace import fixed_base_statespace
from nsdyn.models.isolated.system import build_system
from nsdyn.periodic import fixed_base_response

EPS = np.finfo(float).eps


def test_receptance_is_the_state_space_frequency_response(office):
    A = 0.7  # a non-unit amplitude: the result is A times the receptance's quantities
    freqs = np.geomspace(0.05, 20.0, 60)  # below, through and above the fixed-base modes
    got = fixed_base_response(office, A, freqs)
    sysf = build_system(office, fidelity="fixed", f_max=5.0)
    od = output_dofs(office)
    jx = od["joints_x"]
    dofs = np.concatenate([jx.ravel()] + [np.asarray(v) for v in od["levels_x"]])
    w = 2 * np.pi * freqs
    ss = fixed_base_statespace(sysf, dofs)
    H = np.asarray(ss(1j * w)).reshape(len(dofs), len(w)).T
    nj = jx.size
    drift = np.abs(np.diff(H[:, :nj].reshape(len(w), *jx.shape), axis=1))
    idr = A * (drift / od["heights"][None, :, None]).reshape(len(w), -1).max(axis=1)
    acc = A * np.abs(1.0 - (w**2)[:, None] * H[:, nj:]).max(axis=1)
    # round-off of the two solves (LU: ~n eps times the condition number, of the n x n dynamic
    # stiffness here and of the 2n x 2n jw I - A there), carried by |.|, differences and max
    M, C, K = sysf.M, sysf.C, sysf.K
    n = M.shape[0]
    kappa = np.array(
        [
            np.linalg.cond(K - wk**2 * M + 1j * wk * C)
            + np.linalg.cond(1j * wk * np.eye(2 * n) - np.asarray(ss.A))
            for wk in w
        ]
    )
    dH = 4 * n * kappa * EPS * np.abs(H).max(axis=1)
    assert np.all(dH < 1e-6 * np.abs(H).max(axis=1))  # a bound that can fail
    assert np.all(np.abs(got["idr"] - idr) <= A * 2 * dH / od["heights"].min())
    assert np.all(np.abs(got["acc"] - acc) <= A * w**2 * dH)
    assert np.array_equal(got["f"], freqs)


def test_amplitudes_as_a_sequence_an_array_or_a_number(office):
    freqs = np.geomspace(0.1, 5.0, 25)
    amps = np.array([0.1, 0.5, 2.0])
    many = fixed_base_response(office, amps, freqs)
    assert isinstance(many, list) and len(many) == len(amps)
    assert isinstance(fixed_base_response(office, np.float64(2.0), freqs), dict)
    for a, r in zip(amps, many, strict=True):
        one = fixed_base_response(office, float(a), freqs)
        for key in ("idr", "acc"):
            assert np.array_equal(r[key], one[key])
            assert np.all(one[key] > 0)
    assert fixed_base_response(office, [], freqs) == []


def test_needs_a_frame():
    with pytest.raises(ValueError, match="needs a frame"):
        fixed_base_response(None, 1.0, [1.0])
