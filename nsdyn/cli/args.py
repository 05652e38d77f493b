"""Argument types and exit codes shared by the subcommands (argparse lives only in nsdyn.cli)."""

from __future__ import annotations

import argparse
import errno
import json
import math
import os
import sys
import tempfile
from pathlib import Path

from nsdyn._checks import INT64_MAX, MAX_POINTS, RTOL_MIN

EXIT_USER_ERROR = 2  # bad input the user can fix (same as argparse usage errors)
EXIT_NUMERICS = 3  # the numerics failed (step underflow, Newton divergence, uplift, ...)
EXIT_INTERRUPTED = 130  # stopped by SIGINT/SIGTERM (128 + SIGINT); rerun to resume
EXIT_PIPE_CLOSED = 141  # the reader of stdout closed it (`nsdyn ... | head`; 128 + SIGPIPE)


def positive_float(s: str) -> float:
    """A positive number (``inf`` allowed, e.g. ``--fmax inf``)."""
    try:
        v = float(s)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {s!r}") from None
    if not v > 0:
        raise argparse.ArgumentTypeError(f"expected a positive number, got {s!r}")
    return v


def positive_finite(s: str) -> float:
    """A positive finite number."""
    v = positive_float(s)
    if not math.isfinite(v):
        raise argparse.ArgumentTypeError(f"expected a positive finite number, got {s!r}")
    return v


def forcing_frequency(s: str) -> float:
    """A forcing frequency [Hz] a periodic solve takes (``nsdyn.periodic.protocol``'s range:
    below it the period's integration loses the load to round-off)."""
    from nsdyn.periodic.protocol import F_HIGHEST, F_LOWEST

    v = positive_finite(s)
    if not F_LOWEST <= v <= F_HIGHEST:
        raise argparse.ArgumentTypeError(f"expected a forcing frequency in [{F_LOWEST:g}, "
                                         f"{F_HIGHEST:g}] Hz, got {s!r}")  # fmt: skip
    return v


REFINE_MAX = 1000.0  # the default period's error (~0.3 %) / K^2 reaches the stages' Newton
# tolerance (discretisation.STAGE_RTOL = 1e-9) at K ~ 1000: more steps buy round-off only


def refinement(s: str) -> float:
    """A refinement factor of a default discretisation: a finite number from 1 (fewer steps
    than the default do not resolve a period: at 0.01, 2 steps per period converged to a wrong
    orbit) to REFINE_MAX (past it a compiled period runs for minutes between two checks for
    Ctrl-C, for an error below the stages' tolerance)."""
    v = positive_finite(s)
    if not 1.0 <= v <= REFINE_MAX:
        raise argparse.ArgumentTypeError(
            f"expected a factor from 1 to {REFINE_MAX:g} on the default steps per period "
            f"(the error falls as 1/K^2 from ~0.3 %: K = {REFINE_MAX:g} reaches the stages' "
            f"Newton tolerance 1e-9), got {s!r}"
        )
    return v


def fraction(s: str) -> float:
    """A relative width or tolerance: RTOL_MIN <= v < 1 (below 100x double precision's
    epsilon a bisection's width stops shrinking and the search never ends)."""
    v = positive_finite(s)
    if not RTOL_MIN <= v < 1.0:
        raise argparse.ArgumentTypeError(
            f"expected a relative width from {RTOL_MIN:.2g} (100x double precision's "
            f"epsilon) to below 1, got {s!r}"
        )
    return v


def _int_at_least(s: str, lowest: int) -> int:
    try:
        v = int(s)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected an integer, got {s!r}") from None
    if v < lowest:
        raise argparse.ArgumentTypeError(
            f"expected at least {lowest} (an integer >= {lowest}), got {s!r}"
        )
    if v > INT64_MAX:  # (a compiled loop's count overflowed in a traceback)
        raise argparse.ArgumentTypeError(f"expected an integer of at most {INT64_MAX}, got {s!r}")
    return v


def _int_in(s: str, lowest: int, highest: int, what: str) -> int:
    """``s`` as an integer from ``lowest`` to ``highest`` (``what``: the unit and cost the
    message names above it), else ArgumentTypeError."""
    v = _int_at_least(s, lowest)
    if v > highest:
        raise argparse.ArgumentTypeError(f"expected at most {highest} {what}, got {s!r}")
    return v


def int_in(lowest: int, highest: int, what: str):
    """An argparse ``type``: an integer from ``lowest`` to ``highest`` (:func:`_int_in`), as
    the example scripts bound their counts of runs and points."""
    return lambda s: _int_in(s, lowest, highest, what)


def count(s: str) -> int:
    """A number of frequencies: an integer from 2 to :data:`MAX_POINTS`."""
    return _int_in(s, 2, MAX_POINTS, "frequencies (each one a periodic solve of seconds)")


def pulse_count(s: str) -> int:
    """A number of pulse frequencies of a spectrum: an integer from 2 to :data:`MAX_POINTS`."""
    return _int_in(s, 2, MAX_POINTS, "frequencies (each one a scan and bisection of pulse runs)")


def positive_int(s: str) -> int:
    """An integer of at least 1 (a number of repeats, modes, ...)."""
    return _int_at_least(s, 1)


WORKERS_PER_CPU = 4  # local processes beyond this many per CPU only wait for one another


def workers(s: str) -> int:
    """A number of local worker processes: an integer from 1 to WORKERS_PER_CPU x the
    machine's CPUs (a Dask cluster of 1000 local workers ended in a flood of tracebacks)."""
    import os

    n = os.cpu_count() or 1
    return _int_in(s, 1, WORKERS_PER_CPU * n, f"local processes ({WORKERS_PER_CPU} per CPU of "
                   f"this machine's {n})")  # fmt: skip


def amplitude_list(s: str) -> list[float]:
    """Comma-separated positive amplitudes [m/s²]."""
    if any(not v.strip() for v in s.split(",")):
        raise argparse.ArgumentTypeError(f"expected numbers separated by commas, got {s!r}")
    try:
        vals = [float(v) for v in s.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected numbers separated by commas, got {s!r}"
        ) from None
    if not vals or any(not (v > 0 and math.isfinite(v)) for v in vals):
        raise argparse.ArgumentTypeError(  # (a force scene's are in N)
            f"expected positive amplitudes [m/s^2, or N for a force scene], got {s!r}"
        )
    if len(set(vals)) < len(vals):  # each would be computed again
        raise argparse.ArgumentTypeError(f"expected distinct amplitudes, got {s!r}")
    from nsdyn._checks import MAX_AMPLITUDES

    if len(vals) > MAX_AMPLITUDES:  # (the help's bound: 2 000 curves started unsaid)
        raise argparse.ArgumentTypeError(
            f"expected at most {MAX_AMPLITUDES} amplitudes (a curve each), got {len(vals)}"
        )
    return vals


def _creatable(p: Path, s: str) -> None:
    """ArgumentTypeError unless directory ``p`` exists or can be made: ``p`` itself, else its
    first existing ancestor, is a directory this process may write into."""
    try:  # (a part over 255 bytes: "File name too long" from exists(), a traceback)
        d = next((a for a in (p, *p.absolute().parents) if a.exists()), None)
    except OSError as e:
        raise argparse.ArgumentTypeError(f"cannot create {s!r}: {e.strerror}") from None
    if d is None:
        return
    made = d is not p  # p is to be made inside d
    if not d.is_dir():
        raise argparse.ArgumentTypeError(
            f"cannot create {s!r}: {d} is not a directory" if made
            else f"{s!r} exists and is not a directory"
        )  # fmt: skip
    try:  # a directory made and removed in d: what the command will do (also as root, on a
        # read-only or virtual file system, where permission bits do not tell)
        os.rmdir(tempfile.mkdtemp(prefix=".nsdyn-probe-", dir=d))
    except OSError as e:  # ("not writable" only when it is so: /proc said it beside ENOENT)
        denied = e.errno in (errno.EACCES, errno.EPERM, errno.EROFS)
        why = "is not writable" if denied else "takes no new directory"
        raise argparse.ArgumentTypeError(
            f"cannot create {s!r}: {d} {why} ({e.strerror})" if made
            else f"directory {s!r} {why} ({e.strerror})"
        ) from None  # fmt: skip


def named(s: str) -> str:
    """A bundled name or a file's path: not empty (``--record ""``, an unset shell variable,
    ran the scene's own record without a word)."""
    if not s.strip():
        raise argparse.ArgumentTypeError(f"expected a bundled name or a file's path, got {s!r}")
    return s


def out_dir(s: str) -> str:
    """An output directory that exists or can be created, checked when the command line is
    read, so that a bad ``--out`` fails before the work rather than after it."""
    if not s:
        raise argparse.ArgumentTypeError("expected a directory, got ''")
    _creatable(Path(s), s)
    return s


def figure_script(doc: str, figure: Path) -> Path:
    """Where an example script that redraws a figure of the docs draws it: its command line read
    (``--help`` shows ``doc``), ``figure`` unless ``--out DIR`` puts it into DIR."""
    ap = argparse.ArgumentParser(
        description=doc, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    where = f"folder of the figure (default {figure.parent}: the docs' copy)"
    ap.add_argument("--out", type=out_dir, metavar="DIR", help=where)
    out = ap.parse_args().out
    return figure if out is None else Path(out) / figure.name


def out_file(s: str) -> str:
    """An output file whose directory exists or can be created (and that is not a directory)."""
    p = Path(s)
    if not s:
        raise argparse.ArgumentTypeError("expected a file name, got ''")
    if p.is_dir() or s.endswith(("/", os.sep)):  # ("x.py/" was written as the file x.py)
        raise argparse.ArgumentTypeError(f"expected a file name, got the directory {s!r}")
    if p.is_symlink() or (p.exists() and not p.is_file()):  # (replaced, not written through)
        raise argparse.ArgumentTypeError(f"expected a regular file's name, got {s!r} (a link "
                                         "or a device: it would be replaced)")  # fmt: skip
    if p.suffix.lower() == ".toml":  # (a scene or frame file written over with a script)
        raise argparse.ArgumentTypeError(f"expected a script's name (.py), got {s!r}")
    _creatable(p.parent, str(p.parent))
    return s


def band_message(command: str, fmin: float, fmax: float, given: tuple = (True, True),
                 scene: tuple = (None, None)) -> str:  # fmt: skip
    """The usage error of a frequency band whose top is not above its bottom, in the form of
    every other flag's (``argument --FLAG: expected …, got … (see nsdyn CMD --help)``), naming
    the flag that was given when the other is its default (``given``: --fmin, --fmax) or a
    scene's value (``scene``: where each end not given came from, "sweep.f_max of FILE")."""
    if given[0] and not given[1]:
        top = f"{scene[1]}" if scene[1] else "the default top of the band"
        return (f"argument --fmin: expected a frequency below {fmax:g} Hz ({top}: give --fmax "
                f"above --fmin), got {fmin:g} (see nsdyn {command} --help)")  # fmt: skip
    bottom = scene[0] or "the default bottom of the band"
    low = f"--fmin ({fmin:g} Hz)" if given[0] else f"{fmin:g} Hz ({bottom})"
    return (f"argument --fmax: expected a frequency above {low}, got {fmax:g} "
            f"(see nsdyn {command} --help)")  # fmt: skip


def holes(
    command: str, n_bad: int, n: int, what: str, detail: str, report=None, say: bool = True
) -> int:
    """The status of a finished curve or boundary: 0, or ``EXIT_NUMERICS`` after one line on
    stderr, ``nsdyn COMMAND: K of N WHAT failed (DETAIL)``, when some of its points failed --
    a result with holes is not a success, as a study with failed tasks is not; its files hold
    every point either way. A ``report`` (a --json one, not yet printed) gains ``status`` and
    that line as ``error``, as every failed command's JSON has them (``say=False``: the line
    is not printed, a report for a file written first)."""
    if not n_bad:
        return 0
    line = f"{n_bad} of {n} {what} failed ({detail})"
    if say:
        print(f"nsdyn {command}: {line}", file=sys.stderr)
    if report is not None:
        report.update(status=EXIT_NUMERICS, error=line)
    return EXIT_NUMERICS


def fail(args: argparse.Namespace, message, status: int = EXIT_USER_ERROR,
         what: str = "error", notes=()) -> int:  # fmt: skip
    """``status`` after one line ``nsdyn COMMAND: what: message`` on stderr, then a line
    ``nsdyn COMMAND: note: ...`` for each of ``notes`` (an earlier run's files beside it) and,
    with ``--json``, one JSON object ``{"status", "error"}`` (and ``"notes"``) on stdout (a
    script reading the output reads every outcome)."""
    print(f"nsdyn {args.command}: {what}: {message}", file=sys.stderr)
    for note in notes:
        print(f"nsdyn {args.command}: note: {note}", file=sys.stderr)
    if getattr(args, "json", False):
        import json

        said = {"notes": list(notes)} if notes else {}
        print(json.dumps({"status": status, "error": str(message), **said}))
    return status


PGA_HELP = (
    "scale the record to this PGA [m/s²], every component by one factor: a planar model's "
    "horizontal component; a deck's or building's [motion] pga_component (default the "
    "resultant); the cylinder's larger horizontal peak. Without it a record runs as "
    "recorded (the default scene's record at 3 m/s²)"
)


def stale_figures(out: Path, names, command: str, quiet: bool) -> str:
    """Remove an earlier run's figures ``names`` from ``out`` when this run draws none
    (``--no-figures``: they sat beside the new results, figures of other settings), and say
    so on stderr unless ``quiet``; the note ("" if none went), for the summary's notes."""
    gone = [n for n in names if (Path(out) / n).is_file()]
    for n in gone:
        (Path(out) / n).unlink()
    note = f"removed the earlier run's {', '.join(gone)} (--no-figures draws none)" if gone else ""
    if note and not quiet:
        print(f"nsdyn {command}: note: {note}", file=sys.stderr)
    return note


def old_figures(out: Path, names, command: str, args: argparse.Namespace) -> str:
    """An earlier run's figures ``names`` in ``out``, removed before this run writes its
    tables: redrawn after them (an interrupt in between left an old figure beside the new
    results), or with ``--no-figures`` not drawn at all (:func:`stale_figures`, said: its
    note returned)."""
    note = stale_figures(out, names, command, args.json) if args.no_figures else ""
    for n in names:
        (Path(out) / n).unlink(missing_ok=True)
    return note


# the one-line warnings and notes the command line said on stderr during a command (a
# record's units): a --json summary carries them too (cleared as a command starts)
SAID: list[tuple[str, str]] = []


def same_said(a: str, b: str) -> bool:
    """Whether two notes say the same of one field, named by the scene's key and by the
    library's argument (``solver.dt: ...`` and ``dt: ...``): said once."""
    (ha, _, ta), (hb, _, tb) = a.partition(": "), b.partition(": ")
    return a == b or (ta == tb and " " not in ha + hb and
                      (ha.endswith(f".{hb}") or hb.endswith(f".{ha}")))  # fmt: skip


def with_said(s: dict) -> dict:
    """``s`` with the warnings and notes said on stderr during the command (:data:`SAID`)
    among its ``warnings`` and ``notes`` (each once): a script reading --json sees them."""
    for kind, text in SAID:
        key = "notes" if kind == "note" else "warnings"
        if not any(same_said(text, t) for t in s.get(key, [])):
            s.setdefault(key, []).append(text)
    return s


def json_report(s: dict, status: int = 0, **kw) -> str:
    """The --json text of a finished command: ``s`` :func:`with_said`, led by its ``status``
    (``s``'s own when a failure set it, else ``status``), so that a script reads the outcome
    of every command from one key (a failed one's ``error`` beside it)."""
    s = with_said(s)
    return json.dumps({"status": s.get("status", status), **s}, **kw)


def above_highest(amplitudes, where: str, command: str = "") -> str | None:
    """The refusal of ground acceleration amplitudes above A_HIGHEST (100 g), or None; a flag's
    (``where`` "--a-max") worded as the parser's own ("argument --a-max: ... (see nsdyn
    ``command`` --help)")."""
    from nsdyn.periodic.protocol import A_HIGHEST

    if big := [a for a in amplitudes if not a <= A_HIGHEST]:
        flag = where.startswith("--")
        return (f"{'argument ' * flag}{where}: expected ground acceleration amplitudes <= "
                f"{A_HIGHEST:g} m/s² (100 g), got {big[0]:g}"
                f"{f' (see nsdyn {command} --help)' if flag and command else ''}")  # fmt: skip
    return None


# flags of one command alone (``nsdyn modes FRAME`` takes its frame as an argument, which a
# scene file it names replaces: that frame is the file's)
FLAG_COMMANDS = {"--frame": ("run",), "--fmax": ("run", "modes")}  # (sweep's: its band)
RERUN_RESUMES = {"nsdyn study": "--fresh", "nsdyn sweep": "--restart"}  # (rerun: resumed)


def option_hint(parser: argparse.ArgumentParser, extra: list[str]) -> str:
    """The hint "; did you mean '--resume'?" for the first unknown long option near one of the
    command's own (options are never abbreviated: a prefix is an error, with this hint)."""
    import difflib

    known = [o for a in parser._actions for o in a.option_strings if o.startswith("--")]
    places = {a.dest: a.metavar or a.dest for a in parser._actions if not a.option_strings}
    for word in extra:
        if word.startswith("--"):
            name = word.split("=", 1)[0]
            if name[2:].replace("-", "_") in places and name not in known:  # (`modes --frame`:
                what = places[name[2:].replace("-", "_")]  # a flag of `run`, here the argument)
                return f"; {what} is this command's argument ({parser.prog} {what.upper()})"
            starts = [o for o in known if o.startswith(name)]
            resume = "--resume".startswith(name) or difflib.get_close_matches(
                name, ["--resume"], cutoff=0.85
            )
            if not starts and len(name) > 4 and resume and parser.prog in RERUN_RESUMES:
                return (
                    f"; {parser.prog} resumes by being run again as before (what finished "
                    f"is kept; {RERUN_RESUMES[parser.prog]} starts over)"
                )  # (a study's hint was "did you mean '--fresh'?", which starts over)
            if name in FLAG_COMMANDS:  # (`sweep --frame`: "did you mean '--fmin'?")
                runs = " and ".join(f"nsdyn {c}" for c in FLAG_COMMANDS[name])
                return f"; {name} is a flag of {runs} alone (a scene's scene.frame names a frame)"
            close = starts or difflib.get_close_matches(name, known, n=1)
            if close:
                return f"; did you mean {' or '.join(repr(o) for o in close[:3])}?"
    return ""
