"""The optimum of a design, whichever kind: :func:`optimize_design` dispatches to

- :func:`optimize.discrete.size_design` when hardware keys are free (``model.sizing``),
- :func:`optimize.active_set.optimize_scenarios` when the model carries tissue scenarios,
- :func:`optimize.solve.solve_fixed` otherwise (one NLP at fixed hardware).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from optimize.result import OptimizationResult
from optimize.solve import SolveOptions
from optimize.system import MODEL, DesignModel
from spiralcap.core.checks import guard


@guard(model=MODEL)
def optimize_design(
    model: DesignModel,
    *,
    warm_start: OptimizationResult | dict | None = None,
    frequency_bounds: bool = True,
    progress: Callable[[str], None] | None = None,
    executor: Any | None = None,
) -> OptimizationResult:
    """Best design of ``model`` for its objective (docs/optimisation.md).

    Parameters
    ----------
    model : DesignModel
        The design, SI. Free hardware keys (``model.sizing``) are sized; tissue scenarios
        (``model.scenarios``) are solved by the working-set loop.
    warm_start : OptimizationResult or dict, optional
        A result of a neighbouring problem (the previous sweep point), or a dict of
        ``helical_angle_rad``, ``frequency_hz``, ``field_T`` (T) (and ``t_value``); tried
        first, the grid starts only if it fails. Not used by a sizing.
    frequency_bounds : bool
        False: the evaluation's step-out and highest frequency are left NaN (a sweep's rows
        need neither). Not used by a sizing.
    progress : callable, optional
        ``progress(stage)`` for each stage of a sizing (the relaxation's outer rounds, the
        neighbours), for a progress line.
    executor : optional
        Where a sizing solves its neighbours (:class:`optimize.discrete.Executor`: anything
        with ``submit``/``map``, a process pool, a Dask client); None: here. The result is the
        same either way.

    Returns
    -------
    OptimizationResult
        'optimal', or 'infeasible' naming what is out of reach.

    Examples
    --------
    The built-in design's best helical angle and frequency for the largest worst-case margin
    (one IPOPT solve):

    >>> import math
    >>> from optimize import optimize_design, prepare
    >>> from spiralcap.assemble import build_model
    >>> from spiralcap.design import load_design
    >>> best = optimize_design(prepare(build_model(load_design(None, []))))
    >>> print(f"{best.status}: {math.degrees(best.helical_angle_rad):.2f} deg, {best.frequency_hz:.3f} Hz, "
    ...       f"margin {best.margin_Nm * 1e3:.3f} mN m")
    optimal: 12.16 deg, 1.288 Hz, margin 1.786 mN m
    """
    # imported here: a command that sizes nothing does not load the sizing and scenario modules
    if model.sizing is not None and model.sizing.free:
        from optimize.discrete import size_design

        return size_design(model, progress=progress, executor=executor)
    from optimize.active_set import solve_hardware

    return solve_hardware(model, warm_start, SolveOptions(frequency_bounds=frequency_bounds))
