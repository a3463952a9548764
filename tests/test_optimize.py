"""The optimiser: it beats a dense grid, recovers a known optimum, agrees with SLSQP, and says
plainly when nothing is feasible. Every expression comes from optimize.physics, so these tests
also pin evaluate and optimize to one definition of the margin."""

import json
import math
from dataclasses import replace

import casadi as ca
import numpy as np
import pytest
from reference_slsqp import solve_slsqp
from scipy.optimize import minimize_scalar

from optimize import evaluate, margin_grid, optimize_design, prepare
from optimize import physics as ph
from optimize import problem as pb
from optimize.solve import scales_for
from optimize.system import Tolerances
from spiralcap.assemble import build_model
from spiralcap.assemble.system import constraint_key
from spiralcap.cli import main
from spiralcap.design import load_design


@pytest.fixture(scope="module")
def model():
    return prepare(build_model(load_design()))


@pytest.fixture(scope="module")
def result(model):
    return optimize_design(model)


def test_builtin_design_is_optimal(result):
    assert result.status == "optimal", f"built-in design must be feasible: {result.message}"
    assert result.margin_Nm > 0, "positive margin at the optimum"
    assert result.binding_limits, "something limits the margin (else it would be unbounded)"


def test_optimum_beats_a_dense_grid(model, result):
    b = model.bounds
    A, F = np.meshgrid(
        np.linspace(b.helical_angle_min_rad, b.helical_angle_max_rad, 181),
        np.linspace(b.frequency_min_hz, b.frequency_max_hz, 181),
        indexing="ij",
    )
    g = margin_grid(model, A, F)
    best = np.max(np.where(g["feasible"], g["margin_Nm"], -np.inf))
    assert result.margin_Nm >= best - 1e-9 * abs(best), (
        f"IPOPT optimum {result.margin_Nm:.6e} must match or beat the 181x181 grid's {best:.6e}"
    )


def test_evaluate_reports_the_optimisers_margin(model, result):
    ev = evaluate(model, result.helical_angle_rad, result.frequency_hz)
    assert ev.feasible, f"evaluate at the optimum must be feasible: {ev.failed()}"
    assert math.isclose(ev.margin_Nm, result.margin_Nm, rel_tol=1e-9), (
        "evaluate and optimize share one margin definition (1e-9 relative)"
    )


def test_cli_round_trip_optimize_then_evaluate(capsys):
    assert main(["optimize", "--json"]) == 0
    opt = json.loads(capsys.readouterr().out)
    for key in (
        "status",
        "helical_angle_deg",
        "frequency_hz",
        "margin_Nm",
        "current_amplitudes_A",
        "binding_limits",
        "solve_time_s",
    ):
        assert key in opt, f"optimize --json has {key} (README)"
    assert (
        main(
            [
                "evaluate",
                "--json",
                "--set",
                f"capsule.spiral.helical_angle_deg={opt['helical_angle_deg']!r}",
                "--set",
                f"operation.frequency_hz={opt['frequency_hz']!r}",
            ]
        )
        == 0
    )
    ev = json.loads(capsys.readouterr().out)
    assert ev["feasible"] is True, "evaluate at the returned point: feasible: true (README)"
    assert math.isclose(ev["margin_Nm"], opt["margin_Nm"], rel_tol=1e-9), (
        "evaluate --json margin equals optimize --json margin (1e-9 relative)"
    )


def test_analytic_case_single_current_limit(model):
    """Frequency fixed, every limit but the current lifted: B0* = min_k g_k I_max / h_k exactly,
    and the angle minimises the required torque (found independently by scipy's bounded Brent)."""
    f0 = 1.3
    big = 1e9
    m = replace(
        model,
        constants=None,
        limits=replace(
            model.limits, voltage_V=big, power_W=big, coil_temperature_C=big, field_exposure="off"
        ),
        # the least wall strain the schema allows: it binds nowhere in the angle box
        requirements=replace(
            model.requirements, min_speed_m_s=0.0, min_spiral_turns=0.0, min_wall_strain=1e-4
        ),
        bounds=replace(model.bounds, frequency_min_hz=f0, frequency_max_hz=f0),
        tolerances=Tolerances(),  # the nominal rows (the box is tests/test_tolerances.py's)
    )
    m = prepare(m)
    c = m.constants
    field = min(m.limits.current_A / c.current_per_tesla_A_per_T)

    def need(a):
        return max(
            float(r + t) for r, t in ph.required_torques_Nm(a, f0, c, m.tissues, m.requirements)
        )

    b = m.bounds
    best = minimize_scalar(
        need,
        bounds=(b.helical_angle_min_rad, b.helical_angle_max_rad),
        method="bounded",
        options={"xatol": 1e-12},
    )
    expected = c.moment_Am2 * c.workspace_factor * field - best.fun
    res = optimize_design(m)
    assert res.status == "optimal"
    assert math.isclose(res.field_amplitude_T, field, rel_tol=1e-6), (
        "B0 at the single binding current limit: g I_max / h, 1e-6 relative"
    )
    assert math.isclose(res.margin_Nm, expected, rel_tol=1e-6), (
        "margin equals m κ B0* - min_alpha tau(alpha), 1e-6 relative"
    )
    keys = {constraint_key(bl.name) for bl in res.binding_limits}
    assert {k for k in keys if k.startswith("limits.")} == {"limits.current_A"}, (
        "the current limit is the only binding hardware limit"
    )


def test_ipopt_and_slsqp_agree(model, result):
    alpha, f, _, margin = solve_slsqp(model)
    assert math.isclose(margin, result.margin_Nm, rel_tol=1e-5), (
        "SLSQP (finite differences) and IPOPT (exact derivatives) reach the same margin, 1e-5"
    )
    assert math.isclose(alpha, result.helical_angle_rad, rel_tol=1e-3), (
        "same optimal helical angle, 1e-3 relative"
    )
    assert math.isclose(f, result.frequency_hz, rel_tol=1e-3), "same frequency, 1e-3 relative"


def test_multipliers_predict_a_relaxed_limit(model, result):
    top = max(
        (b for b in result.binding_limits if constraint_key(b.name).startswith("limits.")),
        key=lambda b: abs(b.sensitivity * b.allowed),
    )
    top_key = constraint_key(top.name)
    field = {
        "limits.current_A": "current_A",
        "limits.voltage_V": "voltage_V",
        "limits.power_W": "power_W",
        "limits.coil_temperature_C": "coil_temperature_C",
    }[top_key]
    step = 1e-3 * top.allowed  # for the temperature: 0.1 % of the allowed rise, in kelvin
    relaxed = replace(
        model,
        constants=None,
        limits=replace(model.limits, **{field: getattr(model.limits, field) + step}),
    )
    gained = optimize_design(relaxed).margin_Nm - result.margin_Nm
    assert math.isclose(gained, top.sensitivity * step, rel_tol=0.02), (
        f"multiplier of {top_key} predicts the margin gained by a 0.1 % relaxation (2 %)"
    )


def test_numpy_and_casadi_expressions_agree(model):
    scales = scales_for(model)
    x = ca.SX.sym("x", 4)  # scaled (alpha / 10 deg, f / 1 Hz, B0 / B_ref, t)
    obj, rows, _ = pb.expressions(x, model, scales)
    fn = ca.Function("g", [x], [obj, ca.vertcat(*rows)])
    for x0 in ([0.6, 0.8, 0.9, 0.1], [1.4, 2.5, 0.5, -0.3]):
        o_ca, g_ca = fn(x0)
        o_np, g_np, _ = pb.expressions(x0, model, scales)
        assert abs(float(o_ca) - float(o_np)) <= 1e-12 * max(1, abs(float(o_np))), (
            "numpy and CasADi paths of the objective, 1e-12"
        )
        assert np.allclose(
            np.asarray(g_ca).ravel(), [float(v) for v in g_np], rtol=1e-12, atol=1e-13
        ), "numpy and CasADi paths of every constraint, 1e-12"


def test_impossible_speed_is_infeasible_and_named(capsys):
    code = main(["optimize", "--json", "--set", "requirements.min_speed_mm_s=500"])
    out = json.loads(capsys.readouterr().out)
    assert code == 3, "infeasible design: exit status 3 (README)"
    assert out["status"] == "infeasible"
    assert "requirements.min_speed_mm_s" in [s["key"] for s in out["shortfalls"]], (
        "the shortfall names the speed requirement"
    )
    best = next(s for s in out["shortfalls"] if s["key"] == "requirements.min_speed_mm_s")
    assert 0 < best["best"] < 0.5, "best reachable speed is positive and below 500 mm/s"


def test_text_output_of_infeasible(capsys):
    assert main(["optimize", "--set", "requirements.min_speed_mm_s=500"]) == 3
    captured = capsys.readouterr()
    assert "requirements.min_speed_mm_s" in captured.out and "Traceback" not in captured.err


def test_ratio_objective_maximises_safety_factor(model):
    ratio = optimize_design(replace(model, bounds=replace(model.bounds, objective="ratio")))
    assert ratio.status == "optimal"
    b = model.bounds
    A, F = np.meshgrid(
        np.linspace(b.helical_angle_min_rad, b.helical_angle_max_rad, 121),
        np.linspace(b.frequency_min_hz, b.frequency_max_hz, 121),
        indexing="ij",
    )
    g = margin_grid(model, A, F)
    best = np.max(np.where(g["feasible"], g["safety_factor"], -np.inf))
    assert ratio.safety_factor >= best * (1 - 1e-9), (
        "ratio objective beats the 121x121 grid's best safety factor"
    )


def test_single_heading_leaves_the_unused_axis_idle(capsys):
    """A capsule steered only about z needs no z current: the z pair carries none and its
    limits cannot bind (regression: a zero current once divided by zero)."""
    assert main(["optimize", "--json", "--set", "workspace.headings=[[0, 0, 1]]"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "optimal"
    assert out["current_amplitudes_A"]["z"] == 0.0, "heading along z: no z current"


@pytest.mark.parametrize(
    ("setting", "key"),
    [("limits.x.power_W=5", "limits.x.power_W"), ("limits.power_W=1", "limits.power_W")],
)
def test_a_torque_shortfall_names_the_limit_that_caps_the_field(capsys, setting, key):
    """Infeasible for want of torque: the line names the design key whose limit sets the field
    at the best design found, and that field (the JSON evaluation's, in mT), not only "more
    field would help"."""
    import re

    assert main(["optimize", "--json", "--set", setting]) == 3
    field_mT = json.loads(capsys.readouterr().out)["evaluation"]["field_amplitude_T"] * 1e3
    assert main(["optimize", "--set", setting]) == 3
    out = capsys.readouterr().out
    # (the case limits.power_W=1 is also the check that a 1 W budget cannot turn the capsule)
    short = [ln for ln in out.splitlines() if "falls short of the required torque" in ln]
    assert short, f"{setting}: the text says the torque falls short: {out}"
    line = short[0]
    found = re.search(r"there (\S+) \(.*?\) caps the field at ([\d.]+) mT", line)
    assert found and found.group(1) == key, f"{setting}: names {key}: {line}"
    assert float(found.group(2)) == pytest.approx(field_mT, rel=1e-3), "the field, 4 digits"


def test_an_infeasible_power_or_robust_optimum_prints_no_false_limit_or_nan(capsys):
    """Least power at 2 W: the field at the best design is the solver's own ("fixed"), not a
    limit, so no limit is named; a robust optimum with no feasible point: its scenario check
    is said not to have run, never "nan mN·m"."""
    power = ["optimize.objective=power", "limits.power_W=2", "requirements.min_safety_factor=2"]
    assert main(["optimize", *(a for s in power for a in ("--set", s))]) == 3
    out = capsys.readouterr().out
    assert "falls short" in out and "caps the field" not in out, out
    # x's own power limit at 5 W, as in test_a_torque_shortfall_names_the_limit_that_caps_the_field:
    # the deterministic optimum robust_optimum also solves reuses that test's compiled NLPs
    robust = [
        "optimize.objective=margin_p05",
        "tissue.uncertainty.scale_sigma_log=0.3",
        "limits.x.power_W=5",
        # 128 scenarios, not the default 1024: what is printed of an infeasible robust
        # optimum does not depend on their number; the NLP of a working set of 16 compiles
        # in less time than the default's 80
        "optimize.scenarios=128",
    ]
    assert main(["optimize", *(a for s in robust for a in ("--set", s))]) == 3
    out = capsys.readouterr().out
    assert "nan" not in out.lower(), out
    assert "no feasible optimum to check" in out, "the scenario check says it did not run"
    assert "limits.x.power_W" in out, "the channel that caps the field is named"
