"""Solve the design NLP with IPOPT (exact CasADi derivatives): one compiled problem, many solves.

1. :func:`optimize.compiled.compile_problem` builds the named parametric NLP of a problem
   *structure* once; every number of the design is a parameter. It is memoised by value, so a
   sweep over limits or requirements re-solves the same compiled solver.
2. A coarse vectorised evaluation (:func:`optimize.evaluate.margin_grid`) over angle x frequency
   gives one start per helical-angle band (the problem need not be convex in the angle), or
   the caller passes a warm start (the previous sweep point).
3. If no start converges to a point that meets every requirement, a relaxed problem (slacks on
   the speed, spiral-turn and safety-factor requirements, limits kept hard) finds how far each
   is out of reach, and the result names it.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import Any, NamedTuple

import numpy as np

from optimize import physics as ph
from optimize import problem as pb
from optimize.compiled import compile_problem, structure_of
from optimize.evaluate import _three, evaluate, grip_bound, margin_grid, worst_required
from optimize.nlp import Solution
from optimize.result import BindingLimit, OptimizationResult, Shortfall
from optimize.system import MODEL, DesignModel, prepare
from spiralcap.core.checks import guard, instance

# --- scales and starts ------------------------------------------------------------------------


def scales_for(model: DesignModel) -> pb.Scales:
    """Reference field, torque, power and mass: values at the centre of the search box.

    Parameters
    ----------
    model : DesignModel
        The design (prepared).

    Returns
    -------
    Scales
        Reference field (T), torque (N·m), power (W) and copper mass (kg).
    """
    b = model.bounds
    alpha = 0.5 * (b.helical_angle_min_rad + b.helical_angle_max_rad)
    f = 0.5 * (b.frequency_min_hz + b.frequency_max_hz)
    c = model.constants
    field = max(float(margin_grid(model, alpha, f, capacity=True).field_amplitude_T), 1e-6)
    need = float(worst_required(model, alpha, f).total_Nm)
    # nothing to resist (no axial load, a lumen wider than the capsule): the magnet's torque
    avail = float(ph.available_torque_Nm(field, c))
    return pb.Scales(
        field_T=field,
        torque_Nm=max(abs(need), 1e-3 * avail, 1e-12),
        power_W=max(float(ph.total_loss_W(field, c, model.ambient_temperature_C)), 1e-9),
        mass_kg=max(float(np.sum(c.copper_mass_kg)), 1e-9),
    )


def _minimises_power(model: DesignModel) -> bool:
    return not pb.OBJECTIVES[model.bounds.objective].uses_t


def initial_points(model: DesignModel, scales: pb.Scales, starts: int) -> list[dict[str, float]]:
    """One start per helical-angle band: the best point of a coarse grid in that band.

    Parameters
    ----------
    model : DesignModel
        The design (prepared).
    scales : Scales
        Reference magnitudes.
    starts : int
        Number of starts (helical-angle bands).

    Returns
    -------
    list of dict of str to float
        Per start, ``helical_angle_rad``, ``frequency_hz``, ``field_scaled`` (field /
        ``scales.field_T``, dimensionless) and ``t`` (the epigraph variable, dimensionless).
    """
    b = model.bounds
    alphas = np.linspace(b.helical_angle_min_rad, b.helical_angle_max_rad, 8 * max(starts, 1))
    freqs = np.geomspace(b.frequency_min_hz, b.frequency_max_hz, 24)
    A, F = np.meshgrid(alphas, freqs, indexing="ij")
    g = margin_grid(model, A, F, capacity=True)
    field = g.field_amplitude_T
    # a number everywhere, no contact included (a start only, never a design's margin)
    margin = np.asarray(g.model_margin_Nm, dtype=float)
    t0 = margin / scales.torque_Nm
    if model.bounds.objective == "ratio":
        score = t0 = np.asarray(g.model_safety_factor, dtype=float)
    elif _minimises_power(model):
        need = worst_required(model, A, F).total_Nm
        c = model.constants
        needed = model.requirements.min_safety_factor * need / (c.moment_Am2 * c.workspace_factor)
        ok = needed <= field
        field = np.minimum(needed, field)
        score = np.where(ok, -field, -field - 1.0)
        t0 = np.zeros_like(field)
    else:
        score = margin
    score = np.where(g.feasible, score, score - 1e3 * np.abs(score).max() - 1.0)
    out = []
    for band in np.array_split(np.arange(alphas.size), max(starts, 1)):
        sub = score[band]
        i, j = np.unravel_index(np.argmax(sub), sub.shape)
        out.append(
            {
                "helical_angle_rad": float(A[band][i, j]),
                "frequency_hz": float(F[band][i, j]),
                "field_scaled": float(field[band][i, j]) / scales.field_T,
                "t": float(t0[band][i, j]),
            }
        )
    return out


def grid_points(model: DesignModel) -> list[tuple[float, float, float]]:
    """The grid starts of ``model`` as (angle, frequency, field) points.

    Parameters
    ----------
    model : DesignModel
        The design (prepared).

    Returns
    -------
    list of (float, float, float)
        (angle, rad; frequency, Hz; field, T) of each grid start.
    """
    scales = scales_for(model)
    return [
        (x["helical_angle_rad"], x["frequency_hz"], x["field_scaled"] * scales.field_T)
        for x in initial_points(model, scales, model.bounds.starts)
    ]


def variable_bounds(model: DesignModel) -> dict[str, tuple[float, float]]:
    """Box bounds of the named variables (physical units).

    Parameters
    ----------
    model : DesignModel
        The design.

    Returns
    -------
    dict of str to (float, float)
        Bounds of ``helical_angle_rad``, ``frequency_hz`` and ``t`` (dimensionless).
    """
    b = model.bounds
    t = (0.0, 0.0) if _minimises_power(model) else (-np.inf, np.inf)
    return {
        "helical_angle_rad": (b.helical_angle_min_rad, b.helical_angle_max_rad),
        "frequency_hz": (b.frequency_min_hz, b.frequency_max_hz),
        "t": t,
    }


# --- the solve --------------------------------------------------------------------------------


@dataclass(frozen=True)
class SolveOptions:
    """How :func:`solve_fixed` solves a design at fixed hardware.

    Parameters
    ----------
    diagnose : bool
        When nothing is feasible, solve the relaxed problem that says what is out of reach
        (False: the status is still 'infeasible').
    grid_starts : bool
        Try the grid starts when the warm start fails (False: the warm start alone).
    frequency_bounds : bool
        Search the evaluation's step-out and highest frequency (False: NaN; the rows of a
        sweep and the ranking of sizing's neighbours need neither).
    scales : Scales, optional
        The NLP's reference field (T), torque (N·m), power (W) and mass (kg); default
        :func:`scales_for` of the model (sizing passes the relaxation's).
    candidate : bool
        A result only ranked by its objective and feasibility (sizing's neighbours):
        evaluated at the solver's field as a set field, without the field capacity of the
        limits; the objective agrees with the full result's to the solver's tolerance.
    """

    diagnose: bool = True
    grid_starts: bool = True
    frequency_bounds: bool = True
    scales: pb.Scales | None = None
    candidate: bool = False


def _warm_candidates(warm_start: OptimizationResult | dict | None) -> list[tuple[Any, Any, bool]]:
    """(start, multipliers, warm) of a warm start: a dict of ``helical_angle_rad``, ``frequency_hz``,
    ``field_T`` (``t_value``), or a neighbouring problem's result."""
    if isinstance(warm_start, dict):
        return [(dict(warm_start), None, True)]
    if warm_start is not None and warm_start.solution_x:
        return [(dict(warm_start.solution_x), warm_start.solution_lam_g, True)]
    return []


class _Search(NamedTuple):
    best: Solution | None
    grid: list[dict[str, float]]
    iterations: int
    tried: int


def _search(model: DesignModel, scales: pb.Scales, warm_start: Any, grid_starts: bool) -> _Search:
    """The warm start first (if any; a converged warm solve ends the search), then the grid
    starts unless ``grid_starts`` is False; the best converged solve."""
    bounds = variable_bounds(model)
    candidates = _warm_candidates(warm_start)
    iterations, tried, i = 0, 0, 0
    best: Solution | None = None
    grid: list[dict[str, float]] | None = None
    while True:
        if i >= len(candidates):
            if (best is not None and best.success) or grid is not None:
                break
            if not grid_starts and candidates:
                break
            grid = initial_points(model, scales, model.bounds.starts)
            candidates += [(x, None, False) for x in grid]
            continue
        x0, lam0, warm = candidates[i]
        i += 1
        problem = compile_problem(structure_of(model, warm=warm))
        p = problem.parameters(model, scales)
        if warm:
            x0 = {**x0, "field_scaled": x0["field_T"] / scales.field_T}
            x0["t"] = x0["t_value"] / _obj_scale(model, scales) if "t_value" in x0 else 0.0
        sol = problem.nlp.solve(x0, p, bounds, lam_g0=lam0 if warm else None)
        iterations, tried = iterations + sol.iterations, tried + 1
        if sol.success and (best is None or not best.success or sol.f < best.f):
            best = sol
        if warm and sol.success:
            break
    return _Search(best, grid or [], iterations, tried)


def solve_fixed(
    model: DesignModel,
    warm_start: OptimizationResult | dict | None = None,
    options: SolveOptions = SolveOptions(),
) -> OptimizationResult:
    """Best operating point of ``model`` at its fixed hardware, for its objective (one NLP;
    a model with a whole tissue-scenario set goes through
    :func:`optimize.active_set.optimize_scenarios`).

    Parameters
    ----------
    model : DesignModel
        The design, SI; its hardware is fixed (``model.sizing`` is not read).
    warm_start : OptimizationResult or dict, optional
        A result of a neighbouring problem (the previous sweep point), or a dict of
        ``helical_angle_rad``, ``frequency_hz``, ``field_T`` (T) (and ``t_value``); tried
        first, the grid starts only if it fails.
    options : SolveOptions
        What to search and evaluate.

    Returns
    -------
    OptimizationResult
        'optimal', or 'infeasible' with what is out of reach.
    """
    t0 = time.perf_counter()
    model = prepare(model)
    scales = scales_for(model) if options.scales is None else options.scales
    found = _search(model, scales, warm_start, options.grid_starts)
    best = found.best
    how = (found.iterations, found.tried, t0)
    status_text = best.status if best is not None else "no start"
    if (best is None or not best.success) and not options.diagnose:
        ev = evaluate(model, frequency_bounds=options.frequency_bounds)
        message = "infeasible: no start converged"
        return _result(
            model,
            "infeasible",
            ev,
            (),
            (),
            status_text,
            *how,
            message,
            objective_value=float("nan"),
            solution=None,
            field_set=False,
        )
    if best is None or not best.success:
        return _infeasible(model, scales, found.grid, *how, status_text)
    return _optimum(model, scales, best, found, options, t0)


def _optimum(
    model: DesignModel,
    scales: pb.Scales,
    best: Solution,
    found: _Search,
    options: SolveOptions,
    t0: float,
) -> OptimizationResult:
    """The result at a converged optimum: evaluated, with what binds."""
    xs = best.values()
    alpha, f = xs["helical_angle_rad"], xs["frequency_hz"]
    field = xs["field_scaled"] * scales.field_T
    # the field ends below what the limits allow when the objective or a registered row says so
    # (a candidate: taken as set, its rows hold every limit to the solver's tolerance)
    capacity = (
        field
        if options.candidate
        else float(margin_grid(model, alpha, f, capacity=True).field_amplitude_T)
    )
    field_set = options.candidate or _minimises_power(model) or field < capacity * (1 - 1e-7)
    # an explicit field only where the optimum's differs from the largest the limits allow (or
    # the model carries a set field the optimiser was free to move)
    given = field if field_set else (capacity if model.field_amplitude_T is not None else None)
    ev = evaluate(
        model, alpha, f, field_amplitude_T=given, frequency_bounds=options.frequency_bounds
    )
    how = (found.iterations, found.tried, t0)
    if not ev.feasible:
        return _infeasible(model, scales, found.grid, *how, best.status, ev)
    x_named = {
        **{k: v for k, v in xs.items() if k not in ("field_scaled", "t")},  # + hooks' variables
        "field_T": field,
        "t_value": xs["t"] * _obj_scale(model, scales),
    }
    return _result(
        model,
        "optimal",
        ev,
        binding(model, scales, best),
        (),
        best.status,
        *how,
        "optimal: every requirement met inside every limit",
        objective_value=_objective_value(model, ev, best.f, scales),
        solution=(x_named, best.lam_g),
        field_set=field_set,
    )


_BUILT_IN = ("margin", "ratio", "power", "copper_mass")


def _obj_scale(model: DesignModel, scales: pb.Scales) -> float:
    return float(pb.OBJECTIVES[model.bounds.objective].scale(scales))


def _objective_value(
    model: DesignModel, ev: Any, f: float = float("nan"), scales: pb.Scales | None = None
) -> float:
    """The reported objective at an evaluation: margin, safety factor, power or copper mass;
    for a registered objective, ``U = -sense · scale · F`` from the solver's ``F``."""
    obj = model.bounds.objective
    c = model.constants
    if obj not in _BUILT_IN and scales is not None:
        spec = pb.OBJECTIVES[obj]
        return float(-spec.sense * spec.scale(scales) * f)
    if obj == "ratio":
        return ev.safety_factor
    if obj == "power":  # each pair at its own mean winding temperature at this current
        return float(ph.total_loss_W(ev.field_amplitude_T, c, model.ambient_temperature_C))
    if obj == "copper_mass":
        return float(np.sum(c.copper_mass_kg))
    return ev.margin_Nm


def binding(
    model: DesignModel,
    scales: pb.Scales,
    sol: Solution,
    extra_bounds: dict[str, tuple[float, float]] | None = None,
) -> tuple[BindingLimit, ...]:
    """Active rows and bounds with their sensitivities d objective / d allowed (SI).

    Parameters
    ----------
    model : DesignModel
        The design the NLP was built for, SI.
    scales : Scales
        The NLP's reference field (T), torque (N·m), power (W) and mass (kg).
    sol : Solution
        A converged solve.
    extra_bounds : dict, optional
        Boxes ``(lo, hi)`` of further variables (free hardware) by name, each in the unit its
        name carries (``*_m`` in m, turns a count), reported as ``<name>@max``/``@min``.

    Returns
    -------
    tuple of BindingLimit
        Each binding row or bound: its value and allowed value (SI, temperatures in °C) and
        the gain of the objective per unit of the allowed value.
    """
    spec = pb.OBJECTIVES[model.bounds.objective]
    k = spec.sense * _obj_scale(model, scales)  # U = -sense * scale * F
    if model.bounds.objective == "copper_mass" and not extra_bounds:
        k = 0.0  # fixed hardware: no limit moves the copper (F's power term only picks a field)
    return _row_bindings(model, sol, k, spec.sense) + _bound_bindings(
        model, sol, k, spec.sense, extra_bounds or {}
    )


def _row_bindings(
    model: DesignModel, sol: Solution, k: float, sense: float
) -> tuple[BindingLimit, ...]:
    """The binding rows (``k``: d U / d F, the objective's scale and sense)."""
    allowed, _, value = sol.allowed()
    sens = sol.row_sensitivities()
    amb = float(model.ambient_temperature_C)
    out = []
    for i, row in enumerate(sol.nlp.rows):
        if row.kind in ("objective", "epigraph") or not np.isfinite(allowed[i]):
            continue
        if not _binds(float(value[i]), float(allowed[i]), sol.g[i], sol.lam_g[i]):
            continue
        unit, v, a = row.unit, float(value[i]), float(allowed[i])
        if row.kind == "limit" and unit == "K":  # a temperature rise: the temperature, °C
            unit, v, a = "°C", v + amb, a + amb
        gain = float(-k * sens[i]) if k else 0.0  # no -0.0 where nothing moves
        out.append(BindingLimit(row.name, unit, v, a, gain, row.relax_sign, sense))
    return tuple(out)


def _bound_bindings(
    model: DesignModel,
    sol: Solution,
    k: float,
    sense: float,
    extra_bounds: dict[str, tuple[float, float]],
) -> tuple[BindingLimit, ...]:
    """The variables at a bound of their box (angle, frequency, free hardware)."""
    box = {**variable_bounds(model), **extra_bounds}
    #: (variable, the name its bound is reported under, unit): the angle's and the
    #: frequency's bounds are ``helical_angle_min`` ... (the binding names of the JSON)
    named = [("helical_angle_rad", "helical_angle", "rad"), ("frequency_hz", "frequency", "Hz")]
    named += [(n, n, "turns" if n.endswith("turns") else "m") for n in extra_bounds]
    out = []
    for name, shown, unit in named:
        lam = sol.bound_multiplier(name)  # d F / d ub = -lam (per physical unit)
        if abs(lam) < 1e-9 / sol.nlp.variables[sol.nlp.var_index[name]].ref:
            continue
        lo, hi = box[name]
        x = sol.value(name)
        at_hi = abs(x - hi) < abs(x - lo)
        sep = "@" if name in extra_bounds else "_"
        out.append(
            BindingLimit(
                f"{shown}{sep}{'max' if at_hi else 'min'}",
                unit,
                float(x),
                float(hi if at_hi else lo),
                float(k * lam),
                1.0 if at_hi else -1.0,
                sense,
            )
        )
    return tuple(out)


#: A row binds when its value is within this relative distance of its allowed value.
BINDING_RTOL = 1e-6


def _binds(value: float, allowed: float, g: float, lam: float) -> bool:
    """Whether a row binds at the optimum: its value within :data:`BINDING_RTOL` (relative) of
    its allowed value, or active (g ≈ 0) with a multiplier that is not zero."""
    if np.isfinite(value) and abs(value - allowed) <= BINDING_RTOL * max(abs(allowed), 1e-300):
        return True
    return bool(g >= -BINDING_RTOL and abs(lam) >= 1e-9)


def _infeasible(model, scales, starts, iterations, tried, t0, status_text, ev=None):
    """Solve the relaxed problem and report which requirement is out of reach, by how much.

    The relaxed problem is solved where the spiral grips (``grip_bound``: the helical angle no
    steeper than the one that stretches every wall by ``requirements.min_wall_strain``), so
    the explanation stands at the closest design inside the model's domain, and its
    shortfalls are that design's own evaluation; where no angle grips, at the angle that
    stretches the walls most (the grip itself is then what is out of reach).
    """
    grip = grip_bound(model)
    best, spent = _closest_gripping(model, scales, starts, grip.helical_angle_max_rad)
    iterations += spent
    tried += len(starts or initial_points(model, scales, model.bounds.starts))
    xs = best.values()
    alpha, f = xs["helical_angle_rad"], xs["frequency_hz"]
    capacity = float(margin_grid(model, alpha, f, capacity=True).field_amplitude_T)
    field = xs["field_scaled"] * scales.field_T if _minimises_power(model) else None
    if field is None and model.field_amplitude_T is not None:
        field = capacity
    ev = evaluate(model, alpha, f, field_amplitude_T=field)
    # every requirement out of reach, and any limit the closest design still breaks (a set
    # field above what a limit allows), with the allowed value and the value reached
    from optimize.buildcheck import BUILD_CHECK_NAMES

    shortfalls = tuple(
        Shortfall(c.name, c.unit, c.allowed, c.value)
        for c in ev.failed()
        # the hardware's own: no operating point changes the copper mass; a margin with no
        # contact (NaN) is not a shortfall, the grip that is out of reach is
        if (c.sense == ">=" or c.name in BUILD_CHECK_NAMES) and c.value == c.value
    ) + _hook_shortfalls(best)
    if not grip.reachable:  # no angle grips: that is what is out of reach (no speed without it)
        shortfalls = tuple(s for s in shortfalls if s.name.startswith("wall_strain["))
    if not shortfalls and ev.feasible:
        # the relaxed optimum meets everything (IPOPT failed from the grid starts for another
        # reason): start the problem itself there
        again = _from_relaxed_optimum(model, ev, alpha, f)
        if again.status == "optimal":
            return replace(again, iterations=again.iterations + iterations)
    if not shortfalls:  # IPOPT failed for another reason: say where it stopped, with numbers
        sf = model.requirements.min_safety_factor
        shortfalls = (Shortfall("solver", "1", sf, ev.safety_factor),)
    names = ", ".join(s.name for s in shortfalls)
    return _result(
        model,
        "infeasible",
        ev,
        (),
        shortfalls,
        status_text,
        iterations,
        tried,
        t0,
        f"infeasible: no design inside the limits meets {names}"
        + (
            " (explained at the closest design that grips, every wall strain >= "
            "requirements.min_wall_strain)"
            if grip.reachable
            else " (no helical angle in the bounds grips: explained at the one that stretches "
            "the walls most)"
        ),
        objective_value=float("nan"),
        solution=None,
        field_set=field is not None,
    )


#: The slacks held at zero first when explaining an infeasible design: the speed and the spiral
#: turns are met, so what is left short is the torque (the margin or safety factor), unless
#: no design inside the limits meets them even so.
_HARD_FIRST = ("slack_speed", "slack_turns")


def _closest_gripping(
    model: DesignModel, scales: pb.Scales, starts: list[dict[str, float]], alpha_max_rad: float
) -> tuple[Solution, int]:
    """The design the infeasibility is explained at: the relaxed problem at angles that grip
    (at most ``alpha_max_rad``), first with the speed and turns held (:data:`_HARD_FIRST`:
    the torque is then what is out of reach, by how much), else with every slack free."""
    spent = 0
    if _speed_and_turns_reachable(model, alpha_max_rad):
        best, spent = _relaxed_optimum(model, scales, starts, alpha_max_rad, _HARD_FIRST)
        if best.success:
            return best, spent
    best, more = _relaxed_optimum(model, scales, starts, alpha_max_rad)
    return best, spent + more


def _speed_and_turns_reachable(model: DesignModel, alpha_max_rad: float) -> bool:
    """Whether some helical angle up to ``alpha_max_rad`` (inside the box) meets the speed at
    the highest frequency and the spiral turns: the rows :data:`_HARD_FIRST` holds depend on
    the angle and frequency only (the field, which the limits cap, only moves the torque), so
    this says whether that relaxed problem has a solution without solving it."""
    b, c, req = model.bounds, model.constants, model.requirements
    lo = b.helical_angle_min_rad
    alpha = np.linspace(lo, max(lo, min(b.helical_angle_max_rad, alpha_max_rad)), 257)
    speed = np.asarray(ph.speed_m_s(alpha, b.frequency_max_hz, c, req), dtype=float)
    turns = np.asarray(ph.spiral_turns(alpha, c), dtype=float)
    rtol = 1e-6
    ok = (speed >= req.min_speed_m_s * (1 - rtol)) & (turns >= req.min_spiral_turns * (1 - rtol))
    return bool(ok.any())


def _relaxed_optimum(
    model: DesignModel,
    scales: pb.Scales,
    starts: list[dict[str, float]],
    alpha_max_rad: float | None = None,
    hard: tuple[str, ...] = (),
) -> tuple[Solution, int]:
    """The relaxed problem (slacks on the requirements) from each start: the best solve (a
    converged one first), and the iterations spent. ``alpha_max_rad``: the helical angle held
    at or below it (where the spiral grips, :func:`optimize.evaluate.grip_bound`); ``hard``:
    slacks held at zero (those requirements met)."""
    problem = compile_problem(structure_of(model, relaxed=True))
    p = problem.parameters(model, scales)
    bounds = {**variable_bounds(model), "t": (0.0, 0.0)}
    if alpha_max_rad is not None:
        lo = bounds["helical_angle_rad"][0]
        bounds["helical_angle_rad"] = (
            lo,
            max(lo, min(bounds["helical_angle_rad"][1], alpha_max_rad)),
        )
    bounds.update(dict.fromkeys(hard, (0.0, 0.0)))
    starts = starts or initial_points(model, scales, model.bounds.starts)
    best, iterations = None, 0
    slacks = [v.name for v in problem.nlp.variables if v.name.startswith("slack")]
    for x0 in starts:
        sol = problem.nlp.solve({**x0, "t": 0.0, **dict.fromkeys(slacks, 1.0)}, p, bounds)
        iterations += sol.iterations
        if best is None or (not best.success, best.f) > (not sol.success, sol.f):
            best = sol
    assert best is not None  # at least one start
    return best, iterations


def _from_relaxed_optimum(
    model: DesignModel, ev: Any, alpha: float, f: float
) -> OptimizationResult:
    """The problem itself, warm-started at the relaxed optimum (angle ``alpha``, rad, and
    frequency ``f``, Hz) and its evaluation ``ev``."""
    warm = {
        "helical_angle_rad": alpha,
        "frequency_hz": f,
        "field_T": ev.field_amplitude_T,
        "t_value": _objective_value(model, ev) if not _minimises_power(model) else 0.0,
    }
    if model.bounds.objective not in ("margin", "ratio"):
        warm.pop("t_value")
    return solve_fixed(model, warm, SolveOptions(diagnose=False, grid_starts=False))


def _hook_shortfalls(sol: Solution) -> tuple[Shortfall, ...]:
    """Registered requirement rows the relaxed optimum needs a slack for (``slack[<row>]``),
    with the row's allowed value and the value it reaches there."""
    allowed, _, value = sol.allowed()
    out = []
    for i, row in enumerate(sol.nlp.rows):
        name = f"slack[{row.name}]"
        if name in sol.nlp.var_index and sol.value(name) > 1e-7:
            out.append(Shortfall(row.name, row.unit, float(allowed[i]), float(value[i])))
    return tuple(out)


def _result(
    model,
    status,
    ev,
    binding,
    shortfalls,
    solver_status,
    iterations,
    starts,
    t0,
    message,
    *,
    objective_value,
    solution,
    field_set,
) -> OptimizationResult:
    allocations: list[Any] = []
    for h in model.headings:
        amps, phases = model.coils.rotating_allocation(h, ev.field_amplitude_T)
        allocations.append((_three(amps), _three(phases)))
    return OptimizationResult(
        status=status,
        objective=model.bounds.objective,
        helical_angle_rad=ev.helical_angle_rad,
        frequency_hz=ev.frequency_hz,
        field_amplitude_T=ev.field_amplitude_T,
        margin_Nm=ev.margin_Nm,
        safety_factor=ev.safety_factor,
        current_amplitudes_A=ev.current_amplitudes_A,
        current_phases_rad=tuple(allocations),
        headings=tuple((float(h[0]), float(h[1]), float(h[2])) for h in model.headings),
        speed_m_s=ev.speed_m_s,
        step_out_frequency_hz=ev.step_out_frequency_hz,
        binding_limits=binding,
        shortfalls=shortfalls,
        solver_status=solver_status,
        iterations=iterations,
        starts=starts,
        solve_time_s=time.perf_counter() - t0,
        evaluation=ev,
        message=message,
        objective_value=objective_value,
        field_is_set=field_set,
        solution_x=solution[0] if solution else None,
        solution_lam_g=solution[1] if solution else None,
    )


@guard(
    model=MODEL,
    result=instance(OptimizationResult, "an optimize.OptimizationResult (optimize_design)"),
)
def with_operating_point(model: DesignModel, result: OptimizationResult) -> DesignModel:
    """The model moved to the optimum's helical angle, frequency (and field, where set).

    Parameters
    ----------
    model : DesignModel
        The design.
    result : OptimizationResult
        The optimum.

    Returns
    -------
    DesignModel
        The design at the optimum's angle (rad), frequency (Hz) and set field (T).
    """
    spiral = replace(model.capsule.spiral, helical_angle_rad=result.helical_angle_rad)
    return replace(
        model,
        capsule=replace(model.capsule, spiral=spiral),
        frequency_hz=result.frequency_hz,
        field_amplitude_T=result.field_amplitude_T if result.field_is_set else None,
    )
