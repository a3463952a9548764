"""The calibration section: how the lab's coils, as surveyed, differ from the modelled ones.

Only for a design with a ``[calibration]`` table (``spiralcap calibrate -o``). The survey named
by ``calibration.survey_csv`` is read again and the calibrated model, b0 + sum M_k G_k(p) I_k
(the coils the whole report uses), is checked against every row: residual RMS and largest
residual, and a plot of measured against modelled field. Without the survey file the section
says so and shows the calibration alone.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from spiralcap.report.document import Cell, FigureBlock, Paragraph, Ref, Section, Strong, Table
from spiralcap.report.sections._util import Context

__all__ = ["CalibrationCheck", "build", "calibration_check", "payload"]

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


def _draw(check: CalibrationCheck) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.style import COLOURS, MARKERS

        measured = np.asarray(check.measured_T) * 1e3
        predicted = np.asarray(check.predicted_T) * 1e3
        left, right = fig.subplots(1, 2)
        lo, hi = (
            float(min(measured.min(), predicted.min())),
            float(max(measured.max(), predicted.max())),
        )
        left.plot([lo, hi], [lo, hi], color="0.5", linewidth=1.0, label="model = measured")
        for c, ax in enumerate(_AXES):
            left.plot(
                predicted[:, c],
                measured[:, c],
                linestyle="none",
                marker=MARKERS[c],
                markersize=3.5,
                color=COLOURS[c],
                label=f"B{ax}",
            )
            right.plot(
                np.linalg.norm(measured, axis=1),
                (measured[:, c] - predicted[:, c]) * 1e3,
                linestyle="none",
                marker=MARKERS[c],
                markersize=3.5,
                color=COLOURS[c],
                label=f"B{ax}",
            )
        left.set_xlabel("calibrated model (mT)")
        left.set_ylabel("measured (mT)")
        left.legend(fontsize=7.5, loc="upper left")
        right.axhline(0.0, color="0.5", linewidth=1.0)
        right.set_xlabel("|B| measured (mT)")
        right.set_ylabel("measured − model (µT)")

    return draw


def _actuation_table(ctx: Context) -> Table:
    rows: list[list[Cell]] = []
    for k, ax in enumerate(_AXES):
        col = [ctx.num(f"calibration.actuation_matrix_T_per_A.{c}.{k}", 1e3) for c in range(3)]
        rows.append(
            [
                f"{ax} pair",
                *col,
                ctx.num(f"calibration.gain_factors.{ax}"),
                ctx.num(f"calibration.axis_tilts_deg.{ax}", unit="°"),
            ]
        )
    return Table(
        ["pair", "Bx per A (mT/A)", "By per A (mT/A)", "Bz per A (mT/A)", "gain", "tilt"],
        rows,
        caption="Calibrated field per ampere at the centre (the columns of the actuation matrix "
        "the current allocation inverts), the gain against the modelled pair and the tilt of "
        "its field from the modelled direction.",
    )


def build(ctx: Context, check: CalibrationCheck | None) -> Section | None:
    """The calibration section (None for a design without a calibration)."""
    if check is None:
        return None
    c = "calibration"
    blocks: list[Any] = [
        Paragraph(
            [
                "The design carries a calibration of the lab's coils (",
                "spiralcap calibrate",
                "): each pair's field per ampere is its modelled field times a fitted 3 × 3 map "
                "near the identity, and the survey saw a background field of (",
                ctx.num(f"{c}.background_field_T.0", 1e6),
                ", ",
                ctx.num(f"{c}.background_field_T.1", 1e6),
                ", ",
                ctx.num(f"{c}.background_field_T.2", 1e6),
                ") µT. Every number of this report uses the calibrated coils: the currents "
                "invert the calibrated actuation matrix, so the field turns circularly about "
                "each heading in the real coils, and the waveforms cancel the background.",
            ]
        ),
        _actuation_table(ctx),
    ]
    if check.measured_T is None:
        reason = check.problem or "the design names no calibration.survey_csv"
        blocks.append(
            Paragraph(
                [Strong("Survey not checked. "), f"The survey could not be read: {reason}."],
                kind="note",
            )
        )
        return Section("calibration", "Coil calibration", blocks)
    blocks += [
        Paragraph(
            [
                Strong("Residuals. "),
                "Over the ",
                ctx.num(f"{c}.rows"),
                " rows of the survey (",
                check.survey,
                ") the calibrated model leaves a residual of ",
                ctx.num(f"{c}.residual_rms_T", 1e6, "µT"),
                " RMS per component, at most ",
                ctx.num(f"{c}.residual_max_T", 1e6, "µT"),
                " in magnitude (",
                Ref("fig-calibration"),
                ").",
            ]
        ),
        FigureBlock(
            "fig-calibration",
            "Left: measured field against the calibrated model, every survey row and component "
            "(mT; grey: equality). Right: measured minus model (µT) against the measured |B|: "
            "scatter without a trend is probe noise, a trend with |B| a gain the maps missed.",
            _draw(check),
            size_in=(7.5, 3.3),
        ),
    ]
    return Section("calibration", "Coil calibration", blocks)
