"""Propulsion kinematics of a spiral capsule: forward speed and the torque to push a load.

The model is a documented default meant to be replaced (docs/optimisation.md, Margin: the thrust torque). Assumptions:

* the spiral is a rigid screw turning in a compliant nut formed by the intestinal wall;
* the wall-wire contact is Coulomb friction with the tissue's friction coefficient ``mu``
  (friction angle ``atan(mu)``), acting on the helix (wire centre-line) diameter;
* the axial resistance ``F`` of the bowel acts along the capsule axis;
* all slip of the compliant nut (the wall deforming and sliding back over the wire) is lumped
  into one efficiency ``eta`` on the forward speed.

The resistive torque of the tissue against rotation itself (Zhou et al. 2013) is modelled in
``torque_model``; this module only adds what pushing the axial load costs.
"""

from __future__ import annotations

from typing import Any

from spiralcap.core import backend as bk
from spiralcap.core.checks import angle, guard, nonnegative, positive, unit_interval


@guard(frequency_hz=nonnegative(), lead_m=nonnegative(), slip_efficiency=unit_interval())
def forward_speed_m_s(frequency_hz: Any, lead_m: Any, slip_efficiency: Any) -> Any:
    """Forward speed of the capsule, ``eta f lead``.

    Parameters
    ----------
    frequency_hz : float, array or CasADi
        Rotation frequency of the capsule (synchronous with the field), Hz.
    lead_m : float, array or CasADi
        Advance per revolution of the spiral, m (see :func:`capsule.lead_m`).
    slip_efficiency : float, array or CasADi
        Forward speed / (frequency x lead), dimensionless, in [0, 1]; 1 is a nut on a rigid
        screw.

    Returns
    -------
    float, array or CasADi
        Speed along the capsule axis, m/s.

    Examples
    --------
    2 Hz on a 30 mm lead at half slip efficiency:

    >>> from capsule import forward_speed_m_s
    >>> print(f"{forward_speed_m_s(2.0, 0.03, 0.5) * 1e3:.1f} mm/s")
    30.0 mm/s
    """
    return slip_efficiency * frequency_hz * lead_m


@guard(
    axial_load_N=nonnegative(),
    helix_diameter_m=positive(),
    helical_angle_rad=angle(),
    friction_coefficient=nonnegative(),
)
def thrust_torque_Nm(
    axial_load_N: Any, helix_diameter_m: Any, helical_angle_rad: Any, friction_coefficient: Any
) -> Any:
    """Torque to drive the screw against an axial load, ``F (D_h / 2) tan(alpha + atan(mu))``.

    Parameters
    ----------
    axial_load_N : float, array or CasADi
        Axial resistance the capsule pushes against, N (Zhou et al. 2013 cite 20-100 mN for
        8-13 mm capsules in porcine small intestine).
    helix_diameter_m : float, array or CasADi
        Helix (mean contact) diameter ``D_h``, m.
    helical_angle_rad : float, array or CasADi
        Helical angle ``alpha`` (the screw's lead angle), rad.
    friction_coefficient : float, array or CasADi
        Coulomb friction coefficient ``mu`` between wire and tissue, dimensionless.

    Returns
    -------
    float, array or CasADi
        Torque about the capsule axis, N·m. Grows without bound as ``alpha + atan(mu)`` nears
        90° (the screw locks).

    Notes
    -----
    Torque to raise a load with a square-thread power screw, ``T = F d_m/2 tan(lambda + phi)``
    with lead angle ``lambda`` measured from the plane normal to the axis and friction angle
    ``phi = atan(mu)``: Budynas & Nisbett, *Shigley's Mechanical Engineering Design*, 9th ed.,
    section 8-2 (power screws), eq. (8-1) rewritten with ``tan(lambda) = l / (pi d_m)``. The
    paper's helical angle is that lead angle.
    """
    # At and beyond alpha + atan(mu) = 90 deg the screw self-locks: no torque pushes the load.
    # tan() would wrap round to negative values there (a "thrust" that helps); the angle is held
    # just short of 90 deg instead, so the torque stays what it physically is, beyond any magnet
    # (tan(pi/2 - 1e-6) = 1e6), and self_lock_margin_rad names the cause.
    angle = bk.fmin(helical_angle_rad + bk.arctan(friction_coefficient), SELF_LOCK_ANGLE_rad)
    return 0.5 * axial_load_N * helix_diameter_m * bk.tan(angle)


#: Largest screw angle alpha + atan(mu) the thrust torque is evaluated at, rad (just short of
#: the self-locking 90 deg; see :func:`thrust_torque_Nm`).
SELF_LOCK_ANGLE_rad = 0.5 * 3.141592653589793 - 1e-6


@guard(helical_angle_rad=angle(), friction_coefficient=nonnegative())
def self_lock_margin_rad(helical_angle_rad: Any, friction_coefficient: Any) -> Any:
    """How far the screw is from self-locking, ``pi/2 - (alpha + atan(mu))``, rad.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical (lead) angle ``alpha``, rad.
    friction_coefficient : float, array or CasADi
        Coulomb friction coefficient ``mu`` between wire and tissue, dimensionless.

    Returns
    -------
    float, array or CasADi
        Margin to self-locking, rad. Positive while turning the screw can push the load; at
        zero or below the screw self-locks and :func:`thrust_torque_Nm`
        (``tan(alpha + atan(mu))``) has no meaning.

    Notes
    -----
    Shigley's power-screw relation (see :func:`thrust_torque_Nm`) holds for
    ``lambda + phi < 90°``; beyond it no torque advances the load.
    """
    return 0.5 * bk.pi - helical_angle_rad - bk.arctan(friction_coefficient)
