"""Writing a figure from the CLI (``--plot F.png``): the path checked first, written atomically."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any, cast

from spiralcap.core.errors import InputError

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
    from spiralcap.design import write_text_atomic

    data, drawn = figure_bytes(path, draw, size_in)
    write_text_atomic(path, data)
    return drawn


def figure_bytes(
    path: str, draw: Callable[[Any], Any], size_in: tuple[float, float]
) -> tuple[bytes, Any]:
    """The file ``path`` would hold (its suffix the format): a new Figure in the report style
    drawn with ``draw(fig)``; and what ``draw`` returned. Nothing is written (a command with
    several outputs commits them together)."""
    import io

    import matplotlib
    from matplotlib.figure import Figure

    from spiralcap.figures.style import REPORT_RC

    suffix = Path(path).suffix.lower().lstrip(".")
    with matplotlib.rc_context(cast(Any, REPORT_RC)):
        fig = Figure(figsize=size_in, layout="constrained")
        drawn = draw(fig)
        buf = io.BytesIO()
        fig.savefig(buf, format=suffix, dpi=150, metadata=None)
    return buf.getvalue(), drawn


def add_geometry_plot_argument(parser: Any) -> None:
    """``--plot FIGURE.png``: the geometry view (coils to scale, workspace, capsule)."""
    parser.add_argument(
        "--plot",
        metavar="FIGURE.png",
        help="also draw the hardware to scale (.png, .svg or .pdf): the nested coil pairs "
        "with their winding packs, the workspace and the capsule",
    )


def write_geometry(path: str, design: Any, *, quiet: bool = False) -> Any:
    """Draw the geometry view of ``design`` to ``path`` (:func:`spiralcap.figures.hardware.draw_geometry`)."""
    from spiralcap.design import write_text_atomic

    data, drawn = geometry_bytes(path, design)
    write_text_atomic(path, data)
    if not quiet:
        print(f"wrote {path}")
    return drawn


def geometry_bytes(path: str, design: Any) -> tuple[bytes, Any]:
    """The geometry view of ``design`` as the file ``path`` would hold, and what the drawing
    returned (:func:`figure_bytes`)."""
    from spiralcap.assemble import build_model
    from spiralcap.figures.hardware import draw_geometry

    model = build_model(design)
    return figure_bytes(
        path,
        lambda fig: draw_geometry(
            fig,
            model.coils,
            model.capsule,
            workspace_radius_m=float(design["workspace.radius_m"]),
            min_clearance_m=model.requirements.min_clearance_m,
        ),
        (7.0, 3.5),
    )
