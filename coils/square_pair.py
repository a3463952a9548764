"""A square Helmholtz pair: two coaxial square coils in series with rectangular winding packs.

Geometry: each coil has N turns of round copper wire of bare diameter d wound into a
rectangular section of area A = N π d² / 4 / packing_factor (axial width w = sqrt(A · aspect),
depth h = sqrt(A / aspect) across the side), centred on the mean turn, a square of side a (the
winding's centre line) with sharp corners; its sides are parallel to the other two coordinate
axes. The two coils sit at ±s/2 along the pair's axis, s = 0.5445 a by default (the square
Helmholtz spacing: the centre field's second derivative vanishes there; Firester, Rev. Sci.
Instrum. 37, 1264 (1966)), and carry the same current in the same sense.

The pack is a frame whose every filament is a square: a filament at depth offset δ across the
pack is the square of side a + 2δ, so the pack's mean turn is exactly 4a long, its volume
w h · 4a and its outer surface 2 (w + h) · 4a (the mitred corners add and take away the same).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from coils.electrical import copper_resistivity_ohm_m
from coils.filaments import AXES, Axis, gauss_legendre_pack
from coils.pair import MAX_PACKING_FACTOR, PACK_ASPECT_RANGE, _check_count, _stefan_y1
from coils.square import (
    SquareFilamentSet,
    parallel_filaments_mutual_H,
    square_field_local,
    square_mutual_inductance_H,
)
from spiralcap import backend as bk
from spiralcap.constants import MU0_T_m_per_A
from spiralcap.errors import InputError, check_positive

__all__ = [
    "SQUARE_HELMHOLTZ_RATIO",
    "SquarePair",
    "grover_square_inductance_H",
    "rectangle_gmd_m",
    "square_pack_self_inductance_H",
]

#: Coil spacing / side of a square Helmholtz pair (Firester 1966): the field's second axial
#: derivative vanishes at the centre.
SQUARE_HELMHOLTZ_RATIO = 0.5445
# Gauss-Legendre nodes across each pack for the mutual inductance (as coils.pair).
_MUTUAL_NODES = 4


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
    """
    return bk.sqrt(width_m * width_m + depth_m * depth_m) * bk.exp(
        _stefan_y1(width_m / depth_m) - 2.0
    )


def grover_square_inductance_H(side_m: Any, gmd_m: Any) -> Any:
    """Self inductance of a one-turn square of side a whose section has GMD g, H.

    Neumann's formula side by side: four sides, each the self inductance of a straight
    conductor of length a and GMD g, less the four pairs of opposite sides (distance a,
    opposite currents; perpendicular sides do not couple),

        L = (2 μ0 / π) [a ln((a + sqrt(a² + g²)) / g) - sqrt(a² + g²) + g
                        - a ln(1 + √2) + (√2 - 1) a],

    which for g << a is Grover's square, (2 μ0 a / π) [ln(a/g) - 0.77401 + g/a] (Grover,
    *Inductance Calculations*, 1946, ch. 5, eq. 24 and Table 3). Backend-generic.

    Parameters
    ----------
    side_m : float, array or CasADi
        Side a of the square (centre line of the conductor), m.
    gmd_m : float, array or CasADi
        Geometric mean distance g of the conductor's section from itself, m.

    Returns
    -------
    same kind
        Self inductance L, H (one turn).
    """
    a, g = side_m, gmd_m
    r = bk.sqrt(a * a + g * g)
    return (2.0 * MU0_T_m_per_A / bk.pi) * (
        a * bk.log((a + r) / g)
        - r
        + g
        - a * math.log(1.0 + math.sqrt(2.0))
        + (math.sqrt(2.0) - 1.0) * a
    )


#: Gauss-Legendre nodes across each side of the section for :func:`square_pack_self_inductance_H`
#: (10 x 10 per filament, 10^4 filament pairs: within 3e-5 of a Richardson-extrapolated
#: filament-sum volume integral at aspects 0.3 to 3, tests/test_coils_square.py).
_SELF_NODES = 10


def square_pack_self_inductance_H(side_m: float, width_m: float, depth_m: float) -> float:
    """Self inductance of one turn's worth of a square frame pack (uniform current), H.

    The pack is the set of square filaments of side a + 2δ_i at axial offsets z_i (δ, z
    uniform over the w x h section); L/N² is the section average of the exact square-to-square
    mutual inductance (:func:`coils.square.square_mutual_inductance_H`). With X = a + δ_i + δ_j,
    s = δ_i - δ_j and d = sqrt(s² + (z_i - z_j)²) the distance between the two filaments in the
    section, the like sides give (μ0/4π) 2 [G(X, d) - G(s, d)] and the opposite sides the
    smooth term at sqrt(X² + (z_i - z_j)²) (Campbell's parallel filaments). The only singular
    part, -X ln d, averages exactly: ⟨X ln d⟩ = a ln g, g the section's geometric mean
    distance (:func:`rectangle_gmd_m`; the δ_i + δ_j part averages to zero by symmetry);
    everything else is bounded and averaged by a 10 x 10 Gauss-Legendre rule per filament.
    Grover's square with the GMD (:func:`grover_square_inductance_H`) is the same with every
    filament at side a; it differs from this by 5e-4 (square section) to 2.5e-3 (aspect 0.3)
    at the sides of issue 30.

    Parameters
    ----------
    side_m : float
        Side a of the mean turn, m.
    width_m, depth_m : float
        Axial width w and depth h of the section, m.

    Returns
    -------
    float
        L / N², H.
    """
    d_r, d_z, weight = gauss_legendre_pack(depth_m, (_SELF_NODES,) * 2, width_m)
    di, dj = d_r[:, None], d_r[None, :]
    z = d_z[:, None] - d_z[None, :]
    pair_weight = weight[:, None] * weight[None, :]
    s = di - dj
    d_sq = s * s + z * z
    x = side_m + di + dj
    r = np.sqrt(x * x + d_sq)
    smooth = x * np.log(x + r) - r  # G(X, d) + X ln d
    a_s = np.abs(s)
    d_safe = np.sqrt(np.where(d_sq > 0.0, d_sq, 1.0))
    g_s = np.where(d_sq > 0.0, a_s * np.arcsinh(a_s / d_safe) - np.sqrt(s * s + d_sq), 0.0)
    k = MU0_T_m_per_A / (4.0 * math.pi)
    gmd = float(rectangle_gmd_m(width_m, depth_m))
    like = 2.0 * k * (np.sum(pair_weight * (smooth - g_s)) - side_m * math.log(gmd))
    opposite = parallel_filaments_mutual_H(
        side_m + 2.0 * di, side_m + 2.0 * dj, s, np.sqrt(x * x + z * z)
    )
    return float(4.0 * (like - np.sum(pair_weight * opposite)))


def _check_aspect(aspect: Any) -> float:
    lo, hi = PACK_ASPECT_RANGE
    ok = not isinstance(aspect, bool) and isinstance(aspect, (int, float, np.floating))
    if not ok or not lo <= aspect <= hi:
        raise InputError("pack_aspect", aspect, f"a number in [{lo:g}, {hi:g}]")
    return float(aspect)


@dataclass(frozen=True)
class SquarePair:
    """Two coaxial, series-connected square coils of N turns each; all quantities SI.

    The same interface as :class:`coils.HelmholtzPair` (field, gains, resistance,
    inductances, pack geometry), with the side of the mean turn in place of its radius.

    Parameters
    ----------
    side_m : float
        Side a of each coil's mean turn (the centre line of the winding pack), m.
    turns : int
        Turns N of each coil, count.
    axis : {"x", "y", "z"}
        Common axis of the two coils.
    separation_m : float, optional
        Distance between the coil planes, m; default 0.5445 a (:data:`SQUARE_HELMHOLTZ_RATIO`).
    wire_diameter_m : float
        Bare copper diameter d, m.
    packing_factor : float
        Copper area / pack area, dimensionless, in (0, π/(2√3)).
    filaments : (int, int)
        Number of Gauss-Legendre filaments across the pack's depth and width used for the
        field, counts.
    pack_aspect : float
        Axial width / depth of the winding pack, a ratio (dimensionless), in
        :data:`coils.pair.PACK_ASPECT_RANGE`.

    Raises
    ------
    InputError
        A parameter outside its range, named by its parameter name; also a pack depth >= a
        (``wire_diameter_m``: no room inside the frame) or coils that overlap
        (``separation_m``).
    """

    side_m: float
    turns: int
    axis: Axis = "z"
    separation_m: float | None = None
    wire_diameter_m: float = 2.5e-3
    packing_factor: float = 0.7
    filaments: tuple[int, int] = (1, 1)
    pack_aspect: float = 1.0

    #: The shape of the coils (``coils.HelmholtzPair`` is a ``"circle"``).
    shape: ClassVar[str] = "square"

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "side_m", check_positive("side_m", self.side_m))
        set_(self, "turns", _check_count("turns", self.turns))
        if self.axis not in AXES:
            raise InputError("axis", self.axis, "one of 'x', 'y', 'z'")
        sep = (
            SQUARE_HELMHOLTZ_RATIO * self.side_m if self.separation_m is None else self.separation_m
        )
        set_(self, "separation_m", check_positive("separation_m", sep))
        set_(self, "wire_diameter_m", check_positive("wire_diameter_m", self.wire_diameter_m))
        pf = check_positive("packing_factor", self.packing_factor)
        if pf >= MAX_PACKING_FACTOR:
            raise InputError("packing_factor", pf, f"a number in (0, {MAX_PACKING_FACTOR:.4f})")
        set_(self, "packing_factor", pf)
        if not (isinstance(self.filaments, tuple) and len(self.filaments) == 2):
            raise InputError("filaments", self.filaments, "a pair (depth, axial) of counts >= 1")
        set_(self, "filaments", tuple(_check_count("filaments", n) for n in self.filaments))
        set_(self, "pack_aspect", _check_aspect(self.pack_aspect))
        depth, width = self.winding_pack_depth_m, self.winding_pack_width_m
        if depth >= self.side_m:
            raise InputError(
                "wire_diameter_m",
                self.wire_diameter_m,
                f"a wire thin enough that the winding pack depth (now {depth:.4g} m "
                f"for {self.turns} turns) is below side_m = {self.side_m:.4g} m",
            )
        if width >= sep:
            raise InputError(
                "separation_m",
                self.separation_m,
                f"a separation larger than the winding pack width {width:.4g} m "
                "(else the two coils overlap)",
            )

    # --- geometry ------------------------------------------------------------------------------
    @property
    def axis_index(self) -> int:
        """Axis index: 0, 1 or 2 for x, y or z."""
        return AXES.index(self.axis)

    @property
    def spacing_m(self) -> float:
        """Distance between the two coil planes, m."""
        return float(self.separation_m)  # type: ignore[arg-type]

    @property
    def half_side_m(self) -> float:
        """Half side a/2 of the mean turn, m."""
        return 0.5 * self.side_m

    @property
    def radius_m(self) -> float:
        """Distance from the axis to the middle of the mean turn's sides, a/2, m.

        The square's counterpart of a circle's radius where a length scale is needed (the
        inner face of the pack is at radius_m - h/2 from the axis at the middle of each side,
        the nearest it comes to the axis); lengths, areas and fields use the side.
        """
        return self.half_side_m

    @property
    def turn_radius_m(self) -> float:
        """Radius of the circle as long as the mean turn, 4a / (2π), m: a ring of it has the
        square frame's volume w h · 4a and faces 2 (w + h) · 4a exactly (the thermal model's
        :class:`coils.thermal.WindingPack` takes a pack by this radius)."""
        return self.mean_turn_length_m / (2.0 * math.pi)

    @property
    def wire_area_m2(self) -> float:
        """Bare copper cross-section of the wire, π d² / 4, m²."""
        return math.pi * self.wire_diameter_m**2 / 4.0

    @property
    def winding_pack_area_m2(self) -> float:
        """Cross-section of one coil's winding pack, N π d² / 4 / packing_factor, m²."""
        return self.turns * self.wire_area_m2 / self.packing_factor

    @property
    def winding_pack_side_m(self) -> float:
        """Side of the square of the pack's area, sqrt(w h), m."""
        return math.sqrt(self.winding_pack_area_m2)

    @property
    def winding_pack_width_m(self) -> float:
        """Axial width w = sqrt(A · aspect) of each winding pack, m."""
        return math.sqrt(self.winding_pack_area_m2 * self.pack_aspect)

    @property
    def winding_pack_depth_m(self) -> float:
        """Depth h = sqrt(A / aspect) of each winding pack across its side, m."""
        return math.sqrt(self.winding_pack_area_m2 / self.pack_aspect)

    @property
    def mean_turn_length_m(self) -> float:
        """Length of the mean turn, 4 a, m (exact for the square frame: module notes)."""
        return 4.0 * self.side_m

    @property
    def wire_length_m(self) -> float:
        """Copper length of both coils, 2 N · 4 a, m."""
        return 2.0 * self.turns * self.mean_turn_length_m

    @cached_property
    def filament_set(self) -> SquareFilamentSet:
        """The field model: both coils as Gauss-Legendre grids of square filaments."""
        dr, dz, w = gauss_legendre_pack(
            self.winding_pack_depth_m, self.filaments, self.winding_pack_width_m
        )
        half = 0.5 * self.spacing_m
        n = len(w)
        return SquareFilamentSet(
            axes=np.full(2 * n, self.axis_index),
            half_sides_m=np.tile(self.half_side_m + dr, 2),
            centres_m=np.concatenate([-half + dz, half + dz]),
            turns=np.tile(self.turns * w, 2),
            columns=np.zeros(2 * n, dtype=int),
            column_axes=(self.axis_index,),
        )

    # --- field ---------------------------------------------------------------------------------
    def field(self, points_m: np.ndarray, current_A: float) -> np.ndarray:
        """Field of the pair, T.

        Parameters
        ----------
        points_m : array_like, shape (n, 3) or (3,)
            Field points in the coil frame (pair centre at the origin), m.
        current_A : float
            Current in the series pair, A.

        Returns
        -------
        ndarray, shape (n, 3) (or (3,) for one point)
            Magnetic flux density, T.
        """
        p = np.asarray(points_m, dtype=float)
        b = self.filament_set.field(np.atleast_2d(p), np.array([[float(current_A)]]))
        return b[0] if p.ndim == 1 else b

    @cached_property
    def centre_field_per_amp_T_per_A(self) -> float:
        """Field at the centre per ampere, T/A: the exact sum over the square filaments.

        For one filament per coil, 4 μ0 N a² / (π (a² + s²) sqrt(a²/2 + s²/4)) (each side a
        finite straight wire at distance sqrt(a² + s²)/2; tested).
        """
        fs = self.filament_set
        zero = np.zeros_like(fs.half_sides_m)
        b_w = square_field_local(fs.half_sides_m, zero, zero, -fs.centres_m)[2]
        return float(np.sum(fs.turns * b_w))

    @cached_property
    def pack_centre_field_per_amp_T_per_A(self) -> float:
        """Field at the centre per ampere with each coil's current spread uniformly over its
        rectangular winding pack, T/A.

        8 x 8 Gauss-Legendre square filaments per coil (whatever ``filaments`` the field model
        uses), each the exact centre field of a square loop (:func:`square_field_local`).
        """
        from coils.pair import _PACK_FIELD_NODES

        dr, dz, w = gauss_legendre_pack(
            self.winding_pack_depth_m, (_PACK_FIELD_NODES,) * 2, self.winding_pack_width_m
        )
        half = 0.5 * self.spacing_m
        half_sides = np.tile(self.half_side_m + dr, 2)
        centres = np.concatenate([-half + dz, half + dz])
        zero = np.zeros_like(half_sides)
        b_w = square_field_local(half_sides, zero, zero, -centres)[2]
        return float(np.sum(np.tile(self.turns * w, 2) * b_w))

    # --- electrical ----------------------------------------------------------------------------
    def resistance_ohm(self, temperature_C: float = 20.0) -> float:
        """Resistance of both coils in series at a copper temperature, Ω (DC, as the circle's:
        ρ(T) · 2 N · 4a / (π d²/4), IEC 60028).

        Parameters
        ----------
        temperature_C : float
            Copper temperature, °C.

        Returns
        -------
        float
            DC resistance of the series pair, Ω.
        """
        return float(
            copper_resistivity_ohm_m(temperature_C) * self.wire_length_m / self.wire_area_m2
        )

    @cached_property
    def self_inductance_H(self) -> float:
        """Self inductance of one coil, H: N² times the section average of the exact
        square-to-square mutual inductance, its singular part through the section's geometric
        mean distance (:func:`square_pack_self_inductance_H`; uniform current density).
        Within 2.5e-3 of Grover's square with the GMD (:func:`grover_square_inductance_H`),
        which takes every filament at side a; the tests check both against a filament-sum
        volume integral."""
        per_turn = square_pack_self_inductance_H(
            self.side_m, self.winding_pack_width_m, self.winding_pack_depth_m
        )
        return float(self.turns**2 * per_turn)

    @cached_property
    def mutual_inductance_H(self) -> float:
        """Mutual inductance between the two coils of the pair, H: N² times the exact
        square-to-square formula (:func:`coils.square.square_mutual_inductance_H`) averaged over
        both packs with a 4 x 4 Gauss-Legendre rule each (the packs do not touch)."""
        dr, dz, w = gauss_legendre_pack(
            self.winding_pack_depth_m, (_MUTUAL_NODES,) * 2, self.winding_pack_width_m
        )
        h1, h2 = self.half_side_m + dr[:, None], self.half_side_m + dr[None, :]
        dist = self.spacing_m + dz[:, None] - dz[None, :]
        m = square_mutual_inductance_H(h1, h2, dist)
        return float(self.turns**2 * np.sum(w[:, None] * w[None, :] * m))

    @property
    def series_inductance_H(self) -> float:
        """Inductance of the two coils in series aiding, 2 L + 2 M, H."""
        return 2.0 * self.self_inductance_H + 2.0 * self.mutual_inductance_H

    # --- thermal -------------------------------------------------------------------------------
    @property
    def surface_area_m2(self) -> float:
        """Outer surface of both winding packs, 2 x 2 (w + h) x 4a, m²."""
        perimeter = 2.0 * (self.winding_pack_width_m + self.winding_pack_depth_m)
        return 2.0 * perimeter * self.mean_turn_length_m

    def thermal_conductance_W_per_K(self, heat_transfer_coefficient_W_m2K: float) -> float:
        """Thermal conductance from both coils to ambient air, h A, W/K (as the circle's).

        Parameters
        ----------
        heat_transfer_coefficient_W_m2K : float
            Convective coefficient h, W/(m²·K).

        Returns
        -------
        float
            Thermal conductance h A of both coils' outer surface, W/K.
        """
        h = check_positive("heat_transfer_coefficient_W_m2K", heat_transfer_coefficient_W_m2K)
        return h * self.surface_area_m2
