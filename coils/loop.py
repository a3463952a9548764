"""Exact field of one circular current filament, and Maxwell's mutual inductance of two.

Both are written once against :mod:`spiralcap.core.backend`, so they run on floats, numpy arrays and
CasADi ``SX``/``MX`` values alike (complete elliptic integrals from ``bk.ellipke``).

Field of a filament (Smythe, *Static and Dynamic Electricity*, 3rd ed. 1968, §7.10; in the
notation of Simpson, Lane, Immer & Youngquist, "Simple analytic expressions for the magnetic
field of a circular current loop", NASA/TM-2001-210040): for a loop of radius R centred on the
axis, a point at radius ρ and axial distance ζ from the loop plane, and one ampere,

    α² = (R - ρ)² + ζ²,   β² = (R + ρ)² + ζ²,   m = k² = 4Rρ/β² = 1 - α²/β²,
    B_z = μ0 / (2π α² β) · [(R² - ρ² - ζ²) E(m) + α² K(m)],
    B_ρ = μ0 ζ / (2π α² β ρ) · [(R² + ρ² + ζ²) E(m) - α² K(m)].

The B_ρ bracket equals β² f(m) with f(m) = (1 - m/2) E(m) - (1 - m) K(m) = O(m²), so

    B_ρ / ρ = 8 μ0 R² ζ g(m) / (π α² β³),   g(m) = f(m) / m²,

which is finite on the axis and has no division by ρ. Computing f from K and E cancels about
log10(1/m²) digits, so for m < ``SERIES_BELOW`` g comes from its Maclaurin series (built from
the hypergeometric series of K and E, Abramowitz & Stegun 17.3.11-12); both branches are finite
everywhere, as CasADi's ``if_else`` evaluates both.
"""

from __future__ import annotations

import math
from fractions import Fraction

from spiralcap.core import backend as bk
from spiralcap.core.backend import Scalar
from spiralcap.core.checks import finite, guard, nonnegative, positive
from spiralcap.core.constants import MU0_T_m_per_A

__all__ = [
    "SERIES_BELOW",
    "coaxial_mutual_inductance_H",
    "loop_field",
    "loop_terms",
]

#: Below this elliptic parameter m the series form of g(m) is used: 5 terms truncate at
#: < 1e-16 relative; above it the closed form loses < 1e-9 relative in B_ρ, which is
#: < 1e-12 of |B| there (B_ρ/|B| ~ m/4 near the axis).
SERIES_BELOW = 1e-3
_SERIES_TERMS = 5


def _g_series_coefficients(terms: int) -> tuple[float, ...]:
    """Maclaurin coefficients of g(m) = [(1 - m/2) E - (1 - m) K] / m², exact rationals x π/2.

    K = π/2 Σ a_n m^n and E = π/2 Σ a_n m^n / (1 - 2n) with a_n = (C(2n, n) / 4^n)²
    (Abramowitz & Stegun 17.3.11-12); the coefficient of m^n in f is
    a_n (1/(1-2n) - 1) + a_{n-1} (1 - 1/(2 (3-2n))), zero for n = 0 and 1.
    """
    a = [Fraction(math.comb(2 * n, n), 4**n) ** 2 for n in range(terms + 2)]
    coeffs = []
    for n in range(2, terms + 2):
        c = a[n] * (Fraction(1, 1 - 2 * n) - 1) + a[n - 1] * (1 - Fraction(1, 2 * (3 - 2 * n)))
        coeffs.append(float(c) * math.pi / 2)
    return tuple(coeffs)


_G_COEFFS = _g_series_coefficients(_SERIES_TERMS)


def _g(m: Scalar, K: Scalar, E: Scalar) -> Scalar:
    """g(m) = [E - K + m (K - E/2)] / m², series below SERIES_BELOW (finite for all m)."""
    series = _G_COEFFS[-1]
    for c in reversed(_G_COEFFS[:-1]):
        series = series * m + c
    m_safe = bk.fmax(m, SERIES_BELOW)
    closed = (E - K + m * (K - 0.5 * E)) / (m_safe * m_safe)
    return bk.where(m < SERIES_BELOW, series, closed)


def loop_terms(
    radius_m: Scalar, dz_m: Scalar, rho_m: Scalar, rho_sq_m2: Scalar
) -> tuple[Scalar, Scalar]:
    """(B_ρ/ρ, B_z) of one filament carrying one ampere, finite on the axis.

    Parameters
    ----------
    radius_m : float, array or CasADi
        Loop radius R, m.
    dz_m : float, array or CasADi
        Axial distance ζ of the point from the loop plane, m.
    rho_m, rho_sq_m2 : float, array or CasADi
        Distance ρ of the point from the loop axis, m, and its square ρ², m² (passed separately
        so that a caller can keep ρ² smooth where ρ = sqrt(ρ²) is not differentiable).

    Returns
    -------
    b_rho_over_rho : same kind
        B_ρ / ρ, T/(A·m) (B_ρ = ρ times this; exactly 0 times a finite number on the axis).
    b_z : same kind
        Axial field, T/A.
    """
    R = radius_m
    rp, rm = R + rho_m, R - rho_m
    dz_sq = dz_m * dz_m
    inv_beta_sq = 1.0 / (rp * rp + dz_sq)
    alpha_sq = rm * rm + dz_sq
    m = (4.0 * R) * rho_m * inv_beta_sq
    # 1 - m = α²/β² exactly next to the wire (numpy's K from it; CasADi's AGM takes m alone)
    K, E = bk.ellipke(m, complement=alpha_sq * inv_beta_sq)
    common = (MU0_T_m_per_A / (2.0 * bk.pi)) * bk.sqrt(inv_beta_sq) / alpha_sq
    b_z = common * ((R * R - rho_sq_m2 - dz_sq) * E + alpha_sq * K)
    b_rho_over_rho = common * (16.0 * R * R) * dz_m * inv_beta_sq * _g(m, K, E)
    return b_rho_over_rho, b_z


@guard(radius_m=positive(), z0_m=finite(), rho_m=nonnegative(), z_m=finite())
def loop_field(radius_m: Scalar, z0_m: Scalar, rho_m: Scalar, z_m: Scalar) -> tuple[Scalar, Scalar]:
    """Field of one circular filament per ampere-turn (exact, elliptic integrals).

    The loop lies in the plane z = z0 with its centre on the axis; current circulates
    counter-clockwise seen from +z, so B_z > 0 at the centre. Formula: Smythe (1968) §7.10 /
    Simpson et al. (2001), NASA/TM-2001-210040, rearranged to be finite on the axis (see the
    module docstring). Works elementwise on floats, numpy arrays (broadcast) and CasADi values.
    On the wire itself (ρ = R, z = z0) the field is infinite.

    Parameters
    ----------
    radius_m : float, array or CasADi
        Loop radius R, m (> 0).
    z0_m : float, array or CasADi
        Axial position of the loop plane, m.
    rho_m : float, array or CasADi
        Distance of the field point from the axis, m (>= 0).
    z_m : float, array or CasADi
        Axial position of the field point, m.

    Returns
    -------
    b_rho : same kind
        Radial field, T per ampere-turn; exactly 0 on the axis.
    b_z : same kind
        Axial field, T per ampere-turn.

    Examples
    --------
    The centre of a 0.1 m loop: B_z = μ0 / (2R) per ampere-turn (the textbook value), B_ρ = 0:

    >>> import math
    >>> from coils import loop_field
    >>> b_rho, b_z = loop_field(0.1, 0.0, 0.0, 0.0)
    >>> print(f"{b_z:.6e} T/A; mu0/(2R) = {4e-7 * math.pi / 0.2:.6e} T/A; B_rho = {b_rho}")
    6.283185e-06 T/A; mu0/(2R) = 6.283185e-06 T/A; B_rho = 0.0
    """
    s, b_z = loop_terms(radius_m, z_m - z0_m, rho_m, rho_m * rho_m)
    return rho_m * s, b_z


@guard(radius1_m=positive(), radius2_m=positive(), distance_m=finite())
def coaxial_mutual_inductance_H(radius1_m: Scalar, radius2_m: Scalar, distance_m: Scalar) -> Scalar:
    """Mutual inductance of two coaxial circular filaments (one turn each), H.

    Maxwell, *Treatise* (1873) §701: with k² = m = 4 a b / ((a + b)² + d²),

        M = μ0 sqrt(a b) [(2/k - k) K(m) - (2/k) E(m)]
          = μ0 sqrt(a b) / k · [(2 - m) K(m) - 2 E(m)].

    Parameters
    ----------
    radius1_m, radius2_m : float, array or CasADi
        Filament radii a and b, m (> 0).
    distance_m : float, array or CasADi
        Axial distance d between the filament planes, m (not both d = 0 and a = b).

    Returns
    -------
    same kind
        Mutual inductance, H.

    Examples
    --------
    Two 0.1 m loops 0.1 m apart, against Neumann's double line integral done by brute force:

    >>> import numpy as np
    >>> from coils import coaxial_mutual_inductance_H
    >>> M = coaxial_mutual_inductance_H(0.1, 0.1, 0.1)
    >>> phi = np.linspace(0.0, 2.0 * np.pi, 2000, endpoint=False)
    >>> gap = np.sqrt(2 * 0.1**2 * (1 - np.cos(phi)) + 0.1**2)  # chord to the other loop, m
    >>> neumann = 1e-7 * 0.1**2 * (2 * np.pi) ** 2 * np.mean(np.cos(phi) / gap)
    >>> print(f"{M * 1e9:.4f} nH; Neumann {neumann * 1e9:.4f} nH")
    49.4078 nH; Neumann 49.4078 nH
    """
    a, b, d = radius1_m, radius2_m, distance_m
    m = 4.0 * a * b / ((a + b) * (a + b) + d * d)
    K, E = bk.ellipke(m)
    return MU0_T_m_per_A * bk.sqrt(a * b / m) * ((2.0 - m) * K - 2.0 * E)
