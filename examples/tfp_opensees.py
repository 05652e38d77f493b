"""nsdyn's triple friction pendulum beside OpenSees' TripleFrictionPendulum element.

The bearing of examples/tfp_backbone.py (R1 = R4 = 2.2 m, R2 = R3 = 0.3 m, μ1 = 0.06,
μ2 = μ3 = 0.02, μ4 = 0.10, d1 = d4 = 0.40 m, d2 = d3 = 0.06 m), mapped to the element by
nsdyn.models.isolated.opensees3d_isolated.tfp_element_args (L = R2, R1, R4; Ubar = d3, d1,
d4; friction μ2, μ1, μ4; uy = u_y), with its elastic stage undamped (zeta_e = 0) as the
element's is:

- left: the quasi-static loop to ±0.8 m (regimes I–IV). OpenSees: a static displacement path
  in steps of 0.4 mm. nsdyn: its series model's rate-independent limit (four rigid-plastic
  pendulums R̄_k, μ_k, d̄_k as plays, in series with the elastic spring φ/κ_e), along a
  force path;
- right: the orbit of a 1 t mass on the bearing under a_x = 1.3 sin ωt, a_y = 1.0 sin(ωt +
  60°) m/s², 0.35 Hz, 10 s. nsdyn: sdof_plane / simulate_plane (arctan law). OpenSees:
  Newmark average acceleration, dt = 1 ms.

The bounds of the differences are derived in tests/models/isolated/test_tfp_opensees.py and
docs/guide/opensees.md. Needs openseespy. Writes examples/figures/tfp_opensees.png
(or into ``--out DIR``).

    python examples/tfp_opensees.py
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from nsdyn.atomic import save_figure
from nsdyn.models.isolated.deck import sdof_plane, simulate_plane
from nsdyn.models.isolated.opensees3d_isolated import tfp_single, tfp_slip_mismatch, tfp_solver
from nsdyn.models.isolated.tfp import TripleBearing

FIGURE = Path(__file__).resolve().parent / "figures" / "tfp_opensees.png"
BEARING = dict(R1=2.2, R2=0.3, R3=0.3, R4=2.2, mu1=0.06, mu2=0.02, mu3=0.02, mu4=0.10, d1=0.40,
               d2=0.06, d3=0.06, d4=0.40)  # fmt: skip
G = 9.81


def opensees_loop(b: TripleBearing, A: float, du: float = 4e-4):
    W = 1.0e4
    ops = tfp_single(b, W)
    ops.timeSeries("Path", 2, "-time", 0.0, A, 3 * A, 5 * A, 5.5 * A, "-values", 0.0, A, -A, A, A)
    ops.pattern("Plain", 2, 2)
    ops.sp(2, 1, 1.0)
    tfp_solver(ops)
    ops.integrator("LoadControl", du)  # (small steps: see the guide's limits)
    ops.analysis("Static")
    u, phi = [], []
    for _ in range(int(round(5 * A / du))):
        if ops.analyze(1) != 0:
            raise RuntimeError("OpenSees: a static step did not converge")
        if tfp_slip_mismatch(ops) > 1e-2 * b.u_y:  # the element reports no such failure
            raise RuntimeError("OpenSees: the element lost its internal equilibrium")
        u.append(ops.nodeDisp(2, 1))
        phi.append(ops.eleForce(1, 7) / W)
    ops.wipe()
    return np.array(u), np.array(phi)


def nsdyn_loop(b: TripleBearing, phi_path: np.ndarray) -> np.ndarray:
    """u along a force path: the elastic spring φ/κ_e plus the elements' plays."""
    el = b.elements()
    s = np.zeros(len(el))
    u = np.empty_like(phi_path)
    for j, phi in enumerate(phi_path):
        for k, (R, mu, d) in enumerate(el):
            s[k] = np.clip(np.clip(s[k], R * (phi - mu), R * (phi + mu)), -d, d)
        u[j] = phi / b.k_elastic + s.sum()
    return u


def orbits(b: TripleBearing, f=0.35, ax=1.3, ay=1.0, ph=60.0, t_end=10.0, dt=1e-3):
    m = 1000.0
    r = simulate_plane(sdof_plane(m, b, g=G), {"f": f, "ax": ax, "ay": ay, "phase_y_deg": ph},
                       law="arctan", t_end=t_end, dt_out=dt, rtol=1e-8,
                       atol=(1e-10, 1e-10))  # fmt: skip
    ops = tfp_single(b, m * G, mass=m)
    n = int(round(t_end / dt))
    t = np.arange(n + 1) * dt
    w = 2 * np.pi * f
    ops.timeSeries("Path", 2, "-dt", dt, "-values", *(ax * np.sin(w * t)).tolist())
    ops.timeSeries("Path", 3, "-dt", dt,
                   "-values", *(ay * np.sin(w * t + math.radians(ph))).tolist())  # fmt: skip
    ops.pattern("UniformExcitation", 2, 1, "-accel", 2)
    ops.pattern("UniformExcitation", 3, 2, "-accel", 3)
    tfp_solver(ops)
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    u = np.zeros((n + 1, 2))
    for k in range(n):
        if ops.analyze(1, dt) != 0:
            raise RuntimeError(f"OpenSees: no convergence at t = {(k + 1) * dt:.3f} s")
        if tfp_slip_mismatch(ops) > 1e-2 * b.u_y:  # the element reports no such failure
            raise RuntimeError("OpenSees: the element lost its internal equilibrium")
        u[k + 1] = ops.nodeDisp(2, 1), ops.nodeDisp(2, 2)
    ops.wipe()
    return r.u[:, 0], u


def figure(loop_os, loop_ns, orbit_ns, orbit_os, cap):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(10.0, 4.4), layout="constrained")
    a1, a2 = fig.subplots(1, 2)
    a1.plot(loop_ns[0], loop_ns[1], "-", lw=2.4, color="0.7", label="nsdyn (series model)")
    a1.plot(
        loop_os[0], loop_os[1], "-", lw=1.0, color="C3", label="OpenSees TripleFrictionPendulum"
    )
    a1.set_xlabel("slip u [m]")
    a1.set_ylabel("F/N")
    a1.set_title("quasi-static loop, regimes I–IV", fontsize=9)
    a1.legend(fontsize=8, loc="lower right")
    a2.plot(*orbit_ns.T, "-", lw=2.4, color="0.7", label="nsdyn (arctan law, Radau)")
    a2.plot(*orbit_os.T, "-", lw=1.0, color="C3", label="OpenSees (Newmark, 1 ms)")
    th = np.linspace(0.0, 2 * np.pi, 200)
    a2.plot(cap * np.cos(th), cap * np.sin(th), "k--", lw=0.8, label="d1 + d2 + d3 + d4")
    a2.set_aspect("equal")
    a2.set_xlabel("u_x [m]")
    a2.set_ylabel("u_y [m]")
    a2.set_title("a mass on one TFP, elliptical ground orbit", fontsize=9)
    a2.legend(fontsize=8, loc="upper right")
    return fig


def main() -> int:
    from scipy.spatial import cKDTree

    b = TripleBearing(**BEARING, zeta_e=0.0)  # the element's elastic stage is undamped
    u_os, phi_os = opensees_loop(b, 0.8)
    top = float(np.abs(phi_os).max())
    n = 4000
    phi_ns = np.concatenate([np.linspace(0.0, top, n), np.linspace(top, -top, 2 * n),
                             np.linspace(-top, top, 2 * n)])  # fmt: skip
    u_ns = nsdyn_loop(b, phi_ns)
    print(f"quasi-static loop: largest F/N {top:.4f}; slip at F/N = {top:.4f}: OpenSees "
          f"{u_os.max():.4f} m, nsdyn {u_ns.max():.4f} m")  # fmt: skip
    o_ns, o_os = orbits(b)
    d1, _ = cKDTree(o_ns).query(o_os)
    d2, _ = cKDTree(o_os).query(o_ns)
    print(f"orbit: peak resultant displacement nsdyn {np.hypot(*o_ns.T).max():.4f} m, "
          f"OpenSees {np.hypot(*o_os.T).max():.4f} m; the orbits' Hausdorff distance "
          f"{max(d1.max(), d2.max()) * 1e3:.2f} mm")  # fmt: skip
    save_figure(figure((u_os, phi_os), (u_ns, phi_ns), o_ns, o_os, b.d_cap), FIGURE)
    print(FIGURE)
    return 0


if __name__ == "__main__":
    from nsdyn.cli.args import figure_script

    FIGURE = figure_script(__doc__, FIGURE)
    raise SystemExit(main())
