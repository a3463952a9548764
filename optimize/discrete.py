"""Hardware sizing: solve the continuous relaxation, then search the neighbouring buildable
designs (whole turns, standard wire diameters), re-optimising the operating point of each.

1. The relaxation: hardware and operating point in one NLP (:mod:`optimize.hardware`), with the
   frozen factors (pack corrections, workspace field factor, linearised gaps between the mean
   turns, the clearance correction) recomputed
   exactly at each new hardware and the NLP re-solved warm until they settle.
2. The neighbours: each turn count rounded down and up, each wire diameter to the standard sizes
   just below and above; continuous quantities (radii, magnet, spiral wire) stay at the relaxed
   value. Every neighbour is built exactly (coils, capsule), checked (exact pack clearances,
   bore, copper mass, magnet fit)
   and re-optimised with the fixed-hardware solver; the best wins.
"""

from __future__ import annotations

import bisect
import functools
import itertools
import math
import os
import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any, NamedTuple

import numpy as np

from optimize import hardware as hw
from optimize import problem as pb
from optimize import screen
from optimize.result import HardwareResult, OptimizationResult, Shortfall
from optimize.system import DesignModel, prepare

_OUTER_MAX = 8
#: Frozen factors settled (relative): the relaxed hardware itself moves by ~1e-7 relative from
#: round to round at IPOPT's tolerance where the objective is flat in it (the margin objective),
#: so factors computed from it settle no tighter (the inductance's pack correction by ~1e-8).
_OUTER_RTOL = 1e-7
#: The clearance correction's settling tolerance, m: 1e-6 of the clearance rows' 10 mm scale
#: (the exact clearance is resolved to 1e-9 m; the hardware's round-to-round movement at
#: IPOPT's tolerance moves it by ~2e-9 m).
_DELTA_ATOL_m = 1e-8


def _options(v: hw.FreeVariable, x: float, wires: tuple[float, ...]) -> list[float]:
    if v.kind == "turns":
        lo, hi = math.ceil(v.lo - 1e-9), math.floor(v.hi + 1e-9)
        opts = {min(max(math.floor(x), lo), hi), min(max(math.ceil(x), lo), hi)}
        return sorted(float(o) for o in opts)
    if v.kind == "wire":
        allowed = [d for d in wires if v.lo * (1 - 1e-9) <= d <= v.hi * (1 + 1e-9)]
        if not allowed:
            return []
        i = bisect.bisect_left(allowed, x)
        return sorted({allowed[max(i - 1, 0)], allowed[min(i, len(allowed) - 1)]})
    return [x]


def _neighbours(problem, p, bounds, best, free, sizing) -> tuple[list[dict[str, float]], int]:
    """The discrete designs to try around the relaxed optimum ``best``.

    Wire diameters first: for each combination of the standard sizes just below and above the
    relaxed ones, the relaxation is re-solved with those wires fixed (the turns re-balance), and
    each turn count of that solution is rounded down and up. Without free wires: every turn
    count rounded down and up.
    """
    wires = [v for v in free if v.kind == "wire"]
    rest = [v for v in free if v.kind != "wire"]
    out: list[dict[str, float]] = []
    iterations = 0
    wire_options = [_options(v, best.value(v.name), sizing.wire_diameters_m) for v in wires]
    for wc in itertools.product(*wire_options):
        fixed = dict(zip((v.name for v in wires), wc))
        sol = best
        if wires and rest:
            box = {**bounds, **{n: (d, d) for n, d in fixed.items()}}
            sol = problem.nlp.solve({**best.values(), **fixed}, p, box)
            iterations += sol.iterations
            if not sol.success:
                sol = best
        rest_options = [_options(v, sol.value(v.name), sizing.wire_diameters_m) for v in rest]
        for rc in itertools.product(*rest_options):
            out.append({**fixed, **dict(zip((v.name for v in rest), rc))})
    unique = list({tuple(sorted(c.items())): c for c in out}.values())
    continuous = [v for v in rest if v.kind not in ("turns", "wire")]
    if continuous:  # radii, magnet, spiral wire re-balance around the whole turns and wires
        for combo in unique:
            whole = {v.name: combo[v.name] for v in free if v.kind in ("turns", "wire")}
            box = {**bounds, **{n: (d, d) for n, d in whole.items()}}
            sol = problem.nlp.solve({**best.values(), **combo}, p, box)
            iterations += sol.iterations
            if sol.success:
                combo.update({v.name: sol.value(v.name) for v in continuous})
    return unique, iterations


def buildable(
    model: DesignModel, values: dict[str, float], min_bore_m: float, *, checks: bool = True
) -> DesignModel | None:
    """The model with hardware ``values`` if it can be built and meets the geometric rules
    (``checks=False``: constructible only, for the relaxation's iterates, whose clearance rows
    are exact only once the frozen factors settle)."""
    import capsule as cap
    from optimize.buildcheck import buildable_ok
    from spiralcap.errors import InputError

    try:
        m = hw.with_hardware(model, values)
    except InputError:
        return None
    if checks and not buildable_ok(m):  # clearances (exact where a bound does not decide), mass
        return None
    if hw.bore_m(m) < min_bore_m * (1 - 1e-9):
        return None
    if cap.magnet_fit_check(m.capsule.body, m.capsule.magnet) is not None:
        return None
    return m


class FixedHardwareSolver(NamedTuple):
    """What sizing needs of the fixed-hardware solve; :mod:`optimize.solve` passes itself in
    (so this module does not import it: no import cycle)."""

    optimize_design: Callable[..., OptimizationResult]
    binding: Callable[..., Any]
    initial_points: Callable[..., Any]
    scales_for: Callable[..., Any]
    variable_bounds: Callable[..., Any]
    #: what ``optimize_design(..., evaluate_failed=False)`` raises when no start converges
    no_solution: type[Exception]
    #: ``warm_up(model)`` compiles what a warm-started fixed-hardware solve of ``model`` needs
    warm_up: Callable[[DesignModel], None]


class _Failed(NamedTuple):
    """A neighbour whose fixed-hardware solve found no solution: only its iterations count
    (the search never reads a failed neighbour's evaluation, so none is computed)."""

    iterations: int
    status: str = "infeasible"


def size_design(
    model: DesignModel,
    solver: FixedHardwareSolver,
    progress: Callable[[str], None] | None = None,
) -> OptimizationResult:
    """Size the free hardware of ``model`` (``model.sizing``) for its objective.

    ``progress(stage)`` is told each outer iteration of the relaxation and each neighbour.
    """
    helpers: list[Any] = []
    try:
        res = _size_design(model, solver, progress, helpers)
    except BaseException:
        for helper in helpers:
            helper.cancel()
        raise
    for helper in helpers:
        helper.close()
    return res


def _start_standby(
    solver: FixedHardwareSolver,
    exact: DesignModel,
    helpers: list[Any],
    fixed_model: DesignModel,
    token: tuple | None,
) -> Any:
    """A helper that compiles the neighbours' fixed-hardware problem (that of ``exact``) and
    finds the screen's least required torque now, on a free core, while the relaxation runs
    here; None without one."""
    factory = _STANDBY[0]
    if factory is None:
        return None
    standby = factory(functools.partial(_get_ready, solver, exact, fixed_model, token))
    if standby is not None:
        helpers.append(standby)
    return standby


def _size_design(
    model: DesignModel,
    solver: FixedHardwareSolver,
    progress: Callable[[str], None] | None,
    helpers: list[Any],
    *,
    start: dict[str, float] | None = None,
    relax_only: bool = False,
) -> Any:
    """:func:`size_design`; ``start``: free hardware to start the relaxation from (default the
    model's own, kept inside the box); ``relax_only``: stop after the relaxation (a
    :class:`_Relaxed`, or the infeasible result)."""
    say = progress or (lambda _stage: None)
    from optimize.compiled import compile_problem, structure_of

    _binding = solver.binding
    initial_points, scales_for = solver.initial_points, solver.scales_for
    variable_bounds = solver.variable_bounds
    t0 = time.perf_counter()
    sizing = model.sizing
    fixed_model = replace(model, sizing=None)
    free = sizing.free
    min_bore = sizing.min_bore_m if sizing.min_bore_m is not None else hw.bore_m(model)
    base = {**hw.hardware_of(model), **(start or {})}
    hw_now = {v.name: min(max(base[v.name], v.lo), v.hi) for v in free}
    exact = buildable(fixed_model, hw_now, 0.0, checks=False) or fixed_model
    exact = prepare(exact)
    # neighbours whose field-only limits already break at the least field the requirements
    # need are ruled out without their NLP (optimize.screen); the least required torque is
    # found once per sizing, by the standby helper while the relaxation runs here
    token = (os.getpid(), next(_SIZINGS)) if SCREEN and screen.screens(model) else None
    standby = None if relax_only else _start_standby(solver, exact, helpers, fixed_model, token)
    hs = hw.HardwareStructure(
        tuple(v.name for v in free),
        hw.helmholtz_flags(model),
        len(model.headings),
        model.limits.copper_mass_kg is not None,
    )
    bounds = {**variable_bounds(exact), **{v.name: (v.lo, v.hi) for v in free}}
    scales = scales_for(exact)
    grid = initial_points(exact, scales, model.bounds.starts)
    ws = _working_set(exact, grid, scales)  # tissue scenarios: the ones that matter
    problem = compile_problem(structure_of(ws.model(exact) if ws else exact, hardware=hs))
    starts = [{**x, **hw_now, "power_W_scaled": _loss_scaled(exact, x, scales)} for x in grid]
    iterations, outer, best, frozen_prev = 0, 0, None, None
    outer_max, next_start = _OUTER_MAX, None
    while outer < outer_max:
        outer += 1
        say(f"continuous relaxation, outer iteration {outer}")
        frozen = hw.frozen_factors(exact)
        p = problem.parameters(
            ws.model(exact) if ws else exact, scales, hw.sizing_parameters(exact, frozen, min_bore)
        )
        xs0 = starts if best is None else [next_start or best.values()]
        found = None
        for x0 in xs0:
            sol = problem.nlp.solve(x0, p, bounds)
            iterations += sol.iterations
            if sol.success and (found is None or sol.f < found.f):
                found = sol
        if found is None:
            break
        best = found
        hw_now = {v.name: best.value(v.name) for v in free}
        moved = buildable(fixed_model, hw_now, 0.0, checks=False)
        if moved is None:
            break
        exact = prepare(moved)
        next_start = None
        if ws is not None:  # every scenario at the new optimum: does the tail lie in the set?
            point = (
                best.value("helical_angle"),
                best.value("frequency"),
                best.value("field_scaled") * scales.field_T,
            )
            changed = ws.update(exact, point)
            if changed is not None:  # re-solve on the grown set (the set only grows: finite)
                outer_max += 1
                problem = compile_problem(structure_of(ws.model(exact), hardware=hs))
                next_start = {
                    k: v for k, v in best.values().items() if not _slot_variable(k, changed)
                }
                frozen_prev = frozen
                continue
        if frozen_prev is not None and _settled(frozen_prev, frozen):
            break
        frozen_prev = frozen
    spec = pb.OBJECTIVES[model.bounds.objective]
    scale = float(spec.scale(scales))
    if best is None and start is None and not relax_only and _mass_limited(model):
        # the copper limit may lie far below the starting hardware's copper: start again from
        # the least copper the requirements need, or say that it is more than the limit
        least = _least_copper(model, solver, helpers)
        limit = float(model.limits.copper_mass_kg or 0.0)
        if least is not None:
            iterations += least.iterations
            if least.objective <= limit * (1 + 1e-9):
                if standby is not None:  # the restart starts its own
                    helpers.remove(standby)
                    standby.close()
                res = _size_design(model, solver, progress, helpers, start=least.hardware)
                return replace(
                    res,
                    iterations=res.iterations + iterations,
                    solve_time_s=time.perf_counter() - t0,
                )
            lightest = buildable(fixed_model, least.hardware, 0.0, checks=False) or exact
            return _no_design(
                solver,
                lightest,
                t0,
                iterations,
                f"the requirements need at least {least.objective:.4g} kg of copper (continuous "
                f"relaxation), more than limits.copper_mass_kg = {limit:.4g} kg allows; "
                "closest with the hardware at " + _hardware_text(least.hardware),
            )
    if best is None:  # what is out of reach with the hardware at its box (the first start)
        return _no_design(
            solver,
            exact,
            t0,
            iterations,
            "the relaxed sizing problem has no solution; closest with the hardware at "
            + _hardware_text(hw_now),
        )
    relaxed = {v.name: best.value(v.name) for v in free}
    relaxed_obj = -spec.sense * scale * best.f if spec.uses_t else scale * best.f
    if model.bounds.objective == "copper_mass":  # the mass alone, at the unrounded hardware
        relaxed_obj = _copper_mass_kg({**hw.hardware_of(exact), **relaxed}, exact)
    if relax_only:
        return _Relaxed(relaxed, float(relaxed_obj), iterations)
    warm = {
        "helical_angle": best.value("helical_angle"),
        "frequency": best.value("frequency"),
        "field_T": best.value("field_scaled") * scales.field_T,
    }
    if ws is not None:  # the neighbours start from the relaxation's working set
        warm["scenario_index"] = ws.index
    candidates, extra_iterations = _neighbours(problem, p, bounds, best, free, sizing)
    iterations += extra_iterations
    tried, feasible, winner, first_built = 0, 0, None, None
    by_mass = model.bounds.objective == "copper_mass"
    if by_mass:  # the objective is known before the solve: the first feasible one is the best
        here = hw.hardware_of(exact)
        candidates.sort(key=lambda c: _copper_mass_kg({**here, **relaxed, **c}, exact))

    ctx = _Attempt(solver, fixed_model, relaxed, min_bore, warm, scales, token)
    # with a standby helper (it compiled the fixed-hardware problem while the relaxation ran)
    # the neighbours run there and on a sibling forked from it; else the first here (it
    # compiles the problem the forked ones then share) and the rest on the free cores. Each
    # solve is independent: the same results however spread. By mass in small batches, since
    # the first feasible one ends the search.
    batch = BATCH if by_mass else len(candidates)
    done = 0
    while done < len(candidates) and not (by_mass and winner is not None):
        size = 1 if done == 0 and standby is None else batch
        part = candidates[done : done + size]
        if standby is not None:
            results = standby.map(_attempt, ctx, part)
        else:
            results = _map(functools.partial(_attempt, ctx), part)
        done += len(part)
        for combo, res in zip(part, results, strict=True):
            if by_mass and winner is not None:
                break
            tried += 1
            say(f"whole turns and standard wire: neighbour {tried} of {len(candidates)}")
            if res is None:
                continue
            if first_built is None:
                first_built = buildable(fixed_model, {**relaxed, **combo}, min_bore)
            iterations += res.iterations
            if isinstance(res, _Failed) or res.status != "optimal":
                continue
            feasible += 1
            if winner is None or spec.sense * (res.objective_value - winner[1].objective_value) > 0:
                winner = ({**relaxed, **combo}, res)
    if winner is None:
        # what keeps the neighbours out: the first buildable one's own shortfalls (the
        # relaxed problem at that hardware), or the geometric rule the first one breaks
        closest = first_built
        geometry = ()
        if closest is None and candidates:
            geometry = unbuildable(fixed_model, {**relaxed, **candidates[0]}, min_bore)
        return _no_design(
            solver,
            closest or fixed_model,
            t0,
            iterations,
            f"no buildable neighbour of the relaxed optimum meets every requirement "
            f"({tried} tried)",
            geometry,
        )
    values, res = winner
    # the winner's full result (step-out, highest frequency): the same solve again, bit for bit
    full = standby.call(_full_result, ctx, values) if standby else _full_result(ctx, values)
    res = replace(full, iterations=res.iterations)
    # what binds, and what relaxing it buys, comes from the continuous relaxation (hardware and
    # operating point free together): the gains are those of the continuous bound; the
    # discrete design's own multipliers would hold its hardware fixed (0 for the copper mass)
    sizing_binding = _binding(exact, scales, best, {v.name: (v.lo, v.hi) for v in free})
    result = HardwareResult(
        relaxed=relaxed,
        relaxed_objective=float(relaxed_obj),
        discrete={v.name: values[v.name] for v in free},
        discrete_objective=res.objective_value,
        candidates=tried,
        feasible=feasible,
        outer_iterations=outer,
    )
    return replace(
        res,
        hardware=result,
        binding_limits=sizing_binding,
        iterations=iterations,
        solve_time_s=time.perf_counter() - t0,
        message=f"optimal: {len(free)} hardware quantities sized ({feasible} of {tried} "
        "buildable neighbours feasible); every requirement met inside every limit",
    )


def _get_ready(
    solver: FixedHardwareSolver, exact: DesignModel, fixed_model: DesignModel, token: Any
) -> None:
    """The standby helper's preparation (see :func:`_start_standby`)."""
    solver.warm_up(exact)
    if token is not None:
        _least_required_Nm(token, fixed_model)


#: Sizings started in this process (with the pid, a token naming one sizing's screen)
_SIZINGS = itertools.count()
#: The screen's least required torque per sizing token (found once, in whichever process)
_LEAST: dict[tuple, float] = {}


def _least_required_Nm(token: tuple, fixed_model: DesignModel) -> float:
    """:func:`optimize.screen.least_required_torque_Nm` of ``fixed_model``, once per
    sizing (the neighbours' capsule, tissues and requirements are its own)."""
    if token not in _LEAST:
        if len(_LEAST) > 64:
            _LEAST.clear()
        _LEAST[token] = screen.least_required_torque_Nm(fixed_model)
    return _LEAST[token]


class _Attempt(NamedTuple):
    """What a neighbour's solve needs besides its whole turns and wires (pickled to helpers)."""

    solver: FixedHardwareSolver
    fixed_model: DesignModel
    relaxed: dict[str, float]
    min_bore_m: float
    warm: dict[str, Any]
    scales: Any
    #: the sizing's screen token (None: no screen; see :func:`_least_required_Nm`)
    screen_token: tuple | None = None


def _attempt(ctx: _Attempt, combo: dict[str, float]) -> OptimizationResult | _Failed | None:
    """One buildable neighbour re-optimised (fixed hardware) from the relaxation's operating
    point, with the relaxation's scales; None if it cannot be built, :class:`_Failed` if its
    solve finds no solution or a limit rules it out first (:func:`optimize.screen.out_of_reach`)."""
    m = buildable(ctx.fixed_model, {**ctx.relaxed, **combo}, ctx.min_bore_m)
    if m is None:
        return None
    if ctx.screen_token is not None:
        least = _least_required_Nm(ctx.screen_token, ctx.fixed_model)
        m = prepare(m)
        if screen.out_of_reach(m, least) is not None:
            return _Failed(0, "out of reach")
    try:
        return ctx.solver.optimize_design(
            m,
            warm_start=ctx.warm,
            diagnose=False,
            grid_starts=False,
            frequency_bounds=False,
            evaluate_failed=not SKIP_FAILED_EVALUATION,
            scales=ctx.scales,
            candidate=True,
        )
    except ctx.solver.no_solution as failed:  # only its iterations are read
        return _Failed(int(getattr(failed, "iterations", 0)))


def _full_result(ctx: _Attempt, values: dict[str, float]) -> OptimizationResult:
    """The winner's full result (step-out, highest frequency): its neighbour solve again."""
    m = buildable(ctx.fixed_model, values, ctx.min_bore_m)
    assert m is not None  # it was built as a neighbour
    return ctx.solver.optimize_design(
        m, warm_start=ctx.warm, diagnose=False, grid_starts=False, scales=ctx.scales
    )


#: How the buildable neighbours are mapped, ``mapper(fn, items) -> [fn(x) for x in items]``:
#: serial here; the application sets one that runs them on its free cores
#: (:func:`set_neighbour_map`). Each solve is independent, so the results are the same.
_MAPPER: list[Callable[[Callable[[Any], Any], list[Any]], list[Any]] | None] = [None]
#: Neighbours tried at once when the first feasible one wins (``copper_mass``).
BATCH = 8
#: Neighbours a field-only limit rules out at the least field needed skip their NLP
#: (:mod:`optimize.screen`). False: every one solved, for the test that both agree.
SCREEN = True
#: A neighbour whose solve finds no solution is not evaluated (its result is never read; a
#: quarter of a failed neighbour's time). False: the long way, for the test that both agree.
SKIP_FAILED_EVALUATION = True


#: ``standby(setup)``: a helper process that runs ``setup()`` now and later takes the
#: neighbours (``.map(fn, shared, items)``, ``.call(fn, *args)``, ``.close()``), or None where
#: there is no free core; set by the application (:func:`set_neighbour_map`).
_STANDBY: list[Callable[[Callable[[], Any]], Any] | None] = [None]


def set_neighbour_map(
    mapper: Callable[[Callable[[Any], Any], list[Any]], list[Any]] | None,
    standby: Callable[[Callable[[], Any]], Any] | None = None,
) -> None:
    """Run the neighbours' solves through ``mapper`` (None: one after another here), or, where
    ``standby(setup)`` gives a helper, on it: it compiles the fixed-hardware problem while the
    relaxation runs here."""
    _MAPPER[0] = mapper
    _STANDBY[0] = standby


def _map(fn: Callable[[Any], Any], items: list[Any]) -> list[Any]:
    mapper = _MAPPER[0]
    if mapper is None or len(items) < 2:
        return [fn(x) for x in items]
    return mapper(fn, items)


def _working_set(model: DesignModel, grid: list[dict[str, float]], scales: Any) -> Any:
    """The scenario working set of a model with tissue scenarios (None: none, or the whole set
    is solved at once): the tail at the grid starts (:mod:`optimize.active_set`)."""
    from optimize import active_set as acs

    sc = model.scenarios
    if sc is None or not sc.whole:
        return None
    cap = acs.capacity_for(acs.tail_count(model), sc.count)
    if cap >= sc.count:
        return None
    points = [
        (x["helical_angle"], x["frequency"], x["field_scaled"] * scales.field_T) for x in grid
    ]
    return acs.WorkingSet(model, acs.initial_index(model, cap, points))


def _slot_variable(name: str, slots: set[int]) -> bool:
    """Whether ``name`` is a scenario variable (``…excess[i]``) of one of ``slots``."""
    return "excess[" in name and int(name[name.index("[") + 1 : -1]) in slots


def _loss_scaled(model: DesignModel, x: dict[str, float], scales: Any) -> float:
    """The sizing NLP's loss epigraph variable at a start: worst-heading loss / power scale."""
    from optimize.physics import total_loss_W

    field = x["field_scaled"] * scales.field_T
    loss = total_loss_W(field, model.constants, model.ambient_temperature_C)
    return float(loss) / scales.power_W


def _copper_mass_kg(values: dict[str, float], model: DesignModel) -> float:
    pf = model.coils.pairs[0].packing_factor
    return float(
        sum(
            hw.coil_quantities(
                values[f"{ax}.radius_m"],
                values[f"{ax}.turns"],
                values[f"{ax}.wire_diameter_m"],
                values[f"{ax}.radius_m"],
                packing=pf,
                resistivity=1.0,
                h=1.0,
                aspect=values[f"{ax}.pack_aspect"],
            )["copper_mass_kg"]
            for ax in hw.AXES
        )
    )


def _hardware_text(values: dict[str, float]) -> str:
    return ", ".join(f"{k} = {v:.4g}" for k, v in values.items())


def _mass_limited(model: DesignModel) -> bool:
    return model.limits.copper_mass_kg is not None and model.bounds.objective != "copper_mass"


class _Relaxed(NamedTuple):
    """A continuous relaxation alone (``_size_design(..., relax_only=True)``)."""

    hardware: dict[str, float]
    objective: float
    iterations: int


def _least_copper(
    model: DesignModel, solver: FixedHardwareSolver, helpers: list[Any]
) -> _Relaxed | None:
    """The continuous relaxation of ``model`` with the copper mass minimised and no copper limit
    (None if it has no solution): where the copper limit sits far below the starting hardware,
    IPOPT's starts end "locally infeasible" outside the small set of designs that meet it."""
    least = replace(
        model,
        bounds=replace(model.bounds, objective="copper_mass"),
        limits=replace(model.limits, copper_mass_kg=None),
    )
    out = _size_design(least, solver, None, helpers, relax_only=True)
    return out if isinstance(out, _Relaxed) else None


def _settled(a: hw.Frozen, b: hw.Frozen) -> bool:
    pairs = (
        (a.gain_correction, b.gain_correction),
        (a.mutual_correction, b.mutual_correction),
        (a.workspace_factor, b.workspace_factor),
        (a.gap0_m, b.gap0_m),
    )
    # the ray-traced view factors move in steps of 1/rays as rays graze an edge: settled
    # within 1e-3 (a pack's temperature moves by < 0.01 K per 1e-3 of view factor); the
    # clearance correction in metres (held relative to its ~5 mm it chased the hardware's
    # movements at IPOPT's tolerance and never settled: every sizing ran all _OUTER_MAX rounds)
    return (
        all(np.allclose(x, y, rtol=_OUTER_RTOL, atol=0.0) for x, y in pairs)
        and np.allclose(a.view_factors, b.view_factors, rtol=0.0, atol=1e-3)
        and np.allclose(a.clearance_delta_m, b.clearance_delta_m, rtol=0.0, atol=_DELTA_ATOL_m)
    )


def unbuildable(model: DesignModel, values: dict[str, float], min_bore_m: float) -> tuple:
    """The geometric rules hardware ``values`` breaks, as shortfalls with their numbers
    (nesting gap against the half pack sides, bore against the minimum, magnet fit)."""
    import capsule as cap
    from spiralcap.errors import InputError

    try:
        m = hw.with_hardware(model, values)
    except InputError as exc:
        return (Shortfall(str(exc.key), "", 0.0, 0.0),)
    out = []
    pairs = m.coils.pairs
    for i, j in hw.PAIRS_OF_PAIRS:
        half = 0.5 * (pairs[i].winding_pack_side_m + pairs[j].winding_pack_side_m)
        gap = hw.mean_turn_gap_m(pairs[i], pairs[j])
        if gap < half:
            out.append(Shortfall(f"nesting_{hw.AXES[i]}{hw.AXES[j]}", "m", half, gap))
    if hw.bore_m(m) < min_bore_m * (1 - 1e-9):
        out.append(Shortfall("bore", "m", min_bore_m, hw.bore_m(m)))
    body, magnet = m.capsule.body, m.capsule.magnet
    fit = cap.magnet_fit_check(body, magnet)
    if fit is not None and fit[0] == "diameter_m":
        out.append(Shortfall("magnet_diameter", "m", 2 * body.inner_radius_m, magnet.diameter_m))
    elif fit is not None:
        r_in, half_d = body.inner_radius_m, 0.5 * magnet.diameter_m
        room = body.cylinder_length_m + 2 * math.sqrt(max(r_in**2 - half_d**2, 0.0))
        out.append(Shortfall("magnet_length", "m", room, magnet.length_m))
    return tuple(out)


def _no_design(
    solver: FixedHardwareSolver,
    model: DesignModel,
    t0: float,
    iterations: int,
    why: str,
    geometry: tuple = (),
) -> OptimizationResult:
    """An infeasible result: what is out of reach at ``model``'s hardware (the relaxed
    problem's shortfalls), or the geometric rules the neighbours break."""
    res = solver.optimize_design(model)
    shortfalls = geometry or res.shortfalls
    if not shortfalls:  # that hardware meets everything by itself: say so with its numbers
        ev = res.evaluation
        shortfalls = (
            Shortfall("safety_factor", "1", model.requirements.min_safety_factor, ev.safety_factor),
        )
    return replace(
        res,
        status="infeasible",
        shortfalls=shortfalls,
        iterations=res.iterations + iterations,
        solve_time_s=time.perf_counter() - t0,
        message=f"infeasible: {why}",
    )
