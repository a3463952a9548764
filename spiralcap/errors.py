"""Errors that reach the user as one line: the key, the value given, and what is allowed."""

from __future__ import annotations

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
    """

    def __init__(self, key: str, value: Any, allowed: str) -> None:
        self.key, self.value, self.allowed = key, value, allowed
        super().__init__(f"{key} = {value!r}: {allowed}")


class DataError(SpiralcapError, ValueError):
    """A data file (CSV of bench measurements, design TOML) cannot be read as it stands."""


def check_positive(key: str, value: Any, *, allow_zero: bool = False) -> float:
    """Return ``value`` as a float if it is a finite number > 0 (or >= 0), else raise InputError."""
    import math

    ok = isinstance(value, (int, float)) and not isinstance(value, bool)
    if ok:
        value = float(value)
        ok = math.isfinite(value) and (value >= 0 if allow_zero else value > 0)
    if not ok:
        allowed = "a finite number >= 0" if allow_zero else "a finite number > 0"
        raise InputError(key, value, allowed)
    return value
