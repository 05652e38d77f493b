"""Seed 002, Table 1 on compliant ground: which verdicts change, and how they depend on k.

Every case of ``contact_table1.CASES`` with the impulsive start, on tensionless spring-dashpot
corners (stiffness k per corner, damping ratio zeta of the vertical contact mode, stick spring
k_t = k) and the FE run's friction law (C = 0, mu = mu_s) or the static/dynamic jump law.
Writes ``examples/figures/contact-compliant.png`` (or into ``--out DIR``): max tilt, max corner
uplift and overturning against the ground stiffness for A4-A6 and C2.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

from nsdyn.models.contact import BaseMotion, FrictionLaw, RigidBody
from nsdyn.models.contact.compliant import CompliantGround, simulate_compliant

sys.path.insert(0, str(Path(__file__).parent))
from contact_table1 import CASES, MASS, PGA  # noqa: E402

K_SWEEP = (1e6, 3e6, 1e7, 3e7, 1e8, 1e9, 1e10, 1e11)  # per-corner stiffness [N/m]
ZETAS = (0.0, 0.05)  # damping ratios of the vertical contact mode
K_TABLE = 1e9  # stiffness of the table column [N/m] (settlement 11-37 micrometres)
FIG = Path(__file__).parent / "figures" / "contact-compliant.png"


def run_case(name: str, k: float, zeta: float, C: float = 0.0) -> dict:
    """Compliant-ground run of one Table 1 case (impulsive start); summary dict."""
    a, c, T, mu_s, mu_d = CASES[name][:5]
    body = RigidBody.rectangle(a, c, MASS * c)
    A = PGA * (T / (2 * math.pi)) ** 2
    res = simulate_compliant(body, FrictionLaw(mu_s, mu_d, C),
                             CompliantGround.from_ratio(body, k, zeta),
                             BaseMotion.displacement_sine(A, T, 5), t_end=5 * T + 2.0)  # fmt: skip
    s = res.summary()
    s["slide_mm"] = 1e3 * s["max_slide_m"]
    s["uplift_mm"] = 1e3 * s["max_uplift_m"]
    s["settlement_mm"] = 1e3 * CompliantGround(k).settlement(body)
    return s


def verdict(s: dict) -> str:
    """Seed-style verdict: overturning, tilting (a corner lifted by more than 1 mm), or sliding."""
    if s["overturned"]:
        return "overturn"
    if s["uplift_mm"] > 1.0:
        return "tilt"
    return "slide" if s["slide_mm"] > 1.0 else "rest"


def main(out: Path | None = FIG, cases=None, k_sweep=K_SWEEP) -> dict:
    """Table column (k = K_TABLE, zeta = 0 and 0.05, C = 0 and jump law) plus the k sweep."""
    table = {}
    for name in cases or CASES:
        table[name] = {f"z{z}_C{C}": run_case(name, K_TABLE, z, C)
                       for z in ZETAS for C in (0.0, math.inf)}  # fmt: skip
    sweep = {name: {z: [run_case(name, k, z) for k in k_sweep] for z in ZETAS}
             for name in ("A4", "A5", "A6", "C2") if name in (cases or CASES)}  # fmt: skip
    if out is not None and sweep:
        _chart(sweep, k_sweep, out)
    return {"table": table, "sweep": sweep, "k_sweep": list(k_sweep)}


def _chart(sweep: dict, k_sweep, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from nsdyn.atomic import save_figure

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for name, by_z in sweep.items():
        for z, runs in by_z.items():
            ls = "-" if z == 0 else "--"
            tilt = [r["max_tilt_rad"] for r in runs]
            upl = [max(r["uplift_mm"], 1e-6) for r in runs]
            (ln,) = ax[0].loglog(k_sweep, tilt, ls, marker="o", label=f"{name}, zeta = {z}")
            ax[1].loglog(k_sweep, upl, ls, marker="o", color=ln.get_color())
            for kk, r, t in zip(k_sweep, runs, tilt, strict=True):
                if r["overturned"]:
                    ax[0].plot(kk, t, "kx", ms=12, mew=2)
    ax[0].set(xlabel="corner stiffness k [N/m]", ylabel="max tilt [rad]",
              title="peak tilt (mu = mu_s, impulsive start; x marks an overturn)")  # fmt: skip
    ax[1].axhline(1.0, color="grey", lw=0.8)
    ax[1].set(xlabel="corner stiffness k [N/m]", ylabel="max corner uplift [mm] (1e-6: none)",
              title="lift-off of a base corner")  # fmt: skip
    ax[0].legend(fontsize=7, ncol=2)
    fig.tight_layout()
    save_figure(fig, out)
    plt.close(fig)


if __name__ == "__main__":
    from nsdyn.cli.args import figure_script

    FIG = figure_script(__doc__, FIG)
    res = main(FIG)
    print(f"figure {FIG}")
    for name, cols in res["table"].items():
        print(name, " | ".join(f"{k}: {verdict(s)}, slide {s['slide_mm']:.1f} mm, tilt "
                               f"{s['max_tilt_rad']:.2e} rad, uplift {s['uplift_mm']:.3f} mm"
                               for k, s in cols.items()))  # fmt: skip
    print(
        "stiffness sweep: case, damping ratio, then at each ground stiffness k of "
        f"{', '.join(f'{k:.3g}' for k in res['k_sweep'])}: verdict tilt [rad]/uplift [mm]/"
        "slide [mm]"
    )
    for name, by_z in res["sweep"].items():
        for z, runs in by_z.items():
            print(name, z, [f"{verdict(r)} {r['max_tilt_rad']:.2e}/{r['uplift_mm']:.3g}/"
                            f"{r['slide_mm']:.1f}" for r in runs])  # fmt: skip
