"""Benchmark: the robust optimum on the one compiled NLP (issue 11 on issue 9's problem).

Run: python benchmarks/bench_robust.py
Prints, all in this process:
- the first ``margin_p05`` solve (compiling the NLP of 1024 scenarios x 2 tissue sets) and a
  re-solve with another scenario seed (same structure: the compiled solver is reused, only the
  parameters change) -> the compile share;
- the robust solve against the deterministic ``margin`` solve of the same design (ratio);
- ``sweep --optimize`` over 8 axial loads with ``margin_p05``: the warm-started chain against
  cold solves of the same points (ratio);
- the out-of-sample check: robust vs deterministic optimum on 2^16 fresh samples.
Asserts nothing.
"""

from __future__ import annotations

import time
from dataclasses import replace

from _timing import median_time

from optimize import optimize_design
from optimize import robust as rb
from optimize.compiled import compile_problem
from spiralcap.assemble import build_model
from spiralcap.assemble.tissue import build_uncertainty
from spiralcap.design import load_design
from spiralcap.robust import robust_optimum
from spiralcap.sweep import parse_over, sweep

SETS = [
    "tissue.uncertainty.scale_sigma_log=0.3",
    "tissue.uncertainty.lumen_diameter_sigma_mm=0.3",
    "requirements.min_spiral_turns=0",
    "optimize.objective=margin_p05",
]


def main() -> None:
    design = load_design(None, SETS)
    base = build_model(design)
    unc = build_uncertainty(design)
    model = rb.with_scenarios(base, unc, scenarios=1024, seed=0)
    other = rb.with_scenarios(base, unc, scenarios=1024, seed=7)
    compile_problem.cache_clear()
    t0 = time.perf_counter()
    first = optimize_design(model)
    t_first = time.perf_counter() - t0
    t_again, again = median_time(lambda: optimize_design(other), 3)
    print(
        f"margin_p05, 1024 scenarios x {len(base.tissues)} tissue sets: first solve (with "
        f"compile) {t_first:.2f} s, re-solve with another seed {t_again:.2f} s "
        f"({t_first / t_again:.1f}x; {first.iterations} / {again.iterations} IPOPT iterations)"
    )
    det_model = replace(base, bounds=replace(base.bounds, objective="margin"))
    optimize_design(det_model)
    t_det, _ = median_time(lambda: optimize_design(det_model), 5)
    print(
        f"deterministic margin solve {t_det * 1e3:.0f} ms; robust / deterministic "
        f"{t_again / t_det:.0f}x"
    )
    small = design.with_values({"optimize.scenarios": 256})
    axes = [parse_over("requirements.axial_load_mN=20:90:8")]
    sweep(small, axes[:1], optimize=True)  # compile the warm and the cold solver
    t_chain, res = median_time(lambda: sweep(small, axes, optimize=True), 1)
    from spiralcap.robust import robust_model

    def cold() -> None:
        for v in res.inputs["requirements.axial_load_mN"]:
            optimize_design(robust_model(small.with_values({"requirements.axial_load_mN": v})))

    t_cold, _ = median_time(cold, 1)
    print(
        f"sweep --optimize, 8 loads, margin_p05 over 256 scenarios: warm chain {t_chain:.2f} s, "
        f"cold solves {t_cold:.2f} s ({t_cold / t_chain:.1f}x)"
    )
    rc = robust_optimum(design)
    claim = rc.in_sample.margin_p05_Nm
    fresh = rc.out_of_sample.margin_percentiles_Nm["p05"]
    det = rc.deterministic_out_of_sample.margin_percentiles_Nm["p05"]
    print(
        f"out of sample (2^16 fresh samples): robust p05 {fresh * 1e3:.4g} mN·m "
        f"({100 * (fresh / claim - 1):+.2f} % vs the in-sample claim {claim * 1e3:.4g}), "
        f"deterministic optimum's p05 {det * 1e3:.4g} mN·m"
    )


if __name__ == "__main__":
    main()
