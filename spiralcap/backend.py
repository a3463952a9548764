"""One explicit numpy/CasADi backend: every physics function is written once against this module.

Each function looks at its arguments: if any is a CasADi ``SX``, ``MX`` or ``DM`` it calls the
CasADi function, otherwise the numpy one. Nothing here relies on numpy forwarding ``np.sin`` to
CasADi objects (CasADi 3.8 warns about that), and nothing branches in Python on *data values*:
use :func:`where` (``casadi.if_else``) or a smooth form instead.

Elliptic integrals follow scipy's parameter convention ``m = k**2``. On the numpy path they are
scipy's ``ellipk``/``ellipe``; on the CasADi path a fixed-count arithmetic-geometric-mean (AGM)
iteration, which gives exact values and exact derivatives (7 steps reach machine precision for
``m < 1 - 1e-6``, i.e. anywhere not on the wire itself).
"""

from __future__ import annotations

from typing import Any, TypeAlias

import casadi as _ca
import numpy as _np
from scipy import special as _special

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
    "exp",
    "fmax",
    "fmin",
    "is_casadi",
    "log",
    "pi",
    "sin",
    "softplus",
    "sqrt",
    "square",
    "tan",
    "where",
]

pi = _np.pi
AGM_STEPS = 7
_CASADI_TYPES = (_ca.SX, _ca.MX, _ca.DM)


def is_casadi(*args: Any) -> bool:
    """True if any argument is a CasADi SX, MX or DM value."""
    return any(isinstance(a, _CASADI_TYPES) for a in args)


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


def ellipk(m: Scalar) -> Scalar:
    """Complete elliptic integral of the first kind K(m), parameter ``m = k**2`` (scipy's)."""
    return _agm_K_E(m)[0] if isinstance(m, _CASADI_TYPES) else _special.ellipk(m)


def ellipe(m: Scalar) -> Scalar:
    """Complete elliptic integral of the second kind E(m), parameter ``m = k**2`` (scipy's)."""
    return _agm_K_E(m)[1] if isinstance(m, _CASADI_TYPES) else _special.ellipe(m)


def ellipke(m: Scalar, out: tuple[_np.ndarray, _np.ndarray] | None = None) -> tuple[Scalar, Scalar]:
    """Both K(m) and E(m); on the CasADi path they share one AGM iteration.

    On the numpy path they are scipy's Cephes ``ellipk`` and ``ellipe`` (each a polynomial pair
    and a logarithm, 2.5e-16 relative); ``out`` = (K, E) arrays to write them into. A shared
    numpy AGM or Carlson pass was measured slower than the two compiled calls (about 1.2x at
    7 steps, 10^6 values), so they stay separate on this path.
    """
    if isinstance(m, _CASADI_TYPES):
        return _agm_K_E(m)
    if out is None:
        return _special.ellipk(m), _special.ellipe(m)
    return _special.ellipk(m, out=out[0]), _special.ellipe(m, out=out[1])


__all__.append("ellipke")
