"""Resistive torque of a rotating spiral capsule in the small intestine (Zhou et al. 2013, III).

Each piece is one equation of the paper, written once against :mod:`spiralcap.core.backend` so it
runs on floats, numpy arrays and CasADi SX/MX (differentiable in the helical angle and the
frequency). The reading of eqs. 7-8 and the calibration are in ``docs/torque-model.md``:

- eq. 6, strain of a cross-section: eps = (D_after - D_before) / (D_before + d);
- eqs. 2/4-5, stress at azimuth theta, the tissue having been strained for t = theta/omega:
  sigma = eps [E1 exp(-theta E1/(omega eta1)) + E2 exp(-theta E2/(omega eta2)) + E3];
- eq. 3, thin-walled vessel: p = 2 sigma d / D_after;
- eq. 7 read as force per unit axial length: the load on the element (D_after/2) dtheta dz is
  p (D_after/2) dtheta dz, so the normal load per unit length of one cross-section is
  int_0^{2 pi} p D_after/2 dtheta = d int_0^{2 pi} sigma dtheta (D_after cancels: it is the wall's
  hoop tension), and the friction per unit length is mu times that;
- eq. 8, the moment arm D_after/2; integrated along the contact (the wound length at D' and the
  parts of the hemispherical ends wider than the lumen):

      tau = mu d I(omega) [eps_w (D'/2) L_w + eps_c (D/2) L_c + 2 int_end eps D_after/2 dz],

  with I(omega) = int_0^{2 pi} (sigma/eps) dtheta in closed form
  (:func:`relaxation_integral_Pa`), L_c the unwound cylindrical length.
"""

from __future__ import annotations

from spiralcap.core import backend as bk
from spiralcap.core.backend import Scalar
from spiralcap.core.checks import angle, fields, finite, guard, instance, nonnegative, positive
from torque_model.geometry import ContactGeometry, capsule_d_prime_m, end_contact_moment_m2
from torque_model.tissue import TissueParameters, ViscoelasticConstants

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
_VISCO = fields(
    "the five viscoelastic constants (a torque_model.TissueParameters)",
    E1_Pa=nonnegative(),
    E2_Pa=nonnegative(),
    E3_Pa=nonnegative(),
    eta1_Pa_s=positive(),
    eta2_Pa_s=positive(),
)
_GEOMETRY = instance(ContactGeometry, "a torque_model.ContactGeometry")

__all__ = [
    "angular_frequency_rad_s",
    "contact_factor_m3",
    "contact_factors_m3",
    "friction_per_length_N_m",
    "hoop_pressure_Pa",
    "normal_load_per_length_N_m",
    "relaxation_integral_Pa",
    "relaxation_modulus_Pa",
    "resistive_torque_Nm",
    "section_torque_per_length_N",
    "strain",
    "stress_Pa",
    "torque_breakdown_Nm",
]


@guard(frequency_hz=nonnegative())
def angular_frequency_rad_s(frequency_hz: Scalar) -> Scalar:
    """Eq. 5: omega = 2 pi f, rad/s, from the rotation frequency f in Hz.

    Parameters
    ----------
    frequency_hz : float, array or CasADi
        Rotation frequency f, Hz.

    Returns
    -------
    float, array or CasADi
        Angular frequency omega, rad/s.
    """
    return 2.0 * bk.pi * frequency_hz


@guard(diameter_after_m=positive(), lumen_diameter_m=positive(), wall_thickness_m=positive())
def strain(diameter_after_m: Scalar, lumen_diameter_m: Scalar, wall_thickness_m: Scalar) -> Scalar:
    """Eq. 6: circumferential strain (D_after - D_before) / (D_before + d), dimensionless.

    Parameters
    ----------
    diameter_after_m : float, array or CasADi
        Inner diameter of the deformed intestine D_after (D' in the wound section), m.
    lumen_diameter_m : float
        Undeformed inner diameter D_before, m.
    wall_thickness_m : float
        Wall thickness d, m.

    Returns
    -------
    float, array or CasADi
        The strain, dimensionless; negative where the capsule does not touch (callers clip
        it at zero).

    Examples
    --------
    A 12 mm lumen with a 2 mm wall stretched to 14 mm, ε = (D' - D) / (D + d):

    >>> from torque_model import strain
    >>> print(f"{strain(0.014, 0.012, 0.002):.6f}")
    0.142857
    """
    return (diameter_after_m - lumen_diameter_m) / (lumen_diameter_m + wall_thickness_m)


@guard(time_s=nonnegative(), tissue=_VISCO)
def relaxation_modulus_Pa(time_s: Scalar, tissue: ViscoelasticConstants) -> Scalar:
    """Eq. 2 bracket: E1 exp(-t E1/eta1) + E2 exp(-t E2/eta2) + E3, Pa, at time t (s).

    Parameters
    ----------
    time_s : float, array or CasADi
        Time t since the strain was applied, s.
    tissue : ViscoelasticConstants
        The five constants of the generalized Maxwell model (E in Pa, eta in Pa·s).

    Returns
    -------
    float, array or CasADi
        Relaxation modulus E(t), Pa.

    Examples
    --------
    The five-element model: E1 + E2 + E3 at t = 0, only E3 long after:

    >>> from torque_model import preset, relaxation_modulus_Pa
    >>> t = preset("zhou2013-sample2")
    >>> print(f"{relaxation_modulus_Pa(0.0, t):.3f} Pa = {t.E1_Pa + t.E2_Pa + t.E3_Pa:.3f}; "
    ...       f"{relaxation_modulus_Pa(1e9, t):.3f} Pa = E3 {t.E3_Pa:.3f}")
    6701299.956 Pa = 6701299.956; 4355.156 Pa = E3 4355.156
    """
    t = tissue
    return (
        t.E1_Pa * bk.exp(-time_s * t.E1_Pa / t.eta1_Pa_s)
        + t.E2_Pa * bk.exp(-time_s * t.E2_Pa / t.eta2_Pa_s)
        + t.E3_Pa
    )


@guard(azimuth_rad=finite(), frequency_hz=positive(), strain_=finite(), tissue=_VISCO)
def stress_Pa(
    azimuth_rad: Scalar, frequency_hz: Scalar, strain_: Scalar, tissue: TissueParameters
) -> Scalar:
    """Eq. 4: hoop stress at azimuth theta (rad) behind first contact, Pa.

    The tissue at azimuth theta has been strained for t = theta / omega (section III-B).

    Parameters
    ----------
    azimuth_rad : float, array or CasADi
        Azimuth theta behind the first contact, rad.
    frequency_hz : float, array or CasADi
        Rotation frequency f, Hz.
    strain_ : float, array or CasADi
        Circumferential strain eps (eq. 6), dimensionless.
    tissue : TissueParameters
        Viscoelastic constants of the wall.

    Returns
    -------
    float, array or CasADi
        Hoop stress sigma(theta) = eps E(theta / omega), Pa.
    """
    omega = angular_frequency_rad_s(frequency_hz)
    return strain_ * relaxation_modulus_Pa(azimuth_rad / omega, tissue)


@guard(frequency_hz=nonnegative(), tissue=_VISCO)
def relaxation_integral_Pa(frequency_hz: Scalar, tissue: ViscoelasticConstants) -> Scalar:
    """int_0^{2 pi} of the eq. 4 bracket over one revolution, Pa (times rad), in closed form.

        I(omega) = omega eta1 (1 - exp(-2 pi E1/(omega eta1)))
                 + omega eta2 (1 - exp(-2 pi E2/(omega eta2))) + 2 pi E3,

    evaluated through ``expm1`` (:func:`_relaxed_arm`) so that it stays exact where the
    exponent is small (each arm tends to 2 pi E as omega eta grows) and is finite at f = 0.

    One revolution, theta in [0, 2 pi]: a wall element is strained when the bump reaches it and
    relaxes for one turn until strained again (docs/torque-model.md, "theta range").

    Parameters
    ----------
    frequency_hz : float, array or CasADi
        Rotation frequency f (0 allowed), Hz.
    tissue : ViscoelasticConstants
        The five constants of the generalized Maxwell model (E in Pa, eta in Pa·s).

    Returns
    -------
    float, array or CasADi
        I(omega), Pa (Pa·rad: the integral over the azimuth).
    """
    omega = angular_frequency_rad_s(frequency_hz)
    t = tissue
    return (
        _relaxed_arm(omega, t.E1_Pa, t.eta1_Pa_s)
        + _relaxed_arm(omega, t.E2_Pa, t.eta2_Pa_s)
        + 2.0 * bk.pi * t.E3_Pa
    )


#: Floor that keeps omega eta and the exponent away from 0 (f = 0, E = 0) without a division by 0.
_TINY = 1e-200


def _relaxed_arm(omega: Scalar, modulus: float, viscosity: float) -> Scalar:
    """One Maxwell arm of I(omega): omega eta (1 - e^(-x)), x = 2 pi E / (omega eta), Pa.

    Written as 2 pi E phi(x) with phi(x) = -expm1(-x) / x: no cancellation where x is small
    (large omega eta: phi -> 1, the arm -> 2 pi E), no 0/0 at E = 0 or f = 0 (the arm -> 0,
    a fully relaxed dashpot), the same on floats, arrays and CasADi.
    """
    w = bk.fmax(omega * viscosity, _TINY)
    x = bk.fmax(2.0 * bk.pi * modulus / w, _TINY)
    return 2.0 * bk.pi * modulus * (-bk.expm1(-x) / x)


@guard(stress=finite(), wall_thickness_m=positive(), diameter_after_m=positive())
def hoop_pressure_Pa(stress: Scalar, wall_thickness_m: Scalar, diameter_after_m: Scalar) -> Scalar:
    """Eq. 3: contact pressure of a thin-walled cylinder, p = 2 sigma d / D_after, Pa.

    Parameters
    ----------
    stress : float, array or CasADi
        Hoop stress sigma in the wall, Pa.
    wall_thickness_m : float, array or CasADi
        Wall thickness d, m.
    diameter_after_m : float, array or CasADi
        Inner diameter of the deformed intestine D_after, m.

    Returns
    -------
    float, array or CasADi
        Contact pressure p, Pa.
    """
    return 2.0 * stress * wall_thickness_m / diameter_after_m


@guard(frequency_hz=positive(), strain_=finite(), tissue=_TISSUE)
def normal_load_per_length_N_m(
    frequency_hz: Scalar, strain_: Scalar, tissue: TissueParameters
) -> Scalar:
    """Normal load per unit axial length of one cross-section, N/m.

    int_0^{2 pi} p(theta) (D_after/2) dtheta with eq. 3 = d eps I(omega): the diameter cancels.

    Parameters
    ----------
    frequency_hz : float, array or CasADi
        Rotation frequency f, Hz.
    strain_ : float, array or CasADi
        Circumferential strain eps (eq. 6, clipped at zero by the caller), dimensionless.
    tissue : TissueParameters
        Viscoelastic constants and wall thickness d of the intestine.

    Returns
    -------
    float, array or CasADi
        Normal load per unit axial length, N/m.
    """
    return tissue.wall_thickness_m * strain_ * relaxation_integral_Pa(frequency_hz, tissue)


@guard(frequency_hz=positive(), strain_=finite(), tissue=_TISSUE)
def friction_per_length_N_m(
    frequency_hz: Scalar, strain_: Scalar, tissue: TissueParameters
) -> Scalar:
    """Eq. 7 per unit axial length: circumferential Coulomb friction mu x normal load, N/m.

    Parameters
    ----------
    frequency_hz : float, array or CasADi
        Rotation frequency f, Hz.
    strain_ : float, array or CasADi
        Circumferential strain eps (eq. 6, clipped at zero by the caller), dimensionless.
    tissue : TissueParameters
        Viscoelastic constants, wall thickness and friction coefficient mu.

    Returns
    -------
    float, array or CasADi
        Friction force per unit axial length, N/m.
    """
    return tissue.friction_coefficient * normal_load_per_length_N_m(frequency_hz, strain_, tissue)


@guard(frequency_hz=positive(), diameter_after_m=positive(), tissue=_TISSUE)
def section_torque_per_length_N(
    frequency_hz: Scalar, diameter_after_m: Scalar, tissue: TissueParameters
) -> Scalar:
    """Eq. 8 per unit axial length: friction x D_after/2, N·m/m, for a section of diameter D_after.

    The strain is clipped at zero (a section narrower than the lumen does not touch).

    Parameters
    ----------
    frequency_hz : float, array or CasADi
        Rotation frequency f, Hz.
    diameter_after_m : float, array or CasADi
        Diameter D_after of the section (the deformed lumen), m.
    tissue : TissueParameters
        Viscoelastic constants, lumen and wall diameters, friction coefficient.

    Returns
    -------
    float, array or CasADi
        Resistive torque per unit axial length, N·m/m (= N).
    """
    eps = bk.positive_part(
        strain(diameter_after_m, tissue.lumen_diameter_m, tissue.wall_thickness_m)
    )
    return friction_per_length_N_m(frequency_hz, eps, tissue) * 0.5 * diameter_after_m


@guard(
    helical_angle_rad=angle(),
    frequency_hz=positive(),
    tissue=_TISSUE,
    geometry=_GEOMETRY,
    d_prime_m=positive(optional=True),
)
def torque_breakdown_Nm(
    helical_angle_rad: Scalar,
    frequency_hz: Scalar,
    tissue: TissueParameters,
    geometry: ContactGeometry,
    d_prime_m: Scalar | None = None,
) -> dict[str, Scalar]:
    """The resistive torque split into wound section, unwound cylinder and both ends, N·m.

    Same arguments as :func:`resistive_torque_Nm`; returns a dict with ``"wound"``,
    ``"cylinder"``, ``"ends"`` and ``"total"``.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle of the spiral to the cross-section plane, rad.
    frequency_hz : float, array or CasADi
        Rotation frequency f, Hz.
    tissue : TissueParameters
        Viscoelastic constants (calibrated scale), lumen, wall, friction.
    geometry : ContactGeometry
        The capsule as the tissue sees it.
    d_prime_m : float, array or CasADi, optional
        D' of this angle and capsule (:func:`torque_model.equivalent_diameter_m`), m, when the
        caller has it (one for every tissue set: it depends on the capsule only); computed here
        otherwise.

    Returns
    -------
    dict of str to float, array or CasADi
        Torque of each part and their sum, N·m.

    Examples
    --------
    The same torque by part of the capsule (the parts sum to the total):

    >>> import math
    >>> from torque_model import PAPER_CAPSULE, preset, torque_breakdown_Nm
    >>> parts = torque_breakdown_Nm(math.radians(10.0), 1.0, preset("zhou2013-sample2"), PAPER_CAPSULE)
    >>> print({k: round(float(v) * 1e3, 4) for k, v in parts.items()})  # mN m
    {'wound': 0.8231, 'cylinder': 0.0, 'ends': 0.0101, 'total': 0.8332}
    """
    parts = contact_factors_m3(helical_angle_rad, tissue, geometry, d_prime_m)
    integral = relaxation_integral_Pa(frequency_hz, tissue)
    out = {k: v * integral for k, v in parts.items()}
    out["total"] = out["wound"] + out["cylinder"] + out["ends"]
    return out


@guard(
    helical_angle_rad=angle(), tissue=_TISSUE, geometry=_GEOMETRY, d_prime_m=positive(optional=True)
)
def contact_factors_m3(
    helical_angle_rad: Scalar,
    tissue: TissueParameters,
    geometry: ContactGeometry,
    d_prime_m: Scalar | None = None,
) -> dict[str, Scalar]:
    """Geometric factors G with torque = G x I(omega), m^3, for each part of the contact.

    G = mu d int eps(z) D_after(z)/2 dz over the part: ``"wound"`` (D_after = D', length
    ``geometry.wound_length_m``), ``"cylinder"`` (D_after = D over the unwound cylindrical length
    ``body_length_m - body_diameter_m - wound_length_m``, if positive) and ``"ends"`` (both
    hemispheres, :func:`torque_model.geometry.end_contact_moment_m2`). Strains are clipped at 0.
    They hold everything but the five viscoelastic constants, which enter through
    :func:`relaxation_integral_Pa` only; :func:`torque_model.identify` uses this split.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle of the spiral to the cross-section plane, rad.
    tissue : TissueParameters
        Lumen and wall diameters and friction coefficient (its five constants are not used).
    geometry : ContactGeometry
        The capsule as the tissue sees it.
    d_prime_m : float, array or CasADi, optional
        D' of this angle and capsule (:func:`torque_model.equivalent_diameter_m`), m, when the
        caller has it (one for every tissue set: it depends on the capsule only); computed here
        otherwise.

    Returns
    -------
    dict of str to float, array or CasADi
        ``"wound"``, ``"cylinder"`` and ``"ends"`` factors G, m³.
    """
    mu_d = tissue.friction_coefficient * tissue.wall_thickness_m
    g = geometry

    def per_length(diameter_after: Scalar) -> Scalar:
        eps = bk.positive_part(
            strain(diameter_after, tissue.lumen_diameter_m, tissue.wall_thickness_m)
        )
        return mu_d * eps * 0.5 * diameter_after

    d_prime = d_prime_m if d_prime_m is not None else capsule_d_prime_m(helical_angle_rad, g)
    cylinder_length = bk.fmax(g.body_length_m - g.body_diameter_m - g.wound_length_m, 0.0)
    ends = (
        2.0
        * mu_d
        * end_contact_moment_m2(g.body_diameter_m, tissue.lumen_diameter_m, tissue.wall_thickness_m)
    )
    return {
        "wound": per_length(d_prime) * g.wound_length_m,
        "cylinder": per_length(g.body_diameter_m) * cylinder_length,
        "ends": ends,
    }


@guard(helical_angle_rad=angle(), tissue=_TISSUE, geometry=_GEOMETRY)
def contact_factor_m3(
    helical_angle_rad: Scalar, tissue: TissueParameters, geometry: ContactGeometry
) -> Scalar:
    """Sum of :func:`contact_factors_m3`: torque = contact_factor_m3 x relaxation_integral_Pa.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle of the spiral to the cross-section plane, rad.
    tissue : TissueParameters
        Lumen and wall diameters and friction coefficient.
    geometry : ContactGeometry
        The capsule as the tissue sees it.

    Returns
    -------
    float, array or CasADi
        The total geometric factor G, m³.
    """
    parts = contact_factors_m3(helical_angle_rad, tissue, geometry)
    return parts["wound"] + parts["cylinder"] + parts["ends"]


@guard(
    helical_angle_rad=angle(),
    frequency_hz=positive(),
    tissue=_TISSUE,
    geometry=_GEOMETRY,
    d_prime_m=positive(optional=True),
)
def resistive_torque_Nm(
    helical_angle_rad: Scalar,
    frequency_hz: Scalar,
    tissue: TissueParameters,
    geometry: ContactGeometry,
    d_prime_m: Scalar | None = None,
) -> Scalar:
    """Torque the intestine resists a spiral capsule's rotation with (Zhou 2013 eqs. 2-8), N·m.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi SX/MX
        Helical angle of the spiral to the cross-section plane, rad.
    frequency_hz : float, array or CasADi SX/MX
        Rotation frequency f > 0, Hz. Broadcasts against ``helical_angle_rad`` (numpy).
    tissue : TissueParameters
        Viscoelastic constants (calibrated scale), lumen, wall, friction.
    geometry : ContactGeometry
        The capsule: body diameter D and overall length, spiral wire diameter d_w, wound length
        (the rest of the cylinder, if any, touches at diameter D) and number of starts
        (:func:`torque_model.equivalent_diameter_m`). The paper's capsule is
        :data:`torque_model.PAPER_CAPSULE`.
    d_prime_m : float, array or CasADi, optional
        D' of this angle and capsule (:func:`torque_model.equivalent_diameter_m`), m, when the
        caller has it (one for every tissue set: it depends on the capsule only); computed here
        otherwise.

    Returns
    -------
    float, array or CasADi
        The resistive torque, N·m: wound section (D_after = D'), unwound cylinder and the two
        hemispherical ends (D_after(z) where wider than the lumen).

    Examples
    --------
    The paper's capsule (Zhou et al. 2013) in sample 2 at 10° and 1 Hz, within the 0.6-1.8 mN m
    the paper measured from 0.5 to 3 Hz:

    >>> import math
    >>> from torque_model import PAPER_CAPSULE, preset, resistive_torque_Nm
    >>> tau = resistive_torque_Nm(math.radians(10.0), 1.0, preset("zhou2013-sample2"), PAPER_CAPSULE)
    >>> print(f"{tau * 1e3:.3f} mN m")
    0.833 mN m
    """
    return torque_breakdown_Nm(helical_angle_rad, frequency_hz, tissue, geometry, d_prime_m)[
        "total"
    ]
