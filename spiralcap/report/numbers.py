"""How the report writes numbers and units: 4 significant figures, units read off key names.

One formatter serves the HTML, the PDF and the tests, so a number in the report can be checked
against the JSON the CLI prints: ``fmt(value * scale)`` of the CLI's value is the text shown.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from spiralcap.presentation import unit_of_key

__all__ = ["SIGNIFICANT_FIGURES", "Num", "fmt", "lookup", "unit_gap", "unit_of_key"]

#: Significant figures of every number in the report (the CLI tables use the same 4).
SIGNIFICANT_FIGURES = 4


def fmt(value: Any, digits: int = SIGNIFICANT_FIGURES) -> str:
    """A number to ``digits`` significant figures, positional unless very large or small.

    Parameters
    ----------
    value : float, int, bool, str or None
        What to write. Booleans become ``yes``/``no``, None and NaN an em dash, infinities
        ``∞``; strings pass through unchanged.
    digits : int
        Significant figures (default 4).

    Returns
    -------
    str
        E.g. ``fmt(0.0012345) == '0.001234'``, ``fmt(12345.0) == '12340'``,
        ``fmt(1.5e-9) == '1.5e-09'``.
    """
    if isinstance(value, bool):
        return "yes" if value else "no"
    if value is None:
        return "—"
    if isinstance(value, str):
        return value
    if hasattr(value, "item"):
        value = value.item()
    if isinstance(value, int):
        return str(value)
    v = float(value)
    if math.isnan(v):
        return "—"
    if math.isinf(v):
        return "∞" if v > 0 else "-∞"
    if v == 0.0:
        return "0"  # also -0.0, and tiny negatives rounded away never reach here
    s = f"{v:.{digits}g}"
    if s.startswith("-") and float(s) == 0.0:
        return "0"
    if "e" in s and 1e-4 <= abs(v) < 1e7:
        r = float(s)
        s = str(int(r)) if r == int(r) else f"{r:f}".rstrip("0")
    return s


@dataclass(frozen=True)
class Num:
    """A number shown in the report, tied to the JSON value it comes from.

    Parameters
    ----------
    value : float
        The value in the unit of its JSON source (SI, as the CLI prints it).
    key : str or None
        Dotted path of the value in the report's embedded JSON (``optimize.margin_Nm``,
        ``optimize.binding_limits.0.gain_per_unit``); None for numbers with no JSON source
        (design inputs, which are shown as given).
    scale : float
        Factor from the JSON unit to the shown unit (1e3 for N·m -> mN·m).
    unit : str
        Unit written after the number (may be empty).
    """

    value: Any
    key: str | None = None
    scale: float = 1.0
    unit: str = ""

    @property
    def shown(self) -> Any:
        """The value in the shown unit (``value * scale`` for numbers)."""
        v = self.value
        if isinstance(v, (int, float)) and not isinstance(v, bool) and self.scale != 1.0:
            return v * self.scale
        return v

    @property
    def text(self) -> str:
        """The number as written, without the unit."""
        return fmt(self.shown)

    @property
    def unit_shown(self) -> str:
        """The unit as written after this number: a count of one is singular (``1 turn``)."""
        from spiralcap.presentation import COUNT_UNITS

        return COUNT_UNITS.get(self.unit, self.unit) if self.text == "1" else self.unit

    def __str__(self) -> str:
        return f"{self.text}{unit_gap(self.unit)}{self.unit_shown}"


def unit_gap(unit: str) -> str:
    """The space between a number and its unit: none before ``°`` or an empty unit."""
    return "" if unit in ("", "°") else " "


def lookup(data: Any, path: str) -> Any:
    """The value at dotted ``path`` in nested dicts and lists (list items by index).

    Raises
    ------
    KeyError
        When a step of the path does not exist.
    """
    node = data
    for part in path.split("."):
        if isinstance(node, list):
            node = node[int(part)]
        elif isinstance(node, dict) and part in node:
            node = node[part]
        else:
            raise KeyError(path)
    return node
