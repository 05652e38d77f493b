"""Triple friction pendulum bearings: four sliding surfaces as a series of friction pendulums.

A triple friction pendulum (TFP) has two outer concave plates (surfaces 1 and 4, effective
radii R1, R4, friction μ1, μ4, displacement capacities d1, d4) and an inner articulated slider
(surfaces 2 and 3: R2, R3, μ2, μ3, d2, d3); radii are effective (a surface's radius less
the height of the pivot of the part sliding on it) and capacities measured along them
(d (R − h)/R for a nominal d). With μ2 = μ3 ≤ μ1 ≤ μ4 its backbone passes five
regimes (Fenz & Constantinou 2008, Earthquake Spectra 24(4), Table 1), with the force per unit
normal load φ = F/N:

    I    sliding on 2 and 3   slope du/dφ = R2 + R3   from φ = μ2 (μ3)
    II   sliding on 1 and 3               R1 + R3   from φ = μ1
    III  sliding on 1 and 4               R1 + R4   from φ = μ4
    IV   sliding on 2 and 4               R2 + R4   from φ = μ1 + d1/R1 (surface 1 at its rim)
    V    sliding on 2 and 3               R2 + R3   from φ = μ4 + d4/R4 (surface 4 at its rim)

until the inner slider reaches its rims, φ = μ2 + d2/R2 + d1/R1 (= μ3 + d3/R3 + d4/R4 for a
symmetric bearing), at the total displacement d1 + d2 + d3 + d4. The outer plates turn with
their slide (surface 2 lies on the plate that slides on 1), so surface 2 carries φ = μ2 +
u2/R2 + u1/R1: it stops while 1 slides. The same backbone comes from four single pendulums in
series (the series model of Fenz & Constantinou 2008, Earthquake Spectra 24(4), with its
modified parameters), the same force φN passing through each:

    element   radius R̄        friction   capacity d̄
    1         R1 − R2         μ1         d1 (1 − R2/R1)
    2         R2              μ2         d2 + d1 R2/R1
    3         R3              μ3         d3 + d4 R3/R4
    4         R4 − R3         μ4         d4 (1 − R3/R4)

(an element k slides once φ > μ_k and holds s_k = R̄_k (φ − μ_k) on the backbone; the sums
over the regimes are Table 1's slopes). The capacities d̄ hold while each inner surface's rim
lies past its slide before its outer neighbour moves, d2/R2 ≥ μ1 − μ2 and d3/R3 ≥ μ4 − μ3 (the
published order); a bearing outside it is refused. In the plane every element is a bidirectional
friction pendulum with internal slip s_k ∈ R² (8 states per bearing, after the deck's [q, q̇])
in series with one elastic stage: a spring of stiffness κ_e N, κ_e = min μ / u_y (the yield
displacement u_y: the elastic slip at which the first surface slides), and a dashpot c_e N
across it, c_e = 2 ζ_e √(κ_e/g) (ζ_e the stage's damping ratio, ZETA_E by default; undamped,
its stored energy became motion at every break-away and the peaks converged as √u_y):

    φ = κ_e e + c_e ė,  e = u − Σ_k s_k,   g_k = φ − s_k/R̄_k − κ_s,k ⟨|s_k| − d̄_k⟩ s_k/|s_k|
    ṡ_k = ⟨|g_k| − μ_k⟩ / (κ_e τ) · g_k/|g_k|        (elastic–viscoplastic flow, Perzyna)

a rigid-plastic element (|g_k| ≤ μ_k: stuck) regularised by the relaxation time
τ = OVERSTRESS u_y / (1 m/s): sliding at |ṡ| raises an element's friction by OVERSTRESS min μ
|ṡ| / (1 m/s). A surface's friction may rise with its slip speed, μ_k(w) = μ_fast,k −
(μ_fast,k − μ_k) exp(−a w) (velocity strengthening, μ_fast,k ≥ μ_k): the flow's speed w = |ṡ_k|
then solves |g_k| = μ_k(w) + κ_e τ w (one root, by Newton from w = 0). w is the element's
slip rate, not its surface's speed (element 1 slides at (R1 − R2)/R1 of surface 1's, and in
regime III elements 2 and 3 slide with surfaces 2 and 3 at rest): the series model is exact
for rate-independent friction and, with μ(v), an approximation of the bearing. The rim of element k
is a stiff radial stop κ_s,k = STOP_FACTOR / R̄_k. The bearing resists with F = N φ (with the
dashpot φ is implicit, ė depending on the flows: :mod:`nsdyn.models.isolated._ktfp`); the
deck's kernels read these rows from the bearing table (:mod:`nsdyn.models.isolated.bearings`,
columns B_KIND … B_ELEM + 15, B_EFAST … B_ERATE, B_CEL). The switch law's stick
events do not cover the series model: a TFP runs with the regularised law (Radau IIA).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nsdyn.models.isolated.bearings import (
    B_CEL,
    B_DCAP,
    B_EFAST,
    B_ELEM,
    B_ERATE,
    B_KEL,
    B_KIND,
    B_MUFAST,
    B_MUS,
    B_MUSLOW,
    B_RINV,
    B_TAU,
    KIND_TFP,
    MU_S_FLOOR,
    N_BCOL,
    RADIUS_PLAUSIBLE,
    Bearing,
    BearingError,
    Friction,
    _number,
    scene_coefficients,
)

U_Y = 2.5e-4  # m, default yield displacement (the elastic slip before the first surface slides)
ZETA_E = 1.0  # default damping ratio of the elastic stage (its dashpot c_e = 2 ζ_e √(κ_e/g))
# the largest: over its first 1.5 s the bundled TFP deck's peak |u| held within 1.4 % from
# zeta_e = 0 to 1e5 and scattered past it (0.0349 m at 3e5, 0.0551 m at 1e6 for 0.029 m, with
# exit 0); over the whole record 1e3 and 1e4 stop at 12.55 s, saying so (exit 3)
ZETA_E_MAX = 1e4
OVERSTRESS = 3e-2  # s/m: friction raised by this x min mu per m/s of an element's slip speed
STOP_FACTOR = 1e3  # an element's rim stiffness (per unit N) / its pendulum stiffness 1/R̄
N_INTERNAL = 8  # internal states per bearing: (s_x, s_y) of its four series elements
TFP_KEYS = ("R1", "R2", "R3", "R4", "mu1", "mu2", "mu3", "mu4", "d1", "d2", "d3", "d4")
TFP_OPTIONAL = ("u_y", "zeta_e", "rate", "mu_fast1", "mu_fast2", "mu_fast3", "mu_fast4")


@dataclass(frozen=True)
class TripleBearing(Bearing):
    """A triple friction pendulum: effective radii ``R1`` … ``R4`` [m] (surfaces 1, 4 outer,
    2, 3 of the inner slider; R1 > R2, R4 > R3), friction ``mu1`` … ``mu4`` (the inner
    surfaces' no larger than the outer ones), displacement capacities ``d1`` … ``d4`` [m]
    (the outer ones no smaller than the inner ones), yield displacement ``u_y`` [m], damping
    ratio ``zeta_e`` of the elastic stage (default ZETA_E; 0: undamped). Velocity-dependent
    friction: ``mu_fast1`` … ``mu_fast4`` (each ≥ its ``mu_j``; None: ``mu_j``) and ``rate``
    a [s/m] of μ_j(v) = μ_fast_j − (μ_fast_j − μ_j) exp(−a |v|). The
    friction, radius and capacity of the base class are derived: min μ, R1 + R4 (the
    restoring force N u/(R1 + R4) reported apart from the rest of the bearing's force) and
    d1 + d2 + d3 + d4; giving any of them, or ``k_lam``, ``c``, ``area`` or ``p_ref`` (no
    rubber, damper or pressure dependence), raises a BearingError naming it."""

    friction: Friction | None = None
    R1: float | None = None
    R2: float | None = None
    R3: float | None = None
    R4: float | None = None
    mu1: float | None = None
    mu2: float | None = None
    mu3: float | None = None
    mu4: float | None = None
    d1: float | None = None
    d2: float | None = None
    d3: float | None = None
    d4: float | None = None
    u_y: float = U_Y
    zeta_e: float = ZETA_E
    rate: float = 0.0
    mu_fast1: float | None = None
    mu_fast2: float | None = None
    mu_fast3: float | None = None
    mu_fast4: float | None = None

    def __post_init__(self) -> None:
        w = self.where
        if self.area is not None or self.p_ref is not None:
            k = "area" if self.area is not None else "p_ref"  # (the field given, named)
            raise BearingError(f"{w}.{k}: pressure-dependent friction is not modelled for a "
                               "triple friction pendulum")  # fmt: skip
        if self.k_lam != 0.0 or self.c != 0.0:
            k = "k_lam" if self.k_lam != 0.0 else "c"
            raise BearingError(f"{w}.{k}: a triple friction pendulum has no rubber or damper "
                               "(k_lam = c = 0)")  # fmt: skip
        derived = getattr(self.friction, "_tfp", False)  # (a copy by dataclasses.replace)
        given = {"friction": self.friction is not None, "radius": self.radius != math.inf,
                 "d_cap": self.d_cap != math.inf}  # fmt: skip
        for k in [k for k, v in given.items() if v and not derived]:  # (dropped before)
            raise BearingError(f"{w}.{k}: derived from the surfaces (mu1..mu4, R1..R4, d1..d4) "
                               "of a triple friction pendulum; drop it")  # fmt: skip
        vals = {}
        for k in TFP_KEYS:
            v = getattr(self, k)
            if v is None:
                raise BearingError(f"{w}.{k}: missing; a triple friction pendulum needs "
                                   "R1..R4 [m], mu1..mu4 and d1..d4 [m]")  # fmt: skip
            vals[k] = _number(f"{w}.{k}", v, positive=k[0] in "Rd")
        _number(f"{w}.u_y", self.u_y, positive=True)
        if not 0.0 <= _number(f"{w}.zeta_e", self.zeta_e) <= ZETA_E_MAX:
            raise BearingError(f"{w}.zeta_e: expected a damping ratio of the elastic stage "
                               f"in [0, {ZETA_E_MAX:g}] (0: undamped), got "
                               f"{self.zeta_e:g}")  # fmt: skip
        _number(f"{w}.rate", self.rate)
        if self.rate > 0 and all(getattr(self, f"mu_fast{j}") is None for j in range(1, 5)):
            raise BearingError(f"{w}.rate: the rate of the change from mu_j to mu_fast_j; "
                               "expected mu_fast1..4 beside it (or no rate)")  # fmt: skip
        for j in range(1, 5):
            fast = getattr(self, f"mu_fast{j}")
            if fast is not None and fast != vals[f"mu{j}"] and not self.rate > 0:
                raise BearingError(f"{w}.rate: mu_fast{j} ({fast:g}) differs from mu{j} "
                                   f"({vals[f'mu{j}']:g}), which needs a positive rate a [s/m] "
                                   "of mu(v) = mu_fast - (mu_fast - mu) exp(-a |v|); got "
                                   f"{self.rate:g}")  # fmt: skip
            if fast is not None and _number(f"{w}.mu_fast{j}", fast) < vals[f"mu{j}"]:
                raise BearingError(
                    f"{w}.mu_fast{j}: expected mu_fast{j} >= mu{j} = {vals[f'mu{j}']:g} (a TFP "
                    f"surface's friction rises with the slip speed), got {fast:g}"
                )
        for outer, inner in (("R1", "R2"), ("R4", "R3")):
            if not vals[outer] > vals[inner]:
                if vals[inner] > RADIUS_PLAUSIBLE:  # (R2 = 300 in mm, say: R1 was blamed)
                    raise BearingError(
                        f"{w}.{inner}: {inner} = {vals[inner]:g} m is above the "
                        f"{RADIUS_PLAUSIBLE:g} m of built pendulums and not below {outer} = "
                        f"{vals[outer]:g} m; expected the inner slider's radius in m"
                    )
                raise BearingError(
                    f"{w}.{outer}: expected {outer} > {inner} = {vals[inner]:g} m (an outer "
                    f"surface flatter than the inner slider's), got {vals[outer]:g}"
                )
        for inner in ("mu2", "mu3"):
            if vals[inner] <= 0.0:
                raise BearingError(f"{w}.{inner}: expected a positive friction coefficient, "
                                   f"got {vals[inner]:g}")  # fmt: skip
            lim = min(vals["mu1"], vals["mu4"])
            if vals[inner] > lim:
                raise BearingError(
                    f"{w}.{inner}: expected the inner slider's friction <= mu1 and mu4 "
                    f"({lim:g}) (it slides first), got {vals[inner]:g}"
                )
        for outer in ("d1", "d4"):
            big = "d2" if vals["d2"] >= vals["d3"] else "d3"
            if vals[outer] < vals[big]:
                raise BearingError(
                    f"{w}.{outer}: expected a displacement capacity >= the inner ones' "
                    f"({big} = {vals[big]:g} m), got {outer} = {vals[outer]:g} m"
                )
        for j in range(1, 5):  # a capacity is an arc on its sphere: short of its radius
            if vals[f"d{j}"] >= vals[f"R{j}"]:
                raise BearingError(
                    f"{w}.d{j}: expected a displacement capacity below the surface's radius "
                    f"R{j} = {vals[f'R{j}']:g} m (a slip of d/R rad on its sphere), got "
                    f"{vals[f'd{j}']:g} m"
                )
        for inner, outer in (("2", "1"), ("3", "4")):  # (the series model's regime order)
            reach = vals[f"R{inner}"] * (vals[f"mu{outer}"] - vals[f"mu{inner}"])
            if vals[f"d{inner}"] < reach * (1 - 1e-9) and vals[f"mu{outer}"] <= 1.0:  # (else
                # misplaced rims, 14 mm off; a mu above 1, a percentage, has its own note)
                raise BearingError(
                    f"{w}.d{inner}: the inner surface {inner} would reach its rim before "
                    f"surface {outer} slides (d{inner} = {vals[f'd{inner}']:g} m < R{inner} "
                    f"(mu{outer} - mu{inner}) = {reach:.4g} m), outside the regime order of the "
                    f"series model (Fenz & Constantinou) this bearing follows; expected "
                    f"d{inner} >= {reach:.4g} m"
                )
        d_bar = float(self.elements()[:, 2].min())  # the series elements' capacities
        if self.u_y >= d_bar:  # the stage stands for the surfaces' stick, far inside them
            raise BearingError(
                f"{w}.u_y: expected a yield displacement below every series element's capacity "
                f"(min d̄ = {d_bar:g} m; the elastic slip before the first surface slides, "
                f"default {U_Y:g} m), got {self.u_y:g} m"
            )
        mu_min = min(vals[f"mu{j}"] for j in range(1, 5))
        friction = Friction(mu_min, where=w)
        object.__setattr__(friction, "_tfp", True)
        object.__setattr__(self, "friction", friction)
        object.__setattr__(self, "radius", vals["R1"] + vals["R4"])
        object.__setattr__(self, "d_cap", sum(vals[f"d{j}"] for j in range(1, 5)))

    def coefficients(self) -> dict:
        """The surfaces' friction coefficients given, by their field names."""
        names = [f"mu{j}" for j in range(1, 5)] + [f"mu_fast{j}" for j in range(1, 5)]
        return {f"{self.where}.{k}": float(getattr(self, k)) for k in names
                if getattr(self, k) is not None}  # fmt: skip

    def fast(self) -> list:
        """μ_fast of surfaces 1..4 (their μ where not given)."""
        return [float(getattr(self, f"mu{j}") if getattr(self, f"mu_fast{j}") is None
                      else getattr(self, f"mu_fast{j}")) for j in range(1, 5)]  # fmt: skip

    def elements(self) -> np.ndarray:
        """(4, 3) rows (R̄, μ, d̄) of the series model (see the module text)."""
        R1, R2, R3, R4 = (float(getattr(self, f"R{j}")) for j in range(1, 5))
        d1, d2, d3, d4 = (float(getattr(self, f"d{j}")) for j in range(1, 5))
        mu = [float(getattr(self, f"mu{j}")) for j in range(1, 5)]
        return np.array([
            [R1 - R2, mu[0], d1 * (1.0 - R2 / R1)],
            [R2, mu[1], d2 + d1 * R2 / R1],
            [R3, mu[2], d3 + d4 * R3 / R4],
            [R4 - R3, mu[3], d4 * (1.0 - R3 / R4)],
        ])  # fmt: skip

    @property
    def k_elastic(self) -> float:
        """κ_e [1/m]: the elastic stiffness per unit normal force."""
        return float(self.friction.mu_slow) / float(self.u_y)

    def backbone(self, phi) -> np.ndarray:
        """Total slip u [m] of the rigid-plastic series model at force ratio φ = F/N on
        monotonic loading from rest: sign(φ) Σ_k R̄_k clip(|φ| − μ_k, 0, d̄_k/R̄_k) (odd in φ:
        loading the other way slides the other way). Past the last regime every surface is at
        its rim: u stays at Σ d̄_k, the bearing's capacity (its rim stops take more force)."""
        phi = np.asarray(phi, dtype=float)
        if not np.all(np.isfinite(phi)):  # (NaN came back as NaN, unsaid)
            raise ValueError(f"phi: expected finite force ratios F/N, got {phi.tolist()!r}")
        a = np.abs(phi)
        u = np.zeros_like(phi)
        for R, mu, d in self.elements():
            u += R * np.clip(a - mu, 0.0, d / R)
        return np.sign(phi) * u

    def row(self, n_static: float, g: float) -> np.ndarray:
        """The packed row (the internal states' offset B_IOFF is set by the system)."""
        r = np.zeros(N_BCOL)
        r[B_RINV] = 1.0 / self.radius
        mu_min = float(self.friction.mu_slow)
        r[B_MUSLOW] = r[B_MUFAST] = mu_min
        r[B_MUS] = max(mu_min, MU_S_FLOOR)
        r[B_DCAP] = math.inf  # (the elements carry the rims; contacts read from their slips)
        r[B_KIND] = KIND_TFP
        r[B_KEL] = self.k_elastic
        r[B_TAU] = OVERSTRESS * float(self.u_y) / 1.0
        r[B_CEL] = 2.0 * float(self.zeta_e) * math.sqrt(self.k_elastic / g)
        for k, (R, mu, d) in enumerate(self.elements()):
            c = B_ELEM + 4 * k
            r[c], r[c + 1], r[c + 2], r[c + 3] = 1.0 / R, mu, d, STOP_FACTOR / R
        r[B_EFAST : B_EFAST + 4] = self.fast()
        r[B_ERATE] = self.rate
        return r


def tfp_from_config(cfg: dict, where: str) -> TripleBearing:
    """A :class:`TripleBearing` from a TOML table (``type = "tfp"``: R1..R4, mu1..mu4,
    d1..d4, optional u_y, zeta_e, rate and mu_fast1..4)."""
    other = sorted(set(cfg) - {"type", *TFP_KEYS, *TFP_OPTIONAL})
    if other:
        raise BearingError(f"{where}.{other[0]}: not a key of a triple friction pendulum "
                           f"(type = 'tfp': {', '.join(TFP_KEYS + TFP_OPTIONAL)})")  # fmt: skip
    scene_coefficients(
        cfg, where, [f"mu{j}" for j in range(1, 5)] + [f"mu_fast{j}" for j in range(1, 5)]
    )
    kw = {}
    for k in TFP_KEYS + TFP_OPTIONAL:
        if k in cfg:
            kw[k] = _number(f"{where}.{k}", cfg[k], positive=k[0] in "Rdu")
    return TripleBearing(where=where, **kw)


def surface_limits(res) -> list:
    """The rims reached by the series elements of every TFP of a run: dicts isolator,
    surface ("1", "2", "3", "4": the element of that surface), t_first_s, peak_overshoot_m
    (of the element's slip beyond its capacity d̄, output samples)."""
    out = []
    if res.internal is None or res.internal.shape[1] == 0:
        return out
    for i, b in enumerate(res.system.bearings):
        if not isinstance(b, TripleBearing):
            continue
        o = res.system.internal_offsets()[i] - 6
        for k, (_, _, d) in enumerate(b.elements()):
            s = res.internal[:, o + 2 * k : o + 2 * k + 2]
            over = np.hypot(s[:, 0], s[:, 1]) - d
            hit = np.flatnonzero(over > 0.0)
            if hit.size:
                out.append({"isolator": i, "surface": str(k + 1),
                            "t_first_s": float(res.t[hit[0]]),
                            "peak_overshoot_m": float(over.max())})  # fmt: skip
    return out


def beyond_capacity(res) -> list:
    """Every TFP whose resultant displacement passed its ultimate capacity d1 + d2 + d3 + d4:
    dicts isolator, peak_m, capacity_m, beyond_m. The surfaces' own overshoots
    (:func:`surface_limits`) stay small, because the stops hold each slip; the elastic
    element in series then carries the rim forces (F/N well above μ) and stretches, so the
    bearing's displacement beyond its capacity is larger than any surface's."""
    out = []
    for i, b in enumerate(res.system.bearings):
        if not isinstance(b, TripleBearing):
            continue
        peak = float(np.hypot(res.u[:, i, 0], res.u[:, i, 1]).max())
        if peak > b.d_cap:
            out.append({"isolator": i, "peak_m": peak, "capacity_m": float(b.d_cap),
                        "beyond_m": peak - float(b.d_cap)})  # fmt: skip
    return out


def surfaces_stuck(states: np.ndarray, t: np.ndarray, offsets: list, v_stick: float,
                   stick: np.ndarray) -> np.ndarray:  # fmt: skip
    """``stick`` (nt, ni) with each triple pendulum's column replaced by whether none of its
    surfaces slides: every series element's slip speed (central differences of its slips
    ``states[:, o + 2k : o + 2k + 2]`` on ``t``, ``o`` the isolator's entry of ``offsets``,
    -1 for a single surface) at most ``v_stick``. Its deck slip speed is no test: the elastic
    stage moves the mass while every surface is stuck."""
    out = np.array(stick, dtype=bool, copy=True)
    if t.size < 2:
        return out
    for i, o in enumerate(offsets):
        if o < 0:
            continue
        s = states[:, o : o + N_INTERNAL].reshape(t.size, 4, 2)
        rate = np.gradient(s, t, axis=0)
        out[:, i] = np.hypot(rate[..., 0], rate[..., 1]).max(axis=1) <= v_stick
    return out
