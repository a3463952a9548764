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

import itertools
import json
import math
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
#show table: set text(size: @table_pt@pt)
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


#: Average width of a character of the table font (Libertinus Serif), in em: an estimate on
#: the wide side, so a column estimated to fit does fit.
CHAR_EM = 0.5
#: Type size of the tables, pt (``compact``: the long reference tables).
TABLE_PT, COMPACT_PT = 8.5, 6.5
#: A table of at most this many rows is not split across pages (nor from its caption).
KEEP_TOGETHER_ROWS = 16
#: Figures print at this share of their drawn width (their text stays above 6 pt): a page
#: holds a figure and its discussion more often.
FIGURE_SCALE = 1.0
#: Type size of preformatted text (the design file), pt.
CODE_PT = 6.5
#: A word longer than this (characters) does not widen its column: it breaks at its dots.
WORD_CAP = 24
#: Break opportunity in a long identifier (a design key), PDF only.
_BREAK = "\u200b"
_BREAK_AFTER = re.compile(r"([._/])(?=\w)")


def _line_chars(t: Table) -> float:
    """About how many characters of the table's type fill the text width."""
    return TEXT_WIDTH_IN * 72.0 / (CHAR_EM * (COMPACT_PT if t.compact else TABLE_PT))


def _natural(header: str, texts: Sequence[str]) -> int:
    """A column's width on one line, characters: its longest cell (the header may wrap)."""
    return max([len(w) for w in header.split()] + [len(x) for x in texts] + [1])


def _longest_word(header: str, texts: Sequence[str]) -> int:
    """The longest word of a column (header included), capped at :data:`WORD_CAP` characters: a
    longer one is a design key, broken at its dots by :func:`breakable`."""
    return min(max([len(w) for x in [header, *texts] for w in x.split()] + [1]), WORD_CAP)


def _weight(header: str, texts: Sequence[str], natural: int) -> float:
    """A wide column's claim on what is left of the line: between its typical cell (the upper
    quartile of the lengths) and its longest (their geometric mean), so one long outlier (a
    tissue set's name among numbers, a covariance matrix) wraps in its own column without
    squeezing the others, nor being squeezed to a word a line."""
    lengths = sorted(len(x) for x in texts) or [1]
    typical = max(lengths[(3 * (len(lengths) - 1)) // 4], 1)
    return math.sqrt(typical * natural)


def _wide_columns(natural: Sequence[int], budget: float) -> set[int]:
    """The columns that share what is left once every column narrower than a fair share of it
    keeps its natural width (the fair share grows as narrow columns drop out)."""
    wide = set(range(len(natural)))
    while True:
        left = budget - sum(n for i, n in enumerate(natural) if i not in wide)
        narrow = {i for i in wide if natural[i] <= left / max(len(wide), 1)}
        if not narrow or narrow == wide:
            return wide
        wide -= narrow


def column_layout(
    t: Table, rows: Sequence[Sequence[Cell]], units: Sequence[str]
) -> tuple[list[str], list[float]]:
    """Typst column widths from the content, as a browser lays out a table, and the width of
    each column in characters (estimated).

    Every column keeps its natural width (``auto``) when the table fits on the line. Otherwise
    the columns narrower than a fair share of what is left keep theirs (again as the share grows)
    and the wide ones share the rest in proportion to their typical cell (``Nfr``), so a long
    text never squeezes a column of short ones to a word a line.
    """
    ncol = len(t.headers)
    headers = [header_with_unit(t.headers[i], units[i]) for i in range(ncol)]
    texts = [[cell_text(r[i]) for r in rows if i < len(r)] for i in range(ncol)]
    natural = [_natural(headers[i], texts[i]) for i in range(ncol)]
    budget = _line_chars(t) - 2.0 * ncol  # the cells' insets
    if sum(natural) <= budget:
        return ["auto"] * ncol, [float(n) for n in natural]
    wide = _wide_columns(natural, budget)
    left = budget - sum(natural[i] for i in range(ncol) if i not in wide)
    # every wide column gets its longest word, then a share of the rest by its weight
    least = {i: _longest_word(headers[i], texts[i]) for i in wide}
    weight = {i: _weight(headers[i], texts[i], natural[i]) for i in wide}
    spare = max(left - sum(least.values()), 0.0)
    total = sum(weight.values())
    chars = [
        least[i] + spare * weight[i] / total if i in wide else float(natural[i])
        for i in range(ncol)
    ]
    widths = [f"{chars[i]:.2f}fr" if i in wide else "auto" for i in range(ncol)]
    return widths, chars


def breakable(text: str, chars: float) -> str:
    """``text`` with a break opportunity after each ``.``, ``_`` and ``/`` of every word longer
    than ``chars`` (a design key in a narrow column wraps at its dots instead of overprinting
    the next column); shorter words unchanged, so most keys still copy from the PDF as typed."""
    return " ".join(
        _BREAK_AFTER.sub(r"\1" + _BREAK, w) if len(w) > chars else w for w in text.split(" ")
    )


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

    def cell(self, cell: Cell, shared_unit: str, chars: float = math.inf) -> str:
        if isinstance(cell, Num):
            if shared_unit or not cell.unit:
                return "[" + self.t.s(cell.text) + "]"
            return "[" + self.num(cell) + "]"
        return "[" + self.t.s(breakable(cell_text(cell), chars)) + "]"

    def table(self, t: Table) -> str:
        s = self.t.s
        ncol = len(t.headers)
        numeric = []
        for i in range(ncol):
            cells = [r[i] for r in t.rows if i < len(r) and r[i] not in (None, "")]
            numeric.append(bool(cells) and sum(map(_is_numeric, cells)) >= 0.5 * len(cells))
        units = column_units(t)
        rows = t.rows if t.pdf_rows is None else t.pdf_rows
        widths, chars = column_layout(t, rows, units)
        cols = ", ".join(widths)
        align = ", ".join("right" if n else "left" for n in numeric)
        head = ", ".join(
            f"[*{s(breakable(header_with_unit(h, u), c))}*]"
            for h, u, c in zip(t.headers, units, chars, strict=True)
        )
        body = []
        for row in rows:
            body.append(
                ", ".join(self.cell(c, u, w) for c, u, w in zip(row, units, chars, strict=False))
            )
        inset = "inset: (x: 3pt, y: 1.3pt), " if t.compact else ""
        table = (
            f"table(columns: ({cols},), {inset}align: ({align},), table.header({head}),\n"
            + ",\n".join(body)
            + ")"
        )
        if t.compact:  # small type and tight cells; the caption keeps the document's size
            # a show-set rule: the document's ``show table: set text(...)`` would win over a set
            table = (
                f"[#show table: set text(size: {COMPACT_PT}pt); #set par(leading: 0.4em); #{table}]"
            )
        if not t.caption:
            return f"#{table}\n"
        label = f" <{_label(t.id)}>" if t.id else ""
        fig = f"#figure({table}, caption: [{s(t.caption)}], kind: table){label}\n"
        if len(rows) <= KEEP_TOGETHER_ROWS:  # a short table stays with its caption
            return f"#block(breakable: false)[{fig}]\n"
        return fig

    def figure(self, block: FigureBlock) -> str:
        key = f"fig{len(self.figures)}"
        self.figures[key] = self.svgs[block.id]
        width = min(block.size_in[0], TEXT_WIDTH_IN) * FIGURE_SCALE
        return (
            f'#figure(image(bytes(sys.inputs.at("{key}")), format: "svg", width: {width:.3f}in), '
            f"caption: [{self.t.s(block.caption)}], placement: auto) <{_label(block.id)}>\n"
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
            # three balanced columns of small type: a design file is about 90 short lines
            parts = ", ".join(
                f'raw({self.t.lit(chunk)}, block: true, lang: "toml")'
                for chunk in _balanced_columns(block.text, 3)
            )
            return (
                f"#[#show raw: set text(size: {CODE_PT}pt); "
                f"#grid(columns: (1fr, 1fr, 1fr), column-gutter: 10pt, {parts})]{cap}\n"
            )
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


def _balanced_columns(text: str, n: int) -> list[str]:
    """``text`` in ``n`` runs of whole lines of about equal length, each run starting at a blank
    line or a ``[table]`` header where one is near (a TOML table is not split if it can stay
    whole)."""
    lines = text.rstrip("\n").split("\n")
    cuts = [0]
    for k in range(1, n):
        target = round(k * len(lines) / n)
        near = [
            i
            for i in range(max(cuts[-1] + 1, target - 6), min(len(lines), target + 7))
            if lines[i].startswith("[")
        ]
        cut = min(near, key=lambda i: abs(i - target)) if near else target
        cuts.append(min(max(cut, cuts[-1] + 1), len(lines)))  # never back over a column
    cuts.append(len(lines))
    return ["\n".join(lines[a:b]) for a, b in itertools.pairwise(cuts) if b > a]


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
        "table_pt": str(TABLE_PT),
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
        f"#grid(columns: (auto, 1fr), column-gutter: 1.2em, row-gutter: 0.4em, {grid})\n"
        "#v(0.4em)\n"
    )
    outline = "#outline(title: [Contents], depth: 1, indent: auto)\n"
    # the summary is the first page; the contents open the second
    lead = 1 if sections and sections[0].id == "summary" else 0
    if not lead:
        out.append(outline)
    known = frozenset(numbering(sections)) | {sec.id for sec in sections}
    writer = _Writer(text, svgs, known)
    for i, sec in enumerate(sections):
        if lead and i == lead:
            out.append("#pagebreak(weak: true)\n" + outline)
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
