"""Table export of a run on bidirectional isolators; what the result cannot keep is reported.

Sources: the export only labels arrays (exact equality, see tests/models/conftest.py); the
per-isolator slips are u_i = B_i q with B_i = [[1, 0, -Y_i], [0, 1, X_i]] (the deck's kinematics).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from nsdyn.models.isolated import _kplanerun as kr
from nsdyn.models.isolated.bearings import Bearing, Friction
from nsdyn.models.isolated.deck import rigid_deck, simulate_plane
from nsdyn.models.isolated.plane_result import PlaneIntegrationError, PlaneResult

G = 9.81
ROOT = Path(__file__).resolve().parents[3]
POS = [(-4.0, -3.0), (4.0, -3.0), (4.0, 3.0), (-4.0, 3.0)]


def _run():
    dt = 0.01
    t = np.arange(0.0, 2.0 + dt / 2, dt)
    ax = 2.0 * np.sin(2 * np.pi * 0.8 * t)
    ay = 1.0 * np.sin(2 * np.pi * 1.1 * t)
    d = rigid_deck(2.0e4, 2.0e5, POS, Bearing(Friction(0.05), radius=2.0), ecc=(0.5, 0.2), g=G)
    return simulate_plane(d, (0.0, dt, ax, ay, None), law="arctan")


def test_plane_result_round_trips_through_dataframe_and_dataset(assert_round_trip):
    r = _run()
    assert_round_trip(r)
    cols = r.histories()
    # the slip columns are the kinematics u_i = B_i q, exactly as computed (no resampling)
    X, Y = np.array(POS).T
    np.testing.assert_array_equal(cols["ux_iso_{}_m"][:, 2], r.q[:, 0] - r.q[:, 2] * Y[2])
    np.testing.assert_array_equal(cols["uy_iso_{}_m"][:, 2], r.q[:, 1] + r.q[:, 2] * X[2])


def _fake_run(status, n_events, rows=4):
    ni, nt = 1, 3
    info = np.zeros(kr.N_INFO)
    info[kr.I_NEV] = n_events
    info[kr.I_NOUT] = nt
    info[kr.I_TFAIL] = 1.25
    stops = np.zeros((ni, 3))
    stops[:, kr.P_TFIRST] = np.nan
    d = rigid_deck(1.0e3, 1.0e3, [(0.0, 0.0)], Bearing(Friction(0.05)), g=G)
    return PlaneResult.from_run(d, "switch", np.arange(nt, dtype=float), np.zeros((nt, 6)),
                                np.full((nt, ni), 1e4), np.zeros((nt, ni, 2)),
                                np.zeros((nt, ni, 2)), np.zeros((nt, ni, 2)),
                                np.ones((nt, ni), dtype=np.int64), np.zeros((rows, 6)), stops,
                                info, status, 7500.0, 1e-5)  # fmt: skip


def test_an_overfull_event_table_is_reported_not_cut_silently():
    with pytest.warns(UserWarning, match=r"10 stick-slip events: the event table keeps the first"):
        r = _fake_run(kr.ST_OK, 10)
    assert r.events.shape[0] == 4 and r.summary()["n_events"] == 10


FAILURES = [kr.ST_UNDERFLOW, kr.ST_MAX_STEPS, kr.ST_NONFINITE, kr.ST_SINGULAR, kr.ST_CHATTER,
            kr.ST_EVENTS, kr.ST_NEWTON]  # fmt: skip


@pytest.mark.parametrize("status", FAILURES)
def test_every_failure_status_raises_with_its_time(status):
    with pytest.raises(PlaneIntegrationError, match=r"t = 1\.25 s"):
        _fake_run(status, 0)


def test_nsdyn_run_reports_a_failed_deck_run_in_one_line(tmp_path, monkeypatch, capsys):
    # a numerical failure of the deck's integrator reaches the command line as its one-line
    # reason with the time, and the numerics exit status (no traceback)
    from nsdyn.cli.app import main
    from nsdyn.cli.args import EXIT_NUMERICS
    from nsdyn.models.isolated import deck_scene

    def failing(*a, **k):
        raise PlaneIntegrationError("step size underflow at t = 3.5 s")

    scene = ROOT / "examples" / "scenes" / "sdof-bidirectional-circular.toml"
    monkeypatch.setattr(deck_scene, "simulate_plane", failing)
    rc = main(["run", str(scene), "--no-figures", "--out", str(tmp_path)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == EXIT_NUMERICS
    assert err[-1] == "nsdyn run: numerical failure: step size underflow at t = 3.5 s"
    assert not any("Traceback" in line for line in err)


@pytest.mark.parametrize(
    ("kw", "field"),
    [({"rtol": -1.0}, "rtol"), ({"rtol": 0.0}, "rtol"), ({"atol": (1e-8,)}, "atol"),
     ({"atol": (1e-8, -1.0)}, "atol"), ({"max_step": -1.0}, "max_step"),
     ({"max_steps": 0}, "max_steps"), ({"y0": [np.nan] * 6}, "y0"),
     ({"t_eval": [0.0, np.nan, 1.0]}, "t_eval"),  # (a one-point "result" of zero response)
     ({"t_eval": [0.0, 1.0, np.inf]}, "t_eval")],
)  # fmt: skip
def test_bad_run_options_are_refused_with_the_field_named(kw, field):
    # each of these ran to a misleading status (NaN state, underflow, singular) or silently
    s = rigid_deck(1.0e3, 1.0e3, [(0.0, 0.0)], Bearing(Friction(0.05)), g=G)
    end = {} if "t_eval" in kw else {"t_end": 1.0}  # (t_eval and t_end: not both)
    with pytest.raises(ValueError, match=rf"^{field}: expected"):
        simulate_plane(s, {"f": 1.0, "ax": 2.0, "ay": 2.0, "phase_y_deg": 90.0}, **end, **kw)


@pytest.mark.parametrize(
    ("orbit", "field"),
    [({"f": 1.0, "ax": "big"}, "ax"), ({"f": "1 Hz"}, "f"), ({"f": 1.0, "phase_y_deg": "x"},
     "phase_y_deg"), ({"f": 1.0, "ax": 1.0, "f_z": 0.0}, "f_z: expected a frequency > 0")],
)  # fmt: skip
def test_bad_orbits_are_refused_with_the_field_named(orbit, field):
    s = rigid_deck(1.0e3, 1.0e3, [(0.0, 0.0)], Bearing(Friction(0.05)), g=G)
    with pytest.raises(ValueError, match=rf"^harmonic orbit: {field}"):
        simulate_plane(s, orbit, t_end=1.0)


def test_tfp_element_slips_are_exported_and_close_the_series(assert_round_trip):
    # A deck on two flat sliders and two triple pendulums: the element slips are columns
    # s1x_iso_{i}_m … s4y_iso_{i}_m, NaN for the flat sliders; for a TFP the series closes,
    # u - Σ_k s_k = φ/κ_e with φ = F/N its force per unit normal force (nsdyn.models.
    # isolated.tfp: with its elastic stage undamped, zeta_e = 0, the yield spring carries the
    # bearing's whole force; a dashpot would add c_e (u̇ - Σ ṡ_k)), to round-off.
    from nsdyn.models.isolated.tfp import TripleBearing

    tfp = TripleBearing(R1=2.2, R2=0.3, R3=0.3, R4=2.2, mu1=0.06, mu2=0.02, mu3=0.02,
                        mu4=0.10, d1=0.4, d2=0.06, d3=0.06, d4=0.4, zeta_e=0.0)  # fmt: skip
    flat = Bearing(Friction(0.05), k_lam=2.0e4)
    dt = 0.01
    t = np.arange(0.0, 2.0 + dt / 2, dt)
    rec = (0.0, dt, 2.0 * np.sin(2 * np.pi * 0.8 * t), np.sin(2 * np.pi * 1.1 * t), None)
    d = rigid_deck(2.0e4, 2.0e5, POS, (flat, tfp, flat, tfp), g=G)
    r = simulate_plane(d, rec, law="arctan")
    assert_round_trip(r)
    h = r.histories()
    assert np.all(np.isnan(h["s1x_iso_{}_m"][:, [0, 2]]))
    F = r.friction + r.restoring + r.other
    for i in (1, 3):
        for c, name in enumerate("xy"):
            s = sum(h[f"s{k}{name}_iso_{{}}_m"][:, i] for k in range(1, 5))
            phi = F[:, i, c] / r.N[:, i]
            np.testing.assert_allclose(r.u[:, i, c] - s, phi / tfp.k_elastic, rtol=0,
                                       atol=1e-12 * (1 + np.abs(r.u[:, i, c]).max()))  # fmt: skip
    assert np.abs(r.u[:, 1]).max() > 1e-3
