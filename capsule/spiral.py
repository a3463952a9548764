"""The spiral (helical wire) wound on the capsule's cylindrical part.

Convention (Zhou et al. 2013, section II.A and Fig. 8): the helical angle ``alpha`` is the angle
between the wire and the capsule's cross-section plane. A smaller angle winds more turns over the
wound length and cuts the wire more obliquely, so that each cross-section shows a wider bump.

With ``D_h`` the helix diameter (the wire's centre line, ``D + d_w`` for a wire lying on a body of
diameter ``D``), unrolling one revolution of the helix gives a right triangle with base
``pi D_h`` and height the lead, whence

* lead (advance per revolution of one start) ``= pi D_h tan(alpha)``;
* turns of each start over the wound length ``L_w`` ``= L_w / lead``;
* width of the obliquely cut wire along the circumference ``~ d_w / sin(alpha)`` (the section of a
  round wire by a plane at ``alpha`` to its axis' normal is an ellipse of minor axis ``d_w`` and
  major axis ``d_w / sin(alpha)``).

With ``n`` starts the axial distance between neighbouring wires is ``lead / n``. The functions of
the helical angle are written once against :mod:`spiralcap.core.backend` and accept floats, numpy
arrays and CasADi SX/MX values.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from capsule.body import Body
from spiralcap.core import backend as bk
from spiralcap.core.checks import Spec, angle, guard, nonnegative, positive
from spiralcap.core.constants import to_unit
from spiralcap.core.errors import InputError, check_positive

#: Largest spiral wire diameter accepted, as a fraction of the body diameter. An engineering
#: plausibility bound chosen for this tool (not from a source): beyond it the "spiral" is a
#: thread deeper than a quarter of the capsule and the thin-bump picture of the tissue model no
#: longer applies.
MAX_WIRE_TO_BODY_DIAMETER = 0.25


@guard(body_diameter_m=positive(), wire_diameter_m=nonnegative())
def helix_diameter_m(body_diameter_m: Any, wire_diameter_m: Any) -> Any:
    """Diameter of the helix traced by the wire's centre line, ``D + d_w``.

    Parameters
    ----------
    body_diameter_m : float, array or CasADi
        Outer diameter ``D`` of the body the wire lies on, m.
    wire_diameter_m : float, array or CasADi
        Wire diameter ``d_w``, m.

    Returns
    -------
    float, array or CasADi
        Helix (centre-line) diameter ``D_h``, m.

    Examples
    --------
    A 1 mm wire on an 11 mm body winds on an 12 mm helix (centre line of the wire):

    >>> from capsule import helix_diameter_m
    >>> print(f"{helix_diameter_m(0.011, 0.001) * 1e3:.1f} mm")
    12.0 mm
    """
    return body_diameter_m + wire_diameter_m


@guard(helical_angle_rad=angle(), helix_diameter_m=positive())
def lead_m(helical_angle_rad: Any, helix_diameter_m: Any) -> Any:
    """Advance per revolution of one start, ``pi D_h tan(alpha)``.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Angle ``alpha`` between the wire and the cross-section plane, rad (0 < alpha < pi/2).
    helix_diameter_m : float, array or CasADi
        Helix diameter ``D_h``, m.

    Returns
    -------
    float, array or CasADi
        Lead, m. With ``n`` starts the axial pitch between neighbouring wires is ``lead / n``.

    Notes
    -----
    Unrolled helix (a right triangle of base ``pi D_h``); the helical angle to the cross-section plane as in Zhou et al. 2013, section II-A.

    Examples
    --------
    At 45° the lead equals the helix's circumference, π D:

    >>> import math
    >>> from capsule import lead_m
    >>> print(f"{lead_m(math.radians(45.0), 0.012) * 1e3:.3f} mm; pi D = {math.pi * 12:.3f} mm")
    37.699 mm; pi D = 37.699 mm
    """
    return bk.pi * helix_diameter_m * bk.tan(helical_angle_rad)


@guard(helical_angle_rad=angle(), helix_diameter_m=positive(), wound_length_m=nonnegative())
def spiral_turns(helical_angle_rad: Any, helix_diameter_m: Any, wound_length_m: Any) -> Any:
    """Turns each start makes over the wound length, ``L_w / (pi D_h tan(alpha))``.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle ``alpha``, rad.
    helix_diameter_m : float, array or CasADi
        Helix diameter ``D_h``, m.
    wound_length_m : float, array or CasADi
        Axial length ``L_w`` over which the wire is wound, m.

    Returns
    -------
    float, array or CasADi
        Number of turns (not rounded; 0.7 means 70 % of one revolution). Decreases with alpha.

    Examples
    --------
    15 mm of spiral on a 12 mm helix at 45°: 15 mm over a 37.7 mm lead:

    >>> import math
    >>> from capsule import spiral_turns
    >>> print(f"{spiral_turns(math.radians(45.0), 0.012, 0.015):.4f} turns")
    0.3979 turns
    """
    return wound_length_m / lead_m(helical_angle_rad, helix_diameter_m)


@guard(helical_angle_rad=angle(), wire_diameter_m=positive())
def footprint_width_m(helical_angle_rad: Any, wire_diameter_m: Any) -> Any:
    """Circumferential width of the obliquely cut wire in a cross-section, ``d_w / sin(alpha)``.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle ``alpha``, rad.
    wire_diameter_m : float, array or CasADi
        Wire diameter ``d_w``, m.

    Returns
    -------
    float, array or CasADi
        Chord width of the bump one wire makes in each cross-section, m. Decreases with alpha
        (Zhou et al. 2013, section II.C: the smaller the angle, the larger the raised section).

    Notes
    -----
    Major axis of the ellipse cut from a round wire by a plane at ``alpha`` to the wire's normal
    section; the curvature of the body over that width is neglected.
    """
    return wire_diameter_m / bk.sin(helical_angle_rad)


@guard(helix_diameter_m=positive(), wound_length_m=positive(), min_turns=nonnegative())
def max_helical_angle_for_turns_rad(
    helix_diameter_m: Any, wound_length_m: Any, min_turns: Any
) -> Any:
    """Largest helical angle that still winds ``min_turns`` over the wound length.

    ``atan(L_w / (min_turns pi D_h))``, evaluated as ``atan2`` so that ``min_turns = 0`` (rule
    switched off) gives ``pi/2`` without a division by zero.

    Parameters
    ----------
    helix_diameter_m : float, array or CasADi
        Helix diameter ``D_h``, m.
    wound_length_m : float, array or CasADi
        Wound length ``L_w``, m.
    min_turns : float, array or CasADi
        Fewest turns required (>= 0), dimensionless.

    Returns
    -------
    float, array or CasADi
        Angle, rad.
    """
    return bk.arctan2(wound_length_m, min_turns * bk.pi * helix_diameter_m)


@guard(helix_diameter_m=positive(), wire_diameter_m=positive(), starts=Spec(low=1.0))
def min_helical_angle_for_clearance_rad(
    helix_diameter_m: Any, wire_diameter_m: Any, starts: Any = 1
) -> Any:
    """Smallest helical angle at which neighbouring wires do not overlap.

    Neighbouring wires are ``lead / n`` apart along the axis, i.e. ``(lead / n) cos(alpha)``
    apart perpendicular to the wire; they touch when that equals ``d_w``, i.e. when
    ``sin(alpha) = n d_w / (pi D_h)`` -- equivalently when the ``n`` bumps of width
    ``d_w / sin(alpha)`` fill the whole circumference ``pi D_h``.

    Parameters
    ----------
    helix_diameter_m : float, array or CasADi
        Helix diameter ``D_h``, m.
    wire_diameter_m : float, array or CasADi
        Wire diameter ``d_w``, m.
    starts : int, float, array or CasADi
        Number of starts ``n``.

    Returns
    -------
    float, array or CasADi
        Angle, rad. Only meaningful when ``n d_w < pi D_h`` (NaN otherwise on the numpy path).
    """
    return bk.arcsin(starts * wire_diameter_m / (bk.pi * helix_diameter_m))


@dataclass(frozen=True)
class Spiral:
    """A spiral of round wire wound on the cylindrical part of a capsule body.

    Parameters
    ----------
    helical_angle_rad : float
        Angle between the wire and the cross-section plane, rad, in (0, pi/2).
    wire_diameter_m : float
        Wire diameter, m (> 0). Zhou et al. (2013) use 1 mm.
    wound_length_m : float
        Axial length of the wound region, m (> 0). Zhou et al. (2013) use 15 mm.
    starts : int
        Number of independent wires (starts), >= 1. Zhou et al. (2013) use one.

    Raises
    ------
    spiralcap.core.errors.InputError
        Naming the parameter at fault.
    """

    helical_angle_rad: float
    wire_diameter_m: float
    wound_length_m: float
    starts: int

    def __post_init__(self) -> None:
        a = self.helical_angle_rad
        try:  # numpy scalars, 0-d arrays and 1x1 CasADi DM (an optimiser's result) are welcome
            angle = float(a) if not isinstance(a, bool) else math.nan
        except (TypeError, ValueError):
            angle = math.nan
        if not (math.isfinite(angle) and 0.0 < angle < 0.5 * math.pi):
            raise InputError("helical_angle_rad", a, "a number in (0, pi/2) rad")
        object.__setattr__(self, "helical_angle_rad", angle)
        for name in ("wire_diameter_m", "wound_length_m"):
            object.__setattr__(self, name, check_positive(name, getattr(self, name)))
        n = self.starts
        if not (isinstance(n, int) and not isinstance(n, bool) and n >= 1):
            raise InputError("starts", n, "a whole number >= 1")

    @property
    def helical_angle_deg(self) -> float:
        """Helical angle, deg."""
        return to_unit(self.helical_angle_rad, "deg")

    @property
    def footprint_width_m(self) -> float:
        """Circumferential width of one wire's bump in a cross-section, m."""
        return float(footprint_width_m(self.helical_angle_rad, self.wire_diameter_m))

    def helix_diameter_m(self, body: Body) -> float:
        """Helix (wire centre-line) diameter on ``body``, m.

        Parameters
        ----------
        body : Body
            The shell the wire is wound on.

        Returns
        -------
        float
            ``D + d_w``, m.
        """
        return float(helix_diameter_m(body.diameter_m, self.wire_diameter_m))

    def lead_m(self, body: Body) -> float:
        """Advance per revolution of each start on ``body``, m.

        Parameters
        ----------
        body : Body
            The shell the wire is wound on.

        Returns
        -------
        float
            ``pi D_h tan(alpha)``, m.
        """
        return float(lead_m(self.helical_angle_rad, self.helix_diameter_m(body)))

    def wire_spacing_m(self, body: Body) -> float:
        """Axial distance between neighbouring wires (``lead / starts``) on ``body``, m.

        Parameters
        ----------
        body : Body
            The shell the wire is wound on.

        Returns
        -------
        float
            Wire spacing along the axis, m.
        """
        return self.lead_m(body) / self.starts

    def turns(self, body: Body) -> float:
        """Turns each start makes over the wound length on ``body`` (dimensionless).

        Parameters
        ----------
        body : Body
            The shell the wire is wound on.

        Returns
        -------
        float
            Turns of one start, count (fractional).
        """
        return float(
            spiral_turns(self.helical_angle_rad, self.helix_diameter_m(body), self.wound_length_m)
        )
