"""Render a report document as a typeset PDF with Typst (the ``typst`` pip package).

Why Typst rather than ReportLab's Platypus: Typst typesets mathematics natively (the model's
equations), embeds SVG figures as vector graphics, repeats table headers across page breaks,
numbers figures and tables and resolves references (``@fig-x`` -> "Figure 3") and builds the
contents list with page numbers itself; it ships its own fonts (Libertinus Serif, New Computer
Modern Math, DejaVu Sans Mono), so the output is the same on every machine, and it compiles a
report in a few hundred milliseconds. Platypus would need a second library for SVG and has no
mathematics.

The document is written as Typst markup from the same :mod:`~spiralcap.report.document` blocks
the HTML renders; all text goes in as Typst string literals (``#"..."``), so nothing in a design
file or a message can be read as markup. Figures are the SVG texts drawn once for both outputs
(:mod:`spiralcap.report.render`), handed over through ``sys.inputs``.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import Any, cast

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
    cell_text,
    column_units,
    header_with_unit,
)
from spiralcap.report.numbers import Num, unit_gap

#: Text width of the page (A4, 2 cm side margins), inches.
TEXT_WIDTH_IN = (210.0 - 40.0) / 25.4
_CALLOUT = {"alert": "rgb(164, 22, 26)", "ok": "rgb(27, 110, 58)", "note": "rgb(35, 78, 128)"}

_PREAMBLE = r"""
#set document(title: TITLE, author: AUTHOR)
#set text(font: "Libertinus Serif", size: 10.5pt, lang: "en")
#set par(justify: true, leading: 0.58em, spacing: 0.9em)
#show raw: set text(font: "DejaVu Sans Mono", size: 7.2pt)
#show math.equation: set text(font: "New Computer Modern Math")
#set heading(numbering: "1.")
#show heading.where(level: 1): it => block(above: 1.3em, below: 0.7em, text(size: 14pt, it))
#set page(
  paper: "a4",
  margin: (x: 2cm, top: 2.2cm, bottom: 2cm),
  header: context {
    if counter(page).get().first() > 1 {
      set text(size: 8pt, fill: luma(90))
      [#TITLE #h(1fr) #HEADER_RIGHT]
      v(-0.6em)
      line(length: 100%, stroke: 0.4pt + luma(150))
    }
  },
  footer: context {
    set text(size: 8pt, fill: luma(90))
    [#FOOTER #h(1fr) page #counter(page).display() of #counter(page).final().first()]
  },
)
#set table(
  stroke: (x, y) => if y == 0 { (bottom: 0.8pt) } else { (bottom: 0.3pt + luma(200)) },
  inset: (x: 4pt, y: 3pt),
)
#show table: set text(size: 8.5pt)
#show table: set par(justify: false)
#show figure.where(kind: table): set figure.caption(position: top)
#show figure.where(kind: table): set block(breakable: true)
#show figure.caption: set text(size: 9pt)
#show figure.caption: set par(justify: false)
#show figure.caption: set align(left)
#set figure(gap: 0.5em)
#show link: set text(fill: rgb(35, 78, 128))
#show ref: set text(fill: rgb(35, 78, 128))
"""


def s(text: str) -> str:
    """``text`` as a Typst string expression in markup (nothing in it is read as markup)."""
    esc = text.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n").replace("\r", "")
    return f'#"{esc}"'


def _lit(text: str) -> str:
    """``text`` as a Typst string literal in code (no leading ``#``)."""
    return s(text)[1:]


def _label(anchor: str) -> str:
    return re.sub(r"[^A-Za-z0-9_:.-]", "-", anchor)


def _num(n: Num) -> str:
    unit = unit_gap(n.unit).replace(" ", "\u00a0") + n.unit
    return s(n.text + unit)


def _inline(parts: Sequence[Inline], known: frozenset[str] = frozenset()) -> str:
    """Inline content as markup; a link or reference to an anchor not in ``known`` (when given)
    is written as its text, so a missing target never stops the typesetting."""
    out = []
    for p in parts:
        if isinstance(p, (Link, Ref)) and known and p.anchor not in known:
            out.append(s(p.text if isinstance(p, Link) else p.anchor))
            continue
        if isinstance(p, Num):
            out.append(_num(p))
        elif isinstance(p, Strong):
            out.append(f"#strong({_lit(p.text)})")
        elif isinstance(p, Link):
            out.append(f"#link(<{_label(p.anchor)}>)[{s(p.text)}]")
        elif isinstance(p, Ref):
            out.append(f"#ref(<{_label(p.anchor)}>)")
        else:
            out.append(s(str(p)))
    return "".join(out)


def _is_numeric(cell: Cell) -> bool:
    return isinstance(cell, Num) or (isinstance(cell, (int, float)) and not isinstance(cell, bool))


def _cell(cell: Cell, shared_unit: str) -> str:
    if isinstance(cell, Num):
        if shared_unit or not cell.unit:
            return "[" + s(cell.text) + "]"
        return "[" + _num(cell) + "]"
    return "[" + s(cell_text(cell)) + "]"


def _table(t: Table) -> str:
    ncol = len(t.headers)
    numeric = []
    for i in range(ncol):
        cells = [r[i] for r in t.rows if i < len(r) and r[i] not in (None, "")]
        numeric.append(bool(cells) and sum(map(_is_numeric, cells)) >= 0.5 * len(cells))
    cols = ", ".join("1fr" if i == t.wrap else "auto" for i in range(ncol))
    align = ", ".join("right" if n else "left" for n in numeric)
    units = column_units(t)
    head = ", ".join(
        f"[*{s(header_with_unit(h, u))}*]" for h, u in zip(t.headers, units, strict=True)
    )
    body = []
    for row in t.rows if t.pdf_rows is None else t.pdf_rows:
        body.append(", ".join(_cell(c, u) for c, u in zip(row, units, strict=False)))
    inset = "inset: (x: 3pt, y: 2pt), " if t.compact else ""
    table = (
        f"table(columns: ({cols},), {inset}align: ({align},), table.header({head}),\n"
        + ",\n".join(body)
        + ")"
    )
    if t.compact:  # small type and tight cells; the caption keeps the document's size
        table = f"[#set text(size: 6.5pt); #set par(leading: 0.4em); #{table}]"
    if not t.caption:
        return f"#{table}\n"
    label = f" <{_label(t.id)}>" if t.id else ""
    return f"#figure({table}, caption: [{s(t.caption)}], kind: table){label}\n"


def _figure(block: FigureBlock, key: str) -> str:
    width = min(block.size_in[0], TEXT_WIDTH_IN)
    return (
        f'#figure(image(bytes(sys.inputs.at("{key}")), format: "svg", width: {width:.3f}in), '
        f"caption: [{s(block.caption)}]) <{_label(block.id)}>\n"
    )


def _block(
    block: Any, figures: dict[str, str], svgs: Mapping[str, str], known: frozenset[str]
) -> str:
    if isinstance(block, Paragraph):
        text = _inline(block.parts, known)
        if block.kind:
            colour = _CALLOUT.get(block.kind, _CALLOUT["note"])
            return (
                f"#block(width: 100%, inset: (x: 8pt, y: 6pt), fill: luma(244), "
                f"stroke: (left: 3pt + {colour}))[{text}]\n"
            )
        return text + "\n"
    if isinstance(block, Bullets):
        items = ", ".join(f"[{_inline(i, known)}]" for i in block.items)
        return f"#list({items})\n"
    if isinstance(block, Table):
        return _table(block)
    if isinstance(block, Code):
        cap = f"\n#text(size: 9pt)[{s(block.caption)}]" if block.caption else ""
        return (
            f'#columns(2, gutter: 12pt, raw({_lit(block.text)}, block: true, lang: "toml")){cap}\n'
        )
    if isinstance(block, Equation):
        label = (
            f"#h(1fr) #text(size: 8.5pt, fill: luma(90))[{s(block.label)}]" if block.label else ""
        )
        return f"#block(width: 100%)[#h(1.2em) $ {block.typst} $ {label}]\n"
    if isinstance(block, FigureBlock):
        key = f"fig{len(figures)}"
        figures[key] = svgs[block.id]
        return _figure(block, key)
    raise TypeError(f"unknown report block {type(block).__name__}")


def typst_source(
    front: FrontMatter,
    sections: Sequence[Section],
    footer: str,
    svgs: Mapping[str, str],
) -> tuple[str, dict[str, str]]:
    """The Typst markup of the report and the figure inputs it reads (``sys.inputs``)."""
    figures: dict[str, str] = {}
    pre = (
        _PREAMBLE.replace("#HEADER_RIGHT", s(front.design_source))
        .replace("#TITLE", s(front.title))
        .replace("TITLE", _lit(front.title))
        .replace("AUTHOR", _lit(front.author or "spiralcap"))
        .replace("#FOOTER", s(footer))
    )
    out = [pre]
    rows = [
        ("Project", front.project),
        ("Author", front.author),
        ("Revision", front.revision),
        ("Date", front.date),
        ("Design", f"{front.design_source}"),
        ("Design SHA-256", front.design_sha256),
        ("Made with", f"spiralcap {front.version}"),
    ]
    grid = ", ".join(f"[*{s(k)}*], [{s(v)}]" for k, v in rows if v)
    out.append(
        f'#block(below: 1.2em)[#text(size: 20pt, weight: "bold")[{s(front.title)}]]\n'
        f"#grid(columns: (auto, 1fr), column-gutter: 1.2em, row-gutter: 0.5em, {grid})\n"
        "#v(0.8em)\n#outline(title: [Contents], depth: 1, indent: auto)\n"
    )
    from spiralcap.report.document import numbering

    known = frozenset(numbering(sections)) | {sec.id for sec in sections}
    for sec in sections:
        out.append(f"\n= {s(sec.title)} <{_label(sec.id)}>\n")
        for block in sec.blocks:
            out.append(_block(block, figures, svgs, known))
    return "\n".join(out), figures


def render_pdf(
    front: FrontMatter,
    sections: Sequence[Section],
    footer: str,
    svgs: Mapping[str, str],
) -> tuple[bytes, int]:
    """The report as PDF bytes and its page count.

    Parameters
    ----------
    front : FrontMatter
        Title page: title, project, author, revision, date, design.
    sections : sequence of Section
        The same sections the HTML shows.
    footer : str
        Text at the foot of every page (followed by the page number).
    svgs : mapping id -> SVG text
        Every figure, drawn once (:func:`spiralcap.report.render.render_figures`).
    """
    import typst

    from spiralcap.report.render import matplotlib_font_dir

    source, figures = typst_source(front, sections, footer, svgs)
    pdf = typst.compile(
        source.encode("utf-8"),
        format="pdf",
        sys_inputs=figures,
        font_paths=cast(Any, [matplotlib_font_dir()]),  # the figures' text: DejaVu, as drawn
        ignore_system_fonts=True,
        timestamp=0,
    )
    assert isinstance(pdf, bytes)
    return pdf, page_count(pdf)


def page_count(pdf: bytes) -> int:
    """Pages of a PDF Typst wrote (its page tree's ``/Count``)."""
    counts = [int(m) for m in re.findall(rb"/Type\s*/Pages\b[^>]*?/Count\s+(\d+)", pdf)]
    counts += [int(m) for m in re.findall(rb"/Count\s+(\d+)[^>]*?/Type\s*/Pages\b", pdf)]
    if counts:
        return max(counts)
    return len(re.findall(rb"/Type\s*/Page\b", pdf))
