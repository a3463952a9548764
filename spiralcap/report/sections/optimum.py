"""Section 6: the optimum, its binding limits and multipliers, the limits' use, the currents."""

from __future__ import annotations

from typing import Any, cast

from spiralcap.assemble.system import message_in_key_units
from spiralcap.report.document import Cell, Code, FigureBlock, Paragraph, Ref, Section, Table
from spiralcap.report.numbers import fmt
from spiralcap.report.sections._util import SHOWN_UNITS, Context, readable
from spiralcap.report.sections.margin import checks_table
from spiralcap.report.sections.summary import binding_gain, step_out_clause


def changed_values(design: Any, result: Any) -> dict[str, Any]:
    """The keys ``spiralcap optimize -o`` writes with a value other than the input design's.

    From :func:`spiralcap.assemble.system.optimum_values` (angle, frequency, the field where
    set, freed hardware at its discrete optimum); the optimiser's own ``optimize.free.*``
    switches are not design values and are left out, as in the written file.
    """
    from spiralcap.assemble.system import _FREE_PREFIX, optimum_values

    out = {}
    for key, value in optimum_values(design, result).items():
        old = design.get(key)
        if key.startswith(_FREE_PREFIX):
            continue
        same = (
            isinstance(value, float)
            and isinstance(old, (int, float))
            and abs(value - old) <= 1e-12 * max(abs(value), abs(old))
        )
        if old != value and not same:
            out[key] = value
    return out


def design_file_blocks(ctx: Context) -> list[Any]:
    """The optimised design file as the keys it changes, and how to write the whole file."""
    from spiralcap.design import _to_toml

    changed = changed_values(ctx.data.design, ctx.data.optimization)
    if not changed:
        return [Paragraph(["The optimum is the design as entered: no design key changes."])]
    return [
        Paragraph(
            [
                "The optimised design file differs from the input design in these keys; "
                "`spiralcap optimize DESIGN -o best.toml` writes the complete file, and "
                "`spiralcap evaluate best.toml` reproduces the optimum."
            ]
        ),
        Code(
            _to_toml(changed, comments=False).strip() + "\n",
            caption="The optimised design's changed keys "
            "(spiralcap.assemble.system.optimum_values)",
        ),
    ]


def _binding_table(ctx: Context) -> Table:
    sized = "hardware" in ctx.value("optimize")
    rows: list[list[Cell]] = []
    for i, b in enumerate(ctx.value("optimize.binding_limits")):
        label = b["key_unit"] if b["key_unit"] not in ("1",) else ""
        verb, gain = binding_gain(ctx, i)
        p = f"optimize.binding_limits.{i}"
        rows.append(
            [
                readable(b["name"]),
                b["key"],
                ctx.num(f"{p}.value_in_key_unit", 1.0, label),
                ctx.num(f"{p}.allowed_in_key_unit", 1.0, label),
                verb,
                gain,
            ]
        )
    return Table(
        [
            "binding limit",
            "design key",
            "value",
            "allowed",
            "relaxing means",
            "gain per step relaxed",
        ],
        rows,
        caption="Binding limits and their multipliers: what relaxing each by one step of its "
        "design key (1 unit of it; 0.1 % of strain, 1° of angle) buys in the objective's unit (d objective / d allowed value, from IPOPT's "
        "Lagrange multipliers with the scaling undone"
        + ("; of the continuous relaxation, for the sized hardware)" if sized else ")"),
        id="binding-limits",
    )


def _shared_keys(ctx: Context) -> list[Paragraph]:
    """Keys several binding rows share: relaxing the key relaxes them all, its gain the sum."""
    out = []
    for i, k in enumerate(ctx.value("optimize.binding_keys")):
        if len(k["rows"]) < 2:
            continue
        obj_unit, per = str(k["gain_per_step_label"]).split(" per ", 1)
        out.append(
            Paragraph(
                [
                    f"{k['key']} bounds {len(k['rows'])} of these rows ("
                    + "; ".join(readable(r) for r in k["rows"])
                    + f"); {k['relaxing_means']} it by {per} relaxes them all and gains ",
                    ctx.num(f"optimize.binding_keys.{i}.gain_per_step", 1.0, obj_unit),
                    " in all (IPOPT may split a multiplier among rows that tie in any "
                    "proportion; their sum is what the key buys).",
                ]
            )
        )
    return out


def _shortfall_table(ctx: Context) -> Table:
    rows: list[list[Cell]] = []
    for i, s in enumerate(ctx.value("optimize.shortfalls")):
        label, factor = SHOWN_UNITS.get(s["unit"], (s["unit"], 1.0))
        p = f"optimize.shortfalls.{i}"
        rows.append(
            [
                readable(s["name"]),
                s["key"],
                ctx.num(f"{p}.needed", factor, label),
                ctx.num(f"{p}.best", factor, label),
                ctx.num(f"{p}.short_by", factor, label),
            ]
        )
    at = ctx.value("optimize").get("explained_at", {})
    where = ", ".join(f"{k} = {fmt(v)}" for k, v in at.get("keys", {}).items())
    return Table(
        ["requirement", "design key", "needed", "best reachable", "short by"],
        rows,
        caption="NO FEASIBLE DESIGN: requirements out of reach inside the limits, at the "
        + (
            "closest design that grips the wall"
            if at.get("grips", True)
            else "helical angle that stretches the walls most (none grips)"
        )
        + (
            f" ({where}; `spiralcap evaluate` there gives these numbers)"
            if where and at.get("at_design_hardware", False)
            else f" ({where})"
            if where
            else ""
        ),
        id="shortfalls",
    )


def _allocation_table(ctx: Context) -> Table:
    rows: list[list[Cell]] = []
    for i, a in enumerate(ctx.value("optimize.current_allocation")):
        p = f"optimize.current_allocation.{i}"
        heading = "[" + ", ".join(f"{c:.3g}" for c in a["heading"]) + "]"
        row: list[Cell] = [heading]
        row += [ctx.num(f"{p}.amplitudes_A.{k}") for k in "xyz"]
        row += [ctx.num(f"{p}.phases_deg.{k}") for k in "xyz"]
        rows.append(row)
    return Table(
        ["heading (unit vector)", "I_x (A)", "I_y (A)", "I_z (A)", "φ_x (°)", "φ_y (°)", "φ_z (°)"],
        rows,
        caption=f"Coil current amplitudes and phases at the {ctx.optimum}'s field, per heading "
        "(centre allocation)" + ("" if ctx.feasible else "; no design is feasible"),
        id="allocation",
        compact=True,  # one row per heading (up to 64): small type in the PDF
    )


#: Longest bar label of the utilisation figure, characters (a fitted tissue set's name in a
#: check's name would squeeze the bars to nothing).
LABEL_CHARS = 40


def _short_label(text: str) -> str:
    """``text`` cut to :data:`LABEL_CHARS` characters with an ellipsis."""
    return text if len(text) <= LABEL_CHARS else text[: LABEL_CHARS - 1].rstrip() + "…"


def _draw_utilisation(checks: Any) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.design import plot_limit_utilisation

        names = {c["name"]: _short_label(readable(c["name"])) for c in checks}
        plot_limit_utilisation(fig.subplots(), checks, labels=names)

    return draw


def _tolerance_table(ctx: Context) -> list[Any]:
    """Each toleranced key's feasible interval around the optimum (``spiralcap optimize``'s
    ``tolerance_intervals``), with the requirement that ends it on each side; none without."""
    o = "optimize.tolerance_intervals"
    if "tolerance_intervals" not in ctx.value("optimize"):
        return []
    rows: list[list[Cell]] = []
    for i, k in enumerate(ctx.value(f"{o}.keys")):
        p = f"{o}.keys.{i}"
        offset = bool(k["offset_from_each_tissue_set"])
        head: list[Cell] = [
            k["key"] + (" (offset from each tissue set's own)" if offset else ""),
            k["unit"],
            ctx.num(f"{p}.nominal"),
            ctx.num(f"{p}.tolerance"),
        ]
        if not k["feasible_at_nominal"]:
            rows.append([*head, "fails", "fails", readable(k["low_limited_by"]), ""])
            continue
        rows.append(
            [
                *head,
                ctx.num(f"{p}.low"),
                ctx.num(f"{p}.high"),
                readable(k["low_limited_by"]) if k["low_limited_by"] != "search" else "–",
                readable(k["high_limited_by"]) if k["high_limited_by"] != "search" else "–",
            ]
        )
    return [
        Table(
            [
                "toleranced key",
                "unit",
                "design",
                "±",
                "holds from",
                "holds to",
                "ends below on",
                "ends above on",
            ],
            rows,
            caption="Tolerances ([tolerances]): every requirement is held at its own worst "
            "corner of the box; each key's interval is the room left, "
            + str(ctx.value(f"{o}.varied")),
            id="tolerance-intervals",
        )
    ]


def _objective_rows(ctx: Context, what: str, sense: str) -> list[list[Cell]]:
    o = "optimize"
    if "objective_value_shown" not in ctx.value(o):
        return []
    unit = str(ctx.value(f"{o}.objective_unit")) or "–"
    return [[f"objective: {what} ({sense})", unit, ctx.num(f"{o}.objective_value_shown")]]


def build(ctx: Context) -> Section:
    """The optimum section."""
    o = "optimize"
    feasible = ctx.value(f"{o}.status") == "optimal"
    what = str(ctx.value(f"{o}.objective_description"))
    sense = str(ctx.value(f"{o}.objective_direction"))
    over = "the helical angle, the rotation frequency and the field amplitude"
    if "hardware" in ctx.value(o):
        over += ", and the freed hardware keys"
    starts = int(ctx.value(f"{o}.starts"))
    blocks: list[Any] = [
        Paragraph(
            [
                f"IPOPT {sense} the {what} over {over} (the coil "
                "currents follow exactly from the field and the headings), with exact CasADi "
                "derivatives, from ",
                ctx.num(f"{o}.starts"),
                " start (" if starts == 1 else " starts (",
                ctx.num(f"{o}.iterations"),
                " iterations in all; solver status ",
                str(ctx.value(f"{o}.solver_status")),
                "). ",
                message_in_key_units(str(ctx.value(f"{o}.message"))).rstrip(".") + ". ",
                Ref("fig-utilisation"),
                " shows how close each limit is to binding.",
            ],
            kind="ok" if feasible else "alert",
        )
    ]
    rows: list[list[Cell]] = [
        ["status", "", str(ctx.value(f"{o}.status"))],
        *_objective_rows(ctx, what, sense),
        ["helical angle", "°", ctx.num(f"{o}.helical_angle_deg")],
        ["rotation frequency", "Hz", ctx.num(f"{o}.frequency_hz")],
        ["rotating field at the centre", "mT", ctx.num(f"{o}.field_amplitude_T", 1e3)],
        *(
            cast(
                list[Cell],
                [f"current amplitude, {k} pair", "A", ctx.num(f"{o}.current_amplitudes_A.{k}")],
            )
            for k in "xyz"
        ),
        ["torque margin", "mN·m", ctx.num(f"{o}.margin_Nm", 1e3)],
        ["safety factor", "–", ctx.num(f"{o}.safety_factor")],
        ["forward speed", "mm/s", ctx.num(f"{o}.speed_m_s", 1e3)],
        ["step-out frequency at the operating field", "Hz", ctx.num(f"{o}.step_out_frequency_hz")],
        [
            "whether the drive reaches it",
            "",
            step_out_clause(ctx, o, bool(ctx.value(f"{o}.field_is_set"))),
        ],
    ]
    blocks.append(
        Table(
            ["quantity", "unit", "optimum" if feasible else "closest design"],
            rows,
            caption=(
                "The optimum"
                if feasible
                else "NO FEASIBLE DESIGN: the closest design, where the shortfalls are stated"
            )
            + " (same numbers as `spiralcap optimize --json`)",
            id="optimum-table",
        )
    )
    if feasible:
        if ctx.value(f"{o}.binding_limits"):
            blocks.append(_binding_table(ctx))
            blocks += _shared_keys(ctx)
            blocks.append(
                Paragraph(
                    [
                        "Read a gain as what relaxing that limit by one step of its design key "
                        "(the last column: 1 °C, 1 mm/s, 0.1 % of strain) buys "
                        f"in the {what}, to first order (from IPOPT's multipliers): raising an "
                        "upper limit, lowering a requirement or a lower bound. Bounds of the "
                        "search box (optimize.*) appear when the optimum sits on them. These are "
                        "the gains `spiralcap optimize` prints."
                    ]
                )
            )
        else:
            blocks.append(Paragraph(["No limit binds at the optimum."]))
        blocks += _tolerance_table(ctx)
        blocks += design_file_blocks(ctx)
    else:
        blocks.append(_shortfall_table(ctx))
    blocks.append(
        FigureBlock(
            "fig-utilisation",
            f"How close each limit and requirement is to binding at the {ctx.optimum}"
            + ("" if feasible else " (no design is feasible)")
            + ": value / allowed "
            "for limits, needed / achieved for requirements. Hatched bars at 100 % bind; "
            "cross-hatched bars beyond 100 % are violated.",
            _draw_utilisation(ctx.data.optimize_json["evaluation"]["checks"]),
            size_in=(7.0, 4.6),
        )
    )
    blocks.append(
        checks_table(
            ctx,
            f"{o}.evaluation",
            f"Requirements and limits at the {ctx.optimum}"
            + ("" if feasible else " (no design is feasible)"),
            "checks-optimum",
        )
    )
    blocks.append(_allocation_table(ctx))
    return Section("optimum", "Optimum and binding limits", blocks)
