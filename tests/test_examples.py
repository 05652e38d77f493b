"""The examples run and their numbers obey the physics they illustrate.

Each example exposes ``main()`` returning the numbers it prints; these tests import it.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def load_example(name: str):
    spec = importlib.util.spec_from_file_location(f"example_{name}", EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_api_tour_statics_and_ladder():
    out = load_example("api_tour").main(t_end=2.0)
    # the seed's dof counts (004 §3): 435 full, 13 Craig–Bampton at 5 Hz, 3 rigid (x, y, θ)
    assert out["dofs"]["full"] == 435 and out["dofs"]["cb"] == 13 and out["dofs"]["rigid"] == 3
    # vertical equilibrium: the two normal forces carry the building's weight (to round-off)
    assert np.sum(out["lam0"]) == pytest.approx(out["total_weight"], rel=1e-9)
    # the minimal-coordinate form (seed eqs 23–27) and the multiplier form agree
    assert out["minimal_agrees"]
    # energy balance (input = stored + viscous + friction): the closure error of the
    # trapezoidal power quadrature is second order in the output step, < 1 % at 10 ms
    assert out["summary"]["energy_closure"] < 1e-2


def test_readme_library_example_runs(monkeypatch):
    # the README's library snippet, as written, on a 2 s window of the record
    text = (EXAMPLES.parent / "README.md").read_text(encoding="utf-8")
    code = text.split("```python\n", 1)[1].split("```", 1)[0]
    assert "import nsdyn" in code
    code = code.replace(".scaled_to_pga(3.0)", ".scaled_to_pga(3.0).window(0.0, 2.0)")
    ns: dict = {}
    exec(compile(code, "README.md", "exec"), ns)  # noqa: S102
    assert ns["res"].summary()["energy_closure"] < 1e-2  # as in test_api_tour_…


def test_first_ten_minutes_coulomb_oscillator_decays_linearly_and_sticks():
    out = load_example("first_ten_minutes").main(figures=False)["coulomb"]
    # Coulomb damping (Den Hartog): each half cycle's peak is 2 μg/ω² below the previous one,
    # and the mass sticks once a turning point lies inside the dead band |x| ≤ μg/ω²
    x, d, band = out["x"], out["decrement_per_cycle_m"], out["dead_band_m"]
    a = np.abs(x)
    turning = [
        i for i in range(1, len(x) - 1) if a[i] > a[i - 1] and a[i] >= a[i + 1] and a[i] > band
    ]
    peaks = np.abs(x[turning])
    assert len(peaks) >= 2
    # a sampled turning point lies within dt/2 of the true one: low by at most
    # (1/2) |x''| (dt/2)^2 <= (1/2) w^2 max|x| (dt/2)^2 each; the event run's error (atol 1e-8
    # on displacements, rtol 1e-4 of 0.1 m) adds 1e-5 at most
    dt, w = out["t"][1] - out["t"][0], 2 * np.pi / out["period_s"]
    tol = 2 * 0.5 * w**2 * np.max(a) * (0.5 * dt) ** 2 + 1e-5
    assert np.allclose(np.diff(peaks), -d / 2, rtol=0.0, atol=tol)
    assert abs(out["x_final_m"]) <= out["dead_band_m"] * (1 + 1e-9)


def test_cold_compile_names_the_kernels_it_knows():
    # the benchmark compiles for minutes; a wrong kernel name must stop it before any run
    with pytest.raises(ValueError, match="kernel: expected one of"):
        load_example("cold_compile").main("no-such-kernel", pairs=1)


def test_bench_figures_copies_the_charts_under_the_names_the_docs_embed(tmp_path):
    # the rocking and contact benchmarks write rocking.png and contact-map.png; the docs embed
    # rocking-bench.png and contact-stability.png, which nothing wrote (the charts could not
    # be regenerated); tables not found are named
    mod = load_example("bench_figures")
    out, figs = tmp_path / "bench", tmp_path / "figs"
    out.mkdir()
    for name in ("rocking.png", "contact-map.png", "contact-wp.png"):
        (out / name).write_bytes(name.encode())
    res = mod.main(out, figs)
    assert (figs / "rocking-bench.png").read_bytes() == b"rocking.png"
    assert (figs / "contact-stability.png").read_bytes() == b"contact-map.png"
    assert (figs / "contact-wp.png").read_bytes() == b"contact-wp.png"
    assert sorted(res["copied"]) == sorted(
        str(figs / n) for n in ("rocking-bench.png", "contact-stability.png", "contact-wp.png")
    )  # (and said so)
    assert "periodic.csv (nsdyn bench periodic)" in res["missing"]
    docs = Path(__file__).resolve().parents[1] / "docs" / "guide"
    embedded = (docs / "rocking.md").read_text() + (docs / "contact.md").read_text()
    for name in set(mod.COPIED.values()) - {"stability.png"}:
        assert f"../figures/{name}" in embedded


def test_seed_transient_study_runs_every_case(tmp_path):
    # seed 004's transient study on the Kobe records (15 s each): every case runs, the fixed
    # base with no isolator displacement in its summary (it stopped the script with a
    # KeyError), the rigid superstructure with no drift (exact: its storeys do not deform)
    from nsdyn.ground import default_shared_dir

    shared = default_shared_dir()
    if shared is None or not (shared / "records").is_dir():
        pytest.skip("the shared records are not beside the project (set NSDYN_SHARED)")
    out = load_example("seed_transient_study").main(tmp_path, quick=True)["results"]
    for cases in out.values():
        assert "x_iso_max_m" not in cases["fixed"] and cases["isolated"]["x_iso_max_m"] > 0
        assert cases["rigid"]["idr_max"] == 0.0
    assert (tmp_path / "study_transient.json").is_file()


def test_every_name_an_example_imports_from_nsdyn_exists():
    # an example's imports inside its functions run only on use: a renamed helper
    # (nsdyn.cli.app._caused_by_interrupt, moved to nsdyn.atomic) broke one at its first run
    import ast
    import importlib

    missing = []
    for path in sorted(EXAMPLES.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] == "nsdyn":
                module = importlib.import_module(node.module)
                for a in node.names:
                    sub = f"{node.module}.{a.name}"
                    if not hasattr(module, a.name) and importlib.util.find_spec(sub) is None:
                        missing.append(f"{path.name}: {sub}")
            elif isinstance(node, ast.Import):
                for a in node.names:
                    if a.name.split(".")[0] == "nsdyn":
                        importlib.import_module(a.name)
    assert missing == []


@pytest.mark.parametrize(
    ("argv", "env", "said"),
    [
        # a file as --out: a traceback (status 1) after the first model had run
        (["first_ten_minutes.py", "--out", "README.md"], {},
         "argument --out: 'README.md' exists and is not a directory"),
        # an empty benchmark folder: said with status 0
        (["bench_figures.py", "empty", "--figures", "figs"], {},
         "empty: no benchmark tables or charts to redraw from"),
        # records missing: status 1, asking to set an NSDYN_SHARED that was set
        (["seed_transient_study.py", "--quick", "--out", "o"], {"NSDYN_SHARED": "none"},
         "NSDYN_SHARED = 'none' is no folder"),
        # past the record's end: cut to it without a word, titled 0-100 s
        (["bench_building3d_full.py", "--t-end", "100"], {},
         "argument --t-end: the record synthetic-wn-40s spans 40 s; expected at most that"),
    ],
)  # fmt: skip
def test_an_example_refuses_bad_input_in_one_line_with_status_2(tmp_path, argv, env, said):
    import os
    import subprocess
    import sys

    (tmp_path / "README.md").write_text("a file")
    (tmp_path / "empty").mkdir()
    cmd = [sys.executable, str(EXAMPLES / argv[0]), *argv[1:]]
    r = subprocess.run(cmd, cwd=tmp_path, env={**os.environ, **env}, capture_output=True,
                       text=True, timeout=120)  # fmt: skip
    assert r.returncode == 2 and said in r.stderr and "Traceback" not in r.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["README.md", "empty"]  # none made
