"""Benchmark: cost of extra tissue samples, and Dask overhead and scaling (issue 11).

Run: python benchmarks/bench_uncertainty.py [--no-dask]
Prints
- the marginal rate of margin evaluations, (N2 - N1) / (t(N2) - t(N1)), for the vectorised
  Monte Carlo (two tissue sets, five uncertain inputs; target >= 1e6 per second on one core),
  and its ratio to the scalar path (optimize.evaluate.margin_grid one sample at a time) run in
  the same process;
- a study of 2^21 samples in this process, on a Dask LocalCluster with 1 and with 2 worker
  processes: the Dask overhead (1 worker against this process) and the scaling (1 vs 2).
Asserts nothing.
"""

from __future__ import annotations

import sys
from dataclasses import replace

import numpy as np
from _timing import median_time

from optimize import margin_grid
from optimize import uncertainty as uq
from spiralcap.assemble import build_model
from spiralcap.assemble.tissue import build_uncertainty
from spiralcap.design import load_design

SETS = [
    "tissue.uncertainty.scale_sigma_log=0.25",
    "tissue.uncertainty.E3_sigma_log=0.3",
    "tissue.uncertainty.friction_sigma_log=0.2",
    "tissue.uncertainty.lumen_diameter_sigma_mm=0.3",
    "tissue.uncertainty.wall_thickness_sigma_mm=0.1",
]


def main() -> None:
    design = load_design(None, SETS)
    model = build_model(design)
    problem = uq.margin_problem(model, build_uncertainty(design))
    n1, n2 = 1 << 16, 1 << 20
    t1, _ = median_time(lambda: uq.run_local(problem, n1, 1), 5)
    t2, m = median_time(lambda: uq.run_local(problem, n2, 1)[:, 0], 3)
    rate = (n2 - n1) / (t2 - t1)
    print(
        f"vectorised Monte Carlo: {n1} samples {t1 * 1e3:.1f} ms, {n2} samples {t2 * 1e3:.1f} ms"
        f" -> {rate:.3g} margin evaluations/s per extra sample (target >= 1e6; one core)"
    )
    # reference in the same process: the scalar path, one perturbed tissue tuple at a time
    u = uq.latent_uniforms(problem.dimension, 0, 200, 1)
    arrays = uq.perturbed_tissues(model.tissues, problem.uncertainty, u)

    def scalar():
        from torque_model import TissueParameters

        out = []
        for i in range(u.shape[0]):
            tissues = tuple(
                TissueParameters(
                    **{f: float(getattr(t, f)[i]) for f in uq.VISCOELASTIC},
                    lumen_diameter_m=float(np.broadcast_to(t.lumen_diameter_m, (200,))[i]),
                    wall_thickness_m=float(np.broadcast_to(t.wall_thickness_m, (200,))[i]),
                    friction_coefficient=float(np.broadcast_to(t.friction_coefficient, (200,))[i]),
                )
                for t in arrays
            )
            mm = replace(model, tissues=tissues, constants=model.constants or None)
            out.append(
                float(margin_grid(mm, problem.helical_angle_rad, problem.frequency_hz)["margin_Nm"])
            )
        return out

    ts, ref = median_time(scalar, 3)
    vec = problem.margins_Nm(u)
    print(
        f"scalar path (margin_grid per sample): {u.shape[0] / ts:.3g} evaluations/s; "
        f"vectorised/scalar = {rate / (u.shape[0] / ts):.0f}x; same margins to "
        f"{np.max(np.abs(np.asarray(ref) - vec) / np.abs(vec)):.1e} relative"
    )
    print(f"P(step-out) over {n2} samples: {np.mean(m < 0):.4%}")
    if "--no-dask" in sys.argv:
        return
    dask_scaling(problem)


def dask_scaling(problem: uq.MarginProblem) -> None:
    from distributed import LocalCluster

    from spiralcap.parallel import map_tasks

    n = 1 << 23
    tasks = [(problem, b, 1, "sobol") for b in uq.batches(n)]
    t_local, ref = median_time(lambda: np.concatenate(map_tasks(uq.batch_outcomes, tasks)), 3)
    print(
        f"{n} samples, {len(tasks)} tasks of 8 chunks of {uq.CHUNK}: this process {t_local * 1e3:.0f} ms"
    )
    times = {}
    for workers in (1, 2):
        with LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster:
            addr = cluster.scheduler_address
            map_tasks(uq.batch_outcomes, tasks[:2], dask=addr)  # warm the workers' imports
            t, out = median_time(
                lambda addr=addr: np.concatenate(map_tasks(uq.batch_outcomes, tasks, dask=addr)), 3
            )
        times[workers] = t
        same = np.array_equal(out, ref)
        print(
            f"Dask LocalCluster, {workers} worker process(es): {t * 1e3:.0f} ms "
            f"(bit-identical to local: {same}; includes connecting a client)"
        )
    print(
        f"Dask overhead (1 worker / this process) {times[1] / t_local:.2f}x; "
        f"scaling 1 -> 2 workers {times[1] / times[2]:.2f}x"
    )


if __name__ == "__main__":
    main()
