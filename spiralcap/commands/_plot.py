"""Writing a figure from the CLI (``--plot F.png``): the path checked first, written atomically."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from spiralcap.errors import InputError

#: Figure formats the CLI writes.
FIGURE_SUFFIXES = ("png", "svg", "pdf")


def check_figure_path(option: str, path: str) -> None:
    """Refuse a figure path before any work is done (InputError naming ``option``)."""
    suffix = Path(path).suffix.lower().lstrip(".")
    if suffix not in FIGURE_SUFFIXES:
        raise InputError(option, path, "a file name ending in .png, .svg or .pdf")
    if Path(path).is_dir():
        raise InputError(option, path, "a file path, not an existing folder")


def write_figure(path: str, draw: Callable[[Any], Any], size_in: tuple[float, float]) -> Any:
    """Draw with ``draw(fig)`` on a new Figure in the report style and write it atomically.

    Returns what ``draw`` returned.
    """
    import io

    import matplotlib
    from matplotlib.figure import Figure

    from spiralcap.design import write_text_atomic
    from spiralcap.figures.style import REPORT_RC

    suffix = Path(path).suffix.lower().lstrip(".")
    with matplotlib.rc_context(REPORT_RC):
        fig = Figure(figsize=size_in, layout="constrained")
        drawn = draw(fig)
        buf = io.BytesIO()
        fig.savefig(buf, format=suffix, dpi=150, metadata=None)
    write_text_atomic(path, buf.getvalue())
    return drawn
