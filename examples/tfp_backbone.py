"""The triple friction pendulum's quasi-static loop through its five sliding regimes.

The bearing of the scene examples/scenes/deck-tfp4-3c.toml (R1 = R4 = 2.2 m, R2 = R3 = 0.3 m,
μ1 = 0.06, μ2 = μ3 = 0.02, μ4 = 0.10, d1 = d4 = 0.40 m, d2 = d3 = 0.06 m) pushed slowly to its
full capacity and back: the force per unit normal load φ = F/N against the total slip u.

The loop is nsdyn's series model (nsdyn.models.isolated.tfp: four rigid-plastic pendulums in
series, the same force through each; on a quasi-static path each element's slip s_k follows
the play s_k ← clip(s_k, R̄_k (φ − μ_k), R̄_k (φ + μ_k)), within ±d̄_k) at the elements'
modified parameters. The marks are the published piecewise-linear model (Fenz & Constantinou
2008, Earthquake Spectra 24(4), Table 1) computed apart, from the bearing's own parameters: the
regimes start at φ = μ2, μ1, μ4, μ1 + d1/R1, μ4 + d4/R4 with slopes du/dφ = R2 + R3, R1 + R3,
R1 + R4, R2 + R4, R2 + R3, and end at the inner slider's rims. The marks lie on the loop's
loading branch. Writes examples/figures/tfp_backbone.png (or into ``--out DIR``).

    python examples/tfp_backbone.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from nsdyn.atomic import save_figure
from nsdyn.models.isolated.tfp import TripleBearing

FIGURE = Path(__file__).resolve().parent / "figures" / "tfp_backbone.png"
BEARING = dict(R1=2.2, R2=0.3, R3=0.3, R4=2.2, mu1=0.06, mu2=0.02, mu3=0.02, mu4=0.10, d1=0.40,
               d2=0.06, d3=0.06, d4=0.40)  # fmt: skip


def published_points(p: dict) -> list[tuple[str, float, float]]:
    """(regime, φ, u) where each of regimes I–V starts and where the inner slider reaches its
    rims (Fenz & Constantinou 2008, Table 1; μ2 = μ3, μ2 ≤ μ1 ≤ μ4)."""
    R1, R2, R3, R4 = p["R1"], p["R2"], p["R3"], p["R4"]
    starts = [("I", p["mu2"], R2 + R3), ("II", p["mu1"], R1 + R3), ("III", p["mu4"], R1 + R4),
              ("IV", p["mu1"] + p["d1"] / R1, R2 + R4), ("V", p["mu4"] + p["d4"] / R4, R2 + R3),
              ("end", p["mu2"] + p["d2"] / R2 + p["d1"] / R1, 0.0)]  # fmt: skip
    out, u = [], 0.0
    for k, (name, phi, _) in enumerate(starts):
        if k:
            u += starts[k - 1][2] * (phi - starts[k - 1][1])
        out.append((name, phi, u))
    return out


def quasi_static_loop(bearing: TripleBearing, phi_path: np.ndarray) -> np.ndarray:
    """Total slip u along a path of φ: the series model's rigid-plastic elements as plays."""
    el = bearing.elements()  # (R̄, μ, d̄) per element
    s = np.zeros(len(el))
    u = np.empty_like(phi_path)
    for j, phi in enumerate(phi_path):
        for k, (R, mu, d) in enumerate(el):
            s[k] = np.clip(np.clip(s[k], R * (phi - mu), R * (phi + mu)), -d, d)
        u[j] = s.sum()
    return u


def figure(phi, u, points):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.0, 4.2), layout="constrained")
    ax = fig.add_subplot()
    ax.plot(u, phi, "-", lw=1.4, label="series model (quasi-static loop)")
    for name, ph, uu in points:
        ax.plot(uu, ph, "o", color="C3", ms=5)
        ax.annotate(name, (uu, ph), textcoords="offset points", xytext=(-14, 4), fontsize=8)
    ax.plot([], [], "o", color="C3", label="Fenz & Constantinou 2008, Table 1")
    ax.set_xlabel("total slip u [m]")
    ax.set_ylabel("force per unit normal load F/N")
    ax.set_title("triple friction pendulum: regimes I–V to the inner slider's rims", fontsize=9)
    ax.axhline(0.0, color="0.8", lw=0.6)
    ax.axvline(0.0, color="0.8", lw=0.6)
    ax.legend(fontsize=8, loc="lower right")
    return fig


def main() -> int:
    b = TripleBearing(**BEARING)
    points = published_points(BEARING)
    top = points[-1][1]
    n = 2000
    up = np.linspace(0.0, top, n)
    phi = np.concatenate([up, np.linspace(top, -top, 2 * n), np.linspace(-top, top, 2 * n)])
    u = quasi_static_loop(b, phi)
    for name, ph, uu in points:  # on the first loading branch
        u_model = np.interp(ph, up, u[:n])
        print(f"regime {name:>3s}: phi = {ph:.4f}, u published {uu:.4f} m, series model "
              f"{u_model:.4f} m")  # fmt: skip
    print(f"capacity d1 + d2 + d3 + d4 = {b.d_cap:.3f} m, loop's largest slip {u.max():.3f} m")
    save_figure(figure(phi, u, points), FIGURE)
    print(FIGURE)
    return 0


if __name__ == "__main__":
    from nsdyn.cli.args import figure_script

    FIGURE = figure_script(__doc__, FIGURE)
    raise SystemExit(main())
