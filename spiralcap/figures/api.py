"""Every report figure from Python: functions of the model and result objects.

Each function takes the objects the library returns -- the model of
:func:`spiralcap.assemble.build_model`, an :class:`optimize.Evaluation`, an
:class:`optimize.OptimizationResult` -- computes what it shows through :mod:`spiralcap.curves`
(the same arrays the report uses), draws on ``ax`` (or ``fig`` for multi-panel figures; a new
matplotlib Figure when not given, no pyplot involved) and returns a :class:`Plot`: the figure,
the axes and the typed record of what was drawn.

>>> from spiralcap.assemble import build_model              # doctest: +SKIP
>>> from spiralcap.design import load_design                 # doctest: +SKIP
>>> from optimize import evaluate, optimize_design           # doctest: +SKIP
>>> from spiralcap import figures                            # doctest: +SKIP
>>> model = build_model(load_design())                       # doctest: +SKIP
>>> ev, res = evaluate(model), optimize_design(model)        # doctest: +SKIP
>>> p = figures.margin_vs_frequency(model, ev, res)          # doctest: +SKIP
>>> p.figure.savefig("margin.svg")                           # doctest: +SKIP
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from optimize import DesignModel, Evaluation, OptimizationResult
from spiralcap.core.checks import guard, instance
from spiralcap.core.constants import to_unit

#: the rules for the arguments of the figure functions (a wrong object: one TypeError naming it)
_MODEL = instance(DesignModel, "an optimize.DesignModel (spiralcap.assemble.build_model)")
_EVALUATION = instance(Evaluation, "an optimize.Evaluation (optimize.evaluate)")
_EVALUATION_OR_NONE = instance(Evaluation, "an optimize.Evaluation (optimize.evaluate)", True)
_RESULT = instance(OptimizationResult, "an optimize.OptimizationResult (optimize_design)")
_RESULT_OR_NONE = instance(
    OptimizationResult, "an optimize.OptimizationResult (optimize_design)", True
)

__all__ = [
    "Plot",
    "calibration_residuals",
    "field_maps",
    "geometry",
    "heating",
    "limit_utilisation",
    "margin_map",
    "margin_vs_angle",
    "margin_vs_frequency",
    "margin_vs_power",
    "stray_field_map",
    "tissue_torque",
    "tissue_uncertainty",
    "torque_budget",
    "uniformity_profile",
]


class Plot(NamedTuple):
    """A drawn figure: the Figure, its main Axes, and what the plotting function returned."""

    figure: Any
    ax: Any
    drawn: Any


def _axes(ax: Any, size_in: tuple[float, float]) -> tuple[Any, Any]:
    if ax is not None:
        return ax.figure, ax
    from matplotlib.figure import Figure

    fig = Figure(figsize=size_in, layout="constrained")
    return fig, fig.subplots()


def _figure(fig: Any, size_in: tuple[float, float]) -> Any:
    if fig is not None:
        return fig
    from matplotlib.figure import Figure

    return Figure(figsize=size_in, layout="constrained")


def _found(ev: Any, name: str) -> float | None:
    """``ev.<name>_hz`` (step_out_frequency or max_frequency), None where the search ran out."""
    value = getattr(ev, f"{name}_hz" if name == "max_frequency" else f"{name}_frequency_hz", None)
    if value is None or getattr(ev, f"{name}_beyond_search", False):
        return None
    return float(value)


def _same_point(evaluation: Any, result: Any) -> bool:
    """Whether the design as entered sits at the optimum (angle and frequency to 1e-6)."""
    return math.isclose(
        evaluation.helical_angle_deg, result.helical_angle_deg, rel_tol=1e-6, abs_tol=1e-9
    ) and math.isclose(evaluation.frequency_hz, result.frequency_hz, rel_tol=1e-6, abs_tol=1e-9)


def _apart(x: float | None, other: float | None, span: float) -> float | None:
    """``x``, or None where the other curve already marks a line within 1 % of the axis there
    (two labels on one line would overprint)."""
    if x is None or other is None:
        return x
    return None if abs(x - other) <= 0.01 * span else x


@guard(model=_MODEL, evaluation=_EVALUATION, result=_RESULT_OR_NONE)
def margin_vs_frequency(
    model: Any, evaluation: Any, result: Any = None, *, ax: Any = None, curves: Any = None
) -> Plot:
    """Margin against frequency at the design's helical angle (and the optimum's).

    Each curve takes the largest field the limits allow at every frequency, so it crosses zero
    at the drive's maximum frequency (``max_frequency_hz``, dash-dot); the step-out frequency
    at the operating field (``step_out_frequency_hz``, dashed) is drawn beside it.

    ``curves`` may pass precomputed :func:`spiralcap.curves.frequency_curves` output.
    """
    from spiralcap.curves import frequency_curves
    from spiralcap.figures.design import plot_margin_vs_frequency

    fig, ax = _axes(ax, (7.5, 5.4))
    design, optimum = curves if curves is not None else frequency_curves(model, evaluation, result)
    ev = evaluation
    # the design as entered may be the optimum itself (a design written by `optimize -o`):
    # then one curve says so, and no label is printed twice over itself
    same = optimum is not None and _same_point(ev, result)
    drawn = [
        plot_margin_vs_frequency(
            ax,
            design.x,
            design.margin_Nm,
            feasible=design.feasible,
            step_out_frequency_hz=_found(ev, "step_out"),
            operating_frequency_hz=ev.frequency_hz,
            label=f"as entered{' = optimum' if same else ''}, α = {ev.helical_angle_deg:.3g}°",
            max_frequency_hz=_found(ev, "max_frequency"),
            max_frequency_limited_by=getattr(ev, "max_frequency_limited_by", ""),
            grip=_grip_of(design),
        )
    ]
    if optimum is not None and not same:
        span = float(np.ptp(design.x)) if len(design.x) else 1.0
        drawn.append(
            plot_margin_vs_frequency(
                ax,
                optimum.x,
                optimum.margin_Nm,
                feasible=optimum.feasible,
                style_index=1,
                step_out_frequency_hz=_apart(
                    _found(result.evaluation, "step_out"), _found(ev, "step_out"), span
                ),
                operating_frequency_hz=result.frequency_hz,
                label=f"optimum, α = {result.helical_angle_deg:.3g}°",
                shade=False,
                max_frequency_hz=_apart(
                    _found(result.evaluation, "max_frequency"),
                    _found(ev, "max_frequency"),
                    span,
                ),
                max_frequency_limited_by=result.evaluation.max_frequency_limited_by,
                grip=_grip_of(optimum),
            )
        )
        lo, hi = ax.get_ylim()
        top = np.nanmax([np.nanmax(design.margin_Nm, initial=-np.inf), result.margin_Nm])
        if np.isfinite(top):
            ax.set_ylim(lo, max(hi, 1.1e3 * float(top)))
    # two curves, each with its step-out and maximum frequency: the legend goes below the axes
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncols=2, fontsize=7.5)
    return Plot(fig, ax, tuple(drawn))


@guard(model=_MODEL, result=_RESULT, evaluation=_EVALUATION_OR_NONE)
def margin_vs_angle(
    model: Any, result: Any, evaluation: Any = None, *, ax: Any = None, curve: Any = None
) -> Plot:
    """Margin against helical angle, each angle at the lowest frequency meeting the speed.

    Frequency used on a second (right) axis; the spiral-turns shortfall hatched; the optimum
    starred; the angle as entered dashed. ``curve``: precomputed
    :func:`spiralcap.curves.angle_curve`.
    """
    from spiralcap.curves import angle_curve, angle_range_rad
    from spiralcap.figures.design import plot_margin_vs_angle

    fig, ax = _axes(ax, (7.5, 5.2))
    angles = [result.helical_angle_rad] + (
        [evaluation.helical_angle_rad] if evaluation is not None else []
    )
    c = curve if curve is not None else angle_curve(model, angle_range_rad(model, *angles))
    # start where the margin is above -40 % of its peak: the steep fall at tiny angles would
    # squeeze the useful range (the range is chosen from the data)
    peak = float(np.nanmax(c.margin_Nm)) if np.isfinite(c.margin_Nm).any() else 0.0
    keep = np.nonzero(c.margin_Nm >= -0.4 * abs(peak))[0]
    first = int(keep[0]) - 1 if keep.size else 0
    # never cut off the optimum (or closest design) or the angle as entered
    marked = to_unit(min(angles), "deg")
    first = min(first, int(np.searchsorted(c.x, marked)) - 6)  # a few points left of it
    sl = slice(max(0, first), None)
    drawn = plot_margin_vs_angle(
        ax,
        c.x[sl],
        c.margin_Nm[sl],
        shortfalls=_angle_shortfalls(c, sl),
        optimum_deg=result.helical_angle_deg,
        optimum_margin_Nm=result.margin_Nm,
        design_angle_deg=None if evaluation is None else evaluation.helical_angle_deg,
        label="margin, each angle at the lowest frequency meeting the speed",
        optimum_name="optimum" if result.status == "optimal" else "closest design (infeasible)",
    )
    # the hatched regions' names would cover the curve: the legend goes below the axes
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncols=2, fontsize=7.5)
    if c.frequency_hz is not None:
        twin = ax.twinx()
        fx = c.frequency_hz[sl]
        twin.plot(c.x[sl], fx, color="0.45", linestyle=(0, (3, 1.5)), linewidth=1.2)
        twin.set_ylabel("frequency used (Hz), grey dashed", color="0.3")
        twin.set_ylim(0, 1.1 * float(fx.max()))
        twin.grid(False)
    return Plot(fig, ax, drawn)


#: Legend names of the grip regions on the margin-against-angle figure.
_GRIP_NAMES = {
    "none": "no contact with the wall: no margin (no physics in the model)",
    "below minimum": "wall strain below requirements.min_wall_strain: extrapolated",
}


def _angle_shortfalls(c: Any, sl: slice) -> dict[str, Any]:
    """The hatched regions of the angle figure: no contact and a strain below the minimum
    first (where they hold, the speed and turns are not what fails), then speed and turns."""
    grip = {_GRIP_NAMES[k]: v[sl] for k, v in c.grip_slacks().items()}
    contact = c.wall_strain[sl] > 0 if c.wall_strain is not None else True
    return {  # the grip regions last: the speed and turns keep their hatches
        "speed below requirements.min_speed_mm_s": np.where(
            contact, c.speed_slack_m_s[sl], np.abs(c.speed_slack_m_s[sl])
        ),
        "fewer turns than requirements.min_spiral_turns": np.where(
            contact, c.turns_slack[sl], np.abs(c.turns_slack[sl])
        ),
        **grip,
    }


def _grip_of(curve: Any) -> str:
    """The grip of a curve at one angle (every point the same): ``ok``/``below minimum``/
    ``none``."""
    grip = getattr(curve, "grip", None)
    return "ok" if grip is None or not len(grip) else str(grip[0])


@guard(model=_MODEL, result=_RESULT_OR_NONE, evaluation=_EVALUATION_OR_NONE)
def margin_map(
    model: Any,
    result: Any = None,
    evaluation: Any = None,
    *,
    ax: Any = None,
    grid: Any = None,
) -> Plot:
    """Margin over helical angle x frequency: infeasible hatched, step-out drawn, points marked.

    ``grid``: precomputed :func:`spiralcap.curves.margin_map`.
    """
    from spiralcap.curves import frequency_range_hz
    from spiralcap.curves import margin_map as compute
    from spiralcap.figures.sweep import plot_margin_map

    fig, ax = _axes(ax, (7.0, 4.6))
    if grid is None:
        f_max = frequency_range_hz(model, getattr(evaluation, "step_out_frequency_hz", 0.0)).max()
        grid = compute(model, float(f_max))
    marks = {}
    best = "optimum" if getattr(result, "status", "optimal") == "optimal" else "closest design"
    for what, obj in ((best, result), ("as entered", evaluation)):
        if obj is not None:
            marks[f"{what}, {obj.helical_angle_deg:.3g}°, {obj.frequency_hz:.3g} Hz"] = (
                obj.helical_angle_deg,
                obj.frequency_hz,
            )
    drawn = plot_margin_map(
        ax,
        grid.helical_angle_deg,
        grid.frequency_hz,
        grid.margin_Nm,
        feasible=grid.feasible,
        failing=grid.failing,
        xlabel="helical angle α (deg)",
        ylabel="rotation frequency f (Hz)",
        marks=marks,
    )
    return Plot(fig, ax, drawn)


@guard(evaluation=_EVALUATION, result=_RESULT_OR_NONE)
def torque_budget(evaluation: Any, result: Any = None, *, ax: Any = None) -> Plot:
    """Magnetic torque available against the required torque, as entered (and optimised)."""
    from spiralcap.figures.design import plot_torque_budget

    fig, ax = _axes(ax, (6.5, 4.0))
    points = [("as entered", evaluation)]
    if result is not None:
        points.append(("optimum", result.evaluation))
    return Plot(fig, ax, plot_torque_budget(ax, points))


def limit_utilisation(evaluation: Any, *, ax: Any = None) -> Plot:
    """How close every limit and requirement is to binding (an Evaluation, or a result's)."""
    from spiralcap.figures.design import plot_limit_utilisation
    from spiralcap.presentation import readable

    ev = getattr(evaluation, "evaluation", evaluation)
    fig, ax = _axes(ax, (7.0, 4.6))
    labels = {c.name: readable(c.name) for c in ev.checks}
    return Plot(fig, ax, plot_limit_utilisation(ax, ev.checks, labels=labels))


@guard(model=_MODEL, evaluation=_EVALUATION_OR_NONE, result=_RESULT_OR_NONE)
def tissue_torque(
    model: Any, evaluation: Any = None, result: Any = None, *, ax: Any = None
) -> Plot:
    """Tissue resistive torque of this design's capsule in each tissue set, against frequency.

    One curve per tissue set and helical angle (as entered, optimum); lines without markers.
    """
    from spiralcap.figures.style import restyle_lines
    from spiralcap.figures.torque import legend_tissue_name, plot_torque_vs_frequency

    fig, ax = _axes(ax, (7.0, 4.2))
    from optimize import physics, prepare

    geometry = physics.contact_geometry(prepare(model).constants)
    points = [(o, w) for o, w in ((evaluation, "as entered"), (result, "optimum")) if o]
    if not points:
        points = [(model.capsule.spiral, "design")]
    f_hi = max([3.5] + [1.1 * o.frequency_hz for o, _ in points if hasattr(o, "frequency_hz")])
    f = np.linspace(0.1, f_hi, 80)
    lines = []
    for tissue in model.tissues:
        for obj, what in points:
            angle = to_unit(obj.helical_angle_rad, "deg")
            out = plot_torque_vs_frequency(
                ax, tissue, (angle,), frequency_hz=f, paper_points=(), geometry=geometry
            )
            out.curves[0].set_label(f"{legend_tissue_name(tissue.name)}, α = {angle:.3g}° ({what})")
            lines += out.curves
    restyle_lines(lines, markers=False)
    for obj, what in points:
        if hasattr(obj, "frequency_hz"):
            ax.axvline(
                obj.frequency_hz,
                color="0.3",
                linestyle="--" if what == "as entered" else ":",
                linewidth=1.2,
                label=f"{what} frequency, {obj.frequency_hz:.3g} Hz",
            )
    ax.set_title("this design's capsule")
    handles, labels = ax.get_legend_handles_labels()
    seen = dict(zip(labels, handles, strict=True))
    ax.legend(list(seen.values()), list(seen), loc="upper left", fontsize=8)
    return Plot(fig, ax, tuple(lines))


@guard(model=_MODEL)
def field_maps(
    model: Any, *, fig: Any = None, workspace_radius_m: float | None = None, maps: Any = None
) -> Plot:
    """Signed |B| deviation maps, one per pair driven alone, with one shared colour bar."""
    from matplotlib.lines import Line2D

    from spiralcap.curves import field_maps as compute
    from spiralcap.figures.coils import plot_field_deviation_map

    fig = _figure(fig, (7.5, 3.5))
    maps = maps if maps is not None else compute(model.coils)
    axs = fig.subplots(1, 3)
    drawn = []
    for ax, m in zip(axs, maps, strict=True):
        drawn.append(
            plot_field_deviation_map(
                ax,
                m.u_m,
                m.v_m,
                m.deviation,
                axis_labels=m.plane,
                uniform_radii_m=m.uniform_radii_m,
                workspace_radius_m=workspace_radius_m,
                title=f"{m.axis} pair driven",
                colorbar=False,
                legend=False,
                label_contours=False,
            )
        )
    fig.colorbar(
        drawn[-1].filled,
        ax=list(axs),
        label="|B| / |B(0)| − 1 (%)",
        shrink=0.8,
        location="right",
        format="%g",
        ticks=(-20, -5, -1, 0, 1, 5, 20),
        spacing="uniform",
    )
    from matplotlib.patches import Patch

    proxies: list[Any] = [
        Patch(facecolor="white", edgecolor="0.35", hatch="..", label="weaker than centre"),
        Line2D([], [], color="black", linestyle="-", linewidth=2.0),
        Line2D([], [], color="black", linestyle="--", linewidth=2.0),
        Line2D([], [], color="#E69F00", linestyle=":", linewidth=2.0),
        Line2D([], [], color="black", linestyle="-.", linewidth=1.6),
    ]
    fig.legend(
        proxies,
        [
            "|B| weaker than at the centre by > 1 %",
            "±1 % contour",
            "±5 % contour",
            "±1 % and ±5 % spheres",
            "workspace",
        ],
        loc="outside lower center",
        ncols=3,
        fontsize=8,
    )
    return Plot(fig, axs[0], tuple(drawn))


@guard(model=_MODEL)
def uniformity_profile(model: Any, *, ax: Any = None, profile: Any = None) -> Plot:
    """Signed |B| deviation along each pair's axis and across it, that pair driven alone."""
    from spiralcap.curves import MAP_EXTENT, uniformity_profiles
    from spiralcap.figures.coils import plot_uniformity_profile

    fig, ax = _axes(ax, (7.0, 4.0))
    if profile is None:
        half = MAP_EXTENT * min(p.radius_m for p in model.coils.pairs)
        profile = uniformity_profiles(model.coils, half)
    d, devs = profile
    return Plot(fig, ax, plot_uniformity_profile(ax, d, devs))


def margin_vs_power(
    design: Any,
    *,
    ax: Any = None,
    sweep: Any = None,
    factors: Any = None,
    refinements: int | None = None,
) -> Plot:
    """Best margin against the copper-power budget, re-optimised at each, refined at the knee.

    ``sweep``: a precomputed :func:`spiralcap.curves.adaptive_power_sweep` result; else one is
    run at ``factors`` x ``limits.power_W`` with ``refinements`` extra points at the knee.
    """
    from spiralcap.curves import POWER_FACTORS, POWER_REFINEMENTS, adaptive_power_sweep
    from spiralcap.figures.design import plot_margin_vs_power
    from spiralcap.presentation import readable

    fig, ax = _axes(ax, (7.5, 4.4))
    if sweep is None:
        powers = design["limits.power_W"] * np.asarray(factors or POWER_FACTORS, float)
        extra = POWER_REFINEMENTS if refinements is None else refinements
        sweep = adaptive_power_sweep(design, powers, refinements=extra)
    out = sweep.outputs
    margin = np.array([np.nan if m is None else m for m in out["margin_Nm"]], float)
    drawn = plot_margin_vs_power(
        ax,
        np.asarray(sweep.inputs["limits.power_W"], float),
        margin,
        optimal=[s == "optimal" for s in out["status"]],
        design_power_W=design["limits.power_W"],
        binding=[
            ";".join(readable(n) for n in str(b).split(";") if n) for b in out["binding_limits"]
        ],
    )
    return Plot(fig, ax, drawn)


@guard(model=_MODEL)
def geometry(model: Any, *, fig: Any = None, workspace_radius_m: float | None = None) -> Plot:
    """The hardware to scale: nested coil pairs, the workspace and the capsule."""
    from spiralcap.figures.hardware import draw_geometry

    fig = _figure(fig, (7.0, 3.5))
    drawn = draw_geometry(
        fig,
        model.coils,
        model.capsule,
        workspace_radius_m=workspace_radius_m,
        min_clearance_m=model.requirements.min_clearance_m,
    )
    return Plot(fig, drawn.pairs["x"][0].axes, drawn)


def heating(analysis: Any, *, ax: Any = None) -> Plot:
    """Winding temperature of each pair from switch-on, at its operating current.

    ``analysis``: :func:`spiralcap.analysis.coils.analyse_coils` of the design (its heating
    curves, hot-spot limit and session length), as the report's coil section draws it.
    """
    from spiralcap.figures.thermal import plot_heating_curves

    fig, ax = _axes(ax, (7.5, 2.8))
    drawn = plot_heating_curves(
        ax,
        analysis.heating,
        limit_C=float(analysis.limit_temperature_C),
        session_s=analysis.session_s,
    )
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7.5)
    return Plot(fig, ax, drawn)


def tissue_uncertainty(result: Any, *, fig: Any = None) -> Plot:
    """The margin's distribution over the tissue samples, and its Sobol indices beside it
    when there are two or more uncertain inputs (``result``: the ``result`` of
    :func:`spiralcap.uncertainty.study`)."""
    from spiralcap.figures.uncertainty import plot_margin_distribution, plot_sobol, sobol_panel

    two = sobol_panel(result)
    fig = _figure(fig, (10.0, 4.2) if two else (6.6, 4.2))
    if not two:
        ax = fig.subplots()
        return Plot(fig, ax, plot_margin_distribution(ax, result))
    ax1, ax2 = fig.subplots(1, 2, width_ratios=[1.4, 1.0])
    drawn = {**plot_margin_distribution(ax1, result), **plot_sobol(ax2, result)}
    return Plot(fig, ax1, drawn)


def stray_field_map(
    model: Any,
    field_T: float,
    half_width_m: float,
    *,
    level_T: float | None = None,
    fig: Any = None,
    planes: Any = None,
) -> Plot:
    """Largest |B| over a turn (every heading) at the operating field on the x–z and x–y planes
    out to ``half_width_m``, with the ``level_T`` contour (default 0.5 mT, ICNIRP 2009 for
    implanted devices) and the coil packs."""
    from spiralcap.analysis.stray import IMPLANT_LEVEL_T, peak_field_plane
    from spiralcap.figures.coils import plot_stray_plane

    fig = _figure(fig, (7.5, 3.6))
    half = float(half_width_m)
    level = IMPLANT_LEVEL_T if level_T is None else float(level_T)
    planes = planes or [peak_field_plane(model, field_T, p, half, 45) for p in ("xz", "xy")]
    axs = fig.subplots(1, 2)
    drawn = [plot_stray_plane(ax, p, model.coils, level) for ax, p in zip(axs, planes, strict=True)]
    fig.colorbar(
        drawn[-1],
        ax=list(axs),
        label="largest |B| over a turn (mT)",
        shrink=0.85,
        location="right",
        format="%g",
        ticks=(0.05, 0.1, 0.5, 1, 5, 10, 50, 100),
    )
    return Plot(fig, axs[0], tuple(planes))


def calibration_residuals(check: Any, *, fig: Any = None) -> Plot:
    """A calibrated design's survey: measured against the calibrated model (every row and
    component, mT) and the residual against the measured |B| (µT)
    (:func:`spiralcap.analysis.calibration.calibration_check`)."""
    from spiralcap.figures.style import COLOURS, MARKERS

    fig = _figure(fig, (7.5, 3.3))
    measured = np.asarray(check.measured_T) * 1e3
    predicted = np.asarray(check.predicted_T) * 1e3
    left, right = fig.subplots(1, 2)
    lo, hi = (
        float(min(measured.min(), predicted.min())),
        float(max(measured.max(), predicted.max())),
    )
    left.plot([lo, hi], [lo, hi], color="0.5", linewidth=1.0, label="model = measured")
    for c, ax in enumerate("xyz"):
        left.plot(
            predicted[:, c],
            measured[:, c],
            linestyle="none",
            marker=MARKERS[c],
            markersize=3.5,
            color=COLOURS[c],
            label=f"B{ax}",
        )
        right.plot(
            np.linalg.norm(measured, axis=1),
            (measured[:, c] - predicted[:, c]) * 1e3,
            linestyle="none",
            marker=MARKERS[c],
            markersize=3.5,
            color=COLOURS[c],
            label=f"B{ax}",
        )
    left.set_xlabel("calibrated model (mT)")
    left.set_ylabel("measured (mT)")
    left.legend(fontsize=7.5, loc="upper left")
    right.axhline(0.0, color="0.5", linewidth=1.0)
    right.set_xlabel("|B| measured (mT)")
    right.set_ylabel("measured − model (µT)")
    return Plot(fig, left, None)
