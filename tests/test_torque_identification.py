"""Identification of the five-element constants (Zhou 2013 section III-C) on synthetic data."""

from __future__ import annotations

import math

import numpy as np
import pytest

import torque_model as tm
from spiralcap.core.errors import DataError
from torque_model.identification import _RelaxationIntegral

BASE = tm.preset("zhou2013-sample2")
RICH_TRUTH = BASE.replace(E1_Pa=2e4, E2_Pa=5e4, E3_Pa=1e4, eta1_Pa_s=1e4, eta2_Pa_s=2.5e3)


def _synthetic(
    truth: tm.TissueParameters, f: np.ndarray, angle: np.ndarray | float, noise: float, seed: int
) -> np.ndarray:
    clean = np.asarray(tm.resistive_torque_Nm(angle, f, truth, tm.PAPER_CAPSULE))
    return clean * (1.0 + noise * np.random.default_rng(seed).normal(size=clean.shape))


def test_predicts_unseen_frequencies_and_angles() -> None:
    f = np.tile(np.linspace(0.5, 3.0, 11), 2)
    angle = np.repeat(np.radians([5.0, 10.0]), 11)
    y = _synthetic(BASE, f, angle, noise=0.02, seed=7)
    fit = tm.identify(
        f,
        y,
        angle,
        BASE.replace(E1_Pa=1e3, E2_Pa=1e3, E3_Pa=1e3, eta1_Pa_s=1e3, eta2_Pa_s=1e3),
        tm.PAPER_CAPSULE,
    )
    f_new = np.array([0.6, 1.1, 1.9, 2.6, 2.9])
    for deg in (5.0, 10.0, 15.0):
        a = math.radians(deg)
        pred = np.asarray(fit.predict_Nm(f_new, a))
        true = np.asarray(tm.resistive_torque_Nm(a, f_new, BASE, tm.PAPER_CAPSULE))
        assert np.allclose(pred, true, rtol=0.03), (
            f"fitted model at unseen frequencies, {deg} deg, vs the model that made the data "
            "(2 % noise, tolerance 3 %)"
        )
    assert fit.residual_std == pytest.approx(0.02, rel=0.5), "s estimates the 2 % noise"
    assert fit.tissue.lumen_diameter_m == BASE.lumen_diameter_m, "lumen fixed"
    assert fit.tissue.friction_coefficient == BASE.friction_coefficient, "friction fixed"


def test_says_which_parameters_the_data_cannot_pin_down() -> None:
    f = np.linspace(0.5, 3.0, 8)
    fit = tm.identify(f, _synthetic(BASE, f, 0.17, 0.03, 3), 0.17, BASE, tm.PAPER_CAPSULE)
    assert set(fit.not_pinned_down) >= {"E1_Pa", "E3_Pa", "eta1_Pa_s"}, (
        "sample-2-like curve: arm 1 acts as a spring, so E1, E3 (only E1 + E3 is seen) and "
        "eta1 are flagged (docs/torque-model.md section 5)"
    )
    for name in fit.not_pinned_down:
        assert fit.flags[name], "every unpinned parameter says why"


def test_one_frequency_only_is_singular() -> None:
    f = np.full(6, 1.0)
    fit = tm.identify(f, _synthetic(BASE, f, 0.17, 0.01, 1), 0.17, BASE, tm.PAPER_CAPSULE)
    assert set(fit.not_pinned_down) == set(tm.PARAMETER_NAMES), (
        "six points at one frequency fix one number: all five parameters unpinned"
    )
    assert fit.condition_number > 1e12 or not np.isfinite(fit.condition_number)


def test_rich_data_pin_everything_down() -> None:
    f = np.geomspace(0.05, 20.0, 30)
    y = _synthetic(RICH_TRUTH, f, 0.17, noise=0.002, seed=11)
    fit = tm.identify(f, y, 0.17, BASE, tm.PAPER_CAPSULE)
    assert fit.not_pinned_down == (), (
        "relaxation times 0.5 s and 0.05 s inside 0.05-20 Hz at 0.2 % noise: all identifiable"
    )
    for name in tm.PARAMETER_NAMES:
        true = getattr(RICH_TRUTH, name)
        assert abs(fit.values[name] - true) < 3.0 * fit.standard_errors[name], (
            f"{name}: within 3 standard errors of the true value (99.7 % if s(J^T J)^-1 holds)"
        )
        assert fit.values[name] == pytest.approx(true, rel=0.1), f"{name} recovered within 10 %"
    assert (
        fit.values["eta1_Pa_s"] / fit.values["E1_Pa"]
        >= fit.values["eta2_Pa_s"] / fit.values["E2_Pa"]
    ), "arms ordered slow first (Tables I-II)"


def test_fitted_tissue_reproduces_predictions() -> None:
    f = np.linspace(0.5, 3.0, 7)
    fit = tm.identify(f, _synthetic(BASE, f, 0.17, 0.02, 5), 0.17, BASE, tm.PAPER_CAPSULE)
    direct = np.asarray(tm.resistive_torque_Nm(0.17, f, fit.tissue, tm.PAPER_CAPSULE))
    assert np.allclose(direct, fit.predicted_Nm, rtol=1e-12), (
        "G(alpha) I(omega) factorisation in identify = resistive_torque_Nm (1e-12)"
    )
    assert np.allclose(fit.residuals, (fit.predicted_Nm - fit.torque_Nm) / fit.torque_Nm)


def _hand_integral_and_gradient(f: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """I(omega) of Zhou 2013 eq. 4 over one turn and E dI/dE, eta dI/deta, derived by hand."""
    E1, E2, E3, eta1, eta2 = p
    omega = 2.0 * math.pi * f
    value = np.full_like(omega, 2.0 * math.pi * E3)
    grad = np.zeros((omega.size, 5))
    grad[:, 2] = 2.0 * math.pi * E3
    for E, eta, iE, ieta in ((E1, eta1, 0, 3), (E2, eta2, 1, 4)):
        x = 2.0 * math.pi * E / (omega * eta)
        one_minus = -np.expm1(-x)
        value = value + omega * eta * one_minus
        grad[:, iE] = E * 2.0 * math.pi * np.exp(-x)
        grad[:, ieta] = eta * omega * (one_minus - x * np.exp(-x))
    return value, grad


def test_model_jacobian_matches_hand_derivation_and_finite_differences() -> None:
    f = np.array([0.3, 1.0, 2.5, 7.0])
    p = np.array([2e4, 5e4, 1e4, 1e4, 2.5e3])
    integral = _RelaxationIntegral(f)
    grad = integral.jacobian(np.log(p))
    hand_value, hand_grad = _hand_integral_and_gradient(f, p)
    assert np.allclose(integral.value(p), hand_value, rtol=1e-13, atol=0), (
        "model I(omega) vs the closed form of eq. 4 written by hand, rel 1e-13"
    )
    assert np.allclose(grad, hand_grad, rtol=1e-12, atol=1e-12 * np.abs(hand_grad).max()), (
        "CasADi Jacobian of the model vs the hand-derived dI/dlog p, rel 1e-12"
    )
    for j in range(5):
        h = 1e-6
        up, dn = p.copy(), p.copy()
        up[j] *= math.exp(h)
        dn[j] *= math.exp(-h)
        fd = (integral.value(up) - integral.value(dn)) / (2 * h)
        assert np.allclose(grad[:, j], fd, rtol=1e-6, atol=1e-9 * np.abs(fd).max()), (
            f"dI/dlog p[{j}] vs central difference (1e-6)"
        )


def test_finite_difference_jacobian_gives_same_fit() -> None:
    f = np.linspace(0.05, 20.0, 20)
    y = _synthetic(RICH_TRUTH, f, 0.17, 0.002, 2)
    a = tm.identify(f, y, 0.17, BASE, tm.PAPER_CAPSULE)
    b = tm.identify(f, y, 0.17, BASE, tm.PAPER_CAPSULE, jacobian="2-point", profile_bounds=False)
    assert b.cost == pytest.approx(a.cost, rel=1e-3), "same optimum with scipy's 2-point Jacobian"


def test_refuses_fewer_points_than_parameters() -> None:
    with pytest.raises(DataError, match="4 data points for 5 parameters"):
        tm.identify([0.5, 1, 2, 3], [1e-3, 1.2e-3, 1.5e-3, 1.8e-3], 0.17, BASE, tm.PAPER_CAPSULE)


@pytest.mark.parametrize(
    ("freq", "torque", "match"),
    [
        ([0.5, 1, 2, 3, float("nan")], [1e-3] * 5, "point 5: frequency_hz"),
        ([0.5, 1, 2, 3, 0.0], [1e-3] * 5, "point 5: frequency_hz"),
        ([0.5, 1, 2, 3, 4], [1e-3, -1e-3, 1e-3, 1e-3, 1e-3], "point 2: torque_Nm"),
        ([0.5, 1, 2, 3, 4], [1e-3] * 4, "4 values for 5"),
    ],
)
def test_bad_points_named(freq, torque, match) -> None:
    with pytest.raises(DataError, match=match):
        tm.identify(freq, torque, 0.17, BASE, tm.PAPER_CAPSULE)


def test_no_contact_refused() -> None:
    wide = BASE.replace(lumen_diameter_m=13e-3)
    with pytest.raises(DataError, match="does not touch"):
        tm.identify(np.linspace(0.5, 3, 6), np.full(6, 1e-3), 0.17, wide, tm.PAPER_CAPSULE)
