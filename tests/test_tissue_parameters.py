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
    assert structure_of(base).tissues == names, "the structure holds the names"
    rows = {r.name for r in compile_problem(structure_of(base)).nlp.rows}
    for name in names:
        assert f"wall_strain[{name}]" in rows, f"a wall-strain row named for {name}"
