"""Argument checks shared by the public entry points: an object of the wrong kind is a
TypeError naming the argument, what was expected and how to make one (instead of an
AttributeError from deep inside a model)."""

from __future__ import annotations

import math


class InputWarning(UserWarning):
    """A warning about the user's input (a record's assumed units, a component a model cannot
    feel): the command line prints it as one line, ``nsdyn CMD: warning: ...``."""


class NotedWarning(InputWarning):
    """An input a scene says as a note before its run (a friction law too coarse to model its
    friction, a bearing's implausible contact pressure): a Python call warns, a scene
    silences it around its run (said once)."""


class AccuracyWarning(InputWarning):
    """A finished run whose own check says it is far from accurate (an energy balance; peaks
    its steps did not resolve): its tolerance or step, or the model's scales, are the input
    to change (printed as an input warning)."""


def expect(name: str, value, ok: bool, what: str) -> None:
    """Raise ``TypeError("{name}: expected {what}, got {type}")`` unless ``ok``."""
    if not ok:
        raise TypeError(f"{name}: expected {what}, got {type(value).__name__}")


# Dormand–Prince 5(4), every family's explicit method: stable for h|λ| up to about 3.3 on the
# real axis (a stiff mode bounds its step, whatever the accuracy asked)
DOPRI5_REAL_AXIS = 3.3


def did_you_mean(word, valid) -> str:
    """``"; did you mean 'x'?"`` naming the entry of ``valid`` nearest to ``word``, or ``""``
    when none is near (the hint every "unknown ..." message of nsdyn ends with)."""
    import difflib

    same = [str(v) for v in valid if str(v).lower() == str(word).lower()]  # only the case off
    close = same or difflib.get_close_matches(str(word), [str(v) for v in valid], n=1)
    return f"; did you mean {close[0]!r}?" if close else ""


def edits(a: str, b: str) -> int:
    """The edit distance of ``a`` and ``b`` (insertions, deletions, substitutions)."""
    row = list(range(len(b) + 1))
    for i, ca in enumerate(a, 1):
        prev, row[0] = row[0], i
        for j, cb in enumerate(b, 1):
            prev, row[j] = row[j], min(row[j] + 1, row[j - 1] + 1, prev + (ca != cb))
    return row[-1]


def is_typo(name: str, valid) -> bool:
    """Whether ``name`` is a slip of the pen for one of ``valid``: an edit or two off (one
    for a name under 10 characters). A study's first row lacks a rigid rung's missing
    columns, which is no typo."""
    return any(edits(name, str(c)) <= (1 if len(str(c)) < 10 else 2) for c in valid)


def known_fields(cls, given) -> None:
    """Each keyword in ``given`` a field of the dataclass ``cls``; otherwise a TypeError naming
    the nearest (Python's own named the generated ``__init__`` and no field)."""
    import dataclasses

    names = [f.name for f in dataclasses.fields(cls)]
    for k in given:
        if k not in names:
            raise TypeError(f"{cls.__name__}: {k!r} is not one of its fields "
                            f"({', '.join(names)}){did_you_mean(k, names)}")  # fmt: skip


def fields_checked(cls):
    """A dataclass ``cls`` whose misspelt keyword is named with its nearest field
    (:func:`known_fields`), and whose signature stays that of its fields (a ``__new__`` of
    ``*args, **kw`` had hidden them from ``help`` and ``inspect``)."""
    import inspect

    sig = inspect.signature(cls)  # (the dataclass's generated __init__'s, before __new__)

    def __new__(klass, /, *args, **kw):  # (positional only: a field may be named anything)
        known_fields(klass, kw)
        return object.__new__(klass)

    cls.__new__ = staticmethod(__new__)
    cls.__signature__ = sig
    return cls


def keywords_of(func, passed_on, *, skip=(), also=(), caller: str = "") -> None:
    """Each name in ``passed_on`` (keywords a function hands on to ``func``) must be a
    parameter of ``func`` outside ``skip``; otherwise a TypeError naming the nearest of those
    and of ``also`` (the caller's own keywords, a likely slip of the pen)."""
    import inspect

    known = [k for k in inspect.signature(func).parameters if k not in skip]
    for k in passed_on:
        if k not in known:
            hint = did_you_mean(k, [*known, *also])
            if not hint and k in ALPHA_PARAMETERS and "rho_inf" in known:  # (HHT's alpha)
                hint = ("; the generalized-alpha family (genalpha, hht, newmark) takes rho_inf, "
                        "its spectral radius at infinity, from which alpha_m, alpha_f, beta "
                        "and gamma follow (Baumgarte's alpha and beta: Isolation(alpha=, "
                        "beta=))")  # fmt: skip
            raise TypeError(f"{caller}got an unexpected keyword argument {k!r}{hint}")


ALPHA_PARAMETERS = ("alpha", "alpha_f", "alpha_m", "beta", "gamma")


# the tightest meaningful relative tolerance: 100 times double precision's epsilon 2**-52, the
# floor SciPy's solve_ivp raises a smaller rtol to; below it the relative error test measures
# round-off, and with a tiny atol no step passes (a step underflow or a spent step budget
# whose message would blame the model). Rounded down to the 2.2e-14 its messages print (its
# exact 2.22e-14 refused a 2.2e-14 "expected 2.2e-14 <= rtol")
RTOL_MIN = 2.2e-14


def rel_tol(name: str, value) -> float:
    """A relative tolerance ``RTOL_MIN <= value < 1`` as a float, or ValueError naming
    ``name`` (a tolerance of 1 or more lets an adaptive step accept any error: a run of
    nonsense; below ``RTOL_MIN`` the error test measures round-off)."""
    what = (f"a relative tolerance {RTOL_MIN:.2g} <= {name} < 1 (about 100x double precision's "
            "epsilon)")  # fmt: skip
    return number(name, value, what, lambda v: RTOL_MIN <= v < 1)


INT64_MAX = 2**63 - 1  # the largest count a compiled loop holds


def whole(name: str, value, lo: int = 0, what: str = "", hi: int | None = INT64_MAX) -> int:
    """``value`` as an int from ``lo`` to ``hi`` (a count, a number of steps; a seed takes
    ``hi=None``), or ``ValueError("{name}: expected {what}, got {value!r}")``; a bool or a
    float is never taken (2.7 steps is no count). ``what`` defaults to "a whole number >= lo"."""
    import numpy as np

    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < lo:
        raise ValueError(f"{name}: expected {what or f'a whole number >= {lo}'}, got {value!r}")
    if hi is not None and value > hi:
        raise ValueError(f"{name}: expected {what or f'a whole number >= {lo}'} and at most "
                         f"{hi}, got {value!r}")  # fmt: skip
    return int(value)


def flag(name: str, value) -> bool:
    """``value`` as a bool, or TypeError naming ``name``: a text "no" was truthy (True)."""
    import numpy as np

    if not isinstance(value, bool | np.bool_):
        raise TypeError(f"{name}: expected True or False, got {value!r}")
    return bool(value)


def non_negative_int(name: str, value) -> int:
    """``value`` as an int, or ValueError naming ``name`` (a seed, a count)."""
    return whole(name, value, 0, "a non-negative integer", hi=None)


def finite_numbers(name: str, value, what: str, size: int | None = None):
    """``value`` as a non-empty 1-D float array of finite numbers (``size`` of them when
    given), or ``ValueError("{name}: expected {what}, got {value!r}")``: text, complex
    numbers, bools, nested or ragged lists and NaN are refused, never converted."""
    import numpy as np

    try:
        a = np.asarray(value, dtype=float)
        ok = not isinstance(value, str | bytes) and np.asarray(value).dtype.kind in "iuf"
        if ok and not isinstance(value, np.ndarray):  # [True, 1.0] is float: True is no 1.0
            flat = np.asarray(value, dtype=object).ravel().tolist()
            ok = not any(isinstance(x, bool | np.bool_) for x in flat)
    except (TypeError, ValueError, OverflowError):  # (an int beyond a double: named)
        a, ok = np.empty(0), False
    if not (ok and a.ndim == 1 and a.size and (size is None or a.size == size)
            and np.all(np.isfinite(a))):  # fmt: skip
        raise ValueError(f"{name}: expected {what}, got {value!r}")
    return a


def got_array(a, *shapes: tuple) -> str:
    """What an array refused as one of ``shapes`` of finite numbers is (None in a shape: any
    length): "shape (n, k)" when its shape is none of them, else its first entry that is not
    finite, "row i: [x, nan]" or "entry i: nan" (a NaN was blamed on a shape that was right)."""
    import numpy as np

    a = np.asarray(a, dtype=float)
    bad = np.argwhere(~np.isfinite(a))
    fits = any(len(s) == a.ndim and all(k in (None, n) for k, n in zip(s, a.shape, strict=False))
               for s in shapes)  # fmt: skip
    if not fits or not bad.size:
        return f"shape {a.shape}"
    i = int(bad[0, 0])
    return f"row {i}: {a[i].tolist()}" if a.ndim == 2 else f"entry {i}: {a[i]}"


def number(name: str, value, what: str, ok=None, *, finite: bool = True) -> float:
    """``value`` as a float, or ``ValueError("{name}: expected {what}, got {value!r}")`` when
    it is text or a bool (never converted), not a number, not finite (NaN only, with
    ``finite=False``: an end time of inf is none), or fails ``ok``."""
    import math

    import numpy as np

    v = math.nan
    if not isinstance(value, str | bool | np.bool_):
        try:
            v = float(value)
        except (TypeError, ValueError, OverflowError):  # (an int beyond a double: named)
            pass
    if not (math.isfinite(v) if finite else v == v) or (ok is not None and not ok(v)):
        raise ValueError(f"{name}: expected {what}, got {value!r}")
    return v


def real_samples(name: str, a, what: str = "real samples"):
    """``a`` as a non-empty 1-D float64 array (a copy: the caller's array stays theirs) of
    finite values, or ValueError naming ``name`` and expecting ``what``: text, complex numbers
    (the imaginary part was dropped with only a numpy warning) and bools are refused, never
    converted."""
    import numbers

    import numpy as np

    try:  # (ragged lists: numpy's "inhomogeneous shape", naming nothing)
        obj = np.asarray(a)
        kind = obj.dtype.kind
        if kind == "O":  # (Fractions, any numbers.Real: numbers; text or None among them: not)
            real = all(isinstance(x, numbers.Real) and not isinstance(x, bool | np.bool_)
                       for x in obj.ravel())  # fmt: skip
            kind = "f" if real else "O"
        arr = np.array(a, dtype=np.float64, order="C") if kind in "iuf" else None
    except (TypeError, ValueError, OverflowError):  # (an int or Fraction beyond a double)
        raise ValueError(f"{name}: expected {what}, got {a!r}"[:200]) from None
    if arr is None:
        got = {"c": "complex", "b": "bool", "U": "text", "S": "text"}.get(kind, "non-numeric")
        raise ValueError(f"{name}: expected {what}, got {got} values")
    if arr.ndim != 1 or arr.size < 1:
        raise ValueError(f"{name}: expected a non-empty 1-D array, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        k = int(np.flatnonzero(~np.isfinite(arr))[0])
        raise ValueError(f"{name}: expected finite values, sample {k} is {arr[k]}")
    return arr


MAX_OUTPUTS = 10_000_000  # output samples of one run (of 8 columns: 640 MB)
MAX_STEPS = 200_000_000  # fixed or least steps of one run: refused beyond (hours of stepping)
MAX_POINTS = 10_000  # frequencies of one curve: each a periodic solve of seconds
MAX_AMPLITUDES = 1000  # curves of one sweep (each a continuation over its frequencies)


def output_count(t_end: float, dt_out: float) -> int:
    """Output samples of a run of ``t_end`` every ``dt_out`` [s] (the first included), or
    ValueError naming dt_out beyond ``MAX_OUTPUTS`` (an array of that size would not fit), or
    not a positive finite step (0 divided by zero), or a run that is not positive."""
    number("dt_out", dt_out, "a positive output step [s]", lambda v: v > 0)
    number("t_end", t_end, "a positive duration [s]", lambda v: v > 0)
    n = t_end / dt_out
    if not n <= MAX_OUTPUTS:
        raise ValueError(f"dt_out: {n:.3g} outputs of {dt_out:.3g} s over {t_end:.3g} s "
                         f"exceed {MAX_OUTPUTS:.0e}; expected a longer output step or a "
                         "shorter run")  # fmt: skip
    return int(math.floor(n * (1 + 1e-12))) + 1


def output_step(dt_out, span: float, off: bool = True) -> None:
    """A run's output step over ``span`` [s]: None (the default), 0 (no output, where ``off``),
    or a positive step no longer than the run within :data:`MAX_OUTPUTS`; else ValueError
    naming dt_out. Checked where a run is called and before a scene's run says it starts."""
    if dt_out is None or (off and not isinstance(dt_out, str | bool) and dt_out == 0):
        return
    number("dt_out", dt_out, f"a positive output step no longer than the run ({span:g} s)"
           + (", or 0 for no output" if off else ""), lambda v: 0 < v <= span)  # fmt: skip
    output_count(span, dt_out)


SNAP = 1e-6  # a last output within this share of the run of its end is the end (output_times)


def output_times(t0: float, t_end: float, dt_out: float):
    """Outputs from ``t0`` every ``dt_out`` [s], and ``t_end`` itself where that grid
    misses it: a run ends at its end, whatever the output step (its last interval shorter
    then; a last output within :data:`SNAP` of the run's span, and 1e-3 dt_out, of the end,
    a rounding error of a step that divides the run, is moved onto it, not followed by a
    second one a rounding error later). ValueError as :func:`output_count`."""
    import numpy as np

    n = output_count(t_end - t0, dt_out)
    t = t0 + dt_out * np.arange(n)
    near = min(SNAP * (t_end - t0), 1e-3 * dt_out)  # (a rounding error, not a real sample)
    if abs(t_end - t[-1]) <= near and n > 1:  # (a step dividing the run but for its rounding:
        t[-1] = t_end  # a float32 0.02 s left 2e-7 s before a 10 s end)
    elif t_end - t[-1] > 1e-9 * dt_out:
        t = np.append(t, t_end)
    return t


def step_count(t_end: float, h: float, name: str = "h") -> float:
    """Steps of ``h`` over ``t_end``, or ValueError naming ``name`` beyond ``MAX_STEPS``."""
    n = t_end / h
    if not n <= MAX_STEPS:
        raise ValueError(f"{name}: {n:.3g} steps of {h:.3g} s exceed {MAX_STEPS:.0e}; expected "
                         "a larger step or a shorter run")  # fmt: skip
    return n


FIXED_DT = 0.005  # s, a fixed-step method's step when none is given (records of 200 Hz)


def sampling_step(motion) -> float | None:
    """The sampling step [s] of a sampled excitation (a record, a table), else None."""
    dt = getattr(motion, "dt", None)
    return float(dt) if isinstance(dt, int | float) and dt > 0 else None


def forcing_frequency(motion) -> float | None:
    """The highest frequency [Hz] of a harmonic excitation's components that have an
    amplitude (Harmonic: A_hor at f_hor, A_ver at f_ver; HarmonicForce: F at f; HarmonicPlane:
    ax, ay at f, az at f_z), or None (a record, a table, a pulse: no such components)."""
    fs = []
    for a, k in (("A_hor", "f_hor"), ("A_ver", "f_ver"), ("F", "f"), ("ax", "f"), ("ay", "f"),
                 ("az", "f_z" if getattr(motion, "f_z", None) is not None else "f")):  # fmt: skip
        amp, f = getattr(motion, a, None), getattr(motion, k, None)
        if isinstance(amp, int | float) and amp != 0 and isinstance(f, int | float):
            fs += [f] if 0 < f < math.inf else []
    return max(fs) if fs else None


SAMPLES_PER_PERIOD_MIN = 20  # fewer output samples per excitation period miss the peaks
# a record's outputs further apart than this (or than its sampling step, if longer) read a
# 2.5 Hz floor response fewer than 20 times a period: a peak between two outputs is read low
# by up to 1 - cos(pi f dt_out), 1.2 % at 0.02 s (the scenes' default grid) and 29 % at 0.1 s
# (the bound was 10 samples, 0.1 s at 100 Hz: a shear building's floor peak read 27 % low)
RECORD_OUTPUT_MAX = 0.02  # s


def coarse_output_note(dt_out: float, motion, field: str = "dt_out") -> str | None:
    """A harmonic excitation sampled fewer than SAMPLES_PER_PERIOD_MIN times per period by
    outputs ``dt_out`` apart, or a record's outputs further apart than RECORD_OUTPUT_MAX (or
    its sampling step): the peaks fall between the outputs (one line naming ``field`` and its
    bound)."""
    h = sampling_step(motion)
    span = (getattr(motion, "n", 0) - 1) * (h or 0.0)  # (a longer dt_out is refused: no note)
    return coarse_grid_note(dt_out, forcing_frequency(motion), h, span, field)


def output_gap(t) -> tuple[float, str]:
    """(widest gap, the input it came from) of output times ``t`` (at least two): "dt_out"
    for evenly spaced times, else "t_eval" (given as such: a note names it, not dt_out)."""
    import numpy as np

    gap = np.diff(np.asarray(t, dtype=float))
    even = gap[:-1] if gap.size > 2 else gap  # (a dt_out grid keeps the run's end: its last
    step = np.ptp(even) <= 1e-9 * gap.max() and gap[-1] <= gap[0] * (1 + 1e-9)  # gap shorter)
    return float(gap.max()), "dt_out" if step else "t_eval"


def coarse_grid_note(dt_out: float, f, h, span: float, field: str = "dt_out") -> str | None:
    """:func:`coarse_output_note` of an excitation given by its harmonic frequency ``f`` [Hz]
    or its sampling step ``h`` [s] and its ``span`` [s] (None where it has none). ``field``
    names the input to change ("t_eval": output times given, ``dt_out`` their widest gap)."""
    bound = max(h or 0.0, RECORD_OUTPUT_MAX)  # (a 50 Hz record: every sample)
    head = f"dt_out = {dt_out:g} s"  # (output times given: their widest gap, named so)
    if field == "t_eval":
        head = f"output times (t_eval) up to {dt_out:g} s apart"
    fix = "t_eval's outputs at most" if field == "t_eval" else f"{field} <="
    s = "" if field == "t_eval" else "s"  # (one step reads, times read)
    if h and bound * (1 + 1e-9) < dt_out < span:
        return (f"{head} read{s} the peaks every {dt_out / h:.3g} samples of the record "
                f"({h:g} s): they fall between the outputs; set {fix} {bound:g} s"
                + " apart" * (field == "t_eval"))  # fmt: skip
    if f and dt_out * f * SAMPLES_PER_PERIOD_MIN > 1.0 + 1e-9:
        return (f"{head} sample{s} the {f:g} Hz excitation {1.0 / (f * dt_out):.3g} times per "
                f"period: the peaks fall between the samples; set {fix} "
                f"{1.0 / (SAMPLES_PER_PERIOD_MIN * f):.3g} s"
                + " apart" * (field == "t_eval"))  # fmt: skip
    return None


def default_step(motion, dt: float = FIXED_DT) -> float:
    """A fixed-step method's step when none is given: ``dt``, or the motion's sampling step
    where that is shorter (every sample is stepped on), or a twentieth of a harmonic forcing's
    period where that is (:data:`STEPS_RESOLVING`; :data:`STEPS_PER_PERIOD` the fewest)."""
    rec, f = sampling_step(motion), forcing_frequency(motion)
    dt = dt if rec is None else min(dt, rec)
    return dt if f is None else min(dt, 1.0 / (STEPS_RESOLVING * f))


def check_fixed_step(dt, motion, span: float | None = None, where: str = "dt") -> None:
    """A fixed step ``dt`` no longer than the run's ``span`` (one step over everything: no
    run), nor than the sampling step of ``motion``: a longer one passes over samples, and the
    peaks come out wrong (x_iso 1.79 m against 0.2765 at dt = 1 s on the default scene's
    record; a normal force dipping below zero at 0.2 s). ValueError naming ``where``."""
    if dt is None:
        return
    if span is not None and math.isfinite(dt) and dt > span:
        raise ValueError(f"{where}: a fixed step of {dt:g} s is longer than the run "
                         f"({span:g} s)")  # fmt: skip
    if span is not None and span > 0 and dt > 0:
        step_count(span, dt, where)  # (an exported script of 2e10 steps was written)
    rec = sampling_step(motion)
    if rec is not None and dt > rec * (1 + 1e-9):
        raise ValueError(f"{where}: a fixed step of {dt:g} s is longer than the record's "
                         f"sampling step {rec:g} s: the steps would pass over its samples; "
                         f"expected at most {rec:g} s")  # fmt: skip
    f = forcing_frequency(motion)
    if f is not None and dt * f * STEPS_PER_PERIOD > 1 + 1e-9:  # (a harmonic's own "samples")
        T = 1.0 / f
        raise ValueError(f"{where}: a fixed step of {dt:g} s is {dt / T:.3g} of the forcing "
                         f"period {T:.4g} s: expected at most T/{STEPS_PER_PERIOD} = "
                         f"{T / STEPS_PER_PERIOD:.4g} s ({STEPS_PER_PERIOD} steps a period "
                         f"follow the forcing, {STEPS_RESOLVING} or more resolve its "
                         "peaks)")  # fmt: skip
    if f is not None and dt * f * STEPS_RESOLVING > 1 + 1e-9:
        import warnings

        n = 1.0 / (dt * f)  # (the trapezoidal rule's period error (omega h)^2 / 12)
        warnings.warn(f"{where}: a fixed step of {dt:g} s is T/{n:.3g} of the forcing period "
                      f"{1 / f:.4g} s, where a second-order step's period error is about "
                      f"(2 pi dt/T)^2/12 = {(2 * math.pi / n) ** 2 / 12:.2%}; at most "
                      f"T/{STEPS_RESOLVING} = {1 / (STEPS_RESOLVING * f):.4g} s resolves its "
                      "peaks", NotedWarning, stacklevel=3)  # fmt: skip


# the fewest fixed steps per period of a harmonic forcing: at dt = 1.5 T the force was sampled
# at its zeros only (a slip of 6e-17 m against 0.048 m), at 0.75 T the slip was 50 % too large
STEPS_PER_PERIOD = 8
STEPS_RESOLVING = 20  # steps a period that resolve its peaks: a step not given takes at most T/20


class NumericalFailure(RuntimeError):
    """A numerical method failed where the model is still valid: a step size underflow, a
    contact problem with no solution, a step or event budget spent, a non-finite state. The
    message says when (t or f) and why; the command line ends with status 3."""


def mapped(T, q, name: str = "q"):
    """``T @ q`` for coordinates ``q`` of shape (n,) or (n, ...), n = T's columns; otherwise a
    ValueError naming ``name`` and n (numpy's matmul said "mismatch in its core dimension")."""
    import numpy as np

    q = np.asarray(q)
    n = T.shape[1]
    if q.ndim == 0 or q.shape[0] != n:
        raise ValueError(f"{name}: expected {n} coordinates (shape ({n},) or ({n}, ...)), got "
                         f"shape {q.shape}")  # fmt: skip
    return T @ q


def fingerprint(obj, names) -> tuple:
    """Each named array of ``obj`` as :func:`_bit_sums` (None for an operator): a model's
    matrices as its caches were made from them. A copy of any memory order and a pickle's
    round trip keep it; an edit of an entry, a swap of rows or columns, a contact moved to
    another dof move it (bar edits whose bit changes cancel). O(size), no hash of the bytes:
    about 3 ms per dense 2000 x 2000 matrix."""
    import numpy as np

    out = []
    for name in names:
        a = getattr(obj, name)
        if hasattr(a, "tocsr"):  # (a sparse matrix: its pattern and entries, as stored)
            c = a.tocsr()
            out.append((c.shape, *(_bit_sums(v) for v in (c.indptr, c.indices, c.data))))
        else:
            real = isinstance(a, np.ndarray) and a.dtype.kind in "biuf"
            out.append(_bit_sums(a) if real else None)
    return tuple(out)


def _bit_sums(a) -> tuple:
    """``a``'s shape and position-weighted wrapping sums of its entries' bits as float64
    (exact integer sums, so independent of memory order): of the rows and of the columns for
    a matrix, of the entries for a vector."""
    import numpy as np

    x = np.asarray(a, dtype=float)
    t = x.ndim == 2 and x.flags.f_contiguous and not x.flags.c_contiguous  # (no copy: its
    b = np.ascontiguousarray(x.T if t else x).view(np.uint64)  # transpose, sums swapped)
    parts = (b.ravel(),)
    if b.ndim == 2:
        rows, cols = b.sum(axis=1, dtype=np.uint64), b.sum(axis=0, dtype=np.uint64)
        parts = (cols, rows) if t else (rows, cols)
    w = [np.arange(1, p.size + 1, dtype=np.uint64) for p in parts]
    return (a.shape, *(int((p * wi).sum(dtype=np.uint64)) for p, wi in zip(parts, w, strict=True)))


def unchanged(obj, names, built: tuple, remedy: str) -> None:
    """Refuse ``obj`` when a named array differs from its :func:`fingerprint` ``built``: its
    caches (a static state, a basis, factorised operators) would answer for the old arrays.
    An empty ``built`` (an object pickled before it was kept) is not checked."""
    now = fingerprint(obj, names)
    if built and now != built:
        name = next(n for n, a, b in zip(names, now, built, strict=True) if a != b)
        raise ValueError(f"{getattr(obj, 'name', type(obj).__name__)}: {name} was changed after "
                         f"the model was built; build a new one ({remedy})")  # fmt: skip
