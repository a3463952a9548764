"""Tissue resistive torque against rotation frequency: model curves, paper points, fits.

Functions take ``ax`` and return the artists they drew; they never create figures or files.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from matplotlib.axes import Axes

from spiralcap.core.constants import from_unit, to_unit

if TYPE_CHECKING:
    from torque_model import ContactGeometry

__all__ = ["TorqueDrawn", "plot_fit", "plot_torque_vs_frequency", "save_figure"]


class TorqueDrawn(NamedTuple):
    """Model curves (lines, no markers) and measured or published points (markers only)."""

    curves: list[Any]
    points: list[Any]


_FREQ_LABEL = "rotation frequency f (Hz)"
_TORQUE_LABEL = "resistive torque (mN·m)"


def legend_tissue_name(name: str) -> str:
    """A tissue set's name short enough for a legend: a preset with overridden keys
    (``zhou2013-sample2 + tissue.{E1_kPa, ..., friction_coefficient}``, as a design layered
    with ``spiralcap fit -o`` output has) reads ``zhou2013-sample2 + 8 tissue keys``."""
    head, sep, rest = name.partition(" + tissue.{")
    if not sep:
        return name
    keys, _, tail = rest.partition("}")
    n = len([k for k in keys.split(",") if k.strip()])
    return f"{head} + {n} tissue key{'s' if n != 1 else ''}{tail}"


def plot_torque_vs_frequency(
    ax: Axes,
    tissue: Any = None,
    helical_angles_deg: Sequence[float] = (5.0, 10.0, 15.0, 20.0),
    *,
    frequency_hz: Sequence[float] | np.ndarray | None = None,
    paper_points: Iterable[Any] | None = None,
    geometry: ContactGeometry | None = None,
) -> TorqueDrawn:
    """Model torque against frequency for several helical angles, with the paper's points.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    tissue : torque_model.TissueParameters, optional
        Tissue set (default: preset ``zhou2013-sample2``).
    helical_angles_deg : sequence of float
        One model curve per helical angle, deg.
    frequency_hz : sequence of float, optional
        Frequencies of the curves, Hz (default 0.25-3.5 Hz).
    paper_points : iterable of torque_model.PaperPoint, optional
        Points to overlay (default: :data:`torque_model.PAPER_POINTS` of the tissue's sample
        when the tissue is a Zhou 2013 preset, else none). Pass ``()`` for none.
    geometry : torque_model.ContactGeometry, optional
        The capsule (default :data:`torque_model.PAPER_CAPSULE`, the paper's).

    Returns
    -------
    TorqueDrawn
        Model curves are lines without markers (distinct line styles), one per requested angle
        and one for each paper capsule whose angle is not among them; the paper's points are
        markers only (filled circles: calibration, open squares: validation), coloured as the
        curve of their own angle and labelled with it.
    """
    import torque_model as tm
    from spiralcap.figures.style import LINESTYLES

    tissue = tissue if tissue is not None else tm.preset("zhou2013-sample2")
    f = np.asarray(
        frequency_hz if frequency_hz is not None else np.linspace(0.25, 3.5, 66), dtype=float
    )
    if paper_points is None:
        sample = {"zhou2013-sample2": 2, "zhou2013-sample3": 3}.get(tissue.name)
        paper_points = [p for p in tm.PAPER_POINTS if p.sample == sample]
    paper_points = list(paper_points)
    curves, points = [], []
    colours = {}
    # every data set gets its own model curve: a paper capsule whose angle is not asked for
    # is drawn at its own angle (No. 1 is 5 deg), never against another angle's line
    angles = [float(a) for a in helical_angles_deg]
    angles += sorted({float(p.helical_angle_deg) for p in paper_points} - set(angles))
    for k, angle in enumerate(angles):
        # the paper's capsules are the paper's geometry, whatever the design's
        capsule = geometry if k < len(helical_angles_deg) and geometry else tm.PAPER_CAPSULE
        tau = tm.resistive_torque_Nm(from_unit(angle, "deg"), f, tissue, capsule)
        (line,) = ax.plot(
            f,
            np.asarray(tau) * 1e3,
            label=f"model, α = {angle:g}°"
            + ("" if k < len(helical_angles_deg) else " (paper capsule's angle)"),
            linestyle=LINESTYLES[k % len(LINESTYLES)],
            marker="",
        )
        colours[float(angle)] = line.get_color()
        curves.append(line)
    for p in paper_points:
        colour = colours.get(float(p.helical_angle_deg), "k")
        calibration = p.role == "calibration"
        points.append(
            ax.scatter(
                [p.frequency_hz],
                [p.torque_mNm],
                color=colour if calibration else "white",
                marker="o" if calibration else "s",
                s=42,
                linewidths=1.4,
                zorder=3,
                edgecolors="k" if calibration else colour,
                label=f"paper, No. {p.capsule}, α = {p.helical_angle_deg:g}° ({p.role})",
            )
        )
    ax.set_xlabel(_FREQ_LABEL)
    ax.set_ylabel(_TORQUE_LABEL)
    ax.set_title(f"tissue {legend_tissue_name(tissue.name)}")
    _dedupe_legend(ax)
    return TorqueDrawn(curves, points)


def plot_fit(
    ax: Axes, fit_result: Any, *, frequency_hz: Sequence[float] | np.ndarray | None = None
) -> TorqueDrawn:
    """Measured points and the fitted model curve for each helical angle in a fit.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    fit_result : torque_model.FitResult
        The fit to show.
    frequency_hz : sequence of float, optional
        Frequencies of the model curves, Hz (default: the data range widened by 10 %).

    Returns
    -------
    TorqueDrawn
    """
    r = fit_result
    fmin, fmax = float(np.min(r.frequency_hz)), float(np.max(r.frequency_hz))
    f = np.asarray(
        frequency_hz if frequency_hz is not None else np.linspace(0.9 * fmin, 1.1 * fmax, 80),
        dtype=float,
    )
    curves, points = [], []
    for angle in np.unique(r.helical_angle_rad):
        sel = r.helical_angle_rad == angle
        deg = to_unit(float(angle), "deg")
        pts = ax.scatter(
            r.frequency_hz[sel], r.torque_Nm[sel] * 1e3, zorder=3, label=f"measured, α = {deg:.4g}°"
        )
        (line,) = ax.plot(
            f,
            np.asarray(r.predict_Nm(f, float(angle))) * 1e3,
            color=pts.get_facecolor()[0],
            label=f"fit, α = {deg:.4g}°",
        )
        points.append(pts)
        curves.append(line)
    ax.set_xlabel(_FREQ_LABEL)
    ax.set_ylabel(_TORQUE_LABEL)
    loose = ", ".join(n.split("_")[0] for n in r.not_pinned_down) or "none"
    ax.set_title(f"identified tissue (not pinned down: {loose})")
    ax.legend(fontsize="small")
    return TorqueDrawn(curves, points)


def save_figure(draw: Any, path: str, *args: Any, **kwargs: Any) -> Any:
    """Draw with ``draw(ax, *args, **kwargs)`` on a new Agg figure and write it atomically.

    Returns what ``draw`` returned.
    """
    from spiralcap.design import write_text_atomic

    data, drawn = figure_bytes(draw, path, *args, **kwargs)
    write_text_atomic(path, data)
    return drawn


def figure_bytes(draw: Any, path: str, *args: Any, **kwargs: Any) -> tuple[bytes, Any]:
    """The file :func:`save_figure` would write to ``path`` (format from its suffix), and what
    ``draw`` returned; for writing it together with other outputs, all or nothing."""
    import io

    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.4, 4.4), layout="constrained")
    ax = fig.add_subplot()
    drawn = draw(ax, *args, **kwargs)
    buf = io.BytesIO()
    suffix = str(path).rsplit(".", 1)[-1].lower() if "." in str(path) else "png"
    fig.savefig(buf, format=suffix, dpi=150)
    return buf.getvalue(), drawn


def _dedupe_legend(ax: Axes) -> None:
    handles, labels = ax.get_legend_handles_labels()
    seen: dict[str, Any] = {}
    for h, lab in zip(handles, labels, strict=True):
        seen.setdefault(lab, h)
    ax.legend(list(seen.values()), list(seen), fontsize="small")
