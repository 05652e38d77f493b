"""The printed table of ``nsdyn bench scale3d``: what it may conclude from the runs it has.

Its quick variant runs two sizes over 1 s of the record. It printed a cost exponent of
-0.25 (a line through two noisy points) and a 39 % difference in u_iso between two peaks
of 35 and 58 µm, both on OpenSees' elastic stick branch (slip below STICK_DISP = 0.1 mm):
the bearings never slid.
"""

from __future__ import annotations

from nsdyn.bench.scale3d import FIT_MIN_SIZES, PEAKS, report
from nsdyn.models.isolated.opensees import STICK_DISP


def _rows(u_iso: float) -> list[dict]:
    base = {"whole_process_s": 2.0, "run_s": 1.0, "peak_rss_mb": 200.0}
    peaks = {k: 1e-3 for k in PEAKS} | {"peak_resultant_displacement_m": u_iso}
    return [{**base, **peaks, "tool": "nsdyn", "n_dof": 2712}]


def test_no_exponent_from_fewer_sizes_and_a_stick_only_window_is_said():
    out = report({"rows": _rows(0.5 * STICK_DISP), "fits": {}})
    assert f"no cost exponent: fitted from {FIT_MIN_SIZES} sizes or more" in out
    assert "the isolators did not slide" in out
    # a window where they slid (past the stick branch) and a fit: neither line
    out = report({"rows": _rows(2 * STICK_DISP), "fits": {"nsdyn": 1.0}})
    assert "did not slide" not in out and "no cost exponent" not in out
    assert "fitted exponent (nsdyn, whole process): 1.00" in out


def test_rows_carry_the_coordinates_and_isolators_the_docs_table_gives():
    # the docs' table gave "dofs (sparse system's coordinates)" and "isolators", which the
    # CSV lacked: the coordinates are the nsdyn child's, the isolators one per column line
    from nsdyn.bench.scale3d import SIZES, _rows, building_of_size

    size = SIZES[0]
    run = {"whole_process_s": 2.0, "run_s": 1.0, "hwm_mb": 100.0, **{k: 1e-3 for k in PEAKS}}
    rows = _rows({(size, "nsdyn"): [{**run, "n": 1788}], (size, "opensees"): [run]}, 1.0, 1, True)
    frame = building_of_size(*size)
    for r in rows:
        assert r["n"] == 1788 and r["isolators"] == len(frame.base_nodes) == (5 + 1) * (1 + 1)
        assert r["size"] == "x".join(map(str, size)) and r["n_dof"] == frame.n_dof
