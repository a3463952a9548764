"""Benchmark: re-optimising sweeps and hardware sizing (issue 9 targets).

Run: python benchmarks/bench_sizing.py
1. End to end (fresh processes, imports included): a 40-point ``sweep --optimize`` over a limit
   against one ``spiralcap optimize`` call (target: at most 3x).
2. A sizing run with six free hardware keys (turns and wire of the three pairs): in this process
   with the problem compiled first (cold) and again (compiled), and end to end as a CLI call
   (target: under 2 s). The reference in the same process is one fixed-hardware optimisation.
Asserts nothing; prints the figures.
"""

from __future__ import annotations

from _timing import median_time, run_cli

SIX = [
    f"--free=coils.{ax}.{key}"
    for ax in "xyz"
    for key in ("turns=100:800", "wire_diameter_mm=0.8:3.0")
]


def _cli(*args: str) -> None:
    run_cli(*args, check=False)  # sizing runs may exit 3 (infeasible), still timed


def main() -> None:
    t_one, _ = median_time(lambda: _cli("optimize", "--json"), 3)
    t_sweep, _ = median_time(
        lambda: _cli("sweep", "--optimize", "--json", "--over", "limits.current_A=5:20:40"), 3
    )
    print(
        f"end to end: one optimize {t_one:.2f} s, 40-point sweep --optimize {t_sweep:.2f} s, "
        f"ratio {t_sweep / t_one:.2f}x (target <= 3x)"
    )

    from dataclasses import replace

    from optimize import hardware as hw
    from optimize import optimize_design, prepare
    from optimize.solve import compile_problem
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    model = prepare(build_model(load_design()))
    t_fixed, _ = median_time(lambda: optimize_design(model), 5)
    free = tuple(
        hw.FreeVariable(f"{ax}.{q}", lo, hi)
        for ax in "xyz"
        for q, lo, hi in (("turns", 100, 800), ("wire_diameter_m", 0.8e-3, 3e-3))
    )
    sized = replace(model, sizing=hw.Sizing(free))

    def cold():
        compile_problem.cache_clear()
        return optimize_design(sized)

    t_cold, res = median_time(cold, 3)
    t_warm, _ = median_time(lambda: optimize_design(sized), 3)
    h = res.hardware
    print(
        f"six free keys in process: {t_cold:.2f} s with compilation, {t_warm:.2f} s compiled "
        f"({t_warm / t_fixed:.0f}x one fixed-hardware optimisation of {t_fixed * 1e3:.0f} ms); "
        f"{h.candidates} neighbours, {h.feasible} feasible, {h.outer_iterations} outer iterations"
    )
    print(
        f"  margin: continuous bound {h.relaxed_objective * 1e3:.4f} mN·m, discrete "
        f"{h.discrete_objective * 1e3:.4f} mN·m (built-in hardware: "
        f"{optimize_design(model).margin_Nm * 1e3:.4f} mN·m)"
    )
    t_cli, _ = median_time(lambda: _cli("optimize", "--json", *SIX), 3)
    print(
        f"six free keys end to end (CLI, imports included): {t_cli:.2f} s (target < 2 s), "
        f"{t_cli / t_one:.2f}x one deterministic `spiralcap optimize` ({t_one:.2f} s) of the "
        "same run"
    )


if __name__ == "__main__":
    main()
