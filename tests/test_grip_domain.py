"""Issue 36 items 4-5: no margin where the model has no physics, explanations inside the domain.

Independent references: D' from scipy's ConvexHull of a densely sampled capsule circle and the
spiral wire's wrapped-ellipse cut (the construction of Zhou 2013 Fig. 8, computed numerically,
not with the closed form of ``torque_model.geometry``), the strain of eq. 6 from it by hand.
"""

from __future__ import annotations

import csv
import functools
import math

import numpy as np
import pytest
from cli_outcome import run
from scipy.spatial import ConvexHull

import torque_model as tm
from optimize import evaluate, margin_grid, prepare
from spiralcap.assemble import build_model
from spiralcap.design import load_design

LUMEN_MM = 11.3
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
            *_sets([f"tissue.lumen_diameter_mm={LUMEN_MM}"]),
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
    design = load_design(None, [f"tissue.lumen_diameter_mm={LUMEN_MM}"])
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
    model = prepare(build_model(load_design(None, [f"tissue.lumen_diameter_mm={LUMEN_MM}"])))
    ev = evaluate(model, math.radians(25.0), 1.0)
    assert ev.grip == "none" and math.isnan(ev.margin_Nm) and math.isnan(ev.safety_factor)
    assert ev.speed_m_s == 0.0 and not ev.feasible
    g = margin_grid(model, np.radians([10.0, 25.0]), 1.0)
    assert np.isfinite(g.margin_Nm[0]) and np.isnan(g.margin_Nm[1])
    assert list(g.grip) == ["below minimum", "none"]
    assert np.isfinite(g.model_margin_Nm).all()
    assert g.margin_Nm[0] == pytest.approx(evaluate(model, math.radians(10.0), 1.0).margin_Nm)
