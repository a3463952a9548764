"""Section 3: coil sizing per axis (the ``spiralcap coils --json`` dict) and field uniformity."""

from __future__ import annotations

import math
from typing import Any

from spiralcap.report.document import Cell, FigureBlock, Paragraph, Ref, Section, Strong, Table
from spiralcap.report.numbers import Num
from spiralcap.report.sections._util import Context

#: Rows of the sizing table: (JSON field of each axis, quantity, shown unit, factor).
SIZING_ROWS: tuple[tuple[str, str, str, float], ...] = (
    ("radius_m", "mean coil radius R", "m", 1.0),
    ("separation_m", "coil separation", "m", 1.0),
    ("turns", "turns per coil N", "–", 1.0),
    ("wire_diameter_m", "bare wire diameter", "mm", 1e3),
    ("winding_pack_width_m", "winding-pack width (axial)", "mm", 1e3),
    ("winding_pack_depth_m", "winding-pack depth (radial)", "mm", 1e3),
    ("wire_length_m", "wire length per pair", "m", 1.0),
    ("copper_mass_kg", "copper mass per pair", "kg", 1.0),
    (
        "field_per_amp_T_per_A",
        "centre field per ampere (each coil one loop at its mean radius: the field model)",
        "mT/A",
        1e3,
    ),
    ("resistance_ohm", "resistance of the pair (mean winding temperature)", "Ω", 1.0),
    ("self_inductance_H", "self inductance of one coil", "mH", 1e3),
    ("mutual_inductance_H", "mutual inductance of the two coils", "mH", 1e3),
    ("inductance_H", "series inductance of the pair (2L + 2M)", "mH", 1e3),
    ("impedance_ohm", "impedance |R + jωL| at the operating frequency", "Ω", 1.0),
    ("voltage_amplitude_V", "drive-voltage amplitude at the current limit", "V", 1.0),
    ("power_W", "copper loss at the current limit", "W", 1.0),
    ("surface_conductance_W_per_K", "surface conductance (convection + radiation)", "W/K", 1.0),
    ("surface_temperature_C", "steady mean surface temperature at the current limit", "°C", 1.0),
    ("hot_spot_temperature_C", "steady hot-spot temperature at the current limit", "°C", 1.0),
    ("surface_max_temperature_C", "steady hottest surface at the current limit", "°C", 1.0),
    (
        "convection_coefficient_W_m2K",
        "convection coefficient h_c (area-weighted, at the steady mean surface temperature)",
        "W/(m²·K)",
        1.0,
    ),
    ("radiation_view_factor", "view factor to the room (radiation leaving the coil set)", "–", 1.0),
    ("field_amplitude_T", "centre field at the current limit", "mT", 1e3),
    ("max_current_A", "largest current inside all limits", "A", 1.0),
    ("max_current_limited_by", "which limit sets it", "", 1.0),
    ("max_rotating_field_T", "largest rotating field this pair allows", "mT", 1e3),
)


def _shape_rows(ctx: Context, axes: list[str]) -> list[list[Cell]]:
    """With a square or rectangular pair in the set: each pair's shape and its sides (issue 30,
    38)."""
    rows = [ctx.value(f"coils.axes.{ax}") for ax in axes]
    shapes = [r["shape"] for r in rows]
    if not any("side_m" in r or "sides_m" in r for r in rows):
        return []
    sides: list[Cell] = [
        ctx.num(f"coils.axes.{ax}.side_m")
        if "side_m" in r
        else " x ".join(f"{s:.4g}" for s in r["sides_m"])
        if "sides_m" in r
        else "–"
        for ax, r in zip(axes, rows, strict=True)
    ]
    return [
        ["coil shape (a frame's radius row: half its shorter side)", "", *shapes],
        ["sides of a frame's mean turn", "m", *sides],
    ]


def _sizing_table(ctx: Context) -> Table:
    axes = list(ctx.value("coils.axes"))
    rows: list[list[Cell]] = _shape_rows(ctx, axes)
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
        compact=True,  # ~35 rows of reference numbers: small type in the PDF
    )


def _bom_table(ctx: Context) -> Table:
    """The bill of materials (``bill_of_materials`` of ``spiralcap coils --json``)."""
    b = "coils.bill_of_materials"
    rows: list[list[Cell]] = []
    for i, row in enumerate(ctx.value(b)):
        p = f"{b}.{i}"
        rows.append(
            [
                row["axis"],
                ctx.num(f"{p}.turns"),
                ctx.num(f"{p}.wire_diameter_mm"),
                ctx.num(f"{p}.wire_length_m"),
                ctx.num(f"{p}.copper_mass_kg"),
                ctx.num(f"{p}.resistance_20C_ohm"),
                ctx.num(f"{p}.inductance_H", 1e3),
                ctx.num(f"{p}.operating.current_amplitude_A"),
                ctx.num(f"{p}.operating.voltage_amplitude_V"),
                ctx.num(f"{p}.operating.apparent_power_VA"),
                ctx.num(f"{p}.at_limits.current_amplitude_A"),
                ctx.num(f"{p}.at_limits.voltage_amplitude_V"),
                ctx.num(f"{p}.at_limits.apparent_power_VA"),
            ]
        )
    lead = ctx.value(f"{b}.0.lead_allowance_m") / ctx.value(f"{b}.0.coils")
    return Table(
        [
            "pair",
            "turns/coil",
            "wire (mm)",
            "wire (m)",
            "copper (kg)",
            "R20 (Ω)",
            "L (mH)",
            "I op (A)",
            "V op (V)",
            "S op (VA)",
            "I lim (A)",
            "V lim (V)",
            "S lim (VA)",
        ],
        rows,
        caption=(
            "Bill of materials per pair (two coils in series; same function as `spiralcap "
            f"coils`): wire length of both coils plus {lead:g} m of leads per coil, copper of that "
            "length, resistance at 20 °C and series inductance of the winding; current and "
            "voltage amplitudes and apparent power S = V I / 2 the amplifier must deliver at the "
            "operating point (op) and at the largest field every limit allows that pair (lim)"
        ),
        id="bom-table",
    )


def _build_paragraph(ctx: Context) -> Paragraph:
    c = "coils"
    cl = ctx.value(f"{c}.pack_clearances_m")
    rows = [ctx.value(f"{c}.axes.{ax}") for ax in ctx.value(f"{c}.axes")]
    framed = ["side_m" in r or "sides_m" in r for r in rows]  # a size other than a radius
    kinds = sorted({r["shape"] for r, f in zip(rows, framed, strict=True) if f})
    words = (["rings"] if not all(framed) else []) + (
        [" and ".join(kinds) + " frames"] if kinds else []
    )
    solids = "solid " + " and ".join(words)
    parts: list[Any] = [
        Strong("Can it be built. "),
        f"The winding packs are {solids} of rectangular section; as solids the packs of two "
        "pairs come no closer than ",
    ]
    for i, key in enumerate(cl):
        parts += [
            f"{key} " if i == 0 else f", {key} ",
            ctx.num(f"{c}.pack_clearances_m.{key}", 1e3, "mm"),
        ]
    parts += [
        ", and their inner faces keep ",
        ctx.num(f"{c}.bore_clearance_m", 1e3, "mm"),
        " from the workspace sphere (radius ",
        ctx.num(f"{c}.bore_radius_m", 1e3, "mm"),
        "); coils.min_clearance_mm asks for ",
        ctx.num(f"{c}.min_clearance_m", 1e3, "mm"),
        " (a former's wall and an air gap; ",
        Ref("fig-geometry"),
        " marks where the packs come closest). The three pairs hold ",
        ctx.num(f"{c}.copper_mass_kg", unit="kg"),
        " of copper; ",
        Ref("bom-table"),
        " lists what a workshop and an amplifier vendor need. Wire: ",
        "; ".join(
            f"{r['axis']} pair {r['wire_standard']}, enamel {r['enamel']}"
            for r in ctx.value(f"{c}.bill_of_materials")
        ),
        ".",
    ]
    return Paragraph(parts)


def _draw_maps(data: Any, workspace_radius_m: float) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.api import field_maps

        field_maps(data.model, fig=fig, workspace_radius_m=workspace_radius_m, maps=data.field_maps)

    return draw


def _draw_geometry(model: Any, workspace_radius_m: float) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.api import geometry

        geometry(model, fig=fig, workspace_radius_m=workspace_radius_m)

    return draw


def _draw_profiles(data: Any) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.api import uniformity_profile

        uniformity_profile(data.model, ax=fig.subplots(), profile=data.profile)

    return draw


def _draw_heating(data: Any, session_s: float | None) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.thermal import plot_heating_curves

        ax = fig.subplots()
        plot_heating_curves(
            ax,
            data.heating,
            limit_C=float(data.design["limits.coil_temperature_C"]),
            session_s=session_s,
            surface_limit_C=_surface_limit_C(data.design),
        )
        # beside the axes: above the limit (a short session) the curves fill the lower right
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7.5)

    return draw


def _draw_stray(data: Any) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.api import stray_field_map

        block = data.coils_json["stray_field"]
        stray_field_map(
            data.model,
            float(block["field_amplitude_T"]),
            _stray_half_width_m(block),
            level_T=float(block["level_T"]),
            fig=fig,
        )

    return draw


def _stray_half_width_m(block: dict[str, Any]) -> float:
    """Half the side the stray-field map covers: 1.25 x the farthest fade distance, m."""
    finite = [v for k, v in block["fade_distance_m"].items() if k in ("x", "y", "z")]
    return 1.25 * max(finite) if finite else float(block["search_reach_m"])


#: Size (in) of each figure :func:`coil_figures` draws.
_SIZES_IN = {
    "fig-stray-field": (7.5, 3.6),
    "fig-geometry": (7.0, 3.5),
    "fig-field-maps": (7.5, 3.5),
    "fig-field-profiles": (7.0, 4.0),
    "fig-heating": (7.5, 2.8),
}


def _surface_limit_C(design: Any) -> float | None:
    """``limits.surface_temperature_C`` (°C), None when the design sets no touch limit."""
    value = design.get("limits.surface_temperature_C")
    return None if value is None else float(value)


def _session_s(design: Any, coils_json: Any) -> float | None:
    """The session length (s) of the coils JSON; None without ``operation.session_min``."""
    if design.get("operation.session_min") is None:
        return None
    return float(coils_json["operating_point"]["session_s"])


def _workspace_m(data: Any) -> float:
    return float(data.design["workspace.radius_m"])


#: How each coil figure's draw(fig) is made from the report data.
_FACTORIES: dict[str, Any] = {
    "fig-geometry": lambda d: _draw_geometry(d.model, _workspace_m(d)),
    "fig-field-maps": lambda d: _draw_maps(d, _workspace_m(d)),
    "fig-field-profiles": _draw_profiles,
    "fig-heating": lambda d: _draw_heating(d, _session_s(d.design, d.coils_json)),
    "fig-stray-field": _draw_stray,
}


def coil_figures(data: Any) -> dict[str, tuple[Any, tuple[float, float]]]:
    """The coil section's figures, id -> (draw(fig), size in inches), in reading order.

    They read only the design, the model and the coil analysis (``coils_json``, ``heating``,
    ``field_maps``, ``profile`` of :class:`spiralcap.report.data.ReportData`), so a report on
    several processes draws them while the optimisation is still running; :func:`build` makes
    its figure blocks from the same functions.
    """
    ids = [k for k in _FACTORIES if k != "fig-heating" or data.heating]
    ids = [k for k in ids if k != "fig-stray-field" or "stray_field" in data.coils_json]
    return {k: (_FACTORIES[k](data), _SIZES_IN[k]) for k in ids}


def _figure(data: Any, fig_id: str, caption: str) -> FigureBlock:
    return FigureBlock(fig_id, caption, _FACTORIES[fig_id](data), size_in=_SIZES_IN[fig_id])


def heating_blocks(ctx: Context) -> list[Any]:
    """The heating of the windings at the operating field: a sentence and the heating curves.

    The curves are :attr:`spiralcap.analysis.coils.CoilAnalysis.heating` (lumped heating from
    ambient at each pair's worst-heading current, the hot spot above the mean by the steady
    gradient's ratio); the numbers are those of ``spiralcap coils --json``.
    """
    if not ctx.data.heating:
        return []
    op = "coils.operating_point"
    axes = list(ctx.value(f"{op}.axes"))
    hot = max(axes, key=lambda a: ctx.value(f"{op}.axes.{a}.hot_spot_temperature_C"))
    # the session keys appear in the coils JSON only with operation.session_min
    session_s = _session_s(ctx.data.design, ctx.value("coils"))
    a = f"{op}.axes.{hot}"
    parts: list[Any] = [
        Strong("Heating. "),
        "At the operating field ",
        ctx.num(f"{op}.field_amplitude_T", 1e3, "mT"),
        f" the {hot} pair runs hottest: its hot spot settles at ",
        ctx.num(f"{a}.hot_spot_temperature_C", unit="°C"),
        " (time constant ",
        ctx.num(f"{a}.time_constant_s", 1 / 60, "min"),
        ")",
    ]
    if session_s is not None:
        parts += [
            " and reaches ",
            ctx.num(f"{a}.session_hot_spot_temperature_C", unit="°C"),
            " at the end of the ",
            ctx.num(f"{op}.session_s", 1 / 60, "min"),
            " session (operation.session_min), where the limit applies",
        ]
    surface_limit = _surface_limit_C(ctx.data.design)
    if surface_limit is not None:
        at = "session_surface_max_temperature_C" if session_s is not None else None
        field = at or "surface_max_temperature_C"
        warm = max(axes, key=lambda a: ctx.value(f"{op}.axes.{a}.{field}"))
        parts += [
            f"; the hottest surface, the {warm} pair's, ",
            "settles at " if at is None else "reaches ",
            ctx.num(f"{op}.axes.{warm}.{field}", unit="°C"),
            "" if at is None else " at the session's end",
            " against limits.surface_temperature_C = ",
            Num(surface_limit, key=None, unit="°C"),
        ]
    parts += [" (", Ref("fig-heating"), ")."]
    touch = surface_limit is not None
    caption = (
        "Winding temperature of each pair from switch-on at ambient, at its current for the "
        "worst heading of the operating field (conduction in the pack section from ambient, "
        "the pairs radiating to each other; solid: hot spot at the pack centre, dotted: "
        "mean"
        + ("; dash-dot-dot: the hottest point of its surface" if touch else "")
        + "). Dashed: limits.coil_temperature_C on the hot spot"
        + ("; thick grey dots: limits.surface_temperature_C on the surface" if touch else "")
        + (
            "; dash-dot: end of the session, where the limits apply."
            if session_s is not None
            else ", applied in steady state."
        )
    )
    return [
        Paragraph(parts),
        FigureBlock(
            "fig-heating",
            caption,
            _draw_heating(ctx.data, session_s),
            size_in=_SIZES_IN["fig-heating"],
        ),
    ]


def _total_power_parts(ctx: Context) -> list[Any]:
    """The copper loss at the current limit, or, where a pair runs away thermally there, that
    it has none (never a dash for a number that does not exist)."""
    total = ctx.value("coils.total_power_W")
    if isinstance(total, (int, float)) and math.isfinite(total):
        return [
            ". The heading that draws the most at that current dissipates ",
            ctx.num("coils.total_power_W", unit="W"),
        ]
    runaway = [a["axis"] for a in ctx.value("coils.axes").values() if a.get("thermal_runaway")]
    return [
        ". At that current the "
        + (", ".join(runaway) + (" pair runs" if len(runaway) == 1 else " pairs run"))
        + " away thermally (no steady temperature, so no steady copper loss): the operating "
        "point and the largest current each pair may carry are what count"
    ]


def _runaway_keys(ctx: Context, axes: list[str]) -> str:
    """The current key of each pair in ``axes``: ``limits.current_A`` when they share it, else
    ``x: limits.x.current_A; y: limits.current_A`` (a pair on its own amplifier channel)."""
    keys = {a: str(ctx.value(f"coils.axes.{a}.current_limit_key")) for a in axes}
    if len(set(keys.values())) == 1:
        return next(iter(keys.values()))
    return "; ".join(f"{a}: {k}" for a, k in keys.items())


def _rating_parts(ctx: Context) -> list[Any]:
    """The current each pair is sized at: one amplifier rating (``limits.current_A``), or each
    pair's own channel (``limits.x.current_A``) where one is set."""
    keys = [str(ctx.value(f"coils.axes.{ax}.current_limit_key")) for ax in "xyz"]
    amps = [float(ctx.value(f"coils.axes.{ax}.current_amplitude_A")) for ax in "xyz"]
    if keys == ["limits.current_A"] * 3 and len(set(amps)) == 1:
        return [
            "Each pair is sized at the current-amplitude limit ",
            ctx.num("coils.axes.x.current_amplitude_A", unit="A"),
            " (limits.current_A)",
        ]
    out: list[Any] = ["Each pair is sized at its amplifier channel's current-amplitude limit ("]
    for i, (ax, key) in enumerate(zip("xyz", keys)):
        out += ["; " if i else "", f"{ax}: "]
        out += [ctx.num(f"coils.axes.{ax}.current_amplitude_A", unit="A"), f", {key}"]
    return [*out, ")"]


def build(ctx: Context) -> Section:
    """The coil-sizing section."""
    c = "coils"
    axes = list(ctx.value("coils.axes"))
    design = ctx.data.design
    intro = Paragraph(
        [
            *_rating_parts(ctx),
            " and the operating frequency ",
            ctx.num(f"{c}.frequency_hz", unit="Hz"),
            ", copper resistance at the self-consistent mean winding temperature, ambient ",
            ctx.num(f"{c}.ambient_temperature_C", unit="°C"),
            *_total_power_parts(ctx),
            ". Inside every limit the largest rotating field (worst heading) is ",
            ctx.num(f"{c}.rotating_field_within_limits.max_rotating_field_T", 1e3, "mT"),
            ", set by ",
            str(ctx.value(f"{c}.rotating_field_within_limits.limited_by_words")),
            f" ({ctx.value(f'{c}.rotating_field_within_limits.limit_key')}; the current limit alone "
            "would allow ",
            ctx.num(f"{c}.current_limited_rotating_field_T", 1e3, "mT"),
            ", the power limit alone ",
            ctx.num(f"{c}.rotating_field_within_limits.per_limit_max_field_T.power", 1e3, "mT"),
            "). These limits are the ones the evaluation and the optimiser apply.",
        ]
    )
    ws = float(design["workspace.radius_m"])
    geometry = _figure(
        ctx.data,
        "fig-geometry",
        "The hardware to scale. Left: section through the coil centre in the x–z plane, in mm: "
        "the x and z pairs cut through their winding packs (rectangles of axial width x radial "
        "depth at the mean radius, or at half the side of a frame across the section; solid "
        "and dash-dot lines the coils edge-on), the y pair face-on (its winding annulus or frame, "
        "dashed outline, light fill), the workspace sphere "
        "dash-dotted; black segments: where the packs of two pairs come closest (the 3-D "
        "segment between the solids projected onto the section; its length in the legend). "
        "Right: the capsule "
        "to its own scale: shell, spiral wire at its helical angle over the wound length (front "
        "half thick, back half dashed) and the diametrically magnetised magnet with its "
        "moment m.",
    )
    blocks: list[Any] = [
        intro,
        Paragraph(
            ["The nested pairs and the capsule are drawn to scale in ", Ref("fig-geometry"), "."]
        ),
        geometry,
    ]
    limit_C = design["limits.coil_temperature_C"]
    hot_C = {a: ctx.value(f"{c}.axes.{a}.hot_spot_temperature_C") for a in axes}
    # no number: no steady temperature at that current (the copper's resistance rises with
    # temperature faster than the pair sheds the heat), i.e. thermal runaway
    runaway = [a for a, t in hot_C.items() if not isinstance(t, (int, float))]
    hot = [a for a, t in hot_C.items() if a not in runaway and not t <= limit_C]
    if hot:
        blocks.append(
            Paragraph(
                [
                    "At the full current limit the ",
                    ", ".join(hot),
                    f" coils would exceed limits.coil_temperature_C = {limit_C:g} °C (e.g. ",
                    ctx.num(f"{c}.axes.{hot[0]}.hot_spot_temperature_C", unit="°C"),
                    "), so the evaluation and the optimiser drive them below that current.",
                ],
                kind="note",
            )
        )
    if runaway:
        blocks.append(
            Paragraph(
                [
                    Strong("Thermal runaway. "),
                    f"At the full current limit ({_runaway_keys(ctx, runaway)}) the ",
                    ", ".join(runaway),
                    " pair" + ("s" if len(runaway) > 1 else ""),
                    " would run away thermally: the winding's resistance rises with its "
                    "temperature faster than it can shed the heat, so no steady hot-spot "
                    f"temperature exists (limits.coil_temperature_C = {limit_C:g} °C). The "
                    "evaluation and the optimiser drive them below that current; the limit "
                    "itself cannot be used.",
                ],
                kind="alert",
            )
        )
    blocks.append(_sizing_table(ctx))
    blocks += measured_blocks(ctx)
    blocks.append(_build_paragraph(ctx))
    blocks.append(_bom_table(ctx))
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
                "). ",
                Ref("fig-field-maps"),
                " maps the deviation on planes through the centre, ",
                Ref("fig-field-profiles"),
                " along lines through it.",
            ]
        )
    )
    blocks.append(
        _figure(
            ctx.data,
            "fig-field-maps",
            "Signed deviation of |B| from its centre value (red: stronger, blue: weaker, dotted "
            "where weaker by more than 1 %, so the sign reads in greyscale) on planes "
            "through the coil centre (x–z plane for "
            "the x and z pairs, y–z plane for the y pair), each pair driven alone (a static field "
            "along its axis), from coils.uniformity. Solid contour: ±1 %; dashed: ±5 %; dotted "
            "circles: the ±1 % and ±5 % spheres of that field direction (coils.uniform_region, "
            "radii in the sizing table); dash-dot circle: the design's workspace.",
        )
    )
    blocks.append(
        _figure(
            ctx.data,
            "fig-field-profiles",
            "Signed |B| deviation along each pair's axis and across it, that pair driven alone, "
            "out to where the deviation reaches about 10 %. Dashed lines: ±1 %; dotted: ±5 %. "
            "An ideal Helmholtz pair is flat to fourth order at the "
            "centre; the nested pairs' finite winding packs and spacing set the curvature.",
        )
    )
    blocks += heating_blocks(ctx)
    blocks += stray_blocks(ctx)
    return Section("coils", "Coil sizing and field uniformity", blocks)


def measured_blocks(ctx: Context) -> list[Any]:
    """The lab's measured pairs (``coils.axes.<p>.measured``) beside the computed constants."""
    parts: list[Any] = []
    for ax in ctx.value("coils.axes"):
        m = ctx.value(f"coils.axes.{ax}").get("measured")
        if not m:
            continue
        base = f"coils.axes.{ax}.measured"
        parts.append(f"The {ax} pair as measured: ")
        if "resistance_ohm" in m:
            parts += [
                ctx.num(f"{base}.resistance_ohm", unit="Ω"),
                f" at {m['temperature_C']:g} °C against ",
                ctx.num(f"{base}.computed_resistance_ohm", unit="Ω"),
                " computed (measured / computed − 1: ",
                ctx.num(f"{base}.resistance_deviation", 100.0, "%"),
                ")",
            ]
        if "inductance_H" in m:
            parts += [
                "; " if "resistance_ohm" in m else "",
                ctx.num(f"{base}.inductance_H", 1e3, "mH"),
                " against ",
                ctx.num(f"{base}.computed_inductance_H", 1e3, "mH"),
                " computed (",
                ctx.num(f"{base}.inductance_deviation", 100.0, "%"),
                ")",
            ]
        parts.append(". ")
    if not parts:
        return []
    return [
        Paragraph(
            [
                Strong("Measured pairs. "),
                *parts,
                "The measured values (coils.<pair>.measured.*) replace the computed ones in "
                "the table above and in every voltage, power, heating and waveform figure of "
                "this report; the resistance follows copper's temperature coefficient from its "
                "measuring temperature. A deviation beyond 15 % points at the turn count, the "
                "wire size, series or parallel wiring of the two coils, or the leads.",
            ]
        )
    ]


def stray_blocks(ctx: Context) -> list[Any]:
    """The stray field and the exposure crossings (``coils.stray_field``) and their map."""
    if "stray_field" not in ctx.value("coils"):
        return []
    s = "coils.stray_field"
    fade = ctx.value(f"{s}.fade_distance_m")
    parts: list[Any] = [
        Strong("Stray field and exposure. "),
        "At the operating field (",
        ctx.num(f"{s}.field_amplitude_T", 1e3, "mT"),
        " at the centre) the largest |B| over a turn, over every heading, falls below ",
        ctx.num(f"{s}.level_T", 1e3, "mT"),
        " (ICNIRP 2009's level for people with implanted devices such as pacemakers) beyond ",
    ]
    for i, ax in enumerate("xyz"):
        parts.append(f"{', ' if i else ''}{ax} ")
        if ax in fade:
            parts.append(ctx.num(f"{s}.fade_distance_m.{ax}", 1e3, "mm"))
        else:
            parts += ["more than ", ctx.num(f"{s}.search_reach_m", 1e3, "mm")]
    parts.append(" from the centre along each axis (")
    parts += [Ref("fig-stray-field"), "). "]
    crossing = ctx.value(f"{s}.exposure_crossing_hz")
    for kind in ("occupational", "public"):
        if kind in crossing and crossing[kind] > 0:
            parts += [
                f"It exceeds ICNIRP 2010's {kind} reference level at rotation frequencies above ",
                ctx.num(f"{s}.exposure_crossing_hz.{kind}", unit="Hz"),
                ". ",
            ]
        elif kind in crossing:
            parts.append(f"It exceeds ICNIRP 2010's {kind} reference level at every frequency. ")
        else:
            parts.append(
                f"It stays below ICNIRP 2010's {kind} reference level at every frequency. "
            )
    return [
        Paragraph(parts),
        _figure(
            ctx.data,
            "fig-stray-field",
            "Largest |B| over a turn, over every heading, at the operating field on the x–z and "
            "x–y planes through the coil centre (grey levels, mT), from the calibrated coils "
            "where the design carries a calibration. Orange: the 0.5 mT contour (ICNIRP 2009, "
            "implanted devices); blue: the winding packs cut by the plane; dashed: the outline "
            "of the pair whose axis is normal to the plane.",
        ),
    ]
