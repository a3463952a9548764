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
    "copper_mass_kg": ("copper (kg)", 1.0),
    "power_W": ("copper loss (W)", 1.0),
    "cvar05_Nm": ("CVaR₀.₀₅ (mN·m)", 1e3),  # of the margin: the mean of its worst 5 %
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
    regions: tuple[str, ...] = ()


class SweepDrawn(NamedTuple):
    """What :func:`draw_sweep` drew: its axes, and the margin map for two keys."""

    axes: list[Any]
    margin_map: MarginMapDrawn | None


#: Hatches of the regions where a named requirement fails (the step-out region is "xx").
REGION_HATCHES = ("///", "\\\\\\", "...", "++", "||", "--")


def plot_margin_map(
    ax: Axes,
    x: Any,
    y: Any,
    margin_Nm: Any,
    *,
    feasible: Any = None,
    failing: Any = None,
    xlabel: str = "",
    ylabel: str = "",
    marks: dict[str, tuple[float, float]] | None = None,
    colorbar: bool = True,
) -> MarginMapDrawn:
    """Worst-case margin over a grid of two variables, each failing requirement its own region.

    The colour levels span the margin over the feasible points (all levels go to designs that
    could be chosen); where the margin is negative the capsule steps out: one grey,
    cross-hatched region, not shades of red. Each other requirement that fails is hatched and
    named on the map where it fails.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    x, y : array_like, shapes (nx,) and (ny,)
        Grid coordinates, in the unit of the labels.
    margin_Nm : array_like, shape (ny, nx)
        Margin at each grid point, N·m (shown in mN·m).
    feasible : array_like of bool, shape (ny, nx), optional
        Whether every requirement holds.
    failing : array_like of str, shape (ny, nx), optional
        The requirement that fails at each point (``""``: none, or only the margin), e.g.
        :func:`spiralcap.feasibility.failing_requirements`; without it the infeasible points with
        a positive margin are hatched as "a requirement not met".
    xlabel, ylabel : str
        Axis labels with units.
    marks : mapping label -> (x, y), optional
        Points to mark (``{"optimum": (21.7, 0.67)}``): stars, then diamonds.
    colorbar : bool
        Add a colour bar of the margin.

    Returns
    -------
    MarginMapDrawn
        ``best`` marks the largest margin among the feasible grid points; ``infeasible`` is
        the list of hatched regions (step-out first), ``regions`` their names.
    """
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    from matplotlib.ticker import MaxNLocator

    xs = np.asarray(x, float)
    ys = np.asarray(y, float)
    m = np.asarray(margin_Nm, float) * 1e3
    ok = np.ones(m.shape, bool) if feasible is None else np.asarray(feasible, bool)
    if failing is None:
        names = np.where(~ok & (m >= 0), "a requirement not met", "").astype(object)
    else:
        names = np.asarray(failing, dtype=object)
    shown = ok if ok.any() else m >= 0
    lo = float(np.nanmin(m[shown])) if shown.any() else 0.0
    hi = float(np.nanmax(m)) if np.isfinite(np.nanmax(m)) else lo + 1.0
    lo = max(lo, 0.0)
    if hi - lo <= 1e-9 * max(abs(hi), 1.0):
        hi = lo + max(abs(lo) * 0.01, 1e-6)
    levels = np.asarray(MaxNLocator(nbins=10).tick_values(lo, hi), dtype=float)
    levels = levels[(levels >= 0.0) | (np.arange(levels.size) == 0)]
    if levels[0] < 0:
        levels[0] = 0.0
    # the whole grid: negative margins fall below the first level and the step-out region
    # is drawn over them, both bounded by the same interpolated zero line (no gap)
    filled = ax.contourf(
        xs,
        ys,
        m,
        levels=levels,
        cmap="viridis",
        extend="both" if levels[0] > 0 or (m < 0).any() else "max",
    )
    handles: list[Any] = []
    regions: list[Any] = []
    region_names: list[str] = []
    step_out = None
    if (m < 0).any():
        neg = ax.contourf(
            xs, ys, m, levels=[float(np.nanmin(m)) - 1.0, 0.0], colors=["0.82"], hatches=["xx"]
        )
        _hatch_edges(neg, "0.35")
        regions.append(neg)
        region_names.append("margin < 0: steps out")
        handles.append(
            Patch(facecolor="0.82", edgecolor="0.35", hatch="xx", label="margin < 0: steps out")
        )
        if (m > 0).any():
            step_out = ax.contour(xs, ys, m, levels=[0.0], colors="black", linewidths=2.2)
    distinct = [n for n in dict.fromkeys(names.ravel().tolist()) if n]
    for k, name in enumerate(distinct):
        mask = names == name
        hatch = REGION_HATCHES[k % len(REGION_HATCHES)]
        reg = ax.contourf(
            xs, ys, mask.astype(float), levels=[0.5, 1.5], colors="none", hatches=[hatch]
        )
        _hatch_edges(reg, "0.15")
        regions.append(reg)
        region_names.append(name)
        handles.append(Patch(facecolor="white", edgecolor="0.15", hatch=hatch, label=name))
        j, i = _inside_point(mask)
        ax.annotate(
            name,
            (xs[i], ys[j]),
            ha="center",
            va="center",
            fontsize=7.5,
            bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "0.3", "lw": 0.6},
        )
    if (m < 0).any():
        j, i = _inside_point(m < 0)
        ax.annotate(
            "steps out",
            (xs[i], ys[j]),
            ha="center",
            va="center",
            fontsize=7.5,
            bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "0.3", "lw": 0.6},
        )
    best = None
    if ok.any():
        masked = np.where(ok, m, -np.inf)
        jb, ib = np.unravel_index(int(np.argmax(masked)), m.shape)
        j, i = int(jb), int(ib)
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
        handles.append(Line2D([], [], color="black", linewidth=2.2, label="margin = 0 (step-out)"))
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(False)
    ax.legend(
        handles=handles,
        loc="upper center",
        bbox_to_anchor=(0.5, -0.16),
        ncols=2,
        fontsize=7.5,
        framealpha=0.92,
    )
    cbar = None
    if colorbar:
        cbar = ax.figure.colorbar(filled, ax=ax, label="worst-case margin (mN·m)")
    return MarginMapDrawn(
        filled, step_out, regions or None, best, drawn_marks, cbar, tuple(region_names)
    )


def _hatch_edges(contour: Any, colour: str) -> None:
    for coll in getattr(contour, "collections", [contour]):
        coll.set_edgecolor(colour)
        coll.set_linewidth(0.0)


def _inside_point(mask: np.ndarray) -> tuple[int, int]:
    """The grid index deepest inside ``mask`` (farthest from its edge): where to name it."""
    from scipy.ndimage import distance_transform_edt

    padded = np.pad(mask, 1, constant_values=False)
    depth = distance_transform_edt(padded)[1:-1, 1:-1]
    j, i = np.unravel_index(int(np.argmax(depth)), mask.shape)
    return int(j), int(i)


def _label(key: str) -> str:
    from spiralcap.presentation import unit_of_key

    unit = unit_of_key(key)
    return f"{key} ({unit})" if unit else key


def _fixed_copper(column: str, values: Any) -> bool:
    """The copper mass of hardware the sweep does not size (the same at every point): the
    table says it, a flat panel would not add to it."""
    if column != "copper_mass_kg":
        return False
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    return v.size == 0 or float(np.ptp(v)) <= 1e-9 * max(abs(float(v.mean())), 1e-30)


#: How the 1-key sweep figure names and hatches the grip regions (the ``grip`` column).
GRIP_REGIONS: dict[str, tuple[str, str, str]] = {
    "none": ("no contact: no margin, speed 0", "xx", "0.45"),
    "below minimum": ("wall strain below the minimum: extrapolated", "///", "0.6"),
}


def grip_spans(x: Any, grip: Any) -> list[tuple[str, float, float]]:
    """The runs of equal ``grip`` other than ``"ok"`` along increasing ``x``: (grip, lo, hi),
    each edge halfway to the neighbouring point of another grip (the ends at the first and
    last point)."""
    xs = np.asarray(x, float)
    g = np.asarray(grip, dtype=object)
    out: list[tuple[str, float, float]] = []
    i = 0
    while i < xs.size:
        j = i
        while j + 1 < xs.size and g[j + 1] == g[i]:
            j += 1
        if g[i] in GRIP_REGIONS:
            lo = xs[0] if i == 0 else 0.5 * (xs[i - 1] + xs[i])
            hi = xs[-1] if j == xs.size - 1 else 0.5 * (xs[j] + xs[j + 1])
            if hi == lo:  # a single point at an end: a sliver as wide as half a step
                step = float(np.median(np.diff(xs))) if xs.size > 1 else 1.0
                lo, hi = lo - 0.25 * step, hi + 0.25 * step
            out.append((str(g[i]), float(lo), float(hi)))
        i = j + 1
    return out


def _hatch_grip(axs: list[Any], x: Any, grip: Any) -> list[Any]:
    """Hatch the no-contact and below-minimum spans on every panel; legend handles for them."""
    from matplotlib.patches import Patch

    spans = grip_spans(x, grip)
    for ax in axs:
        for name, lo, hi in spans:
            _, hatch, colour = GRIP_REGIONS[name]
            ax.axvspan(lo, hi, facecolor="none", edgecolor=colour, hatch=hatch, lw=0, zorder=0)
    return [
        Patch(facecolor="white", edgecolor=GRIP_REGIONS[n][2], hatch=GRIP_REGIONS[n][1], label=t)
        for n, t in ((n, GRIP_REGIONS[n][0]) for n in dict.fromkeys(s[0] for s in spans))
    ]


def draw_sweep(fig: Any, result: Any, failing: Any = None) -> SweepDrawn:
    """The figure of a sweep (:class:`spiralcap.sweep.SweepResult`) on ``fig``.

    One swept key: each numeric output against it, stacked, infeasible points (or failed
    re-optimisations) as crosses, the spans with no contact (no margin, speed 0) and below the
    minimum wall strain (extrapolated) hatched and named (:data:`GRIP_REGIONS`). Two keys: the margin map (:func:`plot_margin_map`), the
    first key along x, each failing requirement named where ``failing`` (one name per point,
    :func:`spiralcap.sweep.failing_requirements`) gives it. More keys cannot be drawn on one
    figure.

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
        # points that could not be built (a row marked unbuildable): a grey dotted line each
        unbuilt = np.asarray(out.get("unbuildable", np.zeros(x.shape, bool)), bool)
        failed = ~ok & ~unbuilt
        cols = [c for c in SHOWN_COLUMNS if c in out and not _fixed_copper(c, out[c])]
        axs = list(np.atleast_1d(fig.subplots(len(cols), 1, sharex=True)))
        for k, (ax, col) in enumerate(zip(axs, cols, strict=True)):
            label, factor = SHOWN_COLUMNS[col]
            y = np.asarray(out[col], float) * factor
            ax.plot(x, np.where(ok, y, np.nan), **series_style(k))
            if failed.any():
                ax.plot(x[failed], y[failed], "x", color="#a4161a", markersize=8, markeredgewidth=2)
            for xu in x[unbuilt]:
                ax.axvline(float(xu), color="0.45", linestyle=":", linewidth=1.2)
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
        handles = _hatch_grip(axs, x, out["grip"]) if "grip" in out else []
        if (~ok).any():
            from matplotlib.lines import Line2D

            extra = []
            if failed.any():
                extra.append(
                    Line2D(
                        [],
                        [],
                        marker="x",
                        color="#a4161a",
                        linestyle="none",
                        label="infeasible (a requirement not met)",
                    )
                )
            if unbuilt.any():
                extra.append(
                    Line2D(
                        [],
                        [],
                        color="0.45",
                        linestyle=":",
                        label="cannot be built (unbuildable_reason)",
                    )
                )
            handles = extra + handles
        if handles:
            fig.legend(handles=handles, loc="outside upper center", ncols=2, fontsize=7.5)
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
            margin,  # NaN where the spiral does not touch: named there, not coloured
            feasible=ok,
            failing=None if failing is None else np.asarray(failing, object).reshape(nx, ny).T,
            xlabel=_label(kx),
            ylabel=_label(ky),
        )
        unbuilt = np.asarray(out.get("unbuildable", np.zeros(nx * ny, bool)), bool)
        if unbuilt.any():  # points that could not be built: grey squares, named in the legend
            gx, gy = np.meshgrid(axes[0].values, axes[1].values)
            mask = unbuilt.reshape(nx, ny).T
            (mark,) = ax.plot(
                gx[mask],
                gy[mask],
                "s",
                color="0.6",
                markeredgecolor="black",
                markersize=6,
                linestyle="none",
                label="cannot be built (unbuildable_reason)",
                clip_on=False,
                zorder=6,
            )
            old = ax.get_legend()
            ax.legend(
                handles=[*(old.legend_handles if old is not None else []), mark],
                loc="upper center",
                bbox_to_anchor=(0.5, -0.16),
                ncols=2,
                fontsize=7.5,
                framealpha=0.92,
            )
        return SweepDrawn([ax], drawn)
    raise ValueError("a sweep figure shows one or two swept keys")
