"""Hardware sizing as four named steps: relax, neighbours, rank, finish.

1. :func:`relax`: hardware and operating point in one NLP (:mod:`optimize.hardware`), with the
   frozen factors (pack corrections, workspace field factor, linearised gaps between the mean
   turns, the clearance correction) recomputed exactly at each new hardware and the NLP
   re-solved warm until they settle.
2. :func:`neighbours`: each turn count rounded down and up, each wire diameter to the standard
   sizes just below and above; continuous quantities (radii, magnet, spiral wire) re-balanced
   around them.
3. :func:`rank`: every neighbour built exactly (coils, capsule), checked (exact pack
   clearances, bore, copper mass, magnet fit) and re-optimised at its fixed hardware; the best
   wins. The solves are independent: they go through the caller's ``executor`` (anything with
   ``submit``: a process pool, a Dask client), the same results wherever they run.
4. :func:`finish`: the winner's full result, with the binding limits of the relaxation.

A copper-mass limit far below the starting hardware restarts the relaxation from the least
copper the requirements need (:func:`least_copper`), or says that it is more than the limit.
"""

from __future__ import annotations

import bisect
import functools
import itertools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any, NamedTuple, Protocol

import numpy as np

from optimize import hardware as hw
from optimize import problem as pb
from optimize import screen
from optimize.active_set import solve_hardware
from optimize.compiled import compile_problem, structure_of
from optimize.nlp import Solution
from optimize.result import HardwareResult, OptimizationResult, Shortfall
from optimize.solve import (
    SolveOptions,
    binding,
    initial_points,
    scales_for,
    variable_bounds,
)
from optimize.system import DesignModel, prepare

#: Frozen factors settled (relative): the relaxed hardware itself moves by ~1e-7 relative from
#: round to round at IPOPT's tolerance where the objective is flat in it (the margin objective),
#: so factors computed from it settle no tighter (the inductance's pack correction by ~1e-8).
_OUTER_RTOL = 1e-7
#: The clearance correction's settling tolerance, m: 1e-6 of the clearance rows' 10 mm scale
#: (the exact clearance is resolved to 1e-9 m; the hardware's round-to-round movement at
#: IPOPT's tolerance moves it by ~2e-9 m).
_DELTA_ATOL_m = 1e-8


@dataclass(frozen=True)
class SizingOptions:
    """How a sizing runs.

    Parameters
    ----------
    outer_max : int
        Outer rounds of the relaxation (frozen factors recomputed) before it stops unsettled,
        count.
    batch : int
        Neighbours ranked at once when the first feasible one wins (objective
        ``copper_mass``, neighbours in copper order), count; the result does not depend on it.
    screen : bool
        Rule out neighbours a field-only limit already breaks at the least field the
        requirements need, without their NLP (:mod:`optimize.screen`; the least required
        torque is found once per sizing, by the executor while the relaxation runs). The
        result does not depend on it (tests/test_sizing_speed.py); only the work spent.
    lean : tuple of (float, float) or None
        (copper, objective), fractions, dimensionless: a least-power sizing does not spend more
        than ``1 + copper`` times the copper of the leanest design within ``objective`` of its
        power (:func:`leaner`, issue 36); None: the least power alone.
    """

    outer_max: int = 8
    batch: int = 8
    screen: bool = True
    lean: tuple[float, float] | None = (0.10, 0.01)


class Executor(Protocol):
    """What sizing needs of an executor (``concurrent.futures.Executor``, a Dask client, ...):
    ``submit(fn, *args)`` returning a future whose ``result()`` is ``fn(*args)``. A
    structural type: anything with such a ``submit`` is one, no base class needed."""

    def submit(self, fn: Callable[..., Any], /, *args: Any) -> Any:  # pragma: no cover
        """``fn(*args)`` to run.

        Parameters
        ----------
        fn : callable
            A module-level function (it may be pickled to another process or machine).
        *args
            Its arguments.

        Returns
        -------
        future
            An object whose ``result()`` is ``fn(*args)``.
        """
        ...


def _silent(_stage: str) -> None:
    """A progress callback that says nothing (library functions do not print)."""


class _Done(NamedTuple):
    value: Any

    def result(self) -> Any:
        return self.value


def _submit(executor: Executor | None, fn: Callable[..., Any], *args: Any) -> Any:
    return executor.submit(fn, *args) if executor is not None else _Done(fn(*args))


def _map(executor: Executor | None, fn: Callable[[Any], Any], items: list[Any]) -> list[Any]:
    """``[fn(x) for x in items]``, each call submitted (``map`` differs between executors: a
    Dask client's gives futures, a standard one's results)."""
    if executor is None or len(items) < 2:
        return [fn(x) for x in items]
    futures = [executor.submit(fn, x) for x in items]
    return [f.result() for f in futures]


class _Setup(NamedTuple):
    """What the relaxation solves: the model at the starting hardware and its compiled NLP."""

    model: DesignModel
    fixed_model: DesignModel  # the model without free hardware (neighbours are built from it)
    free: tuple[hw.FreeVariable, ...]
    min_bore_m: float
    hw_start: dict[str, float]
    exact: DesignModel  # prepared, at the starting hardware
    structure: hw.HardwareStructure
    bounds: dict[str, tuple[float, float]]
    scales: Any
    starts: list[dict[str, float]]
    ws: Any  # the scenario working set, or None
    problem: Any


def _starting_model(model: DesignModel, start: dict[str, float] | None) -> DesignModel:
    """The fixed model at the free hardware's start (the model's own, or ``start``), kept
    inside the box, prepared."""
    fixed_model = replace(model, sizing=None)
    hw_start = _start_values(model, start)
    return prepare(buildable(fixed_model, hw_start, 0.0, checks=False) or fixed_model)


def _start_values(model: DesignModel, start: dict[str, float] | None) -> dict[str, float]:
    base = {**hw.hardware_of(model), **(start or {})}
    return {v.name: min(max(base[v.name], v.lo), v.hi) for v in model.sizing.free}


def _setup(
    model: DesignModel, start: dict[str, float] | None = None, exact: DesignModel | None = None
) -> _Setup:
    """The relaxation of ``model`` from ``start`` (default: the model's own hardware);
    ``exact``: :func:`_starting_model` of that, if already built."""
    sizing = model.sizing
    free = sizing.free
    exact = exact if exact is not None else _starting_model(model, start)
    hs = hw.HardwareStructure(
        tuple(v.name for v in free),
        hw.helmholtz_flags(model),
        len(model.headings),
        model.limits.copper_mass_kg is not None,
        hw.shape_keys(model),
    )
    bounds = {**variable_bounds(exact), **{v.name: (v.lo, v.hi) for v in free}}
    scales = scales_for(exact)
    grid = initial_points(exact, scales, model.bounds.starts)
    ws = _working_set(exact, grid, scales)  # tissue scenarios: the ones that matter
    problem = compile_problem(structure_of(ws.model(exact) if ws else exact, hardware=hs))
    hw_start = _start_values(model, start)
    starts = [{**x, **hw_start, "power_W_scaled": _loss_scaled(exact, x, scales)} for x in grid]
    min_bore = sizing.min_bore_m if sizing.min_bore_m is not None else hw.bore_m(model)
    return _Setup(
        model,
        replace(model, sizing=None),
        free,
        min_bore,
        hw_start,
        exact,
        hs,
        bounds,
        scales,
        starts,
        ws,
        problem,
    )


class Relaxation(NamedTuple):
    """The continuous relaxation's outcome (``best`` None: no start converged).

    Attributes
    ----------
    best : Solution or None
        The last round's best converged solve; None if no start converged.
    hardware : dict of str to float
        The free hardware at that optimum (else at the start) by name, each in the unit its
        name carries (``*_m`` in m, turns a count).
    exact : DesignModel
        The fixed model prepared at the last hardware that could be built (``hardware``
        itself unless the last optimum could not be built), SI.
    problem : CompiledProblem
        The last round's compiled NLP (recompiled as the scenario working set grows).
    p : ndarray
        Parameter vector of the last round's solve, each entry in the unit its parameter's
        name carries (None if no round ran).
    outer : int
        Outer rounds run, count.
    iterations : int
        IPOPT iterations spent over all rounds and starts, count.
    settled : bool
        Flag: the frozen factors settled (else the rounds ran out, or a round failed).
    """

    best: Solution | None
    hardware: dict[str, float]
    exact: DesignModel
    problem: Any
    p: Any
    outer: int
    iterations: int
    settled: bool = False


def _best_of(problem: Any, starts: list[dict[str, float]], p: Any, bounds: dict) -> tuple:
    """The best converged solve from ``starts`` (None if none converged), and the iterations."""
    found, iterations = None, 0
    for x0 in starts:
        sol = problem.nlp.solve(x0, p, bounds)
        iterations += sol.iterations
        if sol.success and (found is None or sol.f < found.f):
            found = sol
    return found, iterations


def _point(sol: Solution, scales: Any) -> tuple[float, float, float]:
    return (
        sol.value("helical_angle_rad"),
        sol.value("frequency_hz"),
        sol.value("field_scaled") * scales.field_T,
    )


def relax(
    s: _Setup,
    options: SizingOptions = SizingOptions(),
    progress: Callable[[str], None] | None = None,
) -> Relaxation:
    """Step 1: the continuous relaxation, re-solved warm until the frozen factors settle (and,
    with tissue scenarios, until the tail lies in the working set).

    Parameters
    ----------
    s : _Setup
        The relaxation's model at its starting hardware and its compiled NLP (:func:`_setup`).
    options : SizingOptions
        ``outer_max``: the most outer rounds.
    progress : callable, optional
        ``progress(stage)`` at each outer round (None: nothing is said).

    Returns
    -------
    Relaxation
        The best solution (None if no start converged), the free hardware there (SI: m,
        turns), the model prepared there, the rounds and IPOPT iterations spent.
    """
    say = progress or _silent
    exact, problem, ws = s.exact, s.problem, s.ws
    hw_now = dict(s.hw_start)
    iterations, outer, outer_max = 0, 0, options.outer_max
    best, frozen_prev, next_start, p = None, None, None, None
    settled = False
    while outer < outer_max:
        outer += 1
        say(f"continuous relaxation, outer iteration {outer}")
        frozen = hw.frozen_factors(exact)
        params = hw.sizing_parameters(exact, frozen, s.min_bore_m)
        p = problem.parameters(ws.model(exact) if ws else exact, s.scales, params)
        xs0 = s.starts if best is None else [next_start or best.values()]
        found, its = _best_of(problem, xs0, p, s.bounds)
        iterations += its
        if found is None:
            break
        best = found
        hw_now = {v.name: best.value(v.name) for v in s.free}
        moved = buildable(s.fixed_model, hw_now, 0.0, checks=False)
        if moved is None:
            break
        exact, next_start = prepare(moved), None
        # every scenario at the new optimum: does the tail lie in the set?
        changed = ws.update(exact, _point(best, s.scales)) if ws is not None else None
        if changed is not None:  # re-solve on the grown set (the set only grows: finite)
            outer_max += 1
            problem = compile_problem(structure_of(ws.model(exact), hardware=s.structure))
            next_start = {k: v for k, v in best.values().items() if not _slot_variable(k, changed)}
        elif frozen_prev is not None and _settled(frozen_prev, frozen):
            settled = True
            break
        frozen_prev = frozen
    return Relaxation(best, hw_now, exact, problem, p, outer, iterations, settled)


def _relaxed_objective(s: _Setup, r: Relaxation) -> float:
    """The relaxation's objective value (the copper mass alone at the unrounded hardware)."""
    assert r.best is not None
    if s.model.bounds.objective == "copper_mass":
        return _copper_mass_kg({**hw.hardware_of(r.exact), **r.hardware}, r.exact)
    spec = pb.OBJECTIVES[s.model.bounds.objective]
    scale = float(spec.scale(s.scales))
    return float(-spec.sense * scale * r.best.f if spec.uses_t else scale * r.best.f)


def neighbours(s: _Setup, r: Relaxation) -> tuple[list[dict[str, float]], int]:
    """Step 2: the candidates around the relaxed optimum (see :func:`_neighbours`).

    Parameters
    ----------
    s : _Setup
        The relaxation's setup.
    r : Relaxation
        Its outcome (``r.best`` not None).

    Returns
    -------
    candidates : list of dict
        Free hardware of each candidate by name (SI: turns, m), in copper order when the
        copper mass is the objective.
    iterations : int
        IPOPT iterations of the re-balancing solves, count.
    """
    candidates, iterations = _neighbours(r.problem, r.p, s.bounds, r.best, s.free, s.model.sizing)
    if s.model.bounds.objective == "copper_mass":
        here = hw.hardware_of(r.exact)
        candidates.sort(key=lambda c: _copper_mass_kg({**here, **r.hardware, **c}, r.exact))
    return candidates, iterations


class _Attempt(NamedTuple):
    """What a neighbour's solve needs besides its whole turns and wires (pickled to workers)."""

    fixed_model: DesignModel
    relaxed: dict[str, float]
    min_bore_m: float
    warm: dict[str, Any]
    scales: Any
    #: the screen's least required torque, N·m (None: no screen)
    least_required_Nm: float | None = None


def _attempt_of(s: _Setup, r: Relaxation, least_required_Nm: float | None) -> _Attempt:
    assert r.best is not None
    warm: dict[str, Any] = {
        "helical_angle_rad": r.best.value("helical_angle_rad"),
        "frequency_hz": r.best.value("frequency_hz"),
        "field_T": r.best.value("field_scaled") * s.scales.field_T,
    }
    if s.ws is not None:  # the neighbours start from the relaxation's working set
        warm["scenario_index"] = s.ws.index
    return _Attempt(s.fixed_model, r.hardware, s.min_bore_m, warm, s.scales, least_required_Nm)


class _Failed(NamedTuple):
    """A neighbour the screen ruled out without its solve."""

    iterations: int
    status: str = "infeasible"


#: How a neighbour is solved: warm from the relaxation, with its scales, ranked by objective
#: only (no step-out search, no field capacity: 26-32 % of a sizing, docs/architecture.md).
NEIGHBOUR_SOLVE = SolveOptions(
    diagnose=False,
    grid_starts=False,
    frequency_bounds=False,
    candidate=True,
)


def _attempt(ctx: _Attempt, combo: dict[str, float]) -> OptimizationResult | _Failed | None:
    """One neighbour re-optimised at its fixed hardware (an 'infeasible' result if its solve
    finds no solution): None if it cannot be built, :class:`_Failed` if a limit rules it out
    first (:func:`optimize.screen.out_of_reach`)."""
    m = buildable(ctx.fixed_model, {**ctx.relaxed, **combo}, ctx.min_bore_m)
    if m is None:
        return None
    if ctx.least_required_Nm is not None:
        m = prepare(m)
        if screen.out_of_reach(m, ctx.least_required_Nm) is not None:
            return _Failed(0, "out of reach")
    return solve_hardware(m, ctx.warm, replace(NEIGHBOUR_SOLVE, scales=ctx.scales))


def _full_result(ctx: _Attempt, values: dict[str, float]) -> OptimizationResult:
    """The winner's full result (step-out, highest frequency): its neighbour solve again."""
    m = buildable(ctx.fixed_model, values, ctx.min_bore_m)
    assert m is not None  # it was built as a neighbour
    full = SolveOptions(diagnose=False, grid_starts=False, scales=ctx.scales)
    return solve_hardware(m, ctx.warm, full)


class Ranking(NamedTuple):
    """Step 3's outcome: the best feasible neighbour (hardware, result) or None.

    Attributes
    ----------
    winner : tuple of (dict of str to float, OptimizationResult) or None
        The best feasible neighbour: its free hardware by name, each in the unit its name
        carries (``*_m`` in m, turns a count), and its result; None if none is feasible.
    tried : int
        Neighbours tried (buildable or not), count.
    feasible : int
        Neighbours whose solve ended optimal, count.
    first_built : DesignModel or None
        The first buildable neighbour's model (exact geometric checks), SI; None if none could
        be built.
    iterations : int
        IPOPT iterations of the neighbours' solves, count.
    """

    winner: tuple[dict[str, float], OptimizationResult] | None
    tried: int
    feasible: int
    first_built: DesignModel | None
    iterations: int


def rank(
    ctx: _Attempt,
    candidates: list[dict[str, float]],
    sense: float,
    *,
    first_wins: bool = False,
    executor: Executor | None = None,
    options: SizingOptions = SizingOptions(),
    progress: Callable[[str], None] | None = None,
) -> Ranking:
    """Step 3: solve the neighbours (through ``executor``) and keep the best feasible one.

    Parameters
    ----------
    ctx : _Attempt
        What every neighbour's solve shares (the fixed model, the relaxed hardware, the warm
        start and scales, the screen's least required torque in N·m).
    candidates : list of dict
        The neighbours' free hardware by name (SI: turns, m).
    sense : float
        +1 where a larger objective is better, -1 where a smaller one is (dimensionless).
    first_wins : bool
        Candidates in objective order: the first feasible one ends the search (they are
        solved ``options.batch`` at a time).
    executor : Executor, optional
        Where the solves run (None: here, in order).
    options : SizingOptions
        ``batch``.
    progress : callable, optional
        ``progress(stage)`` for each neighbour (None: nothing is said).

    Returns
    -------
    Ranking
        The winner (hardware, result) or None, the neighbours tried and feasible, the first
        buildable one's model, the IPOPT iterations spent.
    """
    say = progress or _silent
    tried, feasible, iterations = 0, 0, 0
    winner: tuple[dict[str, float], OptimizationResult] | None = None
    first_built = None
    size = options.batch if first_wins else max(len(candidates), 1)
    for start in range(0, len(candidates), size):
        part = candidates[start : start + size]
        for combo, res in zip(part, _map(executor, functools.partial(_attempt, ctx), part)):
            tried += 1
            say(f"whole turns and standard wire: neighbour {tried} of {len(candidates)}")
            if res is None:
                continue
            if first_built is None:
                first_built = buildable(ctx.fixed_model, {**ctx.relaxed, **combo}, ctx.min_bore_m)
            iterations += res.iterations
            if isinstance(res, _Failed) or res.status != "optimal":
                continue
            feasible += 1
            if winner is None or sense * (res.objective_value - winner[1].objective_value) > 0:
                winner = ({**ctx.relaxed, **combo}, res)
            if first_wins:
                break
        if first_wins and winner is not None:
            break
    return Ranking(winner, tried, feasible, first_built, iterations)


def finish(
    s: _Setup,
    r: Relaxation,
    ranking: Ranking,
    ctx: _Attempt,
    executor: Executor | None = None,
) -> OptimizationResult:
    """Step 4: the winner's full result, with what binds taken from the relaxation.

    What binds, and what relaxing it buys, comes from the continuous relaxation (hardware and
    operating point free together); the discrete design's own multipliers would hold its
    hardware fixed (0 for the copper mass).

    Parameters
    ----------
    s : _Setup
        The relaxation's setup.
    r : Relaxation
        Its outcome.
    ranking : Ranking
        The neighbours' ranking (``ranking.winner`` not None).
    ctx : _Attempt
        What the neighbours' solves shared.
    executor : Executor, optional
        Where the winner is solved again in full (None: here).

    Returns
    -------
    OptimizationResult
        The sized design: ``hardware`` (relaxed and discrete hardware, SI), the binding limits
        with their gains, the evaluation with step-out and highest frequency.
    """
    assert ranking.winner is not None and r.best is not None
    values = ranking.winner[0]
    # the same solve again, bit for bit, with the step-out and highest frequency
    full = _submit(executor, _full_result, ctx, values).result()
    free_box = {v.name: (v.lo, v.hi) for v in s.free}
    discrete = {v.name: values[v.name] for v in s.free}
    result = HardwareResult(
        relaxed={**r.hardware, **hw.derived_sizes(s.model, r.hardware)},
        relaxed_objective=_relaxed_objective(s, r),
        discrete={**discrete, **hw.derived_sizes(s.model, discrete)},
        discrete_objective=full.objective_value,
        candidates=ranking.tried,
        feasible=ranking.feasible,
        outer_iterations=r.outer,
        settled=r.settled,
    )
    n, tried, feasible = len(s.free), ranking.tried, ranking.feasible
    return replace(
        full,
        iterations=0,  # the winner's solve is counted once, as a neighbour (size_design adds)
        hardware=result,
        binding_limits=binding(r.exact, s.scales, r.best, free_box),
        message=f"optimal: {n} hardware quantities sized ({feasible} of {tried} "
        "buildable neighbours feasible); every requirement met inside every limit",
    )


def size_design(
    model: DesignModel,
    *,
    progress: Callable[[str], None] | None = None,
    executor: Executor | None = None,
    options: SizingOptions = SizingOptions(),
) -> OptimizationResult:
    """Size the free hardware of ``model`` (``model.sizing``) for its objective.

    Parameters
    ----------
    model : DesignModel
        A design model with free hardware (``model.sizing.free``), SI.
    progress : callable, optional
        ``progress(stage)`` for each outer round of the relaxation and each neighbour.
    executor : optional
        Where the neighbours are solved (``submit``/``map``, e.g. a process pool or a Dask
        client); None: one after another here. The result is the same either way.
    options : SizingOptions
        How the search runs.

    Returns
    -------
    OptimizationResult
        The best buildable design (``hardware`` holds the relaxed and discrete hardware), or
        an infeasible result naming what is out of reach.
    """
    say = progress or _silent
    t0 = time.perf_counter()
    # the screen's least required torque, found once; early, so that an executor finds it
    # while the relaxation runs here
    least_torque = None
    if options.screen and screen.screens(model):
        fixed = replace(model, sizing=None)
        least_torque = _submit(executor, screen.least_required_torque_Nm, fixed)
    s = _setup(model)
    r = relax(s, options, say)
    spent = 0
    if r.best is None and _mass_limited(model):
        # the copper limit may lie far below the starting hardware's copper: start again from
        # the least copper the requirements need, or say that it is more than the limit
        lightest = least_copper(model, options)
        limit = float(model.limits.copper_mass_kg or 0.0)
        if lightest is not None and lightest.objective > limit * (1 + 1e-9):
            closest = buildable(s.fixed_model, lightest.hardware, 0.0, checks=False) or r.exact
            why = (
                f"the requirements need at least {lightest.objective:.4g} kg of copper "
                f"(continuous relaxation), more than limits.copper_mass_kg = {limit:.4g} kg "
                "allows; "
                "closest with the hardware at " + _hardware_text(lightest.hardware)
            )
            spent = r.iterations + lightest.iterations
            return _timed(_no_design(closest, why), t0, spent)
        if lightest is not None:
            spent = r.iterations + lightest.iterations
            s = _setup(model, lightest.hardware)
            r = relax(s, options, say)
    if r.best is None:  # what is out of reach with the hardware at its box (the first start)
        why = "the relaxed sizing problem has no solution; closest with the hardware at "
        return _timed(
            _no_design(r.exact, why + _hardware_text(r.hardware)), t0, spent + r.iterations
        )
    candidates, its = neighbours(s, r)
    ctx = _attempt_of(s, r, least_torque.result() if least_torque is not None else None)
    first_wins = model.bounds.objective == "copper_mass"  # the mass is known before a solve
    sense = pb.OBJECTIVES[model.bounds.objective].sense
    ranking = rank(
        ctx,
        candidates,
        sense,
        first_wins=first_wins,
        executor=executor,
        options=options,
        progress=say,
    )
    spent += r.iterations + its + ranking.iterations
    if ranking.winner is None:
        return _timed(_no_neighbour(s, ranking, candidates, ctx.relaxed), t0, spent)
    res = finish(s, r, ranking, ctx, executor)
    if options.lean is not None and model.bounds.objective in LEAN_OBJECTIVES:
        res, more = leaner(model, res, ctx, options, executor, say)
        spent += more
    return _timed(res, t0, spent)


#: Objectives whose sizing declines copper that buys too little (:func:`leaner`).
LEAN_OBJECTIVES = frozenset({"power"})


def leaner(
    model: DesignModel,
    res: OptimizationResult,
    ctx: _Attempt,
    options: SizingOptions,
    executor: Executor | None = None,
    say: Callable[[str], None] = _silent,
) -> tuple[OptimizationResult, int]:
    """Step 5 (least power): no copper that buys too little power.

    The least power can sit on a flat valley of copper: a pair whose current the worst heading
    hardly uses, sized up for a fraction of a per cent of power. With ``options.lean`` =
    (c, p), the leanest design within p of the least power is found by a least-copper sizing
    with the power limit lowered to (1 + p) × the least power (skipped where its continuous
    relaxation, a lower bound, is not c leaner already); if the least-power design holds
    more than (1 + c) times its copper, that design is taken instead, re-optimised for least
    power at its hardware (its power stays within p). So a sizing never spends more than
    ``c`` more copper for less than ``p`` of its objective.

    Parameters
    ----------
    model : DesignModel
        The design being sized (objective ``power``).
    res : OptimizationResult
        The least-power sizing's result (:func:`finish`).
    ctx : _Attempt
        What its neighbours' solves shared (the fixed model, the warm start, the scales).
    options : SizingOptions
        ``lean``.
    executor : Executor, optional
        Where the solves run (None: here).
    say : callable
        ``say(stage)``.

    Returns
    -------
    tuple of (OptimizationResult, int)
        The result (``res`` itself, or the leaner design with ``hardware.copper_declined``
        naming what was declined; SI) and the IPOPT iterations spent here (a count).
    """
    assert options.lean is not None and res.hardware is not None
    copper, objective = options.lean
    least_power, kg = res.objective_value, res.evaluation.copper_mass_kg
    cap = least_power * (1.0 + objective)
    lean_model = replace(
        model,
        bounds=replace(model.bounds, objective="copper_mass"),
        limits=replace(model.limits, power_W=min(float(model.limits.power_W), cap)),
    )
    say(f"the least copper within {objective:.0%} of the least power")
    # its continuous relaxation first: a bound below every discrete design's copper, so where
    # even it is not leaner enough no neighbour needs solving
    bound = least_copper(lean_model, options)
    spent = 0 if bound is None else bound.iterations
    if bound is None or not bound.objective * (1.0 + copper) < kg:
        return res, spent
    lean = size_design(lean_model, executor=executor, options=replace(options, lean=None))
    spent += lean.iterations
    if lean.status != "optimal" or lean.hardware is None:
        return res, spent
    if not lean.evaluation.copper_mass_kg * (1.0 + copper) < kg:
        return res, spent
    values = {**ctx.relaxed, **lean.hardware.discrete}
    full = _submit(executor, _full_result, ctx, values).result()
    spent += full.iterations
    if full.status != "optimal" or not full.objective_value <= cap * (1 + 1e-9):
        return res, spent
    declined = {
        "copper_kg": kg,
        "objective": least_power,
        "hardware": dict(res.hardware.discrete),
    }
    hardware = replace(
        res.hardware,
        discrete={name: values[name] for name in res.hardware.discrete},
        discrete_objective=full.objective_value,
        copper_declined=declined,
    )
    message = (
        f"{res.message}; {kg:.4g} kg of copper for {least_power:.4g} W declined: "
        f"{full.evaluation.copper_mass_kg:.4g} kg reach {full.objective_value:.4g} W "
        f"(more than {copper:.0%} more copper for less than {objective:.0%} of the power)"
    )
    return replace(
        full,
        iterations=0,
        hardware=hardware,
        message=message,
    ), spent


class _Relaxed(NamedTuple):
    """A continuous relaxation alone: its free hardware and objective value."""

    hardware: dict[str, float]
    objective: float
    iterations: int


def least_copper(model: DesignModel, options: SizingOptions = SizingOptions()) -> _Relaxed | None:
    """The continuous relaxation of ``model`` with the copper mass minimised and no copper limit:
    where the copper limit sits far below the starting hardware, IPOPT's starts end "locally
    infeasible" outside the small set of designs that meet it.

    Parameters
    ----------
    model : DesignModel
        A model with free hardware (``model.sizing``), SI.
    options : SizingOptions
        ``outer_max``.

    Returns
    -------
    _Relaxed or None
        The free hardware (SI), the least copper mass (kg) and the iterations spent; None if
        the relaxation has no solution.
    """
    least = replace(
        model,
        bounds=replace(model.bounds, objective="copper_mass"),
        limits=replace(model.limits, copper_mass_kg=None),
    )
    s = _setup(least)
    r = relax(s, options, lambda _stage: None)
    if r.best is None:
        return None
    return _Relaxed(r.hardware, _relaxed_objective(s, r), r.iterations)


def _timed(res: OptimizationResult, t0: float, iterations: int) -> OptimizationResult:
    """``res`` with the sizing's iterations added and its wall time."""
    return replace(
        res, iterations=res.iterations + iterations, solve_time_s=time.perf_counter() - t0
    )


def _no_neighbour(
    s: _Setup, ranking: Ranking, candidates: list[dict[str, float]], relaxed: dict[str, float]
) -> OptimizationResult:
    """What keeps the neighbours out: the first buildable one's own shortfalls (the relaxed
    problem at that hardware), or the geometric rule the first one breaks."""
    closest = ranking.first_built
    geometry: tuple = ()
    if closest is None and candidates:
        geometry = unbuildable(s.fixed_model, {**relaxed, **candidates[0]}, s.min_bore_m)
    why = (
        "no buildable neighbour of the relaxed optimum meets every requirement "
        f"({ranking.tried} tried)"
    )
    return _no_design(closest or s.fixed_model, why, geometry)


def _no_design(model: DesignModel, why: str, geometry: tuple = ()) -> OptimizationResult:
    """An infeasible result: what is out of reach at ``model``'s hardware (the relaxed
    problem's shortfalls), or the geometric rules the neighbours break."""
    res = solve_hardware(model, None, SolveOptions())
    shortfalls = geometry or res.shortfalls
    if not shortfalls:  # that hardware meets everything by itself: say so with its numbers
        ev = res.evaluation
        shortfalls = (
            Shortfall("safety_factor", "1", model.requirements.min_safety_factor, ev.safety_factor),
        )
    return replace(res, status="infeasible", shortfalls=shortfalls, message=f"infeasible: {why}")


def _mass_limited(model: DesignModel) -> bool:
    return model.limits.copper_mass_kg is not None and model.bounds.objective != "copper_mass"


def _hardware_text(values: dict[str, float]) -> str:
    return ", ".join(f"{k} = {v:.4g}" for k, v in values.items())


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
    count rounded down and up. Continuous quantities then re-balance around each.
    """
    unique, iterations = _rounded(problem, p, bounds, best, free, sizing)
    continuous = [v for v in free if v.kind not in ("turns", "wire")]
    if continuous:  # radii, magnet, spiral wire re-balance around the whole turns and wires
        whole_names = [v.name for v in free if v.kind in ("turns", "wire")]
        for combo in unique:
            box = {**bounds, **{n: (combo[n], combo[n]) for n in whole_names}}
            sol = problem.nlp.solve({**best.values(), **combo}, p, box)
            iterations += sol.iterations
            if sol.success:
                combo.update({v.name: sol.value(v.name) for v in continuous})
    return unique, iterations


def _rounded(problem, p, bounds, best, free, sizing) -> tuple[list[dict[str, float]], int]:
    """Whole turns and standard wires around ``best`` (see :func:`_neighbours`), each once."""
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
    return list({tuple(sorted(c.items())): c for c in out}.values()), iterations


def buildable(
    model: DesignModel, values: dict[str, float], min_bore_m: float, *, checks: bool = True
) -> DesignModel | None:
    """The model with hardware ``values`` if it can be built and meets the geometric rules
    (``checks=False``: no clearance or mass check, for the relaxation's iterates, whose
    clearance rows are exact only once the frozen factors settle).

    Parameters
    ----------
    model : DesignModel
        The fixed model (``sizing`` None) whose hardware ``values`` replace, SI.
    values : dict of str to float
        Hardware by name, each in the unit its name carries (``*_m`` in m, turns a count).
    min_bore_m : float
        Least bore the coils must leave, m (0: any bore).
    checks : bool
        Also the exact pack clearances and the copper mass
        (:func:`optimize.buildcheck.buildable_ok`); the bore and the magnet fit are checked
        either way.

    Returns
    -------
    DesignModel or None
        The model with that hardware (not prepared), SI; None if it cannot be constructed or
        breaks a rule.
    """
    import capsule as cap
    from optimize.buildcheck import buildable_ok
    from spiralcap.core.errors import InputError

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
        (x["helical_angle_rad"], x["frequency_hz"], x["field_scaled"] * scales.field_T)
        for x in grid
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
                key[0],
                key[0].scaled_sizes(key, values[hw.size_name(ax, key)]),
                values[f"{ax}.turns"],
                values[f"{ax}.wire_diameter_m"],
                values[hw.size_name(ax, key)],
                packing=pf,
                resistivity=1.0,
                h=1.0,
                aspect=values[f"{ax}.pack_aspect"],
            )["copper_mass_kg"]
            for ax, key in zip(hw.AXES, hw.shape_keys(model))
        )
    )


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
    (the exact build checks: pack clearances, bore room, copper mass, envelope; the bore
    against the minimum, the magnet fit).

    Parameters
    ----------
    model : DesignModel
        The fixed model (``sizing`` None) whose hardware ``values`` replace, SI.
    values : dict of str to float
        Hardware by name, each in the unit its name carries (``*_m`` in m, turns a count).
    min_bore_m : float
        Least bore the coils must leave, m.

    Returns
    -------
    tuple of Shortfall
        Each broken rule with what it needs and what the hardware gives, in m or kg (build
        checks, bore, magnet diameter or length); the input's key alone
        (no unit, zeros) where the hardware cannot be constructed; empty if none is broken.
    """
    import capsule as cap
    from spiralcap.core.errors import InputError

    try:
        m = hw.with_hardware(model, values)
    except InputError as exc:
        return (Shortfall(str(exc.key), "", 0.0, 0.0),)
    from optimize.buildcheck import build_checks

    # the exact build checks: pack clearances (solids), bore room, copper mass, envelope
    out = [Shortfall(c.name, c.unit, c.allowed, c.value) for c in build_checks(m) if not c.ok]
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
