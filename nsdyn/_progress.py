"""The progress line of a long run: the simulated time reached and the wall time so far.

Every command that runs a transient (``nsdyn run`` on an isolated frame, on a 3D building's
sparse rung) reports through :func:`reporter`, so the line reads the same everywhere and a
run shorter than :data:`QUIET_S` says nothing.
"""

from __future__ import annotations

QUIET_S = 1.0  # wall seconds before the first line: short runs stay quiet


def reporter(say):
    """A ``progress(t_done, t_end, wall_s)`` callback that passes ``say`` one line
    (``  t =   10.00 / 40.00 s   ( 12.9 s)``) once the run has taken more than ``QUIET_S``."""

    def progress(t, t_end, wall):
        if wall > QUIET_S:
            say(f"  t = {t:7.2f} / {t_end:.2f} s   ({wall:5.1f} s)")

    return progress
