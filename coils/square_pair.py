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

from coils.filaments import Axis, gauss_legendre_pack
from coils.pair import _stefan_y1
from coils.square import (
    SquareFilamentSet,
    parallel_filaments_mutual_H,
    square_field_local,
    square_mutual_inductance_H,
)
from coils.winding import MeasuredConstants, WoundPair
from spiralcap.core import backend as bk
from spiralcap.core.constants import MU0_T_m_per_A

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


def _rectangle_points(axis: int, side_u: float, side_v: float, offset: float, n: int) -> np.ndarray:
    """n points evenly (in the parameter) along the mean rectangle of sides (side_u, side_v)
    along the next two axes in ascending order, in the plane ``x[axis] = offset``, (n, 3), m."""
    u, v = [k for k in range(3) if k != axis]
    t = np.arange(n) / n
    pts = np.zeros((n, 3))
    pts[:, axis] = offset
    side, along = np.divmod(4.0 * t, 1.0)  # which side, and how far along it (0..1)
    hu, hv = 0.5 * side_u, 0.5 * side_v
    wu, wv = side_u * (along - 0.5), side_v * (along - 0.5)
    cu = np.choose(side.astype(int), [hu, -wu, -hu, wu])
    cv = np.choose(side.astype(int), [wv, hv, -wv, -hv])
    pts[:, u], pts[:, v] = cu, cv
    return pts


def _rectangle_distance(
    pts: np.ndarray, axis: int, side_u: float, side_v: float, offset: float
) -> np.ndarray:
    """Exact distance of points (n, 3) to the mean rectangle of sides (side_u, side_v) along
    the other two axes in ascending order, in the plane ``x[axis] = offset``, m."""
    u, v = [k for k in range(3) if k != axis]
    normal = pts[:, axis] - offset
    du, dv = np.abs(pts[:, u]) - 0.5 * side_u, np.abs(pts[:, v]) - 0.5 * side_v
    outside = np.hypot(np.maximum(du, 0.0), np.maximum(dv, 0.0))
    in_plane = np.where(np.maximum(du, dv) > 0.0, outside, -np.maximum(du, dv))
    return np.hypot(in_plane, normal)


@dataclass(frozen=True)
class SquarePair(WoundPair):
    """Two coaxial, series-connected square coils of N turns each; all quantities SI.

    The same interface as :class:`coils.HelmholtzPair` (field, gains, resistance,
    inductances, pack geometry), with the side of the mean turn in place of its radius: the
    winding, field, resistance, series inductance and cooling are
    :class:`coils.winding.WoundPair`'s (mean turn 4a); the filament set, centre field and
    inductances are the square's.

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
    measured : coils.winding.MeasuredConstants or None
        A lab's measured R and L of the pair as wired, which its resistance and series
        inductance then answer (default None: computed from the geometry).

    Raises
    ------
    InputError
        A parameter outside its range, named by its parameter name; also a pack depth >= a
        (``wire_diameter_m``: no room inside the frame) or coils that overlap
        (``separation_m``).

    Examples
    --------
    A 0.6 m square pair of 200 turns at the Helmholtz spacing 0.5445 a; its centre field against
    four straight segments per coil (Biot-Savart on the axis of a square loop):

    >>> import math
    >>> import numpy as np
    >>> from coils import SquarePair
    >>> pair = SquarePair(0.6, 200, "x")
    >>> a, h = 0.6, pair.separation_m / 2
    >>> loop = 4e-7 * 200 * a**2 / (2 * (h**2 + a**2 / 4) * math.sqrt(h**2 + a**2 / 2))
    >>> print(f"{pair.separation_m:.4f} m; {pair.field(np.zeros(3), 1.0)[0] * 1e3:.5f} mT/A; by hand {2 * loop * 1e3:.5f}")
    0.3267 m; 0.54291 mT/A; by hand 0.54291
    """

    side_m: float
    turns: int
    axis: Axis = "z"
    separation_m: float | None = None
    wire_diameter_m: float = 2.5e-3
    packing_factor: float = 0.7
    filaments: tuple[int, int] = (1, 1)
    pack_aspect: float = 1.0
    measured: MeasuredConstants | None = None

    #: The shape of the coils (``coils.HelmholtzPair`` is a ``"circle"``).
    shape: ClassVar[str] = "square"
    _SIZE_KEY: ClassVar[str] = "side_m"
    _TURN_LENGTH_PER_SIZE: ClassVar[float] = 4.0
    _DEFAULT_SPACING_PER_SIZE: ClassVar[float] = SQUARE_HELMHOLTZ_RATIO
    _FILAMENT_PAIR: ClassVar[str] = "(depth, axial) of counts"
    SIZE_NAMES: ClassVar[tuple[str, ...]] = ("side_m",)

    # --- the shape's terms (coils.winding.WoundPair) -------------------------------------------
    @classmethod
    def reach_m(cls, sizes: tuple[Any, ...]) -> Any:
        """Distance from the axis to the middle of the mean turn's sides, a/2, m.

        Parameters
        ----------
        sizes : tuple of float or CasADi
            The side (a,), m.

        Returns
        -------
        float or CasADi
            a/2, m.
        """
        return 0.5 * sizes[0]

    @classmethod
    def tube_radius_m(cls, width_m: Any, depth_m: Any) -> Any:
        """Radius of the tube about the mean turn that holds the frame: its sharp outer corner,
        (h/2, h/2, w/2) from the mean turn's corner, is sqrt(h²/2 + w²/4) away, m.

        Parameters
        ----------
        width_m : float or CasADi
            Axial width w of the winding pack, m.
        depth_m : float or CasADi
            Depth h of the winding pack across each side, m.

        Returns
        -------
        float or CasADi
            Tube radius sqrt(h²/2 + w²/4), m.
        """
        return bk.sqrt(0.5 * depth_m * depth_m + 0.25 * width_m * width_m)

    @classmethod
    def thermal_ring(cls, axis: str, sizes: tuple[Any, ...]) -> dict[str, Any]:
        """A ring as long as the mean turn (radius 4a/(2π)) with vertical bars of height a
        where the frame stands in a vertical plane (the x and y pairs), m.

        Parameters
        ----------
        axis : {"x", "y", "z"}
            The pair's axis: the x and y frames stand in a vertical plane, the z frame lies
            flat.
        sizes : tuple of float or CasADi
            The side (a,), m.

        Returns
        -------
        dict of str to float or CasADi
            :class:`coils.thermal.WindingPack` fields by name, each in the unit its name
            carries (m): ``mean_radius_m`` = 2a/π, and ``vertical_bar_height_m`` = a for the x
            and y pairs (absent for z).
        """
        side = sizes[0]
        bars = {"vertical_bar_height_m": side} if axis != "z" else {}
        return {"mean_radius_m": 4.0 * side / (2.0 * bk.pi), **bars}

    @classmethod
    def terms(
        cls, sizes: tuple[Any, ...], turns: Any, separation: Any, width: Any, depth: Any
    ) -> dict[str, Any]:
        """Two square loops of N turns, side a, at ±s/2: centre gain
        4 μ0 N a² / (π (a² + s²) sqrt(a²/2 + s²/4)) (each side a finite straight wire), wire
        2N · 4a, N² times Grover's square with the section's geometric mean distance, and N²
        times the coaxial centre-line squares' mutual inductance; SI, backend-generic.

        Parameters
        ----------
        sizes : tuple of float or CasADi
            The side (a,), m.
        turns : int, float or CasADi
            Turns N of each coil, count.
        separation : float or CasADi
            Distance s between the coil planes, m.
        width : float or CasADi
            Axial width w of each winding pack, m.
        depth : float or CasADi
            Depth h of each winding pack across each side, m.

        Returns
        -------
        dict of str to float or CasADi
            The four terms by name, each in the unit its name carries: ``gain_T_per_A``, T/A;
            ``length_m``, m; ``self_inductance_H`` (one coil) and ``mutual_filament_H``
            (N² times the centre-line squares'), H.
        """
        side = sizes[0]
        half = 0.5 * side
        a2, s2 = side * side, separation * separation
        gain = (
            4.0 * MU0_T_m_per_A * turns * a2 / (bk.pi * (a2 + s2) * bk.sqrt(0.5 * a2 + 0.25 * s2))
        )
        return {
            "gain_T_per_A": gain,
            "length_m": 2.0 * turns * 4.0 * side,
            "self_inductance_H": turns
            * turns
            * grover_square_inductance_H(side, rectangle_gmd_m(width, depth)),
            "mutual_filament_H": turns * turns * square_mutual_inductance_H(half, half, separation),
        }

    @classmethod
    def mean_turn_points(
        cls, axis: int, sizes: tuple[float, ...], offset: float, n: int
    ) -> np.ndarray:
        """n points evenly along the mean square (side a, sides along the other two axes) in
        the plane ``x[axis] = offset``, (n, 3), m.

        Parameters
        ----------
        axis : int
            The pair's axis, an index (0, 1, 2 for x, y, z).
        sizes : tuple of float
            The side (a,), m.
        offset : float
            Axial coordinate of the square's plane, m.
        n : int
            Number of points (evenly along the perimeter, the same step on every side).

        Returns
        -------
        ndarray, shape (n, 3)
            The points, m.
        """
        return _rectangle_points(axis, sizes[0], sizes[0], offset, n)

    @classmethod
    def mean_turn_distance_m(
        cls, points: np.ndarray, axis: int, sizes: tuple[float, ...], offset: float
    ) -> np.ndarray:
        """Exact distance of points (n, 3) to the mean square in the plane ``x[axis] =
        offset``, m.

        Parameters
        ----------
        points : ndarray, shape (n, 3)
            The points, m.
        axis : int
            The pair's axis, an index (0, 1, 2 for x, y, z).
        sizes : tuple of float
            The side (a,), m.
        offset : float
            Axial coordinate of the square's plane, m.

        Returns
        -------
        ndarray, shape (n,)
            Distance of each point to the square's perimeter, m.
        """
        return _rectangle_distance(points, axis, sizes[0], sizes[0], offset)

    def pack_solids(self) -> tuple[Any, Any]:
        """The two packs as solid frames (:class:`coils.clearance.Frame`) at ∓s/2.

        Returns
        -------
        tuple of Frame
            The coil at -s/2 and the coil at +s/2: square frames of side a, the pack's width and
            depth (SI).
        """
        from coils.clearance import Frame

        half = 0.5 * self.spacing_m
        return tuple(  # type: ignore[return-value]
            Frame(
                self.axis_index,
                self.side_m,
                sign * half,
                self.winding_pack_width_m,
                self.winding_pack_depth_m,
            )
            for sign in (-1.0, 1.0)
        )

    def view_pack(self) -> Any:
        """The packs for the view factors (:class:`coils.viewfactors.PackFrame`).

        Returns
        -------
        PackFrame
            The pair's axis index, side a, spacing, pack width and depth (a square: no second
            side; SI).
        """
        from coils.viewfactors import PackFrame

        return PackFrame(
            self.axis_index,
            self.side_m,
            self.spacing_m,
            self.winding_pack_width_m,
            self.winding_pack_depth_m,
        )

    @property
    def vertical_bar_height_m(self) -> float:
        """Height of the vertical bars of a frame in a vertical plane (x, y pairs): a; 0 for the
        horizontal z frame, m."""
        return float(self.side_m) if self.axis != "z" else 0.0

    # --- geometry ------------------------------------------------------------------------------
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
    def mean_turn_length_m(self) -> float:
        """Length of the mean turn, 4 a, m (exact for the square frame: module notes)."""
        return self._TURN_LENGTH_PER_SIZE * self.side_m

    @property
    def _filament_size_m(self) -> float:
        """Half side of the filament at the pack centre, a/2, m."""
        return self.half_side_m

    @cached_property
    def filament_set(self) -> SquareFilamentSet:
        """The field model: both coils as Gauss-Legendre grids of square filaments."""
        half_sides, common = self._filament_set_fields()
        return SquareFilamentSet(half_sides_m=half_sides, **common)

    # --- field ---------------------------------------------------------------------------------
    @staticmethod
    def _centre_field_T_per_A(
        half_sides_m: np.ndarray, centres_m: np.ndarray, turns: np.ndarray
    ) -> float:
        """Field at the centre per ampere of coaxial squares, T/A (:func:`square_field_local`)."""
        zero = np.zeros_like(half_sides_m)
        b_w = square_field_local(half_sides_m, zero, zero, -centres_m)[2]
        return float(np.sum(turns * b_w))

    @cached_property
    def centre_field_per_amp_T_per_A(self) -> float:
        """Field at the centre per ampere, T/A: the exact sum over the square filaments.

        For one filament per coil, 4 μ0 N a² / (π (a² + s²) sqrt(a²/2 + s²/4)) (each side a
        finite straight wire at distance sqrt(a² + s²)/2; tested).
        """
        return self._centre_field_T_per_A(*self._coil_grids(self.filaments))

    # --- electrical ----------------------------------------------------------------------------
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
        return self._mutual_average_H(square_mutual_inductance_H)
