"""Tissue numbers are parameters of the compiled NLP, not part of its structure (issue 38).

Another stiffness, lumen or friction reuses the compiled problem (an ``--optimize`` sweep over
a tissue key compiled at every point before), and the optimum is the one a fresh compile gives.
"""

from __future__ import annotations

import pytest

from optimize import optimize_design
from optimize.compiled import compile_problem, structure_of
from optimize.system import prepare
from spiralcap.assemble import build_model
from spiralcap.design import load_design

#: key -> two values (an override renames the set it changes, "+ tissue.{E1_kPa}", whatever
#: the value: the points of a sweep over the key share the name)
CHANGES = {
    "tissue.E1_kPa": (40.0, 55.0),
    "tissue.lumen_diameter_mm": (11.0, 11.2),
    "tissue.friction_coefficient": (0.08, 0.12),
}


@pytest.mark.parametrize(("key", "values"), CHANGES.items())
def test_a_tissue_number_reuses_the_compiled_problem(key: str, values: tuple) -> None:
    """The design at two values of ``key`` has one structure, and solving the second after
    the first compiles nothing new (the step-out searches, which do not compile, left out)."""
    first, second = (build_model(load_design().with_values({key: v})) for v in values)
    assert structure_of(prepare(second)) == structure_of(prepare(first)), (
        f"{key}: the same structure (tissue numbers are parameters)"
    )
    optimize_design(first, frequency_bounds=False)
    misses = compile_problem.cache_info().misses
    assert optimize_design(second, frequency_bounds=False).status == "optimal", key
    assert compile_problem.cache_info().misses == misses, f"{key}: no new compile"


def test_the_reused_problem_gives_a_fresh_compiles_optimum(monkeypatch) -> None:
    """The optimum at E1 = 55 kPa from the problem compiled at 40 kPa equals the one from a
    problem compiled anew (the cache bypassed, not cleared: other tests keep theirs), to 1e-12
    (the numbers enter as parameter values either way)."""
    import optimize.solve

    first, second = (
        build_model(load_design().with_values({"tissue.E1_kPa": v})) for v in (40.0, 55.0)
    )
    optimize_design(first, frequency_bounds=False)
    reused = optimize_design(second, frequency_bounds=False)
    monkeypatch.setattr(optimize.solve, "compile_problem", compile_problem.__wrapped__)
    fresh = optimize_design(second, frequency_bounds=False)
    assert reused.status == fresh.status == "optimal"
    assert reused.objective_value == pytest.approx(fresh.objective_value, rel=1e-12, abs=0.0), (
        "the reused problem's optimum is a fresh compile's (1e-12)"
    )
    assert reused.helical_angle_rad == pytest.approx(fresh.helical_angle_rad, rel=1e-12), (
        "the same optimum angle (1e-12)"
    )


def test_tissue_names_still_name_the_rows() -> None:
    """The sets' names stay in the structure: the rows are named by them."""
    base = prepare(build_model(load_design()))
    names = tuple(t.name for t in base.tissues)
    assert tuple(n for n, _ in structure_of(base).tissues) == names, "the structure holds the names"
    rows = {r.name for r in compile_problem(structure_of(base)).nlp.rows}
    for name in names:
        assert f"wall_strain[{name}]" in rows, f"a wall-strain row named for {name}"


@pytest.mark.parametrize("modulus", ["E1_kPa", "E3_kPa"])
def test_every_zero_modulus_is_structure(modulus: str) -> None:
    """Each modulus at zero is compiled in (a structure of its own), as E2 below."""
    zero = prepare(build_model(load_design().with_values({f"tissue.{modulus}": 0.0})))
    tiny = prepare(build_model(load_design().with_values({f"tissue.{modulus}": 1e-9})))
    assert structure_of(zero) != structure_of(tiny), f"{modulus} = 0 is structure"


def test_a_zero_modulus_is_compiled_in_and_optimises() -> None:
    """E = 0 (no spring in that arm, allowed by TissueParameters) is part of the structure,
    compiled in as the constant 0: as a parameter value it left 0/0 in the Hessian and the
    built-in design with tissue.E2_kPa = 0 came out infeasible (exit 3) where it is optimal. The
    optimum is the one with the modulus just above zero, to 1e-6 (the model is continuous in E
    at 0; 1e-9 kPa)."""
    modulus = "E2_kPa"
    zero = build_model(load_design().with_values({f"tissue.{modulus}": 0.0}))
    tiny = build_model(load_design().with_values({f"tissue.{modulus}": 1e-9}))
    assert structure_of(prepare(zero)) != structure_of(prepare(tiny)), "zero is structure"
    at_zero, near = (optimize_design(m, frequency_bounds=False) for m in (zero, tiny))
    assert at_zero.status == near.status == "optimal", f"{modulus} = 0 optimises"
    assert at_zero.objective_value == pytest.approx(near.objective_value, rel=1e-6), (
        f"{modulus} = 0 is the limit of E -> 0 (1e-6)"
    )


def test_a_zero_modulus_in_robust_scenarios_optimises(capsys) -> None:
    """The robust problem's scenario moduli zero in every scenario are compiled in as 0 too
    (``ScenarioStructure.zero_moduli``): ``spiralcap optimize`` with margin_p05 at
    tissue.E2_kPa = 0 had NaN in the Hessian and came out infeasible (exit 3; before the tissue
    numbers became parameters too). Its CVaR05 is the one just above zero, to 1e-6 (1e-9 kPa;
    32 scenarios)."""
    import json

    from spiralcap.cli import main

    robust = [
        "--set",
        "optimize.objective=margin_p05",
        "--set",
        "tissue.uncertainty.scale_sigma_log=0.3",
        "--set",
        "optimize.scenarios=32",
    ]
    out = []
    for e in (0.0, 1e-9):
        status = main(["optimize", *robust, "--set", f"tissue.E2_kPa={e}", "--json"])
        assert status == 0, f"margin_p05 with E2 = {e} kPa optimises (exit 0)"
        out.append(json.loads(capsys.readouterr().out))
    assert out[0]["objective_value"] == pytest.approx(out[1]["objective_value"], rel=1e-6), (
        "E2 = 0 is the limit of E2 -> 0 in the scenarios too (1e-6)"
    )
