"""Peak level accelerations of a fixed-step orbit, with the step ends a sharp friction law spoils.

An orbit integrated with ``N`` fixed steps gives its accelerations at the step ends from the
state (the right-hand side). Under a sharp arctan law the friction turns over within ``1/eps``
of zero slip, far inside one step, and a step end that lands in that turn reads an acceleration
the motion does not have (tens of m/s² where the velocity changes by a few m/s² per step).

Each step end's acceleration ``a_n`` is therefore set beside the velocity changes of the two
steps that meet there, ``g_(n-1) = (v_n - v_(n-1)) / h`` and ``g_n``: the means of the
acceleration over those steps. A resolved history lies between them or near them: a jump of
the acceleration at the step end (a stick-slip switch) leaves ``a_n`` on one of the two
plateaus, and a smooth peak passes them by ``O((w h)^2)`` (a 20 % excess for a mode with
``w h = 1.3``). A step end beyond the larger of the two by more than ``ACC_UNRESOLVED - 1``
times it (or below the smaller) is the unresolved switch's; its value is held to the nearer of
``g_(n-1)``, ``g_n``. The orbit is periodic, so the first and last step ends (one state) take
the last and the first steps.
"""

from __future__ import annotations

import numpy as np

from nsdyn.models.isolated.metrics import level_rows

ACC_UNRESOLVED = 1.5  # a step end beyond the velocity changes beside it by 50 % is spoilt
ACC_FLOOR = 1e-9  # m/s², an excess below this is round-off (an orbit at rest)


def step_end_peaks(od: dict, QDD: np.ndarray, V: np.ndarray, h: float, ug: np.ndarray) -> tuple:
    """Peak absolute horizontal acceleration of each level over the step ends, spoilt step
    ends held to the velocity changes beside them (module docstring).

    ``QDD``, ``V`` (N + 1, n): accelerations and velocities at the step ends of one period;
    ``h`` the step; ``ug`` (N + 1, 1) the horizontal ground acceleration (zeros under a
    force). Returns ``(peaks, raw_peaks, n_spoilt)``: per level, with and without the hold,
    and how many step ends (of every output row) were held."""
    L, starts = level_rows(od)
    A = np.asarray(L @ QDD.T) + ug.T  # (rows, N + 1)
    G = np.asarray(L @ (np.diff(V, axis=0) / h).T) + 0.5 * (ug[1:] + ug[:-1]).T  # (rows, N)
    before = np.concatenate([G[:, -1:], G], axis=1)  # the step ending at each step end
    after = np.concatenate([G, G[:, :1]], axis=1)  # the step starting there
    lo, hi = np.minimum(before, after), np.maximum(before, after)
    slack = (ACC_UNRESOLVED - 1.0) * np.maximum(np.abs(lo), np.abs(hi)) + ACC_FLOOR
    spoilt = (A > hi + slack) | (A < lo - slack)
    held = np.where(spoilt, np.clip(A, lo, hi), A)
    raw = np.maximum.reduceat(np.abs(A).max(axis=1), starts)
    peaks = np.maximum.reduceat(np.abs(held).max(axis=1), starts)
    return peaks, raw, int(np.count_nonzero(spoilt))
