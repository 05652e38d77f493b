"""A first compilation shared with a helper process (:class:`nsdyn._numba_cache.Helper`).

What must hold: no kernel is compiled with another kernel as an argument (its type holds a
dispatcher identity that differs per process, so the helper's cache entries would never be
found), a helper that fails or delivers nothing only
costs the wait for its end, and each first compilation split with a helper leaves the
helper's share to it (loaded, not compiled, here; SPLITS below): the default run's flat
right-hand side, its Jacobian, Newton and the factorisation; the switch model's system kernel,
its Jacobian, the friction detector, the settling, the factorisation and the general metrics;
generalized-alpha's system kernel and Jacobian; genalpha-lowrank's system
kernel and metrics; the sweep's Jacobian.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest
from numba import njit, types
from numba.core.registry import CPUDispatcher as Dispatcher

from nsdyn._numba_cache import HELPER_ENV, Helper, compile_note, helper_enabled
from nsdyn.solve import methods

JIT = os.environ.get("NUMBA_DISABLE_JIT", "0") in ("", "0")


@pytest.mark.skipif(not JIT, reason="no compiled signatures under NUMBA_DISABLE_JIT")
def test_no_kernel_takes_a_kernel_argument():
    # a kernel's numba type holds its dispatcher's identity, which numba draws at random per
    # process: a caller compiled for such an argument would be cached under a key no other
    # process (the helper included) ever finds. The loops' callees are module globals,
    # addresses, or copies of one source (nsdyn._kaddress.specialised), never arguments
    for kernel in ("radau", "event", "genalpha"):
        methods.warmup_kernel(methods.METHODS[kernel].kernel, "metrics")
    found = [
        f"{mod.__name__}.{name}{sig}"
        for mod in list(sys.modules.values())
        if getattr(mod, "__name__", "").startswith("nsdyn.")
        for name, obj in list(vars(mod).items())
        for sig in getattr(obj, "signatures", None) or ()
        if isinstance(obj, Dispatcher)
        if any(isinstance(t, types.Dispatcher) for t in sig)
    ]
    assert not found, found
    # the rule's detector: a kernel compiled with a kernel argument is found
    outer = njit(cache=False)(lambda f, x: f(x))
    outer(njit(cache=False)(lambda x: x + 1.0), 1.0)
    assert any(isinstance(t, types.Dispatcher) for t in outer.signatures[0])


def _report_enabled(q):
    q.put(helper_enabled())


@pytest.mark.skipif(not JIT, reason="nothing compiles under NUMBA_DISABLE_JIT")
def test_no_helper_inside_a_process_pool_worker(monkeypatch):
    import multiprocessing

    monkeypatch.delenv(HELPER_ENV, raising=False)
    ctx = multiprocessing.get_context("spawn")
    q = ctx.Queue()
    p = ctx.Process(target=_report_enabled, args=(q,))
    p.start()
    enabled_in_worker = q.get(timeout=120)
    p.join()
    assert enabled_in_worker is False


def test_helper_switched_off_by_environment(monkeypatch):
    monkeypatch.setenv(HELPER_ENV, "0")
    assert not helper_enabled()
    monkeypatch.setenv(HELPER_ENV, "1")
    monkeypatch.setenv("NUMBA_DISABLE_JIT", "1")
    assert not helper_enabled()


@pytest.mark.skipif(not JIT, reason="without numba compiling every kernel counts as ready")
def test_failed_helper_is_waited_out_not_trusted():
    @njit(cache=False)
    def never_compiled(x):
        return x + 1

    with Helper("nsdyn.no_such_module:f") as h:
        # the helper dies on its import: the wait ends with it and says nothing was delivered
        assert not h.wait_for([never_compiled], timeout=120.0)
        assert not h.running()
    assert h.close() not in (0, None)


def test_helper_imports_this_process_nsdyn_not_the_working_directory_one(tmp_path, monkeypatch):
    # `nsdyn run` started in a source checkout with nsdyn installed (the README's first
    # command): the helper must import the nsdyn this process runs, whose numba cache this
    # process reads; a copy in the working directory (here one that cannot be imported) must
    # not shadow it (it did: the helper's kernels landed in the checkout's cache, unused)
    fake = tmp_path / "nsdyn"
    fake.mkdir()
    (fake / "__init__.py").write_text("raise ImportError('the working directory copy')\n")
    monkeypatch.chdir(tmp_path)
    with Helper("nsdyn._numba_cache:helper_enabled") as h:
        pass
    assert h.close() == 0


REPORT = "import os, nsdyn\ndef main():\n    open(os.environ['OUT'], 'w').write(nsdyn.__file__)\n"


def test_helper_imports_the_checkout_nsdyn_this_process_imported(tmp_path):
    # ``python -c`` in a source checkout (as the tests of an installed copy run): this process
    # imports the checkout's nsdyn (the working directory, '' on its path, comes first) and
    # the helper must import that one too, not the installed one (whose kernels have another
    # cache: this process compiled everything again)
    import nsdyn

    checkout = tmp_path / "checkout"
    checkout.mkdir()
    (checkout / "nsdyn").symlink_to(Path(nsdyn.__file__).parent, target_is_directory=True)
    probe = tmp_path / "probe"
    probe.mkdir()
    (probe / "report_nsdyn.py").write_text(REPORT)
    out = tmp_path / "helper-nsdyn.txt"
    code = (
        "import nsdyn\nfrom nsdyn._numba_cache import Helper\n"
        "h = Helper('report_nsdyn:main')\nassert h.close() == 0\nprint(nsdyn.__file__)\n"
    )
    env = dict(os.environ, PYTHONPATH=str(probe), OUT=str(out))
    ran = subprocess.run(
        [sys.executable, "-c", code], cwd=checkout, env=env, capture_output=True, text=True
    )
    assert ran.returncode == 0, ran.stderr
    assert ran.stdout.strip().startswith(str(checkout))  # this process: the checkout's
    assert out.read_text() == ran.stdout.strip()  # the helper: the same file


FRESH_WARMUP = (
    "from numba.core import event as ev\n"
    "seen = set()\n"
    "class L(ev.Listener):\n"
    "    def on_start(self, e): seen.add(e.data['dispatcher'].py_func.__qualname__)\n"
    "    def on_end(self, e): pass\n"
    "ev.register('numba:compile', L())\n"
    "from nsdyn.solve import methods\n"
    "methods.warmup_kernel({kernel!r}, metrics={metrics!r})\n"
    "print(' '.join(sorted(seen)))\n"
)


def _compiled_in_a_fresh_warmup(cache, kernel, metrics) -> set[str]:
    """Names of the kernels a fresh process compiles itself (numba's compile events; a cache
    load raises none) in ``warmup_kernel(kernel, metrics)`` with an empty cache."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), NUMBA_DISABLE_JIT="0")
    env[HELPER_ENV] = "1"
    code = FRESH_WARMUP.format(kernel=kernel, metrics=metrics)
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    return set(out.stdout.split())


# the table's system kernel and the three it calls by address, then its Jacobian (by address
# and its own kernel): nsdyn.solve.compile_split.SYSTEM, by the kernels' names
SYSTEM = ("sys_evaluate", "_assemble", "solve_small", "pinv_into", "jac_table", "sys_jac_at")
# (kernel, metrics, compiled by the calling process, compiled by the helper only): the
# default loop (~15-40 s on two cores; its helper also takes the factorisation, this process
# the metrics) and the switch model's, whose callees
# by address each process compiles by type for the signatures the loop declares, without
# running them. The metrics are those of nsdyn.solve.methods.metrics_for: the flat ones after
# the flat Radau loop, else the general ones, which call the system kernel by address
SPLITS = [
    ("radau", "metrics", {"radau_flat", "start_flat", "evaluate_flat_many"},
     {"feval_flat", "jac_flat_here", "newton_flat", "_factor", "setup", "workspace"}),
    ("event", "metrics-general",
     {"_run", "event_step", "event_start", "newton_general", "_event_at", "_settle",
      "evaluate_many_t"},
     {*SYSTEM, "_detect", "_factor", "accept"}),
    # generalized-alpha: its loop and the metrics (compiled, not run) here; the Jacobian by
    # address, the Jacobian's own kernel (which it calls by address) and the system kernel in
    # the helper
    ("genalpha", "metrics-general",
     {"genalpha_loop", "_residual", "_iteration_matrix", "evaluate_many_t"}, set(SYSTEM)),
    # genalpha-lowrank's set-up evaluates the system kernel once from Python, through the
    # metrics' kernel; its dense loop compiles here from the run's argument types
    # (sparse.loop_args) while the helper compiles the system kernel and then the metrics
    ("genalpha-lowrank", "metrics-general", {"run_steps", "step", "friction"},
     {*SYSTEM[:4], "evaluate_many_t"}),
]  # fmt: skip


@pytest.mark.slow
@pytest.mark.skipif(not JIT, reason="nothing compiles under NUMBA_DISABLE_JIT")
@pytest.mark.parametrize(
    "kernel, metrics, here_expected, by_helper",
    SPLITS,
    ids=["radau", "event", "genalpha", "genalpha-lowrank"],
)
def test_first_warmup_splits_the_compilation_with_its_helper(
    tmp_path, kernel, metrics, here_expected, by_helper
):
    if not helper_enabled():
        pytest.skip("a helper process needs two usable cores and NSDYN_COMPILE_HELPER != 0")
    here = _compiled_in_a_fresh_warmup(tmp_path, kernel, metrics)
    assert here_expected <= here
    assert not here & by_helper, "compiled here, not by the helper"


@pytest.mark.skipif(not JIT, reason="no compiled signatures under NUMBA_DISABLE_JIT")
def test_unilateral_runs_use_the_event_loops_one_compiled_signature():
    # the helper's share of the event loop is compiled for one signature: the switch model's
    # runs and both unilateral methods must all ask for it (else one of them recompiles ~2 min)
    from nsdyn.solve import _kunilateral, methods

    methods.warmup_kernel("event")
    methods.warmup_unilateral()
    assert len(_kunilateral._run.signatures) == 1, _kunilateral._run.signatures


class _IndexOnly:
    """A cache file whose index names one data file (present or not)."""

    def __init__(self, path):
        self.path = path

    def _load_index(self):
        return {("sig",): "kernel-1.nbc"}

    def _data_path(self, name):
        return str(self.path / name)


def test_an_index_entry_counts_only_once_its_data_file_is_written(tmp_path):
    # numba saves a kernel's index before its data file: a waiter that trusted the index
    # alone would try to load a helper's kernel too early, fail and compile it itself
    from types import SimpleNamespace

    from nsdyn._numba_cache import dispatcher_cached

    cf = _IndexOnly(tmp_path)
    disp = SimpleNamespace(signatures=[], _cache=SimpleNamespace(_cache_file=cf))
    assert not dispatcher_cached(disp)
    (tmp_path / "kernel-1.nbc").write_bytes(b"")
    assert dispatcher_cached(disp)


def test_a_kernel_without_a_split_warms_up_beside_a_metrics_helper(monkeypatch):
    # for a kernel the helper does not share (dopri5, the general Radau loop) the helper only
    # compiles the flat metrics: this process warms the whole kernel itself and asks the split
    # table nothing (a first `nsdyn run --method genalpha` took that path and failed, when
    # generalized-alpha had no split)
    from nsdyn.solve import methods

    monkeypatch.setattr(methods, "_COMPILED", {})
    for name in ("dopri5", "radau-generic"):
        m = methods.METHODS[name]
        assert m.kernel not in methods._SPLIT
        assert methods._warm(m.kernel, m, helper=object()) >= 0.0
        assert m.kernel in methods._COMPILED


def test_general_metrics_follow_an_unsplit_loop_in_its_own_process(monkeypatch):
    # the general metrics call the system kernel by address: a helper compiling them beside
    # dopri5 or the general Radau loop would compile the system kernel a second time (the
    # loop compiles it too); they follow the loop in this process, and only the flat
    # metrics (which need no system kernel) go to a helper
    from nsdyn.solve import methods

    started, warmed = [], []
    monkeypatch.setattr(methods, "_COMPILED", {})
    monkeypatch.setattr(methods, "helper_enabled", lambda: True)
    monkeypatch.setattr(methods, "is_cached", lambda kernel: False)
    monkeypatch.setattr(methods, "Helper", lambda target: started.append(target) or _NoHelper())
    monkeypatch.setattr(methods, "_warm", lambda k, m, helper=None, here=None: warmed.append(k))
    monkeypatch.setattr(methods, "warmup_metrics", lambda flat=True: warmed.append(flat))
    methods.warmup_kernel("dopri5", metrics="metrics-general")
    methods.warmup_kernel("radau-general", metrics="metrics-general")
    assert started == [] and warmed == ["dopri5", False, "radau-general", False]
    methods.warmup_kernel("dopri5", metrics="metrics")
    assert started == ["nsdyn.solve.methods:warmup_metrics"]


class _NoHelper:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


@pytest.mark.slow
@pytest.mark.skipif(not JIT, reason="nothing compiles under NUMBA_DISABLE_JIT")
def test_first_sweep_warmup_leaves_the_jacobian_to_its_helper(tmp_path):
    # the period map calls its step, Jacobian and right-hand side by address: a first
    # sweep's warm-up compiles the period map and its step here while the helper compiles
    # the step's iteration matrix (with its LU factorisation: the step, compiled after the
    # period map, loads them), the Jacobian and the right-hand side (and the metrics), so the
    # frame's right-hand side compiles in one process only; no Radau loop compiles (the
    # uplift probe is SciPy's Radau on the period map's own right-hand side and Jacobian),
    # and the orbit quantities call that right-hand side too (orbit_forces, in the helper)
    if not helper_enabled():
        pytest.skip("a helper process needs two usable cores and NSDYN_COMPILE_HELPER != 0")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), NUMBA_DISABLE_JIT="0")
    env[HELPER_ENV] = "1"
    code = FRESH_WARMUP.replace(
        "from nsdyn.solve import methods\nmethods.warmup_kernel({kernel!r}, metrics={metrics!r})\n",
        "from nsdyn.periodic.problem import warmup\nwarmup()\n",
    )
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    here = set(out.stdout.split())
    assert {"period_map", "dirk_step"} <= here
    helpers = {"j_eval", "f_eval", "frame_flat", "frame_flat_jac", "orbit_forces",
               "_iteration_matrix", "lu_factor"}  # fmt: skip
    assert not here & helpers, here
    assert not here & {"radau_flat", "start_flat", "newton_flat", "jac_flat_here", "_factor"}, here
    assert not here & {"feval_flat", "evaluate_flat_many"}, here  # nothing of full coordinates


@pytest.mark.slow
@pytest.mark.skipif(not JIT, reason="nothing compiles under NUMBA_DISABLE_JIT")
def test_switch_warmup_compiles_its_period_map_once(tmp_path):
    # the switch model's warm-up compiles the exact-flow period map from argument values it
    # builds itself (beside the helper's system kernels); the tiny problem's own call after it
    # must find that compilation (the types every problem's call has), not compile another.
    # Without a helper the warm-up compiles from the problem's own call alone: nothing to check
    if not helper_enabled():
        pytest.skip("the hand-built arguments are compiled only beside a helper process, which "
                    "needs two usable cores and NSDYN_COMPILE_HELPER != 0")  # fmt: skip
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), NUMBA_DISABLE_JIT="0")
    env[HELPER_ENV] = "1"
    code = (
        "from nsdyn.periodic import _kswitch as kw, switch_compile\n"
        "switch_compile.warmup()\nprint(len(kw.period_map.signatures))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    assert out.stdout.split()[-1] == "1"


def test_a_run_under_disable_jit_does_not_report_a_compile_time(monkeypatch):
    # it printed "+ 0.00 s compile/load", as though a cache had been loaded
    monkeypatch.setenv("NUMBA_DISABLE_JIT", "1")
    assert "compile" not in compile_note(0.0) and "NUMBA_DISABLE_JIT" in compile_note(0.0)
    assert not helper_enabled()
    monkeypatch.setenv("NUMBA_DISABLE_JIT", "0")
    assert compile_note(1.234) == "+ 1.23 s compile/load"
