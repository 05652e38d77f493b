"""The isolator figure of a pair system: the torsion axis shows the rigid base's twist, or none.

Reference: from_deck's coordinates q = (x, y, θ, z, r_x, r_y) with slips D_i q =
(x − Y_i θ, y + X_i θ) (its docstring), so the twist row is exactly the unit row on θ; a single
isolator has no twist.
"""

from types import SimpleNamespace

import numpy as np

from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.deck import rigid_deck, sdof_plane
from nsdyn.models.isolated.pairs import from_deck, twist_row
from nsdyn.plot.isolators import plane_figure

B = Bearing(Friction(0.05), radius=2.5)
POS = [(-4.0, -3.0), (4.0, -3.0), (4.0, 3.0), (-4.0, 3.0)]


def test_twist_row_of_a_rigid_deck_is_its_rotation_and_a_single_isolator_has_none():
    p = from_deck(rigid_deck(2e5, 1.6e6, POS, B, ecc=(0.6, -0.4), h=1.5))
    np.testing.assert_allclose(twist_row(p), [0, 0, 1, 0, 0, 0], atol=1e-12)
    assert twist_row(from_deck(sdof_plane(1000.0, B))) is None


def _fake(system, twist, slip=0.0):
    nt, ni = 5, system.n_isolators
    z = np.zeros((nt, ni, 2))
    return SimpleNamespace(summary=None, twist=twist, t=np.arange(nt) * 0.1, u=z + slip,
                           N=np.ones((nt, ni)), friction=z, restoring=z, other=z,
                           system=system)  # fmt: skip


def _labels(fig):
    return [a.get_ylabel() for a in fig.axes]


def test_the_figure_labels_the_base_torsion_only_where_there_is_one():
    deck = from_deck(rigid_deck(2e5, 1.6e6, POS, B))
    assert "base torsion θ [mrad]" in _labels(plane_figure(_fake(deck, np.full(5, 1e-3), 0.1)))
    # a symmetric deck's twist of round-off (1e-19 rad beside slips of 0.1 m) was drawn on a
    # 1e-16 axis offset, as if a response; it is said to be none
    fig = plane_figure(_fake(deck, np.full(5, 1e-19), 0.1))
    assert "base torsion θ [mrad]" not in _labels(fig)
    assert "no base torsion (round-off)" in [a.get_title() for a in fig.axes]
    mass = from_deck(sdof_plane(1000.0, B))
    labels = _labels(plane_figure(_fake(mass, None)))
    assert not any("torsion" in s for s in labels)
    assert "normal forces N_i [kN]" in labels
