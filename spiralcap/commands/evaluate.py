"""``spiralcap evaluate``: the design at its operating point."""

from __future__ import annotations

import argparse

from spiralcap.commands._common import add_design_arguments, design_from_args, print_json


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_arguments(parser)


def format_evaluation(ev) -> str:
    """Readable summary of an :class:`optimize.Evaluation`."""
    from spiralcap.commands._common import format_table

    mnm = 1e3
    lines = [
        f"operating point     helical angle {ev.helical_angle_deg:.3g} deg, "
        f"{ev.frequency_hz:.4g} Hz",
        f"rotating field      {ev.field_amplitude_T * 1e3:.4g} mT at the centre "
        f"(limited by {ev.field_limited_by}); weakest over workspace x{ev.workspace_factor:.4f}",
        "currents            "
        + ", ".join(f"{ax} {i:.4g} A" for ax, i in zip("xyz", ev.current_amplitudes_A)),
        f"magnetic torque     {ev.magnetic_torque_Nm * mnm:.4g} mN·m (synchronous, worst point)",
        f"resistive torque    {ev.resistive_torque_Nm * mnm:.4g} mN·m ({ev.worst_tissue})",
        f"thrust torque       {ev.thrust_torque_Nm * mnm:.4g} mN·m",
        f"margin              {ev.margin_Nm * mnm:.4g} mN·m (safety factor {ev.safety_factor:.3g})",
        f"step-out frequency  {ev.step_out_frequency_hz:.4g} Hz"
        f"{' or more (search bound)' if ev.step_out_beyond_search else ''} at this field; the "
        f"drive holds a margin up to {ev.max_frequency_hz:.4g} Hz"
        f"{' or more' if ev.max_frequency_beyond_search else ''} "
        f"(limited by {ev.max_frequency_limited_by})",
        f"forward speed       {ev.speed_m_s * 1e3:.4g} mm/s, spiral turns {ev.spiral_turns:.3g}",
        "",
        format_table(
            ["check", "key", "value", "allowed", "unit", "ok"],
            [
                [
                    c.name,
                    c.key,
                    c.value,
                    f"{c.sense} {c.allowed:.4g}",
                    c.unit,
                    "yes" if c.ok else "NO",
                ]
                for c in ev.checks
            ],
        ),
        "",
        "feasible: "
        + ("yes" if ev.feasible else "NO (" + ", ".join(c.name for c in ev.failed()) + ")"),
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
