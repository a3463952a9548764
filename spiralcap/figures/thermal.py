"""Figures of the coils as they run: winding heating curves and amplifier waveforms.

Each function draws on the ``ax`` (or axes) it is given and returns a frozen record of what it
drew; the data are the typed results of :mod:`spiralcap.analysis.coils` and
:mod:`coils.waveforms`.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from spiralcap.figures.style import series_style

__all__ = [
    "HeatingDrawn",
    "WaveformSequenceDrawn",
    "WaveformsDrawn",
    "change_windows",
    "draw_waveform_sequence",
    "plot_heating_curves",
    "plot_waveforms",
]


@dataclass(frozen=True)
class HeatingDrawn:
    """Artists of :func:`plot_heating_curves`."""

    hot_spot: tuple[Any, ...]
    mean: tuple[Any, ...]
    limit: Any
    session: Any | None
    surface: tuple[Any, ...] = ()
    surface_limit: Any | None = None


def plot_heating_curves(
    ax: Any,
    curves: Sequence[Any],
    *,
    limit_C: float,
    session_s: float | None = None,
    surface_limit_C: float | None = None,
) -> HeatingDrawn:
    """Hot-spot and mean winding temperature of each pair against time from switch-on.

    Parameters
    ----------
    ax : matplotlib Axes
    curves : sequence of spiralcap.analysis.coils.HeatingCurve
        One per pair, at its operating current (conduction in the pack from ambient; τ in the
        legend is the lumped time constant of the mean rise).
    limit_C : float
        ``limits.coil_temperature_C`` (the hot-spot limit), °C; drawn as a horizontal line.
    session_s : float, optional
        Session length, s; drawn as a vertical line.
    surface_limit_C : float, optional
        ``limits.surface_temperature_C``, °C: with it, each pair's hottest surface point is drawn
        too (dash-dot-dot, the pair's colour) and the limit as a thick grey dotted line.
    """
    hot, mean = [], []
    for k, c in enumerate(curves):
        style = series_style(k, markevery=24)
        (h,) = ax.plot(
            c.time_s / 60.0,
            c.hot_spot_C,
            label=f"{c.axis} pair hot spot ({c.current_A:.3g} A, τ = {c.time_constant_s / 60:.3g} min)",
            **style,
        )
        (m,) = ax.plot(
            c.time_s / 60.0,
            c.mean_C,
            color=style["color"],
            linestyle=":",
            linewidth=1.2,
            label=f"{c.axis} pair mean",
        )
        hot.append(h)
        mean.append(m)
    surface: list[Any] = []
    surface_limit = None
    if surface_limit_C is not None:
        for h, c in zip(hot, curves, strict=True):
            if c.surface_max_C is None:
                continue
            (s,) = ax.plot(
                c.time_s / 60.0,
                c.surface_max_C,
                color=h.get_color(),
                linestyle=(0, (6, 2, 1, 2, 1, 2)),
                linewidth=1.1,
                label=f"{c.axis} pair hottest surface",
            )
            surface.append(s)
        surface_limit = ax.axhline(
            surface_limit_C,
            color="0.6",
            linestyle=(0, (1.5, 1.0)),
            linewidth=2.6,
            label="surface limit",
        )
    limit = ax.axhline(limit_C, color="0.2", linestyle="--", linewidth=1.4, label="hot-spot limit")
    session = None
    if session_s is not None:
        session = ax.axvline(
            session_s / 60.0, color="0.4", linestyle="-.", linewidth=1.4, label="end of session"
        )
    ax.set_xlabel("time from switch-on at ambient (min)")
    ax.set_ylabel("winding temperature (°C)")
    ax.set_xlim(0.0, max(float(c.time_s[-1]) for c in curves) / 60.0)
    ax.legend(fontsize="small", loc="lower right")
    return HeatingDrawn(tuple(hot), tuple(mean), limit, session, tuple(surface), surface_limit)


@dataclass(frozen=True)
class WaveformsDrawn:
    """Artists of :func:`plot_waveforms` (per panel, one line per axis)."""

    current: tuple[Any, ...]
    voltage: tuple[Any, ...]
    field: tuple[Any, ...]
    switches: tuple[Any, ...]


def plot_waveforms(
    axes: Sequence[Any],
    w: Any,
    *,
    current_limit_A: Any = None,
    voltage_limit_V: Any = None,
    window_s: tuple[float, float] | None = None,
) -> WaveformsDrawn:
    """Currents, voltages and centre field of a heading sequence on three stacked axes.

    Parameters
    ----------
    axes : three matplotlib Axes
        Current, voltage and field panels (share x).
    w : coils.waveforms.Waveforms
    current_limit_A, voltage_limit_V : float or sequence of 3 floats, optional
        Limits drawn as ± dashed lines (one per pair, in its colour, where the pairs' own
        amplifier channels differ).
    window_s : (float, float), optional
        Draw only the samples in this time window, s (a few cycles: the phases can be read).
    """
    import numpy as np

    out = []
    t = w.time_s
    sel = np.ones(t.size, bool) if window_s is None else (t >= window_s[0]) & (t <= window_s[1])
    t = t[sel]
    every = max(1, len(t) // 12)
    for ax, data, scale, label, lim in (
        (axes[0], w.current_A, 1.0, "coil current (A)", current_limit_A),
        (axes[1], w.voltage_V, 1.0, "drive voltage (V)", voltage_limit_V),
        (axes[2], w.field_T, 1e3, "centre field (mT)", None),
    ):
        lines = tuple(
            ax.plot(
                t,
                data[sel, k] * scale,
                label=f"{'xyz'[k]}",
                linewidth=1.2,
                **series_style(k, markevery=every),
            )[0]
            for k in range(3)
        )
        for _k, value, colour in _limit_lines(lim):
            for sign in (1.0, -1.0):
                ax.axhline(sign * value, color=colour, linestyle="--", linewidth=1.2)
        ax.set_ylabel(label)
        out.append(lines)
    switches = tuple(
        ax.axvline(i * w.dwell_s, color="0.5", linestyle=":", linewidth=1.0)
        for ax in axes
        for i in range(1, len(w.headings))
        if window_s is None or window_s[0] <= i * w.dwell_s <= window_s[1]
    )
    if window_s is not None:
        for ax in axes:
            ax.set_xlim(max(window_s[0], float(w.time_s[0])), min(window_s[1], float(w.time_s[-1])))
    axes[2].set_xlabel("time (s)")
    axes[0].legend(fontsize="small", loc="upper right", ncols=3)
    return WaveformsDrawn(out[0], out[1], out[2], switches)


def _limit_lines(limit: Any) -> list[tuple[int | None, float, str]]:
    """The limit lines to draw: one grey line for one limit (or three equal ones), else one per
    pair in its colour (each pair on its own amplifier channel): ``(pair or None, value,
    colour)``."""
    import numpy as np

    if limit is None:
        return []
    values = [float(v) for v in np.atleast_1d(np.asarray(limit, dtype=float))]
    if len(set(values)) == 1:
        return [(None, values[0], "0.2")]
    return [(k, v, series_style(k)["color"]) for k, v in enumerate(values)]


@dataclass(frozen=True)
class WaveformSequenceDrawn:
    """Artists of :func:`draw_waveform_sequence`: the overview and one record per window."""

    overview: tuple[Any, ...]
    windows: tuple[WaveformsDrawn, ...]
    window_s: tuple[tuple[float, float], ...]


#: At most this many plane changes get a panel of their own (the overview shows them all).
MAX_CHANGE_PANELS = 4


def change_windows(w: Any, cycles: float = 1.5) -> list[tuple[float, float]]:
    """Time windows (s) of a few cycles around each plane change (the start when none).

    Each runs from ``cycles`` periods before the change to ``cycles`` periods after its ramp.
    """
    period = 1.0 / float(w.frequency_hz)
    t_end = float(w.time_s[-1])
    changes = [i * float(w.dwell_s) for i in range(1, len(w.headings))][:MAX_CHANGE_PANELS]
    if not changes:
        return [(0.0, min(t_end, 3.0 * period))]
    return [
        (max(0.0, c - cycles * period), min(t_end, c + float(w.ramp_s) + cycles * period))
        for c in changes
    ]


def draw_waveform_sequence(
    fig: Any,
    w: Any,
    *,
    current_limit_A: Any = None,
    voltage_limit_V: Any = None,
) -> WaveformSequenceDrawn:
    """An overview of the whole sequence and, below, a few cycles around each plane change.

    The overview draws each pair's current amplitude (the largest |I| over the last period)
    against time, so every plane change reads as one step; below, one column per change
    (at most :data:`MAX_CHANGE_PANELS`) shows current, voltage and field over a few cycles
    around it, where phases and the ramp can be read.
    """
    from matplotlib.ticker import MaxNLocator
    from scipy.ndimage import maximum_filter1d

    top, bottom = fig.subfigures(2, 1, height_ratios=(1.0, 2.6))
    ov = top.subplots(1, 2)
    t = w.time_s
    dt = float(t[1] - t[0]) if t.size > 1 else 1.0
    n_period = max(1, round(1.0 / (float(w.frequency_hz) * dt)))
    overview = []
    for ax, data, label, lim in (
        (ov[0], w.current_A, "current amplitude (A)", current_limit_A),
        (ov[1], w.voltage_V, "voltage amplitude (V)", voltage_limit_V),
    ):
        for k in range(3):
            env = maximum_filter1d(abs(data[:, k]), size=n_period, origin=(n_period - 1) // 2)
            overview.append(
                ax.plot(
                    t,
                    env,
                    label=f"{'xyz'[k]} pair",
                    linewidth=1.4,
                    **series_style(k, markevery=max(1, t.size // 10)),
                )[0]
            )
        for pair, value, colour in _limit_lines(lim):
            ax.axhline(
                value,
                color=colour,
                linestyle="--",
                linewidth=1.2,
                label="limit" if pair is None else f"{'xyz'[pair]} pair's limit",
            )
        for i in range(1, len(w.headings)):
            ax.axvline(i * w.dwell_s, color="0.5", linestyle=":", linewidth=1.0)
            if i <= MAX_CHANGE_PANELS:
                ax.annotate(
                    f"change {i}",
                    (i * w.dwell_s, 0.55),
                    xycoords=("data", "axes fraction"),
                    xytext=(0, 0),
                    textcoords="offset points",
                    ha="center",
                    va="center",
                    fontsize=7.5,
                    bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "0.5", "lw": 0.6},
                )
        ax.set_xlabel("time (s)")
        ax.set_ylabel(label)
        ax.set_ylim(bottom=0.0)
    ov[0].legend(fontsize="small", loc="lower left", ncols=2)
    top.suptitle(
        f"overview: {len(w.headings)} heading{'s' if len(w.headings) > 1 else ''}, "
        f"{w.dwell_s:g} s each "
        "(amplitude over the last period)",
        fontsize=10,
    )
    windows = change_windows(w)
    grid = bottom.subplots(3, len(windows), sharey="row", squeeze=False)
    drawn = []
    for j, win in enumerate(windows):
        col = grid[:, j]
        drawn.append(
            plot_waveforms(
                col,
                w,
                current_limit_A=current_limit_A,
                voltage_limit_V=voltage_limit_V,
                window_s=win,
            )
        )
        title = f"change {j + 1} at {(j + 1) * w.dwell_s:g} s" if len(w.headings) > 1 else "start"
        col[0].set_title(title, fontsize=9.5)
        change = (j + 1) * float(w.dwell_s)
        for ax in col:
            ax.xaxis.set_major_locator(MaxNLocator(4))
            if len(w.headings) > 1:
                ax.axvspan(change, change + float(w.ramp_s), color="0.9", zorder=0, lw=0)
            if j > 0:
                ax.set_ylabel("")
        legend = col[0].get_legend()
        if legend is not None:  # the overview's legend names the pairs
            legend.remove()
    more = len(w.headings) - 1 - len(windows)
    bottom.suptitle(
        (
            f"a few cycles around each plane change (shaded: the {w.ramp_s:g} s ramp)"
            if len(w.headings) > 1
            else "the first cycles (one heading: no plane change)"
        )
        + (f"; {more} later changes in the overview only" if more > 0 else ""),
        fontsize=10,
    )
    return WaveformSequenceDrawn(tuple(overview), tuple(drawn), tuple(windows))
