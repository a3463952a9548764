"""Design figures: margin against frequency, helical angle and power budget; limits; torques.

Every function is ``plot_xxx(ax, <arrays or result objects>, ...)``: it draws on ``ax``, labels
the axes with units (mN·m, Hz, deg, W) and returns a dict of what it drew. Inputs are in SI as
the result objects hold them (N·m, Hz, W); the conversion to engineering units happens here.
Series differ by line style and marker as well as colour, so the figures read in grey print.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.ticker import NullFormatter

from spiralcap.figures.style import COLOURS, HATCHES, series_style

__all__ = [
    "plot_limit_utilisation",
    "plot_margin_vs_angle",
    "plot_margin_vs_frequency",
    "plot_margin_vs_power",
    "plot_torque_budget",
]

_MNM = 1e3  # N·m -> mN·m
_MARGIN_LABEL = "worst-case torque margin (mN·m)"


def _get(obj: Any, name: str) -> Any:
    """Field ``name`` of a result object or of its JSON dict (``spiralcap.serialize``)."""
    if isinstance(obj, Mapping):
        return obj[name]
    return getattr(obj, name)


def _shade_infeasible(ax: Axes, x: np.ndarray, feasible: Any, label: str) -> Any:
    """Hatch the x ranges where a requirement fails (readable without colour)."""
    if feasible is None:
        return None
    bad = ~np.asarray(feasible, dtype=bool)
    if not bad.any():
        return None
    return ax.fill_between(
        x,
        0,
        1,
        where=bad,
        transform=ax.get_xaxis_transform(),
        facecolor="none",
        edgecolor="0.6",
        hatch="//",
        linewidth=0.0,
        label=label,
        step="mid",
    )


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
) -> dict[str, Any]:
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
        Whether every requirement holds; the frequencies where one fails are hatched.
    step_out_frequency_hz : float, optional
        Where the margin reaches zero (``Evaluation.step_out_frequency_hz``), Hz; marked with a
        vertical line and its value.
    operating_frequency_hz : float, optional
        The operating (or optimal) frequency, Hz; marked on the curve.
    label : str
        Legend label of the curve.
    style_index : int
        Series number for colour, line style and marker (several calls on one axes).
    shade : bool
        Hatch the infeasible range (only the first of several curves should).

    Returns
    -------
    dict
        ``line`` (Line2D), ``zero`` (Line2D), ``step_out`` (Line2D or None), ``operating``
        (Line2D or None), ``infeasible`` (PolyCollection or None).
    """
    f = np.asarray(frequency_hz, dtype=float)
    m = np.asarray(margin_Nm, dtype=float) * _MNM
    style = series_style(style_index, markevery=max(1, len(f) // 10))
    (line,) = ax.plot(f, m, label=label, **style)
    zero = ax.axhline(0.0, color="black", linewidth=1.0)
    out: dict[str, Any] = {
        "line": line,
        "zero": zero,
        "step_out": None,
        "operating": None,
        "infeasible": None,
    }
    if shade:
        out["infeasible"] = _shade_infeasible(ax, f, feasible, "a requirement not met")
    if (
        step_out_frequency_hz is not None
        and np.isfinite(step_out_frequency_hz)
        and step_out_frequency_hz > 0
    ):
        out["step_out"] = ax.axvline(
            step_out_frequency_hz,
            color=style["color"],
            linestyle=(0, (1, 1.5)),
            linewidth=1.6,
            label=f"step-out, {step_out_frequency_hz:.4g} Hz",
        )
    if operating_frequency_hz is not None:
        y = float(np.interp(operating_frequency_hz, f, m))
        (out["operating"],) = ax.plot(
            [operating_frequency_hz],
            [y],
            linestyle="none",
            marker="*",
            markersize=13,
            color=style["color"],
            markeredgecolor="black",
            label=f"operating point, {operating_frequency_hz:.4g} Hz",
        )
    ax.set_xlabel("rotation frequency f (Hz)")
    ax.set_ylabel(_MARGIN_LABEL)
    ax.legend(loc="best")
    return out


def plot_margin_vs_angle(
    ax: Axes,
    helical_angle_deg: Any,
    margin_Nm: Any,
    *,
    feasible: Any = None,
    optimum_deg: float | None = None,
    optimum_margin_Nm: float | None = None,
    design_angle_deg: float | None = None,
    label: str = "margin",
    style_index: int = 0,
) -> dict[str, Any]:
    """Worst-case torque margin against the spiral's helical angle at one frequency.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    helical_angle_deg : array_like, shape (n,)
        Helical angles, deg.
    margin_Nm : array_like, shape (n,)
        Margin at each angle, N·m.
    feasible : array_like of bool, optional
        Whether every requirement (speed, spiral turns, margin) holds; failures are hatched.
    optimum_deg, optimum_margin_Nm : float, optional
        The optimiser's helical angle (deg) and margin (N·m), marked with a star.
    design_angle_deg : float, optional
        The design's own helical angle, deg, marked with a vertical line.
    label : str
        Legend label of the curve.
    style_index : int
        Series number for colour, line style and marker.

    Returns
    -------
    dict
        ``line``, ``zero``, ``optimum``, ``design``, ``infeasible`` (None where not drawn).
    """
    a = np.asarray(helical_angle_deg, dtype=float)
    m = np.asarray(margin_Nm, dtype=float) * _MNM
    style = series_style(style_index, markevery=max(1, len(a) // 10))
    (line,) = ax.plot(a, m, label=label, **style)
    out: dict[str, Any] = {
        "line": line,
        "zero": ax.axhline(0.0, color="black", linewidth=1.0),
        "optimum": None,
        "design": None,
        "infeasible": None,
    }
    out["infeasible"] = _shade_infeasible(ax, a, feasible, "a requirement not met")
    if design_angle_deg is not None:
        out["design"] = ax.axvline(
            design_angle_deg,
            color="0.3",
            linestyle="--",
            linewidth=1.3,
            label=f"design as entered, {design_angle_deg:.4g}°",
        )
    if optimum_deg is not None and optimum_margin_Nm is not None:
        (out["optimum"],) = ax.plot(
            [optimum_deg],
            [optimum_margin_Nm * _MNM],
            linestyle="none",
            marker="*",
            markersize=14,
            color=COLOURS[1],
            markeredgecolor="black",
            label=f"optimum, {optimum_deg:.4g}°, {optimum_margin_Nm * _MNM:.4g} mN·m",
        )
    ax.set_xlabel("helical angle α (deg)")
    ax.set_ylabel(_MARGIN_LABEL)
    ax.legend(loc="best")
    return out


def plot_margin_vs_power(
    ax: Axes,
    power_W: Any,
    margin_Nm: Any,
    *,
    optimal: Any = None,
    design_power_W: float | None = None,
    binding: Sequence[str] | None = None,
) -> dict[str, Any]:
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
    dict
        ``front`` (Line2D), ``infeasible`` (Line2D or None), ``design`` (Line2D or None),
        ``labels`` (list of Text).
    """
    p = np.asarray(power_W, dtype=float)
    m = np.asarray(margin_Nm, dtype=float) * _MNM
    ok = np.ones(p.shape, bool) if optimal is None else np.asarray(optimal, dtype=bool)
    out: dict[str, Any] = {"infeasible": None, "design": None, "labels": []}
    (out["front"],) = ax.plot(p[ok], m[ok], label="optimum at each power budget", **series_style(0))
    if (~ok).any():
        (out["infeasible"],) = ax.plot(
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
        out["design"] = ax.axvline(
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
                out["labels"].append(
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
    ax.set_xscale("log")
    ax.set_xticks(p, [f"{v:.4g}" for v in p])
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("copper power budget, limits.power_W (W)")
    ax.set_ylabel("optimal " + _MARGIN_LABEL)
    ax.legend(loc="best")
    return out


def plot_limit_utilisation(
    ax: Axes, checks: Sequence[Any], *, labels: Mapping[str, str] | None = None
) -> dict[str, Any]:
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
    dict
        ``bars`` (BarContainer), ``limit`` (Line2D at 100 %), ``labels`` (list of Text).
    """
    names, util, ok = [], [], []
    for c in checks:
        value, allowed, sense = _get(c, "value"), _get(c, "allowed"), _get(c, "sense")
        if allowed == 0:
            continue
        u = value / allowed if sense == "<=" else (allowed / value if value > 0 else np.inf)
        names.append((labels or {}).get(_get(c, "name"), _get(c, "name")))
        util.append(100.0 * u)
        ok.append(bool(_get(c, "ok")))
    y = np.arange(len(names))[::-1]
    shown = np.minimum(np.asarray(util), 150.0)
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
        tag = " binding" if b else ("  EXCEEDED" if not o else "")
        texts.append(
            ax.text(
                min(u, 150.0) + 2,
                yi,
                f"{u:.4g} %{tag}",
                va="center",
                fontsize=8,
                zorder=4,
                bbox={"facecolor": "white", "edgecolor": "none", "pad": 0.8},
            )
        )
    limit = ax.axvline(100.0, color="black", linewidth=1.4, linestyle="--")
    ax.set_yticks(y, names)
    ax.set_xlim(0, 175)
    ax.set_xlabel("utilisation: value / allowed, or needed / achieved (%)")
    ax.grid(axis="y", visible=False)
    return {"bars": bars, "limit": limit, "labels": texts}


def plot_torque_budget(ax: Axes, evaluations: Sequence[tuple[str, Any]]) -> dict[str, Any]:
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
    dict
        ``magnetic``, ``resistive``, ``thrust`` (BarContainer each), ``margins`` (list of Text).
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
    return {"magnetic": b_mag, "resistive": b_res, "thrust": b_thr, "margins": margins}
