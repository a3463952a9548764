"""Convection from a winding pack: dry-air properties and standard correlations (backend-generic).

Everything is a smooth function of the surface and air temperatures written against
:mod:`spiralcap.core.backend`, so the NLP differentiates it. Orientation: gravity along -z, so the
z pair's coils are horizontal rings and the x and y pairs' are vertical rings.

* z pair (axis vertical): the inner and outer cylindrical faces are vertical plates of height w,
  Churchill & Chu (1975a), Int. J. Heat Mass Transfer 18:1323 (Incropera & DeWitt,
  *Fundamentals of Heat and Mass Transfer*, 6th ed., eq. 9.26), every Ra; the upper annulus is
  the upper face of a hot plate, Nu = 0.54 Ra^(1/4) (Lloyd & Moran 1974; Incropera eq. 9.30),
  the lower annulus the lower face, Nu = 0.52 Ra^(1/5) (Incropera 7th ed. eq. 9.32), both with
  L = A/P = d/2.
* x and y pairs (axis horizontal): the pack is a bar of section w x d bent into a ring in a
  vertical plane; it is taken as a horizontal cylinder of the same perimeter,
  D = 2 (w + d)/π, Churchill & Chu (1975b), Int. J. Heat Mass Transfer 18:1049 (Incropera
  eq. 9.34), on all four faces. (Where the ring runs vertically, at its sides, a vertical-plate
  correlation over its height would give less; docs/coils-thermal.md.)
* Forced air (``coils.cooling = "forced"``): the section as a cylinder of the same perimeter in
  cross flow, Churchill & Bernstein (1977), J. Heat Transfer 99:300 (Incropera eq. 7.54),
  combined with the natural value as Nu = (Nu_F³ + Nu_N³)^(1/3) (Churchill 1977, mixed
  convection), which is the natural value at zero speed.

* Square frames (``coils.{x,y,z}.shape = "square"``): the z frame's bars are horizontal with
  the ring's faces (the same correlations); an x or y frame stands in a vertical plane, half
  its length horizontal bars (the horizontal cylinder above) and half vertical bars of height
  the side, every face a vertical plate over that height
  (:func:`vertical_bar_convection_W_m2K`); the pack's coefficient is the mean of the two.

Air (dry, 1 atm): viscosity and conductivity by Sutherland's law (White, *Viscous Fluid Flow*,
3rd ed., Table 1-2 and 1-3: μ0 = 1.716e-5 Pa·s, S = 110.4 K; k0 = 0.0241 W/(m·K), S = 194 K),
ideal-gas density, c_p = 1007 J/(kg·K); within 3 % of Incropera Table A.4 over 250-400 K
(tests/test_coils_cooling.py). Properties at the film temperature (T_s + T_a)/2, β = 1/T_film.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from spiralcap.core import backend as bk

__all__ = [
    "AirProperties",
    "air_properties",
    "forced_cylinder_nusselt",
    "horizontal_cylinder_nusselt",
    "lower_plate_nusselt",
    "pack_convection_W_m2K",
    "upper_plate_nusselt",
    "vertical_bar_convection_W_m2K",
    "vertical_plate_nusselt",
]

_KELVIN = 273.15
_G = 9.80665
_CP = 1007.0
_R_AIR = 287.05
_P_ATM = 101325.0
#: Smallest temperature difference the buoyancy sees, K: sqrt(ΔT² + δ²) keeps Ra > 0 and smooth.
_DT_FLOOR_K = 0.1


@dataclass(frozen=True)
class AirProperties:
    """Dry air at one temperature (SI): conductivity, kinematic viscosity, diffusivity, Pr.

    Attributes
    ----------
    conductivity_W_mK : float or CasADi
        Thermal conductivity, W/(m·K).
    kinematic_viscosity_m2_s : float or CasADi
        Kinematic viscosity ν, m²/s.
    diffusivity_m2_s : float or CasADi
        Thermal diffusivity, m²/s.
    prandtl : float or CasADi
        Prandtl number ν / diffusivity, dimensionless.
    """

    conductivity_W_mK: Any
    kinematic_viscosity_m2_s: Any
    diffusivity_m2_s: Any
    prandtl: Any


def air_properties(temperature_C: Any) -> AirProperties:
    """Dry air at 1 atm: Sutherland viscosity and conductivity, ideal-gas density, c_p const.

    Parameters
    ----------
    temperature_C : float or CasADi
        Air (film) temperature, °C.

    Returns
    -------
    AirProperties
        The properties at that temperature, SI.
    """
    return AirProperties(*_air(temperature_C))


def _air(temperature_C: Any) -> tuple[Any, Any, Any, Any]:
    """:func:`air_properties` as a tuple (conductivity, ν, diffusivity, Pr): the pack's
    correlation reads it thousands of times per sizing."""
    t = temperature_C + _KELVIN
    mu = 1.716e-5 * (t / 273.15) ** 1.5 * (273.15 + 110.4) / (t + 110.4)
    k = 0.0241 * (t / 273.15) ** 1.5 * (273.15 + 194.0) / (t + 194.0)
    rho = _P_ATM / (_R_AIR * t)
    return k, mu / rho, k / (rho * _CP), mu * _CP / k


def vertical_plate_nusselt(ra: Any, pr: Any) -> Any:
    """Churchill & Chu (1975a), every Ra: {0.825 + 0.387 Ra^(1/6)/[1+(0.492/Pr)^(9/16)]^(8/27)}².

    Parameters
    ----------
    ra : float or CasADi
        Rayleigh number on the plate height, dimensionless.
    pr : float or CasADi
        Prandtl number, dimensionless.

    Returns
    -------
    float or CasADi
        Mean Nusselt number on the height, dimensionless.
    """
    f = (1.0 + (0.492 / pr) ** (9.0 / 16.0)) ** (8.0 / 27.0)
    return (0.825 + 0.387 * ra ** (1.0 / 6.0) / f) ** 2


def horizontal_cylinder_nusselt(ra: Any, pr: Any) -> Any:
    """Churchill & Chu (1975b), Ra_D <= 1e12: {0.60 + 0.387 Ra^(1/6)/[1+(0.559/Pr)^(9/16)]^(8/27)}².

    Parameters
    ----------
    ra : float or CasADi
        Rayleigh number on the diameter, dimensionless.
    pr : float or CasADi
        Prandtl number, dimensionless.

    Returns
    -------
    float or CasADi
        Mean Nusselt number on the diameter, dimensionless.
    """
    f = (1.0 + (0.559 / pr) ** (9.0 / 16.0)) ** (8.0 / 27.0)
    return (0.60 + 0.387 * ra ** (1.0 / 6.0) / f) ** 2


def upper_plate_nusselt(ra: Any) -> Any:
    """Upper face of a hot plate, 0.54 Ra^(1/4) (Lloyd & Moran 1974; 1e4 <= Ra <= 1e7).

    Parameters
    ----------
    ra : float or CasADi
        Rayleigh number on L = area / perimeter, dimensionless.

    Returns
    -------
    float or CasADi
        Mean Nusselt number on L, dimensionless.
    """
    return 0.54 * ra**0.25


def lower_plate_nusselt(ra: Any) -> Any:
    """Lower face of a hot plate, 0.52 Ra^(1/5) (Incropera 7th ed. eq. 9.32; 1e4 <= Ra <= 1e9).

    Parameters
    ----------
    ra : float or CasADi
        Rayleigh number on L = area / perimeter, dimensionless.

    Returns
    -------
    float or CasADi
        Mean Nusselt number on L, dimensionless.
    """
    return 0.52 * ra**0.2


def forced_cylinder_nusselt(re: Any, pr: Any) -> Any:
    """Churchill & Bernstein (1977), cylinder in cross flow, Re·Pr >= 0.2.

    Parameters
    ----------
    re : float or CasADi
        Reynolds number on the diameter, dimensionless.
    pr : float or CasADi
        Prandtl number, dimensionless.

    Returns
    -------
    float or CasADi
        Mean Nusselt number on the diameter, dimensionless.
    """
    return (
        0.3
        + 0.62
        * bk.sqrt(re)
        * pr ** (1.0 / 3.0)
        / (1.0 + (0.4 / pr) ** (2.0 / 3.0)) ** (0.25)
        * (1.0 + (re / 282000.0) ** 0.625) ** 0.8
    )


def pack_convection_W_m2K(
    width_m: Any,
    depth_m: Any,
    vertical_axis: bool,
    surface_C: Any,
    ambient_C: Any,
    air_speed_m_s: Any = 0.0,
    forced: bool = False,
) -> Any:
    """Area-weighted convective coefficient of one pack's four faces, W/(m²·K).

    ``vertical_axis``: True for the z pair (horizontal rings), False for x and y (vertical
    rings); the orientation is part of the model's structure, not a value. ``forced``: add
    forced air at ``air_speed_m_s``.

    Parameters
    ----------
    width_m, depth_m : float or CasADi
        Axial width and radial depth of the pack's section, m.
    vertical_axis : bool
        Flag: the pair's axis is vertical (z pair).
    surface_C : float or CasADi
        Mean surface temperature of the pack, °C.
    ambient_C : float or CasADi
        Ambient air temperature, °C.
    air_speed_m_s : float or CasADi
        Speed of the forced air across the pack, m/s (used when ``forced``).
    forced : bool
        Flag: fans blow air across the packs.

    Returns
    -------
    float or CasADi
        Convective heat transfer coefficient, W/(m²·K).
    """
    return _pack_convection_W_m2K(
        width_m, depth_m, surface_C, ambient_C, air_speed_m_s, bool(vertical_axis), bool(forced)
    )


def _pack_convection_W_m2K(
    width_m: Any,
    depth_m: Any,
    surface_C: Any,
    ambient_C: Any,
    air_speed_m_s: Any,
    vertical_axis: bool,
    forced: bool,
) -> Any:
    """:func:`pack_convection_W_m2K` with the structure (orientation, forced) last."""
    # a face below the air: h of ΔT -> 0; Python floats stay Python floats (the fast path)
    if isinstance(surface_C, float) and isinstance(ambient_C, (float, int)):
        surface_C = max(float(surface_C), float(ambient_C))
    else:
        surface_C = bk.fmax(surface_C, ambient_C)
    k, nu, diffusivity, pr = _air(0.5 * (surface_C + ambient_C))
    dt = surface_C - ambient_C
    dt = (dt * dt + _DT_FLOOR_K * _DT_FLOOR_K) ** 0.5
    buoy = _G / (0.5 * (surface_C + ambient_C) + _KELVIN) * dt / (nu * diffusivity)  # Ra / L³
    w, d = width_m, depth_m
    diam = 2.0 * (w + d) / bk.pi
    if vertical_axis:
        # cylinders (share w / (w + d) of the area), annuli up and down (d / (2 (w + d)) each)
        h_side = vertical_plate_nusselt(buoy * w * w * w, pr) * k / w
        half_d = 0.5 * d
        ra_ann = buoy * half_d * half_d * half_d
        h_up = upper_plate_nusselt(ra_ann) * k / half_d
        h_down = lower_plate_nusselt(ra_ann) * k / half_d
        h_nat = (w * h_side + 0.5 * d * (h_up + h_down)) / (w + d)
    else:
        h_nat = horizontal_cylinder_nusselt(buoy * diam * diam * diam, pr) * k / diam
    if not forced:
        return h_nat
    re = air_speed_m_s * diam / nu
    h_forced = forced_cylinder_nusselt(re, pr) * k / diam
    return (h_forced**3 + h_nat**3) ** (1.0 / 3.0)


def vertical_bar_convection_W_m2K(
    width_m: Any,
    depth_m: Any,
    height_m: Any,
    surface_C: Any,
    ambient_C: Any,
    air_speed_m_s: Any = 0.0,
    forced: bool = False,
) -> Any:
    """Convective coefficient of a vertical bar of section w x d and height H, W/(m²·K).

    A square frame in a vertical plane (the x and y pairs of a square set) is two horizontal
    bars, which the ring's horizontal-cylinder correlation describes, and two vertical bars,
    whose four faces are vertical plates of height H: Churchill & Chu (1975a) over L = H
    (Incropera eq. 9.26; air properties, film temperature and ΔT floor as
    :func:`pack_convection_W_m2K`). Forced air crosses the bar as it crosses the ring's
    section: the same cylinder of the section's perimeter, combined as Nu = (Nu_F³ + Nu_N³)^(1/3).
    Backend-generic.

    Parameters
    ----------
    width_m, depth_m : float, array or CasADi
        Section of the bar, m.
    height_m : float, array or CasADi
        Height H of the bar (the frame's side), m.
    surface_C, ambient_C : float, array or CasADi
        Mean surface and air temperatures, °C.
    air_speed_m_s : float, array or CasADi
        Forced-air speed, m/s (``forced`` only).
    forced : bool
        Add forced air.

    Returns
    -------
    float, array or CasADi
        Convective heat-transfer coefficient h of the bar's faces, W/(m²·K).
    """
    if isinstance(surface_C, float) and isinstance(ambient_C, (float, int)):
        surface_C = max(float(surface_C), float(ambient_C))
    else:
        surface_C = bk.fmax(surface_C, ambient_C)
    k, nu, diffusivity, pr = _air(0.5 * (surface_C + ambient_C))
    dt = surface_C - ambient_C
    dt = (dt * dt + _DT_FLOOR_K * _DT_FLOOR_K) ** 0.5
    buoy = _G / (0.5 * (surface_C + ambient_C) + _KELVIN) * dt / (nu * diffusivity)
    h_nat = vertical_plate_nusselt(buoy * height_m * height_m * height_m, pr) * k / height_m
    if not forced:
        return h_nat
    diam = 2.0 * (width_m + depth_m) / bk.pi
    h_forced = forced_cylinder_nusselt(air_speed_m_s * diam / nu, pr) * k / diam
    return (h_forced**3 + h_nat**3) ** (1.0 / 3.0)
