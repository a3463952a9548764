"""Render a report document as a typeset PDF with Typst (the ``typst`` pip package).

Why Typst rather than ReportLab's Platypus: Typst typesets mathematics natively (the model's
equations), embeds SVG figures as vector graphics, repeats table headers across page breaks,
numbers figures and tables and resolves references (``@fig-x`` -> "Figure 3") and builds the
contents list with page numbers itself; it ships its own fonts (Libertinus Serif, New Computer
Modern Math, DejaVu Sans Mono), so the output is the same on every machine, and it compiles a
report in a few hundred milliseconds. Platypus would need a second library for SVG and has no
mathematics.

The document is written as Typst markup from the same :mod:`~spiralcap.report.document` blocks
the HTML renders. No text is ever part of the Typst source: every string (titles, file names,
design values, messages) goes into one JSON array handed over through ``sys.inputs`` and the
markup refers to it by index (``#T.at(12);``), so nothing a design file or a file name holds can
be read as markup or code. Figures are the SVG texts drawn once for both outputs
(:mod:`spiralcap.report.render`), handed over the same way.
"""

from __future__ import annotations

import json
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
LONG_CELL_CHARS = 40
"""A text cell longer than this (a report title, a list of headings, a covariance matrix in
the appendix) would widen an ``auto`` column until the wrapping column has one word a line."""
_CALLOUT = {"alert": "rgb(164, 22, 26)", "ok": "rgb(27, 110, 58)", "note": "rgb(35, 78, 128)"}

_LOAD_TEXT = '#let T = json(bytes(sys.inputs.at("text")))'

#: The page setup; ``@name@`` are filled with expressions that read the text data (never text).
_PREAMBLE = r"""
#set document(title: @title@, author: @author@)
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
      [@title_markup@ #h(1fr) @header_right@]
      v(-0.6em)
      line(length: 100%, stroke: 0.4pt + luma(150))
    }
  },
  footer: context {
    set text(size: 8pt, fill: luma(90))
    [@footer@ #h(1fr) page #counter(page).display() of #counter(page).final().first()]
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


def _column_widths(t: Table, numeric: Sequence[bool]) -> list[str]:
    """Typst column widths: the wrapping column ``1fr``, the rest ``auto``; a text column with
    a cell longer than :data:`LONG_CELL_CHARS` wraps too (``1fr``, the wrapping column ``2fr``),
    so one long value cannot squeeze the others to a word a line."""
    long = [
        i != t.wrap
        and not numeric[i]
        and any(
            len(cell_text(r[i])) > LONG_CELL_CHARS
            for r in (t.rows if t.pdf_rows is None else t.pdf_rows)
            if i < len(r) and not isinstance(r[i], Num)
        )
        for i in range(len(t.headers))
    ]
    wrap_width = "2fr" if any(long) else "1fr"
    return [wrap_width if i == t.wrap else "1fr" if long[i] else "auto" for i in range(len(long))]


class _Text:
    """The report's text, collected as data: ``s(text)`` is an index into a JSON array handed to
    Typst through ``sys.inputs`` (read back with ``json(...)``), so no string of a design file,
    file name or message is ever part of the Typst source (nothing can be read as markup or
    code, whatever characters it holds)."""

    def __init__(self) -> None:
        self.items: list[str] = []
        self._index: dict[str, int] = {}

    def lit(self, text: str) -> str:
        """``text`` as a Typst code expression (a string read from the data)."""
        # a lone surrogate (a non-UTF-8 byte of a command line) cannot go into JSON text
        clean = text.encode("utf-8", "replace").decode("utf-8")
        i = self._index.get(clean)
        if i is None:
            i = self._index[clean] = len(self.items)
            self.items.append(clean)
        return f"T.at({i})"

    def s(self, text: str) -> str:
        """``text`` as text in markup (an embedded expression, ended by ``;``)."""
        return f"#{self.lit(text)};"

    def json(self) -> str:
        return json.dumps(self.items, ensure_ascii=True)


def _label(anchor: str) -> str:
    """An anchor as a Typst label: only ``[A-Za-z0-9_:.-]`` (anchors are the program's ids)."""
    return re.sub(r"[^A-Za-z0-9_:.-]", "-", anchor) or "-"


class _Writer:
    """Typst markup of report blocks; every text goes through :class:`_Text`."""

    def __init__(self, text: _Text, svgs: Mapping[str, str], known: frozenset[str]) -> None:
        self.t = text
        self.svgs = svgs
        self.known = known
        self.figures: dict[str, str] = {}

    def num(self, n: Num) -> str:
        unit = unit_gap(n.unit).replace(" ", "\u00a0") + n.unit_shown
        return self.t.s(n.text + unit)

    def inline(self, parts: Sequence[Inline]) -> str:
        """Inline content as markup; a link or reference to an anchor not in ``known`` (when
        given) is written as its text, so a missing target never stops the typesetting."""
        s = self.t.s
        out = []
        for p in parts:
            if isinstance(p, (Link, Ref)) and self.known and p.anchor not in self.known:
                out.append(s(p.text if isinstance(p, Link) else p.anchor))
                continue
            if isinstance(p, Num):
                out.append(self.num(p))
            elif isinstance(p, Strong):
                out.append(f"#strong({self.t.lit(p.text)});")
            elif isinstance(p, Link):
                out.append(f"#link(<{_label(p.anchor)}>)[{s(p.text)}];")
            elif isinstance(p, Ref):
                out.append(f"#ref(<{_label(p.anchor)}>);")
            else:
                out.append(s(str(p)))
        return "".join(out)

    def cell(self, cell: Cell, shared_unit: str) -> str:
        if isinstance(cell, Num):
            if shared_unit or not cell.unit:
                return "[" + self.t.s(cell.text) + "]"
            return "[" + self.num(cell) + "]"
        return "[" + self.t.s(cell_text(cell)) + "]"

    def table(self, t: Table) -> str:
        s = self.t.s
        ncol = len(t.headers)
        numeric = []
        for i in range(ncol):
            cells = [r[i] for r in t.rows if i < len(r) and r[i] not in (None, "")]
            numeric.append(bool(cells) and sum(map(_is_numeric, cells)) >= 0.5 * len(cells))
        cols = ", ".join(_column_widths(t, numeric))
        align = ", ".join("right" if n else "left" for n in numeric)
        units = column_units(t)
        head = ", ".join(
            f"[*{s(header_with_unit(h, u))}*]" for h, u in zip(t.headers, units, strict=True)
        )
        body = []
        for row in t.rows if t.pdf_rows is None else t.pdf_rows:
            body.append(", ".join(self.cell(c, u) for c, u in zip(row, units, strict=False)))
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

    def figure(self, block: FigureBlock) -> str:
        key = f"fig{len(self.figures)}"
        self.figures[key] = self.svgs[block.id]
        width = min(block.size_in[0], TEXT_WIDTH_IN)
        return (
            f'#figure(image(bytes(sys.inputs.at("{key}")), format: "svg", width: {width:.3f}in), '
            f"caption: [{self.t.s(block.caption)}]) <{_label(block.id)}>\n"
        )

    def block(self, block: Any) -> str:
        s = self.t.s
        if isinstance(block, Paragraph):
            text = self.inline(block.parts)
            if block.kind:
                colour = _CALLOUT.get(block.kind, _CALLOUT["note"])
                return (
                    f"#block(width: 100%, inset: (x: 8pt, y: 6pt), fill: luma(244), "
                    f"stroke: (left: 3pt + {colour}))[{text}]\n"
                )
            return text + "\n"
        if isinstance(block, Bullets):
            items = ", ".join(f"[{self.inline(i)}]" for i in block.items)
            return f"#list({items})\n"
        if isinstance(block, Table):
            return self.table(block)
        if isinstance(block, Code):
            cap = f"\n#text(size: 9pt)[{s(block.caption)}]" if block.caption else ""
            code = self.t.lit(block.text)
            return f'#columns(2, gutter: 12pt, raw({code}, block: true, lang: "toml")){cap}\n'
        if isinstance(block, Equation):  # the program's own mathematics (assumptions.py)
            label = (
                f"#h(1fr) #text(size: 8.5pt, fill: luma(90))[{s(block.label)}]"
                if block.label
                else ""
            )
            return f"#block(width: 100%)[#h(1.2em) $ {block.typst} $ {label}]\n"
        if isinstance(block, FigureBlock):
            return self.figure(block)
        raise TypeError(f"unknown report block {type(block).__name__}")


def _is_numeric(cell: Cell) -> bool:
    return isinstance(cell, Num) or (isinstance(cell, (int, float)) and not isinstance(cell, bool))


def typst_source(
    front: FrontMatter,
    sections: Sequence[Section],
    footer: str,
    svgs: Mapping[str, str],
) -> tuple[str, dict[str, str]]:
    """The Typst markup of the report and the inputs it reads (``sys.inputs``: the figures'
    SVG texts and ``text``, the JSON array of every string the report shows)."""
    from spiralcap.report.document import numbering

    text = _Text()
    s, lit = text.s, text.lit
    fill = {
        "title": lit(front.title),
        "title_markup": s(front.title),
        "author": lit(front.author or "spiralcap"),
        "header_right": s(front.design_source),
        "footer": s(footer),
    }
    pre = re.sub(r"@(\w+)@", lambda m: fill[m.group(1)], _PREAMBLE)  # one pass: never re-read
    out = [_LOAD_TEXT, pre]
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
        '#block(below: 1.2em)[#text(size: 20pt, weight: "bold", hyphenate: false)'
        f"[{s(front.title)}]]\n"
        f"#grid(columns: (auto, 1fr), column-gutter: 1.2em, row-gutter: 0.5em, {grid})\n"
        "#v(0.8em)\n#outline(title: [Contents], depth: 1, indent: auto)\n"
    )
    known = frozenset(numbering(sections)) | {sec.id for sec in sections}
    writer = _Writer(text, svgs, known)
    for sec in sections:
        out.append(f"\n= {s(sec.title)} <{_label(sec.id)}>\n")
        for block in sec.blocks:
            out.append(writer.block(block))
    inputs = dict(writer.figures)
    inputs["text"] = text.json()
    return "\n".join(out), inputs


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

    source, inputs = typst_source(front, sections, footer, svgs)
    pdf = typst.compile(
        source.encode("utf-8"),
        format="pdf",
        sys_inputs=inputs,
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
