"""``spiralcap coils [DESIGN]``: per-axis coil sizing at the design's current and frequency."""

from __future__ import annotations

import argparse
from dataclasses import asdict
from typing import Any

from spiralcap.commands._common import (
    add_design_arguments,
    design_from_args,
    format_table,
    print_json,
)
from spiralcap.schema import winding_temperature_C

_TOLERANCES = (("1pct", 0.01), ("5pct", 0.05))


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """DESIGN, --set, --json and --plot."""
    add_design_arguments(parser)
    from spiralcap.commands._plot import add_geometry_plot_argument

    add_geometry_plot_argument(parser)


def _uniform(system: Any) -> dict[str, Any]:
    from coils import uniform_region

    out: dict[str, Any] = {}
    for name, tol in _TOLERANCES:
        region = uniform_region(system, tol)
        out[f"radius_{name}_m"] = region.radius_m
        out[f"worst_field_direction_{name}"] = region.field_direction
        out[f"limiting_ray_{name}"] = region.limiting_ray
        for pair in system.pairs:
            out.setdefault("per_axis", {}).setdefault(pair.axis, {})[f"radius_{name}_m"] = (
                uniform_region(pair, tol).radius_m
            )
    return out


def _axes_words(axes: tuple[str, ...]) -> str:
    if len(axes) == 1:
        return f"{axes[0]} axis"
    return ", ".join(axes[:-1]) + f" and {axes[-1]} axes alike"


def _within_limits(design: Any) -> dict[str, Any]:
    """What every limit allows at the design's frequency, worst heading: the one definition.

    The numbers come from :func:`optimize.physics.field_capacity_T`, the same function
    ``evaluate`` and ``optimize`` use, so the three commands always agree.
    """
    import numpy as np

    from optimize import physics, prepare
    from spiralcap.assemble import build_model

    model = prepare(build_model(design))
    c = model.constants
    best, caps, terms = physics.field_capacity_T(
        model.frequency_hz, c, model.limits, model.ambient_temperature_C
    )
    caps = [float(x) for x in caps]
    binding = terms[caps.index(min(caps))]
    per_axis = {}
    for k, ax in enumerate("xyz"):
        own = [(cap, t.name) for cap, t in zip(caps, terms) if t.name.endswith(f"_{ax}")]
        cap, name = min(own)
        if not np.isfinite(cap):  # no heading uses this axis: it carries no current, caps nothing
            cap, name = float(best), f"unused_{ax}"
        per_axis[ax] = {
            "max_rotating_field_T": cap,
            "max_current_A": cap * float(c.current_per_tesla_A_per_T[k]),
            "max_current_limited_by": name[: -len(f"_{ax}")],
        }
    return {
        "max_rotating_field_T": float(best),
        "limited_by": binding.name,
        "limit_key": binding.key,
        # limits on an axis no heading uses cap nothing and are left out
        "per_limit_max_field_T": {t.name: cap for t, cap in zip(terms, caps) if np.isfinite(cap)},
        "axes": per_axis,
    }


def sizing_payload(design: Any) -> dict[str, Any]:
    """The dict ``spiralcap coils --json`` prints: per-axis sizing, uniformity, field limits."""
    from coils import size_system
    from spiralcap.assemble.coils import build_coils

    system = build_coils(design)
    sizing = size_system(
        system,
        frequency_hz=design["operation.frequency_hz"],
        current_amplitude_A=design["limits.current_A"],
        winding_temperature_C=winding_temperature_C(design),
        ambient_temperature_C=design["coils.ambient_temperature_C"],
        heat_transfer_coefficient_W_m2K=design["coils.heat_transfer_coefficient_W_m2K"],
    )
    payload = asdict(sizing)
    limits = _within_limits(design)
    payload["axes"] = {a["axis"]: {**a, **limits["axes"][a["axis"]]} for a in payload["axes"]}
    payload["rotating_field_within_limits"] = {k: v for k, v in limits.items() if k != "axes"}
    payload["uniform_region"] = _uniform(system)
    return {"design": getattr(design, "source", "design"), **payload}


def _text(p: dict[str, Any]) -> str:
    axes = [p["axes"][ax] for ax in "xyz"]
    rows = [
        [
            a["axis"],
            a["radius_m"],
            a["turns"],
            a["wire_diameter_m"] * 1e3,
            a["winding_pack_side_m"] * 1e3,
            a["wire_length_m"],
            a["field_per_amp_T_per_A"] * 1e3,
            a["resistance_ohm"],
            a["inductance_H"] * 1e3,
            a["impedance_ohm"],
            a["voltage_amplitude_V"],
            a["power_W"],
            a["temperature_rise_K"],
            a["coil_temperature_C"],
            a["field_amplitude_T"] * 1e3,
        ]
        for a in axes
    ]
    table = format_table(
        [
            "axis",
            "radius_m",
            "turns",
            "wire_mm",
            "pack_mm",
            "wire_m",
            "mT_per_A",
            "R_ohm",
            "L_mH",
            "Z_ohm",
            "V_amp_V",
            "P_W",
            "rise_K",
            "coil_C",
            "B_mT",
        ],
        rows,
    )
    uniform = p["uniform_region"]
    limits = format_table(
        ["axis", "I_max_A", "limited_by", "B_rot_max_mT", "uniform_1pct_m", "uniform_5pct_m"],
        [
            [
                a["axis"],
                a["max_current_A"],
                a["max_current_limited_by"],
                a["max_rotating_field_T"] * 1e3,
                uniform["per_axis"][a["axis"]]["radius_1pct_m"],
                uniform["per_axis"][a["axis"]]["radius_5pct_m"],
            ]
            for a in axes
        ],
    )
    w = p["rotating_field_within_limits"]
    lines = [
        f"design: {p['design']}",
        f"current amplitude {p['current_amplitude_A']:g} A per pair at {p['frequency_hz']:g} Hz; "
        f"copper at {p['winding_temperature_C']:g} °C, ambient {p['ambient_temperature_C']:g} °C, "
        f"h = {p['heat_transfer_coefficient_W_m2K']:g} W/(m²·K)",
        "",
        table,
        f"total copper loss: {p['total_power_W']:.4g} W",
        "",
        "largest current each pair may carry, worst heading (current, voltage, temperature):",
        limits,
        "",
        "uniform region of the three-axis system (worst of 13 static field directions):",
        f"  ±1 %: radius {uniform['radius_1pct_m']:.4g} m;  "
        f"±5 %: radius {uniform['radius_5pct_m']:.4g} m",
        "rotating field, worst heading:",
        f"  at the current limit: {p['current_limited_rotating_field_T'] * 1e3:.4g} mT, set by "
        f"the {_axes_words(tuple(p['current_limiting_axes']))}: the smallest field per amp x "
        "current",
        f"  within all limits: {w['max_rotating_field_T'] * 1e3:.4g} mT, set by {w['limited_by']}"
        f" ({w['limit_key']}); the power limit alone allows "
        f"{w['per_limit_max_field_T']['power'] * 1e3:.4g} mT",
    ]
    hottest = max(axes, key=lambda a: a["coil_temperature_C"])
    if hottest["coil_temperature_C"] > p["winding_temperature_C"]:
        lines.append(
            f"note: at {p['current_amplitude_A']:g} A the {hottest['axis']} coils would "
            f"reach {hottest['coil_temperature_C']:.4g} °C, above the "
            f"{p['winding_temperature_C']:g} °C at which R was evaluated"
        )
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    """Print the sizing table (or JSON); with --plot also draw the geometry view."""
    from spiralcap.commands._plot import check_figure_path, write_geometry

    if args.plot:
        check_figure_path("--plot", args.plot)
    design = design_from_args(args)
    payload = sizing_payload(design)
    if args.json:
        print_json(payload)
    else:
        print(_text(payload))
    if args.plot:
        write_geometry(args.plot, design, quiet=args.json)
    return 0
