"""A run interrupted after a chunk and resumed from its checkpoint is the same run.

Exact by construction: each chunk starts from the state, step, slip modes and open contacts
the previous one ended with, and the checkpoint carries all of them with the records so far
(steps, solver counters, lift-offs and landings, open contacts at the outputs, landing
energy). So the resumed histories equal the uninterrupted run's bit for bit, and so do its
counts. The system: the rigid block on two isolators of test_unilateral_contact.py, lifted
off by a vertical ground acceleration above g (flights of ~0.2 s), with friction events.
"""

from __future__ import annotations

import numpy as np
import pytest
from test_unilateral_contact import A_VER, F_VER, G, block

import nsdyn
from nsdyn.ground.excitation import Harmonic
from nsdyn.solve.checkpoint import Carry

MOTION = Harmonic(2.0, 1.3, A_ver=A_VER, f_ver=F_VER)  # horizontal too: slips and sticks
RUN = dict(t_end=1.6, dt_out=0.01, method="event", rtol=1e-8, chunk_s=0.4)


class Stop(Exception):
    pass


@pytest.mark.parametrize("contact", ["unilateral", "detect"])
def test_a_resumed_run_is_the_uninterrupted_run(tmp_path, contact):
    s = block("switch")
    kw = dict(RUN, contact=contact, uplift="warn")
    if contact == "detect":  # no lift-off: a vertical acceleration below g
        motion = Harmonic(2.0, 1.3, A_ver=0.5 * G, f_ver=F_VER)
    else:
        motion = MOTION
    whole = nsdyn.simulate(s, motion, **kw)
    ck = tmp_path / "ck.npz"
    done = []

    def stop_after_two(t, t_end, wall):
        done.append(t)
        if len(done) == 2:
            raise Stop

    with pytest.raises(Stop):
        nsdyn.simulate(s, motion, checkpoint=ck, progress=stop_after_two, **kw)
    resumed = nsdyn.simulate(s, motion, checkpoint=ck, **kw)
    assert np.array_equal(resumed.t, whole.t) and np.array_equal(resumed.x, whole.x)
    assert resumed.n_steps == whole.n_steps and resumed.stats == whole.stats
    assert resumed.contact_events == whole.contact_events
    a, b = resumed.summary(), whole.summary()
    for key in ("min_normal_force_N", "x_iso_max_m", "lift_offs", "first_lift_off_s",
                "flight_time_s", "n_steps"):  # fmt: skip
        if key in b:
            assert a[key] == b[key], key
    if contact == "unilateral":
        assert b["lift_offs"] > 0 and np.array_equal(resumed.open_contacts, whole.open_contacts)


def test_the_carried_state_survives_the_file():
    c = Carry(h0=1e-3, modes=np.array([1, 0]), open_end=np.array([0, 1]), n_steps=7,
              acc=np.array([0.5, -1.25]),
              stats={"nfev": 3}, uplifts=[(0.5, 1)], cevents=[(0.1, 0, "lift-off", 0.0, 0.0)],
              opens=[np.zeros((3, 2), dtype=np.int64)], impact=-2.5)  # fmt: skip
    d = Carry.from_arrays(_roundtrip(c.arrays()))
    assert d.h0 == c.h0 and np.array_equal(d.modes, c.modes)
    assert np.array_equal(d.open_end, c.open_end) and d.n_steps == 7
    assert np.array_equal(d.acc, c.acc)
    assert d.stats["nfev"] == 3 and d.uplifts == c.uplifts and d.cevents == c.cevents
    assert np.array_equal(d.opens[0], c.opens[0]) and d.impact == c.impact


def test_a_fixed_step_run_in_chunks_is_the_run_in_one_piece(monkeypatch):
    """Generalized-α's a_n is the scheme's own acceleration, not q̈(t_n) (the weighted mean
    (1 − α_m) a_{n+1} + α_m a_n is q̈ at the α point): a chunk that restarted from q̈ departed
    from the run in one piece by O(h²) at its first step. Carried on, the first step after the
    boundary is the same step; the next ones may reuse another Newton matrix (the chunk
    factors afresh), so they differ by what the Newton's stopping test lets through: a last
    scaled increment below NEWTON_TOL in RMS over 2n components, i.e. at most
    NEWTON_TOL·sqrt(2n)·(atol + rtol|x|) per component and step, in each of the two runs."""
    from nsdyn.models.isolated.scene import build_scene_run, load_scene
    from nsdyn.solve import checkpoint
    from nsdyn.solve._kgenalpha import NEWTON_TOL

    system, motion, _ = build_scene_run(load_scene())
    atol, rtol, n = (1e-6, 1e-5), 1e-6, system.n
    kw = dict(t_end=5.05, method="genalpha", dt=0.005, dt_out=0.005, rtol=rtol, atol=atol)
    one = nsdyn.simulate(system, motion, chunk_s=1e9, **kw)
    two = nsdyn.simulate(system, motion, chunk_s=5.0, **kw)
    k = int(np.searchsorted(one.t, 5.0))  # the boundary (both runs identical up to it)
    assert one.t[k] == 5.0 and np.array_equal(one.x[: k + 1], two.x[: k + 1])
    after = one.x[k + 1 :]
    steps = np.arange(1, after.shape[0] + 1)[:, None]
    tol = np.repeat(atol, n)[None, :] + rtol * np.abs(after)
    bound = 2.0 * steps * NEWTON_TOL * np.sqrt(2 * n) * tol
    assert np.all(np.abs(two.x[k + 1 :] - after) <= bound)
    # and the test can fail: restarted from q̈(t_n), the chunk leaves the bound at once
    take = checkpoint.Carry.take

    def forgetful(self, *args, **kw):
        take(self, *args, **kw)
        self.acc = None

    monkeypatch.setattr(checkpoint.Carry, "take", forgetful)
    restarted = nsdyn.simulate(system, motion, chunk_s=5.0, **kw)
    assert np.any(np.abs(restarted.x[k + 1] - after[0]) > 100.0 * bound[0])


def _roundtrip(arrays: dict):
    import io

    buf = io.BytesIO()
    np.savez(buf, **arrays)
    buf.seek(0)
    return np.load(buf)


@pytest.mark.parametrize("dt_out", [0.01, 0.03, 0.07])
def test_chunks_end_every_chunk_s_wherever_the_outputs_fall(dt_out):
    from nsdyn.solve.checkpoint import chunks

    t_eval = np.append(np.arange(0.0, 12.0, dt_out), 12.0)  # (the run's end, the last output)
    plan = chunks(t_eval, 0, 5.0)
    ends = [times[-1] for times, _, _ in plan]
    assert ends == [5.0, 10.0, 12.0]  # exactly: the grid does not move them by its round-off
    starts = [times[0] for times, _, _ in plan]
    assert starts == [0.0, *ends[:-1]]  # each chunk starts where the last one ended
    assert [a for _, a, _ in plan] == [1, *[b for _, _, b in plan[:-1]]]
    assert plan[-1][2] == t_eval.size  # every output once, in order
    for times, a, b in plan:  # the chunk's rows: its outputs, the last maybe its end
        np.testing.assert_allclose(times[1 : 1 + b - a], t_eval[a:b], rtol=0, atol=1e-9 * 5.0)
    # resumed after the first chunk: the same plan from there on
    again = chunks(t_eval, plan[0][2] - 1, 5.0, ends[0])
    assert [p[0].tolist() for p in again] == [p[0].tolist() for p in plan[1:]]


def test_a_damaged_checkpoint_is_one_error_naming_it(tmp_path):
    # a checkpoint cut short (a full disc, a copy interrupted) ended --resume in a traceback
    # (zipfile.BadZipFile); it is a CheckpointError (status 2) naming the file, as another
    # run's is
    from nsdyn.atomic import CheckpointError
    from nsdyn.solve import checkpoint

    path = tmp_path / "c.npz"
    t = np.linspace(0.0, 1.0, 11)
    checkpoint.save(path, t, np.zeros((11, 2)), "k", Carry())
    assert checkpoint.load(path, "k", t)[0].size == 11  # whole: it reads back
    data = path.read_bytes()
    for cut in (data[: len(data) // 2], b"", b"not a zip"):
        path.write_bytes(cut)
        with pytest.raises(CheckpointError, match=r"c\.npz: cannot be read") as e:
            checkpoint.load(path, "k", t)
        assert "\n" not in str(e.value)


def test_a_checkpoint_of_other_chunks_is_another_runs(tmp_path):
    # a run resumed on other chunks is not the run bit for bit (each chunk restarts its
    # step): it was taken, its histories a mix of both; it is refused as other settings are,
    # and a checkpoint given as no path is a TypeError naming it
    from nsdyn.atomic import CheckpointError

    s = block("switch")
    kw = dict(RUN, contact="unilateral", uplift="warn")
    ck = tmp_path / "ck.npz"
    done = []

    def stop_after_one(t, t_end, wall):
        done.append(t)
        raise Stop

    with pytest.raises(Stop):
        nsdyn.simulate(s, MOTION, checkpoint=ck, progress=stop_after_one, **kw)
    with pytest.raises(CheckpointError, match=r"written by another run \(.*chunk_s differ"):
        nsdyn.simulate(s, MOTION, checkpoint=ck, **(kw | {"chunk_s": 0.3}))
    # (the refused run leaves the checkpoint as it was: its own chunks resume it)
    saved = ck.read_bytes()
    with pytest.raises(CheckpointError):
        nsdyn.simulate(s, MOTION, checkpoint=ck, **(kw | {"chunk_s": 0.3}))
    assert ck.read_bytes() == saved
    resumed = nsdyn.simulate(s, MOTION, checkpoint=ck, **kw)
    assert np.array_equal(resumed.x, nsdyn.simulate(s, MOTION, **kw).x)
    with pytest.raises(TypeError, match=r"^checkpoint: expected a file's path, got int"):
        nsdyn.simulate(s, MOTION, checkpoint=123, **kw)
    with pytest.raises(ValueError, match=r"^chunk_s: expected a positive duration"):
        nsdyn.simulate(s, MOTION, **(kw | {"chunk_s": "5"}))
