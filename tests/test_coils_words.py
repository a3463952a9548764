"""`spiralcap coils` in the order an engineer reads, and the touch-temperature warning."""

from __future__ import annotations

import json

import pytest

from spiralcap.analysis.touch import IEC60601_LONG_CONTACT_C
from spiralcap.cli import main


def _out(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    assert main(argv) == 0
    return capsys.readouterr().out


@pytest.fixture(scope="module")
def builtin_text() -> dict[str, str]:
    """The built-in design's ``coils`` text and ``evaluate --json`` output, each run once for
    the tests that read them (the CLI in-process, stdout captured here)."""
    import contextlib
    import io

    out: dict[str, str] = {}
    for name, argv in (("coils", ["coils"]), ("evaluate_json", ["evaluate", "--json"])):
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            assert main(argv) == 0, f"spiralcap {' '.join(argv)} exits 0"
        out[name] = buf.getvalue()
    return out


def test_coils_leads_with_the_operating_point_and_says_runaway_in_words(capsys) -> None:
    text = _out(capsys, ["coils", "--set", "limits.current_A=40"])
    lines = text.splitlines()
    assert lines[0].startswith("design:") and lines[1].startswith("operating point:"), lines[:2]
    assert "undefined" not in lines[1], "the cooling at the operating point is defined"
    assert text.index("operating point:") < text.index("at the amplifier rating, 40 A")
    rating = text[text.index("at the amplifier rating") : text.index("uniform region")]
    for ax in "xyz":
        assert f"at 40 A the {ax} pair runs away thermally" in rating, rating
    assert "hold it below 14.36 A" in rating, "the x pair's largest current inside the limits"
    assert "°C" not in rating and "runaway " not in rating, "no temperature of a runaway branch"


def test_coils_at_a_rating_that_holds_shows_its_temperatures(builtin_text) -> None:
    text = builtin_text["coils"]
    rating = text[text.index("at the amplifier rating, 15 A") : text.index("uniform region")]
    assert "runs away" not in rating and "hot_C" in rating, rating
    assert (
        "at 15 A the y pair's hot spot passes its 90 °C limit: hold it below 11.82 A" in rating
    ), "the rating above what the limits allow is said in words, with the current to keep below"


def test_surface_above_iec_60601_is_a_warning_only_without_a_surface_limit(
    capsys, builtin_text
) -> None:
    warned = _out(capsys, ["evaluate"])
    assert f"above the {IEC60601_LONG_CONTACT_C:g} °C IEC 60601-1" in warned, warned[-400:]
    assert "limits.surface_temperature_C" in warned
    coils_text = builtin_text["coils"]
    assert "IEC 60601-1 allows" in coils_text
    payload = json.loads(builtin_text["evaluate_json"])
    assert len(payload["warnings"]) == 1 and "x, y and z pairs" in payload["warnings"][0]
    quiet = _out(capsys, ["evaluate", "--set", "limits.surface_temperature_C=80"])
    assert "IEC 60601-1" not in quiet, "with the limit set, the check speaks instead"
    cool = json.loads(_out(capsys, ["evaluate", "--json", "--set", "limits.current_A=2"]))
    assert cool["warnings"] == [], "a cool design has no warning"


@pytest.mark.parametrize(
    ("session_min", "limit_C"),
    [(None, 43.0), (30.0, 43.0), (10.0, 43.0), (5.0, 48.0), (1.0, 48.0), (0.5, 51.0)],
)
def test_touch_limit_follows_iec_60601_table_24_by_contact_time(session_min, limit_C) -> None:
    from spiralcap.analysis.touch import touch_limit_C

    seconds = None if session_min is None else 60.0 * session_min
    assert touch_limit_C(seconds)[0] == limit_C, (
        f"IEC 60601-1 3rd ed. Table 24 (metal): {limit_C} °C for {session_min} min, exact"
    )


def test_touch_warning_names_the_limit_of_the_session(capsys, builtin_text) -> None:
    hot = ["limits.current_A=33", "limits.coil_temperature_C=200", "limits.voltage_V=2000"]
    argv = ["evaluate", "--json", "--set", "operation.session_min=5", "--set", "limits.power_W=1e5"]
    short = json.loads(_out(capsys, argv + [a for k in hot for a in ("--set", k)]))["warnings"]
    steady = json.loads(builtin_text["evaluate_json"])["warnings"]
    assert "48 °C" in " ".join(short) and "of 1-10 min" in " ".join(short), short
    assert "43 °C" in " ".join(steady) and "10 min or more" in " ".join(steady), steady
