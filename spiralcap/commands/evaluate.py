"""``spiralcap evaluate``: the design at its operating point."""

from __future__ import annotations

import argparse

from spiralcap.commands._common import add_design_arguments, design_from_args, print_json


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_arguments(parser)


def safety_factor_text(value: float) -> str:
    """A safety factor, or "unbounded (no torque required)" where nothing resists the capsule."""
    return f"{value:.3g}" if value < float("inf") else "unbounded (no torque is required)"


def _failed(name: str) -> str:
    return "self-locking: α + atan μ reaches 90°" if name == "self_lock" else name


def check_words(c, key: str) -> str:
    """A check in the form and unit of its key: ``hot spot 90.0 °C <= 90 °C``;
    ``self-locking: α + atan μ = 48.7°, must stay below 90°``."""
    from spiralcap.presentation import in_key_units, with_unit

    unit, factor = in_key_units(c.unit, key)
    if c.value != c.value:  # NaN: the margin where the spiral does not touch some wall
        return f"none (no contact) {c.sense} {with_unit(f'{c.allowed * factor:.4g}', unit)}"
    if c.name == "self_lock":
        return f"α + atan μ = {c.value * factor:.3g}°, must stay below {c.allowed * factor:g}°"
    value = with_unit(f"{c.value * factor:.4g}", unit)
    return f"{value} {c.sense} {with_unit(f'{c.allowed * factor:.4g}', unit)}"


def tissue_line(ev) -> str:
    """Each tissue set with the strain the spiral stretches its wall by, or that it does not."""
    parts = [
        f"{name} {100 * s:.3g} %" if s > 0 else f"{name}: NOT TOUCHED (strain {100 * s:.3g} %)"
        for name, s in zip(ev.tissue_names, ev.wall_strains)
    ]
    note = (
        " (material overrides reach the first set only)"
        if any("+ tissue.{" in name for name in ev.tissue_names)
        else ""
    )
    return "wall strain         " + ", ".join(parts) + note


#: What stands for a margin where the spiral does not touch some wall.
NO_MARGIN = "none: the spiral does not touch every wall (no contact: the model has no physics)"


def margin_text(ev) -> str:
    """``2.32 mN·m (safety factor 3.61)``; :data:`NO_MARGIN` where there is no contact; a
    strain below the minimum said after the number (the model extrapolates there)."""
    import math

    if not math.isfinite(ev.margin_Nm):
        return NO_MARGIN
    text = f"{ev.margin_Nm * 1e3:.4g} mN·m (safety factor {safety_factor_text(ev.safety_factor)})"
    if getattr(ev, "grip", "ok") == "below minimum":
        text += "; the wall strain is below requirements.min_wall_strain: extrapolated"
    return text


def format_evaluation(ev) -> str:
    """Readable summary of an :class:`optimize.Evaluation`."""
    from spiralcap.assemble.system import check_key
    from spiralcap.commands._common import format_table
    from spiralcap.presentation import model_domain_text, readable, step_out_words
    from spiralcap.serialize import _step_out

    mnm = 1e3

    def check_row(c) -> list:
        return [
            readable(c.name),
            check_key(c.name),
            check_words(c, check_key(c.name)),
            "yes" if c.ok else "NO",
        ]

    lines = [
        f"operating point     helical angle {ev.helical_angle_deg:.3g} deg, "
        f"{ev.frequency_hz:.4g} Hz",
        f"rotating field      {ev.field_amplitude_T * 1e3:.4g} mT at the centre "
        + (
            "(fixed: operation.field_amplitude_mT)"
            if ev.field_limited_by == "fixed"
            else f"(limited by {readable(ev.field_limited_by)}, {check_key(ev.field_limited_by)})"
        )
        + f"; weakest over workspace x{ev.workspace_factor:.4f}",
        "currents            "
        + ", ".join(f"{ax} {i:.4g} A" for ax, i in zip("xyz", ev.current_amplitudes_A)),
        f"magnetic torque     {ev.magnetic_torque_Nm * mnm:.4g} mN·m (synchronous, worst point)",
        f"resistive torque    {ev.resistive_torque_Nm * mnm:.4g} mN·m ({ev.worst_tissue}; "
        f"{ev.weight_friction_Nm * mnm:.3g} mN·m of it the friction of the capsule's weight)",
        tissue_line(ev),
        f"thrust torque       {ev.thrust_torque_Nm * mnm:.4g} mN·m"
        + (
            " (the spiral self-locks: no finite torque pushes the load)"
            if any(c.name == "self_lock" and not c.ok for c in ev.checks)
            else ""
        ),
        f"margin              {margin_text(ev)}",
        "step-out frequency  "
        + (
            step_out_words(
                *_step_out(ev.step_out_frequency_hz),
                ev.max_frequency_hz,
                ev.max_frequency_beyond_search,
                ev.max_frequency_limited_by,
                ev.field_limited_by == "fixed",
            )
            if ev.grip != "none"
            else "none (no contact: nothing for the magnet to step out against)"
        ),
        f"forward speed       {ev.speed_m_s * 1e3:.4g} mm/s, spiral turns {ev.spiral_turns:.3g}"
        + ("" if ev.engaged else " (the spiral does not stretch every wall: no grip, no screw)"),
        f"copper              {ev.copper_mass_kg:.4g} kg ("
        + ", ".join(f"{ax} {m:.4g}" for ax, m in zip("xyz", ev.copper_masses_kg))
        + ")",
        "",
        format_table(
            ["check", "key", "value against allowed", "ok"],
            [check_row(c) for c in ev.checks],
        ),
        model_domain_text(ev.extrapolations),
        "",
        "feasible: "
        + (
            "yes" if ev.feasible else "NO (" + ", ".join(_failed(c.name) for c in ev.failed()) + ")"
        ),
    ]
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    from optimize import evaluate
    from spiralcap import tolerances
    from spiralcap.analysis.touch import evaluation_warnings
    from spiralcap.assemble import build_model
    from spiralcap.serialize import evaluation_to_dict

    design = design_from_args(args)
    model = build_model(design, optimiser=False)
    ev = evaluate(model)
    warnings = evaluation_warnings(model, ev)
    intervals = tolerances.evaluation_rows(model, ev)
    if args.json:
        print_json(
            {
                "design": design.source,
                **evaluation_to_dict(ev),
                "warnings": warnings,
                "tolerance_intervals": tolerances.to_dict(intervals),
            }
        )
    else:
        print("\n".join([format_evaluation(ev), *tolerances.text_lines(intervals), *warnings]))
    return 0
