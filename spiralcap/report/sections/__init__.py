"""The report's sections, one module each; :func:`build_sections` puts them in order."""

from __future__ import annotations

from spiralcap.report.document import Section
from spiralcap.report.sections import (
    assumptions,
    coils,
    inputs,
    margin,
    optimum,
    reproducibility,
    summary,
    tissue,
    tradeoffs,
)
from spiralcap.report.sections._util import Context

__all__ = ["Context", "build_sections"]


def build_sections(ctx: Context, command: str) -> list[Section]:
    """Every section of the report, in reading order."""
    return [
        summary.build(ctx),
        inputs.build(ctx),
        coils.build(ctx),
        tissue.build(ctx),
        margin.build(ctx),
        optimum.build(ctx),
        tradeoffs.build(ctx),
        assumptions.build(ctx),
        reproducibility.build(ctx, command),
    ]
