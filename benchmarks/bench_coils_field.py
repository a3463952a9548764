"""Field speed of ``coils`` against magpylib on the same six loops, in one process.

Prints throughput at 10^6 points (target >= 5x magpylib; one thread: the chunk thread pool was
retired in issue 27, it saved nothing measurable) and the single-point call rate
(target >= 20x magpylib's single-point ``getB``). Our single-point path is the compiled CasADi
Function behind ``ThreeAxisHelmholtz.point_field`` (called through a CasADi buffer), the one a
point-at-a-time optimiser uses. Asserts nothing; run ``python benchmarks/bench_coils_field.py``.
"""

from __future__ import annotations

import time

import magpylib
import numpy as np
import scipy.constants
from scipy.spatial.transform import Rotation

import coils
from spiralcap.core.constants import MU0_T_m_per_A

_TURN_TO = {
    "x": Rotation.from_euler("y", 90, degrees=True),
    "y": Rotation.from_euler("x", -90, degrees=True),
    "z": None,
}


def best_of(fns, repeats: int, clock=time.perf_counter) -> list[float]:
    """Shortest time of each function over ``repeats`` rounds on ``clock``, s.

    The functions are called in turn within each round, so that a load change on the machine
    hits them alike; the ratio of the minima is what is reported. With
    ``clock=time.process_time`` the time is this process's CPU time (user + system), which a
    busy machine disturbs less than the wall clock.
    """
    times = [[] for _ in fns]
    for _ in range(repeats):
        for fn, t in zip(fns, times, strict=True):
            t0 = clock()
            fn()
            t.append(clock() - t0)
    return [min(t) for t in times]


def main() -> None:
    system = coils.ThreeAxisHelmholtz(
        coils.HelmholtzPair(0.4, 400, "x"),
        coils.HelmholtzPair(0.35, 350, "y"),
        coils.HelmholtzPair(0.3, 300, "z"),
    )
    currents = np.array([1.3, -0.7, 2.1])
    loops = [
        magpylib.current.Circle(
            current=p.turns * i,
            diameter=2 * p.radius_m,
            position=s * p.separation_m * np.eye(3)[p.axis_index],
            orientation=_TURN_TO[p.axis],
        )
        for p, i in zip(system.pairs, currents, strict=True)
        for s in (-0.5, 0.5)
    ]
    collection = magpylib.Collection(*loops)
    rng = np.random.default_rng(0)
    points = rng.uniform(-0.2, 0.2, (10**6, 3))

    ours = system.field(points, currents)
    ref = collection.getB(points) * (MU0_T_m_per_A / scipy.constants.mu_0)
    rel = np.linalg.norm(ours - ref, axis=1) / np.linalg.norm(ref, axis=1)
    t_ours, t_mag = best_of(
        [lambda: system.field(points, currents), lambda: collection.getB(points)], 5
    )
    c_ours, c_mag = best_of(
        [lambda: system.field(points, currents), lambda: collection.getB(points)],
        5,
        clock=time.process_time,
    )
    print(
        f"10^6 points, 6 loops: coils {t_ours:.3f} s, magpylib "
        f"{t_mag:.3f} s, ratio {t_mag / t_ours:.1f}x (target >= 5x); CPU time {c_ours:.3f} s vs "
        f"{c_mag:.3f} s, ratio {c_mag / c_ours:.1f}x; max |dB|/|B| {rel.max():.1e}"
    )

    single = points[:2000]
    point_field = system.point_field
    point_field(single[0], currents)  # build the CasADi buffer outside the timing
    t_point, t_numpy, t_mag1 = (
        t / n
        for t, n in zip(
            best_of(
                [
                    lambda: [point_field(p, currents) for p in single],
                    lambda: [system.field(p, currents) for p in single[:500]],
                    lambda: [collection.getB(p) for p in single[:200]],
                ],
                5,
            ),
            (len(single), 500, 200),
            strict=True,
        )
    )
    err = max(
        np.max(np.abs(point_field(p, currents) - system.field(p, currents)[0])) for p in single[:50]
    )
    print(
        f"single point: coils.point_field {t_point * 1e6:.2f} us, numpy field() "
        f"{t_numpy * 1e6:.1f} us, magpylib getB {t_mag1 * 1e6:.1f} us; "
        f"ratio {t_mag1 / t_point:.0f}x (target >= 20x), numpy path {t_mag1 / t_numpy:.1f}x; "
        f"CasADi vs numpy max |dB| {err:.1e} T"
    )


if __name__ == "__main__":
    main()
