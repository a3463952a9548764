"""The resistive torque (Zhou 2013 eqs. 2-8) against the paper's prose numbers and numerics."""

from __future__ import annotations

import dataclasses
import math

import casadi as ca
import numpy as np
import pytest
from scipy import integrate

import torque_model as tm
from torque_model.calibration import fit_calibration_factor, published_tissue
from torque_model.parameters import zhou2013

SAMPLE2 = tm.preset("zhou2013-sample2")
SAMPLE3 = tm.preset("zhou2013-sample3")


@pytest.mark.parametrize(
    "point", tm.PAPER_POINTS, ids=lambda p: f"No{p.capsule}-{p.frequency_hz}Hz"
)
def test_paper_points_sample2(point: tm.PaperPoint) -> None:
    tol = 0.15 if point.role == "calibration" else 0.25
    model = (
        float(
            tm.resistive_torque_Nm(
                math.radians(point.helical_angle_deg), point.frequency_hz, SAMPLE2, tm.PAPER_CAPSULE
            )
        )
        * 1e3
    )
    assert model == pytest.approx(point.torque_mNm, rel=tol), (
        f"capsule No. {point.capsule} at {point.frequency_hz} Hz vs {point.source} "
        f"({point.role}, tolerance {tol:.0%})"
    )


def test_validation_points_never_enter_the_calibration() -> None:
    from torque_model.calibration import calibration_points

    pts = calibration_points()
    assert pts and all(p.capsule == 2 and p.role == "calibration" for p in pts), (
        "calibration uses sample 2 capsule No. 2 only (paper section III-C identification case)"
    )


def test_stored_factor_is_the_least_squares_factor() -> None:
    assert zhou2013.CALIBRATION_FACTOR == pytest.approx(fit_calibration_factor(), rel=1e-4), (
        "CALIBRATION_FACTOR vs least squares on the paper's No. 2 points (docs, 1e-4)"
    )


def test_literal_reading_arithmetic() -> None:
    p = published_tissue(2)
    a = math.radians(10)
    for f, expected in ((0.5, 1.602e-6), (3.0, 5.258e-6)):
        assert float(tm.resistive_torque_Nm(a, f, p, tm.PAPER_CAPSULE)) == pytest.approx(
            expected, rel=1e-3
        ), "Table I read literally in SI: docs/torque-model.md section 2 table (1e-3)"


def test_factor_scales_torque_and_keeps_shape() -> None:
    p = published_tissue(2)
    f = np.array([0.5, 1.0, 2.0, 3.0])
    ratio = tm.resistive_torque_Nm(0.2, f, SAMPLE2, tm.PAPER_CAPSULE) / tm.resistive_torque_Nm(
        0.2, f, p, tm.PAPER_CAPSULE
    )
    assert np.allclose(ratio, zhou2013.CALIBRATION_FACTOR, rtol=1e-12), (
        "torque is linear in a common factor on E1..eta2 (eqs. 2-8: exponents hold E/eta only)"
    )


def test_frequency_shape_matches_paper() -> None:
    a = math.radians(10)
    shape = float(
        tm.resistive_torque_Nm(a, 3.0, SAMPLE2, tm.PAPER_CAPSULE)
        / tm.resistive_torque_Nm(a, 0.5, SAMPLE2, tm.PAPER_CAPSULE)
    )
    assert shape == pytest.approx(1.8 / 0.6, rel=0.12), (
        "tau(3 Hz)/tau(0.5 Hz) vs the paper's 1.8/0.6 for capsule No. 2 (section II-C, 12 %)"
    )


def test_torque_rises_with_frequency_and_falls_with_angle() -> None:
    f = np.linspace(0.2, 5.0, 25)
    a = np.radians(np.linspace(3.0, 40.0, 20))[:, None]
    for tissue in (SAMPLE2, SAMPLE3):
        tau = np.asarray(tm.resistive_torque_Nm(a, f, tissue, tm.PAPER_CAPSULE))
        assert tau.shape == (20, 25), "alpha (20, 1) and f (25,) broadcast to (20, 25)"
        assert np.all(np.diff(tau, axis=1) > 0), (
            f"{tissue.name}: torque rises with frequency (paper section II-C, Figs. 4-5)"
        )
        assert np.all(np.diff(tau, axis=0) < 0), (
            f"{tissue.name}: torque falls as the helical angle grows (paper section II-C)"
        )


@pytest.mark.parametrize("tissue", [SAMPLE2, SAMPLE3], ids=lambda t: t.name)
@pytest.mark.parametrize("f", [0.3, 1.0, 3.0, 8.0])
def test_relaxation_integral_closed_form(tissue: tm.TissueParameters, f: float) -> None:
    ref, _ = integrate.quad(
        lambda th: float(tm.stress_Pa(th, f, 1.0, tissue)),
        0.0,
        2 * math.pi,
        epsabs=0,
        epsrel=1e-12,
        limit=200,
    )
    assert float(tm.relaxation_integral_Pa(f, tissue)) == pytest.approx(ref, rel=1e-9), (
        "closed-form theta integral of eq. 4 over one turn vs scipy quad (1e-9)"
    )


def test_normal_load_is_pressure_integrated_over_the_arc() -> None:
    eps, d_after, f = 0.04, 11.4e-3, 1.5

    def arc_load(th: float) -> float:
        sigma = tm.stress_Pa(th, f, eps, SAMPLE2)
        return float(tm.hoop_pressure_Pa(sigma, SAMPLE2.wall_thickness_m, d_after)) * d_after / 2

    ref, _ = integrate.quad(arc_load, 0.0, 2 * math.pi, epsrel=1e-12, limit=200)
    got = float(tm.normal_load_per_length_N_m(f, eps, SAMPLE2))
    assert got == pytest.approx(ref, rel=1e-9), (
        "int p(theta) D/2 dtheta with eq. 3 = d eps I (hoop tension), scipy quad (1e-9)"
    )


def test_breakdown_sums_and_ends_are_small() -> None:
    parts = tm.torque_breakdown_Nm(math.radians(10), 1.0, SAMPLE2, tm.PAPER_CAPSULE)
    assert float(parts["total"]) == pytest.approx(
        float(parts["wound"] + parts["cylinder"] + parts["ends"]), rel=1e-14
    ), "parts sum"
    assert float(parts["cylinder"]) == 0.0, "26 mm capsule: cylinder (15 mm) = wound length"
    assert 0 < float(parts["ends"]) < 0.02 * float(parts["total"]), (
        "ends touch over 0.74 mm only (z_c = sqrt(5.5^2 - 5.45^2) mm): < 2 % of the torque"
    )
    longer = tm.torque_breakdown_Nm(
        math.radians(10), 1.0, SAMPLE2, dataclasses.replace(tm.PAPER_CAPSULE, body_length_m=30e-3)
    )
    assert float(longer["cylinder"]) > 0, "a 4 mm unwound cylinder at D > lumen adds torque"


def test_numpy_and_casadi_agree() -> None:
    a, f = ca.SX.sym("alpha"), ca.SX.sym("f")
    for tissue in (SAMPLE2, SAMPLE3):
        tau = tm.resistive_torque_Nm(a, f, tissue, tm.PAPER_CAPSULE)
        fn = ca.Function("tau", [a, f], [tau, ca.gradient(tau, a), ca.gradient(tau, f)])
        for deg in (2.0, 5.0, 10.0, 25.0, 60.0):
            for hz in (0.5, 1.7, 3.0, 6.0):
                x = math.radians(deg)
                val, da, df = (float(v) for v in fn(x, hz))
                ref = float(tm.resistive_torque_Nm(x, hz, tissue, tm.PAPER_CAPSULE))
                assert val == pytest.approx(ref, rel=1e-12, abs=0), (
                    "numpy vs CasADi SX resistive torque (CONTRIBUTING: 1e-12)"
                )
                h = 1e-6
                fd_a = (
                    tm.resistive_torque_Nm(x + h, hz, tissue, tm.PAPER_CAPSULE)
                    - tm.resistive_torque_Nm(x - h, hz, tissue, tm.PAPER_CAPSULE)
                ) / (2 * h)
                fd_f = (
                    tm.resistive_torque_Nm(x, hz + h, tissue, tm.PAPER_CAPSULE)
                    - tm.resistive_torque_Nm(x, hz - h, tissue, tm.PAPER_CAPSULE)
                ) / (2 * h)
                assert da == pytest.approx(fd_a, rel=1e-6), "d tau/d alpha vs central difference"
                assert df == pytest.approx(fd_f, rel=1e-6), "d tau/d f vs central difference"


def test_casadi_mx_path() -> None:
    a, f = ca.MX.sym("alpha"), ca.MX.sym("f")
    fn = ca.Function("tau", [a, f], [tm.resistive_torque_Nm(a, f, SAMPLE2, tm.PAPER_CAPSULE)])
    assert float(fn(0.2, 2.0)) == pytest.approx(
        float(tm.resistive_torque_Nm(0.2, 2.0, SAMPLE2, tm.PAPER_CAPSULE)), rel=1e-12
    ), "numpy vs CasADi MX (1e-12)"


def test_sample3_same_order_as_sample2() -> None:
    f = np.array([0.5, 3.0])
    for deg in (5.0, 10.0, 15.0, 20.0):
        tau3 = (
            np.asarray(tm.resistive_torque_Nm(math.radians(deg), f, SAMPLE3, tm.PAPER_CAPSULE))
            * 1e3
        )
        assert np.all((tau3 > 0.2) & (tau3 < 5.0)), (
            "sample 3: 'the same order of magnitude' as sample 2's 0.6-2.3 mN·m (section II-C)"
        )
    parts = tm.torque_breakdown_Nm(math.radians(15), 1.0, SAMPLE3, tm.PAPER_CAPSULE)
    assert float(parts["ends"]) == 0.0, "11.1 mm lumen > 11 mm capsule: ends do not touch"


def test_no_contact_no_torque() -> None:
    wide = SAMPLE2.replace(lumen_diameter_m=13e-3)
    assert float(tm.resistive_torque_Nm(math.radians(10), 1.0, wide, tm.PAPER_CAPSULE)) == 0.0, (
        "a lumen wider than D' is not strained (eq. 6 clipped at zero)"
    )


def test_a_given_d_prime_is_the_one_computed_inside() -> None:
    """Callers with several tissue sets compute D' once (it depends on the capsule only) and
    pass it: the torque, its parts and the wall strain equal those computed without it, bit
    for bit on numbers, and the same expression values on CasADi SX."""
    angles = np.radians([3.0, 10.0, 25.0])
    d_prime = tm.capsule_d_prime_m(angles, tm.PAPER_CAPSULE)
    assert np.array_equal(
        d_prime,
        tm.equivalent_diameter_m(angles, 11e-3, 1e-3, 1),
    ), "capsule_d_prime_m is equivalent_diameter_m of the capsule's diameters and starts"
    for tissue in (SAMPLE2, SAMPLE3):
        given = tm.torque_breakdown_Nm(angles, 1.7, tissue, tm.PAPER_CAPSULE, d_prime)
        inside = tm.torque_breakdown_Nm(angles, 1.7, tissue, tm.PAPER_CAPSULE)
        for part in ("wound", "cylinder", "ends", "total"):
            assert np.array_equal(given[part], inside[part]), f"{part}: bit for bit"
        assert np.array_equal(
            tm.wall_strain(angles, tissue, tm.PAPER_CAPSULE, d_prime),
            tm.wall_strain(angles, tissue, tm.PAPER_CAPSULE),
        ), "wall strain: bit for bit"
    a = ca.SX.sym("alpha")
    shared = tm.resistive_torque_Nm(
        a, 1.7, SAMPLE2, tm.PAPER_CAPSULE, tm.capsule_d_prime_m(a, tm.PAPER_CAPSULE)
    )
    own = tm.resistive_torque_Nm(a, 1.7, SAMPLE2, tm.PAPER_CAPSULE)
    fn = ca.Function("both", [a], [shared, own])
    for x in angles:
        one, two = (float(v) for v in fn(x))
        assert one == two, "SX: the same value at every angle"
