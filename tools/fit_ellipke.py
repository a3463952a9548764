"""Fit the coefficients of ``spiralcap.backend._KE_COEFFS`` (needs mpmath, not a dependency).

K(m) = P_K(x) - ln(x) Q_K(x) and E(m) = P_E(x) - ln(x) x Q'_E(x), x = 1 - m, with P and Q
polynomials of degree 10: the form of the expansions about m = 1 (Abramowitz & Stegun
17.3.34 and 17.3.36), with coefficients fitted here by weighted least squares in relative error,
in 40-digit arithmetic, on 300 Chebyshev nodes of x in [0, 1] plus x = 1e-3 ... 1e-16. Prints
the largest relative error of the double-precision coefficients against mpmath on 2,200 check
points, then the coefficients (x^0 first; for E the log part starts at x^1).

Run: python tools/fit_ellipke.py [degree]
"""

from __future__ import annotations

import sys

import mpmath as mp
import numpy as np

mp.mp.dps = 40


def _K(x: mp.mpf) -> mp.mpf:
    return mp.ellipk(1 - x)


def _E(x: mp.mpf) -> mp.mpf:
    return mp.ellipe(1 - x)


def _nodes(n: int = 300) -> list[mp.mpf]:
    cheb = [(1 - mp.cos(mp.pi * (i + mp.mpf(1) / 2) / n)) / 2 for i in range(n)]
    return sorted(set(cheb + [mp.mpf(10) ** (-k) for k in range(3, 17)]))


def fit(f, degree: int, log_start: int) -> list[float]:
    """Coefficients [P_0..P_d, Q_start..Q_d] minimising the summed squared relative error."""
    xs = _nodes()
    rows, rhs = [], []
    for x in xs:
        w = 1 / abs(f(x))
        rows.append(
            [w * x**k for k in range(degree + 1)]
            + [-w * mp.log(x) * x**k for k in range(log_start, degree + 1)]
        )
        rhs.append(w * f(x))
    A, b = mp.matrix(rows), mp.matrix(rhs)
    c = mp.lu_solve(A.T * A, A.T * b)
    return [float(c[i]) for i in range(A.cols)]


def _evaluate(c: list[float], x: np.ndarray, degree: int, log_start: int) -> np.ndarray:
    p = np.polynomial.polynomial.polyval(x, c[: degree + 1])
    q = np.polynomial.polynomial.polyval(x, c[degree + 1 :]) * x**log_start
    return p - np.log(x) * q


def main() -> None:
    degree = int(sys.argv[1]) if len(sys.argv) > 1 else 10
    check = np.concatenate([np.linspace(1e-6, 1.0, 2001), np.geomspace(1e-16, 1e-6, 200)])
    for name, f, start in (("K", _K, 0), ("E", _E, 1)):
        c = fit(f, degree, start)
        err = max(
            abs(_evaluate(c, np.array([x]), degree, start)[0] / float(f(mp.mpf(x))) - 1)
            for x in check
        )
        print(f"{name}: degree {degree}, max relative error {err:.2e}")
        print(f"{name} = {c!r}")


if __name__ == "__main__":
    main()
