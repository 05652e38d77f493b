"""The period map's start and options, the sweep's options, a resumed curve and a curve's
columns: one clear error naming the argument, or exact identities.

A period map of the wrong state length read past the compiled kernel's array (garbage, or a
crash of the process); 0 steps "mapped" x0 onto itself; a curve of another amplitude was
resumed without a word, its orbits mixed into the new curve.
"""

import math

import numpy as np
import pytest

from nsdyn import periodic as pr
from nsdyn.models.isolated.builders import system_from_matrices
from nsdyn.models.isolated.system import Isolation
from nsdyn.periodic.switch import switch_problem


def _duffing(F=0.045):
    return pr.duffing_problem(0.02, 1.0, 0.3, F)


def _switch():
    iso = Isolation(k_lam=0.0, c=0.0, mu=0.1, law="switch")
    s = system_from_matrices([[1.0]], [[0.1]], [[(2 * math.pi) ** 2]], iso_dofs=[0],
                             influence=[1.0], isolation=iso, weight=iso.g,
                             levels=[[0]])  # fmt: skip
    return switch_problem(s, 1.0)


@pytest.mark.parametrize("make", [_duffing, _switch], ids=["sdirk", "switch"])
@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda P: pr.period_map(P, np.zeros(P.dim + 1), 0.5), r"^x0: expected \d+ finite"),
        (lambda P: pr.period_map(P, np.zeros(100), 0.5), r"^x0: expected \d+ finite numbers"),
        (lambda P: pr.period_map(P, np.full(P.dim, np.nan), 0.5), r"^x0: .* with NaN or inf"),
        (lambda P: pr.period_map(P, P.x_ref, 0.5, n_steps=0), r"^n_steps: expected a whole"),
        # 10^9 steps of one period given to the shooting ran for hours without a word (~40 us
        # a step with its sensitivities on the office's cb model; a discretisation's own
        # count, refined up to 1000 times, is not capped)
        (lambda P: pr.shoot(P, 0.5, n_steps=10**9), r"^n_steps: 1000000000 steps of one period"),
        # 3 steps do not resolve a period: shooting "converged" on an orbit far from it
        (
            lambda P: pr.shoot(P, 0.5, n_steps=3),
            r"^n_steps: expected a whole number of steps "
            r"per period >= 20",
        ),
        (lambda P: pr.warm_start(P, 0.5, np.zeros(3), None), r"^x0: expected \d+ finite"),
        (lambda P: pr.warm_start(P, 0.5, None, None, periods=-1), r"^periods: expected a who"),
        (lambda P: pr.steady_state_sweep(P, 0.5, np.zeros(3)), r"^x0: expected \d+ finite"),
        (lambda P: pr.continue_sequential(P, [0.5], x0=np.zeros(3)), r"^x0: expected \d+ fin"),
    ],
)
def test_a_period_map_is_given_the_problems_state_and_a_step_count(make, call, match):
    with pytest.raises(ValueError, match=match):
        call(make())


@pytest.mark.parametrize(
    ("kw", "err", "match"),
    [({"tol": -1.0}, ValueError, r"^tol: expected a positive finite steady-state tolerance"),
     ({"tol": math.nan}, ValueError, r"^tol: expected a positive finite"),
     ({"max_periods": 0}, ValueError, r"^max_periods: expected a whole number of periods >= 1"),
     ({"max_periods": 2.5}, ValueError, r"^max_periods: expected a whole number"),
     ({"max_time": -1.0}, ValueError, r"^max_time: expected a positive finite time"),
     ({"max_time": math.nan}, ValueError, r"^max_time: expected a positive finite time"),
     ({"disc": "sdirk2"}, TypeError, r"^disc: expected a Discretisation, got str"),
     ({"monodromy": "no"}, TypeError, r"^monodromy: expected True or False")],
)  # fmt: skip
def test_a_steady_state_sweep_names_an_option_it_cannot_run_on(kw, err, match):
    # tol = -1 ended in a math domain error; 0 periods or a negative time ran 3 periods
    with pytest.raises(err, match=match):
        pr.steady_state_sweep(_duffing(), 0.15, **kw)


@pytest.mark.parametrize("continuation", ["sequential", "arclength"])
@pytest.mark.parametrize(
    ("kw", "err", "match"),
    [({"fallback": "no"}, TypeError, r"^fallback: expected True or False, got 'no'"),
     ({"keep_orbits": "no"}, TypeError, r"^keep_orbits: expected True or False")],
)  # fmt: skip
def test_a_continuation_flag_is_a_bool(continuation, kw, err, match):
    # a text "no" was truthy: the fallback stayed on, the orbits were kept
    P = _duffing()
    with pytest.raises(err, match=match):
        if continuation == "sequential":
            pr.continue_sequential(P, [0.15, 0.16], **kw)
        else:
            pr.continue_arclength(P, 0.15, 0.16, points=3, **kw)


@pytest.mark.parametrize("w", [math.nan, 0.0, -1.0, math.inf])
def test_the_arclength_state_weight_is_positive_and_finite(w):
    # NaN or 0 ended in LAPACK's "illegal value" and an SVD that did not converge
    with pytest.raises(ValueError, match=r"^state_weight: expected a positive finite weight"):
        pr.continue_arclength(_duffing(), 0.15, 0.16, points=3, state_weight=w)


@pytest.fixture(scope="module")
def duffing_curve():
    return pr.continue_sequential(_duffing(), [0.15, 0.16])


def test_a_curve_of_another_amplitude_is_not_resumed(duffing_curve):
    other = _duffing(F=0.09)
    with pytest.raises(ValueError, match=r"^start: its last point \(f = 0.16 Hz\) is no "
                       r"periodic orbit of this problem \(residual"):  # fmt: skip
        pr.continue_sequential(other, [0.15, 0.16, 0.17], start=duffing_curve.points)
    with pytest.raises(ValueError, match=r"^start: its last point .* no periodic orbit"):
        pr.continue_arclength(other, 0.15, 0.2, points=3, start=duffing_curve.points)
    with pytest.raises(ValueError, match=r"^start: a curve of amplitude 0.045, this problem's "
                       r"is 0.09"):  # fmt: skip
        pr.continue_sequential(other, [0.15, 0.16, 0.17], start=duffing_curve)
    wider = pr.frame_problem(_two_dofs(), 0.045)  # (a state of 4)
    with pytest.raises(ValueError, match=r"^start: points of 2 states, this problem's state "
                       r"has 4: a curve of another model"):  # fmt: skip
        pr.continue_sequential(wider, [0.15, 0.2], start=duffing_curve.points)


def _two_dofs(mu=0.1):
    iso = Isolation(k_lam=0.0, c=0.0, mu=mu, law="arctan")
    K = (2 * math.pi) ** 2 * np.array([[2.0, -1.0], [-1.0, 1.0]])
    return system_from_matrices(np.eye(2), 0.01 * K, K, iso_dofs=[0], influence=[1.0, 1.0],
                                isolation=iso, weight=2 * iso.g, levels=[[0], [1]])  # fmt: skip


def test_a_curve_of_another_model_is_not_resumed():
    # friction 0.1 and 0.5 at an amplitude that sticks both all period: the last orbit checks
    # out on either, and the first model's curve came back as the second's, every point its
    # own (a curve keeps its problem's digest: the matrices, law, amplitude and load)
    a, b = pr.frame_problem(_two_dofs(0.1), 0.05), pr.frame_problem(_two_dofs(0.5), 0.05)
    assert pr.curve.problem_id(a) == pr.curve.problem_id(pr.frame_problem(_two_dofs(0.1), 0.05))
    grid = pr.log_frequencies(0.5, 0.7, 3)
    c = pr.continue_sequential(a, grid[:2])  # (a curve interrupted after two points)
    assert c.info["problem"] == pr.curve.problem_id(a) != pr.curve.problem_id(b)
    with pytest.raises(ValueError, match=r"^start: a curve of another model or settings"):
        pr.continue_range(b, fmin=0.5, fmax=0.7, points=3, start=c)
    d = pr.continue_range(a, fmin=0.5, fmax=0.7, points=3, start=c)  # (its own: resumed)
    assert d.points[:2] == c.points and d.info["problem"] == c.info["problem"]


def test_a_curve_resumes_on_its_own_problem_and_band(duffing_curve):
    P = _duffing()
    with pytest.raises(ValueError, match=r"^start: its points reach 0.16 Hz, past the band "
                       r"asked for \(0.1 to 0.12 Hz\)"):  # fmt: skip
        pr.continue_sequential(P, [0.1, 0.12], start=duffing_curve.points)
    # a start above the band's start left the band below it out, without a word
    with pytest.raises(ValueError, match=r"^start: its points begin at 0.15 Hz, above the "
                       r"band's start \(0.1 Hz\), which it would leave out"):  # fmt: skip
        pr.continue_sequential(P, [0.1, 0.15, 0.16, 0.17], start=duffing_curve)
    # its points alone resume as a checkpoint's do (a curve whose first frequencies found no
    # orbit without the fallback starts above the band's start)
    c = pr.continue_sequential(P, [0.1, 0.15, 0.16, 0.17], start=duffing_curve.points)
    assert c.column("f").tolist() == [0.15, 0.16, 0.17]
    for start in (duffing_curve, duffing_curve.points):  # the curve, or its points
        c = pr.continue_sequential(P, [0.15, 0.16, 0.17], start=start)
        assert c.points[:2] == duffing_curve.points and c.column("f").tolist() == [0.15, 0.16, 0.17]


def test_a_curves_columns_summary_and_table_are_its_rows(duffing_curve):
    pd = pytest.importorskip("pandas")
    c = duffing_curve
    rows = c.rows()
    # the rows' names are columns too ("IDR" was an AttributeError; "idr" the quantity)
    np.testing.assert_array_equal(c.column("residual"), [r["residual"] for r in rows])
    np.testing.assert_array_equal(c.column("newton_iterations"), [p.iterations for p in c.points])
    with pytest.raises(ValueError, match=r"^name: expected a column of the curve, one of .*"
                       r"got 'amps'; did you mean 'amp'\?"):  # fmt: skip
        c.column("amps")
    s = c.summary()
    amp = c.column("amp")
    assert (s["amplitude"], s["points"], s["f_min_hz"], s["f_max_hz"]) == (0.045, 2, 0.15, 0.16)
    assert s["converged"] == sum(p.converged for p in c.points)
    assert s["idr_max"] is None  # (a Duffing oscillator has no drift)
    df = c.to_dataframe()
    assert list(df.index) == [0.15, 0.16] and df.index.name == "f"
    expected = pd.DataFrame(rows).set_index("f")
    pd.testing.assert_frame_equal(df, expected)
    assert df.attrs["points"] == 2 and amp.size == 2
    # the same table as an xarray Dataset over f, as every time-history result has one
    pytest.importorskip("xarray")
    ds = c.to_xarray()
    assert list(ds.coords) == ["f"] and list(ds["f"].values) == [0.15, 0.16]
    for name in df.columns:
        np.testing.assert_array_equal(ds[name].values, df[name].to_numpy())
    assert ds.attrs["points"] == 2 and "idr_max" not in ds.attrs  # (None: no netCDF attribute)


@pytest.mark.parametrize(
    ("amplitude", "freqs", "match"),
    [(-1.0, [0.5], r"^amplitude: expected a finite forcing amplitude >= 0"),
     (math.nan, [0.5], r"^amplitude: expected a finite forcing amplitude"),
     ("1", [0.5], r"^amplitude: expected a finite forcing amplitude"),
     ([1.0, -2.0], [0.5], r"^amplitude: expected a finite forcing amplitude .* got -2.0"),
     (1.0, [-0.5, 0.5], r"^freqs\[0\]: expected a forcing frequency in"),
     (1.0, [], r"^freqs: expected a 1-D sequence of forcing frequencies"),
     (1.0, 0.5, r"^freqs: expected a 1-D sequence of forcing frequencies"),
     (1.0, [[0.5, 1.0]], r"^freqs: expected a 1-D sequence"),
     (1.0, [0.5, math.nan], r"^freqs: expected a 1-D sequence")],
)  # fmt: skip
def test_a_fixed_base_response_is_asked_for_amplitudes_and_frequencies(frame, amplitude,
                                                                       freqs, match):  # fmt: skip
    # a negative amplitude gave negative drifts, -0.5 Hz the values of +0.5 Hz, an empty or
    # scalar freqs a reshape or index error
    with pytest.raises(ValueError, match=match):
        pr.fixed_base_response(frame, amplitude, freqs)


def test_the_problem_builders_and_the_uplift_search_name_a_wrong_argument():
    # each failed deep inside: "no attribute 'isolation'", "orbit.f: ... got nan", a '<' not
    # supported between str and float, "'int' object is not callable" after the first point
    from nsdyn.periodic.plane import plane_problem

    with pytest.raises(TypeError, match=r"^system: expected an IsolatedSystem"):
        switch_problem("building", 1.0)
    with pytest.raises(TypeError, match=r"^system: expected a PlaneSystem"):
        plane_problem("mass", {"f": 1.0, "ax": 1.0})
    from nsdyn.models.isolated.bearings import Bearing, Friction
    from nsdyn.models.isolated.deck import sdof_plane

    deck = sdof_plane(1.0e5, Bearing(Friction(0.05), radius=2.0))
    with pytest.raises(TypeError, match=r"^orbit: expected a HarmonicPlane or a dict"):
        plane_problem(deck, "circular")
    s = _two_dofs()
    with pytest.raises(ValueError, match=r"^a_lo: expected a positive finite amplitude"):
        pr.uplift_boundary(s, [0.5], a_lo="1")
    with pytest.raises(ValueError, match=r"^a_hi: expected a finite amplitude above a_lo"):
        pr.uplift_boundary(s, [0.5], a_lo=2.0, a_hi=1.0)
    with pytest.raises(TypeError, match=r"^progress: expected a callable"):
        pr.uplift_boundary(s, [0.5], progress=5)
    with pytest.raises(ValueError, match=r"^a_hi: .* and at most 1000 m/s² \(100 g\)"):
        pr.uplift_boundary(s, [0.5], a_hi=2000.0)  # (as nsdyn uplift --a-max)
    with pytest.raises(ValueError, match=r"^monodromy: expected a square matrix of finite "
                       r"numbers, got shape \(2, 3\)"):  # fmt: skip
        pr.floquet_multipliers(np.zeros((2, 3)))


def test_a_curves_maxima_are_over_the_steady_states_its_model_holds():
    # a bilateral point past uplift (18.5 m) and a failed sweep point (the switch sweep left
    # 155 m there) were the summary's maxima, against the sweep table's rule; a unilateral
    # orbit that lifts off is a steady state of its model and counts
    from nsdyn.periodic.curve import Curve, OrbitPoint

    def point(f, x, method="shooting", converged=True, uplift=False):
        return OrbitPoint(f=f, x0=np.zeros(2), method=method, converged=converged,
                          iterations=1, residual=0.0, multipliers=np.zeros(0), n_steps=200,
                          quantities={"x_iso": x, "idr": x / 100, "uplift": uplift})  # fmt: skip

    pts = [point(0.03, 18.5, uplift=True), point(0.05, 1.0), point(0.06, 155.0, "sweep", False),
           point(0.07, 2.0, "unilateral", uplift=True), point(0.08, 0.5, "sweep")]  # fmt: skip
    s = Curve(amplitude=2.0, points=pts).summary()
    assert (s["x_iso_max_m"], s["x_iso_max_f_hz"], s["idr_max"]) == (2.0, 0.07, 0.02)
    assert s["converged"] == 4 and s["sweep_points"] == 1
    frame = Curve(amplitude=2.0, points=pts)  # the failed point's numbers: none, as its row's
    assert math.isnan(frame.column("x_iso")[2]) and math.isnan(frame.column("IDR")[2])
    # a deck's curve: the peak of its resultant slip (its frame maxima were all None)
    for q in pts:
        q.quantities = {"u_peak_m": q.quantities["x_iso"], "uplift": q.quantities["uplift"],
                        "rim_contact": q.f == 0.06}  # fmt: skip
    deck = Curve(amplitude=2.0, points=pts)
    assert deck.rows()[2]["rim_contact"] is True  # (what ended the failed transient: kept)
    s = deck.summary()
    assert (s["u_peak_max_m"], s["u_peak_max_f_hz"]) == (2.0, 0.07) and "x_iso_max_m" not in s
    assert list(deck.rows()[0])[:3] == ["f", "A", "u_peak_m"]  # the deck sweep's columns
    pytest.importorskip("pandas", reason="the frames extra (pandas)")
    df = deck.to_dataframe()  # (it took a frame's columns: IDR, a, x_iso all NaN)
    assert list(df.columns) == list(deck.rows()[0])[1:] and "IDR" not in df.columns
    np.testing.assert_array_equal(df["u_peak_m"], [r["u_peak_m"] for r in deck.rows()])
    assert math.isnan(deck.rows()[2]["u_peak_m"])  # the failed point: no steady state, no peak
    with pytest.raises(ValueError, match=r"^name: expected a column of the curve"):
        deck.column("x_iso")  # (a frame's column: all NaN before)


def test_the_switch_shooting_takes_a_switch_problem():
    # an arctan problem ran its shooting, then stopped at "'PeriodMap' has no attribute 'events'"
    with pytest.raises(TypeError, match=r"^problem: expected a switch_problem\(system, ampl"):
        pr.shoot_switch(_duffing(), 0.15)


def test_a_unilateral_system_is_told_its_curve_is_the_bilateral_one():
    # its contact was dropped without a word: uplift points stood for lift-off orbits
    import nsdyn
    from nsdyn._checks import InputWarning

    iso = Isolation(k_lam=1e4, c=100.0, mu=0.05, contact="unilateral")
    s = nsdyn.shear_building([1e3], [], 0.0, isolation=iso)
    with pytest.warns(InputWarning, match=r"^system: its isolators' contact is unilateral, but"):
        nsdyn.frequency_response(s, 0.5, fmin=0.3, fmax=1.0, points=2)
