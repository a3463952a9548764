"""A lab's measured pair constants: coils.{x,y,z}.measured.* (issue 37).

The issue's case: coils.x.measured.resistance_ohm = 10 (at 20 °C) and inductance_H = 0.8. The
checks are hand formulas written here: IEC 60028's copper (alpha20 = 0.00393 /K) for the
temperature scaling, |Z|² = R² + (2π f L)² for the drive voltage.
"""

from __future__ import annotations

import json
import math

import pytest

from spiralcap.cli import main

ALPHA20 = 0.00393  # IEC 60028 annealed copper, per K at 20 °C
X = ["--set", "coils.x.measured.resistance_ohm=10.0", "--set", "coils.x.measured.inductance_H=0.8"]


def _json(capsys, argv):
    capsys.readouterr()
    assert main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.fixture(scope="module")
def runs():
    import contextlib
    import io

    out = {}
    for name, argv in (
        ("coils", ["coils", *X]),
        ("coils_plain", ["coils"]),
        ("evaluate", ["evaluate", *X]),
        ("evaluate_plain", ["evaluate"]),
    ):
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            assert main([*argv, "--json"]) == 0
        out[name] = json.loads(buf.getvalue())
    return out


def test_coils_uses_exactly_the_measured_constants_for_x(runs) -> None:
    x, plain = runs["coils"]["axes"]["x"], runs["coils_plain"]["axes"]["x"]
    assert x["resistance_20C_ohm"] == 10.0 and x["inductance_H"] == 0.8, "exactly the measured"
    m = x["measured"]
    assert m["computed_resistance_ohm"] == pytest.approx(plain["resistance_20C_ohm"], rel=1e-12)
    assert m["computed_inductance_H"] == pytest.approx(plain["inductance_H"], rel=1e-12)
    assert m["resistance_deviation"] == pytest.approx(10.0 / plain["resistance_20C_ohm"] - 1)
    assert m["inductance_deviation"] == pytest.approx(0.8 / plain["inductance_H"] - 1)
    r = 10.0 * (1 + ALPHA20 * (x["mean_temperature_C"] - 20.0))
    assert x["resistance_ohm"] == pytest.approx(r, rel=1e-12), "R(T) = R20 (1 + a20 (T - 20))"
    z = math.hypot(r, 2 * math.pi * runs["coils"]["frequency_hz"] * 0.8)
    assert x["impedance_ohm"] == pytest.approx(z, rel=1e-12), "|Z|² = R² + (2π f L)², 1e-12"
    warned = " ".join(runs["coils"]["warnings"])
    assert "x pair's measured resistance is 89.7 % above" in warned, warned
    assert "turn count, the wire size, series or parallel wiring" in warned


def test_y_and_z_untouched(runs) -> None:
    for ax in "yz":
        got, plain = runs["coils"]["axes"][ax], runs["coils_plain"]["axes"][ax]
        assert "measured" not in got
        for key in ("resistance_20C_ohm", "inductance_H", "self_inductance_H", "turns"):
            assert got[key] == plain[key], f"{ax}.{key} as computed"


def test_evaluate_drive_voltage_follows_the_measured_pair(runs) -> None:
    checks = {c["name"]: c for c in runs["evaluate"]["checks"]}
    plain = {c["name"]: c for c in runs["evaluate_plain"]["checks"]}
    assert checks["voltage_x"]["value"] != pytest.approx(plain["voltage_x"]["value"], rel=0.01)
    op = runs["coils"]["operating_point"]["axes"]["x"]
    assert runs["coils"]["operating_point"]["field_amplitude_T"] == pytest.approx(
        runs["evaluate"]["field_amplitude_T"], rel=1e-12
    ), "coils and evaluate at the same operating field"
    r = 10.0 * (1 + ALPHA20 * (op["mean_temperature_C"] - 20.0))
    assert op["resistance_ohm"] == pytest.approx(r, rel=1e-12)
    f = runs["evaluate"]["frequency_hz"]
    volts = math.hypot(r, 2 * math.pi * f * 0.8) * op["current_A"]
    assert checks["voltage_x"]["value"] == pytest.approx(volts, rel=1e-9), (
        "V = sqrt(R² + (2π f L)²) I at the operating point with the measured R(T) and L, 1e-9"
    )


def test_measuring_temperature_scales_to_20c(capsys) -> None:
    got = _json(
        capsys,
        [
            "coils",
            "--set",
            "coils.z.measured.resistance_ohm=7",
            "--set",
            "coils.z.measured.temperature_C=60",
        ],
    )
    z = got["axes"]["z"]
    assert z["resistance_20C_ohm"] == pytest.approx(7.0 / (1 + ALPHA20 * 40.0), rel=1e-12)
    assert z["measured"]["temperature_C"] == 60.0 and "inductance_H" not in z["measured"]


def test_waveforms_drive_the_measured_pair(capsys) -> None:
    got = _json(capsys, ["waveforms", "--heading", "0,0,1", "--dwell-s", "1", *X])
    assert got["inductance_H"]["x"] == 0.8
    assert got["resistance_ohm"]["x"] > 10.0, "10 Ω at 20 °C, warmer at the operating point"


def test_sizing_and_stray_temperature_are_refused_in_one_line(capsys) -> None:
    rc = main(["optimize", *X, "--set", "optimize.free.coils.x.turns=[300,500]"])
    err = capsys.readouterr().err
    assert rc == 2 and "coils.x.measured.resistance_ohm" in err and "sizing" in err, err
    assert len(err.strip().splitlines()) == 1
    rc = main(["evaluate", "--set", "coils.y.measured.temperature_C=30"])
    err = capsys.readouterr().err
    assert rc == 2 and "coils.y.measured.resistance_ohm" in err, err


def test_coils_json_with_measured_pairs_and_stray_field_matches_its_schema(runs) -> None:
    from pathlib import Path

    jsonschema = pytest.importorskip("jsonschema")
    path = Path(__file__).resolve().parents[1] / "docs" / "json" / "coils.schema.json"
    schema = json.loads(path.read_text())
    errors = list(jsonschema.Draft202012Validator(schema).iter_errors(runs["coils"]))
    assert not errors, [e.message for e in errors[:3]]
    assert "stray_field" in runs["coils"] and "measured" in runs["coils"]["axes"]["x"]
