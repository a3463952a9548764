"""Helpers shared by the report sections: numbers from the embedded JSON, names, units."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from spiralcap.presentation import SHOWN_UNITS, readable
from spiralcap.report.numbers import Num, lookup

__all__ = ["SHOWN_UNITS", "Context", "readable", "step_out_parts"]


@dataclass(frozen=True)
class Context:
    """What every section reads: the collected data and the JSON embedded in the HTML."""

    data: Any
    payload: Mapping[str, Any]

    def num(self, path: str, scale: float = 1.0, unit: str = "") -> Num:
        """The value at ``path`` of the embedded JSON, shown times ``scale`` with ``unit``."""
        return Num(lookup(self.payload, path), key=path, scale=scale, unit=unit)

    def value(self, path: str) -> Any:
        """The raw value at ``path`` of the embedded JSON."""
        return lookup(self.payload, path)

    def shown(self, path: str, unit: str) -> Num:
        """A value in SI ``unit`` at ``path``, shown in its engineering unit (T -> mT)."""
        label, factor = SHOWN_UNITS.get(unit, (unit, 1.0))
        return self.num(path, factor, label)


def step_out_parts(ctx: Context, path: str) -> list[Any]:
    """A step-out frequency as inline content, worded for the two edge cases.

    ``optimize.step_out_frequency_hz`` searches up to 200 Hz: infinity (JSON ``"inf"``) means
    the margin stays positive that far; 0 means it is negative at every frequency.
    """
    value = ctx.value(path)
    if value == "inf":
        return ["no frequency up to 200 Hz (the margin stays positive)"]
    if value == 0:
        return ["every frequency (the margin is negative even at the lowest)"]
    return [ctx.num(path, unit="Hz")]
