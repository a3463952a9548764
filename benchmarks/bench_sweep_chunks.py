"""Benchmark: the largest vectorised sweep evaluated in equal array calls of at most
``VECTOR_CHUNK`` points (each a progress step off a terminal) against one call over every
point, in the same process, interleaved.

Run: python benchmarks/bench_sweep_chunks.py [POINTS]   (default 250000)
Prints both times and their ratio (target: the chunked run no slower than 1.1x the one call) and
whether the numbers are identical. Asserts nothing.
"""

from __future__ import annotations

import statistics
import sys

import numpy as np
from _timing import median_time

import spiralcap.sweep as sw
from spiralcap.design import load_design


def main(points: int = 250_000) -> None:
    design = load_design()
    inputs = sw._grid([sw.parse_over(f"operation.frequency_hz=0.5:5:{points}")])
    steps: list[int] = []
    default = sw.VECTOR_CHUNK

    def chunked_run():
        sw.VECTOR_CHUNK = default
        return sw._evaluate_vectorised(design, inputs, lambda d, n: steps.append(d))

    def one_call_run():
        sw.VECTOR_CHUNK = 10**9  # one call over every point
        try:
            return sw._evaluate_vectorised(design, inputs)
        finally:
            sw.VECTOR_CHUNK = default

    times: dict[str, list[float]] = {"chunked": [], "one": []}
    for _ in range(3):  # interleaved: a machine shared with other work loads both alike
        t, chunked = median_time(chunked_run, 1)
        times["chunked"].append(t)
        t, one = median_time(one_call_run, 1)
        times["one"].append(t)
    t_chunked, t_one = (statistics.median(times[k]) for k in ("chunked", "one"))
    same = all(np.array_equal(one[k], chunked[k]) for k in one)
    print(f"{points} points, frequency sweep (vectorised)")
    print(f"one array call:            {t_one:8.2f} s")
    print(f"{len(steps) // 3} calls (progress steps): {t_chunked:8.2f} s")
    print(
        f"ratio chunked / one call:  {t_chunked / t_one:8.2f}  (target <= 1.1); identical: {same}"
    )


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 250_000)
