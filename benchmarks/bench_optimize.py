"""Benchmark: CasADi/IPOPT design solve vs scipy SLSQP with finite differences, same problem.

Run: python benchmarks/bench_optimize.py
Prints the optimum of each and the speed ratio (target: IPOPT >= 10x SLSQP; docs/optimisation.md), and the
time of a 10^5-point vectorised evaluation sweep (target about a second). Asserts nothing.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from _timing import median_time

from optimize import margin_grid, optimize_design, prepare
from optimize import solve as solve_module
from spiralcap.assemble import build_model
from spiralcap.design import load_design

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from reference_slsqp import solve_slsqp


def main() -> None:
    design = load_design()
    t_build, model = median_time(lambda: prepare(build_model(design)), 3)
    t_ipopt, res = median_time(lambda: optimize_design(model), 7)

    def cold():
        solve_module.compile_problem.cache_clear()  # rebuild the CasADi graph and IPOPT instance
        return optimize_design(model)

    t_cold, _ = median_time(cold, 5)
    t_slsqp, ref = median_time(lambda: solve_slsqp(model), 3)
    alpha, f, _, margin = ref
    print(f"model build (coils, capsule, tissue, constants): {t_build * 1e3:8.1f} ms")
    print(
        f"IPOPT  (CasADi exact derivatives): {t_ipopt * 1e3:8.1f} ms  "
        f"alpha {res.helical_angle_deg:.6f} deg  f {res.frequency_hz:.6f} Hz  "
        f"margin {res.margin_Nm * 1e3:.9f} mN·m  ({res.starts} starts, "
        f"{res.iterations} iterations; solve_time_s in JSON {res.solve_time_s:.3f})"
    )
    print(
        f"SLSQP  (finite differences)      : {t_slsqp * 1e3:8.1f} ms  "
        f"alpha {np.degrees(alpha):.6f} deg  f {f:.6f} Hz  margin {margin * 1e3:.9f} mN·m"
    )
    print(f"IPOPT cold (graph + IPOPT instance built first): {t_cold * 1e3:8.1f} ms")
    print(
        f"same optimum: margin differs by {abs(margin - res.margin_Nm) / res.margin_Nm:.2e} "
        f"relative; speed ratio SLSQP/IPOPT = {t_slsqp / t_ipopt:.1f}x warm (solver built), "
        f"{t_slsqp / t_cold:.1f}x cold (target >= 10x)"
    )
    # the solves alone, from the same starts: IPOPT (solver built) against SLSQP
    from scipy.optimize import minimize

    from optimize import problem as pb

    scales = solve_module.scales_for(model)
    grid = solve_module.initial_points(model, scales, model.bounds.starts)
    problem = solve_module.compile_problem(solve_module.structure_of(model))
    p = problem.parameters(model, scales)
    vb = solve_module.variable_bounds(model)
    starts = [
        [
            x["helical_angle_rad"] / pb.ALPHA_REF_rad,
            x["frequency_hz"] / pb.F_REF_hz,
            x["field_scaled"],
            x["t"],
        ]
        for x in grid
    ]
    lo = [vb["helical_angle_rad"][0] / pb.ALPHA_REF_rad, vb["frequency_hz"][0], 0.0, vb["t"][0]]
    hi = [vb["helical_angle_rad"][1] / pb.ALPHA_REF_rad, vb["frequency_hz"][1], np.inf, vb["t"][1]]

    def ipopt_only():
        return [problem.nlp.solve(x0, p, None).f for x0 in grid]

    def slsqp_only():
        bounds = [
            (a if np.isfinite(a) else None, b if np.isfinite(b) else None) for a, b in zip(lo, hi)
        ]
        cons = [
            {
                "type": "ineq",
                "fun": lambda x: -np.array([float(g) for g in pb.expressions(x, model, scales)[1]]),
            }
        ]
        return [
            minimize(
                lambda x: float(pb.expressions(x, model, scales)[0]),
                x0,
                method="SLSQP",
                bounds=bounds,
                constraints=cons,
                options={"ftol": 1e-12, "maxiter": 500},
            ).fun
            for x0 in starts
        ]

    t_i, f_i = median_time(ipopt_only, 9)
    t_s, f_s = median_time(slsqp_only, 5)
    print(
        f"solves only, {len(starts)} starts each: IPOPT {t_i * 1e3:.2f} ms, SLSQP "
        f"{t_s * 1e3:.2f} ms, ratio {t_s / t_i:.1f}x; best objective "
        f"{min(f_i):.12f} vs {min(f_s):.12f}"
    )
    n = 100_000
    rng = np.random.default_rng(0)
    b = model.bounds
    a = rng.uniform(b.helical_angle_min_rad, b.helical_angle_max_rad, n)
    fr = rng.uniform(b.frequency_min_hz, b.frequency_max_hz, n)
    t_grid, _ = median_time(lambda: margin_grid(model, a, fr), 5)
    print(
        f"vectorised evaluation of {n:,} (angle, frequency) points: {t_grid * 1e3:.1f} ms "
        f"(target about 1 s)"
    )


if __name__ == "__main__":
    main()
