"""Design figures: margin against frequency, helical angle and power budget; limits; torques.

Every function is ``plot_xxx(ax, <arrays or result objects>, ...)``: it draws on ``ax``, labels
the axes with units (mN·m, Hz, deg, W) and returns a NamedTuple of what it drew. Inputs are in SI as
the result objects hold them (N·m, Hz, W); the conversion to engineering units happens here.
Series differ by line style and marker as well as colour, so the figures read in grey print.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np
from matplotlib.axes import Axes
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

from spiralcap.figures.style import COLOURS, HATCHES, series_style

__all__ = [
    "BudgetDrawn",
    "MarginAngleDrawn",
    "MarginFrequencyDrawn",
    "PowerDrawn",
    "UtilisationDrawn",
    "plot_limit_utilisation",
    "plot_margin_vs_angle",
    "plot_margin_vs_frequency",
    "plot_margin_vs_power",
    "plot_torque_budget",
    "shortfall_spans",
]

_MNM = 1e3  # N·m -> mN·m
_MARGIN_LABEL = "worst-case torque margin (mN·m)"


class MarginFrequencyDrawn(NamedTuple):
    """What :func:`plot_margin_vs_frequency` drew (None where not drawn)."""

    line: Any
    infeasible: Any
    zero: Any
    step_out: Any
    operating: Any
    below_zero: Any
    max_frequency: Any = None


class MarginAngleDrawn(NamedTuple):
    """What :func:`plot_margin_vs_angle` drew: the curve and one shaded span per shortfall."""

    line: Any
    zero: Any
    optimum: Any
    design: Any
    shortfalls: tuple[Any, ...]


class PowerDrawn(NamedTuple):
    """What :func:`plot_margin_vs_power` drew."""

    front: Any
    infeasible: Any
    design: Any
    labels: list[Any]


class UtilisationDrawn(NamedTuple):
    """What :func:`plot_limit_utilisation` drew; ``percent`` holds the utilisations, %."""

    bars: Any
    limit: Any
    labels: list[Any]
    percent: tuple[float, ...]


class BudgetDrawn(NamedTuple):
    """What :func:`plot_torque_budget` drew."""

    magnetic: Any
    resistive: Any
    thrust: Any
    margins: list[Any]


def shortfall_spans(x: Any, slack: Any) -> list[tuple[float, float]]:
    """Intervals of ``x`` where ``slack < 0``, edges at the linearly interpolated zero crossings.

    Parameters
    ----------
    x : array_like, shape (n,)
        Increasing abscissa.
    slack : array_like, shape (n,)
        Requirement slack (achieved - needed); negative where the requirement fails.
    """
    xs = np.asarray(x, dtype=float)
    sl = np.asarray(slack, dtype=float)
    bad = sl < 0
    spans = []
    i = 0
    while i < len(xs):
        if not bad[i]:
            i += 1
            continue
        j = i
        while j + 1 < len(xs) and bad[j + 1]:
            j += 1
        lo = xs[0] if i == 0 else _crossing(xs[i - 1], xs[i], sl[i - 1], sl[i])
        hi = xs[-1] if j == len(xs) - 1 else _crossing(xs[j], xs[j + 1], sl[j], sl[j + 1])
        spans.append((float(lo), float(hi)))
        i = j + 1
    return spans


def _crossing(x0: float, x1: float, y0: float, y1: float) -> float:
    return x0 if y1 == y0 else x0 + (x1 - x0) * (0.0 - y0) / (y1 - y0)


def _get(obj: Any, name: str) -> Any:
    """Field ``name`` of a result object or of its JSON dict (``spiralcap.serialize``)."""
    if isinstance(obj, Mapping):
        return obj[name]
    return getattr(obj, name)


def _has(obj: Any, name: str) -> bool:
    """Whether a result object or its JSON dict has a finite number ``name``."""
    value = obj.get(name) if isinstance(obj, Mapping) else getattr(obj, name, None)
    return isinstance(value, (int, float)) and bool(np.isfinite(value))


def plot_margin_vs_frequency(
    ax: Axes,
    frequency_hz: Any,
    margin_Nm: Any,
    *,
    feasible: Any = None,
    step_out_frequency_hz: float | None = None,
    operating_frequency_hz: float | None = None,
    label: str = "margin",
    style_index: int = 0,
    shade: bool = True,
    max_frequency_hz: float | None = None,
    max_frequency_limited_by: str = "",
    grip: str = "ok",
) -> MarginFrequencyDrawn:
    """Worst-case torque margin against rotation frequency at one helical angle.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    frequency_hz : array_like, shape (n,)
        Rotation frequencies, Hz.
    margin_Nm : array_like, shape (n,)
        Margin (synchronous magnetic torque minus required torque) at each frequency, N·m, e.g.
        ``optimize.margin_grid(model, alpha, f)["margin_Nm"]``.
    feasible : array_like of bool, shape (n,), optional
        Whether every requirement holds at this curve's own helical angle; the part of this
        curve where one fails is drawn thin and dotted (each curve carries its own feasibility,
        so an operating point is never drawn inside another curve's infeasible range).
    step_out_frequency_hz : float, optional
        Where the capsule steps out at the operating field (``Evaluation.step_out_frequency_hz``:
        the magnet's largest synchronous torque at that field equals the required torque), Hz;
        marked with a dashed vertical line and its value.
    operating_frequency_hz : float, optional
        The operating (or optimal) frequency, Hz; marked on the curve.
    label : str
        Legend label of the curve.
    style_index : int
        Series number for colour, line style and marker (several calls on one axes).
    shade : bool
        Hatch the region below zero margin (the capsule steps out there, whatever the curve);
        only the first of several curves should.
    max_frequency_hz : float, optional
        The drive's largest frequency with a positive margin, the field re-maximised at every
        frequency (``Evaluation.max_frequency_hz``; where this curve, drawn at the largest
        field the limits allow, crosses zero), Hz; marked with a dash-dot vertical line.
    max_frequency_limited_by : str
        What limits the field there (``Evaluation.max_frequency_limited_by``), for the label.
    grip : str
        The grip at this curve's helical angle (``optimize.grip_state``; the same at every
        frequency): ``"none"`` (no contact: no margin, the whole width hatched and named, the
        curve absent) or ``"below minimum"`` (the strain below the requirement: the model
        extrapolates; hatched and named), ``"ok"`` draws nothing more.

    Returns
    -------
    MarginFrequencyDrawn
    """
    f = np.asarray(frequency_hz, dtype=float)
    m = np.asarray(margin_Nm, dtype=float) * _MNM
    style = series_style(style_index, markevery=max(1, len(f) // 10))
    ok = np.ones(f.shape, bool) if feasible is None else np.asarray(feasible, dtype=bool)
    # feasible part solid with markers; the rest (extended by one point so the two parts
    # join) thin and dotted in the same colour
    solid = np.where(ok, m, np.nan)
    drawn = bool(np.isfinite(m).any())  # no contact at this angle: no curve to name
    (line,) = ax.plot(f, solid, label=label if drawn else f"_{label}", **style)
    bad_line = None
    if (~ok).any() and drawn:
        grown = ~ok | np.roll(~ok, 1) | np.roll(~ok, -1)
        bad_line = ax.plot(
            f,
            np.where(grown, m, np.nan),
            color=style["color"],
            linestyle=(0, (1, 1.2)),
            linewidth=1.3,
            label=f"{label}: a requirement not met",
        )[0]
    zero = ax.axhline(0.0, color="black", linewidth=1.0)
    _grip_region(ax, f, grip, label, style_index)
    below = None
    if shade:
        below = ax.axhspan(
            -1e9,
            0.0,
            facecolor="none",
            edgecolor="0.7",
            hatch="//",
            linewidth=0.0,
            label="margin < 0: the capsule steps out",
            zorder=0,
        )
    step_out = operating = None
    if (
        step_out_frequency_hz is not None
        and np.isfinite(step_out_frequency_hz)
        and step_out_frequency_hz > 0
    ):
        step_out = ax.axvline(
            step_out_frequency_hz,
            color=style["color"],
            linestyle=(0, (4, 2)),
            linewidth=1.2,
            label=f"step-out at the operating field, {step_out_frequency_hz:.3g} Hz",
        )
    max_line = None
    if max_frequency_hz is not None and np.isfinite(max_frequency_hz) and max_frequency_hz > 0:
        from spiralcap.presentation import readable

        by = f", {readable(max_frequency_limited_by)} limit" if max_frequency_limited_by else ""
        max_line = ax.axvline(
            max_frequency_hz,
            color=style["color"],
            linestyle=(0, (7, 2, 1.5, 2)),
            linewidth=1.6,
            label=f"drive's max. frequency, {max_frequency_hz:.3g} Hz{by}",
        )
    # each vertical line named on the line itself and capped with its curve's marker, so the
    # four lines of two curves read apart in greyscale print too
    short = label.split(",")[0]
    for x_line, what in ((step_out_frequency_hz, "step-out"), (max_frequency_hz, "drive max.")):
        if x_line is None or not np.isfinite(x_line) or x_line <= 0:
            continue
        x = float(x_line)
        ax.annotate(
            f"{what}, {short}: {x:.3g} Hz",
            (x, 0.98),
            xycoords=("data", "axes fraction"),
            xytext=(-2, 0),
            textcoords="offset points",
            rotation=90,
            ha="right",
            va="top",
            fontsize=7,
            color="0.1",
            bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.85},
        )
        ax.plot(
            [x],
            [1.0],
            transform=ax.get_xaxis_transform(),
            marker=style["marker"],
            color=style["color"],
            markeredgecolor="black",
            markersize=7,
            linestyle="none",
            clip_on=False,
            zorder=6,
        )
    if operating_frequency_hz is not None and drawn:
        y = float(np.interp(operating_frequency_hz, f, m))
        (operating,) = ax.plot(
            [operating_frequency_hz],
            [y],
            linestyle="none",
            marker="*",
            markersize=14,
            color=style["color"],
            markeredgecolor="black",
            label=f"operating point, {operating_frequency_hz:.3g} Hz",
            zorder=5,
        )
    finite = m[np.isfinite(m)]
    if finite.size:
        top, bottom = float(finite.max()), float(finite.min())
        span = max(top - min(bottom, 0.0), 1e-9)
        lo = max(bottom, -0.6 * max(top, span * 0.3))
        ax.set_ylim(min(lo, 0.0) - 0.05 * span, top + 0.12 * span)
    ax.set_xlim(float(f.min()), float(f.max()))
    ax.set_xlabel("rotation frequency f (Hz)")
    ax.set_ylabel(_MARGIN_LABEL)
    ax.legend(loc="best", fontsize=7.5)
    return MarginFrequencyDrawn(line, bad_line, zero, step_out, operating, below, max_line)


#: The grip regions of a margin-against-frequency curve: grip -> (words, hatch, edge colour).
_GRIP_REGION = {
    "none": ("no contact with the wall: no margin", "xx", "0.82"),
    "below minimum": ("wall strain below the minimum: extrapolated", "\\\\", "0.6"),
}


def _grip_region(ax: Axes, f: np.ndarray, grip: str, label: str, style_index: int) -> Any:
    """Hatch the curve's whole frequency range where its angle does not grip, named in the
    legend and on the axes (the grip does not depend on frequency)."""
    if grip not in _GRIP_REGION:
        return None
    words, hatch, edge = _GRIP_REGION[grip]
    short = label.split(",")[-1].strip() or label
    span = ax.axvspan(
        float(f.min()),
        float(f.max()),
        facecolor="none",
        edgecolor=edge,
        hatch=hatch,
        linewidth=0.0,
        label=f"{short}: {words}",
        zorder=0,
    )
    ax.annotate(
        f"{short}: {words}",
        (0.5, 0.62 - 0.1 * style_index),
        xycoords="axes fraction",
        ha="center",
        va="center",
        fontsize=8,
        bbox={"boxstyle": "round,pad=0.25", "fc": "white", "ec": "0.3", "lw": 0.6},
    )
    return span


def plot_margin_vs_angle(
    ax: Axes,
    helical_angle_deg: Any,
    margin_Nm: Any,
    *,
    shortfalls: Mapping[str, Any] | None = None,
    optimum_deg: float | None = None,
    optimum_margin_Nm: float | None = None,
    design_angle_deg: float | None = None,
    label: str = "margin",
    style_index: int = 0,
    optimum_name: str = "optimum",
) -> MarginAngleDrawn:
    """Worst-case torque margin against the spiral's helical angle at one frequency.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    helical_angle_deg : array_like, shape (n,)
        Helical angles, deg.
    margin_Nm : array_like, shape (n,)
        Margin at each angle, N·m.
    shortfalls : mapping label -> array_like, optional
        Slack of each requirement along the curve (achieved - needed, any unit; negative where
        it fails), e.g. ``{"speed below the minimum": speed - v_min}``. Each failing range is
        shaded with its own hatch and named in the legend; the edges are the interpolated
        zero crossings, so an optimum on a binding requirement sits on an edge, not inside.
    optimum_deg, optimum_margin_Nm : float, optional
        The optimiser's helical angle (deg) and margin (N·m), marked with a star.
    design_angle_deg : float, optional
        The design's own helical angle, deg, marked with a vertical line.
    label : str
        Legend label of the curve.
    style_index : int
        Series number for colour, line style and marker.
    optimum_name : str
        What the star is called (``"closest design"`` when the optimisation is infeasible).

    Returns
    -------
    MarginAngleDrawn
    """
    a = np.asarray(helical_angle_deg, dtype=float)
    m = np.asarray(margin_Nm, dtype=float) * _MNM
    style = series_style(style_index, markevery=max(1, len(a) // 10))
    (line,) = ax.plot(a, m, label=label, **style)
    zero = ax.axhline(0.0, color="black", linewidth=1.0)
    spans = []
    for k, (name, slack) in enumerate((shortfalls or {}).items()):
        hatch = ("\\\\", "//", "xx", "..")[k % 4]
        for i, (lo, hi) in enumerate(shortfall_spans(a, slack)):
            spans.append(
                ax.axvspan(
                    lo,
                    hi,
                    facecolor="none",
                    edgecolor=("0.55", "0.7", "0.5", "0.6")[k % 4],
                    hatch=hatch,
                    linewidth=0.0,
                    label=name if i == 0 else None,
                    zorder=0,
                )
            )
    design = optimum = None
    if design_angle_deg is not None:
        design = ax.axvline(
            design_angle_deg,
            color="0.3",
            linestyle="--",
            linewidth=1.3,
            label=f"design as entered, {design_angle_deg:.3g}°",
        )
    if optimum_deg is not None and optimum_margin_Nm is not None:
        (optimum,) = ax.plot(
            [optimum_deg],
            [optimum_margin_Nm * _MNM],
            linestyle="none",
            marker="*",
            markersize=15,
            color=COLOURS[1],
            markeredgecolor="black",
            label=f"{optimum_name}, {optimum_deg:.3g}°, {optimum_margin_Nm * _MNM:.3g} mN·m",
            zorder=5,
        )
    ax.set_xlim(float(a.min()), float(a.max()))
    ax.set_xlabel("helical angle α (deg)")
    ax.set_ylabel(_MARGIN_LABEL)
    ax.legend(loc="lower center", fontsize=7.5)
    return MarginAngleDrawn(line, zero, optimum, design, tuple(spans))


def plot_margin_vs_power(
    ax: Axes,
    power_W: Any,
    margin_Nm: Any,
    *,
    optimal: Any = None,
    design_power_W: float | None = None,
    binding: Sequence[str] | None = None,
) -> PowerDrawn:
    """Best achievable margin against the copper-power budget (a Pareto front).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    power_W : array_like, shape (n,)
        Power budgets (``limits.power_W``) at which the design was re-optimised, W.
    margin_Nm : array_like, shape (n,)
        Optimal margin at each budget, N·m (NaN where none was found).
    optimal : array_like of bool, optional
        True where the re-optimisation found a feasible optimum; the others are drawn as
        crosses (the margin shown there is the best of the relaxed problem).
    design_power_W : float, optional
        The design's own power budget, W, marked with a vertical line.
    binding : sequence of str, optional
        Binding limits at each point (``"power;voltage_x"``), written beside the first point
        of each run of equal entries.

    Returns
    -------
    PowerDrawn
    """
    p = np.asarray(power_W, dtype=float)
    m = np.asarray(margin_Nm, dtype=float) * _MNM
    ok = np.ones(p.shape, bool) if optimal is None else np.asarray(optimal, dtype=bool)
    infeasible = design = None
    labels: list[Any] = []
    (front,) = ax.plot(p[ok], m[ok], label="optimum at each power budget", **series_style(0))
    if (~ok).any():
        (infeasible,) = ax.plot(
            p[~ok],
            np.nan_to_num(m[~ok]),
            linestyle="none",
            marker="x",
            markersize=9,
            color=COLOURS[1],
            markeredgewidth=2,
            label="no feasible design",
        )
    if design_power_W is not None:
        design = ax.axvline(
            design_power_W,
            color="0.3",
            linestyle="--",
            linewidth=1.3,
            label=f"design budget, {design_power_W:.4g} W",
        )
    if binding is not None:
        previous = None
        for x, y, text in zip(p, m, binding, strict=True):
            changed, previous = text != previous, text
            if text and changed and np.isfinite(y):
                labels.append(
                    ax.annotate(
                        text.replace(";", ", "),
                        (x, y),
                        textcoords="offset points",
                        xytext=(4, -11),
                        fontsize=7,
                        color="0.25",
                    )
                )
    ax.axhline(0.0, color="black", linewidth=1.0)
    finite = m[np.isfinite(m)]
    top = float(np.max(np.abs(finite))) if finite.size else 0.0
    if top < 0.05:  # nothing feasible: every point near zero; a readable range, not round-off
        ax.set_ylim(-0.5, 0.5)
    ax.ticklabel_format(axis="y", useOffset=False, style="plain")
    ax.set_xscale("log")
    ax.xaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))
    ax.set_xlabel("copper power budget, limits.power_W (W)")
    ax.set_ylabel("optimal " + _MARGIN_LABEL)
    ax.legend(loc="lower right")
    return PowerDrawn(front, infeasible, design, labels)


def plot_limit_utilisation(
    ax: Axes, checks: Sequence[Any], *, labels: Mapping[str, str] | None = None
) -> UtilisationDrawn:
    """How close each limit and requirement is to binding, as a horizontal bar chart.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    checks : sequence of optimize.Check or their dicts (``evaluation_to_dict(ev)["checks"]``)
        Limits ``value <= allowed`` are shown as value / allowed; requirements
        ``value >= allowed`` as allowed / value (needed / achieved). Checks with an allowed
        value of 0 (the margin itself) are left out. 100 % means the check binds.
    labels : mapping name -> str, optional
        Readable names for the checks (``{"voltage_x": "drive voltage, x pair"}``).

    Returns
    -------
    UtilisationDrawn
        The axis ends just past the largest utilisation (at most 150 %, where bars are cut).
    """
    names, util, ok = [], [], []
    for c in checks:
        value, allowed, sense = _get(c, "value"), _get(c, "allowed"), _get(c, "sense")
        if allowed == 0:
            continue
        u = value / allowed if sense == "<=" else (allowed / value if value > 0 else np.inf)
        if _has(c, "utilisation"):  # in the row's own form (a temperature rise, not °C)
            u = _get(c, "utilisation")
        names.append((labels or {}).get(_get(c, "name"), _get(c, "name")))
        util.append(100.0 * u)
        ok.append(bool(_get(c, "ok")))
    y = np.arange(len(names))[::-1]
    shown = np.minimum(np.asarray(util), 150.0)
    right = float(min(150.0, max(105.0, 1.0 + float(np.max(shown, initial=0.0)))))
    binding = np.abs(np.asarray(util) - 100.0) < 0.1
    colours = [
        COLOURS[1] if b else (COLOURS[0] if o else "#a4161a")
        for b, o in zip(binding, ok, strict=True)
    ]
    bars = ax.barh(y, shown, color=colours, edgecolor="black", linewidth=0.6)
    for bar, b, o in zip(bars, binding, ok, strict=True):
        bar.set_hatch(HATCHES[1] if b else ("xx" if not o else ""))
    texts = []
    for yi, u, b, o in zip(y, util, binding, ok, strict=True):
        tag = " binding" if b else (" EXCEEDED" if not o else "")
        inside = min(u, 150.0) > 0.55 * right
        texts.append(
            ax.text(
                min(u, 150.0) - 1.5 if inside else min(u, 150.0) + 1.5,
                yi,
                # needed / nothing achieved (no speed, no strain: no contact): not a percentage
                "nothing achieved: fails"
                if np.isinf(u)
                else (f"{u:.0f} %{tag}" if u >= 10 else f"{u:.2g} %{tag}"),
                va="center",
                ha="right" if inside else "left",
                fontsize=8,
                zorder=4,
                bbox={"facecolor": "white", "edgecolor": "none", "pad": 0.8},
            )
        )
    limit = ax.axvline(100.0, color="black", linewidth=1.4, linestyle="--")
    ax.set_yticks(y, names)
    ax.set_xlim(0, right)
    ax.set_xlabel("utilisation: value / allowed, or needed / achieved (%)")
    ax.grid(axis="y", visible=False)
    return UtilisationDrawn(bars, limit, texts, tuple(float(u) for u in util))


def plot_torque_budget(ax: Axes, evaluations: Sequence[tuple[str, Any]]) -> BudgetDrawn:
    """Available magnetic torque against the required torque, for one or more operating points.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    evaluations : sequence of (label, optimize.Evaluation or its dict)
        Each gets two bars: the synchronous magnetic torque available at the worst workspace
        point, and the required torque stacked from the tissue's resistive torque and the
        thrust torque.

    Returns
    -------
    BudgetDrawn
    """
    n = len(evaluations)
    x = np.arange(n, dtype=float)
    w = 0.36
    mag = np.array([_get(e, "magnetic_torque_Nm") for _, e in evaluations]) * _MNM
    res = np.array([_get(e, "resistive_torque_Nm") for _, e in evaluations]) * _MNM
    thr = np.array([_get(e, "thrust_torque_Nm") for _, e in evaluations]) * _MNM
    b_mag = ax.bar(
        x - w / 2,
        mag,
        w,
        color=COLOURS[0],
        edgecolor="black",
        hatch="",
        label="magnetic torque available (m·B, worst point)",
    )
    b_res = ax.bar(
        x + w / 2,
        res,
        w,
        color=COLOURS[1],
        edgecolor="black",
        hatch="///",
        label="tissue resistive torque",
    )
    b_thr = ax.bar(
        x + w / 2,
        thr,
        w,
        bottom=res,
        color=COLOURS[4],
        edgecolor="black",
        hatch="...",
        label="thrust torque (axial load)",
    )
    margins = []
    for xi, a, r, t in zip(x, mag, res, thr, strict=True):
        margins.append(
            ax.annotate(
                f"margin {a - r - t:.4g} mN·m",
                (xi, max(a, r + t)),
                textcoords="offset points",
                xytext=(0, 4),
                ha="center",
                fontsize=8.5,
            )
        )
    ax.set_xticks(x, [lab for lab, _ in evaluations])
    ax.set_ylabel("torque (mN·m)")
    ax.set_ylim(0, 1.12 * max(float(np.max(mag)), float(np.max(res + thr))))
    ax.grid(axis="x", visible=False)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), ncols=2)
    return BudgetDrawn(b_mag, b_res, b_thr, margins)
