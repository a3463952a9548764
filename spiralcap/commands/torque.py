"""``spiralcap torque``: tissue resistive torque against rotation frequency (Zhou 2013 model)."""

from __future__ import annotations

import argparse
import math
from typing import Any

from spiralcap.commands._common import (
    add_design_arguments,
    allow_negative_numbers,
    check_outputs,
    design_from_args,
    design_paths,
    format_table,
    print_json,
)
from spiralcap.core.constants import from_unit
from spiralcap.core.errors import InputError

DEFAULT_FREQUENCIES_HZ = (0.5, 1.0, 1.5, 2.0, 2.5, 3.0)
#: Frequencies --frequency accepts, Hz: the range of operation.frequency_hz.
FREQUENCY_RANGE_HZ = (1e-3, 100.0)
#: Most frequencies of one table.
MAX_FREQUENCIES = 10_000


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_arguments(parser)
    allow_negative_numbers(parser)
    parser.add_argument(
        "--frequency",
        dest="frequencies",
        type=float,
        action="extend",
        nargs="+",
        metavar="F",
        help="rotation frequencies in Hz (several, or repeat the flag; default "
        + ", ".join(f"{f:g}" for f in DEFAULT_FREQUENCIES_HZ)
        + ")",
    )
    parser.add_argument(
        "--plot", metavar="FILE.png", help="also draw torque against frequency (png, pdf or svg)"
    )


def geometry_from_design(design: Any) -> Any:
    """The design's capsule as a ``torque_model.ContactGeometry`` (SI).

    The capsule is assembled first, so the same cross-key checks hold as for ``evaluate`` (a
    helical angle whose turns overlap, a wire too thick for the body, ...).
    """
    import torque_model as tm
    from spiralcap.assemble import build_capsule

    build_capsule(design)
    return tm.ContactGeometry(
        body_diameter_m=design["capsule.diameter_mm"] * 1e-3,
        body_length_m=design["capsule.length_mm"] * 1e-3,
        wire_diameter_m=design["capsule.spiral.wire_diameter_mm"] * 1e-3,
        wound_length_m=design["capsule.spiral.wound_length_mm"] * 1e-3,
        starts=int(design["capsule.spiral.starts"]),
    )


def run(args: argparse.Namespace) -> int:
    import numpy as np

    import torque_model as tm
    from spiralcap.assemble import build_capsule
    from spiralcap.assemble.tissue import build_tissues

    if args.plot:
        check_plot_path(args.plot)
    check_outputs({"--plot": args.plot}, design_paths(args))
    design = design_from_args(args)
    freqs = args.frequencies or list(DEFAULT_FREQUENCIES_HZ)
    if len(freqs) > MAX_FREQUENCIES:
        raise InputError(
            "--frequency", f"{len(freqs)} values", f"at most {MAX_FREQUENCIES} frequencies"
        )
    lo, hi = FREQUENCY_RANGE_HZ
    for f in freqs:
        if not (math.isfinite(f) and lo <= f <= hi):
            raise InputError(
                "--frequency",
                f,
                f"a frequency from {lo:g} to {hi:g} Hz (as operation.frequency_hz)",
            )
    f = np.asarray(freqs, dtype=float)
    angle_deg = float(design["capsule.spiral.helical_angle_deg"])
    geometry = geometry_from_design(design)
    tissues = build_tissues(design)
    d_prime = float(
        tm.equivalent_diameter_m(
            from_unit(angle_deg, "deg"),
            geometry.body_diameter_m,
            geometry.wire_diameter_m,
            geometry.starts,
        )
    )
    capsule = build_capsule(design)
    radius = float(tm.contact_radius_m(geometry.body_diameter_m, geometry.wire_diameter_m))
    rows = [_tissue_row(tissue, from_unit(angle_deg, "deg"), f, geometry) for tissue in tissues]
    for row, tissue in zip(rows, tissues):
        weight = float(
            tm.weight_friction_torque_Nm(capsule.mass_kg, tissue.friction_coefficient, radius)
        )
        row["weight_friction_mNm"] = weight * 1e3
        row["weight_friction_Nm"] = weight  # SI beside the shown unit (README: JSON in SI)
    if args.plot:
        from spiralcap.figures.torque import plot_torque_vs_frequency, save_figure

        save_figure(
            plot_torque_vs_frequency,
            args.plot,
            tissues[0],
            (angle_deg,),
            frequency_hz=np.linspace(min(f.min(), 0.5), max(f.max(), 3.0), 60),
            geometry=geometry,
        )
    if args.json:
        print_json(
            {
                "frequency_hz": f.tolist(),
                **rows[0],
                "helical_angle_deg": angle_deg,
                "equivalent_diameter_mm": d_prime * 1e3,
                "equivalent_diameter_m": d_prime,
                "worst_case": rows[1:],
                "design": design.source,
            }
        )
        return 0
    print(
        f"resistive torque, helical angle {angle_deg:g} deg, D' = {d_prime * 1e3:.4g} mm "
        f"(design: {design.source})"
    )
    headers = ["frequency_hz"] + [f"torque_mNm [{r['tissue']}]" for r in rows]
    table = [[float(fi)] + [r["torque_mNm"][i] for r in rows] for i, fi in enumerate(f)]
    print(format_table(headers, table))
    for r in rows:
        print(_contact_words(r))
    print(
        f"(the table is the paper's tissue model; a capsule of {capsule.mass_kg * 1e3:.3g} g "
        "lying on the wall adds the friction of its weight, "
        + ", ".join(f"{r['weight_friction_mNm']:.3g} mN·m in {r['tissue']}" for r in rows)
        + ", which evaluate and optimize include)"
    )
    if args.plot:
        print(f"wrote {args.plot}")
    return 0


def _tissue_row(tissue: Any, alpha_rad: float, f: Any, geometry: Any) -> dict[str, Any]:
    """One tissue set's torques (N·m and mN·m at each frequency) and its contact."""
    import numpy as np

    import torque_model as tm

    tau = np.asarray(tm.resistive_torque_Nm(alpha_rad, f, tissue, geometry), dtype=float)
    strain = float(tm.wall_strain(alpha_rad, tissue, geometry))
    return {
        "tissue": tissue.name,
        "torque_Nm": tau.tolist(),
        "torque_mNm": (tau * 1e3).tolist(),
        "lumen_diameter_mm": tissue.lumen_diameter_m * 1e3,
        "wall_thickness_mm": tissue.wall_thickness_m * 1e3,
        "lumen_diameter_m": tissue.lumen_diameter_m,
        "wall_thickness_m": tissue.wall_thickness_m,
        "wall_strain": strain,
        "engaged": strain > 0,
    }


def _contact_words(row: dict[str, Any]) -> str:
    """Whether the spiral touches a tissue set's wall, in words."""
    where = f"{row['tissue']} (lumen {row['lumen_diameter_mm']:.4g} mm)"
    if row["engaged"]:
        return f"{where}: the spiral stretches the wall by {100 * row['wall_strain']:.3g} %"
    return (
        f"{where}: NOT TOUCHED: the spiral does not reach the wall (strain "
        f"{100 * row['wall_strain']:.3g} %), so the model gives no tissue torque and the "
        "spiral cannot screw the capsule forward"
    )


def check_plot_path(path: str) -> None:
    """Refuse a figure path matplotlib cannot write (InputError naming --plot)."""
    suffix = path.rsplit(".", 1)[-1].lower() if "." in path else ""
    if suffix not in ("png", "pdf", "svg"):
        raise InputError("--plot", path, "a file name ending in .png, .pdf or .svg")
