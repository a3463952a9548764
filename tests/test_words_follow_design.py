"""Issue 39, item 5, "words follow the design": the amplifier named is the pair's own channel
where ``limits.{x,y,z}.*`` is set; no internal labels; gains per a sensible step; no labels
printed over each other when the design as entered is the optimum; the range template reads;
``evaluate`` is not refused over an optimiser-only key; ``--set KEY=none`` clears a key; a
repeated ``--free`` is refused; an unbuildable sweep point is a row, not an exit."""

from __future__ import annotations

import itertools
import json
import re
from pathlib import Path

import pytest
from cli_outcome import run, run_json, sound

jsonschema = pytest.importorskip("jsonschema")

ROOT = Path(__file__).resolve().parents[1]
SQUARE = str(ROOT / "examples" / "square_coils.toml")
OWN = ["--set", "limits.x.current_A=12", "--set", "limits.y.current_A=13"]
OWN += ["--set", "limits.z.current_A=14", "--set", "limits.current_A=40"]


def test_coils_names_each_pairs_own_amplifier_channel():
    rc, out, err = run(["coils", *OWN])
    assert rc == 0, err
    assert "40 A per pair" not in out and "amplifier rating, 40 A" not in out, (
        "the global limits.current_A is no pair's rating when every pair has its own channel"
    )
    head = next(ln for ln in out.splitlines() if "amplifier rating" in ln)
    for ax, amps in zip("xyz", (12, 13, 14)):
        assert f"{ax} {amps} A (limits.{ax}.current_A)" in head, head
    doc = run_json(["coils", *OWN])
    for ax, amps in zip("xyz", (12, 13, 14)):
        pair = doc["axes"][ax]
        assert (pair["current_amplitude_A"], pair["current_limit_key"]) == (
            amps,
            f"limits.{ax}.current_A",
        ), "each pair sized at its own channel's current (the design's keys)"
    # the field at the current limits: min over pairs of g_k * I_k (the pairs' own currents)
    g = {ax: doc["axes"][ax]["field_per_amp_T_per_A"] for ax in "xyz"}
    expect = min(g[ax] * a for ax, a in zip("xyz", (12, 13, 14)))
    assert doc["current_limited_rotating_field_T"] == pytest.approx(expect, rel=1e-12), (
        "weakest pair's centre field at its own current (DESIGN.md 4.1: B = g I), 1e-12"
    )
    w = doc["rotating_field_within_limits"]
    assert "_" not in w["limited_by_words"].split(",")[0], w["limited_by_words"]
    assert "axis_" not in out and "set by current_x" not in out and "set by hot_spot" not in out


def test_the_report_names_the_channels_too():
    from spiralcap.report.sections._util import Context
    from spiralcap.report.sections.coils import _rating_parts

    doc = run_json(["coils", *OWN])
    text = "".join(
        str(getattr(p, "value", p)) for p in _rating_parts(Context(None, {"coils": doc}))
    )
    assert "own channel" in text or "channel's" in text, text
    for ax in "xyz":
        assert f"limits.{ax}.current_A" in text, text
    base = run_json(["coils"])
    text = "".join(
        str(getattr(p, "value", p)) for p in _rating_parts(Context(None, {"coils": base}))
    )
    assert "limits.current_A" in text and "limits.x." not in text, text


def test_freed_bound_and_strain_gain_in_words():
    rc, out, err = run(["optimize", "--free", "capsule.magnet.diameter_mm=3:7"])
    assert rc == 0, err
    assert "@max" not in out and "magnet.diameter m" not in out, out
    assert "magnet diameter at the top of its free range" in out, out
    m = re.search(
        r"min_wall_strain\): .*lowering it by 0\.1 % of strain gains ([\d.e-]+) mN·m", out
    )
    assert m, out
    assert "per unit" not in out and "by 1 unit" not in out
    doc = run_json(["optimize", "--free", "capsule.magnet.diameter_mm=3:7"])
    strain = next(b for b in doc["binding_limits"] if b["name"].startswith("wall_strain"))
    assert strain["gain_step"] == "0.1 % of strain"
    assert strain["gain_per_step"] == pytest.approx(
        1e-3 * strain["gain_per_key_unit"], rel=1e-12
    ), "0.1 % of strain is 1e-3 of the key's unit (a strain of 1), 1e-12"
    assert float(m.group(1)) == pytest.approx(strain["gain_per_step"], rel=1e-3), "text = JSON"


def test_entered_equal_optimum_prints_each_label_once():
    import optimize
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design
    from spiralcap.figures.api import margin_vs_frequency

    model = optimize.prepare(build_model(load_design(None)))
    result = optimize.optimize_design(model)
    plot = margin_vs_frequency(model, result.evaluation, result)  # entered = the optimum
    texts = [t.get_text() for t in plot.ax.texts]
    assert len(texts) == len(set(texts)), f"a label drawn twice over itself: {texts}"
    labels = plot.ax.get_legend_handles_labels()[1]
    assert any(lbl.startswith("as entered = optimum") for lbl in labels), labels
    assert not any(lbl.startswith("optimum,") for lbl in labels), labels
    xs = sorted(t.xy[0] for t in plot.ax.texts)
    assert all(b - a > 1e-6 for a, b in itertools.pairwise(xs)), f"two labels on one line: {texts}"


def test_range_template_reads():
    _, _, err = sound(["evaluate", "--set", "optimize.free.coils.x.wire_diameter_mm=[5]"], (2,))
    assert "a pair [min, max] of numbers with min < max" in err, err
    _, _, err = sound(["evaluate", "--set", "optimize.free.coils.x.turns=[5]"], (2,))
    assert "a pair [min, max] of whole numbers with min < max" in err, err


def test_evaluate_is_not_refused_over_an_optimiser_only_key():
    for argv in (
        ["--set", "optimize.helical_angle_min_deg=60"],
        ["--set", "optimize.frequency_min_hz=10"],
        ["--set", "optimize.free.coils.x.side_m=[0.5, 0.9]"],  # a circle's size freed as a side
    ):
        sound(["evaluate", *argv], (0,))
        if "frequency" in argv[1]:
            sound(["coils", *argv], (0,))
        _, _, err = sound(["optimize", *argv], (2,))
        assert "optimize." in err, "the optimiser still refuses its own keys"


def test_set_none_clears_a_key_and_squares_become_circles():
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    design = load_design(
        SQUARE, ["--set", "coils.z.shape=circle", "--set", "coils.z.side_m=none"][1::2]
    )
    model = build_model(design)
    assert model.coils.pairs[2].shape == "circle" and "coils.z.side_m" not in design
    assert (
        load_design(None, ["limits.current_A=40", "limits.current_A=none"])["limits.current_A"]
        == load_design(None)["limits.current_A"]
    ), "none: back to the default"
    doc = run_json(
        ["evaluate", SQUARE, "--set", "coils.z.shape=circle", "--set", "coils.z.side_m=none"]
    )
    coils = run_json(
        ["coils", SQUARE, "--set", "coils.z.shape=circle", "--set", "coils.z.side_m=none"]
    )
    z = coils["axes"]["z"]
    assert z["shape"] == "circle" and "side_m" not in z, "the z pair is a circle again"
    assert isinstance(doc["feasible"], bool), "and the design evaluates"
    _, _, err = sound(["evaluate", "--set", "coils.zz.side_m=none"], (2,))
    assert "coils.zz.side_m" in err and "did you mean coils.z.side_m" in err, err


def test_a_repeated_free_is_refused():
    _, _, err = sound(
        ["optimize", "--free", "coils.x.turns=100:800", "--free", "coils.x.turns=200:300"], (2,)
    )
    assert "coils.x.turns" in err and "freed once" in err, err


@pytest.mark.parametrize("optimise", [False, True])
def test_an_unbuildable_sweep_point_is_a_row(optimise):
    argv = [
        "sweep",
        "--over",
        "capsule.magnet.diameter_mm=5:12:2",
        *(["--optimize"] if optimise else []),
    ]
    rc, out, err = run([*argv, "--json"])
    assert rc == 0 and not err.strip(), err
    doc = json.loads(out)
    schema = json.loads((ROOT / "docs" / "json" / "sweep.schema.json").read_text())
    errors = [e.message for e in jsonschema.Draft202012Validator(schema).iter_errors(doc)]
    assert not errors, errors
    points = doc["points"]
    assert [p["unbuildable"] for p in points] == [False, True], points
    bad = points[1]
    assert "capsule.magnet.diameter_mm = 12.0" in bad["unbuildable_reason"], bad
    assert "margin_Nm" not in bad and bad.get("margin_Nm_undefined") is True
    assert points[0]["margin_Nm"] > 0 and points[0]["unbuildable_reason"] == ""
    if optimise:
        assert bad["status"] == "unbuildable"
    _, text, _ = sound(argv, (0,))
    assert "nan" not in text.lower() and "unbuildable" in text


def test_waveforms_check_each_pair_against_its_own_channel():
    """limits.y.current_A = 12.5 A: the y pair's 11.82 A is closest to its own 12.5 A (not to
    the global 15 A, which the x pair's 12.71 A would be compared with)."""
    argv = ["waveforms", "--heading", "1,0,0", "--heading", "0,1,0", "--dwell-s", "2"]
    _, out, _ = sound([*argv, "--set", "limits.y.current_A=12.5"], (0,))
    lines = [ln for ln in out.splitlines() if "closest to a limit" in ln]
    assert lines and all("vs 12.5 A" in ln and "y pair" in ln for ln in lines), lines
