"""``nsdyn bench periodic``: reference orbits converge, finer settings are more accurate."""

from __future__ import annotations

import csv

from nsdyn.bench import periodic
from nsdyn.cli import bench as command


def test_bench_periodic_quick_end_to_end(tmp_path, capsys):
    """``nsdyn bench periodic --quick``: the reference orbits converge (twice the steps
    changes x_bar_iso and IDR by < 1e-6; the radau period through the reference orbit closes
    to < 1e-6), more steps per period make shooting more accurate, a tighter steady-state
    tolerance makes the sweep more accurate, and the CSV and figure are written."""
    out = tmp_path / "bench"
    assert command.main(["periodic", "--quick", "--out", str(out)]) == 0
    rows = list(csv.DictReader(open(out / "periodic.csv")))
    cells = {(r["A_mps2"], r["f_hz"]) for r in rows}
    assert len(cells) == len(periodic.QUICK_PERIODIC_CELLS)
    for cell in cells:
        mine = {
            (r["label"], float(r["value"])): r for r in rows if (r["A_mps2"], r["f_hz"]) == cell
        }
        chk = mine[("reference-check", periodic.PERIODIC_CHECK[1])]
        ref = mine[("reference", periodic.PERIODIC_REF[1])]
        assert chk["status"] == ref["status"] == "ok"
        assert float(chk["err_xbar"]) < 1e-6 and float(chk["err_idr"]) < 1e-6
        assert float(ref["closure"]) < 1e-6
        for label in ("shooting sdirk2", "sweep sdirk2"):
            pts = sorted((float(v), r) for (lab, v), r in mine.items() if lab == label)
            assert all(r["status"] == "ok" for _, r in pts)
            errs = [float(r["err_xbar"]) + float(r["err_idr"]) for _, r in pts]
            # shooting: more steps (larger value) is better; sweep: smaller tol is better
            assert (errs[-1] < errs[0]) if label.startswith("shooting") else (errs[0] < errs[-1])
    assert (out / "periodic.png").exists() and not list(out.glob(".*"))
    assert "worst err x̄_iso" in capsys.readouterr().out
