"""Write the bundled synthetic ground motions into ``records/`` (deterministic).

Run from the repository root::

    python examples/make_records.py            # writes records/*.csv
    python examples/make_records.py --check    # regenerates in memory and compares with records/

Each record is a synthetic motion of seed 000 §4.1 (modulated white noise) or its Kanai–Tajimi
variant, with a fixed seed, scaled to a horizontal PGA of 3 m/s² (the vertical component with the
same factor). ``main()`` returns the motions so that tests can compare them with the files.

A record listed in ``SECOND_HORIZONTAL`` also gets a second horizontal component a_y in
``records/<stem>-y.txt``: the same generator and parameters with its own seed (an independent
sample of the same process, without vertical), times the *same* scale factor as the first
component, so both horizontal components have the same intensity. ``make_y(stem)`` makes it;
``read_motion3(stem)`` reads a_x, a_y and the vertical together.
"""

import dataclasses
import sys
from pathlib import Path

import numpy as np

from nsdyn.ground import GroundMotion, kanai_tajimi, modulated_white_noise, write_motion

Y_SUFFIX = "-y.txt"  # the companion file of the second horizontal component

COMMAND = "python examples/make_records.py"
PGA = 3.0  # [m/s²] the transient study's PGA (seed 004 §5)
RECORDS_DIR = Path(__file__).resolve().parents[1] / "records"

# file stem -> (generator, keyword arguments incl. seed); every value is written to the header
RECIPES = {
    "synthetic-wn-40s": (
        modulated_white_noise,
        dict(duration=40.0, S0=1.25e-4, dt_ord=0.05, dt=0.01, vertical_ratio=2 / 3, seed=40001),
    ),
    "synthetic-kt-20s": (
        kanai_tajimi,
        dict(
            duration=20.0,
            omega_g=15.6,
            zeta_g=0.6,
            S0=1.25e-4,
            dt=0.01,
            modulate=True,
            vertical_ratio=2 / 3,
            seed=20002,
        ),
    ),
}

# file stem -> seed of its second horizontal component (same recipe otherwise, no vertical)
SECOND_HORIZONTAL = {"synthetic-wn-40s": 40003, "synthetic-kt-20s": 20004}


def make(stem: str) -> GroundMotion:
    """The bundled record ``stem``, generated afresh."""
    generator, kwargs = RECIPES[stem]
    motion = generator(name=stem, **kwargs).scaled_to_pga(PGA)
    return dataclasses.replace(motion, meta={**motion.meta, "command": COMMAND, "pga_target": PGA})


def make_y(stem: str, x: GroundMotion | None = None) -> GroundMotion:
    """The second horizontal component of ``stem``: its recipe with the seed
    ``SECOND_HORIZONTAL[stem]`` and no vertical, times the first component's scale factor."""
    generator, kwargs = RECIPES[stem]
    x = make(stem) if x is None else x
    factor = x.meta["scale_factor"]
    seed = SECOND_HORIZONTAL[stem]
    y = generator(name=f"{stem}-y", **{**kwargs, "vertical_ratio": None, "seed": seed})
    meta = {
        **y.meta,
        "command": COMMAND,
        "scale_factor": factor,
        "component": f"y, the second horizontal component of {stem}",
    }
    return dataclasses.replace(y, a_hor=y.a_hor * factor, meta=meta)


def main(out_dir: Path | None = RECORDS_DIR, write: bool = True) -> dict[str, GroundMotion]:
    """Generate every bundled record; write ``<out_dir>/<stem>.csv`` (and the second horizontal
    components ``<stem>-y.txt``) when ``write``. Returns the records of ``RECIPES``."""
    motions = {stem: make(stem) for stem in RECIPES}
    if write:
        out_dir = Path(out_dir)
        out_dir.mkdir(parents=True, exist_ok=True)
        for stem, motion in motions.items():
            seed = RECIPES[stem][1]["seed"]
            write_motion(motion, out_dir / f"{stem}.csv", command=COMMAND, seed=seed)
        for stem, seed in SECOND_HORIZONTAL.items():
            y = make_y(stem, motions[stem])
            write_motion(y, out_dir / f"{stem}{Y_SUFFIX}", command=COMMAND, seed=seed)
    return motions


if __name__ == "__main__":
    if "--check" in sys.argv:
        from nsdyn.ground import read_motion

        for stem, motion in main(write=False).items():
            stored = read_motion(RECORDS_DIR / f"{stem}.csv")
            # numpy's vectorised exp may differ from libm's by an ulp on some CPUs, so compare
            # to a few ulps of the PGA (the file format itself round-trips bit for bit)
            tol = 16 * np.spacing(stored.pga)
            dev = max(np.max(np.abs(stored.a_hor - motion.a_hor)),
                      np.max(np.abs(stored.a_ver - motion.a_ver)))  # fmt: skip
            verdict = "identical" if dev == 0 else f"within {dev / np.spacing(stored.pga):.0f} ulp"
            print(f"{stem}: {verdict if dev <= tol else 'DIFFERS'}")
            if stem in SECOND_HORIZONTAL:
                y_stored = read_motion(RECORDS_DIR / f"{stem}{Y_SUFFIX}")
                dev = np.max(np.abs(y_stored.a_hor - make_y(stem, motion).a_hor))
                verdict = (
                    "identical" if dev == 0 else f"within {dev / np.spacing(stored.pga):.0f} ulp"
                )
                print(f"{stem}{Y_SUFFIX}: {verdict if dev <= tol else 'DIFFERS'}")
    else:
        for stem, motion in main().items():
            print(f"{RECORDS_DIR / (stem + '.csv')}: {motion}")
