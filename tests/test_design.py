"""Design files: defaults, --set, validation messages, the example file, atomic writes."""

import math

import pytest

from spiralcap.cli import main
from spiralcap.core.errors import DataError, InputError
from spiralcap.design import Design, example_toml, load_design, parse_set, write_text_atomic
from spiralcap.schema import KEYS, defaults


def test_example_file_round_trips_to_the_defaults(tmp_path):
    path = tmp_path / "d.toml"
    path.write_text(example_toml())
    assert dict(load_design(path)) == dict(Design({})), (
        "spiralcap init's file must load to exactly the built-in design"
    )


def test_to_toml_round_trips(tmp_path):
    d = load_design(None, ["coils.x.turns=321", "tissue.worst_case_presets=[]"])
    path = tmp_path / "full.toml"
    path.write_text(d.to_toml())
    assert dict(load_design(path)) == dict(d), "Design.to_toml() reloads to the same design"
    assert load_design(path).sha256() == d.sha256(), "same design, same hash"


@pytest.mark.parametrize(
    "expr, key",
    [
        ("coils.x.radius_mmm=1", "coils.x.radius_mmm"),
        ("coils.x.turns=-3", "coils.x.turns"),
        ("coils.x.turns=2.5", "coils.x.turns"),
        ("coils.x.radius_m=nan", "coils.x.radius_m"),
        ("coils.x.radius_m=0", "coils.x.radius_m"),
        ("capsule.spiral.helical_angle_deg=90", "capsule.spiral.helical_angle_deg"),
        ("capsule.spiral.helical_angle_deg=0", "capsule.spiral.helical_angle_deg"),
        ("limits.field_exposure=sometimes", "limits.field_exposure"),
        ("capsule.diameter_mm=true", "capsule.diameter_mm"),
    ],
)
def test_bad_values_name_the_key(expr, key):
    with pytest.raises(InputError) as err:
        load_design(None, [expr])
    assert err.value.key == key and key in str(err.value), "the error names the key"


def test_unknown_key_suggests_the_near_one():
    with pytest.raises(InputError, match=r"did you mean coils\.x\.radius_m"):
        load_design(None, ["coils.x.radius_mmm=1"])


def test_malformed_set():
    with pytest.raises(InputError, match=r"dotted\.key=value"):
        parse_set("garbage")


def test_malformed_file_names_the_line(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text("[coils.x]\nradius_m = 0.3\nturns = = 4\n")
    with pytest.raises(DataError, match="line 3"):
        load_design(path)


def test_missing_file():
    with pytest.raises(DataError, match="cannot read"):
        load_design("/nonexistent/design.toml")


def test_every_default_passes_its_own_check():
    for key, value in defaults().items():
        assert KEYS[key].check(value), f"default of {key} must satisfy its own rule"


def test_atomic_write_leaves_nothing_on_failure(tmp_path):
    (tmp_path / "sub").mkdir()
    target = tmp_path / "sub" / "out.txt"
    write_text_atomic(target, "ok")
    assert target.read_text() == "ok", "atomic write writes the whole file"
    with pytest.raises(TypeError):
        write_text_atomic(tmp_path / "x.txt", 3.0)  # type: ignore[arg-type]
    assert [p.name for p in tmp_path.iterdir()] == ["sub"], "no temporary file left behind"


def test_init_writes_and_refuses_to_overwrite(tmp_path, capsys):
    path = tmp_path / "design.toml"
    assert main(["init", str(path)]) == 0
    assert "helical_angle_deg = 10.0" in path.read_text(), "example has the 10 deg spiral"
    assert main(["init", str(path)]) == 2, "existing file: exit 2"
    assert "PATH" in capsys.readouterr().err


def test_nan_is_rejected_not_propagated():
    with pytest.raises(InputError):
        Design({"limits.power_W": math.nan})


def test_unwritable_output_is_one_line_exit_2(tmp_path, capsys):
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    target = blocker / "sub" / "design.toml"  # a folder cannot be made inside a file
    with pytest.raises(DataError, match="cannot write"):
        write_text_atomic(target, "x")
    assert main(["init", str(target)]) == 2, "unwritable path: exit 2, no traceback"
    assert "cannot write" in capsys.readouterr().err
