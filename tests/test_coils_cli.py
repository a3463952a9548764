"""Design -> coils (spiralcap.assemble.coils) and the ``spiralcap coils`` command."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

import spiralcap
from spiralcap.core.constants import MU0_T_m_per_A
from spiralcap.core.errors import InputError
from spiralcap.design import load_design

_PKG = Path(spiralcap.__file__).parent


def test_default_design_builds_in_si(build_coils) -> None:
    system = build_coils(load_design())
    assert [p.axis for p in system.pairs] == ["x", "y", "z"]
    assert system.x.wire_diameter_m == pytest.approx(3.0e-3, rel=1e-15), "3.0 mm -> m"
    assert system.z.separation_m == system.z.radius_m == 0.28, "separation defaults to radius"
    assert system.y.centre_field_per_amp_T_per_A == pytest.approx(
        (4 / 5) ** 1.5 * MU0_T_m_per_A * 350 / 0.35, rel=1e-12
    ), "(4/5)^1.5 mu0 N/R, 1e-12"
    other = build_coils(load_design(None, ["coils.z.separation_m=0.25"]))
    assert other.z.separation_m == 0.25


@pytest.mark.parametrize(
    ("override", "key"),
    [
        ("coils.x.wire_diameter_mm=20", "coils.x.wire_diameter_mm"),
        ("coils.z.separation_m=0.03", "coils.z.separation_m"),
        ("coils.z.radius_m=0.34", "coils.z.radius_m"),
    ],
)
def test_cross_key_problems_name_the_key(build_coils, override: str, key: str) -> None:
    with pytest.raises(InputError) as err:
        build_coils(load_design(None, [override]))
    assert err.value.key == key, str(err.value)


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["--set", "coils.x.radius_mmm=1"], "coils.x.radius_mmm"),
        (["--set", "coils.x.turns=-3"], "coils.x.turns"),
        (["--set", "coils.x.radius_m=nan"], "coils.x.radius_m"),
        (["--set", "coils.packing_factor=0.95"], "coils.packing_factor"),
        (["--set", "garbage"], "--set"),
        (["--set", "coils.x.wire_diameter_mm=20"], "coils.x.wire_diameter_mm"),
        (["--set", "coils.z.radius_m=0.34"], "coils.z.radius_m"),
        (["/nonexistent/design.toml"], "/nonexistent/design.toml"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(run_cli, capsys, argv: list, needle: str) -> None:
    status = run_cli(["coils", *argv])
    err = capsys.readouterr().err
    assert status == 2, err
    assert needle in err and err.count("\n") == 1, err


def test_malformed_toml_names_the_line(run_cli, capsys, tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text("[coils.x]\nradius_m = = 0.4\n", encoding="utf-8")
    assert run_cli(["coils", str(path)]) == 2
    err = capsys.readouterr().err
    assert "line 2" in err and err.count("\n") == 1, err


def test_unknown_key_suggests_the_right_one(run_cli, capsys) -> None:
    assert run_cli(["coils", "--set", "coils.x.radius_mmm=1"]) == 2
    assert "coils.x.radius_m?" in capsys.readouterr().err


def test_json_output(run_cli, capsys, tmp_path: Path) -> None:
    path = tmp_path / "d.toml"
    path.write_text("[coils.z]\nturns = 250\n", encoding="utf-8")
    assert run_cli(["coils", str(path), "--json", "--set", "operation.frequency_hz=2"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["design"] == str(path) and out["frequency_hz"] == 2.0
    assert out["current_amplitude_A"] == 15.0
    assert set(out["axes"]) == {"x", "y", "z"}
    need = {
        "radius_m",
        "turns",
        "field_per_amp_T_per_A",
        "resistance_ohm",
        "inductance_H",
        "voltage_amplitude_V",
        "power_W",
        "temperature_rise_K",
        "wire_length_m",
        "impedance_ohm",
        "hot_spot_temperature_C",
        "max_rotating_field_T",
        "max_current_A",
    }
    for ax in "xyz":
        assert need <= set(out["axes"][ax]), need - set(out["axes"][ax])
    z = out["axes"]["z"]
    assert z["turns"] == 250
    assert z["power_W"] == pytest.approx(z["resistance_ohm"] * 15.0**2 / 2, rel=1e-12), (
        "copper loss of a sinusoidal current R I^2/2, 1e-12"
    )
    assert z["hot_spot_temperature_C"] == pytest.approx(25 + z["temperature_rise_K"], rel=1e-12), (
        "hot-spot temperature = ambient + rise, 1e-12"
    )
    assert z["resistance_ohm"] == pytest.approx(
        z["resistance_20C_ohm"] * (1 + 0.00393 * (z["mean_temperature_C"] - 20)), rel=1e-12
    ), "resistance at the mean winding temperature (IEC 60028 alpha = 0.00393/K), 1e-12"
    assert out["current_limiting_axes"] == ["z"], "fewest turns per metre: z is weakest"
    region = out["uniform_region"]
    assert region["radius_1pct_m"] < region["radius_5pct_m"] < 0.3, (
        "±1 % region inside the ±5 % one, both inside the coils"
    )


def test_text_output(run_cli, capsys) -> None:
    assert run_cli(["coils"]) == 0
    out = capsys.readouterr().out
    for needle in ("mT_per_A", "±1 %", "worst heading", "set by the x axis"):
        assert needle in out, needle


def test_limits_by_hand_and_shared_with_evaluate(run_cli, capsys) -> None:
    """A low voltage limit makes the voltage bind: I_max = V_max/|Z| by hand; and the field
    within all limits is the same number `spiralcap evaluate` drives the coils at."""
    sets = ["--set", "limits.voltage_V=20", "--set", "coils.z.turns=200"]
    assert run_cli(["coils", "--json", *sets]) == 0
    out = json.loads(capsys.readouterr().out)
    z = out["axes"]["z"]
    from optimize import physics, prepare
    from spiralcap.assemble import build_model
    from spiralcap.core.constants import COPPER_TEMPERATURE_COEFFICIENT_per_K as alpha
    from spiralcap.design import load_design

    model = prepare(build_model(load_design(None, ["limits.voltage_V=20", "coils.z.turns=200"])))
    i = z["max_current_A"]
    mean = float(physics.pair_state(i, 2, model.constants, 25.0).mean_C)
    r = z["resistance_20C_ohm"] * (1.0 + alpha * (mean - 20.0))
    z_ohm = math.hypot(r, 2 * math.pi * 2.0 * z["inductance_H"])
    assert i == pytest.approx(20.0 / z_ohm, rel=1e-9), (
        "voltage-limited current amplitude V_max/|Z| (Ohm's law) with R at the winding's own "
        "mean temperature at that current, 1e-9"
    )
    assert z["max_current_limited_by"] == "voltage"
    assert out["current_limiting_axes"] == ["z"], "fewest turns per metre: z is weakest"
    w = out["rotating_field_within_limits"]
    assert w["max_rotating_field_T"] == pytest.approx(
        min(out["axes"][a]["max_rotating_field_T"] for a in "xyz"), rel=1e-12
    ), "worst heading: min_k g_k I_max,k (docs/optimisation.md, Limits), power not binding here"
    assert run_cli(["evaluate", "--json", *sets]) == 0
    ev = json.loads(capsys.readouterr().out)
    assert ev["field_amplitude_T"] == pytest.approx(w["max_rotating_field_T"], rel=1e-12), (
        "coils and evaluate share one definition of the limits (optimize.physics), 1e-12"
    )
