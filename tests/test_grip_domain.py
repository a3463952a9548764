"""Issue 36 items 4-5: no margin where the model has no physics, explanations inside the domain.

Independent references: D' from scipy's ConvexHull of a densely sampled capsule circle and the
spiral wire's wrapped-ellipse cut (the construction of Zhou 2013 Fig. 8, computed numerically,
not with the closed form of ``torque_model.geometry``), the strain of eq. 6 from it by hand.
"""

from __future__ import annotations

import csv
import functools
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from cli_outcome import NO_TOLERANCE_SETS, run
from scipy.spatial import ConvexHull

import torque_model as tm
from optimize import evaluate, margin_grid, prepare
from spiralcap.assemble import build_model
from spiralcap.design import load_design

LUMEN_MM = 11.3
#: The nominal spiral (no [tolerances] box): the ConvexHull references here are of the design's
#: own angle, wire and lumen; the box's worst corner is checked in
#: test_sweep_strain_is_held_at_its_worst_corner.
NOMINAL = list(NO_TOLERANCE_SETS)
#: The issue's sweep: 3-30 deg at a lumen of 11.3 mm (a 1 mm spiral on the 11 mm capsule).
ANGLES = np.linspace(3.0, 30.0, 28)


@functools.cache
def hull_d_prime_mm(alpha_deg: float, body_mm: float = 11.0, wire_mm: float = 1.0) -> float:
    """D' = perimeter / pi of the convex hull of the capsule circle and the wire's cut, wrapped
    round the wire's centre radius (docs/torque-model.md section 1), by scipy's ConvexHull."""
    R, r_w = body_mm / 2, wire_mm / 2
    centre = R + r_w
    psi_m = r_w / (centre * math.sin(math.radians(alpha_deg)))
    u = np.linspace(-1.0, 1.0, 4001)
    rho = centre + r_w * np.sqrt(np.clip(1.0 - u * u, 0.0, None))
    bump = np.c_[rho * np.sin(u * psi_m), rho * np.cos(u * psi_m)]
    t = np.linspace(0.0, 2.0 * np.pi, 20_000, endpoint=False)
    pts = np.r_[np.c_[R * np.cos(t), R * np.sin(t)], bump]
    v = pts[ConvexHull(pts).vertices]
    return float(np.sum(np.linalg.norm(np.roll(v, -1, axis=0) - v, axis=1)) / np.pi)


def _sets(values: list[str]) -> list[str]:
    return [a for v in values for a in ("--set", v)]


@pytest.fixture(scope="module")
def angle_sweep(tmp_path_factory):
    """``sweep`` over 3-30 deg at a 11.3 mm lumen: the CSV rows and the figure's path."""
    folder = tmp_path_factory.mktemp("grip")
    table, figure = folder / "s.csv", folder / "s.png"
    over = f"capsule.spiral.helical_angle_deg=3:30:{ANGLES.size}"
    rc, out, err = run(
        [
            "sweep",
            "--over",
            over,
            *_sets([*NOMINAL, f"tissue.lumen_diameter_mm={LUMEN_MM}"]),
            "--csv",
            str(table),
            "--plot",
            str(figure),
        ]
    )
    assert rc == 0, out + err
    with table.open() as fh:
        return list(csv.DictReader(fh)), figure


def test_sweep_has_no_margin_where_the_spiral_does_not_touch(angle_sweep):
    """Issue 36 done-when: contact against D' (ConvexHull) vs the lumen at every row; no margin
    (NaN) and speed 0 where there is none; the rows below the minimum strain marked and
    infeasible; the margin present wherever the spiral touches."""
    rows, _ = angle_sweep
    walls_mm = {
        1e3 * tm.preset(n).wall_thickness_m for n in ("zhou2013-sample2", "zhou2013-sample3")
    }
    need = tm.DEFAULT_MIN_WALL_STRAIN
    kinds = set()
    for row, alpha in zip(rows, ANGLES, strict=True):
        assert float(row["capsule.spiral.helical_angle_deg"]) == pytest.approx(alpha)
        d_prime = hull_d_prime_mm(float(alpha))
        strain = min((d_prime - LUMEN_MM) / (LUMEN_MM + w) for w in walls_mm)
        assert float(row["wall_strain"]) == pytest.approx(strain, abs=2e-5), (
            f"{alpha} deg: eq. 6 at the ConvexHull D' {d_prime:.5f} mm, 2e-5"
        )
        if d_prime <= LUMEN_MM:
            kinds.add("none")
            assert row["grip"] == "none", f"{alpha} deg: D' {d_prime:.4f} mm <= lumen"
            assert math.isnan(float(row["margin_Nm"])), f"{alpha} deg: no contact, no margin"
            assert math.isnan(float(row["safety_factor"]))
            assert float(row["speed_m_s"]) == 0.0 and row["feasible"] == "False"
            continue
        assert math.isfinite(float(row["margin_Nm"])), f"{alpha} deg: touches, a margin"
        assert float(row["speed_m_s"]) > 0
        if strain < need:
            kinds.add("below")
            assert row["grip"] == "below minimum" and row["feasible"] == "False", alpha
        else:
            kinds.add("ok")
            assert row["grip"] == "ok", alpha
    assert kinds == {"none", "below", "ok"}, "the sweep crosses all three regions"


def test_sweep_figure_hatches_and_names_both_regions(angle_sweep):
    """The figure of that sweep: each panel hatches the two spans, the legend names them, and
    the no-contact span starts between the last touching and the first free angle."""
    from matplotlib.figure import Figure

    from spiralcap.figures.sweep import GRIP_REGIONS, draw_sweep
    from spiralcap.sweep import parse_over, sweep

    _, figure = angle_sweep
    assert figure.stat().st_size > 10_000, "the PNG was written"
    design = load_design(None, [*NOMINAL, f"tissue.lumen_diameter_mm={LUMEN_MM}"])
    result = sweep(design, [parse_over(f"capsule.spiral.helical_angle_deg=3:30:{ANGLES.size}")])
    fig = Figure(layout="constrained")
    drawn = draw_sweep(fig, result)
    names = {t.get_text() for leg in fig.legends for t in leg.get_texts()}
    assert {GRIP_REGIONS["none"][0], GRIP_REGIONS["below minimum"][0]} <= names, names
    free = [a for a in ANGLES if hull_d_prime_mm(float(a)) <= LUMEN_MM]
    edge = 0.5 * (free[0] + (free[0] - 1.0))  # halfway between the neighbouring grid points
    for ax in drawn.axes:
        spans = [p for p in ax.patches if p.get_hatch()]
        assert len(spans) == 2, "one span per region on every panel"
        starts = sorted(p.get_x() for p in spans)
        assert starts[-1] == pytest.approx(edge), "no contact from halfway to the first free angle"


def test_api_margin_is_nan_without_contact():
    """``evaluate`` and ``margin_grid``: NaN margin and safety factor, speed 0 where the spiral
    does not touch (D' of 25 deg by ConvexHull is below 11.3 mm); ``model_margin_Nm`` keeps the
    formulas' number for starting points only."""
    assert hull_d_prime_mm(25.0) < LUMEN_MM
    model = prepare(
        build_model(load_design(None, [*NOMINAL, f"tissue.lumen_diameter_mm={LUMEN_MM}"]))
    )
    ev = evaluate(model, math.radians(25.0), 1.0)
    assert ev.grip == "none" and math.isnan(ev.margin_Nm) and math.isnan(ev.safety_factor)
    assert ev.speed_m_s == 0.0 and not ev.feasible
    g = margin_grid(model, np.radians([10.0, 25.0]), 1.0)
    assert np.isfinite(g.margin_Nm[0]) and np.isnan(g.margin_Nm[1])
    assert list(g.grip) == ["below minimum", "none"]
    assert np.isfinite(g.model_margin_Nm).all()
    assert g.margin_Nm[0] == pytest.approx(evaluate(model, math.radians(10.0), 1.0).margin_Nm)


def test_notebook_view_shows_no_margin_without_contact():
    """The notebook table of a no-contact evaluation says so instead of a number or 'nan'."""
    from spiralcap.notebook import NO_CONTACT

    model = prepare(
        build_model(load_design(None, [*NOMINAL, f"tissue.lumen_diameter_mm={LUMEN_MM}"]))
    )
    page = evaluate(model, math.radians(25.0), 1.0)._repr_html_()
    assert NO_CONTACT in page and "nan" not in page.lower(), "no margin, named"
    assert "does not touch every wall" in page


#: The issue's infeasible case: a 9 mm capsule with a 2.25 mm spiral wire in a 10.5 mm lumen,
#: driven by examples/square_coils.toml's square coils with 30 W per amplifier channel.
LAB = [
    "capsule.diameter_mm=9",
    "capsule.spiral.wire_diameter_mm=2.25",
    "tissue.lumen_diameter_mm=10.5",
    "optimize.helical_angle_min_deg=4",  # the 2.25 mm wire's turns touch below 3.65 deg
    "limits.x.power_W=30",
    "limits.y.power_W=30",
    "limits.z.power_W=30",
]
SQUARE = str(Path(__file__).resolve().parents[1] / "examples" / "square_coils.toml")


@pytest.fixture(scope="module")
def lab_infeasible():
    """``optimize --json`` and the text of the lab's case (each run once)."""
    rc, out, err = run(["optimize", SQUARE, *_sets(LAB), "--json"])
    assert rc == 3, out + err
    rc_text, text, _ = run(["optimize", SQUARE, *_sets(LAB)])
    assert rc_text == 3
    return json.loads(out), text


def test_infeasible_case_is_explained_at_a_design_that_grips(lab_infeasible):
    """Issue 36 done-when: exit 3, explained where the spiral grips (the strain there by the
    ConvexHull D' and eq. 6 >= the minimum), the limiting requirement the torque (reachable
    grip is not named), and the shortfall printed equal to ``evaluate`` of that design."""
    doc, text = lab_infeasible
    at = doc["explained_at"]
    assert at["grips"] is True
    alpha = at["keys"]["capsule.spiral.helical_angle_deg"]
    d_prime = hull_d_prime_mm(float(alpha), body_mm=9.0, wire_mm=2.25)
    walls_mm = {
        1e3 * tm.preset(n).wall_thickness_m for n in ("zhou2013-sample2", "zhou2013-sample3")
    }
    strain = min((d_prime - 10.5) / (10.5 + w) for w in walls_mm)
    assert strain >= tm.DEFAULT_MIN_WALL_STRAIN * (1 - 1e-4), (
        f"{alpha:.4f} deg: eq. 6 at the ConvexHull D' {d_prime:.5f} mm grips (1e-4: the hull)"
    )
    names = [s["name"] for s in doc["shortfalls"]]
    assert names == ["margin"], f"the torque is what is out of reach, not the grip: {names}"
    sets = [f"{k}={v!r}" for k, v in at["keys"].items()]
    ev = json.loads(run(["evaluate", SQUARE, *_sets([*LAB, *sets]), "--json"])[1])
    short = doc["shortfalls"][0]
    assert -ev["margin_Nm"] == pytest.approx(short["short_by"], rel=1e-9), (
        "the shortfall is that design's own evaluation (1e-9)"
    )
    assert ev["grip"] == "ok" and ev["speed_m_s"] >= 5e-3 * (1 - 1e-6), "speed met there"
    line = next(ln for ln in text.splitlines() if "falls short of the required torque" in ln)
    printed = float(re.search(r"by ([\d.]+) mN·m", line).group(1))
    assert printed == pytest.approx(-ev["margin_Nm"] * 1e3, rel=5e-4), "4 figures printed"
    assert "--set capsule.spiral.helical_angle_deg=" in text, "the design is named"


def test_advice_stays_inside_the_model_first(lab_infeasible):
    """The advice names the spiral wire, the magnet and the coil turns before any requirement,
    and says that lowering the grip row extrapolates."""
    doc, text = lab_infeasible
    advice = doc["advice"]
    first_requirement = next(i for i, a in enumerate(advice) if "requirements." in a)
    inside = " ".join(advice[:first_requirement])
    for key in ("capsule.spiral.wire_diameter_mm", "capsule.magnet.", "coils.x.turns"):
        assert key in inside, f"{key} before any requirement: {advice}"
    assert "extrapolates" in advice[-1] and "requirements.min_wall_strain" in advice[-1]
    assert "what would help, in this order:" in text


def test_no_angle_grips_names_the_grip_only():
    """A 0.5 mm wire on the 9 mm capsule in the 10.5 mm lumen cannot touch at any angle (D'
    by ConvexHull at the smallest angle is below the lumen): the grip is what is out of reach,
    named alone (the speed is 0 there only because nothing grips)."""
    assert hull_d_prime_mm(4.0, body_mm=9.0, wire_mm=0.5) < 10.5
    # the lab's case with its 30 W channels kept (a torque short too would not be named): the
    # same compiled NLPs as lab_infeasible's, not two more
    sets = [*LAB, "capsule.spiral.wire_diameter_mm=0.5"]
    rc, out, err = run(["optimize", SQUARE, *_sets(sets), "--json"])
    assert rc == 3, err
    doc = json.loads(out)
    assert {s["name"].split("[")[0] for s in doc["shortfalls"]} == {"wall_strain"}
    assert doc["explained_at"]["grips"] is False
    assert "capsule.spiral.wire_diameter_mm" in doc["advice"][0]


def _paragraphs(section) -> str:
    from spiralcap.report.document import Paragraph
    from spiralcap.report.numbers import Num

    out = []
    for b in section.blocks:
        if isinstance(b, Paragraph):
            out.append(
                "".join(
                    p.text if isinstance(p, Num) else getattr(p, "text", str(p)) for p in b.parts
                )
            )
    return "\n".join(out)


def test_report_says_no_feasible_design_on_its_first_page_and_tables(lab_infeasible):
    """The summary (the first page) of the lab's infeasible case: no 'Proposed change: the
    optimum', the advice in place of 'relax a limit', and the shortfall table captioned as no
    feasible design at the closest design that grips, with the keys evaluate reproduces."""
    from spiralcap.report.sections import conclusion, summary
    from spiralcap.report.sections._util import Context
    from spiralcap.report.sections.optimum import _shortfall_table

    doc, _ = lab_infeasible
    rc, out, _ = run(["evaluate", SQUARE, *_sets(LAB), "--json"])
    assert rc == 0
    ev = json.loads(out)
    design = load_design(SQUARE, LAB)
    payload = {
        "evaluate": ev,
        "optimize": doc,
        "conclusion": conclusion.conclusion_payload(ev, doc, design, None),
    }
    ctx = Context(None, payload)
    text = _paragraphs(summary.build(ctx))
    assert "Proposed change: the optimum" not in text
    assert "No proposed change: no feasible design" in text and "NO FEASIBLE DESIGN" in text
    assert "Relax a limit or a requirement" not in text
    assert "(1) a thicker spiral wire (capsule.spiral.wire_diameter_mm)" in text
    caption = _shortfall_table(ctx).caption
    assert caption.startswith("NO FEASIBLE DESIGN") and "grips the wall" in caption
    assert "capsule.spiral.helical_angle_deg = " in caption and "gives these numbers" in caption
    assert doc["explained_at"]["at_design_hardware"] is True


def test_grip_bound_against_the_convex_hull():
    """``optimize.grip_bound`` on the built-in design (sample 3: lumen 11.1 mm, wall 1 mm) is
    the angle where eq. 6 at the ConvexHull D' equals the default 1.68 % (the model's D' is
    within 3e-5 of the hull's, docs/torque-model.md: 0.05 deg), and the built-in optimum sits
    on it (the grip row binds there)."""
    from scipy.optimize import brentq

    from optimize import grip_bound, optimize_design

    model = prepare(build_model(load_design(None, NOMINAL)))
    need = tm.DEFAULT_MIN_WALL_STRAIN
    hull = brentq(lambda a: (hull_d_prime_mm(a) - 11.1) / 12.1 - need, 19.0, 21.0, xtol=1e-4)
    bound = grip_bound(model)
    assert bound.reachable and bound.least_strain_at_max >= need * (1 - 1e-9)
    assert math.degrees(bound.helical_angle_max_rad) == pytest.approx(hull, abs=0.05)
    res = optimize_design(model)
    assert res.helical_angle_rad == pytest.approx(bound.helical_angle_max_rad, rel=1e-6)


@pytest.fixture(scope="module")
def no_contact_case():
    """The built-in design entered at 25 deg in an 11.3 mm lumen (no contact), its optimum."""
    from optimize import optimize_design

    sets = [*NOMINAL, f"tissue.lumen_diameter_mm={LUMEN_MM}", "capsule.spiral.helical_angle_deg=25"]
    model = prepare(build_model(load_design(None, sets)))
    return model, evaluate(model), optimize_design(model)


def test_report_figures_hatch_and_name_both_regions(no_contact_case):
    """The report's margin-against-angle, margin-against-frequency and margin-map figures name
    no contact and the strain below the minimum; the angle figure's no-contact span starts
    where the ConvexHull D' meets the lumen (within one grid step of the curve)."""
    from scipy.optimize import brentq

    from spiralcap.feasibility import NO_CONTACT
    from spiralcap.figures import api

    model, ev, res = no_contact_case
    angle = api.margin_vs_angle(model, res, ev)
    names = {t.get_text() for t in angle.ax.get_legend().get_texts()}
    assert {api._GRIP_NAMES["none"], api._GRIP_NAMES["below minimum"]} <= names, names
    edge = brentq(lambda a: hull_d_prime_mm(a) - LUMEN_MM, 15.0, 25.0, xtol=1e-4)
    span = next(s for s in angle.drawn.shortfalls if s.get_label() == api._GRIP_NAMES["none"])
    step = (45.0 - 2.0) / 240
    assert span.get_x() == pytest.approx(edge, abs=step), "no contact from D' = lumen on"
    freq = api.margin_vs_frequency(model, ev, res)
    names = {t.get_text() for t in freq.ax.get_legend().get_texts()}
    assert "α = 25°: no contact with the wall: no margin" in names, names
    assert not any(n.startswith("as entered") for n in names), "no curve named where none is"
    regions = api.margin_map(model, res, ev).drawn.regions
    assert NO_CONTACT in regions and any(r.endswith("extrapolated") for r in regions), regions


def test_evaluate_text_marks_below_minimum_as_extrapolated():
    """15 deg in the 11.3 mm lumen touches (strain 0.3 %) but below the minimum: the margin is
    shown, named as extrapolated, and the design is infeasible."""
    from spiralcap.commands.evaluate import format_evaluation

    model = prepare(
        build_model(load_design(None, [*NOMINAL, f"tissue.lumen_diameter_mm={LUMEN_MM}"]))
    )
    ev = evaluate(model, math.radians(15.0), 1.0)
    assert ev.grip == "below minimum" and math.isfinite(ev.margin_Nm) and not ev.feasible
    text = format_evaluation(ev)
    assert "below requirements.min_wall_strain: extrapolated" in text


def test_advice_for_a_limit_the_hardware_breaks_names_no_requirement():
    """A shortfall that is the hardware's own limit (copper mass, clearances) is answered with
    other hardware or a higher limit, not 'relax a requirement'; with a requirement short too,
    the requirement line comes last."""
    from types import SimpleNamespace

    from optimize import Shortfall
    from spiralcap.explain import advice

    ev = SimpleNamespace(checks=(), field_limited_by="")
    copper = Shortfall("copper_mass", "kg", 1.0, 142.0)
    only = advice(SimpleNamespace(shortfalls=(copper,), evaluation=ev))
    assert len(only) == 1 and "limits.copper_mass_kg" in only[0], only
    both = advice(
        SimpleNamespace(shortfalls=(copper, Shortfall("margin", "N·m", 0.0, -1e-4)), evaluation=ev)
    )
    assert "coils.x.turns" in both[0] and "limits.copper_mass_kg" in both[1]
    assert both[-1].startswith("relaxing a requirement"), both


def test_sweep_strain_is_held_at_its_worst_corner():
    """With the default [tolerances] box each point's strain is the least over the box: the
    ConvexHull D' at the steepest angle and the thinnest wire against the widest lumen (issue
    36 item 3); no margin where that corner does not touch."""
    from spiralcap.sweep import parse_over, sweep

    design = load_design(None, [f"tissue.lumen_diameter_mm={LUMEN_MM}"])
    da, dw, dl = (
        design[f"tolerances.{k}"]
        for k in ("helical_angle_deg", "spiral_wire_diameter_mm", "lumen_diameter_mm")
    )
    assert da > 0 and dw > 0 and dl > 0, "the built-in box is not empty"
    angles = np.array([8.0, 16.0, 24.0])
    result = sweep(design, [parse_over("capsule.spiral.helical_angle_deg=8:24:3")])
    walls = [1e3 * tm.preset(n).wall_thickness_m for n in ("zhou2013-sample2", "zhou2013-sample3")]
    lumen = LUMEN_MM + dl
    for i, alpha in enumerate(angles):
        d_prime = hull_d_prime_mm(float(alpha) + da, wire_mm=1.0 - dw)
        strain = min((d_prime - lumen) / (lumen + w) for w in walls)
        got = float(result.outputs["wall_strain"][i])
        assert got == pytest.approx(strain, abs=3e-5), (
            f"{alpha} deg: eq. 6 at the box's least-strain corner (ConvexHull D'), 3e-5"
        )
        if d_prime <= lumen:
            assert math.isnan(float(result.outputs["margin_Nm"][i])), f"{alpha}: no margin"
