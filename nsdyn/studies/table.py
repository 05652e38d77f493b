"""The results table of a study: one CSV row per task, keyed by the task's input hash.

Layout of a study's output directory::

    results.csv        every finished task once, in task order (written at the end and on
                       every resume; atomic)
    parts/part-*.csv   rows of batches finished since (each part written atomically as soon as
                       its batch returns, so a kill loses at most the batches in flight)

Reading merges ``results.csv`` and the parts and keeps one row per key (an ``ok`` row over a
``failed`` one, else the first), so a row written twice — by a run killed between writing
``results.csv`` and removing the parts — is still counted once. Floats are written in their
shortest round-trip form (``repr``), so a table read back is bit-for-bit the table written.

Why CSV and not Parquet: a study's table is small (one row of a few dozen scalars per run;
10⁵ runs is about 20 MB, read in well under a second), appended in small pieces while the
study runs, and read by anything; Parquet would add a dependency for no measurable gain at
this size. :meth:`Table.to_parquet` writes a typed copy when ``pyarrow`` is installed, for
people who load results into pandas or Dask dataframes.
"""

from __future__ import annotations

import csv
import io
import math
import os
import time
from pathlib import Path

import numpy as np

from nsdyn._checks import did_you_mean
from nsdyn.atomic import CheckpointError, atomic_open

RESULTS = "results.csv"
# the rows (failed ones too) of tasks outside the current grid (it was narrowed, or a base field
# changed): kept beside the table, so that a study that widens its grid again reuses them
OUTSIDE = "outside-grid.csv"
# what a study's analyses (and --parquet) write beside the table: a fresh start removes them,
# so that an interrupted fresh run never leaves the previous run's analyses beside its table
ANALYSIS_OUTPUTS = {  # each analysis' (table, figure)
    "design": ("design.csv", "pareto.png"),
    "fragility": ("fragility.csv", "fragility.png"),
    "percentiles": ("percentiles.csv", "distributions.png"),
    "incidence": ("incidence.csv", "incidence.png"),
}
PARQUET = "results.parquet"
ANALYSIS_FILES = (*(f for pair in ANALYSIS_OUTPUTS.values() for f in pair), PARQUET)
PARTS = "parts"
OWNER = ".study.json"  # the study whose results the folder holds: {"name", "kind"}
LEAD_COLUMNS = ("index", "key", "record", "sample")  # first columns, in this order
TAIL_COLUMNS = ("status", "error", "task_s")  # after the parameters


def pyarrow_modules():
    """pyarrow and pyarrow.parquet, or OSError naming the extra (asked before a study runs:
    a missing pyarrow was said only after all its runs)."""
    try:
        import pyarrow as pa
        import pyarrow.parquet as pq
    except ImportError:
        raise OSError('writing Parquet needs pyarrow: pip install "nsdyn[parquet]"') from None
    return pa, pq


def checked_keep(source: str, keep, parameters) -> list | None:
    """A study's ``keep``: a list of result names, none of them a column the table holds for
    every task (its lead and tail columns, its parameters: a result of that name wrote over
    it, a kept ``key`` lost the table, a kept parameter emptied its column); SceneError
    naming ``study.keep`` otherwise."""
    from nsdyn.models.scenefile import SceneError

    if keep is not None and not all(isinstance(k, str) for k in keep):
        raise SceneError(f"{source}: study.keep: expected a list of field names, got {keep!r}")
    if keep is not None and not keep:  # (a table of no result at all)
        raise SceneError(f"{source}: study.keep: an empty list keeps no result; name the "
                         "results to keep, or drop keep to keep them all")  # fmt: skip
    once(source, "study.keep", list(keep or ()))  # (a name twice was taken as once)
    own = [k for k in keep or () if k in (*LEAD_COLUMNS, *TAIL_COLUMNS, *parameters)]
    if own:
        raise SceneError(f"{source}: study.keep: {own[0]!r} is a column of the table itself "
                         "(index, key, record, sample, status, error, task_s and the "
                         "parameters); expected results of the run")  # fmt: skip
    return keep


def column_names(source: str, where: str, spec: dict, key: str, empty_ok: bool = False) -> list:
    """The column names ``spec[key]`` of an analysis table ``where`` (none when not given):
    a list of text, none twice (a name given twice made its row or column twice), and not
    empty unless ``empty_ok`` (``[]`` ran the default without a word); SceneError naming
    ``where + key`` otherwise."""
    from nsdyn.models.scenefile import SceneError

    if key not in spec:
        return []
    val = spec[key]
    if not isinstance(val, list) or not all(isinstance(v, str) for v in val):
        raise SceneError(f"{source}: {where}{key}: expected a list of column names, got {val!r}")
    if not val and not empty_ok:
        raise SceneError(f"{source}: {where}{key}: expected one column name or more, got [] "
                         "(drop the key for its default)")  # fmt: skip
    once(source, f"{where}{key}", val)
    return val


def once(source: str, where: str, vals: list) -> None:
    """SceneError naming the first value of ``vals`` given twice."""
    from nsdyn.models.scenefile import SceneError

    twice = next((v for i, v in enumerate(vals) if v in vals[:i]), None)
    if twice is not None:
        raise SceneError(f"{source}: {where}: {twice!r} given twice; expected distinct values")


TIMING_COLUMNS = ("task_s", "wall_s", "compile_s")  # differ between runs of the same task


TEXT_COLUMNS = ("key", "record", "status", "error")  # names and words, whatever they look like


def _parse(s: str | None):
    """A cell as written: an int only if it is one as Python writes it ("001" stays text)."""
    if s is None or s == "":  # None: a short row (csv.DictReader's restval)
        return None
    if s in ("True", "False"):
        return s == "True"
    try:
        i = int(s)
    except ValueError:
        pass
    else:
        return i if str(i) == s else s
    try:
        return float(s)
    except ValueError:
        return s


class Table:
    """Rows of a study (dicts), with column access for the analyses."""

    def __init__(self, rows: list[dict], param_names: list[str] | None = None):
        self.rows = rows
        self.param_names = list(param_names or [])

    def __len__(self) -> int:
        return len(self.rows)

    def __repr__(self) -> str:
        cols = self.columns
        shown = ", ".join(cols[:8]) + (f", ... ({len(cols) - 8} more)" if len(cols) > 8 else "")
        return f"<study Table: {len(self.rows)} rows; columns {shown}>"

    @property
    def columns(self) -> list[str]:
        lead = [c for c in LEAD_COLUMNS if any(c in r for r in self.rows)]
        params = [c for c in self.param_names if c not in lead]
        tail = [c for c in TAIL_COLUMNS if any(c in r for r in self.rows)]
        seen = set(lead) | set(params) | set(tail)
        rest = []
        for r in self.rows:
            for k in r:
                if k not in seen:
                    seen.add(k)
                    rest.append(k)
        return lead + params + tail + rest

    def column(self, name: str, strict: bool = True) -> np.ndarray:
        """A numeric column (NaN where missing or not a number; booleans as 0/1). A name no row
        has is a KeyError naming the nearest column (a typo read as all NaN), a column of text
        alone a ValueError pointing to :meth:`values`; ``strict=False`` gives their NaN (the
        analyses, which note such columns)."""
        if strict and self.rows and name not in self.columns:
            raise KeyError(f"{name!r}: no such column{did_you_mean(name, self.columns)}")
        out = np.full(len(self.rows), np.nan)
        text = False
        for i, r in enumerate(self.rows):
            v = r.get(name)
            if isinstance(v, bool | int | float):
                out[i] = float(v)
            text |= isinstance(v, str) and v != ""
        if strict and text and np.isnan(out).all():  # ('record', 'status': all NaN before)
            raise ValueError(f"{name!r} holds text, not numbers: table.values({name!r}) gives it")
        return out

    def values(self, name: str) -> list:
        return [r.get(name) for r in self.rows]

    def ok(self) -> Table:
        """The rows of tasks that finished without error."""
        return Table([r for r in self.rows if r.get("status") == "ok"], self.param_names)

    def to_dataframe(self):
        """The rows as a pandas DataFrame, one column per :attr:`columns` in their order (an
        empty cell NaN or None; needs the ``frames`` extra)."""
        from nsdyn._tabular import _need

        pd = _need("pandas")
        return pd.DataFrame.from_records(self.rows, columns=self.columns)

    def to_csv(self) -> str:
        buf = io.StringIO()
        w = csv.DictWriter(buf, fieldnames=self.columns, lineterminator="\n")
        w.writeheader()
        for r in self.rows:
            w.writerow({k: ("" if v is None else v) for k, v in r.items()})
        return buf.getvalue()

    def write_csv(self, path: str | Path) -> Path:
        with atomic_open(path, "w", newline="") as fh:
            fh.write(self.to_csv())
        return Path(path)

    def to_parquet(self, path: str | Path) -> Path:
        """A typed Parquet copy (needs pyarrow: ``pip install "nsdyn[parquet]"``)."""
        pa, pq = pyarrow_modules()
        cols = {c: [r.get(c) for r in self.rows] for c in self.columns}
        arrays = {}
        for c, vals in cols.items():
            try:
                arrays[c] = pa.array(vals)
            except (pa.ArrowInvalid, pa.ArrowTypeError):  # mixed types: text
                arrays[c] = pa.array([None if v is None else str(v) for v in vals])
        with atomic_open(path, "wb") as fh:
            pq.write_table(pa.table(arrays), fh)
        return Path(path)


def read_results(out_dir: str | Path) -> Table:
    """The table a study left in ``out_dir`` (its results.csv, values parsed as
    :func:`read_csv` parses them): ``read_results("nsdyn-study/NAME").to_dataframe()``, its
    columns in the file's order (the parameters before status, error and task_s, as the
    study's own table has them)."""
    path = Path(out_dir) / RESULTS
    if Path(out_dir).is_file() and Path(out_dir).name == RESULTS:  # (the table itself given)
        path = Path(out_dir)
    if not path.is_file():
        if any((Path(out_dir) / PARTS).glob("part-*.csv")):  # (said as a missing folder)
            raise FileNotFoundError(f"{out_dir}: no {RESULTS} yet: an interrupted study, its "
                                    f"finished rows in {PARTS}/; run the study again (nsdyn "
                                    "study FILE --out DIR, or run_study) to finish it and "
                                    "write the table")  # fmt: skip
        if Path(out_dir).is_file():  # (its results.parquet: it said "no results.csv")
            raise FileNotFoundError(f"{out_dir}: not a study's folder or its {RESULTS} (a "
                                    "results.parquet reads with pandas.read_parquet)")  # fmt: skip
        raise FileNotFoundError(f"{out_dir}: no {RESULTS}; expected the folder a study wrote")
    if not path.read_text().strip():
        raise TableFileError(f"{path}: empty; expected the table a study wrote (a header, "
                             "rows)")  # fmt: skip
    rows = read_csv(path)
    header = list(rows[0]) if rows else []
    tail = next((i for i, c in enumerate(header) if c in TAIL_COLUMNS), len(header))
    return Table(rows, [c for c in header[:tail] if c not in LEAD_COLUMNS])


class TableFileError(CheckpointError):
    """A study's results table (the point it resumes from) that cannot be read: the message
    names the file and line (``nsdyn study``: one line, status 2)."""


def read_csv(path: str | Path) -> list[dict]:
    """Rows of a results CSV, values parsed (int, float, bool, text; empty -> None); the
    :data:`TEXT_COLUMNS` stay text (a record named "001" is not record 1).

    Every column of the header stays in every row, an empty cell as None, so a column that is
    empty in every row (a kept name no task's summary has) survives a write and a read."""
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    for i, row in enumerate(rows):
        if None in row or None in row.values():  # (more cells than the header's, or fewer)
            raise TableFileError(f"{path}: line {i + 2}: {'more' if None in row else 'fewer'} "
                                 "cells than the header has columns; expected a study's table "
                                 "(a cell per column): move it away, or rerun the study with "
                                 "--fresh")  # fmt: skip
    return [{k: v if k in TEXT_COLUMNS else _parse(v) for k, v in row.items()} for row in rows]


def _better(new: dict, old: dict) -> bool:
    return old.get("status") != "ok" and new.get("status") == "ok"


class ResultsStore:
    """The results of one study in ``out_dir``: finished keys, streamed parts, compaction."""

    def __init__(self, out_dir: str | Path, param_names: list[str] | None = None, keep=None):
        self.out = Path(out_dir)
        self.parts = self.out / PARTS
        self.param_names = list(param_names or [])
        self.keep = list(keep or ())  # the kept columns' order (rows of a reordered keep reused)
        self._n_written = 0
        self.n_outside = 0  # rows (failed ones too) kept outside the grid by the last compact

    def _part_files(self) -> list[Path]:
        if not self.parts.is_dir():
            return []
        return sorted(p for p in self.parts.glob("part-*.csv") if not p.name.startswith("."))

    def clean_temporaries(self) -> None:
        """Remove temporary files a killed writer left (never a finished part)."""
        if self.parts.is_dir():
            for p in self.parts.glob(".part-*.tmp"):
                p.unlink(missing_ok=True)
        for name in (RESULTS, OUTSIDE):
            for p in self.out.glob(f".{name}-*.tmp"):
                p.unlink(missing_ok=True)

    def read(self) -> dict[str, dict]:
        """key -> row over ``results.csv`` and every part (one row per key)."""
        rows: dict[str, dict] = {}
        tables = [self.out / OUTSIDE, self.out / RESULTS]
        files = [f for f in tables if f.is_file()] + list(self._part_files())
        for f in files:
            for r in read_csv(f):
                k = str(r.get("key"))
                if k not in rows or _better(r, rows[k]):
                    rows[k] = r
        return rows

    def n_finished(self) -> tuple[int, int]:
        """(tasks, of them failed) that ``results.csv`` and the parts hold: the rows a rerun
        resumes (a failed one runs again under --retry-failed), not ``outside-grid.csv``'s.
        Reads the key and status cells alone (an interrupt's count: parsing every cell of
        10⁵ rows took 6 s); OSError, ValueError or csv.Error from a file it cannot read."""
        ok: dict[str, bool] = {}
        files = [self.out / RESULTS] if (self.out / RESULTS).is_file() else []
        for f in files + self._part_files():
            with open(f, newline="") as fh:
                cells = csv.reader(fh)
                head = next(cells, [])
                if "key" not in head:
                    continue
                k, s = head.index("key"), head.index("status") if "status" in head else -1
                for row in cells:
                    if len(row) > k:
                        ok[row[k]] = ok.get(row[k], False) or 0 <= s < len(row) and row[s] == "ok"
        return len(ok), sum(not v for v in ok.values())

    def append(self, rows: list[dict]) -> Path:
        """Write one part holding ``rows`` (atomically)."""
        self._n_written += 1
        name = f"part-{time.time_ns():020d}-{os.getpid()}-{self._n_written:06d}.csv"
        path = self.parts / name
        Table(rows, self.param_names).write_csv(path)
        return path

    def compact(self, order: dict[str, int] | None = None, aliases: dict | None = None) -> Table:
        """Merge everything into ``results.csv`` in task order and remove the parts.

        ``order``: key -> task index of the current study; rows of other keys (a grid was
        narrowed) move to ``OUTSIDE`` (failed ones too: a wider grid reuses them as a resume
        does, a failed task rerun only by --retry-failed) and every kept row takes its current
        index.
        """
        merged = self.read()
        for old, new in (aliases or {}).items():  # (a row under its earlier key: re-keyed, or
            row = merged.pop(old, None)  # dropped for a better one under the new key)
            if row is not None and (new not in merged or _better(row, merged[new])):
                merged[new] = row | {"key": new}
        if order is not None:
            outside = [r for k, r in merged.items() if k not in order]
            if outside:
                Table(outside, self.param_names).write_csv(self.out / OUTSIDE)
            else:
                (self.out / OUTSIDE).unlink(missing_ok=True)
            self.n_outside = len(outside)
            merged = {k: r | {"index": order[k]} for k, r in merged.items() if k in order}
        rows = sorted(merged.values(), key=lambda r: (r.get("index", 0), str(r.get("key"))))
        rows = [{k: r[k] for k in self.keep if k in r} | r for r in rows]
        table = Table(rows, self.param_names)
        if rows:
            table.write_csv(self.out / RESULTS)
        else:  # (a regrid keeping no row: no header-only table to be read as an empty study)
            (self.out / RESULTS).unlink(missing_ok=True)
        for p in self._part_files():
            p.unlink(missing_ok=True)
        return table

    def regrid(self, order: dict[str, int], aliases: dict | None = None) -> bool:
        """Before a run on another grid (rows of keys not in ``order``): :meth:`compact` to the
        current grid and remove the analyses of the old one, so that an interrupted run leaves
        no table or analysis of another grid beside its rows. Returns whether it did."""
        table = self.out / RESULTS  # (rows kept in OUTSIDE are another grid's by design)
        here = [table] * table.is_file() + list(self._part_files())
        kept = [self.out / OUTSIDE] * (self.out / OUTSIDE).is_file()  # (and an earlier key's)
        old = any(str(r.get("key")) in (aliases or {}) for f in here + kept for r in read_csv(f))
        if not old and all(str(r.get("key")) in order for f in here for r in read_csv(f)):
            return False
        self.compact(order, aliases)
        for name in ANALYSIS_FILES:  # (a Parquet copy the command line asked for is written
            (self.out / name).unlink(missing_ok=True)  # anew after the run: nsdyn.cli.study)
        return True

    def claim(self, name: str, kind: str) -> None:
        """Mark the folder as holding study ``name``'s results (a scene of ``kind``), or
        CheckpointError when it holds another study's: a cylinder study's rows were merged
        into a rocking study's table (as tasks "outside this grid") and its analyses
        replaced."""
        import json

        from nsdyn.atomic import CheckpointError

        mine = {"name": str(name), "kind": str(kind)}
        try:
            old = json.loads((self.out / OWNER).read_text())
        except (OSError, ValueError):
            old = None
        if isinstance(old, dict) and old.get("kind") != mine["kind"] and self.read():
            raise CheckpointError(f"{self.out}: holds the results of study {old.get('name')!r} "
                                  f"({old.get('kind')} scenes), not of {name!r} ({kind}): rows "
                                  "of another family; give another folder (--out, "
                                  "out_dir), or start fresh to replace them (--fresh, "
                                  "fresh=True)")  # fmt: skip
        self.out.mkdir(parents=True, exist_ok=True)
        with atomic_open(self.out / OWNER, "w") as fh:
            fh.write(json.dumps(mine))

    def reset(self) -> None:
        """Forget every result and the analyses made from them (a fresh start)."""
        for name in (RESULTS, OUTSIDE, OWNER, *ANALYSIS_FILES):
            (self.out / name).unlink(missing_ok=True)
        for p in self._part_files():
            p.unlink(missing_ok=True)


def empty_columns(table: Table, names, partly: bool = False) -> str | None:
    """A note naming the columns an analysis reads that hold no number in any successful row
    (a result this scene kind does not have, a misspelt one, a text column, a default the
    study's keep drops): their statistics are NaN, which said nothing of why. With ``partly``
    also those without a number in some successful rows (a setback frame's drift ratio): their
    statistics are over fewer runs than a group's ``n``."""
    ok = [r for r in table.rows if r.get("status") == "ok"]
    if not ok:
        return None

    def number(v) -> bool:  # (a true/false outcome counts as 0 or 1, as the analyses read it)
        return isinstance(v, int | float) and math.isfinite(v)

    count = {n: sum(number(r.get(n)) for r in ok) for n in dict.fromkeys(names)}
    bad = [n for n, k in count.items() if k == 0]
    some = [f"{n!r} ({len(ok) - k} of {len(ok)})" for n, k in count.items()
            if partly and 0 < k < len(ok)]  # fmt: skip
    notes = []
    if bad:
        have = sorted({k for r in ok for k, v in r.items() if number(v)} - {"index", "task_s"})
        notes.append(f"{', '.join(map(repr, bad))}: no number in any successful row"
                     f"{did_you_mean(bad[0], have)} (numeric columns: {', '.join(have)}); "
                     "their statistics are NaN")  # fmt: skip
    if some:
        notes.append(f"{', '.join(some)}: no number in some successful rows; their "
                     "statistics are over the rest, fewer than n in the groups that lack "
                     "them")  # fmt: skip
    return "; ".join(notes) or None
