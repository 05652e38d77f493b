"""Isolator design search (seed 004 §5) as a study: K_lam x c x mu over a record set, the IDR
and floor-acceleration objectives, the 400 mm gap, the Pareto front and the seed's design.

    python examples/study_design_search.py [--quick] [--kobe] [--out DIR]

``--kobe`` uses the seed's four Kobe records (shared/records); otherwise the bundled study
(two bundled records and two simulated earthquakes). ``--quick`` keeps the first and last value
of each design variable and 5 s of each record (a smoke run of a few seconds; the seed's
design is not among them, and its "reference" says so).
"""

from __future__ import annotations

import argparse
import json
from dataclasses import replace
from pathlib import Path

from nsdyn.cli.args import out_dir
from nsdyn.models.scenefile import SceneError
from nsdyn.studies.analyses import run_analyses
from nsdyn.studies.execute import run_study
from nsdyn.studies.study import load_study

STUDIES = Path(__file__).resolve().parent / "studies"


def main(
    out: str | Path = "nsdyn-out/study-design",
    quick: bool = False,
    kobe: bool = False,
    workers: int | None = None,
    executor=None,
) -> dict:
    name = "seed004-design-kobe.toml" if kobe else "isolator-design.toml"
    study = load_study(STUDIES / name)
    if quick:
        study.parameters = [
            replace(p, values=(p.values[0], p.values[-1])) for p in study.parameters
        ]
        study.base["motion"]["t_end"] = 5.0
        study.name += "-quick"
    run = run_study(study, out, workers=workers, executor=executor)
    an = run_analyses(study, run.table, out, figures=not quick)
    d = an["design"]
    return {
        "n_tasks": run.n_tasks,
        "n_failed": run.n_failed,
        "wall_s": run.wall_s,
        "n_designs": d["n_designs"],
        "n_feasible": d["n_feasible"],
        "pareto": d["pareto"],
        "chosen": d["chosen"],
        "reference": d["reference"]
        if not quick
        else "not run: --quick keeps the first and "
        "last value of each variable, and the seed's design is neither",
        "design_table": d["table"],
    }


if __name__ == "__main__":
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )  # (the first line alone ended mid-sentence)
    ap.add_argument("--out", type=out_dir, default="nsdyn-out/study-design",
                    help="results folder (default nsdyn-out/study-design)")  # fmt: skip
    ap.add_argument("--quick", action="store_true",
                    help="first and last value of each variable, 5 s of each record")  # fmt: skip
    ap.add_argument("--kobe", action="store_true",
                    help="the seed's four Kobe records from shared/records")  # fmt: skip
    a = ap.parse_args()
    try:
        res = main(a.out, a.quick, a.kobe)
    except SceneError as e:  # e.g. --kobe without the shared records: one line, status 2
        ap.exit(2, f"{ap.prog}: error: {e}\n")
    print(json.dumps(res, indent=1))
