"""``nsdyn bench opensees``: registered, and its quick run compares like with like.

The quick run (3 s of the bundled record) needs openseespy; it skips without it.
"""

from __future__ import annotations

import csv
import sys

import pytest

from nsdyn.bench import BENCHMARKS, load_benchmark
from nsdyn.models.isolated.opensees import OpenSeesUnavailable, load_opensees


def _has_opensees() -> bool:
    try:
        load_opensees()
    except OpenSeesUnavailable:
        return False
    return True


def test_registered():
    assert BENCHMARKS["opensees"] == "nsdyn.bench.opensees"
    assert callable(load_benchmark("opensees").run_bench)


@pytest.mark.skipif(not _has_opensees(), reason='openseespy not installed: "nsdyn[opensees]"')
def test_quick_run_rows_and_agreement(tmp_path):
    """Rows for OpenSees (modal and beta-K damping), nsdyn full (the reference of the
    differences), nsdyn with the export's damping (eps x1, x10) and CB-5. OpenSees against
    nsdyn with the same damping and the sharper arctan law agree within 1.5 % (the bound of
    tests/models/isolated/test_opensees_export.py, same model and window)."""
    res = load_benchmark("opensees").run_bench(tmp_path, True, repeats=1, quiet=True)
    rows = {r["run"]: r for r in res["rows"]}
    ref = rows["nsdyn full"]
    assert ref["d_x_iso_max"] == 0.0 and ref["n_dof"] == 435
    os_row = rows["OpenSees full"]
    same = next(r for k, r in rows.items() if k.startswith("nsdyn full, export's damping, eps"))
    for k in ("x_iso_max", "idr_max", "floor_acc_max"):
        assert os_row[k] == pytest.approx(same[k], rel=0.015)
    assert rows["nsdyn CB-5 (default radau)"]["n_dof"] == 13
    with open(res["csv"]) as fh:
        assert len(list(csv.DictReader(fh))) == len(rows)
    assert (tmp_path / "opensees_model_modal.py").is_file()


def test_without_opensees_says_how_to_install(tmp_path, monkeypatch):
    """An optional extra: without openseespy the benchmark returns no rows and the reason
    names the install command (``nsdyn bench all`` goes on)."""
    monkeypatch.setitem(sys.modules, "openseespy", None)
    monkeypatch.setitem(sys.modules, "openseespy.opensees", None)
    mod = load_benchmark("opensees")
    res = mod.run_bench(tmp_path, True, quiet=True)
    assert res["rows"] == [] and res["status"] == "unavailable"
    assert 'pip install "nsdyn[opensees]"' in mod.report(res)


def test_asked_for_by_name_without_opensees_it_exits_2(tmp_path, monkeypatch, capsys):
    # it ran nothing: a script must not read exit 0 (`nsdyn bench all` goes on without it)
    from nsdyn.cli import main

    monkeypatch.setitem(sys.modules, "openseespy", None)
    monkeypatch.setitem(sys.modules, "openseespy.opensees", None)
    for what in ("opensees", "opensees3d"):
        assert main(["bench", what, "--quick", "--json", "--out", str(tmp_path)]) == 2
        err = capsys.readouterr().err.strip()
        assert f"benchmark '{what}' did not run" in err and "nsdyn[opensees]" in err
        assert "\n" not in err
