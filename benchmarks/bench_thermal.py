"""Benchmark: cost of the winding thermal model in the field capacity (issue 10).

Run: python benchmarks/bench_thermal.py
Compares, in one process, the largest-field computation over 10^5 frequencies with the
self-consistent winding model (default) against the same design with the copper temperature
fixed (``coils.winding_temperature_C``: every limit but the hot spot a closed-form power law),
and one ``evaluate`` (with step-out and max_frequency searches) likewise. Asserts nothing.
"""

from __future__ import annotations

import numpy as np
from _timing import median_time

from optimize import evaluate, margin_grid, prepare
from spiralcap.assemble import build_model
from spiralcap.design import load_design


def main() -> None:
    f = np.linspace(0.5, 5.0, 100_000)
    alpha = np.radians(10.0)
    models = {
        "self-consistent": prepare(build_model(load_design())),
        "fixed 80 °C copper": prepare(
            build_model(load_design(None, ["coils.winding_temperature_C=80"]))
        ),
    }
    times = {}
    for name, m in models.items():
        evaluate(m)
        t_grid, _ = median_time(lambda m=m: margin_grid(m, alpha, f), 3)
        t_eval, _ = median_time(lambda m=m: evaluate(m), 7)
        times[name] = (t_grid, t_eval)
        print(
            f"{name:20s} margin_grid 1e5: {t_grid * 1e3:8.1f} ms   evaluate: {t_eval * 1e3:7.1f} ms"
        )
    (g1, e1), (g0, e0) = times["self-consistent"], times["fixed 80 °C copper"]
    print(f"ratio self-consistent / fixed: margin_grid {g1 / g0:.1f}x, evaluate {e1 / e0:.1f}x")


if __name__ == "__main__":
    main()
