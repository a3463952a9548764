"""Benchmark: identification of one capsule's torque curve (torque_model.identify).

Run: python benchmarks/bench_identification.py
Times the fit of 11 points (0.5-3 Hz, 2 % noise) of capsule No. 2 made by the calibrated
sample-2 model, and of a 30-point wide-band curve (0.05-20 Hz, all five parameters
identifiable), each with the analytic Jacobian and, as the same-process reference, scipy's
2-point finite-difference Jacobian, with and without the profile (bound) test. Target: well
under a second per fit. Prints figures, asserts nothing.
"""

from __future__ import annotations

import math

import numpy as np
from _timing import median_time

import torque_model as tm


def _case(
    name: str,
    f: np.ndarray,
    truth: tm.TissueParameters,
    noise: float,
    base: tm.TissueParameters,
    repeat: int = 7,
) -> None:
    angle = math.radians(10.0)
    clean = np.asarray(tm.resistive_torque_Nm(angle, f, truth, tm.PAPER_CAPSULE))
    y = clean * (1 + noise * np.random.default_rng(2013).normal(size=f.size))
    print(f"{name}: {f.size} points, {noise:.1%} noise")
    ref = None
    for jac in ("analytic", "2-point"):
        for profile in (True, False):
            t, fit = median_time(
                lambda jac=jac, profile=profile: tm.identify(
                    f, y, angle, base, tm.PAPER_CAPSULE, jacobian=jac, profile_bounds=profile
                ),
                repeat,
            )
            ref = ref or t
            print(
                f"  jacobian {jac:8s} profile {'on ' if profile else 'off'}: "
                f"{t * 1e3:8.1f} ms  ({t / ref:4.2f} x analytic+profile)  cost {fit.cost:.6e}  "
                f"not pinned down: {', '.join(fit.not_pinned_down) or 'none'}"
            )


def main() -> None:
    base = tm.preset("zhou2013-sample2")
    _case("capsule No. 2 curve, sample-2 tissue", np.linspace(0.5, 3.0, 11), base, 0.02, base)
    rich = base.replace(E1_Pa=2e4, E2_Pa=5e4, E3_Pa=1e4, eta1_Pa_s=1e4, eta2_Pa_s=2.5e3)
    _case("wide-band curve, identifiable tissue", np.geomspace(0.05, 20.0, 30), rich, 0.002, base)
    t_model, _ = median_time(
        lambda: tm.resistive_torque_Nm(
            np.radians(np.linspace(2, 45, 1000))[:, None],
            np.linspace(0.5, 5, 100),
            base,
            tm.PAPER_CAPSULE,
        ),
        5,
    )
    print(f"model on a 1000 x 100 (angle x frequency) numpy grid: {t_model * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
