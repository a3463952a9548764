"""The public API refuses nonsense: argument checks at the entry points of the domain packages.

A public function of ``coils``, ``capsule``, ``torque_model`` or ``optimize`` is wrapped with
:func:`guard`, which checks each named physical argument (finite, sign, type) and raises
:class:`~spiralcap.core.errors.InputError` (a ``ValueError``) or ``TypeError`` naming the
argument, its value and what is allowed.

The same checks serve numpy and CasADi: a CasADi ``SX``/``MX`` value is symbolic and passes
unchecked (there is nothing concrete to check, and no Python ``if`` may look at its value); a
``DM`` is checked as the numbers it holds. A call from inside the domain packages themselves is
not checked again (its arguments were checked where they entered, and intermediate arrays may
carry a NaN on purpose, a pair that runs away thermally): the wrapper looks at its caller's
module once and steps aside, so building and solving an NLP costs nothing extra.
"""

from __future__ import annotations

import functools
import inspect
import math
import numbers
import sys
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ParamSpec, TypeVar

import numpy as np

from spiralcap.core.errors import InputError

__all__ = [
    "Spec",
    "angle",
    "choice",
    "fields",
    "finite",
    "guard",
    "instance",
    "is_symbolic",
    "nonnegative",
    "positive",
    "positive_finite",
    "satisfies",
    "temperature",
    "unit_interval",
]

P = ParamSpec("P")
R = TypeVar("R")

#: Callers inside these packages are trusted (their arguments were checked on the way in).
DOMAIN_PACKAGES = ("coils", "capsule", "torque_model", "optimize")

#: Largest magnitude of any number, in its SI unit: no quantity of a capsule, a coil or a
#: tissue comes near it (the stiffest dashpot the tests probe is 1.2e24 Pa·s), and beyond it the
#: physics' powers and exponentials overflow to inf or NaN (1e308 is finite, its square is not).
MAX_MAGNITUDE = 1e30

#: Absolute zero, °C: the lowest temperature a ``*_C`` argument may have.
ABSOLUTE_ZERO_C = -273.15


def is_symbolic(value: Any) -> bool:
    """Whether ``value`` is a CasADi ``SX`` or ``MX`` (a symbol, checked nowhere here)."""
    mod = type(value).__module__
    return mod.startswith("casadi") and type(value).__name__ in ("SX", "MX")


def _numbers(name: str, value: Any) -> np.ndarray | None:
    """``value`` as a float array, None if symbolic; TypeError if it is not real numbers."""
    if is_symbolic(value):
        return None
    if isinstance(value, (bool, np.bool_, str, bytes)) or value is None:
        raise TypeError(f"{name} = {value!r}: a real number (or an array of them) is needed")
    if type(value).__module__.startswith("casadi"):  # DM: concrete numbers
        value = np.asarray(value.full() if hasattr(value, "full") else value)
    if isinstance(value, numbers.Real):
        try:
            return np.asarray(float(value))
        except OverflowError:  # an int too large for a float
            return np.asarray(math.inf)
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError):
        arr = np.asarray(None)
    if arr.dtype.kind not in "iuf" or arr.dtype == np.bool_:
        raise TypeError(f"{name} = {_short(value)}: a real number (or an array of them) is needed")
    return arr if arr.dtype.kind == "f" else arr.astype(float)


def _short(value: Any) -> str:
    text = repr(value).replace("\n", " ")
    return text if len(text) <= 120 else text[:117] + "..."


@dataclass(frozen=True)
class Spec:
    """What one numeric argument may be: finite, and inside ``(low, high)`` or ``[low, high]``.

    Attributes
    ----------
    low, high : float or None
        Bounds (None: unbounded on that side), in the argument's own unit.
    low_open, high_open : bool
        Whether the bound itself is excluded.
    optional : bool
        Whether ``None`` is accepted (the function then takes its default).
    scalar : bool
        Whether only one number is accepted (not an array).
    """

    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    optional: bool = False
    scalar: bool = False

    def allowed(self) -> str:
        """The rule in words: ``a finite number > 0 and <= 1e+30``."""
        parts = []
        if self.low is not None:
            parts.append(f"{'>' if self.low_open else '>='} {self.low:g}")
        elif self.high is not None:
            parts.append(f">= {-MAX_MAGNITUDE:g}")
        if self.high is not None:
            parts.append(f"{'<' if self.high_open else '<='} {self.high:g}")
        elif self.low is not None:
            parts.append(f"<= {MAX_MAGNITUDE:g}")
        words = "a finite number " + (
            " and ".join(parts) if parts else f"of magnitude <= {MAX_MAGNITUDE:g}"
        )
        return words + (" (or None)" if self.optional else "")

    def _number_ok(self, v: float) -> bool:
        if not (math.isfinite(v) and abs(v) <= MAX_MAGNITUDE):
            return False
        if self.low is not None and not (v > self.low if self.low_open else v >= self.low):
            return False
        return self.high is None or (v < self.high if self.high_open else v <= self.high)

    def check(self, name: str, value: Any) -> None:
        """Raise InputError (ValueError) or TypeError if ``value`` breaks the rule."""
        if value is None and self.optional:
            return
        if type(value) is float or type(value) is int:  # the common case, without numpy
            try:
                number = float(value)
            except OverflowError:  # an int too large for a float: not a finite number
                number = math.inf
            if self._number_ok(number):
                return
            raise InputError(name, value, self.allowed())
        arr = _numbers(name, value)
        if arr is None:
            return
        if self.scalar and arr.ndim != 0:
            raise TypeError(f"{name} = {_short(value)}: one number is needed, not an array")
        # the least and the largest element decide (NaN propagates through both)
        ok = not arr.size or (
            self._number_ok(float(arr.min())) and self._number_ok(float(arr.max()))
        )
        if not ok:
            raise InputError(name, value if arr.ndim == 0 else _Shown(value), self.allowed())


class _Shown:
    """An array shown short in an error message."""

    def __init__(self, value: Any) -> None:
        self.value = value

    def __repr__(self) -> str:
        return _short(np.asarray(self.value).tolist())


def finite(optional: bool = False, scalar: bool = False) -> Spec:
    """Any finite number."""
    return Spec(optional=optional, scalar=scalar)


def positive(optional: bool = False, scalar: bool = False) -> Spec:
    """A finite number > 0 (a length, a frequency, a mass, a moment)."""
    return Spec(low=0.0, low_open=True, optional=optional, scalar=scalar)


def nonnegative(optional: bool = False, scalar: bool = False) -> Spec:
    """A finite number >= 0 (a load, a current amplitude, a power)."""
    return Spec(low=0.0, optional=optional, scalar=scalar)


def unit_interval(optional: bool = False, scalar: bool = False) -> Spec:
    """A finite number in [0, 1] (an efficiency, a fraction)."""
    return Spec(low=0.0, high=1.0, optional=optional, scalar=scalar)


def angle(optional: bool = False, scalar: bool = False) -> Spec:
    """A helical angle, rad: strictly between 0 and pi/2."""
    return Spec(
        low=0.0, high=math.pi / 2, low_open=True, high_open=True, optional=optional, scalar=scalar
    )


def temperature(optional: bool = False, scalar: bool = False) -> Spec:
    """A temperature, °C: finite and above absolute zero."""
    return Spec(low=ABSOLUTE_ZERO_C, low_open=True, optional=optional, scalar=scalar)


@dataclass(frozen=True)
class _Instance:
    kind: type | tuple[type, ...]
    words: str
    optional: bool = False

    def check(self, name: str, value: Any) -> None:
        if value is None and self.optional:
            return
        if not isinstance(value, self.kind):
            raise TypeError(f"{name} = {_short(value)}: {self.words} is needed")


@dataclass(frozen=True)
class _Choice:
    values: tuple[str, ...]

    def check(self, name: str, value: Any) -> None:
        if not isinstance(value, str):
            raise TypeError(f"{name} = {_short(value)}: one of {', '.join(self.values)} is needed")
        if value not in self.values:
            raise InputError(name, value, "one of " + ", ".join(self.values))


def choice(*values: str) -> _Choice:
    """One of the strings ``values`` (a mode, a kind)."""
    return _Choice(tuple(values))


@dataclass(frozen=True)
class _Fields:
    fields: tuple[tuple[str, Spec], ...]
    words: str

    def check(self, name: str, value: Any) -> None:
        missing = [f for f, _ in self.fields if not hasattr(value, f)]
        if missing:
            raise TypeError(f"{name} = {_short(value)}: {self.words} is needed")
        for f, spec in self.fields:
            spec.check(f"{name}.{f}", getattr(value, f))


def fields(words: str, **specs: Spec) -> _Fields:
    """An object with these numeric attributes, each checked by its rule (a duck type: a
    ``torque_model.TissueParameters`` or the arrays of one, ``optimize.uncertainty``)."""
    return _Fields(tuple(specs.items()), words)


@dataclass(frozen=True)
class _Custom:
    test: Callable[[str, Any], None]

    def check(self, name: str, value: Any) -> None:
        self.test(name, value)


def satisfies(test: Callable[[str, Any], None]) -> _Custom:
    """A rule written as a function ``test(name, value)`` that raises (an object whose numbers
    are checked field by field, ``optimize.system.check_model``)."""
    return _Custom(test)


def instance(kind: type | tuple[type, ...], words: str, optional: bool = False) -> _Instance:
    """An object of ``kind`` (``words``: what it is, e.g. ``"an optimize.DesignModel"``)."""
    return _Instance(kind, words, optional)


def positive_finite(name: str, value: Any) -> float:
    """``value`` as a float if it is a finite real number > 0, else InputError/TypeError."""
    positive().check(name, value)
    return float(value)


def _trusted_caller(depth: int = 2) -> bool:
    """Whether the function's caller is a module of a domain package (then it is not checked)."""
    try:
        caller = sys._getframe(depth).f_globals.get("__name__", "")
    except ValueError:  # no such frame
        return False
    return caller.split(".", 1)[0] in DOMAIN_PACKAGES


#: What :func:`guard` takes for an argument: a numeric rule or an object's.
Rule = Spec | _Instance | _Choice | _Fields | _Custom


def guard(**specs: Rule) -> Callable[[Callable[P, R]], Callable[P, R]]:
    """Check the named arguments of a public function before it runs (see the module notes).

    Parameters
    ----------
    **specs : Spec or instance(...)
        Argument name -> its rule (:func:`positive`, :func:`angle`, :func:`instance`, ...).
    """

    def wrap(fn: Callable[P, R]) -> Callable[P, R]:
        params = list(inspect.signature(fn).parameters.values())
        missing = set(specs) - {p.name for p in params}
        if missing:
            raise TypeError(f"guard on {fn.__qualname__}: no argument {sorted(missing)}")
        # where each checked argument sits: its position (None: keyword only) and its rule; an
        # argument left at its default is not checked (the defaults are the package's own)
        where = [
            (p.name, None if p.kind is p.KEYWORD_ONLY else i, specs[p.name])
            for i, p in enumerate(params)
            if p.name in specs
        ]

        @functools.wraps(fn)
        def checked(*args: P.args, **kwargs: P.kwargs) -> R:
            if not _trusted_caller():
                for name, pos, spec in where:
                    if name in kwargs:
                        spec.check(name, kwargs[name])
                    elif pos is not None and pos < len(args):
                        spec.check(name, args[pos])
            return fn(*args, **kwargs)

        return checked

    return wrap
