"""Figures of an uncertainty study: the margin's distribution with the failure region, and the
Sobol indices of the margin.

Each function takes an :class:`optimize.uncertainty.UncertaintyResult` and an ``ax``, and
returns what it drew. :func:`save_uncertainty_figure` puts both side by side in one file.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from spiralcap.figures.style import COLOURS, HATCHES, REPORT_RC


def plot_margin_distribution(ax: Any, result: Any) -> dict[str, Any]:
    """Histogram of the worst-case margin of the samples that do not fail (mN·m, density of the
    whole sample) and the CDF of the counted margin on a twin axis.

    The failure region (counted margin <= 0: step-out, or below the minimum strain, whose
    margin counts as min(margin, 0)) is shaded and hatched and names P(failure) and its parts;
    the 5th percentile and the nominal margin are marked. Returns the artists: ``hist``,
    ``cdf``, ``failure``, ``p05``, ``nominal``.
    """
    m = np.asarray(result.margins_Nm) * 1e3
    strains = np.asarray(getattr(result, "strains", np.zeros(0)))
    ok = m >= 0
    if strains.size == m.size:
        ok &= strains >= result.min_wall_strain
    shown = m[ok]  # only samples that do not fail are a margin (none: an empty histogram)
    lo, hi = np.percentile(m, [0.5, 99.95])
    span = max(hi - lo, 0.5)  # mN·m: every sample alike (all failed, counted as 0) still shows
    lo = min(lo, -0.05 * span)
    hi = max(hi, float(np.max(shown)) if shown.size else hi, 0.05 * span)
    bins = np.linspace(lo, hi, 80)
    # density over the whole sample: the bars' area is the share that does not fail (failed
    # samples are not a margin; their share is in the hatched region's label)
    weights = np.full(shown.size, 1.0 / (m.size * (bins[1] - bins[0])))
    _, _, hist = ax.hist(
        shown,
        bins=bins,
        weights=weights,
        color=COLOURS[0],
        alpha=0.55,
        label="samples that do not fail (histogram)",
    )
    ax.set_ylim(bottom=0.0)  # a density: none below 0, also with no sample to show
    fail = getattr(result, "failure", None)
    p_fail = fail.value if fail is not None else result.stepout_probability
    below = getattr(result, "below_min_strain", None)
    parts = f"step-out {100 * result.stepout_probability:.3g} %"
    if below is not None:
        parts += f", below min. strain {100 * below.value:.3g} %"
    failure = ax.axvspan(
        lo,
        0.0,
        facecolor="0.92",
        hatch="//",
        edgecolor="0.65",
        linewidth=0,
        zorder=0,
        label=f"failure: P = {100 * p_fail:.3g} % ({parts})",
    )
    p05 = result.margin_percentiles_Nm["p05"] * 1e3
    line_p05 = ax.axvline(
        p05, color=COLOURS[1], linestyle="--", label=f"p05 (counted) = {p05:.3g} mN·m"
    )
    nom = result.nominal_margin_Nm * 1e3  # NaN: no contact at the nominal lumen, no margin
    nom_label = "nominal: no contact, no margin" if np.isnan(nom) else f"nominal = {nom:.3g} mN·m"
    line_nom = ax.axvline(0.0 if np.isnan(nom) else nom, color="black", linestyle=":")
    line_nom.set_label(nom_label)
    line_nom.set_visible(not np.isnan(nom))
    ax.set_xlim(lo, hi)
    ax.set_xlabel("worst-case torque margin (mN·m)")
    ax.set_ylabel("probability density (1/mN·m)")
    twin = ax.twinx()
    xs = np.sort(m)
    ys = np.arange(1, xs.size + 1) / xs.size
    step = max(xs.size // 2000, 1)
    (cdf,) = twin.plot(
        xs[::step],
        ys[::step],
        color=COLOURS[2],
        linestyle="-",
        label="cumulative, counted margin (right axis)",
    )
    twin.set_ylim(0, 1.0)
    twin.set_ylabel("cumulative probability")
    twin.grid(False)
    handles = [hist[0], cdf, failure, line_p05, line_nom]
    ax.legend(
        handles,
        [h.get_label() for h in handles],
        loc="upper center",
        bbox_to_anchor=(0.5, -0.16),
        ncol=2,
        fontsize="small",
    )
    ax.set_title(
        f"margin over {result.samples} tissue samples ({result.method}); a failed sample "
        "counts as min(margin, 0)",
        fontsize="medium",
    )
    return {"hist": hist, "cdf": cdf, "failure": failure, "p05": line_p05, "nominal": line_nom}


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
    ax.set_xlabel("Sobol index of the counted margin\n(share of its variance)")
    ax.legend(loc="upper right", fontsize="small")
    ax.set_title(f"sensitivity ({s.base_samples} base samples)")
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
            fig = Figure(figsize=(11.0, 5.2), layout="constrained")
            ax1, ax2 = fig.subplots(1, 2, width_ratios=[1.4, 1.0])
            drawn = {**plot_margin_distribution(ax1, result), **plot_sobol(ax2, result)}
        else:  # one uncertain input (its index is 1) or none computed: no Sobol panel
            fig = Figure(figsize=(6.6, 5.2), layout="constrained")
            drawn = plot_margin_distribution(fig.subplots(), result)
        buf = io.BytesIO()
        suffix = str(path).rsplit(".", 1)[-1].lower() if "." in str(path) else "png"
        fig.savefig(buf, format=suffix, dpi=150)
    write_text_atomic(path, buf.getvalue())
    return drawn
