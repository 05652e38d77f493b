"""``nsdyn spectrum`` end to end on the bundled seed 003 column.

Sources: a pulse below g tan α cannot lift the block (Housner 1963), so no overturning
amplitude ratio a_p/(g tan α) is below 1; the minimum overturning amplitude of one-sine pulses
grows with the pulse frequency ratio ω_p/p (Zhang & Makris 2001, Fig. 3).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from nsdyn.cli import main

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"


def test_spectrum_command_writes_a_physical_spectrum(tmp_path, capsys):
    scene = str(SCENES / "rocking-seed003-column.toml")
    argv = ["spectrum", scene, "--n", "3", "--wmin", "1.5", "--wmax", "6", "--rtol", "1e-3",
            "--workers", "1", "--out", str(tmp_path), "--json"]  # fmt: skip
    assert main(argv) == 0
    rep = json.loads(capsys.readouterr().out)
    # a success's JSON leads with status 0, as a failure's with its status
    assert next(iter(rep)) == "status" and rep["status"] == 0
    a = np.array(rep["a_min_ratio"], dtype=float)
    assert np.all(a >= 1.0)
    assert np.all(np.diff(a) > 0)
    assert Path(rep["csv"]).is_file() and Path(rep["figure"]).is_file()
    assert rep["compile_s"] >= 0.0  # the kernel compiled (or loaded) before the workers


def test_a_max_bounds_the_search_below_which_nothing_can_overturn(tmp_path, capsys):
    # --a-max 1: a pulse at or below g tan α cannot lift the block, so none of the
    # frequencies overturns within the search (each '> a_max'); the default (30) finds them
    scene = str(SCENES / "rocking-seed003-column.toml")
    argv = ["spectrum", scene, "--n", "2", "--wmin", "1.5", "--wmax", "3", "--workers", "1",
            "--no-figures", "--out", str(tmp_path), "--json"]  # fmt: skip
    old = tmp_path / "spectrum-rocking-seed003-column-sine.png"  # (an earlier run's: it goes)
    old.write_bytes(b"png")
    assert main([*argv, "--a-max", "1"]) == 0
    rep = json.loads(capsys.readouterr().out)
    assert not old.exists() and any(f"removed the earlier run's {old.name}" in n
                                    for n in rep["notes"])  # fmt: skip
    assert rep["search"]["a_max_ratio"] == 1.0 and rep["a_min_ratio"] == [None, None]
    assert set(rep["frequency_status"]) == {"no overturning up to a_max"}
    assert main(argv) == 0
    assert all(a > 1.0 for a in json.loads(capsys.readouterr().out)["a_min_ratio"])


def test_spectrum_announces_a_first_compilation(tmp_path, capsys, monkeypatch):
    # a cold cache: the rocking kernel compiles once, before the workers start, saying so on
    # stderr (stdout keeps the one JSON object)
    from nsdyn.models.rocking import scene as rocking_scene

    monkeypatch.setattr(rocking_scene, "kernels_cached", lambda model: False)
    scene = str(SCENES / "rocking-seed003-column.toml")
    argv = ["spectrum", scene, "--n", "2", "--wmin", "1.5", "--wmax", "3", "--rtol", "1e-2",
            "--workers", "1", "--no-figures", "--out", str(tmp_path), "--json"]  # fmt: skip
    assert main(argv) == 0
    out = capsys.readouterr()
    assert "compiling the rocking kernels once" in out.err
    assert json.loads(out.out)["compile_s"] > 0.0  # the warm-up's own time, apart


@pytest.mark.parametrize(
    "extra, needle",
    [(["--wmin", "5", "--wmax", "2"], "--wmax"), (["--workers", "0"], "--workers"),
     # a spectrum's frequency is a scan and bisection of pulse runs (not a periodic solve)
     (["--n", "100000000"], "--n: expected at most 10000 frequencies (each one a scan and "
      "bisection of pulse runs)")],
)  # fmt: skip
def test_spectrum_rejects_bad_flags(tmp_path, capsys, extra, needle):
    argv = ["spectrum", str(SCENES / "rocking-seed003-column.toml"), "--out", str(tmp_path)]
    try:  # (a count the parser refuses ends it with SystemExit, status 2 as well)
        status = main(argv + extra)
    except SystemExit as e:
        status = e.code
    assert status == 2
    assert needle in capsys.readouterr().err


def test_spectrum_rejects_a_scene_of_another_kind(tmp_path, capsys):
    scene = tmp_path / "c.toml"
    scene.write_text('[scene]\nkind = "cylinder"\n')
    assert main(["spectrum", str(scene), "--out", str(tmp_path)]) == 2
    assert "scene.kind" in capsys.readouterr().err


def test_spectrum_takes_the_scene_s_tolerance_and_names_its_unused_motion(tmp_path, capsys):
    # a scene's solver.tol of 1e-3 gave the spectrum of 1e-9 (the default) without a word,
    # and its [motion] (a record) was accepted without a remark
    scene = tmp_path / "col.toml"
    scene.write_text('[scene]\nkind = "rocking"\n[block]\nwidth = 0.6\nheight = 4.0\n'
                     '[motion]\nrecord = "synthetic-wn-40s"\n[solver]\ntol = 1e-7\n')  # fmt: skip
    argv = ["spectrum", str(scene), "--n", "2", "--wmin", "1.5", "--wmax", "3", "--workers",
            "1", "--no-figures", "--out", str(tmp_path / "o")]  # fmt: skip
    assert main([*argv, "--json"]) == 0
    rep = json.loads(capsys.readouterr().out)
    assert rep["search"]["tol"] == 1e-7
    assert rep["notes"] == [f"{scene}: [motion] not used: a spectrum drives the block with "
                            "one sine pulse per run (--shape), at the amplitudes and "
                            "frequencies it searches"]  # fmt: skip
    assert main(argv) == 0
    assert "nsdyn spectrum: note: " in capsys.readouterr().err
