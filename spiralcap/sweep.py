"""Sweeps: evaluate or re-optimise a design across a grid of design keys.

Keys that enter the margin only as operating variables or limit values (helical angle,
frequency, ``limits.*`` numbers, ``requirements.*``) are swept in one vectorised call of
:func:`optimize.margin_grid` (10^5 points in well under a second); any other key rebuilds the
model point by point. ``optimize=True`` re-optimises at every grid point, optionally in worker
processes.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from spiralcap.core.checks import guard, instance
from spiralcap.core.constants import from_unit
from spiralcap.core.errors import InputError
from spiralcap.design import Design
from spiralcap.schema import KEYS, si_name, to_si

#: design key -> where it lives in the model (the angle and the frequency by their model field
#: names of :data:`spiralcap.keymap.FIELD_KEYS`, or the model part holding the SI value under
#: the key's SI leaf name); the SI conversion comes from the schema's unit table
_VECTOR_KEYS: dict[str, str] = {
    "capsule.spiral.helical_angle_deg": "spiral.helical_angle_rad",
    "operation.frequency_hz": "operation.frequency_hz",
    "limits.current_A": "limits",
    "limits.voltage_V": "limits",
    "limits.power_W": "limits",
    "limits.coil_temperature_C": "limits",
    "requirements.axial_load_mN": "requirements",
    "requirements.slip_efficiency": "requirements",
    "requirements.min_speed_mm_s": "requirements",
    "requirements.min_spiral_turns": "requirements",
    "requirements.min_wall_strain": "requirements",
}
#: Most grid points a sweep may have, by mode: the vectorised evaluation holds a few dozen
#: float arrays of this length (2.5e5 points: ~0.2 GB at most); point-by-point evaluation
#: rebuilds the model each time (~10 ms), re-optimisation solves an NLP each time (~0.1-1 s).
MAX_POINTS = {"vectorised": 250_000, "points": 20_000, "optimize": 5_000}
EVALUATE_COLUMNS = (
    "margin_Nm",
    "safety_factor",
    "field_amplitude_T",
    "speed_m_s",
    "wall_strain",  # the least over the tissue sets (the spiral grips where > 0)
    "feasible",
    # "ok" / "below minimum" (requirements.min_wall_strain, extrapolated) / "none" (no contact:
    # margin_Nm and safety_factor NaN, speed 0)
    "grip",
)
#: Most points of a vectorised evaluation per array call: a larger grid is cut into equal calls,
#: each a progress step (a call costs about 1.5 s besides its points, the field-capacity
#: bisection; at most 4 calls for the largest grid, MAX_POINTS["vectorised"]).
VECTOR_CHUNK = 65_536
#: Consecutive grid points re-optimised as one warm-started chain (one task).
OPTIMIZE_CHUNK = 16
OPTIMIZE_COLUMNS = (
    "status",
    "helical_angle_deg",
    "frequency_hz",
    "margin_Nm",
    "safety_factor",
    "field_amplitude_T",
    "binding_limits",
    "grip",  # of the optimum, or of the closest design where none is feasible
)


#: The objective's own value where no column above holds it (margin and ratio have theirs,
#: the copper mass is always a column), in its unit; a registered objective's as
#: ``objective_value``. ``margin_p05`` maximises the CVaR at 5 % (the mean of the worst 5 % of
#: the scenario margins), not the 5th percentile: its column says so (``cvar05_Nm``, as in
#: ``optimize --json``'s ``robust.in_sample``).
_OBJECTIVE_COLUMNS = {"power": "power_W", "margin_p05": "cvar05_Nm"}


def optimize_columns(model: Any) -> tuple[str, ...]:
    """The columns of an optimising sweep of ``model``: :data:`OPTIMIZE_COLUMNS`, the copper
    mass of the three pairs (kg), the objective's own value where those do not hold it, and,
    when hardware is free, the sized (discrete) hardware by design key (design units)."""
    from spiralcap.assemble.system import hardware_design_values

    extra = ["copper_mass_kg"]
    objective = model.bounds.objective
    if objective in _OBJECTIVE_COLUMNS:
        extra.append(_OBJECTIVE_COLUMNS[objective])
    elif objective not in ("margin", "ratio", "copper_mass"):
        extra.append("objective_value")
    if model.sizing is not None:
        extra += list(hardware_design_values({v.name: 1.0 for v in model.sizing.free}))
    return (*OPTIMIZE_COLUMNS, *extra)


@dataclass(frozen=True)
class Axis:
    """One swept key: ``n`` values from ``start`` to ``stop`` inclusive."""

    key: str
    values: np.ndarray


@dataclass(frozen=True)
class SweepResult:
    """Grid of swept keys (flattened, C order) and one array per output column."""

    axes: tuple[Axis, ...]
    inputs: dict[str, np.ndarray]
    outputs: dict[str, np.ndarray]
    mode: str


@guard(expr=instance(str, "text of the form KEY=START:STOP:N"))
def parse_over(expr: str) -> Axis:
    """Parse ``KEY=START:STOP:N`` (N >= 1; a whole-number key takes whole START and STOP, the
    points between are rounded and must stay distinct)."""
    key, sep, rng = expr.partition("=")
    parts = rng.split(":")
    allowed = "the form KEY=START:STOP:N, e.g. operation.frequency_hz=0.5:5:10"
    if not sep or len(parts) != 3:
        raise InputError("--over", expr, allowed)
    key = key.strip()
    if key not in KEYS or KEYS[key].kind not in (float, int):
        raise InputError("--over", expr, "a numeric design key (see `spiralcap init`)")
    try:
        start, stop, n = float(parts[0]), float(parts[1]), int(parts[2])
    except ValueError:
        raise InputError("--over", expr, allowed) from None
    if not (1 <= n <= MAX_POINTS["vectorised"]) or not (
        math.isfinite(start) and math.isfinite(stop)
    ):
        raise InputError(
            "--over", expr, f"finite START and STOP and 1 <= N <= {MAX_POINTS['vectorised']}"
        )
    values = np.linspace(start, stop, n)
    for v in (start, stop):
        if KEYS[key].kind is int and not v.is_integer():  # a count: whole-number bounds
            raise InputError("--over", expr, f"whole numbers START and STOP: {key} is a count")
        if not KEYS[key].check(int(v) if KEYS[key].kind is int else v):
            raise InputError(key, v, KEYS[key].allowed)
    if KEYS[key].kind is int:
        values = np.unique(np.round(values).astype(int))
    return Axis(key, values)


def _grid(axes: Sequence[Axis]) -> dict[str, np.ndarray]:
    mesh = np.meshgrid(*[a.values for a in axes], indexing="ij")
    return {a.key: m.ravel() for a, m in zip(axes, mesh)}


@guard(design=instance(Design, "a spiralcap.design.Design (spiralcap.design.load_design)"))
def sweep(
    design: Design,
    axes: Sequence[Axis],
    *,
    optimize: bool = False,
    workers: int = 1,
    progress: Callable[[int, int], None] | None = None,
    dask: str | None = None,
    model: Any = None,
) -> SweepResult:
    """Evaluate (or re-optimise) ``design`` at every point of the grid spanned by ``axes``.

    ``workers`` local processes or a Dask scheduler at ``dask`` run the re-optimisations
    (:func:`spiralcap.parallel.map_tasks`); the rows do not depend on where they ran.
    ``model``: ``optimization_model(design)`` already built (prepared or not), re-optimised in
    this process where every swept key is a limit or a requirement instead of building it
    again (same rows: the same model).

    Raises
    ------
    InputError
        The grid has more points than :data:`MAX_POINTS` allows for the mode (checked before
        any work).
    """
    size = math.prod(len(a.values) for a in axes)
    kind = (
        "optimize"
        if optimize
        else ("vectorised" if all(a.key in _VECTOR_KEYS for a in axes) else "points")
    )
    if size > MAX_POINTS[kind]:
        raise InputError(
            "--over",
            " ".join(f"{a.key}:{len(a.values)}" for a in axes),
            f"a grid of at most {MAX_POINTS[kind]} points for this sweep "
            f"({'re-optimising' if optimize else 'evaluating'}"
            f"{'' if kind != 'points' else ' point by point'}; this one has {size})",
        )
    inputs = _grid(axes)
    if optimize:
        outputs = _optimize_points(design, inputs, workers, progress, dask, model)
        mode = "optimize"
    elif all(a.key in _VECTOR_KEYS for a in axes):
        outputs = _evaluate_vectorised(design, inputs, progress)
        mode = "evaluate (vectorised)"
    else:
        outputs = _evaluate_points(design, inputs, progress)
        mode = "evaluate (point by point)"
    return SweepResult(tuple(axes), inputs, outputs, mode)


def _vector_model(
    design: Design, inputs: dict[str, np.ndarray], base: Any = None
) -> tuple[Any, Any, Any]:
    """The model with the swept limits and requirements as arrays, and the angle and frequency
    at every point (rad, Hz); ``base`` is the prepared model of ``design`` when already built."""
    from optimize import prepare
    from spiralcap.assemble import build_model

    model = base if base is not None else prepare(build_model(design, optimiser=False))
    alpha: Any = model.capsule.spiral.helical_angle_rad
    f: Any = model.frequency_hz
    groups: dict[str, dict[str, Any]] = {"limits": {}, "requirements": {}}
    for key, values in inputs.items():
        where = _VECTOR_KEYS[key]
        if where == "spiral.helical_angle_rad":
            alpha = to_si(key, values)
        elif where == "operation.frequency_hz":
            f = to_si(key, values)
        else:
            groups[where][si_name(key)] = to_si(key, values)
    model = replace(
        model,
        limits=replace(model.limits, **groups["limits"]),
        requirements=replace(model.requirements, **groups["requirements"]),
    )
    n = len(next(iter(inputs.values())))
    return model, np.broadcast_to(alpha, (n,)), np.broadcast_to(f, (n,))


def _evaluate_vectorised(
    design: Design,
    inputs: dict[str, np.ndarray],
    progress: Callable[[int, int], None] | None = None,
) -> dict[str, np.ndarray]:
    """Every point in equal array calls of at most :data:`VECTOR_CHUNK` points (the same
    numbers as one call: each point is computed on its own), ``progress(done, total)`` after
    each."""
    from optimize import margin_grid, prepare
    from spiralcap.assemble import build_model

    base = prepare(build_model(design, optimiser=False))
    n = len(next(iter(inputs.values())))
    parts: dict[str, list[np.ndarray]] = {k: [] for k in EVALUATE_COLUMNS}
    calls = -(-n // VECTOR_CHUNK)
    step = -(-n // calls)
    for lo in range(0, n, step):
        chunk = {k: v[lo : lo + step] for k, v in inputs.items()}
        model, alpha, f = _vector_model(design, chunk, base)
        out = margin_grid(model, alpha, f)
        for k in EVALUATE_COLUMNS:
            parts[k].append(np.broadcast_to(np.asarray(out[k]), alpha.shape))
        if progress:
            progress(min(lo + step, n), n)
    return {k: np.concatenate(v) for k, v in parts.items()}


def failing_requirements(design: Design, result: SweepResult) -> np.ndarray | None:
    """The requirement that fails at each point of a vectorised sweep (``""``: none, or only
    a negative margin), as :func:`spiralcap.feasibility.failing_requirements`; None for other
    modes (their points are rebuilt or re-optimised one by one)."""
    from optimize import margin_grid
    from spiralcap.feasibility import failing_requirements as failing

    if result.mode != "evaluate (vectorised)":
        return None
    model, alpha, f = _vector_model(design, result.inputs)
    return failing(model, alpha, margin_grid(model, alpha, f))


def _evaluate_points(design, inputs, progress) -> dict[str, np.ndarray]:
    from optimize import evaluate
    from spiralcap.assemble import build_model

    n = len(next(iter(inputs.values())))
    rows = []
    reasons = []
    for i in range(n):
        try:
            ev = evaluate(build_model(_at(design, inputs, i), optimiser=False))
        except InputError as exc:  # this point cannot be built: a row that says so and why
            rows.append((math.nan,) * (len(EVALUATE_COLUMNS) - 2) + (False, "unbuildable"))
            reasons.append(str(exc))
        else:
            rows.append(
                (
                    ev.margin_Nm,
                    ev.safety_factor,
                    ev.field_amplitude_T,
                    ev.speed_m_s,
                    min(ev.wall_strains),
                    ev.feasible,
                    ev.grip,
                )
            )
            reasons.append("")
        if progress:
            progress(i + 1, n)
    out = {k: np.array([r[j] for r in rows]) for j, k in enumerate(EVALUATE_COLUMNS)}
    return {**out, **unbuildable_columns(reasons)}


def unbuildable_columns(reasons: Sequence[str]) -> dict[str, np.ndarray]:
    """``unbuildable`` (flag) and ``unbuildable_reason`` (the one-line error, "" where the
    point was built) when any point of a sweep could not be built; no columns when all were."""
    if not any(reasons):
        return {}
    return {
        "unbuildable": np.array([bool(r) for r in reasons]),
        "unbuildable_reason": np.array(list(reasons), dtype=object),
    }


def _at(design: Design, inputs: dict[str, np.ndarray], i: int) -> Design:
    values = {}
    for k, v in inputs.items():
        values[k] = int(v[i]) if KEYS[k].kind is int else float(v[i])
    return design.with_values(values)


def _row(r, columns: tuple[str, ...] = OPTIMIZE_COLUMNS) -> tuple:
    """``columns`` (:func:`optimize_columns`) of the result ``r``; NaN where it has none (the
    sized hardware of an infeasible sizing)."""
    from spiralcap.assemble.system import hardware_design_values
    from spiralcap.presentation import binding

    values: dict[str, Any] = dict(
        zip(
            OPTIMIZE_COLUMNS,
            (
                r.status,
                r.helical_angle_deg,
                r.frequency_hz,
                r.margin_Nm,
                r.safety_factor,
                r.field_amplitude_T,
                ";".join(b.name for b in binding(r.binding_limits)),
                r.evaluation.grip,
            ),
        )
    )
    values["copper_mass_kg"] = float(r.evaluation.copper_mass_kg)
    for name in (*_OBJECTIVE_COLUMNS.values(), "objective_value"):
        values[name] = float(r.objective_value)
    if r.hardware is not None:
        values.update(hardware_design_values(r.hardware.discrete))
    return tuple(values.get(c, float("nan")) for c in columns)


def _light(keys: Any) -> bool:
    """True when every key is a limit or a requirement (one built model serves every point)."""
    return all(_VECTOR_KEYS.get(k, "") in ("limits", "requirements") for k in keys)


def with_values(base: Any, values: dict[str, float]) -> Any:
    """``base`` (a model) with limit and requirement keys set to ``values`` (design units)."""
    groups: dict[str, dict[str, Any]] = {"limits": {}, "requirements": {}}
    for key, value in values.items():
        groups[_VECTOR_KEYS[key]][si_name(key)] = float(to_si(key, float(value)))
    return replace(
        base,
        limits=replace(base.limits, **groups["limits"]),
        requirements=replace(base.requirements, **groups["requirements"]),
    )


def _models(design: Design, inputs: dict[str, np.ndarray], base: Any = None):
    """The model at every grid point: limits and requirements replaced in one built model
    (``base``, else built here), any other key rebuilt from the design."""
    from optimize import prepare
    from spiralcap.robust import optimization_model

    n = len(next(iter(inputs.values())))
    # the Constants do not depend on the limits (the winding resistance is self-consistent with
    # the heating at each current, not taken at the temperature limit): one model serves all
    if _light(inputs):
        base = prepare(base if base is not None else optimization_model(design))
    else:
        base = None
    for i in range(n):
        if base is None:
            try:
                yield optimization_model(_at(design, inputs, i))
            except InputError as exc:  # an unbuildable point: its error in the model's place
                yield exc
            continue
        yield with_values(base, {key: float(values[i]) for key, values in inputs.items()})


def _optimize_chunk(
    design: Design,
    inputs: dict[str, np.ndarray],
    progress: Callable[[int], None] | None = None,
    base: Any = None,
    columns: tuple[str, ...] = OPTIMIZE_COLUMNS,
) -> list[tuple]:
    """Re-optimise the points of one chunk, each warm-started from the previous optimum
    (variables and multipliers; the first from the grid starts). The problem's numbers are
    parameters, so the chunk re-solves one compiled solver."""
    from optimize import optimize_design
    from spiralcap.stopping import raise_if_requested

    rows: list[tuple] = []
    previous: Any = None
    for i, model in enumerate(_models(design, inputs, base)):
        if isinstance(model, InputError):  # status "unbuildable", the reason last
            previous = None
            rows.append(_unbuildable_row(columns, str(model)))
        else:
            warm = previous if previous is not None and previous.feasible else None
            # the rows need no step-out or highest frequency: those searches are skipped
            previous = optimize_design(model, warm_start=warm, frequency_bounds=False)
            raise_if_requested()  # a stop request whose exception was lost ends the chunk here
            rows.append((*_row(previous, columns), ""))
        if progress:
            progress(i + 1)
    return rows


def _unbuildable_row(columns: tuple[str, ...], reason: str) -> tuple:
    """A row of a point that cannot be built: status ``unbuildable``, no numbers (NaN), no
    binding limits, then the reason (the chunk's rows end with it)."""
    values = {"status": "unbuildable", "binding_limits": "", "grip": "unbuildable"}
    return (*(values.get(c, math.nan) for c in columns), reason)


def _optimize_points(
    design, inputs, workers, progress, dask=None, base=None
) -> dict[str, np.ndarray]:
    """Re-optimise at every point, in chunks of :data:`OPTIMIZE_CHUNK` consecutive points.

    A chunk is a warm-started chain from a cold first point and is fixed by its index range,
    so the rows are the same bit for bit here, in worker processes or on a Dask cluster.
    """
    from spiralcap.assemble import build_model

    columns = optimize_columns(base if base is not None else build_model(design))
    n = len(next(iter(inputs.values())))
    chunks = [
        {k: v[s : s + OPTIMIZE_CHUNK] for k, v in inputs.items()}
        for s in range(0, n, OPTIMIZE_CHUNK)
    ]
    if (workers > 1 and len(chunks) > 1) or dask is not None:  # one chunk: here, with base
        from spiralcap.parallel import map_tasks

        parts = map_tasks(
            _optimize_chunk,
            [(design, c, None, None, columns) for c in chunks],
            workers=workers,
            dask=dask,
            progress=(lambda done, _: progress(min(done * OPTIMIZE_CHUNK, n), n))
            if progress
            else None,
        )
    else:
        parts = []
        for j, c in enumerate(chunks):
            done = j * OPTIMIZE_CHUNK
            report = (lambda i, d=done: progress(d + i, n)) if progress else None
            parts.append(_optimize_chunk(design, c, report, base, columns))
    rows = [r for part in parts for r in part]
    out = {k: np.array([r[j] for r in rows]) for j, k in enumerate(columns)}
    return {**out, **unbuildable_columns([r[-1] for r in rows])}


def optimize_row(model: Any, warm: dict[str, Any] | None = None) -> dict[str, Any]:
    """One row of :func:`optimize_columns`: ``model`` re-optimised (no step-out search).

    ``warm``: a row of a neighbouring problem (``helical_angle_deg``, ``frequency_hz``,
    ``field_amplitude_T``) to start from; its optimum need not be feasible here
    (:func:`optimize.optimize_design` falls back to the grid starts when the warm start fails).
    """
    from optimize import optimize_design

    start = None
    if warm is not None and warm["status"] == "optimal":
        start = {
            "helical_angle_rad": from_unit(float(warm["helical_angle_deg"]), "deg"),
            "frequency_hz": float(warm["frequency_hz"]),
            "field_T": float(warm["field_amplitude_T"]),
        }
    columns = optimize_columns(model)
    return result_row(optimize_design(model, warm_start=start, frequency_bounds=False), columns)


def result_row(result: Any, columns: tuple[str, ...] = OPTIMIZE_COLUMNS) -> dict[str, Any]:
    """An :class:`optimize.OptimizationResult` as a row of ``columns``
    (:func:`optimize_columns`)."""
    return dict(zip(columns, _row(result, columns)))
