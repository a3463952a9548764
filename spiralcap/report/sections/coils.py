"""Section 3: coil sizing per axis (the ``spiralcap coils --json`` dict) and field uniformity."""

from __future__ import annotations

from typing import Any

from spiralcap.report.document import Cell, FigureBlock, Paragraph, Section, Strong, Table
from spiralcap.report.sections._util import Context

#: Rows of the sizing table: (JSON field of each axis, quantity, shown unit, factor).
SIZING_ROWS: tuple[tuple[str, str, str, float], ...] = (
    ("radius_m", "mean coil radius R", "m", 1.0),
    ("separation_m", "coil separation", "m", 1.0),
    ("turns", "turns per coil N", "–", 1.0),
    ("wire_diameter_m", "bare wire diameter", "mm", 1e3),
    ("winding_pack_side_m", "winding-pack side", "mm", 1e3),
    ("wire_length_m", "wire length per pair", "m", 1.0),
    ("field_per_amp_T_per_A", "centre field per ampere", "mT/A", 1e3),
    ("resistance_ohm", "resistance of the pair (winding temperature)", "Ω", 1.0),
    ("self_inductance_H", "self inductance of one coil", "mH", 1e3),
    ("mutual_inductance_H", "mutual inductance of the two coils", "mH", 1e3),
    ("inductance_H", "series inductance of the pair (2L + 2M)", "mH", 1e3),
    ("impedance_ohm", "impedance |R + jωL| at the operating frequency", "Ω", 1.0),
    ("voltage_amplitude_V", "drive-voltage amplitude at the current limit", "V", 1.0),
    ("power_W", "copper loss at the current limit", "W", 1.0),
    ("thermal_conductance_W_per_K", "convective thermal conductance", "W/K", 1.0),
    ("temperature_rise_K", "steady temperature rise at the current limit", "K", 1.0),
    ("coil_temperature_C", "coil temperature at the current limit", "°C", 1.0),
    ("field_amplitude_T", "centre field at the current limit", "mT", 1e3),
    ("max_current_A", "largest current inside all limits", "A", 1.0),
    ("max_current_limited_by", "which limit sets it", "", 1.0),
    ("max_rotating_field_T", "largest rotating field this pair allows", "mT", 1e3),
)


def _sizing_table(ctx: Context) -> Table:
    axes = list(ctx.value("coils.axes"))
    rows: list[list[Cell]] = []
    for field, label, unit, factor in SIZING_ROWS:
        row: list[Cell] = [label, unit]
        for ax in axes:
            value = ctx.value(f"coils.axes.{ax}.{field}")
            if isinstance(value, str):
                row.append(value.replace("_", " "))
            else:
                row.append(ctx.num(f"coils.axes.{ax}.{field}", factor))
        rows.append(row)
    for tol in ("1pct", "5pct"):
        row = [f"radius of the ±{tol[0]} % sphere, this pair alone", "m"]
        row += [ctx.num(f"coils.uniform_region.per_axis.{ax}.radius_{tol}_m") for ax in axes]
        rows.append(row)
    return Table(
        ["quantity", "unit", *[f"{a} pair" for a in axes]],
        rows,
        caption="Coil sizing per axis (same numbers as `spiralcap coils --json`)",
        wrap=0,
        id="coil-table",
    )


def _draw_maps(maps: Any, workspace_radius_m: float) -> Any:
    def draw(fig: Any) -> None:
        from matplotlib.lines import Line2D

        from spiralcap.figures.coils import plot_field_deviation_map

        axs = fig.subplots(1, 3)
        drawn = None
        for ax, m in zip(axs, maps, strict=True):
            drawn = plot_field_deviation_map(
                ax,
                m.u_m,
                m.v_m,
                m.deviation,
                axis_labels=m.plane,
                uniform_radii_m=m.uniform_radii_m,
                workspace_radius_m=workspace_radius_m,
                title=f"{m.axis} pair driven",
                colorbar=False,
                legend=False,
                label_contours=False,
            )
        assert drawn is not None  # three maps drawn above
        fig.colorbar(
            drawn["filled"],
            ax=list(axs),
            label="|B| deviation (%)",
            shrink=0.8,
            location="right",
            format="%g",
        )
        proxies = [
            Line2D([], [], color="black", linestyle="-", linewidth=2.0),
            Line2D([], [], color="black", linestyle="--", linewidth=2.0),
            Line2D([], [], color="#D55E00", linestyle=":", linewidth=1.8),
            Line2D([], [], color="black", linestyle="-.", linewidth=1.6),
        ]
        fig.legend(
            proxies,
            [
                "±1 % contour",
                "±5 % contour",
                "±1 % and ±5 % spheres (radii in the table)",
                "workspace",
            ],
            loc="outside lower center",
            ncols=2,
            fontsize=8,
        )

    return draw


def _draw_profiles(profile: Any) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.coils import plot_uniformity_profile

        ax = fig.subplots()
        d, devs = profile
        plot_uniformity_profile(ax, d, devs)
        ax.set_ylim(-12, 6)

    return draw


def build(ctx: Context) -> Section:
    """The coil-sizing section."""
    c = "coils"
    axes = list(ctx.value("coils.axes"))
    design = ctx.data.design
    intro = Paragraph(
        [
            "Each pair is sized at the current-amplitude limit ",
            ctx.num(f"{c}.current_amplitude_A", unit="A"),
            " and the operating frequency ",
            ctx.num(f"{c}.frequency_hz", unit="Hz"),
            ", copper resistance at ",
            ctx.num(f"{c}.winding_temperature_C", unit="°C"),
            ", ambient ",
            ctx.num(f"{c}.ambient_temperature_C", unit="°C"),
            ". All three pairs at that current dissipate ",
            ctx.num(f"{c}.total_power_W", unit="W"),
            ". Inside every limit the largest rotating field (worst heading) is ",
            ctx.num(f"{c}.rotating_field_within_limits.max_rotating_field_T", 1e3, "mT"),
            ", set by ",
            str(ctx.value(f"{c}.rotating_field_within_limits.limited_by")).replace("_", " "),
            f" ({ctx.value(f'{c}.rotating_field_within_limits.limit_key')}; the current limit alone "
            "would allow ",
            ctx.num(f"{c}.current_limited_rotating_field_T", 1e3, "mT"),
            ", the power limit alone ",
            ctx.num(f"{c}.rotating_field_within_limits.per_limit_max_field_T.power", 1e3, "mT"),
            "). These limits are the ones the evaluation and the optimiser apply.",
        ]
    )
    blocks: list[Any] = [intro]
    limit_C = design["limits.coil_temperature_C"]
    hot = [a for a in axes if ctx.value(f"{c}.axes.{a}.coil_temperature_C") > limit_C]
    if hot:
        blocks.append(
            Paragraph(
                [
                    "At the full current limit the ",
                    ", ".join(hot),
                    f" coils would exceed limits.coil_temperature_C = {limit_C:g} °C (e.g. ",
                    ctx.num(f"{c}.axes.{hot[0]}.coil_temperature_C", unit="°C"),
                    "), so the evaluation and the optimiser drive them below that current.",
                ],
                kind="note",
            )
        )
    blocks.append(_sizing_table(ctx))
    ws = float(design["workspace.radius_m"])
    blocks.append(
        Paragraph(
            [
                Strong("Uniformity. "),
                "Over all 13 static field directions (axes, face and body "
                "diagonals) |B| stays within ±1 % of its centre value inside a sphere of radius ",
                ctx.num(f"{c}.uniform_region.radius_1pct_m", 1e3, "mm"),
                " and within ±5 % inside ",
                ctx.num(f"{c}.uniform_region.radius_5pct_m", 1e3, "mm"),
                f"; the design's workspace radius is {ws * 1e3:g} mm. The evaluation does not assume "
                "uniformity: it takes the weakest rotating field over the workspace points and "
                "headings (the workspace field factor, ",
                ctx.num("evaluate.workspace_field_factor"),
                ").",
            ]
        )
    )
    blocks.append(
        FigureBlock(
            "fig-field-maps",
            "|B| deviation from its centre value on planes through the coil centre (x–z plane for "
            "the x and z pairs, y–z plane for the y pair), each pair driven alone (a static field "
            "along its axis), from coils.uniformity. Solid contour: ±1 %; dashed: ±5 %; dotted "
            "circles: the ±1 % and ±5 % spheres of that field direction (coils.uniform_region, "
            "radii in the sizing table); dash-dot circle: the design's workspace.",
            _draw_maps(ctx.data.field_maps, ws),
            size_in=(7.5, 3.5),
        )
    )
    blocks.append(
        FigureBlock(
            "fig-field-profiles",
            "|B| deviation along each pair's axis and across it, that pair driven alone. Dashed "
            "lines: ±1 %; dotted: ±5 %. An ideal Helmholtz pair is flat to fourth order at the "
            "centre; the nested pairs' finite winding packs and spacing set the curvature.",
            _draw_profiles(ctx.data.profile),
            size_in=(7.0, 4.0),
        )
    )
    return Section("coils", "Coil sizing and field uniformity", blocks)
