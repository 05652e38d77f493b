"""What ``simulate`` does with inputs that used to run silently wrong or fail deep inside.

Sources: the single-mass isolator (m, k_lam, mu) whose exact free vibration without friction is
x(t) = x0 cos(w t), w = sqrt(k/m); the switch law as the arctan law's limit eps -> inf (seed 004
eq. 7); energy conservation of an undamped oscillator; the static equilibrium (the weight on
the contacts, compressive positive); seed 004's office frame, first fixed-base mode 0.46 Hz.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import nsdyn
from nsdyn.models.isolated.builders import MatrixError

M_, K_, MU = 1000.0, 4e4, 0.05


def _mass(**iso):
    return nsdyn.shear_building([M_], [], 0.0, isolation=nsdyn.Isolation(k_lam=K_, c=0.0, **iso))


def test_event_refuses_a_law_without_friction_and_says_it_replaces_the_arctan_law():
    with pytest.raises(ValueError, match=r"^method 'event' integrates the switch friction law"):
        nsdyn.simulate(_mass(mu=MU, law="none"), None, method="event", t_end=1.0, dt_out=0.01,
                       x0=[0.1, 0.0])  # fmt: skip
    s = _mass(mu=MU, law="arctan", eps=50.0)
    # an InputWarning, as every input nsdyn says it does not take as given (a filter on
    # nsdyn's warnings missed a bare UserWarning)
    with pytest.warns(nsdyn.InputWarning, match=r"not this system's arctan law \(eps = 50 s/m\)"):
        r = nsdyn.simulate(s, None, method="event", t_end=1.0, dt_out=0.01, x0=[0.1, 0.0])
    assert r.summary()["law"] == "switch" and r.summary()["method_reason"] == "given: 'event'"
    assert nsdyn.simulate(s, None, t_end=1.0, dt_out=0.01, x0=[0.1, 0.0]).summary()["law"] == (
        "arctan"
    )
    # law "none" on an adaptive method: the exact undamped free vibration
    r = nsdyn.simulate(_mass(mu=MU, law="none"), None, t_end=3.0, dt_out=1e-3, x0=[0.1, 0.0],
                       rtol=1e-8, atol=1e-12)  # fmt: skip
    exact = 0.1 * np.cos(math.sqrt(K_ / M_) * r.t)
    assert np.max(np.abs(r.x[:, 0] - exact)) < 1e-6  # rtol 1e-8 over 3 s (~3 periods)


def test_a_run_that_returns_on_failure_ends_where_it_failed():
    # max_steps spent in the first chunk: the run stops there (no later chunk started from
    # the failed state, which gave time gaps), and the summary says so
    dt = 0.01
    t = np.arange(0.0, 15.0 + dt / 2, dt)
    gm = nsdyn.GroundMotion(0.0, dt, np.where((t > 5) & (t < 10), 3 * np.sin(10 * np.pi * t), 0))
    r = nsdyn.simulate(_mass(mu=MU, law="switch"), gm, max_steps=60, on_failure="return")
    assert r.t[-1] < 5.0 and np.allclose(np.diff(r.t), dt)
    s = r.summary()
    assert s["success"] is False and s["failure"] and s["t_end_s"] == r.t[-1]
    ok = nsdyn.simulate(_mass(mu=MU, law="switch"), gm).summary()
    assert ok["success"] is True and "failure" not in ok


@pytest.mark.parametrize("eps", [1e8, 1e9])
def test_a_sharp_arctan_law_reaches_the_switch_law_under_the_default_tolerance(eps):
    # the velocity tolerance is held below the law's turn (0.1/eps): at eps 3e8-1e9 the
    # default run read the slip 16 % low or stopped at 5e-5 m
    H = nsdyn.Harmonic(1.0, 1.0)
    ref = nsdyn.simulate(_mass(mu=MU, law="switch"), H, method="event", t_end=3.0, dt_out=0.01)
    r = nsdyn.simulate(_mass(mu=MU, law="arctan", eps=eps), H, t_end=3.0, dt_out=0.01)
    x_ref = ref.summary()["x_iso_max_m"]
    assert r.summary()["x_iso_max_m"] == pytest.approx(x_ref, rel=0.01)  # the eps -> inf limit


def test_a_first_step_can_be_given():
    r = nsdyn.simulate(_mass(mu=MU, law="switch"), nsdyn.Harmonic(1.0, 1.0), t_end=1.0,
                       method="radau", h0=1e-3)  # fmt: skip
    assert r.t[-1] == 1.0


def test_the_energy_closure_of_a_free_vibration_is_scaled_by_its_energy():
    # undamped, frictionless: the stored energy (200 J) is conserved, so the closure is the
    # integrator's drift relative to it, not 1 (the scale left the initial energy out)
    r = nsdyn.simulate(_mass(mu=0.0, law="none"), None, t_end=3.0, dt_out=1e-3, x0=[0.1, 0.0])
    e = r.response.energy
    assert abs(e["stored_change"]) / (0.5 * K_ * 0.1**2) < 1e-3  # rtol 1e-4 per step
    assert e["closure"] == pytest.approx(abs(e["stored_change"]) / 200.0, rel=1e-9)


@pytest.mark.parametrize("fidelity", ["cb", "full"])
def test_a_building_left_at_rest_closes_its_balance_and_is_not_flagged(fidelity):
    # no ground motion from static equilibrium: every work term is round-off, and the balance
    # closes against the stored energies' round-off (metrics.STORED_ROUND_OFF), not its own
    # (the closure read 4.07); the floor "peaks" (1e-9 m/s²) are no motion to resolve
    frame = nsdyn.load_frame("office-11")
    system = nsdyn.build_system(frame, nsdyn.Isolation(), fidelity=fidelity)  # (cb: 5 Hz)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = nsdyn.simulate(system, nsdyn.GroundMotion(0.0, 0.01, np.zeros(200))).summary()
    assert s["energy_closure"] < 1e-2 and s["notes"] == []


def test_contact_rows_that_pull_at_rest_are_refused():
    Mm, Z = np.diag([M_, M_]), np.zeros((2, 2))
    iso = nsdyn.Isolation(k_lam=0.0, c=0.0, mu=0.1, law="switch")

    def build(sign):
        return nsdyn.system_from_matrices(Mm, Z, Z, iso_dofs=[0], influence=[[1, 0], [0, 1]],
                                          contact_rows=[[0, sign]], isolation=iso)  # fmt: skip

    lam = build(1.0).static_equilibrium()[1]
    assert lam == pytest.approx([M_ * 9.81], rel=1e-3)  # the weight, compressive positive
    with pytest.raises(MatrixError, match=r"^contact_rows: contact 0 carries no compression"):
        build(-1.0)


def test_a_vertical_component_a_model_cannot_feel_is_said():
    s = _mass(mu=MU, law="switch")
    with pytest.warns(UserWarning, match="its vertical component is not felt"):
        nsdyn.simulate(s, nsdyn.Harmonic(1.0, 1.0, A_ver=8.0, f_ver=2.0), t_end=0.5)
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        nsdyn.simulate(s, nsdyn.Harmonic(1.0, 1.0), t_end=0.5)


def test_a_fixed_base_model_without_modes_is_refused_naming_the_first():
    frame = nsdyn.load_frame("office-11")
    with pytest.raises(ValueError, match=r"^f_max: no fixed-base mode at or below 0.1 Hz \(the "
                                         r"first is 0.46\d Hz\)"):  # fmt: skip
        nsdyn.build_system(frame, nsdyn.Isolation(), fidelity="fixed", f_max=0.1)


@pytest.mark.parametrize(
    ("kw", "error", "says"),
    [({"t_end": math.inf}, ValueError, "t_end: expected a finite end time"),
     ({"t_eval": np.array([])}, ValueError, "t_eval: expected two or more increasing"),
     ({"t_eval": np.array([0.0, 0.2, 0.1])}, ValueError, "t_eval: expected two or more"),
     ({"t_end": 1.0, "progress": 5}, TypeError, "progress: expected a callable"),
     ({"t_end": 1.0, "checkpoint": "."}, ValueError, "checkpoint: expected a file's path"),
     ({"t_end": 1.0, "method": "newmark", "dt": 5.0}, ValueError,
      "dt: a fixed step of 5 s is longer than the run")],
)  # fmt: skip
def test_bad_run_arguments_are_named(kw, error, says):
    with pytest.raises(error, match=says):
        nsdyn.simulate(_mass(mu=MU, law="switch"), nsdyn.Harmonic(1.0, 1.0), **kw)


def test_a_fixed_step_over_the_records_samples_is_refused():
    # a step that passes over samples reads the record at its step ends only: the exported
    # OpenSees run at dt = 1 s peaked at x_iso 1.79 m against 0.2765 (dt = 5 ms)
    from nsdyn.solve.run_inputs import default_step

    rec = nsdyn.read_motion("synthetic-kt-20s").until(2.0)
    with pytest.raises(ValueError, match=r"^dt: a fixed step of 0.02 s is longer than the "
                                         r"record's sampling step 0.01 s"):  # fmt: skip
        nsdyn.simulate(_mass(mu=MU, law="switch"), rec, method="newmark", dt=0.02)
    # the default fixed step steps on every sample of a record finer than 5 ms
    assert default_step(rec) == 0.005 and default_step(nsdyn.Harmonic(1.0, 1.0)) == 0.005
    assert default_step(rec.resampled(0.002)) == 0.002


def test_plane_runs_name_their_bad_ground_and_kappa():
    from nsdyn.models.isolated.bearings import Bearing, Friction
    from nsdyn.models.isolated.deck import sdof_plane, simulate_plane

    s = sdof_plane(M_, Bearing(Friction(MU), radius=2.5))
    z = np.zeros(101)
    with pytest.raises(ValueError, match=r"^ground: raw arrays are \(t0, dt, ax, ay, az\)"):
        simulate_plane(s, (0.0, 0.01, z))
    with pytest.raises(ValueError, match=r"^ground.ax: expected a record of two samples or more"):
        simulate_plane(s, (0.0, 0.01, z[:0], z[:0], z[:0]))
    # an orbit's dict without its frequency named what it lacks as "got dict"
    with pytest.raises(TypeError, match=r"needs 'f' \[Hz\].* got keys \['ax', 'ay'\]$"):
        simulate_plane(s, {"ax": 1.0, "ay": 0.0}, t_end=1.0)
    for kappa in (-50.0, 0.0, math.nan):
        with pytest.raises(ValueError, match=r"^kappa: expected a positive number"):
            simulate_plane(s, (0.0, 0.01, z, z, z), kappa=kappa)


@pytest.mark.parametrize("value", ["abc", "1.0", True, float("nan"), None])
def test_a_harmonic_excitations_values_must_be_numbers_named_by_field(value):
    # "1.0" was stored as text (and failed later in a kernel); "abc" failed with float()'s
    # bare message
    from nsdyn.ground.excitation import Harmonic, HarmonicForce
    from nsdyn.ground.orbit import HarmonicPlane

    with pytest.raises(ValueError, match="^Harmonic.A_hor: expected a finite number, got"):
        Harmonic(value, 1.0)
    with pytest.raises(ValueError, match="^HarmonicForce.f: expected a finite number"):
        HarmonicForce(1.0, value, dofs=(0,))
    with pytest.raises(ValueError, match="^HarmonicPlane.ax: expected a finite number"):
        HarmonicPlane(1.0, value, 1.0)
    h = Harmonic(2, 1)  # numbers are kept as floats
    assert type(h.A_hor) is float and type(h.f_hor) is float


def test_a_harmonic_excitation_is_named_by_its_amplitude_and_frequency():
    # the run's banner and summary name it in units, not as a Python repr
    from nsdyn.ground.excitation import Harmonic, HarmonicForce
    from nsdyn.solve.transient import describe

    assert describe(Harmonic(13.5, 0.93, phase=0.5)) == (
        "ground: harmonic, 13.5 m/s² at 0.93 Hz, phase 0.5 rad"
    )
    assert describe(Harmonic(2.0, 1.0, A_ver=1.0, f_ver=2.0)) == (
        "ground: harmonic, 2 m/s² at 1 Hz; vertical 1 m/s² at 2 Hz"
    )
    assert describe(HarmonicForce(1635.0, 1.5, dofs=(0,))) == (
        "force: harmonic, 1635 N at 1.5 Hz on dofs [0]"
    )
    assert describe(HarmonicForce(1635.0, 1.5, dofs=(0, 1), weights=(2.0, 1.0), phase=0.3)) == (
        "force: harmonic, 1635 N at 1.5 Hz, phase 0.3 rad on dofs [0, 1], weights [2.0, 1.0]"
    )


def test_a_run_outside_its_record_says_so_and_the_ground_rests_there():
    # a record sampled from t = 1 s to 2 s, run from 0 s to 3 s: the ground is at rest before
    # its first sample and after its last (the run took that silently); a mass at rest with
    # the ground at rest stays exactly where it is (no force acts on it before 1 s)
    dt = 0.01
    gm = nsdyn.GroundMotion(1.0, dt, 2.0 * np.sin(2 * np.pi * np.arange(101) * dt))
    r = nsdyn.simulate(_mass(mu=MU, law="switch"), gm, t_eval=np.linspace(0.0, 3.0, 301))
    assert r.notes[:2] == [
        "the run starts at t = 0 s, before the record's first sample (1 s): the ground is at "
        "rest before it",
        "the run ends at t = 3 s, past the record's end (2 s): the ground is at rest after it, "
        "the last 1 s are free motion",
    ]
    assert np.all(r.x[r.t < 1.0] == r.x[0])
    inside = nsdyn.simulate(_mass(mu=MU, law="switch"), gm)  # (its own grid: no note)
    assert not any("record's" in n for n in inside.notes)
    # a sampled force past its samples: zero there, said as a force's
    ft = nsdyn.ForceTable(1.0, dt, np.ones(101), dofs=[0])
    r = nsdyn.simulate(_mass(mu=MU, law="switch"), ft, t_eval=np.linspace(1.0, 3.0, 201))
    assert r.notes[0].startswith("the run ends at t = 3 s, past the force table's end (2 s): the "
                                 "force is zero after it")  # fmt: skip


def test_a_run_shorter_than_its_default_output_step_names_t_end():
    # it named dt_out, which the caller never passed (the record's 0.01 s step is the default)
    system = nsdyn.build_system(nsdyn.load_frame("office-11"), nsdyn.Isolation(),
                                fidelity="rigid")  # fmt: skip
    motion = nsdyn.read_motion("synthetic-wn-40s").window(0.0, 5.0)
    with pytest.raises(ValueError, match=r"^t_end: a run of 1e-09 s is shorter than the motion"):
        nsdyn.simulate(system, motion, t_end=1e-9)
    with pytest.raises(ValueError, match=r"^dt_out: an output step of 2 s is longer than the "):
        nsdyn.simulate(system, motion, t_end=1.0, dt_out=2.0)


def test_a_misspelt_isolation_keyword_is_named_with_its_nearest_field():
    # Python's own error named the generated __init__ ("Isolation.__init__() got an
    # unexpected keyword argument 'laww'", from inside dataclasses) and no field
    with pytest.raises(TypeError, match=r"^Isolation: 'muu' is not one of its fields \(k_lam, "
                       r".*\); did you mean 'mu'\?$"):  # fmt: skip
        nsdyn.Isolation(muu=0.1)
    system = nsdyn.build_system(nsdyn.load_frame("office-11"), nsdyn.Isolation(),
                                fidelity="rigid")  # fmt: skip
    with pytest.raises(TypeError, match=r"'laww' is not one of its fields .*'law'\?$"):
        system.with_isolation(laww="switch")
    assert system.with_isolation(law="switch").isolation.law == "switch"
    # help() and inspect read its fields (the check's __new__ of *args, **kw had hidden them),
    # and a field named as the check's own argument (c, the damper) passes through replace
    import dataclasses
    import inspect

    fields = [f.name for f in dataclasses.fields(nsdyn.Isolation)]
    assert list(inspect.signature(nsdyn.Isolation).parameters) == fields
    assert dataclasses.replace(nsdyn.Isolation(), c=2.0e4).c == 2.0e4


@pytest.mark.parametrize("method", ["newmark", "genalpha"])
def test_a_fixed_step_longer_than_an_eighth_of_the_forcing_period_is_refused(method):
    # a Coulomb oscillator (m 1000 kg, k 4e4 N/m, mu 0.05) under 1635 N at 1.5 Hz: at dt = 1 s
    # (1.5 periods) the force was sampled at its zeros only, a slip of 6e-17 m against
    # 0.048 m, reported as a success; records refuse a step past their sampling step, and a
    # harmonic's period is sampled by the steps alone
    from nsdyn._checks import STEPS_PER_PERIOD

    iso = nsdyn.Isolation(k_lam=4e4, c=0.0, mu=0.05, law="arctan", eps=500.0)
    s = nsdyn.system_from_matrices([[1000.0]], [[0.0]], [[0.0]], iso_dofs=[0], influence=[1.0],
                                   weight=9810.0, isolation=iso)  # fmt: skip
    load = nsdyn.HarmonicForce(1635.0, 1.5, dofs=(0,))
    T = 1.0 / 1.5
    for dt in (1.0, T / STEPS_PER_PERIOD * 1.01):
        said = (rf"^dt: a fixed step of {dt:g} s is .* of the forcing period 0.6667 s: "
                rf"expected at most T/{STEPS_PER_PERIOD}")  # fmt: skip
        with pytest.raises(ValueError, match=said):
            nsdyn.simulate(s, load, t_end=4.0, method=method, dt=dt)
    # 8 steps a period run, said with their period error (a second-order step's (w h)^2/12,
    # the trapezoidal rule's: 5.1 % at T/8); from 20 steps a period on, nothing is said
    from nsdyn._checks import STEPS_RESOLVING, NotedWarning

    with pytest.warns(NotedWarning, match=r"is T/8 of the forcing period 0.6667 s, where a "
                      r"second-order step's period error is about \(2 pi dt/T\)\^2/12 = "
                      r"5.14%; at most T/20 = 0.03333 s resolves its peaks"):  # fmt: skip
        ok = nsdyn.simulate(s, load, t_end=4.0, method=method, dt=T / STEPS_PER_PERIOD)
    assert ok.response.x_iso.max() > 0.01  # (8 steps a period: it slides, as at dt -> 0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", NotedWarning)
        nsdyn.simulate(s, load, t_end=4.0, method=method, dt=T / STEPS_RESOLVING)
    ground = nsdyn.Harmonic(3.0, 2.0)  # (a ground acceleration's period too: 0.5 s)
    with pytest.raises(ValueError, match=r"forcing period 0.5 s"):
        nsdyn.simulate(s, ground, t_end=4.0, method=method, dt=0.1)
    # a component without amplitude has no period to resolve, and a step not given (the
    # auto method's fixed steps) is one the check takes: a twentieth of the period at most
    nsdyn.simulate(s, nsdyn.Harmonic(3.0, 2.0, A_ver=0.0, f_ver=40.0), t_end=0.5,
                   method=method, dt=0.005)  # fmt: skip
    from nsdyn._checks import FIXED_DT, default_step

    assert default_step(nsdyn.HarmonicForce(1635.0, 30.0, dofs=(0,))) == 1.0 / 600.0
    assert default_step(load) == FIXED_DT  # (1.5 Hz: the 0.005 s default is T/133)


def test_a_python_run_says_when_its_outputs_miss_the_peaks():
    # outputs 1 s apart under a 1.5 Hz force read a Coulomb oscillator's peak slip as 0.020 m
    # against 0.048 m, without a word (the command line said so); 20 outputs a period read it
    from nsdyn._checks import SAMPLES_PER_PERIOD_MIN, AccuracyWarning

    iso = nsdyn.Isolation(k_lam=4e4, c=0.0, mu=0.05, law="switch")
    s = nsdyn.system_from_matrices([[1000.0]], [[0.0]], [[0.0]], iso_dofs=[0], influence=[1.0],
                                   weight=9810.0, isolation=iso)  # fmt: skip
    load = nsdyn.HarmonicForce(1635.0, 1.5, dofs=(0,))
    with pytest.warns(AccuracyWarning, match=r"^dt_out = 1 s samples the 1.5 Hz excitation "
                      r"0.667 times per period: .* set dt_out <= 0.0333 s"):  # fmt: skip
        r = nsdyn.simulate(s, load, t_end=8.0, method="event", dt_out=1.0)
    assert r.summary()["notes"][-1].startswith("dt_out = 1 s samples")
    # a dt_out grid whose last step is short (t_end no multiple of it) is still dt_out's
    with pytest.warns(AccuracyWarning, match=r"^dt_out = 1 s samples the 1.5 Hz"):
        nsdyn.simulate(s, load, t_end=7.5, method="event", dt_out=1.0)
    # output times given: named as such (the line named a dt_out the call never gave)
    t = np.array([0.0, 0.5, 2.0, 3.0, 8.0])
    with pytest.warns(AccuracyWarning, match=r"^output times \(t_eval\) up to 5 s apart sample "
                      r"the 1.5 Hz .* set t_eval's outputs at most 0.0333 s apart$"):  # fmt: skip
        nsdyn.simulate(s, load, t_eval=t, method="event")
    for t in ([0.0, 1.0, 2.0, 3.0, 8.0], [0.0, 0.1, 8.0]):  # (even but for a longer last gap)
        with pytest.warns(AccuracyWarning, match=r"^output times \(t_eval\) up to"):
            nsdyn.simulate(s, load, t_eval=np.array(t), method="event")
    fine = 1.0 / (1.5 * SAMPLES_PER_PERIOD_MIN)
    with warnings.catch_warnings():
        warnings.simplefilter("error", AccuracyWarning)
        nsdyn.simulate(s, load, t_end=8.0, method="event", dt_out=fine)


def test_the_default_output_grid_samples_a_harmonics_fastest_component():
    # a 10 Hz vertical beside a 1 Hz horizontal: the default grid (100 a horizontal period)
    # read the vertical 10 times a period, and the run warned of its own grid
    from nsdyn._checks import AccuracyWarning
    from nsdyn.solve.transient import HARMONIC_SAMPLES

    iso = nsdyn.Isolation(k_lam=4e4, c=0.0, mu=0.05, law="switch")
    s = nsdyn.system_from_matrices([[1000.0]], [[0.0]], [[0.0]], iso_dofs=[0], influence=[1.0],
                                   weight=9810.0, isolation=iso)  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # (its vertical is not felt: said)
        warnings.simplefilter("error", AccuracyWarning)
        r = nsdyn.simulate(s, nsdyn.Harmonic(1.0, 1.0, A_ver=2.0, f_ver=10.0), t_end=1.0,
                           method="event")  # fmt: skip
    assert r.summary()["dt_out_s"] == pytest.approx(1.0 / (10.0 * HARMONIC_SAMPLES))


def test_a_run_past_its_record_says_so_to_its_caller():
    # the ground is at rest after a record's last sample: the run goes on as free motion,
    # which res.notes held alone (a deck's run warned); said in a NotedWarning as well
    a = 3.0 * np.sin(np.linspace(0.0, 20.0, 400))  # 4 s of samples every 0.01 s
    with pytest.warns(nsdyn.NotedWarning, match=r"past the record's end \(3.99 s\): .* the "
                      r"last 1.01 s are free motion"):  # fmt: skip
        r = nsdyn.simulate(_mass(mu=MU, law="arctan"), nsdyn.GroundMotion(0.0, 0.01, a),
                           t_end=5.0, dt_out=0.01)  # fmt: skip
    assert r.notes[0].startswith("the run ends at t = 5 s, past the record's end")


def test_a_start_off_the_contacts_is_refused_naming_x0():
    # a frame lifted 5 cm ran "successfully": Baumgarte pulled it down over the run while its
    # normal forces read the weight. The static equilibrium lies on R q = 0 (its KKT solve).
    s = nsdyn.build_system(nsdyn.load_frame("portal"), nsdyn.Isolation(), fidelity="rigid")
    x0, _ = s.static_equilibrium()
    lifted = x0.copy()
    lifted[: s.n] += 0.05 * np.linalg.pinv(s.R)[:, 0]  # contact 0 open by 5 cm
    with pytest.raises(
        ValueError, match=r"^x0: its contact 0 is off the constraint \(R q = 0.05 m"
    ):
        nsdyn.simulate(s, None, t_end=0.1, dt_out=0.01, x0=lifted)
    moving = x0.copy()
    moving[s.n :] += 0.2 * np.linalg.pinv(s.R)[:, 1]  # contact 1 opening at 0.2 m/s
    with pytest.raises(ValueError, match=r"^x0: its contact 1 .*\(R qd = 0.2 m/s\)"):
        nsdyn.simulate(s, None, t_end=0.1, dt_out=0.01, x0=moving)
    with pytest.raises(ValueError, match=r"^x0: expected \[q, qd\] of length 6, got 5"):
        nsdyn.simulate(s, None, t_end=0.1, dt_out=0.01, x0=x0[:5])
    sway = x0.copy()
    sway[s.n :] += 0.1 * np.linalg.svd(s.R)[2][-1]  # a velocity the contacts allow (R qd = 0)
    assert nsdyn.simulate(s, None, t_end=0.1, dt_out=0.01, x0=sway).t[-1] == pytest.approx(0.1)


def test_times_without_any_of_the_record_are_refused_and_free_motion_is_the_runs_own():
    # a run at 20-30 s on a 10 s record was excited by nothing, and its note said "the last
    # 20.01 s are free motion" of a 10 s run
    gm = nsdyn.GroundMotion(0.0, 0.01, np.sin(np.arange(1000) * 0.05))  # 0 to 9.99 s
    s = _mass(mu=MU)
    for t in (np.linspace(20.0, 30.0, 11), np.linspace(-10.0, -5.0, 11)):
        with pytest.raises(ValueError, match=r"^t_eval: the run's times .* do not overlap the "
                           r"record's samples \(0 to 9.99 s\)"):  # fmt: skip
            nsdyn.simulate(s, gm, t_eval=t)
    with pytest.warns(nsdyn.NotedWarning, match="past the record's end"):
        r = nsdyn.simulate(s, gm, t_eval=np.linspace(5.0, 15.0, 101))
    assert any("the last 5.01 s are free motion" in n for n in r.notes)  # 15 - 9.99
    # a run that starts between the record's last sample and one step after it (9.995 s):
    # free motion all along, 12 - 9.995 s (it counted from the record's end: 2.01 s)
    with pytest.warns(nsdyn.NotedWarning, match="past the record's end"):
        r = nsdyn.simulate(s, gm, t_eval=np.linspace(9.995, 12.0, 11))
    assert any("the last 2.005 s are free motion" in n for n in r.notes)


@pytest.mark.parametrize("key", ["alpha", "alpha_f"])
def test_hhts_alpha_is_answered_with_rho_inf(key):
    # TypeError "unexpected keyword argument 'alpha'" gave no hint of how HHT is tuned
    with pytest.raises(TypeError, match=rf"'{key}'; the generalized-alpha family .* takes "
                       r"rho_inf"):  # fmt: skip
        nsdyn.simulate(_mass(), nsdyn.Harmonic(1.0, 1.0), method="hht", dt=0.01, t_end=0.1,
                       **{key: 0.1})  # fmt: skip
