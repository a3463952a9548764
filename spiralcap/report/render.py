"""Draw the report's figures once, as SVG, for both the HTML and the PDF.

Each :class:`~spiralcap.report.document.FigureBlock` is drawn on a fresh matplotlib Figure of
its ``size_in`` in the report style and saved as SVG. Lines are vectors and text stays text
(``svg.fonttype = "none"``, font DejaVu Sans): the figures' words are searchable and selectable in
the HTML and the PDF, the files are smaller, and saving costs 15 % less than glyphs written as
paths. The PDF typesets that text in matplotlib's own DejaVu fonts (Typst is given their folder,
:func:`matplotlib_font_dir`), so it matches the layout exactly; a browser without DejaVu Sans
falls back to the next sans-serif in the SVG's font list (Arial, Helvetica: narrower, so nothing
overruns). The HTML embeds the SVG as a ``data:`` URI, the PDF passes it to Typst; drawing once
keeps the PDF's extra cost to the typesetting alone.

The constrained layout is solved once, then frozen (``set_layout_engine(None)``) before saving:
with an engine attached, ``savefig`` draws the whole figure twice (once only to lay it out).
"""

from __future__ import annotations

import io
from collections.abc import Mapping, Sequence
from concurrent.futures import Future
from dataclasses import dataclass
from typing import Any, cast

from spiralcap.report.document import FigureBlock, Section

#: rcParams that make the SVG reproducible (no date, fixed ids) and self-contained.
SVG_RC = {"svg.hashsalt": "spiralcap", "svg.fonttype": "none"}


def _freeze_layout(fig: Any) -> None:
    """Solve the figure's layout once and fix the axes there (``savefig`` then draws once)."""
    engine = fig.get_layout_engine()
    if engine is not None:
        engine.execute(fig)
        fig.set_layout_engine(None)


def matplotlib_font_dir() -> str:
    """matplotlib's bundled TrueType fonts (DejaVu), which the SVG text names."""
    import os

    import matplotlib

    return os.path.join(matplotlib.get_data_path(), "fonts", "ttf")


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
        _freeze_layout(fig)
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
        _freeze_layout(fig)
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=dpi, metadata={"Software": "spiralcap (matplotlib)"})
    return buf.getvalue()


def preload() -> None:
    """Import what drawing the figures needs (about 0.2 s), e.g. while analyses run elsewhere.

    Forked drawers then start with matplotlib and the figure modules loaded (matplotlib has no
    other one-time cost: its font list loads on import, and a first figure costs what any
    other does).
    """
    import importlib

    for name in _FIGURE_MODULES:
        importlib.import_module(name)


_FIGURE_MODULES = (
    "matplotlib.figure",
    "matplotlib.backends.backend_svg",
    "spiralcap.figures.api",
    "spiralcap.figures.coils",
    "spiralcap.figures.design",
    "spiralcap.figures.hardware",
    "spiralcap.figures.sweep",
    "spiralcap.figures.thermal",
    "spiralcap.figures.torque",
)


def draw_svgs(figures: Mapping[str, tuple[Any, tuple[float, float]]]) -> dict[str, str]:
    """``id -> SVG`` of figures given as ``id -> (draw(fig), size in inches)``."""
    return {
        k: figure_svg(FigureBlock(k, "", draw, size_in=size)) for k, (draw, size) in figures.items()
    }


@dataclass(frozen=True)
class DrawnElsewhere:
    """Figures another process is drawing: their ids, and the future whose result is id -> SVG
    (:func:`draw_svgs` on a :func:`spiralcap.parallel.process_pool`)."""

    ids: frozenset[str]
    job: Future


def render_figures(
    sections: Sequence[Section], *, workers: int = 1, elsewhere: DrawnElsewhere | None = None
) -> dict[str, str]:
    """``figure id -> SVG text`` for every figure of the report, in reading order.

    With ``workers >= 2`` the figures are handed out, one at a time, to ``workers`` forked
    processes (:func:`spiralcap.parallel.process_pool`); each figure is drawn by the same
    function either way, so the SVG text is the same. Figures ``elsewhere`` is already drawing
    are not drawn again; its SVGs are taken when it is done.
    """
    from spiralcap.parallel import can_fork, inherited, process_pool

    blocks = [b for s in sections for b in s.blocks if isinstance(b, FigureBlock)]
    ids = elsewhere.ids if elsewhere is not None else frozenset()
    todo = [b for b in blocks if b.id not in ids]
    if workers >= 2 and len(todo) > 1 and can_fork():
        preload()  # once, before forking, rather than in every process
        with inherited(lambda i: figure_svg(todo[i])) as draw, process_pool(workers) as pool:
            svgs = list(pool.map(draw, range(len(todo))))
    else:
        svgs = [figure_svg(b) for b in todo]
    done = dict(zip((b.id for b in todo), svgs, strict=True))
    if elsewhere is not None:
        done.update(elsewhere.job.result())
    return {b.id: done[b.id] for b in blocks}
