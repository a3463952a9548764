"""Render a report document as one self-contained HTML file.

Everything the page needs is inside it: CSS in a ``<style>`` element, figures as base64 PNG
``data:`` URIs, the numbers as JSON in ``<script type="application/json" id="spiralcap-data">``.
No script runs and nothing is fetched, so the file opens offline and reads the same in print.
"""

from __future__ import annotations

import base64
import html
import io
import json
from collections.abc import Mapping, Sequence
from typing import Any

from spiralcap.report.document import (
    Bullets,
    Cell,
    Code,
    FigureBlock,
    Inline,
    Link,
    Paragraph,
    Section,
    Strong,
    Table,
)
from spiralcap.report.numbers import Num, fmt, unit_gap

#: Resolution of the embedded PNG figures, dots per inch (sharp on screen and in print).
PNG_DPI = 150

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
         text-align: left; }
th { background: var(--shade); border-bottom: 2px solid var(--ink); }
td.n { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
.num { font-variant-numeric: tabular-nums; }
code, pre { font-family: "DejaVu Sans Mono", Consolas, monospace; font-size: 0.85rem; }
pre { background: var(--shade); padding: 0.7rem; overflow-x: auto; border-left: 3px solid
      var(--rule); }
figure { margin: 1rem 0 1.4rem; page-break-inside: avoid; }
figure img { width: 100%; max-width: 100%; height: auto; display: block;
             border: 1px solid var(--rule); }
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


def _inline(parts: Sequence[Inline]) -> str:
    out = []
    for p in parts:
        if isinstance(p, Num):
            out.append(_num(p))
        elif isinstance(p, Link):
            out.append(f'<a href="#{html.escape(p.anchor)}">{html.escape(p.text)}</a>')
        elif isinstance(p, Strong):
            out.append(f"<strong>{html.escape(p.text)}</strong>")
        else:
            out.append(html.escape(str(p)))
    return "".join(out)


def _num(n: Num) -> str:
    attrs = ""
    if n.key is not None:
        attrs = f' data-key="{html.escape(n.key)}" data-scale="{n.scale!r}"'
    unit = ("\u00a0" if unit_gap(n.unit) else "") + html.escape(n.unit)
    return f'<span class="num"{attrs}>{html.escape(n.text)}</span>{unit}'


def _cell(cell: Cell) -> tuple[str, bool]:
    if isinstance(cell, Num):
        return _num(cell), True
    if cell is None:
        return "", False
    numeric = isinstance(cell, (int, float)) and not isinstance(cell, bool)
    return html.escape(fmt(cell)), numeric


def _table(t: Table) -> str:
    rows = []
    for row in t.rows:
        cells = []
        for c in row:
            text, numeric = _cell(c)
            cells.append(f'<td class="n">{text}</td>' if numeric else f"<td>{text}</td>")
        rows.append("<tr>" + "".join(cells) + "</tr>")
    ident = f' id="{html.escape(t.id)}"' if t.id else ""
    cap = f"<caption>{html.escape(t.caption)}</caption>" if t.caption else ""
    head = "".join(f"<th>{html.escape(h)}</th>" for h in t.headers)
    return (
        f"<table{ident}>{cap}<thead><tr>{head}</tr></thead><tbody>"
        + "\n".join(rows)
        + "</tbody></table>"
    )


def figure_png(block: FigureBlock, dpi: int = PNG_DPI) -> bytes:
    """Draw a figure block on a fresh Agg figure and return the PNG bytes."""
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from spiralcap.figures.style import REPORT_RC

    with matplotlib.rc_context(REPORT_RC):
        fig = Figure(figsize=block.size_in, layout="constrained")
        FigureCanvasAgg(fig)
        block.draw(fig)
        buf = io.BytesIO()
        fig.savefig(
            buf,
            format="png",
            dpi=dpi,
            facecolor="white",
            metadata={"Software": "spiralcap (matplotlib)"},
        )
    return buf.getvalue()


def _figure(block: FigureBlock, number: int) -> str:
    data = base64.b64encode(figure_png(block)).decode("ascii")
    cap = html.escape(block.caption)
    alt = html.escape(block.caption.split(". ")[0])
    return (
        f'<figure id="{html.escape(block.id)}"><img alt="{alt}" '
        f'src="data:image/png;base64,{data}">'
        f"<figcaption><strong>Figure {number}.</strong> {cap}</figcaption></figure>"
    )


def _block(block: Any, counter: list[int]) -> str:
    if isinstance(block, Paragraph):
        cls = f' class="callout {block.kind}"' if block.kind else ""
        return f"<p{cls}>{_inline(block.parts)}</p>"
    if isinstance(block, Bullets):
        return "<ul>" + "".join(f"<li>{_inline(i)}</li>" for i in block.items) + "</ul>"
    if isinstance(block, Table):
        return _table(block)
    if isinstance(block, Code):
        cap = f"<figcaption>{html.escape(block.caption)}</figcaption>" if block.caption else ""
        return f"<figure><pre>{html.escape(block.text)}</pre>{cap}</figure>"
    if isinstance(block, FigureBlock):
        counter[0] += 1
        return _figure(block, counter[0])
    raise TypeError(f"unknown report block {type(block).__name__}")


def _json_script(data: Mapping[str, Any]) -> str:
    text = json.dumps(data, indent=1, ensure_ascii=False, allow_nan=False)
    text = text.replace("</", "<\\/")  # a JSON string can never close the script element
    return f'<script type="application/json" id="spiralcap-data">\n{text}\n</script>'


def render_html(
    title: str,
    subtitle: str,
    sections: Sequence[Section],
    data: Mapping[str, Any],
    footer: str = "",
) -> str:
    """The whole report as one HTML document (a string).

    Parameters
    ----------
    title, subtitle : str
        Page heading and the line under it.
    sections : sequence of Section
        Rendered in order, numbered, with a table of contents.
    data : Mapping
        JSON-ready numbers embedded in ``<script type="application/json" id="spiralcap-data">``
        (NaN and infinities must already be converted; see
        :func:`spiralcap.commands._common._jsonable`).
    footer : str
        Plain text for the page foot.
    """
    counter = [0]
    toc = "".join(
        f'<li><a href="#{html.escape(s.id)}">{html.escape(s.title)}</a></li>' for s in sections
    )
    body = []
    for i, s in enumerate(sections, 1):
        inner = "\n".join(_block(b, counter) for b in s.blocks)
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
            f'<header><h1>{html.escape(title)}</h1><p class="subtitle">{html.escape(subtitle)}</p>'
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
