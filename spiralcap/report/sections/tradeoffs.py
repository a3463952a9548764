"""Section 7: trade-offs -- margin against helical angle, and against the power budget."""

from __future__ import annotations

from typing import Any

import numpy as np

from spiralcap.report.document import Cell, FigureBlock, Paragraph, Section, Table
from spiralcap.report.sections._util import Context, readable


def power_sweep_payload(data: Any) -> dict[str, Any]:
    """The re-optimisation sweep over ``limits.power_W`` as JSON-ready columns."""
    sw = data.power_sweep
    out: dict[str, Any] = {"power_W": [float(v) for v in sw.inputs["limits.power_W"]]}
    for key, col in sw.outputs.items():
        out[key] = [v.item() if hasattr(v, "item") else v for v in col]
    return out


def _draw_angle(data: Any) -> Any:
    ev, res = data.evaluation, data.optimization

    def draw(fig: Any) -> None:
        from spiralcap.figures.design import plot_margin_vs_angle

        ax = fig.subplots()
        c = data.angle_optimum
        # start where the margin is above -40 % of its peak: the steep fall at tiny angles
        # would squeeze the useful range (the range is chosen from the data)
        peak = float(np.nanmax(c.margin_Nm))
        keep = np.nonzero(c.margin_Nm >= -0.4 * abs(peak))[0]
        sl = slice(max(0, int(keep[0]) - 1) if keep.size else 0, None)
        plot_margin_vs_angle(
            ax,
            c.x[sl],
            c.margin_Nm[sl],
            shortfalls={
                "speed below requirements.min_speed_mm_s": c.speed_slack_m_s[sl],
                "fewer turns than requirements.min_spiral_turns": c.turns_slack[sl],
            },
            optimum_deg=res.helical_angle_deg,
            optimum_margin_Nm=res.margin_Nm,
            design_angle_deg=ev.helical_angle_deg,
            label="margin, each angle at the lowest frequency meeting the speed",
        )
        if c.frequency_hz is not None:
            twin = ax.twinx()
            fx = c.frequency_hz[sl]
            twin.plot(c.x[sl], fx, color="0.45", linestyle=(0, (3, 1.5)), linewidth=1.2)
            twin.set_ylabel("frequency used (Hz), grey dashed", color="0.3")
            twin.set_ylim(0, 1.1 * float(fx.max()))
            twin.grid(False)

    return draw


def _draw_power(data: Any, sweep: dict[str, Any]) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.design import plot_margin_vs_power

        ax = fig.subplots()
        margin = np.array([np.nan if m is None else m for m in sweep["margin_Nm"]], float)
        plot_margin_vs_power(
            ax,
            sweep["power_W"],
            margin,
            optimal=[s == "optimal" for s in sweep["status"]],
            design_power_W=data.design["limits.power_W"],
            binding=[
                ";".join(readable(n) for n in b.split(";") if n) for b in sweep["binding_limits"]
            ],
        )

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
        caption="Re-optimisation at each power budget (spiralcap sweep --optimize "
        "--over limits.power_W=...)",
    )
    angle_fig = FigureBlock(
        "fig-margin-angle",
        "Worst-case torque margin against the spiral's helical angle (optimize.margin_grid), "
        "each angle run at the lowest frequency inside the bounds that meets the minimum speed "
        "(grey dashed, right axis): the margin a helical-angle tolerance costs. Small angles "
        "need a higher frequency (more tissue torque, less field); large angles cost thrust "
        "torque and fall below the minimum number of spiral turns (hatched: that requirement "
        "fails). Star: the optimum; dashed line: the angle as entered.",
        _draw_angle(ctx.data),
        size_in=(7.5, 4.4),
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
            "spiral's helical angle (a manufacturing tolerance), and what more amplifier and "
            "cooling power buys."
        ]
    )
    return Section("tradeoffs", "Trade-offs", [intro, angle_fig, power_fig, table])
