"""Field speed of a square three-axis set against magpylib polylines and against the circles.

Three nested square pairs (sides 0.95 / 0.78 / 0.62 m, one filament per coil) at 2·10^5 points:
``coils`` (four square roots per filament and point, :mod:`coils.rectangle` at a = b) against magpylib's
``Polyline`` squares on the same six filaments, and against the circular set of the same size
(:mod:`coils.filaments`), all timed in this process as ratios (best of a few rounds, CPU time).
Asserts nothing; run ``python benchmarks/bench_square_field.py``.
"""

from __future__ import annotations

import time

import magpylib
import numpy as np
from bench_coils_field import best_of

import coils


def _square_vertices(axis: int, half: float, centre: float) -> np.ndarray:
    out = np.zeros((5, 3))
    u, v = (axis + 1) % 3, (axis + 2) % 3
    for i, (a, b) in enumerate([(1, -1), (1, 1), (-1, 1), (-1, -1), (1, -1)]):
        out[i, u], out[i, v], out[i, axis] = a * half, b * half, centre
    return out


def main() -> None:
    sides = {"x": 0.95, "y": 0.78, "z": 0.62}
    squares = coils.ThreeAxisHelmholtz(
        *(coils.SquarePair(sides[ax], 300, ax, wire_diameter_m=2e-3) for ax in "xyz")
    )
    circles = coils.ThreeAxisHelmholtz(
        *(coils.HelmholtzPair(sides[ax] / 2, 300, ax, wire_diameter_m=2e-3) for ax in "xyz")
    )
    currents = np.array([1.3, -0.7, 2.1])
    lines = magpylib.Collection(
        *(
            magpylib.current.Polyline(
                current=p.turns * i,
                vertices=_square_vertices(p.axis_index, p.half_side_m, s * p.spacing_m),
            )
            for p, i in zip(squares.pairs, currents, strict=True)
            for s in (-0.5, 0.5)
        )
    )
    points = np.random.default_rng(0).uniform(-0.25, 0.25, (200_000, 3))
    ours, magpy, round_ = best_of(
        [
            lambda: squares.field(points, currents),
            lambda: lines.getB(points),
            lambda: circles.field(points, currents),
        ],
        repeats=3,
        clock=time.process_time,
    )
    print(f"square set, {len(points)} points: coils {ours:.3f} s CPU")
    print(f"  magpylib Polyline / coils: {magpy / ours:.1f}x")
    print(f"  circles (coils.filaments) / squares: {round_ / ours:.2f}x")


if __name__ == "__main__":
    main()
