"""The progress of a compiled run watched from another thread (nsdyn._progress.watched), and
which of a curve's points get a line (nsdyn._progress.PointLines).

The watcher reports while the run is still going, hands back the run's result or raises its
exception, and changes nothing of what the run computes: a pair system's or a deck's histories
with a progress callback equal those without it bit for bit (the loop only writes one more
counter).
"""

from __future__ import annotations

import threading

import numpy as np
import pytest

from nsdyn import _progress
from nsdyn._progress import PointLines, watched


def test_progress_is_reported_while_the_run_goes_on_and_its_result_returned():
    # the run waits until a progress line has come: so that line came while it was running
    seen = threading.Event()
    calls = []

    def run():
        assert seen.wait(60.0), "no progress while the run was going"
        return "done"

    def progress(t, t_end, wall):
        calls.append((t, t_end, wall))
        seen.set()

    assert watched(run, lambda: 1.5, progress, 4.0, every=0.0) == "done"
    assert calls and all(c[:2] == (1.5, 4.0) and c[2] >= 0.0 for c in calls)


def test_the_run_s_exception_is_raised_in_the_caller():
    def run():
        raise ValueError("step size underflow at t = 1 s")

    with pytest.raises(ValueError, match="underflow at t = 1 s"):
        watched(run, lambda: 0.0, lambda *a: None, 1.0)


@pytest.mark.parametrize("kind", ["pairs", "deck"])
@pytest.mark.parametrize("law", ["arctan", "switch"])
def test_a_watched_run_is_the_same_run(kind, law, monkeypatch):
    # both loops (Radau IIA; located events) of a pair system and of the deck under a progress
    # callback called at every watch (WATCH_S = 0): the same histories to the last bit, and
    # every time reported within the run's span, in order
    from nsdyn.models.isolated import Bearing, Friction, rigid_deck
    from nsdyn.models.isolated.deck import simulate_plane
    from nsdyn.models.isolated.pairs import from_deck, simulate_pairs

    monkeypatch.setattr(_progress, "WATCH_S", 0.0)
    deck = rigid_deck(1.0e6, 5.0e7, [[-5.0, -3.0], [5.0, -3.0], [0.0, 4.0]],
                      Bearing(Friction(0.05), radius=2.0))  # fmt: skip
    system, simulate = (
        (from_deck(deck), simulate_pairs) if kind == "pairs" else (deck, simulate_plane)
    )
    orbit = {"f": 0.5, "ax": 2.0, "ay": 1.0, "phase_y_deg": 90.0}
    plain = simulate(system, orbit, law=law, t_end=2.0)
    times = []
    seen = simulate(system, orbit, law=law, t_end=2.0,
                    progress=lambda t, t_end, wall: times.append((t, t_end)))  # fmt: skip
    assert np.array_equal(plain.q, seen.q) and np.array_equal(plain.u, seen.u)
    assert np.array_equal(plain.N, seen.N) and np.array_equal(plain.events, seen.events)
    assert all(0.0 <= t <= t_end == 2.0 for t, t_end in times)
    assert [t for t, _ in times] == sorted(t for t, _ in times)


def test_time_left_of_a_curve_is_the_mean_point_times_the_points_left():
    from nsdyn._progress import time_left

    # exact arithmetic: mean 3 s x 10 points = 30 s; 96 s x 149 points = 3.97 h; 90 min
    assert time_left([2.0, 4.0], 10) == ", about 30 s left"
    assert time_left([96.0], 149) == ", about 4.0 h left"
    assert time_left([90.0, float("nan"), None], 60) == ", about 90 min left"
    assert time_left([1.0], 0) == "" and time_left([], 5) == ""


@pytest.mark.parametrize("watch", [0.0, 1.0e9])
def test_a_curve_says_its_first_last_and_failed_points_and_others_once_a_watch(watch, monkeypatch):
    # 600 points at 0.04 s said 600 lines; now the first and the last point and each without a
    # steady state are said always, the others at most once a WATCH_S (0: each; 1e9: none)
    monkeypatch.setattr(_progress, "WATCH_S", watch)
    said = []
    lines = PointLines(said.append)
    for k in range(1, 601):
        lines(k, k, 600, k not in (7, 300))
    lines.close()
    assert said == (list(range(1, 601)) if watch == 0.0 else [1, 7, 300, 600])


def test_an_arclength_curve_s_last_point_is_said_when_it_ends(monkeypatch):
    # an arclength curve counts past its grid's n (2 here, 12 points): its last point was not
    # said (k == n fired mid-curve); the line held back is said when the curve ends
    monkeypatch.setattr(_progress, "WATCH_S", 1.0e9)
    said = []
    lines = PointLines(said.append)
    for k in range(1, 13):
        lines(k, k, 2)
    assert said == [1, 2]
    lines.close()
    lines.close()  # (said once)
    assert said == [1, 2, 12]


def test_a_held_last_line_is_said_without_its_time_left(monkeypatch):
    # a curve that ended (or stopped) after a held-back point said "(0.01 s, about 0 s left)"
    monkeypatch.setattr(_progress, "WATCH_S", 1.0e9)
    said = []
    lines = PointLines(said.append)
    lines("p1 (0.01 s, about 9 s left)", 1, 6, final="p1 (0.01 s)")
    lines("p4 (0.01 s, about 2 s left)", 4, 6, final="p4 (0.01 s)")
    lines.close()
    assert said == ["p1 (0.01 s, about 9 s left)", "p4 (0.01 s)"]
