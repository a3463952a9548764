"""Frame pairs: two coaxial rectangular (or square) coils in series with rectangular packs.

Geometry: each coil's mean turn is a rectangle of sides a, b (the winding's centre line) along the
next two axes in cyclic order (x: y, z; y: z, x; z: x, y), sharp corners; the winding pack is
the section of :class:`coils.winding.WoundPair` (w x h, h across each side), so the pack is a
frame whose filament at depth offset δ is the rectangle of sides a + 2δ, b + 2δ: its mean turn
is exactly 2(a + b) long, its volume w h · 2(a + b) and its faces 2(w + h) · 2(a + b). The coils
sit at ±s/2 along the pair's axis, s by default the spacing with zero field curvature at the
centre for the aspect b/a (:func:`coils.rectangle.helmholtz_spacing_ratio`, 0.5445 a at a = b).

:class:`FramePair` holds all of it once, in the sides (a, b) its subclass maps its sizes to
(:meth:`FramePair.sides_of`): :class:`RectanglePair` (``sides_m``, two sides) here and
:class:`coils.SquarePair` (``side_m``, a = b) in :mod:`coils.square_pair`. A new frame shape
is a subclass with its size field, its size names and that map.

Field: Biot-Savart of four finite straight segments per filament
(:class:`coils.rectangle.RectangleFilamentSet`). Self inductance: N² times the section average
of the exact rectangle-to-rectangle mutual inductance
(:func:`coils.rectangle.rectangle_pack_self_inductance_H`); the sizing's closed forms
(:meth:`FramePair.terms`) take Grover's rectangle with the section's geometric mean distance
(:func:`coils.rectangle.grover_rectangle_inductance_H`, :func:`coils.rectangle.rectangle_gmd_m`).
Mutual inductance: N² times the exact coaxial-rectangle Neumann formula averaged over both packs.
Long frames are what labs build for patient access: the frame is long along the body.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from coils.filaments import Axis
from coils.rectangle import (
    RECTANGLE_ASPECT_RANGE,
    RectangleFilamentSet,
    grover_rectangle_inductance_H,
    helmholtz_spacing_ratio,
    rectangle_axial_field_T_per_A,
    rectangle_field_local,
    rectangle_gmd_m,
    rectangle_mutual_inductance_H,
    rectangle_pack_self_inductance_H,
)
from coils.winding import MeasuredConstants, WoundPair
from spiralcap.core import backend as bk
from spiralcap.core.errors import InputError, check_positive

__all__ = ["FramePair", "RectanglePair"]


def _ascending(axis: int, sizes: tuple[Any, ...]) -> tuple[Any, Any]:
    """The sides (a, b) along the next two axes in cyclic order, reordered to the two other
    axes in ascending order (a y pair's a runs along z, its b along x)."""
    a, b = sizes
    return (b, a) if axis == 1 else (a, b)


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


class FramePair(WoundPair):
    """Base of the frame pairs (rectangular and square turns): everything but the size field.

    Not made on its own: a frozen dataclass with :class:`coils.winding.WoundPair`'s fields and
    a size field derives from it and maps its sizes to the mean turn's sides (a, b) along the
    next two axes in cyclic order (:meth:`sides_of`); the field, gains, inductances, pack
    solids, cooling and the backend-generic terms the sizing asks are all here, in a and b.
    """

    _FILAMENT_PAIR: ClassVar[str] = "(depth, axial) of counts"

    @classmethod
    def sides_of(cls, sizes: tuple[Any, ...]) -> tuple[Any, Any]:
        """The mean turn's sides (a, b) along the next two axes in cyclic order at sizes
        ``sizes`` (:attr:`SIZE_NAMES` order), m (backend-generic).

        Parameters
        ----------
        sizes : tuple of float or CasADi
            The pair's sizes, m.

        Returns
        -------
        tuple of float or CasADi
            (a, b), m. The base class has none (NotImplementedError): each frame supplies them.
        """
        raise NotImplementedError

    @property
    def frame_sides_m(self) -> tuple[float, float]:
        """The mean turn's sides (a, b) along the next two axes in cyclic order, m."""
        a, b = self.sides_of(self.sizes_m)
        return (float(a), float(b))

    # --- the shape's terms (coils.winding.WoundPair) -------------------------------------------
    @classmethod
    def turn_length_m(cls, sizes: tuple[Any, ...]) -> Any:
        """The mean turn, 2 (a + b), m (exact for the mitred frame).

        Parameters
        ----------
        sizes : tuple of float or CasADi
            The sizes in :attr:`SIZE_NAMES` order, m (:meth:`sides_of` gives the sides a, b
            along the next two axes in cyclic order).

        Returns
        -------
        float or CasADi
            Mean turn length 2 (a + b), m.
        """
        a, b = cls.sides_of(sizes)
        return 2.0 * (a + b)

    @classmethod
    def reach_m(cls, sizes: tuple[Any, ...]) -> Any:
        """Distance from the axis to the middle of the longer sides, min(a, b)/2, m.

        Parameters
        ----------
        sizes : tuple of float or CasADi
            The sizes in :attr:`SIZE_NAMES` order, m (:meth:`sides_of` gives the sides a, b
            along the next two axes in cyclic order).

        Returns
        -------
        float or CasADi
            min(a, b)/2, m.
        """
        a, b = cls.sides_of(sizes)
        return 0.5 * bk.fmin(a, b)

    @classmethod
    def depth_limit_m(cls, sizes: tuple[Any, ...]) -> Any:
        """The pack's depth must stay below the shorter side, m.

        Parameters
        ----------
        sizes : tuple of float or CasADi
            The sizes in :attr:`SIZE_NAMES` order, m (:meth:`sides_of` gives the sides a, b
            along the next two axes in cyclic order).

        Returns
        -------
        float or CasADi
            The depth limit min(a, b), m.
        """
        a, b = cls.sides_of(sizes)
        return bk.fmin(a, b)

    @classmethod
    def reaches_m(cls, sizes: tuple[Any, ...]) -> tuple[Any, Any]:
        """(a/2, b/2): the mean turn's half sides along the next two axes in cyclic order, m.

        Parameters
        ----------
        sizes : tuple of float or CasADi
            The sizes in :attr:`SIZE_NAMES` order, m (:meth:`sides_of` gives the sides a, b
            along the next two axes in cyclic order).

        Returns
        -------
        tuple of float or CasADi
            (a/2, b/2), m.
        """
        a, b = cls.sides_of(sizes)
        return (0.5 * a, 0.5 * b)

    @classmethod
    def tube_radius_m(cls, width_m: Any, depth_m: Any) -> Any:
        """The frame's sharp outer corner, sqrt(h²/2 + w²/4) from the mean turn's corner, m.

        Parameters
        ----------
        width_m : float or CasADi
            Axial width w of the winding pack, m.
        depth_m : float or CasADi
            Depth h of the winding pack across each side, m.

        Returns
        -------
        float or CasADi
            Radius sqrt(h²/2 + w²/4) of the tube about the mean turn that holds the frame, m.
        """
        return bk.sqrt(0.5 * depth_m * depth_m + 0.25 * width_m * width_m)

    @classmethod
    def thermal_ring(cls, axis: str, sizes: tuple[Any, ...]) -> dict[str, Any]:
        """A ring as long as the mean turn (radius (a + b)/π), with vertical bars of the side
        along z where the frame stands in a vertical plane (x pair: b; y pair: a), m.

        Parameters
        ----------
        axis : {"x", "y", "z"}
            The pair's axis: the x and y frames stand in a vertical plane, the z frame lies
            flat.
        sizes : tuple of float or CasADi
            The sizes in :attr:`SIZE_NAMES` order, m (:meth:`sides_of` gives the sides a, b
            along the next two axes in cyclic order).

        Returns
        -------
        dict of str to float or CasADi
            :class:`coils.thermal.WindingPack` fields by name, each in the unit its name
            carries (m): ``mean_radius_m`` = (a + b)/π, and ``vertical_bar_height_m`` for the
            x and y pairs (absent for z).
        """
        ring = {"mean_radius_m": cls.turn_length_m(sizes) / (2.0 * bk.pi)}
        if axis == "z":
            return ring
        a, b = cls.sides_of(sizes)
        return {**ring, "vertical_bar_height_m": b if axis == "x" else a}

    @classmethod
    def terms(
        cls, sizes: tuple[Any, ...], turns: Any, separation: Any, width: Any, depth: Any
    ) -> dict[str, Any]:
        """Two rectangles of N turns at ±s/2: centre gain 2 N B1(s/2)
        (:func:`coils.rectangle.rectangle_axial_field_T_per_A`), wire 2N · 2(a + b), N² times
        Grover's rectangle with the section's GMD and N² times the centre-line rectangles'
        mutual inductance; SI, backend-generic.

        Parameters
        ----------
        sizes : tuple of float or CasADi
            The sizes in :attr:`SIZE_NAMES` order, m (:meth:`sides_of` gives the sides a, b
            along the next two axes in cyclic order).
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
            (N² times the centre-line rectangles'), H.
        """
        a, b = cls.sides_of(sizes)
        return {
            "gain_T_per_A": 2.0 * turns * rectangle_axial_field_T_per_A(a, b, 0.5 * separation),
            "length_m": 2.0 * turns * 2.0 * (a + b),
            "self_inductance_H": turns
            * turns
            * grover_rectangle_inductance_H(a, b, rectangle_gmd_m(width, depth)),
            "mutual_filament_H": turns
            * turns
            * rectangle_mutual_inductance_H(0.5 * a, 0.5 * b, 0.5 * a, 0.5 * b, separation),
        }

    @classmethod
    def mean_turn_points(
        cls, axis: int, sizes: tuple[float, ...], offset: float, n: int
    ) -> np.ndarray:
        """n points along the mean rectangle in the plane ``x[axis] = offset``, (n, 3), m.

        Parameters
        ----------
        axis : int
            The pair's axis, an index (0, 1, 2 for x, y, z).
        sizes : tuple of float
            The sizes in :attr:`SIZE_NAMES` order, m (:meth:`sides_of` gives the sides a, b
            along the next two axes in cyclic order).
        offset : float
            Axial coordinate of the rectangle's plane, m.
        n : int
            Number of points (a quarter on each side, evenly along it).

        Returns
        -------
        ndarray, shape (n, 3)
            The points, m.
        """
        su, sv = _ascending(axis, cls.sides_of(sizes))
        return _rectangle_points(axis, su, sv, offset, n)

    @classmethod
    def mean_turn_distance_m(
        cls, points: np.ndarray, axis: int, sizes: tuple[float, ...], offset: float
    ) -> np.ndarray:
        """Exact distance of points (n, 3) to the mean rectangle, m.

        Parameters
        ----------
        points : ndarray, shape (n, 3)
            The points, m.
        axis : int
            The pair's axis, an index (0, 1, 2 for x, y, z).
        sizes : tuple of float
            The sizes in :attr:`SIZE_NAMES` order, m (:meth:`sides_of` gives the sides a, b
            along the next two axes in cyclic order).
        offset : float
            Axial coordinate of the rectangle's plane, m.

        Returns
        -------
        ndarray, shape (n,)
            Distance of each point to the rectangle's perimeter, m.
        """
        su, sv = _ascending(axis, cls.sides_of(sizes))
        return _rectangle_distance(points, axis, su, sv, offset)

    def pack_solids(self) -> tuple[Any, Any]:
        """The two packs as solid frames of sides a ± h, b ± h at ∓s/2.

        Returns
        -------
        tuple of Frame
            The coil at -s/2 and the coil at +s/2 (:class:`coils.clearance.Frame` of mean
            sides a, b and the pack's width and depth, SI).
        """
        from coils.clearance import Frame

        half = 0.5 * self.spacing_m
        a, b = self.frame_sides_m
        w, h = self.winding_pack_width_m, self.winding_pack_depth_m
        return tuple(  # type: ignore[return-value]
            Frame(self.axis_index, a, sign * half, w, h, side_v_m=b) for sign in (-1.0, 1.0)
        )

    def view_pack(self) -> Any:
        """The packs for the view factors (:class:`coils.viewfactors.PackFrame`).

        Returns
        -------
        PackFrame
            The pair's axis index, sides a and b, spacing, pack width and depth (SI).
        """
        from coils.viewfactors import PackFrame

        a, b = self.frame_sides_m
        return PackFrame(
            self.axis_index,
            a,
            self.spacing_m,
            self.winding_pack_width_m,
            self.winding_pack_depth_m,
            side_v_m=b,
        )

    @property
    def vertical_bar_height_m(self) -> float:
        """The side along z of a frame in a vertical plane (x pair: b, y pair: a), m; 0 for z."""
        return float(self.thermal_ring(self.axis, self.sizes_m).get("vertical_bar_height_m", 0.0))

    # --- geometry ------------------------------------------------------------------------------
    @property
    def radius_m(self) -> float:
        """Distance from the axis to the middle of the longer sides, min(a, b)/2, m: the nearest
        the mean turn comes to the axis (bore, uniform-region scale)."""
        return 0.5 * min(self.frame_sides_m)

    @property
    def turn_radius_m(self) -> float:
        """Radius of the circle as long as the mean turn, (a + b)/π, m (thermal rings)."""
        return self.mean_turn_length_m / (2.0 * math.pi)

    @property
    def _filament_size_m(self) -> float:
        """Half side a/2 of the filament at the pack centre, m."""
        return 0.5 * self.frame_sides_m[0]

    @property
    def _extra_half_v_m(self) -> float:
        """(b - a)/2: a filament's half side along v less its half side along u, m."""
        a, b = self.frame_sides_m
        return 0.5 * (b - a)

    @cached_property
    def filament_set(self) -> RectangleFilamentSet:
        """The field model: both coils as Gauss-Legendre grids of rectangular filaments."""
        half_u, common = self._filament_set_fields()
        return RectangleFilamentSet(
            half_sides_m=half_u, half_sides_v_m=half_u + self._extra_half_v_m, **common
        )

    # --- field ---------------------------------------------------------------------------------
    def _centre_field_T_per_A(
        self, half_u_m: np.ndarray, centres_m: np.ndarray, turns: np.ndarray
    ) -> float:
        """Field at the centre per ampere of coaxial rectangles, T/A."""
        zero = np.zeros_like(half_u_m)
        b_w = rectangle_field_local(
            half_u_m, half_u_m + self._extra_half_v_m, zero, zero, -centres_m
        )
        return float(np.sum(turns * b_w[2]))

    @cached_property
    def centre_field_per_amp_T_per_A(self) -> float:
        """Field at the centre per ampere, T/A: the exact sum over the rectangular filaments."""
        return self._centre_field_T_per_A(*self._coil_grids(self.filaments))

    # --- electrical ----------------------------------------------------------------------------
    @cached_property
    def self_inductance_H(self) -> float:
        """Self inductance of one coil, H: N² times the section average of the exact
        rectangle-to-rectangle mutual inductance, its singular part through the section's
        geometric mean distance (:func:`coils.rectangle.rectangle_pack_self_inductance_H`;
        uniform current density). Within 2.5e-3 of Grover's rectangle with the GMD (the
        closed form of :meth:`terms`, every filament at the mean sides); the tests check both
        against a filament-sum volume integral. The one method a measured value would replace."""
        a, b = self.frame_sides_m
        per_turn = rectangle_pack_self_inductance_H(
            a, b, self.winding_pack_width_m, self.winding_pack_depth_m
        )
        return float(self.turns**2 * per_turn)

    @cached_property
    def mutual_inductance_H(self) -> float:
        """Mutual inductance between the two coils, H: N² times the exact coaxial-rectangle
        formula (:func:`coils.rectangle.rectangle_mutual_inductance_H`) averaged over both packs
        with a 4 x 4 Gauss-Legendre rule each."""
        extra = self._extra_half_v_m

        def kernel(h1: Any, h2: Any, dist: Any) -> Any:
            return rectangle_mutual_inductance_H(h1, h1 + extra, h2, h2 + extra, dist)

        return self._mutual_average_H(kernel)


@dataclass(frozen=True)
class RectanglePair(FramePair):
    """Two coaxial, series-connected rectangular coils of N turns each; all quantities SI.

    The interface of :class:`coils.HelmholtzPair` and :class:`coils.SquarePair` (field, gains,
    resistance, inductances, pack geometry, solids, cooling) with two sides in place of a
    radius.

    Parameters
    ----------
    sides_m : (float, float)
        Sides a, b of each coil's mean turn along the next two axes in cyclic order, m
        (b / a in :data:`coils.rectangle.RECTANGLE_ASPECT_RANGE`).
    turns : int
        Turns N of each coil, count.
    axis : {"x", "y", "z"}
        Common axis of the two coils.
    separation_m : float, optional
        Distance between the coil planes, m; default the spacing with zero centre curvature.
    wire_diameter_m : float
        Bare copper diameter d, m.
    packing_factor : float
        Copper area / pack area, dimensionless, in (0, π/(2√3)).
    filaments : (int, int)
        Gauss-Legendre filaments across the pack's depth and width for the field, counts.
    pack_aspect : float
        Axial width / depth of the winding pack, dimensionless.
    measured : coils.winding.MeasuredConstants or None
        A lab's measured R and L of the pair as wired, which its resistance and series
        inductance then answer (default None: computed from the geometry).

    Raises
    ------
    InputError
        A parameter outside its range, named by its parameter name (``sides_m`` for two sides
        whose ratio is outside its range); a pack depth >= the shorter side
        (``wire_diameter_m``) or coils that overlap (``separation_m``).

    Examples
    --------
    >>> p = RectanglePair(sides_m=(0.8, 0.62), turns=300, wire_diameter_m=2.36e-3)
    >>> round(p.separation_m / 0.8, 4), round(p.mean_turn_length_m, 3)
    (0.4597, 2.84)
    """

    sides_m: tuple[float, float]
    turns: int
    axis: Axis = "z"
    separation_m: float | None = None
    wire_diameter_m: float = 2.5e-3
    packing_factor: float = 0.7
    filaments: tuple[int, int] = (1, 1)
    pack_aspect: float = 1.0
    measured: MeasuredConstants | None = None

    #: The shape of the coils.
    shape: ClassVar[str] = "rectangle"
    _SIZE_KEY: ClassVar[str] = "sides_m"
    #: One size, the first side a: the sizing scales the rectangle at its aspect b / a.
    SIZE_NAMES: ClassVar[tuple[str, ...]] = ("side_a_m",)
    #: The sizes that follow the free one (:meth:`scaled_sizes`): the second side b.
    DERIVED_SIZE_NAMES: ClassVar[tuple[str, ...]] = ("side_b_m",)

    def _check_size(self) -> tuple[str, float]:
        """Two sides > 0 with b / a in range (InputError naming ``sides_m``); the shorter side
        is what the pack's depth must stay below."""
        s = self.sides_m
        if not (isinstance(s, (tuple, list)) and len(s) == 2):
            raise InputError("sides_m", s, "two sides [a, b] in m")
        a, b = (check_positive("sides_m", float(v)) for v in s)
        lo, hi = RECTANGLE_ASPECT_RANGE
        if not lo <= b / a <= hi:
            raise InputError("sides_m", [a, b], f"two sides with a ratio b/a in [{lo:g}, {hi:g}]")
        object.__setattr__(self, "sides_m", (a, b))
        return "sides_m", min(a, b)

    # --- the sizes ------------------------------------------------------------------------------
    @classmethod
    def sides_of(cls, sizes: tuple[Any, ...]) -> tuple[Any, Any]:
        """The sides (a, b): the sizes themselves, m.

        Parameters
        ----------
        sizes : tuple of float or CasADi
            The sides (a, b), m.

        Returns
        -------
        tuple of float or CasADi
            (a, b), m.
        """
        return (sizes[0], sizes[1])

    @property
    def sizes_m(self) -> tuple[float, ...]:
        """The sides (a, b), m."""
        return (float(self.sides_m[0]), float(self.sides_m[1]))

    @property
    def _size_m(self) -> float:
        """The first side a, m (the scale of tolerances)."""
        return float(self.sides_m[0])

    def size_fields(self, sizes: tuple[float, ...]) -> dict[str, Any]:
        """``sides_m`` of sizes (a, b); a lone first side keeps the aspect b / a.

        Parameters
        ----------
        sizes : tuple of float
            The sides (a, b), or the first side (a,) alone, m.

        Returns
        -------
        dict of str to tuple of float
            ``{"sides_m": (a, b)}``, in the unit its name carries (m).
        """
        a = float(sizes[0])
        b = float(sizes[1]) if len(sizes) > 1 else a * self.sides_m[1] / self.sides_m[0]
        return {"sides_m": (a, b)}

    @property
    def shape_key(self) -> tuple[Any, ...]:
        """The class and the aspect b / a (fixed while the sizing scales the rectangle)."""
        return (type(self), self.sides_m[1] / self.sides_m[0])

    @classmethod
    def scaled_sizes(cls, key: tuple[Any, ...], size: Any) -> tuple[Any, ...]:
        """(a, a · b/a) for the aspect of ``key``, m.

        Parameters
        ----------
        key : tuple
            The shape key (:attr:`shape_key`): the class and the aspect b / a.
        size : float or CasADi
            The first side a, m.

        Returns
        -------
        tuple of float or CasADi
            The sides (a, b), m.
        """
        return (size, key[1] * size)

    @classmethod
    def spacing_per_size(cls, key: tuple[Any, ...]) -> float:
        """The zero-curvature spacing / a at the aspect of ``key`` (a numerical root).

        Parameters
        ----------
        key : tuple
            The shape key (:attr:`shape_key`): the class and the aspect b / a.

        Returns
        -------
        float
            Default separation over the first side a, dimensionless
            (:func:`coils.rectangle.helmholtz_spacing_ratio`; 0.5445 at b = a).
        """
        return helmholtz_spacing_ratio(1.0, key[1])

    @classmethod
    def default_spacing_m(cls, sizes: tuple[Any, ...]) -> Any:
        """The spacing with zero centre curvature at sides (a, b), m (numbers only: a
        numerical root, :func:`coils.rectangle.helmholtz_spacing_ratio`).

        Parameters
        ----------
        sizes : tuple of float
            The sides (a, b), m (numbers, not CasADi expressions).

        Returns
        -------
        float
            Default separation of the coil planes, m.
        """
        a, b = float(sizes[0]), float(sizes[1])
        return helmholtz_spacing_ratio(a, b) * a
