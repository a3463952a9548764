"""Per-pair amplifier channels and the room envelope.

A lab drives each pair from its own amplifier (e.g. three of 1.5 kW and 70 V) and must fit the
coil set in a room. ``limits.{x,y,z}.current_A``, ``voltage_V``, ``power_W`` bound each pair on
its own (the global keys stay the default), ``limits.envelope_mm`` the set's outer box as
solids. Independent references: the CAD solids' bounding box (build123d/OpenCASCADE) for the
envelope, a hand inversion of R I² / 2 for the channel power cap.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from cli_outcome import NO_TOLERANCE_SETS, run, run_json

from coils.clearance import outer_box_m
from optimize import evaluate, optimize_design
from optimize.system import prepare
from spiralcap.assemble import build_model
from spiralcap.design import load_design


def _check(ev: dict, name: str) -> dict:
    return next(c for c in ev["checks"] if c["name"] == name)


def test_channel_voltage_bounds_its_pair():
    base = run_json(["evaluate"])
    ev = run_json(["evaluate", "--set", "limits.y.voltage_V=40"])
    check = _check(ev, "axis_voltage_y")
    assert check["key"] == "limits.y.voltage_V" and check["allowed"] == 40.0
    assert check["value"] <= 40.0 * (1 + 1e-9), "the y pair's drive voltage at most 40 V"
    assert ev["field_amplitude_T"] < base["field_amplitude_T"], "a lower field than without"
    assert not any(c["name"] == "voltage_y" for c in ev["checks"]), "the global row gives way"
    assert _check(ev, "voltage_x")["key"] == "limits.voltage_V", "other pairs keep the global"


def test_channel_voltage_binds_in_the_optimiser():
    # one IPOPT start (default 4): the channel row binds whichever start wins
    res = run_json(["optimize", "--set", "limits.y.voltage_V=40", "--set", "optimize.starts=1"])
    keys = {b["key"] for b in res["binding_limits"]}
    assert "limits.y.voltage_V" in keys, keys


def test_channel_power_cap_by_hand():
    """With a fixed copper temperature the pair's loss is R_T I² / 2, I = B0 I_per_T: the field
    the channel allows is sqrt(2 P / R_T) / I_per_T (hand inversion, 1e-9)."""
    sets = ["coils.winding_temperature_C=60", "limits.x.power_W=50", "limits.power_W=1e5"]
    sets += ["limits.voltage_V=1e4", "limits.current_A=1e3", "limits.coil_temperature_C=250"]
    sets += ["limits.field_exposure=off"]
    model = prepare(build_model(load_design(None, sets)))
    c = model.constants
    r_t = float(c.resistance_20C_ohm[0]) * (1 + 0.00393 * (60 - 20))
    field = math.sqrt(2 * 50 / r_t) / float(c.current_per_tesla_A_per_T[0])
    ev = evaluate(model)
    assert ev.field_limited_by == "axis_power_x"
    assert ev.field_amplitude_T == pytest.approx(field, rel=1e-9), "sqrt(2P/R)/I_per_T, by hand"
    check = next(ch for ch in ev.checks if ch.name == "axis_power_x")
    assert check.value == pytest.approx(50.0, rel=1e-9) and check.ok


def test_bill_of_materials_names_the_channel():
    out = run_json(["coils", "--set", "limits.y.voltage_V=40", "--set", "limits.y.power_W=1500"])
    rows = {r["axis"]: r for r in out["bill_of_materials"]}
    assert rows["y"]["channel_voltage_V"] == 40.0 and rows["y"]["channel_power_W"] == 1500.0
    assert rows["y"]["channel_limits"] == "own channel" and rows["x"]["channel_limits"] == "global"


def test_envelope_box_against_the_cad_solids():
    """The set's outer box against the bounding box of the STEP solids (OpenCASCADE), 1e-6 m."""
    pytest.importorskip("build123d")
    from spiralcap.cad import cad_bodies, compound

    model = build_model(load_design())
    box = compound(cad_bodies(model.coils.pairs)).bounding_box()
    size_mm = np.array([box.size.X, box.size.Y, box.size.Z])
    assert np.allclose(outer_box_m(model.coils.pairs) * 1e3, size_mm, atol=1e-3), (
        "outer box of the packs = the CAD model's bounding box (1 um)"
    )


def test_envelope_too_small_is_infeasible():
    ev = run_json(["evaluate", "--set", "limits.envelope_mm=[800,800,800]"])
    failed = [c for c in ev["checks"] if not c["ok"]]
    assert ev["feasible"] is False
    assert {c["key"] for c in failed} == {"limits.envelope_mm"}, failed
    assert {c["name"] for c in failed} == {"envelope_y", "envelope_z"}


def test_envelope_binds_a_sizing():
    sets = ["optimize.objective=power", "requirements.min_safety_factor=2"]
    sets += ["limits.envelope_mm=[2000,910,910]", *NO_TOLERANCE_SETS]  # nominal rows
    sets += ["optimize.starts=1"]  # one IPOPT start: the envelope binds the hardware
    free = [
        "optimize.free.coils.x.turns=[100,800]",
        "optimize.free.coils.x.wire_diameter_mm=[0.8,3]",
    ]
    model = build_model(load_design(None, sets + free))
    res = optimize_design(model)
    assert res.status == "optimal"
    assert any(b.name.startswith("envelope_") for b in res.binding_limits), res.binding_limits
    box = outer_box_m(model.coils.pairs)  # the entered set for reference
    assert box[1] > 0.91, "the entered coils do not fit: the sizing had to shrink the x pack"
    assert res.evaluation.feasible, "the sized design fits the envelope"


@pytest.mark.parametrize(
    "arg",
    [
        "limits.envelope_mm=[800,800]",
        "limits.envelope_mm=[800,800,0]",
        "limits.y.voltage_V=0",
        "limits.z.power_W=-1",
    ],
)
def test_bad_input(arg):
    rc, out, err = run(["evaluate", "--set", arg])
    assert rc == 2 and out == "" and len(err.strip().splitlines()) == 1
    assert arg.split("=")[0] in err
