"""Winding thermal model: hot spot of a rectangular pack, self-consistent resistance, run time.

Each coil's winding pack (axial width w, radial depth d, mean radius R_m) is a homogeneous
conductor with uniform heat generation q''' = P / V (V = w d · 2π R_m per coil) and an effective
transverse conductivity k. It loses heat from its four faces (A = 2(w + d) · 2π R_m per coil)
by convection h and grey-body
radiation ε σ (T_s⁴ - T_a⁴); no conduction into the frame. Every function is written once
against :mod:`spiralcap.backend` (floats, numpy arrays, CasADi) with no branch on data values;
the two coils of a pair are identical, so a pair is handled with its total area, volume, heat
capacity and loss (the intensive results are the same per coil).

Hot spot. For a square section with isothermal faces and uniform q''' the centre lies
``KAPPA_CENTRE q''' c²/k`` above the faces and the section mean ``KAPPA_MEAN q''' c²/k``;
a w x d rectangle has ``κ(w/d) q''' w d/k`` from the same series
(:func:`rectangle_pack_coefficients`, equal to the square numbers at w = d)
(Carslaw & Jaeger, *Conduction of Heat in Solids*, 2nd ed., 1959, §6.3; the same Poisson
problem as Saint-Venant torsion of a square bar, Timoshenko & Goodier, *Theory of Elasticity*,
1970, §109: centre 0.0737, mean 0.0351 = J/(4 a⁴) with J = 0.1406 a⁴). The faces are taken
isothermal at the mean surface temperature the energy balance gives; for a Biot number
h c/k of order 1 the exact (Robin) centre rise lies between this and the uniform-flux value
1/12 = 0.0833, so the hot spot may be up to 13 % of the internal rise higher (docs/coils.md).

Resistance. Copper resistivity is linear in temperature, so the resistance of a pack equals
that at its mean temperature; the loss P = R(T_mean) I²/2 is solved together with the heating.

Run time. A lumped transient from ambient: heat capacity C (copper and impregnation) at the
mean temperature, losing heat through the internal mean-to-surface resistance in series with
the surface conductance G = A (h + h_r); radiation is linearised as the secant coefficient h_r
at the surface temperature of the steady limit state (exact there). The loss rises linearly with
the mean temperature, so the mean rise is an exact exponential with time constant
τ = C / (1/R_th - α R20 I²/2). The hot spot is taken as the mean plus the *steady* centre-to-mean
offset for the instantaneous loss from the first second (the gradient diffuses in
c²/(2π² a_th) ≈ 14 min for the built-in packs, shorter than τ): conservative early on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from spiralcap import backend as bk
from spiralcap.constants import (
    COPPER_RESISTIVITY_20C_ohm_m,
    COPPER_TEMPERATURE_COEFFICIENT_per_K,
)

__all__ = [
    "KAPPA_CENTRE",
    "KAPPA_MEAN",
    "COPPER_VOLUMETRIC_HEAT_CAPACITY_J_m3K",
    "IMPREGNATION_VOLUMETRIC_HEAT_CAPACITY_J_m3K",
    "LimitState",
    "STEFAN_BOLTZMANN_W_m2K4",
    "SteadyState",
    "Transient",
    "WindingPack",
    "limit_state",
    "radiation_coefficient_W_m2K",
    "rectangle_pack_coefficients",
    "square_pack_coefficients",
    "steady_state",
    "surface_loss_W",
    "transient",
]

#: Stefan-Boltzmann constant, W/(m²·K⁴) (CODATA 2018, exact).
STEFAN_BOLTZMANN_W_m2K4 = 5.670374419e-8
#: Copper: density 8960 kg/m³ times specific heat 385 J/(kg·K) (CRC Handbook, 97th ed.).
COPPER_VOLUMETRIC_HEAT_CAPACITY_J_m3K = 8960.0 * 385.0
#: The rest of the pack taken as epoxy impregnation/enamel: 1200 kg/m³ x 1100 J/(kg·K)
#: (typical cured epoxy; air voids would lower it, which shortens τ: see docs/coils.md).
IMPREGNATION_VOLUMETRIC_HEAT_CAPACITY_J_m3K = 1200.0 * 1100.0
_KELVIN = 273.15
_NEWTON_STEPS = 10


def square_pack_coefficients(terms: int = 60) -> tuple[float, float]:
    """Centre and mean rise of a square of side a, isothermal faces, in units of q''' a²/k.

    Series solution of ∇²θ = -q'''/k on |x|, |y| <= b = a/2 with θ = 0 on the faces
    (Carslaw & Jaeger 1959, §6.3), λ_n = (2n+1)π/(2b):
    θ(0,0) = b²/2 - Σ 2(-1)^n / (b λ_n³ cosh λ_n b) and
    mean θ = b²/3 - Σ 2 tanh(λ_n b) / (b³ λ_n⁵), both times q'''/k, divided by a² = 4b².
    """
    b = 0.5
    centre = b * b / 2.0
    mean = b * b / 3.0
    for n in range(terms):
        lam = (2 * n + 1) * math.pi / (2.0 * b)
        centre -= 2.0 * (-1) ** n / (b * lam**3 * math.cosh(lam * b))
        mean -= 2.0 * math.tanh(lam * b) / (b**3 * lam**5)
    return centre, mean


#: Centre and mean rise coefficients of the square pack (0.07367, 0.03514).
KAPPA_CENTRE, KAPPA_MEAN = square_pack_coefficients()
#: Series terms of :func:`rectangle_pack_coefficients`: summed along the shorter side each term
#: falls by e^{-π} at least, so 12 terms are exact to machine precision.
_RECT_TERMS = 12
#: Σ_{n>=0} (2n+1)^-5 = (31/32) ζ(5), ζ(5) = 1.0369277551433699 (Abramowitz & Stegun 23.2).
_ODD_ZETA5 = 31.0 / 32.0 * 1.0369277551433699263


def rectangle_pack_coefficients(width: Any, depth: Any) -> tuple[Any, Any]:
    """Centre and mean rise of a w x d rectangle, isothermal faces, in units of q''' w d/k.

    The series of :func:`square_pack_coefficients` on |x| <= a, |y| <= b with a the shorter
    half-side (it then converges as e^{-(2n+1)π b/(2a)}), λ_n = (2n+1)π/(2a):
    θ(0,0) = a²/2 - Σ 2(-1)^n / (a λ_n³ cosh λ_n b) and
    mean θ = a²/3 - Σ 2 tanh(λ_n b) / (a² b λ_n⁵), both divided by w d = 4ab (Carslaw &
    Jaeger 1959, §6.3). The value is symmetric in w, d and smooth; min/max only choose the
    way to sum it (backend-generic). At w = d it equals :data:`KAPPA_CENTRE`, :data:`KAPPA_MEAN`.
    """
    a = 0.5 * bk.fmin(width, depth)
    b = 0.5 * bk.fmax(width, depth)
    centre = a * a / 2.0
    # Σ 1/λ_n⁵ = (2a/π)⁵ Σ 1/(2n+1)⁵ = (2a/π)⁵ (31/32) ζ(5) in closed form; tanh = 1 - (1 - tanh)
    # leaves an exponentially convergent remainder
    mean = a * a / 3.0 - 2.0 / (a * a * b) * (2.0 * a / math.pi) ** 5 * _ODD_ZETA5
    for n in range(_RECT_TERMS):
        lam = (2 * n + 1) * math.pi / (2.0 * a)
        e = bk.exp(-2.0 * lam * b)  # overflow-safe sech and 1 - tanh
        sech = 2.0 * bk.sqrt(e) / (1.0 + e)
        centre = centre - 2.0 * (-1) ** n / (a * lam**3) * sech
        mean = mean + 2.0 / (a * a * b * lam**5) * (2.0 * e / (1.0 + e))
    return centre / (4.0 * a * b), mean / (4.0 * a * b)


@dataclass(frozen=True)
class WindingPack:
    """Thermal description of one pair's two identical rectangular winding packs (SI).

    Fields may be floats, numpy arrays or CasADi values (sizing with free geometry).

    Parameters
    ----------
    pack_width_m : axial width w of each winding pack, m.
    pack_depth_m : radial depth d of each winding pack, m.
    mean_radius_m : mean radius of each coil, m.
    packing_factor : copper area / pack area.
    conductivity_W_mK : effective transverse conductivity k of the pack, W/(m·K).
    heat_transfer_coefficient_W_m2K : convective coefficient h at the faces, W/(m²·K).
    emissivity : grey-body emissivity ε of the faces.
    coils : number of identical coils (2 for a pair).
    """

    pack_width_m: Any
    pack_depth_m: Any
    mean_radius_m: Any
    packing_factor: Any
    conductivity_W_mK: Any
    heat_transfer_coefficient_W_m2K: Any
    emissivity: Any
    coils: int = 2

    @property
    def surface_area_m2(self) -> Any:
        """Outer faces of all coils, coils · 2(w + d) · 2π R_m (Pappus), m²."""
        perimeter = 2.0 * (self.pack_width_m + self.pack_depth_m)
        return self.coils * perimeter * 2.0 * bk.pi * self.mean_radius_m

    @property
    def section_m2(self) -> Any:
        """Cross-section w d of one pack, m²."""
        return self.pack_width_m * self.pack_depth_m

    @property
    def volume_m3(self) -> Any:
        """Pack volume of all coils, coils · w d · 2π R_m, m³."""
        return self.coils * self.section_m2 * 2.0 * bk.pi * self.mean_radius_m

    @property
    def poisson_coefficients(self) -> tuple[Any, Any]:
        """(centre, mean) rise of the section in units of q''' w d/k."""
        return rectangle_pack_coefficients(self.pack_width_m, self.pack_depth_m)

    @property
    def heat_capacity_J_per_K(self) -> Any:
        """Lumped heat capacity, V (pf ρc_Cu + (1 - pf) ρc_impregnation), J/K."""
        pf = self.packing_factor
        return self.volume_m3 * (
            pf * COPPER_VOLUMETRIC_HEAT_CAPACITY_J_m3K
            + (1.0 - pf) * IMPREGNATION_VOLUMETRIC_HEAT_CAPACITY_J_m3K
        )

    @property
    def centre_resistance_K_per_W(self) -> Any:
        """Hot-spot rise above the faces per watt of pack loss, κ_c w d/(k V), K/W."""
        kappa = self.poisson_coefficients[0]
        return kappa * self.section_m2 / (self.conductivity_W_mK * self.volume_m3)

    @property
    def mean_resistance_K_per_W(self) -> Any:
        """Mean rise above the faces per watt of pack loss, κ_m w d/(k V), K/W."""
        kappa = self.poisson_coefficients[1]
        return kappa * self.section_m2 / (self.conductivity_W_mK * self.volume_m3)


def radiation_coefficient_W_m2K(surface_C: Any, ambient_C: Any, emissivity: Any) -> Any:
    """Secant radiation coefficient ε σ (T_s² + T_a²)(T_s + T_a), W/(m²·K).

    Exact in the sense h_r (T_s - T_a) = ε σ (T_s⁴ - T_a⁴) (grey surface in a large enclosure
    at ambient; Incropera & DeWitt, *Fundamentals of Heat and Mass Transfer*, 6th ed., eq. 1.9).
    """
    ts, ta = surface_C + _KELVIN, ambient_C + _KELVIN
    return emissivity * STEFAN_BOLTZMANN_W_m2K4 * (ts * ts + ta * ta) * (ts + ta)


def surface_loss_W(pack: WindingPack, surface_C: Any, ambient_C: Any) -> Any:
    """Heat the faces shed at a surface temperature: A [h (T_s - T_a) + ε σ (T_s⁴ - T_a⁴)], W."""
    h_r = radiation_coefficient_W_m2K(surface_C, ambient_C, pack.emissivity)
    return (
        pack.surface_area_m2
        * (pack.heat_transfer_coefficient_W_m2K + h_r)
        * (surface_C - ambient_C)
    )


def _surface_loss_slope_W_per_K(pack: WindingPack, surface_C: Any) -> Any:
    ts = surface_C + _KELVIN
    return pack.surface_area_m2 * (
        pack.heat_transfer_coefficient_W_m2K
        + 4.0 * pack.emissivity * STEFAN_BOLTZMANN_W_m2K4 * ts * ts * ts
    )


def _where(condition: Any, if_true: Any, if_false: Any) -> Any:
    """:func:`spiralcap.backend.where`, a Python float where numpy gives a 0-d array.

    Same values; the Newton loops that follow run several times faster on scalars than on 0-d
    arrays (the evaluation paths call them thousands of times).
    """
    return _plain(bk.where(condition, if_true, if_false))


def _plain(x: Any) -> Any:
    """A Python float for a numpy scalar or 0-d array (same value), anything else as it is."""
    if isinstance(x, np.generic) or (isinstance(x, np.ndarray) and x.ndim == 0):
        return float(x)
    return x


class _Faces:
    """:func:`surface_loss_W` and its slope with the pack's invariants computed once.

    The Newton loops below evaluate both a dozen times per solve; the same operations in the
    same order as :func:`surface_loss_W` / :func:`_surface_loss_slope_W_per_K` (bit-identical
    numbers), but the face area, ``ε σ``, ``4 ε σ`` and ``T_a`` enter the CasADi graph once.
    """

    def __init__(self, pack: WindingPack, ambient_C: Any) -> None:
        self.area = pack.surface_area_m2
        self.h = pack.heat_transfer_coefficient_W_m2K
        self.eps_sigma = pack.emissivity * STEFAN_BOLTZMANN_W_m2K4
        self.four_eps_sigma = 4.0 * pack.emissivity * STEFAN_BOLTZMANN_W_m2K4
        self.ambient_C = ambient_C
        self.ta = ambient_C + _KELVIN
        self.ta2 = self.ta * self.ta

    def loss_W(self, surface_C: Any) -> Any:
        ts, ta = surface_C + _KELVIN, self.ta
        h_r = self.eps_sigma * (ts * ts + self.ta2) * (ts + ta)
        return self.area * (self.h + h_r) * (surface_C - self.ambient_C)

    def slope_W_per_K(self, surface_C: Any) -> Any:
        ts = surface_C + _KELVIN
        return self.area * (self.h + self.four_eps_sigma * ts * ts * ts)


@dataclass(frozen=True)
class LimitState:
    """The steady state whose hot spot sits exactly at the limit (temperatures °C, loss W)."""

    surface_C: Any
    mean_C: Any
    hot_spot_C: Any
    power_W: Any


def limit_state(pack: WindingPack, hot_spot_C: Any, ambient_C: Any) -> LimitState:
    """Steady state with the hot spot at ``hot_spot_C``: the most loss the pack can shed.

    Solves r_c Q(T_s) = T_hot - T_s for the surface temperature (Q the surface loss, r_c the
    centre resistance) by Newton's method from T_s = T_hot; the residual is convex and
    increasing, so the iterates fall monotonically onto the root (10 fixed steps, no branch; 6 reach machine precision near the root).

    Parameters
    ----------
    pack : WindingPack
    hot_spot_C : float, array or CasADi
        Hot-spot temperature, °C (the limit).
    ambient_C : float, array or CasADi
        Ambient air, °C.
    """
    r_c = pack.centre_resistance_K_per_W
    faces = _Faces(pack, ambient_C)
    ts = hot_spot_C + 0.0 * r_c
    for _ in range(_NEWTON_STEPS):
        resid = r_c * faces.loss_W(ts) + ts - hot_spot_C
        ts = ts - resid / (r_c * faces.slope_W_per_K(ts) + 1.0)
    power = faces.loss_W(ts)
    return LimitState(
        surface_C=ts,
        mean_C=ts + pack.mean_resistance_K_per_W * power,
        hot_spot_C=ts + r_c * power,
        power_W=power,
    )


def _resistance_ohm(resistance_20C_ohm: Any, temperature_C: Any) -> Any:
    return resistance_20C_ohm * (
        1.0 + COPPER_TEMPERATURE_COEFFICIENT_per_K * (temperature_C - 20.0)
    )


@dataclass(frozen=True)
class SteadyState:
    """Steady temperatures (°C), loss (W) and resistance (Ω) at one current amplitude.

    ``runaway`` is 1 where no steady state was found: the internal loss outgrows conduction
    (α R20 I²/2 · r_mean >= 1) or the Newton iterates (which approach the root from above) had
    not converged, i.e. temperatures of thousands of °C. The other fields are then finite upper
    bounds (far beyond any limit), so limits built on them stay violated and smooth.
    """

    surface_C: Any
    mean_C: Any
    hot_spot_C: Any
    power_W: Any
    resistance_ohm: Any
    runaway: Any


def steady_state(
    pack: WindingPack, resistance_20C_ohm: Any, current_amplitude_A: Any, ambient_C: Any
) -> SteadyState:
    """Self-consistent steady state of a pair carrying a sinusoid of amplitude I.

    The loss P = R(T_mean) I²/2 with T_mean = T_s + r_m P is linear-fractional in T_s; the
    surface balance Q(T_s) = P(T_s) is solved by Newton's method from the root of its tangent
    at ambient (an upper bound, Q being convex), 10 fixed steps.

    Parameters
    ----------
    pack : WindingPack
    resistance_20C_ohm : float, array or CasADi
        Pair resistance at 20 °C, Ω.
    current_amplitude_A : float, array or CasADi
        Current amplitude (peak), A.
    ambient_C : float
        Ambient air, °C.
    """
    resistance_20C_ohm, current_amplitude_A, ambient_C = (
        _plain(x) for x in (resistance_20C_ohm, current_amplitude_A, ambient_C)
    )
    alpha = COPPER_TEMPERATURE_COEFFICIENT_per_K
    half_i2 = 0.5 * current_amplitude_A * current_amplitude_A
    r_m = pack.mean_resistance_K_per_W
    denom = 1.0 - alpha * resistance_20C_ohm * half_i2 * r_m
    ok_denom = denom > 0.0
    safe = _where(ok_denom, denom, 1.0)
    p_amb = _resistance_ohm(resistance_20C_ohm, ambient_C) * half_i2 / safe  # P at T_s = T_a
    slope = alpha * resistance_20C_ohm * half_i2 / safe  # dP/dT_s
    faces = _Faces(pack, ambient_C)
    g0 = faces.slope_W_per_K(ambient_C + 0.0 * slope) - slope
    ok_start = g0 > 0.0
    ts = ambient_C + p_amb / _where(ok_start, g0, 1.0)
    ts = _where(ok_start, ts, ambient_C + 5000.0)
    for _ in range(_NEWTON_STEPS):
        p = p_amb + slope * (ts - ambient_C)
        resid = faces.loss_W(ts) - p
        ts = ts - resid / (faces.slope_W_per_K(ts) - slope)
    p = p_amb + slope * (ts - ambient_C)
    resid = faces.loss_W(ts) - p
    converged = bk.abs(resid) <= 1e-9 * bk.fmax(p, 1e-12) + 1e-12
    stable = faces.slope_W_per_K(ts) - slope > 0.0  # cooling outgrows heating
    valid = ok_denom * converged * stable * (ts >= ambient_C - 1e-9)
    runaway = _where(valid, 0.0, 1.0)
    ts = _where(valid, ts, ambient_C + 1e4)  # runaway: a bound far above any limit
    p = _where(valid, p, faces.loss_W(ts))
    mean = ts + r_m * p
    return SteadyState(
        surface_C=ts,
        mean_C=mean,
        hot_spot_C=ts + pack.centre_resistance_K_per_W * p,
        power_W=p,
        resistance_ohm=_resistance_ohm(resistance_20C_ohm, mean),
        runaway=runaway,
    )


def _relative_growth(x: Any) -> Any:
    """(1 - e^{-x}) / x, continuous through x = 0 and overflow-safe (x >= -50 is used)."""
    x = bk.fmax(x, -50.0)
    small = bk.abs(x) < 1e-4
    xs = _where(small, 1.0, x)
    return _where(small, 1.0 - 0.5 * x + x * x / 6.0, (1.0 - bk.exp(-xs)) / xs)


@dataclass(frozen=True)
class Transient:
    """Lumped heating from ambient at time ``time_s`` (temperatures °C, W, s, J/K).

    ``time_constant_s`` is τ of the exponential the mean rise follows; ``final_*`` are the
    temperatures it tends to (the linearised steady state).
    """

    time_s: Any
    surface_C: Any
    mean_C: Any
    hot_spot_C: Any
    power_W: Any
    time_constant_s: Any
    heat_capacity_J_per_K: Any
    final_mean_C: Any
    final_hot_spot_C: Any


def transient(
    pack: WindingPack,
    resistance_20C_ohm: Any,
    current_amplitude_A: Any,
    ambient_C: Any,
    time_s: Any,
    radiation_surface_C: Any,
) -> Transient:
    """Lumped heating of a pair switched on at ambient, after ``time_s`` seconds.

    C dθ/dt = P_a + p₁ θ - θ / R_th with θ the mean rise, P_a = R(T_a) I²/2, p₁ = α R20 I²/2,
    R_th = r_m + 1/G, G = A (h + h_r(radiation_surface_C)). Hence θ(t) = (P_a/C) t φ(t/τ) with
    φ(x) = (1 - e^{-x})/x and τ = C / (1/R_th - p₁) (negative τ: thermal runaway, θ grows
    without bound). Surface θ_s = θ / (1 + G r_m); hot spot θ + (r_c - r_m) P.

    Parameters
    ----------
    pack : WindingPack
    resistance_20C_ohm : float, array or CasADi
        Pair resistance at 20 °C, Ω.
    current_amplitude_A : float, array or CasADi
        Current amplitude, A.
    ambient_C : float
        Ambient air and starting temperature, °C.
    time_s : float, array or CasADi
        Time since switch-on, s.
    radiation_surface_C : float, array or CasADi
        Surface temperature at which the radiation is linearised (secant), °C.
    """
    alpha = COPPER_TEMPERATURE_COEFFICIENT_per_K
    half_i2 = 0.5 * current_amplitude_A * current_amplitude_A
    p_a = _resistance_ohm(resistance_20C_ohm, ambient_C) * half_i2
    p1 = alpha * resistance_20C_ohm * half_i2
    g = pack.surface_area_m2 * (
        pack.heat_transfer_coefficient_W_m2K
        + radiation_coefficient_W_m2K(radiation_surface_C, ambient_C, pack.emissivity)
    )
    r_m, r_c = pack.mean_resistance_K_per_W, pack.centre_resistance_K_per_W
    r_th = r_m + 1.0 / g
    cap = pack.heat_capacity_J_per_K
    decay = 1.0 / r_th - p1  # W/K
    rise = p_a / cap * time_s * _relative_growth(time_s * decay / cap)
    power = p_a + p1 * rise
    final = p_a / decay
    return Transient(
        time_s=time_s,
        surface_C=ambient_C + rise / (1.0 + g * r_m),
        mean_C=ambient_C + rise,
        hot_spot_C=ambient_C + rise + (r_c - r_m) * power,
        power_W=power,
        time_constant_s=cap / decay,
        heat_capacity_J_per_K=cap,
        final_mean_C=ambient_C + final,
        final_hot_spot_C=ambient_C + final + (r_c - r_m) * (p_a + p1 * final),
    )


def pair_resistance_20C_ohm(wire_length_m: Any, wire_diameter_m: Any) -> Any:
    """Resistance of a wire at 20 °C, ρ20 ℓ / (π d²/4), Ω (IEC 60028)."""
    return COPPER_RESISTIVITY_20C_ohm_m * wire_length_m / (bk.pi * wire_diameter_m**2 / 4.0)
