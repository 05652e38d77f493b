"""A signal during a chunk of a checkpointed run stops it after that chunk's checkpoint.

What is asserted (behaviour): a compiled chunk cannot be stopped inside, and the signal was
raised as the chunk returned, before its checkpoint was written, so an interrupt waited for the
chunk and then lost it (a resume started where the last checkpoint had; two interrupts and two
resumes made no progress). Now the chunk's result and checkpoint are kept, then the signal
stops the run (KeyboardInterrupt, as before), and the resume ends as the uninterrupted run did,
to the bit (the same steps: a chunk boundary carries the solver's next step).
"""

from __future__ import annotations

import os
import signal
import threading

import numpy as np
import pytest

import nsdyn
from nsdyn.solve import integrate
from nsdyn.solve.checkpoint import holding_signals

pytestmark = pytest.mark.skipif(
    threading.current_thread() is not threading.main_thread(),
    reason="signal handlers are set in the main thread only",
)


@pytest.fixture(autouse=True)
def _interruptible():
    # Python's own Ctrl-C handler, whatever this process inherited (a test run started in the
    # background of a shell without job control has SIGINT ignored, and an ignored signal is
    # left ignored by the hold, by design)
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, old)


def test_a_signal_inside_the_hold_is_raised_as_it_ends():
    seen = []
    with pytest.raises(KeyboardInterrupt):
        with holding_signals():
            os.kill(os.getpid(), signal.SIGINT)
            seen.append("after the signal")  # (still running: held)
    assert seen == ["after the signal"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored


def test_nothing_is_held_without_a_checkpoint_or_when_ignored_and_sigterm_comes_first():
    # without a checkpoint holding gains nothing: a SIGTERM waited for a whole chunk; an
    # ignored SIGINT was recorded and raised; a SIGTERM held beside a SIGINT was dropped
    seen = []
    with pytest.raises(KeyboardInterrupt):
        with holding_signals(False):
            os.kill(os.getpid(), signal.SIGINT)
            seen.append("not reached")
    assert seen == []
    old_int = signal.signal(signal.SIGINT, signal.SIG_IGN)
    old_term = signal.signal(signal.SIGTERM, lambda s, f: seen.append("term"))
    try:
        with holding_signals():
            os.kill(os.getpid(), signal.SIGINT)  # ignored, as it was
        assert signal.getsignal(signal.SIGINT) == signal.SIG_IGN and seen == []
        signal.signal(signal.SIGINT, signal.default_int_handler)
        with pytest.raises(KeyboardInterrupt):
            with holding_signals():
                os.kill(os.getpid(), signal.SIGINT)
                os.kill(os.getpid(), signal.SIGTERM)
        assert seen == ["term"]  # raised first, then the interrupt
    finally:
        signal.signal(signal.SIGINT, old_int)
        signal.signal(signal.SIGTERM, old_term)


def test_an_interrupted_chunk_is_checkpointed_before_the_run_stops(tmp_path, monkeypatch):
    dt = 0.01
    t = np.arange(0.0, 12.0 + dt / 2, dt)
    gm = nsdyn.GroundMotion(0.0, dt, 3.0 * np.sin(2 * np.pi * 1.3 * t))
    system = nsdyn.shear_building([1e4, 1e4], [2e6], 0.02,
                                  isolation=nsdyn.Isolation(k_lam=5e4, c=1e3, mu=0.05))  # fmt: skip
    ref = nsdyn.simulate(system, gm, chunk_s=5.0)
    ckpt = tmp_path / "run.ckpt.npz"
    real, calls = integrate.solve, []

    def interrupted(*a, **kw):  # a Ctrl-C while the second chunk computes
        calls.append(1)
        if len(calls) == 2:
            os.kill(os.getpid(), signal.SIGINT)
        return real(*a, **kw)

    monkeypatch.setattr(integrate, "solve", interrupted)
    with pytest.raises(KeyboardInterrupt):
        nsdyn.simulate(system, gm, chunk_s=5.0, checkpoint=ckpt)
    with np.load(ckpt) as z:
        assert z["t"][-1] == 10.0  # the second chunk's end: kept, not lost
    monkeypatch.setattr(integrate, "solve", real)
    res = nsdyn.simulate(system, gm, chunk_s=5.0, checkpoint=ckpt)
    np.testing.assert_array_equal(res.x, ref.x)


def test_a_chunk_in_its_own_thread_is_answered_at_once_and_kept(monkeypatch):
    # a compiled chunk that releases the GIL runs in a thread of its own (held_call), so that
    # the waiting thread answers a signal at once (it said nothing for the whole chunk: 17 s
    # of a full-order Radau run); the run stops once the chunk ends, and a second signal is
    # held as the first (stopped inside a chunk, a run left a kernel computing beside the
    # interpreter's exit: now and then a crash under load)
    import io

    from nsdyn.solve import checkpoint

    order: list[str] = []

    class Said(io.StringIO):
        def write(self, text):
            order.append("said") if checkpoint.STOPPING in text else None
            return len(text)

    monkeypatch.setattr(checkpoint.sys, "stderr", Said())

    def until(cond):  # (polling with Event.wait releases the GIL, as a nogil kernel does)
        for _ in range(500):
            if cond():
                return True
            threading.Event().wait(0.01)
        return False

    def chunk(n_signals):
        held = checkpoint._HOLDS[-1].held
        for k in range(n_signals):
            os.kill(os.getpid(), signal.SIGINT)
            until(lambda k=k: len(held) > k)  # (handled before the next: two at once are one)
        until(lambda: "said" in order)
        order.append("chunk end")
        return "done"

    for n_signals in (1, 2):
        order.clear()
        kept = []
        with pytest.raises(KeyboardInterrupt):  # (raised after the chunk, as it ends)
            with holding_signals():
                kept.append(checkpoint.held_call(lambda n=n_signals: chunk(n)))
        assert kept == ["done"] and order == ["said", "chunk end"]  # said once, chunk kept
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored
