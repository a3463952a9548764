"""Exact field of rectangular current filaments, their mutual and self inductance, and the
Helmholtz spacing of a rectangle pair (backend-generic where it says so). A square is the a = b
case of every formula here (:mod:`coils.square` only names it).

A rectangular filament of half sides (h_u, h_v) lies in the plane w = 0 of its local frame
(u, v, w), corners at (±h_u, ±h_v, 0), the current circulating counter-clockwise seen from +w
(so B_w > 0 at the centre, as for a circular loop). The local frame of a filament on axis a is
the right-handed cyclic one, (u, v, w) = (p_{a+1}, p_{a+2}, p_a - c), so its first side (2 h_u)
runs along the next axis in cyclic order and its second (2 h_v) along the one after (x: y, z;
y: z, x; z: x, y): squares on the three axes nest into a cube.

Field of one straight segment (Biot-Savart in closed form; Hanson & Hirshman, "Compact
expressions for the Biot-Savart fields of a filamentary segment", Phys. Plasmas 9, 4410 (2002),
eq. 1): a segment of length L from x_i to x_f with unit direction e, and a point at distances
R_i, R_f from its ends, carrying one ampere,

    B = μ0/(4π) · 2 L (R_i + R_f) / (R_i R_f ((R_i + R_f)² - L²)) · e x (p - x_i).

The sides at u = ±h_u have length 2 h_v, those at v = ±h_v length 2 h_u; with
f(a, b, L) = 2L(a + b) / (a b ((a + b)² - L²)) and d_st the distance to the corner
(s h_u, t h_v, 0),

    f0 = f(d+-, d++, 2h_v),  f1 = f(d-+, d++, 2h_u),  f2 = f(d--, d-+, 2h_v),  f3 = f(d--, d+-, 2h_u),
    B_u = μ0/(4π) w (f0 - f2),   B_v = μ0/(4π) w (f1 - f3),
    B_w = μ0/(4π) [(h_u - u) f0 + (h_v - v) f1 + (h_u + u) f2 + (h_v + v) f3]:

four square roots per filament and point. At the centre of a square of side a,
B_w = 2√2 μ0 / (π a) per ampere (the textbook square loop). Finite everywhere off the wire.

Mutual inductance of two coaxial, parallel, equally oriented rectangles (Neumann's formula side
by side): only parallel sides couple (perpendicular ones have dl · dl' = 0); two parallel
straight filaments of lengths l1, l2 at distance d, the second starting s further along, have
(Grover, *Inductance Calculations*, 1946, ch. 3, eq. 19; Campbell's form)

    M = μ0/(4π) [G(s + l2) - G(s) - G(s + l2 - l1) + G(s - l1)],
    G(x) = x asinh(x/d) - sqrt(x² + d²)   (even in x),

and the like sides couple at distance sqrt((h1 - h2)² + z²) per direction, the opposite ones
at sqrt((h1 + h2)² + z²) with opposite sense.

Self inductance of one turn's worth of a frame pack (:func:`rectangle_pack_self_inductance_H`):
the section average of the exact rectangle-to-rectangle mutual inductance, its one singular
part through the section's geometric mean distance. Grover's rectangle with the GMD
(:func:`grover_rectangle_inductance_H`: each side a straight conductor of GMD g (Grover 1946,
ch. 3) less the two pairs of opposite sides,

    L = (μ0/2π) Σ_sides [l ln((l + sqrt(l² + g²))/g) - sqrt(l² + g²) + g] - 2 (M_a(b) + M_b(a)),

for g << a, b Grover's rectangle, DESIGN.md 4.1; Grover 1946, ch. 5, eq. 28) is the same with
every filament at the mean turn's sides; the sizing's closed forms use it.

Helmholtz spacing: the on-axis field of one rectangle of sides a, b at height z is
2 μ0 I a b / (π sqrt(a² + b² + 4z²)) [1/(a² + 4z²) + 1/(b² + 4z²)]; the pair's centre field has
zero curvature where d²/dz² of it vanishes at z = s/2 (:func:`helmholtz_spacing_ratio`, found
numerically; 0.54451 at a = b, Firester's 0.5445).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, ClassVar

import numpy as np

from coils.filaments import AxisFilaments, gauss_legendre_pack
from coils.pair import _stefan_y1
from spiralcap.core import backend as bk
from spiralcap.core.backend import Scalar
from spiralcap.core.constants import MU0_T_m_per_A
from spiralcap.core.errors import InputError

__all__ = [
    "RECTANGLE_ASPECT_RANGE",
    "RectangleFilamentSet",
    "grover_rectangle_inductance_H",
    "helmholtz_spacing_ratio",
    "parallel_filaments_mutual_H",
    "rectangle_axial_field_T_per_A",
    "rectangle_field_local",
    "rectangle_gmd_m",
    "rectangle_mutual_inductance_H",
    "rectangle_pack_self_inductance_H",
]

#: Range of the side ratio b / a a rectangle pair is made for: beyond it the spacing with zero
#: centre curvature is no longer a Helmholtz-like pair (the two long sides act alone).
RECTANGLE_ASPECT_RANGE = (0.25, 4.0)


def _segment_factor(a: Scalar, b: Scalar, length: Scalar) -> Scalar:
    """f(a, b) = 2 L (a + b) / (a b ((a + b)² - L²)) of Hanson & Hirshman (2002), 1/m²."""
    s = a + b
    return (2.0 * length) * s / (a * b * (s - length) * (s + length))


def _g(x: Scalar, d: Scalar) -> Scalar:
    """G(x) = x asinh(x/d) - sqrt(x² + d²), even in x (computed on |x|: no cancellation)."""
    ax = bk.abs(x)
    r = bk.sqrt(ax * ax + d * d)
    return ax * bk.log((ax + r) / d) - r


def parallel_filaments_mutual_H(
    length1_m: Scalar, length2_m: Scalar, offset_m: Scalar, distance_m: Scalar
) -> Scalar:
    """Mutual inductance of two parallel straight filaments, same sense, H.

    Filament 1 runs from 0 to l1, filament 2 from s to s + l2 along a parallel line at
    distance d (Neumann's double integral in closed form; Grover 1946, ch. 3):
    M = μ0/(4π) [G(s + l2) - G(s) - G(s + l2 - l1) + G(s - l1)].

    Parameters
    ----------
    length1_m, length2_m : float, array or CasADi
        Lengths l1, l2, m.
    offset_m : float, array or CasADi
        Start s of filament 2 along filament 1's line, m.
    distance_m : float, array or CasADi
        Distance d between the two lines, m (> 0).

    Returns
    -------
    same kind
        Mutual inductance, H.
    """
    l1, l2, s, d = length1_m, length2_m, offset_m, distance_m
    return (MU0_T_m_per_A / (4.0 * bk.pi)) * (
        _g(s + l2, d) - _g(s, d) - _g(s + l2 - l1, d) + _g(s - l1, d)
    )


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
    sides at sqrt((h1 + h2)² + z²) (:func:`parallel_filaments_mutual_H`): the sides
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
    Far apart, two coaxial loops of area A couple as dipoles, μ0 A² / (2π z³):

    >>> import math
    >>> m = rectangle_mutual_inductance_H(0.03, 0.02, 0.03, 0.02, 5.0)
    >>> round(float(m / (4e-7 * math.pi * (0.06 * 0.04) ** 2 / (2 * math.pi * 5.0**3))), 3)
    1.0
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
    A square (a = b) of GMD g << a: Grover's square, (2 μ0 a / π) [ln(a/g) - 0.77401 + g/a]:

    >>> import math
    >>> thin = 2 * 4e-7 * math.pi * 0.6 / math.pi * (math.log(0.6 / 0.001) - 0.77401 + 0.001 / 0.6)
    >>> bool(abs(grover_rectangle_inductance_H(0.6, 0.6, 0.001) / thin - 1) < 1e-5)
    True
    """
    a, b, g = side_a_m, side_b_m, gmd_m
    own = 2.0 * _straight_self_H(a, g) + 2.0 * _straight_self_H(b, g)
    opposite = parallel_filaments_mutual_H(a, a, 0.0, b) + parallel_filaments_mutual_H(b, b, 0.0, a)
    return own - 2.0 * opposite


def rectangle_gmd_m(width_m: Any, depth_m: Any) -> Any:
    """Maxwell's geometric mean distance of a w x h rectangle from itself, m.

    g = sqrt(w² + h²) exp(y1 - 2) with y1 of Stefan's formula (Rosa & Grover, Bull. Bur.
    Stand. 8, 1912, eq. 91; 0.2235 (w + h) for a square, exactly 0.447049 w). Backend-generic.

    Parameters
    ----------
    width_m, depth_m : float, array or CasADi
        Sides of the rectangle, m.

    Returns
    -------
    same kind
        Geometric mean distance g, m.

    Examples
    --------
    >>> round(float(rectangle_gmd_m(0.02, 0.02)) / 0.02, 6)  # Maxwell's square: 0.447049 a
    0.447049
    """
    return bk.sqrt(width_m * width_m + depth_m * depth_m) * bk.exp(
        _stefan_y1(width_m / depth_m) - 2.0
    )


#: Gauss-Legendre nodes across each side of the section for
#: :func:`rectangle_pack_self_inductance_H` (10 x 10 per filament, 10^4 filament pairs: within
#: 3e-5 of a Richardson-extrapolated filament-sum volume integral at aspects 0.3 to 3,
#: tests/test_coils_square.py and tests/test_coils_rectangle.py).
_SELF_NODES = 10


def _frame_sides_self_H(
    length_m: float, across_m: float, sec: dict[str, Any], log_gmd: float
) -> float:
    """One direction's share of :func:`rectangle_pack_self_inductance_H` (per pair of sides):
    the like sides of mean length l (the singular part through the GMD) less the opposite
    sides across the frame's other side, H."""
    di, dj, s, z, d_sq, g_s, pw = (sec[k] for k in ("di", "dj", "s", "z", "d_sq", "g_s", "pw"))
    x = length_m + di + dj
    r = np.sqrt(x * x + d_sq)
    smooth = x * np.log(x + r) - r  # G(X, d) + X ln d
    k = MU0_T_m_per_A / (4.0 * math.pi)
    like = 2.0 * k * (np.sum(pw * (smooth - g_s)) - length_m * log_gmd)
    x_across = across_m + di + dj
    opposite = parallel_filaments_mutual_H(
        length_m + 2.0 * di, length_m + 2.0 * dj, s, np.sqrt(x_across * x_across + z * z)
    )
    return float(like - np.sum(pw * opposite))


def rectangle_pack_self_inductance_H(
    side_a_m: float, side_b_m: float, width_m: float, depth_m: float
) -> float:
    """Self inductance of one turn's worth of a rectangular frame pack (uniform current), H.

    The pack is the set of rectangular filaments of sides a + 2δ_i, b + 2δ_i at axial offsets
    z_i (δ, z uniform over the w x h section); L/N² is the section average of the exact
    rectangle-to-rectangle mutual inductance (:func:`rectangle_mutual_inductance_H`). Per
    direction, with l the mean side along it (a, then b), m the other (b, then a),
    X = l + δ_i + δ_j, s = δ_i - δ_j and d = sqrt(s² + (z_i - z_j)²) the distance between the
    two filaments in the section: the two pairs of like sides (lengths l + 2δ_i, l + 2δ_j,
    offset s) give (μ0/4π) 2 [G(X, d) - G(s, d)] each, the two pairs of opposite sides the
    smooth Campbell term at distance sqrt((m + δ_i + δ_j)² + (z_i - z_j)²). The only singular
    part, -X ln d, averages exactly: ⟨X ln d⟩ = l ln g, g the section's geometric mean distance
    (:func:`rectangle_gmd_m`; the δ_i + δ_j part averages to zero by symmetry); everything else
    is bounded and averaged by a 10 x 10 Gauss-Legendre rule per filament. At a = b it is the
    square's 4 (like - opposite), operation for operation. Grover's rectangle with the GMD
    (:func:`grover_rectangle_inductance_H`) is the same with every filament at the mean sides;
    it differs from this by 5e-4 (square section) to 2.5e-3 (aspect 0.3).

    Parameters
    ----------
    side_a_m, side_b_m : float
        Sides a, b of the mean turn, m.
    width_m, depth_m : float
        Axial width w and depth h of the section, m.

    Returns
    -------
    float
        L / N², H.

    Examples
    --------
    A thin section (1 mm on 0.8 x 0.62 m): Grover's rectangle with the GMD, every filament at the
    mean sides, is within 2e-5 of it:

    >>> exact = rectangle_pack_self_inductance_H(0.8, 0.62, 1e-3, 1e-3)
    >>> grover = grover_rectangle_inductance_H(0.8, 0.62, float(rectangle_gmd_m(1e-3, 1e-3)))
    >>> bool(abs(exact / grover - 1) < 2e-5)
    True
    """
    d_r, d_z, weight = gauss_legendre_pack(depth_m, (_SELF_NODES,) * 2, width_m)
    di, dj = d_r[:, None], d_r[None, :]
    z = d_z[:, None] - d_z[None, :]
    s = di - dj
    d_sq = s * s + z * z
    a_s = np.abs(s)
    d_safe = np.sqrt(np.where(d_sq > 0.0, d_sq, 1.0))
    g_s = np.where(d_sq > 0.0, a_s * np.arcsinh(a_s / d_safe) - np.sqrt(s * s + d_sq), 0.0)
    sec = {"di": di, "dj": dj, "s": s, "z": z, "d_sq": d_sq, "g_s": g_s}
    sec["pw"] = weight[:, None] * weight[None, :]
    log_gmd = math.log(float(rectangle_gmd_m(width_m, depth_m)))
    along_a = _frame_sides_self_H(side_a_m, side_b_m, sec, log_gmd)
    along_b = _frame_sides_self_H(side_b_m, side_a_m, sec, log_gmd)
    return float(2.0 * along_a + 2.0 * along_b)


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
class RectangleFilamentSet(AxisFilaments):
    """Rectangular filaments: the filaments of :class:`coils.filaments.AxisFilaments` with two
    half sides each, in their local frames (u, v, w) (see the module notes); squares where
    ``half_sides_v_m`` is None.

    One code path for numpy (n, 3) points and CasADi (1, 3) rows (:meth:`_field_rows`), the
    local coordinates picked by the constant selection matrices.

    Parameters
    ----------
    half_sides_m : ndarray, shape (L,)
        Half side h_u of each rectangle along u (the next axis in cyclic order), m.
    half_sides_v_m : ndarray, shape (L,), or None
        Half side h_v along v (the axis after), m; None: squares, h_v = h_u.
    axes, centres_m, turns, columns, column_axes : ndarray or tuple
        As in :class:`coils.filaments.AxisFilaments`: axis indices, axial centres (m), turns
        (a count) and drive columns of the filaments, and the axis of each column.

    Examples
    --------
    One square of side 0.6 m on z: its centre field per ampere, 2√2 μ0 / (π a):

    >>> import math
    >>> one = RectangleFilamentSet(
    ...     axes=np.array([2]), half_sides_m=np.array([0.3]), centres_m=np.array([0.0]),
    ...     turns=np.array([1.0]), columns=np.array([0]), column_axes=(2,))
    >>> b = one.field(np.zeros((1, 3)), np.ones((1, 1)))[0, 2]
    >>> round(float(b / (2 * math.sqrt(2) * 4e-7 * math.pi / (math.pi * 0.6))), 6)
    1.0
    """

    half_sides_m: np.ndarray
    half_sides_v_m: np.ndarray | None = None

    _SIZE_KEY: ClassVar[str] = "half_sides_m"
    _CHUNK_ELEMENTS: ClassVar[int] = 65536

    def _shape_matrices(self, mats: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """``put_u``, ``put_v``, ``put_w`` (L, 3): where B_u, B_v, B_w of each filament go;
        ``sizes_v`` (1, L): the half sides along v, m."""
        out = {"put_" + c: mats["sel_" + c].T.copy() for c in "uvw"}
        v = self.half_sides_m if self.half_sides_v_m is None else self.half_sides_v_m
        out["sizes_v"] = np.asarray(v, dtype=float)[None, :]
        return out

    def _local(self, points: Scalar, mats: dict[str, Any]) -> tuple[Scalar, Scalar, Scalar]:
        """(B_u, B_v, B_w) per ampere of every filament at every point, shape (n, L)."""
        u = points @ mats["sel_u"]
        v = points @ mats["sel_v"]
        w = points @ mats["sel_w"] - mats["centres"]
        return rectangle_field_local(mats["sizes"], mats["sizes_v"], u, v, w)

    def _field_rows(self, points: Scalar, currents: Scalar, mats: dict[str, Any]) -> Scalar:
        """B, T: the local fields times each filament's ampere-turns, put in place."""
        b_u, b_v, b_w = self._local(points, mats)
        amp_turns = (mats["weights"] @ currents).T  # (1, L)
        return (
            (b_u * amp_turns) @ mats["put_u"]
            + (b_v * amp_turns) @ mats["put_v"]
            + (b_w * amp_turns) @ mats["put_w"]
        )

    def _matrix_chunk(self, points: np.ndarray) -> np.ndarray:
        """G, shape (n, 3, n_currents), T/A: the local fields put in place, by drive column."""
        mats = self._matrices(False)
        weights = mats["weights"]
        b_u, b_v, b_w = self._local(points, mats)
        return (
            np.einsum("nl,li,lk->nik", b_u, mats["put_u"], weights)
            + np.einsum("nl,li,lk->nik", b_v, mats["put_v"], weights)
            + np.einsum("nl,li,lk->nik", b_w, mats["put_w"], weights)
        )
