"""A design under tissue uncertainty: the Monte Carlo study the CLI and the report run.

The design's ``[tissue.uncertainty]`` table says what is uncertain; :func:`study` samples it
(:mod:`optimize.uncertainty`), evaluates the worst-case margin of every sample at the operating
point, and summarises the failure probability (step-out or lost grip), percentiles and Sobol
indices (SALib). The
samples run in chunks here, in worker processes or on a Dask cluster
(:func:`spiralcap.parallel.map_tasks`): same seed, same numbers bit for bit.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, ClassVar

from optimize.views import Viewable
from spiralcap.core.errors import InputError

DEFAULT_SAMPLES = 1 << 16
DEFAULT_SOBOL_BASE = 1 << 12


@dataclass(frozen=True)
class Study(Viewable):
    """An uncertainty study and where/how long it ran; in a notebook a table of the failure
    probability and the margin's percentiles, ``.plot()`` its distribution
    (:mod:`spiralcap.notebook`)."""

    _view_kind: ClassVar[str] = "uncertainty_study"

    result: Any  # optimize.uncertainty.UncertaintyResult
    uncertainty: Any  # optimize.uncertainty.TissueUncertainty
    where: str
    elapsed_s: float


def check_sobol_base(sobol_base: Any) -> int:
    """``--sobol-samples``: 0 (no Sobol indices) or a power of two up to
    :data:`optimize.uncertainty.MAX_SOBOL_BASE`, else InputError naming the option."""
    from optimize import uncertainty as uq

    if (
        isinstance(sobol_base, bool)
        or not isinstance(sobol_base, int)
        or (sobol_base != 0 and (sobol_base < 2 or sobol_base & (sobol_base - 1)))
        or sobol_base > uq.MAX_SOBOL_BASE
    ):
        raise InputError(
            "--sobol-samples",
            sobol_base,
            f"0 or a power of 2 from 2 to {uq.MAX_SOBOL_BASE} (SALib evaluates base x (inputs "
            "+ 2) points at once)",
        )
    return sobol_base


def study(
    design: Any,
    *,
    samples: int = DEFAULT_SAMPLES,
    seed: int = 0,
    method: str = "sobol",
    sobol_base: int = DEFAULT_SOBOL_BASE,
    workers: int = 1,
    dask: str | None = None,
    progress: Any = None,
    model: Any = None,
) -> Study:
    """Sample the design's tissue uncertainty and summarise the worst-case margin.

    Raises
    ------
    InputError
        No uncertain input, ``samples`` < 1, ``sobol_base`` not 0 or a power of two,
        ``workers`` < 1, an unreachable or missing Dask.
    """
    from optimize import uncertainty as uq
    from spiralcap.assemble import build_model
    from spiralcap.assemble.tissue import build_uncertainty
    from spiralcap.parallel import check_workers, map_tasks, where

    uq.check_samples(samples)
    uq.check_seed(seed)
    check_workers(workers)
    check_sobol_base(sobol_base)
    unc = build_uncertainty(design)
    if not unc.active:
        raise InputError(
            "tissue.uncertainty",
            "none",
            "at least one sigma > 0 or covariance_from (e.g. --set "
            "tissue.uncertainty.scale_sigma_log=0.3)",
        )
    problem = uq.margin_problem(
        model if model is not None else build_model(design, optimiser=False), unc
    )
    t0 = time.perf_counter()
    # tasks of 8 chunks (2^18 samples, ~0.1 s): each chunk's samples are fixed by its index
    # range and the seed, so the grouping changes nothing in the result
    tasks = [(problem, b, seed, method) for b in uq.batches(samples)]
    parts = map_tasks(uq.batch_outcomes, tasks, workers=workers, dask=dask, progress=progress)
    import numpy as np

    outcomes = np.concatenate(parts)
    sob = uq.sobol_indices(problem, sobol_base, seed) if sobol_base else None
    result = uq.summarise(problem, outcomes, seed, method, sob)
    return Study(result, unc, where(workers, dask), time.perf_counter() - t0)


def failure_to_dict(r: Any) -> dict[str, Any]:
    """``failure_probability``: the share of failed samples and its parts, each with its Wilson
    interval (the parts overlap: a sample can step out and lose grip), and the closed forms
    where they exist (:func:`optimize.uncertainty.grip_loss_probability`)."""
    from optimize import uncertainty as uq

    def part(p: Any, closed: str | None = None) -> dict[str, Any]:
        out: dict[str, Any] = {"value": p.value, "ci95": list(p.ci95), "samples": p.count}
        if closed is not None and closed in r.closed_form:
            out["closed_form"] = r.closed_form[closed]
        return out

    return {
        **part(r.failure),
        "definition": uq.FAILURE_DEFINITION,
        "min_wall_strain": r.min_wall_strain,
        "interval": "Wilson score 95 % (binomial; conservative for quasi-random points)",
        "parts": {
            "stepout_probability": part(r.stepout),
            "below_min_strain_probability": part(r.below_min_strain, "below_min_strain"),
            "no_grip_probability": part(r.no_grip, "no_grip"),
        },
    }


def _nominal_margin(margin_Nm: float) -> dict[str, Any]:
    """The nominal margin's JSON keys: absent, with ``nominal_margin_Nm_undefined``, where the
    nominal spiral does not touch some wall (the rule of ``margin_Nm`` in evaluate's JSON)."""
    if math.isnan(margin_Nm):
        return {"nominal_margin_Nm_undefined": True}
    return {"nominal_margin_Nm": margin_Nm}


def study_to_dict(st: Study, design_source: str = "") -> dict[str, Any]:
    """JSON-ready mapping (SI units in every key)."""
    from optimize import uncertainty as uq

    r = st.result
    out: dict[str, Any] = {
        "design": design_source,
        "samples": r.samples,
        "seed": r.seed,
        "method": r.method,
        "ran_on": st.where,
        "elapsed_s": st.elapsed_s,
        "uncertain_inputs": list(dict.fromkeys(g for _, g in st.uncertainty.factors())),
        **_nominal_margin(r.nominal_margin_Nm),
        "available_torque_Nm": r.available_torque_Nm,
        "failure_probability": failure_to_dict(r),
        "stepout_probability": r.stepout_probability,
        "no_grip_probability": r.no_grip_probability,
        "stepout_probability_ci95": list(r.stepout_ci95),
        "stepout_probability_interval": "Wilson score (binomial; conservative for quasi-random)",
        "margin_percentiles_Nm": r.margin_percentiles_Nm,
        "margin_mean_Nm": r.margin_mean_Nm,
        "margin_std_Nm": r.margin_std_Nm,
        "margin_counting": uq.MARGIN_COUNTING,
        "speed_percentiles_m_s": r.speed_percentiles_m_s,
        "speed_note": "the design's speed where the sample does not fail, 0 in every failed "
        "sample (step-out or below the minimum wall strain)",
    }
    if r.sobol is not None:
        s = r.sobol
        out["sobol"] = {
            "estimator": f"SALib Saltelli/Jansen, {s.base_samples} base samples",
            "indices": {
                name: {
                    "first_order": s.first_order[i],
                    "first_order_ci95_halfwidth": s.first_order_conf[i],
                    "total": s.total[i],
                    "total_ci95_halfwidth": s.total_conf[i],
                }
                for i, name in enumerate(s.inputs)
            },
        }
    return out
