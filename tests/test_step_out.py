"""Step-out named right: the capsule's step-out at the operating field vs the drive's limit."""

import json
import math

import pytest

from optimize import evaluate, prepare, step_out_frequency_hz
from spiralcap.assemble import build_model
from spiralcap.cli import main
from spiralcap.design import load_design


def _model(*overrides):
    return prepare(build_model(load_design(None, overrides)))


def test_fixed_field_at_step_out_gives_zero_margin():
    ev = evaluate(_model())
    f = ev.step_out_frequency_hz
    assert 0 < f < 200 and not ev.step_out_beyond_search
    fixed = evaluate(
        _model(
            f"operation.field_amplitude_mT={ev.field_amplitude_T * 1e3!r}",
            f"operation.frequency_hz={f!r}",
        )
    )
    assert fixed.field_limited_by == "fixed"
    assert fixed.field_amplitude_T == pytest.approx(ev.field_amplitude_T, rel=1e-15)
    assert abs(fixed.margin_Nm) <= 1e-6 * fixed.required_torque_Nm, (
        "issue 10: evaluate at step_out_frequency_hz with the field fixed has margin 0 "
        "(to 1e-6 of the load)"
    )
    assert fixed.step_out_frequency_hz == pytest.approx(f, rel=1e-9), (
        "the step-out depends on the field only, not on the frequency evaluated at (1e-9)"
    )


def test_step_out_beyond_the_search_range_is_flagged(capsys):
    m = _model()
    strong = step_out_frequency_hz(m, m.capsule.spiral.helical_angle_rad, field_T=10.0)
    assert strong.beyond_search and strong.frequency_hz == 200.0, (
        "a 10 T field holds the capsule beyond 200 Hz: the bound, flagged"
    )
    assert main(["evaluate", "--json", "--set", "operation.field_amplitude_mT=900"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["step_out_beyond_search"] is True
    for key in ("step_out_frequency_hz", "max_frequency_hz"):
        assert isinstance(out[key], float) and math.isfinite(out[key]), key
    assert isinstance(out["max_frequency_limited_by"], str)
