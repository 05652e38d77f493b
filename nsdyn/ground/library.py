"""The record libraries: the synthetic records bundled with nsdyn and the shared research set.

Bundled records live in ``<repo>/records`` of a source tree or the package ``nsdyn.data.records``
when installed (``read_motion(name)`` reads one). The shared research records are read in place
from ``$NSDYN_SHARED`` or ``shared/`` beside the repository, never copied into the project;
:func:`kobe_records` gathers the four 1995 Kobe records of the transient study (seed 004 §5),
each ü(t) in m/s² at its own Δt.
"""

from __future__ import annotations

import os
from pathlib import Path

from nsdyn._bundled import RECORDS, REPO_ROOT
from nsdyn.ground.motion import GroundMotion
from nsdyn.ground.readers import read_motion


def bundled_records() -> list[str]:
    """Names of the bundled synthetic records (``read_motion(name)`` reads one)."""
    return RECORDS.names()


def default_shared_dir() -> Path | None:
    """``$NSDYN_SHARED`` or ``shared/`` beside the repository, if it exists (else None)."""
    env = os.environ.get("NSDYN_SHARED")
    if env:
        return Path(env) if Path(env).is_dir() else None
    # a source checkout beside shared/, or the working directory of one (installed package)
    for candidate in (
        REPO_ROOT.parent / "shared",
        Path.cwd().resolve().parent / "shared",
        Path.cwd().resolve() / "shared",
    ):
        if candidate.is_dir():
            return candidate
    return None


def _records_dir(shared_dir: str | os.PathLike | None) -> Path:
    base = Path(shared_dir) if shared_dir is not None else default_shared_dir()
    if base is None:
        raise FileNotFoundError("no shared records directory: set NSDYN_SHARED")
    for cand in (base / "records", base):
        if (cand / "raw").is_dir():
            return cand
    raise FileNotFoundError(f"{base} holds no records/raw directory")


def kobe_records(
    shared_dir: str | os.PathLike | None = None, component: str = "000"
) -> dict[str, GroundMotion]:
    """The four 1995 Kobe records of the transient study (seed 004 §5), by station.

    Per shared/records/PROVENANCE.md:

    * "KJMA": JMA Kobe, NGA-West2 RSN1106 (raw/kobe_kjma_000.AT2 or _090, g, dt 0.02 s,
      0.834 / 0.630 g), with the UP component (raw/kobe_kjma_up.AT2) as vertical;
    * "Shin-Osaka": RSN1116 SHI000/SHI090 from the FEMA P695 far-field set
      (converted/kobe_shi000_fema_p695.txt, g, dt 0.01 s, 0.243 / 0.212 g); no vertical;
    * "Nishi-Akashi": RSN1111 NIS000/NIS090, same source (converted/kobe_nis000…, 0.509 /
      0.503 g); no vertical;
    * "unidentified": raw/kobe_unidentified_osm.dat, one horizontal component, m/s² (inferred),
      dt 0.02 s, 6.80 m/s². Its PGA matches Takarazuka (≈0.69 g) but the station is
      **unverified**; ``component`` does not apply to it.

    Parameters
    ----------
    shared_dir : path, optional
        The ``shared`` directory (or its ``records`` subdirectory). Default:
        :func:`default_shared_dir`.
    component : {"000", "090"}
        Horizontal component of the three identified stations.
    """
    if component not in ("000", "090"):
        raise ValueError(f"component must be '000' or '090', got {component!r}")
    d = _records_dir(shared_dir)
    out = {
        "KJMA": read_motion(
            d / "raw" / f"kobe_kjma_{component}.AT2",
            vertical=d / "raw" / "kobe_kjma_up.AT2",
            name="KJMA",
        ),
        "Shin-Osaka": read_motion(
            d / "converted" / f"kobe_shi{component}_fema_p695.txt", name="Shin-Osaka"
        ),
        "Nishi-Akashi": read_motion(
            d / "converted" / f"kobe_nis{component}_fema_p695.txt", name="Nishi-Akashi"
        ),
        "unidentified": read_motion(
            d / "raw" / "kobe_unidentified_osm.dat", units="m/s2", name="Kobe (unidentified)"
        ),
    }
    stations = {
        "KJMA": ("JMA Kobe (KJMA), RSN1106", component),
        "Shin-Osaka": ("Shin-Osaka (SHI), RSN1116", component),
        "Nishi-Akashi": ("Nishi-Akashi (NIS), RSN1111", component),
        "unidentified": ("unknown (PGA matches Takarazuka; unverified)", "unknown horizontal"),
    }
    return {
        k: m._replace(meta_update={"station": stations[k][0], "component": stations[k][1]})
        for k, m in out.items()
    }
