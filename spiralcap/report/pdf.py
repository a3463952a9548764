"""Render a report document as a PDF with matplotlib's PdfPages (no external program needed).

Text flows onto A4 pages (headings, paragraphs, monospaced tables); every figure gets a page of
its own with its caption under it. The result is returned as bytes so the caller can write it
atomically together with the HTML.
"""

from __future__ import annotations

import io
import textwrap
from collections.abc import Sequence
from typing import Any

from spiralcap.report.document import (
    Bullets,
    Code,
    FigureBlock,
    Paragraph,
    Section,
    Table,
    cell_text,
    inline_text,
)

PAGE_IN = (8.27, 11.69)  # A4 portrait, inches
MARGIN_IN = 0.75
_BODY_PT, _MONO_PT, _H_PT, _TITLE_PT = 10.0, 7.6, 14.0, 18.0
_LINE = 1.35  # line height / font size
_CHAR_W = 0.6  # monospace advance / font size (DejaVu Sans Mono)
_WRAP_BODY = 95  # characters per body line at 10 pt on A4


class _Pages:
    """A cursor over text pages: lines are placed top-down; a full page starts the next."""

    def __init__(self, pdf: Any, footer: str) -> None:
        self.pdf, self.footer = pdf, footer
        self.fig: Any = None
        self.y = 0.0
        self.number = 0

    def _new(self) -> None:
        from matplotlib.figure import Figure

        self.flush()
        self.fig = Figure(figsize=PAGE_IN)
        self.y = PAGE_IN[1] - MARGIN_IN

    def flush(self) -> None:
        if self.fig is not None:
            self._finish(self.fig)
            self.fig = None

    def _finish(self, fig: Any) -> None:
        self.number += 1
        fig.text(
            0.5,
            0.35 / PAGE_IN[1],
            f"{self.footer} — page {self.number}",
            ha="center",
            va="bottom",
            fontsize=7.5,
            color="0.35",
        )
        self.pdf.savefig(fig)

    def line(
        self,
        text: str,
        size: float = _BODY_PT,
        *,
        mono: bool = False,
        bold: bool = False,
        color: str = "black",
        indent_in: float = 0.0,
    ) -> None:
        height = size * _LINE / 72.0
        if self.fig is None or self.y - height < MARGIN_IN:
            self._new()
        self.y -= height
        self.fig.text(
            (MARGIN_IN + indent_in) / PAGE_IN[0],
            self.y / PAGE_IN[1],
            text,
            fontsize=size,
            family="monospace" if mono else "sans-serif",
            weight="bold" if bold else "normal",
            color=color,
            va="baseline",
        )

    def space(self, points: float) -> None:
        self.y -= points / 72.0

    def need(self, lines: int, size: float = _BODY_PT) -> None:
        """Start a new page unless ``lines`` more lines fit on this one."""
        if self.fig is None or self.y - lines * size * _LINE / 72.0 < MARGIN_IN:
            self._new()

    def figure_page(self, block: FigureBlock, number: int) -> None:
        """Give a figure a page: drawn at the top, full text width, its caption under it."""
        import matplotlib

        from spiralcap.figures.style import REPORT_RC

        self.flush()
        with matplotlib.rc_context(REPORT_RC):
            self._figure_page(block, number)

    def _figure_page(self, block: FigureBlock, number: int) -> None:
        from matplotlib.figure import Figure

        page = Figure(figsize=PAGE_IN, layout="constrained")
        w_avail = PAGE_IN[0] - 2 * MARGIN_IN
        h_avail = PAGE_IN[1] - 2 * MARGIN_IN
        height = block.size_in[1] * min(1.0, w_avail / block.size_in[0]) + 0.3
        grid = page.subfigures(
            3,
            3,
            width_ratios=[MARGIN_IN, w_avail, MARGIN_IN],
            height_ratios=[MARGIN_IN, h_avail, MARGIN_IN],
        )
        cell = grid[1][1]  # type: ignore[index]  # subfigures(3, 3) is a 3 x 3 array
        top, bottom = cell.subfigures(2, 1, height_ratios=[height, h_avail - height])
        block.draw(top)
        rest = h_avail - height
        y = 1.0 - 0.15 / rest
        for ln in textwrap.wrap(f"Figure {number}. {block.caption}", _WRAP_BODY):
            bottom.text(0.0, y, ln, fontsize=9.5, va="top")
            y -= 9.5 * _LINE / 72.0 / rest
        self._finish(page)


def _table_lines(t: Table, width: int) -> list[str]:
    cells = [[cell_text(c) for c in row] for row in t.rows]
    ncol = len(t.headers)
    widths = [max([len(t.headers[i])] + [len(r[i]) for r in cells]) for i in range(ncol)]
    if t.wrap is not None and sum(widths) + 2 * (ncol - 1) > width:
        others = sum(w for i, w in enumerate(widths) if i != t.wrap) + 2 * (ncol - 1)
        widths[t.wrap] = max(12, width - others)
    lines = [
        "  ".join(h.ljust(w) for h, w in zip(t.headers, widths, strict=True)),
        "  ".join("-" * w for w in widths),
    ]
    for row in cells:
        wrapped = [
            textwrap.wrap(c, widths[i]) or [""] if i == t.wrap else [c] for i, c in enumerate(row)
        ]
        for k in range(max(len(w) for w in wrapped)):
            lines.append(
                "  ".join(
                    (w[k] if k < len(w) else "").ljust(widths[i]) for i, w in enumerate(wrapped)
                ).rstrip()
            )
    return lines


def render_pdf(
    title: str,
    subtitle: str,
    sections: Sequence[Section],
    footer: str,
    metadata: dict[str, str] | None = None,
) -> tuple[bytes, int]:
    """The report as PDF bytes and its page count.

    Parameters
    ----------
    title, subtitle : str
        Shown at the top of the first page.
    sections : sequence of Section
        The same sections the HTML shows.
    footer : str
        Text at the foot of every page (followed by the page number).
    metadata : dict, optional
        PDF document information (Title, Author, Subject, ...).
    """
    from matplotlib.backends.backend_pdf import PdfPages

    buf = io.BytesIO()
    mono_chars = int((PAGE_IN[0] - 2 * MARGIN_IN) * 72.0 / (_MONO_PT * _CHAR_W))
    figure_no = 0
    with PdfPages(
        buf, metadata={"Title": title, "Creator": "spiralcap", **(metadata or {})}
    ) as pdf:
        pages = _Pages(pdf, footer)
        pages.line(title, _TITLE_PT, bold=True)
        for ln in textwrap.wrap(subtitle, _WRAP_BODY):
            pages.line(ln, _BODY_PT, color="0.3")
        pages.space(6)
        for n, sec in enumerate(sections, 1):
            pages.need(6)
            pages.space(8)
            pages.line(f"{n}. {sec.title}", _H_PT, bold=True)
            pages.space(3)
            for block in sec.blocks:
                if isinstance(block, FigureBlock):
                    figure_no += 1
                    pages.figure_page(block, figure_no)
                    continue
                _text_block(pages, block, mono_chars)
                pages.space(5)
        pages.flush()
        count = pages.number
    return buf.getvalue(), count


def _text_block(pages: _Pages, block: Any, mono_chars: int) -> None:
    if isinstance(block, Paragraph):
        colour = {"alert": "#a4161a", "ok": "#1b6e3a"}.get(block.kind, "black")
        for ln in textwrap.wrap(inline_text(block.parts), _WRAP_BODY):
            pages.line(ln, bold=block.kind == "alert", color=colour)
    elif isinstance(block, Bullets):
        for item in block.items:
            for i, ln in enumerate(textwrap.wrap(inline_text(item), _WRAP_BODY - 4)):
                pages.line(("•  " if i == 0 else "   ") + ln, indent_in=0.1)
    elif isinstance(block, Table):
        lines = _table_lines(block, mono_chars)
        if block.caption:
            pages.need(min(len(lines), 8) + 1)
            pages.line(block.caption, 9.5, bold=True)
        for ln in lines:
            pages.line(ln, _MONO_PT, mono=True)
    elif isinstance(block, Code):
        for ln in block.text.splitlines():
            for piece in textwrap.wrap(ln, mono_chars) or [""]:
                pages.line(piece, _MONO_PT, mono=True)
        if block.caption:
            pages.line(block.caption, 9.0, color="0.3")
    else:
        raise TypeError(f"unknown report block {type(block).__name__}")
