"""Physical constants, material data (SI) and the design-unit table. Imported by every package;
imports none."""

from __future__ import annotations

from typing import Any

#: Vacuum permeability, T·m/A (CODATA 2018: 1.25663706212e-6; the pre-2019 exact 4π·1e-7
#: differs by 5e-10 relative, below every tolerance in this project).
MU0_T_m_per_A = 1.25663706212e-6

#: Resistivity of annealed copper at 20 °C, Ω·m (IEC 60028 standard annealed copper, 1/58 Ω·mm²/m).
COPPER_RESISTIVITY_20C_ohm_m = 1.7241e-8

#: Temperature coefficient of copper resistivity at 20 °C, 1/K (IEC 60028).
COPPER_TEMPERATURE_COEFFICIENT_per_K = 0.00393

#: Standard gravity, m/s² (used to quote loads in gram-force where a paper does).
STANDARD_GRAVITY_m_s2 = 9.80665

#: Density of annealed copper, kg/m³ (IEC 60028: 8.89 g/cm³ at 20 °C, the standard of the
#: winding wire). The one copper density: the copper mass and the winding's heat capacity.
COPPER_DENSITY_kg_m3 = 8890.0

#: Specific heat of copper at 20-25 °C, J/(kg·K) (CRC Handbook of Chemistry and Physics, 97th
#: ed., 0.385 J/(g·K)).
COPPER_SPECIFIC_HEAT_J_kgK = 385.0

#: Unit suffixes of design-key names -> (SI unit suffix, factor to SI). The longest matching
#: suffix wins, so ``_kPa_s`` is read before ``_s`` and ``_mm_s`` before ``_s``. A name whose
#: suffix is already SI (``_m``, ``_A``, ``_hz``, ``_C``) or has none converts with factor 1.
UNIT_SUFFIXES: dict[str, tuple[str, float]] = {
    "_mm": ("_m", 1e-3),
    "_mm_s": ("_m_s", 1e-3),
    "_mm2": ("_m2", 1e-6),
    "_um": ("_m", 1e-6),
    "_cm": ("_m", 1e-2),
    "_mT": ("_T", 1e-3),
    "_uT": ("_T", 1e-6),
    "_deg": ("_rad", 0.017453292519943295),
    "_mN": ("_N", 1e-3),
    "_mNm": ("_Nm", 1e-3),
    "_kPa": ("_Pa", 1e3),
    "_kPa_s": ("_Pa_s", 1e3),
    "_mA": ("_A", 1e-3),
    "_mH": ("_H", 1e-3),
    "_kW": ("_W", 1e3),
    "_kV": ("_V", 1e3),
    "_g": ("_kg", 1e-3),
    "_min": ("_s", 60.0),
    "_ms": ("_s", 1e-3),
    "_kHz": ("_hz", 1e3),
}


def design_unit(name: str) -> tuple[str, str, float]:
    """The unit suffix of a design key's name, its SI suffix and the factor to SI.

    ``design_unit("requirements.axial_load_mN")`` -> ``("_mN", "_N", 1e-3)``; a name without a
    non-SI suffix gives ``("", "", 1.0)``.
    """
    leaf = name.rpartition(".")[2]
    best = ""
    for suffix in UNIT_SUFFIXES:
        if leaf.endswith(suffix) and len(suffix) > len(best) and len(leaf) > len(suffix):
            best = suffix
    if not best:
        return "", "", 1.0
    si, factor = UNIT_SUFFIXES[best]
    return best, si, factor


def from_si(value: Any, factor: float) -> Any:
    """``value`` in SI back to the design unit whose factor to SI is ``factor``.

    Divides by factors >= 1 and multiplies by the reciprocal of smaller ones, so that decimal
    prefixes come back exactly (0.0109 m -> 10.9 mm, not 10.899999999999999).
    """
    return value / factor if factor >= 1.0 else value * (1.0 / factor)


#: A unit's name (a suffix of :data:`UNIT_SUFFIXES` without its underscore: ``deg``, ``mm``,
#: ``mNm``) -> its factor to SI, the same numbers the design keys use.
UNIT_FACTORS: dict[str, float] = {
    suffix[1:]: factor for suffix, (_, factor) in UNIT_SUFFIXES.items()
}


def _factor(unit: str) -> float:
    try:
        return UNIT_FACTORS[unit]
    except KeyError:
        raise KeyError(
            f"unit {unit!r} is not in the unit table; one of {sorted(UNIT_FACTORS)}"
        ) from None


def to_unit(value_si: Any, unit: str) -> Any:
    """``value_si`` (SI) in ``unit`` of the unit table: the one SI -> display conversion.

    Works on floats, numpy arrays and CasADi symbols alike (a multiplication); decimal prefixes
    come back exactly (:func:`from_si`), and ``to_unit(x, "deg")`` is bit for bit
    ``math.degrees(x)``.

    Examples
    --------
    >>> to_unit(0.5235987755982988, "deg")
    29.999999999999996
    >>> to_unit(0.0109, "mm")
    10.9
    """
    return from_si(value_si, _factor(unit))


def from_unit(value: Any, unit: str) -> Any:
    """``value`` in ``unit`` of the unit table, in SI: the one design/display -> SI conversion.

    Works on floats, numpy arrays and CasADi symbols alike (a multiplication);
    ``from_unit(x, "deg")`` is bit for bit ``math.radians(x)``.

    Examples
    --------
    >>> from_unit(30.0, "deg")
    0.5235987755982988
    >>> from_unit(12.0, "mm")
    0.012
    """
    return value * _factor(unit)
