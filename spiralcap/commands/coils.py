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
    """DESIGN, --set and --json."""
    add_design_arguments(parser)


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
                uniform_region(pair, tol).radius_m)
    return out


def _axes_words(axes: tuple[str, ...]) -> str:
    if len(axes) == 1:
        return f"{axes[0]} axis"
    return ", ".join(axes[:-1]) + f" and {axes[-1]} axes alike"


def _text(source: str, sizing: Any, uniform: dict[str, Any]) -> str:
    rows = [[a.axis, a.radius_m, a.turns, a.wire_diameter_m * 1e3, a.winding_pack_side_m * 1e3,
             a.wire_length_m, a.field_per_amp_T_per_A * 1e3, a.resistance_ohm,
             a.inductance_H * 1e3, a.impedance_ohm, a.voltage_amplitude_V, a.power_W,
             a.temperature_rise_K, a.coil_temperature_C, a.field_amplitude_T * 1e3]
            for a in sizing.axes]
    table = format_table(
        ["axis", "radius_m", "turns", "wire_mm", "pack_mm", "wire_m", "mT_per_A", "R_ohm",
         "L_mH", "Z_ohm", "V_amp_V", "P_W", "rise_K", "coil_C", "B_mT"], rows)
    limits = format_table(
        ["axis", "I_max_A", "limited_by", "B_rot_max_mT", "uniform_1pct_m", "uniform_5pct_m"],
        [[a.axis, a.max_current_A, a.max_current_limited_by, a.max_rotating_field_T * 1e3,
          uniform["per_axis"][a.axis]["radius_1pct_m"],
          uniform["per_axis"][a.axis]["radius_5pct_m"]] for a in sizing.axes])
    s = sizing
    limited = (f"the {s.rotating_field_limiting_axis} axis ({s.rotating_field_limited_by} limit)"
               if s.rotating_field_limited_by != "power" else "the total power limit")
    lines = [
        f"design: {source}",
        f"current amplitude {s.current_amplitude_A:g} A per pair at {s.frequency_hz:g} Hz; "
        f"copper at {s.winding_temperature_C:g} °C, ambient {s.ambient_temperature_C:g} °C, "
        f"h = {s.heat_transfer_coefficient_W_m2K:g} W/(m²·K)",
        "",
        table,
        f"total copper loss: {s.total_power_W:.4g} W",
        "",
        "largest current each pair may carry (current, voltage and coil-temperature limits):",
        limits,
        "",
        "uniform region of the three-axis system (worst of 13 static field directions):",
        f"  ±1 %: radius {uniform['radius_1pct_m']:.4g} m;  "
        f"±5 %: radius {uniform['radius_5pct_m']:.4g} m",
        "rotating field, worst heading:",
        f"  at the current limit: {s.current_limited_rotating_field_T * 1e3:.4g} mT, "
        f"set by the {_axes_words(s.current_limiting_axes)}: the smallest field per amp x current",
        f"  within all limits: {s.max_rotating_field_T * 1e3:.4g} mT, set by {limited}; "
        f"the power limit alone allows {s.power_limited_rotating_field_T * 1e3:.4g} mT",
    ]
    hottest = max(s.axes, key=lambda a: a.coil_temperature_C)
    if hottest.coil_temperature_C > s.winding_temperature_C:
        lines.append(f"note: the {hottest.axis} coils reach {hottest.coil_temperature_C:.4g} °C, "
                     "above coils.winding_temperature_C at which R was evaluated")
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    """Print the sizing table (or JSON)."""
    from coils import size_system
    from spiralcap.assemble.coils import build_coils

    design = design_from_args(args)
    system = build_coils(design)
    sizing = size_system(
        system, frequency_hz=design["operation.frequency_hz"],
        current_amplitude_A=design["limits.current_A"],
        winding_temperature_C=winding_temperature_C(design),
        ambient_temperature_C=design["coils.ambient_temperature_C"],
        heat_transfer_coefficient_W_m2K=design["coils.heat_transfer_coefficient_W_m2K"],
        voltage_limit_V=design["limits.voltage_V"], power_limit_W=design["limits.power_W"],
        coil_temperature_limit_C=design["limits.coil_temperature_C"])
    uniform = _uniform(system)
    if args.json:
        payload = asdict(sizing)
        payload["axes"] = {a["axis"]: a for a in payload["axes"]}
        print_json({"design": design.source, **payload, "uniform_region": uniform})
    else:
        print(_text(design.source, sizing, uniform))
    return 0
