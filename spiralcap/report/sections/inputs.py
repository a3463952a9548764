"""Section 2: every design key with its value, unit, meaning and the values it allows."""

from __future__ import annotations

from typing import Any

from spiralcap.report.document import Paragraph, Ref, Section, Table
from spiralcap.report.numbers import fmt, unit_of_key
from spiralcap.report.sections._util import Context
from spiralcap.schema import KEYS


def show_value(value: Any) -> str:
    """A design value as given: numbers exactly (4 significant figures when that is exact);
    a matrix (``tissue.fit.covariance_log``) to 4 significant figures, so 25 numbers of 17
    digits do not take a table's width (the exact values: the design file under
    Reproducibility and the embedded JSON)."""
    if value is None:
        return "unset"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        if isinstance(value, list):
            if value and all(isinstance(r, list) for r in value):
                return "[" + ", ".join("[" + ", ".join(map(fmt, r)) + "]" for r in value) + "]"
            return "[" + ", ".join(show_value(v) for v in value) + "]"
        return str(value)
    short = fmt(value)
    try:
        exact = float(short) == float(value)
    except ValueError:
        exact = False
    return short if exact else repr(value)


def _rows(design: Any) -> tuple[list[list[str]], list[list[str]]]:
    """(rows of the keys that differ from the defaults, rows of every key)."""
    rows, changed_rows = [], []
    for key, spec in KEYS.items():
        value = design.get(key)
        default = spec.default
        if value is None:
            state = "unset"
        elif value == default:
            state = "default"
        else:
            state = "CHANGED"
        row = [
            key,
            show_value(value),
            unit_of_key(key) or "–",
            state,
            f"{spec.help}. Allowed: {spec.allowed}.",
        ]
        rows.append(row)
        if state == "CHANGED":
            changed_rows.append([key, show_value(value), show_value(default), row[2], spec.help])
    return changed_rows, rows


def build(ctx: Context) -> Section:
    """The design-inputs section: the keys that differ from the defaults, first."""
    design = ctx.data.design
    changed_rows, _ = _rows(design)
    n = len(changed_rows)
    intro = Paragraph(
        [
            f"Design source: {design.source}. ",
            f"{n} {'key differs' if n == 1 else 'keys differ'} from the built-in defaults"
            + (" (below); " if n else "; ")
            + "every key of the design schema, with its meaning and the values it allows, is "
            "listed in ",
            Ref("inputs-table"),
            " (appendix). Optional keys left unset take their value from elsewhere: the tissue "
            "preset for tissue.*, the coil radius (Helmholtz spacing) for coils.*.separation_m, "
            "the magnet grade for capsule.magnet.remanence_T.",
        ]
    )
    blocks: list[Any] = [intro]
    if changed_rows:
        blocks.append(
            Table(
                ["key", "value", "default", "unit", "meaning"],
                changed_rows,
                caption="Design inputs that differ from the built-in defaults",
                wrap=4,
                id="inputs-changed",
            )
        )
    return Section("inputs", "Design inputs", blocks)


def build_appendix(ctx: Context) -> Section:
    """Appendix: every design key with its value, unit, state, meaning and allowed values."""
    _, rows = _rows(ctx.data.design)
    set_rows = [r for r in rows if r[3] != "unset"]
    table = Table(
        ["key", "value", "unit", "state", "meaning and allowed values"],
        rows,
        caption="All design inputs (CHANGED: differs from the built-in default). The PDF lists "
        f"the {len(set_rows)} keys that have a value; the HTML report lists all {len(rows)}, "
        "the unset optional ones included",
        wrap=4,
        id="inputs-table",
        compact=True,  # ~100 keys: small type in the PDF keeps the document short
        pdf_rows=set_rows,
    )
    return Section("all-inputs", "Appendix: all design inputs", [table])
