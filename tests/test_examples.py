"""The ``Examples`` sections of the public API run as doctests (issue 38 item 6).

Every docstring example in :data:`MODULES` is found by :class:`doctest.DocTestFinder` and run
here, one test each, with its output compared to what the docstring shows (numbers printed
to the digits that matter, each checked in the example against an independent value where
one exists: a textbook formula, Neumann's integral, magpylib). The built-in design's model is
prepared once by a fixture, as a session would have it; only :data:`SLOW` solve with IPOPT.
Their speed is not asserted here (measured, not tested: issue 38 asks < 0.2 s of CPU each).
"""

from __future__ import annotations

import doctest
import importlib

import pytest

MODULES = (
    "coils.loop",
    "coils.pair",
    "coils.square_pair",
    "coils.square",
    "coils.rectangle",
    "coils.rectangle_pair",
    "coils.system",
    "coils.electrical",
    "coils.uniformity",
    "coils.rotating",
    "coils.sizing",
    "capsule.spiral",
    "capsule.torque",
    "capsule.propulsion",
    "capsule.magnet",
    "capsule.mass",
    "capsule.model",
    "torque_model.presets",
    "torque_model.model",
    "torque_model.geometry",
    "optimize.system",
    "optimize.evaluate",
    "optimize.physics",
    "optimize.optimum",
    "spiralcap.export",
)
#: Examples that solve an NLP with IPOPT (at most two, issue 38).
SLOW = {"optimize.optimum.optimize_design"}
#: The fewest examples the four domain packages and spiralcap.export must show.
MIN_EXAMPLES = 30

_FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def _collect() -> dict[str, doctest.DocTest]:
    finder = doctest.DocTestFinder(exclude_empty=True)
    found = {}
    for name in MODULES:
        for test in finder.find(importlib.import_module(name)):
            if test.examples:
                found[test.name] = test
    return found


TESTS = _collect()


def test_enough_examples() -> None:
    assert len(TESTS) >= MIN_EXAMPLES, (
        f"{len(TESTS)} docstrings with examples in {len(MODULES)} modules, issue 38 asks for "
        f">= {MIN_EXAMPLES}"
    )
    assert len(SLOW) <= 2 and SLOW <= set(TESTS), "at most two IPOPT examples, each listed"


@pytest.fixture(scope="module")
def warm() -> None:
    """The built-in design prepared and evaluated once (its compiled thermal states are
    per-process caches), so each example's time is its own."""
    from optimize import evaluate, prepare
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    evaluate(prepare(build_model(load_design(None, []))), frequency_bounds=False)


@pytest.mark.parametrize("name", sorted(TESTS))
def test_example(name: str, warm: None) -> None:
    test = TESTS[name]
    test.globs = dict(test.globs)  # each run on a fresh copy of the module's namespace
    runner = doctest.DocTestRunner(optionflags=_FLAGS)
    out: list[str] = []
    result = runner.run(test, out=out.append, clear_globs=False)
    assert result.failed == 0, f"{name}: the docstring's example output differs:\n{''.join(out)}"
