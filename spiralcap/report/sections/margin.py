"""Section 5: the torque margin at the design's operating point and against frequency."""

from __future__ import annotations

from typing import Any

from spiralcap.report.document import Cell, FigureBlock, Paragraph, Ref, Section, Table
from spiralcap.report.sections._util import SHOWN_UNITS, Context, readable, step_out_parts
from spiralcap.report.sections.summary import step_out_clause

#: Rows of the operating-point table: (Evaluation JSON field, label, shown unit, factor).
EVALUATION_ROWS: tuple[tuple[str, str, str, float], ...] = (
    ("helical_angle_deg", "helical angle", "°", 1.0),
    ("frequency_hz", "rotation frequency", "Hz", 1.0),
    ("field_amplitude_T", "rotating field at the centre", "mT", 1e3),
    ("field_limited_by", "field limited by", "", 1.0),
    ("workspace_field_factor", "weakest field over the workspace / centre field", "–", 1.0),
    ("current_amplitudes_A.x", "current amplitude, x pair", "A", 1.0),
    ("current_amplitudes_A.y", "current amplitude, y pair", "A", 1.0),
    ("current_amplitudes_A.z", "current amplitude, z pair", "A", 1.0),
    ("magnetic_torque_Nm", "synchronous magnetic torque (worst point)", "mN·m", 1e3),
    ("resistive_torque_Nm", "tissue resistive torque (worst set)", "mN·m", 1e3),
    ("thrust_torque_Nm", "thrust torque for the axial load", "mN·m", 1e3),
    ("required_torque_Nm", "required torque", "mN·m", 1e3),
    ("worst_tissue", "worst tissue set", "", 1.0),
    ("margin_Nm", "torque margin", "mN·m", 1e3),
    ("safety_factor", "safety factor", "–", 1.0),
    ("lag_angle_deg", "lag angle of the magnet behind the field", "°", 1.0),
    ("step_out_frequency_hz", "step-out frequency at the operating field", "Hz", 1.0),
    ("max_frequency_hz", "drive's maximum frequency (field re-maximised)", "Hz", 1.0),
    ("speed_m_s", "forward speed", "mm/s", 1e3),
    ("spiral_turns", "spiral turns over the wound length", "–", 1.0),
    ("feasible", "every requirement and limit met", "", 1.0),
)


def evaluation_table(ctx: Context, columns: list[tuple[str, str]], caption: str) -> Table:
    """The operating-point table, one column per (JSON prefix, heading)."""
    rows: list[list[Cell]] = []
    for field, label, unit, factor in EVALUATION_ROWS:
        row: list[Cell] = [label, unit or "–"]
        for prefix, _ in columns:
            value = ctx.value(f"{prefix}.{field}")
            if isinstance(value, str):
                row.append(readable(value))  # a limit's name in words, not its row label
            elif isinstance(value, bool):
                row.append("yes" if value else "NO")
            else:
                row.append(ctx.num(f"{prefix}.{field}", factor))
        rows.append(row)
    return Table(
        ["quantity", "unit", *[h for _, h in columns]],
        rows,
        caption=caption,
        wrap=0,
        id="operating-points",
    )


def checks_table(ctx: Context, prefix: str, caption: str, ident: str) -> Table:
    """Every requirement and limit of an evaluation: value, allowed, utilisation, verdict."""
    rows: list[list[Cell]] = []
    for i, c in enumerate(ctx.value(f"{prefix}.checks")):
        label, factor = SHOWN_UNITS.get(c["unit"], (c["unit"], 1.0))
        label = "" if label == "1" else label  # a ratio (a strain) has no unit to print
        rows.append(
            [
                # the self-lock row's value is alpha + atan(mu), not the helical angle its key sets
                "self-locking: α + atan μ" if c["name"] == "self_lock" else readable(c["name"]),
                c["key"],
                ctx.num(f"{prefix}.checks.{i}.value", factor, label)
                if c.get("value") is not None
                else "none (no contact)",  # the margin where the spiral does not touch
                c["sense"],
                ctx.num(f"{prefix}.checks.{i}.allowed", factor, label),
                "yes" if c["ok"] else "NO",
            ]
        )
    return Table(
        ["check", "design key", "value", "", "allowed", "ok"],
        rows,
        caption=caption,
        id=ident,
        compact=True,  # a reference table of ~20 rows: small type in the PDF
    )


def _max_frequency_parts(ctx: Context, prefix: str) -> list[Any]:
    """The drive's maximum frequency of the evaluation at ``prefix`` and what limits it."""
    value = ctx.value(f"{prefix}.max_frequency_hz")
    by = readable(str(ctx.value(f"{prefix}.max_frequency_limited_by")))
    if value is None or value != value:  # no contact: no margin to reach zero
        return ["no frequency (no contact: no margin)"]
    if ctx.value(f"{prefix}.max_frequency_beyond_search"):
        return [f"beyond {value:g} Hz"]
    if value == 0:
        return ["no frequency"]
    return [ctx.num(f"{prefix}.max_frequency_hz", unit="Hz"), f" ({by} limit)"]


def _draw_frequency(data: Any) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.api import margin_vs_frequency

        margin_vs_frequency(
            data.model,
            data.evaluation,
            data.optimization,
            ax=fig.subplots(),
            curves=(data.freq_design, data.freq_optimum),
        )

    return draw


def _draw_map(data: Any) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.api import margin_map

        margin_map(
            data.model, data.optimization, data.evaluation, ax=fig.subplots(), grid=data.margin_map
        )

    return draw


def _draw_budget(data: Any) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.api import torque_budget

        torque_budget(data.evaluation, data.optimization, ax=fig.subplots())

    return draw


def build(ctx: Context) -> Section:
    """The margin section."""
    e, o = "evaluate", "optimize"
    step = ctx.value(f"{e}.step_out_frequency_hz")
    intro = Paragraph(
        [
            "The margin is the weakest synchronous magnetic torque over the workspace points and "
            "headings minus the largest required torque (tissue resistive + thrust) over the tissue "
            "sets, with the coils driven at the largest rotating field every limit allows at that "
            "frequency (docs/optimisation.md). It falls with frequency: the tissue torque rises and "
            "the inductive drive voltage and the exposure limit cut the field. Driven at the "
            "operating field, the capsule steps out of synchrony at ",
            *step_out_parts(ctx, f"{e}.step_out_frequency_hz"),
            " at the design's helical angle and at ",
            *step_out_parts(ctx, f"{o}.step_out_frequency_hz"),
            f" at the {ctx.optimum}'s; with the field raised to what the limits allow at each "
            "frequency, the drive keeps a positive margin up to ",
            *_max_frequency_parts(ctx, e),
            " and ",
            *_max_frequency_parts(ctx, f"{o}.evaluation"),
            " (",
            Ref("fig-margin-frequency"),
            "). So, as entered: step-out ",
            step_out_clause(ctx, e, ctx.value(f"{e}.field_limited_by") == "fixed"),
            f"; at the {ctx.optimum}: step-out ",
            step_out_clause(ctx, o, bool(ctx.value(f"{o}.field_is_set"))),
            ". ",
            Ref("fig-torque-budget"),
            " splits the torques at the two operating points.",
        ]
    )
    blocks: list[Any] = [intro]
    if step == 0:
        blocks.append(
            Paragraph(
                [
                    "At the design's helical angle the margin is negative at "
                    "every frequency: the magnet cannot turn the capsule."
                ],
                kind="alert",
            )
        )
    blocks.append(
        FigureBlock(
            "fig-margin-frequency",
            "Worst-case torque margin against rotation frequency at the design's helical angle "
            + ("and at the optimum's" if ctx.feasible else "(no feasible optimum)")
            + ", the field the largest the limits allow at each frequency "
            "(optimize.margin_grid). Each curve is solid where every requirement holds at its "
            "own angle and thin and dotted where one fails; dash-dot vertical lines: the "
            "drive's maximum frequency (max_frequency_hz, where the curve reaches zero); dashed: "
            "the step-out frequency at the operating field (step_out_frequency_hz); stars: the "
            "operating points; hatched: negative margin; a curve at an angle whose spiral does "
            "not grip is hatched and named (no contact: no margin; below the minimum wall "
            "strain: extrapolated).",
            _draw_frequency(ctx.data),
            size_in=(7.5, 5.0),
        )
    )
    if ctx.data.margin_map is not None:
        blocks.append(
            Paragraph(
                [
                    "Over the whole design space of helical angle and frequency (",
                    Ref("fig-margin-map"),
                    ") the feasible region is bounded by the minimum speed (low frequency, "
                    "small angle), the minimum number of spiral turns (large angle) and the "
                    "boundary where the margin reaches zero: with the field the largest the "
                    "limits allow, the drive's maximum frequency at each angle.",
                ]
            )
        )
        blocks.append(
            FigureBlock(
                "fig-margin-map",
                "Worst-case torque margin over helical angle and rotation frequency "
                "(optimize.margin_grid on a 90 × 90 grid inside the optimiser's angle bounds). "
                "Colour levels span the feasible margins; grey, cross-hatched: margin < 0, the "
                "capsule steps out; each other hatched region is named by the requirement that "
                "fails there; thick black line: margin = 0, where the capsule steps out even at the "
                "largest field (the drive's maximum frequency); open circle: "
                "the best feasible grid point; star: the optimiser's "
                + ("optimum" if ctx.feasible else "closest design (no design is feasible)")
                + "; diamond: the design as entered; no contact (the spiral does not touch "
                "the wall): no margin there, hatched; a wall strain below the minimum: "
                "extrapolated, hatched.",
                _draw_map(ctx.data),
                size_in=(7.0, 4.6),
            )
        )
    blocks.append(
        evaluation_table(
            ctx,
            [(e, "as entered"), (f"{o}.evaluation", ctx.optimum)],
            "Operating points (same numbers as `spiralcap evaluate --json` and the evaluation "
            "inside `spiralcap optimize --json`)",
        )
    )
    blocks.append(
        FigureBlock(
            "fig-torque-budget",
            f"Torque budget at the operating point as entered and at the {ctx.optimum}: the "
            "synchronous "
            "torque the magnet can deliver at the weakest workspace point against the required "
            "torque (tissue resistive, hatched, plus thrust, dotted).",
            _draw_budget(ctx.data),
            size_in=(6.5, 4.0),
        )
    )
    blocks.append(
        checks_table(ctx, e, "Requirements and limits of the design as entered", "checks-entered")
    )
    return Section("margin", "Torque margin and step-out", blocks)
