"""Section 1, one page: the verdict, what binds, what to change, the bill of materials in brief.

The summary is the report's first page: a reviewer reads the verdict on the design as entered,
the optimum the optimiser proposes (margin, speed, the limits that bind it), what to change
first and what the workshop and the amplifiers must supply, then turns the page for the rest.
"""

from __future__ import annotations

from typing import Any

from spiralcap.assemble.system import message_in_key_units
from spiralcap.report.document import Block, Cell, Inline, Link, Paragraph, Section, Strong, Table
from spiralcap.report.numbers import Num, fmt
from spiralcap.report.sections._util import Context, readable


def binding_gain(ctx: Context, limit_index: int) -> tuple[str, Num]:
    """How relaxing binding limit ``i`` helps: the verb and the gain per step of its key.

    Mirrors ``spiralcap optimize``: "raising it by 1 °C gains 0.02448 mN·m" (``lowering`` for a
    requirement or a lower bound), from the JSON's ``gain_per_step`` (the objective's shown
    unit -- mN·m, W, kg or the safety factor -- per ``gain_step`` of the design key: 1 °C, 1°,
    0.1 % of strain) and ``relaxing_means``.
    """
    path = f"optimize.binding_limits.{limit_index}"
    b = ctx.value(path)
    return b["relaxing_means"], ctx.num(f"{path}.gain_per_step", 1.0, b["gain_per_step_label"])


def objective_parts(ctx: Context) -> list[Inline]:
    """``the copper mass of the three coil pairs, minimised: 140.06 kg``, inline."""
    o = "optimize"
    what = str(ctx.value(f"{o}.objective_description"))
    sense = str(ctx.value(f"{o}.objective_direction"))
    unit = str(ctx.value(f"{o}.objective_unit"))
    out: list[Inline] = [f"the {what}, {sense}"]
    if "objective_value_shown" in ctx.value(o):
        out += [": ", ctx.num(f"{o}.objective_value_shown", unit=unit)]
    return out


def step_out_clause(ctx: Context, prefix: str, field_fixed: bool) -> str:
    """The step-out frequency of the result at ``prefix`` and whether the drive reaches it
    (:func:`spiralcap.presentation.step_out_words`)."""
    from spiralcap.presentation import step_out_words

    ev = ctx.value(prefix) if prefix.endswith("evaluate") else ctx.value(f"{prefix}.evaluation")
    top = ctx.value(prefix)
    return step_out_words(
        top.get("step_out_frequency_hz", float("nan")),  # absent: no contact
        top["step_out_bound"],
        ev.get("max_frequency_hz", float("nan")),
        ev["max_frequency_beyond_search"],
        ev["max_frequency_limited_by"],
        field_fixed,
    )


def binding_parts(ctx: Context, limit_index: int) -> list[Inline]:
    """``total copper power (limits.power_W): raising it by one W gains 0.01 mN·m``, inline."""
    b = ctx.value(f"optimize.binding_limits.{limit_index}")
    verb, gain = binding_gain(ctx, limit_index)
    unit = gain.unit.split(" per ", 1)[-1]
    better = "less" if b["objective_sense"] < 0 else "more"
    if fmt(float(gain.value)) == "0":  # say what a zero gain means, not "gains 0"
        fixed = ctx.value("optimize.objective") == "copper_mass" and not ctx.value("optimize").get(
            "hardware"
        )
        return [
            Strong(readable(b["name"])),
            f" ({b['key']}): on its bound, "
            + (
                "but the copper is fixed (free hardware keys to size it)"
                if fixed
                else "relaxing it does not change the objective to four figures"
            ),
        ]
    return [
        Strong(readable(b["name"])),
        f" ({b['key']}): {verb} it by {unit} gains ",
        Num(gain.value, gain.key, gain.scale, gain.unit.split(" per ", 1)[0]),
        f" {better}",
    ]


def build(ctx: Context) -> Section:
    """The summary section."""
    o = "optimize"
    feasible = ctx.value(f"{o}.status") == "optimal"
    lines: list[Paragraph] = []
    if feasible:
        lines.append(
            Paragraph(
                [
                    Strong("Objective:"),
                    " ",
                    *objective_parts(ctx),
                    ". ",
                    Strong("Margin:"),
                    " ",
                    ctx.num(f"{o}.margin_Nm", 1e3, "mN·m"),
                    " worst-case torque margin (safety factor ",
                    ctx.num(f"{o}.safety_factor"),
                    ") at the optimum: helical angle ",
                    ctx.num(f"{o}.helical_angle_deg", unit="°"),
                    ", rotation ",
                    ctx.num(f"{o}.frequency_hz", unit="Hz"),
                    ", rotating field ",
                    ctx.num(f"{o}.field_amplitude_T", 1e3, "mT"),
                    ".",
                ]
            )
        )
        lines.append(
            Paragraph(
                [
                    Strong("Speed:"),
                    " ",
                    ctx.num(f"{o}.speed_m_s", 1e3, "mm/s"),
                    " forward; at this helical angle the capsule steps out of synchrony at ",
                    step_out_clause(ctx, o, bool(ctx.value(f"{o}.field_is_set"))),
                    ".",
                ]
            )
        )
        binding = ctx.value(f"{o}.binding_limits")
        parts: list[Inline] = [
            Strong("Binding limits:" if len(binding) > 1 else "Binding limit:"),
            " ",
        ]
        if not binding:
            parts.append("none: the optimum lies inside every limit.")
        for i in range(len(binding)):
            if i:
                parts.append("; ")
            parts += binding_parts(ctx, i)
        parts.append(".")
        lines.append(Paragraph(parts))
        verdict = Paragraph(
            [
                "Feasible: the optimiser found a helical angle, frequency and coil currents that "
                "meet every requirement inside every limit (",
                Link("section Optimum", "optimum"),
                ").",
            ],
            kind="ok",
        )
    else:
        shortfalls = ctx.value(f"{o}.shortfalls")
        head: list[Inline] = [
            Strong("Margin:"),
            " NO FEASIBLE DESIGN. Out of reach inside the limits: ",
        ]
        for i, sf in enumerate(shortfalls):
            if i:
                head.append("; ")
            head += [
                f"{readable(sf['name'])} ({sf['key']}) needs ",
                ctx.shown(f"{o}.shortfalls.{i}.needed", sf["unit"]),
                ", the best reachable is ",
                ctx.shown(f"{o}.shortfalls.{i}.best", sf["unit"]),
            ]
        if not shortfalls:
            head.append(
                _without_status(message_in_key_units(str(ctx.value(f"{o}.message")))).rstrip(".")
            )
        head.append(".")
        lines.append(Paragraph(head, kind="alert"))
        speed_parts: list[Inline] = [Strong("Speed:"), " "]
        speed = [i for i, s in enumerate(shortfalls) if s["name"] == "speed"]
        if speed:
            i = speed[0]
            speed_parts += [
                "out of reach: needs ",
                ctx.shown(f"{o}.shortfalls.{i}.needed", "m/s"),
                ", the best reachable inside the limits is ",
                ctx.shown(f"{o}.shortfalls.{i}.best", "m/s"),
                ".",
            ]
        else:
            speed_parts += ["closest design reaches ", ctx.num(f"{o}.speed_m_s", 1e3, "mm/s"), "."]
        lines.append(Paragraph(speed_parts))
        lines.append(
            Paragraph(
                [
                    Strong("Binding limit:"),
                    " the hardware and exposure limits are kept hard; what is "
                    "out of reach, and by how much, is listed in ",
                    Link("section Optimum", "optimum"),
                    ". What would help, in this order: ",
                    advice_sentence(ctx),
                ]
            )
        )
        verdict = Paragraph(
            [
                "Infeasible: no design inside the limits meets every requirement. The tables "
                "and figures below show the closest design "
                + (
                    "that still grips the wall (every wall strain at least "
                    "requirements.min_wall_strain), where the shortfalls are stated."
                    if ctx.value(f"{o}").get("explained_at", {}).get("grips", True)
                    else "the optimiser found: no helical angle inside the bounds grips the wall."
                )
            ],
            kind="alert",
        )
    # a review reads the design as entered first, then the optimum as a proposed change
    sized = sized_hardware_changes(ctx)
    proposed = Paragraph(
        [
            Strong("Proposed change: the optimum."),
            (
                " The optimiser re-chose the operating point and sized the freed hardware ("
                + ", ".join(sized)
                + ") inside the same limits; "
                if sized
                else " The optimiser re-chose the operating point inside the same hardware "
                "and limits; "
            )
            + "adopting it is a change to the design (whether it is safe under uncertainty, and "
            "who the exposure levels protect: ",
            Link("section Conclusion", "conclusion"),
            ").",
        ]
    )
    if not feasible:  # nothing to adopt: the first page says so instead
        proposed = _no_proposal(ctx)
    blocks: list[Block] = [
        _as_entered(ctx),
        *_warnings(ctx),
        proposed,
        *lines,
        change_first(ctx),
        verdict,
    ]
    if (ctx.payload.get("coils") or {}).get("bill_of_materials"):
        blocks.append(bom_brief(ctx))
    return Section("summary", "Summary", blocks)


def advice_sentence(ctx: Context) -> str:
    """The infeasible result's advice (``optimize.advice``, :func:`spiralcap.explain.advice`)
    as one numbered sentence: design changes inside the model first, a requirement last."""
    advice = ctx.value("optimize").get("advice") or [
        "relax a limit or a requirement listed as out of reach in section Optimum"
    ]
    return "; ".join(f"({i}) {a}" for i, a in enumerate(advice, 1)) + "."


def _no_proposal(ctx: Context) -> Paragraph:
    """The first page's place of the proposed change when nothing is feasible: no proposal."""
    return Paragraph(
        [
            Strong("No proposed change: no feasible design."),
            " The optimiser found no helical angle, frequency and field that meet every "
            "requirement inside the limits; the closest design below is not a design to adopt (",
            Link("section Optimum", "optimum"),
            ").",
        ],
        kind="alert",
    )


def _warnings(ctx: Context) -> list[Paragraph]:
    """The evaluation's warnings (a pack surface above IEC 60601-1's touch limit) as callouts."""
    out = []
    for w in (ctx.payload.get("evaluate") or {}).get("warnings", []):
        text = w.removeprefix("warning: ")
        out.append(Paragraph([Strong("Warning. "), text[:1].upper() + text[1:] + "."], "alert"))
    return out


def _same(ctx: Context, a: str, b: str, scale: float = 1.0) -> bool:
    """Whether two results print alike (4 significant figures, as the report shows them)."""
    return fmt(float(ctx.value(a)) * scale) == fmt(float(ctx.value(b)) * scale)


def _operating_point_change(ctx: Context) -> list[Inline]:
    """``helical angle 10° → 21.7°, rotation 2 Hz → 0.6667 Hz``: only what changes."""
    e, o = "evaluate", "optimize"
    out: list[Inline] = []
    for name, key, unit in (
        ("helical angle", "helical_angle_deg", "°"),
        ("rotation", "frequency_hz", "Hz"),
    ):
        if _same(ctx, f"{e}.{key}", f"{o}.{key}"):
            continue
        out += [
            ", " if out else "",
            f"{name} ",
            ctx.num(f"{e}.{key}", unit=unit),
            " → ",
            ctx.num(f"{o}.{key}", unit=unit),
        ]
    return out


def change_first(ctx: Context) -> Paragraph:
    """What to change first: what fails, the proposed operating point and hardware (only what
    differs), and the binding limit worth most; one sentence when the design is already at its
    optimum."""
    c, e, o = "conclusion", "evaluate", "optimize"
    parts: list[Inline] = [Strong("What to change first. ")]
    failing = [r for r in ctx.value(f"{e}.checks") if not r["ok"]]
    if failing:
        parts.append(
            "Fix what fails as entered: "
            + ", ".join(f"{readable(r['name'])} ({r['key']})" for r in failing)
            + ". "
        )
    if ctx.value(f"{o}.status") != "optimal":
        parts += ["No design is feasible; what would help, in this order: ", advice_sentence(ctx)]
        return Paragraph(parts)
    point = _operating_point_change(ctx)
    sized = sized_hardware_changes(ctx)
    if not point and not sized:
        parts.append(
            "Nothing: the design as entered is already at its optimum (the optimiser's "
            "operating point is the one entered, the worst-case margin "
        )
        parts += [ctx.num(f"{o}.margin_Nm", 1e3, "mN·m"), ")."]
    else:
        parts += [
            "Adopt the proposed operating point and hardware ("
            if sized
            else "Adopt the proposed operating point ("
            if point
            else "Adopt the proposed hardware (",
            Link("section Optimum", "optimum"),
            "): ",
            *point,
            "".join(f"{', ' if point or i else ''}{change}" for i, change in enumerate(sized)),
        ]
        parts += _margin_change(ctx)
    gains = (ctx.payload.get(c) or {}).get("limit_gains")
    if gains and fmt(float(gains[0]["objective_percent_per_percent"])) != "0":
        g = gains[0]
        parts += [
            " Beyond that, the binding limit worth most is ",
            f"{readable(g['name'])} ({g['key']}): {g['relaxing_means']} it by 1 % of its "
            "bound gains ",
            ctx.num(f"{c}.limit_gains.0.objective_percent_per_percent", unit="%"),
            " of the objective.",
        ]
    return Paragraph(parts)


def _margin_change(ctx: Context) -> list[Inline]:
    """``; the worst-case margin goes from 1.2 mN·m to 2.3 mN·m.`` (or stays; or, where the
    design as entered does not touch every wall, that it has none)."""
    e, o = "evaluate", "optimize"
    entered = ctx.value(f"{e}.margin_Nm")  # None / NaN: no contact, no margin
    if not (isinstance(entered, (int, float)) and entered == entered):
        return [
            "; as entered the spiral does not touch every wall (no margin), the proposed "
            "design's worst-case margin is ",
            ctx.num(f"{o}.margin_Nm", 1e3, "mN·m"),
            ".",
        ]
    end = (
        "."
        if ctx.value(f"{o}.margin_Nm") >= entered
        else (" (the optimum trades margin for its objective).")
    )
    if _same(ctx, f"{e}.margin_Nm", f"{o}.margin_Nm", 1e3):
        return ["; the worst-case margin stays ", ctx.num(f"{o}.margin_Nm", 1e3, "mN·m"), end]
    return [
        "; the worst-case margin goes from ",
        ctx.num(f"{e}.margin_Nm", 1e3, "mN·m"),
        " to ",
        ctx.num(f"{o}.margin_Nm", 1e3, "mN·m"),
        end,
    ]


def bom_brief(ctx: Context) -> Table:
    """The bill of materials in brief: per pair, what the workshop winds and what its amplifier
    delivers at the operating point (the full table is in the coil section)."""
    b = "coils.bill_of_materials"
    rows: list[list[Cell]] = []
    for i, row in enumerate(ctx.value(b)):
        p = f"{b}.{i}"
        rows.append(
            [
                f"{row['axis']} pair",
                ctx.num(f"{p}.turns"),
                ctx.num(f"{p}.wire_diameter_mm"),
                ctx.num(f"{p}.copper_mass_kg"),
                ctx.num(f"{p}.operating.current_amplitude_A"),
                ctx.num(f"{p}.operating.voltage_amplitude_V"),
                ctx.num(f"{p}.operating.apparent_power_VA"),
            ]
        )
    return Table(
        [
            "pair",
            "turns per coil",
            "wire (mm)",
            "copper (kg)",
            "current (A)",
            "voltage (V)",
            "apparent power (VA)",
        ],
        rows,
        caption="Bill of materials in brief, the design as entered: two coils in series per "
        "pair; current and voltage amplitudes and the apparent power each pair's amplifier "
        "delivers at the operating point (the full bill of materials is in section Coil "
        "sizing)",
        id="bom-brief",
    )


def sized_hardware_changes(ctx: Context) -> list[str]:
    """The freed hardware keys the optimiser sized, as entered and as sized (buildable):
    ``["coils.x.turns 400 → 680", ...]``; empty when no hardware key is freed."""
    hardware = ctx.value("optimize").get("hardware")
    if not hardware:
        return []
    out = []
    for key, new in hardware["discrete"].items():
        old = ctx.data.design.get(key)
        was = f"{old:.6g}" if isinstance(old, (int, float)) else "unset"
        if was == f"{new:.6g}":  # sized to what it was: not a change
            continue
        out.append(f"{key} {was} → {new:.6g}")
    return out


def _as_entered(ctx: Context) -> Paragraph:
    e = "evaluate"
    failed = [c["name"] for c in ctx.value(f"{e}.checks") if not c["ok"]]
    parts: list[Any] = [
        Strong("As entered."),
        " The design as entered (helical angle ",
        ctx.num(f"{e}.helical_angle_deg", unit="°"),
        ", ",
        ctx.num(f"{e}.frequency_hz", unit="Hz"),
        *_margin_words(ctx, e),
        " and moves at ",
        ctx.num(f"{e}.speed_m_s", 1e3, "mm/s"),
        "; ",
    ]
    if failed:
        parts.append("it does NOT meet: " + ", ".join(readable(n) for n in failed) + ".")
    else:
        parts.append("it meets every requirement and limit.")
    return Paragraph(parts, kind="alert" if failed else "ok")


def _margin_words(ctx: Context, e: str) -> list[Any]:
    """``) has a margin of 2.3 mN·m (safety factor 3.6)``, or that it has none: the spiral does
    not touch every wall (no contact), or the strain is below the minimum (extrapolated)."""
    grip = ctx.value(e).get("grip", "ok")
    if grip == "none":
        return [") has no margin: the spiral does not touch every wall (no contact),"]
    out: list[Any] = [
        ") has a margin of ",
        ctx.num(f"{e}.margin_Nm", 1e3, "mN·m"),
        " (safety factor ",
        ctx.num(f"{e}.safety_factor"),
        ")",
    ]
    if grip == "below minimum":
        out.append(", with a wall strain below requirements.min_wall_strain (extrapolated),")
    return out


def _without_status(message: str) -> str:
    """``infeasible: no design ...`` -> ``no design ...`` (the status is said already)."""
    head, sep, rest = message.partition(": ")
    return rest if sep and head in ("infeasible", "optimal") else message
