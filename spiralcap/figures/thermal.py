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

__all__ = ["HeatingDrawn", "WaveformsDrawn", "plot_heating_curves", "plot_waveforms"]


@dataclass(frozen=True)
class HeatingDrawn:
    """Artists of :func:`plot_heating_curves`."""

    hot_spot: tuple[Any, ...]
    mean: tuple[Any, ...]
    limit: Any
    session: Any | None


def plot_heating_curves(
    ax: Any,
    curves: Sequence[Any],
    *,
    limit_C: float,
    session_s: float | None = None,
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
    return HeatingDrawn(tuple(hot), tuple(mean), limit, session)


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
    current_limit_A: float | None = None,
    voltage_limit_V: float | None = None,
) -> WaveformsDrawn:
    """Currents, voltages and centre field of a heading sequence on three stacked axes.

    Parameters
    ----------
    axes : three matplotlib Axes
        Current, voltage and field panels (share x).
    w : coils.waveforms.Waveforms
    current_limit_A, voltage_limit_V : float, optional
        Limits drawn as ± dashed lines.
    """
    out = []
    t = w.time_s
    every = max(1, len(t) // 12)
    for ax, data, scale, label, lim in (
        (axes[0], w.current_A, 1.0, "coil current (A)", current_limit_A),
        (axes[1], w.voltage_V, 1.0, "drive voltage (V)", voltage_limit_V),
        (axes[2], w.field_T, 1e3, "centre field (mT)", None),
    ):
        lines = tuple(
            ax.plot(
                t,
                data[:, k] * scale,
                label=f"{'xyz'[k]}",
                linewidth=1.2,
                **series_style(k, markevery=every),
            )[0]
            for k in range(3)
        )
        if lim is not None:
            for sign in (1.0, -1.0):
                ax.axhline(sign * lim, color="0.2", linestyle="--", linewidth=1.2)
        ax.set_ylabel(label)
        out.append(lines)
    switches = tuple(
        ax.axvline(i * w.dwell_s, color="0.5", linestyle=":", linewidth=1.0)
        for ax in axes
        for i in range(1, len(w.headings))
    )
    axes[2].set_xlabel("time (s)")
    axes[0].legend(fontsize="small", loc="upper right", ncols=3)
    return WaveformsDrawn(out[0], out[1], out[2], switches)
