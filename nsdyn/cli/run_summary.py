"""The printed summary of ``nsdyn run``: one row per metric the run's model defines."""

from __future__ import annotations

from nsdyn.cli.run_checks import duration_text


def _uplift_cell(v) -> str:
    if not v:
        return "none"
    first = v[0]
    more = f", {len(v) - 1} more" if len(v) > 1 else ""
    return f"t = {first['t_s']:.4f} s (contact {first['contact']}){more}"


CLOSURE_NOTE = 1e-2  # above this, the closure row says what the number measures


def _closure_cell(v: float) -> str:
    """The closure error, and above :data:`CLOSURE_NOTE` what it is: a check of the work
    integrals by the trapezoidal rule on the output grid, which measures the grid as much as
    the run (not the integrator's error, which its tolerance bounds)."""
    if not v > CLOSURE_NOTE:
        return f"{v:.2e}"
    return (f"{v:.2e} (the work integrals by the trapezoidal rule on the output grid: a "
            "finer [solver] dt_out tightens it)")  # fmt: skip


def _fixed_cell(v: dict) -> str:
    """--compare-fixed's peaks, "-" for one the model does not define (a setback: no IDR)."""
    fmt = (("idr_max", "{:.3e}"), ("floor_acc_max_mps2", "{:.3f} m/s²"),
           ("roof_drift_max_m", "{:.4f} m"))  # fmt: skip
    return " / ".join(f.format(v[k]) if k in v else "-" for k, f in fmt)


def summary_rows(s: dict) -> list[str]:
    """The printed rows of a run's summary ``s`` (label, value): the metrics the model
    defines. A run with unilateral contacts models lift-off, so it has no uplift row (that
    row reports the no-uplift model's violations); its lift-off rows say what happened."""
    base = "iso" if "x_iso_max_m" in s else "base"  # (a fixed base: no isolators)
    rigid = " (rigid: the storeys do not deform)" * (s.get("fidelity") == "rigid")  # (not 0 found)
    rows = [  # (label, key, format): metrics the model does not define are absent
        ("duration / output step", "t_end_s", lambda v: duration_text(s, v)),
        ("peak isolator displacement x_iso", "x_iso_max_m", lambda v: f"{v:.4f} m"),
        ("peak interstorey drift ratio", "idr_max", lambda v: f"{v:.3e}" + rigid),
        ("peak absolute floor acceleration", "floor_acc_max_mps2", lambda v: f"{v:.3f} m/s²"),
        (f"peak roof drift x_top - x_{base}", "roof_drift_max_m", lambda v: f"{v:.4f} m" + rigid),
        ("minimum normal force", "min_normal_force_N", lambda v: f"{v + 0.0:.4g} N"),  # no "-0"
        ("share of time all isolators stick", "stick_fraction", lambda v: f"{v:.2f}"),
        ("energy balance closure error", "energy_closure", _closure_cell),
        ("uplift", "uplift", _uplift_cell),
        ("contact assumption", "contact", str),
        ("a normal force < 0 (lift-off)", "would_lift_off", lambda v: "yes" if v else "no"),
        ("lift-offs / landings", "lift_offs", lambda v: f"{v} / {s.get('landings', 0)}"),
        ("first lift-off", "first_lift_off_s", lambda v: f"{v:.4f} s"),
        ("flight time per contact", "flight_time_s", lambda v: ", ".join(f"{x:.3f} s" for x in v)),
        ("peak landing velocity", "max_landing_velocity_mps", lambda v: f"{v:.4f} m/s"),
        ("peak landing impulse", "max_landing_impulse_Ns", lambda v: f"{v:.4g} N s"),
        ("energy lost at landings", "impact_energy_J", lambda v: f"{abs(v):.4g} J"),
        ("fixed base: IDR / floor acc. / roof", "fixed_base", _fixed_cell),
    ]
    skip = "uplift" if s.get("contact") == "unilateral" else ""
    return [f"  {label:36s} {fmt(s[key])}" for label, key, fmt in rows
            if key != skip and s.get(key) is not None]  # fmt: skip
