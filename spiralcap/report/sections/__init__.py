"""The report's sections, one module each; :func:`build_sections` puts them in order."""

from __future__ import annotations

from spiralcap.report.document import Section
from spiralcap.report.sections import (
    assumptions,
    calibration,
    coils,
    comparison,
    conclusion,
    inputs,
    margin,
    optimum,
    reproducibility,
    summary,
    tissue,
    tradeoffs,
    uncertainty,
)
from spiralcap.report.sections._util import Context

__all__ = ["Context", "build_sections"]


def build_sections(ctx: Context, command: str) -> list[Section]:
    """Every section of the report, in reading order (the comparison only when asked for, the
    tissue uncertainty only when the design has one)."""
    compared = comparison.build(ctx)
    uncertain = uncertainty.build(ctx, getattr(ctx.data, "uncertainty", None))
    check = calibration.calibration_check(ctx.data.design, ctx.data.model)
    calibrated = calibration.build(ctx, check)
    return [
        summary.build(ctx),
        inputs.build(ctx),
        coils.build(ctx),
        *([calibrated] if calibrated is not None else []),
        tissue.build(ctx),
        margin.build(ctx),
        *([uncertain] if uncertain is not None else []),
        optimum.build(ctx),
        tradeoffs.build(ctx),
        *([compared] if compared is not None else []),
        conclusion.build(ctx),
        assumptions.build(ctx),
        reproducibility.build(ctx, command),
        inputs.build_appendix(ctx),
    ]
