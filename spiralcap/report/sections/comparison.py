"""Optional section: this design beside a second one (``spiralcap report A --compare B``)."""

from __future__ import annotations

import math
from typing import Any

from spiralcap.report.document import Cell, Paragraph, Section, Strong, Table
from spiralcap.report.numbers import Num
from spiralcap.report.sections._util import Context
from spiralcap.report.sections.inputs import show_value


def _rows(rows: Any) -> list[list[Cell]]:
    out: list[list[Cell]] = []
    for r in rows:
        cells: list[Cell] = [("▸ " if r.differs else "") + r.quantity, r.unit or "–"]
        vals = r.shown_values()
        for v in vals:
            if v is None:
                cells.append("–")
            elif isinstance(v, bool):
                cells.append("yes" if v else "NO")
            elif isinstance(v, float):
                cells.append(Num(v))
            else:
                cells.append(str(v).replace("_", " "))
        if r.differs and all(isinstance(v, float) and math.isfinite(v) for v in vals):
            cells.append(Num(vals[1] - vals[0]))
        else:
            cells.append("")
        out.append(cells)
    return out


def build(ctx: Context) -> Section | None:
    """The comparison section, or None when the report compares nothing."""
    c = ctx.data.comparison
    if c is None:
        return None
    a, b = c.labels
    keys = Table(
        ["design key", a, b],
        [[k.key, *[show_value(v) for v in k.values]] for k in c.changed_keys] or [["none", "", ""]],
        caption=f"Design keys that differ between {a} and {b}",
        wrap=0,
        id="compare-keys",
    )
    heads = ["quantity", "unit", a, b, "difference"]
    ev = Table(
        heads,
        _rows(c.evaluated),
        caption="Both designs at their operating points as entered (▸: the values differ)",
        wrap=0,
        id="compare-evaluated",
    )
    opt = Table(
        heads,
        _rows(c.optimised),
        caption="Both designs optimised (▸: the values differ)",
        wrap=0,
        id="compare-optimised",
    )
    ma, mb = (r.margin_Nm * 1e3 for r in c.optimizations)
    intro = Paragraph(
        [
            Strong("Compared with "),
            f"{c.sources[1]}: ",
            f"{len(c.changed_keys)} design key(s) differ. Optimised, the margin is ",
            Num(ma, unit="mN·m"),
            f" for {a} and ",
            Num(mb, unit="mN·m"),
            f" for {b} (difference ",
            Num(mb - ma, unit="mN·m"),
            "). Both are evaluated and optimised by the same functions as the rest of this "
            "report (`spiralcap compare` prints the same tables).",
        ]
    )
    return Section("comparison", "Comparison with a second design", [intro, keys, ev, opt])
