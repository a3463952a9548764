"""Section 7: trade-offs -- margin against helical angle, and against the power budget."""

from __future__ import annotations

from typing import Any

from spiralcap.report.document import Cell, FigureBlock, Paragraph, Ref, Section, Table
from spiralcap.report.sections._util import Context, readable


def power_sweep_payload(data: Any) -> dict[str, Any]:
    """The re-optimisation sweep over ``limits.power_W`` as JSON-ready columns."""
    sw = data.power_sweep
    out: dict[str, Any] = {"power_W": [float(v) for v in sw.inputs["limits.power_W"]]}
    for key, col in sw.outputs.items():
        out[key] = [v.item() if hasattr(v, "item") else v for v in col]
    return out


def _draw_angle(data: Any) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.api import margin_vs_angle

        margin_vs_angle(
            data.model,
            data.optimization,
            data.evaluation,
            ax=fig.subplots(),
            curve=data.angle_optimum,
        )

    return draw


def _draw_power(data: Any, sweep: dict[str, Any]) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.api import margin_vs_power

        margin_vs_power(data.design, ax=fig.subplots(), sweep=data.power_sweep)

    return draw


def build(ctx: Context) -> Section:
    """The trade-offs section."""
    sweep = ctx.value("tradeoffs.power_sweep")
    rows: list[list[Cell]] = []
    for i, status in enumerate(sweep["status"]):
        p = "tradeoffs.power_sweep"
        binding = ", ".join(readable(n) for n in sweep["binding_limits"][i].split(";") if n)
        rows.append(
            [
                ctx.num(f"{p}.power_W.{i}", unit="W"),
                status,
                ctx.num(f"{p}.helical_angle_deg.{i}", unit="°"),
                ctx.num(f"{p}.frequency_hz.{i}", unit="Hz"),
                ctx.num(f"{p}.field_amplitude_T.{i}", 1e3, "mT"),
                ctx.num(f"{p}.margin_Nm.{i}", 1e3, "mN·m"),
                binding or "none",
            ]
        )
    table = Table(
        [
            "power budget",
            "status",
            "helical angle",
            "frequency",
            "field",
            "margin",
            "binding limits",
        ],
        rows,
        wrap=6,
        id="power-sweep",
        compact=True,  # every budget's row: small type in the PDF
        caption="Re-optimisation at each power budget (spiralcap sweep --optimize "
        "--over limits.power_W=...)"
        + (
            "; an infeasible row shows the closest design that grips the wall, not an optimum"
            if any(st != "optimal" for st in sweep["status"])
            else ""
        ),
    )
    angle_fig = FigureBlock(
        "fig-margin-angle",
        "Worst-case torque margin against the spiral's helical angle (optimize.margin_grid), "
        "each angle run at the lowest frequency inside the bounds that meets the minimum speed "
        "(grey dashed, right axis): the margin a helical-angle tolerance costs. Small angles "
        "need a higher frequency (more tissue torque, less field); large angles cost thrust "
        "torque and fall below the minimum number of spiral turns (hatched: that requirement "
        "fails). Where the spiral stretches the wall less than requirements.min_wall_strain "
        "the model extrapolates, and where it does not touch the wall there is no margin: both "
        "hatched and named. Star: the "
        + ("optimum" if ctx.feasible else "closest design (no design is feasible)")
        + "; dashed line: the angle as entered.",
        _draw_angle(ctx.data),
        size_in=(7.5, 5.2),
    )
    power_fig = FigureBlock(
        "fig-margin-power",
        "Best achievable margin against the copper-power budget, each point a full "
        "re-optimisation (helical angle, frequency and currents) with every other limit kept. "
        "Where the curve flattens, power no longer binds and another limit (named beside each "
        "point) takes over. Dashed line: the design's budget.",
        _draw_power(ctx.data, sweep),
        size_in=(7.5, 4.4),
    )
    intro = Paragraph(
        [
            "Two trade-offs a designer asks about first: how sensitive the margin is to the "
            "spiral's helical angle (a manufacturing tolerance, ",
            Ref("fig-margin-angle"),
            "), and what more amplifier and cooling power buys (",
            Ref("fig-margin-power"),
            ", ",
            Ref("power-sweep"),
            ").",
        ]
    )
    return Section("tradeoffs", "Trade-offs", [intro, angle_fig, power_fig, table])
