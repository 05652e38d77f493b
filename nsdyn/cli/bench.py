"""``nsdyn bench``: the benchmarks' command-line arguments, dispatch and printed summaries
(the benchmarks themselves are in :mod:`nsdyn.bench`).

``nsdyn bench NAME | all [--quick] [--out DIR] [--repeats N] [--records LIST] [--cold-compile]
[--families] [--curve] [--no-figures] [--json]`` runs benchmark NAME of
:data:`nsdyn.bench.BENCHMARKS` (``all``: each in the table's order) through its
``run_bench(out_dir, quick, **options)``,
passing only the options its ``OPTIONS`` lists, then prints its ``report`` (or its summary)
and the files it wrote, or with ``--json`` one JSON object ``{"status": exit status, name:
summary}`` (and ``"notes"``) and nothing else.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import textwrap
import warnings
from pathlib import Path

import numpy as np

from nsdyn._checks import AccuracyWarning
from nsdyn.bench.common import DEFAULT_OUT, RECORDS, REPEATS
from nsdyn.cli.args import fail, out_dir, positive_int, stale_figures

__all__ = ["configure", "main", "run"]

# one line per benchmark for the help of the NAME argument
HELP = {
    "accuracy": "work-precision chart",
    "fidelity": "model ladder",
    "stability": "step-size, drift and shooting maps",
    "speed": "transient speed table against SciPy",
    "periodic": "work-precision of shooting and the steady-state sweep",
    "rocking": "rocking bodies",
    "contact": "planar contact bodies",
    "cylinder": "the cylinder",
    "studies": "study throughput: local process pool against a Dask local cluster",
    "switch_shooting": "shooting on the switch model against arctan shooting and event-driven runs",
    "full-model": "the 435-dof frame with the low-rank generalized-α against radau",
    "opensees": "the full frame in OpenSees (exported script) against nsdyn full and CB-5",
    "opensees3d": "the 3D office building in OpenSees (exported script) against nsdyn's "
    "building rungs",
    "scale": "cost against model size: nsdyn's full-order methods and CB against the exported "
    "OpenSees model, with fitted exponents",
    "scale3d": "cost of the full 3D rung against building size, against exported OpenSees",
    "isolators": "bidirectional isolators: work-precision of the two laws, cost per isolator",
}
RECORDS_DEFAULT = "wn,kt"
# (flag, option) of the options that only some benchmarks take (their OPTIONS)
_GIVEN = (
    ("--repeats", "repeats"),
    ("--records", "records"),
    ("--cold-compile", "cold_compile"),
    ("--families", "families"),
    ("--curve", "curve"),
)
_FLAG = {option: flag for flag, option in _GIVEN}
OPTION_HELP = {  # (the help of each; `nsdyn bench NAME --help` lists the benchmark's own)
    "repeats": f"timed repeats per point, median quoted (default: the benchmark's own, {REPEATS} "
    "and 1 with --quick for most; speed 5 (3), its default-run ratio at least 5, isolators 5 "
    "(2), scale 1). rocking, contact, cylinder, stability and studies take none (rocking and "
    "cylinder time a fixed 7 (3) and 5 (3))",
    "records": "accuracy: comma-separated records among wn (white noise), kt (Kanai-Tajimi)",
    "cold_compile": "speed: also time the JIT compilation with an empty numba cache (a few "
    "minutes)",
    "families": "speed: also the first run of every model family, each in a fresh process with "
    "an empty numba cache, then a cached start (several minutes)",
    "curve": "switch_shooting: instead of the points, one whole 150-point curve (--quick: 40), "
    "switch against arctan",
}
EXIT_UNAVAILABLE = 1  # `all`: a benchmark module exists but does not import


def configure(p: argparse.ArgumentParser) -> None:
    """Arguments of ``nsdyn bench``."""
    p.set_defaults(command="bench")  # its messages name it also when run alone (tests)
    from nsdyn.bench import BENCHMARKS

    names = [*BENCHMARKS, "all"]
    spelt = {n.replace("_", "-"): n for n in names}  # switch-shooting, full_model: either

    def benchmark(word: str) -> str:
        name = spelt.get(word.replace("_", "-"))
        if name is None:
            from nsdyn._checks import did_you_mean

            hint = did_you_mean(word, names)  # (named as the help names them)
            raise argparse.ArgumentTypeError(
                f"unknown benchmark {word!r}{hint} (benchmarks: {', '.join(names)})"
            )
        return name

    p.add_argument(
        "what",
        type=benchmark,
        choices=names,
        metavar="BENCHMARK",
        help="; ".join(f"{name}: {HELP.get(name, BENCHMARKS[name])}" for name in BENCHMARKS)
        + "; all: each in this order",
    )
    p.add_argument("--quick", action="store_true", help="short windows and few points (CI)")
    p.add_argument(
        "--out", type=out_dir, default=str(DEFAULT_OUT), metavar="DIR", help="output directory"
    )
    p.add_argument("--repeats", type=positive_int, default=None, metavar="N",
                   help=OPTION_HELP["repeats"])  # fmt: skip
    p.add_argument("--records", default=RECORDS_DEFAULT, metavar="LIST",
                   help=OPTION_HELP["records"])  # fmt: skip
    for option in ("cold_compile", "families", "curve"):
        p.add_argument(_FLAG[option], action="store_true", help=OPTION_HELP[option])
    p.add_argument("--no-figures", action="store_true", help="write the CSV tables only")
    p.add_argument("--json", action="store_true", help="print one JSON summary and nothing else")


def benchmark_help(args: list[str]) -> str | None:
    """The help of ``nsdyn bench NAME --help`` (``args`` after ``bench``): what benchmark NAME
    measures (its module's first two paragraphs), the options it takes and those every one
    takes; None without a benchmark's name (the command's help then)."""
    from nsdyn.bench import BENCHMARKS, BenchmarkUnavailable, load_benchmark

    spelt = {n.replace("_", "-"): n for n in BENCHMARKS}
    valued = ("--out", "--repeats", "--records")  # (their values are no benchmark's name)
    words = [a for i, a in enumerate(args) if i == 0 or args[i - 1] not in valued]
    name = next((spelt[a.replace("_", "-")] for a in words if a.replace("_", "-") in spelt), None)
    if name is None:
        return None
    try:
        module = load_benchmark(name)
    except BenchmarkUnavailable as e:
        return f"nsdyn bench {name}: {HELP.get(name, BENCHMARKS[name])}\n\n{e}"
    taken = getattr(module, "OPTIONS", ())
    own = [o for o in OPTION_HELP if o in taken]
    meta = {"repeats": " N", "records": " LIST"}
    usage = " ".join(["usage: nsdyn bench", name, "[--quick] [--out DIR]",
                      *(f"[{_FLAG[o]}{meta.get(o, '')}]" for o in own),
                      *["[--no-figures]"] * ("figures" in taken), "[--json]"])  # fmt: skip
    about = "\n\n".join((module.__doc__ or "").strip().split("\n\n")[:2])

    def value(m) -> str:  # a numeric constant's value (1e-9, not 1e-09); any other as written
        v = getattr(module, m[1], None)
        if not isinstance(v, int | float) or isinstance(v, bool):
            return m[1]
        return re.sub(r"e([+-])0(\d)", r"e\1\2", f"{v:g}")

    about = re.sub(r":data:`~?([A-Z][A-Z0-9_]+)`", value, about)  # (RECORD_S: 10.0)
    about = re.sub(r":\w+:`~?([^`]+)`", r"\1", about.replace("``", "`").replace("::", ":"))
    if not about.endswith((".", ")")):  # (a list or formula follows: "...:", "...,", "by")
        about = about.rstrip(" :,") + " (more in its module's text)"
    about = re.sub(r"`([A-Z][A-Z0-9_]+)`", value, about)

    def option(flag: str, text: str) -> str:
        return textwrap.fill(text, 88, initial_indent=f"  {flag:<16}", subsequent_indent=" " * 18,
                             break_on_hyphens=False)  # fmt: skip

    lines = [textwrap.fill(usage, 88, subsequent_indent=" " * 12, break_on_hyphens=False), "",
             about, "",
             "options of this benchmark:"]  # fmt: skip
    lines += [option(_FLAG[o] + meta.get(o, ""), OPTION_HELP[o]) for o in own]
    lines += ["  (none of its own)"] * (not own) + ["options of every benchmark:"]
    lines += [option("--quick", "short windows and few points (CI)"),
              option("--out DIR", f"output directory (default {DEFAULT_OUT})")]  # fmt: skip
    if "figures" in taken:
        figures = ", ".join(getattr(module, "FIGURES", ()))
        lines.append(option("--no-figures", f"write the CSV tables only, not {figures}"))
    lines += [option("--json", "print one JSON summary and nothing else"), "",
              "every benchmark: nsdyn bench --help; docs/guide/benchmarks.md"]  # fmt: skip
    return "\n".join(lines)


def _jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, float | np.floating):
        return float(obj) if np.isfinite(obj) else None
    if isinstance(obj, np.integer):
        return int(obj)
    return obj


def _cell(v) -> str:
    if isinstance(v, bool) or v is None:
        return str(v).lower() if v is not None else "-"
    if isinstance(v, float | np.floating):
        return f"{float(v):.4g}"
    return str(v)


def _plain(obj, indent: str = "") -> list[str]:
    """A benchmark's summary as text (for those without a report of their own): one
    ``key  value`` line per number, nested tables indented, a list of rows as a table."""
    lines: list[str] = []
    for k, v in obj.items():
        if isinstance(v, dict):
            lines += [f"{indent}{k}:", *_plain(v, indent + "  ")]
        elif isinstance(v, list | tuple) and v and all(isinstance(r, dict) for r in v):
            cols = list(dict.fromkeys(c for r in v for c in r))
            cells = [[_cell(r.get(c)) for c in cols] for r in v]
            w = [max(len(c), *(len(row[i]) for row in cells)) for i, c in enumerate(cols)]
            lines.append(f"{indent}{k}:")
            lines.append(indent + "  " + "  ".join(c.rjust(w[i]) for i, c in enumerate(cols)))
            lines += [indent + "  " + "  ".join(x.rjust(w[i]) for i, x in enumerate(row))
                      for row in cells]  # fmt: skip
        elif isinstance(v, list | tuple) and v and all(isinstance(r, list | tuple) for r in v):
            cells = [[_cell(x) for x in r] for r in v]  # rows without names: aligned columns
            w = [max(len(row[i]) for row in cells if i < len(row))
                 for i in range(max(map(len, cells)))]  # fmt: skip
            lines.append(f"{indent}{k}:")
            lines += [indent + "  " + "  ".join(x.rjust(w[i]) for i, x in enumerate(row))
                      for row in cells]  # fmt: skip
        elif isinstance(v, list | tuple):
            lines.append(f"{indent}{k}  {', '.join(_cell(x) for x in v)}")
        else:
            lines.append(f"{indent}{k}  {_cell(v)}")
    return lines


_FILE_KEYS = ("csv", "png", "json")  # a result's file paths when it has no "files"


def _files(res) -> list[tuple[str, str]]:
    """(key, path) of each file a result lists under "files" (a dict or a list of paths), or
    else names as its "csv", "png" or "json" paths."""
    files = res.get("files", {}) if isinstance(res, dict) else {}
    if not files and isinstance(res, dict):
        return [(k, res[k]) for k in _FILE_KEYS if isinstance(res.get(k), str)]
    if isinstance(files, dict):
        return [(str(k), str(v)) for k, v in files.items()]
    return [("file", str(v)) for v in files]


def run(args: argparse.Namespace) -> int:
    """Run ``nsdyn bench``; returns the exit status (0 ok, 1 a benchmark of ``all`` does not
    import, 2 bad arguments or a benchmark asked for by name is not available)."""
    from nsdyn.bench import BENCHMARKS, BenchmarkUnavailable, load_benchmark

    records = tuple(r.strip() for r in args.records.split(",") if r.strip())
    bad = [r for r in records if r not in RECORDS]
    if bad or not records:
        return fail(args, f"--records: expected some of {sorted(RECORDS)}, got {bad}")
    twice = sorted({r for r in records if records.count(r) > 1})
    if twice:  # (it ran each as often as named: its rows repeated)
        return fail(args, f"--records: expected each record once, got {', '.join(twice)} twice")
    options = {
        "repeats": args.repeats,
        "records": records,
        "figures": not args.no_figures,
        "quiet": args.json,
        "cold_compile": getattr(args, "cold_compile", False),
        "families": getattr(args, "families", False),
        "curve": getattr(args, "curve", False),
    }
    given = {  # the benchmark-specific options the user set
        "repeats": args.repeats is not None,
        "records": args.records != RECORDS_DEFAULT,
        "cold_compile": options["cold_compile"],
        "families": options["families"],
        "curve": options["curve"],
    }
    whats = list(BENCHMARKS) if args.what == "all" else [args.what]
    summary, status, notes = {}, 0, []
    for what in whats:
        try:
            module = load_benchmark(what)
        except BenchmarkUnavailable as e:
            if args.what != "all":
                return fail(args, e)
            print(f"nsdyn bench: {e}", file=sys.stderr)
            summary[what] = {"status": "unavailable", "reason": str(e)}
            status = status if e.absent else EXIT_UNAVAILABLE
            continue
        taken = {k: options[k] for k in getattr(module, "OPTIONS", ()) if k in options}
        unused = [f for f, k in _GIVEN if k not in getattr(module, "OPTIONS", ()) and given[k]]
        if unused and args.what != "all":  # `all` hands each benchmark the options it takes
            return fail(args, f"{', '.join(unused)}: not an option of benchmark {what!r}")
        if args.no_figures and "figures" not in getattr(module, "OPTIONS", ()):
            if args.what != "all" and not args.json:  # (nothing to skip: said, not refused)
                print(f"nsdyn bench: note: benchmark {what!r} draws no figures; --no-figures "
                      "changes nothing", file=sys.stderr)  # fmt: skip
        if args.no_figures:  # (an earlier run's figures sat beside the new tables)
            gone = stale_figures(Path(args.out), getattr(module, "FIGURES", ()), "bench", args.json)
            notes += [gone] * bool(gone)  # (--json: said in the summary)
        with warnings.catch_warnings():  # (coarse steps on purpose: their errors are charted)
            warnings.simplefilter("ignore", AccuracyWarning)
            res = module.run_bench(Path(args.out), args.quick, **taken)
        if isinstance(res, dict) and res.get("status") == "unavailable" and args.what != "all":
            # an optional extra found missing inside the run (OpenSees): asked for by name,
            # that is a failure a script must see, not a success that ran nothing
            return fail(args, f"benchmark {what!r} did not run: {res.get('reason', '')}")
        summarise = getattr(module, "summarise", None)
        summary[what] = summarise(res) if summarise is not None else res
        if not args.json:
            report = getattr(module, "report", None)
            if report is not None:
                print(report(res))
            elif isinstance(summary[what], dict):
                print(f"{what}:")
                listed = {"files", *(k for k, _ in _files(summary[what]))}  # listed below
                body = {k: v for k, v in summary[what].items() if k not in listed}
                print("\n".join(_plain(_jsonable(body), "  ")))
            else:
                print(f"{what}: {summary[what]}")
            for k, v in _files(res):
                print(f"{k}: {v}")
    if args.json:  # (the exit status first, as every command's JSON; then each benchmark's)
        print(
            json.dumps(
                _jsonable({"status": status, **summary, **({"notes": notes} if notes else {})})
            )
        )
    return status


def main(argv: list[str] | None = None) -> int:
    """``nsdyn bench ...`` on its own (tests call it with an argument list)."""
    import nsdyn.bench

    parser = argparse.ArgumentParser(
        prog="nsdyn bench", description=nsdyn.bench.__doc__.splitlines()[0], allow_abbrev=False
    )
    configure(parser)
    text = benchmark_help(argv or []) if {"-h", "--help"} & set(argv or []) else None
    if text is not None:
        print(text)
        return 0
    return run(parser.parse_args(argv))


if __name__ == "__main__":
    sys.exit(main())
