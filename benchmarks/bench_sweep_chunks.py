"""Benchmark: a large vectorised sweep evaluated in about ten array calls (each a progress step
off a terminal) against one call over every point, in the same process.

Run: python benchmarks/bench_sweep_chunks.py [POINTS]
Prints both times and their ratio (target: the chunked run no slower than 1.1x the one call) and
whether the numbers are identical. Asserts nothing.
"""

from __future__ import annotations

import sys

import numpy as np
from _timing import median_time

import spiralcap.sweep as sw
from spiralcap.design import load_design


def main(points: int = 100_000) -> None:
    design = load_design()
    inputs = sw._grid([sw.parse_over(f"operation.frequency_hz=0.5:5:{points}")])
    steps: list[int] = []
    t_chunked, chunked = median_time(
        lambda: sw._evaluate_vectorised(design, inputs, lambda d, n: steps.append(d)), 3
    )
    default = sw.VECTOR_CHUNK
    sw.VECTOR_CHUNK = 10**9  # one call over every point
    try:
        t_one, one = median_time(lambda: sw._evaluate_vectorised(design, inputs), 3)
    finally:
        sw.VECTOR_CHUNK = default
    same = all(np.array_equal(one[k], chunked[k]) for k in one)
    print(f"{points} points, frequency sweep (vectorised)")
    print(f"one array call:            {t_one:8.2f} s")
    print(f"{len(steps) // 3} calls (progress steps): {t_chunked:8.2f} s")
    print(
        f"ratio chunked / one call:  {t_chunked / t_one:8.2f}  (target <= 1.1); identical: {same}"
    )


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 100_000)
