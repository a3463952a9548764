"""Exact field of square current filaments, and their mutual inductance (backend-generic).

A square filament of half side h lies in the plane w = 0 of its local frame (u, v, w), corners
at (±h, ±h, 0), the current circulating counter-clockwise seen from +w (so B_w > 0 at the
centre, as for a circular loop). The local frame of a filament on axis a is the right-handed
cyclic one, (u, v, w) = (p_{a+1}, p_{a+2}, p_a - c): its sides are parallel to the other two
coordinate axes, so squares on the three axes nest into a cube.

Field of one straight segment (Biot-Savart in closed form; Hanson & Hirshman, "Compact
expressions for the Biot-Savart fields of a filamentary segment", Phys. Plasmas 9, 4410 (2002),
eq. 1): a segment of length L from x_i to x_f with unit direction e, and a point at distances
R_i, R_f from its ends, carrying one ampere,

    B = μ0/(4π) · 2 L (R_i + R_f) / (R_i R_f ((R_i + R_f)² - L²)) · e x (p - x_i).

For the side at u = +h running along +v, e x (p - x_i) = (w, 0, h - u); the other three sides
are its images under quarter turns about w. With d_st the distance from the point to the corner
(s h, t h, 0) and f(a, b) = 2L(a + b) / (a b ((a + b)² - L²)), L = 2h,

    f0 = f(d+-, d++),  f1 = f(d-+, d++),  f2 = f(d--, d-+),  f3 = f(d--, d+-),
    B_u = μ0/(4π) w (f0 - f2),   B_v = μ0/(4π) w (f1 - f3),
    B_w = μ0/(4π) [(h - u) f0 + (h - v) f1 + (h + u) f2 + (h + v) f3]:

four square roots per filament and point. At the centre B_w = √2 μ0 / (π h) = 2√2 μ0 / (π a)
per ampere for side a (the textbook square loop). Finite everywhere off the wire; only on the
wire itself ((R_i + R_f)² = L²) is it infinite.

Mutual inductance of two coaxial, parallel squares (Neumann's formula side by side): only
parallel sides couple (perpendicular ones have dl · dl' = 0); two parallel straight filaments
of lengths l1, l2 at distance d, the second starting s further along, have (Grover, *Inductance
Calculations*, 1946, ch. 3, eq. 19; Campbell's form)

    M = μ0/(4π) [G(s + l2) - G(s) - G(s + l2 - l1) + G(s - l1)],
    G(x) = x asinh(x/d) - sqrt(x² + d²)   (even in x),

and the squares couple through their four pairs of like sides (distance sqrt((h1-h2)² + z²),
same sense) and four pairs of opposite sides (distance sqrt((h1+h2)² + z²), opposite sense).
"""

from __future__ import annotations

import operator
from dataclasses import dataclass
from functools import reduce
from typing import Any, ClassVar

import numpy as np

from coils.filaments import AxisFilaments
from spiralcap.core import backend as bk
from spiralcap.core.backend import Scalar
from spiralcap.core.constants import MU0_T_m_per_A

__all__ = [
    "MixedFilamentSet",
    "SquareFilamentSet",
    "parallel_filaments_mutual_H",
    "square_field_local",
    "square_mutual_inductance_H",
]


def _segment_factor(a: Scalar, b: Scalar, length: Scalar) -> Scalar:
    """f(a, b) = 2 L (a + b) / (a b ((a + b)² - L²)) of Hanson & Hirshman (2002), 1/m²."""
    s = a + b
    return (2.0 * length) * s / (a * b * (s - length) * (s + length))


def square_field_local(
    half_side_m: Scalar, u_m: Scalar, v_m: Scalar, w_m: Scalar
) -> tuple[Scalar, Scalar, Scalar]:
    """Field of one square filament per ampere in its local frame (see the module notes), T/A.

    Parameters
    ----------
    half_side_m : float, array or CasADi
        Half side h of the square, m (> 0).
    u_m, v_m : float, array or CasADi
        In-plane coordinates of the field point (along the sides), m.
    w_m : float, array or CasADi
        Coordinate of the point along the square's axis, from its plane, m.

    Returns
    -------
    b_u, b_v, b_w : same kind
        Field components per ampere, T/A (broadcast over the arguments).
    """
    h = half_side_m
    w_sq = w_m * w_m
    up, um, vp, vm = u_m - h, u_m + h, v_m - h, v_m + h
    up2, um2, vp2, vm2 = up * up + w_sq, um * um + w_sq, vp * vp, vm * vm
    d_pp = bk.sqrt(up2 + vp2)  # corner (+h, +h)
    d_pm = bk.sqrt(up2 + vm2)  # corner (+h, -h)
    d_mp = bk.sqrt(um2 + vp2)  # corner (-h, +h)
    d_mm = bk.sqrt(um2 + vm2)  # corner (-h, -h)
    length = 2.0 * h
    f0 = _segment_factor(d_pm, d_pp, length)  # side u = +h, along +v
    f1 = _segment_factor(d_mp, d_pp, length)  # side v = +h, along -u
    f2 = _segment_factor(d_mm, d_mp, length)  # side u = -h, along -v
    f3 = _segment_factor(d_mm, d_pm, length)  # side v = -h, along +u
    k = MU0_T_m_per_A / (4.0 * bk.pi)
    b_u = k * w_m * (f0 - f2)
    b_v = k * w_m * (f1 - f3)
    b_w = k * ((h - u_m) * f0 + (h - v_m) * f1 + (h + u_m) * f2 + (h + v_m) * f3)
    return b_u, b_v, b_w


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


def square_mutual_inductance_H(
    half_side1_m: Scalar, half_side2_m: Scalar, distance_m: Scalar
) -> Scalar:
    """Mutual inductance of two coaxial, parallel, equally oriented square filaments, H.

    Four pairs of like sides at distance sqrt((h1 - h2)² + z²) minus four pairs of opposite
    sides at sqrt((h1 + h2)² + z²) (:func:`parallel_filaments_mutual_H`, offset h1 - h2).

    Parameters
    ----------
    half_side1_m, half_side2_m : float, array or CasADi
        Half sides h1, h2, m.
    distance_m : float, array or CasADi
        Axial distance z between the planes, m (not both z = 0 and h1 = h2).

    Returns
    -------
    same kind
        Mutual inductance, H (one turn each).
    """
    h1, h2, z = half_side1_m, half_side2_m, distance_m
    near = bk.sqrt((h1 - h2) * (h1 - h2) + z * z)
    far = bk.sqrt((h1 + h2) * (h1 + h2) + z * z)
    l1, l2, s = 2.0 * h1, 2.0 * h2, h1 - h2
    return 4.0 * (
        parallel_filaments_mutual_H(l1, l2, s, near) - parallel_filaments_mutual_H(l1, l2, s, far)
    )


@dataclass(frozen=True, kw_only=True)
class SquareFilamentSet(AxisFilaments):
    """Square filaments: the filaments of :class:`coils.filaments.AxisFilaments` with a half
    side each, in their local frames (u, v, w) (see the module notes).

    One code path for numpy (n, 3) points and CasADi (1, 3) rows (:meth:`_field_rows`), the
    local coordinates picked by the constant selection matrices.

    Parameters
    ----------
    half_sides_m : ndarray, shape (L,)
        Half side of each square, m.
    axes, centres_m, turns, columns, column_axes : ndarray or tuple
        As in :class:`coils.filaments.AxisFilaments`: axis indices, axial centres (m), turns
        (a count) and drive columns of the filaments, and the axis of each column.
    """

    half_sides_m: np.ndarray

    _SIZE_KEY: ClassVar[str] = "half_sides_m"
    _CHUNK_ELEMENTS: ClassVar[int] = 65536

    def _shape_matrices(self, mats: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """``put_u``, ``put_v``, ``put_w`` (L, 3): where B_u, B_v, B_w of each filament go."""
        return {"put_" + c: mats["sel_" + c].T.copy() for c in "uvw"}

    def _local(self, points: Scalar, mats: dict[str, Any]) -> tuple[Scalar, Scalar, Scalar]:
        """(B_u, B_v, B_w) per ampere of every filament at every point, shape (n, L)."""
        u = points @ mats["sel_u"]
        v = points @ mats["sel_v"]
        w = points @ mats["sel_w"] - mats["centres"]
        return square_field_local(mats["sizes"], u, v, w)

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


@dataclass(frozen=True)
class MixedFilamentSet:
    """Circular and square filament sets driven by the same currents: their fields add.

    Parameters
    ----------
    parts : tuple
        :class:`coils.filaments.FilamentSet` and :class:`SquareFilamentSet` objects with the
        same drive columns (``column_axes``).
    """

    parts: tuple[Any, ...]

    @property
    def column_axes(self) -> tuple[int, ...]:
        """Axis index of each drive column (0, 1, 2 for x, y, z)."""
        return tuple(self.parts[0].column_axes)

    @property
    def n_currents(self) -> int:
        """Number of drive currents."""
        return len(self.column_axes)

    def field(self, points: Scalar, currents: Scalar) -> Scalar:
        return reduce(operator.add, (part.field(points, currents) for part in self.parts))

    def field_matrix(self, points: np.ndarray) -> np.ndarray:
        return reduce(operator.add, (part.field_matrix(points) for part in self.parts))

    # the parts' sum, documented as theirs
    field.__doc__ = AxisFilaments.field.__doc__
    field_matrix.__doc__ = AxisFilaments.field_matrix.__doc__
