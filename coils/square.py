"""Square current filaments: the a = b case of :mod:`coils.rectangle`, by name.

A square filament of half side h is the rectangle of half sides (h, h) in the same cyclic local
frame (u, v, w) = (p_{a+1}, p_{a+2}, p_a - c); its field, its mutual inductance and the filament
set are the rectangle's (:func:`coils.rectangle.rectangle_field_local`,
:func:`coils.rectangle.rectangle_mutual_inductance_H`,
:class:`coils.rectangle.RectangleFilamentSet` with ``half_sides_v_m`` None). Nothing here
computes anything of its own: the names stay for the callers that think in squares.
"""

from __future__ import annotations

from coils.filaments import MixedFilamentSet
from coils.rectangle import (
    RectangleFilamentSet,
    parallel_filaments_mutual_H,
    rectangle_mutual_inductance_H,
)
from spiralcap.core.backend import Scalar

__all__ = [
    "MixedFilamentSet",
    "SquareFilamentSet",
    "parallel_filaments_mutual_H",
    "square_mutual_inductance_H",
]

#: Square filaments: the rectangle's filament set with ``half_sides_v_m`` None (h_v = h_u).
SquareFilamentSet = RectangleFilamentSet


def square_mutual_inductance_H(
    half_side1_m: Scalar, half_side2_m: Scalar, distance_m: Scalar
) -> Scalar:
    """Mutual inductance of two coaxial, parallel, equally oriented square filaments, H: the
    rectangles' (:func:`coils.rectangle.rectangle_mutual_inductance_H`) at h_u = h_v.
    Backend-generic.

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
    h1, h2 = half_side1_m, half_side2_m
    return rectangle_mutual_inductance_H(h1, h1, h2, h2, distance_m)
