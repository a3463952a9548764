"""One explicit numpy/CasADi backend: every physics function is written once against this module.

Each function looks at its arguments: if any is a CasADi ``SX``, ``MX`` or ``DM`` it calls the
CasADi function, otherwise the numpy one. Nothing here relies on numpy forwarding ``np.sin`` to
CasADi objects (CasADi 3.8 warns about that), and nothing branches in Python on *data values*:
use :func:`where` (``casadi.if_else``) or a smooth form instead.

Elliptic integrals follow scipy's parameter convention ``m = k**2``. On the numpy path ``ellipk``,
``ellipe`` and ``ellipke`` (both at once, what the field uses) are scipy's Cephes functions
(``ellipkm1`` where the caller has 1 - m exactly); on the CasADi path a fixed-count arithmetic-geometric-mean (AGM)
iteration, which gives exact values and exact derivatives (7 steps reach machine precision for
``m < 1 - 1e-6``, i.e. anywhere not on the wire itself).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any, TypeAlias

import casadi as _ca
import numpy as _np

#: A value a physics function of the optimisation variables accepts and returns: a float, a
#: numpy array (broadcast elementwise) or a CasADi SX/MX/DM. Meant as
#: ``float | numpy.ndarray | casadi.SX | casadi.MX | casadi.DM``; spelled ``Any`` for the type
#: checker because a union cannot say "all SX or all MX", and CasADi's stubs (rightly) reject
#: ``SX * MX``, so every arithmetic expression on the union would be flagged.
Scalar: TypeAlias = Any
#: The numpy-only counterpart (a float or an array), for functions with no CasADi path.
Array: TypeAlias = "float | _np.ndarray"

__all__ = [
    "AGM_STEPS",
    "Array",
    "Scalar",
    "abs",
    "arccos",
    "arcsin",
    "arctan",
    "arctan2",
    "cos",
    "ellipe",
    "ellipk",
    "ellipke",
    "exp",
    "expm1",
    "fmax",
    "fmin",
    "is_casadi",
    "log",
    "log1p",
    "pi",
    "positive_part",
    "positive_part_lifted",
    "sin",
    "softplus",
    "sqrt",
    "sqrt_guarded",
    "square",
    "tan",
    "where",
]

pi = _np.pi
AGM_STEPS = 7
_CASADI_TYPES = (_ca.SX, _ca.MX, _ca.DM)


def is_casadi(*args: Any) -> bool:
    """True if any argument is a CasADi SX, MX or DM value."""
    for a in args:  # a plain loop: called on every backend operation
        if isinstance(a, _CASADI_TYPES):
            return True
    return False


def _unary(np_fn: Any, ca_fn: Any) -> Any:
    def fn(x: Scalar) -> Scalar:
        return ca_fn(x) if isinstance(x, _CASADI_TYPES) else np_fn(x)

    fn.__name__ = np_fn.__name__
    fn.__doc__ = f"Elementwise ``{np_fn.__name__}`` on floats, numpy arrays or CasADi values."
    return fn


sin = _unary(_np.sin, _ca.sin)
cos = _unary(_np.cos, _ca.cos)
tan = _unary(_np.tan, _ca.tan)
arctan = _unary(_np.arctan, _ca.atan)
arcsin = _unary(_np.arcsin, _ca.asin)
arccos = _unary(_np.arccos, _ca.acos)
exp = _unary(_np.exp, _ca.exp)
expm1 = _unary(_np.expm1, _ca.expm1)
log1p = _unary(_np.log1p, _ca.log1p)
log = _unary(_np.log, _ca.log)
sqrt = _unary(_np.sqrt, _ca.sqrt)
abs = _unary(_np.abs, _ca.fabs)
square = _unary(_np.square, lambda x: x * x)


def arctan2(y: Scalar, x: Scalar) -> Scalar:
    """Four-quadrant arctangent ``atan2(y, x)``."""
    return _ca.atan2(y, x) if is_casadi(y, x) else _np.arctan2(y, x)


def where(condition: Scalar, if_true: Scalar, if_false: Scalar) -> Scalar:
    """``condition ? if_true : if_false`` elementwise (``numpy.where`` / ``casadi.if_else``)."""
    if is_casadi(condition, if_true, if_false):
        return _ca.if_else(condition, if_true, if_false)
    return _np.where(condition, if_true, if_false)


def fmax(a: Scalar, b: Scalar) -> Scalar:
    """Elementwise maximum."""
    return _ca.fmax(a, b) if is_casadi(a, b) else _np.maximum(a, b)


def fmin(a: Scalar, b: Scalar) -> Scalar:
    """Elementwise minimum."""
    return _ca.fmin(a, b) if is_casadi(a, b) else _np.minimum(a, b)


#: While an NLP is built: the function that turns ``max(x, 0)`` of a CasADi expression into an
#: epigraph variable (:func:`positive_part_lifted`); None otherwise.
_LIFT: ContextVar[Callable[[Any], Any] | None] = ContextVar("_LIFT", default=None)


def positive_part(x: Scalar) -> Scalar:
    """``max(x, 0)`` elementwise: a contact strain that is zero where there is no contact.

    On numbers it is :func:`fmax`. Inside :func:`positive_part_lifted` (an NLP being built) a
    CasADi expression of the decision variables becomes an epigraph variable ``s >= x, s >= 0``
    (the builder's ``lift``): exact wherever the quantity only costs (a resistive torque grows
    with it and the optimiser pushes ``s`` down onto ``max(x, 0)``), and smooth, so an optimum
    on the kink (a spiral that just stops touching the wall) is a vertex IPOPT converges to
    instead of a corner it cycles around.
    """
    lift = _LIFT.get()
    if lift is not None and is_casadi(x):
        return lift(x)
    return fmax(x, 0.0)


@contextmanager
def positive_part_lifted(lift: Callable[[Any], Any]) -> Iterator[None]:
    """Within the block, :func:`positive_part` of a CasADi expression calls ``lift(x)``."""
    token = _LIFT.set(lift)
    try:
        yield
    finally:
        _LIFT.reset(token)


def sqrt_guarded(x: Scalar) -> Scalar:
    """``sqrt(x)`` for ``x >= 0`` whose derivative stays finite at ``x = 0`` on the CasADi path.

    CasADi differentiates both branches of ``if_else``, so the argument of the square root is
    replaced by 1 where ``x <= 0`` and the result by 0 there. numpy's ``sqrt(0)`` is already 0,
    so the numpy path is a plain square root.
    """
    if is_casadi(x):
        positive = x > 0.0
        return _ca.if_else(positive, _ca.sqrt(_ca.if_else(positive, x, 1.0)), 0.0)
    return _np.sqrt(x)


def softplus(x: Scalar, sharpness: float = 1.0) -> Scalar:
    """Smooth ``max(x, 0)``: ``log(1 + exp(s x)) / s``, overflow-safe on both paths."""
    s = sharpness
    return (fmax(s * x, 0.0) + log(1.0 + exp(-abs(s * x)))) / s


def _agm_K_E(m: Scalar) -> tuple[Scalar, Scalar]:
    """Complete elliptic integrals K(m), E(m) by a fixed-count AGM (CasADi path)."""
    a = 1.0
    b = _ca.sqrt(1.0 - m)
    c_sq_sum = 0.5 * m  # 2**(n-1) c_n**2 at n = 0, c_0**2 = m
    weight = 0.5
    for _ in range(AGM_STEPS):
        c = 0.5 * (a - b)
        a, b = 0.5 * (a + b), _ca.sqrt(a * b)
        weight *= 2.0
        c_sq_sum = c_sq_sum + weight * c * c
    k = _np.pi / (2.0 * a)
    return k, k * (1.0 - c_sq_sum)


def _scipy_special() -> Any:
    """``scipy.special``, imported on first use: about 0.1 s that a command stopped by an input
    error, or one that never takes an elliptic integral, does not pay."""
    from scipy import special

    return special


def ellipk(m: Scalar) -> Scalar:
    """Complete elliptic integral of the first kind K(m), parameter ``m = k**2`` (scipy's)."""
    return _agm_K_E(m)[0] if isinstance(m, _CASADI_TYPES) else _scipy_special().ellipk(m)


def ellipe(m: Scalar) -> Scalar:
    """Complete elliptic integral of the second kind E(m), parameter ``m = k**2`` (scipy's)."""
    return _agm_K_E(m)[1] if isinstance(m, _CASADI_TYPES) else _scipy_special().ellipe(m)


def _ellipke_numpy(m: Any, complement: Any = None) -> tuple[Any, Any]:
    """K and E by scipy's Cephes ``ellipk``/``ellipe``; with ``complement`` (1 - m, given more
    accurately than by subtraction) K by ``ellipkm1``, exact next to m = 1."""
    _special = _scipy_special()
    mm = _np.asarray(m, dtype=float)
    if complement is not None and _np.all(_np.asarray(complement) <= 1.0):
        K = _special.ellipkm1(_np.asarray(complement, dtype=float))
    else:  # m < 0 lies outside ellipkm1's range
        K = _special.ellipk(mm)
    return K, _special.ellipe(mm)


def ellipke(m: Scalar, complement: Any = None) -> tuple[Scalar, Scalar]:
    """Both K(m) and E(m); on the CasADi path they share one AGM iteration.

    On the numpy path scipy's Cephes ``ellipk``/``ellipe`` (``ellipkm1`` when the caller gives
    1 - m). An own log-plus-polynomials pass was 1.3x faster on large arrays but saved 4 % of
    any command (docs/architecture.md): retired.

    Parameters
    ----------
    m : float, array or CasADi
        Parameter m = k², 0 <= m <= 1.
    complement : array, optional
        1 - m when the caller has it more accurately than by subtraction (numpy path; the
        loop field passes alpha²/beta², exact near the wire where m -> 1).
    """
    if isinstance(m, _CASADI_TYPES):
        return _agm_K_E(m)
    return _ellipke_numpy(m, complement)
