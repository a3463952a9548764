"""How values are shown to people: engineering units for SI values, and JSON-ready values.

One table serves the CLI text, the report and the figures, so a value reads the same
everywhere (``0.01115 T`` is always ``11.15 mT``). Application-level: imports nothing from
``spiralcap.commands`` or ``spiralcap.report``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from spiralcap.core.constants import to_unit
from spiralcap.keymap import design_key, si_factor

#: How an SI unit is shown: SI unit -> (shown unit, factor from SI to shown).
SHOWN_UNITS: dict[str, tuple[str, float]] = {
    "T": ("mT", to_unit(1.0, "mT")),
    "m/s": ("mm/s", to_unit(1.0, "mm_s")),
    "N·m": ("mN·m", to_unit(1.0, "mNm")),
    "m": ("mm", to_unit(1.0, "mm")),
    "H": ("mH", to_unit(1.0, "mH")),
    "rad": ("deg", to_unit(1.0, "deg")),
}


#: Key-name unit suffixes (longest first) -> how the unit is written.
_SUFFIX_UNITS: tuple[tuple[str, str], ...] = (
    ("_W_m2K", "W/(m²·K)"),
    ("_kPa_s", "kPa·s"),
    ("_mm_s", "mm/s"),
    ("_m_s", "m/s"),
    ("_kPa", "kPa"),
    ("_deg", "°"),
    ("_hz", "Hz"),
    ("_Hz", "Hz"),
    ("_mm", "mm"),
    ("_mN", "mN"),
    ("_mNm", "mN·m"),
    ("_Nm", "N·m"),
    ("_mT", "mT"),
    ("_T", "T"),
    ("_C", "°C"),
    ("_K", "K"),
    ("_A", "A"),
    ("_V", "V"),
    ("_W", "W"),
    ("_m", "m"),
    ("_s", "s"),
)


def unit_of_key(key: str) -> str:
    """The unit a design key names in its suffix (``coils.x.radius_m`` -> ``m``), or ``""``.

    Counts (``turns``, ``starts``), ratios (``packing_factor``) and choices have no unit.
    """
    leaf = key.rsplit(".", 1)[-1]
    for suffix, unit in _SUFFIX_UNITS:
        if leaf.endswith(suffix):
            return unit
    return ""


#: Readable names of the checks, limits and bounds the optimiser reports.
_NAMES = {
    "margin": "torque margin",
    "speed": "forward speed",
    "spiral_turns": "spiral turns",
    "self_lock": "self-locking",
    "power": "total copper power",
    "field_exposure": "field exposure (ICNIRP 2010)",
    "helical_angle_min": "lower helical-angle bound",
    "helical_angle_max": "upper helical-angle bound",
    "frequency_min": "lower frequency bound",
    "frequency_max": "upper frequency bound",
    "solver": "solver did not converge",
    "wall_strain": "wall strain (grip)",
    "envelope_x": "coil set along x (envelope)",
    "envelope_y": "coil set along y (envelope)",
    "envelope_z": "coil set along z (envelope)",
}
_PER_AXIS = {
    "axis_current": "current (own channel)",
    "axis_voltage": "drive voltage (own channel)",
    "axis_power": "copper power (own channel)",
    "axis_apparent_power": "apparent power V·I/2 (own channel)",
    "current": "current",
    "voltage": "drive voltage",
    "temperature_rise": "coil temperature rise",
    "hot_spot": "winding hot spot",
}


#: (SI unit of a value, unit its design key names) -> factor from the first to the second
_TO_KEY_UNIT: dict[tuple[str, str], float] = {
    ("m/s", "mm/s"): to_unit(1.0, "mm_s"),
    ("rad", "°"): to_unit(1.0, "deg"),
    ("T", "mT"): to_unit(1.0, "mT"),
    ("m", "mm"): to_unit(1.0, "mm"),
    ("N·m", "mN·m"): to_unit(1.0, "mNm"),
    ("N", "mN"): to_unit(1.0, "mN"),
    ("K", "°C"): 1.0,  # a temperature difference: per K is per °C
}


def in_key_units(unit: str, key: str) -> tuple[str, float]:
    """``(label, factor)`` that shows a value in SI ``unit`` in the unit of design key ``key``.

    ``requirements.min_speed_mm_s`` shows m/s as mm/s (x 1e3); ``capsule.spiral.helical_angle_deg``
    shows rad as ° ; ``limits.coil_temperature_C`` shows °C (and a difference in K) as °C. A key
    with no unit in its name (a count, a ratio, ``limits.field_exposure``) shows the value in
    its engineering unit (:func:`shown`: T as mT).
    """
    if "." not in key:  # not a design key (the margin itself): its engineering unit
        return shown(unit)
    target = unit_of_key(key)
    if target == unit:
        return unit, 1.0
    if (unit, target) in _TO_KEY_UNIT:
        return target, _TO_KEY_UNIT[(unit, target)]
    return shown(unit)


def with_unit(number: str, unit: str) -> str:
    """A formatted number and its unit: ``"2.257 turns"``, ``"1 turn"`` (a count of one is
    singular), ``"0.4"`` (no unit for ``""`` or ``"1"``)."""
    if unit in ("", "1"):
        return number
    if unit in COUNT_UNITS and number == "1":
        unit = COUNT_UNITS[unit]
    return f"{number} {unit}"


COUNT_UNITS = {"turns": "turn", "starts": "start"}


def readable(name: str) -> str:
    """``voltage_x`` -> ``drive voltage, x pair``; unknown names are returned unchanged."""
    if name in _NAMES:
        return _NAMES[name]
    if "@" in name:  # a freed hardware key at the end of its range: ``magnet.diameter_m@max``
        stem, _, end = name.partition("@")
        where = {"max": "top", "min": "bottom"}.get(end, end)
        return f"{_hardware_words(stem)} at the {where} of its free range"
    if name.endswith("]") and "[" in name:  # a per-tissue row: ``wall_strain[sample3]``
        stem, _, inner = name[:-1].partition("[")
        return f"{readable(stem)}, {inner}"
    stem, _, axis = name.rpartition("_")
    if stem in _PER_AXIS and axis in ("x", "y", "z"):
        return f"{_PER_AXIS[stem]}, {axis} pair"
    return name.replace("_", " ")


def _hardware_words(name: str) -> str:
    """A free hardware variable in words: ``x.wire_diameter_m`` -> ``wire diameter, x pair``,
    ``magnet.diameter_m`` -> ``magnet diameter``, ``spiral.wire_diameter_m`` -> ``spiral wire
    diameter``."""
    part, _, leaf = name.partition(".")
    for suffix in ("_mm", "_m"):
        leaf = leaf.removesuffix(suffix)
    leaf = leaf.replace("_", " ")
    if part in ("x", "y", "z"):
        return f"{leaf}, {part} pair"
    return f"{part} {leaf}".strip()


def shown(unit: str) -> tuple[str, float]:
    """``(label, factor)`` that shows a value in SI ``unit`` in its engineering unit.

    Units without an engineering form (A, V, W, K, Hz, ...) are shown as they are.
    """
    return SHOWN_UNITS.get(unit, (unit, 1.0))


def jsonable(value: Any) -> Any:
    """``value`` with numpy values as Python numbers, NaN as None and infinities as ``"inf"``.

    Mappings become dicts with string keys, tuples become lists.
    """
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if hasattr(value, "tolist"):
        return jsonable(value.tolist())
    if isinstance(value, float) and not math.isfinite(value):
        return None if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return value


def step_out_words(
    step_out_hz: float,
    bound: str,
    max_frequency_hz: float,
    max_frequency_beyond: bool,
    limited_by: str,
    field_fixed: bool,
) -> str:
    """The step-out frequency with whether the drive can reach it, in one clause.

    ``bound`` is the JSON's ``step_out_bound`` ("found", "above_search_range",
    "below_search_range"); ``max_frequency_hz`` the highest frequency at which the drive, with
    the field re-maximised there, still keeps a positive margin (``limited_by`` the limit that
    sets the field there); ``field_fixed``: the operating field is set (below what the limits
    allow), so the drive can raise it at higher frequencies.
    """
    at = "at the set field" if field_fixed else "at the operating field"
    if bound == "no_contact":  # the spiral does not touch every wall: no margin, no step-out
        return "none: the spiral does not touch every wall (no contact, no margin)"
    if bound == "below_search_range":
        return f"below {step_out_hz:g} Hz: the capsule cannot keep up at any frequency {at}"
    drive = f"{max_frequency_hz:.3g} Hz" + (" or more" if max_frequency_beyond else "")
    by = readable(limited_by) if limited_by else "the limits"
    if bound == "above_search_range":
        head = f"above {step_out_hz:g} Hz (the top of the search) {at}"
    else:
        head = f"{step_out_hz:.3g} Hz {at}"
    if max_frequency_beyond or max_frequency_hz >= step_out_hz:
        if field_fixed:
            return (
                f"{head}; raising the field to what the limits allow keeps a positive margin up "
                f"to {drive} ({by})"
            )
        return f"{head}; the drive can reach it (it keeps a positive margin up to {drive})"
    return (
        f"{head}; the drive cannot hold that field above {drive} ({by} limits it), so the drive "
        "limit comes first"
    )


#: objective -> (what it is, shown unit, factor from SI, sense)
OBJECTIVES: dict[str, tuple[str, str, float, str]] = {
    "margin": ("worst-case torque margin", "mN·m", 1e3, "maximised"),
    "margin_p05": (
        "CVaR₀.₀₅ (mean of the worst 5 %) of the worst-case margin over the tissue scenarios "
        "(lost grip counted as failure: the least of torque and grip margins)",
        "mN·m",
        1e3,
        "maximised",
    ),
    "ratio": ("worst-case safety factor", "", 1.0, "maximised"),
    "power": ("worst-heading copper power", "W", 1.0, "minimised"),
    "copper_mass": ("copper mass of the three coil pairs", "kg", 1.0, "minimised"),
}


def objective_words(objective: str) -> tuple[str, str, float, str]:
    """``(description, shown unit, factor from SI, "maximised" | "minimised")`` of an
    objective; a registered objective unknown here is named as it is, in SI."""
    return OBJECTIVES.get(objective, (objective.replace("_", " "), "", 1.0, "optimised"))


def gain_per_key_unit(objective: str, unit: str, key: str, gain_si: float) -> tuple[float, str]:
    """A binding limit's gain per unit relaxed (objective SI per SI ``unit`` of the limit) in
    the objective's shown unit per unit of the design key: ``(value, "kg per °C")``."""
    _, obj_unit, obj_factor, _ = objective_words(objective)
    key_unit, key_factor = in_key_units(unit, key)
    if key_unit in ("", "1"):
        key_unit = "unit"
    elif key_unit == "turns":
        key_unit = "turn"
    obj = obj_unit or ("safety factor" if objective == "ratio" else "")
    return gain_si * obj_factor / key_factor, f"{obj} per {key_unit}".strip()


#: Keys whose own unit is no useful step to quote a gain per: key -> (step in the key's unit,
#: the step in words). A strain of 1 is 100 %; a safety factor of 1 doubles it.
GAIN_STEPS: dict[str, tuple[float, str]] = {
    "requirements.min_wall_strain": (1e-3, "0.1 % of strain"),
    "requirements.min_safety_factor": (0.1, "0.1 of the safety factor"),
    "requirements.slip_efficiency": (0.01, "0.01 of slip efficiency"),
    "requirements.max_failure_probability": (0.01, "1 % of failure probability"),
}


def gain_step(key: str, key_unit: str) -> tuple[float, str]:
    """The step a gain is quoted per, in the key's unit, and in words: ``(1.0, "1 °C")``,
    ``(1.0, "1°")`` for an angle, ``(1.0, "1 turn")``, ``(0.001, "0.1 % of strain")`` for
    ``requirements.min_wall_strain``; a key with no unit and no entry in :data:`GAIN_STEPS`
    per 0.01 of it (not "per unit", a doubling of most ratios)."""
    stem = key.removeprefix("optimize.free.")
    if stem in GAIN_STEPS:
        return GAIN_STEPS[stem]
    if stem.endswith((".turns", ".starts")) or key_unit in ("turns", "starts"):
        return 1.0, "1 turn" if stem.endswith("turns") or key_unit == "turns" else "1 start"
    if key_unit == "°":
        return 1.0, "1°"
    if key_unit in ("", "1", "unit"):
        return 0.01, "0.01"
    return 1.0, f"1 {key_unit}"


#: A limit binds only where the solution sits on it: its value within this relative distance of
#: the bound (IPOPT meets an active row to about 1e-8; a value 5 % inside its bound, such as a
#: relaxed hardware value past a bound its multiplier still names, does not bind).
ON_BOUND_RTOL = 1e-3


def on_bound(value: float, allowed: float) -> bool:
    """Whether ``value`` sits on its bound ``allowed`` (a bound of 0 is taken as sat on: its
    distance has no scale here)."""
    if allowed == 0 or not (math.isfinite(value) and math.isfinite(allowed)):
        return True
    return abs(value - allowed) <= ON_BOUND_RTOL * abs(allowed)


def binding(limits: Any) -> tuple[Any, ...]:
    """The binding limits (``optimize.BindingLimit`` or their JSON dicts) whose value sits on
    the bound: what the CLI, the JSON, the comparison, the sweep and the report call binding."""

    def parts(b: Any) -> tuple[float, float]:
        if isinstance(b, dict):
            return float(b["value"]), float(b["allowed"])
        return float(b.value), float(b.allowed)

    return tuple(b for b in limits if on_bound(*parts(b)))


def _domain_words(words: str, field: str, unit: str) -> tuple[str, str, str, float]:
    """(words, design key, shown unit, factor from SI) of a model field shown in its design
    key's unit (:mod:`spiralcap.keymap`)."""
    key = design_key(field)
    return words, key, unit, 1.0 / si_factor(key)


#: How each model input of torque_model.domain.CALIBRATED is named and shown: quantity ->
#: (words, design key, shown unit, factor from SI); the key and factor from spiralcap.keymap.
_DOMAIN_WORDS: dict[str, tuple[str, str, str, float]] = {
    "helical_angle_rad": _domain_words("helical angle", "spiral.helical_angle_rad", "°"),
    "frequency_hz": _domain_words("rotation frequency", "operation.frequency_hz", "Hz"),
    "body_diameter_m": _domain_words("capsule diameter", "body.diameter_m", "mm"),
    "wire_diameter_m": _domain_words("spiral wire diameter", "spiral.wire_diameter_m", "mm"),
    "starts": _domain_words("spiral starts", "spiral.starts", ""),
    "lumen_diameter_m": _domain_words("lumen", "tissue.lumen_diameter_m", "mm"),
    # a ratio shown in per cent (its key has no unit)
    "wall_strain": ("wall strain", "requirements.min_wall_strain", "%", 100.0),
}


def extrapolation_words(e: Any) -> str:
    """One model input outside the paper's calibration, in words: ``helical angle 21.7° (the
    paper measured 5-20°)``; ``e`` a :class:`torque_model.domain.Extrapolation`."""
    words, _, unit, k = _DOMAIN_WORDS[e.quantity]
    where = f" in {e.where}" if e.where else ""
    measured = (
        f"{e.low * k:.3g}{_sp(unit)}"
        if e.low == e.high
        else f"{e.low * k:.3g}-{e.high * k:.3g}{_sp(unit)}"
    )
    return f"{words} {e.value * k:.4g}{_sp(unit)}{where} (the paper measured {measured})"


def extrapolation_key(e: Any) -> str:
    """The design key behind an extrapolated model input (``capsule.spiral.helical_angle_deg``)."""
    return _DOMAIN_WORDS[e.quantity][1]


def _sp(unit: str) -> str:
    return unit if unit in ("", "°") else f" {unit}"


def model_domain_text(extrapolations: Any) -> str:
    """One paragraph: inside the paper's calibration, or each input the model extrapolates in."""
    if not extrapolations:
        return "tissue model        inside the paper's calibrated range (Zhou 2013)"
    items = "; ".join(extrapolation_words(e) for e in extrapolations)
    return f"tissue model        EXTRAPOLATES outside the paper's calibration: {items}"


def edge_text(edges: Any) -> str:
    """``; the optimum sits on the calibrated edge of: ...`` or ``""``."""
    if not edges:
        return ""
    return "; the optimum sits on the calibrated edge of: " + "; ".join(
        extrapolation_words(e) for e in edges
    )
