"""``spiralcap compare``, ``sweep --plot``, ``coils --plot`` and progress, read from outside.

Independent checks: the margins ``compare --json`` reports equal what ``optimize --json``
prints for each design on its own; the geometry view puts each winding pack where the design
says (mean radius, half the separation); the sweep's margin map draws its zero contour where
the margin changes sign.
"""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import numpy as np
import pytest
from _te_memo import solved_once, solved_once_here  # noqa: F401 (the fixture)

from spiralcap.cli import main

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def _run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(argv)
    return status, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def builtin_optimum() -> dict:
    """``spiralcap optimize --json`` of the built-in design, run once: the reference both
    compare tests hold their first design's row to. (Each model is evaluated and optimised
    once in this process (tests/_te_memo.py): these tests optimise the built-in design five
    times, the 800 W one four times, by ``optimize``, ``compare`` and the report's section.)"""
    with solved_once_here():
        status, out, _ = _run(["optimize", "--json"])
    assert status == 0
    return json.loads(out)


@pytest.mark.usefixtures("solved_once")
def test_compare_json_names_the_changed_key_and_both_margins(builtin_optimum: dict) -> None:
    status, out, _ = _run(
        ["compare", "builtin", "builtin", "--set", "2:limits.power_W=800", "--json"]
    )
    assert status == 0
    data = json.loads(out)
    assert data["spiralcap_version"], "--json carries the version"
    assert [k["key"] for k in data["changed_keys"]] == ["limits.power_W"]
    assert data["changed_keys"][0]["values"] == [2000.0, 800.0]
    status, o, _ = _run(["optimize", "--json", "--set", "limits.power_W=800"])
    assert status == 0
    alone = [builtin_optimum["margin_Nm"], json.loads(o)["margin_Nm"]]
    assert data["margin_Nm"]["optimize"] == pytest.approx(alone, rel=1e-9), (
        "compare optimises each design as `spiralcap optimize` does (same margins, 1e-9)"
    )
    rows = {r["quantity"]: r for r in data["optimize"]}
    assert rows["torque margin"]["differs"] and not rows["helical angle"]["differs"]


@pytest.mark.usefixtures("solved_once")
def test_compare_names_each_optimum_objective_in_its_own_unit(builtin_optimum: dict) -> None:
    """Designs that optimise different objectives: each optimum's objective is a text row with
    its value in its unit (as `spiralcap optimize` prints it), and the copper mass is a row."""
    status, out, _ = _run(
        ["compare", "builtin", "builtin", "--set", "2:optimize.objective=power", "--json"]
    )
    assert status == 0
    rows = {r["quantity"]: r for r in json.loads(out)["optimize"]}
    margin, power = rows["objective"]["text"]
    _, o, _ = _run(["optimize", "--json", "--set", "optimize.objective=power"])
    alone = [builtin_optimum, json.loads(o)]
    assert margin.startswith("worst-case torque margin, maximised: ") and margin.endswith(" mN·m")
    assert power.startswith("worst-heading copper power, minimised: ") and power.endswith(" W")
    assert float(power.split(": ")[1].split()[0]) == pytest.approx(
        alone[1]["objective_value_shown"], rel=1e-3
    ), "the power the optimiser reports, in W (4 figures)"
    assert rows["copper mass"]["values"] == pytest.approx(
        [a["copper_mass_kg"] for a in alone], rel=1e-12
    )


@pytest.mark.usefixtures("solved_once")
def test_compare_text_marks_what_differs() -> None:
    status, out, _ = _run(["compare", "builtin", "builtin", "--set", "2:limits.power_W=800"])
    assert status == 0
    assert "limits.power_W" in out and "mN·m" in out and "mm/s" in out
    margin = [ln for ln in out.splitlines() if "torque margin" in ln]
    assert margin and all(ln.startswith("* ") for ln in margin), "differing rows marked"
    angle = [ln for ln in out.splitlines() if "helical angle" in ln and "deg" in ln]
    assert angle and not angle[0].startswith("*")


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["compare", "builtin"], "DESIGN"),
        (["compare", "builtin", "builtin", "--set", "3:limits.power_W=800"], "--set"),
        (["sweep", "--over", "limits.power_W=500:900:2", "--plot", "x.jpg"], "--plot"),
        (
            [
                "sweep",
                "--over",
                "limits.power_W=500:900:2",
                "--over",
                "limits.voltage_V=100:150:2",
                "--over",
                "limits.current_A=10:15:2",
                "--plot",
                "x.png",
            ],
            "--plot",
        ),
        (["coils", "--plot", "geometry.txt"], "--plot"),
    ],
)
def test_bad_plot_and_compare_input_exits_2(argv: list[str], needle: str) -> None:
    status, _, err = _run(argv)
    assert status == 2, f"bad input exits 2: {argv}"
    assert needle in err and "Traceback" not in err


def test_sweep_plot_two_keys_draws_the_margin_map(tmp_path: Path) -> None:
    from spiralcap.design import load_design
    from spiralcap.figures.sweep import draw_sweep
    from spiralcap.sweep import parse_over, sweep

    target = tmp_path / "map.png"
    argv = [
        "sweep",
        "--over",
        "capsule.spiral.helical_angle_deg=5:40:8",
        "--over",
        "operation.frequency_hz=0.5:7:9",
        "--plot",
        str(target),
    ]
    status, out, _ = _run(argv)
    assert status == 0 and target.read_bytes().startswith(PNG_MAGIC)
    assert "margin_mNm" in out and "speed_mm_s" in out, "text columns in mN·m and mm/s"
    from matplotlib.figure import Figure

    axes = [parse_over(a) for a in argv[2:6:2]]
    result = sweep(load_design(), axes)
    drawn = draw_sweep(Figure(), result)
    assert drawn.margin_map is not None and drawn.margin_map.step_out is not None
    margin = np.asarray(result.outputs["margin_Nm"]).reshape(8, 9)
    assert (margin > 0).any() and (margin < 0).any(), "the grid spans the step-out boundary"
    assert drawn.margin_map.infeasible is not None, "infeasible region hatched"


def test_sweep_plot_one_key_and_coils_geometry(tmp_path: Path) -> None:
    one = tmp_path / "one.svg"
    status, _, _ = _run(["sweep", "--over", "limits.power_W=500:3000:4", "--plot", str(one)])
    assert status == 0 and b"<svg" in one.read_bytes()
    geo = tmp_path / "geo.png"
    status, out, _ = _run(["coils", "--plot", str(geo)])
    assert status == 0 and geo.read_bytes().startswith(PNG_MAGIC)
    assert f"wrote {geo}" in out


def test_geometry_view_draws_packs_where_the_design_puts_them() -> None:
    from matplotlib.figure import Figure

    from spiralcap.assemble import build_model
    from spiralcap.design import load_design
    from spiralcap.figures.hardware import draw_geometry

    design = load_design()
    model = build_model(design)
    drawn = draw_geometry(
        Figure(figsize=(7, 3.5)), model.coils, model.capsule, workspace_radius_m=0.05
    )
    for name in ("x", "z"):
        pair = getattr(model.coils, name)
        side = pair.winding_pack_side_m * 1e3
        centres = sorted(
            (round(p.get_x() + side / 2, 9), round(p.get_y() + side / 2, 9))
            for p in drawn.pairs[name]
            if hasattr(p, "get_width")
        )
        h, r = pair.separation_m / 2 * 1e3, pair.radius_m * 1e3
        expected = sorted(
            (round(a, 9), round(b, 9))
            for a, b in (
                (sa * h, sr * r) if name == "x" else (sr * r, sa * h)
                for sa in (-1, 1)
                for sr in (-1, 1)
            )
        )
        assert np.asarray(centres) == pytest.approx(np.asarray(expected), abs=1e-9), (
            f"{name} packs at (±separation/2, ±radius) in mm, from the design"
        )
    ws = drawn.workspace.get_xydata()
    assert np.hypot(*ws.T) == pytest.approx(50.0, rel=1e-12), "workspace circle r = 50 mm"
    assert drawn.capsule_axes is not None


def test_progress_shows_stage_rate_and_time_left_only_when_asked() -> None:
    from spiralcap.progress import progress_bar, stages

    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        with progress_bar("evaluating", enabled=True) as update:
            assert update is not None
            for i in range(1, 4):
                update(i, 3)
        with stages(("evaluate", "optimize"), enabled=True) as say:
            assert say is not None
            say("evaluate")
            say("optimize")
    text = err.getvalue()
    assert "evaluating" in text and "3/3" in text and "point/s" in text, "rate shown"
    assert "<" in text, "tqdm's elapsed<remaining time shown"
    assert "optimize" in text, "the stage name shown"
    with progress_bar("x", enabled=False) as update:
        assert update is None, "nothing drawn off a terminal"


@pytest.mark.usefixtures("solved_once")
def test_report_comparison_section_renders_in_html_and_pdf() -> None:
    from types import SimpleNamespace

    from spiralcap.compare import compare_designs
    from spiralcap.design import load_design
    from spiralcap.report.document import FrontMatter
    from spiralcap.report.html import render_html
    from spiralcap.report.pdf import render_pdf
    from spiralcap.report.sections import Context, comparison

    a, b = load_design(), load_design(None, ["limits.power_W=800"])
    c = compare_designs([a, b], ("this design", "compared design"))
    section = comparison.build(Context(SimpleNamespace(comparison=c), {}))
    assert section is not None
    front = FrontMatter("t", "", "", "", "today", "built-in", "0" * 64, "0")
    page = render_html(front, [section], {}, figures={})
    assert "limits.power_W" in page and "▸ torque margin" in page, "changed rows marked"
    pdf, pages = render_pdf(front, [section], "", {})
    assert pdf.startswith(b"%PDF-") and pages >= 1
    assert comparison.build(Context(SimpleNamespace(comparison=None), {})) is None
