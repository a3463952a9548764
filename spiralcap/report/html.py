"""Render a report document as one self-contained HTML file.

Everything the page needs is inside it: CSS in a ``<style>`` element, figures as base64 SVG
``data:`` URIs (vector, drawn once by :mod:`spiralcap.report.render`), the numbers as JSON in ``<script type="application/json" id="spiralcap-data">``.
No script runs and nothing is fetched, so the file opens offline and reads the same in print.
"""

from __future__ import annotations

import base64
import html
import json
from collections.abc import Mapping, Sequence
from typing import Any

from spiralcap.report.document import (
    Bullets,
    Cell,
    Code,
    Equation,
    FigureBlock,
    FrontMatter,
    Inline,
    Link,
    Paragraph,
    Ref,
    Section,
    Strong,
    Table,
    column_units,
    header_with_unit,
)
from spiralcap.report.numbers import Num, fmt, unit_gap

_CSS = """
:root { --ink: #1a1a1a; --muted: #555; --rule: #c8c8c8; --ok: #1b6e3a; --alert: #a4161a;
        --note: #234e80; --shade: #f3f4f6; }
* { box-sizing: border-box; }
body { font-family: "DejaVu Sans", "Segoe UI", Helvetica, Arial, sans-serif; color: var(--ink);
       margin: 0 auto; max-width: 62rem; padding: 1.5rem 2rem 4rem; line-height: 1.45;
       font-size: 15px; background: #fff; }
h1 { font-size: 1.7rem; margin: 0 0 0.2rem; }
h2 { font-size: 1.3rem; margin: 2.2rem 0 0.6rem; padding-bottom: 0.2rem;
     border-bottom: 2px solid var(--ink); }
.subtitle { color: var(--muted); margin: 0 0 1rem; }
nav.toc { background: var(--shade); padding: 0.6rem 1rem; border-radius: 4px; }
nav.toc ol { margin: 0.2rem 0; padding-left: 1.4rem; columns: 2; }
nav.toc a { color: var(--note); text-decoration: none; }
table { border-collapse: collapse; margin: 0.6rem 0 1rem; width: 100%; font-size: 0.9rem; }
caption { caption-side: top; text-align: left; font-weight: bold; padding: 0.2rem 0; }
th, td { border-bottom: 1px solid var(--rule); padding: 0.25rem 0.5rem; vertical-align: top;
         text-align: left; overflow-wrap: break-word; }
td:first-child { overflow-wrap: anywhere; }
#inputs-table td:first-child, #inputs-changed td:first-child { width: 17rem; }
@media (max-width: 900px) {
  #inputs-table td:first-child, #inputs-changed td:first-child { width: auto; }
}
th.n { text-align: right; }
#bom-table { font-size: 0.8rem; } /* 13 columns: fits a 820 px window */
#bom-table th, #bom-table td { padding: 0.25rem 0.3rem; }
/* 6 columns with long design keys and gains per step: fits a 820 px window */
#binding-limits { font-size: 0.8rem; }
#binding-limits th, #binding-limits td { padding: 0.25rem 0.3rem; }
#binding-limits td:last-child { white-space: normal; } /* the gain wraps before "per" */
th { background: var(--shade); border-bottom: 2px solid var(--ink); }
td.n { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
.num { font-variant-numeric: tabular-nums; }
code, pre { font-family: "DejaVu Sans Mono", Consolas, monospace; font-size: 0.85rem; }
pre { background: var(--shade); padding: 0.7rem; overflow-x: auto; border-left: 3px solid
      var(--rule); }
figure { margin: 1rem 0 1.4rem; page-break-inside: avoid; }
figure img { max-width: 100%; height: auto; display: block; margin: 0 auto;
             border: 1px solid var(--rule); }
.eq { margin: 0.6rem 0 0.8rem 1.5rem; font-family: "DejaVu Serif", "Cambria Math", serif;
      font-size: 1.05rem; display: flex; justify-content: space-between; gap: 1rem; }
.eq .src { color: var(--muted); font-family: inherit; font-size: 0.85rem; }
dl.front { display: grid; grid-template-columns: max-content 1fr; gap: 0.1rem 1rem;
           margin: 0.4rem 0 1rem; }
dl.front dt { font-weight: bold; } dl.front dd { margin: 0; }
figcaption { font-size: 0.9rem; color: var(--muted); margin-top: 0.3rem; }
.callout { padding: 0.6rem 0.9rem; border-left: 5px solid var(--note); background: var(--shade);
           margin: 0.8rem 0; }
.callout.ok { border-left-color: var(--ok); }
.callout.alert { border-left-color: var(--alert); background: #fdecec; }
.summary p { font-size: 1.12rem; margin: 0.25rem 0; }
.summary .label { display: inline-block; min-width: 8.5rem; font-weight: bold; }
footer { margin-top: 3rem; color: var(--muted); font-size: 0.85rem; border-top: 1px solid
         var(--rule); padding-top: 0.5rem; }
@media print {
  body { max-width: none; padding: 0; font-size: 11pt; }
  nav.toc { display: none; }
  h2 { page-break-after: avoid; }
  table, pre { page-break-inside: avoid; }
}
"""


def _inline(parts: Sequence[Inline], numbers: Mapping[str, str] | None = None) -> str:
    out = []
    for p in parts:
        if isinstance(p, Ref):
            text = (numbers or {}).get(p.anchor, p.anchor)
            out.append(f'<a href="#{html.escape(p.anchor)}">{html.escape(text)}</a>')
            continue
        if isinstance(p, Num):
            out.append(_num(p))
        elif isinstance(p, Link):
            out.append(f'<a href="#{html.escape(p.anchor)}">{html.escape(p.text)}</a>')
        elif isinstance(p, Strong):
            out.append(f"<strong>{html.escape(p.text)}</strong>")
        else:
            out.append(html.escape(str(p)))
    return "".join(out)


def _num(n: Num, with_unit: bool = True) -> str:
    attrs = ""
    if n.key is not None:
        attrs = f' data-key="{html.escape(n.key)}" data-scale="{n.scale!r}"'
    unit = ("\u00a0" if unit_gap(n.unit) else "") + html.escape(n.unit_shown) if with_unit else ""
    return f'<span class="num"{attrs}>{html.escape(n.text)}</span>{unit}'


def _cell(cell: Cell, shared_unit: str = "") -> tuple[str, bool]:
    if isinstance(cell, Num):
        return _num(cell, with_unit=not shared_unit), True
    if cell is None:
        return "", False
    numeric = isinstance(cell, (int, float)) and not isinstance(cell, bool)
    return html.escape(fmt(cell)), numeric


def _table(t: Table, number: str = "") -> str:
    units = column_units(t)
    rows = []
    for row in t.rows:
        cells = []
        for c, u in zip(row, units, strict=False):
            text, numeric = _cell(c, u)
            cells.append(f'<td class="n">{text}</td>' if numeric else f"<td>{text}</td>")
        rows.append("<tr>" + "".join(cells) + "</tr>")
    ident = f' id="{html.escape(t.id)}"' if t.id else ""
    lead = f"{number}. " if number else ""
    cap = f"<caption>{lead}{html.escape(t.caption)}</caption>" if t.caption else ""
    numeric_cols = _numeric_columns(t)
    heads = [header_with_unit(h, u) for h, u in zip(t.headers, units, strict=True)]
    head = "".join(
        f'<th class="n">{html.escape(h)}</th>' if numeric_cols[i] else f"<th>{html.escape(h)}</th>"
        for i, h in enumerate(heads)
    )
    return (
        f"<table{ident}>{cap}<thead><tr>{head}</tr></thead><tbody>"
        + "\n".join(rows)
        + "</tbody></table>"
    )


def _numeric_columns(t: Table) -> list[bool]:
    """Columns whose body cells are mostly numbers (right-aligned, header too)."""
    out = []
    for i in range(len(t.headers)):
        cells = [r[i] for r in t.rows if i < len(r) and r[i] not in (None, "")]
        nums = sum(
            isinstance(c, Num) or (isinstance(c, (int, float)) and not isinstance(c, bool))
            for c in cells
        )
        out.append(bool(cells) and nums >= 0.5 * len(cells))
    return out


def _figure(block: FigureBlock, number: str, svg: str) -> str:
    data = base64.b64encode(svg.encode("utf-8")).decode("ascii")
    cap = html.escape(block.caption)
    alt = html.escape(block.caption.split(". ")[0])
    width = f"{block.size_in[0]:g}in"
    return (
        f'<figure id="{html.escape(block.id)}"><img alt="{alt}" style="width:{width}" '
        f'src="data:image/svg+xml;base64,{data}">'
        f"<figcaption><strong>{number}.</strong> {cap}</figcaption></figure>"
    )


def _block(block: Any, numbers: Mapping[str, str], figures: Mapping[str, str]) -> str:
    if isinstance(block, Paragraph):
        cls = f' class="callout {block.kind}"' if block.kind else ""
        return f"<p{cls}>{_inline(block.parts, numbers)}</p>"
    if isinstance(block, Bullets):
        return "<ul>" + "".join(f"<li>{_inline(i, numbers)}</li>" for i in block.items) + "</ul>"
    if isinstance(block, Table):
        return _table(block, numbers.get(block.id, ""))
    if isinstance(block, Code):
        cap = f"<figcaption>{html.escape(block.caption)}</figcaption>" if block.caption else ""
        return f"<figure><pre>{html.escape(block.text)}</pre>{cap}</figure>"
    if isinstance(block, Equation):
        src = f'<span class="src">{html.escape(block.label)}</span>' if block.label else ""
        return f'<div class="eq"><span>{html.escape(block.text)}</span>{src}</div>'
    if isinstance(block, FigureBlock):
        return _figure(block, numbers[block.id], figures[block.id])
    raise TypeError(f"unknown report block {type(block).__name__}")


def _front(front: FrontMatter) -> str:
    rows = [
        ("Project", front.project),
        ("Author", front.author),
        ("Revision", front.revision),
        ("Date", front.date),
        ("Design", f"{front.design_source} (SHA-256 {front.design_sha256[:16]}…)"),
        ("Made with", f"spiralcap {front.version}"),
    ]
    return (
        '<dl class="front">'
        + "".join(f"<dt>{html.escape(k)}</dt><dd>{html.escape(v)}</dd>" for k, v in rows if v)
        + "</dl>"
    )


def _json_script(data: Mapping[str, Any]) -> str:
    text = json.dumps(data, indent=1, ensure_ascii=False, allow_nan=False)
    # Inside <script> the HTML parser knows no character references; with <, > and & written as
    # JSON escapes no text can close the element, open a comment (<!--) or look like markup,
    # and the text still parses as the same JSON.
    for raw, esc in (("<", "\\u003c"), (">", "\\u003e"), ("&", "\\u0026")):
        text = text.replace(raw, esc)
    text = text.replace("\u2028", "\\u2028").replace("\u2029", "\\u2029")
    return f'<script type="application/json" id="spiralcap-data">\n{text}\n</script>'


def render_html(
    front: FrontMatter,
    sections: Sequence[Section],
    data: Mapping[str, Any],
    footer: str = "",
    figures: Mapping[str, str] | None = None,
) -> str:
    """The whole report as one HTML document (a string).

    Parameters
    ----------
    front : FrontMatter
        Title, project, author, revision, date and the design's identity.
    sections : sequence of Section
        Rendered in order, numbered, with a table of contents.
    data : Mapping
        JSON-ready numbers embedded in ``<script type="application/json" id="spiralcap-data">``
        (NaN and infinities must already be converted; see
        :func:`spiralcap.presentation.jsonable`).
    footer : str
        Plain text for the page foot.
    figures : mapping id -> SVG text, optional
        The figures already drawn (:func:`spiralcap.report.render.render_figures`); drawn here
        when not given.
    """
    from spiralcap.report.document import numbering

    if figures is None:
        from spiralcap.report.render import render_figures

        figures = render_figures(sections)
    numbers = numbering(sections)
    title = front.title
    toc = "".join(
        f'<li><a href="#{html.escape(s.id)}">{html.escape(s.title)}</a></li>' for s in sections
    )
    body = []
    for i, s in enumerate(sections, 1):
        inner = "\n".join(_block(b, numbers, figures) for b in s.blocks)
        cls = ' class="summary"' if s.id == "summary" else ""
        body.append(
            f'<section id="{html.escape(s.id)}"{cls}><h2>{i}. {html.escape(s.title)}'
            f"</h2>\n{inner}\n</section>"
        )
    return "\n".join(
        [
            "<!DOCTYPE html>",
            '<html lang="en">',
            "<head>",
            '<meta charset="utf-8">',
            '<meta name="viewport" content="width=device-width, initial-scale=1">',
            f"<title>{html.escape(title)}</title>",
            f"<style>{_CSS}</style>",
            "</head>",
            "<body>",
            f"<header><h1>{html.escape(title)}</h1>{_front(front)}"
            f'<nav class="toc"><strong>Contents</strong><ol>{toc}</ol></nav></header>',
            "<main>",
            *body,
            "</main>",
            f"<footer>{html.escape(footer)}</footer>",
            _json_script(data),
            "</body>",
            "</html>",
            "",
        ]
    )
