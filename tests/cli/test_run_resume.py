"""A run's checkpoint is continued only by the same run: the scene, the fidelity and the ground
motion's samples (a record edited since the interruption changes the run, not the scene)."""

import dataclasses
import json

import numpy as np
import pytest

from nsdyn.cli.run_resume import CHECKPOINT, IDENTITY, open_checkpoint, run_identity
from nsdyn.ground import GroundMotion
from nsdyn.models.scenefile import SceneError

CFG = {"scene": {"fidelity": "rigid"}, "motion": {"record": "r.csv"}}


def _interrupted(out, motion):
    """A folder as an interrupted run of ``motion`` leaves it: a checkpoint to t = 0.01 s and
    the settings it was run with."""
    np.savez(out / CHECKPOINT, t=np.array([0.0, 0.01]))
    (out / IDENTITY).write_text(json.dumps(run_identity(CFG, None, motion)))


def test_a_record_edited_since_the_checkpoint_is_refused_before_resuming(tmp_path, capsys):
    # the scene was the same, so the run said "resuming from t = 0.01 s" and then refused
    m = GroundMotion(t0=0.0, dt=0.01, a_hor=np.array([0.0, 1.0, 0.0]), name="r")
    _interrupted(tmp_path, m)
    edited = dataclasses.replace(m, a_hor=np.array([0.0, 2.0, 0.0]))
    with pytest.raises(SceneError, match=r"other settings \(differing: the record's samples\)"):
        open_checkpoint(tmp_path, run_identity(CFG, None, edited), resume=True, quiet=False)
    assert "resuming" not in capsys.readouterr().err
    # the same samples under another name and header: the same run, resumed
    renamed = dataclasses.replace(m, name="other", meta={"title": "x"})
    *_, t = open_checkpoint(tmp_path, run_identity(CFG, None, renamed), resume=True, quiet=False)
    assert t == 0.01 and "resuming from t = 0.01 s" in capsys.readouterr().err


def test_a_checkpoint_of_other_settings_names_them_as_scene_fields(tmp_path):
    # it named the identity's keys: "differing: fidelity, scene.scene.fidelity, scene.solver.
    # method", two of them names no user typed
    m = GroundMotion(t0=0.0, dt=0.01, a_hor=np.array([0.0, 1.0, 0.0]), name="r")
    np.savez(tmp_path / CHECKPOINT, t=np.array([0.0, 0.01]))
    old = {**CFG, "scene": {**CFG["scene"], "fidelity": "cb"}, "solver": {"rtol": 1e-6}}
    (tmp_path / IDENTITY).write_text(json.dumps(run_identity(old, "cb", m)))
    new = {**old, "scene": {**CFG["scene"], "fidelity": "full"},
           "solver": {"rtol": 1e-6, "method": "radau"}}  # fmt: skip
    with pytest.raises(SceneError, match=r"\(differing: scene.fidelity, solver.method\); "):
        open_checkpoint(tmp_path, run_identity(new, "full", m), resume=True, quiet=True)


def test_a_checkpoint_of_an_older_nsdyn_is_said_to_be_one(tmp_path):
    # its settings had no motion samples: "differing: motion" blamed a record not edited
    m = GroundMotion(t0=0.0, dt=0.01, a_hor=np.array([0.0, 1.0, 0.0]), name="r")
    np.savez(tmp_path / CHECKPOINT, t=np.array([0.0, 0.01]))
    (tmp_path / IDENTITY).write_text(json.dumps(run_identity(CFG, None)))
    with pytest.raises(SceneError, match=r"other settings \(an older nsdyn\)"):
        open_checkpoint(tmp_path, run_identity(CFG, None, m), resume=True, quiet=True)


def test_a_damaged_checkpoint_is_said_to_be_one(tmp_path):
    # an identity file cut or garbled was blamed on "other settings (an older nsdyn)"
    np.savez(tmp_path / CHECKPOINT, t=np.array([0.0, 0.01]))
    for text in ("garbage", '{"scene": '):
        (tmp_path / IDENTITY).write_text(text)
        with pytest.raises(SceneError, match=r": the checkpoint there is unreadable \("):
            open_checkpoint(tmp_path, run_identity(CFG, None), resume=True, quiet=True)
    (tmp_path / IDENTITY).unlink()
    with pytest.raises(SceneError, match=r"missing, damaged or cut\); run without --resume"):
        open_checkpoint(tmp_path, run_identity(CFG, None), resume=True, quiet=True)


def test_a_discarded_or_missing_checkpoint_is_a_note_of_a_quiet_run(tmp_path, capsys):
    # --json (quiet) said neither: the interrupted run's checkpoint went without a word
    m = GroundMotion(t0=0.0, dt=0.01, a_hor=np.array([0.0, 1.0, 0.0]), name="r")
    _interrupted(tmp_path, m)
    notes: list = []
    open_checkpoint(tmp_path, run_identity(CFG, None, m), resume=False, quiet=True, notes=notes)
    assert not (tmp_path / CHECKPOINT).exists() and capsys.readouterr().err == ""
    assert len(notes) == 1 and notes[0].startswith("starting afresh; the checkpoint an ")
    open_checkpoint(tmp_path, run_identity(CFG, None, m), resume=True, quiet=True, notes=notes)
    assert notes[1] == f"--resume: no checkpoint in {tmp_path}; the run starts at the beginning"
