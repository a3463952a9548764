"""A Helmholtz pair: two coaxial coils in series with rectangular winding packs.

Geometry: each coil has N turns of round copper wire of bare diameter d wound into a rectangular
cross-section of area A = N π d² / 4 / packing_factor, axial width w = sqrt(A · aspect) and
radial depth h = sqrt(A / aspect) (aspect = w/h, 1 = square), centred on the mean radius R; the
two coils sit at ±s/2 along the pair's axis (s = R is Helmholtz spacing, s between the packs'
mid-planes) and carry the same current in the same sense, so their fields add at the centre.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from coils.electrical import copper_resistivity_ohm_m
from coils.filaments import AXES, Axis, FilamentSet, gauss_legendre_pack
from coils.loop import coaxial_mutual_inductance_H, loop_field
from spiralcap.constants import MU0_T_m_per_A
from spiralcap.errors import InputError, check_positive

__all__ = ["MAX_PACKING_FACTOR", "PACK_ASPECT_RANGE", "HelmholtzPair", "stefan_bracket"]

#: Densest packing of equal round wires (hexagonal), π / (2 sqrt 3).
MAX_PACKING_FACTOR = math.pi / (2.0 * math.sqrt(3.0))

# Stefan's formula constants for a square section (b = c), Rosa & Grover (1912) Table 23:
# y1 = 2 - ln(sqrt(2) / 0.447049) from Maxwell's geometric mean distance of a square, y2.
_STEFAN_Y1 = 0.848340
_STEFAN_Y2 = 0.8162
# y2(x) of Stefan's formula for x = b/c != 1, as ln(y2 x²/(1 + x²)) = P(ln x), a degree-6
# polynomial fitted (0.2 <= x <= 5) to y2 from Richardson-extrapolated filament volume integrals
# of Maxwell's formula (this module's tests check the inductance against such an integral); the
# fit is normalised to Rosa & Grover's 0.8162 at x = 1. The b² y2/(16 a²) term is < 1e-3 of L
# for packs below 0.3 R, so the fit's few % in y2 are < 5e-5 in L (tested, aspect 0.3 to 3.5).
_Y2_FIT = (
    -0.012828510154320405,
    -0.009083704113209431,
    0.09602787909165807,
    0.10615457103015795,
    -0.25647656859790363,
    -0.6158715203775984,
    -0.8962061425000086,
)
#: Range of the winding pack aspect (axial width / radial depth) the models are made for.
PACK_ASPECT_RANGE = (0.25, 4.0)
# Gauss-Legendre nodes across each pack for the mutual inductance (converged to < 1e-10).
_MUTUAL_NODES = 4
# Gauss-Legendre nodes across each pack for the pack's own centre field (the on-axis integrand is
# smooth over the pack: 8 x 8 meets the closed form to 1e-15 for the built-in pairs and a pack
# 0.4 R wide at aspect 3, where 4 x 4 is 7e-9 off).
_PACK_FIELD_NODES = 8


def _stefan_y1(x: Any) -> Any:
    """y1 of Stefan's formula from Maxwell's geometric mean distance g of a b x c rectangle,
    y1 = 2 - ln(d/g), x = b/c (exact; 0.84834 at x = 1, 1/2 as x -> 0), backend-generic."""
    from spiralcap import backend as bk

    return (
        -1.0 / 12.0
        - x * x / 12.0 * bk.log(1.0 + 1.0 / (x * x))
        - 1.0 / (12.0 * x * x) * bk.log(1.0 + x * x)
        + 2.0 / 3.0 * (x * bk.arctan(1.0 / x) + bk.arctan(x) / x)
    )


_Y1_AT_1 = float(_stefan_y1(1.0))


def _stefan_y2(x: Any) -> Any:
    from spiralcap import backend as bk

    u = bk.log(x)
    p = 0.0 * u
    for coefficient in _Y2_FIT:
        p = p * u + coefficient
    return _STEFAN_Y2 * bk.exp(p - _Y2_FIT[-1]) * (1.0 + x * x) / (2.0 * x * x)


def stefan_bracket(radius: Any, width: Any, depth: Any) -> Any:
    """L / (μ0 a N²) of one coil by Stefan's formula, axial width b, radial depth c, radius a.

    (1 + (3b² + c²)/(96 a²)) ln(8a/d) - y1 + b²/(16 a²) y2, d = sqrt(b² + c²) (Rosa & Grover,
    Bull. Bur. Stand. 8, 1912, eq. 91), y1 from the rectangle's geometric mean distance, y2 from
    :data:`_Y2_FIT`; at b = c exactly the square-section constants. Backend-generic.

    Parameters
    ----------
    radius : float or CasADi
        Mean radius a of the coil, m.
    width : float or CasADi
        Axial width b of the winding pack, m.
    depth : float or CasADi
        Radial depth c of the winding pack, m.

    Returns
    -------
    float or CasADi
        L / (μ0 a N²), dimensionless.
    """
    from spiralcap import backend as bk

    a, b, c = radius, width, depth
    x = b / c
    return (
        (1.0 + (3.0 * b * b + c * c) / (96.0 * a * a)) * bk.log(8.0 * a / bk.sqrt(b * b + c * c))
        - (_STEFAN_Y1 + (_stefan_y1(x) - _Y1_AT_1))
        + b * b / (16.0 * a * a) * _stefan_y2(x)
    )


def _check_count(key: str, value: Any) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise InputError(key, value, "a whole number >= 1")
    return int(value)


@dataclass(frozen=True)
class HelmholtzPair:
    """Two coaxial, series-connected coils of N turns each; all quantities SI.

    Parameters
    ----------
    radius_m : float
        Mean radius R of each coil (centre of the winding pack), m.
    turns : int
        Turns N of each coil, count.
    axis : {"x", "y", "z"}
        Common axis of the two coils.
    separation_m : float, optional
        Distance between the coil planes, m; default R (Helmholtz spacing).
    wire_diameter_m : float
        Bare copper diameter d, m.
    packing_factor : float
        Copper area / pack area, dimensionless, in (0, π/(2√3)).
    filaments : (int, int)
        Number of Gauss-Legendre filaments across the radial and axial pack extent used for
        the *field* (1, 1 = one filament at the mean radius; larger counts model the real
        pack).
    pack_aspect : float
        Axial width / radial depth of the winding pack, dimensionless, in
        :data:`PACK_ASPECT_RANGE`; 1 = square.

    Raises
    ------
    InputError
        A parameter outside its range, named by its parameter name; also a pack depth >= R
        (``wire_diameter_m``) or coils that overlap (``separation_m``).
    """

    radius_m: float
    turns: int
    axis: Axis = "z"
    separation_m: float | None = None
    wire_diameter_m: float = 2.5e-3
    packing_factor: float = 0.7
    filaments: tuple[int, int] = (1, 1)
    pack_aspect: float = 1.0

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "radius_m", check_positive("radius_m", self.radius_m))
        set_(self, "turns", _check_count("turns", self.turns))
        if self.axis not in AXES:
            raise InputError("axis", self.axis, "one of 'x', 'y', 'z'")
        sep = self.radius_m if self.separation_m is None else self.separation_m
        set_(self, "separation_m", check_positive("separation_m", sep))
        set_(self, "wire_diameter_m", check_positive("wire_diameter_m", self.wire_diameter_m))
        pf = check_positive("packing_factor", self.packing_factor)
        if pf >= MAX_PACKING_FACTOR:
            raise InputError("packing_factor", pf, f"a number in (0, {MAX_PACKING_FACTOR:.4f})")
        set_(self, "packing_factor", pf)
        if not (isinstance(self.filaments, tuple) and len(self.filaments) == 2):
            raise InputError("filaments", self.filaments, "a pair (radial, axial) of counts >= 1")
        set_(self, "filaments", tuple(_check_count("filaments", n) for n in self.filaments))
        lo, hi = PACK_ASPECT_RANGE
        aspect = self.pack_aspect
        if isinstance(aspect, bool) or not isinstance(aspect, (int, float, np.floating)):
            raise InputError("pack_aspect", aspect, f"a number in [{lo:g}, {hi:g}]")
        if not lo <= aspect <= hi:
            raise InputError("pack_aspect", aspect, f"a number in [{lo:g}, {hi:g}]")
        set_(self, "pack_aspect", float(aspect))
        depth, width = self.winding_pack_depth_m, self.winding_pack_width_m
        if depth >= self.radius_m:
            raise InputError(
                "wire_diameter_m",
                self.wire_diameter_m,
                f"a wire thin enough that the winding pack depth (now {depth:.4g} m "
                f"for {self.turns} turns) is below radius_m = {self.radius_m:.4g} m",
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
        """Distance between the two coil planes, m (``separation_m``, R when not given)."""
        return self.radius_m if self.separation_m is None else self.separation_m

    #: The shape of the coils (:class:`coils.SquarePair` is a ``"square"``).
    shape: ClassVar[str] = "circle"

    @property
    def turn_radius_m(self) -> float:
        """Radius of the circle as long as the mean turn, m: R itself (the square pair's is
        2a/π; the thermal model's rings use it)."""
        return self.radius_m

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
        """Radial depth h = sqrt(A / aspect) of each winding pack, m."""
        return math.sqrt(self.winding_pack_area_m2 / self.pack_aspect)

    @property
    def wire_length_m(self) -> float:
        """Copper length of both coils, 2 N · 2π R (mean turn on the mean radius), m."""
        return 2.0 * self.turns * 2.0 * math.pi * self.radius_m

    @cached_property
    def filament_set(self) -> FilamentSet:
        """The field model: both coils as Gauss-Legendre filament grids, one drive column."""
        dr, dz, w = gauss_legendre_pack(
            self.winding_pack_depth_m, self.filaments, self.winding_pack_width_m
        )
        half = 0.5 * self.spacing_m
        n = len(w)
        return FilamentSet(
            axes=np.full(2 * n, self.axis_index),
            radii_m=np.tile(self.radius_m + dr, 2),
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
        """Field at the centre per ampere of the pair's field model (``filaments``), T/A.

        Exact sum over the filaments; for one filament at s = R it is (4/5)^{3/2} μ0 N / R. With
        ``filaments = (1, 1)`` (what a design builds) each coil is one loop at its mean radius:
        the gain every field, current and limit uses, not the pack's
        (:attr:`pack_centre_field_per_amp_T_per_A`).
        """
        fs = self.filament_set
        return float(np.sum(fs.turns * loop_field(fs.radii_m, fs.centres_m, 0.0, 0.0)[1]))

    @cached_property
    def pack_centre_field_per_amp_T_per_A(self) -> float:
        """Field at the centre per ampere with each coil's current spread uniformly over its
        rectangular winding pack, T/A.

        8 x 8 Gauss-Legendre filaments per coil (whatever ``filaments`` the field model uses),
        each the exact on-axis field of a loop; checked in the tests against the closed form of
        a thick solenoid's axial field (uniform current density over the section).
        """
        dr, dz, w = gauss_legendre_pack(
            self.winding_pack_depth_m, (_PACK_FIELD_NODES,) * 2, self.winding_pack_width_m
        )
        half = 0.5 * self.spacing_m
        radii = np.tile(self.radius_m + dr, 2)
        centres = np.concatenate([-half + dz, half + dz])
        turns = np.tile(self.turns * w, 2)
        return float(np.sum(turns * loop_field(radii, centres, 0.0, 0.0)[1]))

    # --- electrical ----------------------------------------------------------------------------
    def resistance_ohm(self, temperature_C: float = 20.0) -> float:
        """Resistance of both coils in series at a copper temperature, Ω.

        R = ρ(T) ℓ / (π d²/4), ρ(T) from :func:`coils.electrical.copper_resistivity_ohm_m` (IEC
        60028). DC value: at the drive frequencies here (< 100 Hz) the copper skin depth (> 6 mm)
        exceeds the wire radius.

        Parameters
        ----------
        temperature_C : float
            Copper temperature, °C.

        Returns
        -------
        float
            Resistance of the pair, Ω.
        """
        return float(
            copper_resistivity_ohm_m(temperature_C) * self.wire_length_m / self.wire_area_m2
        )

    @cached_property
    def self_inductance_H(self) -> float:
        """Self inductance of one coil, H.

        Stefan's formula for a circular coil of rectangular section b x c (axial x radial) and
        mean radius a (Rosa & Grover, Bull. Bur. Stand. 8, 1912, eq. 91; Grover, *Inductance
        Calculations*, 1946, ch. 16):

            L = μ0 a N² [(1 + (3b² + c²)/(96 a²)) ln(8a/d) - y1 + b²/(16 a²) y2],
            d = sqrt(b² + c²),

        with y1 = 0.84834, y2 = 0.8162 for a square section (:func:`stefan_bracket` for b != c).
        Uniform current density over the pack. Checked in the tests against a filament-sum of
        Maxwell's mutual formula (volume integral) to < 2e-5 (square) and < 5e-5 (aspect 0.3-3.5).
        """
        a = self.radius_m
        bracket = float(stefan_bracket(a, self.winding_pack_width_m, self.winding_pack_depth_m))
        return MU0_T_m_per_A * a * self.turns**2 * bracket

    @cached_property
    def mutual_inductance_H(self) -> float:
        """Mutual inductance between the two coils of the pair, H.

        N² times Maxwell's exact formula for coaxial filaments
        (:func:`coils.loop.coaxial_mutual_inductance_H`), averaged over both square packs with a
        4 x 4 Gauss-Legendre rule each (uniform current density; the integrand is smooth because
        the packs do not touch).
        """
        dr, dz, w = gauss_legendre_pack(
            self.winding_pack_depth_m, (_MUTUAL_NODES,) * 2, self.winding_pack_width_m
        )
        r1, r2 = self.radius_m + dr[:, None], self.radius_m + dr[None, :]
        dist = self.separation_m + dz[:, None] - dz[None, :]
        m = coaxial_mutual_inductance_H(r1, r2, dist)
        return float(self.turns**2 * np.sum(w[:, None] * w[None, :] * m))

    @property
    def series_inductance_H(self) -> float:
        """Inductance of the two coils in series aiding, 2 L + 2 M, H."""
        return 2.0 * self.self_inductance_H + 2.0 * self.mutual_inductance_H

    # --- thermal -------------------------------------------------------------------------------
    @property
    def surface_area_m2(self) -> float:
        """Outer surface of both winding packs, 2 x 2(w + h) x 2πR (Pappus), m²."""
        perimeter = 2.0 * (self.winding_pack_width_m + self.winding_pack_depth_m)
        return 2.0 * perimeter * 2.0 * math.pi * self.radius_m

    def thermal_conductance_W_per_K(self, heat_transfer_coefficient_W_m2K: float) -> float:
        """Thermal conductance from both coils to ambient air, h A, W/K.

        Assumes each winding pack is isothermal (no internal gradient) and loses heat by
        convection from all four faces of its section (inner, outer and both annular
        faces, total 2(w + h) · 2πR per coil) with one coefficient h that also absorbs radiation;
        no conduction into the frame. Pair it with the copper loss of both coils.

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
