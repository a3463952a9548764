"""The report as a renderer-neutral document: sections of paragraphs, tables, figures, code.

Sections build these blocks from result dicts; :mod:`spiralcap.report.html` and
:mod:`spiralcap.report.pdf` render the same blocks, so the HTML and the PDF say the same thing.
Inline content is a sequence of strings and :class:`~spiralcap.report.numbers.Num` values.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Union

from spiralcap.report.numbers import Num

#: Inline content: plain text and numbers tied to the embedded JSON.
Inline = Union[str, Num, "Link", "Strong", "Ref"]
Cell = Union[str, Num, int, float, None]


@dataclass(frozen=True)
class Strong:
    """Emphasised inline text."""

    text: str


@dataclass(frozen=True)
class Link:
    """An in-document link to a section or figure anchor (``#margin``); never an external URL."""

    text: str
    anchor: str


@dataclass(frozen=True)
class Ref:
    """A numbered reference to a figure or table by its id: rendered ``Figure 3``."""

    anchor: str


@dataclass(frozen=True)
class Paragraph:
    """A paragraph of inline content. ``kind`` 'note', 'ok' or 'alert' renders as a callout."""

    parts: Sequence[Inline]
    kind: str = ""


@dataclass(frozen=True)
class Bullets:
    """A bulleted list; each item is a sequence of inline content."""

    items: Sequence[Sequence[Inline]]


@dataclass(frozen=True)
class Table:
    """A table: header row, body rows, an optional caption; cells are text or numbers.

    ``wrap`` names the column (index) of the longest text; a hint only: the PDF now sizes every
    column from its content (:func:`spiralcap.report.pdf.column_layout`).
    ``compact``: typeset small and tight in the PDF (long reference tables; HTML unchanged).
    ``pdf_rows``: the rows the PDF shows instead of ``rows`` (a shorter printed table; the HTML
    shows ``rows``).
    """

    headers: Sequence[str]
    rows: Sequence[Sequence[Cell]]
    caption: str = ""
    wrap: int | None = None
    id: str = ""
    compact: bool = False
    pdf_rows: Sequence[Sequence[Cell]] | None = None


@dataclass(frozen=True)
class Code:
    """Preformatted text (the design TOML)."""

    text: str
    caption: str = ""


@dataclass(frozen=True)
class FigureBlock:
    """A figure: ``draw(fig)`` draws onto a matplotlib Figure or SubFigure of ``size_in``.

    The HTML embeds it as a PNG; the PDF gives it a page. ``id`` is its anchor, ``caption``
    explains what to read off it.
    """

    id: str
    caption: str
    draw: Callable[[Any], Any]
    size_in: tuple[float, float] = (7.0, 4.2)


@dataclass(frozen=True)
class Equation:
    """A displayed equation: Typst math for the PDF, the same in plain Unicode for the HTML.

    ``typst`` is the body of a Typst ``$ ... $`` block; ``text`` is what the HTML shows;
    ``label`` is shown beside it (the source: ``Zhou 2013 eq. 8``).
    """

    typst: str
    text: str
    label: str = ""


@dataclass(frozen=True)
class FrontMatter:
    """What the title page says: title, project, author, revision, and the design's identity."""

    title: str
    project: str
    author: str
    revision: str
    date: str
    design_source: str
    design_sha256: str
    version: str


Block = Union[Paragraph, Bullets, Table, Code, FigureBlock, Equation]


@dataclass(frozen=True)
class Section:
    """One numbered section of the report."""

    id: str
    title: str
    blocks: Sequence[Block] = field(default_factory=tuple)


def inline_text(parts: Sequence[Inline]) -> str:
    """Inline content as plain text (numbers with their units)."""
    out = []
    for p in parts:
        if isinstance(p, (Link, Strong)):
            out.append(p.text)
        elif isinstance(p, Ref):
            out.append(p.anchor)
        else:
            out.append(str(p))
    return "".join(out)


def cell_text(cell: Cell) -> str:
    """A table cell as plain text (numbers to 4 significant figures, with units)."""
    from spiralcap.report.numbers import fmt

    if isinstance(cell, Num):
        return str(cell)
    if cell is None:
        return ""
    return fmt(cell)


def numbering(sections: Sequence[Section]) -> dict[str, str]:
    """``id -> "Figure 3"`` for every figure (and ``"Table 2"`` for tables with an id).

    Both renderers number in reading order, so a :class:`Ref` reads the same in HTML and PDF.
    """
    out: dict[str, str] = {}
    nfig = ntab = 0
    for s in sections:
        for b in s.blocks:
            if isinstance(b, FigureBlock):
                nfig += 1
                out[b.id] = f"Figure {nfig}"
            elif isinstance(b, Table) and b.caption:
                ntab += 1
                if b.id:
                    out[b.id] = f"Table {ntab}"
    return out


def column_units(table: Table) -> list[str]:
    """Per column, the unit every number in it shares ('' when none or mixed).

    Renderers put a shared unit in the header (``power budget (W)``) and write the numbers
    bare; a column of mixed units keeps the unit by each number.
    """
    out = []
    for i in range(len(table.headers)):
        units = {c.unit for r in table.rows if i < len(r) and isinstance((c := r[i]), Num)}
        out.append(units.pop() if len(units) == 1 else "")
    return out


def header_with_unit(header: str, unit: str) -> str:
    """``power budget`` + ``W`` -> ``power budget (W)`` (unchanged when the unit is empty)."""
    return f"{header} ({unit})" if unit and f"({unit})" not in header else header
