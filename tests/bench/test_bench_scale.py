"""``nsdyn bench scale``: the buildings of any size it measures and its cost fit."""

import numpy as np
import pytest

from nsdyn.bench import BENCHMARKS, load_benchmark
from nsdyn.bench.scale import SIZES, fit_exponent, scale_frame


def _nodes(bays, n_h, n_v, storeys=11):
    # regular_frame's numbering: the base's column feet, then per storey the inner column
    # nodes (n_v - 1 per column) and the beam line (n_h per bay, plus one)
    return (bays + 1) + storeys * ((bays + 1) * (n_v - 1) + bays * n_h + 1)


def test_sizes_span_the_office_to_twenty_thousand_dofs():
    assert scale_frame(*SIZES[0]).n_dof == 435  # the office frame itself
    for size in SIZES[1:]:
        assert scale_frame(*size).n_dof == 3 * _nodes(*size)
    assert 3 * _nodes(*SIZES[-1]) >= 20_000


def test_wider_frames_carry_the_office_per_bay():
    # The floor masses scale with the bays; the members add rho_A times their lengths:
    # total mass = bays x office floors + sum(rho_A L) (exact to round-off).
    office = scale_frame(*SIZES[0])
    f = scale_frame(3, 6, 6)
    floors = office.total_mass - float(np.sum(office.rho_A * office.lengths))
    members = float(np.sum(f.rho_A * f.lengths))
    assert f.total_mass == pytest.approx(3 * floors + members, rel=1e-12)
    assert np.allclose(f.storey_heights, office.storey_heights)


def test_fit_recovers_a_power_law():
    # wall = a n^p sampled exactly: least squares in log-log returns p and a to round-off
    n = np.array([435.0, 1593.0, 4635.0, 20520.0])
    p, a = fit_exponent(n, 3e-4 * n**1.1)
    assert p == pytest.approx(1.1, rel=1e-12) and a == pytest.approx(3e-4, rel=1e-9)


def test_registered():
    assert BENCHMARKS["scale"] == "nsdyn.bench.scale"
    assert callable(load_benchmark("scale").run_bench)


@pytest.mark.slow
def test_quick_run_writes_its_files(tmp_path):
    # the quick bench: two sizes, every tool (OpenSees when installed), CSV and PNG written;
    # with OpenSees, nsdyn's full model with OpenSees' damping within 2 % of OpenSees' peaks
    # (the scale target of the full-models page: the same model and step, so what remains is
    # the regularised law against OpenSees' elastic stick and Newmark's period error)
    import importlib.util

    res = load_benchmark("scale").run_bench(tmp_path, True, quiet=True)
    assert (tmp_path / "scale.csv").is_file() and (tmp_path / "scale.png").is_file()
    rows = [r for r in res["rows"] if r["tool"] == "stiffness" and "d_x_iso_max" in r]
    if importlib.util.find_spec("openseespy") is not None:
        assert rows  # one comparison per size
    for r in rows:
        assert abs(r["d_x_iso_max"]) < 0.02


def test_no_exponent_from_two_sizes():
    # --quick runs two sizes, through which any power law passes: it printed "run ~ n^0.03"
    from nsdyn.bench.scale import FIT_MIN_SIZES, _fits, report

    rows = [{"tool": "stiffness", "n_dof": n, "run_s": 1.0, "whole_process_s": 2.0,
             "run": "x", "peak_rss_mb": 1.0} for n in (435, 1593)]  # fmt: skip
    res = {"rows": rows, "fits": _fits(rows)}
    assert FIT_MIN_SIZES == 3 and res["fits"] == {}
    assert "no cost exponent: fitted from 3 sizes or more" in report(res)
    assert set(_fits([*rows, {**rows[0], "n_dof": 4635}])) == {"stiffness"}
