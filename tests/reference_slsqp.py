"""Test oracle: a second, independent solver for the same design problem (scipy SLSQP, FD).

Used by the tests (IPOPT and SLSQP must agree) and by ``benchmarks/bench_optimize.py`` (speed
ratio); it lives with the tests, not in the ``optimize`` package. It evaluates exactly the same expressions (:func:`optimize.problem.expressions`) on
floats, so any difference is the solver's, not the model's.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import minimize

from optimize import problem as pb
from optimize.solve import initial_points, scales_for, variable_bounds
from optimize.system import DesignModel, prepare


def solve_slsqp(model: DesignModel) -> tuple[float, float, float, float]:
    """Best (helical_angle_rad, frequency_hz, field_T, objective) over the same starts as IPOPT.

    ``objective`` is the margin in N·m (or the safety factor for the ratio objective).
    """
    model = prepare(model)
    scales = scales_for(model)
    vb = variable_bounds(model)
    refs = {"helical_angle_rad": pb.ALPHA_REF_rad, "frequency_hz": pb.F_REF_hz, "t": 1.0}
    bounds = [
        *(
            (
                vb[n][0] / refs[n] if np.isfinite(vb[n][0]) else None,
                vb[n][1] / refs[n] if np.isfinite(vb[n][1]) else None,
            )
            for n in ("helical_angle_rad", "frequency_hz")
        ),
        (0.0, None),
        tuple(None if not np.isfinite(v) else v for v in vb["t"]),
    ]

    def fun(x):
        return float(pb.expressions(x, model, scales)[0])

    def cons(x):
        return -np.array([float(g) for g in pb.expressions(x, model, scales)[1]])

    best = None
    for s0 in initial_points(model, scales, model.bounds.starts):
        x0 = [
            s0["helical_angle_rad"] / pb.ALPHA_REF_rad,
            s0["frequency_hz"],
            s0["field_scaled"],
            s0["t"],
        ]
        res = minimize(
            fun,
            np.asarray(x0),
            method="SLSQP",
            bounds=bounds,
            constraints=[{"type": "ineq", "fun": cons}],
            options={"ftol": 1e-12, "maxiter": 500},
        )
        feasible = np.all(cons(res.x) >= -1e-8)
        if feasible and (best is None or res.fun < best.fun):
            best = res
    if best is None:
        raise RuntimeError("SLSQP found no feasible point from any start")
    a, r, b, t = best.x
    obj_scale = float(pb.OBJECTIVES[model.bounds.objective].scale(scales))
    return a * pb.ALPHA_REF_rad, r * pb.F_REF_hz, b * scales.field_T, t * obj_scale
