"""Command line: ``nsdyn SUBCOMMAND ...``.

Each subcommand is two functions, ``configure(parser)`` adding its arguments and
``run(args) -> int`` doing the work, registered in :data:`COMMANDS`. To add one, write the
pair and add a :class:`Command` entry; :func:`main` builds the parser from the table.

Errors the user can fix (bad frame file, unwritable output directory, an argument out of
range) print one line to stderr and exit with status 2; no traceback. SIGINT or SIGTERM stops
a command with one line and status 130: every file is written atomically, so what is on disk
is complete; ``run --resume`` continues from a run's checkpoint, and a rerun of ``sweep`` or
``study`` resumes by itself (the line says which).
"""

from __future__ import annotations

import argparse
import gc
import importlib
import os
import signal
import sys
import warnings
from collections.abc import Callable
from dataclasses import dataclass

from nsdyn.cli.args import (
    EXIT_INTERRUPTED,
    EXIT_NUMERICS,
    EXIT_PIPE_CLOSED,
    EXIT_USER_ERROR,
    FLAG_COMMANDS,
    SAID,
    fail,
    option_hint,
    same_said,
    with_said,
)
from nsdyn.cli.stop import SIGNALLED as _SIGNALLED  # (one list: app._SIGNALLED)
from nsdyn.cli.stop import on_signal as _on_signal

__all__ = ["COMMANDS", "Command", "build_parser", "main", "script"]


def _user_errors() -> tuple[type[BaseException], ...]:
    from nsdyn.atomic import CheckpointError
    from nsdyn.ground import RecordFileError
    from nsdyn.models.scenefile import SceneError
    from nsdyn.structure import FrameFileError

    return (FrameFileError, OSError, SceneError, RecordFileError, CheckpointError)


# scene keys a command-line flag sets: an error about the key names the flag that gave it
FLAG_KEYS = {"solver.method": "--method", "solver.dt": "--dt", "motion.record": "--record",
             "motion.pga": "--pga", "motion.t_end": "--t-end", "scene.f_max": "--fmax",
             "structure.f_max": "--fmax", "motion.units": "--units",
             "scene.fidelity": "--fidelity", "structure.fidelity": "--fidelity",
             "solver.max_steps": "--max-steps", "scene.frame": "--frame",
             "solver.law": "--friction"}  # fmt: skip


def flagged(message: str, args: argparse.Namespace) -> str:
    """``message`` with a scene key a flag of ``args`` set named with that flag
    (``s.toml: solver.method (--method): ...``): the file does not hold the value blamed."""
    for key, flag in FLAG_KEYS.items():
        v = getattr(args, flag[2:].replace("-", "_"), None)
        if flag in FLAG_COMMANDS and getattr(args, "command", None) not in FLAG_COMMANDS[flag]:
            continue
        if not v or f": {key}:" not in message:
            continue
        said = {str(v), repr(v)} | ({f"{v:g}"} if isinstance(v, float) else set())
        rest = message.split(f": {key}:", 1)[1]  # (a run's end is the flag's: "1e+11 samples")
        got = rest.rsplit("got ", 1)[1].split() if "got " in rest else []  # (a value echoed:
        got = got[0].strip("'\",;()") if got else None  # the flag's, or the file's own)
        if key in ("motion.t_end", "motion.units"):  # (the flag's, whatever else the message)
            blamed = got is None or got in said
        else:
            blamed = any(s in rest for s in said)  # (the flag's value, not the file's)
        if blamed:
            message = message.replace(f": {key}:", f": {key} ({flag}):", 1)
    t_end = getattr(args, "t_end", None)
    against = ("longer than the run", " outputs of ")  # (not "expected a positive number")
    if t_end is not None and ": solver.dt_out:" in message and any(a in message for a in against):
        message += f" (the run ends at --t-end {t_end:g} s)"  # (the file's step against the
        # flag's end: only the step was named)
    return message


def _numerics_errors() -> tuple[type[BaseException], ...]:
    """Every family's numerical failure (IntegrationError and UpliftError, the deck's
    PlaneIntegrationError, the cylinder's SimulationError, the rocking, contact and shooting
    solvers' own) is a NumericalFailure."""
    from nsdyn._checks import NumericalFailure

    return (NumericalFailure,)


@dataclass(frozen=True)
class Command:
    """A subcommand: one-line help, argument set-up, and the function that runs it."""

    help: str
    configure: Callable[[argparse.ArgumentParser], None]
    run: Callable[[argparse.Namespace], int]


# --------------------------------------------------------------------------- table


def _lazy(module: str, attr: str) -> Callable:
    """``module.attr``, imported on first call (keeps ``nsdyn --help`` fast)."""
    return lambda arg: getattr(importlib.import_module(module), attr)(arg)


COMMANDS: dict[str, Command] = {
    "modes": Command(
        help="fixed-base modes, dof counts (full and Craig–Bampton), mass and f_bis (a 3D "
        "frame: modes with their families and mass fractions, dofs and mass)",
        configure=_lazy("nsdyn.cli.modes", "configure"),
        run=_lazy("nsdyn.cli.modes", "run"),
    ),
    "sweep": Command(
        help="frequency-amplitude diagrams of periodic solutions (shooting + continuation)",
        configure=_lazy("nsdyn.cli.sweep", "configure"),
        run=_lazy("nsdyn.cli.sweep", "run"),
    ),
    "uplift": Command(
        help="uplift boundary: the smallest harmonic amplitude A*(f) at which an isolator's "
        "normal force reaches zero in steady state (shooting + root finding)",
        configure=_lazy("nsdyn.cli.uplift", "configure"),
        run=_lazy("nsdyn.cli.uplift", "run"),
    ),
    "bench": Command(
        help="work-precision, fidelity and stability benchmarks (speed against accuracy)",
        configure=_lazy("nsdyn.cli.bench", "configure"),
        run=_lazy("nsdyn.cli.bench", "run"),
    ),
    "spectrum": Command(
        help="overturning spectrum of a rocking block or frame: minimum overturning pulse "
        "amplitude against pulse frequency (bracketing + bisection)",
        configure=_lazy("nsdyn.cli.spectrum", "configure"),
        run=_lazy("nsdyn.cli.spectrum", "run"),
    ),
    "study": Command(
        help="many runs of a scene over parameters and records (local processes or Dask), "
        "resumable; design searches, percentiles, fragility curves",
        configure=_lazy("nsdyn.cli.study", "configure"),
        run=_lazy("nsdyn.cli.study", "run"),
    ),
    "export": Command(
        help="write a scene's full isolated-frame model as a standalone OpenSees (openseespy) "
        "script that runs the record and prints the peaks",
        configure=_lazy("nsdyn.cli.export", "configure"),
        run=_lazy("nsdyn.cli.export", "run"),
    ),
    "run": Command(
        help="transient run of a scene: isolated frame (default: office-11 on isolators, "
        "synthetic record), deck on bidirectional isolators, 3D building, rocking "
        "block/frame, contact body or cylinder",
        configure=_lazy("nsdyn.cli.run", "configure"),
        run=_lazy("nsdyn.cli.run", "run"),
    ),
}


class _Parser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line on stderr and status 2, and whose
    commands take their options before, between and after their positionals
    (``nsdyn export opensees --t-end 2 SCENE``: argparse alone would have matched the optional
    SCENE, empty, together with ``opensees``)."""

    _intermixing = False

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("allow_abbrev", False)  # `--res` is not `--resume`: say so, not guess
        super().__init__(*args, **kwargs)

    def parse_known_args(self, args=None, namespace=None):
        if self._subparsers is not None or self._intermixing:  # nsdyn itself; the inner passes
            return super().parse_known_args(args, namespace)
        self._intermixing = True
        try:
            return self.parse_known_intermixed_args(args, namespace)
        finally:
            self._intermixing = False

    def error(self, message: str):
        print(f"{self.prog}: error: {message} (see {self.prog} --help)", file=sys.stderr)
        if _JSON[0]:  # a usage error is an outcome too for a script reading the JSON
            import json

            print(json.dumps({"status": EXIT_USER_ERROR, "error": message}))
        raise SystemExit(EXIT_USER_ERROR)


_JSON = [False]  # the command line holds --json (set by main before parsing)


_ENDING = [False]  # set by the script: main's return ends the process


def _interrupt_line(args: argparse.Namespace) -> str:
    """What an interrupted command leaves and how to go on: only ``run`` (with ``--resume``)
    and ``sweep`` (by itself) continue from a checkpoint; the others start over."""
    from pathlib import Path

    done = f"nsdyn {args.command}: interrupted; files on disk are complete"
    if args.command == "sweep":  # a frame's sweep, or a deck's or 3D building's in the plane
        from nsdyn.studies import plane_sweep
        from nsdyn.studies.sweep import CHECKPOINT_NAME, DEFAULT_OUT

        out = Path(getattr(args, "out", None) or DEFAULT_OUT)
        names = (CHECKPOINT_NAME, plane_sweep.CHECKPOINT_NAME)
        if any(any(out.glob(n.replace("{amplitude}", "*"))) for n in names):
            old = " (its sweep.csv is an earlier run's)" * (out / "sweep.csv").is_file()
            again = ("rerun it without --restart to resume from them, with it to start over"
                     if getattr(args, "restart", False) else "rerun the same command to "
                     "resume")  # fmt: skip
            return f"nsdyn sweep: interrupted; the checkpoints in {out} are complete{old}, {again}"
        return f"{done}; it stopped before its first checkpoint, a rerun starts over"
    if args.command == "run":
        from nsdyn.cli.run import DEFAULT_OUT, FINISHED
        from nsdyn.cli.run_resume import CHECKPOINT

        if FINISHED:  # (it was "stopped before its first checkpoint")
            drawn = len(FINISHED) > 1 or getattr(args, "no_figures", False)
            return (f"nsdyn run: interrupted after the run finished: its histories are "
                    f"{FINISHED[0]}, " + ("its files are complete" if drawn else
                                          "its figure was not drawn"))  # fmt: skip
        out = Path(getattr(args, "out", None) or DEFAULT_OUT)
        if (out / CHECKPOINT).is_file():
            return f"{done}, rerun it with --resume to continue from its checkpoint in {out}"
        from nsdyn.atomic import WRITTEN

        if (kind := _scene_kind_of(args)) != "isolated":  # (only an isolated frame's run keeps
            files, verb = ", ".join(WRITTEN), "are" if len(WRITTEN) > 1 else "is"  # one)
            wrote = f"; {files} {verb} this run's, its other files were not written" * bool(files)
            return f"{done}{wrote}; a {kind} scene's run keeps no checkpoint, a rerun starts over"
        return f"{done}; it stopped before its first checkpoint, a rerun starts over"
    if args.command == "study":  # (stopped outside its tasks' own handler)
        from nsdyn.cli.study import STARTED, stopped_line

        if STARTED:  # (its tasks had started: it said "before its tasks started ... a rerun
            return f"nsdyn study: {stopped_line(STARTED[0])}"  # runs them" of finished ones)
        return ("nsdyn study: interrupted before its tasks started; the results folder is as "
                "it was (a rerun runs them)")  # fmt: skip
    if args.command in WRITES_AT_END:
        from nsdyn.atomic import WRITTEN

        out = getattr(args, "out", None) or "the output folder"
        if WRITTEN:  # (interrupted between its files: "it wrote no file" beside the CSV)
            return (f"nsdyn {args.command}: interrupted while writing its results: "
                    f"{', '.join(WRITTEN)} {'are' if len(WRITTEN) > 1 else 'is'} this run's "
                    f"and complete, any other file in {out} an earlier run's; this command "
                    "keeps no checkpoint, a rerun starts over")  # fmt: skip
        there = not getattr(args, "out", None) or Path(out).is_dir()  # (a new folder: none)
        old = f", and any in {out} are an earlier run's" * there
        return (f"nsdyn {args.command}: interrupted before writing its results: it wrote no "
                f"file{old}; this command keeps no checkpoint, a rerun starts over")  # fmt: skip
    return f"{done}; this command keeps no checkpoint, a rerun starts over"


# commands that write all their files once their work is done (an interrupt leaves none)
WRITES_AT_END = ("uplift", "spectrum", "modes", "export")


def _scene_kind_of(args: argparse.Namespace) -> str:
    """The ``[scene] kind`` of ``nsdyn run``'s scene (``isolated`` without one, or when the
    file does not say)."""
    if getattr(args, "scene", None) is None:
        return "isolated"
    try:
        from nsdyn.models.scenefile import read_toml, scene_kind

        return scene_kind(read_toml(args.scene), str(args.scene))
    except Exception:  # (the run itself named what is wrong with the file)
        return "isolated"


def _one_line_warnings(command: str, default: Callable) -> Callable:
    """``warnings.showwarning`` that prints nsdyn's own warnings about the user's input (a
    record's units, a component a model cannot feel: ``InputWarning``) as one line,
    ``nsdyn CMD: warning: ...`` (a ``NotedWarning``, what a scene's run says as a note:
    ``nsdyn CMD: note: ...``), without Python's file, line and source echo; any other
    warning as Python shows it."""

    def show(message, category, filename, lineno, file=None, line=None):
        from nsdyn._checks import InputWarning, NotedWarning

        if issubclass(category, InputWarning):
            kind = "note" if issubclass(category, NotedWarning) else "warning"
            if any(k == kind and same_said(str(message), m) for k, m in SAID):  # (said once)
                return
            SAID.append((kind, str(message)))  # (--json: in the summary as well)
            print(f"nsdyn {command}: {kind}: {message}", file=sys.stderr if file is None else file)
            return
        default(message, category, filename, lineno, file, line)

    return show


def _version() -> str:
    """``nsdyn --version``: this package's version and those of the libraries its numbers
    depend on (what a bug report needs)."""
    from importlib.metadata import PackageNotFoundError, version

    import nsdyn

    def v(dist: str) -> str:
        try:
            return version(dist)
        except PackageNotFoundError:
            return "not installed"

    libs = ", ".join(f"{d} {v(d)}" for d in ("numpy", "scipy", "numba"))
    return f"nsdyn {nsdyn.__version__} (Python {sys.version.split()[0]}; {libs})"


class _VersionAction(argparse.Action):
    def __call__(self, parser, namespace, values, option_string=None):
        print(_version())
        parser.exit()


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The parser of every command; with ``only`` (a command's name) the options of that one
    alone are set up, and the other commands' modules are not imported (a command's start
    pays only for its own imports); with ``only=""`` none are (the top-level options and
    ``nsdyn --help``, which lists every command either way)."""
    parser = _Parser(prog="nsdyn", description="Non-smooth dynamics of friction base-isolated "
                     "frames.")  # fmt: skip
    parser.add_argument("--version", action=_VersionAction, nargs=0, help="print the "
                        "versions of nsdyn, Python, numpy, scipy and numba and exit")  # fmt: skip
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    parser.commands = {}  # name -> the command's own parser (its usage errors name it)
    for name, cmd in COMMANDS.items():
        p = sub.add_parser(name, help=cmd.help, description=cmd.help)
        if only is None or name == only:
            cmd.configure(p)
        p.set_defaults(_run=cmd.run)
        parser.commands[name] = p
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``nsdyn`` script; returns the exit status."""
    argv = sys.argv[1:] if argv is None else list(argv)
    _JSON[0] = "--json" in argv  # reset when main returns
    try:
        return _main(argv)
    except BrokenPipeError:  # the reader closed stdout (`nsdyn modes F --json | head`)
        if not _stdout_broken():  # another pipe's (a worker's): a real error
            raise
        return EXIT_PIPE_CLOSED
    finally:
        _JSON[0] = False


def _stdout_broken() -> bool:
    """Whether stdout is a pipe whose reader has gone (poll reports an error on it)."""
    import select

    try:
        poller = select.poll()
        poller.register(sys.stdout.fileno(), select.POLLOUT)
        return any(ev & select.POLLERR for _, ev in poller.poll(0))
    except (OSError, ValueError, AttributeError):  # a stream without a file descriptor
        return False


def _pipe_closed() -> int:
    """The script's end when stdout's reader has gone: what is still buffered goes to
    /dev/null, so that the interpreter's last flush raises nothing (a process killed by
    SIGPIPE would end with the same status, 128 + 13)."""
    _stdout_to(os.devnull)
    return EXIT_PIPE_CLOSED


def _stdout_to(path: str | None) -> None:
    """Point the process's fd 1 at ``path`` (None: at stderr's file) for the rest of its life."""
    try:
        fd = os.open(path, os.O_WRONLY) if path else sys.stderr.fileno()
        os.dup2(fd, sys.stdout.fileno())
        if path:
            os.close(fd)
    except (OSError, ValueError, AttributeError):  # a stream without a file descriptor
        pass


def _flushed() -> bool:
    """Flush stdout; False when its reader has gone."""
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        return False
    except (OSError, ValueError, AttributeError):
        pass
    return True


def _main(argv: list[str]) -> int:
    only = argv[0] if argv and argv[0] in COMMANDS else ""  # no command: configure none
    if only == "bench" and {"-h", "--help"} & set(argv):  # a benchmark's own help
        from nsdyn.cli.bench import benchmark_help

        text = benchmark_help(argv[1:])
        if text is not None:
            print(text)
            return 0
    parser = build_parser(only)
    if not argv:  # `nsdyn` alone: one line, every command named
        parser.error(f"a command is required: {', '.join(COMMANDS)}")
    if not only and argv[0].startswith("-") and argv[0] not in ("-h", "--help", "--version"):
        cmd = next((a for a in argv if a in COMMANDS), None)  # options before the command
        if cmd is not None:
            rest = [a for a in argv if a != cmd]
            parser.error(f"options go after the command: nsdyn {cmd} {' '.join(rest)}")
        import difflib  # (--versoin: "a command is required")

        word = argv[0].split("=", 1)[0]
        close = difflib.get_close_matches(word, ["--help", "--version"], n=1, cutoff=0.8)
        if word not in ("--help", "--version"):  # (--version=1: argparse's own message)
            hint = (f"; did you mean {close[0]!r}?" if close else
                    f"; a command's options go after it, nsdyn COMMAND {argv[0]}")  # fmt: skip
            parser.error(
                f"unrecognized option {argv[0]!r}{hint} (before a command nsdyn "
                f"takes --help and --version; commands: {', '.join(COMMANDS)})"
            )
    if not only and not argv[0].startswith("-"):  # a mistyped command: the closest one
        from nsdyn._checks import did_you_mean

        hint = did_you_mean(argv[0], list(COMMANDS))
        parser.error(f"unknown command {argv[0]!r}{hint} (commands: {', '.join(COMMANDS)})")
    args, extra = parser.parse_known_args(argv)  # a usage error: one line, SystemExit(2)
    if extra:  # reported by the command's own parser: "nsdyn run: error: …"
        own = parser.commands[args.command]
        own.error(f"unrecognized arguments: {' '.join(extra)}{option_hint(own, extra)}")
    _SIGNALLED[0] = False
    from nsdyn.atomic import EARLIER, WRITTEN

    WRITTEN.clear(), EARLIER.clear(), SAID.clear()  # (what this command writes and says)
    try:  # SIGTERM stops a command the way Ctrl-C does (atomic files; checkpoints kept)
        old = signal.signal(signal.SIGTERM, _on_signal), signal.signal(signal.SIGINT, _on_signal)
    except ValueError:  # not the main thread: leave signals alone
        old = None
    shown = warnings.showwarning
    warnings.showwarning = _one_line_warnings(args.command, shown)
    try:
        try:
            return int(args._run(args))
        except Exception as exc:  # a signal raised inside a jitted kernel surfaces wrapped;
            # one inside numba's compiler can be swallowed by a callback and leave an error
            # of its own: after a signal, any error is the signal's
            from nsdyn.atomic import caused_by_interrupt

            if not (_SIGNALLED[0] or caused_by_interrupt(exc)):
                raise
            raise KeyboardInterrupt from exc
    except KeyboardInterrupt:
        _SIGNALLED[0] = True  # (a later signal, while this one's stop is said: ignored)
        line = _interrupt_line(args)
        print(line, *(f"nsdyn {args.command}: note: {n}" for n in EARLIER), sep="\n",
              file=sys.stderr)  # fmt: skip
        if getattr(args, "json", False):  # an outcome too (stdout was empty)
            import json

            error = line.removeprefix(f"nsdyn {args.command}: ")
            said = with_said({"notes": list(EARLIER)} if EARLIER else {})  # (and its notes)
            print(json.dumps({"status": EXIT_INTERRUPTED, "error": error} | said), flush=True)
        return EXIT_INTERRUPTED
    except BrokenPipeError:  # no error of the input: main stops quietly
        raise
    except _user_errors() as exc:
        return fail(args, flagged(str(exc), args))  # one line: an input is fixed, not run
    except MemoryError as exc:  # (dt_out = 1e-5 s on a 3D building: numpy's traceback)
        return fail(args, f"out of memory ({exc}): ask for fewer outputs (a larger solver."
                    "dt_out), a shorter run or a smaller model")  # fmt: skip
    except _numerics_errors() as exc:
        from nsdyn.solve.integrate import UpliftError

        # an uplift under contact "detect" is the model's assumption ending, not the numerics
        what = "model limit" if isinstance(exc, UpliftError) else "numerical failure"
        return fail(args, exc, EXIT_NUMERICS, what, EARLIER)
    finally:
        warnings.showwarning = shown
        if old is not None and _ENDING[0]:  # the script's command is done, its outcome out:
            for sig in (signal.SIGINT, signal.SIGTERM):  # a signal now turned a success into
                signal.signal(sig, signal.SIG_IGN)  # 130 (or 143) unsaid, or a second one an
            # interrupt's line into a traceback (`timeout` signals the process, then its group)
        elif old is not None:  # a caller that goes on (tests, notebooks): its own handlers
            signal.signal(signal.SIGTERM, old[0])
            signal.signal(signal.SIGINT, old[1])


# the commands whose first run compiles beside a helper process: the package whose kernels
# tell whether numba's cache ever held them, and the module every such helper imports first
_STANDBY_FOR = {
    "run": ("solve", "nsdyn.solve.compile_split"),
    "study": ("solve", "nsdyn.solve.compile_split"),
    "sweep": ("periodic", "nsdyn.periodic.problem"),
    "uplift": ("periodic", "nsdyn.periodic.problem"),
}


def _start_standby(argv: list[str]) -> None:
    """Start the compile helper's process now (:func:`nsdyn._numba_cache.start_standby`) when
    ``argv`` is a command that compiles with one and numba's cache has never held its
    package's kernels (:func:`nsdyn._numba_cache.never_compiled`): its imports then run beside
    this process's, not after them."""
    from pathlib import Path

    from nsdyn import _numba_cache as nc

    pick = _STANDBY_FOR.get(argv[0]) if argv else None
    if pick is None or "-h" in argv or "--help" in argv:
        return
    package, preload = pick
    if nc.never_compiled(Path(nc.__file__).parent / package / "__init__.py"):
        nc.start_standby(preload)


def script(argv: list[str] | None = None) -> int:
    """The ``nsdyn`` script and ``python -m nsdyn.cli``: :func:`main` (a signal during its
    imports: one line, status 130), then every object left is moved out of the collector's
    reach (:func:`gc.freeze`): the last collection traversed every object numba left, 0.35 s
    after a first compilation, 0.13 s after a cached start (docs/dev/first-runs.md); exit
    handlers still run. Into an empty cache the compile helper starts first
    (:func:`_start_standby`); the first generation waits for a million new objects, not 700
    (:func:`hold_collections`). Not for callers that go on (tests, notebooks): :func:`main`."""
    from nsdyn._numba_cache import hold_collections, release_standby

    signal.signal(signal.SIGTERM, _on_signal)  # (as Ctrl-C, before main sets its own)
    _ENDING[0] = True  # main leaves the signals ignored, not restored, when it returns
    try:
        hold_collections()  # the start-up's objects are not traversed again and again
        _start_standby(sys.argv[1:] if argv is None else argv)
        code = main(argv)
    except KeyboardInterrupt:  # before main's own handling began (its imports): one line
        print("nsdyn: interrupted as it started; it wrote nothing", file=sys.stderr)
        code = EXIT_INTERRUPTED
    finally:
        _ENDING[0] = False
        release_standby()
    gc.freeze()
    if code == EXIT_PIPE_CLOSED or not _flushed():  # the output's reader has gone
        return _pipe_closed()
    _stdout_kept_for_results()
    return code


def _stdout_kept_for_results() -> None:
    """When the command ran OpenSees here (``bench opensees``), fd 1 to stderr for the end:
    OpenSees prints "Process 0 Terminating" on stdout at exit (after a ``--json`` summary)."""
    if "openseespy.opensees" in sys.modules:  # (stdout was flushed by the caller)
        _stdout_to(None)


if __name__ == "__main__":
    sys.exit(script())
