"""The progress line of a long run: the simulated time reached and the wall time so far.

Every command that runs a transient (``nsdyn run`` on an isolated frame, on a 3D building's
sparse rung) reports through :func:`reporter`, so the line reads the same everywhere and a
run shorter than :data:`QUIET_S` says nothing.
"""

from __future__ import annotations

QUIET_S = 1.0  # wall seconds before the first line: short runs stay quiet
WATCH_S = 5.0  # wall seconds between two lines of a watched compiled run


def reporter(say):
    """A ``progress(t_done, t_end, wall_s)`` callback that passes ``say`` one line
    (``  t =   10.00 / 40.00 s   ( 12.9 s)``) once the run has taken more than ``QUIET_S``."""

    def progress(t, t_end, wall):
        if wall > QUIET_S:
            say(f"  t = {t:7.2f} / {t_end:.2f} s   ({wall:5.1f} s)")

    return progress


def watched(run, reached, progress, t_end: float, every: float | None = None):
    """``run()`` (a compiled loop that releases the GIL) in a thread of its own while this
    one calls ``progress(reached(), t_end, wall_s)`` every ``every`` seconds (default
    :data:`WATCH_S`); its result, or its exception raised here. A Ctrl-C interrupts the wait
    (the thread, a daemon, ends with the process)."""
    import threading
    import time

    every = WATCH_S if every is None else every
    box: dict = {}

    def work():
        try:
            box["result"] = run()
        except BaseException as e:  # handed to the caller
            box["error"] = e

    th = threading.Thread(target=work, name="nsdyn-run", daemon=True)
    w0 = time.perf_counter()
    last = w0
    th.start()
    while th.is_alive():
        th.join(0.2)
        now = time.perf_counter()
        if th.is_alive() and now - last >= every:
            progress(reached(), t_end, now - w0)
            last = now
    if "error" in box:
        raise box["error"]
    return box["result"]


class PointLines:
    """A curve's progress lines: ``lines(text, k, n, plain)`` says the line of its k-th point
    of ``n`` when it is the first or the n-th, when it is not ``plain`` (no steady state), and
    otherwise at most once per :data:`WATCH_S` of wall time, so that a curve of 600 points at
    0.04 s each says a few lines, not 600 (every point is in the CSV). A line held back is
    said by :meth:`close` if no other came after it: the curve's last point, which an
    arclength curve (past its grid's n) or one that skipped frequencies knows only at its
    end."""

    def __init__(self, say):
        self.say, self.last, self.held = say, -float("inf"), None

    def __call__(self, text: str, k: int, n: int, plain: bool = True, final=None) -> None:
        """``final``: the line to say instead if this one is held back and turns out the
        curve's last (without its estimate of the time left); default ``text``."""
        import time

        now = time.perf_counter()
        if k <= 1 or k == n or not plain or now - self.last >= WATCH_S:
            self.say(text)
            self.last, self.held = now, None
        else:
            self.held = text if final is None else final

    def close(self) -> None:
        """Say the line held back, if any (the curve has ended, or stopped: an interrupt or
        an error, after its points so far)."""
        if self.held is not None:
            self.say(self.held)
            self.held = None


def curve_count(k: int, n: int, walls: list, continuation: str) -> tuple[str, str]:
    """(``"/150"``, the time left) of a curve's k-th point of ``n``; an arclength curve takes
    its own steps, so ``(" (arclength)", "")``: its grid's total read "16/4", past its end."""
    if continuation == "arclength":
        return " (arclength)", ""
    return f"/{n}", time_left(walls, n - k)


def time_left(walls: list, remaining: int) -> str:
    """``", about 12 min left"``: the mean wall time of the points done in this run times the
    points still to do (a curve's estimate, shown from its first point on: a triple friction
    pendulum's orbit takes minutes a point); ``""`` when none is left or none was timed."""
    import math

    ws = [w for w in walls if isinstance(w, int | float) and math.isfinite(w)]
    if remaining <= 0 or not ws:
        return ""
    left = remaining * sum(ws) / len(ws)
    if left < 90:
        return f", about {left:.0f} s left"
    if left < 2 * 3600:
        return f", about {left / 60:.0f} min left"
    return f", about {left / 3600:.1f} h left"
