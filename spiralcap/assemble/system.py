"""Design -> :class:`optimize.DesignModel`: coils, capsule, tissues, workspace, limits, options."""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from spiralcap.core.checks import guard, instance
from spiralcap.core.constants import from_unit, to_unit
from spiralcap.core.errors import InputError
from spiralcap.design import Design
from spiralcap.keymap import design_key, field_of, from_field_si, si_factor
from spiralcap.schema import FREEABLE_KEYS, to_si, winding_temperature_C

#: Below this helical angle the D' conversion of torque_model.geometry no longer holds for the
#: paper's capsule (the bump wraps round the back; see its docstring).
MIN_MODEL_ANGLE_deg = 1.8


def _headings(design: Design) -> np.ndarray:
    from optimize.system import default_headings

    raw = design["workspace.headings"]
    if raw == "all":
        return default_headings()
    h = np.asarray(raw, dtype=float)
    h = h / np.max(np.abs(h), axis=1, keepdims=True)  # first to O(1): no overflow in the norm
    return h / np.linalg.norm(h, axis=1, keepdims=True)


@guard(design=instance(Design, "a spiralcap.design.Design (spiralcap.design.load_design)"))
def build_model(design: Design, *, optimiser: bool = True):
    """The :class:`optimize.DesignModel` of a validated design (SI inside).

    ``optimiser=False``: a model that is only evaluated (``evaluate``, ``coils``, a sweep that
    does not re-optimise) is not refused over keys only the optimiser reads
    (:func:`check_optimiser_keys`); its bounds are then whatever the design says.

    Raises
    ------
    InputError
        Cross-key problems: bounds in the wrong order, a coil limit below ambient temperature.
    """
    from optimize.system import Bounds, DesignModel, Limits, Requirements, workspace_points
    from spiralcap.assemble.capsule import build_capsule
    from spiralcap.assemble.coils import build_coils
    from spiralcap.assemble.tissue import build_tissues

    d = design
    if optimiser:
        check_optimiser_keys(d)
    floor = angle_floor_deg(d)
    tolerances = build_tolerances(d)
    if d["limits.coil_temperature_C"] <= d["coils.ambient_temperature_C"]:
        raise InputError(
            "limits.coil_temperature_C",
            d["limits.coil_temperature_C"],
            f"a temperature above coils.ambient_temperature_C = "
            f"{d['coils.ambient_temperature_C']:g}",
        )
    surface = d.get("limits.surface_temperature_C")
    if surface is not None and surface <= d["coils.ambient_temperature_C"]:
        raise InputError(
            "limits.surface_temperature_C",
            surface,
            f"a temperature above coils.ambient_temperature_C = "
            f"{d['coils.ambient_temperature_C']:g}",
        )
    if d.get("coils.cooling") == "forced" and d.get("coils.air_speed_m_s") is None:
        raise InputError(
            "coils.air_speed_m_s",
            None,
            "a speed in [0, 20] m/s: coils.cooling = 'forced' needs coils.air_speed_m_s",
        )
    limits = Limits(
        current_A=d["limits.current_A"],
        voltage_V=d["limits.voltage_V"],
        power_W=d["limits.power_W"],
        coil_temperature_C=d["limits.coil_temperature_C"],
        field_exposure=d["limits.field_exposure"],
        surface_temperature_C=surface,
        copper_mass_kg=d.get("limits.copper_mass_kg"),
        **channel_limits(d),
    )
    req = Requirements(
        axial_load_N=to_si("requirements.axial_load_mN", d["requirements.axial_load_mN"]),
        slip_efficiency=d["requirements.slip_efficiency"],
        min_speed_m_s=to_si("requirements.min_speed_mm_s", d["requirements.min_speed_mm_s"]),
        min_spiral_turns=d["requirements.min_spiral_turns"],
        min_wall_strain=d["requirements.min_wall_strain"],
        min_safety_factor=d["requirements.min_safety_factor"],
        min_clearance_m=to_si("coils.min_clearance_mm", d["coils.min_clearance_mm"]),
        bore_radius_m=bore_radius_m(d),
    )
    bounds = Bounds(
        helical_angle_min_rad=to_si(
            "optimize.helical_angle_min_deg", d["optimize.helical_angle_min_deg"]
        ),
        helical_angle_max_rad=to_si(
            "optimize.helical_angle_max_deg", d["optimize.helical_angle_max_deg"]
        ),
        frequency_min_hz=d["optimize.frequency_min_hz"],
        frequency_max_hz=d["optimize.frequency_max_hz"],
        objective=d["optimize.objective"],
        starts=d["optimize.starts"],
    )
    tissues = tuple(build_tissues(d))
    _check_lumen_tolerance(d, tissues)
    return DesignModel(
        coils=build_coils(d),
        capsule=build_capsule(d),
        tissues=tissues,
        frequency_hz=d["operation.frequency_hz"],
        headings=_headings(d),
        points_m=workspace_points(d["workspace.radius_m"]),
        limits=limits,
        requirements=req,
        bounds=_bounds_within_floor(bounds, floor, tolerances),
        tolerances=tolerances,
        winding_temperature_C=winding_temperature_C(d),
        ambient_temperature_C=d["coils.ambient_temperature_C"],
        heat_transfer_coefficient_W_m2K=d.get("coils.heat_transfer_coefficient_W_m2K"),
        cooling=d.get("coils.cooling") or "natural",
        air_speed_m_s=d.get("coils.air_speed_m_s") or 0.0,
        winding_conductivity_W_mK=d["coils.winding_conductivity_W_mK"],
        surface_emissivity=d["coils.surface_emissivity"],
        session_s=None
        if d.get("operation.session_min") is None
        else to_si("operation.session_min", d["operation.session_min"]),
        field_amplitude_T=(
            None
            if d.get("operation.field_amplitude_mT") is None
            else to_si("operation.field_amplitude_mT", d["operation.field_amplitude_mT"])
        ),
        sizing=build_sizing(d) if optimiser else None,  # free hardware: the optimiser's
    )


def angle_floor_deg(design: Design) -> float:
    """The least helical angle the capsule's spiral can be wound at (its turns do not touch)
    and the model holds at, deg."""
    import capsule as cap

    body_m = to_si("capsule.diameter_mm", design["capsule.diameter_mm"])
    wire_m = to_si("capsule.spiral.wire_diameter_mm", design["capsule.spiral.wire_diameter_mm"])
    least_rad = cap.min_helical_angle_for_clearance_rad(
        cap.helix_diameter_m(body_m, wire_m), wire_m, design["capsule.spiral.starts"]
    )
    return max(MIN_MODEL_ANGLE_deg, to_unit(least_rad, "deg"))


def check_optimiser_keys(design: Design) -> None:
    """The optimiser's own keys against each other and the capsule: bounds in order, the
    smallest helical angle makeable (InputError naming the key otherwise)."""
    d = design
    for lo, hi in (
        ("optimize.helical_angle_min_deg", "optimize.helical_angle_max_deg"),
        ("optimize.frequency_min_hz", "optimize.frequency_max_hz"),
    ):
        if d[lo] > d[hi]:
            raise InputError(hi, d[hi], f"a value >= {lo} = {d[lo]:g}")
    floor = angle_floor_deg(d)
    if d["optimize.helical_angle_min_deg"] < floor:
        raise InputError(
            "optimize.helical_angle_min_deg",
            d["optimize.helical_angle_min_deg"],
            f"an angle >= {floor:.3g} deg (below it the spiral's turns touch or the "
            "paper's profile conversion no longer holds)",
        )


def build_tolerances(d: Design) -> Any:
    """The :class:`optimize.system.Tolerances` of ``[tolerances]`` (SI), checked against the
    design's own values: the band of each key must stay inside what the key allows.

    Raises
    ------
    InputError
        A tolerance that takes the spiral's angle out of (0, 90) deg or its wire to zero.
    """
    from optimize.system import Tolerances

    da = d["tolerances.helical_angle_deg"]
    angle = d["capsule.spiral.helical_angle_deg"]
    if not (angle - da > 0.0 and angle + da < 90.0):
        raise InputError(
            "tolerances.helical_angle_deg",
            da,
            f"a tolerance that keeps capsule.spiral.helical_angle_deg = {angle:g} ± it inside "
            "(0, 90) deg",
        )
    dw = d["tolerances.spiral_wire_diameter_mm"]
    wire = d["capsule.spiral.wire_diameter_mm"]
    if not dw < wire:
        raise InputError(
            "tolerances.spiral_wire_diameter_mm",
            dw,
            f"a tolerance below capsule.spiral.wire_diameter_mm = {wire:g}",
        )
    return Tolerances(
        helical_angle_rad=to_si("tolerances.helical_angle_deg", da),
        spiral_wire_diameter_m=to_si("tolerances.spiral_wire_diameter_mm", dw),
        lumen_diameter_m=to_si("tolerances.lumen_diameter_mm", d["tolerances.lumen_diameter_mm"]),
    )


def _check_lumen_tolerance(d: Design, tissues: tuple) -> None:
    """Every tissue set's narrowest lumen (its lumen less the tolerance) must stay open."""
    dl = d["tolerances.lumen_diameter_mm"]
    least = to_unit(min(t.lumen_diameter_m for t in tissues), "mm")
    if not dl < least:
        raise InputError(
            "tolerances.lumen_diameter_mm",
            dl,
            f"a tolerance below the narrowest tissue set's lumen, {least:g} mm",
        )


def _bounds_within_floor(bounds: Any, floor_deg: float, tolerances: Any) -> Any:
    """``bounds`` with the least helical angle raised so that its flattest corner (the angle
    less its tolerance) stays at or above ``floor_deg``, the model's and the spiral's floor:
    the optimiser cannot hold a row at a corner outside the model."""
    from dataclasses import replace

    least = from_unit(floor_deg, "deg") + tolerances.helical_angle_rad
    if bounds.helical_angle_min_rad >= least:
        return bounds
    return replace(bounds, helical_angle_min_rad=min(least, bounds.helical_angle_max_rad))


def channel_limits(d: Design) -> dict[str, Any]:
    """The per-pair amplifier limits (``limits.{x,y,z}.current_A`` ...) and the envelope as
    :class:`optimize.Limits` fields (SI; NaN where a pair has no limit of its own)."""
    out: dict[str, Any] = {}
    own = set()
    kinds = (("current", "A"), ("voltage", "V"), ("power", "W"), ("apparent_power", "VA"))
    for kind, unit in kinds:
        values = [d.get(f"limits.{ax}.{kind}_{unit}") for ax in "xyz"]
        if any(v is not None for v in values):
            out[f"axis_{kind}_{unit}"] = np.array(
                [np.nan if v is None else float(v) for v in values]
            )
            own |= {f"{kind}_{ax}" for ax, v in zip("xyz", values) if v is not None}
    env = d.get("limits.envelope_mm")
    if env is not None:
        out["envelope_m"] = np.array([to_si("limits.envelope_mm", float(v)) for v in env])
    out["own"] = frozenset(own)
    return out


#: optimiser row / bound name (optimize.problem, optimize.physics) -> the design key it bounds.
#: Per-axis and per-tissue rows (``current_x``, ``safety_factor[sample2]``) map by their stem.
_CONSTRAINT_KEYS = {
    "current": "limits.current_A",
    "voltage": "limits.voltage_V",
    "temperature": "limits.coil_temperature_C",
    "temperature_rise": "limits.coil_temperature_C",
    "hot_spot": "limits.coil_temperature_C",
    "surface_temperature": "limits.surface_temperature_C",
    "power": "limits.power_W",
    "field_exposure": "limits.field_exposure",
    "speed": "requirements.min_speed_mm_s",
    "spiral_turns": "requirements.min_spiral_turns",
    "wall_strain": "requirements.min_wall_strain",
    "safety_factor": "requirements.min_safety_factor",
    "margin": "margin_Nm",
    "self_lock": "optimize.helical_angle_max_deg",
    "helical_angle_max": "optimize.helical_angle_max_deg",
    "helical_angle_min": "optimize.helical_angle_min_deg",
    "frequency_max": "optimize.frequency_max_hz",
    "frequency_min": "optimize.frequency_min_hz",
    "solver": "optimize.starts",
    "failure_probability": "requirements.max_failure_probability",
    "tolerance": "tolerances",
    "copper_mass": "limits.copper_mass_kg",
    "bore_clearance": "coils.min_clearance_mm",
    "envelope": "limits.envelope_mm",
}
#: per-pair amplifier rows (``axis_voltage_y``) -> their design key, by axis
_CHANNEL_KEYS = {
    "axis_current": "limits.{}.current_A",
    "axis_voltage": "limits.{}.voltage_V",
    "axis_power": "limits.{}.power_W",
    "axis_apparent_power": "limits.{}.apparent_power_VA",
}


def check_key(name: str) -> str:
    """The design key behind a check of :func:`optimize.evaluate` (its name, e.g. ``hot_spot_x``).

    As :func:`constraint_key`, except that the self-locking check names the helical angle itself
    (in the optimiser the same row is bounded through the angle's upper bound).
    """
    return "capsule.spiral.helical_angle_deg" if name == "self_lock" else constraint_key(name)


def constraint_key(name: str) -> str:
    """The design key behind an optimiser constraint name ('' when none).

    ``current_x`` -> ``limits.current_A``; ``safety_factor[zhou2013-sample2]`` ->
    ``requirements.min_safety_factor``; a freed hardware key's bound ``coils.x.turns@max`` ->
    ``coils.x.turns``.
    """
    stem = name.split("[", 1)[0].split("@", 1)[0]
    if stem in _CONSTRAINT_KEYS:
        return _CONSTRAINT_KEYS[stem]
    head, _, axis = stem.rpartition("_")
    if head in _CHANNEL_KEYS and axis in ("x", "y", "z"):
        return _CHANNEL_KEYS[head].format(axis)
    hardware = {hw_name: key for key, (hw_name, _) in _HARDWARE_NAMES.items()}
    if stem in hardware:  # a freed key at the edge of its box
        return "optimize.free." + hardware[stem]
    geometry = {
        "pack_side": "coils.{}.wire_diameter_mm",
        "pack_separation": "coils.{}.separation_m",
        "bore": "requirements.min_bore_m",
    }
    head, _, axis = stem.rpartition("_")
    if head in geometry and axis in ("x", "y", "z"):
        return geometry[head].format(axis)
    if stem.startswith(("clearance_", "bore_clearance")):
        return "coils.min_clearance_mm"
    if stem.startswith("magnet_"):
        return "capsule.magnet." + stem.split("_", 1)[1] + "_mm"
    if stem == "spiral_clearance":
        return "capsule.spiral.wire_diameter_mm"
    if "." in stem:  # a design key itself (free hardware bounds)
        return stem
    head, _, axis = stem.rpartition("_")
    if axis in ("x", "y", "z") and head in _CONSTRAINT_KEYS:
        return _CONSTRAINT_KEYS[head]
    return ""


#: freeable design key -> (optimize.hardware name, SI factor): the hardware rows of
#: :data:`spiralcap.keymap.FIELD_KEYS`, the factor from the key's name (a rectangle is sized at
#: its aspect by its first side a; the sized design holds [a, b])
_HARDWARE_NAMES: dict[str, tuple[str, float]] = {
    key: (field_of(key), si_factor(key)) for key in FREEABLE_KEYS
}
_FREE_PREFIX = "optimize.free."


def message_in_key_units(message: str) -> str:
    """An optimiser message with its hardware values as design keys in their own units:
    ``x.wire_diameter_m = 0.003`` -> ``coils.x.wire_diameter_mm = 3`` (the domain package names
    the variables in SI; the user set them as design keys)."""
    import re

    by_name = {name: (key, factor) for key, (name, factor) in _HARDWARE_NAMES.items()}

    def swap(m: re.Match[str]) -> str:
        key, factor = by_name[m.group(1)]
        return f"{key} = {float(m.group(2)) / factor:.4g}"

    names = "|".join(re.escape(n) for n in sorted(by_name, key=len, reverse=True))
    return re.sub(rf"(?<![\w.])({names}) = ([-+0-9.eE]+)", swap, message)


def free_keys(design: Design) -> dict[str, tuple[float, float]]:
    """The freed design keys and their [min, max], in the key's units."""
    return {
        k[len(_FREE_PREFIX) :]: (float(v[0]), float(v[1]))
        for k, v in design.items()
        if k.startswith(_FREE_PREFIX) and v is not None
    }


def _check_free_sizes(design: Design, free: dict[str, tuple[float, float]]) -> None:
    """A freed pair size must be the pair's own: ``radius_m`` of a circle, ``side_m`` of a
    square, ``sides_m`` of a rectangle (InputError naming the freed key otherwise)."""
    from spiralcap.assemble.coils import SHAPES

    sizes = {size for _, size in SHAPES.values()}
    for key, rng in free.items():
        head, _, quantity = key.rpartition(".")
        if quantity not in sizes or not head.startswith("coils."):
            continue
        shape = design.get(head + ".shape", "circle")
        own = SHAPES[shape][1]
        if quantity != own:
            raise InputError(
                _FREE_PREFIX + key,
                list(rng),
                f"the size of a {shape} pair: free {head}.{own} ({head}.shape = '{shape}')",
            )


def build_sizing(design: Design) -> Any:
    """The :class:`optimize.hardware.Sizing` of the freed keys (None when nothing is free)."""
    from optimize import hardware as hw

    free = free_keys(design)
    if not free:
        return None
    from spiralcap.assemble.measured import check_no_sizing

    check_no_sizing(design, free)
    _check_free_sizes(design, free)
    variables = tuple(
        hw.FreeVariable(
            _HARDWARE_NAMES[k][0], lo * _HARDWARE_NAMES[k][1], hi * _HARDWARE_NAMES[k][1]
        )
        for k, (lo, hi) in free.items()
    )
    wires_mm = (
        hw.IEC_R40_mm if design["coils.wire_standard"] == "iec-r40" else hw.awg_diameters_mm()
    )
    for key, (lo, hi) in free.items():  # a coil's wire is a standard diameter: one must fit
        if key.startswith("coils.") and key.endswith(".wire_diameter_mm"):
            if not any(lo <= d <= hi for d in wires_mm):
                raise InputError(
                    _FREE_PREFIX + key,
                    [lo, hi],
                    f"a range holding at least one standard wire diameter "
                    f"(coils.wire_standard = {design['coils.wire_standard']!r})",
                )
    return hw.Sizing(
        variables,
        tuple(d * 1e-3 for d in wires_mm),
        design.get("requirements.min_bore_m"),
    )


def hardware_design_values(values: dict[str, float]) -> dict[str, Any]:
    """optimize.hardware values (SI, by name) -> design keys in their units."""
    by_name = {name: (key, factor) for key, (name, factor) in _HARDWARE_NAMES.items()}
    out: dict[str, Any] = {}
    for name, v in values.items():
        if name.endswith(".side_b_m"):  # a rectangle's second side: with its first below
            continue
        key, factor = by_name[name]
        out[key] = round(v) if key.endswith(".turns") else float(f"{v / factor:.12g}")
        second = values.get(name.removesuffix("side_a_m") + "side_b_m")
        if name.endswith(".side_a_m") and second is not None:
            out[key] = [out[key], float(f"{second:.12g}")]
    return out


def optimum_values(design: Design, result: Any) -> dict[str, Any]:
    """The design keys an optimum sets: angle, frequency, the field where the objective set it,
    and every freed hardware key at its discrete optimum."""
    fields = {
        "spiral.helical_angle_rad": result.helical_angle_rad,
        "operation.frequency_hz": result.frequency_hz,
    }
    if result.field_is_set or design.get("operation.field_amplitude_mT") is not None:
        fields["operation.field_amplitude_T"] = result.field_amplitude_T
    values: dict[str, Any] = {design_key(f): float(from_field_si(f, v)) for f, v in fields.items()}
    if result.hardware is not None:
        values.update(hardware_design_values(result.hardware.discrete))
    return values


def optimum_design_toml(design: Design, result: Any) -> str:
    """The optimised design as a complete, commented design file (like ``spiralcap init``)."""
    from spiralcap.design import _to_toml

    values = {
        k: v
        for k, v in {**design, **optimum_values(design, result)}.items()
        if not k.startswith(_FREE_PREFIX)
    }
    # a path the design names, relative to the file that named it, would point elsewhere from
    # the written file's folder: write it absolute
    for key in ("tissue.uncertainty.covariance_from", "calibration.survey_csv"):
        named = design.path_of(key) if values.get(key) is not None else None
        if named is not None:
            values[key] = os.path.abspath(named)
    head = (
        "# spiralcap design file written by `spiralcap optimize` "
        f"(objective {result.objective}).\n"
        f"# Started from: {design.source}. Optimum: margin {result.margin_Nm * 1e3:.6g} mN·m, "
        f"safety factor {result.safety_factor:.6g}.\n"
        f"# Copper: {result.evaluation.copper_mass_kg:.6g} kg ("
        + ", ".join(f"{ax} {m:.4g} kg" for ax, m in zip("xyz", result.evaluation.copper_masses_kg))
        + ").\n"
        "# `spiralcap evaluate` on this file reproduces the optimum.\n\n"
    )
    return head + _to_toml(values, comments=True)


def bore_radius_m(d: Design) -> float:
    """Radius of the sphere the packs' inner faces keep ``coils.min_clearance_mm`` from: the
    workspace sphere's, m.

    Not ``requirements.min_bore_m``: that key is the least clear diameter between the packs'
    inner faces (2R − h) a sizing keeps, and its default is the design's own, so the key left
    out and the key set to its default size the same coils (issue 26). Half the key here made a
    default entered by hand ask for ``coils.min_clearance_mm`` more than the design has on each
    side (least power 160.6 W -> 302.8 W).
    """
    return float(d["workspace.radius_m"])
