"""Design -> :class:`capsule.Capsule`: the ``capsule.*`` keys converted to SI and cross-checked.

Each key is validated on its own by :mod:`spiralcap.schema`; this module checks the keys against
each other (a magnet that does not fit the shell, a ring without a bore, a spiral longer than the
cylinder) and names the design key at fault in the :class:`~spiralcap.core.errors.InputError`.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

from spiralcap.core.errors import InputError
from spiralcap.keymap import FIELD_KEYS
from spiralcap.schema import KEYS, to_si, validate_value

if TYPE_CHECKING:
    from capsule import Capsule

#: Capsule-domain field (``part.parameter``) -> design key (the capsule's rows of
#: :data:`spiralcap.keymap.FIELD_KEYS`).
_DESIGN_KEY: dict[str, str] = {
    field: key
    for field, key in FIELD_KEYS.items()
    if field.startswith(("body.", "spiral.", "magnet."))
}


def _get(design: Mapping[str, Any], key: str) -> Any:
    """The design's value for ``key`` checked against the schema, else the schema default.

    A :class:`~spiralcap.design.Design` is validated already; checking again costs nothing and
    lets a plain mapping of a few keys be built with the same guarantees (sizes > 0, ...).
    """
    value = design[key] if key in design else KEYS[key].default
    return None if value is None else validate_value(key, value)


@contextmanager
def _named(design: Mapping[str, Any], part: str) -> Iterator[None]:
    """Re-raise a domain InputError (``diameter_m``) under its design key (``capsule....``)."""
    try:
        yield
    except InputError as exc:
        key = _DESIGN_KEY.get(f"{part}.{exc.key}", exc.key)
        value = design.get(key, exc.value) if key in KEYS else exc.value
        raise InputError(key, value, exc.allowed) from None


def build_capsule(design: Mapping[str, Any]) -> Capsule:
    """Build the capsule a design describes.

    Parameters
    ----------
    design : Mapping[str, Any]
        A validated design (``spiralcap.design.Design``) or any mapping of design keys; absent
        keys take their schema defaults. Reads ``capsule.diameter_mm``, ``capsule.length_mm``,
        ``capsule.shell_thickness_mm``, ``capsule.spiral.{helical_angle_deg, wire_diameter_mm,
        wound_length_mm, starts}`` and ``capsule.magnet.{shape, diameter_mm, length_mm,
        inner_diameter_mm, grade, remanence_T}`` (``remanence_T``, when given, overrides the
        grade).

    Returns
    -------
    capsule.Capsule
        Body, spiral and magnet in SI.

    Raises
    ------
    spiralcap.core.errors.InputError
        Naming the design key at fault: ``capsule.length_mm`` not above the diameter,
        ``capsule.shell_thickness_mm`` not below the radius, ``capsule.magnet.inner_diameter_mm``
        inconsistent with the shape or not below the outer diameter, ``capsule.magnet.diameter_mm``
        or ``capsule.magnet.length_mm`` for a magnet that does not fit inside the shell,
        ``capsule.spiral.wire_diameter_mm`` above 25 % of the body diameter,
        ``capsule.spiral.wound_length_mm`` longer than the cylindrical part,
        ``capsule.spiral.helical_angle_deg`` so small that neighbouring turns overlap.
    """
    import capsule as cap

    d = {k: _get(design, k) for k in _DESIGN_KEY.values()}
    d["capsule.magnet.shape"] = _get(design, "capsule.magnet.shape")

    diameter, length = d["capsule.diameter_mm"], d["capsule.length_mm"]
    if length <= diameter:
        raise InputError(
            "capsule.length_mm",
            length,
            f"more than capsule.diameter_mm = {diameter:g} "
            "(two hemispherical ends need a full diameter)",
        )
    shell = d["capsule.shell_thickness_mm"]
    if shell >= 0.5 * diameter:
        raise InputError(
            "capsule.shell_thickness_mm",
            shell,
            f"less than the capsule radius {0.5 * diameter:g} mm",
        )
    with _named(design, "body"):
        body = cap.Body(
            diameter_m=to_si("capsule.diameter_mm", diameter),
            length_m=to_si("capsule.length_mm", length),
            shell_thickness_m=to_si("capsule.shell_thickness_mm", shell),
        )

    shape, bore = d["capsule.magnet.shape"], d["capsule.magnet.inner_diameter_mm"]
    outer = d["capsule.magnet.diameter_mm"]
    if shape == "ring" and not bore:
        raise InputError(
            "capsule.magnet.inner_diameter_mm",
            bore,
            "a bore > 0 for a ring magnet (or set capsule.magnet.shape=cylinder)",
        )
    if shape == "cylinder" and bore:
        raise InputError(
            "capsule.magnet.inner_diameter_mm",
            bore,
            "0 for a cylinder magnet (or set capsule.magnet.shape=ring)",
        )
    if bore >= outer:
        raise InputError(
            "capsule.magnet.inner_diameter_mm",
            bore,
            f"less than capsule.magnet.diameter_mm = {outer:g}",
        )
    remanence = d["capsule.magnet.remanence_T"]
    if remanence is None:
        with _named(design, "magnet"):
            remanence = cap.remanence_for_grade(d["capsule.magnet.grade"])
    with _named(design, "magnet"):
        magnet = cap.Magnet(
            diameter_m=to_si("capsule.magnet.diameter_mm", outer),
            length_m=to_si("capsule.magnet.length_mm", d["capsule.magnet.length_mm"]),
            remanence_T=remanence,
            inner_diameter_m=to_si("capsule.magnet.inner_diameter_mm", bore),
        )

    angle = d["capsule.spiral.helical_angle_deg"]
    with _named(design, "spiral"):
        spiral = cap.Spiral(
            helical_angle_rad=to_si("capsule.spiral.helical_angle_deg", angle),
            wire_diameter_m=to_si(
                "capsule.spiral.wire_diameter_mm", d["capsule.spiral.wire_diameter_mm"]
            ),
            wound_length_m=to_si(
                "capsule.spiral.wound_length_mm", d["capsule.spiral.wound_length_mm"]
            ),
            starts=d["capsule.spiral.starts"],
        )

    problems = cap.geometry_problems(body, spiral, magnet)
    if problems:
        field, reason = problems[0]
        key = _DESIGN_KEY[field]
        raise InputError(key, d[key], reason)
    mass = _get(design, "capsule.mass_g")
    set_mass = None if mass is None else to_si("capsule.mass_g", mass)
    return cap.Capsule(body=body, spiral=spiral, magnet=magnet, set_mass_kg=set_mass)
