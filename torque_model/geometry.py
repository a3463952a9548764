"""Deformed-lumen geometry of Zhou et al. 2013: D' of the wound section, contact of the ends.

Equivalent diameter D' (Fig. 8, section III-B)
----------------------------------------------
A cross-section through the wound part of the capsule cuts the capsule body (a circle of
diameter D) and, once, the spiral wire (diameter d_w) whose centre line is a helix of radius
R_h = (D + d_w)/2 at helical angle alpha to the cross-section plane. Within the plane the wire
cut is, to first order in d_w/R_h, an ellipse *wrapped round the helix circle*: radially
d_w/2 either side of R_h, and angularly ``psi_m = (d_w/2) / (R_h sin(alpha))`` either side of
its centre (the cut is about d_w / sin(alpha) long along the circumference at R_h). The taut
intestinal wall takes the convex envelope of the circle and this bump; the paper converts its
perimeter P to a circle of the same perimeter, D' = P / pi.

The outer edge of the bump, with parameter t in [0, pi/2] from its crest, is

    rho(t) = R_h + (d_w/2) cos t,   psi(t) = psi_m sin t,

and the envelope follows it from the crest to the point t* where its outward normal is at
distance R from the axis (there the envelope leaves the bump along a common tangent with the
capsule circle). With c = cos t* the tangency condition ``rho^2 psi' = R |x'|`` squares to

    F(c) = psi_m^2 c^2 rho^2 (rho^2 - R^2) - R^2 (d_w/2)^2 (1 - c^2) = 0,

a polynomial in c that is increasing and convex on [0, 1] with F(0) < 0 < F(1), so Newton's
method started at c = 1 converges monotonically to the one root; a fixed count of
:data:`NEWTON_STEPS` steps reaches machine precision for alpha >= 1.8 deg (and exact derivatives
follow by differentiating through the converged iteration). Numbers stop once the iterate has
settled (a fixed point, or Newton's last bit alternating): the same bits as the full count, in
about a fifth of the steps. Then

    P = 2 pi R - 2 R phi* + 2 sqrt(rho*^2 - R^2) + 2 S(t*),

with phi* = psi(t*) + atan((d_w/2) sin t* / (rho* psi_m cos t*)) the angle of the common
tangent's normal, sqrt(rho*^2 - R^2) the length of the tangent segment and S(t*) the arc length
of the bump edge from its crest to t*, by :data:`QUADRATURE_NODES`-point Gauss-Legendre
quadrature (the integrand is analytic on the interval).

Accuracy: against the numerical convex hull of the capsule circle and the exact plane section of
a circular tube of diameter d_w swept along the helix (tests/test_torque_geometry.py), D' agrees
to 6e-6 relative at alpha = 5 deg, 3e-5 at 20 deg and 5e-5 at 45 deg (the wrapped-ellipse cut,
first order in d_w/D_h, is the only approximation). D' is smooth (analytic) in alpha, d_w
and D. Valid while the envelope still touches the capsule circle, phi* < pi / starts: for the
paper's capsule (D = 11 mm, d_w = 1 mm, one start) alpha > 1.75 deg (at 1.6 deg the bump wraps
round the back and the formula overestimates D' by 0.3 %). Below about 2 deg neighbouring turns
nearly touch anyway (lead pi D_h tan(alpha)).

An earlier note for this project quoted D' = 11.71, 11.44, 11.35, 11.31 mm at 5, 10, 15, 20 deg: those numbers come
from measuring the cut's angular half-width on the capsule radius R instead of the wire's centre
radius R_h; the tube section gives 11.667, 11.416, 11.339, 11.304 mm.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from spiralcap.core import backend as bk
from spiralcap.core.backend import Scalar
from spiralcap.core.checks import Spec, angle, guard, instance, positive
from spiralcap.core.errors import InputError, check_positive

__all__ = [
    "NEWTON_STEPS",
    "QUADRATURE_NODES",
    "ContactGeometry",
    "capsule_d_prime_m",
    "end_contact_moment_m2",
    "equivalent_diameter_m",
]

#: Newton steps for the tangency point (monotone convergence from c = 1).
NEWTON_STEPS = 40
#: Gauss-Legendre nodes for the arc length of the bump edge.
QUADRATURE_NODES = 24

_GL_X, _GL_W = np.polynomial.legendre.leggauss(QUADRATURE_NODES)


@dataclass(frozen=True)
class ContactGeometry:
    """The capsule as the intestine touches it: the dimensions the torque model reads, SI.

    No defaults: the design file (``spiralcap.schema``) holds the product's default capsule and
    :data:`torque_model.PAPER_CAPSULE` the one of Zhou et al. 2013.

    Parameters
    ----------
    body_diameter_m : float
        Capsule diameter D (cylinder and hemispherical ends), m (> 0).
    body_length_m : float
        Overall capsule length including both hemispherical ends, m (> 0).
    wire_diameter_m : float
        Spiral wire diameter d_w, m (> 0).
    wound_length_m : float
        Axial length of the spiral, m (> 0); the rest of the cylinder, if any, touches at D.
    starts : int
        Number of spiral wires (>= 1); the paper used 1.

    Raises
    ------
    InputError
        A dimension that is not a finite number > 0, or ``starts`` not a whole number >= 1.
    """

    body_diameter_m: float
    body_length_m: float
    wire_diameter_m: float
    wound_length_m: float
    starts: int

    def __post_init__(self) -> None:
        for name in ("body_diameter_m", "body_length_m", "wire_diameter_m", "wound_length_m"):
            value = getattr(self, name)
            if bk.is_casadi(value):  # a symbol of the NLP (free hardware, parameters): unchecked
                continue
            object.__setattr__(self, name, check_positive(name, value))
        n = self.starts
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
            raise InputError("starts", n, "a whole number >= 1")
        object.__setattr__(self, "starts", int(n))


def _tangency_cos(psi_m: Scalar, R: Scalar, r_w: Scalar, R_h: Scalar) -> Scalar:
    """cos t* of the common tangent point on the bump edge (Newton on F(c) from c = 1,
    :data:`NEWTON_STEPS` steps; numbers stop once settled, :func:`_newton_settled`)."""
    psi2 = psi_m * psi_m
    R2 = R * R
    q = R2 * r_w * r_w

    def step(c: Scalar) -> Scalar:
        rho = R_h + r_w * c
        rho2 = rho * rho
        F = psi2 * c * c * rho2 * (rho2 - R2) - q * (1.0 - c * c)
        # d/dc of c^2 rho^2 (rho^2 - R^2) = 2c rho^2 (rho^2-R^2) + c^2 (4 rho^3 - 2 rho R^2) r_w
        dF = (
            psi2
            * (2.0 * c * rho2 * (rho2 - R2) + c * c * r_w * (4.0 * rho2 * rho - 2.0 * rho * R2))
            + 2.0 * q * c
        )
        return c - F / dF

    c = 1.0 + 0.0 * psi_m
    if bk.is_casadi(c):  # a symbol: the fixed count of steps in the graph
        for _ in range(NEWTON_STEPS):
            c = step(c)
        return c
    return _newton_settled(step, c, NEWTON_STEPS)


def _newton_settled(step: Callable[[Any], Any], c: Any, steps: int) -> Any:
    """``steps`` iterations of ``step`` from ``c`` on numbers, bit for bit, stopping early once
    every element has settled: at a fixed point, or alternating between two neighbouring floats
    (Newton's last bit), where the rest of the iterations only repeat that cycle. A NaN never
    settles and runs every step."""
    prev = None
    for k in range(steps):
        nxt = step(c)
        # each element fixed or in a 2-cycle (a float compared as one: np.all costs 10 us)
        if prev is not None and (nxt == prev if isinstance(nxt, float) else np.all(nxt == prev)):
            return nxt if (steps - 1 - k) % 2 == 0 else c
        prev, c = c, nxt
    return c


@guard(
    helical_angle_rad=angle(),
    body_diameter_m=positive(),
    wire_diameter_m=positive(),
    starts=Spec(low=1.0),
)
def equivalent_diameter_m(
    helical_angle_rad: Scalar, body_diameter_m: Scalar, wire_diameter_m: Scalar, starts: int
) -> Scalar:
    """Diameter D' of the circle with the perimeter of the deformed lumen (Zhou 2013, Fig. 8).

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi SX/MX
        Angle between the spiral wire and the capsule's cross-section plane, rad
        (valid above about 1.8 deg for the paper's capsule; see the module docstring).
    body_diameter_m : float, array or CasADi
        Diameter D of the capsule's cylindrical part, m (the paper's PillCam SB2: 11 mm).
    wire_diameter_m : float, array or CasADi
        Diameter d_w of the spiral wire, m (the paper's: 1 mm).
    starts : int
        Number of spiral wires (starts), equally spaced round the circumference; each
        cross-section cuts each once. The paper's capsules have one. Valid while neighbouring
        bumps' envelopes do not meet (half-angle of each below pi/starts).

    Returns
    -------
    float, array or CasADi
        D' = (perimeter of the convex envelope of the capsule circle and the wire cut) / pi, m.
        Broadcasts its arguments.

    Notes
    -----
    Construction and accuracy are in the module docstring. With n starts the perimeter gains
    n times the excess of one bump.
    The formula is exact for the wrapped-ellipse cut; against the true tube section the
    residual is below 1e-4 relative for 5-45 deg.
    """
    R = 0.5 * body_diameter_m
    r_w = 0.5 * wire_diameter_m
    R_h = R + r_w
    psi_m = r_w / (R_h * bk.sin(helical_angle_rad))
    c = _tangency_cos(psi_m, R, r_w, R_h)
    s = bk.sqrt(1.0 - c * c)
    t_star = bk.arccos(c)
    rho_t = R_h + r_w * c
    phi_t = psi_m * s + bk.arctan(r_w * s / (rho_t * psi_m * c))
    tangent = bk.sqrt(rho_t * rho_t - R * R)
    arc = 0.0
    for x, w in zip(_GL_X, _GL_W, strict=True):
        t = 0.5 * t_star * (1.0 + float(x))
        ct, st = bk.cos(t), bk.sin(t)
        rho = R_h + r_w * ct
        arc = arc + float(w) * bk.sqrt(r_w * r_w * st * st + rho * rho * psi_m * psi_m * ct * ct)
    arc = 0.5 * t_star * arc
    return 2.0 * R + (2.0 * starts / bk.pi) * (tangent + arc - R * phi_t)


@guard(
    helical_angle_rad=angle(), geometry=instance(ContactGeometry, "a torque_model.ContactGeometry")
)
def capsule_d_prime_m(helical_angle_rad: Scalar, geometry: ContactGeometry) -> Scalar:
    """:func:`equivalent_diameter_m` of ``geometry``'s capsule at ``helical_angle_rad``.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle of the spiral to the cross-section plane, rad.
    geometry : ContactGeometry
        The capsule (body and wire diameters, m; starts).

    Returns
    -------
    float, array or CasADi
        D', m.

    Examples
    --------
    The paper's capsule at 45°: the equivalent diameter lies between the body's 11 mm and the
    helix's outer 13 mm:

    >>> import math
    >>> from torque_model import PAPER_CAPSULE, capsule_d_prime_m
    >>> print(f"{capsule_d_prime_m(math.radians(45.0), PAPER_CAPSULE) * 1e3:.4f} mm")
    11.2571 mm
    """
    g = geometry
    return equivalent_diameter_m(helical_angle_rad, g.body_diameter_m, g.wire_diameter_m, g.starts)


@guard(body_diameter_m=positive(), lumen_diameter_m=positive(), wall_thickness_m=positive())
def end_contact_moment_m2(
    body_diameter_m: Scalar, lumen_diameter_m: Scalar, wall_thickness_m: Scalar
) -> Scalar:
    """Integral of strain x moment arm over one hemispherical end: int eps(z) D_after(z)/2 dz.

    The end is a hemisphere of radius R = D/2 (Zhou 2013, section III-B: "the spherical radius,
    which is 5.5 mm"). At axial distance z from its base D_after(z) = 2 sqrt(R^2 - z^2); it
    touches the wall only where D_after > D_before, i.e. for z < z_c = sqrt(R^2 - D_before^2/4),
    and there eq. 6 gives eps = (D_after - D_before)/(D_before + d). In closed form

        int_0^z_c eps D_after/2 dz
          = [2 (R^2 z_c - z_c^3/3) - D_before (z_c r_c + R^2 asin(z_c/R))/2] / (D_before + d),

    r_c = sqrt(R^2 - z_c^2). Zero when the lumen is at least as wide as the capsule.

    Parameters
    ----------
    body_diameter_m : float, array or CasADi
        Capsule diameter D (twice the end radius), m.
    lumen_diameter_m : float, array or CasADi
        Undeformed inner diameter of the intestine D_before, m.
    wall_thickness_m : float, array or CasADi
        Wall thickness d, m.

    Returns
    -------
    float, array or CasADi
        The integral, m^2 (multiply by mu d times the theta-integral of the relaxation modulus
        to get the end's torque).
    """
    R = 0.5 * body_diameter_m
    # finite derivative where the lumen is wider than the capsule (no contact, z_c = 0)
    zc = bk.sqrt_guarded(bk.fmax(R * R - 0.25 * lumen_diameter_m * lumen_diameter_m, 0.0))
    rc = bk.sqrt(R * R - zc * zc)
    ratio = bk.fmin(zc / R, 1.0)
    integral = (
        2.0 * (R * R * zc - zc * zc * zc / 3.0)
        - lumen_diameter_m * (zc * rc + R * R * bk.arcsin(ratio)) / 2.0
    )
    return integral / (lumen_diameter_m + wall_thickness_m)
