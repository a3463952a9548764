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
from dataclasses import dataclass, field
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
    "ReportData",
    "coil_sizing_json",
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
    out["platform"] = platform.platform(terse=True)
    return out


def coil_sizing_json(design: Design) -> tuple[dict[str, Any], str]:
    """The dict ``spiralcap coils --json`` prints for ``design``, and where it came from."""
    from spiralcap.analysis.coils import analyse_coils, coils_payload

    return coils_payload(analyse_coils(design)), "spiralcap.analysis.coils.analyse_coils(design)"


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


def collect(
    design: Design,
    *,
    power_factors: tuple[float, ...] = POWER_FACTORS,
    workers: int = 1,
    progress: Callable[[str], None] | None = None,
    compare: Design | None = None,
) -> ReportData:
    """Evaluate and optimise ``design`` and run the sweeps and field maps the report shows.

    Parameters
    ----------
    design : Design
        A validated design.
    power_factors : tuple of float
        Power budgets of the trade-off sweep as multiples of ``limits.power_W``.
    workers : int
        Worker processes for the re-optimisation sweep (1: in this process).
    progress : callable, optional
        Called with the name of each stage as it starts.
    compare : Design, optional
        A second design to evaluate and optimise beside this one
        (:func:`spiralcap.compare.compare_designs`).

    Returns
    -------
    ReportData

    Raises
    ------
    spiralcap.errors.InputError
        The design is inconsistent (raised by :func:`spiralcap.assemble.build_model`).
    """
    from optimize import evaluate, optimize_design, prepare
    from spiralcap.assemble import build_model
    from spiralcap.presentation import jsonable as _jsonable
    from spiralcap.serialize import evaluation_to_dict, optimization_to_dict

    say = progress or (lambda _stage: None)
    timings: dict[str, float] = {}
    t = time.perf_counter()

    def lap(name: str) -> None:
        nonlocal t
        now = time.perf_counter()
        timings[name] = now - t
        t = now

    say("evaluate")
    model = prepare(build_model(design))
    ev = evaluate(model)
    lap("evaluate")
    say("optimize")
    from spiralcap.robust import optimization_model

    res = optimize_design(optimization_model(design, model))  # with tissue scenarios if asked
    lap("optimize")
    evaluate_json = _jsonable({"design": design.source, **evaluation_to_dict(ev)})
    optimize_json = _jsonable({"design": design.source, **optimization_to_dict(res)})

    say("coil sizing")
    from spiralcap.analysis.coils import analyse_coils, coils_payload

    analysis = analyse_coils(design)  # once: the dict the CLI prints and the heating curves
    coils_json = _jsonable(coils_payload(analysis))
    coils_note = "spiralcap.analysis.coils.analyse_coils(design)"
    heating = analysis.heating
    lap("coils")

    say("margin curves")
    freq_design, freq_opt = frequency_curves(model, ev, res)
    angle_opt = angle_curve(
        model, angle_range_rad(model, ev.helical_angle_rad, res.helical_angle_rad)
    )
    mmap = margin_map(model, float(freq_design.x.max()))
    lap("margin curves")

    say("power sweep")
    powers = design["limits.power_W"] * np.asarray(power_factors, dtype=float)
    power_sweep = adaptive_power_sweep(design, powers, workers=workers)
    powers = np.asarray(power_sweep.inputs["limits.power_W"], float)
    lap("power sweep")

    say("field maps")
    maps = field_maps(model.coils, uniform_radii_m(coils_json))
    profile = uniformity_profiles(
        model.coils, MAP_EXTENT * min(p.radius_m for p in model.coils.pairs)
    )
    lap("field maps")
    from spiralcap.report.sections import uncertainty as _uncertainty

    uncertainty = None
    if design_has_uncertainty(design):  # the built-in design has none: no extra work
        say("uncertainty")
        uncertainty = _uncertainty.collect(design, model=model)
        lap("uncertainty")
    comparison = None
    if compare is not None:
        from spiralcap.compare import compare_designs

        say("comparison")
        comparison = compare_designs([design, compare], ("this design", "compared design"))
        lap("comparison")
    return ReportData(
        design=design,
        model=model,
        evaluation=ev,
        optimization=res,
        evaluate_json=evaluate_json,
        optimize_json=optimize_json,
        coils_json=coils_json,
        coils_note=coils_note,
        freq_design=freq_design,
        freq_optimum=freq_opt,
        angle_optimum=angle_opt,
        power_sweep=power_sweep,
        power_values_W=powers,
        field_maps=maps,
        profile=profile,
        versions=versions(),
        timings_s=timings,
        margin_map=mmap,
        comparison=comparison,
        uncertainty=uncertainty,
        heating=heating,
    )
