"""Whether the spiral grips the wall, and the friction of the capsule's weight.

Engagement
----------
The paper's model (eqs. 6-8) resists the rotation only where the capsule stretches the lumen:
the wound section's strain eps_w = (D' - D_before) / (D_before + d) (eq. 6 at D_after = D').
A spiral whose equivalent diameter D' does not exceed the lumen presses nothing into the wall,
so the model gives no tissue torque, and, equally, the spiral cannot screw the capsule forward:
screw propulsion needs the wall wrapped round the thread. The design therefore requires
eps_w >= ``requirements.min_wall_strain`` for every tissue set (an NLP row, so no optimiser can
settle where the spiral only grazes the wall and the model's resistance vanishes).

The default, :data:`DEFAULT_MIN_WALL_STRAIN` = 0.0168, includes the least strain at which the
paper measured a spiral capsule's torque: capsule No. 4 (20 deg) in sample 3 (lumen 11.1 mm, wall
1 mm) stretches the wall by 1.6852 % with this module's :func:`wall_strain` (D' = 11.3039 mm)
and by 1.6826 % with the exact tube section's hull (D' = 11.3036 mm, docs/torque-model.md);
rounded down to the three figures the paper gives its lumens to, 1.68 %, both readings of that
measured case grip (``torque_model.domain.CALIBRATED``'s lower end is the same 1.68 %). Below
it nothing in the paper shows that a spiral grips.

Weight friction
---------------
The paper stood its intestine vertical "to avoid the influence from the gravity" (section
II-B): its torques, and so the calibration, hold no weight term. In a patient the capsule lies
on the wall, which carries its weight m g as an extra normal load on the lower side; Coulomb
friction on it opposes the rotation at the radius the capsule touches with, the spiral's crest
D/2 + d_w:

    tau_g = mu m g (D/2 + d_w),

with mu the capsule-mucosa friction coefficient, which the paper itself defines by weight
(eq. 1: mu = f / (m g), the force to pull the capsule over the flattened intestine). The hoop
tension of eqs. 2-8 presses the wall evenly round the capsule (no net force), the weight adds a
net one: the two normal loads add, and so do their friction moments, with nothing counted
twice. Buoyancy in intestinal content is neglected (the full weight: more resistance, the
conservative side). With it the resistance is never zero while the capsule lies on tissue.
"""

from __future__ import annotations

from spiralcap.core.backend import Scalar
from spiralcap.core.checks import angle, fields, guard, instance, nonnegative, positive
from spiralcap.core.constants import STANDARD_GRAVITY_m_s2
from torque_model.geometry import ContactGeometry, capsule_d_prime_m
from torque_model.model import strain
from torque_model.tissue import TissueParameters

#: rules for the tissue and geometry arguments of the public functions here
_TISSUE = fields(
    "a torque_model.TissueParameters (torque_model.preset)",
    E1_Pa=nonnegative(),
    E2_Pa=nonnegative(),
    E3_Pa=nonnegative(),
    eta1_Pa_s=positive(),
    eta2_Pa_s=positive(),
    lumen_diameter_m=positive(),
    wall_thickness_m=positive(),
    friction_coefficient=nonnegative(),
)
_GEOMETRY = instance(ContactGeometry, "a torque_model.ContactGeometry")

__all__ = [
    "DEFAULT_MIN_WALL_STRAIN",
    "contact_radius_m",
    "wall_strain",
    "weight_friction_torque_Nm",
]

#: Least wound-section strain a spiral must impose to count as gripping the wall: the least the
#: paper's capsules imposed on its samples (No. 4, 20 deg, sample 3: 1.6852 % by this model's D',
#: 1.6826 % by the exact tube's hull), rounded down to three figures so that case grips.
DEFAULT_MIN_WALL_STRAIN = 0.0168


@guard(
    helical_angle_rad=angle(), tissue=_TISSUE, geometry=_GEOMETRY, d_prime_m=positive(optional=True)
)
def wall_strain(
    helical_angle_rad: Scalar,
    tissue: TissueParameters,
    geometry: ContactGeometry,
    d_prime_m: Scalar | None = None,
) -> Scalar:
    """Strain the wound section imposes on the wall, eq. 6 at D_after = D' (not clipped).

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle of the spiral to the cross-section plane, rad.
    tissue : TissueParameters
        The tissue set (its lumen D_before, m, and wall thickness d, m, are read).
    geometry : ContactGeometry
        The capsule as the tissue touches it (body and spiral wire diameters, m; starts).
    d_prime_m : float, array or CasADi, optional
        D' of this angle and capsule (:func:`torque_model.equivalent_diameter_m`), m, when the
        caller has it (one for every tissue set: it depends on the capsule only); computed here
        otherwise.

    Returns
    -------
    float, array or CasADi
        (D' - D_before) / (D_before + d), dimensionless; <= 0 where the spiral does not touch
        the wall (no engagement).
    """
    d_prime = d_prime_m if d_prime_m is not None else capsule_d_prime_m(helical_angle_rad, geometry)
    return strain(d_prime, tissue.lumen_diameter_m, tissue.wall_thickness_m)


@guard(body_diameter_m=positive(), wire_diameter_m=nonnegative())
def contact_radius_m(body_diameter_m: Scalar, wire_diameter_m: Scalar) -> Scalar:
    """Radius at which a capsule lying on the wall touches it: the spiral's crest, m.

    Parameters
    ----------
    body_diameter_m : float or CasADi
        Capsule diameter D, m.
    wire_diameter_m : float or CasADi
        Spiral wire diameter d_w, m (the wire sits on the shell: crest at D/2 + d_w).

    Returns
    -------
    float or CasADi
        D/2 + d_w, m.
    """
    return 0.5 * body_diameter_m + wire_diameter_m


@guard(mass_kg=nonnegative(), friction_coefficient=nonnegative(), contact_radius_m_=nonnegative())
def weight_friction_torque_Nm(
    mass_kg: Scalar, friction_coefficient: Scalar, contact_radius_m_: Scalar
) -> Scalar:
    """Coulomb friction of the capsule's weight against its rotation, mu m g r, N·m.

    Parameters
    ----------
    mass_kg : float or CasADi
        Capsule mass, kg (its full weight rests on the wall; buoyancy neglected).
    friction_coefficient : float
        Capsule-mucosa friction coefficient mu, dimensionless (defined by weight, Zhou 2013
        eq. 1).
    contact_radius_m_ : float or CasADi
        Radius at which the capsule touches the wall, m (:func:`contact_radius_m`).

    Returns
    -------
    float or CasADi
        The friction torque, N·m (>= 0).
    """
    return friction_coefficient * mass_kg * STANDARD_GRAVITY_m_s2 * contact_radius_m_
