"""``spiralcap coils [DESIGN]``: per-axis coil sizing at the design's current and frequency."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable, Sequence
from typing import Any

from spiralcap.commands._common import (
    add_design_arguments,
    check_outputs,
    design_from_args,
    design_paths,
    format_table,
    print_json,
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """DESIGN, --set, --json and --plot."""
    add_design_arguments(parser)
    from spiralcap.commands._plot import add_geometry_plot_argument

    add_geometry_plot_argument(parser)
    parser.add_argument(
        "--step",
        metavar="COILS.step",
        help="also write the coil set as a CAD model: six named solid winding packs (mm) "
        'in a STEP file (needs the cad extra: pip install "spiralcap[cad]")',
    )
    parser.add_argument(
        "--stl",
        metavar="COILS.stl",
        help="also write the same solids as an STL mesh (needs the cad extra)",
    )
    parser.add_argument(
        "--field-grid",
        metavar="FILE.csv|FILE.npz",
        help="also write the field per ampere of each pair on a grid over the workspace cube: "
        "columns x_m, y_m, z_m and B{x,y,z}_per_A_{x,y,z}_T_per_A (component, then pair), as "
        "CSV or NumPy .npz arrays of those names",
    )
    parser.add_argument(
        "--grid-step-mm",
        type=float,
        metavar="S",
        help="grid spacing of --field-grid, mm (default: the workspace diameter / 20)",
    )
    from spiralcap.commands._common import allow_negative_numbers

    allow_negative_numbers(parser)  # --grid-box-mm -600,600,...
    parser.add_argument(
        "--grid-box-mm",
        metavar="X0,X1,Y0,Y1,Z0,Z1",
        help="the box --field-grid samples, mm from the coil centre (default: the cube round "
        "the workspace sphere), e.g. -600,600,-600,600,0,0 for the x-y plane out to 600 mm",
    )
    parser.add_argument(
        "--cad-workspace",
        action="store_true",
        help="add the workspace sphere to the CAD model as a seventh body",
    )


def _axes_words(axes: tuple[str, ...]) -> str:
    if len(axes) == 1:
        return f"{axes[0]} axis"
    return ", ".join(axes[:-1]) + f" and {axes[-1]} axes alike"


def sizing_payload(design: Any) -> dict[str, Any]:
    """The dict ``spiralcap coils --json`` prints (spiralcap.analysis.coils)."""
    from spiralcap.analysis.coils import analyse_coils, coils_payload

    return coils_payload(analyse_coils(design))


def _run(v: Any) -> Any:
    """A number, or "runaway" where a pair has no steady temperature (NaN)."""
    return "runaway" if isinstance(v, float) and math.isnan(v) else v


def _watts(v: float) -> str:
    return f"{v:.4g} W" if math.isfinite(v) else "unbounded (a pair runs away thermally)"


def _cooling_words(p: dict[str, Any]) -> str:
    """The surface heat transfer at the operating point (fixed h, or the correlation's h)."""
    h = p.get("heat_transfer_coefficient_W_m2K")
    if h is not None:
        return f"h = {h:g} W/(m²·K)"
    op = p["operating_point"]["axes"]
    hs = ", ".join(
        f"{h:.3g}" if math.isfinite(h) else "undefined"
        for h in (op[ax].get("convection_coefficient_W_m2K", math.nan) for ax in "xyz")
    )
    return (
        f"{p['cooling']} convection h_c = {hs} W/(m²·K) (x, y, z; at the surface temperatures "
        "of the table below)"
    )


def _size_cell(a: dict[str, Any]) -> Any:
    """A pair's size: its radius, a square's side, or a rectangle's sides as ``a x b``, m."""
    if "sides_m" in a:
        return " x ".join(f"{s:.4g}" for s in a["sides_m"])
    return a["side_m"] if "side_m" in a else a["radius_m"]


def _hardware_table(axes: list[dict[str, Any]]) -> str:
    """What does not depend on the current: geometry, copper, field per ampere, inductance."""
    frames = any("side_m" in a or "sides_m" in a for a in axes)  # a size other than a radius
    return format_table(
        [
            "axis",
            "radius_or_side_m" if frames else "radius_m",
            "turns",
            "wire_mm",
            "pack_w_mm",
            "pack_d_mm",
            "wire_m",
            "Cu_kg",
            "loop_mT_per_A",
            "L_mH",
            "F_room",
        ],
        [
            [
                a["axis"] + (f" ({a['shape']})" if "side_m" in a or "sides_m" in a else ""),
                _size_cell(a),
                a["turns"],
                a["wire_diameter_m"] * 1e3,
                a["winding_pack_width_m"] * 1e3,
                a["winding_pack_depth_m"] * 1e3,
                a["wire_length_m"],
                a["copper_mass_kg"],
                a["field_per_amp_T_per_A"] * 1e3,
                a["inductance_H"] * 1e3,
                a["radiation_view_factor"],
            ]
            for a in axes
        ],
    )


def _rating_lines(p: dict[str, Any]) -> list[str]:
    """The three pairs at their amplifier ratings (each pair's channel), in words: a pair that runs
    away thermally is said so with the current to hold it below, never with temperatures."""
    axes = [p["axes"][ax] for ax in "xyz"]
    steady = [a for a in axes if not a.get("thermal_runaway")]
    lines = [_rating_head(p)]
    limit_C = p["operating_point"]["limit_temperature_C"]
    for a in axes:
        rating = a["current_amplitude_A"]
        if not a.get("thermal_runaway") and a["hot_spot_temperature_C"] > limit_C:
            lines.append(
                f"  at {rating:g} A the {a['axis']} pair's hot spot passes its {limit_C:g} °C "
                f"limit: hold it below {a['max_current_A']:.4g} A "
                f"({_limited_words(a['max_current_limited_by'], a['max_current_limit_key'])})"
            )
        if a.get("thermal_runaway"):
            lines.append(
                f"  at {rating:g} A the {a['axis']} pair runs away thermally (it has no steady "
                f"temperature): hold it below {a['max_current_A']:.4g} A "
                f"({_limited_words(a['max_current_limited_by'], a['max_current_limit_key'])})"
            )
    if len(steady) < len(axes):  # radiating to each other: no common steady state, no numbers
        lines.append(
            "  the three pairs have no common steady state at this current (they heat each "
            "other), so no temperature, resistance or loss is given for any of them"
        )
    else:
        lines.append(
            format_table(
                ["axis", "R_ohm", "Z_ohm", "V_amp_V", "P_W", "surf_C", "hot_C", "B_mT"],
                [
                    [
                        a["axis"],
                        a["resistance_ohm"],
                        a["impedance_ohm"],
                        a["voltage_amplitude_V"],
                        a["power_W"],
                        a["surface_temperature_C"],
                        a["hot_spot_temperature_C"],
                        a["field_amplitude_T"] * 1e3,
                    ]
                    for a in axes
                ],
            )
        )
    wh = p["worst_heading"]
    lines.append(
        f"total copper loss at {_ratings(p)}, worst heading "
        f"({', '.join(f'{x:.3g}' for x in wh['heading'])}): {_watts(p['total_power_W'])} "
        f"at {wh['field_amplitude_T'] * 1e3:.4g} mT"
    )
    return lines


def _channel_keys(p: dict[str, Any]) -> list[str]:
    """Each pair's amplifier current key: its own channel's where set, else the global one."""
    return [p["axes"][ax]["current_limit_key"] for ax in "xyz"]


def _ratings(p: dict[str, Any]) -> str:
    """``40 A`` (one rating for every pair) or ``x 12 A, y 13 A, z 40 A``."""
    amps = [p["axes"][ax]["current_amplitude_A"] for ax in "xyz"]
    if len(set(amps)) == 1:
        return f"{amps[0]:g} A"
    return ", ".join(f"{ax} {a:g} A" for ax, a in zip("xyz", amps))


def _rating_head(p: dict[str, Any]) -> str:
    """The rating the pairs are sized at, naming each amplifier channel's design key."""
    amps = [p["axes"][ax]["current_amplitude_A"] for ax in "xyz"]
    keys = _channel_keys(p)
    if len(set(keys)) == 1 and len(set(amps)) == 1:
        return (
            f"at the amplifier rating, {amps[0]:g} A per pair ({keys[0]}), all three pairs "
            "together, steady:"
        )
    each = ", ".join(f"{ax} {a:g} A ({k})" for ax, a, k in zip("xyz", amps, keys))
    return f"at each pair's amplifier rating, {each}, all three pairs together, steady:"


def _limited_words(limited_by: str, key: str = "") -> str:
    words = {
        "hot_spot": "its winding hot-spot limit",
        "voltage": "its drive-voltage limit",
        "current": "its amplifier's current limit",
        "surface": "its surface-temperature limit",
        "surface_temperature": "its surface-temperature limit",
        "power": "its amplifier's power limit",
        "unused": "no heading uses this pair",
    }.get(limited_by, limited_by.replace("_", " ") + " limit")
    return f"{words}, {key}" if key else words


def _clearance_lines(p: dict[str, Any]) -> list[str]:
    need = p["min_clearance_m"]
    cl = p["pack_clearances_m"]

    def mark(v: float) -> str:
        return "ok" if v >= need * (1 - 1e-6) else "TOO CLOSE"

    return [
        f"winding packs as solids (axial width x radial depth), least clearance allowed "
        f"{need * 1e3:.4g} mm (coils.min_clearance_mm):",
        *(f"  {k}: {v * 1e3:.4g} mm  {mark(v)}" for k, v in cl.items()),
        f"  inner faces to the workspace sphere (radius {p['bore_radius_m']:.4g} m): "
        f"{p['bore_clearance_m'] * 1e3:.4g} mm  {mark(p['bore_clearance_m'])}",
        f"copper: {p['copper_mass_kg']:.4g} kg in the three pairs",
    ]


def _operating_table(op: dict[str, Any]) -> str:
    session = op.get("session_s")
    return format_table(
        [
            "axis",
            "I_A",
            "R_ohm",
            "P_W",
            "surface_C",
            "mean_C",
            "hot_spot_C",
            "C_kJ_per_K",
            "tau_min",
        ]
        + (["session_end_hot_C"] if session is not None else []),
        [
            [
                t["axis"],
                t["current_A"],
                t["resistance_ohm"],
                t["power_W"],
                t["surface_temperature_C"],
                t["mean_temperature_C"],
                t["hot_spot_temperature_C"],
                t["heat_capacity_J_per_K"] * 1e-3,
                t["time_constant_s"] / 60.0,
            ]
            + ([t["session_hot_spot_temperature_C"]] if session is not None else [])
            for t in (op["axes"][ax] for ax in "xyz")
        ],
    )


def _calibration_lines(p: dict[str, Any]) -> list[str]:
    """With calibrated coils: each pair's calibrated centre field per ampere, gain and tilt."""
    cal = p.get("calibration")
    if not cal:
        return []
    a = cal["actuation_matrix_T_per_A"]
    lines = ["  calibrated coils (calibration.*: the field per ampere every figure uses):"]
    for k, ax in enumerate("xyz"):
        col = ", ".join(f"{a[c][k] * 1e3:+.5f}" for c in range(3))
        lines.append(
            f"    {ax} pair ({col}) mT/A at the centre: gain {cal['gain_factors'][ax]:.4f}, "
            f"tilt {cal['axis_tilts_deg'][ax]:.3f} deg"
        )
    bg = ", ".join(f"{v * 1e6:+.3g}" for v in cal["background_field_T"])
    lines.append(f"    background field ({bg}) uT, cancelled by the waveforms")
    return lines


def _measured_lines(axes: list[dict[str, Any]]) -> list[str]:
    """Per measured pair: measured beside computed R and L, with the deviation (the measured
    values are the ones every figure uses)."""
    lines = []
    for a in axes:
        m = a.get("measured")
        if not m:
            continue
        parts = []
        if "resistance_ohm" in m:
            parts.append(
                f"R {m['resistance_ohm']:.4g} Ω at {m['temperature_C']:g} °C (computed "
                f"{m['computed_resistance_ohm']:.4g} Ω, {m['resistance_deviation'] * 100:+.3g} %)"
            )
        if "inductance_H" in m:
            parts.append(
                f"L {m['inductance_H'] * 1e3:.4g} mH (computed "
                f"{m['computed_inductance_H'] * 1e3:.4g} mH, {m['inductance_deviation'] * 100:+.3g} %)"
            )
        lines.append(
            f"  {a['axis']} pair as measured (coils.{a['axis']}.measured.*, used): "
            + "; ".join(parts)
        )
    return lines


def _text(p: dict[str, Any], bom: str = "", stray: Sequence[str] = ()) -> str:
    """The operating point first (where the design runs), then what each pair may carry, the
    hardware, the amplifier rating in words, uniformity, clearances and the bill of materials."""
    axes = [p["axes"][ax] for ax in "xyz"]
    uniform = p["uniform_region"]
    limits = format_table(
        ["axis", "I_max_A", "limited_by", "B_rot_max_mT", "uniform_1pct_m", "uniform_5pct_m"],
        [
            [
                a["axis"],
                a["max_current_A"],
                a["max_current_limited_by"].replace("_", " "),
                a["max_rotating_field_T"] * 1e3,
                uniform["per_axis"][a["axis"]]["radius_1pct_m"],
                uniform["per_axis"][a["axis"]]["radius_5pct_m"],
            ]
            for a in axes
        ],
    )
    w = p["rotating_field_within_limits"]
    op = p["operating_point"]
    session = op.get("session_s")
    run_words = (
        "steady state"
        if session is None
        else f"a {session / 60:g} min run from ambient (limit applies at its end)"
    )
    lines = [
        f"design: {p['design']}",
        f"operating point: rotating field {op['field_amplitude_T'] * 1e3:.4g} mT"
        f"{' (fixed)' if op['field_fixed'] else ''} at {p['frequency_hz']:g} Hz, each pair at "
        f"its worst-heading current, {run_words}; hot-spot limit "
        f"{op['limit_temperature_C']:g} °C; ambient {p['ambient_temperature_C']:g} °C, "
        f"{_cooling_words(p)}, emissivity {p['surface_emissivity']:g}, winding k = "
        f"{p['winding_conductivity_W_mK']:g} W/(m·K); R at the self-consistent mean temperature",
        _operating_table(op),
        *p.get("warnings", []),
        "",
        "largest current each pair may carry, worst heading (current, voltage, hot spot):",
        limits,
        "",
        "the pairs (loop_mT_per_A: centre field per ampere with each coil one loop at its mean "
        "radius, the field model):",
        _hardware_table(axes),
        *_measured_lines(axes),
        *_calibration_lines(p),
        "",
        *_rating_lines(p),
        "",
        "uniform region of the three-axis system (worst of 13 static field directions):",
        f"  ±1 %: radius {uniform['radius_1pct_m']:.4g} m;  "
        f"±5 %: radius {uniform['radius_5pct_m']:.4g} m",
        "rotating field, worst heading:",
        f"  at the current limit: {p['current_limited_rotating_field_T'] * 1e3:.4g} mT, set by "
        f"the {_axes_words(tuple(p['current_limiting_axes']))}: the smallest field per amp x "
        "current",
        f"  within all limits: {w['max_rotating_field_T'] * 1e3:.4g} mT, set by "
        f"{w['limited_by_words']}"
        f" ({w['limit_key']}); the power limit alone allows "
        f"{w['per_limit_max_field_T']['power'] * 1e3:.4g} mT",
        "",
        *([*stray, ""] if stray else []),
        *_clearance_lines(p),
    ]
    if bom:
        lines += ["", "bill of materials (per pair, both coils in series):", bom]
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    """Print the sizing table (or JSON); with --plot also draw the geometry view."""
    from spiralcap.commands._plot import check_figure_path

    check_outputs(
        {
            "--plot": args.plot,
            "--step": args.step,
            "--stl": args.stl,
            "--field-grid": args.field_grid,
        },
        design_paths(args),
    )
    if args.plot:
        check_figure_path("--plot", args.plot)
    _check_cad_paths(args)
    _check_grid_arguments(args)
    design = design_from_args(args)
    grid = _field_grid(args, design)  # before any output: a bad step leaves nothing printed
    from spiralcap.analysis.bom import bom_table
    from spiralcap.analysis.coils import analyse_coils, coils_payload

    analysis = analyse_coils(design)
    payload = coils_payload(analysis)
    said = _write_outputs(args, design, grid)  # committed before anything is printed
    if args.json:
        print_json(payload)
    else:
        from spiralcap.analysis.stray import stray_words

        stray = stray_words(analysis.stray) if analysis.stray is not None else []
        print(_text(payload, bom_table(analysis.bill_of_materials), stray))
    said()
    return 0


def _write_outputs(args: argparse.Namespace, design: Any, grid: Any) -> Callable[[], None]:
    """--plot, --step/--stl and --field-grid: each made in memory, then all committed together
    (all or nothing); returns what says so (called after the command's own output)."""
    from spiralcap.commands._plot import geometry_bytes
    from spiralcap.design import write_files_atomic

    outputs: dict[str, bytes] = {}
    if args.plot:
        outputs[args.plot] = geometry_bytes(args.plot, design)[0]
    cad = _cad_files(args, design) if args.step or args.stl else None
    if cad is not None:
        outputs.update(cad[0])
    if grid is not None:
        from spiralcap.export import field_grid_bytes

        outputs[args.field_grid] = field_grid_bytes(args.field_grid, grid)
    if not outputs:
        return lambda: None
    write_files_atomic(outputs)

    def say() -> None:
        if args.plot and not args.json:
            print(f"wrote {args.plot}")
        if cad is not None:
            _say_cad(args, cad[1], list(cad[0]))
        if grid is not None:
            _say_grid(args, grid)

    return say


def _check_grid_arguments(args: argparse.Namespace) -> None:
    """--field-grid: a .csv or .npz name; --grid-step-mm: a spacing > 0, only with it."""
    from spiralcap.core.errors import InputError

    if args.field_grid is not None and not args.field_grid.lower().endswith((".csv", ".npz")):
        raise InputError("--field-grid", args.field_grid, "a file name ending in .csv or .npz")
    if args.grid_step_mm is not None:
        if args.field_grid is None:
            raise InputError("--grid-step-mm", args.grid_step_mm, "used with --field-grid")
        if not (math.isfinite(args.grid_step_mm) and args.grid_step_mm > 0):
            raise InputError("--grid-step-mm", args.grid_step_mm, "a grid spacing > 0 mm")
    if getattr(args, "grid_box_mm", None) is not None:
        if args.field_grid is None:
            raise InputError("--grid-box-mm", args.grid_box_mm, "used with --field-grid")
        parse_grid_box_mm(args.grid_box_mm)


#: Largest distance from the centre a --grid-box-mm edge may have, mm (the model's room: 10 m).
GRID_BOX_LIMIT_MM = 10_000.0


def parse_grid_box_mm(text: str) -> tuple[float, ...]:
    """``--grid-box-mm X0,X1,Y0,Y1,Z0,Z1`` as six numbers in m (lower <= upper on each axis).

    Raises
    ------
    InputError
        Not six finite numbers, a lower end above its upper end, or an edge beyond 10 m.
    """
    allowed = (
        "six numbers X0,X1,Y0,Y1,Z0,Z1 in mm with X0 <= X1, Y0 <= Y1, Z0 <= Z1, each within "
        f"+/-{GRID_BOX_LIMIT_MM:g} mm of the centre"
    )
    from spiralcap.core.errors import InputError

    try:
        values = [float(v) for v in str(text).split(",")]
    except ValueError:
        raise InputError("--grid-box-mm", text, allowed) from None
    if len(values) != 6 or not all(
        math.isfinite(v) and abs(v) <= GRID_BOX_LIMIT_MM for v in values
    ):
        raise InputError("--grid-box-mm", text, allowed)
    if any(values[2 * i] > values[2 * i + 1] for i in range(3)):
        raise InputError("--grid-box-mm", text, allowed)
    return tuple(v * 1e-3 for v in values)


def _field_grid(args: argparse.Namespace, design: Any) -> Any:
    """The --field-grid samples over the workspace cube (None without --field-grid)."""
    if args.field_grid is None:
        return None
    from spiralcap.export import field_grid

    step = None if args.grid_step_mm is None else args.grid_step_mm * 1e-3
    import numpy as np

    from spiralcap.core.errors import InputError

    box = getattr(args, "grid_box_mm", None)
    box_m = None if box is None else parse_grid_box_mm(box)
    with np.errstate(all="ignore"):  # a point on a filament: judged below, not warned
        grid = field_grid(design, float(design["workspace.radius_m"]), step, box_m)
    bad = ~np.isfinite(grid.field_per_A_T_per_A).all(axis=(1, 2))
    if bad.any():  # the field of a filament is singular on its wire
        at = ", ".join(f"{1e3 * v:.4g}" for v in grid.points_m[np.argmax(bad)])
        raise InputError(
            "--grid-box-mm" if box is not None else "--grid-step-mm",
            box if box is not None else args.grid_step_mm,
            f"a grid with no point on a winding (the field there is singular; e.g. ({at}) mm)",
        )
    return grid


def _say_grid(args: argparse.Namespace, grid: Any) -> None:
    import sys

    print(
        f"wrote the field per ampere of each pair at {len(grid.points_m)} points "
        f"(step {grid.step_m * 1e3:.4g} mm) to {args.field_grid}",
        file=sys.stderr if args.json else sys.stdout,
    )


def _check_cad_paths(args: argparse.Namespace) -> None:
    """--step / --stl: the suffix, and the CAD kernel installed (exit 2 before any work)."""
    from spiralcap.cad import require_cad
    from spiralcap.core.errors import InputError

    for flag, path, suffixes in (
        ("--step", args.step, (".step", ".stp")),
        ("--stl", args.stl, (".stl",)),
    ):
        if path is None:
            continue
        if not path.lower().endswith(suffixes):
            raise InputError(flag, path, f"a file name ending in {' or '.join(suffixes)}")
        require_cad(flag, path)
    if args.cad_workspace and not (args.step or args.stl):
        raise InputError("--cad-workspace", True, "used with --step or --stl")


def _cad_files(args: argparse.Namespace, design: Any) -> tuple[dict[str, bytes], int]:
    """The STEP and/or STL files' contents, and how many winding packs they hold."""
    from spiralcap.assemble.coils import build_coils
    from spiralcap.cad import cad_bodies, cad_files

    system = build_coils(design)
    radius = float(design["workspace.radius_m"]) if args.cad_workspace else None
    files = cad_files(cad_bodies(system.pairs, radius), args.step, args.stl)
    return dict(files), len(system.pairs) * 2


def _say_cad(args: argparse.Namespace, packs: int, written: list[str]) -> None:
    import sys

    if not args.json:
        print(
            f"wrote the CAD model ({packs} winding packs"
            f"{' and the workspace' if args.cad_workspace else ''}) to {', '.join(written)}"
        )
    else:
        print(f"wrote {', '.join(written)}", file=sys.stderr)
