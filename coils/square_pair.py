"""A square Helmholtz pair: the a = b case of the frame pair (:class:`coils.rectangle_pair.FramePair`).

Geometry: each coil has N turns of round copper wire of bare diameter d wound into a
rectangular section of area A = N π d² / 4 / packing_factor (axial width w = sqrt(A · aspect),
depth h = sqrt(A / aspect) across the side), centred on the mean turn, a square of side a (the
winding's centre line) with sharp corners; its sides are parallel to the other two coordinate
axes. The two coils sit at ±s/2 along the pair's axis, s = 0.5445 a by default (the square
Helmholtz spacing: the centre field's second derivative vanishes there; Firester, Rev. Sci.
Instrum. 37, 1264 (1966); the rectangle's numerical root gives 0.54451 at a = b), and carry the
same current in the same sense.

Everything physical (field, gains, inductances, solids, cooling, the sizing's terms) is the
frame pair's with sides (a, a); this module holds the square's size field ``side_m``, its names
and the rounded Firester spacing the square has always used.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

from coils.filaments import Axis
from coils.rectangle import grover_rectangle_inductance_H, rectangle_gmd_m
from coils.rectangle_pair import FramePair
from coils.winding import MeasuredConstants

__all__ = [
    "SQUARE_HELMHOLTZ_RATIO",
    "SquarePair",
    "grover_square_inductance_H",
    "rectangle_gmd_m",
]

#: Coil spacing / side of a square Helmholtz pair (Firester 1966): the field's second axial
#: derivative vanishes at the centre.
SQUARE_HELMHOLTZ_RATIO = 0.5445


def grover_square_inductance_H(side_m: Any, gmd_m: Any) -> Any:
    """Self inductance of a one-turn square of side a whose section has GMD g, H: Grover's
    rectangle with the GMD (:func:`coils.rectangle.grover_rectangle_inductance_H`) at a = b,
    for g << a Grover's square, (2 μ0 a / π) [ln(a/g) - 0.77401 + g/a] (Grover, *Inductance
    Calculations*, 1946, ch. 5, eq. 24 and Table 3). Backend-generic.

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
    return grover_rectangle_inductance_H(side_m, side_m, gmd_m)


@dataclass(frozen=True)
class SquarePair(FramePair):
    """Two coaxial, series-connected square coils of N turns each; all quantities SI.

    The same interface as :class:`coils.HelmholtzPair` (field, gains, resistance,
    inductances, pack geometry), with the side of the mean turn in place of its radius: the
    frame pair (:class:`coils.rectangle_pair.FramePair`) with both sides a.

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
    _DEFAULT_SPACING_PER_SIZE: ClassVar[float] = SQUARE_HELMHOLTZ_RATIO
    SIZE_NAMES: ClassVar[tuple[str, ...]] = ("side_m",)

    @classmethod
    def sides_of(cls, sizes: tuple[Any, ...]) -> tuple[Any, Any]:
        """The sides (a, a) of the side (a,), m.

        Parameters
        ----------
        sizes : tuple of float or CasADi
            The side (a,), m.

        Returns
        -------
        tuple of float or CasADi
            (a, a), m.
        """
        return (sizes[0], sizes[0])

    @property
    def half_side_m(self) -> float:
        """Half side a/2 of the mean turn, m."""
        return 0.5 * self.side_m
