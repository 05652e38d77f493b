"""A short tour of the public API: frame -> model ladder -> state evaluation -> transient run.

    python examples/api_tour.py

``main()`` returns the numbers it prints, so tests can import and check them.
"""

from __future__ import annotations

import numpy as np

from nsdyn import (
    Harmonic,
    Isolation,
    build_system,
    fixed_base_statespace,
    load_frame,
    read_motion,
    simulate,
)


def main(t_end: float = 10.0) -> dict:
    frame = load_frame("office-11")
    iso = Isolation(k_lam=5e4, c=1e4, mu=0.03, law="arctan", eps=7500.0)  # seed eq (16)

    # one description, four fidelities
    ladder = {
        fid: build_system(frame, iso, fidelity=fid)  # (f_max: 5 Hz, the cut-off of cb, fixed)
        for fid in ("fixed", "rigid", "cb", "full")
    }
    dofs = {fid: s.n for fid, s in ladder.items()}
    print("generalised dofs per fidelity:", dofs)

    # static equilibrium under gravity: the normal forces carry the weight
    cb = ladder["cb"]
    x0, lam0 = cb.static_equilibrium()
    print(
        f"static normal forces {lam0[0]:.4g} + {lam0[1]:.4g} N = M_s g = "
        f"{frame.total_mass * 9.81:.4g} N"
    )

    # accelerations and forces at any state, here sliding at 0.1 m/s under 1 m/s^2
    x = x0.copy()
    x[cb.n :] += cb.Q @ (cb.Q.T @ (cb.D.T @ np.array([0.1, 0.1])))
    ev = cb.evaluate(0.25, x, Harmonic(1.0, 1.0))
    print("normal forces", ev["lam"], "friction forces", ev["tau"], "modes", ev["modes"])

    # minimal coordinates (seed eqs 23-27): z = [x1 th1 x2 th2 q_r]
    z, zd = cb.Q.T @ x[: cb.n], cb.Q.T @ x[cb.n :]
    zdd = cb.minimal_accelerations(0.25, z, zd, Harmonic(1.0, 1.0))
    print(
        "minimal-coordinate accelerations agree with the multiplier form:",
        np.allclose(cb.Q @ zdd, ev["qdd"], atol=1e-9 * np.abs(ev["qdd"]).max()),
    )

    # the fixed-base frame is linear: a python-control state space
    sys = fixed_base_statespace(ladder["fixed"])
    print("fixed-base poles [Hz]:", np.round(np.sort(np.abs(sys.poles()))[::2] / 2 / np.pi, 3))

    # a transient run on the bundled synthetic record
    motion = read_motion("synthetic-wn-40s").scaled_to_pga(3.0).window(0.0, t_end)
    res = simulate(cb, motion, method="radau")
    s = res.summary()
    print(
        f"{t_end:g} s of synthetic-wn-40s: x_iso_max {s['x_iso_max_m']:.3f} m, "
        f"IDR_max {s['idr_max']:.2e}, run {s['wall_s']:.2f} s"
    )
    return {
        "dofs": dofs,
        "lam0": lam0,
        "total_weight": frame.total_mass * 9.81,
        "minimal_agrees": bool(
            np.allclose(cb.Q @ zdd, ev["qdd"], atol=1e-9 * np.abs(ev["qdd"]).max())
        ),
        "summary": s,
    }


if __name__ == "__main__":
    import argparse

    argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    ).parse_args()  # --help; no options
    main()
