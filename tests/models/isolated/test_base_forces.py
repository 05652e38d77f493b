"""The base shear and torsional moment of a run from its bearings' forces (a rigid deck's,
as the cb and full rungs' of a 3D building): the pendulum law summed over equal bearings."""

from __future__ import annotations

import numpy as np

from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.deck import simulate_plane


def test_a_centred_deck_s_base_shear_is_its_weight_times_the_pendulum_law():
    # four equal friction pendulums under a centred deck: every bearing slides alike (no
    # twist), so the base shear is Σ N_i (u/R + μ v/|v|) = m (g + a_z) (u/R + μ v/|v|) while
    # it slips (the normal forces sum to the weight and the vertical's inertia whatever the
    # overturning does), and its torsional moment about the centre of mass is round-off
    from nsdyn.models.isolated import base_force_peaks, base_forces  # (the public names)
    from nsdyn.models.isolated.deck import rigid_deck
    from nsdyn.models.isolated.plane_ground import ground_history

    m, R, mu, g = 4e5, 2.0, 0.05, 9.81
    pos = [(-4.0, -3.0), (4.0, -3.0), (4.0, 3.0), (-4.0, 3.0)]
    deck = rigid_deck(m, m * 100 / 12, pos, Bearing(Friction(mu), radius=R), h=1.5, g=g)
    orbit = {"f": 0.7, "ax": 3.0, "ay": 1.0, "phase_y_deg": 30.0, "az": 2.0, "f_z": 1.9}
    r = simulate_plane(deck, orbit, law="switch", t_end=6.0, dt_out=0.01, rtol=1e-10)
    V, T = base_forces(r, deck.ecc)
    slip = np.all(r.modes == 1, axis=1)
    u, v = r.u[:, 0], r.v[:, 0]  # (all four alike)
    law = (m * (g + ground_history(orbit, r.t)[2]))[:, None] * (
        u / R + mu * v / np.linalg.norm(v, axis=1, keepdims=True).clip(1e-300)
    )
    scale = np.abs(V).max()
    assert slip.sum() > 100
    assert np.abs(V.T[slip] - law[slip]).max() <= 1e-9 * scale
    peaks = base_force_peaks(r, deck.ecc)
    assert peaks["peak_torsional_moment_Nm"] <= 1e-12 * scale * 5.0  # (round-off: 5 m arm)
    assert peaks["peak_base_shear_N"] == float(np.hypot(*V).max())
