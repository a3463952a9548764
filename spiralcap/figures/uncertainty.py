"""Figures of an uncertainty study: the margin's distribution with the step-out region, and the
Sobol indices of the margin.

Each function takes an :class:`optimize.uncertainty.UncertaintyResult` and an ``ax``, and
returns what it drew. :func:`save_uncertainty_figure` puts both side by side in one file.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from spiralcap.figures.style import COLOURS, HATCHES, REPORT_RC


def plot_margin_distribution(ax: Any, result: Any) -> dict[str, Any]:
    """Histogram of the worst-case margin (mN·m, density) and its CDF on a twin axis.

    The step-out region (margin < 0) is shaded and hatched; the 5th percentile and the nominal
    margin are marked. Returns the artists: ``hist``, ``cdf``, ``stepout``, ``p05``, ``nominal``.
    """
    m = np.asarray(result.margins_Nm) * 1e3
    lo, hi = np.percentile(m, [0.5, 99.95])
    lo = min(lo, -0.05 * (hi - lo))
    bins = np.linspace(lo, hi, 80)
    # density of the whole sample (the tails beyond the shown range are left out, not piled up)
    weights = np.full(m.size, 1.0 / (m.size * (bins[1] - bins[0])))
    _, _, hist = ax.hist(
        m, bins=bins, weights=weights, color=COLOURS[0], alpha=0.55, label="samples (histogram)"
    )
    stepout = ax.axvspan(
        lo,
        0.0,
        facecolor="0.92",
        hatch="//",
        edgecolor="0.65",
        linewidth=0,
        zorder=0,
        label=f"step-out: P = {100 * result.stepout_probability:.3g} %",
    )
    p05 = result.margin_percentiles_Nm["p05"] * 1e3
    line_p05 = ax.axvline(p05, color=COLOURS[1], linestyle="--", label=f"p05 = {p05:.3g} mN·m")
    nom = result.nominal_margin_Nm * 1e3
    line_nom = ax.axvline(nom, color="black", linestyle=":", label=f"nominal = {nom:.3g} mN·m")
    ax.set_xlim(lo, hi)
    ax.set_xlabel("worst-case torque margin (mN·m)")
    ax.set_ylabel("probability density (1/mN·m)")
    twin = ax.twinx()
    xs = np.sort(m)
    ys = np.arange(1, xs.size + 1) / xs.size
    step = max(xs.size // 2000, 1)
    (cdf,) = twin.plot(
        xs[::step], ys[::step], color=COLOURS[2], linestyle="-", label="cumulative (right axis)"
    )
    twin.set_ylim(0, 1.0)
    twin.set_ylabel("cumulative probability")
    twin.grid(False)
    handles = [hist[0], cdf, stepout, line_p05, line_nom]
    ax.legend(handles, [h.get_label() for h in handles], loc="center left", fontsize="small")
    ax.set_title(
        f"margin over {result.samples} tissue samples ({result.method}); 0.5-99.95 % shown"
    )
    return {"hist": hist, "cdf": cdf, "stepout": stepout, "p05": line_p05, "nominal": line_nom}


def sobol_panel(result: Any) -> bool:
    """Whether a Sobol panel says anything: indices computed over two or more input groups.

    With one uncertain input its indices are 1 by construction (a single bar at 1).
    """
    return result.sobol is not None and len(result.sobol.inputs) >= 2


def plot_sobol(ax: Any, result: Any) -> dict[str, Any]:
    """First-order and total Sobol indices of the margin, horizontal bars with 95 % whiskers.

    Returns ``first_order`` and ``total`` (bar containers), or an empty dict without indices.
    """
    s = result.sobol
    if s is None:
        ax.text(0.5, 0.5, "Sobol indices not computed", ha="center", transform=ax.transAxes)
        ax.set_axis_off()
        return {}
    y = np.arange(len(s.inputs))
    h = 0.38
    first = ax.barh(
        y - h / 2,
        s.first_order,
        h,
        xerr=s.first_order_conf,
        color=COLOURS[0],
        hatch=HATCHES[0],
        edgecolor="black",
        label="first order",
        capsize=2,
    )
    total = ax.barh(
        y + h / 2,
        s.total,
        h,
        xerr=s.total_conf,
        color="white",
        hatch=HATCHES[1],
        edgecolor=COLOURS[1],
        label="total",
        capsize=2,
    )
    ax.set_yticks(y, [n.replace("_", " ") for n in s.inputs])
    ax.invert_yaxis()
    ax.set_xlim(min(0.0, float(np.min(s.first_order)) - 0.05), 1.05)
    ax.set_xlabel("Sobol index of the margin (share of variance)")
    ax.legend(loc="lower right", fontsize="small")
    ax.set_title(f"sensitivity (SALib, {s.base_samples} base samples)")
    return {"first_order": first, "total": total}


def save_uncertainty_figure(path: str, result: Any) -> dict[str, Any]:
    """The distribution and, with two or more uncertain inputs, the Sobol panel beside it,
    written atomically to ``path`` (png, pdf or svg)."""
    import io

    import matplotlib
    from matplotlib.figure import Figure

    from spiralcap.design import write_text_atomic

    with matplotlib.rc_context(REPORT_RC):
        if sobol_panel(result):
            fig = Figure(figsize=(11.0, 4.4), layout="constrained")
            ax1, ax2 = fig.subplots(1, 2, width_ratios=[1.4, 1.0])
            drawn = {**plot_margin_distribution(ax1, result), **plot_sobol(ax2, result)}
        else:  # one uncertain input (its index is 1) or none computed: no Sobol panel
            fig = Figure(figsize=(6.6, 4.4), layout="constrained")
            drawn = plot_margin_distribution(fig.subplots(), result)
        buf = io.BytesIO()
        suffix = str(path).rsplit(".", 1)[-1].lower() if "." in str(path) else "png"
        fig.savefig(buf, format=suffix, dpi=150)
    write_text_atomic(path, buf.getvalue())
    return drawn
