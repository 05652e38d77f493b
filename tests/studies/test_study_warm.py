"""A study of rocking, contact or cylinder scenes compiles its family's kernels once, in the
parent, before its workers start (``nsdyn.studies.scenes.warm_scene_kernels``).

What is asserted (behaviour, not timing): one warm-up per family and ``warm_key`` (the part of
a scene that selects the compiled code), none for other kinds, a faulty scene left to its own
check; and, into an empty numba cache, the family's first-compile notice printed once by a
whole ``nsdyn study`` on two workers (each worker printed it before: each compiled).
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from nsdyn.models.contact import scene as contact_scene
from nsdyn.models.rocking import scene as rocking_scene
from nsdyn.models.scenefile import SceneError
from nsdyn.studies.scenes import warm_scene_kernels
from nsdyn.studies.study import load_study
from nsdyn.studies.tasks import expand

ROOT = Path(__file__).resolve().parents[2]

ROCKING = """
[study]
name = "rocking-warm"

[base.scene]
kind = "rocking"
model = "{model}"

[base.block]
width = 0.4
height = 2.0

[base.motion]
pulse = "sine"
a_p_g = 1.0
f_p = 1.0
n_cycles = 1
t_end = 0.5

[parameters]
{parameters}
"""

ISOLATED = """
[study]
name = "isolated"

[base.scene]
fidelity = "rigid"

[base.motion]
pga = 3.0
t_end = 1.0

[parameters]
"isolation.mu" = [0.02, 0.05]
"""


def _tasks(tmp_path, parameters: str, model: str = "block"):
    p = tmp_path / f"{model}.toml"
    p.write_text(textwrap.dedent(ROCKING.format(parameters=parameters, model=model)))
    return expand(load_study(p))


def test_one_warm_up_per_family_and_kernel_key(tmp_path, monkeypatch):
    calls = []
    monkeypatch.setattr(rocking_scene, "warm_scene", lambda cfg, src: calls.append(cfg) or 0.0)
    pga = '"motion.a_p_g" = [0.6, 0.8]'
    tasks = _tasks(tmp_path, pga) + _tasks(tmp_path, pga, "compliant")  # two studies' tasks
    assert len(tasks) == 4
    assert warm_scene_kernels(tasks) == ["rocking", "rocking"]
    assert [c["scene"]["model"] for c in calls] == ["block", "compliant"]


@pytest.mark.parametrize("error", [SceneError, RuntimeError])
def test_other_kinds_are_not_warmed_here_and_a_faulty_scene_is_skipped(
    tmp_path, monkeypatch, error
):
    def faulty(cfg, src):  # a bad field, or a run that fails at once: the task's to report
        raise error(f"{src}: block.width: expected a positive number")

    monkeypatch.setattr(rocking_scene, "warm_scene", faulty)
    tasks = _tasks(tmp_path, '"motion.a_p_g" = [0.6, 0.8]')
    assert warm_scene_kernels(tasks) == []  # the task's own check reports the fault
    monkeypatch.setattr(contact_scene, "warm_scene", lambda cfg, src: pytest.fail("warmed"))
    iso = tmp_path / "iso.toml"
    iso.write_text(ISOLATED)
    assert warm_scene_kernels(expand(load_study(iso))) == []


@pytest.mark.slow  # a first compilation of the rocking kernel into an empty cache
def test_a_study_on_two_workers_compiles_its_family_once(tmp_path):
    study = tmp_path / "s.toml"
    pga = '"motion.a_p_g" = [0.6, 0.8]'
    study.write_text(textwrap.dedent(ROCKING.format(parameters=pga, model="block")))
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"), NUMBA_DISABLE_JIT="0")
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), env.get("PYTHONPATH")) if p)
    res = subprocess.run(
        [sys.executable, "-m", "nsdyn.cli", "study", str(study), "--workers", "2",
         "--out", str(tmp_path / "out"), "--no-figures"],
        env=env, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert res.returncode == 0, res.stderr
    assert res.stderr.count("compiling the rocking kernels") == 1, res.stderr
