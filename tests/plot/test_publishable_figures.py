"""Figures worth publishing: the transient figure names the record and its PGA, draws the
ground motion, has no empty panel (no normal forces without contact rows), a legend on every
panel with more than one line; the contact tilt axis is scaled to the physics (at least a
fraction of the slenderness), not to round-off; the cylinder's 3D axes carry their units;
a missing spectrum point is explained, not printed as nan."""

from __future__ import annotations

import math

import numpy as np
import pytest

import nsdyn
from nsdyn import Isolation, system_from_matrices

pytest.importorskip("matplotlib")

K2 = (2 * math.pi) ** 2


def _shear_building():
    """Two storeys on a friction isolator, built from matrices: levels, no contact rows."""
    iso = Isolation(k_lam=0.0, c=0.0, mu=0.1, law="arctan", eps=100.0)
    return system_from_matrices(
        [[1.0, 0.0], [0.0, 1.0]], [[0.2, -0.2], [-0.2, 0.2]], [[K2, -K2], [-K2, K2]],
        iso_dofs=[0], influence=[1.0, 1.0], isolation=iso, weight=2 * iso.g,
        levels=[[0], [1]],
    )  # fmt: skip


@pytest.fixture(scope="module")
def shear_run():
    motion = nsdyn.read_motion("synthetic-wn-40s").window(0.0, 2.0).scaled_to_pga(3.0)
    return nsdyn.simulate(_shear_building(), motion, method="radau"), motion


def _axes_labels(fig) -> list[str]:
    return [ax.get_ylabel() for ax in fig.axes]


def test_title_names_the_record_and_its_pga(shear_run):
    from nsdyn.plot import plot_transient

    res, motion = shear_run
    fig = plot_transient(res, motion, note="outcome: x")
    title = fig.get_suptitle()
    assert "synthetic-wn-40s" in title and "PGA 3 m/s²" in title and "outcome: x" in title
    assert "synthetic-wn-40s, t = 0-2 s (PGA" in title  # (2 s of the 40 s record, as run)
    assert "ground acceleration [m/s²]" in _axes_labels(fig)


def test_shear_building_has_no_normal_force_panel_and_no_empty_axes(shear_run):
    from nsdyn.plot import plot_transient

    res, motion = shear_run
    assert res.response.lam.shape[1] == 0  # the model has no contact rows
    fig = plot_transient(res, motion)
    assert not any("normal force" in lab for lab in _axes_labels(fig))
    for ax in fig.axes:
        assert ax.get_lines(), f"empty panel {ax.get_ylabel()!r}"


def test_every_panel_with_two_lines_has_a_legend(shear_run):
    from nsdyn.plot import plot_transient

    res, motion = shear_run
    fig = plot_transient(res, motion, fixed=res)  # any run stands in for the fixed base here
    multi = [ax for ax in fig.axes if len(ax.get_lines()) > 1]
    assert multi, "the comparison draws two lines somewhere"
    for ax in multi:
        assert ax.get_legend() is not None, ax.get_ylabel() or ax.get_xlabel()


def test_contact_tilt_axis_has_a_physical_floor():
    """A sliding block tilts by round-off only (|theta| ~ 1e-15 rad): the axis spans at least
    1 % of the slenderness alpha = atan(b/h), so the noise draws as a flat line at zero."""
    from nsdyn import FrictionLaw, RigidBody
    from nsdyn.models.contact import BaseMotion, simulate_event
    from nsdyn.models.contact.figures import history_figure, tilt_limits

    body = RigidBody.rectangle(1.1, 1.0, mass=2500.0)
    alpha = math.atan2(0.55, 0.5)
    lo, hi = tilt_limits(np.array([1e-15, -3e-15]), alpha)
    assert hi == -lo == pytest.approx(0.01 * alpha, rel=1e-15)
    assert tilt_limits(np.array([0.3]), alpha)[1] == pytest.approx(0.33, rel=1e-15)
    # a constant ground acceleration of 0.4 g slides a block with mu = 0.2 < b/h = 1.1 (no
    # tipping: rocking needs mu > b/h), so its tilt stays at round-off
    res = simulate_event(body, FrictionLaw(0.2), BaseMotion.constant(0.4 * 9.81), t_end=0.2,
                         dt_out=0.01)  # fmt: skip
    assert res.summary()["max_slide_m"] > 0 and res.summary()["max_tilt_rad"] < 1e-9
    fig = history_figure(res, body)
    assert fig.axes[0].get_ylim()[1] >= 0.01 * alpha * (1 - 1e-12)


def test_cylinder_3d_axes_are_labelled():
    from nsdyn.models.cylinder import CylinderParams, earthquake, simulate
    from nsdyn.models.cylinder.figures import motion_figure

    dt, ag = earthquake(0, duration=0.5, dt=0.01)
    fig = motion_figure(simulate(CylinderParams(), ag, dt))
    ax3 = next(ax for ax in fig.axes if ax.name == "3d")
    assert (ax3.get_xlabel(), ax3.get_ylabel(), ax3.get_zlabel()) == ("x [m]", "y [m]", "z [m]")
    for ax in fig.axes:
        if len(ax.get_lines()) > 1:
            assert ax.get_legend() is not None, ax.get_ylabel()
    # the uplift panel draws two quantities on twin axes: one legend names both
    up = next(ax for ax in fig.axes if ax.get_ylabel() == "lifted area / πr²")
    assert len(up.get_legend().get_texts()) == 2


def test_spectrum_table_and_figure_explain_a_missing_point(tmp_path, capsys):
    """At omega_p / p = 18 and 20 a one-sine pulse of up to 30 g tan alpha does not overturn the
    seed 003 column (the minimum overturning amplitude grows steeply with the pulse frequency,
    Zhang & Makris 2001): the table says so with the bound, never nan."""
    from pathlib import Path

    from nsdyn.cli import main

    scene = Path(__file__).parents[2] / "examples" / "scenes" / "rocking-seed003-column.toml"
    rc = main(["spectrum", str(scene), "--n", "2", "--wmin", "18", "--wmax", "20", "--out",
               str(tmp_path)])  # fmt: skip
    assert rc in (0, None)
    out = capsys.readouterr().out
    assert "nan" not in out.lower()
    assert "> 30" in out and "no overturning up to a_max = 30" in out


def _cli_figure(monkeypatch, tmp_path, *flags):
    """The figure ``nsdyn run`` saves (captured instead of written)."""
    import nsdyn.cli.run as run_mod
    from nsdyn.cli import main

    saved = []
    monkeypatch.setattr(run_mod, "save_figure", lambda fig, path, **kw: saved.append(fig))
    assert main(["run", "--out", str(tmp_path), *flags]) in (0, None)
    assert len(saved) == 1
    return saved[0]


def test_default_run_figure_names_the_record_and_pga(monkeypatch, tmp_path, capsys):
    # the default scene: office-11 under the whole synthetic-wn-40s scaled to a PGA of 3 m/s²
    fig = _cli_figure(monkeypatch, tmp_path)
    title = fig.get_suptitle()
    assert "synthetic-wn-40s" in title and "PGA 3 m/s²" in title and "outcome:" in title
    labels = [ax.get_ylabel() for ax in fig.axes]
    assert "ground acceleration [m/s²]" in labels and "normal force [kN]" in labels


@pytest.mark.slow
def test_compare_fixed_draws_the_fixed_base_beside(monkeypatch, tmp_path, capsys):
    # a second run of the fixed-base frame (its kernel compiles once, then loads): the fixed
    # base's top drifts more than the isolated frame's top relative to its base (seed 004
    # Fig. 7, the same comparison under the Kobe records at a PGA of 3 m/s²), both drawn,
    # with a legend
    fig = _cli_figure(monkeypatch, tmp_path, "--t-end", "10", "--compare-fixed")
    drift = next(ax for ax in fig.axes if ax.get_ylabel() == "top drift [m]")
    iso, fixed = drift.get_lines()
    assert "fixed base" in fixed.get_label() and drift.get_legend() is not None
    assert np.max(np.abs(fixed.get_ydata())) > np.max(np.abs(iso.get_ydata()))
