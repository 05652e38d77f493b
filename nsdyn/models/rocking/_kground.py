"""Numba kernel: the ground acceleration (ü_hor, ü_ver) seen by the rocking integrators.

Excitation kinds (``gk``) and their flat parameters ``gp``:

- ``GK_NONE`` (0): no ground motion;
- ``GK_TABLE`` (1): ``gp = [t0, dt, has_vertical]``, samples ``tab_h``, ``tab_v`` [m/s²],
  linear interpolation on ``[t0, t0 + (n-1) dt]``, zero outside;
- ``GK_PULSE`` (2): ``gp = Pulse.code() = [shape, a_p, omega_p, D, t_start, ver_ratio, t_c]``
  of :mod:`nsdyn.ground.pulses` (sine / cosine: ``a_p sin|cos(omega_p tau)``; Ricker:
  ``a_p (1 - w² s²/2) exp(-w² s²/4)``, ``s = tau - t_c``; rectangular: ``a_p``), zero
  outside ``[t_start, t_start + D)``.

Breakpoints (table samples, pulse start and end) are where the excitation is not smooth; the
integrators stop steps there. ``left`` selects the left limit at a breakpoint (the value a step
ending there must see), otherwise the right limit.
"""

import math

import numpy as np
from numba import njit

from nsdyn import _kaddress as ka

GK_NONE = 0  # no excitation
GK_TABLE = 1  # sampled record, linear interpolation
GK_PULSE = 2  # closed-form pulse
# the one-sided limit ``ground`` takes at a breakpoint, as typed values (a literal True or
# False beside a variable would compile ``ground`` and its callers once more)
LEFT_LIMIT = np.bool_(True)
RIGHT_LIMIT = np.bool_(False)
BP_EPS = 1e-12  # relative tolerance in time when deciding whether t sits on a breakpoint


@ka.compiled_only
def ground(t, left, gk, gp, tab_h, tab_v):
    """(ü_hor, ü_ver) at time ``t`` [m/s²]."""
    if gk == GK_TABLE:
        t0 = gp[0]
        dt = gp[1]
        n = tab_h.size
        x = (t - t0) / dt
        if x < 0.0 or x > n - 1:
            return 0.0, 0.0
        if left and x == 0.0:
            return 0.0, 0.0
        if (not left) and x == n - 1:
            return 0.0, 0.0
        k = int(math.floor(x))
        if k >= n - 1:
            k = n - 2
        if k < 0:
            return tab_h[0], tab_v[0] if gp[2] > 0.5 else 0.0
        w = x - k
        ah = (1.0 - w) * tab_h[k] + w * tab_h[k + 1]
        av = 0.0
        if gp[2] > 0.5:
            av = (1.0 - w) * tab_v[k] + w * tab_v[k + 1]
        return ah, av
    if gk == GK_PULSE:
        tau = t - gp[4]
        dur = gp[3]
        if left:
            inside = tau > 0.0 and tau <= dur
        else:
            inside = tau >= 0.0 and tau < dur
        if not inside:
            return 0.0, 0.0
        shape = int(gp[0])
        w = gp[2]
        if shape == 1:
            a = gp[1] * math.sin(w * tau)
        elif shape == 2:
            a = gp[1] * math.cos(w * tau)
        elif shape == 4:
            a = gp[1]
        else:
            s2 = (w * (tau - gp[6])) ** 2
            a = gp[1] * (1.0 - 0.5 * s2) * math.exp(-0.25 * s2)
        return a, gp[5] * a
    return 0.0, 0.0


# the ground motion by address (:func:`nsdyn._kaddress.tcall`, declared and put in the table
# by nsdyn.models.rocking.rocking_compile): the rocking block's loop evaluates it at seven
# places (its right-hand side, the uplift test, the impact), each of which would otherwise
# link, LLVM optimise and translate again a copy of it
ka.tslot("rock.ground", ground, "nsdyn.models.rocking.rocking_compile:callees")


@njit(cache=True, error_model="numpy", inline="always")
def ground_t(t, left, gk, gp, tab_h, tab_v):
    """:func:`ground` called by its address in the table of :mod:`nsdyn._kaddress`."""
    return ka.tcall("rock.ground", (t, left, gk, gp, tab_h, tab_v))


@ka.compiled_only
def next_breakpoint(t, gk, gp, n_tab):
    """The first breakpoint strictly after ``t`` (``inf`` if none)."""
    tol = BP_EPS * (1.0 + abs(t))
    if gk == GK_TABLE:
        t0 = gp[0]
        dt = gp[1]
        if t < t0 - tol:
            return t0
        k = math.floor((t - t0) / dt + 1e-9) + 1.0
        if k > n_tab - 1:
            return math.inf
        return t0 + k * dt
    if gk == GK_PULSE:
        ts = gp[4]
        te = gp[4] + gp[3]
        if t < ts - tol:
            return ts
        if t < te - tol:
            return te
        return math.inf
    return math.inf


@ka.compiled_only
def step_to_breakpoint(t, h, t_end, gk, gp, n_tab):
    """(step, ends there): the step ``h`` from ``t``, shortened to end on the next breakpoint
    or on ``t_end`` if it would pass one."""
    at_bp = False
    tbp = next_breakpoint(t, gk, gp, n_tab)
    if t + h >= tbp:
        h = tbp - t
        at_bp = True
    if t + h >= t_end:
        h = t_end - t
        at_bp = True
    return h, at_bp


@ka.compiled_only
def rest_step(t, gk, gp, n_tab):
    """Step of the uplift scan while the block is at rest (table dt, or T_p / 64)."""
    if gk == GK_TABLE:
        return gp[1]
    if gk == GK_PULSE:
        return 2.0 * math.pi / gp[2] / 64.0
    return math.inf
