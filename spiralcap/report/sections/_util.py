"""Helpers shared by the report sections: numbers from the embedded JSON, names, units."""

from __future__ import annotations

import math
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
        """The value at ``path`` of the embedded JSON, shown times ``scale`` with ``unit``
        (:data:`NO_CONTACT` for a margin the model does not have: no contact)."""
        if self._unbounded(path):
            return Num("unbounded", key=None, unit=unit)
        if self._flag(path, "_undefined") or (
            path.endswith(_NO_CONTACT_FIELDS) and lookup(self.payload, path) is None
        ):  # the embedded JSON holds a NaN as None
            return Num(NO_CONTACT, key=None)
        return Num(lookup(self.payload, path), key=path, scale=scale, unit=unit)

    def value(self, path: str) -> Any:
        """The raw value at ``path`` of the embedded JSON ("unbounded" for an absent number
        whose ``<path>_unbounded`` flag is set, NaN for one whose ``<path>_undefined`` flag is,
        see ``spiralcap.serialize``)."""
        if self._unbounded(path):
            return "unbounded"
        if self._flag(path, "_undefined"):
            return math.nan
        return lookup(self.payload, path)

    def _flag(self, path: str, suffix: str) -> bool:
        try:
            lookup(self.payload, path)
            return False
        except KeyError:
            try:
                return lookup(self.payload, path + suffix) is True
            except KeyError:
                return False

    @property
    def feasible(self) -> bool:
        """Whether the optimisation found a feasible design."""
        return self.payload.get("optimize", {}).get("status") == "optimal"

    @property
    def optimum(self) -> str:
        """What the optimiser's design is called: ``optimum``, or ``closest design`` when no
        design is feasible (the one the shortfalls are stated at)."""
        return "optimum" if self.feasible else "closest design"

    def _unbounded(self, path: str) -> bool:
        try:
            lookup(self.payload, path)
            return False
        except KeyError:
            try:
                return lookup(self.payload, path + "_unbounded") is True
            except KeyError:
                return False

    def shown(self, path: str, unit: str) -> Num:
        """A value in SI ``unit`` at ``path``, shown in its engineering unit (T -> mT)."""
        label, factor = SHOWN_UNITS.get(unit, (unit, 1.0))
        return self.num(path, factor, label)


#: A margin, safety factor or step-out the model does not have (the spiral does not touch).
NO_CONTACT = "none (no contact with the wall)"
#: The fields that are NaN (None in the report's JSON) exactly where there is no contact.
_NO_CONTACT_FIELDS = ("margin_Nm", "safety_factor", "step_out_frequency_hz")


def step_out_parts(ctx: Context, path: str) -> list[Any]:
    """A step-out frequency as inline content, worded for the two edge cases.

    ``optimize.step_out_frequency_hz`` searches a bounded range; the sibling ``step_out_bound``
    says ``"above_search_range"`` when the margin stays positive to its top (the value is that
    top) and ``"below_search_range"`` when it is negative at every frequency.
    """
    value = ctx.value(path)
    bound = ctx.value(path.rpartition(".")[0] + ".step_out_bound")
    if bound == "no_contact":
        return ["no frequency (no contact with the wall: no margin)"]
    if bound == "above_search_range":
        return [f"no frequency up to {value:g} Hz (the margin stays positive)"]
    if bound == "below_search_range":
        return ["every frequency (the margin is negative even at the lowest)"]
    return [ctx.num(path, unit="Hz")]
