"""Design keys and the model fields they set, in one table (issue 38).

A model field is named ``part.field`` with its SI unit in the name (``magnet.diameter_m``,
``x.turns``): the capsule's parts (:class:`capsule.Capsule`: ``body``, ``spiral``, ``magnet``)
and the coil hardware a sizing may free (:data:`optimize.hardware.NAMES`) use the same names.
Its design key carries the unit the user writes (``capsule.magnet.diameter_mm``); the factor
between the two comes from the key's name through the one unit table
(:func:`spiralcap.core.constants.design_unit`), never by hand. The assembler
(``spiralcap.assemble``) and the presentation read the map from here.
"""

from __future__ import annotations

from typing import Any

from spiralcap.core.constants import design_unit, from_si

__all__ = ["FIELD_KEYS", "design_key", "field_of", "from_field_si", "si_factor"]

_AXES = ("x", "y", "z")

#: Model field (SI, ``part.field``) -> design key (units in its name).
FIELD_KEYS: dict[str, str] = {
    # the capsule (capsule.Capsule's parts)
    "body.diameter_m": "capsule.diameter_mm",
    "body.length_m": "capsule.length_mm",
    "body.shell_thickness_m": "capsule.shell_thickness_mm",
    "spiral.helical_angle_rad": "capsule.spiral.helical_angle_deg",
    "spiral.wire_diameter_m": "capsule.spiral.wire_diameter_mm",
    "spiral.wound_length_m": "capsule.spiral.wound_length_mm",
    "spiral.starts": "capsule.spiral.starts",
    "magnet.diameter_m": "capsule.magnet.diameter_mm",
    "magnet.length_m": "capsule.magnet.length_mm",
    "magnet.inner_diameter_m": "capsule.magnet.inner_diameter_mm",
    "magnet.remanence_T": "capsule.magnet.remanence_T",
    "magnet.grade": "capsule.magnet.grade",
    # the coil hardware (optimize.hardware.NAMES; a rectangle is sized by its first side, its
    # design key holds both sides)
    **{f"{ax}.turns": f"coils.{ax}.turns" for ax in _AXES},
    **{f"{ax}.wire_diameter_m": f"coils.{ax}.wire_diameter_mm" for ax in _AXES},
    **{f"{ax}.radius_m": f"coils.{ax}.radius_m" for ax in _AXES},
    **{f"{ax}.side_m": f"coils.{ax}.side_m" for ax in _AXES},
    **{f"{ax}.side_a_m": f"coils.{ax}.sides_m" for ax in _AXES},
    **{f"{ax}.pack_aspect": f"coils.{ax}.pack_aspect" for ax in _AXES},
    # the operating point and the patient
    "operation.frequency_hz": "operation.frequency_hz",
    "operation.field_amplitude_T": "operation.field_amplitude_mT",
    "tissue.lumen_diameter_m": "tissue.lumen_diameter_mm",
}


def design_key(field: str) -> str:
    """The design key of a model field: ``magnet.diameter_m`` -> ``capsule.magnet.diameter_mm``.

    Parameters
    ----------
    field : str
        A model field of :data:`FIELD_KEYS`.

    Returns
    -------
    str
        Its design key.

    Examples
    --------
    >>> design_key("spiral.helical_angle_rad")
    'capsule.spiral.helical_angle_deg'
    """
    return FIELD_KEYS[field]


def field_of(key: str) -> str:
    """The model field a design key sets (the inverse of :func:`design_key`).

    Examples
    --------
    >>> field_of("coils.z.wire_diameter_mm")
    'z.wire_diameter_m'
    """
    return _FIELDS[key]


def si_factor(key: str) -> float:
    """The factor from a design key's unit to SI, from its name (the unit table).

    Examples
    --------
    >>> si_factor("capsule.magnet.diameter_mm")
    0.001
    """
    return design_unit(key)[2]


def from_field_si(field: str, value: Any) -> Any:
    """A model field's SI value in its design key's unit (decimal prefixes come back exactly).

    Examples
    --------
    >>> from_field_si("body.diameter_m", 0.0109)
    10.9
    """
    return from_si(value, si_factor(design_key(field)))


_FIELDS = {key: field for field, key in FIELD_KEYS.items()}
