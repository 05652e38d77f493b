"""The first-run notice of the rocking, contact and cylinder scene runners.

What is asserted (the behaviour, not a timing): the line ``compiling the <family> kernels once
(about N s; cached afterwards)…`` is on stderr *before* the first call of the family's kernels
when they are not in numba's cache, followed by the compile time; nothing when they are; the
"is cached" probe of each family says False in a process with an empty ``NUMBA_CACHE_DIR``
and True once the kernels ran; the summary reports ``compile_s`` apart from ``wall_s``.
"""

from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "examples" / "scenes"


def _rocking():
    return {"scene": {"kind": "rocking", "model": "block"},
            "block": {"width": 0.4, "height": 2.0}, "motion": {"t_end": 0.05}}  # fmt: skip


def _contact():
    return {"scene": {"kind": "contact"}, "body": {"width": 1.1, "height": 1.0, "mass": 1.0},
            "friction": {"mu_s": 0.5}, "motion": {"t_end": 0.05}}  # fmt: skip


def _cylinder():
    return {"scene": {"kind": "cylinder"}, "motion": {"duration": 0.1}}


FAMILIES = {"rocking": _rocking, "contact": _contact, "cylinder": _cylinder}
# the function of each runner that makes the first (compiling) call of the kernels
FIRST_CALL = {
    "rocking": ("nsdyn.models.rocking.block", "warmup"),
    "contact": ("nsdyn.models.contact.scene", "simulate"),
    "cylinder": ("nsdyn.models.cylinder.scene", "simulate"),
}


def _scene(family):
    return importlib.import_module(f"nsdyn.models.{family}.scene")


@pytest.mark.parametrize("family", FAMILIES)
def test_notice_before_the_first_compilation(family, monkeypatch, capsys, tmp_path):
    mod = _scene(family)
    monkeypatch.setattr(mod, "kernels_cached", lambda *a: False)  # as with an empty cache
    where, name = FIRST_CALL[family]
    owner = importlib.import_module(where)
    real, seen = getattr(owner, name), []

    def first_call(*a, **kw):
        if not seen:  # what stderr holds when the kernels are first called
            seen.append(capsys.readouterr().err)
        return real(*a, **kw)

    monkeypatch.setattr(owner, name, first_call)
    s = mod.run_scene(FAMILIES[family](), source="t.toml", out_dir=tmp_path, figures=False,
                      quiet=True)  # fmt: skip
    head = f"compiling the {family} kernels once (about {mod.COMPILE_ABOUT_S:.0f} s; cached "
    assert seen and head in seen[0] and "afterwards)…" in seen[0]
    assert "compiled in" in capsys.readouterr().err  # then how long it took
    assert s["compile_s"] > 0.0 and s["wall_s"] > 0.0  # each timed, apart


@pytest.mark.parametrize("family", FAMILIES)
def test_no_notice_when_the_kernels_are_ready(family, capsys, tmp_path):
    mod = _scene(family)
    cfg = FAMILIES[family]
    mod.run_scene(cfg(), source="t.toml", out_dir=tmp_path, figures=False, quiet=True)
    capsys.readouterr()
    # the probe itself (not a mock): the kernels ran in this process
    mod.run_scene(cfg(), source="t.toml", out_dir=tmp_path, figures=False, quiet=False)
    assert "compiling the" not in capsys.readouterr().err


def _env(cache: Path) -> dict:
    # the JIT on in the child whatever this run's mode (under NUMBA_DISABLE_JIT=1 nothing
    # compiles, so no probe could say "not cached")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), NUMBA_DISABLE_JIT="0")
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), env.get("PYTHONPATH")) if p)
    return env


PROBES = """
import json
from nsdyn.models.contact.scene import build as contact_build, kernels_cached as contact
from nsdyn.models.cylinder.scene import build as cylinder_build, kernels_cached as cylinder
from nsdyn.models.rocking.scene import build_model, kernels_cached as rocking
from nsdyn.models.rocking.compliant import CompliantBlock
rock = build_model({"block": {"width": 0.4, "height": 2.0}}, "t.toml")
comp = CompliantBlock.from_frequency(width=0.4, height=2.0, mass=1.0, omega_v=300.0, zeta=2.0)
opts = contact_build({"scene": {"kind": "contact"}, "body": {"width": 1.0, "height": 1.0},
                      "friction": {"mu_s": 0.5}}, "t.toml")[4]
out = {"rocking": rocking(rock), "rocking-compliant": rocking(comp),
       "contact-event": contact(opts), "contact-moreau": contact(dict(opts, method="moreau")),
       "cylinder": cylinder(cylinder_build({"scene": {"kind": "cylinder"},
                                            "motion": {"duration": 0.1}}, "t.toml")[0])}
print(json.dumps(out))
"""


def test_probes_say_not_cached_with_an_empty_cache(tmp_path):
    # a fresh process with an empty NUMBA_CACHE_DIR: nothing of any family is compiled yet
    res = subprocess.run([sys.executable, "-P", "-c", PROBES], env=_env(tmp_path),
                         capture_output=True, text=True, timeout=300)  # fmt: skip
    assert res.returncode == 0, res.stderr
    probes = json.loads(res.stdout.strip().splitlines()[-1])
    assert probes == dict.fromkeys(probes, False) and len(probes) == 5


SCENE_FILES = {
    "rocking": ("rocking-seed001-cask.toml", []),
    "contact": ("contact-seed002-A5.toml", ["--t-end", "1"]),
    "cylinder": ("cylinder-uplift.toml", ["--t-end", "1"]),
}


@pytest.mark.slow  # a first compilation of the family's kernels into an empty cache
@pytest.mark.parametrize("family", SCENE_FILES)
def test_nsdyn_run_announces_only_a_first_compilation(family, tmp_path):
    # two `nsdyn run --json` processes sharing one empty numba cache: the first compiles and
    # says so on stderr before it does, the second loads the cache and says nothing
    scene, extra = SCENE_FILES[family]
    cmd = [sys.executable, "-P", "-m", "nsdyn.cli", "run", str(SCENES / scene), *extra,
           "--json", "--no-figures", "--out", str(tmp_path / "out")]  # fmt: skip
    env = _env(tmp_path / "numba")
    runs = [subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=900)
            for _ in range(2)]  # fmt: skip
    for r in runs:
        assert r.returncode == 0, r.stderr
    first, second = (json.loads(r.stdout) for r in runs)
    assert f"compiling the {family} kernels once (about" in runs[0].stderr
    assert "compiling the" not in runs[1].stderr
    # compiling does all that loading does and more: seconds against a tenth of one
    assert first["compile_s"] > second["compile_s"] > 0.0
