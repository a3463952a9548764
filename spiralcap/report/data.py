"""Run the analyses a report shows and keep their results (no formatting, no plotting).

Every number the report prints comes from the dicts the CLI prints
(:func:`spiralcap.serialize.evaluation_to_dict`, :func:`spiralcap.serialize.optimization_to_dict`,
the ``spiralcap coils --json`` dict); the arrays behind the figures come from the domain
packages' own vectorised functions (:func:`optimize.margin_grid`, :func:`coils.uniformity`,
:func:`spiralcap.sweep.sweep`). Nothing here re-derives physics.
"""

from __future__ import annotations

import importlib.metadata
import math
import platform
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from spiralcap.design import Design

#: Power budgets of the trade-off sweep, as multiples of the design's ``limits.power_W``.
POWER_FACTORS = (0.25, 0.4, 0.63, 1.0, 1.6, 2.5, 4.0)
#: Points of the margin-against-frequency and margin-against-angle curves.
CURVE_POINTS = 241
#: Grid of each field map (points per side) and its half-width as a fraction of the smallest
#: coil radius (kept clear of the windings, where the filament field is singular).
MAP_POINTS, MAP_EXTENT = 81, 0.8
#: Uniformity tolerances reported (±1 % and ±5 %).
TOLERANCES = (0.01, 0.05)
_AXES = ("x", "y", "z")
#: The plane of each field map: the driven pair's axis and a second axis (indices).
_MAP_PLANES = {0: (0, 2), 1: (1, 2), 2: (0, 2)}


@dataclass(frozen=True)
class FieldMap:
    """|B| deviation on a plane through the centre with one pair driven (static field).

    Attributes
    ----------
    axis : str
        The driven pair (``x``, ``y`` or ``z``); the field at the centre points along it.
    plane : tuple of str
        The plane's two axes (``("x", "z")``).
    u_m, v_m : ndarray
        Grid coordinates, m.
    deviation : ndarray, shape (len(v_m), len(u_m))
        |B(p)| / |B(0)| - 1, dimensionless (``coils.uniformity``).
    uniform_radii_m : dict float -> float
        Radius of the ±tolerance sphere for this field direction, m
        (``coils.uniform_region_radius_m(system, tol, direction=e_axis)``).
    """

    axis: str
    plane: tuple[str, str]
    u_m: np.ndarray
    v_m: np.ndarray
    deviation: np.ndarray
    uniform_radii_m: dict[float, float]


@dataclass(frozen=True)
class Curve:
    """A margin curve from :func:`optimize.margin_grid` along one variable."""

    x: np.ndarray
    margin_Nm: np.ndarray
    feasible: np.ndarray


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
    from spiralcap.commands.coils import sizing_payload

    return sizing_payload(design), "spiralcap.commands.coils.sizing_payload(design)"


def _curve(model: Any, alpha: Any, f: Any, x: np.ndarray) -> Curve:
    from optimize import margin_grid

    g = margin_grid(model, alpha, f)
    return Curve(
        x=x, margin_Nm=np.asarray(g["margin_Nm"], float), feasible=np.asarray(g["feasible"], bool)
    )


def frequency_range_hz(model: Any, step_out_hz: float) -> np.ndarray:
    """Frequencies of the margin-against-frequency curve: past the step-out and the bounds."""
    b = model.bounds
    hi = 1.5 * b.frequency_max_hz
    if math.isfinite(step_out_hz) and step_out_hz > 0:
        hi = max(hi, 1.3 * step_out_hz)
    hi = max(hi, 1.2 * model.frequency_hz)
    return np.linspace(0.02 * hi, hi, CURVE_POINTS)


def field_maps(system: Any, uniform: dict[str, Any]) -> tuple[FieldMap, ...]:
    """One deviation map per pair, that pair driven alone (its static field at the centre).

    Parameters
    ----------
    system : coils.ThreeAxisHelmholtz
        The coils.
    uniform : dict
        The ``uniform_region`` entry of the ``spiralcap coils --json`` dict; its per-axis
        radii are drawn on the maps (so the figure and the table show the same radii).
    """
    import coils

    gains = np.asarray(system.centre_gains_T_per_A, dtype=float)
    half = MAP_EXTENT * min(p.radius_m for p in system.pairs)
    grid = np.linspace(-half, half, MAP_POINTS)
    maps = []
    for k in range(3):
        iu, iv = _MAP_PLANES[k]
        uu, vv = np.meshgrid(grid, grid)
        pts = np.zeros((uu.size, 3))
        pts[:, iu], pts[:, iv] = uu.ravel(), vv.ravel()
        dev = np.asarray(coils.uniformity(system, pts, np.eye(3)[k] / gains)).reshape(uu.shape)
        per_axis = uniform["per_axis"][_AXES[k]]
        radii = {tol: float(per_axis[f"radius_{round(100 * tol)}pct_m"]) for tol in TOLERANCES}
        maps.append(FieldMap(_AXES[k], (_AXES[iu], _AXES[iv]), grid, grid, dev, radii))
    return tuple(maps)


def uniformity_profiles(
    system: Any, half_width_m: float, n: int = 121
) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """|B| deviation along each pair's axis and across it, that pair driven alone."""
    import coils

    gains = np.asarray(system.centre_gains_T_per_A, dtype=float)
    d = np.linspace(-half_width_m, half_width_m, n)
    out: dict[str, np.ndarray] = {}
    for k in range(3):
        across = (k + 1) % 3
        for j, words in ((k, "along its axis"), (across, f"along {_AXES[across]}")):
            pts = np.zeros((n, 3))
            pts[:, j] = d
            out[f"{_AXES[k]} pair, {words}"] = np.asarray(
                coils.uniformity(system, pts, np.eye(3)[k] / gains)
            )
    return d, out


def collect(
    design: Design,
    *,
    power_factors: tuple[float, ...] = POWER_FACTORS,
    workers: int = 1,
    progress: Callable[[str], None] | None = None,
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
    from spiralcap.commands._common import _jsonable
    from spiralcap.serialize import evaluation_to_dict, optimization_to_dict
    from spiralcap.sweep import Axis, sweep

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
    coils_json, coils_note = coil_sizing_json(design)
    coils_json = _jsonable(coils_json)
    lap("coils")

    say("margin curves")
    f_grid = frequency_range_hz(model, ev.step_out_frequency_hz)
    if res.status == "optimal":
        f_grid = np.union1d(f_grid, frequency_range_hz(model, res.step_out_frequency_hz))
    freq_design = _curve(model, ev.helical_angle_rad, f_grid, f_grid)
    freq_opt = (
        _curve(model, res.helical_angle_rad, f_grid, f_grid) if res.status == "optimal" else None
    )
    b = model.bounds
    lo = min(b.helical_angle_min_rad, ev.helical_angle_rad, res.helical_angle_rad)
    hi = max(b.helical_angle_max_rad, ev.helical_angle_rad, res.helical_angle_rad)
    a_grid = np.linspace(lo, hi, CURVE_POINTS)
    angle_opt = _curve(model, a_grid, res.frequency_hz, np.degrees(a_grid))
    lap("margin curves")

    say("power sweep")
    powers = design["limits.power_W"] * np.asarray(power_factors, dtype=float)
    power_sweep = sweep(design, [Axis("limits.power_W", powers)], optimize=True, workers=workers)
    lap("power sweep")

    say("field maps")
    maps = field_maps(model.coils, coils_json["uniform_region"])
    profile = uniformity_profiles(
        model.coils, MAP_EXTENT * min(p.radius_m for p in model.coils.pairs)
    )
    lap("field maps")
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
    )
