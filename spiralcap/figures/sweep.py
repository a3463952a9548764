"""Sweep figures: outputs against one swept key, or a margin map over two.

:func:`plot_margin_map` draws the worst-case margin over a grid of two variables as filled
contours, hatches where a requirement is not met, draws the zero-margin (step-out) boundary
thick and marks the best feasible point (and, optionally, the design and the optimiser's
point). :func:`draw_sweep` turns a :class:`spiralcap.sweep.SweepResult` into the figure
``spiralcap sweep --plot`` writes: one key -> the outputs against it, stacked; two keys -> the
margin map. Values arrive in SI (as the sweep holds them) and are shown in mN·m, mT, mm/s.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from matplotlib.axes import Axes

from spiralcap.figures.style import COLOURS, series_style

__all__ = ["MarginMapDrawn", "SweepDrawn", "draw_sweep", "plot_margin_map"]

#: Output column -> (axis label, factor from SI).
SHOWN_COLUMNS: dict[str, tuple[str, float]] = {
    "margin_Nm": ("margin (mN·m)", 1e3),
    "safety_factor": ("safety factor", 1.0),
    "field_amplitude_T": ("field (mT)", 1e3),
    "speed_m_s": ("speed (mm/s)", 1e3),
    "helical_angle_deg": ("α (deg)", 1.0),
    "frequency_hz": ("f (Hz)", 1.0),
}


class MarginMapDrawn(NamedTuple):
    """What :func:`plot_margin_map` drew (None where not drawn)."""

    filled: Any
    step_out: Any
    infeasible: Any
    best: Any
    marks: list[Any]
    colorbar: Any


class SweepDrawn(NamedTuple):
    """What :func:`draw_sweep` drew: its axes, and the margin map for two keys."""

    axes: list[Any]
    margin_map: MarginMapDrawn | None


def plot_margin_map(
    ax: Axes,
    x: Any,
    y: Any,
    margin_Nm: Any,
    *,
    feasible: Any = None,
    xlabel: str = "",
    ylabel: str = "",
    marks: dict[str, tuple[float, float]] | None = None,
    colorbar: bool = True,
) -> MarginMapDrawn:
    """Worst-case margin over a grid of two variables, with the infeasible region hatched.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    x, y : array_like, shapes (nx,) and (ny,)
        Grid coordinates, in the unit of the labels.
    margin_Nm : array_like, shape (ny, nx)
        Margin at each grid point, N·m (shown in mN·m).
    feasible : array_like of bool, shape (ny, nx), optional
        Whether every requirement holds; the rest is hatched.
    xlabel, ylabel : str
        Axis labels with units.
    marks : mapping label -> (x, y), optional
        Points to mark (``{"optimum": (21.7, 0.67)}``): stars, then diamonds.
    colorbar : bool
        Add a colour bar of the margin.

    Returns
    -------
    MarginMapDrawn
        ``best`` marks the largest margin among the feasible grid points.
    """
    xs = np.asarray(x, float)
    ys = np.asarray(y, float)
    from matplotlib.colors import TwoSlopeNorm
    from matplotlib.ticker import MaxNLocator

    m = np.asarray(margin_Nm, float) * 1e3
    lo, hi = float(np.nanmin(m)), float(np.nanmax(m))
    lo, hi = min(lo, -1e-3 * abs(hi) - 1e-12), max(hi, 1e-3 * abs(lo) + 1e-12)
    levels = MaxNLocator(nbins=18).tick_values(lo, hi)
    norm = TwoSlopeNorm(0.0, vmin=float(levels[0]), vmax=float(levels[-1]))
    filled = ax.contourf(xs, ys, m, levels=levels, cmap="RdBu", norm=norm, extend="both")
    step_out = None
    if np.nanmin(m) < 0 < np.nanmax(m):
        step_out = ax.contour(xs, ys, m, levels=[0.0], colors="black", linewidths=2.2)
        ax.clabel(step_out, fmt={0.0: "margin 0 (step-out)"}, fontsize=7.5)
    infeasible = best = None
    ok = np.ones(m.shape, bool) if feasible is None else np.asarray(feasible, bool)
    if (~ok).any():
        infeasible = ax.contourf(
            xs,
            ys,
            (~ok).astype(float),
            levels=[0.5, 1.5],
            colors="none",
            hatches=["///"],
        )
        for coll in getattr(infeasible, "collections", [infeasible]):
            coll.set_edgecolor("0.25")
            coll.set_linewidth(0.0)
    handles: list[Any] = []
    from matplotlib.patches import Patch

    if infeasible is not None:
        handles.append(
            Patch(facecolor="white", edgecolor="0.25", hatch="///", label="a requirement not met")
        )
    if ok.any():
        masked = np.where(ok, m, -np.inf)
        j, i = np.unravel_index(int(np.argmax(masked)), m.shape)
        (best,) = ax.plot(
            [xs[i]],
            [ys[j]],
            marker="o",
            markersize=9,
            markerfacecolor="white",
            markeredgecolor="black",
            markeredgewidth=1.6,
            linestyle="none",
            label=f"best feasible grid point, {m[j, i]:.3g} mN·m",
        )
        handles.append(best)
    drawn_marks = []
    for k, (label, (px, py)) in enumerate((marks or {}).items()):
        (mk,) = ax.plot(
            [px],
            [py],
            marker="*" if k == 0 else "D",
            markersize=15 if k == 0 else 8,
            color=COLOURS[(k + 1) % len(COLOURS)],
            markeredgecolor="black",
            linestyle="none",
            label=label,
        )
        drawn_marks.append(mk)
        handles.append(mk)
    if step_out is not None:
        from matplotlib.lines import Line2D

        handles.append(Line2D([], [], color="black", linewidth=2.2, label="margin = 0 (step-out)"))
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(False)
    ax.legend(handles=handles, loc="upper right", fontsize=7.5, framealpha=0.92)
    cbar = None
    if colorbar:
        cbar = ax.figure.colorbar(filled, ax=ax, label="worst-case torque margin (mN·m)")
    return MarginMapDrawn(filled, step_out, infeasible, best, drawn_marks, cbar)


def _label(key: str) -> str:
    from spiralcap.presentation import unit_of_key

    unit = unit_of_key(key)
    return f"{key} ({unit})" if unit else key


def draw_sweep(fig: Any, result: Any) -> SweepDrawn:
    """The figure of a sweep (:class:`spiralcap.sweep.SweepResult`) on ``fig``.

    One swept key: each numeric output against it, stacked, infeasible points (or failed
    re-optimisations) as crosses. Two keys: the margin map (:func:`plot_margin_map`), the
    first key along x. More keys cannot be drawn on one figure.

    Raises
    ------
    ValueError
        More than two swept keys.
    """
    axes = result.axes
    out = result.outputs
    if len(axes) == 1:
        key = axes[0].key
        x = np.asarray(result.inputs[key], float)
        if "feasible" in out:
            ok = np.asarray(out["feasible"], bool)
        else:
            ok = np.asarray(out["status"]) == "optimal"
        cols = [c for c in SHOWN_COLUMNS if c in out]
        axs = list(np.atleast_1d(fig.subplots(len(cols), 1, sharex=True)))
        for k, (ax, col) in enumerate(zip(axs, cols, strict=True)):
            label, factor = SHOWN_COLUMNS[col]
            y = np.asarray(out[col], float) * factor
            ax.plot(x, np.where(ok, y, np.nan), **series_style(k))
            if (~ok).any():
                ax.plot(x[~ok], y[~ok], "x", color="#a4161a", markersize=8, markeredgewidth=2)
            if col == "margin_Nm":
                ax.axhline(0.0, color="black", linewidth=1.0)
            finite = y[np.isfinite(y)]
            if finite.size and float(np.ptp(finite)) <= 1e-6 * max(
                abs(float(finite.mean())), 1e-30
            ):
                # a constant output: a flat line at its value, not an axis of rounding noise
                mid = float(finite.mean())
                ax.set_ylim(mid - 0.05 * abs(mid) - 1e-12, mid + 0.05 * abs(mid) + 1e-12)
            ax.ticklabel_format(axis="y", useOffset=False, style="plain")
            ax.set_ylabel(label, fontsize=8.5)
        axs[-1].set_xlabel(_label(key))
        if (~ok).any():
            from matplotlib.lines import Line2D

            axs[0].legend(
                handles=[
                    Line2D(
                        [],
                        [],
                        marker="x",
                        color="#a4161a",
                        linestyle="none",
                        label="infeasible (a requirement not met)",
                    )
                ],
                loc="best",
                fontsize=7.5,
            )
        return SweepDrawn(axs, None)
    if len(axes) == 2:
        kx, ky = axes[0].key, axes[1].key
        nx, ny = len(axes[0].values), len(axes[1].values)
        # the grid is flattened in C order over (first key, second key)
        margin = np.asarray(out["margin_Nm"], float).reshape(nx, ny).T
        if "feasible" in out:
            ok = np.asarray(out["feasible"], bool).reshape(nx, ny).T
        else:
            ok = (np.asarray(out["status"]) == "optimal").reshape(nx, ny).T
        ax = fig.subplots()
        drawn = plot_margin_map(
            ax,
            np.asarray(axes[0].values, float),
            np.asarray(axes[1].values, float),
            np.nan_to_num(margin, nan=float(np.nanmin(margin))),
            feasible=ok,
            xlabel=_label(kx),
            ylabel=_label(ky),
        )
        return SweepDrawn([ax], drawn)
    raise ValueError("a sweep figure shows one or two swept keys")
