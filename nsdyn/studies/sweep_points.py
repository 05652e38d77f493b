"""Sweep checkpoints' parts: an orbit point as a JSON record and back, a checkpoint file's
data, and the frequencies a resumed ``--no-fallback`` curve left without a point (the rest of
the checkpoints, their identity and refusal, is :mod:`nsdyn.studies.sweep`'s)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np


def point_to_dict(p) -> dict:
    """JSON-able record of an :class:`nsdyn.periodic.OrbitPoint` (without its orbit)."""
    mu = np.asarray(p.multipliers)
    return {
        "f": p.f,
        "x0": np.asarray(p.x0).tolist(),
        "method": p.method,
        "converged": bool(p.converged),
        "iterations": int(p.iterations),
        "residual": float(p.residual) if math.isfinite(p.residual) else None,
        "mu_re": mu.real.tolist(),
        "mu_im": mu.imag.tolist(),
        "n_steps": int(p.n_steps),
        "note": p.note,
        "quantities": {
            k: (
                v
                if v is None or isinstance(v, str)
                else bool(v)
                if isinstance(v, bool | np.bool_)
                else float(v)
            )
            for k, v in p.quantities.items()
        },
        "s": None if not math.isfinite(p.s) else p.s,
        "dlogf_ds": None if not math.isfinite(p.dlogf_ds) else p.dlogf_ds,
    }


def point_from_dict(d: dict):
    from nsdyn.periodic import OrbitPoint

    nan = float("nan")
    return OrbitPoint(
        f=float(d["f"]),
        x0=np.asarray(d["x0"], dtype=float),
        method=d["method"],
        converged=bool(d["converged"]),
        iterations=int(d["iterations"]),
        residual=nan if d["residual"] is None else float(d["residual"]),
        multipliers=np.asarray(d["mu_re"]) + 1j * np.asarray(d["mu_im"]),
        n_steps=int(d["n_steps"]),
        note=d["note"],
        quantities=dict(d["quantities"]),
        s=nan if d["s"] is None else float(d["s"]),
        dlogf_ds=nan if d["dlogf_ds"] is None else float(d["dlogf_ds"]),
    )


def checkpoint_data(path: Path) -> tuple[dict | None, str]:
    """(the checkpoint file's data, "") or (None, "" without a file, else "unreadable")."""
    try:
        data = json.loads(Path(path).read_text())
        if not isinstance(data, dict):
            raise ValueError(path)
    except FileNotFoundError:
        return None, ""
    except (OSError, ValueError):
        return None, "unreadable"
    return data, ""


def skipped_before(ckpt: Path, start, settings) -> list:
    """The [f, why] of the frequencies a resumed ``--no-fallback`` sequential curve left
    without a point below its last one (a rerun does not revisit them): the grid's that no
    resumed point holds, with the reason the checkpoint kept (a finished run's), else that
    of an interrupted run, which kept none."""
    if not start or settings.fallback:
        return []
    from nsdyn.periodic.continuation import log_frequencies

    kept = (checkpoint_data(ckpt)[0] or {}).get("skipped")  # (a malformed one: none kept)
    kept = [x for x in (kept if isinstance(kept, list) else [])
            if isinstance(x, list) and len(x) == 2 and isinstance(x[0], int | float)]  # fmt: skip
    have = np.array([p.f for p in start])
    if settings.continuation != "sequential":  # (off the grid: the kept ones below the last)
        return [(float(f), str(w)) for f, w in kept if f < have[-1]]
    out = []
    for f in log_frequencies(settings.fmin, settings.fmax, settings.points):
        if f >= have[-1] or np.any(np.abs(have - f) <= 1e-9 * f):
            continue
        why = next((str(w) for g, w in kept if abs(float(g) - f) <= 1e-9 * f), None)
        out.append((float(f), why or "no periodic orbit in an earlier, interrupted run (its "
                    "reason was not kept)"))  # fmt: skip
    return out
