"""nsdyn's default earthquake run against SciPy's Radau on the same equations, in one process.

Office frame (CB-5, 13 dofs), isolated, arctan eps = 7500, the bundled 40 s record at PGA
3 m/s^2. nsdyn: ``simulate`` at its default tolerances, median of 5 runs after compilation,
timed before and after the SciPy runs (each ratio is printed against both times: on a
loaded machine they bracket it). SciPy: ``solve_ivp(method="Radau")`` on the plain-NumPy
equations of :func:`nsdyn.bench.baseline.numpy_equations` with the analytic Jacobian, at rtol
1e-4 and 1e-5 (atol = rtol / 100), timed once. Errors of the x_iso history against nsdyn radau
at rtol 1e-9. ``main`` returns the numbers it prints.

    python examples/scipy_ratio.py
"""

import numpy as np

from nsdyn import Isolation, build_system, load_frame, read_motion, simulate
from nsdyn.bench import run_errors, run_nsdyn, run_scipy_radau


def main() -> dict:
    """nsdyn's median wall time, steps and err_x before and after SciPy's runs, and per SciPy
    rtol its wall time, f-evaluations, err_x and ratio to nsdyn's time."""
    system = build_system(load_frame("office-11"), Isolation(), fidelity="cb", f_max=5.0)
    motion = read_motion("synthetic-wn-40s")
    ref = run_nsdyn(system, motion, "radau", label="reference", rtol=1e-9, repeats=1)

    def nsdyn_default():
        walls = []
        for _ in range(5):
            r = simulate(system, motion)
            walls.append(r.wall_s)
        err = np.max(np.abs(r.response.x_iso - ref.x_iso)) / ref.x_iso_max
        return float(np.median(walls)), r.n_steps, float(err)

    before = nsdyn_default()
    scipy = {}
    print(f"nsdyn default: {before[0]:.3f} s, {before[1]} steps, err_x {before[2]:.1e}", flush=True)
    for rtol in (1e-4, 1e-5):
        sc = run_scipy_radau(system, motion, rtol, repeats=1)
        err = run_errors(sc, ref)["err_x"]
        print(
            f"scipy Radau rtol {rtol:g}: {sc.walls[-1]:.1f} s, {sc.nfev} f-evaluations, "
            f"err_x {err:.1e}, {sc.walls[-1] / before[0]:.0f}x the nsdyn time",
            flush=True,
        )
        scipy[rtol] = {
            "wall_s": sc.walls[-1],
            "nfev": sc.nfev,
            "err_x": err,
            "ratio": sc.walls[-1] / before[0],
        }
    after = nsdyn_default()
    again = ", ".join(f"{v['wall_s'] / after[0]:.0f}x at rtol {k:g}" for k, v in scipy.items())
    print(f"nsdyn default again: {after[0]:.3f} s (SciPy's time {again} of this one: the two "
          "nsdyn timings bracket the ratio on a machine whose load moved)")  # fmt: skip
    keys = ("wall_s", "n_steps", "err_x")
    return {
        "nsdyn_before": dict(zip(keys, before, strict=True)),
        "nsdyn_after": dict(zip(keys, after, strict=True)),
        "scipy": scipy,
    }


if __name__ == "__main__":
    import argparse

    argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    ).parse_args()  # --help; no options
    main()
