"""Exact field of rectangular current filaments, their mutual inductance and self inductance,
and the Helmholtz spacing of a rectangle pair (backend-generic where it says so).

A rectangular filament of half sides (h_u, h_v) lies in the plane w = 0 of its local frame
(u, v, w), corners at (±h_u, ±h_v, 0), the current circulating counter-clockwise seen from +w,
in the same cyclic local frame as the squares of :mod:`coils.square`: (u, v, w) =
(p_{a+1}, p_{a+2}, p_a - c) for a filament on axis a, so its first side (2 h_u) runs along the
next axis in cyclic order and its second (2 h_v) along the one after (x: y, z; y: z, x; z: x, y).

Field: the four sides are finite straight segments (Hanson & Hirshman, Phys. Plasmas 9, 4410
(2002), eq. 1, as in :mod:`coils.square`), the sides at u = ±h_u of length 2 h_v and those at
v = ±h_v of length 2 h_u; with f(a, b, L) = 2L(a + b) / (a b ((a + b)² - L²)) and d_st the
distance to the corner (s h_u, t h_v, 0),

    f0 = f(d+-, d++, 2h_v),  f1 = f(d-+, d++, 2h_u),  f2 = f(d--, d-+, 2h_v),  f3 = f(d--, d+-, 2h_u),
    B_u = μ0/(4π) w (f0 - f2),   B_v = μ0/(4π) w (f1 - f3),
    B_w = μ0/(4π) [(h_u - u) f0 + (h_v - v) f1 + (h_u + u) f2 + (h_v + v) f3];

at h_u = h_v the operations of :func:`coils.square.square_field_local`, bit for bit.

Mutual inductance of two coaxial, parallel, equally oriented rectangles: the like sides couple
at distance sqrt((h1 - h2)² + z²) per direction, the opposite ones at sqrt((h1 + h2)² + z²)
(Neumann's formula side by side, :func:`coils.square.parallel_filaments_mutual_H`).

Self inductance of one turn whose section has geometric mean distance g: Neumann's formula side by
side, each side the self inductance of a straight conductor (length l, GMD g; Grover,
*Inductance Calculations*, 1946, ch. 3) less the two pairs of opposite sides,

    L = (μ0/2π) Σ_sides [l ln((l + sqrt(l² + g²))/g) - sqrt(l² + g²) + g] - 2 (M_a(b) + M_b(a)),

which for g << a, b is Grover's rectangle (DESIGN.md 4.1; Grover 1946, ch. 5, eq. 28) with the
wire's GMD: (μ0/π)[a ln(2a/g) + b ln(2b/g) + 2d - a asinh(a/b) - b asinh(b/a) - 2(a + b)].

Helmholtz spacing: the on-axis field of one rectangle of sides a, b at height z is
2 μ0 I a b / (π sqrt(a² + b² + 4z²)) [1/(a² + 4z²) + 1/(b² + 4z²)]; the pair's centre field has
zero curvature where d²/dz² of it vanishes at z = s/2 (:func:`helmholtz_spacing_ratio`, found
numerically; 0.54451 at a = b, Firester's 0.5445).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any, ClassVar

import numpy as np

from coils.square import SquareFilamentSet, _segment_factor, parallel_filaments_mutual_H
from spiralcap.core import backend as bk
from spiralcap.core.backend import Scalar
from spiralcap.core.constants import MU0_T_m_per_A
from spiralcap.core.errors import InputError

__all__ = [
    "RECTANGLE_ASPECT_RANGE",
    "RectangleFilamentSet",
    "grover_rectangle_inductance_H",
    "helmholtz_spacing_ratio",
    "rectangle_axial_field_T_per_A",
    "rectangle_field_local",
    "rectangle_mutual_inductance_H",
]

#: Range of the side ratio b / a a rectangle pair is made for: beyond it the spacing with zero
#: centre curvature is no longer a Helmholtz-like pair (the two long sides act alone).
RECTANGLE_ASPECT_RANGE = (0.25, 4.0)


def rectangle_field_local(
    half_u_m: Scalar, half_v_m: Scalar, u_m: Scalar, v_m: Scalar, w_m: Scalar
) -> tuple[Scalar, Scalar, Scalar]:
    """Field of one rectangular filament per ampere in its local frame (module notes), T/A.

    Parameters
    ----------
    half_u_m, half_v_m : float, array or CasADi
        Half sides h_u, h_v along u and v, m (> 0).
    u_m, v_m : float, array or CasADi
        In-plane coordinates of the field point, m.
    w_m : float, array or CasADi
        Coordinate of the point along the rectangle's axis, from its plane, m.

    Returns
    -------
    b_u, b_v, b_w : same kind
        Field components per ampere, T/A (broadcast over the arguments).

    Examples
    --------
    >>> import math
    >>> b = rectangle_field_local(0.4, 0.31, 0.0, 0.0, 0.0)[2]
    >>> a, c = 0.8, 0.62  # the centre of a rectangle: 2 μ0 sqrt(a² + c²) / (π a c)
    >>> round(float(b / (2 * 4e-7 * math.pi * math.hypot(a, c) / (math.pi * a * c))), 6)
    1.0
    """
    hu, hv = half_u_m, half_v_m
    w_sq = w_m * w_m
    up, um, vp, vm = u_m - hu, u_m + hu, v_m - hv, v_m + hv
    up2, um2, vp2, vm2 = up * up + w_sq, um * um + w_sq, vp * vp, vm * vm
    d_pp = bk.sqrt(up2 + vp2)  # corner (+h_u, +h_v)
    d_pm = bk.sqrt(up2 + vm2)  # corner (+h_u, -h_v)
    d_mp = bk.sqrt(um2 + vp2)  # corner (-h_u, +h_v)
    d_mm = bk.sqrt(um2 + vm2)  # corner (-h_u, -h_v)
    length_u, length_v = 2.0 * hu, 2.0 * hv
    f0 = _segment_factor(d_pm, d_pp, length_v)  # side u = +h_u, along +v
    f1 = _segment_factor(d_mp, d_pp, length_u)  # side v = +h_v, along -u
    f2 = _segment_factor(d_mm, d_mp, length_v)  # side u = -h_u, along -v
    f3 = _segment_factor(d_mm, d_pm, length_u)  # side v = -h_v, along +u
    k = MU0_T_m_per_A / (4.0 * bk.pi)
    b_u = k * w_m * (f0 - f2)
    b_v = k * w_m * (f1 - f3)
    b_w = k * ((hu - u_m) * f0 + (hv - v_m) * f1 + (hu + u_m) * f2 + (hv + v_m) * f3)
    return b_u, b_v, b_w


def rectangle_mutual_inductance_H(
    half_u1_m: Scalar, half_v1_m: Scalar, half_u2_m: Scalar, half_v2_m: Scalar, distance_m: Scalar
) -> Scalar:
    """Mutual inductance of two coaxial, parallel, equally oriented rectangular filaments, H.

    Per direction, two pairs of like sides at sqrt((h1 - h2)² + z²) less two pairs of opposite
    sides at sqrt((h1 + h2)² + z²) (:func:`coils.square.parallel_filaments_mutual_H`): the sides
    along u (lengths 2 h_u1, 2 h_u2) sit at v = ±h_v, those along v at u = ±h_u.
    Backend-generic.

    Parameters
    ----------
    half_u1_m, half_v1_m, half_u2_m, half_v2_m : float, array or CasADi
        Half sides of the two rectangles, m.
    distance_m : float, array or CasADi
        Axial distance z between their planes, m.

    Returns
    -------
    same kind
        Mutual inductance, H (one turn each).

    Examples
    --------
    >>> from coils.square import square_mutual_inductance_H
    >>> m_sq = square_mutual_inductance_H(0.3, 0.3, 0.2)
    >>> bool(abs(rectangle_mutual_inductance_H(0.3, 0.3, 0.3, 0.3, 0.2) / m_sq - 1) < 1e-15)
    True
    """
    u1, v1, u2, v2, z = half_u1_m, half_v1_m, half_u2_m, half_v2_m, distance_m
    z2 = z * z
    along_u = parallel_filaments_mutual_H(
        2.0 * u1, 2.0 * u2, u1 - u2, bk.sqrt((v1 - v2) * (v1 - v2) + z2)
    ) - parallel_filaments_mutual_H(
        2.0 * u1, 2.0 * u2, u1 - u2, bk.sqrt((v1 + v2) * (v1 + v2) + z2)
    )
    along_v = parallel_filaments_mutual_H(
        2.0 * v1, 2.0 * v2, v1 - v2, bk.sqrt((u1 - u2) * (u1 - u2) + z2)
    ) - parallel_filaments_mutual_H(
        2.0 * v1, 2.0 * v2, v1 - v2, bk.sqrt((u1 + u2) * (u1 + u2) + z2)
    )
    return 2.0 * along_u + 2.0 * along_v


def _straight_self_H(length_m: Any, gmd_m: Any) -> Any:
    """Self inductance of a straight conductor of length l whose section has GMD g, H:
    (μ0/2π)[l ln((l + sqrt(l² + g²))/g) - sqrt(l² + g²) + g] (Grover 1946, ch. 3)."""
    r = bk.sqrt(length_m * length_m + gmd_m * gmd_m)
    return (MU0_T_m_per_A / (2.0 * bk.pi)) * (length_m * bk.log((length_m + r) / gmd_m) - r + gmd_m)


def grover_rectangle_inductance_H(side_a_m: Any, side_b_m: Any, gmd_m: Any) -> Any:
    """Self inductance of a one-turn rectangle of sides a, b whose section has GMD g, H.

    The module notes' side-by-side Neumann form (each side a straight conductor with the
    section's GMD, less the opposite sides' mutual inductance); for g << a, b it is Grover's
    rectangle, (μ0/π)[a ln(2a/g) + b ln(2b/g) + 2d - a asinh(a/b) - b asinh(b/a) - 2(a + b)],
    d = sqrt(a² + b²). Backend-generic.

    Parameters
    ----------
    side_a_m, side_b_m : float, array or CasADi
        Sides a, b of the rectangle (centre line of the conductor), m.
    gmd_m : float, array or CasADi
        Geometric mean distance g of the conductor's section from itself, m.

    Returns
    -------
    same kind
        Self inductance L, H (one turn).

    Examples
    --------
    >>> from coils.square_pair import grover_square_inductance_H
    >>> sq = grover_square_inductance_H(0.6, 0.01)
    >>> bool(abs(grover_rectangle_inductance_H(0.6, 0.6, 0.01) / sq - 1) < 1e-12)
    True
    """
    a, b, g = side_a_m, side_b_m, gmd_m
    own = 2.0 * _straight_self_H(a, g) + 2.0 * _straight_self_H(b, g)
    opposite = parallel_filaments_mutual_H(a, a, 0.0, b) + parallel_filaments_mutual_H(b, b, 0.0, a)
    return own - 2.0 * opposite


def rectangle_axial_field_T_per_A(side_a_m: Any, side_b_m: Any, z_m: Any) -> Any:
    """Field per ampere on the axis of one rectangle of sides a, b at distance z from its plane,
    2 μ0 a b / (π sqrt(a² + b² + 4z²)) [1/(a² + 4z²) + 1/(b² + 4z²)], T/A. Backend-generic.

    Parameters
    ----------
    side_a_m, side_b_m : float, array or CasADi
        Sides of the rectangle, m.
    z_m : float, array or CasADi
        Distance from its plane along the axis, m.

    Returns
    -------
    same kind
        B_w per ampere, T/A.

    Examples
    --------
    >>> b0 = rectangle_axial_field_T_per_A(0.8, 0.62, 0.0)
    >>> bool(abs(b0 / rectangle_field_local(0.4, 0.31, 0.0, 0.0, 0.0)[2] - 1) < 1e-14)
    True
    """
    a2, b2, z4 = side_a_m * side_a_m, side_b_m * side_b_m, 4.0 * z_m * z_m
    return (
        2.0
        * MU0_T_m_per_A
        * side_a_m
        * side_b_m
        / (bk.pi * bk.sqrt(a2 + b2 + z4))
        * (1.0 / (a2 + z4) + 1.0 / (b2 + z4))
    )


def _axial_curvature(ratio: float, t: float) -> float:
    """d²/dt² of the on-axis field of a rectangle of sides 1, ``ratio`` at t (exact: CasADi's
    second derivative of :func:`rectangle_axial_field_T_per_A`), T/(A·m²)."""
    return float(_curvature_function()(ratio, t))


@lru_cache(maxsize=1)
def _curvature_function() -> Any:
    import casadi as ca

    r, t = ca.SX.sym("r"), ca.SX.sym("t")
    f = rectangle_axial_field_T_per_A(1.0, r, t)
    d2 = ca.jacobian(ca.jacobian(f, t), t)
    return ca.Function("curvature", [r, t], [d2])


def helmholtz_spacing_ratio(side_a_m: float, side_b_m: float) -> float:
    """Spacing / side a at which a pair of coaxial rectangles (sides a, b) has zero field
    curvature at its centre, dimensionless.

    The pair's centre field is 2 B1(s/2) with B1 the single rectangle's on-axis field
    (:func:`rectangle_axial_field_T_per_A`), and its second derivative at the centre 2 B1''(s/2):
    the spacing is twice the inflection point of B1, found by bisection (scipy's brentq) on its
    exact second derivative between 0.05 and 2 times the longer side. 0.54451 at a = b (Firester's
    square Helmholtz spacing, 0.5445).

    Parameters
    ----------
    side_a_m, side_b_m : float
        Sides of the mean turn, m; b / a in :data:`RECTANGLE_ASPECT_RANGE`.

    Returns
    -------
    float
        s / a, dimensionless.

    Raises
    ------
    InputError
        ``sides_m`` with a side ratio outside :data:`RECTANGLE_ASPECT_RANGE`.

    Examples
    --------
    >>> round(helmholtz_spacing_ratio(1.0, 1.0), 5)
    0.54451
    """
    a, b = float(side_a_m), float(side_b_m)
    lo, hi = RECTANGLE_ASPECT_RANGE
    if not (a > 0 and b > 0 and lo <= b / a <= hi):
        raise InputError("sides_m", [a, b], f"two sides > 0 with a ratio b/a in [{lo:g}, {hi:g}]")
    return _spacing_ratio(b / a)


@lru_cache(maxsize=256)
def _spacing_ratio(ratio: float) -> float:
    from scipy.optimize import brentq

    t_hi = 2.0 * max(1.0, ratio)
    return 2.0 * float(brentq(lambda t: _axial_curvature(ratio, t), 0.025, t_hi, xtol=1e-15))


@dataclass(frozen=True, kw_only=True)
class RectangleFilamentSet(SquareFilamentSet):
    """Rectangular filaments: :class:`coils.square.SquareFilamentSet` with a second half side.

    Parameters
    ----------
    half_sides_m : ndarray, shape (L,)
        Half side h_u of each rectangle along u (the next axis in cyclic order), m.
    half_sides_v_m : ndarray, shape (L,)
        Half side h_v along v (the axis after), m.
    axes, centres_m, turns, columns, column_axes : ndarray or tuple
        As in :class:`coils.filaments.AxisFilaments`: axis indices, axial centres (m), turns
        (a count) and drive columns of the filaments, and the axis of each column.
    """

    half_sides_v_m: np.ndarray

    _CHUNK_ELEMENTS: ClassVar[int] = 65536

    def _shape_matrices(self, mats: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """The square's placement matrices and ``sizes_v`` (1, L), m."""
        out = super()._shape_matrices(mats)
        out["sizes_v"] = np.asarray(self.half_sides_v_m, dtype=float)[None, :]
        return out

    def _local(self, points: Scalar, mats: dict[str, Any]) -> tuple[Scalar, Scalar, Scalar]:
        """(B_u, B_v, B_w) per ampere of every filament at every point, shape (n, L)."""
        u = points @ mats["sel_u"]
        v = points @ mats["sel_v"]
        w = points @ mats["sel_w"] - mats["centres"]
        return rectangle_field_local(mats["sizes"], mats["sizes_v"], u, v, w)
