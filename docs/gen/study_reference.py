"""The study-file reference: every table and key of a study file, from the reader's own lists.

The keys come from the constants the study reader (``nsdyn/studies/study.py``) and the
analyses (``nsdyn/studies/analyses.py``) check files against; the meanings are written here,
one per key, and ``tests/docs/test_study_reference.py`` checks that the two name the same keys.
"""

from __future__ import annotations

STUDY = {
    "name": "the study's name: its output folder `nsdyn-study/NAME` (default: the file's stem)",
    "scene": "the base scene file, relative to the study file (default: the isolated frame's "
    "default scene)",
    "keep": "result fields kept per run (default: every scalar field of the run's summary)",
    "samples": "joint random draws of the random parameters (default 0: none)",
    "seed": "seed of those draws (default 0)",
    "batch": "tasks per batch sent to a worker (default 0: automatic, about 6 batches per worker "
    "and at most 64 tasks each)",
}
RECORDS = {
    "names": "bundled record names or files (relative to the study file)",
    "folder": "a folder whose files matching `glob` are records",
    "glob": 'the pattern of `folder`\'s files (default `"*"`)',
    "set": '`"kobe"`: the four 1995 Kobe records (read in place from the shared records); '
    '`"bundled"`: every bundled record',
    "simulated": "simulated earthquakes, `{n, seed, duration, dt, generator}` (below)",
    "pairs": "records given by component files, a list of `{name, x, y, z}` (below); scene "
    "kinds `deck`, `building3d` and `cylinder`",
}
SIMULATED = {
    "n": "number of records (required)",
    "seed": "the seed (required); each record's own seed is drawn from numpy's SeedSequence of it",
    "duration": "length [s] (default 20)",
    "dt": "sample step [s] (default 0.01)",
    "generator": "the generator (seed 000 §4.1; default the modulated white noise)",
}
PAIRS = {
    "name": "the record's name in the results (default: the x file's stem)",
    "x": "the first horizontal component's file",
    "y": "the second horizontal component's file",
    "z": "the vertical component's file (optional)",
}
ANALYSES = {
    "design": {
        "variables": "the parameters that make a design (default: every grid parameter but "
        "`motion.seed`, an earthquake axis like the records)",
        "objectives": "results to minimise (default `idr_max`, `floor_acc_max_mps2`, seed 004 §5)",
        "constraints": "`{result = upper bound}` or `{result = {min = a, max = b}}` (default "
        "`x_iso_max_m` within the 0.4 m seismic gap)",
        "aggregate": "how a design's runs over records and draws combine: `mean` (default), "
        "`median` or `max`",
        "reference": "`{parameter = value}`: a design of the grid to compare with (which "
        "feasible designs dominate it), a value for each of the design's variables",
    },
    "percentiles": {
        "quantities": "the results tabulated",
        "by": "the parameters the table is grouped by (default: every grid parameter but "
        "`motion.seed`)",
        "percentiles": "the percentiles, each in 0..100 (default 16, 50, 84: the median and the "
        "±1σ band of a lognormal spread)",
    },
    "fragility": {
        "im": "the intensity measure, a column (required; e.g. `motion.pga`)",
        "edp": "the demand, a result (required; e.g. `idr_max`)",
        "limits": "the limit states, values of `edp`; one lognormal curve each",
        "confidence": "level of the confidence band, in (0, 1) (default 0.95)",
    },
    "incidence": {
        "angle": 'the incident-angle parameter (default `"motion.rotate"`, degrees)',
        "quantities": "the results compared over the angles (default: the scene kind's peaks)",
    },
}


def _table(rows: dict, extra: dict | None = None) -> list[str]:
    lines = ["| key | meaning |", "|---|---|"]
    for key, text in rows.items():
        lines.append(f"| `{key}` | {text}{(extra or {}).get(key, '')} |")
    return lines + [""]


def page() -> str:
    """The Markdown of ``reference/studies.md``."""
    from nsdyn.studies.study import GENERATORS, GRID_FORMS, RANDOM_FORMS, SIMULATED_FIELDS

    types = {k: f" ({t.__name__})" for k, t in SIMULATED_FIELDS.items()}
    types["generator"] = f": one of {', '.join(f'`{g}`' for g in GENERATORS)}"
    lines = [
        "# Study-file reference",
        "",
        "A study is a TOML file that `nsdyn study STUDY.toml` runs: a base scene over a grid of",
        "parameters, random draws and a set of records, then its analyses (the",
        "[studies guide](../guide/studies.md) shows them at work). Every table and key is",
        "listed below; a key that is not listed is refused with the nearest valid one, and a",
        "value of the wrong form with the file, the field and the expected form.",
        "This page is generated from the lists the study reader checks files against",
        "(`nsdyn/studies/study.py`, `nsdyn/studies/analyses.py`). Example studies are in",
        "`examples/studies/`.",
        "",
        "## `[study]`",
        "",
        *_table(STUDY),
        "## `[base.TABLE]`",
        "",
        "Scene tables merged over the base scene's own (`[base.motion] t_end = 20.0`); the keys",
        "are the scene kind's ([scene-file reference](scenes.md)).",
        "",
        "## `[parameters]`",
        "",
        '`"table.field" = FORM`, a scene field of the base scene\'s kind and its values (any key',
        "of the kind's [scene-file reference](scenes.md) but `scene.kind` and `scene.name`,",
        "whether the base scene sets it or not). Grids",
        f"({', '.join(f'`{f}`' for f in GRID_FORMS)}) multiply; random forms",
        f"({', '.join(f'`{f}`' for f in RANDOM_FORMS)}) are drawn jointly `study.samples`",
        "times:",
        "",
        "| form | values |",
        "|---|---|",
        "| `[v1, v2, …]` or `{ values = [v1, v2, …] }` | the listed values (numbers or texts) |",
        "| `{ linspace = [a, b, n] }` | n values evenly spaced from a to b |",
        "| `{ logspace = [a, b, n] }` | n values evenly spaced in log from a to b (a, b > 0) |",
        "| `{ uniform = [low, high] }` | uniform draws, low < high |",
        "| `{ loguniform = [low, high] }` | log-uniform draws, 0 < low < high |",
        "| `{ normal = [mean, std] }` | normal draws, std > 0 |",
        "| `{ lognormal = [median, beta] }` | lognormal draws, both positive |",
        "",
        "A field its scene reference declares *integer* (`motion.seed`, `motion.n_cycles`,",
        "`solver.max_steps`, …) takes whole numbers, given as a list, a `linspace` or a",
        "`logspace`, and they reach the scene and `results.csv` as integers (`3`, not `3.0`); a",
        "fraction or a random form there is refused, naming the field. (A study begun before",
        "this, with such a field on a `linspace`, reruns those tasks on resume: their keys",
        "hashed `3.0`.)",
        "",
        "## `[records]`",
        "",
        *_table(RECORDS),
        "`simulated = { … }`:",
        "",
        *_table(SIMULATED, types),
        "`pairs = [{ … }, …]`:",
        "",
        *_table(PAIRS),
        "## `[analysis.NAME]`",
        "",
    ]
    for name, rows in ANALYSES.items():
        lines += [f"`[analysis.{name}]`:", "", *_table(rows)]
    return "\n".join(lines)
