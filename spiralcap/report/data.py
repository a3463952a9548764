"""Run the analyses a report shows and keep their results (no formatting, no plotting).

Every number the report prints comes from the dicts the CLI prints
(:func:`spiralcap.serialize.evaluation_to_dict`, :func:`spiralcap.serialize.optimization_to_dict`,
the ``spiralcap coils --json`` dict); the arrays behind the figures come from
:mod:`spiralcap.curves`. Nothing here re-derives physics.
"""

from __future__ import annotations

import importlib.metadata
import platform
import time
from collections.abc import Callable
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np

from spiralcap.curves import (
    MAP_EXTENT,
    POWER_FACTORS,
    TOLERANCES,
    Curve,
    FieldMap,
    MarginMap,
    adaptive_power_sweep,
    angle_curve,
    angle_range_rad,
    field_maps,
    frequency_curves,
    margin_map,
    uniformity_profiles,
)
from spiralcap.design import Design

__all__ = [
    "CoilStage",
    "ReportData",
    "collect",
    "design_has_uncertainty",
    "uniform_radii_m",
    "versions",
]


@dataclass(frozen=True)
class ReportData:
    """Everything one report shows; built by :func:`collect`."""

    design: Design
    model: Any
    evaluation: Any
    optimization: Any
    evaluate_json: dict[str, Any]
    optimize_json: dict[str, Any]
    coils_json: dict[str, Any]
    coils_note: str
    freq_design: Curve
    freq_optimum: Curve | None
    angle_optimum: Curve
    power_sweep: Any
    power_values_W: np.ndarray
    field_maps: tuple[FieldMap, ...]
    profile: tuple[np.ndarray, dict[str, np.ndarray]]
    versions: dict[str, str]
    timings_s: dict[str, float] = field(default_factory=dict)
    comparison: Any = None
    margin_map: MarginMap | None = None
    #: spiralcap.uncertainty.Study, only when the design has tissue uncertainty.
    uncertainty: Any = None
    #: spiralcap.analysis.coils.HeatingCurve per pair, at the operating field.
    heating: tuple[Any, ...] = ()

    @property
    def feasible(self) -> bool:
        """True when the optimiser found a design meeting every requirement."""
        return self.optimization.status == "optimal"


def versions() -> dict[str, str]:
    """Versions of spiralcap, Python and the libraries behind the numbers and figures."""
    from spiralcap import __version__

    out = {"spiralcap": __version__, "python": platform.python_version()}
    for dist in ("numpy", "scipy", "casadi", "magpylib", "matplotlib"):
        try:
            out[dist] = importlib.metadata.version(dist)
        except importlib.metadata.PackageNotFoundError:
            out[dist] = "not installed"
    # system, kernel release and machine; not platform.platform(), whose processor field runs
    # `uname -p` in a subprocess (a fork of this whole process, 0.05 s of a report)
    out["platform"] = "-".join(
        p for p in (platform.system(), platform.release(), platform.machine()) if p
    )
    return out


def uniform_radii_m(coils_json: dict[str, Any]) -> dict[str, dict[float, float]]:
    """Per-axis uniform-sphere radii (axis -> tolerance -> m) from the coil analysis' dict.

    The one place the report reads the coil analysis' per-axis radii; the typed coil analysis
    of issue 13 replaces the dict here.
    """
    per_axis = coils_json["uniform_region"]["per_axis"]
    return {
        axis: {tol: float(per_axis[axis][f"radius_{round(100 * tol)}pct_m"]) for tol in TOLERANCES}
        for axis in per_axis
    }


def design_has_uncertainty(design: Design) -> bool:
    """True when any ``tissue.uncertainty.*`` sigma is positive or a covariance is named."""
    from spiralcap.assemble.tissue import build_uncertainty

    return bool(build_uncertainty(design).active)


def _stopwatch() -> tuple[dict[str, float], Callable[[str], None]]:
    """``(timings, lap)``: ``lap(name)`` records the seconds since the previous lap."""
    timings: dict[str, float] = {}
    t = time.perf_counter()

    def lap(name: str) -> None:
        nonlocal t
        now = time.perf_counter()
        timings[name] = now - t
        t = now

    return timings, lap


def _core_stage(
    design: Design, model: Any, say: Callable[[str], None]
) -> tuple[dict[str, Any], dict[str, float]]:
    """Evaluation, optimisation and the margin curves and map around both (and the tissue
    uncertainty study when the design has one)."""
    from optimize import evaluate, optimize_design
    from spiralcap.analysis.touch import evaluation_warnings
    from spiralcap.presentation import jsonable as _jsonable
    from spiralcap.robust import optimization_model
    from spiralcap.serialize import evaluation_to_dict, optimization_to_dict

    timings, lap = _stopwatch()
    say("evaluate")
    ev = evaluate(model)
    lap("evaluate")
    say("optimize")
    res = optimize_design(optimization_model(design, model))  # with tissue scenarios if asked
    lap("optimize")
    say("margin curves")
    freq_design, freq_opt = frequency_curves(model, ev, res)
    angle_opt = angle_curve(
        model, angle_range_rad(model, ev.helical_angle_rad, res.helical_angle_rad)
    )
    out: dict[str, Any] = {
        "evaluation": ev,
        "optimization": res,
        "evaluate_json": _jsonable(
            {
                "design": design.source,
                **evaluation_to_dict(ev),
                "warnings": evaluation_warnings(model, ev),
                **_evaluation_intervals(model, ev),
            }
        ),
        "optimize_json": _jsonable(
            {
                "design": design.source,
                **optimization_to_dict(res),
                **_tolerance_intervals(design, res),
            }
        ),
        "freq_design": freq_design,
        "freq_optimum": freq_opt,
        "angle_optimum": angle_opt,
        "margin_map": margin_map(model, float(freq_design.x.max())),
        "uncertainty": None,
    }
    lap("margin curves")
    if design_has_uncertainty(design):  # the built-in design has none: no extra work
        from spiralcap.report.sections import uncertainty as _uncertainty

        say("uncertainty")
        out["uncertainty"] = _uncertainty.collect(design, model=model)
        lap("uncertainty")
    return out, timings


def _evaluation_intervals(model: Any, ev: Any) -> dict[str, Any]:
    """``{"tolerance_intervals": ...}`` of the design as ``spiralcap evaluate --json`` gives it."""
    from spiralcap import tolerances

    return {"tolerance_intervals": tolerances.to_dict(tolerances.evaluation_rows(model, ev))}


def _tolerance_intervals(design: Design, res: Any) -> dict[str, Any]:
    """``{"tolerance_intervals": ...}`` of the optimum as ``spiralcap optimize --json`` gives
    it (spiralcap.tolerances); empty without an optimum."""
    from spiralcap import tolerances

    rows = tolerances.optimum_rows(design, res)
    return {"tolerance_intervals": tolerances.to_dict(rows)} if rows else {}


@dataclass(frozen=True)
class CoilStage:
    """The design, its model and the coil analysis: all the coil section's figures read.

    Ready before the optimisation is, so a report on several processes draws those figures
    while it runs (:func:`collect`'s ``while_waiting``). The fields after ``model`` are
    :class:`ReportData`'s of the same names.
    """

    design: Design
    model: Any
    coils_json: dict[str, Any]
    coils_note: str
    heating: tuple[Any, ...]
    field_maps: tuple[FieldMap, ...]
    profile: tuple[np.ndarray, dict[str, np.ndarray]]


def _coil_stage(
    design: Design, model: Any, say: Callable[[str], None]
) -> tuple[CoilStage, dict[str, float]]:
    """The coil analysis (the ``spiralcap coils --json`` dict, heating curves), field maps and
    uniformity profiles."""
    from spiralcap.analysis.coils import analyse_coils, coils_payload
    from spiralcap.presentation import jsonable as _jsonable

    timings, lap = _stopwatch()
    say("coil sizing")
    analysis = analyse_coils(design, model)  # once: the CLI's dict and the heating curves
    coils_json = _jsonable(coils_payload(analysis))
    lap("coils")
    say("field maps")
    half = MAP_EXTENT * min(p.radius_m for p in model.coils.pairs)
    stage = CoilStage(
        design=design,
        model=model,
        coils_json=coils_json,
        coils_note="spiralcap.analysis.coils.analyse_coils(design)",
        heating=tuple(analysis.heating),
        field_maps=field_maps(model.coils, uniform_radii_m(coils_json)),
        profile=uniformity_profiles(model.coils, half),
    )
    lap("field maps")
    return stage, timings


def _power_stage(
    design: Design, powers_W: np.ndarray, say: Callable[[str], None], model: Any, optimum: Any
) -> tuple[dict[str, Any], dict[str, float]]:
    """The best margin against the power budget, re-optimised at each (adaptively refined),
    going out from the design's own optimum when given."""
    timings, lap = _stopwatch()
    say("power sweep")
    power_sweep = adaptive_power_sweep(design, powers_W, model=model, optimum=optimum)
    out = {
        "power_sweep": power_sweep,
        "power_values_W": np.asarray(power_sweep.inputs["limits.power_W"], float),
    }
    lap("power sweep")
    return out, timings


def _core_then_power(
    design: Design, model: Any, powers_W: np.ndarray, say: Callable[[str], None]
) -> tuple[tuple[dict[str, Any], dict[str, float]], tuple[dict[str, Any], dict[str, float]]]:
    """:func:`_core_stage`, then :func:`_power_stage` from its optimum (the compiled NLP and
    the model's cached field caps shared)."""
    core = _core_stage(design, model, say)
    return core, _power_stage(design, powers_W, say, model, core[0]["optimization"])


def _model(design: Design) -> Any:
    """The prepared design model (:func:`spiralcap.assemble.build_model`)."""
    from optimize import prepare
    from spiralcap.assemble import build_model

    return prepare(build_model(design))


def collect(
    design: Design,
    *,
    power_factors: tuple[float, ...] = POWER_FACTORS,
    workers: int = 1,
    progress: Callable[[str], None] | None = None,
    compare: Design | None = None,
    while_waiting: Callable[[CoilStage], None] | None = None,
) -> ReportData:
    """Evaluate and optimise ``design`` and run the sweeps and field maps the report shows.

    Two independent groups of analyses: the evaluation, optimisation, margin curves and the
    power-budget sweep (warm-started from that optimum); the coil analysis and field maps. With
    ``workers >= 2`` (on a system that can fork) the first runs in a forked process while this
    one does the second (and ``while_waiting``); the results are the same numbers bit for bit
    as with ``workers=1``, where everything runs here in turn.

    Parameters
    ----------
    design : Design
        A validated design.
    power_factors : tuple of float
        Power budgets of the trade-off sweep as multiples of ``limits.power_W``.
    workers : int
        Processes to use (1: everything in this process; more than 2 gain nothing here).
    progress : callable, optional
        Called with the name of each stage as it starts (as it finishes, when run in parallel).
    compare : Design, optional
        A second design to evaluate and optimise beside this one
        (:func:`spiralcap.compare.compare_designs`).
    while_waiting : callable, optional
        With the analyses forked: called here as ``while_waiting(coils)`` once the coil
        analysis (:class:`CoilStage`) is done, while the other process still computes. The
        report starts drawing the coil figures there.

    Returns
    -------
    ReportData

    Raises
    ------
    spiralcap.core.errors.InputError
        The design is inconsistent (raised by :func:`spiralcap.assemble.build_model`).
    """
    from spiralcap.parallel import can_fork, inherited, process_pool

    say = progress or (lambda _stage: None)
    powers = design["limits.power_W"] * np.asarray(power_factors, dtype=float)
    if workers >= 2 and can_fork():
        model = _model(design)
        # what the child imports, imported once here before it is forked (forking before
        # these imports, to run them in both processes at once, measured slower)
        import spiralcap.robust
        import spiralcap.serialize
        import spiralcap.sweep  # noqa: F401

        quiet = lambda _stage: None  # noqa: E731 -- the children print nothing
        core_then_power = lambda: _core_then_power(design, model, powers, quiet)  # noqa: E731
        with inherited(core_then_power) as job, process_pool(1) as pool:
            analyses = pool.submit(job)
            coil, coil_t = _coil_stage(design, model, say)
            if while_waiting is not None:
                while_waiting(coil)
            (core, core_t), (power, power_t) = analyses.result()
        for stage in (*core_t, "power sweep"):
            say(stage)
    else:
        model = _model(design)
        (core, core_t), (power, power_t) = _core_then_power(design, model, powers, say)
        coil, coil_t = _coil_stage(design, model, say)
    timings = {**core_t, **coil_t, **power_t}
    comparison = None
    if compare is not None:
        from spiralcap.compare import compare_designs

        say("comparison")
        t = time.perf_counter()
        comparison = compare_designs([design, compare], ("this design", "compared design"))
        timings["comparison"] = time.perf_counter() - t
    return ReportData(
        design=design,
        model=model,
        **core,
        **{f.name: getattr(coil, f.name) for f in fields(CoilStage)[2:]},
        **power,
        versions=versions(),
        timings_s=timings,
        comparison=comparison,
    )
