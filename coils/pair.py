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

from coils.filaments import Axis, FilamentSet
from coils.loop import coaxial_mutual_inductance_H, loop_field
from coils.winding import MAX_PACKING_FACTOR, PACK_ASPECT_RANGE, MeasuredConstants, WoundPair
from spiralcap.core import backend as bk
from spiralcap.core.constants import MU0_T_m_per_A

__all__ = ["MAX_PACKING_FACTOR", "PACK_ASPECT_RANGE", "HelmholtzPair", "stefan_bracket"]

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


def _stefan_y1(x: Any) -> Any:
    """y1 of Stefan's formula from Maxwell's geometric mean distance g of a b x c rectangle,
    y1 = 2 - ln(d/g), x = b/c (exact; 0.84834 at x = 1, 1/2 as x -> 0), backend-generic."""
    from spiralcap.core import backend as bk

    return (
        -1.0 / 12.0
        - x * x / 12.0 * bk.log(1.0 + 1.0 / (x * x))
        - 1.0 / (12.0 * x * x) * bk.log(1.0 + x * x)
        + 2.0 / 3.0 * (x * bk.arctan(1.0 / x) + bk.arctan(x) / x)
    )


_Y1_AT_1 = float(_stefan_y1(1.0))


def _stefan_y2(x: Any) -> Any:
    from spiralcap.core import backend as bk

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
    from spiralcap.core import backend as bk

    a, b, c = radius, width, depth
    x = b / c
    return (
        (1.0 + (3.0 * b * b + c * c) / (96.0 * a * a)) * bk.log(8.0 * a / bk.sqrt(b * b + c * c))
        - (_STEFAN_Y1 + (_stefan_y1(x) - _Y1_AT_1))
        + b * b / (16.0 * a * a) * _stefan_y2(x)
    )


@dataclass(frozen=True)
class HelmholtzPair(WoundPair):
    """Two coaxial, series-connected coils of N turns each; all quantities SI.

    The winding, field, resistance, series inductance and cooling are
    :class:`coils.winding.WoundPair`'s (mean turn 2π R); the filament set, centre field and
    inductances are the circle's.

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
    measured : coils.winding.MeasuredConstants or None
        A lab's measured R and L of the pair as wired, which its resistance and series
        inductance then answer (default None: computed from the geometry).

    Raises
    ------
    InputError
        A parameter outside its range, named by its parameter name; also a pack depth >= R
        (``wire_diameter_m``) or coils that overlap (``separation_m``).

    Examples
    --------
    A 0.3 m, 300-turn pair: the centre field per ampere is the textbook (4/5)^(3/2) μ0 N / R:

    >>> import math
    >>> import numpy as np
    >>> from coils import HelmholtzPair
    >>> pair = HelmholtzPair(0.3, 300, "z")
    >>> b = pair.field(np.zeros(3), 1.0)
    >>> print(f"{b[2] * 1e3:.5f} mT/A; (4/5)^1.5 mu0 N/R = {0.8**1.5 * 4e-7 * math.pi * 300 / 0.3 * 1e3:.5f}")
    0.89918 mT/A; (4/5)^1.5 mu0 N/R = 0.89918
    >>> print(f"separation {pair.separation_m} m, series inductance {pair.series_inductance_H * 1e3:.1f} mH")
    separation 0.3 m, series inductance 214.5 mH
    """

    radius_m: float
    turns: int
    axis: Axis = "z"
    separation_m: float | None = None
    wire_diameter_m: float = 2.5e-3
    packing_factor: float = 0.7
    filaments: tuple[int, int] = (1, 1)
    pack_aspect: float = 1.0
    measured: MeasuredConstants | None = None

    #: The shape of the coils (:class:`coils.SquarePair` is a ``"square"``).
    shape: ClassVar[str] = "circle"
    _SIZE_KEY: ClassVar[str] = "radius_m"
    _TURN_LENGTH_PER_SIZE: ClassVar[float] = 2.0 * math.pi
    _DEFAULT_SPACING_PER_SIZE: ClassVar[float] = 1.0
    _FILAMENT_PAIR: ClassVar[str] = "(radial, axial) of counts"
    SIZE_NAMES: ClassVar[tuple[str, ...]] = ("radius_m",)
    RING: ClassVar[bool] = True

    # --- the shape's terms (coils.winding.WoundPair) -------------------------------------------
    @classmethod
    def thermal_ring(cls, axis: str, sizes: tuple[Any, ...]) -> dict[str, Any]:
        """The thermal model's ring: the coil itself, ``mean_radius_m`` = R, m.

        Parameters
        ----------
        axis : {"x", "y", "z"}
            The pair's axis (a ring has no vertical bars whatever its axis).
        sizes : tuple of float or CasADi
            The radius (R,), m.

        Returns
        -------
        dict of str to float or CasADi
            ``mean_radius_m`` = R, in the unit its name carries (m).
        """
        return {"mean_radius_m": sizes[0]}

    @classmethod
    def terms(
        cls, sizes: tuple[Any, ...], turns: Any, separation: Any, width: Any, depth: Any
    ) -> dict[str, Any]:
        """Two coaxial loops of N turns at ±s/2: centre gain μ0 N R² / (R² + s²/4)^{3/2}
        (Biot-Savart on the axis), wire 2N · 2πR, Stefan's self inductance (Rosa & Grover
        1912, eq. 91) and N² times Maxwell's coaxial mutual inductance; SI, backend-generic.

        Parameters
        ----------
        sizes : tuple of float or CasADi
            The radius (R,), m.
        turns : int, float or CasADi
            Turns N of each coil, count.
        separation : float or CasADi
            Distance s between the coil planes, m.
        width : float or CasADi
            Axial width b of each winding pack, m.
        depth : float or CasADi
            Radial depth c of each winding pack, m.

        Returns
        -------
        dict of str to float or CasADi
            The four terms by name, each in the unit its name carries: ``gain_T_per_A``, T/A;
            ``length_m``, m; ``self_inductance_H`` (one coil) and ``mutual_filament_H``
            (N² times the mean-radius loops'), H.
        """
        radius = sizes[0]
        gain = (
            MU0_T_m_per_A
            * turns
            * radius
            * radius
            / (radius * radius + 0.25 * separation * separation) ** 1.5
        )
        return {
            "gain_T_per_A": gain,
            "length_m": 2.0 * turns * 2.0 * bk.pi * radius,
            "self_inductance_H": MU0_T_m_per_A
            * radius
            * turns
            * turns
            * stefan_bracket(radius, width, depth),
            "mutual_filament_H": turns
            * turns
            * coaxial_mutual_inductance_H(radius, radius, separation),
        }

    @classmethod
    def mean_turn_points(
        cls, axis: int, sizes: tuple[float, ...], offset: float, n: int
    ) -> np.ndarray:
        """n points evenly round the mean circle (radius R) in the plane ``x[axis] = offset``,
        (n, 3), m.

        Parameters
        ----------
        axis : int
            The pair's axis, an index (0, 1, 2 for x, y, z).
        sizes : tuple of float
            The radius (R,), m.
        offset : float
            Axial coordinate of the circle's plane, m.
        n : int
            Number of points (evenly in angle, the first on the lower-numbered in-plane axis).

        Returns
        -------
        ndarray, shape (n, 3)
            The points, m.
        """
        phi = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
        u, v = [k for k in range(3) if k != axis]
        pts = np.zeros((n, 3))
        pts[:, u], pts[:, v] = sizes[0] * np.cos(phi), sizes[0] * np.sin(phi)
        pts[:, axis] = offset
        return pts

    @classmethod
    def mean_turn_distance_m(
        cls, points: np.ndarray, axis: int, sizes: tuple[float, ...], offset: float
    ) -> np.ndarray:
        """Exact distance of points (n, 3) to the mean circle in the plane ``x[axis] =
        offset``: hypot(ρ - R, x[axis] - offset), m.

        Parameters
        ----------
        points : ndarray, shape (n, 3)
            The points, m.
        axis : int
            The pair's axis, an index (0, 1, 2 for x, y, z).
        sizes : tuple of float
            The radius (R,), m.
        offset : float
            Axial coordinate of the circle's plane, m.

        Returns
        -------
        ndarray, shape (n,)
            Distance of each point to the circle, m.
        """
        radial = np.sqrt(np.sum(np.delete(points, axis, axis=1) ** 2, axis=1))
        return np.hypot(radial - sizes[0], points[:, axis] - offset)

    def pack_solids(self) -> tuple[Any, Any]:
        """The two packs as solid rings (:func:`coils.clearance.pair_rings`).

        Returns
        -------
        tuple of Ring
            The coil at -s/2 and the coil at +s/2 (:class:`coils.clearance.Ring`, SI).
        """
        from coils.clearance import pair_rings

        return pair_rings(self)

    def view_pack(self) -> Any:
        """The packs for the view factors (:class:`coils.viewfactors.PackRing`).

        Returns
        -------
        PackRing
            The pair's axis index, mean radius, spacing, pack width and depth (SI).
        """
        from coils.viewfactors import PackRing

        return PackRing(
            self.axis_index,
            self.radius_m,
            self.spacing_m,
            self.winding_pack_width_m,
            self.winding_pack_depth_m,
        )

    # --- geometry ------------------------------------------------------------------------------
    @property
    def turn_radius_m(self) -> float:
        """Radius of the circle as long as the mean turn, m: R itself (the square pair's is
        2a/π; the thermal model's rings use it)."""
        return self.radius_m

    @property
    def _filament_size_m(self) -> float:
        """Radius of the filament at the pack centre, R, m."""
        return self.radius_m

    @cached_property
    def filament_set(self) -> FilamentSet:
        """The field model: both coils as Gauss-Legendre filament grids, one drive column."""
        radii, common = self._filament_set_fields()
        return FilamentSet(radii_m=radii, **common)

    # --- field ---------------------------------------------------------------------------------
    @staticmethod
    def _centre_field_T_per_A(
        radii_m: np.ndarray, centres_m: np.ndarray, turns: np.ndarray
    ) -> float:
        """Field at the centre per ampere of coaxial loops, T/A (exact on-axis field)."""
        return float(np.sum(turns * loop_field(radii_m, centres_m, 0.0, 0.0)[1]))

    @cached_property
    def centre_field_per_amp_T_per_A(self) -> float:
        """Field at the centre per ampere of the pair's field model (``filaments``), T/A.

        Exact sum over the filaments; for one filament at s = R it is (4/5)^{3/2} μ0 N / R. With
        ``filaments = (1, 1)`` (what a design builds) each coil is one loop at its mean radius:
        the gain every field, current and limit uses, not the pack's
        (:attr:`pack_centre_field_per_amp_T_per_A`).
        """
        return self._centre_field_T_per_A(*self._coil_grids(self.filaments))

    # --- electrical ----------------------------------------------------------------------------
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
        return self._mutual_average_H(coaxial_mutual_inductance_H)
