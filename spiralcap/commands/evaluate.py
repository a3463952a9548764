"""``spiralcap evaluate``: the design at its operating point."""

from __future__ import annotations

import argparse

from spiralcap.commands._common import add_design_arguments, design_from_args, print_json


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_arguments(parser)


def safety_factor_text(value: float) -> str:
    """A safety factor, or "unbounded (no torque required)" where nothing resists the capsule."""
    return f"{value:.3g}" if value < float("inf") else "unbounded (no torque is required)"


def step_out_text(hz: float) -> str:
    """A step-out frequency in words for the two ends of the search range."""
    from spiralcap.serialize import _step_out

    value, bound = _step_out(hz)
    if bound == "above_search_range":
        return f"above {value:g} Hz (the top of the search)"
    if bound == "below_search_range":
        return f"below {value:g} Hz (the capsule cannot keep up at any frequency)"
    return f"{value:.4g} Hz"


def _failed(name: str) -> str:
    return "the spiral self-locks: α + atan μ ≥ 90°" if name == "self_lock" else name


def format_evaluation(ev) -> str:
    """Readable summary of an :class:`optimize.Evaluation`."""
    from spiralcap.commands._common import format_table
    from spiralcap.presentation import shown

    mnm = 1e3

    from spiralcap.assemble.system import check_key

    def check_row(c) -> list:
        unit, factor = shown(c.unit)
        return [
            c.name,
            check_key(c.name),
            c.value * factor,
            f"{c.sense} {c.allowed * factor:.4g}",
            unit,
            "yes" if c.ok else "NO",
        ]

    lines = [
        f"operating point     helical angle {ev.helical_angle_deg:.3g} deg, "
        f"{ev.frequency_hz:.4g} Hz",
        f"rotating field      {ev.field_amplitude_T * 1e3:.4g} mT at the centre "
        + (
            "(fixed: operation.field_amplitude_mT)"
            if ev.field_limited_by == "fixed"
            else f"(limited by {ev.field_limited_by})"
        )
        + f"; weakest over workspace x{ev.workspace_factor:.4f}",
        "currents            "
        + ", ".join(f"{ax} {i:.4g} A" for ax, i in zip("xyz", ev.current_amplitudes_A)),
        f"magnetic torque     {ev.magnetic_torque_Nm * mnm:.4g} mN·m (synchronous, worst point)",
        f"resistive torque    {ev.resistive_torque_Nm * mnm:.4g} mN·m ({ev.worst_tissue})",
        f"thrust torque       {ev.thrust_torque_Nm * mnm:.4g} mN·m"
        + (
            " (the spiral self-locks: no finite torque pushes the load)"
            if any(c.name == "self_lock" and not c.ok for c in ev.checks)
            else ""
        ),
        f"margin              {ev.margin_Nm * mnm:.4g} mN·m (safety factor "
        f"{safety_factor_text(ev.safety_factor)})",
        f"step-out frequency  {step_out_text(ev.step_out_frequency_hz)}"
        " at this field; the "
        f"drive holds a margin up to {ev.max_frequency_hz:.4g} Hz"
        f"{' or more' if ev.max_frequency_beyond_search else ''} "
        f"(limited by {ev.max_frequency_limited_by})",
        f"forward speed       {ev.speed_m_s * 1e3:.4g} mm/s, spiral turns {ev.spiral_turns:.3g}",
        f"copper              {ev.copper_mass_kg:.4g} kg ("
        + ", ".join(f"{ax} {m:.4g}" for ax, m in zip("xyz", ev.copper_masses_kg))
        + ")",
        "",
        format_table(
            ["check", "key", "value", "allowed", "unit", "ok"],
            [check_row(c) for c in ev.checks],
        ),
        "",
        "feasible: "
        + (
            "yes" if ev.feasible else "NO (" + ", ".join(_failed(c.name) for c in ev.failed()) + ")"
        ),
    ]
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    from optimize import evaluate
    from spiralcap.assemble import build_model
    from spiralcap.serialize import evaluation_to_dict

    design = design_from_args(args)
    ev = evaluate(build_model(design))
    if args.json:
        print_json({"design": design.source, **evaluation_to_dict(ev)})
    else:
        print(format_evaluation(ev))
    return 0
