"""``spiralcap capsule``: magnet moment, spiral lead, speed and thrust torque of a design."""

from __future__ import annotations

import argparse

from spiralcap.commands._common import (
    add_design_arguments,
    design_from_args,
    format_table,
    print_json,
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """DESIGN, --set and --json (see :func:`spiralcap.commands._common.add_design_arguments`)."""
    add_design_arguments(parser)


def run(args: argparse.Namespace) -> int:
    """Print the capsule's figures at ``operation.frequency_hz``; 0 on success.

    The thrust torque pushes ``requirements.axial_load_mN`` with the friction coefficient of the
    design's (first) tissue set; speed uses ``requirements.slip_efficiency``. A spiral with fewer
    than ``requirements.min_spiral_turns`` turns is legal but flagged (``full_turn_ok: false``).
    """
    from spiralcap.assemble import build_capsule, build_tissues

    design = design_from_args(args)
    cap = build_capsule(design)
    tissue = build_tissues(design)[0]
    fig = cap.figures(
        frequency_hz=design["operation.frequency_hz"],
        axial_load_N=design["requirements.axial_load_mN"] * 1e-3,
        friction_coefficient=tissue.friction_coefficient,
        slip_efficiency=design["requirements.slip_efficiency"],
        min_turns=design["requirements.min_spiral_turns"],
    )
    if args.json:
        payload = {
            "design_source": design.source,
            "tissue": getattr(tissue, "name", None),
            "magnet_shape": cap.magnet.shape,
            "spiral_starts": cap.spiral.starts,
            "wound_length_m": cap.spiral.wound_length_m,
            "wire_diameter_m": cap.spiral.wire_diameter_m,
            **fig.to_dict(),
        }
        print_json(payload)
        return 0

    b, s, m = cap.body, cap.spiral, cap.magnet
    print(f"design: {design.source}")
    print(
        f"body {b.diameter_m * 1e3:g} x {b.length_m * 1e3:g} mm (shell "
        f"{b.shell_thickness_m * 1e3:g} mm); spiral {s.helical_angle_deg:g} deg, "
        f"{s.wire_diameter_m * 1e3:g} mm wire over {s.wound_length_m * 1e3:g} mm, "
        f"{s.starts} start{'' if s.starts == 1 else 's'}; {m.shape} magnet {m.diameter_m * 1e3:g}"
        + (f"/{m.inner_diameter_m * 1e3:g}" if m.inner_diameter_m else "")
        + f" x {m.length_m * 1e3:g} mm, B_r {m.remanence_T:g} T"
    )
    print(
        f"at {fig.frequency_hz:g} Hz, axial load {fig.axial_load_N * 1e3:g} mN, slip "
        f"efficiency {fig.slip_efficiency:g}, friction coefficient "
        f"{fig.friction_coefficient:g} (tissue {getattr(tissue, 'name', '?')})"
    )
    print()
    rows = [
        ("magnet moment", fig.magnet_moment_Am2, "A·m²"),
        ("synchronous torque per mT", fig.synchronous_torque_per_mT_Nm * 1e3, "mN·m/mT"),
        ("helix diameter", fig.helix_diameter_m * 1e3, "mm"),
        ("lead (pitch) per revolution", fig.lead_m * 1e3, "mm"),
        ("wire spacing (lead / starts)", fig.wire_spacing_m * 1e3, "mm"),
        ("turns over wound length", fig.turns, "-"),
        ("bump width in cross-section", fig.footprint_width_m * 1e3, "mm"),
        ("forward speed", fig.speed_m_s * 1e3, "mm/s"),
        ("thrust torque", fig.thrust_torque_Nm * 1e3, "mN·m"),
    ]
    print(format_table(("quantity", "value", "unit"), rows))
    if not fig.full_turn_ok:
        angle = fig.max_helical_angle_for_min_turns_deg
        print(
            f"warning: the spiral makes {fig.turns:.3g} turns over the "
            f"{s.wound_length_m * 1e3:g} mm wound length, fewer than "
            f"requirements.min_spiral_turns = {fig.min_turns:g} (needs a helical angle <= "
            f"{angle:.3g} deg); allowed, but flagged as hard to manufacture"
        )
    else:
        print(f"spiral turns >= requirements.min_spiral_turns = {fig.min_turns:g}: ok")
    return 0
