"""One failure in the Monte Carlo: step-out OR a wall stretched by less than the minimum strain.

Independent checks: the share of samples below the minimum strain against a closed form written
here (D', the lumens and walls, a normal lumen offset, scipy.stats), the classification of single
samples against ``optimize.evaluate`` of the same tissues, and the counting rules themselves.
"""

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

import torque_model as tm
from optimize import evaluate
from optimize import uncertainty as uq
from optimize.system import prepare
from spiralcap.assemble import build_model
from spiralcap.assemble.tissue import build_uncertainty
from spiralcap.design import load_design
from tests.cli_outcome import run

#: The built-in design's deterministic optimum sits on the strain edge of the wider lumen
#: (zhou2013-sample3 stretched by exactly requirements.min_wall_strain), issue 36.
EDGE = (
    "capsule.spiral.helical_angle_deg=19.64702354367885",
    "operation.frequency_hz=0.743",
    "requirements.min_wall_strain=0.017",  # the edge is this strain's (held if the default moves)
    # the samples perturb the tissue about the nominal spiral; evaluate, the reference here,
    # then judges the same nominal spiral (no [tolerances] box: it holds rows at its corners)
    "tolerances.helical_angle_deg=0",
    "tolerances.spiral_wire_diameter_mm=0",
    "tolerances.lumen_diameter_mm=0",
)
LUMEN = "tissue.uncertainty.lumen_diameter_sigma_mm=0.3"


def _below_closed_form(model, alpha_rad: float, sigma_m: float, eps_min: float) -> float:
    """P(some set's strain < eps_min) for one normal lumen offset shared by every set:
    strain_k = (D' - L_k - d)/(L_k + d + w_k) < eps  <=>  d > (D' - L_k - eps (L_k + w_k))/(1 + eps).
    (The sampler truncates the offset at -90 % of the lumen: 30 standard deviations here.)"""
    c = model.constants
    d_prime = float(
        tm.equivalent_diameter_m(alpha_rad, c.body_diameter_m, c.wire_diameter_m, c.starts)
    )
    x = min(
        (d_prime - t.lumen_diameter_m - eps_min * (t.lumen_diameter_m + t.wall_thickness_m))
        / (1.0 + eps_min)
        for t in model.tissues
    )
    return float(stats.norm.sf(x / sigma_m))


@pytest.fixture(scope="module")
def edge_study():
    from spiralcap.uncertainty import study

    design = load_design(None, [*EDGE, LUMEN])
    return design, study(design, samples=100_000, sobol_base=0)


def test_edge_optimum_fails_half_the_samples(edge_study):
    design, st = edge_study
    r = st.result
    model = prepare(build_model(design))
    exact = _below_closed_form(
        model, math.radians(19.64702354367885), 0.3e-3, design["requirements.min_wall_strain"]
    )
    se = math.sqrt(exact * (1 - exact) / r.samples)
    assert abs(exact - 0.5) < 0.01, f"closed form {exact:.4f}: the edge optimum is on the edge"
    assert abs(r.below_min_strain.value - exact) < 4 * se, (
        f"P(below min strain) {r.below_min_strain.value:.5f} vs closed form {exact:.5f} "
        f"(D', lumens, walls, normal offset; 4 binomial standard errors {se:.2g})"
    )
    assert r.closed_form["below_min_strain"] == pytest.approx(exact, rel=1e-4), (
        "the code's closed form equals the one written here (truncation negligible; the code "
        "judges the strain with evaluate's 1e-6 tolerance: 1e-4)"
    )
    assert r.failure.value >= r.below_min_strain.value >= r.no_grip.value > 0.2, (
        "failure includes every sample below the minimum strain, which includes no contact"
    )
    assert r.failure.value <= r.below_min_strain.value + r.stepout_probability + 1e-15
    assert r.speed_percentiles_m_s["p05"] == 0.0 and r.speed_percentiles_m_s["p50"] == 0.0, (
        "speed 0 in every failed sample: half fail, so p05 and p50 are 0"
    )
    assert r.margin_percentiles_Nm["p05"] <= 0.0, "a failed sample never counts as good margin"
    lo, hi = r.failure.ci95
    assert lo <= r.failure.value <= hi


def test_each_sample_is_classified_as_evaluate_judges_it():
    """Single samples against ``optimize.evaluate`` of the same tissues (lumen moved by the
    sample's offset): its margin, its wall strains, and so fails/does not fail."""
    design = load_design(None, [*EDGE, LUMEN])
    model = build_model(design)
    problem = uq.margin_problem(model, build_uncertainty(design))
    u = np.array([[0.02], [0.3], [0.49], [0.51], [0.8], [0.995]])
    out = problem.outcomes(u)
    eps = design["requirements.min_wall_strain"]
    for ui, (m, strain) in zip(u[:, 0], out):
        delta = 0.3e-3 * stats.norm.ppf(ui)
        tissues = tuple(
            replace(t, lumen_diameter_m=t.lumen_diameter_m + delta) for t in model.tissues
        )
        ev = evaluate(replace(model, tissues=tissues, constants=None))
        # evaluate's margin is NaN without contact (no physics there); the sample keeps the
        # formulas' margin (available - required) and is counted as failed below
        formula = ev.magnetic_torque_Nm - ev.required_torque_Nm
        assert m == pytest.approx(formula, rel=1e-9, abs=1e-15), "margin as evaluate's torques"
        assert np.isnan(ev.margin_Nm) == (ev.grip == "none"), "evaluate: NaN margin iff no contact"
        assert strain == pytest.approx(min(ev.wall_strains), rel=1e-9, abs=1e-15)
        fails = ev.margin_Nm < 0 or min(ev.wall_strains) < eps
        assert bool(uq.failed(m, strain, eps)) == fails, f"u={ui}: evaluate says fails={fails}"
        counted = uq.counted_margins(m, strain, eps)
        assert counted == (min(m, 0.0) if fails else m), "failed: min(margin, 0); else margin"


def test_without_lumen_spread_failure_is_stepout():
    """Scale-only uncertainty at a design that grips well: no sample loses grip, so the failure
    probability is the step-out probability (and the counted margins are the margins)."""
    p = uq.margin_problem(
        build_model(load_design(None, ["tissue.uncertainty.scale_sigma_log=0.5"])),
        build_uncertainty(load_design(None, ["tissue.uncertainty.scale_sigma_log=0.5"])),
    )
    o = uq.run_local(p, 4096, seed=3)
    r = uq.summarise(p, o, 3, "sobol")
    assert r.below_min_strain.value == 0.0 and r.no_grip.value == 0.0
    assert r.failure.value == r.stepout_probability > 0
    assert np.array_equal(r.margins_Nm, o[:, 0])


def test_cli_leads_with_failure_and_json_has_its_parts():
    argv = ["uncertainty", *(w for s in (*EDGE, LUMEN) for w in ("--set", s))]
    argv += ["--samples", "8192", "--sobol-samples", "0"]
    rc, text, _ = run(argv)
    assert rc == 0, text
    first = [ln for ln in text.splitlines() if ln.strip()][2]
    assert first.startswith("P(failure)"), f"the text leads with P(failure): {first!r}"
    rc, out, _ = run([*argv, "--json"])
    doc = json.loads(out)
    import jsonschema

    with open(
        Path(__file__).resolve().parents[1] / "docs/json/uncertainty.schema.json", encoding="utf-8"
    ) as fh:
        jsonschema.validate(doc, json.load(fh))
    f = doc["failure_probability"]
    parts = f["parts"]
    assert set(parts) == {
        "stepout_probability",
        "below_min_strain_probability",
        "no_grip_probability",
    }
    for p in (f, *parts.values()):
        assert p["ci95"][0] <= p["value"] <= p["ci95"][1], "a Wilson interval around each"
    assert abs(parts["below_min_strain_probability"]["value"] - 0.5) < 0.02
    assert "min(margin, 0)" in doc["margin_counting"]
    assert doc["speed_percentiles_m_s"]["p05"] == 0.0


#: A design whose robust optimum can hold P(failure) <= 5 % with the lumen spread: a 1.5 mm
#: spiral (D' large enough at about 8 deg) and a stronger magnet to turn it there (with the
#: built-in 1 mm spiral the lumen spread needs about 3-4 deg, where the torque is out of reach).
ROBUST_DESIGN = (
    LUMEN,
    "requirements.min_wall_strain=0.017",
    "capsule.spiral.wire_diameter_mm=1.5",
    "optimize.helical_angle_min_deg=3",
    "capsule.magnet.diameter_mm=8",
    "capsule.magnet.length_mm=14",
    "requirements.max_failure_probability=0.05",
)


@pytest.mark.slow
def test_robust_optimum_fails_at_most_5_percent_of_fresh_samples():
    from spiralcap.robust import robust_optimum

    # 256 scenarios, not the default 1024: the claim is checked on the 100,000 fresh samples,
    # whatever the number of scenarios the optimum was found on (P(failure) 1.9 % with 1024,
    # 1.9 % with 256); a working set of 32 rows compiles and solves in less time than 80
    design = load_design(None, [*ROBUST_DESIGN, "optimize.scenarios=256"])
    rc = robust_optimum(design, samples=100_000)
    res, oos = rc.result, rc.out_of_sample
    assert res.status == "optimal", res.status
    _, hi = oos.failure.ci95
    assert oos.samples == 100_000 and hi <= 0.05, (
        f"P(failure) {oos.failure.value:.4f} (Wilson 95 % up to {hi:.4f}) <= 0.05 over 100,000 "
        "fresh samples (step-out or below the minimum strain)"
    )
    model = prepare(build_model(design))
    exact = _below_closed_form(
        model, res.helical_angle_rad, 0.3e-3, design["requirements.min_wall_strain"]
    )
    se = math.sqrt(exact * (1 - exact) / oos.samples)
    assert 0.002 < exact and abs(oos.below_min_strain.value - exact) < 4 * se, (
        f"fresh P(below min strain) {oos.below_min_strain.value:.5f} vs closed form "
        f"{exact:.5f} (D', lumens, walls, normal offset; 4 binomial standard errors {se:.2g})"
    )
    assert rc.in_sample.failure_probability <= 0.05, "CVaR_p >= 0 implies P <= p in-sample"
    d_oos = rc.deterministic_out_of_sample
    assert d_oos.failure.value > 0.15 > oos.failure.value, (
        "the deterministic optimum (on the nominal strain edge) fails far more often"
    )


def test_margin_p05_moves_off_the_nominal_strain_edge():
    """The built-in design, lumen sigma 0.3 mm: the deterministic optimum stretches the wider
    lumen by exactly the minimum strain (half the samples lose grip); margin_p05, counting lost
    grip as failure, moves to a steeper spiral (a smaller angle) that stretches every nominal
    wall well beyond it."""
    from optimize import optimize_design
    from spiralcap.robust import robust_model

    # 128 scenarios (256 before): the move off the edge is judged on the nominal sets and by
    # the closed form, not on the scenarios; a working set of 16 rows instead of 32
    sets = [LUMEN, "optimize.objective=margin_p05", "optimize.scenarios=128"]
    design = load_design(None, [*sets, "requirements.min_wall_strain=0.017"])
    model = robust_model(design)
    res = optimize_design(model)
    eps = design["requirements.min_wall_strain"]
    assert res.status == "optimal"
    assert min(evaluate(res_model(model, res)).wall_strains) > 1.5 * eps, (
        "off the edge: the least nominal strain is well above the minimum"
    )
    assert res.helical_angle_deg < 15.0, "a smaller angle (wider bump, larger D')"
    edge = uq.margin_problem(model, build_uncertainty(design), math.radians(19.647), 0.743)
    before = _below_closed_form(prepare(model), edge.helical_angle_rad, 0.3e-3, eps)
    after = _below_closed_form(prepare(model), res.helical_angle_rad, 0.3e-3, eps)
    assert after < 0.25 < before, (
        f"the share below the minimum strain falls from {before:.3f} to {after:.3f} (closed form)"
    )


def res_model(model, res):
    """The model at the optimum's angle and frequency (the nominal sets)."""
    from dataclasses import replace as _replace

    from optimize.solve import with_operating_point

    return with_operating_point(_replace(model, scenarios=None), res)


def test_grip_rows_only_where_the_scenarios_move_the_strain():
    """Scale-only scenarios stretch every wall as the nominal sets do (held at the minimum by
    the nominal wall-strain rows): no grip rows, so the robust optimum is the one without them
    (the CVaR equals that of the torque margins alone); with a lumen spread the rows are
    there."""
    from optimize import robust as rb

    base = build_model(load_design(None, []))
    scale = uq.TissueUncertainty(scale_sigma_log=0.3)
    lumen = uq.TissueUncertainty(scale_sigma_log=0.3, lumen_diameter_sigma_m=0.1e-3)
    a = prepare(rb.with_scenarios(base, scale, scenarios=32))
    b = prepare(rb.with_scenarios(base, lumen, scenarios=32))
    assert not a.scenarios.grip and b.scenarios.grip
    alpha, f, field = math.radians(19.6), 0.75, 10e-3
    ra = rb.scenario_rows(
        alpha,
        f,
        field,
        a.constants,
        a.requirements,
        a.scenarios.tissues,
        a.scenarios.grip_torque_Nm,
        a.scenarios.grip,
    )
    rb_ = rb.scenario_rows(
        alpha,
        f,
        field,
        b.constants,
        b.requirements,
        b.scenarios.tissues,
        b.scenarios.grip_torque_Nm,
        b.scenarios.grip,
    )
    assert len(ra) == len(base.tissues) and len(rb_) == 2 * len(base.tissues)
    # the grip margin is negative exactly where the strain (eq. 6, written here) is below the
    # minimum: the effective margin counts a lost grip as a failure
    c = b.constants
    d_prime = tm.equivalent_diameter_m(alpha, c.body_diameter_m, c.wire_diameter_m, c.starts)
    eps = b.requirements.min_wall_strain
    for k, t in enumerate(b.scenarios.tissues):
        strain = (d_prime - t.lumen_diameter_m) / (t.lumen_diameter_m + t.wall_thickness_m)
        grip = np.asarray(rb_[len(base.tissues) + k])
        assert np.array_equal(grip < 0, strain < eps), "grip margin < 0 <=> strain < minimum"


def test_nominal_margin_absent_without_nominal_contact():
    """A nominal lumen wider than D' (11.8 mm against D' of about 11.3 mm at 20 deg): the model
    has no margin there, so the nominal margin is NaN, as evaluate's (and absent from the JSON
    with its ``_undefined`` flag); with contact it is evaluate's margin."""
    from spiralcap.uncertainty import _nominal_margin

    for lumen, contact in (("11.8", False), ("10.9", True)):
        design = load_design(None, [*EDGE, LUMEN, f"tissue.lumen_diameter_mm={lumen}"])
        model = build_model(design)
        nominal = uq.margin_problem(model, build_uncertainty(design)).nominal_margin_Nm()
        ev = evaluate(model)
        assert (ev.grip != "none") == contact, f"lumen {lumen} mm: contact by evaluate"
        if contact:
            assert nominal == pytest.approx(ev.margin_Nm, rel=1e-9), "nominal = evaluate's margin"
            assert _nominal_margin(nominal) == {"nominal_margin_Nm": nominal}
        else:
            assert math.isnan(nominal) and math.isnan(ev.margin_Nm), "no contact: no margin"
            assert _nominal_margin(nominal) == {"nominal_margin_Nm_undefined": True}
