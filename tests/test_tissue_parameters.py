"""Tissue numbers are parameters of the compiled NLP, not part of its structure (issue 38).

Another stiffness, lumen or friction reuses the compiled problem (an ``--optimize`` sweep over
a tissue key compiled at every point before), and the optimum is the one a fresh compile gives.
"""

from __future__ import annotations

from dataclasses import replace

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
    """The design at two values of ``key`` has one structure; solving the second after the
    first compiles nothing new, and its optimum equals the one from a cache cleared first (a
    fresh compile), to 1e-12 (the numbers enter as parameter values either way)."""
    base, other = (build_model(load_design().with_values({key: v})) for v in values)
    assert structure_of(prepare(other)) == structure_of(prepare(base)), (
        f"{key}: the same structure (tissue numbers are parameters)"
    )
    optimize_design(base)
    misses = compile_problem.cache_info().misses
    reused = optimize_design(other)
    assert compile_problem.cache_info().misses == misses, f"{key}: no new compile"
    compile_problem.cache_clear()
    fresh = optimize_design(other)
    assert reused.status == fresh.status
    assert reused.objective_value == pytest.approx(fresh.objective_value, rel=1e-12, abs=0.0), (
        f"{key}: the reused problem's optimum is a fresh compile's (1e-12)"
    )
    assert replace(reused, solve_time_s=0.0).helical_angle_rad == pytest.approx(
        fresh.helical_angle_rad, rel=1e-12
    ), f"{key}: the same optimum angle (1e-12)"


def test_tissue_names_still_name_the_rows() -> None:
    """The sets' names stay in the structure: the rows are named by them."""
    base = prepare(build_model(load_design()))
    names = tuple(t.name for t in base.tissues)
    assert structure_of(base).tissues == names, "the structure holds the names"
    rows = {r.name for r in compile_problem(structure_of(base)).nlp.rows}
    for name in names:
        assert f"wall_strain[{name}]" in rows, f"a wall-strain row named for {name}"
