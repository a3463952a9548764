"""The scenarios that matter: the robust NLP solved on a working set of them (cutting planes).

The CVaR objective and the failure row (:mod:`optimize.robust`) sum over every tissue scenario,
but at the optimum only the lower tail counts: with ``k = ceil(β S)`` (52 of 1024 at β = 0.05)
every scenario whose margin lies above the ``k``-th smallest has ``u_s = 0`` and an inactive row.
So the problem is solved on a **working set** ``A`` of the scenarios, with the sums still
normalised by the whole set's ``1/(β S)``:

    max  η − Σ_{s ∈ A} u_s / (β S),   u_s >= η − m_s(x),  u_s >= 0   (s ∈ A).

Dropping rows relaxes the problem, so its optimum bounds the whole problem's; and if at that
optimum no scenario outside ``A`` undercuts the ``k``-th smallest margin of ``A`` (the tail of the
whole set lies in ``A``), the whole problem's objective at that point equals the bound: it **is**
the whole problem's optimum (same for ``CVaR_p >= 0``: the whole set's ``CVaR_p`` at the point
equals ``A``'s, which the solve kept >= 0). Otherwise the scenarios that undercut join ``A`` and
the problem is re-solved warm from the last optimum (kept scenarios keep their slot, variables
and multipliers). Every scenario ever in the tail stays in ``A``, so ``A`` grows each round and the
loop ends (at worst with the whole set). The working set has a fixed capacity (compiled once; the
scenario data are parameters), about 1.25 k, doubled only when the tail outgrows it.

``requirements.max_failure_probability`` with an objective that has no scenarios (``margin``,
...) is first solved without the constraint: if the whole set's ``CVaR_p`` at that optimum is
already >= 0, the constraint cannot bind and that optimum is the answer (``skipped``, with the
evidence); otherwise the loop above starts there.

The check at the end is over every scenario of the whole set (numpy, the margins of
:func:`optimize.robust.scenario_margins`).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from optimize.robust import cvar
from optimize.solve import SolveOptions, grid_points, solve_fixed
from optimize.system import DesignModel, prepare

#: A scenario outside the working set may undercut the tail's edge by this share of the largest
#: |margin| (solver tolerance; its effect on CVaR is below it by the factor 1/(β S)).
TIE_RTOL = 1e-9
#: A working set no smaller than this (a few scenarios more than the tail).
MIN_CAPACITY = 16


@dataclass(frozen=True)
class ScenarioSolve:
    """How a robust optimum was found and its check over every scenario (SI).

    ``scenarios``: the whole set; ``capacity``: the working set's size (``scenarios`` when the
    whole set was solved at once, 0 when none was needed); ``rounds``: NLP solves of the loop;
    ``index``: the final working set (whole-set indices, slot order); ``skipped``: the
    failure constraint could not bind (the optimum without it already meets it);
    ``cvar_Nm`` / ``failure_cvar_Nm``: CVaR_β and CVaR_p of the worst-case margin over the whole
    set at the optimum; ``failure_probability``: the whole set's failure share there;
    ``outside_min_Nm`` / ``tail_edge_Nm``: the smallest margin outside the working set and the
    ``k``-th smallest inside it (the check: the first is not below the second).

    Attributes
    ----------
    scenarios : int
        Number of scenarios of the whole set.
    capacity : int
        Number of scenarios in the working set (see above).
    rounds : int
        Number of NLP solves of the loop.
    index : tuple of int
        The final working set, whole-set indices in slot order.
    skipped : bool
        Flag: the failure constraint could not bind.
    cvar_Nm, failure_cvar_Nm : float
        CVaR_β and CVaR_p of the worst-case margin over the whole set, N·m.
    failure_probability : float
        The whole set's failure share, a probability.
    outside_min_Nm, tail_edge_Nm : float
        Smallest margin outside the working set and the tail's edge inside it, N·m.
    """

    scenarios: int
    capacity: int
    rounds: int
    index: tuple[int, ...]
    skipped: bool
    cvar_Nm: float
    failure_cvar_Nm: float
    failure_probability: float
    outside_min_Nm: float
    tail_edge_Nm: float


def worst_margins(
    model: DesignModel, helical_angle_rad: float, frequency_hz: float, field_T: float
) -> np.ndarray:
    """The effective margin of every scenario of ``model`` (the least of its torque and grip
    margins over the tissue sets, :func:`optimize.robust.scenario_rows`; < 0: it fails), N·m.

    Parameters
    ----------
    model : DesignModel
        The design with its scenarios (prepared).
    helical_angle_rad : float
        Helical angle, rad.
    frequency_hz : float
        Rotation frequency, Hz.
    field_T : float
        Rotating-field amplitude at the centre, T.

    Returns
    -------
    ndarray, shape (S,)
        Worst-case margin of each scenario, N·m.
    """
    from optimize.robust import effective_margins, scenario_rows

    sc = model.scenarios
    c, req = model.constants, model.requirements
    rows = scenario_rows(
        helical_angle_rad, frequency_hz, field_T, c, req, sc.tissues, sc.grip_torque_Nm, sc.grip
    )
    return effective_margins(rows, sc.count)


def tail_count(model: DesignModel) -> int:
    """How many scenarios the CVaR terms of ``model`` weigh at most (``ceil(max(β, p) S)``).

    Parameters
    ----------
    model : DesignModel
        The design with its scenarios.

    Returns
    -------
    int
        Number of scenarios in the tail.
    """
    sc = model.scenarios
    share = sc.beta if model.bounds.objective == "margin_p05" else 0.0
    if sc.max_failure_probability is not None:
        share = max(share, sc.max_failure_probability)
    return max(math.ceil(share * sc.count - 1e-9), 1)


def capacity_for(tail: int, whole: int) -> int:
    """Working-set size for a tail of ``tail`` scenarios: 1.25 x, rounded up to 16 (the whole
    set when that is more than half of it).

    Parameters
    ----------
    tail : int
        Number of scenarios in the tail.
    whole : int
        Number of scenarios of the whole set.

    Returns
    -------
    int
        Number of scenarios of the working set.
    """
    cap = max(MIN_CAPACITY, 16 * math.ceil(1.25 * tail / 16))
    return whole if 2 * cap > whole else cap


def _point(res: Any) -> tuple[float, float, float]:
    """The NLP optimum's angle, frequency and field (the solver's own field, not rounded to the
    capacity evaluate reports)."""
    x = res.solution_x or {}
    return (
        float(x.get("helical_angle_rad", res.helical_angle_rad)),
        float(x.get("frequency_hz", res.frequency_hz)),
        float(x.get("field_T", res.field_amplitude_T)),
    )


def _record(model, res, rounds, capacity, index, skipped) -> ScenarioSolve:
    sc = model.scenarios
    m = worst_margins(model, *_point(res)) if res.feasible else np.full(sc.count, np.nan)
    p = sc.max_failure_probability
    idx = np.asarray(index, dtype=np.intp)
    inside = np.zeros(sc.count, dtype=bool)
    inside[idx] = True
    k = min(tail_count(model), max(idx.size, 1))
    edge = float(np.sort(m[inside])[k - 1]) if idx.size else float("nan")
    outside = float(np.min(m[~inside])) if (~inside).any() else float("inf")
    return ScenarioSolve(
        scenarios=sc.count,
        capacity=capacity,
        rounds=rounds,
        index=tuple(int(i) for i in idx),
        skipped=skipped,
        cvar_Nm=cvar(m, sc.beta),
        failure_cvar_Nm=cvar(m, p) if p is not None else float("nan"),
        failure_probability=float(np.mean(m < 0)),
        outside_min_Nm=outside,
        tail_edge_Nm=edge,
    )


def initial_index(model, cap, points) -> np.ndarray:
    """The first working set: the ``cap`` scenarios of the best rank at any of ``points``
    (ties by index).

    Parameters
    ----------
    model : DesignModel
        The design with its whole scenario set.
    cap : int
        Number of scenarios of the working set.
    points : list of (float, float, float)
        (angle, rad; frequency, Hz; field, T) points to rank the scenarios at.

    Returns
    -------
    ndarray of int
        Whole-set indices of the working set.
    """
    if not points:
        return np.arange(cap)
    ranks = []
    for a, f, b in points:
        order = np.argsort(worst_margins(model, a, f, b), kind="stable")
        r = np.empty_like(order)
        r[order] = np.arange(order.size)
        ranks.append(r)
    best = np.min(np.stack(ranks), axis=0)
    return np.lexsort((np.arange(best.size), best))[:cap]


def _warm_index(warm: Any) -> np.ndarray | None:
    if isinstance(warm, dict):
        idx = warm.get("scenario_index")
    else:
        rec = getattr(warm, "scenario_solve", None)
        idx = rec.index if rec is not None and rec.capacity < rec.scenarios else None
    return None if idx is None else np.asarray(idx, dtype=np.intp)


def _core(warm: Any) -> Any:
    """A warm start without scenario variables (for a problem of another working set)."""
    if warm is None:
        return None
    if isinstance(warm, dict):
        return {k: v for k, v in warm.items() if k != "scenario_index"}
    if not warm.solution_x:
        return None
    keep = ("helical_angle_rad", "frequency_hz", "field_T", "t_value")
    return {k: v for k, v in warm.solution_x.items() if k in keep}


def _warm_point(warm: Any) -> tuple[float, float, float] | None:
    """The (angle, frequency, field) of a warm start, if it has one."""
    if isinstance(warm, dict):
        if "helical_angle_rad" in warm and "frequency_hz" in warm and "field_T" in warm:
            return (warm["helical_angle_rad"], warm["frequency_hz"], warm["field_T"])
        return None
    if warm is not None and warm.solution_x:
        return _point(warm)
    return None


def _slot_warm(res: Any, model: DesignModel, changed: set[int]) -> Any:
    """``res`` as a warm start for the same working-set structure with the slots ``changed``
    holding other scenarios: their variables start where their rows hold, multipliers 0."""
    from optimize.compiled import compile_problem, structure_of

    if not res.solution_x or res.solution_lam_g is None:
        return _core(res)
    x = {
        k: v
        for k, v in res.solution_x.items()
        if not (k.endswith("]") and "excess[" in k and int(k[k.index("[") + 1 : -1]) in changed)
    }
    lam = np.array(res.solution_lam_g, dtype=float)
    rows = compile_problem(structure_of(model)).nlp.rows
    if lam.size != len(rows):
        return _core(res)
    for i, row in enumerate(rows):
        if row.kind == "epigraph" and row.name.endswith("]") and "cvar[" in row.name:
            slot = int(row.name[row.name.rindex("[") + 1 : -1])
            if slot in changed:
                lam[i] = 0.0
    return replace(res, solution_x=x, solution_lam_g=lam)


def _next_index(index, m, must, cap) -> tuple[np.ndarray, set[int]]:
    """The next working set: every scenario of ``must``, the rest the worst at this point;
    kept scenarios keep their slot. Returns it and the slots that changed."""
    ranked = np.argsort(m, kind="stable")
    desired = list(must)
    chosen = set(desired)
    for s in ranked:
        if len(desired) >= cap:
            break
        if int(s) not in chosen:
            desired.append(int(s))
            chosen.add(int(s))
    if len(index) != cap:
        return np.array(desired, dtype=np.intp), set(range(cap))
    new = [int(s) if int(s) in chosen else -1 for s in index]
    incoming = iter(s for s in desired if s not in set(new))
    changed = set()
    for i, s in enumerate(new):
        if s < 0:
            new[i] = next(incoming)
            changed.add(i)
    return np.array(new, dtype=np.intp), changed


def solve_hardware(
    model: DesignModel, warm_start: Any = None, options: SolveOptions | None = None
) -> Any:
    """The optimum of ``model`` at its fixed hardware: over its tissue scenarios
    (:func:`optimize_scenarios`) when it carries a whole scenario set, else one NLP
    (:func:`optimize.solve.solve_fixed`).

    Parameters
    ----------
    model : DesignModel
        The design, SI (its hardware fixed).
    warm_start : OptimizationResult or dict, optional
        As :func:`optimize_scenarios`: angle (rad), frequency (Hz), field (T).
    options : SolveOptions, optional
        How each NLP is solved (default ``SolveOptions()``).

    Returns
    -------
    OptimizationResult
    """
    if model.scenarios is not None and model.scenarios.whole:
        return optimize_scenarios(model, warm_start, options)
    return solve_fixed(model, warm_start, options or SolveOptions())


def optimize_scenarios(
    model: DesignModel, warm_start: Any = None, options: SolveOptions | None = None
) -> Any:
    """The robust optimum of ``model`` (whole scenario set, fixed hardware) by the working-set
    loop: each round one NLP on the working set (:func:`optimize.solve.solve_fixed`), checked
    over every scenario.

    Parameters
    ----------
    model : DesignModel
        The design with its whole tissue-scenario set (``model.scenarios``), SI.
    warm_start : OptimizationResult or dict, optional
        A neighbouring problem's result, or a dict of ``helical_angle_rad``,
        ``frequency_hz``, ``field_T`` and optionally ``scenario_index`` (a working set to start from);
        without one, the grid starts rank the scenarios for the first working set.
    options : SolveOptions, optional
        How each working-set NLP is solved (default ``SolveOptions()``).

    Returns
    -------
    OptimizationResult
        With ``scenario_solve`` recording the working set and rounds.
    """
    t0 = time.perf_counter()
    how = options or SolveOptions()
    res = _working_set_loop(model, lambda m, warm: solve_fixed(m, warm, how), warm_start)
    return replace(res, solve_time_s=time.perf_counter() - t0)


def _working_set_loop(
    model: DesignModel, solve: Callable[[DesignModel, Any], Any], warm_start: Any
) -> Any:
    """:func:`optimize_scenarios` with ``solve(model, warm_start)`` the one-NLP solve."""
    model = prepare(model)
    sc = model.scenarios
    whole = sc.count
    tail = tail_count(model)
    cap = capacity_for(tail, whole)
    rounds = 0
    warm = warm_start
    points: list[tuple[float, float, float]] = []
    if model.bounds.objective != "margin_p05":  # the chance constraint alone: can it bind?
        free = solve(replace(model, scenarios=None), _core(warm_start))
        rounds += 1
        if not free.feasible:  # infeasible without the row: more so with it
            return replace(free, scenario_solve=_record(model, free, rounds, 0, (), False))
        rec = _record(model, free, rounds, 0, (), False)
        if rec.failure_cvar_Nm >= -TIE_RTOL * _size(model, free):
            return replace(free, scenario_solve=replace(rec, skipped=True))
        points, warm = [_point(free)], _core(free)
    if cap >= whole:
        res = solve(model, warm)
        rec = _record(model, res, rounds + 1, whole, range(whole), False)
        return replace(res, scenario_solve=rec)
    prev = _warm_index(warm_start)
    if prev is not None and prev.size == cap:  # a neighbouring solve's working set and slots
        ws = WorkingSet(model, prev)
        if isinstance(warm, dict):
            warm = _core(warm)
    else:
        if not points:
            point = _warm_point(warm)
            points = [point] if point is not None else []
        if not points:
            points = grid_points(model)
        ws = WorkingSet(model, initial_index(model, cap, points))
        warm = _core(warm)
    while True:
        working = ws.model(model)
        res = solve(working, warm)
        rounds += 1
        if not res.feasible:
            return _infeasible(model, res, rounds, ws.capacity, ws.index)
        changed = ws.update(model, _point(res))
        if changed is None:
            return replace(res, scenario_solve=ws.record(model, res, rounds))
        same = len(changed) < ws.capacity
        warm = _slot_warm(res, working, changed) if same else _core(res)


class WorkingSet:
    """The scenarios a robust NLP is solved on, and how they grow (see the module notes).

    ``index``: whole-set indices in slot order (its size is the capacity compiled in).

    Parameters
    ----------
    model : DesignModel
        The design with its whole scenario set.
    index : ndarray of int
        Whole-set indices of the first working set, slot order.
    """

    def __init__(self, model: DesignModel, index: np.ndarray) -> None:
        self.index = np.asarray(index, dtype=np.intp)
        self.tail = tail_count(model)
        self.whole = model.scenarios.count
        self.ever: set[int] = set()

    @property
    def capacity(self) -> int:
        """Number of scenarios compiled in."""
        return int(self.index.size)

    def model(self, model: DesignModel) -> DesignModel:
        """``model`` (whole scenario set) carrying this working set instead.

        Parameters
        ----------
        model : DesignModel
            The design with its whole scenario set.

        Returns
        -------
        DesignModel
            The same design carrying the working set.
        """
        return replace(model, scenarios=model.scenarios.working(self.index))

    def update(self, model: DesignModel, point: tuple[float, float, float]) -> set[int] | None:
        """Check the optimum ``point`` over every scenario of ``model``: None if no scenario
        outside the set undercuts the tail's edge inside it (the set's optimum is the whole
        problem's), else move to the next set and return the slots that changed (all of them
        when the capacity grew).

        Parameters
        ----------
        model : DesignModel
            The design with its whole scenario set.
        point : (float, float, float)
            The optimum's angle (rad), frequency (Hz) and field (T).

        Returns
        -------
        set of int or None
            Indices of the slots that changed, or None when the working set's optimum is the whole
            problem's.
        """
        m = worst_margins(model, *point)
        inside = np.zeros(self.whole, dtype=bool)
        inside[self.index] = True
        k = min(self.tail, self.index.size)
        edge = np.sort(m[inside])[k - 1]
        tol = TIE_RTOL * max(float(np.max(np.abs(m))), 1e-300)
        undercut = np.flatnonzero(~inside & (m < edge - tol))
        self.ever.update(int(s) for s in np.argsort(m, kind="stable")[: self.tail])
        if undercut.size == 0:
            return None
        # the tail here is not all in the set: it joins (so the set grows each round); the
        # rest of the set is the worst at this point
        must = sorted(self.ever, key=lambda s: (m[s], s))
        cap = self.capacity
        while len(must) > cap:
            cap = min(self.whole, 2 * cap)
        self.index, changed = _next_index(self.index, m, must, cap)
        return changed

    def record(self, model: DesignModel, res: Any, rounds: int) -> ScenarioSolve:
        """The evidence of a converged solve.

        Parameters
        ----------
        model : DesignModel
            The design with its whole scenario set.
        res : OptimizationResult
            The converged solve.
        rounds : int
            Number of NLP solves so far.

        Returns
        -------
        ScenarioSolve
            The record of the loop.
        """
        return _record(model, res, rounds, self.capacity, self.index, False)


def _size(model: DesignModel, res: Any) -> float:
    m = worst_margins(model, *_point(res))
    return max(float(np.max(np.abs(m))), 1e-300)


def _infeasible(model, res, rounds, cap, index) -> Any:
    """An infeasible working-set result (the whole problem, more constrained, is infeasible
    too), its failure shortfall measured over the whole set at the closest design."""
    sc = model.scenarios
    m = worst_margins(model, res.helical_angle_rad, res.frequency_hz, res.field_amplitude_T)
    share = float(np.mean(m < 0))
    shortfalls = tuple(
        replace(s, best=share) if s.name == "failure_probability" else s for s in res.shortfalls
    )
    rec = ScenarioSolve(
        sc.count,
        cap,
        rounds,
        tuple(int(i) for i in index),
        False,
        cvar(m, sc.beta),
        cvar(m, sc.max_failure_probability) if sc.max_failure_probability else float("nan"),
        share,
        float("nan"),
        float("nan"),
    )
    return replace(res, shortfalls=shortfalls, scenario_solve=rec)
