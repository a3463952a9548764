"""limits.{x,y,z}.apparent_power_VA: the amplifier channel's V I / 2 as a limit row (issue 37)."""

from __future__ import annotations

import json
import math

import pytest

from spiralcap.cli import main


def _json(capsys, argv):
    capsys.readouterr()
    assert main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _checks(payload):
    return {c["name"]: c for c in payload["checks"]}


@pytest.mark.parametrize("fixed", [False, True], ids=["self-consistent R", "fixed R"])
def test_apparent_power_row_is_v_times_i_over_two_and_binds(capsys, fixed) -> None:
    extra = ["--set", "coils.winding_temperature_C=60"] if fixed else []
    free = _json(capsys, ["evaluate", *extra])
    capped = _json(capsys, ["evaluate", "--set", "limits.x.apparent_power_VA=500", *extra])
    rows = _checks(capped)
    va = rows["axis_apparent_power_x"]
    current, volts = rows["current_x"]["value"], rows["voltage_x"]["value"]
    assert va["value"] == pytest.approx(0.5 * current * volts, rel=1e-12), (
        "S = V I / 2 from the evaluate rows' own current and drive voltage, 1e-12"
    )
    assert va["value"] == pytest.approx(500.0, rel=1e-9), "the cap puts S_x on its 500 VA, 1e-9"
    assert va["key"] == "limits.x.apparent_power_VA" and va["unit"] == "VA"
    assert capped["field_amplitude_T"] < free["field_amplitude_T"], "500 VA caps the field"
    untouched = _checks(free)
    assert "axis_apparent_power_x" not in untouched, "no row without the key"
    s_free = 0.5 * untouched["current_x"]["value"] * untouched["voltage_x"]["value"]
    assert s_free > 500.0, f"the built-in x channel needs {s_free:.4g} VA > 500 VA (so it binds)"


def test_apparent_power_by_hand_from_r_l_and_the_current(capsys) -> None:
    """|Z| = sqrt(R² + (2π f L)²) from the coils output at the same field, S = |Z| I² / 2."""
    capped = _json(capsys, ["evaluate", "--set", "limits.y.apparent_power_VA=300"])
    coils = _json(
        capsys,
        ["coils", "--set", f"operation.field_amplitude_mT={capped['field_amplitude_T'] * 1e3!r}"],
    )
    r = coils["operating_point"]["axes"]["y"]["resistance_ohm"]
    ind = coils["axes"]["y"]["inductance_H"]
    z = math.hypot(r, 2 * math.pi * capped["frequency_hz"] * ind)
    i = _checks(capped)["current_y"]["value"]
    assert 0.5 * z * i * i == pytest.approx(300.0, rel=1e-6), (
        "hand |Z| I² / 2 with the coils command's R (mean winding temperature) and L, 1e-6"
    )


def test_optimize_names_the_apparent_power_limit_it_binds(capsys) -> None:
    # one IPOPT start (default 4): the channel row binds whichever start wins
    out = _json(
        capsys,
        ["optimize", "--set", "limits.x.apparent_power_VA=500", "--set", "optimize.starts=1"],
    )
    binding = {b["name"]: b for b in out["binding_limits"]}
    assert "axis_apparent_power_x" in binding, list(binding)
    assert binding["axis_apparent_power_x"]["key"] == "limits.x.apparent_power_VA"
    assert binding["axis_apparent_power_x"]["value"] == pytest.approx(500.0, rel=1e-6)


def test_apparent_power_cap_on_arrays_of_frequencies_is_each_scalar_cap() -> None:
    """The report's curves ask the cap on arrays, one-element ones too: each element is the
    scalar search's answer, and at it S_x = V I / 2 is the limit (a by-hand |Z| I² / 2)."""
    import numpy as np

    from coils.electrical import impedance_ohm
    from optimize import physics, prepare
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    model = prepare(build_model(load_design().with_values({"limits.x.apparent_power_VA": 300.0})))
    c, amb = model.constants, model.ambient_temperature_C
    freqs = np.array([0.5, 2.0, 4.0])
    caps = [physics.field_capacity_T(f, c, model.limits, amb)[0] for f in freqs]
    for shape in ((1,), (1, 1)):
        one = physics.field_capacity_T(np.full(shape, 2.0), c, model.limits, amb)[0]
        assert np.shape(one) == shape and float(one.ravel()[0]) == float(caps[1])
    many = physics.field_capacity_T(freqs, c, model.limits, amb)[0]
    np.testing.assert_array_equal(many, np.array(caps, dtype=float))
    for f, cap in zip(freqs, caps, strict=True):
        i = float(cap) * float(c.current_per_tesla_A_per_T[0])
        r = float(physics.winding_resistance_ohm(i, 0, c, amb))
        s = 0.5 * float(impedance_ohm(r, float(c.inductance_H[0]), f)) * i * i
        assert s <= 300.0 * (1 + 1e-9), f"at {f} Hz the cap keeps S_x <= 300 VA ({s})"
