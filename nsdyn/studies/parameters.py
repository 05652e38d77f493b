"""The ``[parameters]`` of a study file: each varied scene field parsed to a :class:`Parameter`
(a grid of values, a linspace or logspace, or a random law), its values distinct, whole numbers
for an integer field. Every error names the file and the field."""

from __future__ import annotations

import math
from dataclasses import dataclass

from nsdyn._checks import did_you_mean
from nsdyn.models.scenefile import SceneError, number, unknown_key

NUMERIC_FIELDS = {"motion.rotate": "angles in degrees"}  # parameters that must be numbers
GRID_FORMS = ("values", "linspace", "logspace")
RANDOM_FORMS = ("uniform", "loguniform", "normal", "lognormal")
MAX_TASKS = 1_000_000  # refuse studies larger than this (a typo in a grid)
# scene fields a study does not vary: what it says of each
OWN_FIELDS = {
    "scene.kind": "a study runs the one scene kind of its base scene; run a study per kind",
    "scene.name": "names the run, not its physics: every name would repeat the same run; the "
    "table names each task by its parameters",
}


@dataclass(frozen=True)
class Parameter:
    """One varied scene field: ``name`` = "table.field"; grid ``values`` or a random law."""

    name: str
    values: tuple = ()
    law: str | None = None  # one of RANDOM_FORMS for a random parameter
    args: tuple = ()

    @property
    def random(self) -> bool:
        return self.law is not None


def _err(source: str, where: str, msg: str) -> SceneError:
    return SceneError(f"{source}: {where}: {msg}")


def whole_numbers(source: str, p: Parameter, whole: set[str], real=frozenset()) -> Parameter:
    """``p`` with its values as ints where its field is an integer one (a linspace's 3.0 is
    written 3 to the table and read as 3 by the scene); a fraction or a random law there is
    refused, naming the field. Where the field is a real number (``real``) its whole values
    are floats: [2, 3] is the same tasks as [2.0, 3.0] (it ran them all again)."""
    if p.name in real and not p.random:
        return Parameter(p.name, values=tuple(
            float(v) if isinstance(v, int) and not isinstance(v, bool) else v
            for v in p.values))  # fmt: skip
    if p.name not in whole:
        return p
    where = f"parameters.{p.name}"
    if p.random:
        raise _err(source, f"{where}.{p.law}", "an integer field takes whole numbers (a list, "
                   "linspace or logspace of them), not a random law")  # fmt: skip
    out = []
    for v in p.values:
        ok = isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
        if not ok or abs(v - round(v)) > 1e-9 * max(1.0, abs(v)):
            raise _err(source, where, f"expected whole numbers (an integer field), got {v!r}")
        out.append(int(round(v)))
    return Parameter(p.name, values=tuple(out))


def parse_parameter(source: str, name: str, spec, known: set[str]) -> Parameter:
    where = f"parameters.{name}"
    if name in OWN_FIELDS:  # (scene.name ran one run once per name; scene.kind misled)
        raise _err(source, where, OWN_FIELDS[name])
    own = sorted(k for k in known if k.startswith(f"{name}."))
    if own:  # (a table: it was "unknown scene field; did you mean 'bearing.c'?")
        shown = ", ".join(own[:6]) + (", …" if len(own) > 6 else "")
        raise _err(source, where, f"[{name}] is a table; a parameter varies one of its fields "
                   f"({shown})")  # fmt: skip
    if name not in known:
        leaf = [k for k in sorted(known) if k.rsplit(".", 1)[-1] == name.rsplit(".", 1)[-1]]
        hint = (did_you_mean(name, leaf) or f"; did you mean {leaf[0]!r}?" if leaf  # 'bearing.mu'
                else did_you_mean(name, sorted(known)))  # fmt: skip
        tables = sorted({k.split(".", 1)[0] for k in known})  # (the example named this key)
        raise SceneError(f"{source}: {where}: unknown scene field{hint} (expected 'table.field' "
                         f"of this scene's tables: {', '.join(tables)})")  # fmt: skip
    if isinstance(spec, list):
        if not spec:  # (named as written, not as parameters.NAME.values)
            raise _err(source, where, "expected a non-empty list of values, got []")
        spec = {"values": spec}
    if not isinstance(spec, dict) or len(spec) != 1:
        raise _err(
            source,
            where,
            "expected a list of values or one of { values | linspace | logspace | "
            f"{' | '.join(RANDOM_FORMS)} = [...] }}, got {spec!r}",
        )
    ((form, args),) = spec.items()
    if form not in GRID_FORMS + RANDOM_FORMS:
        raise unknown_key(source, f"{where}.", form, GRID_FORMS + RANDOM_FORMS)
    if not isinstance(args, list) or not args:
        raise _err(source, f"{where}.{form}", f"expected a non-empty list, got {args!r}")
    if form == "values":
        kinds = {type(v) for v in args}
        if name in NUMERIC_FIELDS and not kinds <= {int, float}:
            bad = next(v for v in args if isinstance(v, bool) or not isinstance(v, int | float))
            raise _err(source, f"{where}.values",
                       f"expected numbers ({NUMERIC_FIELDS[name]}), got {bad!r}")  # fmt: skip
        if not (kinds <= {int, float} or kinds <= {str} or kinds <= {bool}):
            raise _err(source, f"{where}.values", f"expected numbers, strings or booleans, all "
                       f"of one kind, got {args!r}")  # fmt: skip
        return Parameter(name, values=distinct(source, f"{where}.values", args, name))
    nums = [number(source, f"{where}.{form}[{i}]", a, positive=False) for i, a in enumerate(args)]
    if form in ("linspace", "logspace"):
        if len(nums) != 3 or nums[2] != int(nums[2]) or not 1 <= nums[2] <= MAX_TASKS:
            what = f"expected [first, last, count], a count of 1 to {MAX_TASKS}, got {args!r}"
            raise _err(source, f"{where}.{form}", what)  # (a count of 1e9 filled the memory)
        a, b, n = nums[0], nums[1], int(nums[2])
        if n == 1 and a != b:  # (it ran `first` alone, without a word)
            raise _err(source, f"{where}.{form}", f"a count of 1 takes `first` alone and "
                       f"drops `last` ({b:g}); expected a count >= 2, or one value")  # fmt: skip
        if form == "logspace":
            if not (a > 0 and b > 0):
                raise _err(source, f"{where}.logspace", f"expected positive ends, got {args!r}")
            vals = [a * (b / a) ** (i / (n - 1)) if n > 1 else a for i in range(n)]
        else:
            vals = [a + (b - a) * i / (n - 1) if n > 1 else a for i in range(n)]
        return Parameter(name, values=distinct(source, f"{where}.{form}", vals, name))
    if len(nums) != 2:
        raise _err(source, f"{where}.{form}", f"expected two numbers, got {args!r}")
    a, b = nums
    ok = {"uniform": a < b, "loguniform": 0 < a < b, "normal": b > 0, "lognormal": a > 0 < b}
    if not ok[form]:
        what = {
            "uniform": "[low, high] with low < high",
            "loguniform": "[low, high] with 0 < low < high",
            "normal": "[mean, std] with std > 0",
            "lognormal": "[median, beta] both positive",
        }[form]
        raise _err(source, f"{where}.{form}", f"expected {what}, got {args!r}")
    return Parameter(name, law=form, args=(a, b))


def distinct(source: str, where: str, vals: list, name: str = "") -> tuple:
    """``vals`` as a tuple, refused when a value repeats (two tasks of one key: one row), an
    angle (:data:`NUMERIC_FIELDS`) modulo 360° (0 and 360 deg: one incident direction)."""
    seen: dict = {}
    for v in vals:
        k = round(v % 360.0, 9) % 360.0 if name in NUMERIC_FIELDS else v
        if k in seen:
            same = "twice" if seen[k] == v else f"and {seen[k]!r}, one direction (modulo 360)"
            raise _err(source, where, f"expected distinct values, got {v!r} {same}")
        seen[k] = v
    return tuple(vals)
