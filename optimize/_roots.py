"""Brent's bracketed root of a scalar function, without importing ``scipy.optimize``.

``scipy.optimize`` costs about a quarter of a second to import (it pulls in ``scipy.linalg``,
``scipy.fft`` and the linear-programming solvers); the step-out frequency needs only a root in a
bracket, so ``spiralcap evaluate`` starts faster with this one function.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from spiralcap.core.errors import InputError

__all__ = ["brentq"]


def brentq(
    f: Callable[[float], float],
    a: float,
    b: float,
    xtol: float = 2e-12,
    rtol: float = 8.881784197001252e-16,
    maxiter: int = 100,
) -> float:
    """Root of ``f`` in [a, b], where f(a) and f(b) differ in sign (Brent's method).

    Inverse quadratic interpolation or the secant step when it stays inside the bracket and
    shrinks it fast enough, bisection otherwise (R. P. Brent, *Algorithms for Minimization
    without Derivatives*, Prentice-Hall 1973, ch. 4, procedure *zero*). Stops when the bracket
    is within ``2 (xtol + rtol |x|)``, the tolerance convention of ``scipy.optimize.brentq``.

    Parameters
    ----------
    f : callable
        Continuous function of one float.
    a, b : float
        Bracket ends, f(a) f(b) <= 0.
    xtol, rtol : float
        Absolute and relative tolerance on the root.
    maxiter : int
        Iteration limit (the best estimate so far is returned after it).

    Returns
    -------
    float
        The root.

    Raises
    ------
    InputError
        f(a) and f(b) have the same sign (``bracket``).
    """
    fa, fb = f(a), f(b)
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if (fa > 0.0) == (fb > 0.0):
        raise InputError("bracket", (a, b), "an interval where the function changes sign")
    c, fc = a, fa  # b is the best estimate, c the previous one, a the contrapoint
    d = e = b - a
    for _ in range(maxiter):
        if (fb > 0.0) == (fc > 0.0):  # keep the root between b and c
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        tol = 2.0 * rtol * abs(b) + 0.5 * xtol
        half = 0.5 * (c - b)
        if abs(half) <= tol or fb == 0.0:
            return b
        if abs(e) >= tol and abs(fa) > abs(fb):
            s = fb / fa
            if a == c:  # secant
                p, q = 2.0 * half * s, 1.0 - s
            else:  # inverse quadratic interpolation
                qa, r = fa / fc, fb / fc
                p = s * (2.0 * half * qa * (qa - r) - (b - a) * (r - 1.0))
                q = (qa - 1.0) * (r - 1.0) * (s - 1.0)
            if p > 0.0:
                q = -q
            p = abs(p)
            if 2.0 * p < min(3.0 * half * q - abs(tol * q), abs(e * q)):
                e, d = d, p / q
            else:
                d = e = half
        else:
            d = e = half
        a, fa = b, fb
        b += d if abs(d) > tol else math.copysign(tol, half)
        fb = f(b)
    return b
