"""Winding thermal model: packs that see each other, convection by correlation, conduction in time.

Each coil's winding pack (axial width w, radial depth d, mean radius R_m) is a homogeneous
conductor with uniform heat generation q''' = P / V (V = w d · 2π R_m per coil) and an
effective transverse conductivity k. Its four faces (A = 2 (w + d) · 2π R_m per coil) lose heat
by convection, h_c (T - T_a), and by grey-body radiation to the room and to the other packs,
ε σ [(1 - F_self) T⁴ - F_room T_a⁴ - Σ_j F_j T_j⁴] (:mod:`coils.viewfactors`: F from a ray
trace of the nested set; reflections between packs neglected, second order in 1 - ε). Nothing
is conducted to the frame. Every function is written once against :mod:`spiralcap.core.backend`
(floats, numpy arrays, CasADi) with no branch on data values; the two coils of a pair are
identical, so a pair is handled with its total area, volume, heat capacity and loss.

Convection: ``convection = "fixed"`` uses ``heat_transfer_coefficient_W_m2K`` exactly;
"natural" (the default of a design) the correlations of :mod:`coils.convection` at the
film temperature the solve reaches; "forced" adds air at ``air_speed_m_s``.

Conduction: the section is cooled on all four faces by the area-weighted h_eff = h_c + h_r
(radiation as its secant coefficient at the solved surface temperature, exact there), the
Robin problem of :mod:`coils.conduction` (steady: exact series; in time: modes). The hot spot
is its centre, the surface temperature its hottest face point.

Resistance. Copper resistivity is linear in temperature, so the resistance of a pack equals
that at its mean temperature; the loss P = R(T_mean) I²/2 is solved together with the heating.

Run time (:func:`transient`): conduction in the section from ambient with the same faces,
linearised at the surface temperature the session ends near, the source following the mean
temperature (:func:`coils.conduction.robin_transient`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from coils.conduction import robin_statics, robin_transient
from coils.convection import (
    _pack_convection_W_m2K,
    pack_convection_W_m2K,
    vertical_bar_convection_W_m2K,
)
from spiralcap.core import backend as bk
from spiralcap.core.constants import (
    COPPER_DENSITY_kg_m3,
    COPPER_RESISTIVITY_20C_ohm_m,
    COPPER_SPECIFIC_HEAT_J_kgK,
    COPPER_TEMPERATURE_COEFFICIENT_per_K,
)

__all__ = [
    "CONVECTION_MODES",
    "KAPPA_CENTRE",
    "KAPPA_MEAN",
    "PACK_NUMBER_FIELDS",
    "COPPER_VOLUMETRIC_HEAT_CAPACITY_J_m3K",
    "IMPREGNATION_VOLUMETRIC_HEAT_CAPACITY_J_m3K",
    "STEFAN_BOLTZMANN_W_m2K4",
    "SteadyState",
    "Surroundings",
    "Transient",
    "WindingPack",
    "convection_coefficient_W_m2K",
    "radiant_surroundings",
    "radiation_coefficient_W_m2K",
    "rectangle_pack_coefficients",
    "session_linearisation_C",
    "square_pack_coefficients",
    "steady_state",
    "surface_estimate_C",
    "surface_loss_W",
    "transient",
]

#: Stefan-Boltzmann constant, W/(m²·K⁴) (CODATA 2018, exact).
STEFAN_BOLTZMANN_W_m2K4 = 5.670374419e-8
#: Copper: the wire's density (IEC 60028 annealed copper, 8890 kg/m³, the same as the copper
#: mass) times its specific heat 385 J/(kg·K) (CRC Handbook, 97th ed.), J/(m³·K).
COPPER_VOLUMETRIC_HEAT_CAPACITY_J_m3K = COPPER_DENSITY_kg_m3 * COPPER_SPECIFIC_HEAT_J_kgK
#: The rest of the pack taken as epoxy impregnation/enamel: 1200 kg/m³ x 1100 J/(kg·K)
#: (typical cured epoxy; air voids would lower it, which shortens τ: see docs/coils.md).
IMPREGNATION_VOLUMETRIC_HEAT_CAPACITY_J_m3K = 1200.0 * 1100.0
#: How the faces are cooled: a fixed h, natural convection, natural plus forced air.
CONVECTION_MODES = ("fixed", "natural", "forced")
_KELVIN = 273.15
_NEWTON_STEPS = 6
_ESTIMATE_STEPS = 5
_POLISH_STEPS = 3
#: Step of the forward difference of h_c in the Newton slope, K (taken once per stage, the
#: iterates converge linearly with a factor ~1e-2: 7 + 4 steps reach 1e-10 of the loss).
_DH_STEP_K = 0.5


def square_pack_coefficients(terms: int = 60) -> tuple[float, float]:
    """Centre and mean rise of a square of side a, isothermal faces, in units of q''' a²/k.

    Series solution of ∇²θ = -q'''/k on |x|, |y| <= b = a/2 with θ = 0 on the faces
    (Carslaw & Jaeger 1959, §6.3), λ_n = (2n+1)π/(2b):
    θ(0,0) = b²/2 - Σ 2(-1)^n / (b λ_n³ cosh λ_n b) and
    mean θ = b²/3 - Σ 2 tanh(λ_n b) / (b³ λ_n⁵), both times q'''/k, divided by a² = 4b².

    Parameters
    ----------
    terms : int
        Number of series terms summed.

    Returns
    -------
    centre, mean : float
        Rise coefficients κ_c and κ_m, dimensionless (times q''' a²/k for K).
    """
    b = 0.5
    centre = b * b / 2.0
    mean = b * b / 3.0
    for n in range(terms):
        lam = (2 * n + 1) * math.pi / (2.0 * b)
        centre -= 2.0 * (-1) ** n / (b * lam**3 * math.cosh(lam * b))
        mean -= 2.0 * math.tanh(lam * b) / (b**3 * lam**5)
    return centre, mean


#: Centre and mean rise coefficients of the square pack with isothermal faces (0.07367,
#: 0.03514): the limit h -> ∞ of the Robin problem (tests).
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

    Parameters
    ----------
    width, depth : float, array or CasADi
        Axial width w and radial depth d of the section, m.

    Returns
    -------
    centre, mean : float, array or CasADi
        Rise coefficients, dimensionless (times q''' w d/k for K).
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


#: :class:`WindingPack`'s number fields, in order (its others, ``vertical_axis``,
#: ``convection`` and ``coils``, are its structure); the height last (0 for a ring).
PACK_NUMBER_FIELDS = (
    "pack_width_m",
    "pack_depth_m",
    "mean_radius_m",
    "packing_factor",
    "conductivity_W_mK",
    "heat_transfer_coefficient_W_m2K",
    "emissivity",
    "air_speed_m_s",
    "vertical_bar_height_m",
)


@dataclass(frozen=True)
class WindingPack:
    """Thermal description of one pair's two identical rectangular winding packs (SI).

    Fields may be floats, numpy arrays or CasADi values (sizing with free geometry), except
    ``convection``, ``vertical_axis`` and ``coils`` (structure).

    Parameters
    ----------
    pack_width_m : float, array or CasADi
        Axial width w of each winding pack, m.
    pack_depth_m : float, array or CasADi
        Radial depth d of each winding pack, m.
    mean_radius_m : float, array or CasADi
        Mean radius of each coil, m.
    packing_factor : float, array or CasADi
        Copper area / pack area, dimensionless.
    conductivity_W_mK : float, array or CasADi
        Effective transverse conductivity k of the pack, W/(m·K).
    heat_transfer_coefficient_W_m2K : float, array or CasADi
        Convective coefficient h at the faces (``"fixed"``), W/(m²·K).
    emissivity : float, array or CasADi
        Grey-body emissivity ε of the faces, dimensionless.
    air_speed_m_s : float, array or CasADi
        Forced-air speed (``"forced"``), m/s.
    vertical_axis : bool
        Flag: True for a pair whose axis is vertical (z).
    convection : str
        One of :data:`CONVECTION_MODES`.
    coils : int
        Number of identical coils (2 for a pair).
    vertical_bar_height_m : float, array or CasADi
        A square or rectangular frame in a vertical plane (an x or y pair): the height of its
        vertical bars, m (the convection is then the length-weighted mean of the horizontal and
        the vertical bars'); 0 (default): a ring, or a horizontal frame. A square pack is otherwise
        a ring of its mean turn's length (``mean_radius_m`` = 4a/(2π)): the same volume and
        faces.
    """

    pack_width_m: Any
    pack_depth_m: Any
    mean_radius_m: Any
    packing_factor: Any
    conductivity_W_mK: Any
    heat_transfer_coefficient_W_m2K: Any
    emissivity: Any
    air_speed_m_s: Any = 0.0
    vertical_axis: bool = False
    convection: str = "fixed"
    coils: int = 2
    vertical_bar_height_m: Any = 0.0

    @property
    def surface_area_m2(self) -> Any:
        """Outer faces of all coils, coils · 2 (w + d) · 2π R_m (Pappus), m²."""
        return (
            self.coils
            * 2.0
            * (self.pack_width_m + self.pack_depth_m)
            * 2.0
            * bk.pi
            * self.mean_radius_m
        )

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
        """(centre, mean) rise of the section with isothermal faces, in units of q w d/k, so
        dimensionless (the limit h -> infinity of the Robin problem the model solves)."""
        return rectangle_pack_coefficients(self.pack_width_m, self.pack_depth_m)

    @property
    def volumetric_heat_capacity_J_m3K(self) -> Any:
        """pf ρc_Cu + (1 - pf) ρc_impregnation, J/(m³·K)."""
        pf = self.packing_factor
        return (
            pf * COPPER_VOLUMETRIC_HEAT_CAPACITY_J_m3K
            + (1.0 - pf) * IMPREGNATION_VOLUMETRIC_HEAT_CAPACITY_J_m3K
        )

    @property
    def centre_resistance_K_per_W(self) -> Any:
        """Centre rise above isothermal faces per watt of pack loss, κ_c w d/(k V), K/W."""
        return (
            self.poisson_coefficients[0]
            * self.section_m2
            / (self.conductivity_W_mK * self.volume_m3)
        )

    @property
    def mean_resistance_K_per_W(self) -> Any:
        """Mean rise above isothermal faces per watt of pack loss, κ_m w d/(k V), K/W."""
        return (
            self.poisson_coefficients[1]
            * self.section_m2
            / (self.conductivity_W_mK * self.volume_m3)
        )

    @property
    def heat_capacity_J_per_K(self) -> Any:
        """Lumped heat capacity, V (pf ρc_Cu + (1 - pf) ρc_impregnation), J/K."""
        return self.volume_m3 * self.volumetric_heat_capacity_J_m3K


@dataclass(frozen=True)
class Surroundings:
    """What a pack's faces radiate to besides the room at ambient.

    ``radiant_C``: temperature T_r with (1 - F_self) T_r⁴ = F_room T_a⁴ + Σ_j F_j T_j⁴ (the
    other packs at their own temperatures); ``radiating_fraction``: 1 - F_self (the share of
    its emission that does not land on its own pair). Default: a pack alone in the room.

    Attributes
    ----------
    radiant_C : float, array or CasADi
        Radiant temperature T_r of the surroundings, °C.
    radiating_fraction : float, array or CasADi
        1 - F_self, dimensionless.
    """

    radiant_C: Any
    radiating_fraction: Any = 1.0


def radiant_surroundings(
    view_factors: Any, k: int, others_surface_C: Any, ambient_C: Any
) -> Surroundings:
    """:class:`Surroundings` of pair k from its view-factor row ``[room, x, y, z]`` and the
    surface temperatures of the three pairs (entry k is not used).

    Parameters
    ----------
    view_factors : ndarray, shape (3, 4)
        View factors, dimensionless, rows ``[room, x, y, z]`` per pair.
    k : int
        Index of the pair (0, 1, 2 for x, y, z).
    others_surface_C : sequence of float or CasADi
        Mean surface temperature of each of the three pairs, °C.
    ambient_C : float or CasADi
        Room temperature, °C.

    Returns
    -------
    Surroundings
        What pair k radiates to (°C, dimensionless fraction).
    """
    ta = ambient_C + _KELVIN
    f_self = view_factors[k][1 + k]
    sum4 = view_factors[k][0] * ta**4
    for j in range(3):
        if j != k:
            tj = others_surface_C[j] + _KELVIN
            sum4 = sum4 + view_factors[k][1 + j] * (tj * tj) * (tj * tj)
    frac = 1.0 - f_self
    return Surroundings((sum4 / frac) ** 0.25 - _KELVIN, frac)


def radiation_coefficient_W_m2K(surface_C: Any, ambient_C: Any, emissivity: Any) -> Any:
    """Secant radiation coefficient ε σ (T_s² + T_a²)(T_s + T_a), W/(m²·K).

    Exact in the sense h_r (T_s - T_a) = ε σ (T_s⁴ - T_a⁴) (grey surface in a large enclosure
    at ambient; Incropera & DeWitt, *Fundamentals of Heat and Mass Transfer*, 6th ed., eq. 1.9).

    Parameters
    ----------
    surface_C : float, array or CasADi
        Surface temperature, °C.
    ambient_C : float, array or CasADi
        Temperature of the enclosure, °C.
    emissivity : float, array or CasADi
        Grey-body emissivity ε, dimensionless.

    Returns
    -------
    float, array or CasADi
        Radiation coefficient h_r, W/(m²·K).
    """
    ts, ta = surface_C + _KELVIN, ambient_C + _KELVIN
    return emissivity * STEFAN_BOLTZMANN_W_m2K4 * (ts * ts + ta * ta) * (ts + ta)


def convection_coefficient_W_m2K(pack: WindingPack, surface_C: Any, ambient_C: Any) -> Any:
    """Area-weighted convective coefficient of the pack's faces at ``surface_C``, W/(m²·K).

    Parameters
    ----------
    pack : WindingPack
        The pack and its cooling mode.
    surface_C : float, array or CasADi
        Mean surface temperature, °C.
    ambient_C : float, array or CasADi
        Air temperature, °C.

    Returns
    -------
    float, array or CasADi
        Convective coefficient h_c, W/(m²·K).
    """
    if pack.convection == "fixed":
        return pack.heat_transfer_coefficient_W_m2K + 0.0 * surface_C
    h = pack_convection_W_m2K(
        pack.pack_width_m,
        pack.pack_depth_m,
        pack.vertical_axis,
        surface_C,
        ambient_C,
        pack.air_speed_m_s,
        forced=pack.convection == "forced",
    )
    return _with_vertical_bars(pack, h, surface_C, ambient_C)


def _with_vertical_bars(pack: WindingPack, h_ring: Any, surface_C: Any, ambient_C: Any) -> Any:
    """The ring's coefficient, or for a frame in a vertical plane the length-weighted mean of it
    (its horizontal bars) and the vertical bars' (:func:`coils.convection.
    vertical_bar_convection_W_m2K`): h + f (h_bar - h) with f = 2 height / (2π R_m) the
    vertical bars' share of the mean turn (1/2 for a square, b/(a + b) for a rectangle whose
    vertical side is b). A height of 0 (a number) is a ring: returned as it is; a symbolic
    height of 0 gives f = 0, the same value."""
    height = pack.vertical_bar_height_m
    if isinstance(height, (int, float)) and height == 0.0:
        return h_ring
    # the vertical bars' share of the mean turn, 2 height / (2π R_m): 1/2 for a square frame
    share = height / (bk.pi * pack.mean_radius_m)
    h_bar = vertical_bar_convection_W_m2K(
        pack.pack_width_m,
        pack.pack_depth_m,
        bk.fmax(height, pack.pack_width_m),
        surface_C,
        ambient_C,
        pack.air_speed_m_s,
        forced=pack.convection == "forced",
    )
    return h_ring + share * (h_bar - h_ring)


def _surroundings(env: Surroundings | None, ambient_C: Any) -> Surroundings:
    return Surroundings(ambient_C) if env is None else env


def surface_loss_W(
    pack: WindingPack, surface_C: Any, ambient_C: Any, env: Surroundings | None = None
) -> Any:
    """Heat the faces shed at a mean surface temperature, W:
    A [h_c (T_s - T_a) + ε σ (1 - F_self)(T_s⁴ - T_r⁴)].

    Parameters
    ----------
    pack : WindingPack
        The pack and its cooling.
    surface_C : float, array or CasADi
        Mean surface temperature T_s, °C.
    ambient_C : float, array or CasADi
        Air temperature T_a, °C.
    env : Surroundings, optional
        What the faces radiate to (default: the room at ambient).

    Returns
    -------
    float, array or CasADi
        Heat shed by convection and radiation, W.
    """
    return _Faces(pack, ambient_C, _surroundings(env, ambient_C)).loss_W(surface_C)


def _where(condition: Any, if_true: Any, if_false: Any) -> Any:
    """:func:`spiralcap.core.backend.where`, a Python float where numpy gives a 0-d array."""
    if type(condition) in (bool, float) and type(if_true) is float and type(if_false) is float:
        return if_true if condition else if_false  # the same float, without numpy
    return _plain(bk.where(condition, if_true, if_false))


def _plain(x: Any) -> Any:
    """A Python float for a numpy scalar or 0-d array (same value), anything else as it is."""
    if isinstance(x, np.generic) or (isinstance(x, np.ndarray) and x.ndim == 0):
        return float(x)
    return x


class _Faces:
    """The faces' loss, its Newton slope and the linearised coefficients, invariants once."""

    def __init__(self, pack: WindingPack, ambient_C: Any, env: Surroundings) -> None:
        self.pack = pack
        # numpy scalars (the view factors' rows) as Python floats: the same values, float math
        self.area = _plain(pack.surface_area_m2)
        self.eps_sigma = _plain(pack.emissivity * STEFAN_BOLTZMANN_W_m2K4 * env.radiating_fraction)
        self.ambient_C = ambient_C
        self.tr = _plain(env.radiant_C + _KELVIN)
        self.tr2 = self.tr * self.tr
        # numbers throughout: the correlation called directly (the sizing's hot path)
        self._floats = pack.convection != "fixed" and all(
            type(x) is float
            for x in (pack.pack_width_m, pack.pack_depth_m, ambient_C, pack.air_speed_m_s)
        )

    def convection(self, surface_C: Any) -> Any:
        if self._floats and type(surface_C) is float:
            p = self.pack
            h = _pack_convection_W_m2K(
                p.pack_width_m,
                p.pack_depth_m,
                surface_C,
                self.ambient_C,
                p.air_speed_m_s,
                bool(p.vertical_axis),
                p.convection == "forced",
            )
            return _with_vertical_bars(p, h, surface_C, self.ambient_C)
        return convection_coefficient_W_m2K(self.pack, surface_C, self.ambient_C)

    def radiation(self, surface_C: Any) -> Any:
        """Secant coefficient to the radiant temperature, W/(m²·K)."""
        ts = surface_C + _KELVIN
        return self.eps_sigma * (ts * ts + self.tr2) * (ts + self.tr)

    def loss_W(self, surface_C: Any, hc: Any = None) -> Any:
        ts = surface_C + _KELVIN
        hc = self.convection(surface_C) if hc is None else hc
        return self.area * (
            hc * (surface_C - self.ambient_C) + self.radiation(surface_C) * (ts - self.tr)
        )

    def convection_slope(self, surface_C: Any) -> Any:
        """dh_c/dT_s by a forward difference over 0.5 K (0 for a fixed h), W/(m²·K²)."""
        if self.pack.convection == "fixed":
            return 0.0
        return (self.convection(surface_C + _DH_STEP_K) - self.convection(surface_C)) / _DH_STEP_K

    def slope_W_per_K(self, surface_C: Any, hc: Any = None, dh: Any = 0.0) -> Any:
        """d(loss)/dT_s with the convective slope ``dh`` (taken at the stage's start)."""
        ts = surface_C + _KELVIN
        hc = self.convection(surface_C) if hc is None else hc
        conv = hc + dh * (surface_C - self.ambient_C)
        return self.area * (conv + 4.0 * self.eps_sigma * ts * ts * ts)

    def linearised(self, surface_C: Any) -> tuple[Any, Any, Any]:
        """(h_c, h_eff = h_c + h_r, sink rise above ambient) of the faces at ``surface_C``."""
        hc = self.convection(surface_C)
        hr = self.radiation(surface_C)
        heff = hc + hr
        return hc, heff, hr * (self.tr - _KELVIN - self.ambient_C) / heff


@dataclass(frozen=True)
class _Internal:
    """Rises above the mean surface per watt of pack loss, K/W (Robin statics at h_eff)."""

    centre: Any
    mean: Any
    surface_max: Any


def _internal(pack: WindingPack, h_eff: Any) -> _Internal:
    h_eff = bk.fmax(h_eff, 1e-6)  # a diverged iterate (flagged runaway) must stay finite
    st = robin_statics(pack.pack_width_m, pack.pack_depth_m, h_eff, pack.conductivity_W_mK)
    per_w = 1.0 / (pack.conductivity_W_mK * pack.volume_m3)
    return _Internal(
        (st.centre - st.surface_mean) * per_w,
        (st.mean - st.surface_mean) * per_w,
        (st.surface_max - st.surface_mean) * per_w,
    )


def _resistance_ohm(resistance_20C_ohm: Any, temperature_C: Any) -> Any:
    return resistance_20C_ohm * (
        1.0 + COPPER_TEMPERATURE_COEFFICIENT_per_K * (temperature_C - 20.0)
    )


def _balance_inputs(
    pack: WindingPack,
    resistance_20C_ohm: Any,
    current_amplitude_A: Any,
    ambient_C: Any,
    env: Surroundings | None,
) -> tuple[Any, Any, Any, _Faces]:
    """(R20, ambient, I²/2, the faces) of a surface balance; numpy scalars as Python floats
    (the same values: the scalar path stays in float math)."""
    resistance_20C_ohm, current_amplitude_A, ambient_C = (
        _plain(x) for x in (resistance_20C_ohm, current_amplitude_A, ambient_C)
    )
    half_i2 = 0.5 * current_amplitude_A * current_amplitude_A
    return (
        resistance_20C_ohm,
        ambient_C,
        half_i2,
        _Faces(pack, ambient_C, _surroundings(env, ambient_C)),
    )


@dataclass(frozen=True)
class SteadyState:
    """Steady temperatures (°C), loss (W), resistance (Ω), coefficients (W/(m²·K)) at one current.

    ``surface_C`` is the mean face temperature, ``surface_max_C`` the hottest face point.
    ``runaway`` is 1 where no steady state was found: the internal loss outgrows cooling or the
    Newton iterates had not converged, i.e. temperatures of thousands of °C. The other fields
    are then finite upper bounds (far beyond any limit), so limits built on them stay violated
    and smooth.

    Attributes
    ----------
    surface_C, mean_C, hot_spot_C : float, array or CasADi
        Mean face, mean winding and hottest winding temperature, °C.
    power_W : float, array or CasADi
        Copper loss of the pair, W.
    resistance_ohm : float, array or CasADi
        Pair resistance at ``mean_C``, Ω.
    runaway : float, array or CasADi
        Flag, 1.0 where no steady state was found, else 0.0.
    surface_max_C : float, array or CasADi
        Hottest face point, °C.
    convection_W_m2K, effective_h_W_m2K : float, array or CasADi
        Convective and effective (convection + radiation) face coefficient, W/(m²·K).
    centre_offset_K_per_W, mean_offset_K_per_W, surface_max_offset_K_per_W : float, array or CasADi
        Rise of the centre, the mean and the hottest face point above the mean face per watt of
        pack loss, K/W.
    """

    surface_C: Any
    mean_C: Any
    hot_spot_C: Any
    power_W: Any
    resistance_ohm: Any
    runaway: Any
    surface_max_C: Any = None
    convection_W_m2K: Any = None
    effective_h_W_m2K: Any = None
    centre_offset_K_per_W: Any = None
    mean_offset_K_per_W: Any = None
    surface_max_offset_K_per_W: Any = None

    @property
    def internal(self) -> _Internal:
        """Robin offsets above the mean face per watt, at ``effective_h_W_m2K``."""
        return _Internal(
            self.centre_offset_K_per_W, self.mean_offset_K_per_W, self.surface_max_offset_K_per_W
        )


def _newton(
    faces: _Faces, ts: Any, p_amb: Any, slope: Any, ambient_C: Any, steps: int
) -> tuple[Any, Any]:
    dh = faces.convection_slope(ts)  # frozen over the stage: linear convergence, factor ~1e-3
    for _ in range(steps):
        p = p_amb + slope * (ts - ambient_C)
        hc = faces.convection(ts)
        resid = faces.loss_W(ts, hc) - p
        ts = ts - resid / (faces.slope_W_per_K(ts, hc, dh) - slope)
    return ts, p_amb + slope * (ts - ambient_C)


def steady_state(
    pack: WindingPack,
    resistance_20C_ohm: Any,
    current_amplitude_A: Any,
    ambient_C: Any,
    env: Surroundings | None = None,
) -> SteadyState:
    """Self-consistent steady state of a pair carrying a sinusoid of amplitude I.

    The loss P = R(T_mean) I²/2 with T_mean = T_s + r_m P (r_m the Robin mean-above-surface
    resistance at the faces' h_eff) is linear-fractional in the mean surface temperature T_s;
    the surface balance Q(T_s) = P(T_s) is solved by Newton's method from the root of its
    tangent 30 K above ambient (6 steps with the mean taken at the surface, then 3 with r_m
    at that solution's h_eff); the mean, hot spot and hottest face point from the statics at
    that h_eff (the polish moves the surface by ~1 K, h_eff by ~0.1 %, the offsets by less),
    which is also the ``effective_h_W_m2K`` reported.

    Parameters
    ----------
    pack : WindingPack
        The pair's packs and their cooling.
    resistance_20C_ohm : float, array or CasADi
        Pair resistance at 20 °C, Ω.
    current_amplitude_A : float, array or CasADi
        Current amplitude (peak), A.
    ambient_C : float
        Ambient air, °C.
    env : Surroundings, optional
        The other packs it radiates to (default: alone in the room).

    Returns
    -------
    SteadyState
        Temperatures in °C, loss in W, resistance in Ω, coefficients in W/(m²·K).
    """
    resistance_20C_ohm, ambient_C, half_i2, faces = _balance_inputs(
        pack, resistance_20C_ohm, current_amplitude_A, ambient_C, env
    )
    alpha = COPPER_TEMPERATURE_COEFFICIENT_per_K
    r_m: Any = 0.0  # first stage: the mean at the surface; then the Robin offset at h_eff
    inner = None
    ok_denom: Any = 1.0
    ts: Any = ambient_C
    p: Any = 0.0
    for stage, steps in enumerate((_NEWTON_STEPS, _POLISH_STEPS)):
        denom = 1.0 - alpha * resistance_20C_ohm * half_i2 * r_m
        ok_denom = ok_denom * (denom > 0.0)
        safe = _where(denom > 0.0, denom, 1.0)
        p_amb = _resistance_ohm(resistance_20C_ohm, ambient_C) * half_i2 / safe
        slope = alpha * resistance_20C_ohm * half_i2 / safe  # dP/dT_s
        if stage == 0:  # tangent of the balance at a surface 30 K above ambient
            g0 = faces.slope_W_per_K(ambient_C + 30.0 + 0.0 * slope) - slope
            ok_start = g0 > 0.0
            ts = ambient_C + p_amb / _where(ok_start, g0, 1.0)
            ts = _where(ok_start, ts, ambient_C + 5000.0)
        ts, p = _newton(faces, ts, p_amb, slope, ambient_C, steps)
        if stage == 0:  # the Robin offsets at this h_eff (the polish moves T_s by ~1 K)
            heff = faces.linearised(ts)[1]
            inner = _internal(pack, heff)
            r_m = inner.mean
    hc = faces.convection(ts)
    resid = faces.loss_W(ts, hc) - p
    converged = bk.abs(resid) <= 1e-5 * bk.fmax(p, 1e-12) + 1e-12
    stable = faces.slope_W_per_K(ts, hc) - slope > 0.0  # cooling outgrows heating
    valid = ok_denom * converged * stable * (ts >= ambient_C - 1e-9)
    runaway = _where(valid, 0.0, 1.0)
    ts = _where(valid, ts, ambient_C + 1e4)  # runaway: a bound far above any limit
    p = _where(valid, p, faces.loss_W(ts))
    hc = faces.convection(ts)
    assert inner is not None
    mean = ts + inner.mean * p
    return SteadyState(
        surface_C=ts,
        mean_C=mean,
        hot_spot_C=ts + inner.centre * p,
        power_W=p,
        resistance_ohm=_resistance_ohm(resistance_20C_ohm, mean),
        runaway=runaway,
        surface_max_C=ts + inner.surface_max * p,
        convection_W_m2K=hc,
        effective_h_W_m2K=heff,
        centre_offset_K_per_W=inner.centre,
        mean_offset_K_per_W=inner.mean,
        surface_max_offset_K_per_W=inner.surface_max,
    )


def surface_estimate_C(
    pack: WindingPack,
    resistance_20C_ohm: Any,
    current_amplitude_A: Any,
    ambient_C: Any,
    env: Surroundings | None = None,
    session_s: Any = None,
) -> Any:
    """Quick mean surface temperature of a pair (the coupling's view of its neighbours), °C.

    The balance of :func:`steady_state` with the loss at the surface temperature (no internal
    rise: its mean-above-surface share, ~3 % of the rise, left out) in 5 Newton steps from the
    same start; with a session, the lumped fraction 1 - e^(-t/τ) of that rise.

    Parameters
    ----------
    pack : WindingPack
        The pair's packs and their cooling.
    resistance_20C_ohm : float, array or CasADi
        Pair resistance at 20 °C, Ω.
    current_amplitude_A : float, array or CasADi
        Current amplitude (peak), A.
    ambient_C : float, array or CasADi
        Ambient air, °C.
    env : Surroundings, optional
        The other packs it radiates to (default: alone in the room).
    session_s : float, array or CasADi, optional
        Length of the session, s (default: steady state).

    Returns
    -------
    float, array or CasADi
        Mean surface temperature, °C.
    """
    resistance_20C_ohm, ambient_C, half_i2, faces = _balance_inputs(
        pack, resistance_20C_ohm, current_amplitude_A, ambient_C, env
    )
    alpha = COPPER_TEMPERATURE_COEFFICIENT_per_K
    p_amb = _resistance_ohm(resistance_20C_ohm, ambient_C) * half_i2
    slope = alpha * resistance_20C_ohm * half_i2
    g0 = faces.slope_W_per_K(ambient_C + 30.0 + 0.0 * slope) - slope
    ok = g0 > 0.0
    ts = _where(ok, ambient_C + p_amb / _where(ok, g0, 1.0), ambient_C + 5000.0)
    ts, _ = _newton(faces, ts, p_amb, slope, ambient_C, _ESTIMATE_STEPS)
    if session_s is None:
        return ts
    decay = faces.linearised(ts)[1] * pack.surface_area_m2 - slope
    tau = pack.heat_capacity_J_per_K / bk.where(decay > 0.0, decay, 1e-30)
    return ambient_C + (ts - ambient_C) * (1.0 - bk.exp(-session_s / tau))


@dataclass(frozen=True)
class Transient:
    """Heating from ambient at time ``time_s`` (temperatures °C, W, s, J/K).

    ``time_constant_s`` is the lumped τ = C / (1/R_th - α R20 I²/2) of the mean rise;
    ``final_*`` the steady temperatures of the same linearised faces.

    Attributes
    ----------
    time_s : float, array or CasADi
        Time since switch-on, s.
    surface_C, mean_C, hot_spot_C : float, array or CasADi
        Mean face, mean winding and hottest winding temperature at ``time_s``, °C.
    power_W : float, array or CasADi
        Copper loss at ``time_s``, W.
    time_constant_s : float, array or CasADi
        Lumped time constant of the mean rise, s.
    heat_capacity_J_per_K : float, array or CasADi
        Heat capacity of the packs, J/K.
    final_mean_C, final_hot_spot_C : float, array or CasADi
        Steady mean and hottest winding temperature of the linearised faces, °C.
    surface_max_C : float, array or CasADi
        Hottest face point at ``time_s``, °C.
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
    surface_max_C: Any = None


def transient(
    pack: WindingPack,
    resistance_20C_ohm: Any,
    current_amplitude_A: Any,
    ambient_C: Any,
    time_s: Any,
    linearise_surface_C: Any,
    env: Surroundings | None = None,
) -> Transient:
    """Heating of a pair switched on at ambient, after ``time_s`` seconds, by conduction.

    The faces are linearised at the mean surface temperature ``linearise_surface_C``
    (convection at that film temperature, radiation as its secant coefficient to the radiant
    surroundings ``env``): h_eff and a sink θ_env above ambient. The section then heats by
    :func:`coils.conduction.robin_transient` with the source q = (P_a + p₁ θ_mean)/V,
    P_a = R(T_a) I²/2, p₁ = α R20 I²/2 (copper resistance linear in T).

    Parameters
    ----------
    pack : WindingPack
        The pair's packs and their cooling.
    resistance_20C_ohm, current_amplitude_A : float, array or CasADi
        Pair resistance at 20 °C (Ω) and current amplitude (A).
    ambient_C : float
        Ambient air and starting temperature, °C.
    time_s : float, array or CasADi
        Time since switch-on, s.
    linearise_surface_C : float, array or CasADi
        Surface temperature at which the faces are linearised, °C.
    env : Surroundings, optional
        The other packs it radiates to (default: alone in the room).

    Returns
    -------
    Transient
        Temperatures in °C, loss in W, times in s, heat capacity in J/K.
    """
    env = _surroundings(env, ambient_C)
    alpha = COPPER_TEMPERATURE_COEFFICIENT_per_K
    half_i2 = 0.5 * current_amplitude_A * current_amplitude_A
    p_a = _resistance_ohm(resistance_20C_ohm, ambient_C) * half_i2
    p1 = alpha * resistance_20C_ohm * half_i2
    faces = _Faces(pack, ambient_C, env)
    _, heff, sink = faces.linearised(linearise_surface_C)
    vol = pack.volume_m3
    run = robin_transient(
        pack.pack_width_m,
        pack.pack_depth_m,
        heff,
        pack.conductivity_W_mK,
        pack.volumetric_heat_capacity_J_m3K,
        p_a / vol,
        p1 / vol,
        sink,
        time_s,
    )
    inner = _internal(pack, heff)
    r_th = inner.mean + 1.0 / (heff * pack.surface_area_m2)  # mean above the sink, K/W
    cap = pack.heat_capacity_J_per_K
    decay = 1.0 / r_th - p1
    final = (sink / r_th + p_a) / decay  # mean rise: θ = sink + r_th (P_a + p₁ θ)
    final_power = p_a + p1 * final
    return Transient(
        time_s=time_s,
        surface_C=ambient_C + run.surface_mean,
        mean_C=ambient_C + run.mean,
        hot_spot_C=ambient_C + run.centre,
        power_W=p_a + p1 * run.mean,
        time_constant_s=cap / decay,
        heat_capacity_J_per_K=cap,
        final_mean_C=ambient_C + final,
        final_hot_spot_C=ambient_C + final + (inner.centre - inner.mean) * final_power,
        surface_max_C=ambient_C + run.surface_max,
    )


def session_linearisation_C(steady: SteadyState, tau_s: Any, time_s: Any, ambient_C: Any) -> Any:
    """Surface temperature a session of ``time_s`` ends near: T_a + (T_s - T_a)(1 - e^(-t/τ)).

    The faces of :func:`transient` are linearised there (exact at steady state, where the
    session ends at the steady surface); τ is the lumped time constant of the steady faces.

    Parameters
    ----------
    steady : SteadyState
        The pair's steady state.
    tau_s : float, array or CasADi
        Lumped time constant, s.
    time_s : float, array or CasADi
        Session length, s.
    ambient_C : float, array or CasADi
        Ambient air, °C.

    Returns
    -------
    float, array or CasADi
        Surface temperature to linearise at, °C.
    """
    return ambient_C + (steady.surface_C - ambient_C) * (1.0 - bk.exp(-time_s / tau_s))


def pair_resistance_20C_ohm(wire_length_m: Any, wire_diameter_m: Any) -> Any:
    """Resistance of a wire at 20 °C, ρ20 ℓ / (π d²/4), Ω (IEC 60028).

    Parameters
    ----------
    wire_length_m : float, array or CasADi
        Wire length ℓ, m.
    wire_diameter_m : float, array or CasADi
        Bare copper diameter d, m.

    Returns
    -------
    float, array or CasADi
        Resistance at 20 °C, Ω.
    """
    return COPPER_RESISTIVITY_20C_ohm_m * wire_length_m / (bk.pi * wire_diameter_m**2 / 4.0)
