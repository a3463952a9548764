"""The compiled parametric NLP: named rows and multipliers, objectives power and copper_mass,
the saved optimum as a design file, warm-started sweeps, and the extension hook."""

import json
import math
from dataclasses import replace

import numpy as np
import pytest
from _te_memo import optimum as solved_optimum
from _te_memo import solved_once  # noqa: F401 (the fixture)

from optimize import MarginGrid, evaluate, margin_grid, optimize_design, prepare, worst_required
from optimize import problem as pb
from optimize.physics import total_loss_W
from optimize.solve import compile_problem, structure_of
from optimize.system import Tolerances
from spiralcap.assemble import build_model
from spiralcap.cli import main
from spiralcap.design import load_design
from spiralcap.sweep import parse_over, sweep


@pytest.fixture(scope="module")
def model():
    return prepare(build_model(load_design()))


@pytest.fixture(scope="module")
def power_result(model):
    m = replace(
        model,
        bounds=replace(model.bounds, objective="power"),
        requirements=replace(model.requirements, min_safety_factor=2.0),
    )
    return m, solved_optimum(m)  # the same as `optimize` of these keys (tests/_te_memo.py)


@pytest.fixture(scope="module")
def optimum(model):
    """The built-in design's margin optimum, solved once for the tests that read it (and
    the `spiralcap optimize` run below: tests/_te_memo.py)."""
    return solved_optimum(model)


def test_rows_are_named_and_one_per_tissue(model):
    nlp = compile_problem(structure_of(model)).nlp
    names = nlp.row_names
    tissues = [t.name for t in model.tissues]
    for t in tissues:
        for stem in ("margin", "safety_factor", "self_lock"):
            assert f"{stem}[{t}]" in names, f"row {stem}[{t}] exists (one per tissue set)"
    for ax in "xyz":
        assert f"current_{ax}" in names and f"voltage_{ax}" in names
    assert not any("limits." in n or "requirements." in n for n in names), (
        "the optimiser names its rows, not design keys (issue 13 item 4)"
    )


def test_self_lock_rows_hold_at_the_optimum(model, optimum):
    res = optimum
    import capsule as cap

    for t in model.tissues:
        lock = float(cap.self_lock_margin_rad(res.helical_angle_rad, t.friction_coefficient))
        assert lock >= pb.SELF_LOCK_MIN_MARGIN_rad, (
            "pi/2 - alpha - atan(mu) >= 1 deg at the optimum (Shigley power screw)"
        )


def test_self_lock_row_binds_when_it_is_the_tightest(model):
    """A friction of 2 allows alpha <= 90 - 1 - atan(2) = 25.57 deg; with the angle box opened
    to 80 deg and the speed requirement raised, the optimiser is pushed to large angles and must
    stop at the self-lock row (capsule.self_lock_margin_rad)."""
    tis = tuple(replace(t, friction_coefficient=2.0) for t in model.tissues)
    m = replace(
        model,
        constants=None,
        tissues=tis,
        requirements=replace(model.requirements, axial_load_N=0.0, min_speed_m_s=0.0),
        bounds=replace(model.bounds, helical_angle_max_rad=math.radians(80), objective="ratio"),
        tolerances=Tolerances(),  # the row at the design's own angle (no box)
    )
    nlp = compile_problem(structure_of(prepare(m))).nlp
    from optimize.solve import scales_for

    mm = prepare(m)
    p = compile_problem(structure_of(mm)).parameters(mm, scales_for(mm))
    x = nlp.scaled_start(
        {"helical_angle_rad": math.radians(30.0), "frequency_hz": 1.0, "field_scaled": 1.0}, p
    )
    _, g = nlp.evaluate(x, p)
    row = nlp.row_names.index(f"self_lock[{tis[0].name}]")
    expected = math.radians(1.0) - (math.pi / 2 - math.radians(30.0) - math.atan(2.0))
    assert math.isclose(g[row], expected, rel_tol=1e-12), "self-lock row = 1 deg - margin"


def test_power_objective_meets_the_safety_factor_with_least_field(model, power_result):
    m, res = power_result
    assert res.status == "optimal"
    assert res.safety_factor >= 2.0 * (1 - 1e-9), "requirements.min_safety_factor = 2 met"
    amb = m.ambient_temperature_C
    power = float(total_loss_W(res.field_amplitude_T, m.constants, amb))
    assert math.isclose(res.objective_value, power, rel_tol=1e-12), (
        "objective = worst-heading loss at the pairs' own mean winding temperatures"
    )
    as_entered = evaluate(model)
    entered_power = float(total_loss_W(as_entered.field_amplitude_T, m.constants, amb))
    assert power < entered_power, "less copper power than the as-entered design"
    less = evaluate(
        m, res.helical_angle_rad, res.frequency_hz, field_amplitude_T=0.99 * res.field_amplitude_T
    )
    assert less.safety_factor < 2.0, "1 % less field no longer meets the safety factor"


def test_power_sensitivity_to_the_safety_factor_is_analytic(power_result):
    """At fixed angle and frequency the field needed scales with the safety factor, so
    d P / d SF = P'(B0) B0 / SF (envelope theorem). P is no longer quadratic in B0 (the
    resistance rises with the winding temperature), so P' is a central difference of the same
    loss function (step 1e-5 B0; agreement 1e-6)."""
    m, res = power_result
    b = next(b for b in res.binding_limits if b.name.startswith("safety_factor["))
    b0, h = res.field_amplitude_T, 1e-5
    c, amb = m.constants, m.ambient_temperature_C
    dp = (float(total_loss_W(b0 * (1 + h), c, amb)) - float(total_loss_W(b0 * (1 - h), c, amb))) / (
        2 * h
    )  # = P'(B0) B0
    assert math.isclose(b.sensitivity, dp / 2.0, rel_tol=1e-6), (
        "multiplier of the safety-factor row = P'(B0) B0 / SF (envelope theorem)"
    )


def test_copper_mass_objective_with_fixed_copper_takes_least_power(model, power_result):
    m = replace(
        model,
        bounds=replace(model.bounds, objective="copper_mass"),
        requirements=replace(model.requirements, min_safety_factor=2.0),
    )
    res = optimize_design(m)
    assert res.status == "optimal"
    assert math.isclose(res.objective_value, float(np.sum(m.constants.copper_mass_kg)))
    assert math.isclose(res.safety_factor, 2.0, rel_tol=1e-5), "the tie-break takes least field"


@pytest.mark.usefixtures("solved_once")
def test_optimize_output_reproduced_by_evaluate(tmp_path, capsys):
    out = tmp_path / "best.toml"
    assert main(["optimize", "--json", "-o", str(out)]) == 0
    opt = json.loads(capsys.readouterr().out)
    text = out.read_text()
    assert text.startswith("# spiralcap design file") and "# turns of each coil" in text
    assert main(["evaluate", "--json", str(out)]) == 0
    ev = json.loads(capsys.readouterr().out)
    for k in ("margin_Nm", "helical_angle_deg", "frequency_hz"):
        assert math.isclose(ev[k], opt[k], rel_tol=1e-6), f"evaluate best.toml: same {k}, 1e-6"
    limits = [b["name"] for b in opt["binding_limits"] if b["key"].startswith("limits.")]
    assert limits == [ev["field_limited_by"]] == ["hot_spot_y"], (
        "the optimiser's binding limit is the one evaluate says sets the field (the hot spot)"
    )
    # 1.786 mN·m: natural convection by correlation, packs radiating to each other, the Robin
    # hot spot, buildable coils, the friction of the capsule's weight, the wall-strain row at its
    # default 1.68 % and the default tolerance box (1.768 at 1.7 %; 2.323 without the box; 2.481
    # before the weight and the grip; 3.027 with h = 10, packs alone)
    assert math.isclose(opt["margin_Nm"] * 1e3, 1.786, rel_tol=1e-3), "built-in optimum 1.786 mN·m"


@pytest.mark.usefixtures("solved_once")
def test_power_optimum_saved_with_its_field(tmp_path, capsys):
    out = tmp_path / "p.toml"
    args = ["--set", "optimize.objective=power", "--set", "requirements.min_safety_factor=2"]
    assert main(["optimize", "--json", "-o", str(out), *args]) == 0
    opt = json.loads(capsys.readouterr().out)
    assert "field_amplitude_mT = " in out.read_text()
    assert main(["evaluate", "--json", str(out)]) == 0
    ev = json.loads(capsys.readouterr().out)
    assert ev["feasible"] and math.isclose(ev["safety_factor"], 2.0, rel_tol=1e-6)
    assert math.isclose(ev["margin_Nm"], opt["margin_Nm"], rel_tol=1e-6)


def test_infeasible_writes_nothing(tmp_path, capsys):
    out = tmp_path / "no.toml"
    assert main(["optimize", "-o", str(out), "--set", "limits.power_W=1"]) == 3
    assert not out.exists(), "nothing written for an infeasible design"
    capsys.readouterr()


def test_sweep_optimize_warm_starts_match_cold_solves():
    d = load_design()
    res = sweep(d, [parse_over("limits.current_A=6:20:8")], optimize=True)
    for i in (0, 3, 7):
        v = float(res.inputs["limits.current_A"][i])
        cold = optimize_design(build_model(d.with_values({"limits.current_A": v})))
        assert math.isclose(res.outputs["margin_Nm"][i], cold.margin_Nm, rel_tol=1e-7), (
            "warm-started sweep point equals an independent multi-start solve (1e-7)"
        )


def test_registered_constraint_is_part_of_every_problem(model):
    """The hook: a builder adding a cap on the field binds and is reported by name."""

    def cap_field(ctx):
        return [
            pb.Term(pb.Row("field_cap", "limit", "T"), ctx.field_T, 10e-3, lambda v, a: v / a - 1.0)
        ]

    pb.register_constraint(cap_field)
    try:
        res = optimize_design(model)
    finally:
        pb.CONSTRAINTS.remove(cap_field)
    assert res.status == "optimal" and math.isclose(res.field_amplitude_T, 10e-3, rel_tol=1e-7)
    cap = next(b for b in res.binding_limits if b.name == "field_cap")
    m = model.constants.moment_Am2 * model.constants.workspace_factor
    assert math.isclose(cap.sensitivity, m, rel_tol=1e-6), (
        "d margin / d field cap = m κ (the margin is linear in B0 at fixed angle, frequency)"
    )
    assert optimize_design(model).field_amplitude_T > 10e-3, "removed again: the cap is gone"


def test_margin_grid_and_worst_required_are_typed(model):
    g = margin_grid(model, np.radians([10.0, 20.0]), 1.0)
    assert isinstance(g, MarginGrid) and g.margin_Nm.shape == (2,)
    w = worst_required(model, np.radians(20.0), 1.0)
    assert math.isclose(float(w.total_Nm), float(w.resistive_Nm + w.thrust_Nm), rel_tol=1e-12)


def test_evaluate_honours_a_set_field(capsys):
    assert main(["evaluate", "--json", "--set", "operation.field_amplitude_mT=3"]) == 0
    ev = json.loads(capsys.readouterr().out)
    assert math.isclose(ev["field_amplitude_T"], 3e-3, rel_tol=1e-12)
    m = prepare(build_model(load_design()))
    c = m.constants
    need = ev["required_torque_Nm"]
    assert math.isclose(
        ev["margin_Nm"], c.moment_Am2 * c.workspace_factor * 3e-3 - need, rel_tol=1e-12
    ), "margin = m κ B0 - τ at the set field (docs/optimisation.md)"
    assert main(["evaluate", "--json", "--set", "operation.field_amplitude_mT=60"]) == 0
    ev = json.loads(capsys.readouterr().out)
    assert ev["feasible"] is False
    assert any(c["name"].startswith("current_") and not c["ok"] for c in ev["checks"]), (
        "60 mT needs more than the current limit allows"
    )


def test_margin_optimum_ignores_a_set_field(model, optimum):
    """The field is a decision variable: a design carrying a set field (e.g. a saved power
    optimum) re-optimised for the margin reaches the same optimum (1e-9)."""
    free = optimum
    fixed = optimize_design(replace(model, field_amplitude_T=3e-3))
    assert math.isclose(fixed.margin_Nm, free.margin_Nm, rel_tol=1e-9)
    assert math.isclose(fixed.field_amplitude_T, free.field_amplitude_T, rel_tol=1e-9)


@pytest.mark.parametrize(
    "sets",
    [[], ["operation.session_min=20"], ["coils.winding_temperature_C=60"]],
    ids=["steady", "session", "fixed-copper-temperature"],
)
def test_compiled_rows_with_parameter_constants_equal_the_numeric_rows(sets):
    """The compiled NLP builds Constants (thermal packs included) from named parameters; its
    rows at a point equal the rows with the numeric Constants of the design (1e-10): the hot
    spot, the self-consistent resistance and the loss are the same expressions."""
    from optimize.solve import scales_for

    m = prepare(build_model(load_design(None, sets)))
    scales = scales_for(m)
    problem = compile_problem(structure_of(m))
    names = problem.nlp.row_names
    for point in ((0.3, 1.2, 0.8), (0.6, 3.0, 1.1)):
        x = {
            "helical_angle_rad": point[0],
            "frequency_hz": point[1],
            "field_scaled": point[2],
            "t": 0.1,
        }
        p = problem.parameters(m, scales)
        _, g = problem.nlp.evaluate(problem.nlp.scaled_start(x, p), p)
        scaled = (point[0] / pb.ALPHA_REF_rad, point[1] / pb.F_REF_hz, point[2], 0.1)
        _, g_np, rows = pb.expressions(scaled, m, scales)
        by_name = dict(zip(names, np.asarray(g).ravel()))
        for row, value in zip(rows, g_np):
            assert math.isclose(by_name[row.name], float(value), rel_tol=1e-10, abs_tol=1e-12), (
                f"{row.name}: parameter Constants and numeric Constants agree (1e-10)"
            )


def test_warm_solver_shares_the_graph_and_solves_as_a_fresh_one(model):
    """The warm-start problem reuses the cold problem's expressions and derivative functions
    (one graph per structure); its solves equal those of a warm solver compiled from scratch bit
    for bit (same functions, same IPOPT options)."""
    from optimize.compiled import _WARM_OPTIONS, _build
    from optimize.solve import initial_points, scales_for, variable_bounds

    cold = compile_problem(structure_of(model))
    warm = compile_problem(structure_of(model, warm=True))
    assert warm.nlp.dldp is cold.nlp.dldp and warm.nlp.rows == cold.nlp.rows, "one graph"
    assert warm.nlp.solver is not cold.nlp.solver, "its own IPOPT options"
    fresh = _build(structure_of(model, warm=True)).compile(_WARM_OPTIONS)
    scales = scales_for(model)
    p = cold.parameters(model, scales)
    start = cold.nlp.solve(initial_points(model, scales, 1)[0], p, variable_bounds(model))
    shifted = p * (1 + 1e-3)  # a neighbouring problem, warm-started from the optimum
    a = warm.nlp.solve(start.x_scaled, shifted, variable_bounds(model), lam_g0=start.lam_g)
    b = fresh.solve(start.x_scaled, shifted, variable_bounds(model), lam_g0=start.lam_g)
    assert a.success and a.iterations == b.iterations, "same iterations"
    assert np.array_equal(a.x_scaled, b.x_scaled) and np.array_equal(a.lam_g, b.lam_g), (
        "shared-graph warm solver == warm solver compiled from scratch, bit for bit"
    )
