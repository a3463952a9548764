"""Print-readable figure style shared by the report's figures.

Figures must read in black-and-white print: every series differs by line style and marker as
well as colour, lines are at least 1.6 pt, text at least 9 pt. :data:`REPORT_RC` is applied
with ``matplotlib.rc_context`` around drawing and saving; :func:`series_style` gives the k-th
series its colour, line style and marker.
"""

from __future__ import annotations

from typing import Any

#: rcParams for report figures (used inside ``matplotlib.rc_context``).
REPORT_RC: dict[Any, Any] = {  # matplotlib types its keys as a Literal of rc names
    "font.size": 10.0,
    "axes.titlesize": 10.5,
    "axes.labelsize": 10.0,
    "xtick.labelsize": 9.0,
    "ytick.labelsize": 9.0,
    "legend.fontsize": 8.5,
    "legend.framealpha": 0.9,
    "lines.linewidth": 1.8,
    "lines.markersize": 6.0,
    "axes.grid": True,
    "grid.color": "0.85",
    "grid.linewidth": 0.6,
    "axes.axisbelow": True,
    "savefig.facecolor": "white",
    "figure.facecolor": "white",
}

#: Colour-blind-safe colours (Okabe & Ito 2008), then line styles and markers, cycled together.
COLOURS = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000")
LINESTYLES = ("-", "--", "-.", ":", (0, (5, 1.5, 1, 1.5, 1, 1.5)), (0, (8, 2)))
MARKERS = ("o", "s", "^", "D", "v", "P", "X")

#: Hatches that mark bars without relying on colour.
HATCHES = ("", "///", "...", "xx", "\\\\", "++")


def series_style(k: int, *, markevery: int | None = None) -> dict[str, Any]:
    """Keyword arguments for ``ax.plot`` of the k-th series (colour, line style, marker)."""
    style: dict[str, Any] = {
        "color": COLOURS[k % len(COLOURS)],
        "linestyle": LINESTYLES[k % len(LINESTYLES)],
        "marker": MARKERS[k % len(MARKERS)],
    }
    if markevery is not None:
        style["markevery"] = markevery
    return style


def restyle_lines(lines: Any, *, markevery: int | None = 8, markers: bool = True) -> None:
    """Give already-drawn lines distinct line styles (and markers) keeping their colours.

    Pass ``markers=False`` for model curves drawn with measured points: markers then mean
    data only, never a model.
    """
    for k, line in enumerate(lines):
        line.set_linestyle(LINESTYLES[k % len(LINESTYLES)])
        if not markers:
            line.set_marker("")
            continue
        line.set_marker(MARKERS[k % len(MARKERS)])
        if markevery is not None:
            line.set_markevery(markevery)
