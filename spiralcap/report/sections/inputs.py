"""Section 2: every design key with its value, unit, meaning and the values it allows."""

from __future__ import annotations

from typing import Any

from spiralcap.report.document import Paragraph, Section, Table
from spiralcap.report.numbers import fmt, unit_of_key
from spiralcap.report.sections._util import Context
from spiralcap.schema import KEYS


def show_value(value: Any) -> str:
    """A design value as given: numbers exactly (4 significant figures when that is exact)."""
    if value is None:
        return "unset"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        if isinstance(value, list):
            return "[" + ", ".join(show_value(v) for v in value) + "]"
        return str(value)
    short = fmt(value)
    try:
        exact = float(short) == float(value)
    except ValueError:
        exact = False
    return short if exact else repr(value)


def build(ctx: Context) -> Section:
    """The design-inputs section."""
    design = ctx.data.design
    rows = []
    changed = 0
    for key, spec in KEYS.items():
        value = design.get(key)
        default = spec.default
        if value is None:
            state = "unset"
        elif value == default:
            state = "default"
        else:
            state = "CHANGED"
            changed += 1
        rows.append(
            [
                key,
                show_value(value),
                unit_of_key(key) or "–",
                state,
                f"{spec.help}. Allowed: {spec.allowed}.",
            ]
        )
    intro = Paragraph(
        [
            f"Design source: {design.source}. Every key of the design schema is listed, in the "
            f"units its name carries; {changed} "
            f"{'differs' if changed == 1 else 'differ'} from the built-in defaults (marked "
            "CHANGED). Optional keys left unset take their value from elsewhere: the tissue preset "
            "for tissue.*, the coil radius (Helmholtz spacing) for coils.*.separation_m, the magnet "
            "grade for capsule.magnet.remanence_T."
        ]
    )
    table = Table(
        ["key", "value", "unit", "state", "meaning and allowed values"],
        rows,
        caption="Design inputs",
        wrap=4,
        id="inputs-table",
    )
    return Section("inputs", "Design inputs", [intro, table])
