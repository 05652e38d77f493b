"""The Python API refuses what it cannot compute, naming the argument and the expected form,
instead of hanging, dividing by zero, failing deep inside, or returning another run's numbers.

Source of the expected behaviour: the error convention of docs/guide/troubleshooting.md (a
TypeError or ValueError naming the argument); the physics of each guard is stated at its test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import nsdyn
from nsdyn.atomic import CheckpointError


@pytest.fixture(scope="module")
def building():
    iso = nsdyn.Isolation(k_lam=2e5, c=2e4, mu=0.05, eps=500.0)
    return nsdyn.shear_building([2e4, 1e4], [2e7], 0.05, isolation=iso, heights=3.0)


@pytest.fixture(scope="module")
def record():
    return nsdyn.read_motion("synthetic-wn-40s").window(0.0, 6.0).scaled_to_pga(3.0)


def test_a_checkpoint_is_continued_only_by_the_run_that_wrote_it(tmp_path, building, record):
    """A finished run's checkpoint holds the whole run: the same run returns it as it was;
    a run with another motion (twice the PGA) is refused, never given the first run's
    histories."""
    ck = tmp_path / "ck.npz"
    first = nsdyn.simulate(building, record, checkpoint=ck, chunk_s=2.0)
    again = nsdyn.simulate(building, record, checkpoint=ck, chunk_s=2.0)
    assert np.array_equal(first.x, again.x)
    with pytest.raises(CheckpointError, match="written by another run"):
        nsdyn.simulate(building, record.scaled_to_pga(6.0), checkpoint=ck, chunk_s=2.0)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"chunk_s": -1.0}, "chunk_s: expected a positive"),
        ({"dt_out": 20.0}, "longer than the run"),
        ({"dt_out": 0.0}, "dt_out: expected a positive"),
        ({"rtol": "1e-4"}, "rtol: expected a relative tolerance 2.2e-14 <= rtol < 1"),
        ({"rtol": 1.0}, "rtol: expected a relative tolerance 2.2e-14 <= rtol < 1"),
        ({"rtoll": 1e-6}, "did you mean 'rtol'"),
        # a landing's coefficient on a run without landings was dropped without a word
        (
            {"restitution": 0.5},
            "restitution: .* contact='detect' has none of; expected contact='unilateral'",
        ),
    ],
)
def test_simulate_refuses_settings_it_cannot_run(building, record, kwargs, match):
    with pytest.raises((TypeError, ValueError), match=match):
        nsdyn.simulate(building, record, **kwargs)


def test_simulate_names_the_object_it_expected(building):
    with pytest.raises(TypeError, match="system: expected an IsolatedSystem"):
        nsdyn.simulate("office-11", nsdyn.Harmonic(1.0, 1.0), t_end=1.0)
    with pytest.raises(TypeError, match=r"planar\(\)"):
        nsdyn.simulate(building, nsdyn.read_motion3("synthetic-wn-40s"))
    with pytest.raises(TypeError, match="the number 3.0"):
        nsdyn.simulate(building, 3.0)
    with pytest.raises(TypeError, match="isolation: expected an Isolation"):
        nsdyn.shear_building([2e4, 1e4], [2e7], 0.05, isolation="iso")
    with pytest.raises(TypeError, match="isolation: expected an Isolation"):
        nsdyn.build_system("office-11", "iso")


@pytest.mark.parametrize("f_max", [-1.0, 0.0, float("nan")])
def test_a_cut_off_that_is_no_frequency_is_refused(f_max):
    """f_max <= 0 would keep no fixed-interface mode; NaN kept all 435 (the full model)."""
    with pytest.raises(ValueError, match="f_max: expected a positive frequency"):
        nsdyn.build_system("office-11", nsdyn.Isolation(), f_max=f_max)


def test_isolation_values_the_laws_cannot_use_are_refused():
    # arctan: mu N (2/pi) atan(eps v) needs eps > 0; the switch law has no eps
    with pytest.raises(ValueError, match="isolation.eps: the arctan law needs a positive"):
        nsdyn.Isolation(eps=0.0)
    assert nsdyn.Isolation(law="switch", eps=0.0).eps == 0.0
    with pytest.raises(ValueError, match="isolation.g: expected a positive gravity"):
        nsdyn.Isolation(g=0.0)  # the normal forces would vanish
    with pytest.raises(ValueError, match="isolation.mu: expected a finite non-negative"):
        nsdyn.Isolation(mu="0.05")
    with pytest.raises(ValueError, match=r"isolation.mu: expected one value or 2 \(one per"):
        nsdyn.build_system("office-11", nsdyn.Isolation(mu=(0.03, 0.05, 0.07)))  # 2 bearings


def test_velocity_dependent_friction_needs_its_rate():
    """mu(v) = mu_fast - (mu_fast - mu_slow) exp(-a |v|) is mu_slow everywhere for a = 0."""
    from nsdyn.models.isolated.bearings import BearingError, Friction

    with pytest.raises(BearingError, match="needs a positive rate"):
        Friction(0.04, mu_fast=0.07)
    assert Friction(0.04, mu_fast=0.07, rate=30.0).fast == 0.07


def test_the_triple_bearing_backbone_is_odd():
    """The rigid-plastic series model is symmetric: u(-phi) = -u(phi) exactly."""
    from nsdyn.models.isolated.tfp import TripleBearing

    tfp = TripleBearing(R1=2.2, R2=0.3, R3=0.3, R4=2.2, mu1=0.06, mu2=0.02, mu3=0.02, mu4=0.10,
                        d1=0.40, d2=0.06, d3=0.06, d4=0.40)  # fmt: skip
    phi = np.linspace(0.0, 0.3, 31)
    u = tfp.backbone(phi)
    assert u[-1] > 0 and np.array_equal(tfp.backbone(-phi), -u)


def test_force_tables_and_records_refuse_what_they_cannot_mean():
    F = np.column_stack([np.arange(10.0), 100 + np.arange(10.0)])
    with pytest.raises(ValueError, match=r"ForceTable.F: expected one force history"):
        nsdyn.ForceTable(0.0, 0.01, F, dofs=[0])
    assert nsdyn.ForceTable(0.0, 0.01, F[:, :1], dofs=[0]).F.shape == (10,)  # one column
    with pytest.raises(ValueError, match="t0: expected a finite time"):
        nsdyn.GroundMotion(float("nan"), 0.01, np.sin(np.arange(100) * 0.1))
    # text and ragged lists (numpy's messages, naming nothing), one sample ("t_end" blamed,
    # never given)
    with pytest.raises(ValueError, match=r"^ForceTable.F: expected real forces \[N\], got text"):
        nsdyn.ForceTable(0.0, 0.01, "abc", dofs=[0])
    with pytest.raises(ValueError, match=r"^ForceTable.F: expected real forces \[N\], got \[\[1"):
        nsdyn.ForceTable(0.0, 0.01, [[1.0, 2.0], [3.0]], dofs=[0])
    # complex forces lost their imaginary part with only numpy's ComplexWarning
    with pytest.raises(ValueError, match=r"^ForceTable.F: expected real forces \[N\], got compl"):
        nsdyn.ForceTable(0.0, 0.01, np.array([1 + 2j, 3.0, 1j]), dofs=[0])
    with pytest.raises(ValueError, match=r"^ForceTable.F: expected two samples or more"):
        nsdyn.ForceTable(0.0, 0.01, 1.0, dofs=[0])
    with pytest.raises(ValueError, match=r"^ForceTable.dt: expected a positive step \[s\]"):
        nsdyn.ForceTable(0.0, "0.01", np.ones(10), dofs=[0])
    # a numpy float32 step is the float it holds: the table's end is its last sample's time
    ft = nsdyn.ForceTable(0.0, np.float32(0.01), np.ones(300), dofs=[0])
    assert type(ft.dt) is float and ft.t0 + ft.duration == ft.t[-1]


def test_numpy_scalars_and_one_dof_index_are_the_numbers_they_hold():
    # dt_out = np.float32(0.5) was "expected a positive output step"; iso_dofs = 0 read as
    # "rows of shape (1, 1)"; 0 x 0 matrices ended in a numpy reduction error
    from nsdyn.models.isolated.builders import MatrixError

    b = nsdyn.shear_building([1e4], [], 0.0, isolation=nsdyn.Isolation(k_lam=4e4, c=0.0))
    for dt_out, n in ((np.float32(0.5), 5), (np.int64(1), 3)):
        assert nsdyn.simulate(b, nsdyn.Harmonic(2.0, 0.5), t_end=2.0, dt_out=dt_out).t.size == n
    iso = nsdyn.Isolation(k_lam=5e4, c=1e3, mu=0.05)
    M, C, K = np.diag([1e4, 1e4]), np.zeros((2, 2)), np.array([[2e6, -1e6], [-1e6, 1e6]])
    kw = {"influence": [1, 1], "weight": 1.5e5, "isolation": iso}
    one = nsdyn.system_from_matrices(M, C, K, iso_dofs=0, **kw)
    assert np.array_equal(one.D, nsdyn.system_from_matrices(M, C, K, iso_dofs=[0], **kw).D)
    with pytest.raises(MatrixError, match=r"^iso_dofs: .* got \[0\.5\]$"):
        nsdyn.system_from_matrices(M, C, K, iso_dofs=[0.5], **kw)
    with pytest.raises(MatrixError, match=r"^M: expected a square matrix of one dof or more"):
        z = np.zeros((0, 0))
        nsdyn.system_from_matrices(z, z, z, iso_dofs=[], influence=[], weight=1.0, isolation=iso)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: nsdyn.sine_pulse(1.0, 0.0), "f: expected a positive pulse frequency"),
        # a duration shorter than the pulse was lengthened to it without a word
        (lambda: nsdyn.sine_pulse(1.0, 2.0, duration=0.1), r"duration: .* T_p = 0\.5 s"),
        (lambda: nsdyn.modulated_white_noise(20.0, S0=-1e-4, seed=1), "S0: expected a non"),
        (lambda: nsdyn.modulated_white_noise(20.0, seed="a"), "seed: expected a non-negative"),
        (lambda: nsdyn.cylinder_earthquake(-1), "seed: expected a non-negative integer"),
    ],
)
def test_signal_generators_name_the_bad_argument(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@pytest.mark.parametrize(
    "kwargs, match",
    [({"rtol": 0.0}, "rtol"), ({"rtol": -1.0}, "rtol"), ({"scan": 1.0}, "scan"),
     ({"omega_ratios": [-2.0]}, "omega_ratios"), ({"omega_ratios": [1e-300]}, "omega_ratios"),
     ({"a_max": 1e300}, "a_max")],
)  # fmt: skip
def test_spectrum_settings_that_never_converge_are_refused(kwargs, match):
    """rtol <= 0 never ends the bisection, scan <= 1 never ends the bracketing; a pulse of
    1e300 s and a scan to 1e300 g tan α ended in a step size underflow."""
    blk = nsdyn.RockingBlock(width=0.3, height=1.2)
    args = {"omega_ratios": [2.0], **kwargs}
    with pytest.raises(ValueError, match=f"{match}: expected"):
        nsdyn.overturning_spectrum(blk, args.pop("omega_ratios"), **args)


def test_a_block_more_slender_than_its_equations_resolve_is_refused():
    # width 1e-20 m on 1.2 m: alpha 8.3e-21 rad printed as 0.0000, the spectrum found no
    # overturning anywhere; a block at the bound (width = 1e-4 height) is a block
    with pytest.raises(ValueError, match=r"^RockingBlock: width: width / height = 8\.33333e-21; "):
        nsdyn.RockingBlock(width=1e-20, height=1.2)
    assert nsdyn.RockingBlock(width=1.2e-4, height=1.2).alpha == pytest.approx(math.atan(1e-4))


def test_rigid_body_runs_refuse_outputs_and_starts_they_cannot_give():
    body = nsdyn.RigidBody.rectangle(1.1, 1.0, 1250.0)
    law = nsdyn.FrictionLaw(0.57, 0.29)
    mo = nsdyn.BaseMotion.displacement_sine(0.193, 2.18, 5, "impulsive")
    for kw, match in (({"t_end": -1.0}, "t_end"), ({"t_end": 5.0, "dt_out": 0.0}, "dt_out")):
        with pytest.raises(ValueError, match=f"{match}: expected a positive"):
            nsdyn.simulate_event(body, law, mo, **kw)
    for rtol in (-1.0, 1.0):  # an error test err <= rtol |y| passes any step from rtol = 1
        with pytest.raises(ValueError, match="rtol: expected a relative tolerance 2.2e-14 <="):
            nsdyn.simulate_event(body, law, mo, t_end=5.0, rtol=rtol)
    with pytest.raises(TypeError, match="BaseMotion.from_motion"):
        nsdyn.simulate_event(body, law, nsdyn.read_motion("synthetic-wn-40s"), t_end=1.0)
    with pytest.raises(TypeError, match="^motion: expected a GroundMotion, Table or Harmonic"):
        nsdyn.BaseMotion.from_motion("synthetic-wn-40s")  # (a name, not a record: the wrong kind)
    # the rectangle lies on its side at theta_ov = pi/2: a start there is overturned already
    with pytest.raises(ValueError, match="theta0: a tilt of 2 rad lays the body on its side"):
        nsdyn.simulate_event(body, law, None, t_end=1.0, theta0=2.0)
    for A, period, n in ((0.1, 0.0, 5), (float("nan"), 2.0, 5), (0.1, 2.0, 2.5)):
        with pytest.raises(ValueError, match="expected"):
            nsdyn.BaseMotion.displacement_sine(A, period, n, "impulsive")
    blk = nsdyn.RockingBlock(width=0.3, height=1.2)
    pulse = nsdyn.one_sine(0.4 * 9.81, 4 * math.pi)
    with pytest.raises(ValueError, match="expected a positive"):
        nsdyn.simulate_rocking(blk, pulse, t_end=6.0, dt_out=-1.0)
    for tol in (-1.0, 1.0):
        with pytest.raises(ValueError, match="tol: expected a relative tolerance 2.2e-14 <="):
            nsdyn.simulate_rocking(blk, pulse, t_end=6.0, tol=tol)


def test_objects_of_the_wrong_kind_are_named_by_every_family():
    from nsdyn.structure import fixed_base_modes_3d, load_frame3d

    body = nsdyn.RigidBody.rectangle(1.1, 1.0, 1250.0)
    law = nsdyn.FrictionLaw(0.57, 0.29)
    dt, ag = nsdyn.cylinder_earthquake(0)
    soft = nsdyn.CompliantBlock.from_frequency(width=2.0, height=4.0, mass=1e5, omega_v=543.0,
                                               zeta=2.0)  # fmt: skip
    rigid = nsdyn.RockingBlock(width=0.3, height=1.2)
    for call, match in (
        (lambda: nsdyn.simulate_rocking("block", None, t_end=1.0), "model: expected a Rocking"),
        (lambda: nsdyn.simulate_rocking(soft, t_end=1.0), r"nsdyn\.simulate_compliant\("),
        (lambda: nsdyn.simulate_compliant(rigid, t_end=1.0), r"nsdyn\.simulate_rocking\("),
        (lambda: nsdyn.simulate_event(body, 0.5, None, t_end=1.0), "friction: expected a Fr"),
        (lambda: nsdyn.simulate_event("box", law, None, t_end=1.0), "body: expected a RigidBody"),
        (lambda: nsdyn.frequency_response("office-11", 0.5), "system: expected an Isolated"),
        (lambda: nsdyn.simulate_cylinder("cyl", ag, dt), "p: expected CylinderParams"),
        (lambda: fixed_base_modes_3d("portal-3d"), "frame: expected a Frame3D"),
    ):
        with pytest.raises(TypeError, match=match):
            call()
    with pytest.raises(ValueError, match="q0: expected 3 finite values"):
        nsdyn.simulate_event(body, law, None, t_end=1.0, q0=[0.0])
    with pytest.raises(ValueError, match=r"a plane frame \(its \[frame\] table\); load it"):
        load_frame3d("office-11")


def test_numbers_given_as_text_are_refused_not_converted():
    rec = nsdyn.read_motion("synthetic-wn-40s")
    for call, match in (
        (lambda: rec.scaled_to_pga("3"), "target: expected a finite PGA"),
        (lambda: nsdyn.read_motion3("synthetic-wn-40s").rotated("30"), "angle_deg: expected"),
        (lambda: nsdyn.read_motion3("synthetic-wn-40s").scaled_to_pga("3"), "target: expected"),
        (lambda: nsdyn.CylinderParams(k="9814"), "k: expected a positive finite number"),
    ):
        with pytest.raises(ValueError, match=match):
            call()


def test_an_unknown_method_or_a_text_output_step_is_named(building):
    # a KeyError from the method table and a numpy TypeError from isfinite before
    rec = nsdyn.read_motion("synthetic-wn-40s").with_vertical(None).window(0.0, 1.0)
    for kw, match in (
        ({"method": "Radau"}, r"^method: expected 'auto' or one of \['dopri5'"),
        ({"dt_out": "0.01"}, r"^dt_out: expected a positive output step"),
    ):
        with pytest.raises(ValueError, match=match):
            nsdyn.simulate(building, rec, **kw)


def test_a_misspelt_continuation_option_names_the_nearest(building):
    with pytest.raises(TypeError, match="'pionts'; did you mean 'points'"):
        nsdyn.frequency_response(building, 0.5, fmin=0.3, fmax=1.0, pionts=3)
