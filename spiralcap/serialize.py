"""Result objects -> plain dicts with units in every key: the one source for JSON and the report.

The dicts are derived from the result dataclasses field by field, so a field added to
:class:`optimize.Evaluation` or :class:`optimize.OptimizationResult` appears in the JSON without
a second list. What the JSON shows differently from the dataclass is in three tables only:

- :data:`RENAMES`: a field shown under another name (``workspace_factor`` ->
  ``workspace_field_factor``);
- :data:`TRANSFORMS`: a field shown in another form (per-axis tuples as ``{"x": .., "y": ..,
  "z": ..}``; a field named ``*_rad`` is shown in degrees as ``*_deg``);
- :data:`PROPERTIES`: read-only properties shown as if they were fields.

Every number field has one type, a finite number (docs/json/README.md):

- ``safety_factor`` is absent, and ``safety_factor_unbounded`` true, when no torque is required
  (``required_torque_Nm == 0``: magnet torque / 0 has no finite value);
- ``step_out_frequency_hz`` is a bound when the search found none: ``step_out_bound`` says
  ``"found"``, ``"above_search_range"`` (the step-out lies above the value given, the top of
  the search) or ``"below_search_range"`` (the capsule cannot turn even at the value given, the
  bottom of the search);
- ``lag_angle_deg`` is 90 when the magnet cannot hold the load (``synchronous`` false);
- ``margin_Nm`` and ``safety_factor`` are absent, with ``margin_Nm_undefined`` and
  ``safety_factor_undefined`` true, where the spiral does not touch some wall (``grip``
  ``"none"``: the model has no physics there).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any

from spiralcap.core.constants import to_unit

_AXES = ("x", "y", "z")

#: dataclass field -> JSON name
RENAMES: dict[str, str] = {
    "workspace_factor": "workspace_field_factor",
    "sensitivity": "sensitivity_per_unit",
}


def _by_axis(value: Any) -> dict[str, float]:
    return dict(zip(_AXES, (float(v) for v in value)))


#: dataclass field -> (JSON name, conversion); applied before the ``*_rad`` rule
TRANSFORMS: dict[str, tuple[str, Callable[[Any], Any]]] = {
    "current_amplitudes_A": ("current_amplitudes_A", _by_axis),
    "copper_masses_kg": ("copper_masses_kg", _by_axis),
    "relax_sign": ("relaxing_means", lambda s: "raising" if s > 0 else "lowering"),
}

#: properties shown as fields where a class has them
PROPERTIES = ("gain_per_unit_relaxed", "short_by", "copper_mass_kg", "engaged", "grip")

#: fields shown by a dedicated rule of their parent (not field by field)
_SKIPPED = {"current_phases_rad", "headings", "solution_x", "solution_lam_g", "scenario_solve"}


def to_dict(obj: Any) -> dict[str, Any]:
    """A result dataclass as a JSON-ready dict, by the tables above (recursing into fields)."""
    out: dict[str, Any] = {}
    for f in dataclasses.fields(obj):
        if f.name in _SKIPPED:
            continue
        value = getattr(obj, f.name)
        if f.name in TRANSFORMS:
            name, conv = TRANSFORMS[f.name]
            out[name] = conv(value)
        elif f.name.endswith("_rad") and isinstance(value, (int, float)):
            out[f.name[: -len("_rad")] + "_deg"] = to_unit(value, "deg")
        else:
            out[RENAMES.get(f.name, f.name)] = _value(value)
    for prop in PROPERTIES:
        if hasattr(type(obj), prop):
            out[prop] = getattr(obj, prop)
    return out


def _value(value: Any) -> Any:
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return to_dict(value)
    if isinstance(value, (tuple, list)):
        return [_value(v) for v in value]
    if hasattr(value, "item") and getattr(value, "ndim", 1) == 0:
        return value.item()
    return value


def _step_out(hz: float) -> tuple[float, str]:
    from optimize.evaluate import STEP_OUT_SEARCH_HZ

    lo, hi = STEP_OUT_SEARCH_HZ
    if not math.isfinite(hz) or hz >= hi:
        return hi, "above_search_range"
    if hz <= 0 or hz < lo:
        return lo, "below_search_range"
    return hz, "found"


def _finite_fields(out: dict[str, Any], margin_Nm: float) -> dict[str, Any]:
    """Safety factor, step-out and lag as finite numbers with their flags (see module notes)."""
    sf = out.pop("safety_factor")
    out["safety_factor_unbounded"] = math.isinf(sf)
    if math.isfinite(sf):
        out["safety_factor"] = sf
    elif math.isnan(sf):  # no contact: no margin, no ratio (print_json leaves margin_Nm out)
        out["safety_factor_undefined"] = True
    if math.isnan(margin_Nm) and math.isnan(out["step_out_frequency_hz"]):
        out["step_out_bound"] = "no_contact"  # print_json flags the NaN as undefined
    else:
        hz = out["step_out_frequency_hz"]
        out["step_out_frequency_hz"], out["step_out_bound"] = _step_out(hz)
    if "lag_angle_deg" in out:
        out["synchronous"] = not margin_Nm < 0  # no contact (NaN): nothing but the weight holds
    return out


def evaluation_to_dict(ev: Any) -> dict[str, Any]:
    """JSON-ready figures of an :class:`optimize.Evaluation` (each check with its design key)."""
    from spiralcap.assemble.system import check_key

    out = to_dict(ev)
    out["checks"] = [_check(c, check_key(c["name"])) for c in out["checks"]]
    return _finite_fields(out, ev.margin_Nm)


#: a utilisation shown for a requirement achieved not at all (needed / 0)
_UTILISATION_CAP = 1e6


def _check(c: dict[str, Any], key: str) -> dict[str, Any]:
    """A check in SI (``value``, ``allowed`` in ``unit``: N·m, m/s, rad, m, T; temperatures in
    °C) and in the unit of its design key (``value_in_key_unit``, ``allowed_in_key_unit`` in
    ``key_unit``: the speed in mm/s, the self-lock α + atan μ in degrees against 90);
    ``utilisation`` in the row's own form (1 binds)."""
    from spiralcap.presentation import in_key_units

    unit, factor = in_key_units(c["unit"], key)
    util = c.get("utilisation", float("nan"))
    if not math.isfinite(util):
        util = _UTILISATION_CAP if util > 0 else 0.0
    return {
        "name": c["name"],
        "key": key,
        **c,
        "key_unit": unit,
        "value_in_key_unit": c["value"] * factor,
        "allowed_in_key_unit": c["allowed"] * factor,
        "utilisation": min(util, _UTILISATION_CAP),
    }


_OBJECTIVE_UNITS = {
    "margin": "N·m",
    "margin_p05": "N·m",
    "ratio": "1",
    "power": "W",
    "copper_mass": "kg",
}


def optimization_to_dict(res: Any) -> dict[str, Any]:
    """JSON-ready figures of an :class:`optimize.OptimizationResult`."""
    from spiralcap.assemble.system import constraint_key

    out = to_dict(res)
    out["current_allocation"] = [
        {
            "heading": [float(c) for c in h],
            "amplitudes_A": _by_axis(a),
            "phases_deg": dict(zip(_AXES, (to_unit(p, "deg") for p in ph))),
        }
        for h, (a, ph) in zip(res.headings, res.current_phases_rad)
    ]
    from spiralcap.presentation import binding, gain_per_key_unit, in_key_units, objective_words

    unit = _OBJECTIVE_UNITS.get(res.objective, "1")
    what, shown_unit, factor, sense = objective_words(res.objective)
    out["objective_description"] = what
    out["objective_unit"] = shown_unit
    out["objective_direction"] = sense
    if math.isfinite(res.objective_value):
        out["objective_value_shown"] = res.objective_value * factor
    out["binding_limits"] = list(binding(out["binding_limits"]))
    for b in out["binding_limits"]:
        b["key"] = constraint_key(b["name"])
        b["gain_unit"] = unit + "/" + b["unit"]
        key_unit, key_factor = in_key_units(b["unit"], b["key"])
        b["key_unit"] = key_unit
        b["value_in_key_unit"] = b["value"] * key_factor
        b["allowed_in_key_unit"] = b["allowed"] * key_factor
        b["gain_per_key_unit"], b["gain_per_key_unit_label"] = gain_per_key_unit(
            res.objective, b["unit"], b["key"], b["gain_per_unit_relaxed"]
        )
        _gain_per_step(b)
    out["binding_keys"] = binding_keys(out["binding_limits"])
    for s in out["shortfalls"]:
        s["key"] = constraint_key(s["name"])
    out["evaluation"] = evaluation_to_dict(res.evaluation)
    out["copper_mass_kg"] = res.evaluation.copper_mass_kg
    out["copper_masses_kg"] = _by_axis(res.evaluation.copper_masses_kg)
    if not math.isfinite(res.objective_value):  # no optimum (infeasible): no objective value
        out.pop("objective_value", None)
    if res.status != "optimal" and res.evaluation is not None:
        from spiralcap.explain import advice, at_design_hardware, explained_at_values, grips

        # where the shortfalls stand (the design keys evaluate reproduces them with, at the
        # design's own hardware), whether it grips, and what to change, in order (issue 36)
        out["explained_at"] = {
            "keys": explained_at_values(res),
            "grips": grips(res),
            "at_design_hardware": at_design_hardware(res),
        }
        out["advice"] = advice(res)
    hardware = _hardware(res.hardware)
    if hardware is None:  # fixed hardware: no sizing part (one type per field, no null)
        out.pop("hardware", None)
    else:
        out["hardware"] = hardware
    return _finite_fields(out, res.margin_Nm)


def _gain_per_step(b: dict[str, Any]) -> None:
    """``gain_per_step`` (the objective's shown unit) for relaxing the key by ``gain_step`` (in
    words; ``gain_step_in_key_unit`` in the key's unit): 1 °C, 1°, 0.1 % of strain."""
    from spiralcap.presentation import gain_step

    step, words = gain_step(b["key"], b["key_unit"])
    b["gain_step_in_key_unit"] = step
    b["gain_step"] = words
    b["gain_per_step"] = b["gain_per_key_unit"] * step
    obj_unit = b["gain_per_key_unit_label"].split(" per ", 1)[0]
    b["gain_per_step_label"] = f"{obj_unit} per {words}".strip()


def binding_keys(binding: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """The binding rows grouped by design key: relaxing a key relaxes all its rows at once
    (three pairs' current limits are one ``limits.current_A``), so its gain is their sum --
    where rows tie, IPOPT may split the multiplier among them in any proportion."""
    out: dict[str, dict[str, Any]] = {}
    for b in binding:
        key = b["key"] or b["name"]
        if key not in out:
            out[key] = {
                "key": key,
                "key_unit": b["key_unit"],
                "relaxing_means": b["relaxing_means"],
                "rows": [],
                "gain_per_key_unit": 0.0,
                "gain_per_key_unit_label": b["gain_per_key_unit_label"],
            }
        out[key]["rows"].append(b["name"])
        out[key]["gain_per_key_unit"] += b["gain_per_key_unit"]
    for k in out.values():
        _gain_per_step(k)
    return list(out.values())


def _hardware(h) -> dict[str, Any] | None:
    """The sizing part of an optimum: relaxed bound and discrete design, in design-key units."""
    if h is None:
        return None
    from spiralcap.assemble.system import hardware_design_values

    relaxed = {k: v for k, v in h.relaxed.items() if not k.endswith(".turns")}
    relaxed_keys = hardware_design_values(relaxed)
    relaxed_keys.update(
        {f"coils.{k.split('.')[0]}.turns": v for k, v in h.relaxed.items() if k.endswith(".turns")}
    )
    return {
        "relaxed": relaxed_keys,
        "relaxed_objective": h.relaxed_objective,
        "discrete": hardware_design_values(h.discrete),
        "discrete_objective": h.discrete_objective,
        "rounding_cost": h.rounding_cost,
        "rounding_cost_relative": h.rounding_cost / abs(h.relaxed_objective)
        if h.relaxed_objective
        else 0.0,
        "candidates": h.candidates,
        "feasible_candidates": h.feasible,
        "outer_iterations": h.outer_iterations,
        "settled": h.settled,
        **_copper_declined(h),
    }


def _copper_declined(h: Any) -> dict[str, Any]:
    """``copper_declined`` of a least-power sizing that gave up copper buying too little power
    (optimize.discrete.leaner): the least-power design's copper (kg), power (W) and hardware
    (design keys); absent otherwise."""
    d = getattr(h, "copper_declined", None)
    if not d:
        return {}
    from spiralcap.assemble.system import hardware_design_values

    return {
        "copper_declined": {
            "copper_mass_kg": d["copper_kg"],
            "objective_value": d["objective"],
            "hardware": hardware_design_values(d["hardware"]),
        }
    }
