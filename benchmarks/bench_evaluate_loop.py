"""Benchmark: a script that evaluates the built-in design at 100 operating points, with the
caps that do not depend on the frequency solved once per frequency search
(``optimize.physics.frequency_free_caps_T``) and solved at every frequency of it (off).

Run: python benchmarks/bench_evaluate_loop.py [--repeat N]
One process, the two taking turns; prints the medians and the saving ``1 - on / off``. Asserts
nothing (docs/architecture.md, speed pieces).
"""

from __future__ import annotations

import statistics
import sys
import time

import numpy as np


def _loop(model, points) -> float:
    from optimize import evaluate

    t0 = time.perf_counter()
    for alpha, f in points:
        evaluate(model, alpha, f)
    return time.perf_counter() - t0


def main() -> None:
    import optimize.physics as ph
    from optimize import prepare
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    repeat = int(sys.argv[sys.argv.index("--repeat") + 1]) if "--repeat" in sys.argv else 5
    model = prepare(build_model(load_design()))
    b = model.bounds
    rng = np.random.default_rng(0)
    points = list(
        zip(
            rng.uniform(b.helical_angle_min_rad, b.helical_angle_max_rad, 100),
            rng.uniform(b.frequency_min_hz, b.frequency_max_hz, 100),
        )
    )
    real = ph.frequency_free_caps_T
    _loop(model, points[:3])  # compiled pieces built once
    on, off = [], []
    for _ in range(repeat):
        ph.frequency_free_caps_T = real
        on.append(_loop(model, points))
        ph.frequency_free_caps_T = lambda *a: {}
        off.append(_loop(model, points))
    ph.frequency_free_caps_T = real
    m_on, m_off = statistics.median(on), statistics.median(off)
    print(
        f"100 evaluations: on {m_on:.2f} s, off {m_off:.2f} s, saving {100 * (1 - m_on / m_off):.0f} %"
        f" (median of {repeat})"
    )


if __name__ == "__main__":
    main()
