"""A calibrated design's coils against the survey they were fitted to (the report, the gallery).

The survey named by ``calibration.survey_csv`` is read again and the calibrated model,
b0 + sum M_k G_k(p) I_k (the coils every figure uses), evaluated at each of its rows.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["CalibrationCheck", "calibration_check", "payload"]

_AXES = ("x", "y", "z")


@dataclass(frozen=True)
class CalibrationCheck:
    """The calibrated coils against their survey (SI); ``measured_T`` None without it.

    Attributes
    ----------
    actuation_matrix_T_per_A, model_actuation_T_per_A : ndarray, shape (3, 3)
        Calibrated and modelled centre field per ampere (column k: pair k), T/A.
    background_T : ndarray, shape (3,)
        The calibration's background field, T.
    survey : str
        The survey path as the design names it (empty: none named).
    measured_T, predicted_T : ndarray, shape (n, 3) or None
        The survey's readings and the calibrated model at its rows, T.
    problem : str
        Why the survey could not be read (empty when it was).
    """

    actuation_matrix_T_per_A: np.ndarray
    model_actuation_T_per_A: np.ndarray
    background_T: np.ndarray
    survey: str
    measured_T: np.ndarray | None = None
    predicted_T: np.ndarray | None = None
    problem: str = ""


def calibration_check(design: Any, model: Any) -> CalibrationCheck | None:
    """The check of ``model``'s calibrated coils against the design's survey (None: no
    calibration).

    Parameters
    ----------
    design : spiralcap.design.Design
        The design (its ``calibration.*`` keys).
    model : optimize.DesignModel
        Its model, whose coils carry the calibration.

    Returns
    -------
    CalibrationCheck or None
        Actuation, background and, when the survey reads, measured and modelled field, T.
    """
    coils = model.coils
    if getattr(coils, "calibration", None) is None:
        return None
    from spiralcap.assemble.calibration import nominal
    from spiralcap.core.errors import SpiralcapError
    from spiralcap.survey import read_survey_csv

    centre = np.zeros((1, 3))
    base = CalibrationCheck(
        actuation_matrix_T_per_A=np.asarray(coils.actuation_matrix_T_per_A),
        model_actuation_T_per_A=nominal(coils).field_matrix(centre)[0],
        background_T=np.asarray(coils.background_T),
        survey=str(design.get("calibration.survey_csv") or ""),
    )
    path = design.path_of("calibration.survey_csv")
    if path is None:
        return base
    try:
        survey = read_survey_csv(path)
    except SpiralcapError as exc:
        return CalibrationCheck(**{**base.__dict__, "problem": str(exc)})
    g = coils.field_matrix(survey.points_m)
    predicted = np.einsum("nck,nk->nc", g, survey.currents_A) + base.background_T
    return CalibrationCheck(
        **{**base.__dict__, "measured_T": survey.fields_T, "predicted_T": predicted}
    )


def payload(check: CalibrationCheck) -> dict[str, Any]:
    """The report JSON's ``calibration`` block (SI; the residuals only with the survey)."""
    from coils.calibration import gains_and_tilts

    gains, tilts = gains_and_tilts(check.actuation_matrix_T_per_A, check.model_actuation_T_per_A)
    out: dict[str, Any] = {
        "survey": check.survey,
        "actuation_matrix_T_per_A": check.actuation_matrix_T_per_A.tolist(),
        "model_actuation_matrix_T_per_A": check.model_actuation_T_per_A.tolist(),
        "background_field_T": check.background_T.tolist(),
        "gain_factors": dict(zip(_AXES, map(float, gains), strict=True)),
        "axis_tilts_deg": dict(zip(_AXES, map(float, tilts), strict=True)),
    }
    if check.measured_T is not None and check.predicted_T is not None:
        res = check.measured_T - check.predicted_T
        out.update(
            rows=len(res),
            residual_rms_T=float(np.sqrt(np.mean(res**2))),
            residual_max_T=float(np.max(np.linalg.norm(res, axis=1))),
        )
    return out
