"""Figures of space frames: the deformed shape drawn is the frame moved by scale × u; the
figures of a building3d run (deformed shape at the peak, mode shapes) are written."""

from __future__ import annotations

import numpy as np
import pytest

from nsdyn.plot.frames3d import (
    FrameGeometry,
    auto_scale,
    member_lines,
    plot_deformed_3d,
    plot_mode_shapes_3d,
    scene_figures,
)
from nsdyn.structure import fixed_base_modes_3d, load_frame3d

EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def portal():
    return load_frame3d("portal-3d")


def _lines(fig, gid: str) -> list[np.ndarray]:
    (ax,) = fig.axes
    (h,) = [h for h in ax.get_lines() if h.get_gid() == gid]  # one artist per set of members
    return member_lines(h)


def _bound(frame, u, scale) -> float:
    # a drawn point is p + scale × Rᵀ(R u_end) with R orthonormal: the round trip through the
    # local axes and the sums cost a few eps of |p| and of scale × |u| (10 eps is ample)
    return 10 * EPS * (np.abs(frame.nodes).max() + scale * np.abs(u).max())


def test_deformed_coordinates_are_nodes_plus_scale_times_u(portal):
    rng = np.random.default_rng(3)
    u = 1e-3 * rng.standard_normal(portal.n_dof)
    scale = 250.0
    fig = plot_deformed_3d(portal, u, scale=scale)
    und, dfm = _lines(fig, "undeformed"), _lines(fig, "deformed")
    el = portal.elements
    assert len(und) == len(dfm) == len(el)
    t = u.reshape(-1, 6)[:, :3]
    tol = _bound(portal, u, scale)
    for k, (a, b) in enumerate(el):
        assert np.array_equal(und[k][0], portal.nodes[a])
        assert np.array_equal(und[k][-1], portal.nodes[b])
        assert np.abs(dfm[k][0] - (portal.nodes[a] + scale * t[a])).max() <= tol
        assert np.abs(dfm[k][-1] - (portal.nodes[b] + scale * t[b])).max() <= tol


def test_uniform_translation_moves_every_drawn_point(portal):
    # the cubic Hermite functions sum to one (N1 + N3 = 1) and the rotations are zero: a rigid
    # translation d moves every drawn point of every member by scale × d
    d = np.array([0.02, -0.01, 0.005])
    u = np.zeros((portal.n_nodes, 6))
    u[:, :3] = d
    scale = 30.0
    fig = plot_deformed_3d(portal, u.ravel(), scale=scale)
    und = [np.linspace(portal.nodes[a], portal.nodes[b], 7) for a, b in portal.elements]
    tol = _bound(portal, u, scale)
    for p0, p in zip(und, _lines(fig, "deformed"), strict=True):
        assert np.abs(p - (p0 + scale * d)).max() <= tol


def test_auto_scale_draws_the_largest_translation_as_a_fixed_share(portal):
    from nsdyn.plot.frames3d import SHAPE_SCALE

    m = fixed_base_modes_3d(portal, n_modes=3)
    u = m.full()[:, 0]
    s = auto_scale(portal, u)
    fig = plot_deformed_3d(portal, u)
    drawn = zip(_lines(fig, "deformed"), portal.elements, strict=True)
    moved = max(np.abs(p - np.linspace(portal.nodes[a], portal.nodes[b], 7)).max()
                for p, (a, b) in drawn)  # fmt: skip
    # the nodes move by at most SHAPE_SCALE × size; a bent member between them may bulge a bit
    assert np.isclose(s * np.abs(u.reshape(-1, 6)[:, :3]).max(), SHAPE_SCALE * portal.size)
    assert moved >= SHAPE_SCALE * portal.size * (1 - 1e-12)
    assert len(plot_mode_shapes_3d(m, n=3).axes) == 3


def test_geometry_from_saved_arrays_draws_the_same(portal, tmp_path):
    from nsdyn.models.isolated.building3d_shape import write_shape

    rng = np.random.default_rng(4)
    u = 1e-3 * rng.standard_normal(portal.n_dof)
    path = write_shape(tmp_path, portal, {"t_peak": 1.0, "u": u, "what": "test"})
    with np.load(path) as d:
        geo = FrameGeometry.from_arrays({k: d[k] for k in d.files})
    a = _lines(plot_deformed_3d(portal, u, scale=100.0), "deformed")
    b = _lines(plot_deformed_3d(geo, u, scale=100.0), "deformed")
    assert all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))


SCENE = """
[scene]
kind = "building3d"
[structure]
frame3d = "portal-3d"
fidelity = "{fid}"
n_modes = 6
[bearing]
type = "fps"
radius = 1.5
mu = 0.04
[motion]
kind = "record3"
record = "synthetic-kt-20s"
t_end = 6.0
"""


@pytest.mark.parametrize("fid", ["fixed", "rigid"])
def test_building3d_run_writes_its_figures(tmp_path, fid):
    import tomllib

    from nsdyn.models.isolated import building3d_scene

    cfg = tomllib.loads(SCENE.format(fid=fid))
    if fid == "fixed":
        del cfg["bearing"]
    s = building3d_scene.run_scene(cfg, source=str(tmp_path / "s.toml"), out_dir=tmp_path,
                                   figures=True, quiet=True)  # fmt: skip
    files = scene_figures(s, tmp_path)
    names = {p.rsplit("/", 1)[-1] for p in files}
    assert names == ({"building3d-deformed.png", "building3d-modes.png"} if fid == "fixed"
                     else {"building3d-deformed.png"})  # fmt: skip
    with np.load(tmp_path / "building3d-shape.npz") as d:
        u, t_peak = d["u"].reshape(-1, 6), float(d["t_peak"])
    if fid == "rigid":
        # the building moves rigidly with the deck: at the instant of the peak slip every
        # base node is displaced by its isolator's slip, whose largest is the run's peak
        with np.load(tmp_path / "building3d.npz") as h:
            k = int(np.flatnonzero(h["t"] == t_peak)[0])
            slip = h["u"][k]
        base = load_frame3d("portal-3d").base_nodes
        assert np.allclose(u[base, :2], slip, rtol=0, atol=1e-12 * np.abs(slip).max())
        assert np.isclose(np.hypot(*slip.T).max(), s["peak_resultant_displacement_m"],
                          rtol=1e-12)  # fmt: skip
