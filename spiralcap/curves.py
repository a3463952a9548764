"""The arrays behind the figures: margin curves and maps, field maps, the power trade-off.

Each function runs the domain packages' own vectorised functions (``optimize.margin_grid``,
``coils.uniformity``, :func:`spiralcap.sweep.sweep`) and returns a frozen dataclass; the
report (:mod:`spiralcap.report.data`) and the figures API (:mod:`spiralcap.figures.api`) both
read them, so a figure drawn from Python and the report's figure are the same. Nothing here
re-derives physics, draws or writes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from spiralcap.core.constants import to_unit
from spiralcap.design import Design

#: Power budgets of the trade-off sweep, as multiples of the design's ``limits.power_W``.
POWER_FACTORS = (0.25, 0.5, 1.0, 2.0, 4.0)
#: Extra re-optimisations placed adaptively where the Pareto curve bends (its knee).
POWER_REFINEMENTS = 4
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
    """A margin curve from :func:`optimize.margin_grid` along one variable.

    ``speed_slack_m_s`` and ``turns_slack`` are achieved minus required (negative where the
    requirement fails), with :data:`optimize.evaluate.FEASIBILITY_RTOL` allowed, as
    ``feasible`` is.
    """

    x: np.ndarray
    margin_Nm: np.ndarray
    feasible: np.ndarray
    speed_slack_m_s: np.ndarray
    turns_slack: np.ndarray
    frequency_hz: np.ndarray | None = None
    #: least wall strain over the tissue sets at each point, dimensionless (<= 0: no contact,
    #: where ``margin_Nm`` is NaN)
    wall_strain: np.ndarray | None = None
    #: ``requirements.min_wall_strain`` (below it the model extrapolates), dimensionless
    min_wall_strain: float | None = None

    @property
    def grip(self) -> np.ndarray | None:
        """``"ok"``, ``"below minimum"`` or ``"none"`` at each point (optimize.grip_state)."""
        if self.wall_strain is None or self.min_wall_strain is None:
            return None
        from optimize.evaluate import grip_state

        return grip_state(self.wall_strain, self.min_wall_strain)

    def grip_slacks(self) -> dict[str, np.ndarray]:
        """Slacks (negative where the region lies) of no contact and of a strain below the
        minimum, continuous through both edges, for :func:`shortfall_spans`-style hatching:
        ``{"none": strain, "below minimum": -min(strain, min - strain)}``."""
        if self.wall_strain is None or self.min_wall_strain is None:
            return {}
        s = np.asarray(self.wall_strain, float)
        need = float(self.min_wall_strain) * (1 - 1e-6)  # FEASIBILITY_RTOL, as the check
        return {"none": s, "below minimum": -np.minimum(s, need - s)}


@dataclass(frozen=True)
class MarginMap:
    """Margin and feasibility over helical angle x frequency (``optimize.margin_grid``).

    ``margin_Nm`` and ``feasible`` have shape ``(len(frequency_hz), len(helical_angle_deg))``;
    ``failing`` (same shape, str) names the first requirement not met at each point other
    than a negative margin (step-out, drawn as its own region), ``""`` where none is.
    """

    helical_angle_deg: np.ndarray
    frequency_hz: np.ndarray
    margin_Nm: np.ndarray
    feasible: np.ndarray
    failing: np.ndarray | None = None


#: Points per side of the angle x frequency margin map.
MAP_GRID = 90


def margin_map(model: Any, f_max_hz: float) -> MarginMap:
    """The margin over the optimiser's helical-angle bounds and 0.02–``f_max_hz`` Hz."""
    from optimize import margin_grid

    b = model.bounds
    a = np.linspace(b.helical_angle_min_rad, b.helical_angle_max_rad, MAP_GRID)
    f = np.linspace(0.02 * f_max_hz, f_max_hz, MAP_GRID)
    aa, ff = np.meshgrid(a, f)
    from spiralcap.feasibility import failing_requirements

    g = margin_grid(model, aa, ff)
    return MarginMap(
        to_unit(a, "deg"),
        f,
        _grid_field(g, "margin_Nm").astype(float),
        _grid_field(g, "feasible").astype(bool),
        failing_requirements(model, aa, g),
    )


def _grid_field(grid: Any, name: str) -> np.ndarray:
    """A field of ``optimize.margin_grid``'s result (a mapping today, a dataclass later)."""
    value = grid[name] if isinstance(grid, dict) else getattr(grid, name)
    return np.asarray(value)


def angle_curve(model: Any, helical_angle_rad: np.ndarray) -> Curve:
    """Margin against helical angle, each angle at the lowest frequency meeting the speed.

    The margin falls with frequency, and the speed is proportional to it, so at each angle the
    best frequency inside the bounds is the one that just meets ``min_speed`` (or the lower
    bound); the spiral-turns requirement does not depend on frequency. This is the margin a
    helical-angle tolerance costs when the frequency is re-chosen, not at a fixed frequency.
    """
    from optimize import margin_grid

    b, req = model.bounds, model.requirements
    per_hz = _grid_field(margin_grid(model, helical_angle_rad, 1.0), "speed_m_s").astype(float)
    needed = req.min_speed_m_s / np.maximum(per_hz, 1e-300)
    frequency_hz = np.clip(needed, b.frequency_min_hz, b.frequency_max_hz)
    c = curve(
        model,
        helical_angle_rad,
        frequency_hz,
        to_unit(np.asarray(helical_angle_rad, dtype=float), "deg"),
    )
    return replace(c, frequency_hz=frequency_hz)


def curve(model: Any, helical_angle_rad: Any, frequency_hz: Any, x: np.ndarray) -> Curve:
    """Margin, feasibility and requirement slacks at helical angles ``helical_angle_rad`` and
    frequencies ``frequency_hz``, broadcast; ``x`` is what the curve is drawn against."""
    from optimize import margin_grid
    from optimize.evaluate import FEASIBILITY_RTOL

    g = margin_grid(model, helical_angle_rad, frequency_hz)
    req = model.requirements
    tol = 1.0 - FEASIBILITY_RTOL
    return Curve(
        x=x,
        margin_Nm=_grid_field(g, "margin_Nm").astype(float),
        feasible=_grid_field(g, "feasible").astype(bool),
        speed_slack_m_s=_grid_field(g, "speed_m_s") - req.min_speed_m_s * tol,
        turns_slack=_grid_field(g, "spiral_turns") - req.min_spiral_turns * tol,
        wall_strain=np.broadcast_to(_grid_field(g, "wall_strain"), np.shape(g.margin_Nm)),
        min_wall_strain=float(req.min_wall_strain),
    )


def frequency_range_hz(model: Any, *marks_hz: float) -> np.ndarray:
    """Frequencies of the margin-against-frequency curve: past the optimiser's bounds and past
    every frequency in ``marks_hz`` (step-out, the drive's maximum) that was found."""
    b = model.bounds
    hi = 1.5 * b.frequency_max_hz
    for mark in marks_hz:
        if math.isfinite(mark) and mark > 0:
            hi = max(hi, 1.3 * mark)
    hi = max(hi, 1.2 * model.frequency_hz)
    return np.linspace(0.02 * hi, hi, CURVE_POINTS)


def adaptive_power_sweep(
    design: Design,
    powers_W: np.ndarray,
    *,
    refinements: int = POWER_REFINEMENTS,
    workers: int = 1,
    model: Any = None,
    optimum: Any = None,
) -> Any:
    """Re-optimise at each power budget, then bisect where the Pareto curve bends.

    Each refinement adds one budget, at the geometric mean of the interval whose ends differ
    most: by a change of the binding set or of the status (the knee, where power stops
    binding), weighted by the change of margin and the interval's width in log power. A
    refinement is warm-started from the optimum at the lower end of its interval (the upper
    one if the lower is infeasible; grid starts if neither is optimal), as a sweep's points
    are from the previous point's.

    Parameters
    ----------
    design : Design
    powers_W : ndarray
        The first budgets, W (re-optimised as one :func:`spiralcap.sweep.sweep`).
    refinements : int
        Budgets added adaptively.
    workers : int
        Worker processes for the first budgets (the refinements run here, one after another).
    model : DesignModel, optional
        ``spiralcap.assemble.build_model(design)`` if the caller has it (prepared: its
        Constants and their cached field caps are reused); built here otherwise. Tissue
        scenarios are added here when the design asks for them
        (:func:`spiralcap.robust.optimization_model`).
    optimum : optimize.OptimizationResult, optional
        The design's own optimum (``optimize_design`` of that model, at its ``limits.power_W``)
        if the caller has it. Then the first budgets are two warm-started chains going out
        from it, up and down in power (its own budget, if among them, is its row), in this
        process, instead of a sweep whose first budget starts cold; the rows agree to the
        solver's tolerance (1e-10 relative).

    Returns
    -------
    spiralcap.sweep.SweepResult
        One axis, ``limits.power_W``, sorted by power.
    """
    from optimize import prepare
    from spiralcap.robust import optimization_model
    from spiralcap.sweep import Axis, SweepResult, optimize_row, sweep, with_values

    key = "limits.power_W"
    base = prepare(optimization_model(design, model))  # one model for every budget
    if optimum is not None and optimum.status == "optimal":
        p = np.sort(np.asarray(powers_W, float))
        out = _chains_from(optimum, base, key, p, float(design[key]))
    else:
        axis = Axis(key, np.asarray(powers_W, float))
        first = sweep(design, [axis], optimize=True, workers=workers, model=base)
        p = np.asarray(first.inputs[key], float)
        out = {k: np.asarray(v) for k, v in first.outputs.items()}
    for _ in range(refinements):
        margin = np.nan_to_num(np.asarray(out["margin_Nm"], float))
        changed = (out["binding_limits"][1:] != out["binding_limits"][:-1]) | (
            out["status"][1:] != out["status"][:-1]
        )
        span = max(float(np.ptp(margin)), 1e-12)
        score = np.log(p[1:] / p[:-1]) * (
            1.0 + 4.0 * changed + np.abs(np.diff(margin)) / span * 4.0
        )
        i = int(np.argmax(score))
        new = float(np.sqrt(p[i] * p[i + 1]))
        ends = [{k: v[j] for k, v in out.items()} for j in (i, i + 1)]
        warm = next((e for e in ends if e["status"] == "optimal"), None)
        row = optimize_row(with_values(base, {key: new}), warm)
        p = np.insert(p, i + 1, new)
        out = {k: np.insert(v, i + 1, row[k]) for k, v in out.items()}
    return SweepResult((Axis(key, p),), {key: p}, out, "optimize")


def _chains_from(
    optimum: Any, base: Any, key: str, powers_W: np.ndarray, own_W: float
) -> dict[str, np.ndarray]:
    """Rows at sorted ``powers_W``: warm-started chains from ``optimum`` (at ``own_W``), up
    through the budgets at or above it and down through those below."""
    from spiralcap.sweep import optimize_columns, optimize_row, result_row, with_values

    columns = optimize_columns(base)
    anchor = result_row(optimum, columns)
    rows: list[Any] = [None] * len(powers_W)
    up = [j for j in range(len(powers_W)) if powers_W[j] >= own_W]
    down = [j for j in reversed(range(len(powers_W))) if powers_W[j] < own_W]
    for chain in (up, down):
        warm = anchor
        for j in chain:
            if powers_W[j] == own_W:
                rows[j] = anchor
            else:
                rows[j] = optimize_row(with_values(base, {key: float(powers_W[j])}), warm)
            warm = rows[j]
    return {k: np.array([r[k] for r in rows]) for k in columns}


def field_maps(
    system: Any, uniform_radii_m: Mapping[str, Mapping[float, float]] | None = None
) -> tuple[FieldMap, ...]:
    """One deviation map per pair, that pair driven alone (its static field at the centre).

    Parameters
    ----------
    system : coils.ThreeAxisHelmholtz
        The coils.
    uniform_radii_m : mapping axis -> (tolerance -> radius, m), optional
        The ±tolerance sphere of each pair's field direction, drawn on its map (the report
        passes the coil analysis' radii, so the figure and the table show the same numbers);
        computed with ``coils.uniform_region_radius_m`` when not given.
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
        if uniform_radii_m is not None:
            radii = {tol: float(uniform_radii_m[_AXES[k]][tol]) for tol in TOLERANCES}
        else:
            radii = {
                tol: float(coils.uniform_region_radius_m(system, tol, direction=np.eye(3)[k]))
                for tol in TOLERANCES
            }
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


def _marks_hz(ev: Any) -> tuple[float, ...]:
    """The step-out and maximum frequencies of an evaluation that lie inside the search."""
    out = []
    if not getattr(ev, "step_out_beyond_search", False):
        out.append(float(ev.step_out_frequency_hz))
    if hasattr(ev, "max_frequency_hz") and not ev.max_frequency_beyond_search:
        out.append(float(ev.max_frequency_hz))
    return tuple(out)


def frequency_curves(model: Any, evaluation: Any, result: Any = None) -> tuple[Curve, Curve | None]:
    """Margin against frequency at the design's helical angle and at the optimum's.

    The frequency range runs past both step-out frequencies and the optimiser's bounds; the
    optimum's curve is None when the optimisation found no feasible design (or none is given).
    """
    f_grid = frequency_range_hz(model, *_marks_hz(evaluation))
    feasible = result is not None and result.status == "optimal"
    if not feasible:
        return curve(model, evaluation.helical_angle_rad, f_grid, f_grid), None
    f_grid = np.union1d(f_grid, frequency_range_hz(model, *_marks_hz(result.evaluation)))
    # both angles in one grid: the field capacity (the costly part, the same at either angle)
    # is solved once per frequency; each row is the curve of its angle alone, bit for bit
    alphas = np.array([[evaluation.helical_angle_rad], [result.helical_angle_rad]])
    both = curve(model, alphas, f_grid[np.newaxis, :], f_grid)
    design, optimum = (
        Curve(
            f_grid,
            both.margin_Nm[i],
            both.feasible[i],
            both.speed_slack_m_s[i],
            both.turns_slack[i],
            wall_strain=None if both.wall_strain is None else both.wall_strain[i],
            min_wall_strain=both.min_wall_strain,
        )
        for i in (0, 1)
    )
    return design, optimum


def angle_range_rad(model: Any, *angles_rad: float) -> np.ndarray:
    """Helical angles of the angle trade-off: the optimiser's bounds widened to ``angles_rad``."""
    b = model.bounds
    lo = min(b.helical_angle_min_rad, *angles_rad)
    hi = max(b.helical_angle_max_rad, *angles_rad)
    return np.linspace(lo, hi, CURVE_POINTS)
