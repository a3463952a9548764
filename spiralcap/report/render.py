"""Draw the report's figures once, as SVG, for both the HTML and the PDF.

Each :class:`~spiralcap.report.document.FigureBlock` is drawn on a fresh matplotlib Figure of
its ``size_in`` in the report style and saved as SVG (vector: lines, text as paths, so the PDF
needs none of matplotlib's fonts). The HTML embeds the SVG as a ``data:`` URI, the PDF passes it
to Typst; drawing once keeps the PDF's extra cost to the typesetting alone.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from typing import Any, cast

from spiralcap.report.document import FigureBlock, Section

#: rcParams that make the SVG reproducible (no date, fixed ids) and self-contained.
SVG_RC = {"svg.hashsalt": "spiralcap", "svg.fonttype": "path"}


def figure_svg(block: FigureBlock) -> str:
    """Draw ``block`` on a new Figure in the report style and return the SVG text."""
    import matplotlib
    from matplotlib.backends.backend_svg import FigureCanvasSVG
    from matplotlib.figure import Figure

    from spiralcap.figures.style import REPORT_RC

    with matplotlib.rc_context(cast(Any, {**REPORT_RC, **SVG_RC})):
        fig = Figure(figsize=block.size_in, layout="constrained")
        FigureCanvasSVG(fig)
        block.draw(fig)
        buf = io.StringIO()
        fig.savefig(buf, format="svg", metadata={"Date": None, "Creator": "spiralcap"})
    return buf.getvalue()


def figure_png(block: FigureBlock, dpi: int = 150) -> bytes:
    """Draw ``block`` as a PNG (for the gallery and for checks by eye)."""
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from spiralcap.figures.style import REPORT_RC

    with matplotlib.rc_context(cast(Any, REPORT_RC)):
        fig = Figure(figsize=block.size_in, layout="constrained")
        FigureCanvasAgg(fig)
        block.draw(fig)
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=dpi, metadata={"Software": "spiralcap (matplotlib)"})
    return buf.getvalue()


def render_figures(sections: Sequence[Section]) -> dict[str, str]:
    """``figure id -> SVG text`` for every figure of the report, in reading order."""
    return {b.id: figure_svg(b) for s in sections for b in s.blocks if isinstance(b, FigureBlock)}
