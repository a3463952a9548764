"""Solve the design NLP with IPOPT (exact CasADi derivatives), from several starts.

1. A coarse vectorised evaluation (:func:`optimize.evaluate.margin_grid`) over angle x frequency
   gives one start per helical-angle band (the problem need not be convex in the angle).
2. IPOPT maximises the epigraph variable from each start; the best converged point wins.
3. If no start converges to a point that meets every requirement, a relaxed problem (slacks on
   the speed, spiral-turn and margin requirements, limits kept hard) finds how far each is out of
   reach, and the result says so.
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any

import casadi as ca
import numpy as np

from optimize import problem as pb
from optimize.evaluate import _three, evaluate, margin_grid, worst_required
from optimize.result import BindingLimit, OptimizationResult, Shortfall
from optimize.system import DesignModel, prepare

_IPOPT_OPTIONS: dict[str, Any] = {
    "ipopt.print_level": 0,
    "print_time": False,
    "ipopt.sb": "yes",
    "ipopt.tol": 1e-10,
    "ipopt.constr_viol_tol": 1e-10,
    "ipopt.max_iter": 300,
    # the starts are good grid points: a smaller initial barrier saves iterations
    "ipopt.mu_init": 1e-3,
}
_SUCCESS = {"Solve_Succeeded", "Solved_To_Acceptable_Level"}


def scales_for(model: DesignModel) -> pb.Scales:
    """Reference field and torque: the values at the centre of the search box."""
    b = model.bounds
    alpha = 0.5 * (b.helical_angle_min_rad + b.helical_angle_max_rad)
    f = 0.5 * (b.frequency_min_hz + b.frequency_max_hz)
    field = float(margin_grid(model, alpha, f)["field_amplitude_T"])
    need = float(worst_required(model, alpha, f)[2])
    return pb.Scales(field_T=max(field, 1e-6), torque_Nm=max(abs(need), 1e-9))


def initial_points(model: DesignModel, scales: pb.Scales, starts: int) -> list[list[float]]:
    """One start per helical-angle band: the best point of a coarse grid in that band."""
    b = model.bounds
    alphas = np.linspace(b.helical_angle_min_rad, b.helical_angle_max_rad, 8 * max(starts, 1))
    freqs = np.geomspace(b.frequency_min_hz, b.frequency_max_hz, 24)
    A, F = np.meshgrid(alphas, freqs, indexing="ij")
    g = margin_grid(model, A, F)
    score = g["safety_factor"] if model.bounds.objective == "ratio" else g["margin_Nm"]
    score = np.where(g["feasible"], score, score - 1e3 * np.abs(score).max() - 1.0)
    out = []
    for band in np.array_split(np.arange(alphas.size), max(starts, 1)):
        sub = score[band]
        i, j = np.unravel_index(np.argmax(sub), sub.shape)
        a, f = A[band][i, j], F[band][i, j]
        t0 = score[band][i, j] / (1.0 if model.bounds.objective == "ratio" else scales.torque_Nm)
        out.append(
            [
                a / pb.ALPHA_REF_rad,
                f / pb.F_REF_hz,
                float(g["field_amplitude_T"][band][i, j]) / scales.field_T,
                float(t0),
            ]
        )
    return out


_SOLVERS: dict[tuple, tuple] = {}
_CACHE_SIZE = 32


def build_solver(model: DesignModel, scales: pb.Scales, relaxed: bool = False):
    """The IPOPT solver of the (optionally relaxed) problem and its constraint metadata.

    Building the CasADi graph and the IPOPT instance costs tens of milliseconds, several times
    more than the solve; a solver is therefore kept for the model it was built for (the same
    :class:`Constants` object and options), so re-solves — starts, sweeps, benchmarks — reuse it.
    """
    key = (
        id(model.constants),
        id(model.tissues),
        model.limits,
        model.requirements,
        model.bounds.objective,
        scales,
        relaxed,
    )
    hit = _SOLVERS.get(key)
    if hit is not None and hit[0] is model.constants and hit[1] is model.tissues:
        return hit[2], hit[3]
    solver, info = _build(model, scales, relaxed)
    if len(_SOLVERS) >= _CACHE_SIZE:
        _SOLVERS.pop(next(iter(_SOLVERS)))
    _SOLVERS[key] = (model.constants, model.tissues, solver, info)
    return solver, info


def _build(model: DesignModel, scales: pb.Scales, relaxed: bool):
    x = ca.SX.sym("x", 4)
    s = ca.SX.sym("s", 3) if relaxed else None
    obj, rows, info = pb.expressions(x, model, scales, relax=s)
    z = ca.vertcat(x, s) if s is not None else x
    nlp = {"x": z, "f": obj, "g": ca.vertcat(*rows)}
    return ca.nlpsol("spiralcap_design", "ipopt", nlp, _IPOPT_OPTIONS), info


def optimize_design(model: DesignModel) -> OptimizationResult:
    """Maximise the worst-case margin (or safety factor) of ``model``; see the module notes."""
    t0 = time.perf_counter()
    model = prepare(model)
    scales = scales_for(model)
    solver, info = build_solver(model, scales)
    lo, hi = pb.variable_bounds(model, scales)
    best = None
    iterations = 0
    starts = initial_points(model, scales, model.bounds.starts)
    for x0 in starts:
        sol = solver(x0=x0, lbx=lo, ubx=hi, lbg=-np.inf, ubg=0.0)
        st = solver.stats()
        iterations += int(st.get("iter_count", 0))
        if st["return_status"] in _SUCCESS and (best is None or float(sol["f"]) < best[0]):
            best = (float(sol["f"]), sol, st["return_status"])
    status_text = best[2] if best else solver.stats()["return_status"]
    if best is None:
        return _infeasible(model, scales, starts, iterations, t0, status_text)
    sol = best[1]
    xs = np.asarray(sol["x"]).ravel()
    alpha, f = xs[0] * pb.ALPHA_REF_rad, xs[1] * pb.F_REF_hz
    ev = evaluate(model, alpha, f)
    if not ev.feasible:
        return _infeasible(model, scales, starts, iterations, t0, status_text, ev)
    binding = _binding(model, scales, info, sol, xs)
    return _result(
        model,
        "optimal",
        ev,
        binding,
        (),
        status_text,
        iterations,
        len(starts),
        t0,
        "optimal: every requirement met inside every limit",
    )


def _binding(model, scales, info, sol, xs) -> tuple[BindingLimit, ...]:
    """Active constraints and bounds with their multipliers in engineering units."""
    lam_g = np.asarray(sol["lam_g"]).ravel()
    g = np.asarray(sol["g"]).ravel()
    obj_scale = 1.0 if model.bounds.objective == "ratio" else scales.torque_Nm
    out = []
    for row, lam, gi in zip(info, lam_g, g):
        if row.kind == "margin" or gi < -1e-6 or abs(lam) < 1e-9:
            continue
        allowed = row.allowed
        if row.name == "field_exposure":
            allowed = pb.exposure_allowed_T(model, xs[1] * pb.F_REF_hz)
        value = allowed * (1.0 + gi) if row.kind == "limit" else allowed
        out.append(
            BindingLimit(
                row.name,
                row.key,
                row.unit,
                float(value),
                float(allowed),
                float(row.sign * lam * obj_scale / allowed),
                row.sign,
            )
        )
    lam_x = np.asarray(sol["lam_x"]).ravel()
    lo, hi = pb.variable_bounds(model, scales)
    for i, (name, key_lo, key_hi, unit, ref) in enumerate(
        (
            (
                "helical_angle",
                "optimize.helical_angle_min_deg",
                "optimize.helical_angle_max_deg",
                "rad",
                pb.ALPHA_REF_rad,
            ),
            (
                "frequency",
                "optimize.frequency_min_hz",
                "optimize.frequency_max_hz",
                "Hz",
                pb.F_REF_hz,
            ),
        )
    ):
        if abs(lam_x[i]) < 1e-9:
            continue
        at_hi = abs(xs[i] - hi[i]) < abs(xs[i] - lo[i])
        bound = (hi if at_hi else lo)[i] * ref
        out.append(
            BindingLimit(
                f"{name}_{'max' if at_hi else 'min'}",
                key_hi if at_hi else key_lo,
                unit,
                float(xs[i] * ref),
                float(bound),
                float(lam_x[i] * obj_scale / ref),
                1.0 if at_hi else -1.0,
            )
        )
    return tuple(out)


def _infeasible(model, scales, starts, iterations, t0, status_text, ev=None):
    """Solve the relaxed problem and report which requirement is out of reach, by how much."""
    solver, _ = build_solver(model, scales, relaxed=True)
    lo, hi = pb.variable_bounds(model, scales)
    best = None
    for x0 in starts:
        x0 = [*x0[:3], 0.0, 1.0, 1.0, 1.0]
        sol = solver(
            x0=x0,
            lbx=[*lo[:3], 0.0, 0.0, 0.0, 0.0],
            ubx=[*hi[:3], 0.0, np.inf, np.inf, np.inf],
            lbg=-np.inf,
            ubg=0.0,
        )
        iterations += int(solver.stats().get("iter_count", 0))
        if best is None or float(sol["f"]) < best[0]:
            best = (float(sol["f"]), sol)
    assert best is not None  # at least one start was solved
    xs = np.asarray(best[1]["x"]).ravel()
    alpha, f = xs[0] * pb.ALPHA_REF_rad, xs[1] * pb.F_REF_hz
    ev = evaluate(model, alpha, f)
    shortfalls = tuple(
        Shortfall(c.name, c.key, c.unit, c.allowed, c.value) for c in ev.failed() if c.sense == ">="
    )
    if not shortfalls:  # the relaxed optimum meets everything: IPOPT failed for another reason
        shortfalls = (Shortfall("solver", "optimize.starts", "", 0.0, 0.0),)
    names = ", ".join(s.key for s in shortfalls)
    return _result(
        model,
        "infeasible",
        ev,
        (),
        shortfalls,
        status_text,
        iterations,
        len(starts),
        t0,
        f"infeasible: no design inside the limits meets {names}",
    )


def _result(
    model, status, ev, binding, shortfalls, solver_status, iterations, starts, t0, message
) -> OptimizationResult:
    allocations = []
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
        headings=tuple(_three(h) for h in model.headings),
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
    )


def with_operating_point(model: DesignModel, result: OptimizationResult) -> DesignModel:
    """The model moved to the optimum's helical angle and frequency."""
    spiral = replace(model.capsule.spiral, helical_angle_rad=result.helical_angle_rad)
    return replace(
        model, capsule=replace(model.capsule, spiral=spiral), frequency_hz=result.frequency_hz
    )
