"""The sweep figure draws every point and its legend names only what is drawn.

A synthetic curve with one stepped-sweep point and two uplift points (values of the bilateral
model, outside its validity) and no unstable point: the uplift points must appear as their own
markers at their values (not vanish), the sweep point as its marker, and the legend must list
exactly those two marker kinds — no "unstable" entry, no "fixed base" entry without fixed-base
curves.
"""

import numpy as np
import pytest

from nsdyn.plot.frames import MARKER_LABELS, sweep_figure


def _rows():
    f = np.geomspace(0.01, 1.0, 8)
    rows = []
    for k, fk in enumerate(f):
        rows.append(
            {
                "f": fk,
                "IDR": 1e-3 * (k + 1),
                "a": 0.5 * (k + 1),
                "x_iso": 0.01 * (k + 1),
                "stick_all_period": False,
                "stable": True,
                "method": "sweep" if k == 5 else "shooting",
                "uplift": k in (2, 3),
            }
        )
    return rows


def _markers(ax, marker):
    pts = []
    for line in ax.get_lines():
        if line.get_marker() == marker:
            pts.extend(zip(line.get_xdata(), line.get_ydata(), strict=True))
    return pts


def test_uplift_and_fallback_points_are_drawn_and_the_legend_matches():
    rows = _rows()
    fig = sweep_figure([{"A": 1.0, "rows": rows}])
    ax_idr, ax_acc, _ = fig.axes
    up = _markers(ax_idr, "^")
    assert sorted(x for x, _ in up) == sorted([rows[2]["f"], rows[3]["f"]])
    assert {y for _, y in up} == {rows[2]["IDR"], rows[3]["IDR"]}  # their values, drawn
    assert [x for x, _ in _markers(ax_idr, "o")] == [rows[5]["f"]]
    assert not _markers(ax_idr, "x")
    labels = {t.get_text() for t in ax_acc.get_legend().get_texts()}
    assert labels == {MARKER_LABELS["sweep"], MARKER_LABELS["uplift"]}
    # the solid line leaves the uplift band out
    solid = [ln for ln in ax_idr.get_lines() if ln.get_linestyle() == "-"][0]
    assert np.isnan(np.asarray(solid.get_ydata())[[2, 3]]).all()


def test_unilateral_rows_are_drawn_on_the_curve_with_their_own_marker():
    # rows the unilateral sweep recomputed are valid points of that model: on the solid line,
    # marked as such, and no longer shown as bilateral uplift values
    rows = _rows()
    for k in (2, 3):
        rows[k]["method"] = "unilateral"
    fig = sweep_figure([{"A": 1.0, "rows": rows}])
    ax_idr, ax_acc, _ = fig.axes
    assert sorted(x for x, _ in _markers(ax_idr, "s")) == sorted([rows[2]["f"], rows[3]["f"]])
    assert not _markers(ax_idr, "^")
    solid = [ln for ln in ax_idr.get_lines() if ln.get_linestyle() == "-"][0]
    assert np.isfinite(np.asarray(solid.get_ydata())[[2, 3]]).all()
    labels = {t.get_text() for t in ax_acc.get_legend().get_texts()}
    assert labels == {MARKER_LABELS["sweep"], MARKER_LABELS["unilateral"]}


def test_a_deck_sweep_that_sticks_everywhere_draws_a_linear_axis_without_a_warning():
    # every orbit stuck: peaks of 0 on a log axis printed matplotlib's "Data has no positive
    # values, and therefore cannot be log-scaled" on the command's stderr
    import io
    import warnings

    from nsdyn.plot.plane_sweep import plane_sweep_figure

    row = {"u_peak_m": 0.0, "uplift": False, "rim_contact": False, "converged": True,
           "stable": True, "method": "shooting", "stick_fraction": 1.0}  # fmt: skip
    rows = [{"f": f, **row} for f in (0.3, 0.6)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fig = plane_sweep_figure([{"A": 0.5, "rows": rows}], "stuck")
        fig.savefig(io.BytesIO(), format="png")  # (drawn: the axes scaled)
    assert fig.axes[0].get_yscale() == "linear"


def test_a_converged_point_between_two_gaps_is_drawn():
    # a point between two failed ones (no value) formed a segment of one point: neither line
    # nor marker drew it, though it converged
    rows = _rows()
    for row in rows:
        row["uplift"] = False
    for k in (1, 3):
        rows[k].update(IDR=float("nan"), a=float("nan"), x_iso=float("nan"))
    fig = sweep_figure([{"A": 1.0, "rows": rows}])
    for ax, key in zip(fig.axes, ("IDR", "a", "x_iso"), strict=True):
        assert (rows[2]["f"], rows[2][key]) in _markers(ax, ".")
        assert (rows[0]["f"], rows[0][key]) in _markers(ax, ".")  # (the first: a gap after it)


def test_a_path_given_as_the_fixed_base_curves_is_refused():
    # the second argument is the fixed-base responses, not a path (it failed inside the
    # drawing: "'in <string>' requires string as left operand, not float")
    with pytest.raises(TypeError, match=r"^fixed: expected a dict .* got str; save the figure"):
        sweep_figure([{"A": 1.0, "rows": []}], "sweep.png")


def test_a_rigid_frame_sweep_says_its_drift_is_zero_without_a_warning():
    # the rigid fidelity's IDR is 0 at every point: an empty log panel and matplotlib's "no
    # positive values" on stderr; now a linear, labelled panel
    import io
    import warnings

    rows = [{**r, "IDR": 0.0} for r in _rows()]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fig = sweep_figure([{"A": 0.5, "rows": rows}])
        fig.savefig(io.BytesIO(), format="png")
    ax = fig.axes[0]
    assert ax.get_yscale() == "linear"
    assert [t.get_text() for t in ax.texts] == [
        "isolated: IDR 0 at every point, the storeys do not deform (rigid)"
    ]
    assert fig.axes[2].get_yscale() == "log"  # (the others keep theirs)


def test_a_rigid_frame_sweep_beside_its_fixed_base_still_says_its_drift_is_zero():
    # the command line draws the fixed base's curves beside a frame's: its IDR panel then
    # held the fixed base's line alone, the isolated frame's zero unsaid
    import io

    rows = [{**r, "IDR": 0.0} for r in _rows()]
    f = np.array([r["f"] for r in rows])
    fixed = {0.5: {"f": f, "idr": 1e-3 * np.ones_like(f), "acc": np.ones_like(f)}}
    fig = sweep_figure([{"A": 0.5, "rows": rows}], fixed)
    fig.savefig(io.BytesIO(), format="png")
    ax = fig.axes[0]
    assert ax.get_yscale() == "log"  # (the fixed base's curve keeps its axis)
    assert [t.get_text() for t in ax.texts] == [
        "isolated: IDR 0 at every point, the storeys do not deform (rigid)"
    ]
