"""The robust optimum of a design file: tissue scenarios in, an out-of-sample check out.

``optimize.objective = "margin_p05"`` and ``requirements.max_failure_probability`` are solved by
the one design NLP (:func:`optimize.optimize_design`) on a model that carries tissue scenarios
(:func:`optimize.robust.with_scenarios`, from the design's ``[tissue.uncertainty]``,
``optimize.scenarios`` and ``optimize.scenario_seed``). :func:`robust_optimum` adds what the
optimiser claims on its own scenarios and checks it on fresh samples it never saw, for the
robust optimum and for the deterministic (nominal-margin) optimum alike.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

from spiralcap.core.errors import InputError

#: Fresh samples of the out-of-sample check: 2^16 keep the p05's sampling error ~0.1 % of it.
OUT_OF_SAMPLE = 1 << 16
#: Offset of the fresh seed from the scenario seed (another scrambling of the sequence).
FRESH_SEED_OFFSET = 1_000_003


def wants_robust(design: Any) -> bool:
    """Whether the design's optimum must be judged over tissue scenarios."""
    return (
        design["optimize.objective"] == "margin_p05"
        or design.get("requirements.max_failure_probability") is not None
    )


def robust_model(design: Any, model: Any = None) -> Any:
    """The design's model with its tissue scenarios (``model``: the built model, if at hand).

    Raises
    ------
    InputError
        Naming ``optimize.objective`` when the design has no uncertain tissue input.
    """
    from optimize.robust import with_scenarios
    from spiralcap.assemble import build_model
    from spiralcap.assemble.tissue import build_uncertainty

    unc = build_uncertainty(design)
    if not unc.active:
        key = "optimize.objective"
        if design["optimize.objective"] != "margin_p05":
            key = "requirements.max_failure_probability"
        raise InputError(
            key,
            design[key],
            "a design with tissue uncertainty: margin_p05 and max_failure_probability need "
            "[tissue.uncertainty] (e.g. --set tissue.uncertainty.scale_sigma_log=0.3)",
        )
    return with_scenarios(
        model if model is not None else build_model(design),
        unc,
        scenarios=int(design["optimize.scenarios"]),
        seed=int(design["optimize.scenario_seed"]),
        max_failure_probability=design.get("requirements.max_failure_probability"),
    )


def optimization_model(design: Any, model: Any = None) -> Any:
    """The model ``optimize_design`` needs: with tissue scenarios when the design asks."""
    from spiralcap.assemble import build_model

    if wants_robust(design):
        return robust_model(design, model)
    return model if model is not None else build_model(design)


@dataclass(frozen=True)
class RobustCheck:
    """The robust optimum, its in-sample claim, and fresh-sample checks of it and of the
    deterministic optimum (SI)."""

    result: Any  # optimize.OptimizationResult
    in_sample: Any  # optimize.robust.InSample
    out_of_sample: Any  # optimize.uncertainty.UncertaintyResult at the robust optimum
    deterministic: Any  # OptimizationResult, objective "margin", no scenarios
    deterministic_out_of_sample: Any  # UncertaintyResult at the deterministic optimum
    fresh_seed: int
    grip_torque_Nm: float
    objective: str
    max_failure_probability: float | None


def robust_optimum(design: Any, samples: int = OUT_OF_SAMPLE) -> RobustCheck:
    """Solve the design over its scenarios, then check it on ``samples`` fresh tissues.

    The deterministic optimum and its fresh-sample check follow (running them in a forked
    process meanwhile saved 12 % of the command: not kept, docs/architecture.md).
    """
    from optimize import optimize_design
    from optimize import robust as rb
    from spiralcap.assemble import build_model

    base = build_model(design)
    det_model = replace(base, bounds=replace(base.bounds, objective="margin"))
    fresh = int(design["optimize.scenario_seed"]) + FRESH_SEED_OFFSET

    def deterministic() -> tuple[Any, Any]:
        det = optimize_design(det_model)
        return det, _fresh(design, det, samples, fresh)

    model = robust_model(design, base)
    res = optimize_design(model)
    oos = _fresh(design, res, samples, fresh)
    if res.scenario_solve is not None and res.scenario_solve.skipped:
        det, det_oos = res, oos  # the failure row cannot bind: the deterministic optimum
    else:
        det, det_oos = deterministic()
    own = model if res.hardware is None else robust_model(*_as_built(design, res))
    return RobustCheck(
        result=res,
        in_sample=rb.in_sample(own, res),
        out_of_sample=oos,
        deterministic=det,
        deterministic_out_of_sample=det_oos,
        fresh_seed=fresh,
        grip_torque_Nm=model.scenarios.grip_torque_Nm,
        objective=model.bounds.objective,
        max_failure_probability=model.scenarios.max_failure_probability,
    )


def _as_built(design: Any, res: Any) -> tuple[Any, Any]:
    """The design (and its model) with the optimum's sized hardware, if it sized any."""
    from spiralcap.assemble import build_model

    if res.hardware is None:
        return design, None
    from spiralcap.assemble.system import hardware_design_values

    sized = design.with_values(hardware_design_values(res.hardware.discrete))
    return sized, build_model(sized)


def _fresh(design: Any, res: Any, samples: int, seed: int) -> Any:
    """The optimum's margin distribution over ``samples`` fresh tissues (its own hardware)."""
    from optimize import uncertainty as uq
    from spiralcap.assemble import build_model
    from spiralcap.assemble.tissue import build_uncertainty

    built, model = _as_built(design, res)
    p = uq.margin_problem(
        model if model is not None else build_model(built),
        build_uncertainty(design),
        res.helical_angle_rad,
        res.frequency_hz,
        field_T=res.field_amplitude_T,
    )
    return uq.summarise(p, uq.run_local(p, samples, seed), seed, "sobol")


def _failure_dict(r: Any) -> dict[str, Any]:
    """P(failure) and its parts (with Wilson intervals) of a fresh-sample check."""
    from spiralcap.uncertainty import failure_to_dict

    return failure_to_dict(r)


def robust_to_dict(rc: RobustCheck) -> dict[str, Any]:
    """The ``"robust"`` part of ``optimize --json`` (SI units in the keys)."""
    ins, oos, d_oos = rc.in_sample, rc.out_of_sample, rc.deterministic_out_of_sample
    p05 = oos.margin_percentiles_Nm["p05"]
    return {
        "objective": rc.objective,
        "scenarios": ins.scenarios,
        "scenario_seed": ins.seed,
        "beta": ins.beta,
        "grip_torque_Nm": rc.grip_torque_Nm,
        "failure_counting": "a scenario fails when it steps out or stretches some wall by less "
        "than requirements.min_wall_strain; its effective margin is the least of its torque "
        "margins and its grip margins grip_torque_Nm x (strain / min_wall_strain - 1)",
        # one type per field: present only when the design constrains it
        **(
            {}
            if rc.max_failure_probability is None
            else {"max_failure_probability": rc.max_failure_probability}
        ),
        "in_sample": {
            "margin_p05_Nm": ins.margin_p05_Nm,
            "cvar05_Nm": ins.cvar_Nm,
            "failure_probability": ins.failure_probability,
            "stepout_probability": ins.stepout_probability,
            "below_min_strain_probability": ins.below_min_strain_probability,
        },
        "out_of_sample": {
            "samples": oos.samples,
            "seed": rc.fresh_seed,
            "margin_p05_Nm": p05,
            "failure_probability": _failure_dict(oos),
            "stepout_probability": oos.stepout_probability,
            "stepout_probability_ci95": list(oos.stepout_ci95),
            **(
                {"p05_relative_to_claim": p05 / ins.margin_p05_Nm - 1.0}
                if ins.margin_p05_Nm
                else {}
            ),
        },
        "solve": scenario_solve_to_dict(rc.result.scenario_solve),
        "deterministic_optimum": {
            "status": rc.deterministic.status,
            "helical_angle_deg": rc.deterministic.helical_angle_deg,
            "frequency_hz": rc.deterministic.frequency_hz,
            "margin_Nm": rc.deterministic.margin_Nm,
            "out_of_sample_margin_p05_Nm": d_oos.margin_percentiles_Nm["p05"],
            "out_of_sample_failure_probability": d_oos.failure.value,
            "out_of_sample_stepout_probability": d_oos.stepout_probability,
            "out_of_sample_below_min_strain_probability": d_oos.below_min_strain.value,
        },
    }


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def scenario_solve_to_dict(rec: Any) -> dict[str, Any] | None:
    """How the scenarios were solved and the check over all of them
    (:class:`optimize.active_set.ScenarioSolve`), SI."""
    if rec is None:
        return None
    check = {
        "cvar05_Nm": _finite(rec.cvar_Nm),
        "failure_cvar_Nm": _finite(rec.failure_cvar_Nm),  # only with max_failure_probability
        "failure_probability": _finite(rec.failure_probability),
        "smallest_margin_outside_working_set_Nm": _finite(rec.outside_min_Nm),
        "tail_edge_in_working_set_Nm": _finite(rec.tail_edge_Nm),
    }
    return {  # a number that does not apply is left out, never null (docs/json/README.md)
        "scenarios": rec.scenarios,
        "working_set": rec.capacity,
        "rounds": rec.rounds,
        "failure_constraint_cannot_bind": rec.skipped,
        "check": {k: v for k, v in check.items() if v is not None},
    }


def format_scenario_solve(rec: Any, p: float | None) -> str:
    """One or two text lines: how the scenarios were solved and the evidence."""
    if rec is None:
        return ""
    n = rec.scenarios
    if rec.skipped:
        return (
            f"scenario solve      P(failure) <= {p:g} cannot bind: the optimum without it has "
            f"CVaR_{p:g} {rec.failure_cvar_Nm * 1e3:.4g} mN·m >= 0 and P(failure) "
            f"{100 * rec.failure_probability:.3g} % over all {n} scenarios; returned at once"
        )
    if rec.capacity >= n:
        return f"scenario solve      all {n} scenarios in one NLP ({rec.rounds} solve(s))"
    if not (math.isfinite(rec.outside_min_Nm) and math.isfinite(rec.tail_edge_Nm)):
        return (
            f"scenario solve      working set {rec.capacity} of {n} scenarios, {rec.rounds} "
            "round(s); not checked over all: no feasible optimum to check"
        )
    return (
        f"scenario solve      working set {rec.capacity} of {n} scenarios, {rec.rounds} round(s); "
        f"checked over all {n}: smallest margin outside {rec.outside_min_Nm * 1e3:.4g} mN·m "
        f">= the tail's edge inside {rec.tail_edge_Nm * 1e3:.4g} mN·m"
    )
