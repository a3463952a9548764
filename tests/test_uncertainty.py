"""Tissue uncertainty: closed forms, agreement with evaluate(), Sobol indices, reproducibility."""

import math
from dataclasses import replace

import numpy as np
import pytest
from cli_outcome import NO_TOLERANCE_SETS
from scipy import stats

from optimize import evaluate
from optimize import uncertainty as uq
from spiralcap.assemble import build_model
from spiralcap.assemble.tissue import build_uncertainty
from spiralcap.design import load_design


def _problem(*sets: str, one_set: bool = False) -> uq.MarginProblem:
    extra = ["tissue.worst_case_presets=[]"] if one_set else []
    design = load_design(None, [*sets, *extra])
    return uq.margin_problem(build_model(design), build_uncertainty(design))


@pytest.mark.parametrize("method", ["random", "sobol"])
def test_scale_only_stepout_matches_closed_form(method):
    sigma = 0.5
    p = _problem(f"tissue.uncertainty.scale_sigma_log={sigma}", one_set=True)
    n = 200_000
    m = uq.run_local(p, n, seed=11, method=method)[:, 0]
    exact = uq.closed_form_stepout_probability(p)
    est = float(np.mean(m < 0))
    se = math.sqrt(exact * (1 - exact) / n)
    assert 0.005 < exact < 0.5, "the check needs a probability well inside (0, 1)"
    assert abs(est - exact) < 4 * se, (
        f"P(step-out) {est:.5f} vs closed form 1-Phi(ln k*/sigma) = {exact:.5f} "
        f"(margin linear in the common factor k; within 4 standard errors {se:.2g})"
    )


def test_samples_evaluate_like_evaluate_with_scaled_tissues():
    # a scale-only sample at latent u is the model with every tissue scaled by exp(sigma z)
    sigma = 0.4
    # the samples are the nominal capsule's: evaluate without the tolerance box (issue 36)
    design = load_design(None, [f"tissue.uncertainty.scale_sigma_log={sigma}", *NO_TOLERANCE_SETS])
    model = build_model(design)
    p = uq.margin_problem(model, build_uncertainty(design))
    u = np.array([[0.5], [0.1], [0.93]])
    got = p.margins_Nm(u)
    for ui, mi in zip(u[:, 0], got):
        k = math.exp(sigma * stats.norm.ppf(ui))
        scaled = replace(model, tissues=tuple(t.scaled(k) for t in model.tissues), constants=None)
        ref = evaluate(scaled).margin_Nm
        assert mi == pytest.approx(ref, rel=1e-12, abs=1e-15), (
            "vectorised sample margin equals optimize.evaluate with TissueParameters.scaled(k) "
            "(same physics; 1e-12 relative)"
        )
    assert p.nominal_margin_Nm() == pytest.approx(evaluate(model).margin_Nm, rel=1e-12)


def test_sobol_indices_match_product_of_lognormals():
    # no axial load and one tissue set: margin = A - R0 * X1 * X2 with X1 = exp(s1 z1) (scale)
    # and X2 = exp(s2 z2) (friction; the resistive torque is linear in mu). Analytic indices:
    # V = E[X1^2]E[X2^2] - (E X1 E X2)^2, S1_1 = Var X1 (E X2)^2 / V, ST_1 = Var X1 E[X2^2] / V.
    s1, s2 = 0.3, 0.2
    p = _problem(
        f"tissue.uncertainty.scale_sigma_log={s1}",
        f"tissue.uncertainty.friction_sigma_log={s2}",
        "requirements.axial_load_mN=0",
        one_set=True,
    )
    res = uq.sobol_indices(p, base_samples=1 << 13, seed=3)

    def moments(s):
        return math.exp(s * s / 2), math.exp(2 * s * s)

    (e1, q1), (e2, q2) = moments(s1), moments(s2)
    v = q1 * q2 - (e1 * e2) ** 2
    exact = {
        "scale": ((q1 - e1**2) * e2**2 / v, (q1 - e1**2) * q2 / v),
        "friction": ((q2 - e2**2) * e1**2 / v, (q2 - e2**2) * q1 / v),
    }
    for i, name in enumerate(res.inputs):
        s1_ex, st_ex = exact[name]
        assert abs(res.first_order[i] - s1_ex) < max(3 * res.first_order_conf[i], 0.03), (
            f"first-order Sobol index of {name}: {res.first_order[i]:.3f} vs analytic "
            f"{s1_ex:.3f} for a product of log-normals (Saltelli 2010 estimator, 3 conf)"
        )
        assert abs(res.total[i] - st_ex) < max(3 * res.total_conf[i], 0.03), (
            f"total Sobol index of {name}: {res.total[i]:.3f} vs analytic {st_ex:.3f}"
        )


def test_chunks_and_sequences_are_reproducible():
    p = _problem(
        "tissue.uncertainty.scale_sigma_log=0.3", "tissue.uncertainty.lumen_diameter_sigma_mm=0.3"
    )
    n = uq.CHUNK + 1000
    for method in uq.METHODS:
        a = uq.run_local(p, n, seed=5, method=method)
        b = uq.run_local(p, n, seed=5, method=method)
        assert np.array_equal(a, b), f"{method}: same seed, same margins bit for bit"
    # quasi-random: sample i is point i of one sequence, however it is chunked
    whole = uq.latent_uniforms(2, 0, 2 * uq.CHUNK, 7, "sobol")
    tail = uq.latent_uniforms(2, uq.CHUNK, 10, 7, "sobol")
    assert np.array_equal(whole[uq.CHUNK : uq.CHUNK + 10], tail)
    assert not np.array_equal(uq.run_local(p, 1000, seed=6), uq.run_local(p, 1000, seed=5))


def test_geometry_offsets_are_truncated_and_correlations_honoured():
    cov = np.array(
        [
            [0.04, 0.03, 0, 0, 0],
            [0.03, 0.09, 0, 0, 0],
            [0, 0, 0.01, 0, 0],
            [0, 0, 0, 0.0, 0],
            [0, 0, 0, 0, 0.02],
        ]
    )
    unc = uq.TissueUncertainty(wall_thickness_sigma_m=2e-3, covariance_log=tuple(map(tuple, cov)))
    design = load_design()
    model = build_model(design)
    u = uq.latent_uniforms(len(unc.factors()), 0, 1 << 15, 1, "sobol")
    (t0, _) = uq.perturbed_tissues(model.tissues, unc, u)
    assert np.min(t0.wall_thickness_m) >= 0.1 * 1e-3 * (1 - 1e-12), "wall truncated at 10 %"
    logs = np.log(
        np.stack([getattr(t0, f) / getattr(model.tissues[0], f) for f in uq.VISCOELASTIC])
    )
    assert np.allclose(np.cov(logs), cov, atol=2e-3), (
        "sample covariance of the log-parameters reproduces the given (singular) covariance"
    )


@pytest.mark.parametrize(
    "kwargs",
    [
        {"scale_sigma_log": -0.1},
        {"sigma_log": (0, 0, float("nan"), 0, 0)},
        {"covariance_log": ((1.0, 2.0),)},
        {"covariance_log": tuple(tuple(r) for r in -np.eye(5))},
    ],
)
def test_bad_uncertainty_is_an_input_error(kwargs):
    from spiralcap.core.errors import InputError

    with pytest.raises(InputError):
        uq.TissueUncertainty(**kwargs)


def test_a_set_field_is_the_field_of_the_samples():
    """operation.field_amplitude_mT: the study's nominal margin is evaluate()'s at that field."""
    design = load_design(
        None,
        [
            "tissue.uncertainty.scale_sigma_log=0.3",
            "operation.field_amplitude_mT=6",
            *NO_TOLERANCE_SETS,  # the samples are the nominal capsule's (issue 36)
        ],
    )
    model = build_model(design)
    p = uq.margin_problem(model, build_uncertainty(design))
    ev = evaluate(model)
    assert math.isclose(ev.field_amplitude_T, 6e-3, rel_tol=1e-12)
    assert math.isclose(p.nominal_margin_Nm(), ev.margin_Nm, rel_tol=1e-12), (
        "nominal margin of the samples = evaluate() at the set field (same physics, 1e-12)"
    )
