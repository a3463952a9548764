"""Design -> Capsule (spiralcap.assemble.capsule) and the ``spiralcap capsule`` command."""

from __future__ import annotations

import json
import math
import re
import types
from pathlib import Path

import pytest

import spiralcap
from spiralcap.core.errors import InputError
from spiralcap.design import load_design

_PKG = Path(spiralcap.__file__).parent
#: Zhou et al. 2013 II.C: friction coefficient of intestine sample 2 (the default preset).
_SAMPLE2_MU = 0.28


def _build(assemble: types.ModuleType, *overrides: str):
    return assemble.build_capsule(load_design(None, overrides))


def test_default_design_builds_in_si(assemble: types.ModuleType) -> None:
    cap = _build(assemble)
    assert cap.body.diameter_m == pytest.approx(11e-3, rel=1e-15), "11 mm -> m, rel 1e-15"
    assert cap.spiral.helical_angle_rad == pytest.approx(math.radians(10.0), rel=1e-15)
    assert cap.spiral.wound_length_m == pytest.approx(15e-3, rel=1e-15)
    assert cap.magnet.remanence_T == pytest.approx(1.345, rel=1e-15), (
        "N45 nominal mid-band 1.32-1.37 T (Shanghai Magnet grade table), rel 1e-15"
    )
    assert cap.magnet.shape == "cylinder"


def test_remanence_overrides_grade(assemble: types.ModuleType) -> None:
    assert _build(assemble, "capsule.magnet.grade=N52").magnet.remanence_T == 1.44
    cap = _build(assemble, "capsule.magnet.grade=N52", "capsule.magnet.remanence_T=1.2")
    assert cap.magnet.remanence_T == 1.2, "remanence_T overrides the grade (schema.py)"


def test_ring_builds(assemble: types.ModuleType) -> None:
    cap = _build(assemble, "capsule.magnet.shape=ring", "capsule.magnet.inner_diameter_mm=2")
    assert cap.magnet.inner_diameter_m == pytest.approx(2e-3) and cap.magnet.shape == "ring"


@pytest.mark.parametrize(
    ("overrides", "key"),
    [
        (("capsule.magnet.diameter_mm=20",), "capsule.magnet.diameter_mm"),
        (("capsule.magnet.length_mm=30",), "capsule.magnet.length_mm"),
        (("capsule.magnet.shape=ring",), "capsule.magnet.inner_diameter_mm"),
        (("capsule.magnet.inner_diameter_mm=2",), "capsule.magnet.inner_diameter_mm"),
        (
            ("capsule.magnet.shape=ring", "capsule.magnet.inner_diameter_mm=6"),
            "capsule.magnet.inner_diameter_mm",
        ),
        (("capsule.spiral.wire_diameter_mm=3",), "capsule.spiral.wire_diameter_mm"),
        (("capsule.spiral.wound_length_mm=16",), "capsule.spiral.wound_length_mm"),
        (("capsule.shell_thickness_mm=5.5",), "capsule.shell_thickness_mm"),
        (("capsule.length_mm=11",), "capsule.length_mm"),
        (("capsule.spiral.helical_angle_deg=1",), "capsule.spiral.helical_angle_deg"),
        (
            ("capsule.spiral.starts=4", "capsule.spiral.helical_angle_deg=5"),
            "capsule.spiral.helical_angle_deg",
        ),
    ],
)
def test_cross_key_problems_name_the_key(
    assemble: types.ModuleType, overrides: tuple, key: str
) -> None:
    with pytest.raises(InputError) as err:
        _build(assemble, *overrides)
    assert err.value.key == key, f"{overrides}: expected the error to name {key}, got {err.value}"


def test_wire_limit_says_why(assemble: types.ModuleType) -> None:
    with pytest.raises(InputError) as err:
        _build(assemble, "capsule.spiral.wire_diameter_mm=3")
    assert "25%" in str(err.value) and "2.75" in str(err.value), str(err.value)


def test_cli_magnet_too_wide_exits_2_naming_the_key(run_cli, capsys) -> None:
    status = run_cli(["capsule", "--set", "capsule.magnet.diameter_mm=20"])
    err = capsys.readouterr().err
    assert status == 2, err
    assert "capsule.magnet.diameter_mm" in err and err.count("\n") == 1, err


@pytest.mark.parametrize(
    "override",
    [
        "capsule.diameter_mm=0",
        "capsule.length_mm=-26",
        "capsule.shell_thickness_mm=0",
        "capsule.magnet.diameter_mm=0",
        "capsule.magnet.length_mm=-1",
        "capsule.spiral.wire_diameter_mm=0",
        "capsule.spiral.wound_length_mm=0",
        "capsule.spiral.helical_angle_deg=0",
        "capsule.spiral.starts=0",
    ],
)
def test_cli_non_positive_sizes_exit_2(run_cli, capsys, override: str) -> None:
    assert run_cli(["capsule", "--set", override]) == 2
    assert override.split("=")[0] in capsys.readouterr().err


def test_cli_json_default(run_cli, capsys) -> None:
    assert run_cli(["capsule", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in (
        "magnet_moment_Am2",
        "pitch_m",
        "lead_m",
        "helix_diameter_m",
        "turns",
        "thrust_torque_Nm",
        "speed_m_s",
        "footprint_width_m",
        "synchronous_torque_per_mT_Nm",
        "full_turn_ok",
    ):
        assert key in out, f"JSON must carry {key}"
    lead = math.pi * 12e-3 * math.tan(math.radians(10.0))
    assert out["pitch_m"] == pytest.approx(lead, rel=1e-12), (
        "pi D_h tan(alpha) with D_h = 12 mm at 10 deg (Zhou et al. 2013 II-A convention), rel 1e-12"
    )
    assert out["speed_m_s"] == pytest.approx(0.5 * 2.0 * lead, rel=1e-12), (
        "slip 0.5 x 2 Hz x lead (schema defaults), rel 1e-12"
    )
    assert out["full_turn_ok"] is True and out["turns"] == pytest.approx(15e-3 / lead)
    mu = out["friction_coefficient"]
    assert out["thrust_torque_Nm"] == pytest.approx(
        0.05 * 6e-3 * math.tan(math.radians(10.0) + math.atan(mu)), rel=1e-12
    ), "50 mN x 6 mm x tan(alpha + atan mu) (Shigley power screw), rel 1e-12"
    assert out["synchronous_torque_per_mT_Nm"] == pytest.approx(
        out["magnet_moment_Am2"] * 1e-3, rel=1e-15
    ), "m x 1 mT, rel 1e-15"


def test_cli_uses_tissue_friction(run_cli, capsys, assemble) -> None:
    expected = assemble.build_tissues(load_design())[0].friction_coefficient
    assert run_cli(["capsule", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["friction_coefficient"] == expected
    assert expected == pytest.approx(_SAMPLE2_MU), (
        "default preset zhou2013-sample2: mu = 0.28 (Zhou et al. 2013 II.C), rel 1e-6"
    )


def test_cli_flags_less_than_one_turn(run_cli, capsys) -> None:
    assert run_cli(["capsule", "--set", "capsule.spiral.helical_angle_deg=30"]) == 0
    text = capsys.readouterr().out
    assert re.search(r"^warning: the spiral makes 0\.689 turns", text, re.M), (
        f"15 mm / (pi 12 mm tan 30 deg) = 0.689 turns < 1 must be flagged:\n{text}"
    )
    assert run_cli(["capsule", "--json", "--set", "capsule.spiral.helical_angle_deg=30"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["full_turn_ok"] is False and out["turns"] == pytest.approx(0.68916, rel=1e-4), (
        "hand value 15 / 21.766 = 0.68916 turns at 30 deg, rel 1e-4"
    )
    assert (
        run_cli(
            [
                "capsule",
                "--json",
                "--set",
                "capsule.spiral.helical_angle_deg=30",
                "--set",
                "requirements.min_spiral_turns=0",
            ]
        )
        == 0
    )
    assert json.loads(capsys.readouterr().out)["full_turn_ok"] is True, "0 switches the rule off"


def test_cli_text_default(run_cli, capsys) -> None:
    assert run_cli(["capsule"]) == 0
    text = capsys.readouterr().out
    assert "magnet moment" in text and "thrust torque" in text and "warning" not in text, text


def test_plain_mapping_is_validated_key_by_key(assemble: types.ModuleType) -> None:
    with pytest.raises(InputError) as err:
        assemble.build_capsule({"capsule.diameter_mm": 0})
    assert err.value.key == "capsule.diameter_mm", str(err.value)
    cap = assemble.build_capsule({"capsule.spiral.helical_angle_deg": 20})
    assert cap.spiral.helical_angle_deg == pytest.approx(20.0), "absent keys take schema defaults"
