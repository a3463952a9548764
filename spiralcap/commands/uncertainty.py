"""``spiralcap uncertainty``: step-out probability and margin distribution over uncertain tissue.

The design's ``[tissue.uncertainty]`` table says what is uncertain; the command samples it
(:mod:`optimize.uncertainty`), evaluates the worst-case margin of every sample at the operating
point, and reports the step-out probability, percentiles and Sobol indices (SALib). The samples
run in chunks here, in ``--workers`` processes or on a Dask cluster (``--dask``): same seed, same
numbers bit for bit.
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import dataclass
from typing import Any

from spiralcap.commands._common import add_design_arguments, design_from_args, print_json
from spiralcap.errors import InputError

DEFAULT_SAMPLES = 1 << 16
DEFAULT_SOBOL_BASE = 1 << 12


def add_execution_arguments(parser: argparse.ArgumentParser) -> None:
    """``--workers N | --dask ADDRESS`` (shared with ``sweep``)."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument(
        "--workers", type=int, default=1, metavar="N", help="local worker processes (default 1)"
    )
    group.add_argument(
        "--dask",
        metavar="ADDRESS",
        help="run the chunks on a running Dask scheduler, e.g. tcp://HOST:8786 "
        '(optional extra: pip install ".[dask]")',
    )


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_arguments(parser)
    parser.add_argument(
        "--samples",
        type=int,
        default=DEFAULT_SAMPLES,
        metavar="N",
        help=f"tissue samples (default {DEFAULT_SAMPLES})",
    )
    parser.add_argument("--seed", type=int, default=0, metavar="S", help="sampling seed")
    parser.add_argument(
        "--method",
        choices=("sobol", "halton", "random"),
        default="sobol",
        help="scrambled quasi-random sequence or pseudo-random draws (default sobol)",
    )
    parser.add_argument(
        "--sobol-samples",
        type=int,
        default=DEFAULT_SOBOL_BASE,
        metavar="N",
        help=f"base samples of the Sobol-index estimate, a power of 2; 0 skips it "
        f"(default {DEFAULT_SOBOL_BASE})",
    )
    parser.add_argument("--plot", metavar="FILE.png", help="margin distribution and Sobol bars")
    add_execution_arguments(parser)


@dataclass(frozen=True)
class Study:
    """An uncertainty study and where/how long it ran."""

    result: Any  # optimize.uncertainty.UncertaintyResult
    uncertainty: Any  # optimize.uncertainty.TissueUncertainty
    where: str
    elapsed_s: float


def study(
    design: Any,
    *,
    samples: int = DEFAULT_SAMPLES,
    seed: int = 0,
    method: str = "sobol",
    sobol_base: int = DEFAULT_SOBOL_BASE,
    workers: int = 1,
    dask: str | None = None,
    progress: Any = None,
    model: Any = None,
) -> Study:
    """Sample the design's tissue uncertainty and summarise the worst-case margin.

    Raises
    ------
    InputError
        No uncertain input, ``samples`` < 1, ``sobol_base`` not 0 or a power of two,
        ``workers`` < 1, an unreachable or missing Dask.
    """
    from optimize import uncertainty as uq
    from spiralcap.assemble import build_model
    from spiralcap.assemble.tissue import build_uncertainty
    from spiralcap.parallel import check_workers, map_tasks, where

    uq.check_samples(samples)
    uq.check_seed(seed)
    check_workers(workers)
    if sobol_base != 0 and (sobol_base < 2 or sobol_base & (sobol_base - 1)):
        raise InputError("--sobol-samples", sobol_base, "0 or a power of 2 >= 2")
    unc = build_uncertainty(design)
    if not unc.active:
        raise InputError(
            "tissue.uncertainty",
            "none",
            "at least one sigma > 0 or covariance_from (e.g. --set "
            "tissue.uncertainty.scale_sigma_log=0.3)",
        )
    problem = uq.margin_problem(model if model is not None else build_model(design), unc)
    t0 = time.perf_counter()
    # tasks of 8 chunks (2^18 samples, ~0.1 s): each chunk's samples are fixed by its index
    # range and the seed, so the grouping changes nothing in the result
    tasks = [(problem, b, seed, method) for b in uq.batches(samples)]
    parts = map_tasks(uq.batch_margins, tasks, workers=workers, dask=dask, progress=progress)
    import numpy as np

    margins = np.concatenate(parts)
    sob = uq.sobol_indices(problem, sobol_base, seed) if sobol_base else None
    result = uq.summarise(problem, margins, seed, method, sob)
    return Study(result, unc, where(workers, dask), time.perf_counter() - t0)


def study_to_dict(st: Study, design_source: str = "") -> dict[str, Any]:
    """JSON-ready mapping (SI units in every key)."""
    r = st.result
    out: dict[str, Any] = {
        "design": design_source,
        "samples": r.samples,
        "seed": r.seed,
        "method": r.method,
        "ran_on": st.where,
        "elapsed_s": st.elapsed_s,
        "uncertain_inputs": list(dict.fromkeys(g for _, g in st.uncertainty.factors())),
        "nominal_margin_Nm": r.nominal_margin_Nm,
        "available_torque_Nm": r.available_torque_Nm,
        "stepout_probability": r.stepout_probability,
        "stepout_probability_ci95": list(r.stepout_ci95),
        "stepout_probability_interval": "Wilson score (binomial; conservative for quasi-random)",
        "margin_percentiles_Nm": r.margin_percentiles_Nm,
        "margin_mean_Nm": r.margin_mean_Nm,
        "margin_std_Nm": r.margin_std_Nm,
        "speed_percentiles_m_s": r.speed_percentiles_m_s,
        "speed_note": "the design's speed where the margin holds, 0 where it steps out",
    }
    if r.sobol is not None:
        s = r.sobol
        out["sobol"] = {
            "estimator": f"SALib Saltelli/Jansen, {s.base_samples} base samples",
            "indices": {
                name: {
                    "first_order": s.first_order[i],
                    "first_order_ci95_halfwidth": s.first_order_conf[i],
                    "total": s.total[i],
                    "total_ci95_halfwidth": s.total_conf[i],
                }
                for i, name in enumerate(s.inputs)
            },
        }
    return out


def format_study(st: Study, design_source: str = "") -> str:
    """Readable summary of a :class:`Study`."""
    from spiralcap.commands._common import format_table

    r = st.result
    lo, hi = r.stepout_ci95
    mp, sp = r.margin_percentiles_Nm, r.speed_percentiles_m_s
    lines = [
        f"design {design_source}: {r.samples} tissue samples ({r.method}, seed {r.seed}) on "
        f"{st.where}, {st.elapsed_s:.3g} s",
        "uncertain inputs    " + ", ".join(dict.fromkeys(g for _, g in st.uncertainty.factors())),
        f"nominal margin      {r.nominal_margin_Nm * 1e3:.4g} mN·m "
        f"(magnetic torque {r.available_torque_Nm * 1e3:.4g} mN·m)",
        f"step-out prob.      {100 * r.stepout_probability:.4g} % "
        f"(95 % interval {100 * lo:.3g}-{100 * hi:.3g} %)",
        "margin, mN·m        " + "  ".join(f"{k} {v * 1e3:.4g}" for k, v in mp.items()),
        "speed, mm/s         "
        + "  ".join(f"{k} {v * 1e3:.4g}" for k, v in sp.items())
        + "  (0 where it steps out)",
    ]
    if r.sobol is not None:
        s = r.sobol
        lines += [
            "",
            f"Sobol indices of the margin (SALib, {s.base_samples} base samples; ± 95 %):",
            format_table(
                ["input", "first_order", "±", "total", "± "],
                [
                    [n, s.first_order[i], s.first_order_conf[i], s.total[i], s.total_conf[i]]
                    for i, n in enumerate(s.inputs)
                ],
            ),
        ]
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    from optimize.uncertainty import check_samples, check_seed
    from spiralcap.commands.torque import check_plot_path
    from spiralcap.parallel import check_workers

    check_samples(args.samples)
    check_seed(args.seed)
    check_workers(args.workers)
    if args.plot:
        check_plot_path(args.plot)
    design = design_from_args(args)
    progress = _progress if sys.stderr.isatty() and not args.json else None
    st = study(
        design,
        samples=args.samples,
        seed=args.seed,
        method=args.method,
        sobol_base=args.sobol_samples,
        workers=args.workers,
        dask=args.dask,
        progress=progress,
    )
    if args.plot:
        from spiralcap.figures.uncertainty import save_uncertainty_figure

        save_uncertainty_figure(args.plot, st.result)
    if args.json:
        print_json(study_to_dict(st, design.source))
    else:
        print(format_study(st, design.source))
        if args.plot:
            print(f"wrote {args.plot}")
    return 0


def _progress(done: int, total: int) -> None:
    sys.stderr.write(f"\rchunks {done}/{total}")
    if done == total:
        sys.stderr.write("\n")
    sys.stderr.flush()


# --- robust optimum: `spiralcap optimize` with objective margin_p05 or max_stepout_probability --

OUT_OF_SAMPLE = 1 << 16


def wants_robust(design: Any) -> bool:
    """Whether ``spiralcap optimize`` must solve over tissue scenarios (optimize/robust.py)."""
    return (
        design["optimize.objective"] == "margin_p05"
        or design.get("requirements.max_stepout_probability") is not None
    )


@dataclass(frozen=True)
class RobustCheck:
    """The robust optimum, its out-of-sample check, and the deterministic optimum's."""

    robust: Any  # optimize.robust.RobustResult
    out_of_sample: Any  # UncertaintyResult at the robust optimum, fresh seed
    deterministic: Any  # OptimizationResult with objective "margin"
    deterministic_out_of_sample: Any  # UncertaintyResult at the deterministic optimum
    fresh_seed: int


def robust_solve(design: Any, model: Any = None) -> Any:
    """The robust NLP of ``design`` (optimize.robust.RobustResult), without the fresh check."""
    from optimize import robust as rb
    from spiralcap.assemble import build_model
    from spiralcap.assemble.tissue import build_uncertainty

    unc = build_uncertainty(design)
    if not unc.active:
        raise InputError(
            "optimize.objective",
            design["optimize.objective"],
            "margin_p05 and requirements.max_stepout_probability need [tissue.uncertainty] "
            "(e.g. --set tissue.uncertainty.scale_sigma_log=0.3)",
        )
    return rb.optimize_robust(
        model if model is not None else build_model(design),
        unc,
        max_stepout_probability=design.get("requirements.max_stepout_probability"),
        scenarios=int(design["optimize.scenarios"]),
        seed=int(design["optimize.scenario_seed"]),
    )


def robust_optimum(design: Any, samples: int = OUT_OF_SAMPLE) -> RobustCheck:
    """Solve the robust NLP, then check it (and the deterministic optimum) on fresh samples."""
    from dataclasses import replace

    from optimize import optimize_design
    from optimize import uncertainty as uq
    from spiralcap.assemble import build_model
    from spiralcap.assemble.tissue import build_uncertainty

    model = build_model(design)
    unc = build_uncertainty(design)
    res = robust_solve(design, model)
    seed = res.seed
    fresh = seed + 1_000_003  # a different scrambling: samples the optimiser never saw

    def check(alpha: float, f: float) -> Any:
        p = uq.margin_problem(model, unc, alpha, f)
        return uq.summarise(p, uq.run_local(p, samples, fresh), fresh, "sobol")

    o = res.optimization
    det = optimize_design(replace(model, bounds=replace(model.bounds, objective="margin")))
    return RobustCheck(
        res,
        check(o.helical_angle_rad, o.frequency_hz),
        det,
        check(det.helical_angle_rad, det.frequency_hz),
        fresh,
    )


def robust_to_dict(rc: RobustCheck) -> dict[str, Any]:
    """The robust part of ``optimize --json`` (SI units in the keys)."""
    r, oos, d_oos = rc.robust, rc.out_of_sample, rc.deterministic_out_of_sample
    return {
        "objective": r.objective,
        "scenarios": r.scenarios,
        "scenario_seed": r.seed,
        "beta": r.beta,
        "max_stepout_probability": r.max_stepout_probability,
        "in_sample": {
            "margin_p05_Nm": r.margin_p05_Nm,
            "cvar05_Nm": r.cvar05_Nm,
            "stepout_probability": r.stepout_probability,
        },
        "out_of_sample": {
            "samples": oos.samples,
            "seed": rc.fresh_seed,
            "margin_p05_Nm": oos.margin_percentiles_Nm["p05"],
            "stepout_probability": oos.stepout_probability,
            "stepout_probability_ci95": list(oos.stepout_ci95),
            "p05_relative_to_claim": oos.margin_percentiles_Nm["p05"] / r.margin_p05_Nm - 1.0
            if r.margin_p05_Nm
            else None,
        },
        "deterministic_optimum": {
            "status": rc.deterministic.status,
            "helical_angle_deg": rc.deterministic.helical_angle_deg,
            "frequency_hz": rc.deterministic.frequency_hz,
            "margin_Nm": rc.deterministic.margin_Nm,
            "out_of_sample_margin_p05_Nm": d_oos.margin_percentiles_Nm["p05"],
            "out_of_sample_stepout_probability": d_oos.stepout_probability,
        },
    }


def format_robust(rc: RobustCheck) -> str:
    """Text lines for the robust part of ``spiralcap optimize``."""
    r, oos, d_oos = rc.robust, rc.out_of_sample, rc.deterministic_out_of_sample
    d = robust_to_dict(rc)["out_of_sample"]
    rel = d["p05_relative_to_claim"]
    cons = (
        f", P(step-out) <= {r.max_stepout_probability:g} (CVaR)"
        if r.max_stepout_probability
        else ""
    )
    return "\n".join(
        [
            f"tissue scenarios    {r.scenarios} (Sobol', seed {r.seed}); objective "
            f"{r.objective}{cons}",
            f"in-sample           margin p05 {r.margin_p05_Nm * 1e3:.4g} mN·m, CVaR05 "
            f"{r.cvar05_Nm * 1e3:.4g} mN·m, P(step-out) {100 * r.stepout_probability:.3g} %",
            f"out-of-sample       margin p05 {oos.margin_percentiles_Nm['p05'] * 1e3:.4g} mN·m"
            + (f" ({100 * rel:+.2g} % vs claim)" if rel is not None else "")
            + f", P(step-out) {100 * oos.stepout_probability:.3g} % "
            f"({oos.samples} fresh samples, seed {rc.fresh_seed})",
            f"deterministic opt.  {rc.deterministic.helical_angle_deg:.4g} deg, "
            f"{rc.deterministic.frequency_hz:.4g} Hz: out-of-sample margin p05 "
            f"{d_oos.margin_percentiles_Nm['p05'] * 1e3:.4g} mN·m, P(step-out) "
            f"{100 * d_oos.stepout_probability:.3g} %",
        ]
    )


def run_robust(args: argparse.Namespace, design: Any) -> int:
    """``spiralcap optimize`` for a robust design (called from commands/optimize.py)."""
    from spiralcap.commands.optimize import EXIT_INFEASIBLE, format_result
    from spiralcap.serialize import optimization_to_dict

    rc = robust_optimum(design)
    res = rc.robust.optimization
    if args.json:
        print_json(
            {"design": design.source, **optimization_to_dict(res), **{"robust": robust_to_dict(rc)}}
        )
    else:
        print(format_result(res))
        print(format_robust(rc))
    return 0 if res.status == "optimal" else EXIT_INFEASIBLE
