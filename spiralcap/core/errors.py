"""Errors that reach the user as one line: the key, the value given, and what is allowed."""

from __future__ import annotations

import math
from typing import Any


class SpiralcapError(Exception):
    """Base for every error the CLI turns into a one-line message and exit status 2."""

    exit_status = 2


class InputError(SpiralcapError, ValueError):
    """A named input has a value outside what is allowed.

    Parameters
    ----------
    key : str
        The design key (``coils.x.radius_m``) or parameter name (``radius_m``) at fault.
    value : Any
        The value that was given.
    allowed : str
        What would have been accepted, in words (``"a finite number > 0"``).
    where : str, optional
        The file and line the value came from (``base.toml line 12``), put first.
    """

    def __init__(self, key: str, value: Any, allowed: str, where: str | None = None) -> None:
        self.key, self.value, self.allowed, self.where = key, value, allowed, where
        shown = _short_repr(value)
        named = short_text(str(key), 120)
        super().__init__(f"{where + ': ' if where else ''}{named} = {shown}: {allowed}")

    def __reduce__(self) -> tuple[Any, ...]:
        # rebuilt from its fields, so it crosses to and from worker processes whole
        return (type(self), (self.key, self.value, self.allowed, self.where))


def _short_repr(value: Any, limit: int = 240) -> str:
    """``repr`` of a value cut to ``limit`` characters, so an error stays one short line."""
    try:
        text = repr(value)
    except ValueError:  # an int too long to print
        return "<a number too long to show>"
    text = text.replace("\n", " ")
    return text if len(text) <= limit else text[: limit - 3] + "..."


def short_text(text: str, limit: int = 120) -> str:
    """``text`` cut in the middle to at most ``limit`` characters (``coils.x.aaa...zzz.turns``),
    so a long key stays recognisable by both ends and an error stays one short line.

    Parameters
    ----------
    text : str
        A key or name as given.
    limit : int
        Most characters kept, the ``...`` included.
    """
    if len(text) <= limit:
        return text
    head = (limit - 3) * 2 // 3
    return text[:head] + "..." + text[len(text) - (limit - 3 - head) :]


class DataError(SpiralcapError, ValueError):
    """A data file (CSV of bench measurements, design TOML) cannot be read as it stands."""


def csv_number(raw: str, column: str, where: str) -> float:
    """One CSV cell as a finite float, else a DataError naming the line and column (an empty
    cell, a cell that is not a number, an infinity or NaN); the cell's own range is the
    caller's to check.

    Parameters
    ----------
    raw : str
        The cell as read.
    column : str
        Its column's name.
    where : str
        The file and line, for the message (``bench.csv, line 3``).

    Returns
    -------
    float
        The value, in the unit the column's name carries.

    Examples
    --------
    >>> csv_number("0.5", "frequency_hz", "b.csv, line 2")
    0.5
    """
    if raw == "":
        raise DataError(f"{where}, column {column}: empty cell")
    try:
        value = float(raw)
    except ValueError:
        raise DataError(
            f"{where}, column {column}: {_short_repr(raw, 62)} is not a number"
        ) from None
    if not math.isfinite(value):
        raise DataError(f"{where}, column {column}: {raw!r} is not a finite number")
    return value


def check_positive(key: str, value: Any, *, allow_zero: bool = False) -> float:
    """Return ``value`` as a float if it is a finite real number > 0 (or >= 0), else raise
    InputError (numpy scalars included; an integer too large for a float is not finite)."""
    import math
    import numbers

    ok = isinstance(value, numbers.Real) and not isinstance(value, bool)
    if ok:
        try:
            number = float(value)
        except OverflowError:
            number = math.inf
        ok = math.isfinite(number) and (number >= 0 if allow_zero else number > 0)
    if not ok:
        allowed = "a finite number >= 0" if allow_zero else "a finite number > 0"
        raise InputError(key, value, allowed)
    return number
