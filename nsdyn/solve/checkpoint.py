"""What a chunked transient run carries from one chunk to the next, and its checkpoint file.

An interrupted run resumes as the same run: besides the histories, the checkpoint holds what
the next chunk starts from -- the step the solver would take next, the event method's slip
modes, the open contacts of a unilateral run -- and the records made so far: steps, solver
statistics, uplifts, contact events (lift-offs, landings), the open contacts at the outputs and
the landings' energy. A fingerprint of the model, excitation, start, output times and options
(:func:`run_key`) ties the file to the run that wrote it.
"""

from __future__ import annotations

import contextvars
import hashlib
import signal
import sys
import threading
import zipfile
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from nsdyn.atomic import CheckpointError, atomic_open


@dataclass
class _Hold:
    """The signals a checkpointed run holds (``held``), and whether the run said, while its
    chunk computed in a thread of its own, that it stops once the chunk ends (``said``)."""

    held: list = field(default_factory=list)
    said: bool = False

    def signalled(self, signum, frame) -> None:
        self.held.append(signum)


_HOLDS: list[_Hold] = []  # the holds in force, the innermost last


@contextmanager
def holding_signals(active: bool = True):
    """SIGINT and SIGTERM held while a chunk runs and its checkpoint is written (``active``:
    a run that keeps one), then raised, SIGTERM first (their handlers: the command's stop, a
    KeyboardInterrupt, or the end of the process). A compiled chunk cannot be stopped inside;
    the signal was raised as it returned, before its checkpoint, so the chunk waited for was
    lost (a resume started where the last checkpoint had). A chunk run by :func:`held_call`
    is waited for in this thread, which says at once that the run stops after it. A run
    without a checkpoint, a signal ignored, or a thread other than the main one: nothing
    held."""
    if not active or threading.current_thread() is not threading.main_thread():
        yield
        return
    hold = _Hold()
    sigs = [s for s in (signal.SIGTERM, signal.SIGINT) if signal.getsignal(s) != signal.SIG_IGN]
    old = [signal.signal(s, hold.signalled) for s in sigs]
    _HOLDS.append(hold)
    try:
        yield
    finally:
        _HOLDS.remove(hold)
        for s, h in zip(sigs, old, strict=True):
            signal.signal(s, h)
        for s in sigs:  # (SIGTERM first: a KeyboardInterrupt raised first dropped it)
            if s in hold.held:
                signal.raise_signal(s)


STOPPING = "nsdyn: stopping once this chunk ends, its work kept for a resume"


def held_call(run):
    """``run()``, a compiled chunk of a run holding its signals (:func:`holding_signals`), in
    a thread of its own while this one waits, so that a signal is answered at once
    (:data:`STOPPING` on stderr, once per chunk); the run stops when the chunk ends, its
    checkpoint written (a second signal is held as the first: a run stopped inside a chunk
    left a kernel computing beside the interpreter's exit, which could crash it). Its
    result, or its exception raised here. Without a hold (a call without a checkpoint, a
    thread other than the main one) ``run()`` here. Kernels that keep the GIL are answered
    as they return, as before."""
    if not _HOLDS or threading.current_thread() is not threading.main_thread():
        return run()
    hold, box = _HOLDS[-1], {}
    context = contextvars.copy_context()  # (numpy's error state, as the caller's)

    def work() -> None:
        try:
            box["result"] = context.run(run)
        except BaseException as e:  # noqa: BLE001 -- handed to the caller
            box["error"] = e

    th = threading.Thread(target=work, name="nsdyn-chunk", daemon=True)
    th.start()
    while th.is_alive():
        if hold.held and not hold.said:
            hold.said = True
            print(STOPPING, file=sys.stderr, flush=True)
        th.join(0.1)
    if "error" in box:
        raise box["error"]
    return box["result"]


FORMAT = "nsdyn-checkpoint-3"  # in every fingerprint: files of an older layout are refused
CHUNK_S = 5.0  # seconds of simulated time per chunk (progress / checkpoint granularity)


def chunked(chunk_s: float) -> dict:
    """The chunk length for a run's key (:func:`run_key`): other chunks are another run
    (a resumed run is the same run bit for bit only on its own chunks), the default none, so
    that a checkpoint of the default chunks written before keeps its key."""
    return {} if chunk_s == CHUNK_S else {"chunk_s": float(chunk_s)}


STAT_KEYS = ("nfev", "njev", "n_lu", "n_rejected", "n_events")  # solver counters summed


@dataclass
class Carry:
    """The state one chunk hands to the next, and the records of the chunks so far."""

    h0: float | None = None  # the step the solver would take next (adaptive methods)
    modes: np.ndarray | None = None  # event method: slip modes at the chunk's end
    open_end: np.ndarray | None = None  # unilateral: open contacts at the chunk's end
    acc: np.ndarray | None = None  # generalized-alpha: its algorithmic acceleration at the end
    t_at: float | None = None  # the time the chunks reached (a chunk's end: not always an output)
    x_at: np.ndarray | None = None  # the state there, where the next chunk starts
    n_steps: int = 0
    stats: dict = field(default_factory=dict)
    uplifts: list = field(default_factory=list)  # (t, contact)
    cevents: list = field(default_factory=list)  # (t, contact, kind, v_n, impulse)
    opens: list = field(default_factory=list)  # unilateral: open contacts at the outputs
    impact: float = 0.0  # kinetic energy change of the landings [J]

    def take(self, sol, unilateral: bool, adaptive: bool, n_out: int | None = None) -> None:
        """Carry the end of the chunk just solved (``sol``, an integrate.Solution), whose rows
        after its start are ``n_out`` outputs (and its end, off the grid; default all)."""
        h = sol.h_last
        self.h0 = float(h) if adaptive and np.isfinite(h) and h > 0 else None
        self.modes = getattr(sol, "modes", None)
        self.acc = getattr(sol, "acc_end", None)
        self.t_at, self.x_at = float(sol.t[-1]), sol.x[-1].copy()
        self.n_steps += sol.n_steps
        for key in STAT_KEYS:
            self.stats[key] = self.stats.get(key, 0) + int(getattr(sol, key, 0) or 0)
        if unilateral:
            self.open_end = sol.open_end
            self.cevents.extend(sol.contact_events)
            rows = sol.open_contacts[: None if n_out is None else 1 + n_out]
            self.opens.append(rows[1:] if self.opens else rows)
            self.impact += sol.impact_energy
        else:  # a unilateral run's lift-offs are its contact events
            self.uplifts.extend(getattr(sol, "uplift", []) or [])

    def arrays(self) -> dict:
        a = {"h0": np.float64(np.nan if self.h0 is None else self.h0),
             "n_steps": np.int64(self.n_steps), "impact": np.float64(self.impact),
             "stats": np.array([self.stats.get(k, 0) for k in STAT_KEYS], dtype=np.int64),
             "uplift_t": np.array([u[0] for u in self.uplifts], dtype=float),
             "uplift_k": np.array([u[1] for u in self.uplifts], dtype=np.int64)}  # fmt: skip
        if self.modes is not None:
            a["modes"] = np.asarray(self.modes)
        if self.open_end is not None:
            a["open_end"] = np.asarray(self.open_end)
        if self.acc is not None:
            a["acc"] = np.asarray(self.acc)
        if self.x_at is not None:
            a.update(t_at=np.float64(self.t_at), x_at=np.asarray(self.x_at))
        if self.opens:
            a["opens"] = np.concatenate(self.opens)
        ce = self.cevents
        a.update(ce_t=np.array([e[0] for e in ce], dtype=float),
                 ce_k=np.array([e[1] for e in ce], dtype=np.int64),
                 ce_kind=np.array([e[2] for e in ce], dtype=np.str_),
                 ce_v=np.array([e[3] for e in ce], dtype=float),
                 ce_imp=np.array([e[4] for e in ce], dtype=float))  # fmt: skip
        return a

    @classmethod
    def from_arrays(cls, d) -> Carry:
        h0 = float(d["h0"])
        stats = dict(zip(STAT_KEYS, (int(v) for v in d["stats"]), strict=True))
        uplifts = [(float(t), int(k)) for t, k in zip(d["uplift_t"], d["uplift_k"], strict=True)]
        cols = (d["ce_t"], d["ce_k"], d["ce_kind"], d["ce_v"], d["ce_imp"])
        cevents = [(float(t), int(k), str(s), float(v), float(i))
                   for t, k, s, v, i in zip(*cols, strict=True)]  # fmt: skip
        files = set(d.files)
        return cls(
            h0=None if np.isnan(h0) else h0,
            modes=d["modes"] if "modes" in files else None,
            open_end=d["open_end"] if "open_end" in files else None,
            acc=d["acc"] if "acc" in files else None,
            t_at=float(d["t_at"]) if "t_at" in files else None,
            x_at=d["x_at"] if "x_at" in files else None,
            n_steps=int(d["n_steps"]), stats=stats, uplifts=uplifts, cevents=cevents,
            opens=[d["opens"]] if "opens" in files else [], impact=float(d["impact"]),
        )  # fmt: skip


def chunks(t_eval: np.ndarray, k0: int, chunk_s: float, t_from: float | None = None) -> list:
    """The chunks of a run whose outputs up to ``t_eval[k0]`` are written and whose
    integration reached ``t_from`` (default ``t_eval[k0]``): per chunk ``(times, a, b)``, its
    times the start, the outputs ``t_eval[a:b]`` and the end, the rows after the start those
    outputs (and the end where no output is there).

    Chunks end every ``chunk_s`` seconds from ``t_eval[0]`` and at the run's end, wherever
    the outputs fall: the output grid samples the run and does not move its steps, which a
    chunk end on the grid did (an adaptive step shortened to land there, a fixed step grid
    restarted off its phase). An output within 1e-9 chunk_s of an end is the state at that
    end (not at the output's own time, which would move the end by its round-off)."""
    t0, t_end = float(t_eval[0]), float(t_eval[-1])
    t_from = float(t_eval[k0]) if t_from is None else float(t_from)
    tol = 1e-9 * chunk_s
    plan, a = [], k0 + 1
    j = int(np.floor((t_from - t0) / chunk_s + 1e-9)) + 1
    while t_from < t_end:
        tb = min(t0 + j * chunk_s, t_end)
        j += 1
        if tb <= t_from + tol and tb < t_end:
            continue
        b = int(np.searchsorted(t_eval, tb + tol, side="right"))
        on_grid = b > a and t_eval[b - 1] >= tb - tol
        plan.append((np.concatenate(([t_from], t_eval[a : b - on_grid], [tb])), a, b))
        a, t_from = b, tb
    return plan


def run_key(P, x0, t_eval, options: dict) -> str:
    """A fingerprint of everything a run's histories depend on: the kernel tuple ``P`` (the
    model and its excitation), an explicit start ``x0``, the output times and the solver's
    options (and the checkpoint layout). A checkpoint is continued only by the run that
    wrote it."""
    h = hashlib.sha256(FORMAT.encode())
    for v in (tuple(P), x0, np.asarray(t_eval, dtype=float),
              [(k, options[k]) for k in sorted(options)]):  # fmt: skip
        feed(h, v)
    return h.hexdigest()


def feed(h, v) -> None:
    """Add ``v`` to the hash ``h``: an array by its dtype, shape and bytes, a tuple or list
    element by element (bracketed), anything else by its repr."""
    if isinstance(v, tuple | list):
        h.update(b"(")
        for e in v:
            feed(h, e)
        h.update(b")")
    elif isinstance(v, np.ndarray):
        h.update(f"{v.dtype}{v.shape}".encode())
        h.update(np.ascontiguousarray(v).tobytes())
    else:
        h.update(repr(v).encode())


def save(path: Path, t: np.ndarray, x: np.ndarray, key: str, carry: Carry) -> None:
    """Write the histories so far and the carried state, atomically."""
    with atomic_open(path, "wb") as fh:
        np.savez(fh, t=t, x=x, key=np.str_(key), **carry.arrays())


def load(path: Path, key: str, t_eval: np.ndarray):
    """(t, x, Carry) of the checkpoint at ``path`` written by the run ``key``, or None if it
    holds nothing of these output times; :class:`CheckpointError` if another run wrote it, or
    if it cannot be read (cut short, damaged)."""
    try:
        return _load(path, key, t_eval)
    except CheckpointError:
        raise
    except (OSError, EOFError, ValueError, KeyError, zipfile.BadZipFile) as e:
        raise CheckpointError(
            f"checkpoint {path}: cannot be read ({type(e).__name__}: {e}); delete it to start "
            "the run over (nsdyn run: a run without --resume starts over and replaces it)"
        ) from None


def _load(path: Path, key: str, t_eval: np.ndarray):
    with np.load(path) as d:
        if "key" not in d.files or str(d["key"]) != key:
            raise CheckpointError(
                f"checkpoint {path}: written by another run (its system, motion, start, output "
                "times, solver options or chunk_s differ, or by an older nsdyn); delete it, or "
                "give this run another checkpoint file"
            )
        t = d["t"]
        if not (t.size and np.allclose(t, t_eval[: t.size])):
            return None
        return t, d["x"], Carry.from_arrays(d)
