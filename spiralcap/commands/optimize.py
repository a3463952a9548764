"""``spiralcap optimize``: helical angle, frequency and coil currents for the largest margin."""

from __future__ import annotations

import argparse
import math

from spiralcap.commands._common import add_design_arguments, design_from_args, print_json

#: how to show a sensitivity per SI unit in engineering units: unit -> (label, factor)
_ENGINEERING = {
    "N·m": ("mN·m", 1e-3),
    "A": ("A", 1.0),
    "V": ("V", 1.0),
    "W": ("W", 1.0),
    "K": ("K", 1.0),
    "T": ("mT", 1e-3),
    "m/s": ("mm/s", 1e-3),
    "turns": ("turn", 1.0),
    "rad": ("deg", math.pi / 180),
    "Hz": ("Hz", 1.0),
}
EXIT_INFEASIBLE = 3


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_arguments(parser)


def format_result(res) -> str:
    """Readable summary of an :class:`optimize.OptimizationResult`."""
    from spiralcap.commands.evaluate import safety_factor_text, step_out_text

    lines = [
        f"status              {res.status} ({res.solver_status}, {res.iterations} IPOPT "
        f"iterations, {res.starts} starts, {res.solve_time_s:.3f} s)"
    ]
    if res.status == "optimal":
        lines += [
            f"helical angle       {res.helical_angle_deg:.4g} deg",
            f"frequency           {res.frequency_hz:.4g} Hz",
            f"rotating field      {res.field_amplitude_T * 1e3:.4g} mT",
            "current amplitudes  "
            + ", ".join(f"{a} {i:.4g} A" for a, i in zip("xyz", res.current_amplitudes_A)),
            f"margin              {res.margin_Nm * 1e3:.4g} mN·m "
            f"(safety factor {safety_factor_text(res.safety_factor)})",
            f"forward speed       {res.speed_m_s * 1e3:.4g} mm/s",
            f"step-out frequency  {step_out_text(res.step_out_frequency_hz)}",
            "binding limits:",
        ]
        gain = "mN·m" if res.objective == "margin" else "safety factor"
        scale = 1e3 if res.objective == "margin" else 1.0
        for b in res.binding_limits:
            label, factor = _ENGINEERING.get(b.unit, (b.unit, 1.0))
            verb = "raising" if b.relax_sign > 0 else "lowering"
            lines.append(
                f"  {b.name:<20} {b.key:<32} {verb} it by 1 {label} gains "
                f"{b.gain_per_unit_relaxed * factor * scale:.4g} {gain}"
            )
        if not res.binding_limits:
            lines.append("  none")
    else:
        lines.append(res.message)
        for s in res.shortfalls:
            label, factor = _ENGINEERING.get(s.unit, (s.unit, 1.0))
            if s.name == "margin":
                lines.append(
                    f"  the magnet's torque falls short of the required torque by "
                    f"{s.short_by / factor:.4g} {label} at the best design inside the "
                    "limits (more field, a stronger magnet or a lighter load would help)"
                )
            else:
                lines.append(
                    f"  {s.key}: needs {s.needed / factor:.4g} {label}, best reachable "
                    f"{s.best / factor:.4g} {label} (short by {s.short_by / factor:.4g})"
                )
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    from optimize import optimize_design
    from spiralcap.assemble import build_model
    from spiralcap.serialize import optimization_to_dict

    design = design_from_args(args)
    res = optimize_design(build_model(design))
    if args.json:
        print_json({"design": design.source, **optimization_to_dict(res)})
    else:
        print(format_result(res))
    return 0 if res.status == "optimal" else EXIT_INFEASIBLE
