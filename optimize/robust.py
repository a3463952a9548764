"""The design NLP over tissue scenarios: a CVaR objective and a step-out probability constraint.

``optimize.objective = "margin_p05"`` maximises the lower 5 % tail of the worst-case margin over
``S`` tissue scenarios drawn from the design's uncertainty (:mod:`optimize.uncertainty`, scrambled
Sobol' points, so the tail is sampled evenly). The 5th percentile itself (value-at-risk) is a
non-smooth, non-convex function of the scenario margins; its Rockafellar-Uryasev (2000) CVaR
bound is smooth in epigraph form and is what IPOPT maximises:

    CVaR_β(m) = max over η of  η − (1/(β S)) Σ_s u_s,   u_s >= η − m_s(x),  u_s >= 0,

with ``β = 0.05``; at the optimum ``η`` is the β-quantile (the in-sample p05) of the scenario
margins, and CVaR <= p05, so the claim is conservative. ``m_s`` is the worst over the design's
tissue sets for scenario s (one ``u_s`` per scenario, one row per set).

``requirements.max_stepout_probability = p`` adds, for any objective, ``CVaR_p(m) >= 0``
(Nemirovski & Shapiro 2006: the convex conservative approximation of the chance constraint
``P(m < 0) <= p``), with its own ``η'`` and ``v_s``.

Scenario count: the empirical CDF at the 5th percentile has standard deviation
``sqrt(β(1 − β)/S)`` (binomial); ``S = 1024`` (a power of two: a balanced Sobol' block) keeps it
at 0.7 percentage points for pseudo-random scenarios and below that for Sobol' points, with 51
scenarios in the tail, while the NLP stays small (S + 5 variables; ~2 s). The quantile's own
error is that CDF error divided by the density at p05: where the margin's spread is large
against its p05 (a heavy lower tail), more scenarios are needed, and the command's
out-of-sample check says so. The scenario margins enter the NLP as one vector expression: the
tissue parameters are CasADi column vectors (:class:`optimize.uncertainty.TissueArrays`).

The rest of the NLP — limits, requirements, the nominal worst-case margin ``t >= 0`` — is
:func:`optimize.problem.expressions` unchanged.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import Any

import casadi as ca
import numpy as np

from optimize import physics as ph
from optimize import problem as pb
from optimize import solve as sv
from optimize import uncertainty as uq
from optimize.evaluate import evaluate
from optimize.system import DesignModel, prepare

BETA = 0.05
DEFAULT_SCENARIOS = 1024


@dataclass(frozen=True)
class RobustResult:
    """The robust optimum and what it claims on its own scenarios (in-sample), SI.

    ``optimization`` is the usual result (evaluated with the nominal tissue sets).
    ``margin_p05_Nm``: 5th percentile of the scenario margins at the optimum (in-sample claim);
    ``cvar05_Nm``: mean of the worst 5 %; ``stepout_probability``: share of scenarios with a
    negative margin. ``scenario_u``: the latent uniforms of the scenarios (to reproduce them).
    """

    optimization: Any
    objective: str
    scenarios: int
    seed: int
    beta: float
    max_stepout_probability: float | None
    margin_p05_Nm: float
    cvar05_Nm: float
    stepout_probability: float
    scenario_margins_Nm: np.ndarray
    scenario_u: np.ndarray


def cvar_rows(margins: list[Any], eta: Any, u: Any, beta: float) -> tuple[Any, list[Any]]:
    """Rockafellar-Uryasev epigraph: (CVaR_β expression, rows ``<= 0``).

    ``margins``: one (S x 1) expression per tissue set (scenario margins, any scale);
    ``eta``: scalar variable; ``u``: S variables bounded below by 0.
    """
    n = u.shape[0]
    rows = [eta - m - u for m in margins]
    return eta - ca.sum1(u) / (beta * n), rows


def scenario_tissues(
    tissues: tuple, unc: uq.TissueUncertainty, scenarios: int, seed: int
) -> tuple[np.ndarray, tuple]:
    """Latent uniforms (S x d, Sobol') and the perturbed tissue sets (numpy arrays)."""
    u = uq.latent_uniforms(len(unc.factors()), 0, scenarios, seed, "sobol")
    return u, uq.perturbed_tissues(tissues, unc, u)


def _as_dm(arrays: tuple) -> tuple:
    out = []
    for t in arrays:
        vals = {
            f: ca.DM(np.broadcast_to(np.asarray(getattr(t, f), float), (n_of(arrays),)).copy())
            for f in (*uq.VISCOELASTIC, "lumen_diameter_m", "wall_thickness_m")
        }
        mu = np.broadcast_to(np.asarray(t.friction_coefficient, float), (n_of(arrays),)).copy()
        out.append(uq.TissueArrays(**vals, friction_coefficient=ca.DM(mu), name=t.name))
    return tuple(out)


def n_of(arrays: tuple) -> int:
    """Number of scenarios in a tuple of TissueArrays."""
    return int(np.asarray(arrays[0].E1_Pa).size)


def scenario_margins(alpha: Any, f: Any, field: Any, model: DesignModel, arrays: tuple) -> list:
    """Per tissue set, the margin of every scenario (numpy arrays or CasADi vectors), N·m."""
    c = model.constants
    avail = ph.available_torque_Nm(field, c)
    return [
        avail - (r + t) for r, t in ph.required_torques_Nm(alpha, f, c, arrays, model.requirements)
    ]


def optimize_robust(
    model: DesignModel,
    unc: uq.TissueUncertainty,
    *,
    objective: str | None = None,
    max_stepout_probability: float | None = None,
    scenarios: int = DEFAULT_SCENARIOS,
    seed: int = 0,
    beta: float = BETA,
) -> RobustResult:
    """Solve the design NLP with the CVaR objective and/or the step-out constraint.

    ``objective``: ``"margin_p05"`` (CVaR_β of the margin), ``"margin"`` or ``"ratio"`` (the
    deterministic objective, with the step-out constraint). Defaults to the model's.
    """
    t0 = time.perf_counter()
    model = prepare(model)
    objective = objective or model.bounds.objective
    if not unc.active:
        from spiralcap.errors import InputError

        raise InputError("tissue.uncertainty", "none", "an uncertain input for robust design")
    u_lat, arrays = scenario_tissues(model.tissues, unc, scenarios, seed)
    det_model = replace(model, bounds=replace(model.bounds, objective="margin"))
    base = objective if objective in ("margin", "ratio") else "margin"
    scales = sv.scales_for(det_model)
    x = ca.SX.sym("x", 4)
    obj, rows, info = pb.expressions(
        x, replace(det_model, bounds=replace(model.bounds, objective=base)), scales
    )
    alpha, f, field = x[0] * pb.ALPHA_REF_rad, x[1] * pb.F_REF_hz, x[2] * scales.field_T
    sym = [m / scales.torque_Nm for m in scenario_margins(alpha, f, field, model, _as_dm(arrays))]
    lo_extra: list[float] = []
    hi_extra: list[float] = []
    z = [x]
    if objective == "margin_p05":
        eta, u = ca.SX.sym("eta"), ca.SX.sym("u", scenarios)
        cvar, r = cvar_rows(sym, eta, u, beta)
        obj = -cvar
        rows += r
        z += [eta, u]
        lo_extra += [-np.inf] + [0.0] * scenarios
        hi_extra += [np.inf] * (scenarios + 1)
    if max_stepout_probability is not None:
        eta2, v = ca.SX.sym("eta2"), ca.SX.sym("v", scenarios)
        cvar_p, r = cvar_rows(sym, eta2, v, max_stepout_probability)
        rows += [*r, -cvar_p]
        z += [eta2, v]
        lo_extra += [-np.inf] + [0.0] * scenarios
        hi_extra += [np.inf] * (scenarios + 1)
    solver = ca.nlpsol(
        "spiralcap_robust",
        "ipopt",
        {"x": ca.vertcat(*z), "f": obj, "g": ca.vertcat(*rows)},
        {**sv._IPOPT_OPTIONS, "ipopt.mu_init": 1e-1},  # type: ignore[dict-item]
    )
    lo, hi = pb.variable_bounds(model, scales)
    if objective == "margin_p05":
        lo[3] = 0.0  # t: the nominal worst-case margin stays >= 0 (a requirement)
    lbx, ubx = [*lo, *lo_extra], [*hi, *hi_extra]
    best, iterations = None, 0
    starts = sv.initial_points(det_model, scales, model.bounds.starts)
    for x0 in starts:
        z0 = _start(x0, model, scales, arrays, objective, max_stepout_probability, beta)
        sol = solver(x0=z0, lbx=lbx, ubx=ubx, lbg=-np.inf, ubg=0.0)
        st = solver.stats()
        iterations += int(st.get("iter_count", 0))
        if st["return_status"] in sv._SUCCESS and (best is None or float(sol["f"]) < best[0]):
            best = (float(sol["f"]), sol, st["return_status"])
    if best is None:
        res = _infeasible(model, unc, objective, max_stepout_probability, scenarios, seed, t0)
        if res is None:
            res = sv._infeasible(
                det_model, scales, starts, iterations, t0, solver.stats()["return_status"]
            )
    else:
        xs = np.asarray(best[1]["x"]).ravel()[:4]
        a_opt, f_opt = xs[0] * pb.ALPHA_REF_rad, xs[1] * pb.F_REF_hz
        ev = evaluate(det_model, a_opt, f_opt)
        m_in = _in_sample(model, unc, u_lat, a_opt, f_opt)
        status = "optimal" if ev.feasible else "infeasible"
        if status == "optimal" and max_stepout_probability is not None:
            status = (
                "optimal" if np.mean(m_in < 0) <= max_stepout_probability + 1e-9 else "infeasible"
            )
        binding = sv._binding(det_model, scales, info, best[1], xs) if status == "optimal" else ()
        res = sv._result(
            replace(model, bounds=replace(model.bounds, objective=objective)),
            status,
            ev,
            binding,
            (),
            best[2],
            iterations,
            len(starts),
            t0,
            f"{status}: {objective} over {scenarios} tissue scenarios"
            + (f", P(step-out) <= {max_stepout_probability:g}" if max_stepout_probability else ""),
        )
    m_in = _in_sample(model, unc, u_lat, res.helical_angle_rad, res.frequency_hz)
    return RobustResult(
        optimization=res,
        objective=objective,
        scenarios=scenarios,
        seed=seed,
        beta=beta,
        max_stepout_probability=max_stepout_probability,
        margin_p05_Nm=float(np.percentile(m_in, 100 * beta)),
        cvar05_Nm=float(np.mean(np.sort(m_in)[: max(int(np.ceil(beta * scenarios)), 1)])),
        stepout_probability=float(np.mean(m_in < 0)),
        scenario_margins_Nm=m_in,
        scenario_u=u_lat,
    )


def _in_sample(model, unc, u_lat, alpha, f) -> np.ndarray:
    return uq.margin_problem(model, unc, alpha, f).margins_Nm(u_lat)


def _start(x0, model, scales, arrays, objective, p_max, beta) -> list[float]:
    """x0 extended with η = β-quantile of the scenario margins at x0 and u = (η − m)+."""
    alpha, f, field = x0[0] * pb.ALPHA_REF_rad, x0[1] * pb.F_REF_hz, x0[2] * scales.field_T
    m = (
        np.min(np.stack(scenario_margins(alpha, f, field, model, arrays)), axis=0)
        / scales.torque_Nm
    )
    z = list(x0)
    if objective == "margin_p05":
        z[3] = max(z[3], 0.0)
        eta = float(np.quantile(m, beta))
        z += [eta, *np.maximum(eta - m, 0.0)]
    if p_max is not None:
        eta = float(np.quantile(m, p_max))
        z += [eta, *np.maximum(eta - m, 0.0)]
    return z


def _infeasible(model, unc, objective, p_max, scenarios, seed, t0) -> Any:
    """The step-out constraint cannot hold: the design with the largest CVaR_p, as a shortfall.

    Returns None when the constraint is not the cause (no ``p_max``, or its CVaR can be >= 0).
    """
    from optimize.result import Shortfall

    if p_max is None:
        return None
    best = optimize_robust(
        model, unc, objective="margin_p05", scenarios=scenarios, seed=seed, beta=p_max
    )
    o = best.optimization
    if o.status != "optimal":
        return None
    k = max(int(np.ceil(p_max * scenarios)), 1)
    cvar = float(np.mean(np.sort(best.scenario_margins_Nm)[:k]))
    if cvar >= 0:
        return None
    short = Shortfall(
        "stepout_probability_cvar", "requirements.max_stepout_probability", "N·m", 0.0, cvar
    )
    return sv._result(
        replace(model, bounds=replace(model.bounds, objective=objective)),
        "infeasible",
        o.evaluation,
        (),
        (short,),
        "Infeasible_Problem_Detected",
        o.iterations,
        o.starts,
        t0,
        f"infeasible: no design inside the limits keeps the mean margin of the worst "
        f"{100 * p_max:g} % of the {scenarios} scenarios >= 0 (the CVaR form of "
        f"requirements.max_stepout_probability); the best design shown reaches {cvar * 1e3:.3g} "
        f"mN·m (its P(step-out) {100 * best.stepout_probability:.3g} %)",
    )
