"""The initial tilt of every rocking body, one convention for the Python API and the scene files.

A body that rocks about a base corner (block, rocking frame, contact body, cylinder) may start
tilted. The tilt is given either as an angle or as a fraction of the slenderness alpha (the
tilt at which the body's weight passes over the pivot), exactly one of the two::

    theta0 [rad]        or        theta0_over_alpha [-],   theta0 = theta0_over_alpha * alpha

with alpha = atan(B / H) for a block of width 2B and height 2H (the angle of the line from the
pivot to the centre of mass from the vertical; for a cylinder of radius r and height 2H,
alpha = atan(r / H)). The same two names are the keys of the scenes' ``[motion]`` table.

A run that ends with the body past alpha and leaning further has not overturned by its end but
is falling unless the ground pushes it back: its outcome says so (:func:`past_tip_over`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from nsdyn._checks import number as check_number
from nsdyn.models.scenefile import SceneError, number


def initial_tilt(theta0: float | None, theta0_over_alpha: float | None, alpha: float) -> float:
    """The initial tilt [rad] from ``theta0`` [rad] or ``theta0_over_alpha`` (times ``alpha``
    [rad]); neither gives 0. ValueError when both are given or one is not a finite number."""
    if theta0 is not None and theta0_over_alpha is not None:
        raise ValueError(
            "theta0 and theta0_over_alpha: give the initial tilt one way, not both "
            f"(theta0 = {theta0!r} rad, theta0_over_alpha = {theta0_over_alpha!r})"
        )
    for name, v in (("theta0", theta0), ("theta0_over_alpha", theta0_over_alpha)):
        if v is not None:
            check_number(name, v, "a finite number")
    tilt = 0.0 if theta0 is None else float(theta0)
    if theta0_over_alpha is not None:
        tilt = float(theta0_over_alpha) * float(alpha)
    if not abs(tilt) < 0.5 * math.pi:
        name = "theta0" if theta0 is not None else "theta0_over_alpha"
        raise ValueError(f"{name}: a tilt of {tilt:.4g} rad lays the body on its side or beyond; "
                         f"expected |theta0| < pi/2 ({0.5 * math.pi:.4g} rad)")  # fmt: skip
    return tilt


def scene_tilt(table: Mapping, source: str, where: str = "motion") -> dict:
    """The initial tilt of a scene's ``[where]`` table as the keyword the Python API takes:
    ``{"theta0": v}`` [rad], ``{"theta0_over_alpha": v}`` or ``{}``; :class:`SceneError` naming
    the file and key when both are given or a value is not a finite number."""
    keys = [k for k in ("theta0", "theta0_over_alpha") if k in table]
    if len(keys) == 2:
        raise SceneError(
            f"{source}: {where}.theta0_over_alpha: give the initial tilt as "
            f"{where}.theta0 [rad] or as {where}.theta0_over_alpha, not both"
        )
    return {k: number(source, f"{where}.{k}", table[k], positive=False) for k in keys}


def leaning_past(end: float, rate: float, alpha: float) -> bool:
    """Whether a body at tilt ``end`` [rad] turning at ``rate`` [rad/s] is past its tip-over
    angle ``alpha`` and leaning further (falling, unless the ground pushes it back)."""
    return bool(abs(end) > alpha and end * rate > 0)


NAMES = ("final_theta_rad", "final_thetad_rad_per_s")  # a summary's last tilt and its rate


def final_tilt(theta, rate, alpha: float, over: bool, names: tuple[str, str] = NAMES) -> dict:
    """A summary's last tilt and its rate (keys ``names``) and ``past_tip_over_at_end``
    (:func:`leaning_past`, false for a run that ended ``over``: overturned, toppled) from the
    histories ``theta`` [rad] and ``rate`` [rad/s]."""
    end = float(theta[-1]) if len(theta) else 0.0
    turn = float(rate[-1]) if len(rate) else 0.0
    past = leaning_past(end, turn, alpha) and not over
    return {names[0]: end, names[1]: turn, "past_tip_over_at_end": past}


def past_tip_over(end: float, alpha: float, name: str) -> str:
    """The outcome line of a run that ends at tilt ``end`` [rad] past ``alpha``, leaning
    further (``name``: the tilt's name in the summary's words)."""
    return (f"LEANING PAST ITS TIP-OVER ANGLE at the end: {name} {end:.3g} rad "
            f"({abs(end) / alpha:.3g} alpha) and growing, not overturned by t_end; a longer "
            "t_end shows whether it falls")  # fmt: skip
