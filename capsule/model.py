"""The whole capsule: body, spiral and magnet, their consistency, and its headline figures."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

from capsule.body import GEOMETRY_RTOL, Body
from capsule.magnet import Magnet, magnet_fit_check
from capsule.mass import mass_from_parts_kg
from capsule.propulsion import forward_speed_m_s, thrust_torque_Nm
from capsule.spiral import (
    MAX_WIRE_TO_BODY_DIAMETER,
    Spiral,
    max_helical_angle_for_turns_rad,
    min_helical_angle_for_clearance_rad,
)
from capsule.torque import max_synchronous_torque_Nm
from spiralcap.core.checks import guard, instance
from spiralcap.core.constants import to_unit
from spiralcap.core.errors import InputError, check_positive


@guard(
    body=instance(Body, "a capsule.Body"),
    spiral=instance(Spiral, "a capsule.Spiral"),
    magnet=instance(Magnet, "a capsule.Magnet"),
)
def geometry_problems(body: Body, spiral: Spiral, magnet: Magnet) -> list[tuple[str, str]]:
    """Every way the three parts do not make a buildable capsule.

    Parameters
    ----------
    body : Body
        Capsule shell.
    spiral : Spiral
        Spiral wound on the cylindrical part.
    magnet : Magnet
        Magnet centred in the shell.

    Returns
    -------
    list of (str, str)
        ``(field, reason)`` pairs, ``field`` one of ``magnet.diameter_m``, ``magnet.length_m``,
        ``spiral.wire_diameter_m``, ``spiral.wound_length_m``, ``spiral.helical_angle_rad``,
        ``spiral.starts``; empty when the capsule can be built. Reasons quote sizes in mm.
    """
    out: list[tuple[str, str]] = []
    fit = magnet_fit_check(body, magnet)
    if fit is not None:
        out.append((f"magnet.{fit[0]}", fit[1]))
    wire_max = MAX_WIRE_TO_BODY_DIAMETER * body.diameter_m
    if spiral.wire_diameter_m > wire_max * (1.0 + GEOMETRY_RTOL):
        out.append(
            (
                "spiral.wire_diameter_m",
                f"at most {wire_max * 1e3:g} mm: {MAX_WIRE_TO_BODY_DIAMETER:.0%} of the body "
                f"diameter {body.diameter_m * 1e3:g} mm (a plausibility bound of this tool)",
            )
        )
    if spiral.wound_length_m > body.cylinder_length_m * (1.0 + GEOMETRY_RTOL):
        out.append(
            (
                "spiral.wound_length_m",
                f"at most the cylindrical part's length {body.cylinder_length_m * 1e3:g} mm "
                "(length - diameter); the spiral is wound on the cylinder only",
            )
        )
    d_h = spiral.helix_diameter_m(body)
    if spiral.starts * spiral.wire_diameter_m < math.pi * d_h:
        a_min = float(
            min_helical_angle_for_clearance_rad(d_h, spiral.wire_diameter_m, spiral.starts)
        )
        if spiral.helical_angle_rad < a_min * (1.0 - GEOMETRY_RTOL):
            out.append(
                (
                    "spiral.helical_angle_rad",
                    f"at least {to_unit(a_min, 'deg'):.3g} deg, else neighbouring turns of the "
                    f"{spiral.wire_diameter_m * 1e3:g} mm wire ({spiral.starts} start{'' if spiral.starts == 1 else 's'}) "
                    "overlap",
                )
            )
    else:
        n_max = math.pi * d_h / spiral.wire_diameter_m
        out.append(
            (
                "spiral.starts",
                f"fewer than pi D_h / d_w = {n_max:.3g} starts, else the "
                "wires cannot all fit round the circumference",
            )
        )
    return out


@dataclass(frozen=True)
class CapsuleFigures:
    """Headline figures of a capsule at an operating point (SI; units in every name).

    Attributes
    ----------
    magnet_moment_Am2 : float
        Magnet moment ``B_r V / mu0``, A·m^2.
    magnet_volume_m3 : float
        Magnet volume, m^3.
    remanence_T : float
        Magnet remanence, T.
    helical_angle_deg : float
        Helical angle, deg.
    helix_diameter_m : float
        Wire centre-line diameter, m.
    lead_m : float
        Advance per revolution of each start, m.
    pitch_m : float
        Same as ``lead_m`` (the advance per turn, pi D_h tan(alpha); :func:`capsule.lead_m`), m.
    wire_spacing_m : float
        Axial distance between neighbouring wires, ``lead / starts``, m.
    turns : float
        Turns of each start over the wound length, count (fractional).
    min_turns : float
        Fewest turns asked for (0: rule off), count.
    full_turn_ok : bool
        ``turns >= min_turns``.
    max_helical_angle_for_min_turns_deg : float
        Largest helical angle that still gives ``min_turns``, degrees.
    footprint_width_m : float
        Circumferential width of one wire's bump in a cross-section, m.
    frequency_hz : float
        Rotation frequency, Hz.
    slip_efficiency : float
        Forward speed / (frequency x lead), dimensionless.
    speed_m_s : float
        Forward speed, m/s.
    axial_load_N : float
        Axial load pushed, N.
    friction_coefficient : float
        Wire-tissue friction coefficient used for the thrust torque, dimensionless.
    thrust_torque_Nm : float
        Torque to push the axial load, N·m.
    synchronous_torque_per_mT_Nm : float
        Largest synchronous torque per millitesla of rotating field, ``m x 1 mT``, N·m.
    """

    magnet_moment_Am2: float
    magnet_volume_m3: float
    remanence_T: float
    helical_angle_deg: float
    helix_diameter_m: float
    lead_m: float
    pitch_m: float
    wire_spacing_m: float
    turns: float
    min_turns: float
    full_turn_ok: bool
    max_helical_angle_for_min_turns_deg: float
    footprint_width_m: float
    frequency_hz: float
    slip_efficiency: float
    speed_m_s: float
    axial_load_N: float
    friction_coefficient: float
    thrust_torque_Nm: float
    synchronous_torque_per_mT_Nm: float

    def to_dict(self) -> dict[str, Any]:
        """The figures as a plain dict (for JSON).

        Returns
        -------
        dict of str to float
            Field name to value, in the unit its name carries (``_m``, ``_deg``, ``_Nm`` ...).
        """
        return asdict(self)


@dataclass(frozen=True)
class Capsule:
    """A spiral capsule: shell, spiral and magnet that fit together.

    Parameters
    ----------
    body : Body
        Capsule shell.
    spiral : Spiral
        Spiral on the cylindrical part.
    magnet : Magnet
        Diametrically magnetised magnet centred in the shell.
    set_mass_kg : float or None
        Measured capsule mass, kg; None: estimated from the parts
        (:func:`capsule.mass.mass_from_parts_kg`).

    Raises
    ------
    spiralcap.core.errors.InputError
        For the first problem :func:`geometry_problems` finds, naming e.g. ``magnet.diameter_m``.

    Examples
    --------
    An 11 × 26 mm capsule with a 1 mm wire at 45° and an 8 × 10 mm N52 magnet:

    >>> import math
    >>> from capsule import Body, Capsule, Magnet, Spiral
    >>> cap = Capsule(
    ...     Body(0.011, 0.026, 0.0005),
    ...     Spiral(math.radians(45.0), 0.001, 0.015, 1),
    ...     Magnet(0.008, 0.010, 1.44),
    ... )
    >>> print(f"{cap.mass_kg * 1e3:.2f} g, moment {cap.magnet.moment_Am2:.3f} A m2")
    5.88 g, moment 0.576 A m2
    """

    body: Body
    spiral: Spiral
    magnet: Magnet
    set_mass_kg: float | None = None

    def __post_init__(self) -> None:
        if self.set_mass_kg is not None:  # 0: weightless (the paper's bench); < 0, NaN: no
            check_positive("set_mass_kg", self.set_mass_kg, allow_zero=True)
        problems = geometry_problems(self.body, self.spiral, self.magnet)
        if problems:
            field, reason = problems[0]
            part, _, name = field.partition(".")
            raise InputError(field, getattr(getattr(self, part), name), reason)

    @property
    def helix_diameter_m(self) -> float:
        """Wire centre-line diameter, m."""
        return self.spiral.helix_diameter_m(self.body)

    @property
    def lead_m(self) -> float:
        """Advance per revolution of each start, m."""
        return self.spiral.lead_m(self.body)

    @property
    def turns(self) -> float:
        """Turns of each start over the wound length, count (fractional)."""
        return self.spiral.turns(self.body)

    @property
    def moment_Am2(self) -> float:
        """Magnet moment, A·m^2."""
        return self.magnet.moment_Am2

    @property
    def mass_kg(self) -> float:
        """Capsule mass, kg: the measured one, else estimated from the parts."""
        if self.set_mass_kg is not None:
            return float(self.set_mass_kg)
        return float(
            mass_from_parts_kg(self.body.diameter_m, self.body.length_m, self.magnet.volume_m3)
        )

    def figures(
        self,
        frequency_hz: float,
        axial_load_N: float,
        friction_coefficient: float,
        slip_efficiency: float = 1.0,
        min_turns: float = 1.0,
    ) -> CapsuleFigures:
        """The capsule's figures at an operating point.

        Parameters
        ----------
        frequency_hz : float
            Rotation frequency, Hz.
        axial_load_N : float
            Axial load the spiral pushes, N.
        friction_coefficient : float
            Wire-tissue Coulomb friction coefficient, dimensionless.
        slip_efficiency : float
            Forward speed / (frequency x lead), dimensionless, in [0, 1].
        min_turns : float
            Fewest spiral turns over the wound length that count as manufacturable (0: off),
            count.

        Returns
        -------
        CapsuleFigures
            Magnet, spiral and kinematic figures, SI with units in the field names.
        """
        s, d_h = self.spiral, self.helix_diameter_m
        lead, turns = self.lead_m, self.turns
        return CapsuleFigures(
            magnet_moment_Am2=self.moment_Am2,
            magnet_volume_m3=self.magnet.volume_m3,
            remanence_T=self.magnet.remanence_T,
            helical_angle_deg=s.helical_angle_deg,
            helix_diameter_m=d_h,
            lead_m=lead,
            pitch_m=lead,
            wire_spacing_m=lead / s.starts,
            turns=turns,
            min_turns=float(min_turns),
            full_turn_ok=bool(turns >= min_turns),
            max_helical_angle_for_min_turns_deg=to_unit(
                float(max_helical_angle_for_turns_rad(d_h, s.wound_length_m, float(min_turns))),
                "deg",
            ),
            footprint_width_m=s.footprint_width_m,
            frequency_hz=float(frequency_hz),
            slip_efficiency=float(slip_efficiency),
            speed_m_s=float(forward_speed_m_s(frequency_hz, lead, slip_efficiency)),
            axial_load_N=float(axial_load_N),
            friction_coefficient=float(friction_coefficient),
            thrust_torque_Nm=float(
                thrust_torque_Nm(axial_load_N, d_h, s.helical_angle_rad, friction_coefficient)
            ),
            synchronous_torque_per_mT_Nm=float(max_synchronous_torque_Nm(self.moment_Am2, 1e-3)),
        )
