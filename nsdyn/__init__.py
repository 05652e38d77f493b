"""nsdyn — non-smooth structural dynamics of friction base-isolated frames.

The public API, by pipeline stage (structure → ground → models → solve → periodic → studies).
Names load lazily on first use, so ``import nsdyn`` stays cheap for the command line::

    import nsdyn
    frame = nsdyn.load_frame("office-11")
    system = nsdyn.build_system(frame, nsdyn.Isolation(mu=0.03), fidelity="cb", f_max=5.0)
    res = nsdyn.simulate(system, nsdyn.read_motion("synthetic-wn-40s").scaled_to_pga(3.0))
"""

from nsdyn._lazy import exports

__version__ = "0.1.0"

# public name -> module that defines it ("module:attr" where the names differ)
_API = {
    # structure
    "Frame": "nsdyn.structure",
    "FrameFileError": "nsdyn.structure",
    "Section": "nsdyn.structure",
    "base_isolation_frequency": "nsdyn.structure",
    "load_frame": "nsdyn.structure",
    "regular_frame": "nsdyn.structure",
    "CBModel": "nsdyn.structure",
    "craig_bampton": "nsdyn.structure",
    "fixed_base_modes": "nsdyn.structure",
    # ground
    "G_EARTH": "nsdyn.ground",
    "Harmonic": "nsdyn.ground",
    "Table": "nsdyn.ground",
    "GroundMotion": "nsdyn.ground",
    "RecordFileError": "nsdyn.ground",
    "UnitError": "nsdyn.ground.motion",
    "UnitWarning": "nsdyn.ground",
    "bundled_records": "nsdyn.ground",
    "kanai_tajimi": "nsdyn.ground",
    "kobe_records": "nsdyn.ground",
    "modulated_white_noise": "nsdyn.ground",
    "read_motion": "nsdyn.ground",
    "sine_pulse": "nsdyn.ground",
    "write_motion": "nsdyn.ground",
    "GroundMotion3": "nsdyn.ground",
    "HarmonicPlane": "nsdyn.ground",
    "read_motion3": "nsdyn.ground",
    "write_motion3": "nsdyn.ground",
    "bundled_records3": "nsdyn.ground",
    "motion3_from_table": "nsdyn.ground",
    # models: the isolated frame
    "Isolation": "nsdyn.models.isolated.system",
    "IsolatedSystem": "nsdyn.models.isolated.system",
    "build_system": "nsdyn.models.isolated.system",
    "system_from_matrices": "nsdyn.models.isolated.builders",
    "shear_building": "nsdyn.models.isolated.builders",
    "export_opensees": "nsdyn.models.isolated.opensees",
    "MatrixError": "nsdyn.models.isolated.builders",
    "build_scene_run": "nsdyn.models.isolated.scene",
    "linear_statespace": "nsdyn.models.isolated.statespace",
    "fixed_base_statespace": "nsdyn.models.isolated.statespace",
    "Response": "nsdyn.models.isolated.metrics",
    "SceneError": "nsdyn.models.isolated.scene",
    "load_scene": "nsdyn.models.isolated.scene",
    "build_scene": "nsdyn.models.isolated.scene",
    "HarmonicForce": "nsdyn.ground",
    "ForceTable": "nsdyn.ground",
    "Pulse": "nsdyn.ground.pulses",
    "one_sine": "nsdyn.ground.pulses",
    "one_cosine": "nsdyn.ground.pulses",
    "n_cycle_sine": "nsdyn.ground.pulses",
    "ricker": "nsdyn.ground.pulses",
    "rectangular": "nsdyn.ground.pulses",
    # models: rocking blocks and frames (seeds 001, 003)
    "RockingBlock": "nsdyn.models.rocking.block",
    "RockingFrame": "nsdyn.models.rocking.frame",
    "CompliantBlock": "nsdyn.models.rocking.compliant",
    "RockingResult": "nsdyn.models.rocking.results",
    "simulate_rocking": "nsdyn.models.rocking.block",
    "simulate_compliant": "nsdyn.models.rocking.compliant",
    "housner_restitution": "nsdyn.models.rocking.block",
    "overturning_spectrum": "nsdyn.models.rocking.spectra",
    "OverturningSpectrum": "nsdyn.models.rocking.spectra",
    # models: planar rigid bodies with frictional contacts (seed 002)
    "RigidBody": "nsdyn.models.contact",
    "FrictionLaw": "nsdyn.models.contact",
    "BaseMotion": "nsdyn.models.contact",
    "ContactResult": "nsdyn.models.contact",
    "simulate_event": "nsdyn.models.contact",
    "simulate_moreau": "nsdyn.models.contact",
    "onset_mode": "nsdyn.models.contact",
    "CompliantGround": "nsdyn.models.contact",
    "simulate_contact_compliant": "nsdyn.models.contact:simulate_compliant",
    # models: rigid cylinder on a Winkler foundation (seed 000)
    "CylinderParams": "nsdyn.models.cylinder",
    "CylinderResult": "nsdyn.models.cylinder",
    "simulate_cylinder": "nsdyn.models.cylinder:simulate",
    "CylinderSimulationError": "nsdyn.models.cylinder:SimulationError",
    "design_foundation": "nsdyn.models.cylinder",
    "compare_foundations": "nsdyn.models.cylinder",
    "cylinder_earthquake": "nsdyn.models.cylinder:earthquake",
    # solve
    "METHODS": "nsdyn.solve.integrate",
    "IntegrationError": "nsdyn.solve.integrate",
    "UpliftError": "nsdyn.solve.integrate",
    "UpliftWarning": "nsdyn.solve.integrate",
    "InputWarning": "nsdyn._checks",  # (filter them: warnings.simplefilter("error", ...))
    "NumericalFailure": "nsdyn._checks",  # (every numerical stop's base class: exit status 3)
    "PlaneIntegrationError": "nsdyn.models.isolated.plane_result",
    "CapacityWarning": "nsdyn.models.isolated.plane_result",  # (a rim stop reached)
    "TensionWarning": "nsdyn.models.isolated.plane_result",
    "CheckpointError": "nsdyn.atomic",
    "NotedWarning": "nsdyn._checks",
    "AccuracyWarning": "nsdyn._checks",  # (a run's peaks its steps did not resolve)
    "CONTACTS": "nsdyn.models.isolated.system",
    "Solution": "nsdyn.solve.integrate",
    # the low-level integrator: named ``integrate`` here because ``nsdyn.solve`` is the package
    "integrate": "nsdyn.solve.integrate:solve",
    "TransientResult": "nsdyn.solve.transient",
    "simulate": "nsdyn.solve.transient",
    # periodic
    "Discretisation": "nsdyn.periodic",
    "PeriodicProblem": "nsdyn.periodic",
    "frame_problem": "nsdyn.periodic",
    "shoot": "nsdyn.periodic",
    "ShootingResult": "nsdyn.periodic",
    "floquet_multipliers": "nsdyn.periodic",
    "steady_state_sweep": "nsdyn.periodic",
    "uplift_boundary": "nsdyn.periodic",
    "continue_sequential": "nsdyn.periodic",
    "continue_arclength": "nsdyn.periodic",
    "continue_range": "nsdyn.periodic.continuation",
    "frequency_response": "nsdyn.periodic",
    "OrbitPoint": "nsdyn.periodic",
    "PeriodicModel": "nsdyn.periodic",
    "SwitchProblem": "nsdyn.periodic",
    "SwitchShootingResult": "nsdyn.periodic",
    "switch_problem": "nsdyn.periodic",
    "shoot_switch": "nsdyn.periodic",
    "switch_response": "nsdyn.periodic",
    "Curve": "nsdyn.periodic",
    # studies
    "load_study": "nsdyn.studies",
    "Study": "nsdyn.studies",
    "run_study": "nsdyn.studies",
    "StudyRun": "nsdyn.studies",
    "dask_executor": "nsdyn.studies",
    "run_scene_summary": "nsdyn.studies",
    "fit_lognormal": "nsdyn.studies",
    "fit_lognormal_counts": "nsdyn.studies",
    "LognormalFragility": "nsdyn.studies",
    "pareto_front": "nsdyn.studies",
    "design_points": "nsdyn.studies",
    "percentile_table": "nsdyn.studies",
    "run_analyses": "nsdyn.studies",
    "advise": "nsdyn.studies.advisor",
    "Advice": "nsdyn.studies.advisor",
}

__all__ = sorted(_API) + ["__version__"]


__getattr__, __dir__ = exports(globals(), _API)
