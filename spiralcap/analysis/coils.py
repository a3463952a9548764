"""The coil analysis behind ``spiralcap coils`` and the report's coil section.

:func:`analyse_coils` sizes every pair at the current limit (coils.size_system), takes what the
limits allow from :func:`optimize.physics.field_capacity` (the one definition that ``evaluate``
and ``optimize`` use, binding limit named once there), the thermal state of each pair at the
operating point (steady, or at the end of ``operation.session_min``, with its heating curve),
and the uniform regions. :func:`coils_payload` is the JSON form ``spiralcap coils --json``
prints.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace
from typing import Any, ClassVar

import numpy as np

from optimize.views import Viewable
from spiralcap.core.checks import guard, instance
from spiralcap.design import Design

_TOLERANCES = (("1pct", 0.01), ("5pct", 0.05))
_AXES = ("x", "y", "z")


@dataclass(frozen=True)
class AxisLimit:
    """Largest current one pair may carry inside every limit (worst heading), and why."""

    axis: str
    max_current_A: float
    max_current_limited_by: str
    max_rotating_field_T: float
    max_current_limit_key: str = ""  # the design key of that limit ("" for an unused pair)


@dataclass(frozen=True)
class HeatingCurve:
    """Heating of one pair from ambient at its operating current (°C against s): at each time
    the end of a session that long (conduction in the pack, :mod:`coils.thermal_system`)."""

    axis: str
    current_A: float
    time_s: np.ndarray
    surface_C: np.ndarray
    mean_C: np.ndarray
    hot_spot_C: np.ndarray
    time_constant_s: float
    heat_capacity_J_per_K: float
    final_mean_C: float
    final_hot_spot_C: float
    surface_max_C: np.ndarray | None = None


@dataclass(frozen=True)
class AxisOperatingThermal:
    """Thermal state of one pair at the operating field (worst-heading current).

    Steady temperatures always; ``session_*`` at the end of the session (None without one).
    ``resistance_ohm`` is at the mean winding temperature of the run (session end, or steady):
    the resistance ``spiralcap waveforms`` drives with.
    """

    axis: str
    current_A: float
    resistance_ohm: float
    power_W: float
    surface_temperature_C: float
    mean_temperature_C: float
    hot_spot_temperature_C: float
    heat_capacity_J_per_K: float
    time_constant_s: float
    session_hot_spot_temperature_C: float | None
    session_mean_temperature_C: float | None
    surface_max_temperature_C: float = float("nan")
    convection_coefficient_W_m2K: float = float("nan")
    radiation_view_factor: float = 1.0
    session_surface_max_temperature_C: float | None = None


@dataclass(frozen=True)
class UniformRegions:
    """Radii of the ±1 % and ±5 % spheres (three-axis system and each pair alone), m."""

    radius_1pct_m: float
    radius_5pct_m: float
    worst_field_direction_1pct: tuple[float, ...]
    worst_field_direction_5pct: tuple[float, ...]
    limiting_ray_1pct: tuple[float, ...]
    limiting_ray_5pct: tuple[float, ...]
    per_axis_radius_1pct_m: dict[str, float]
    per_axis_radius_5pct_m: dict[str, float]


@dataclass(frozen=True)
class CoilAnalysis(Viewable):
    """Everything ``spiralcap coils`` reports (SI; names carry units); in a notebook a table of
    the operating point, ``.plot()`` the heating curves (:mod:`spiralcap.notebook`)."""

    _view_kind: ClassVar[str] = "coil_analysis"

    design: str
    sizing: Any  # coils.SystemSizing at the current limit
    capacity: Any  # optimize.physics.FieldCapacity at the operating frequency
    axis_limits: tuple[AxisLimit, ...]
    operating_field_T: float
    operating_field_fixed: bool
    session_s: float | None
    limit_temperature_C: float
    operating: tuple[AxisOperatingThermal, ...]
    heating: tuple[HeatingCurve, ...]
    uniform: UniformRegions
    min_clearance_m: float = 0.0
    pack_clearances_m: dict[str, float] | None = None  # {"x/y": …, "x/z": …, "y/z": …}
    bore_clearance_m: float = math.nan
    bore_radius_m: float = 0.0
    bill_of_materials: tuple = ()  # spiralcap.analysis.bom.BomRow per pair
    warnings: tuple[str, ...] = ()  # spiralcap.analysis.touch: a pack surface too hot to hold
    stray: Any = None  # spiralcap.analysis.stray.StrayField at the operating field
    measured: tuple = ()  # spiralcap.analysis.measured.MeasuredPair per measured pair
    calibration: dict[str, Any] | None = None  # calibrated coils: actuation, gains, tilts (SI)
    #: each pair's amplifier current key: ``limits.x.current_A`` where set, else the global one
    current_keys: tuple[str, ...] = ("limits.current_A",) * 3


def _uniform(system: Any) -> UniformRegions:
    from coils.uniformity import pair_uniform_regions, uniform_regions

    tols = [tol for _, tol in _TOLERANCES]
    pairs = pair_uniform_regions(system.pairs, tols)
    regions = uniform_regions(system, tols, pair_regions=pairs)
    whole = {name: r for (name, _), r in zip(_TOLERANCES, regions)}
    per = {
        name: {p.axis: float(pairs[k][i].radius_m) for k, p in enumerate(system.pairs)}
        for i, (name, _) in enumerate(_TOLERANCES)
    }
    return UniformRegions(
        radius_1pct_m=float(whole["1pct"].radius_m),
        radius_5pct_m=float(whole["5pct"].radius_m),
        worst_field_direction_1pct=tuple(float(x) for x in whole["1pct"].field_direction),
        worst_field_direction_5pct=tuple(float(x) for x in whole["5pct"].field_direction),
        limiting_ray_1pct=tuple(float(x) for x in whole["1pct"].limiting_ray),
        limiting_ray_5pct=tuple(float(x) for x in whole["5pct"].limiting_ray),
        per_axis_radius_1pct_m=per["1pct"],
        per_axis_radius_5pct_m=per["5pct"],
    )


def operating_thermal(
    model: Any, field_T: float
) -> tuple[list[AxisOperatingThermal], list[HeatingCurve]]:
    """Thermal state and heating curve of each pair at centre field ``field_T`` (worst heading).

    ``model`` is a prepared :class:`optimize.DesignModel`. The steady state and the session's
    end are :func:`optimize.physics.pair_states` (the pairs radiating to each other); the curve
    at time t is the end of a session of length t (the same model, so it passes through the
    session's end and starts at ambient)."""
    from coils.thermal_system import pair_temperatures
    from optimize import physics
    from spiralcap.core.constants import COPPER_TEMPERATURE_COEFFICIENT_per_K as ALPHA

    c, amb = model.constants, model.ambient_temperature_C
    per = np.asarray(c.current_per_tesla_A_per_T, dtype=float)
    currents = [field_T * float(per[k]) for k in range(3)]
    r20s = [float(r) for r in c.resistance_20C_ohm]
    steady = pair_temperatures(c.packs, r20s, currents, amb, c.view_factors)
    session = None if c.session_s is None else physics.pair_states(field_T, c, amb)
    taus = [float(st.time_constant_s) for st in steady]
    span = max((4.0 * t if np.isfinite(t) and t > 0 else 3600.0) for t in taus)
    if c.session_s is not None:
        span = max(span, 1.2 * c.session_s)
    t = np.linspace(0.0, span, 241)
    if c.session_s is not None:
        t = np.unique(np.append(t, float(c.session_s)))
    runs = pair_temperatures(c.packs, r20s, currents, amb, c.view_factors, t)
    vf = None if c.view_factors is None else np.asarray(c.view_factors, dtype=float)
    out, curves = [], []
    for k, ax in enumerate(_AXES):
        st, pack, run = steady[k], c.packs[k], runs[k]
        end = None if session is None else session[k]
        mean_run = float(st.mean_C) if end is None else float(end.mean_C)
        out.append(
            AxisOperatingThermal(
                axis=ax,
                current_A=currents[k],
                resistance_ohm=r20s[k] * (1.0 + ALPHA * (mean_run - 20.0)),
                power_W=float(st.power_W),
                surface_temperature_C=float(st.surface_C),
                mean_temperature_C=float(st.mean_C),
                hot_spot_temperature_C=float(st.hot_spot_C),
                heat_capacity_J_per_K=float(pack.heat_capacity_J_per_K),
                time_constant_s=taus[k],
                session_hot_spot_temperature_C=None if end is None else float(end.hot_spot_C),
                session_mean_temperature_C=None if end is None else float(end.mean_C),
                surface_max_temperature_C=float(st.surface_max_C),
                convection_coefficient_W_m2K=float(st.convection_W_m2K),
                radiation_view_factor=1.0 if vf is None else float(vf[k, 0]),
                session_surface_max_temperature_C=(
                    None if end is None else float(end.surface_max_C)
                ),
            )
        )
        curves.append(
            HeatingCurve(
                axis=ax,
                current_A=currents[k],
                time_s=t,
                surface_C=np.asarray(run.surface_C, dtype=float),
                mean_C=np.asarray(run.mean_C, dtype=float),
                hot_spot_C=np.asarray(run.hot_spot_C, dtype=float),
                time_constant_s=taus[k],
                heat_capacity_J_per_K=float(pack.heat_capacity_J_per_K),
                final_mean_C=float(st.mean_C),
                final_hot_spot_C=float(st.hot_spot_C),
                surface_max_C=np.asarray(run.surface_max_C, dtype=float),
            )
        )
    return out, curves


@guard(design=instance(Design, "a spiralcap.design.Design (spiralcap.design.load_design)"))
def analyse_coils(design: Any, model: Any = None) -> CoilAnalysis:
    """The coil analysis of a validated design (see the module docstring).

    ``model``: ``spiralcap.assemble.build_model(design)`` if the caller has it (its Constants
    and their cached field caps are reused); built here otherwise.
    """
    from coils import size_system
    from optimize import physics, prepare
    from spiralcap.assemble import build_model
    from spiralcap.assemble.system import constraint_key

    model = prepare(model if model is not None else build_model(design, optimiser=False))
    c = model.constants
    # each pair at its own amplifier channel's current where limits.{x,y,z}.current_A is set
    channels = tuple(float(model.limits.channel("current", k)[1]) for k in range(3))
    sizing = size_system(
        model.coils,
        frequency_hz=model.frequency_hz,
        current_amplitude_A=channels,
        ambient_temperature_C=model.ambient_temperature_C,
        heat_transfer_coefficient_W_m2K=model.heat_transfer_coefficient_W_m2K,
        winding_conductivity_W_mK=model.winding_conductivity_W_mK,
        surface_emissivity=model.surface_emissivity,
        headings=model.headings,
        packs=c.packs,
        view_factors=c.view_factors,
    )
    cap = physics.field_capacity(model.frequency_hz, c, model.limits, model.ambient_temperature_C)
    per = np.asarray(c.current_per_tesla_A_per_T, dtype=float)
    limits = []
    for k, ax in enumerate(_AXES):
        own = [(v, name) for name, v in cap.caps_T.items() if name.endswith(f"_{ax}")]
        best, name = min(own)
        if not np.isfinite(best):  # no heading uses this axis: it carries no current, caps nothing
            best, name = cap.field_T, f"unused_{ax}"
        amps = best * float(per[k])
        limits.append(
            AxisLimit(
                axis=ax,
                max_current_A=amps,
                max_current_limited_by=stable_limit_name(name)[: -len(f"_{ax}")],
                max_rotating_field_T=best,
                max_current_limit_key=constraint_key(name),
            )
        )
    fixed = model.field_amplitude_T is not None
    field = cap.field_T if model.field_amplitude_T is None else float(model.field_amplitude_T)
    operating, curves = operating_thermal(model, field)
    from coils.clearance import bore_clearance_m, pack_clearances_m
    from spiralcap.analysis.bom import bill_of_materials

    req = model.requirements
    analysis = CoilAnalysis(
        design=str(getattr(design, "source", "design")),
        sizing=sizing,
        capacity=cap,
        axis_limits=tuple(limits),
        operating_field_T=field,
        operating_field_fixed=fixed,
        session_s=c.session_s,
        limit_temperature_C=float(model.limits.coil_temperature_C),
        operating=tuple(operating),
        heating=tuple(curves),
        uniform=_uniform(model.coils),
        min_clearance_m=float(req.min_clearance_m),
        pack_clearances_m=pack_clearances_m(model.coils.pairs),
        bore_clearance_m=bore_clearance_m(model.coils.pairs, req.bore_radius_m),
        bore_radius_m=float(req.bore_radius_m),
        current_keys=tuple(constraint_key(model.limits.channel("current", k)[0]) for k in range(3)),
    )
    from spiralcap.analysis.measured import measured_pairs
    from spiralcap.analysis.stray import stray_field
    from spiralcap.analysis.touch import touch_warning

    touch = touch_warning(model, field)
    measured = measured_pairs(model.coils)
    return replace(
        analysis,
        bill_of_materials=bill_of_materials(model, analysis),
        warnings=(() if touch is None else (touch.words(),))
        + tuple(w for m in measured for w in m.warnings()),
        stray=stray_field(model, field),
        measured=measured,
        calibration=calibration_summary(model.coils),
    )


def calibration_summary(coils: Any) -> dict[str, Any] | None:
    """The calibrated centre actuation of ``coils`` beside the model's (None: not calibrated):
    ``actuation_matrix_T_per_A`` (column k: pair k), ``model_actuation_matrix_T_per_A``,
    ``gain_factors``, ``axis_tilts_deg``, ``background_field_T``."""
    if getattr(coils, "calibration", None) is None:
        return None
    from coils.calibration import gains_and_tilts
    from spiralcap.assemble.calibration import nominal

    a = np.asarray(coils.actuation_matrix_T_per_A)
    g = nominal(coils).field_matrix(np.zeros((1, 3)))[0]
    gains, tilts = gains_and_tilts(a, g)
    return {
        "actuation_matrix_T_per_A": a.tolist(),
        "model_actuation_matrix_T_per_A": g.tolist(),
        "gain_factors": dict(zip(_AXES, map(float, gains), strict=True)),
        "axis_tilts_deg": dict(zip(_AXES, map(float, tilts), strict=True)),
        "background_field_T": [float(v) for v in coils.background_T],
    }


def stable_limit_name(name: str) -> str:
    """A limit's name in the JSON, the same whichever amplifier channel sets it:
    ``axis_voltage_y`` (the y pair's own channel, ``limits.y.voltage_V``) -> ``voltage_y``, as
    the global limit's row is named; the design key that sets it is in ``per_limit_key``."""
    return name[len("axis_") :] if name.startswith("axis_") else name


def coils_payload(a: CoilAnalysis) -> dict[str, Any]:
    """The JSON dict of ``spiralcap coils --json`` (units in every key)."""
    sizing = asdict(a.sizing)
    if sizing["heat_transfer_coefficient_W_m2K"] is None:  # one type per field: no null
        del sizing["heat_transfer_coefficient_W_m2K"]
    sizing["axes"] = _axes_payload(a, sizing["axes"])
    uniform = _uniform_payload(a.uniform)
    op = {x.axis: asdict(x) for x in a.operating}
    from spiralcap.assemble.system import constraint_key
    from spiralcap.presentation import readable

    return {
        "design": a.design,
        **sizing,
        "rotating_field_within_limits": {
            "max_rotating_field_T": a.capacity.field_T,
            "limited_by": stable_limit_name(a.capacity.limited_by),
            "limited_by_words": readable(a.capacity.limited_by),
            "limit_key": constraint_key(a.capacity.limited_by),
            "per_limit_max_field_T": {
                stable_limit_name(k): v for k, v in a.capacity.caps_T.items()
            },
            "per_limit_key": {stable_limit_name(k): constraint_key(k) for k in a.capacity.caps_T},
        },
        "operating_point": {
            "field_amplitude_T": a.operating_field_T,
            "field_fixed": a.operating_field_fixed,
            **({} if a.session_s is None else {"session_s": a.session_s}),
            "limit_temperature_C": a.limit_temperature_C,
            # one type per field: the session_* temperatures only with a session
            "axes": {ax: {k: v for k, v in d.items() if v is not None} for ax, d in op.items()},
        },
        "uniform_region": uniform,
        "copper_mass_kg": float(sum(s["copper_mass_kg"] for s in sizing["axes"].values())),
        "min_clearance_m": a.min_clearance_m,
        "pack_clearances_m": dict(a.pack_clearances_m or {}),
        "bore_clearance_m": a.bore_clearance_m,
        "bore_radius_m": a.bore_radius_m,
        "bill_of_materials": [
            {**asdict(r), "wire_diameter_m": r.wire_diameter_mm * 1e-3}  # SI beside the spec
            for r in a.bill_of_materials
        ],
        "warnings": list(a.warnings),
        **({} if a.stray is None else {"stray_field": _stray_payload(a.stray)}),
        **({} if a.calibration is None else {"calibration": a.calibration}),
    }


def _axes_payload(a: CoilAnalysis, axes: list[dict[str, Any]]) -> dict[str, Any]:
    """Each pair's sizing, its limits and flags, keyed by axis: measured beside computed where
    the lab measured the pair, the amplifier channel each is sized at, a side only on a square
    and sides only on a rectangle, a square pack's side only where the pack is square."""
    from spiralcap.analysis.measured import measured_payload

    lim = {x.axis: asdict(x) for x in a.axis_limits}
    out = {
        s["axis"]: {
            **s,
            **lim[s["axis"]],
            # no steady state at the current limit: the temperatures, R and P are undefined
            "thermal_runaway": not math.isfinite(s["hot_spot_temperature_C"]),
        }
        for s in axes
    }
    for m in a.measured:  # a lab's measured pair: measured beside computed, the deviation
        out[m.axis]["measured"] = measured_payload(m)
    for ax, key in zip(_AXES, a.current_keys):  # the amplifier channel each pair is sized at
        out[ax]["current_limit_key"] = key
    for s in out.values():
        _shape_fields(s)
    return out


def _shape_fields(s: dict[str, Any]) -> None:
    """Drop the size fields a pair's shape does not have (one type per field: no null)."""
    if s["side_m"] is None:  # a side only on a square pair (radius_m: half of it)
        del s["side_m"]
    if s["sides_m"] is None:  # sides only on a rectangle (radius_m: half the shorter)
        del s["sides_m"]
    else:
        s["sides_m"] = list(s["sides_m"])
    if not math.isclose(s["winding_pack_width_m"], s["winding_pack_depth_m"], rel_tol=1e-12):
        del s["winding_pack_side_m"]  # the side of a square pack only where it is one


def _uniform_payload(u: Any) -> dict[str, Any]:
    """The uniform regions (±1 %, ±5 %) in SI, the whole field's and each axis's."""
    return {
        "radius_1pct_m": u.radius_1pct_m,
        "radius_5pct_m": u.radius_5pct_m,
        "worst_field_direction_1pct": list(u.worst_field_direction_1pct),
        "worst_field_direction_5pct": list(u.worst_field_direction_5pct),
        "limiting_ray_1pct": list(u.limiting_ray_1pct),
        "limiting_ray_5pct": list(u.limiting_ray_5pct),
        "per_axis": {
            ax: {
                "radius_1pct_m": u.per_axis_radius_1pct_m[ax],
                "radius_5pct_m": u.per_axis_radius_5pct_m[ax],
            }
            for ax in _AXES
        },
    }


def _stray_payload(stray: Any) -> dict[str, Any]:
    from spiralcap.analysis.stray import stray_payload

    return stray_payload(stray)
