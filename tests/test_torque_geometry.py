"""D' (Zhou 2013 Fig. 8) and the hemispherical-end contact against independent numerics."""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest
from scipy import integrate, optimize
from scipy.spatial import ConvexHull

from torque_model.geometry import end_contact_moment_m2, equivalent_diameter_m


def _hull_diameter(radius: float, bump: np.ndarray) -> float:
    """Perimeter / pi of the convex hull of a densely sampled circle and the bump points."""
    t = np.linspace(0.0, 2.0 * np.pi, 100_000, endpoint=False)
    pts = np.r_[np.c_[radius * np.cos(t), radius * np.sin(t)], bump]
    v = pts[ConvexHull(pts).vertices]
    return float(np.sum(np.linalg.norm(np.roll(v, -1, axis=0) - v, axis=1)) / np.pi)


def _wrapped_ellipse(
    R: float, r_w: float, alpha: float, centre_radius: float, starts: int = 1, n: int = 20_001
) -> np.ndarray:
    psi_m = r_w / (centre_radius * math.sin(alpha))
    u = np.linspace(-1.0, 1.0, n)
    rho = R + r_w + r_w * np.sqrt(np.clip(1.0 - u * u, 0.0, None))
    out = []
    for k in range(starts):
        psi = u * psi_m + 2.0 * np.pi * k / starts
        out.append(np.c_[rho * np.sin(psi), rho * np.cos(psi)])
    return np.concatenate(out)


def _tube_section(R: float, r_w: float, alpha: float, n: int = 240) -> np.ndarray:
    """Outer edge of the exact plane section z = 0 of a round tube (radius r_w) along the helix."""
    R_h = R + r_w
    lead_per_rad = R_h * math.tan(alpha)

    def dist(r: float, psi: float) -> float:
        def sq(s: float) -> float:
            return (
                (r * math.cos(psi) - R_h * math.cos(s)) ** 2
                + (r * math.sin(psi) - R_h * math.sin(s)) ** 2
                + (lead_per_rad * s) ** 2
            )

        return math.sqrt(
            optimize.minimize_scalar(sq, bracket=(psi - 0.5, psi, psi + 0.5), tol=1e-14).fun
        )

    psi_max = 1.5 * r_w / (R_h * math.sin(alpha))
    pts = []
    for psi in np.linspace(-psi_max, psi_max, n):
        if dist(R_h, psi) >= r_w:
            continue
        r = optimize.brentq(
            lambda r, psi=psi: dist(r, psi) - r_w, R_h, R_h + 1.01 * r_w, xtol=1e-14
        )
        pts.append((r * math.sin(psi), r * math.cos(psi)))
    return np.array(pts)


@pytest.mark.parametrize("alpha_deg", [5.0, 10.0, 20.0, 45.0])
def test_d_prime_matches_convex_hull_of_exact_tube_section(alpha_deg: float) -> None:
    alpha = math.radians(alpha_deg)
    reference = _hull_diameter(5.5, _tube_section(5.5, 0.5, alpha))
    model = float(equivalent_diameter_m(alpha, 11.0, 1.0, 1))
    assert model == pytest.approx(reference, rel=1e-4), (
        f"D' at {alpha_deg} deg vs scipy ConvexHull of the exact tube section (wrapped-ellipse "
        "approximation, tolerance 1e-4 relative)"
    )


@pytest.mark.parametrize(
    ("alpha_deg", "D", "d_w", "starts"),
    [
        (1.8, 11.0, 1.0, 1),
        (3.0, 11.0, 1.0, 1),
        (5.0, 11.0, 1.0, 1),
        (12.0, 11.0, 1.0, 1),
        (30.0, 11.0, 1.0, 1),
        (80.0, 11.0, 1.0, 1),
        (8.0, 6.0, 0.3, 1),
        (8.0, 14.0, 2.0, 1),
        (10.0, 11.0, 1.0, 2),
        (20.0, 11.0, 1.0, 3),
    ],
)
def test_d_prime_closed_form_is_exact_for_wrapped_ellipse(alpha_deg, D, d_w, starts) -> None:
    alpha = math.radians(alpha_deg)
    reference = _hull_diameter(
        D / 2, _wrapped_ellipse(D / 2, d_w / 2, alpha, (D + d_w) / 2, starts)
    )
    model = float(equivalent_diameter_m(alpha, D, d_w, starts))
    assert model == pytest.approx(reference, rel=2e-7), (
        "closed-form hull perimeter vs scipy ConvexHull of the sampled wrapped ellipse "
        "(sampling error only, tolerance 2e-7 relative)"
    )


def test_design_md_figures_come_from_the_capsule_radius_variant() -> None:
    quoted = {5: 11.71, 10: 11.44, 15: 11.35, 20: 11.31}
    for deg, value in quoted.items():
        a = math.radians(deg)
        variant = _hull_diameter(5.5, _wrapped_ellipse(5.5, 0.5, a, centre_radius=5.5))
        assert variant == pytest.approx(value, abs=0.006), (
            "the earlier D' figures (docs/torque-model.md) = hull with the cut's width laid on radius R (2 decimals)"
        )
        assert float(equivalent_diameter_m(a, 11e-3, 1e-3, 1)) * 1e3 < value, (
            "the tube-centre (R_h) construction gives a smaller D' than the earlier figures"
        )


def test_d_prime_derivative_casadi_matches_finite_difference() -> None:
    a = ca.SX.sym("a")
    fn = ca.Function("dD", [a], [ca.jacobian(equivalent_diameter_m(a, 11e-3, 1e-3, 1), a)])
    for deg in (2.0, 5.0, 10.0, 30.0, 70.0):
        x = math.radians(deg)
        h = 1e-6
        fd = (
            equivalent_diameter_m(x + h, 11e-3, 1e-3, 1)
            - equivalent_diameter_m(x - h, 11e-3, 1e-3, 1)
        ) / (2 * h)
        assert float(fn(x)) == pytest.approx(fd, rel=1e-6), (
            "CasADi dD'/dalpha vs central difference of the numpy path (tolerance 1e-6)"
        )


def test_d_prime_numpy_and_casadi_agree() -> None:
    a = ca.SX.sym("a")
    fn = ca.Function("D", [a], [equivalent_diameter_m(a, 11e-3, 1e-3, 1)])
    for x in np.radians([1.6, 5.0, 10.0, 20.0, 60.0]):
        assert float(fn(x)) == pytest.approx(
            float(equivalent_diameter_m(x, 11e-3, 1e-3, 1)), rel=1e-12, abs=0
        ), "numpy vs CasADi SX D' (1e-12)"


def test_d_prime_limits() -> None:
    D = np.asarray(equivalent_diameter_m(np.radians(np.linspace(2, 89, 200)), 11e-3, 1e-3, 1))
    assert np.all(np.diff(D) < 0), "D' falls as the helical angle grows (paper section II-C)"
    assert D[-1] > 11e-3 and D[-1] < 11.3e-3, "a round bump of 1 mm adds < 0.3 mm to D' at 89 deg"


@pytest.mark.parametrize("lumen_mm", [10.0, 10.5, 10.9, 10.99])
def test_end_contact_closed_form_matches_quadrature(lumen_mm: float) -> None:
    R, Db, d = 5.5e-3, lumen_mm * 1e-3, 1e-3

    def integrand(z: float) -> float:
        d_after = 2 * math.sqrt(R * R - z * z)
        return max(d_after - Db, 0.0) / (Db + d) * d_after / 2

    zc = math.sqrt(R * R - Db * Db / 4)
    ref, _ = integrate.quad(integrand, 0.0, zc, epsabs=0, epsrel=1e-12)
    assert float(end_contact_moment_m2(2 * R, Db, d)) == pytest.approx(ref, rel=1e-9), (
        "end contact integral vs scipy quad of eq. 6 x D_after/2 over the hemisphere (1e-9)"
    )


def test_no_end_contact_when_lumen_is_wider() -> None:
    assert float(end_contact_moment_m2(11e-3, 11.1e-3, 1e-3)) == 0.0, (
        "sample 3 (11.1 mm lumen > 11 mm capsule): the ends do not touch (paper section III-B)"
    )


def _fixed_count_tangency_cos(psi_m, R, r_w, R_h):
    """The tangency Newton with every one of NEWTON_STEPS steps (the CasADi graph's count),
    the module's operations in the module's order (bits are the point), without its stop."""
    from torque_model.geometry import NEWTON_STEPS

    psi2, R2 = psi_m * psi_m, R * R
    q = R2 * r_w * r_w
    c = 1.0 + 0.0 * psi_m
    for _ in range(NEWTON_STEPS):
        rho = R_h + r_w * c
        rho2 = rho * rho
        F = psi2 * c * c * rho2 * (rho2 - R2) - q * (1.0 - c * c)
        dF = (
            psi2
            * (2.0 * c * rho2 * (rho2 - R2) + c * c * r_w * (4.0 * rho2 * rho - 2.0 * rho * R2))
            + 2.0 * q * c
        )
        c = c - F / dF
    return c


def test_tangency_newton_stops_early_with_the_same_bits() -> None:
    """Numbers stop the tangency Newton once settled (fixed point or last-bit 2-cycle): the
    same bits as all NEWTON_STEPS steps, floats and arrays, over 0.5-89.5 deg, D 4-20 mm,
    d_w 0.05-3 mm (exact equality, not a tolerance: the skipped steps only repeat)."""
    from torque_model.geometry import _tangency_cos

    rng = np.random.default_rng(38)
    alpha = np.radians(rng.uniform(0.5, 89.5, 2000))
    R = 0.5 * rng.uniform(4e-3, 20e-3, 2000)
    r_w = 0.5 * rng.uniform(0.05e-3, 3e-3, 2000)
    R_h = R + r_w
    psi = r_w / (R_h * np.sin(alpha))
    brute = _fixed_count_tangency_cos(psi, R, r_w, R_h)
    assert np.array_equal(_tangency_cos(psi, R, r_w, R_h), brute), "arrays: bit for bit"
    singles = [_tangency_cos(*(float(v[i]) for v in (psi, R, r_w, R_h))) for i in range(300)]
    assert singles == [float(b) for b in brute[:300]], "floats: bit for bit"
    sym = ca.SX.sym("psi")
    graph = ca.Function("c", [sym], [_tangency_cos(sym, R[0], r_w[0], R_h[0])])
    assert float(graph(psi[0])) == pytest.approx(float(brute[0]), rel=1e-14), (
        "CasADi keeps the fixed count: the same value to rounding (1e-14)"
    )
