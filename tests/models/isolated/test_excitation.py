"""The excitation channels along a history by numpy equal the system kernel's, bit for bit.

Source: :func:`nsdyn.models.isolated._kernel.ground_accel` defines the excitation every
integrator sees; :func:`nsdyn.models.isolated.excitation.ground_many` must give the same
floats (the response metrics add it to the relative accelerations, the sparse path steps with
it), with the record's edges as the kernel treats them: zero before the record's start and
after its last sample, the last sample itself exactly on it.
"""

from __future__ import annotations

import numpy as np
import pytest

from nsdyn.models.isolated import _kernel as ks
from nsdyn.models.isolated.excitation import ground_many
from nsdyn.solve.methods import _tiny_problem


def _with_ground(P, harmonic: bool, rng):
    P = list(P)
    gp, ip = P[ks.I_GPAR].copy(), P[ks.I_IPAR].copy()
    if harmonic:
        ip[ks.K_GROUND] = ks.GROUND_HARMONIC
        for i, v in zip((ks.G_AH, ks.G_FH, ks.G_PH, ks.G_AV, ks.G_FV, ks.G_PV),
                        (2.3, 1.7, 0.4, 0.9, 3.1, -0.2), strict=True):  # fmt: skip
            gp[i] = v
    else:
        ip[ks.K_GROUND] = 0
        gp[ks.G_T0], gp[ks.G_DT] = 0.3, 0.01
        P[ks.I_AH], P[ks.I_AV] = rng.standard_normal(400), rng.standard_normal(400)
    P[ks.I_GPAR], P[ks.I_IPAR] = gp, ip
    return tuple(P)


@pytest.mark.parametrize("harmonic", [False, True], ids=["record", "harmonic"])
def test_ground_many_equals_the_kernels_ground_accel(harmonic):
    rng = np.random.default_rng(7)
    P = _with_ground(_tiny_problem()[0], harmonic, rng)
    # random instants over and around the record, and every sample instant with its neighbours
    t = np.concatenate([rng.uniform(-1.0, 5.0, 500), 0.3 + 0.01 * np.arange(-3, 404)])
    expected = np.array([ks.ground_accel(float(tk), P) for tk in t])
    got = ground_many(t, P)
    assert got.shape == (t.size, 2)
    np.testing.assert_array_equal(got, expected)
    if not harmonic:  # the edges: zero before the start and past the end, the last sample on it
        edge = ground_many(np.array([0.3 - 1e-12, 0.3 + 399 * 0.01, 4.3, 0.3]), P)
        assert edge[0].tolist() == [0.0, 0.0] and edge[2].tolist() == [0.0, 0.0]
        assert edge[3].tolist() == [P[ks.I_AH][0], P[ks.I_AV][0]]
        assert edge[1].tolist() == list(ks.ground_accel(0.3 + 399 * 0.01, P))
