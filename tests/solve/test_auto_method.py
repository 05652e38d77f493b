"""method = "auto": the documented rule per kind of system (docs/guide/full-models-and-scale.md).

1. unilateral contact: event for the switch law, radau otherwise;
2. the switch law: radau;
3. a full-order model (sparse operators), or AUTO_LARGE_N coordinates or more with a smooth law:
   genalpha-lowrank at AUTO_DT;
4. otherwise radau. An explicit method always wins.
"""

import numpy as np
import pytest

from nsdyn.ground import Harmonic
from nsdyn.models.isolated.statespace import demo_frame
from nsdyn.models.isolated.system import Isolation, build_system
from nsdyn.solve.auto import AUTO_LARGE_N, choose_for_system, choose_method
from nsdyn.solve.transient import simulate


@pytest.mark.parametrize(
    ("n", "law", "contact", "full", "expected"),
    [
        (13, "arctan", "detect", False, "radau"),  # the default CB run
        (13, "none", "bilateral", False, "radau"),
        (13, "switch", "detect", False, "radau"),
        (13, "switch", "unilateral", False, "event"),
        (13, "arctan", "unilateral", False, "radau"),
        (AUTO_LARGE_N, "arctan", "detect", False, "genalpha-lowrank"),
        (AUTO_LARGE_N - 1, "arctan", "detect", False, "radau"),
        (435, "arctan", "detect", True, "genalpha-lowrank"),
        (435, "none", "bilateral", True, "genalpha-lowrank"),
        (435, "switch", "detect", True, "radau"),
        (435, "arctan", "unilateral", True, "radau"),
    ],
)
def test_auto_rule(n, law, contact, full, expected):
    method, reason = choose_method(n, law, contact, full_order=full)
    assert method == expected
    assert reason.startswith("auto: ") and method in reason and "\n" not in reason


def test_auto_on_the_ladder():
    # The default run (Craig-Bampton at 5 Hz, arctan law) keeps Radau; the full model of the
    # same frame goes to the sparse factor-once method (the fast path of --fidelity full).
    frame = demo_frame()
    cb = build_system(frame, Isolation(), fidelity="cb", f_max=5.0)
    full = build_system(frame, Isolation(), fidelity="full")
    assert choose_for_system(cb)[0] == "radau"
    assert choose_for_system(full)[0] == "genalpha-lowrank"
    assert choose_for_system(full.with_isolation(contact="unilateral"))[0] == "radau"


def test_simulate_reports_the_choice_and_explicit_method_wins():
    frame = demo_frame()
    full = build_system(frame, Isolation(), fidelity="full")
    g = Harmonic(1.0, 1.0)
    auto = simulate(full, g, t_end=0.05)
    assert auto.method == "genalpha-lowrank"
    s = auto.summary()
    assert s["method"] == "genalpha-lowrank" and s["method_reason"].startswith("auto: ")
    assert "(dt 0.005 s, factored once)" in s["method_reason"] and s["n_steps"] == 10
    # a step given to "auto" is the step its reason names (it said 0.005 s of a 2.5 ms run)
    r = simulate(full, g, t_end=0.05, dt=0.0025).summary()
    assert "(dt 0.0025 s, factored once)" in r["method_reason"] and r["n_steps"] == 20
    given = simulate(full, g, t_end=0.05, method="radau")
    said = f"given: 'radau' (full-order model, {full.n} dofs, dense)"  # (its dense copies)
    assert given.method == "radau" and given.summary()["method_reason"] == said
    # both integrate the same model: the isolator displacement agrees to the fixed step's
    # accuracy (second order at dt = 5 ms on a 1 Hz excitation, far below 1 %)
    assert np.isclose(auto.response.x_iso_max, given.response.x_iso_max, rtol=1e-2, atol=1e-6)


def test_solve_accepts_auto():
    # the front door of the kernel tuples: the same rule on P's size, law and contact
    from nsdyn.solve.integrate import solve
    from nsdyn.solve.methods import _tiny_problem

    P, x0 = _tiny_problem()  # two coordinates, arctan law: rule 4
    assert solve(P, x0, np.linspace(0.0, 0.02, 3), method="auto").method == "radau"


def test_cli_full_fidelity_takes_the_fast_path_and_says_why(tmp_path, capsys):
    # `nsdyn run --fidelity full` as typed: the sparse factor-once method, announced in one
    # line on the console and stored in the summary; the default run keeps Radau
    import json

    from nsdyn.cli import main

    args = ["run", "--t-end", "0.2", "--no-figures", "--out", str(tmp_path)]
    assert main([*args, "--fidelity", "full"]) == 0
    err = capsys.readouterr().err
    line = [ln for ln in err.splitlines() if ln.startswith("method  auto:")]
    assert len(line) == 1 and "genalpha-lowrank" in line[0]
    assert main([*args, "--json"]) == 0
    s = json.loads(capsys.readouterr().out)
    assert s["method"] == "radau" and s["method_reason"].startswith("auto: ")
