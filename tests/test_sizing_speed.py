"""Sizing's shortcuts give the answers of the long way (issue 19: six free keys fast).

- the neighbours' buildability decided by a proven clearance bound first is the answer of every
  exact check (``build_checks``), on designs that pass by the bound, need the exact distance,
  and fail;
- the frozen factors' settling rule ends the outer loop before ``_OUTER_MAX`` rounds and the
  sized design is the one the strict rule (every round run) finds.
"""

from dataclasses import replace

import pytest

from optimize import discrete, optimize_design, prepare
from optimize import hardware as hw
from optimize.buildcheck import build_checks, buildable_ok
from spiralcap.assemble import build_model
from spiralcap.design import load_design

SIX = tuple(
    hw.FreeVariable(f"{ax}.{q}", lo, hi)
    for ax in hw.AXES
    for q, lo, hi in (("turns", 100, 800), ("wire_diameter_m", 0.8e-3, 3e-3))
)


@pytest.fixture(scope="module")
def model():
    sets = ["optimize.objective=power", "requirements.min_safety_factor=2"]
    return prepare(build_model(load_design(None, sets)))


def test_bound_first_buildability_equals_every_exact_check(model):
    base = hw.hardware_of(model)
    verdicts, exact_needed = [], 0
    for turns in (150, 400, 600, 800):
        for wire in (0.8e-3, 1.6e-3, 2.5e-3, 3.0e-3):
            values = {**base, **{f"{ax}.turns": turns for ax in hw.AXES}}
            values.update({f"{ax}.wire_diameter_m": wire for ax in hw.AXES})
            m = hw.with_hardware(model, values)
            want = all(c.ok for c in build_checks(m))
            assert buildable_ok(m) == want, (
                f"{turns} turns of {wire * 1e3} mm wire: the bound-first answer is every exact "
                "check's (optimize.buildcheck.build_checks)"
            )
            verdicts.append(want)
            exact_needed += any(
                c.name.startswith("clearance") and abs(c.value - c.allowed) < 5e-3
                for c in build_checks(m)
            )
    assert any(verdicts) and not all(verdicts), "the designs tried both pass and fail"
    assert exact_needed, "some clearances lie within 5 mm of the requirement (bound not decisive)"


def test_settled_sizing_is_the_strict_rules_design(model, monkeypatch):
    sized = replace(model, sizing=hw.Sizing(SIX))
    fast = optimize_design(sized)
    monkeypatch.setattr(discrete, "_OUTER_RTOL", 1e-9)
    monkeypatch.setattr(discrete, "_DELTA_ATOL_m", 0.0)  # the rule before: never settled
    strict = optimize_design(sized)
    assert strict.hardware.outer_iterations == discrete._OUTER_MAX
    assert fast.hardware.outer_iterations < discrete._OUTER_MAX, "settled early"
    assert fast.hardware.discrete == strict.hardware.discrete, "the same sized design"
    assert fast.objective_value == pytest.approx(strict.objective_value, rel=1e-9), (
        "the same discrete optimum (its operating point solved from a relaxation 1e-7 apart)"
    )
    for k, v in strict.hardware.relaxed.items():
        assert fast.hardware.relaxed[k] == pytest.approx(v, rel=1e-6), (
            f"continuous bound {k}: within the relaxation's own round-to-round movement"
        )
