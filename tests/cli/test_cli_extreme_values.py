"""Numbers that are valid TOML but past what a model can run: refused in one line naming the
file and the field (status 2) before any run, where a run failed on a numerical error that
blamed something else (the record, the matrices) or ended in a traceback."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from nsdyn.cli import main
from nsdyn.models.isolated.defaults import EPS_MAX
from nsdyn.models.isolated.tolerances import RUN_RTOL

SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"


def _refused(tmp_path, capsys, scene: Path, needle: str, *extra: str) -> str:
    rc = main(["run", str(scene), "--t-end", "0.2", "--no-figures", "--out",
               str(tmp_path / "o"), *extra])  # fmt: skip
    err = capsys.readouterr().err.strip()
    assert rc == 2 and len(err.splitlines()) == 1, err
    assert re.search(needle, err), err
    assert not (tmp_path / "o").exists()  # (refused before the run: nothing written)
    return err


def _edit(tmp_path, name: str, old: str, new: str) -> Path:
    text = (SCENES / name).read_text()
    assert old in text
    p = tmp_path / "s.toml"
    p.write_text(text.replace(old, new, 1))
    return p


def test_the_sharpest_arctan_law_is_one_a_step_can_cross():
    # the turn |v| ~ 1/eps at least ten times what gravity adds to a velocity in the solvers'
    # smallest step (MIN_STEP = 1e-12 s): EPS_MAX ~ 1 / (10 g MIN_STEP), within a factor 2
    from nsdyn.solve._kcommon import MIN_STEP

    assert 0.5 < EPS_MAX * 10 * 9.81 * MIN_STEP < 2.0


@pytest.mark.parametrize(
    ("name", "old", "new", "field"),
    [
        # a frame scene's [isolation] (the shear building at 1e300: a NaN blamed on the record)
        ("isolated-shear-3storey.toml", "eps = 500.0", "eps = 1e300", "isolation.eps"),
        ("isolated-shear-3storey.toml", "eps = 500.0", f"eps = {2 * EPS_MAX:g}",
         "isolation.eps"),
        # a deck's and a 3D building's [solver] with the arctan law (a traceback)
        ("deck-tfp4-3c.toml", "[solver]", "[solver]\neps = 1e300", "solver.eps"),
        ("building3d-office-rigid.toml", 'law = "switch"', 'law = "arctan"\neps = 1e300',
         "solver.eps"),
    ],
)  # fmt: skip
def test_an_arctan_law_too_sharp_for_any_step_is_refused(tmp_path, capsys, name, old, new,
                                                         field):  # fmt: skip
    bound = re.escape(f"{EPS_MAX:g}")
    _refused(tmp_path, capsys, _edit(tmp_path, name, old, new),
             rf"^nsdyn run: error: .*s\.toml: {re.escape(field)}: expected an arctan sharpness "
             rf"of at most {bound} s/m .* the sharp limit is the switch law")  # fmt: skip


def test_an_arctan_law_too_sharp_is_refused_in_python():
    import nsdyn
    from nsdyn.models.isolated.deck import law_params

    with pytest.raises(ValueError, match=r"^isolation.eps: expected an arctan sharpness"):
        nsdyn.Isolation(eps=1e300)
    with pytest.raises(ValueError, match=r"^eps: expected an arctan sharpness"):
        law_params("arctan", eps=math.nextafter(EPS_MAX, math.inf))
    with pytest.raises(ValueError, match=r"got 2e\+10; the sharp limit"):
        nsdyn.Isolation(eps=np.float32(2e10))  # (a NumPy number too)
    nsdyn.Isolation(eps=EPS_MAX)  # (the bound itself is taken)
    law_params("arctan", eps=EPS_MAX)


@pytest.mark.parametrize("key", ["H", "r"])
def test_a_cylinder_whose_inertia_overflows_is_refused(tmp_path, capsys, key):
    # H = 1e300: I_t = m (3 r^2 + 4 H^2) / 12 overflows (a traceback before)
    text = (SCENES / "cylinder-uplift.toml").read_text()
    p = tmp_path / "s.toml"
    p.write_text(re.sub(rf"(?m)^{key} = .*$", f"{key} = 1e300", text, count=1))
    _refused(tmp_path, capsys, p, r"s\.toml: \[cylinder\] r, H, m, k: expected sizes whose "
             r"inertias and moments are finite .* got r = .*, H = .*")  # fmt: skip


def test_an_isolator_spring_that_spoils_the_normal_forces_is_refused(tmp_path, capsys,
                                                                     monkeypatch):  # fmt: skip
    # the default frame's first second: its minimum normal force (a constraint force) at the
    # stiffest spring taken, STIFF_BEARING_RATIO x the structure's stiffest entry, is that
    # of a moderately stiff one (the base held: 1e10 N/m) to 1e-4; unchecked, 1e18 N/m
    # returned 40 % of it with exit 0, and is refused naming the field
    from nsdyn.models.isolated import bearings
    from nsdyn.models.isolated.scene import build_scene_run, load_scene
    from nsdyn.solve.transient import simulate

    system, motion, _ = build_scene_run(load_scene())
    stiff = np.abs(np.diagonal(system.with_isolation(k_lam=0.0).K)).max()

    def n_min(k_lam):
        r = simulate(system.with_isolation(k_lam=k_lam), motion, t_end=1.0, dt_out=0.01)
        return r.summary()["min_normal_force_N"]

    held = n_min(1.0e10)
    assert n_min(bearings.STIFF_BEARING_RATIO * stiff) == pytest.approx(held, rel=1e-4)
    with pytest.raises(ValueError, match=r"^isolation.k_lam: expected an isolator spring of "):
        system.with_isolation(k_lam=1.0e18)
    monkeypatch.setattr(bearings, "STIFF_BEARING_RATIO", math.inf)
    assert n_min(1.0e18) < 0.9 * held  # (what the refusal spares)
    monkeypatch.undo()
    p = tmp_path / "s.toml"
    p.write_text("[isolation]\nk_lam = 1e18\n")
    said = (r"s\.toml: isolation\.k_lam: expected an isolator spring of at most 1e\+06x the "
            r"structure's stiffest entry \(2\.68e\+10 N/m\), got 1e\+18 N/m")  # fmt: skip
    _refused(tmp_path, capsys, p, said)


def test_a_stiff_spring_under_a_given_normal_force_is_taken():
    # a shear building's normal force is given (no contact rows): its peaks at 1e20 N/m are
    # those of 1e12 N/m (both the base held) to the run's tolerance, so no refusal there
    from nsdyn.models.isolated.scene import build_scene_run, load_scene
    from nsdyn.solve.transient import simulate

    system, motion, _ = build_scene_run(load_scene(SCENES / "isolated-shear-3storey.toml"))
    acc = [simulate(system.with_isolation(k_lam=k), motion, t_end=1.0,
                    dt_out=0.01).summary()["floor_acc_max_mps2"] for k in (1e12, 1e20)]  # fmt: skip
    assert acc[1] == pytest.approx(acc[0], rel=RUN_RTOL)


@pytest.mark.parametrize(
    ("old", "new", "field"),
    [
        # 1.1e151 steps blamed on motion.t_end (--t-end), which the scene had right
        ("stiffness = 1.0e7", "stiffness = 1e300", "ground.stiffness"),
        # an inf step refused as "solver.h: expected 0 < h < inf s", a key not given
        ("damping_ratio = 0.0", "damping_ratio = 1e300", "ground.damping_ratio"),
    ],
)
def test_a_compliant_ground_too_stiff_or_damped_names_its_key(tmp_path, capsys, old, new,
                                                               field):  # fmt: skip
    p = _edit(tmp_path, "contact-compliant-C2.toml", old, new)
    rc = main(["run", str(p), "--no-figures", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and len(err.splitlines()) == 1, err
    said = (rf"s\.toml: {field}: the ground's stiffness and damping bound the explicit step "
            r"to .* steps over 9\.75 s, more than 2e\+08")  # (not the warm-up's)  # fmt: skip
    assert re.search(said, err), err


@pytest.mark.parametrize("zeta", [0.0, 0.1, 1.0, 10.0, 1e3])
def test_the_compliant_grounds_step_is_the_damped_oscillators_limit(zeta):
    # 2 (sqrt(1 + z^2) - z) / w with w^2 the trace bound sum_j (k + k_t)(1/m + |r_j|^2 / J)
    # and z = c w / (2 k), evaluated as 2 / (sqrt(1 + z^2) + z) / w: the same number (to the
    # closed form's own cancellation, z^2 x 1e-16), and 1 / (z w) at z = 1e300, where the
    # closed form gave an inf step
    from nsdyn.models.contact.body import RigidBody
    from nsdyn.models.contact.compliant import CompliantGround, stable_step

    body = RigidBody.rectangle(1.1, 3.3, 7500.0)
    for z_given in (zeta, 1e300):
        ground = CompliantGround.from_ratio(body, 1.0e7, z_given)
        r2 = np.sum(body.contacts**2, axis=1)
        w = math.sqrt(np.sum((ground.k + ground.kt) * (1.0 / body.mass + r2 / body.J)))
        z = ground.c * w / (2.0 * ground.k)
        h, z_said = stable_step(body, ground)
        assert z_said == pytest.approx(z, rel=1e-14)
        want = 2.0 * (math.sqrt(1.0 + z * z) - z) / w if z < 1e6 else 1.0 / (z * w)
        assert h == pytest.approx(want, rel=max(1e-14, 4 * z * z * 2.2e-16))


def test_a_contact_sine_too_fast_for_the_body_is_refused(tmp_path, capsys):
    # a 1e-6 s period stepped for 25 s and failed on its step budget at 0.025 s; refused as
    # a rocking pulse is, past 1000 times the body's fastest rocking frequency about a base
    # corner, p = sqrt(m g R / (J + m R^2)), sqrt(3 g / (4 R)) for A5's 1.1 m x 1.0 m prism
    p = _edit(tmp_path, "contact-seed002-A5.toml", "period = ", "period = 1e-6\n#")
    err = _refused(tmp_path, capsys, p, r"s\.toml: motion\.period: 1e-06 s is 2e\+06 times "
                   r"faster than the body's rocking frequency p = 3\.146 /s; expected at most "
                   r"1000 p")  # fmt: skip
    assert math.sqrt(3 * 9.81 / (4 * math.hypot(0.55, 0.5))) == pytest.approx(3.146, abs=5e-4)
    assert "(its steps follow the sine)" in err


def test_a_study_refuses_these_values_before_its_tasks_run(tmp_path, capsys):
    # a task's spring past the structure, or its ground too stiff to step, was a failed row
    # (exit 3, "rerun with --retry-failed") where nsdyn run refuses it (exit 2)
    frame = tmp_path / "frame.toml"
    frame.write_text('[study]\nname = "k"\n[base.motion]\npga = 3.0\nt_end = 0.5\n'
                     '[parameters]\n"isolation.k_lam" = [5.0e4, 1e18]\n')  # fmt: skip
    contact = tmp_path / "contact.toml"
    contact.write_text(f'[study]\nname = "g"\nscene = "{SCENES / "contact-compliant-C2.toml"}"\n'
                       '[parameters]\n"ground.stiffness" = [1.0e7, 1e300]\n')  # fmt: skip
    for study, field in ((frame, "isolation.k_lam"), (contact, "ground.stiffness")):
        rc = main(["study", str(study), "--out", str(tmp_path / study.stem)])
        err = capsys.readouterr().err.strip()
        assert rc == 2 and len(err.splitlines()) == 1, err
        assert re.search(rf"{study.name}: task 1 \(.*\): {re.escape(field)}: ", err), err
        assert not (tmp_path / study.stem / "results.csv").exists()


def test_each_refusal_names_the_key_that_makes_it(tmp_path, capsys):
    # a stick spring far stiffer than the ground's (its damping ratio of 5 % was blamed); a
    # [star] case that overflows the inertia ("[cylinder] and [foundation]" were blamed)
    p = _edit(tmp_path, "contact-compliant-C2.toml", "damping_ratio = 0.0",
              "damping_ratio = 0.05\nstick_stiffness = 1e20")  # fmt: skip
    _refused(tmp_path, capsys, p, r"s\.toml: ground\.stick_stiffness: the ground's stiffness")
    p = _edit(tmp_path, "cylinder-uplift.toml", "[cylinder]", '[star]\ncase = "H*1e300"\n\n'
              "[cylinder]")  # fmt: skip
    _refused(tmp_path, capsys, p, r"s\.toml: star\.case: 'H\*1e300' gives r, H, m, k: ")


def test_a_structure_given_by_matrices_is_not_told_to_use_a_frames_model():
    # the fixed-base hint (--fixed-base, fidelity 'fixed') is refused for a [structure] scene
    from nsdyn.models.isolated.builders import system_from_matrices
    from nsdyn.models.isolated.system import Isolation

    M, K = np.diag([1.0e4, 1.0e4]), np.array([[2.0e7, 0.0], [0.0, 2.0e7]])
    args = dict(iso_dofs=[0], influence=np.array([[1.0, 1.0], [0.0, 1.0]]),
                contact_rows=np.array([[0.0, 1.0]]))  # fmt: skip
    system_from_matrices(M, np.zeros((2, 2)), K, isolation=Isolation(k_lam=2.0e13), **args)
    with pytest.raises(ValueError, match=r"isolation.k_lam: .* a base held fixed is the "
                       r"structure's matrices without the isolators$"):  # fmt: skip
        system_from_matrices(M, np.zeros((2, 2)), K, isolation=Isolation(k_lam=2.0e14), **args)


def test_a_stabilisation_that_makes_its_own_lift_offs_is_said(tmp_path, capsys):
    # the bundled uplift pocket over 16 periods: 47-54 lift-offs from alpha = 2 pi to 1e4,
    # 886 at 1e5 (alpha^2 R q equals gravity at a gap of 1e-9 m, below the drift the
    # contacts keep after landings), with exit 0 and no word; said past ALPHA_PLAUSIBLE
    # where contacts lift off (elsewhere the stabilisation acts on a drift alone)
    import json
    import warnings

    import nsdyn
    from nsdyn.models.isolated.bearings import ALPHA_PLAUSIBLE

    with pytest.warns(nsdyn.NotedWarning, match=r"^isolation.alpha = 100000 1/s: the "
                      r"contacts' stabilisation alpha\^2 R q equals gravity at a gap of "
                      r"g/alpha\^2 = 9\.8e-10 m"):  # fmt: skip
        lifting = nsdyn.Isolation(alpha=1e5, contact="unilateral")
    with warnings.catch_warnings():
        warnings.simplefilter("error", nsdyn.InputWarning)
        nsdyn.Isolation(alpha=ALPHA_PLAUSIBLE, contact="unilateral").changed(c=1.0)
        nsdyn.Isolation(alpha=1e5)  # (contact "detect": no lift-off for it to make)
        lifting.changed(c=1.0)  # (said once)
    counts = {}
    for alpha in (ALPHA_PLAUSIBLE, 10 * ALPHA_PLAUSIBLE):
        p = _edit(tmp_path, "isolated-uplift-pocket.toml", "[isolation]",
                  f"[isolation]\nalpha = {alpha}")  # fmt: skip
        p.write_text(re.sub(r"(?m)^n_periods = .*$", "n_periods = 16", p.read_text()))
        out = tmp_path / f"o{alpha:g}"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", nsdyn.InputWarning)
            assert main(["run", str(p), "--json", "--no-figures", "--out", str(out)]) == 0
        counts[alpha] = json.loads(capsys.readouterr().out)["lift_offs"]
    assert counts[10 * ALPHA_PLAUSIBLE] > 5 * counts[ALPHA_PLAUSIBLE] > 0


def test_a_sweep_says_the_stabilisation_does_not_act_on_its_orbits():
    from nsdyn.studies.sweep import unused_scene_notes

    raw = {"isolation": {"alpha": 1e6, "beta": 1.0, "mu": 0.05}}
    (note,) = unused_scene_notes(raw, True)
    assert note.startswith("isolation.alpha and isolation.beta: no effect on a sweep, whose ")
    # lift-off orbits (--contact unilateral) feel it: the lift-off note, whatever the scene's
    # own contact (the sweep's flag decides; its Isolation's own note is not said)
    (lifts,) = unused_scene_notes(raw, True, "unilateral")
    assert lifts.startswith("isolation.alpha = 1e+06 1/s: the contacts' stabilisation ")
    assert unused_scene_notes({"isolation": {"alpha": 6.0}}, True, "unilateral") == []


def test_a_sweep_says_once_that_a_lifting_scene_is_swept_on_bilateral_orbits(tmp_path):
    # a scene whose contact is unilateral: a sweep without --contact unilateral says once, for
    # all amplitudes, that it shoots the bilateral orbits; with it, nothing (the lift-off
    # points are recomputed); the curve's own warning (frequency_response) is the sweep's
    # to say, not each amplitude's
    import warnings

    from nsdyn.models.isolated.scene import load_scene
    from nsdyn.studies.sweep import SweepSettings, bilateral_sweep_note, sweep_amplitudes

    cfg = load_scene(str(SCENES / "isolated-uplift-pocket.toml"))
    said = {}
    for contact in ("bilateral", "unilateral"):
        with warnings.catch_warnings(record=True) as seen:
            warnings.simplefilter("always")
            sweep_amplitudes(cfg, [0.1, 0.2], SweepSettings(5.0, 10.0, 2, contact=contact),
                             tmp_path / contact, workers=1, quiet=True)  # fmt: skip
        said[contact] = [str(w.message) for w in seen if "unilateral" in str(w.message)]
    (once,) = said["bilateral"]
    assert once.startswith("isolation.contact = 'unilateral', but a sweep shoots the bilateral")
    assert said["unilateral"] == []
    # the switch law's sweep has no lift-off pass of its own: the flag recomputes them on the
    # arctan law (nsdyn sweep refuses --contact unilateral with --friction switch)
    switch = bilateral_sweep_note(cfg, SweepSettings(friction="switch"))
    assert "(nsdyn sweep --friction arctan --contact unilateral)" in switch
    assert switch.endswith("with lift-off and landing on the arctan law")


def test_a_triple_pendulums_elastic_damping_is_taken_to_where_its_peaks_hold(tmp_path, capsys):
    # the bundled TFP deck's first 1.5 s: peak |u| 0.0290 m at zeta_e = 1 (the default) and at
    # the largest taken, ZETA_E_MAX, to 2 %; past 1e5 the peaks scattered (0.0551 m at 1e6,
    # exit 0), and such a damping ratio is refused naming bearing.zeta_e
    import json

    from nsdyn.models.isolated.tfp import ZETA_E_MAX

    peaks = []
    for zeta in (1.0, ZETA_E_MAX):
        p = _edit(tmp_path, "deck-tfp4-3c.toml", "[bearing]", f"[bearing]\nzeta_e = {zeta}")
        out = tmp_path / f"o{zeta:g}"
        assert main(["run", str(p), "--t-end", "1.5", "--json", "--no-figures", "--out",
                     str(out)]) == 0  # fmt: skip
        peaks.append(json.loads(capsys.readouterr().out)["peak_resultant_displacement_m"])
    assert peaks[1] == pytest.approx(peaks[0], rel=0.02)
    p = _edit(tmp_path, "deck-tfp4-3c.toml", "[bearing]", "[bearing]\nzeta_e = 1e6")
    _refused(tmp_path, capsys, p, r"s\.toml: bearing\.zeta_e: expected a damping ratio of the "
             r"elastic stage in \[0, 10000\]")  # fmt: skip
