"""Issue 20.2: words that say what the numbers are -- every check in the form and unit of its
key, the self-lock as a bound on alpha + atan mu, the step-out with whether the drive reaches
it, and a report that names its objective in its own unit."""

from __future__ import annotations

import html
import math
import re

import pytest
from _td_cli import cli_json
from _treports_shared import sizing_report
from cli_outcome import NO_TOLERANCES, run


def _json(*argv: str) -> dict:
    """``spiralcap *argv --json``, exit 0 (``_td_cli``: each run once in this process)."""
    return cli_json(*argv)


def test_hot_spot_check_is_in_degrees_celsius_against_the_key():
    doc = _json("evaluate", "--set", "limits.coil_temperature_C=80")
    hot = [c for c in doc["checks"] if c["name"].startswith("hot_spot_")]
    assert len(hot) == 3
    amb = 25.0  # coils.ambient_temperature_C default (docs/coils-thermal.md)
    for c in hot:
        assert (c["key"], c["unit"], c["allowed"]) == ("limits.coil_temperature_C", "°C", 80.0)
        assert (c["key_unit"], c["allowed_in_key_unit"]) == ("°C", 80.0), "°C in the key too"
        assert c["value"] <= 80.0 * (1 + 1e-9), "the field is capped by the hot spot"
        assert c["utilisation"] == pytest.approx((c["value"] - amb) / (80.0 - amb), rel=1e-12), (
            "utilisation: the rise over the allowed rise"
        )
    assert max(c["value"] for c in hot) == pytest.approx(80.0, rel=1e-9), "one pair binds"
    speed = next(c for c in doc["checks"] if c["name"] == "speed")
    assert (speed["unit"], speed["allowed"]) == ("m/s", 0.005), "JSON in SI (README): 5 mm/s"
    assert (speed["key_unit"], speed["allowed_in_key_unit"]) == ("mm/s", 5.0), (
        "requirements.min_speed_mm_s = 5, in the key's unit"
    )


def test_evaluate_text_says_checks_self_lock_and_step_out_in_words():
    rc, out, _ = run(["evaluate", *NO_TOLERANCES])  # the design's own angle, no box
    assert rc == 0
    assert re.search(r"winding hot spot, [xyz] pair .* 90 °C <= 90 °C", out), out
    assert "65 <= 65" not in out and " K " not in out
    m = re.search(r"self-locking .* α \+ atan μ = ([\d.]+)°, must stay below 90°", out)
    assert m, out
    doc = _json("evaluate", *NO_TOLERANCES)
    lock = next(c for c in doc["checks"] if c["name"] == "self_lock")
    mu = 0.51  # zhou2013-sample3, the most frictional set (Zhou 2013, Table I)
    assert lock["value_in_key_unit"] == pytest.approx(
        doc["helical_angle_deg"] + math.degrees(math.atan(mu)), abs=1e-9
    )
    assert lock["unit"] == "rad" and lock["value"] == pytest.approx(
        math.radians(lock["value_in_key_unit"]), rel=1e-12
    ), "the check itself in SI (rad)"
    assert doc["max_frequency_hz"] < doc["step_out_frequency_hz"], "the built-in case"
    assert (
        f"{doc['step_out_frequency_hz']:.3g} Hz at the operating field; the drive cannot hold "
        f"that field above {doc['max_frequency_hz']:.3g} Hz"
    ) in out and "so the drive limit comes first" in out, out


def test_optimize_text_has_no_unitless_numbers():
    rc, out, _ = run(
        [
            "optimize",
            "--set",
            "optimize.objective=copper_mass",
            "--set",
            "requirements.min_safety_factor=2",
            "--free",
            "coils.x.turns=100:800",
            "--free",
            "coils.x.wire_diameter_mm=0.8:3.0",
            "--set",  # the grip held low, so the spiral-turns row binds at 1 turn
            "requirements.min_wall_strain=0.005",
            "--set",  # one start: the words are under test, not the multi-start search (the
            "optimize.starts=1",  # text is the 4-start one bar IPOPT's iteration count)
        ]
    )
    assert rc == 0
    assert "1 starts" not in out
    assert not re.search(r"(?<![\d.])1 turns\b", out), f"a count of one is singular: {out}"
    assert re.search(r"1 turn of 1 turn; lowering it by 1 turn gains", out), out
    assert re.search(r"objective +copper mass of the three coil pairs, minimised: [\d.]+ kg", out)
    assert re.search(r"whole turns and standard wire cost [\d.e-]+ kg", out), out
    assert re.search(
        r"requirements.min_safety_factor.*lowering it by 0.1 of the safety factor gains "
        r"[\d.]+ kg less",
        out,
    ), "issue 39: a gain per a sensible step of a ratio, not 'per unit'"
    assert "per unit" not in out and "by 1 unit" not in out


def test_singular_counts_in_evaluate_and_with_unit():
    from spiralcap.presentation import with_unit

    assert (with_unit("1", "turns"), with_unit("2.257", "turns")) == ("1 turn", "2.257 turns")
    assert (with_unit("1", "starts"), with_unit("0.4", "1"), with_unit("1", "mm")) == (
        "1 start",
        "0.4",
        "1 mm",
    )
    rc, out, _ = run(["evaluate"])
    assert rc == 0
    assert re.search(r"turns >= 1 turn +yes", out), out
    assert not re.search(r"(?<![\d.])1 turns\b", out), out


def test_power_report_names_power_in_watts_never_a_safety_factor_objective():
    """The least-power sizing report (``_treports_shared.SIZING``: objective power, safety
    factor 2, the grip held low so the spiral turns bind; its PDF is test_report_layout.py's)."""
    t = re.sub(r"<script.*?</script>|<style.*?</style>", "", sizing_report().html, flags=re.S)
    text = re.sub(r"\s+", " ", html.unescape(re.sub(r"<[^>]+>", " ", t)))
    assert "IPOPT minimised the worst-heading copper power" in text
    assert re.search(r"Objective: the worst-heading copper power, minimised: [\d.]+ W", text)
    assert "safety factor per" not in text, "no gain in safety factor for a power design"
    assert "maximised the worst-case safety factor" not in text
    assert re.search(r"gains [\d.]+ W less", text), "gains in watts"
    # the optimum binds the spiral-turns requirement at 1: a count of one is singular
    assert re.search(r"spiral turns requirements\.min_spiral_turns 1 turn 1 turn ", text), text
    assert not re.search(r"(?<![\d.])1 turns\b", text), "no '1 turns' in the report"


def test_a_report_number_of_one_count_is_singular():
    from spiralcap.report.numbers import Num

    assert (str(Num(1.0, unit="turns")), str(Num(2.257, unit="turns"))) == ("1 turn", "2.257 turns")
    assert (str(Num(1, unit="starts")), str(Num(1.0, unit="mm"))) == ("1 start", "1 mm")


def test_report_checks_table_names_the_self_lock_quantity():
    """The self-lock row's value is α + atan μ (37° for the built-in 10° spiral), not the
    helical angle its key sets: the row says so."""
    from spiralcap.report.sections._util import Context
    from spiralcap.report.sections.margin import checks_table

    doc = _json("evaluate", *NO_TOLERANCES)  # the design's own angle, no box
    table = checks_table(Context(None, {"evaluate": doc}), "evaluate", "checks", "t")
    row = next(r for r in table.rows if r[1] == "capsule.spiral.helical_angle_deg")
    assert row[0] == "self-locking: α + atan μ", row
    mu = 0.51  # the most frictional tissue set: zhou2013-sample3 (Zhou et al. 2013, eq. 1)
    expected = doc["helical_angle_deg"] + math.degrees(math.atan(mu))
    assert row[2].shown == pytest.approx(expected, rel=1e-9), "α + atan μ, independently"


def test_infeasible_sizing_names_the_hardware_as_design_keys():
    """Least copper at safety factor 2 within 140 W: least power for it is ~163 W (the
    power objective on the same freed keys), so no design; the closest hardware is named
    by its design keys in their units (3 mm wire, not 'x.wire_diameter_m = 0.003')."""
    from spiralcap.assemble.system import message_in_key_units

    assert message_in_key_units("at x.wire_diameter_m = 0.003, magnet.length_m = 0.01") == (
        "at coils.x.wire_diameter_mm = 3, capsule.magnet.length_mm = 10"
    )
    rc, out, _ = run(
        [
            "optimize",
            "--set",
            "optimize.objective=copper_mass",
            "--set",
            "requirements.min_safety_factor=2",
            "--set",
            "limits.power_W=140",
            "--free",
            "coils.x.turns=50:2000",
            "--free",
            "coils.x.wire_diameter_mm=0.5:5",
            "--set",  # one start (2 tried, not 8): the same shortfall and closest hardware as
            "optimize.starts=1",  # 4 starts, word for word; the words are under test here
        ]
    )
    assert rc == 3, out
    assert "coils.x.wire_diameter_mm = " in out and "wire_diameter_m =" not in out, out
    # (0.915 at the closest design that grips, with the default tolerance box; 1.3 without)
    found = re.search(r"requirements.min_safety_factor: needs 2, best reachable (\d\.\d+)", out)
    assert found and 0 < float(found.group(1)) < 2, out
