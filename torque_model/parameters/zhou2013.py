"""Zhou, Alici, Than, Li (2013): porcine small-intestine samples 2 and 3.

Source: H. Zhou, G. Alici, T. D. Than, W. Li, "Modeling and experimental investigation of
rotational resistance of a spiral-type robotic capsule inside a real intestine", IEEE/ASME
Trans. Mechatronics 18(5), 2013.

- Five-element constants E1, E2, E3 (kPa), eta1, eta2 (kPa·s): Table I (sample 2, identified on
  capsule No. 2, 10 deg) and Table II (sample 3, identified on capsule No. 3, 15 deg); the model
  they belong to is eqs. 2-8.
- Lumen (D_before, eq. 6): section II-B, 10.9 mm (sample 2) and 11.1 mm (sample 3); wall
  thickness (d, eqs. 3 and 6): 1 mm for both; friction (mu, eq. 7, measured by eq. 1):
  section II-C, 0.28 (sample 2) and 0.51 (sample 3).

The published moduli and viscosities, put through eqs. 2-8 in SI, give a torque
``1 / CALIBRATION_FACTOR`` of what the paper measured. The tool therefore uses the published sets
with every modulus and viscosity multiplied by :data:`CALIBRATION_FACTOR`, fitted on sample 2,
capsule No. 2 only (see ``docs/torque-model.md`` for the reading and the arithmetic). The factor
leaves every E/eta ratio, and so the shape of torque against frequency, as published.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from spiralcap.core.errors import InputError
from torque_model.tissue import TissueParameters

#: The keys a parameter set must have, exactly (units in the names).
KEYS = (
    "E1_kPa",
    "E2_kPa",
    "E3_kPa",
    "eta1_kPa_s",
    "eta2_kPa_s",
    "lumen_diameter_mm",
    "wall_thickness_mm",
    "friction_coefficient",
)

#: Table I and section II (sample 2), as published.
SAMPLE2: dict[str, float] = {
    "E1_kPa": 0.12,
    "E2_kPa": 18.64,
    "E3_kPa": 0.0122,
    "eta1_kPa_s": 43.51,
    "eta2_kPa_s": 0.2213,
    "lumen_diameter_mm": 10.9,
    "wall_thickness_mm": 1.0,
    "friction_coefficient": 0.28,
}

#: Table II and section II (sample 3), as published.
SAMPLE3: dict[str, float] = {
    "E1_kPa": 0.0348,
    "E2_kPa": 0.7722,
    "E3_kPa": 0.0448,
    "eta1_kPa_s": 9.491,
    "eta2_kPa_s": 0.2489,
    "lumen_diameter_mm": 11.1,
    "wall_thickness_mm": 1.0,
    "friction_coefficient": 0.51,
}

#: One factor on every modulus and viscosity of both published sets (dimensionless); fitted by
#: least squares in relative error to the paper's sample-2 capsule-No.-2 points (0.6 mN·m at
#: 0.5 Hz, 1.8 mN·m at 3 Hz) under the reading of docs/torque-model.md. Regenerate with
#: ``torque_model.calibration.fit_calibration_factor()``.
CALIBRATION_FACTOR = 356.98

_VISCOELASTIC = ("E1_kPa", "E2_kPa", "E3_kPa", "eta1_kPa_s", "eta2_kPa_s")


def check_parameter_set(values: Mapping[str, Any], source: str) -> dict[str, float]:
    """Return ``values`` as floats if it has exactly :data:`KEYS`, each a finite number > 0.

    Parameters
    ----------
    values : mapping of str to float
        A parameter set, the unit in each key name (kPa, kPa·s, mm; friction dimensionless).
    source : str
        Prefix of the key an error names (``"zhou2013"``, ``"tissue"``).

    Returns
    -------
    dict of str to float
        The same set as floats, the unit in each key name, in :data:`KEYS` order.

    Raises
    ------
    InputError
        An unknown or missing key, or a value that is not a finite positive number.
    """
    import math

    for key in values:
        if key not in KEYS:
            raise InputError(f"{source}.{key}", values[key], "a key from " + ", ".join(KEYS))
    out: dict[str, float] = {}
    for key in KEYS:
        if key not in values:
            raise InputError(f"{source}.{key}", None, "a value (the key is missing)")
        v = values[key]
        ok = isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0
        if not ok:
            raise InputError(f"{source}.{key}", v, "a finite number > 0")
        out[key] = float(v)
    return out


def calibrated(values: Mapping[str, Any], factor: float = CALIBRATION_FACTOR) -> dict[str, float]:
    """A published set with every modulus and viscosity multiplied by ``factor``.

    Parameters
    ----------
    values : mapping of str to float
        A set with exactly :data:`KEYS`, the unit in each key name (kPa, kPa·s, mm).
    factor : float
        Calibration factor on the moduli and viscosities, dimensionless.

    Returns
    -------
    dict of str to float
        The calibrated set, the unit in each key name (geometry and friction unchanged).
    """
    out = check_parameter_set(values, "zhou2013")
    return {k: (v * factor if k in _VISCOELASTIC else v) for k, v in out.items()}


#: The values the tool uses (published x CALIBRATION_FACTOR), same units as the published sets.
SAMPLE2_CALIBRATED = calibrated(SAMPLE2)
SAMPLE3_CALIBRATED = calibrated(SAMPLE3)


def calibrated_tissue(
    values: Mapping[str, Any], name: str, factor: float = CALIBRATION_FACTOR
) -> TissueParameters:
    """The calibrated set as a :class:`torque_model.TissueParameters` (SI).

    Parameters
    ----------
    values : mapping of str to float
        A set with exactly :data:`KEYS`, the unit in each key name (kPa, kPa·s, mm).
    name : str
        Name the tissue carries (a preset name).
    factor : float
        Calibration factor on the moduli and viscosities, dimensionless.

    Returns
    -------
    TissueParameters
        The calibrated set in SI (Pa, Pa·s, m).
    """
    return TissueParameters.from_design_table(calibrated(values, factor), name=name)
