"""``nsdyn uplift``: table, JSON and figure of the uplift boundary; scene errors name the field.

The subcommand is driven through its own ``configure``/``run`` pair (the command table of
``nsdyn.cli.app`` only dispatches to them).
"""

from __future__ import annotations

import argparse
import json

from nsdyn.cli import uplift as cli_uplift


def run_cli(argv: list[str]) -> int:
    p = argparse.ArgumentParser(prog="nsdyn uplift")
    cli_uplift.configure(p)
    return cli_uplift.run(p.parse_args(argv))


def test_json_lists_every_frequency_and_writes_the_files(tmp_path, capsys):
    out = tmp_path / "o"
    rc = run_cli(["--fmin", "0.06", "--fmax", "2", "--points", "2", "--json", "--out", str(out)])
    assert rc == 0
    rep = json.loads(capsys.readouterr().out)  # stdout holds one JSON object only
    assert json.loads((out / "uplift.json").read_text()) == rep
    # a success's JSON leads with status 0, as a failure's with its status
    assert next(iter(rep)) == "status" and rep["status"] == 0
    assert (out / "uplift.png").stat().st_size > 0
    pts = rep["points"]
    assert [p["f_hz"] for p in pts] == [0.06, 2.0]
    # at the isolation frequency the margin reaches zero inside the bracket; above it the
    # friction caps the base shear (no uplift up to a_max) - or the point says why not
    for p in pts:
        if p["status"] == "ok":
            assert p["a_below"] < p["a_crit"] <= p["a_above"] <= rep["a_hi"]
            assert p["min_normal_force_below_N"] > 0 >= p["min_normal_force_above_N"]
        else:
            assert p["a_crit"] is None and p["status"]
    assert pts[0]["status"] == "ok"
    assert rep["compile_s"] >= 0.0 and rep["wall_s"] > 0.0  # the compilation reported apart


def test_first_use_announces_the_periodic_kernels(tmp_path, capsys, monkeypatch):
    # a cold cache: the periodic kernels compile before the boundary search, saying so on
    # stderr (stdout keeps the one JSON object)
    from nsdyn.periodic import problem

    monkeypatch.setattr(problem, "kernels_cached", lambda: False)
    rc = run_cli(["--fmin", "2", "--fmax", "3", "--points", "2", "--a-max", "0.2", "--json",
                  "--no-figures", "--out", str(tmp_path)])  # fmt: skip
    assert rc == 0
    out = capsys.readouterr()
    assert "compiling the periodic kernels (first use only, cached afterwards)" in out.err
    assert json.loads(out.out)["compile_s"] > 0.0  # the warm-up's own time, apart


def test_table_prints_one_row_per_frequency(tmp_path, capsys):
    rc = run_cli(["--fmin", "1", "--fmax", "2", "--points", "2", "--a-max", "2", "--out",
                  str(tmp_path), "--no-figures"])  # fmt: skip
    assert rc == 0
    text = capsys.readouterr().out
    rows = [ln for ln in text.splitlines() if ln.strip().startswith(("1 ", "2 "))]
    assert len(rows) == 2 and all("no uplift up to A = 2 m/s²" in r for r in rows)
    assert not (tmp_path / "uplift.png").exists()


def test_fixed_base_scene_is_refused_with_the_field(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text('[scene]\nfidelity = "fixed"\n')
    assert run_cli([str(scene), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "s.toml" in err and "scene.fidelity" in err


def test_reversed_frequency_range_is_a_user_error(tmp_path, capsys):
    assert run_cli(["--fmin", "2", "--fmax", "1", "--out", str(tmp_path)]) == 2
    assert "--fmax" in capsys.readouterr().err


def test_the_data_is_written_without_json_and_without_figures(tmp_path, capsys):
    # only the figure was written without --json, nothing at all with --no-figures too; an
    # earlier run's figure goes (it sat beside the new data, drawn for other settings)
    out = tmp_path / "o"
    out.mkdir()
    (out / "uplift.png").write_bytes(b"an earlier run's")
    rc = run_cli(["--fmin", "0.5", "--fmax", "1", "--points", "2", "--no-figures",
                  "--out", str(out)])  # fmt: skip
    assert rc == 0
    rep = json.loads((out / "uplift.json").read_text())
    assert [p["f_hz"] for p in rep["points"]] == [0.5, 1.0]
    said = capsys.readouterr()
    assert f"data:   {out / 'uplift.json'}" in said.out
    assert "removed the earlier run's uplift.png" in said.err
    assert not (out / "uplift.png").exists()


def test_a_failed_frequency_makes_the_status_3_and_names_it(tmp_path, capsys, monkeypatch):
    # a boundary with a hole is not a success (exit 3, as a study with failed tasks), yet
    # every frequency's row and the data file are written; "no uplift" is an answer, not a
    # failure
    import math

    from nsdyn.periodic import uplift as up

    def fake(system, freqs, a_lo, a_hi, progress=None, **kw):
        pts = [
            up.UpliftPoint(f=freqs[0], a_crit=1.0, status=up.STATUS_OK, a_below=0.9,
                           a_above=1.0, g_below=1.0, g_above=0.0, shootings=3, sweeps=0,
                           rho_max=math.nan, wall_s=0.0),
            up.UpliftPoint(f=freqs[1], a_crit=math.nan, status=up.STATUS_NO_UPLIFT,
                           a_below=a_hi, a_above=math.inf, g_below=1.0, g_above=math.nan,
                           shootings=3, sweeps=0, rho_max=math.nan, wall_s=0.0),
            up.UpliftPoint(f=freqs[2], a_crit=math.nan, status="shooting failed at A=2: x",
                           a_below=1.0, a_above=math.inf, g_below=1.0, g_above=math.nan,
                           shootings=3, sweeps=0, rho_max=math.nan, wall_s=0.0),
        ]  # fmt: skip
        return up.UpliftBoundary(pts, "fake", 1.0, a_lo, a_hi, 1e-3)

    monkeypatch.setattr(up, "uplift_boundary", fake)
    out = tmp_path / "o"
    rc = run_cli(["--fmin", "1", "--fmax", "4", "--points", "3", "--no-figures",
                  "--out", str(out)])  # fmt: skip
    assert rc == 3
    err = capsys.readouterr().err
    assert err.count("1 of 3 frequencies failed (f = 4 Hz") == 1
    saved = json.loads((out / "uplift.json").read_text())
    assert len(saved["points"]) == 3
    # the file and --json carry the status and its line (the file was written before them)
    assert saved["status"] == 3 and saved["error"].startswith("1 of 3 frequencies failed")
    rc = run_cli(["--fmin", "1", "--fmax", "4", "--points", "3", "--no-figures", "--json",
                  "--out", str(out)])  # fmt: skip
    printed = json.loads(capsys.readouterr().out.splitlines()[-1])
    assert rc == 3 and (printed["status"], printed["error"]) == (3, saved["error"])


def test_an_amplitude_above_100_g_is_refused_before_any_work(tmp_path, capsys):
    # --a-max 1e30 was searched (the other commands refuse ground accelerations above 100 g)
    assert run_cli(["--a-max", "1e30", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith("argument --a-max: expected ground acceleration amplitudes <= 1000 m/s² "
                        "(100 g), got 1e+30 (see nsdyn uplift --help)")  # fmt: skip
    assert len(err.splitlines()) == 1
    assert not (tmp_path / "o").exists()
