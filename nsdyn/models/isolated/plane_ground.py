"""The ground of the planar family's runs, packed for its kernels: a three-component record
(``t0, dt, ax, ay, az``, an object, a dict or raw arrays) or a harmonic orbit (an object or a
dict of :class:`nsdyn.HarmonicPlane`'s fields), each field checked and named when it is wrong
(a misspelt record key was dropped without a word, a NaN start blamed on ``t_end``)."""

from __future__ import annotations

import math

import numpy as np

from nsdyn._checks import did_you_mean, number
from nsdyn.models.isolated import _kplane as kp

RECORD_KEYS = ("t0", "dt", "ax", "ay", "az")  # a record given as a dict


def _samples(name: str, a) -> np.ndarray:
    """A component as a float array, or ValueError naming it (text: numpy's own error)."""
    try:
        if np.asarray(a).dtype.kind not in "iuf":
            raise ValueError
        return np.asarray(a, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"ground.{name}: expected accelerations [m/s²] (numbers), got "
                         f"{type(a).__name__}") from None  # fmt: skip


def _attr(obj, name, default=None):
    if isinstance(obj, dict):
        return obj.get(name, default)
    return getattr(obj, name, default)


def orbit_of(d: dict):
    """A harmonic orbit given as a dict: ``HarmonicPlane(**d)``, its defaults (φ_y = 90°) and
    checks, an unknown key refused with the nearest field's name."""
    import dataclasses

    from nsdyn._checks import did_you_mean
    from nsdyn.ground.orbit import HarmonicPlane

    names = [f.name for f in dataclasses.fields(HarmonicPlane)]
    for k in d:
        if k not in names:
            hint = did_you_mean(str(k), names)
            raise ValueError(f"harmonic orbit: {k!r}: no such field{hint} (the fields of "
                             f"nsdyn.HarmonicPlane: {', '.join(names)})")  # fmt: skip
    try:
        return HarmonicPlane(**{"ax": 0.0, **d})  # a dict may leave out a component
    except ValueError as e:
        raise ValueError(f"harmonic orbit: {str(e).removeprefix('HarmonicPlane.')}") from None


def pack_ground(ground) -> tuple[int, np.ndarray, np.ndarray, float]:
    """(kind, gp, table (3, n), duration) of a ground description.

    ``ground``: an object with ``t0, dt, ax, ay, az`` (a three-component record, az may be
    None), a harmonic orbit with ``f, ax, ay, phase_y_deg, az, f_z, phase_z_deg`` (object, or
    dict read as ``HarmonicPlane(**dict)`` with its defaults, φ_y = 90° (a circle when
    A_x = A_y; 0 for a line), and checks; a_x = A_x sin ωt,
    a_y = A_y sin(ωt + φ_y), a_z = A_z sin(ω_z t + φ_z), checked against its ``accel(t)``
    when it has one), or raw arrays ``(t0, dt, ax, ay, az)``.
    """
    gp = np.zeros(kp.N_GP)
    gp[kp.GP_DT] = 1.0
    if isinstance(ground, dict) and "f" in ground:
        ground = orbit_of(ground)
    if isinstance(ground, tuple | list):  # (a list of the five was "got list")
        if len(ground) != 5:
            raise ValueError(f"ground: raw arrays are (t0, dt, ax, ay, az) (ay, az may be "
                             f"None), got {len(ground)} values")  # fmt: skip
        t0, dt, ax, ay, az = ground
        ground = {"t0": t0, "dt": dt, "ax": ax, "ay": ay, "az": az}
    if _attr(ground, "f") is not None:

        def num(name, default):
            v = _attr(ground, name, default)
            v = default if v is None else v
            if isinstance(v, bool) or not isinstance(v, int | float | np.integer | np.floating):
                raise ValueError(f"harmonic orbit: {name}: expected a number, got {v!r}")
            return float(v)

        from nsdyn.ground.orbit import HarmonicPlane  # (its φ_y default, 90°: one orbit)

        f = num("f", 0.0)
        phy = num("phase_y_deg", HarmonicPlane.phase_y_deg)
        vals = [f, num("ax", 0.0), num("ay", 0.0), math.radians(phy),
                num("az", 0.0), num("f_z", f), math.radians(num("phase_z_deg", 0.0))]  # fmt: skip
        for k, v in zip((kp.GP_F, kp.GP_AX, kp.GP_AY, kp.GP_PHY, kp.GP_AZ, kp.GP_FZ, kp.GP_PHZ),
                        vals, strict=True):  # fmt: skip
            gp[k] = v
        if not (np.all(np.isfinite(gp)) and f > 0 and gp[kp.GP_FZ] > 0):
            raise ValueError(f"harmonic orbit: expected f, f_z > 0 and finite amplitudes, got "
                             f"{vals}")  # fmt: skip
        tab = np.zeros((3, 0))
        if hasattr(ground, "accel"):  # the orbit's own definition must match the kernel's
            ag = np.zeros(3)
            for t in np.linspace(0.0, 1.0 / f, 7)[1:]:
                kp.ground(float(t), kp.G_HARMONIC, gp, tab, ag)
                ref = np.asarray(ground.accel(float(t)), dtype=float).ravel()[:3]
                if not np.allclose(
                    ag[: ref.size], ref, rtol=1e-12, atol=1e-12 * (1 + np.abs(ref).max())
                ):
                    raise ValueError(f"harmonic orbit: accel({t:g}) = {ref} differs from the "
                                     f"kernel's form {ag} (phase convention)")  # fmt: skip
        return kp.G_HARMONIC, gp, tab, math.inf
    if isinstance(ground, dict) and "dt" not in ground:  # (an orbit without its frequency?)
        raise TypeError(f"ground: a dict is a harmonic orbit, which needs 'f' [Hz] (with ax, ay, "
                        f"...), or a record, which needs 't0', 'dt' and 'ax'; got keys "
                        f"{sorted(ground)}")  # fmt: skip
    if _attr(ground, "ax") is None or _attr(ground, "dt") is None:
        raise TypeError(
            "ground: expected a three-component record (t0, dt, ax, ay, az), a "
            f"harmonic orbit (f, ax, ay, ...) or raw arrays, got {type(ground).__name__}"
        )
    if isinstance(ground, dict) and (odd := sorted(set(map(str, ground)) - set(RECORD_KEYS))):
        hint = did_you_mean(odd[0], RECORD_KEYS)
        raise ValueError(f"ground: {odd[0]!r}: no field of a record{hint} (the fields: "
                         f"{', '.join(RECORD_KEYS)})")  # fmt: skip
    ax = _samples("ax", _attr(ground, "ax"))
    n = ax.size
    if n < 2:
        raise ValueError(f"ground.ax: expected a record of two samples or more, got {n}")
    rows = []
    for name in ("ax", "ay", "az"):
        a = _attr(ground, name)
        a = np.zeros(n) if a is None else _samples(name, a)
        if a.shape != (n,):  # (ax (n, 1) was "n samples (as ax)")
            what = "a 1-D array of samples" if name == "ax" else f"{n} samples (as ax)"
            raise ValueError(f"ground.{name}: expected {what}, got shape {a.shape}")
        if not np.all(np.isfinite(a)):
            bad = int(np.flatnonzero(~np.isfinite(a))[0])
            raise ValueError(f"ground.{name}: sample {bad} is {a[bad]}; expected finite values")
        rows.append(a)
    dt = number("ground.dt", _attr(ground, "dt"), "a positive time step [s]", lambda v: v > 0)
    t0 = _attr(ground, "t0", 0.0)  # (NaN was blamed on t_end)
    gp[kp.GP_T0] = number("ground.t0", 0.0 if t0 is None else t0, "a finite start time [s]")
    gp[kp.GP_DT] = dt
    return kp.G_TABLE, gp, np.ascontiguousarray(np.vstack(rows)), (n - 1) * dt


def tfp_start_said(q, q_rest, has_tfp: bool) -> None:
    """Warn (InputWarning) when ``y0`` starts a system with triple pendulums at displacements
    ``q`` off its rest ``q_rest`` without their element slips: the slips start at zero, so the
    whole offset is in each bearing's elastic element (released from 0.5 m, a bearing settled
    at -0.08 m, as no pendulum swings)."""
    if not has_tfp or np.array_equal(np.asarray(q, dtype=float), np.asarray(q_rest, dtype=float)):
        return
    import warnings

    from nsdyn._checks import InputWarning

    warnings.warn("y0: the triple pendulums' element slips start at zero, so the offset of q "
                  "is all in their elastic elements, a start no pendulum takes; give y0 its "
                  "slips too (after [q, q̇]: each bearing's four (s_x, s_y); with equal "
                  "frictions s_k = R̄_k u/(R1 + R4), docs: bidirectional isolators)",
                  InputWarning, stacklevel=3)  # fmt: skip


def ground_history(ground, t: np.ndarray) -> np.ndarray:
    """Ground accelerations (3, nt) at times ``t`` as the run's kernels see them (a record
    interpolated linearly, zero outside; an orbit's closed form)."""
    gk, gp, tab, _ = pack_ground(ground)
    out = np.zeros((3, len(t)))
    ag = np.zeros(3)
    for k, tk in enumerate(np.asarray(t, float)):
        kp.ground(float(tk), gk, gp, tab, ag)
        out[:, k] = ag
    return out
