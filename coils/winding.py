"""What a pair of series coils with rectangular winding packs has whatever shape its turns are.

:class:`coils.HelmholtzPair` (circular turns, size the mean radius R),
:class:`coils.SquarePair` (square turns, size the side a of the mean turn) and
:class:`coils.RectanglePair` (rectangular turns, sides a, b) share the winding:
N turns of round copper wire of bare diameter d in a section of area
A = N π d² / 4 / packing_factor, axial width w = sqrt(A · aspect), depth h = sqrt(A / aspect)
across the turn; two coils at ±s/2 on the pair's axis carrying the same current in the same
sense. :class:`WoundPair` holds what follows from that alone: the input checks, the pack
geometry, the Gauss-Legendre grids of both packs, the field, the DC resistance, the series
inductance and the convective conductance. Each pair supplies its size, the length of its mean
turn (2π per unit of radius for a circle; 2(a + b) for the frames of
:class:`coils.rectangle_pair.FramePair`, the square's a = b), the filament set of its shape, the
centre field of a set of its filaments and its inductances.

The shape is an object every layer asks (issue 38): each pair class also owns its
backend-generic terms for numpy and CasADi (:meth:`WoundPair.terms`: the two-filament gain, the
wire, the self and mutual inductance; :meth:`~WoundPair.turn_length_m`,
:meth:`~WoundPair.reach_m`, :meth:`~WoundPair.depth_limit_m`, :meth:`~WoundPair.tube_radius_m`,
:meth:`~WoundPair.half_extents_m`, :meth:`~WoundPair.thermal_ring`, the mean turn's points and
distance, :meth:`~WoundPair.scaled_sizes`, :meth:`~WoundPair.spacing_per_size`) and its parts
(:meth:`~WoundPair.pack_solids`, :meth:`~WoundPair.view_pack`,
:attr:`~WoundPair.vertical_bar_height_m`, :meth:`~WoundPair.formula_corrections`,
:attr:`~WoundPair.size_keys`, :attr:`~WoundPair.RING`), so the sizing NLP, the clearances, the
cooling, the CAD and the export never test which shape a pair is. The resistance
(:meth:`WoundPair.resistance_ohm`) and each shape's ``self_inductance_H`` and
``mutual_inductance_H`` are each one method: where a measured value would sit.

A lab's pair as measured (issue 37) is the pair's own field ``measured``
(:class:`MeasuredConstants`, default None): where given, :meth:`WoundPair.resistance_ohm` and
:attr:`WoundPair.series_inductance_H` answer the measured values (R following copper's
temperature coefficient from the measuring temperature), and
:meth:`WoundPair.computed_resistance_ohm` and :attr:`WoundPair.computed_series_inductance_H`
answer what the geometry gives, for the side-by-side deviation. Every consumer asks the pair;
none holds an override of its own.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from coils.electrical import copper_resistivity_ohm_m
from coils.filaments import AXES, Axis, gauss_legendre_pack
from spiralcap.core import backend as bk
from spiralcap.core.constants import COPPER_DENSITY_kg_m3
from spiralcap.core.errors import InputError, check_positive

__all__ = ["MAX_PACKING_FACTOR", "PACK_ASPECT_RANGE", "MeasuredConstants", "WoundPair"]

#: Densest packing of equal round wires (hexagonal), π / (2 sqrt 3).
MAX_PACKING_FACTOR = math.pi / (2.0 * math.sqrt(3.0))
#: Range of the winding pack aspect (axial width / radial depth) the models are made for.
PACK_ASPECT_RANGE = (0.25, 4.0)
# Gauss-Legendre nodes across each pack for the mutual inductance (converged to < 1e-10).
_MUTUAL_NODES = 4
# Gauss-Legendre nodes across each pack for the pack's own centre field (the on-axis integrand is
# smooth over the pack: 8 x 8 meets the closed form to 1e-15 for the built-in pairs and a pack
# 0.4 R wide at aspect 3, where 4 x 4 is 7e-9 off).
_PACK_FIELD_NODES = 8


def _check_count(key: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise InputError(key, value, "a whole number >= 1")
    return int(value)


def _check_aspect(aspect: Any) -> float:
    lo, hi = PACK_ASPECT_RANGE
    ok = not isinstance(aspect, bool) and isinstance(aspect, (int, float, np.floating))
    if not ok or not lo <= aspect <= hi:
        raise InputError("pack_aspect", aspect, f"a number in [{lo:g}, {hi:g}]")
    return float(aspect)


@dataclass(frozen=True)
class MeasuredConstants:
    """A lab's pair as measured at its terminals (both coils in series, as wired to its
    channel); SI.

    Parameters
    ----------
    resistance_ohm : float or None
        Series resistance at ``temperature_C``, Ω; None: not measured (the computed one).
    temperature_C : float
        Copper temperature of the resistance measurement, °C (default 20).
    inductance_H : float or None
        Series inductance, mutual inductance included, H; None: not measured.

    Raises
    ------
    InputError
        A value that is not a positive number, a temperature outside [-50, 250] °C (the
        copper model's range), or neither constant given, named by its parameter name.

    Examples
    --------
    >>> m = MeasuredConstants(resistance_ohm=7.0, temperature_C=60.0)
    >>> round(m.resistance_ohm_at(20.0), 4)  # copper's coefficient back to 20 °C
    6.0491
    """

    resistance_ohm: float | None = None
    temperature_C: float = 20.0
    inductance_H: float | None = None

    def __post_init__(self) -> None:
        """Check the fields (InputError named by the field), store them as floats."""
        set_ = object.__setattr__
        if self.resistance_ohm is None and self.inductance_H is None:
            raise InputError("resistance_ohm", None, "a measured resistance or inductance")
        for key in ("resistance_ohm", "inductance_H"):
            value = getattr(self, key)
            if value is not None:
                set_(self, key, check_positive(key, value))
        t = self.temperature_C
        ok = not isinstance(t, bool) and isinstance(t, (int, float, np.floating))
        if not ok or not -50.0 <= t <= 250.0:
            raise InputError("temperature_C", t, "a temperature in [-50, 250] °C")
        set_(self, "temperature_C", float(t))

    def resistance_ohm_at(self, temperature_C: float) -> float:
        """The measured resistance brought to a copper temperature, Ω: R_m ρ(T) / ρ(T_m)
        (IEC 60028, :func:`coils.electrical.copper_resistivity_ohm_m`).

        Parameters
        ----------
        temperature_C : float
            Copper temperature, °C.

        Returns
        -------
        float
            The pair's resistance at that temperature, Ω.

        Raises
        ------
        ValueError
            No resistance was measured (only the inductance).
        """
        if self.resistance_ohm is None:
            raise ValueError("no measured resistance")
        rho = copper_resistivity_ohm_m
        return self.resistance_ohm * float(rho(temperature_C) / rho(self.temperature_C))


class WoundPair:
    """Base of the coil pairs: the winding, field, resistance and cooling they share; SI.

    Not made on its own: a frozen dataclass (:class:`coils.HelmholtzPair`,
    :class:`coils.SquarePair`) with the fields ``turns``, ``axis``, ``separation_m``,
    ``wire_diameter_m``, ``packing_factor``, ``filaments``, ``pack_aspect`` and ``measured``
    (:class:`MeasuredConstants` or None) and a size field
    named by ``_SIZE_KEY`` derives from it and sets the class constants: ``_SIZE_KEY``,
    ``_TURN_LENGTH_PER_SIZE`` (mean turn length / size, or its own :meth:`turn_length_m`),
    ``_DEFAULT_SPACING_PER_SIZE``
    (separation / size when ``separation_m`` is not given) and ``_FILAMENT_PAIR`` (how the
    error names the two filament counts). It supplies ``filament_set``,
    ``_filament_size_m`` (the size coordinate of a filament at the pack centre),
    ``_centre_field_T_per_A`` and the inductances ``self_inductance_H`` and
    ``mutual_inductance_H``.
    """

    _SIZE_KEY: ClassVar[str]
    _TURN_LENGTH_PER_SIZE: ClassVar[float]
    _DEFAULT_SPACING_PER_SIZE: ClassVar[float]
    _FILAMENT_PAIR: ClassVar[str]

    if TYPE_CHECKING:  # the fields and shape parts of the dataclasses deriving from this
        turns: int
        axis: Axis
        separation_m: float | None
        wire_diameter_m: float
        packing_factor: float
        filaments: tuple[int, int]
        pack_aspect: float
        measured: MeasuredConstants | None

        @property
        def filament_set(self) -> Any: ...
        @property
        def _filament_size_m(self) -> float: ...
        @property
        def self_inductance_H(self) -> float: ...
        @property
        def mutual_inductance_H(self) -> float: ...
        @property
        def centre_field_per_amp_T_per_A(self) -> float: ...
        @property
        def radius_m(self) -> float: ...

        _centre_field_T_per_A: Callable[..., float]

    def __post_init__(self) -> None:
        """Check every field (InputError named by the field), store the checked values."""
        set_ = object.__setattr__
        key, size = self._check_size()
        set_(self, "turns", _check_count("turns", self.turns))
        if self.axis not in AXES:
            raise InputError("axis", self.axis, "one of 'x', 'y', 'z'")
        default = self.default_spacing_m(self.sizes_m)
        sep = default if self.separation_m is None else self.separation_m
        set_(self, "separation_m", check_positive("separation_m", sep))
        set_(self, "wire_diameter_m", check_positive("wire_diameter_m", self.wire_diameter_m))
        pf = check_positive("packing_factor", self.packing_factor)
        if pf >= MAX_PACKING_FACTOR:
            raise InputError("packing_factor", pf, f"a number in (0, {MAX_PACKING_FACTOR:.4f})")
        set_(self, "packing_factor", pf)
        if not (isinstance(self.filaments, tuple) and len(self.filaments) == 2):
            raise InputError("filaments", self.filaments, f"a pair {self._FILAMENT_PAIR} >= 1")
        set_(self, "filaments", tuple(_check_count("filaments", n) for n in self.filaments))
        set_(self, "pack_aspect", _check_aspect(self.pack_aspect))
        self._check_fits(key, size, sep)

    def _check_size(self) -> tuple[str, float]:
        """Check and store the size field; return its name and the size the pack's depth must
        stay below (the radius, the side), m."""
        key = self._SIZE_KEY
        size = check_positive(key, getattr(self, key))
        object.__setattr__(self, key, size)
        return key, size

    # --- the shape's terms (backend-generic, of the sizes; what the sizing NLP asks) ----------
    #: The names of the pair's sizes as hardware quantities (``radius_m``; ``side_m``; ...).
    SIZE_NAMES: ClassVar[tuple[str, ...]]
    #: The names of the sizes that follow the first (:meth:`scaled_sizes`), none here.
    DERIVED_SIZE_NAMES: ClassVar[tuple[str, ...]] = ()

    @property
    def sizes_m(self) -> tuple[float, ...]:
        """The pair's sizes, in the order of :attr:`SIZE_NAMES`, m."""
        return (float(getattr(self, self._SIZE_KEY)),)

    def with_sizes(self, sizes_m: tuple[float, ...]) -> Any:
        """This pair with sizes ``sizes_m`` (the order of :attr:`SIZE_NAMES`, m); a pair at
        its default spacing keeps it; it carries no measured constants.

        Parameters
        ----------
        sizes_m : tuple of float
            The new sizes in the order of :attr:`SIZE_NAMES`, m.

        Returns
        -------
        WoundPair
            A pair of the same class and fields but those sizes, ``measured`` None, and the
            default spacing of the new sizes where this pair had its default spacing.
        """
        from dataclasses import replace

        me: Any = self
        sep = None if self.helmholtz else self.separation_m
        # a pair of other sizes is not the pair the lab measured: computed constants
        return replace(me, **self.size_fields(sizes_m), separation_m=sep, measured=None)

    #: Flag: the pack is a solid of revolution (a ring), so the torus of :meth:`tube_radius_m`
    #: about the mean turn holds it and the least distance is at least the torus bound.
    RING: ClassVar[bool] = False

    @property
    def shape_key(self) -> tuple[Any, ...]:
        """What a compiled sizing problem needs to know of the shape: the class, and any
        number the sizes follow besides the one free size (hashable)."""
        return (type(self),)

    @classmethod
    def scaled_sizes(cls, key: tuple[Any, ...], size: Any) -> tuple[Any, ...]:
        """The sizes (:attr:`SIZE_NAMES` order) of a pair of shape ``key`` whose first size is
        ``size`` (backend-generic), m.

        Parameters
        ----------
        key : tuple
            The shape key (:attr:`shape_key`): the pair class and any fixed number its sizes
            follow.
        size : float or CasADi
            The first (free) size, m.

        Returns
        -------
        tuple of float or CasADi
            The sizes in :attr:`SIZE_NAMES` order, m: ``(size,)`` for a one-size pair.
        """
        return (size,)

    @classmethod
    def spacing_per_size(cls, key: tuple[Any, ...]) -> float:
        """Default spacing / first size of a pair of shape ``key``, dimensionless.

        Parameters
        ----------
        key : tuple
            The shape key (:attr:`shape_key`).

        Returns
        -------
        float
            Default separation over the first size, dimensionless (the class's
            ``_DEFAULT_SPACING_PER_SIZE``: 1 for a circle, 0.5445 for a square).
        """
        return cls._DEFAULT_SPACING_PER_SIZE

    def size_fields(self, sizes: tuple[float, ...]) -> dict[str, Any]:
        """The dataclass fields that set sizes ``sizes``, by name (for ``dataclasses.replace``).

        Parameters
        ----------
        sizes : tuple of float
            Sizes in :attr:`SIZE_NAMES` order, m.

        Returns
        -------
        dict of str to float
            The size field by its name (``radius_m`` or ``side_m``), in the unit its name
            carries (m).
        """
        return {self._SIZE_KEY: float(sizes[0])}

    @property
    def size_keys(self) -> dict[str, Any]:
        """The pair's size as its design key's leaf and value: ``{"radius_m": R}``,
        ``{"side_m": a}`` or ``{"sides_m": (a, b)}``, m."""
        return {self._SIZE_KEY: getattr(self, self._SIZE_KEY)}

    @property
    def helmholtz(self) -> bool:
        """Flag: the separation is the default spacing of the sizes (to 1e-12 of the size)."""
        size = self._size_m
        return abs(self.spacing_m - self.default_spacing_m(self.sizes_m)) <= 1e-12 * size

    @classmethod
    def default_spacing_m(cls, sizes: tuple[Any, ...]) -> Any:
        """The separation the pair has by default at sizes ``sizes``, m (backend-generic).

        Parameters
        ----------
        sizes : tuple of float or CasADi
            Sizes in :attr:`SIZE_NAMES` order, m.

        Returns
        -------
        float or CasADi
            Default separation of the coil planes, m (the first size times the class's spacing
            ratio).
        """
        return cls._DEFAULT_SPACING_PER_SIZE * sizes[0]

    @classmethod
    def turn_length_m(cls, sizes: tuple[Any, ...]) -> Any:
        """Length of the mean turn at sizes ``sizes``, m (backend-generic).

        Parameters
        ----------
        sizes : tuple of float or CasADi
            Sizes in :attr:`SIZE_NAMES` order, m.

        Returns
        -------
        float or CasADi
            Mean turn length, m (the first size times the class's length per size).
        """
        return cls._TURN_LENGTH_PER_SIZE * sizes[0]

    @classmethod
    def reach_m(cls, sizes: tuple[Any, ...]) -> Any:
        """Least distance from the axis to the mean turn (R; a/2 of a square), m.

        Parameters
        ----------
        sizes : tuple of float or CasADi
            Sizes in :attr:`SIZE_NAMES` order, m.

        Returns
        -------
        float or CasADi
            The least distance, m (here the first size).
        """
        return sizes[0]

    @classmethod
    def depth_limit_m(cls, sizes: tuple[Any, ...]) -> Any:
        """What the pack's depth must stay below: R, or the (least) side of a frame, m.

        Parameters
        ----------
        sizes : tuple of float or CasADi
            Sizes in :attr:`SIZE_NAMES` order, m.

        Returns
        -------
        float or CasADi
            The depth limit, m (here the first size).
        """
        return sizes[0]

    @classmethod
    def reaches_m(cls, sizes: tuple[Any, ...]) -> tuple[Any, Any]:
        """Distance from the axis to the mean turn's middle along the next two axes in cyclic
        order, m (R and R for a circle).

        Parameters
        ----------
        sizes : tuple of float or CasADi
            Sizes in :attr:`SIZE_NAMES` order, m.

        Returns
        -------
        tuple of float or CasADi
            The two distances, m (here :meth:`reach_m` twice).
        """
        r = cls.reach_m(sizes)
        return (r, r)

    @classmethod
    def tube_radius_m(cls, width_m: Any, depth_m: Any) -> Any:
        """Radius of the tube about the mean turn that holds the whole pack, m: half the
        section's diagonal for a ring (backend-generic).

        Parameters
        ----------
        width_m : float or CasADi
            Axial width w of the winding pack, m.
        depth_m : float or CasADi
            Depth h of the winding pack across the turn, m.

        Returns
        -------
        float or CasADi
            Tube radius sqrt(w² + h²) / 2, m.
        """
        return 0.5 * bk.sqrt(width_m * width_m + depth_m * depth_m)

    @classmethod
    def half_extents_m(
        cls, axis_index: int, sizes: tuple[Any, ...], separation_m: Any, width_m: Any, depth_m: Any
    ) -> list[Any]:
        """Half-extent of the two packs as solids along x, y and z, m (backend-generic): along
        the axis s/2 + w/2, across it the mean turn's reach plus h/2.

        Parameters
        ----------
        axis_index : int
            The pair's axis, an index (0, 1, 2 for x, y, z).
        sizes : tuple of float or CasADi
            Sizes in :attr:`SIZE_NAMES` order, m.
        separation_m : float or CasADi
            Distance s between the coil planes, m.
        width_m : float or CasADi
            Axial width w of each winding pack, m.
        depth_m : float or CasADi
            Depth h of each winding pack across the turn, m.

        Returns
        -------
        list of float or CasADi
            The three half extents along x, y, z, m (:func:`coils.clearance.pair_extent_m`).
        """
        from coils.clearance import pair_extent_m

        return pair_extent_m(axis_index, cls.reaches_m(sizes), separation_m, width_m, depth_m)

    @classmethod
    def thermal_ring(cls, axis: str, sizes: tuple[Any, ...]) -> dict[str, Any]:
        """The thermal model's ring (:class:`coils.thermal.WindingPack`): ``mean_radius_m`` of
        the circle as long as the mean turn, and a frame's ``vertical_bar_height_m``, m.

        Parameters
        ----------
        axis : {"x", "y", "z"}
            The pair's axis (a frame in a vertical plane has vertical bars).
        sizes : tuple of float or CasADi
            Sizes in :attr:`SIZE_NAMES` order, m.

        Returns
        -------
        dict of str to float or CasADi
            :class:`coils.thermal.WindingPack` fields by name, each in the unit its name
            carries (m): here ``mean_radius_m``, the mean turn's length / 2π.
        """
        return {"mean_radius_m": cls.turn_length_m(sizes) / (2.0 * bk.pi)}

    @classmethod
    def terms(
        cls, sizes: tuple[Any, ...], turns: Any, separation: Any, width: Any, depth: Any
    ) -> dict[str, Any]:
        """The shape's closed forms at these sizes (backend-generic, SI): the two-filament
        centre gain ``gain_T_per_A``, the wire ``length_m`` of both coils, one coil's
        ``self_inductance_H`` and N² times the centre-line filaments' ``mutual_filament_H``.

        Parameters
        ----------
        sizes : tuple of float or CasADi
            Sizes in :attr:`SIZE_NAMES` order, m.
        turns : int, float or CasADi
            Turns N of each coil, count.
        separation : float or CasADi
            Distance s between the coil planes, m.
        width : float or CasADi
            Axial width w of each winding pack, m.
        depth : float or CasADi
            Depth h of each winding pack across the turn, m.

        Returns
        -------
        dict of str to float or CasADi
            The four terms by name, each in the unit its name carries: ``gain_T_per_A``, T/A;
            ``length_m``, m; ``self_inductance_H`` and ``mutual_filament_H``, H. The base
            class has none (NotImplementedError): each shape supplies them.
        """
        raise NotImplementedError

    @classmethod
    def mean_turn_points(
        cls, axis: int, sizes: tuple[float, ...], offset: float, n: int
    ) -> np.ndarray:
        """n points evenly along the mean turn in the plane ``x[axis] = offset``, (n, 3), m.

        Parameters
        ----------
        axis : int
            The pair's axis, an index (0, 1, 2 for x, y, z).
        sizes : tuple of float
            Sizes in :attr:`SIZE_NAMES` order, m.
        offset : float
            Axial coordinate of the turn's plane, m.
        n : int
            Number of points.

        Returns
        -------
        ndarray, shape (n, 3)
            The points, m. The base class has none (NotImplementedError): each shape supplies
            them.
        """
        raise NotImplementedError

    @classmethod
    def mean_turn_distance_m(
        cls, points: np.ndarray, axis: int, sizes: tuple[float, ...], offset: float
    ) -> np.ndarray:
        """Exact distance of points (n, 3) to the mean turn in the plane ``x[axis] = offset``,
        m.

        Parameters
        ----------
        points : ndarray, shape (n, 3)
            The points, m.
        axis : int
            The pair's axis, an index (0, 1, 2 for x, y, z).
        sizes : tuple of float
            Sizes in :attr:`SIZE_NAMES` order, m.
        offset : float
            Axial coordinate of the turn's plane, m.

        Returns
        -------
        ndarray, shape (n,)
            Distance of each point to the mean turn, m. The base class has none
            (NotImplementedError): each shape supplies it.
        """
        raise NotImplementedError

    # --- the pair's own solids, cooling and corrections ----------------------------------------
    def pack_solids(self) -> tuple[Any, Any]:
        """The two packs as solids at ∓s/2 (:mod:`coils.clearance`).

        Returns
        -------
        tuple of two solids
            The coil at -s/2 and the coil at +s/2 (a :class:`coils.clearance.Ring` or
            :class:`coils.clearance.Frame` each, SI). The base class has none
            (NotImplementedError): each shape supplies them.
        """
        raise NotImplementedError

    def view_pack(self) -> Any:
        """The pack geometry the view factors are traced on (:mod:`coils.viewfactors`).

        Returns
        -------
        PackRing or PackFrame
            The pair's packs (:class:`coils.viewfactors.PackRing` or
            :class:`coils.viewfactors.PackFrame`, SI). The base class has none
            (NotImplementedError): each shape supplies it.
        """
        raise NotImplementedError

    @property
    def vertical_bar_height_m(self) -> float:
        """Height of a frame's vertical bars when it stands in a vertical plane, m (0: a ring
        or a horizontal frame; :class:`coils.thermal.WindingPack`)."""
        return 0.0

    @property
    def tube_m(self) -> float:
        """:meth:`tube_radius_m` of this pair's pack, m."""
        return float(self.tube_radius_m(self.winding_pack_width_m, self.winding_pack_depth_m))

    @property
    def extents_m(self) -> list[float]:
        """:meth:`half_extents_m` of this pair, m."""
        return [
            float(v)
            for v in self.half_extents_m(
                self.axis_index,
                self.sizes_m,
                self.spacing_m,
                self.winding_pack_width_m,
                self.winding_pack_depth_m,
            )
        ]

    def formula_corrections(self) -> tuple[float, float]:
        """(gain, mutual) corrections of the closed forms (:meth:`terms`) to this pair: its
        exact centre field over the two-filament formula's, and the series inductance's excess
        over the formulas' self inductance, 2(L + M - L_formula), over 2 N² M_filament, so
        2 L_formula + 2 c M_filament is the pair's series inductance exactly.

        Returns
        -------
        tuple of float
            (gain, mutual) correction factors, dimensionless: the centre field per ampere over
            ``terms``' ``gain_T_per_A``, and (L + M - L_formula) / N² M_filament.
        """
        q = self.terms(
            self.sizes_m,
            self.turns,
            self.separation_m,
            self.winding_pack_width_m,
            self.winding_pack_depth_m,
        )
        gain = self.centre_field_per_amp_T_per_A / float(q["gain_T_per_A"])
        excess = self.mutual_inductance_H + self.self_inductance_H - float(q["self_inductance_H"])
        return gain, excess / float(q["mutual_filament_H"])

    def _check_fits(self, key: str, size: float, sep: float) -> None:
        """The pack fits: its depth below the size ``key`` = ``size``, m, and its width below
        the spacing ``sep``, m (else InputError naming the wire or the separation)."""
        depth, width = self.winding_pack_depth_m, self.winding_pack_width_m
        if depth >= size:
            raise InputError(
                "wire_diameter_m",
                self.wire_diameter_m,
                f"a wire thin enough that the winding pack depth (now {depth:.4g} m "
                f"for {self.turns} turns) is below {key} = {size:.4g} m",
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
        """Distance between the two coil planes, m (``separation_m``; when not given, the
        pair's default spacing, set at construction)."""
        return float(self.separation_m)  # type: ignore[arg-type]

    @property
    def _size_m(self) -> float:
        """The pair's size (R of a circle, a of a square), m."""
        return float(getattr(self, self._SIZE_KEY))

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
        """Side of the square of the pack's area, sqrt(w h), m (the side itself at aspect 1)."""
        return math.sqrt(self.winding_pack_area_m2)

    @property
    def winding_pack_width_m(self) -> float:
        """Axial width w = sqrt(A · aspect) of each winding pack, m."""
        return math.sqrt(self.winding_pack_area_m2 * self.pack_aspect)

    @property
    def winding_pack_depth_m(self) -> float:
        """Depth h = sqrt(A / aspect) of each winding pack across the turn (radial for a
        circle, across the side for a square), m."""
        return math.sqrt(self.winding_pack_area_m2 / self.pack_aspect)

    @property
    def wire_length_m(self) -> float:
        """Copper length of both coils, 2 N times the mean turn (2π R, or 4 a for a square), m."""
        return 2.0 * self.turns * self.mean_turn_length_m

    @property
    def mean_turn_length_m(self) -> float:
        """Length of the mean turn (:meth:`turn_length_m` of the sizes), m."""
        return float(self.turn_length_m(self.sizes_m))

    @property
    def copper_mass_kg(self) -> float:
        """Copper of both coils, density (IEC 60028) x wire length x bare section, kg."""
        return COPPER_DENSITY_kg_m3 * self.wire_length_m * self.wire_area_m2

    def _coil_grids(self, nodes: tuple[int, int]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Both coils as Gauss-Legendre filament grids over their packs: the filaments' size
        coordinates (radius or half side), m, axial centres, m, and turns, a count each."""
        dr, dz, w = gauss_legendre_pack(self.winding_pack_depth_m, nodes, self.winding_pack_width_m)
        half = 0.5 * self.spacing_m
        sizes = np.tile(self._filament_size_m + dr, 2)
        return sizes, np.concatenate([-half + dz, half + dz]), np.tile(self.turns * w, 2)

    def _filament_set_fields(self) -> tuple[np.ndarray, dict[str, Any]]:
        """The field model's filaments, ``self.filaments`` per pack, one drive column: their
        size coordinates, m, and the other fields of a filament set by name."""
        sizes, centres, turns = self._coil_grids(self.filaments)
        common = {
            "axes": np.full(len(turns), self.axis_index),
            "centres_m": centres,
            "turns": turns,
            "columns": np.zeros(len(turns), dtype=int),
            "column_axes": (self.axis_index,),
        }
        return sizes, common

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
    def pack_centre_field_per_amp_T_per_A(self) -> float:
        """Field at the centre per ampere with each coil's current spread uniformly over its
        rectangular winding pack, T/A.

        8 x 8 Gauss-Legendre filaments of the pair's shape per coil (whatever ``filaments``
        the field model uses), each the exact centre field of its loop; checked in the tests
        against the closed form of a thick solenoid's axial field (circle) and the filament sum
        (square).
        """
        return self._centre_field_T_per_A(*self._coil_grids((_PACK_FIELD_NODES,) * 2))

    # --- electrical ----------------------------------------------------------------------------
    def resistance_ohm(self, temperature_C: float = 20.0) -> float:
        """Resistance of both coils in series at a copper temperature, Ω: the measured one
        where the pair has one (``measured``, brought from its measuring temperature with
        copper's coefficient), else :meth:`computed_resistance_ohm`.

        Parameters
        ----------
        temperature_C : float
            Copper temperature, °C.

        Returns
        -------
        float
            Resistance of the series pair, Ω.
        """
        m = self.measured
        if m is not None and m.resistance_ohm is not None:
            return m.resistance_ohm_at(temperature_C)
        return self.computed_resistance_ohm(temperature_C)

    def computed_resistance_ohm(self, temperature_C: float = 20.0) -> float:
        """Resistance of both coils in series at a copper temperature from the geometry, Ω.

        R = ρ(T) ℓ / (π d²/4), ℓ = :attr:`wire_length_m`, ρ(T) from
        :func:`coils.electrical.copper_resistivity_ohm_m` (IEC 60028). DC value: at the drive
        frequencies here (< 100 Hz) the copper skin depth (> 6 mm) exceeds the wire radius.

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

    def _mutual_average_H(self, kernel: Callable[..., Any]) -> float:
        """N² times ``kernel(size 1, size 2, distance)`` (the mutual inductance of two coaxial
        filaments of the pair's shape, H) averaged over both packs with a 4 x 4 Gauss-Legendre
        rule each (uniform current density; smooth because the packs do not touch), H."""
        dr, dz, w = gauss_legendre_pack(
            self.winding_pack_depth_m, (_MUTUAL_NODES,) * 2, self.winding_pack_width_m
        )
        size = self._filament_size_m
        dist = self.spacing_m + dz[:, None] - dz[None, :]
        m = kernel(size + dr[:, None], size + dr[None, :], dist)
        return float(self.turns**2 * np.sum(w[:, None] * w[None, :] * m))

    @property
    def series_inductance_H(self) -> float:
        """Inductance of the pair at its terminals, H: the measured one where the pair has one
        (``measured``), else :attr:`computed_series_inductance_H`."""
        m = self.measured
        if m is not None and m.inductance_H is not None:
            return m.inductance_H
        return self.computed_series_inductance_H

    @property
    def computed_series_inductance_H(self) -> float:
        """Inductance of the two coils in series aiding from the geometry, 2 L + 2 M, H."""
        return 2.0 * self.self_inductance_H + 2.0 * self.mutual_inductance_H

    # --- thermal -------------------------------------------------------------------------------
    @property
    def surface_area_m2(self) -> float:
        """Outer surface of both winding packs, 2 x 2(w + h) x the mean turn (2πR by Pappus,
        or 4a for a square frame), m²."""
        perimeter = 2.0 * (self.winding_pack_width_m + self.winding_pack_depth_m)
        return 2.0 * perimeter * self.mean_turn_length_m

    def thermal_conductance_W_per_K(self, heat_transfer_coefficient_W_m2K: float) -> float:
        """Thermal conductance from both coils to ambient air, h A, W/K.

        Assumes each winding pack is isothermal (no internal gradient) and loses heat by
        convection from all four faces of its section (inner, outer and both side faces, total
        2(w + h) times the mean turn per coil) with one coefficient h that also absorbs
        radiation; no conduction into the frame. Pair it with the copper loss of both coils.

        Parameters
        ----------
        heat_transfer_coefficient_W_m2K : float
            Convective coefficient h, W/(m²·K).

        Returns
        -------
        float
            Conductance h A of both coils, W/K.
        """
        h = check_positive("heat_transfer_coefficient_W_m2K", heat_transfer_coefficient_W_m2K)
        return h * self.surface_area_m2
