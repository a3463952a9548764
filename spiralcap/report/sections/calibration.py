"""The calibration section: how the lab's coils, as surveyed, differ from the modelled ones.

Only for a design with a ``[calibration]`` table (``spiralcap calibrate -o``). The survey named
by ``calibration.survey_csv`` is read again and the calibrated model, b0 + sum M_k G_k(p) I_k
(the coils the whole report uses), is checked against every row: residual RMS and largest
residual, and a plot of measured against modelled field. Without the survey file the section
says so and shows the calibration alone.
"""

from __future__ import annotations

from typing import Any

from spiralcap.analysis.calibration import CalibrationCheck, calibration_check, payload
from spiralcap.report.document import Cell, FigureBlock, Paragraph, Ref, Section, Strong, Table
from spiralcap.report.sections._util import Context

__all__ = ["build", "calibration_check", "payload"]

_AXES = ("x", "y", "z")


def _draw(check: CalibrationCheck) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.api import calibration_residuals

        calibration_residuals(check, fig=fig)

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
