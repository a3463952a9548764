"""Figure functions of spiralcap.figures.design and .coils: what they draw, in which units.

Each function takes ``ax`` and returns its artists; the tests draw on an Agg figure, render it
(so layout and drawing warnings surface as errors) and check the data and labels. Expected
values are the inputs converted by hand (N·m -> mN·m x1e3, relative -> % x100), exact.
"""

from __future__ import annotations

import io

import numpy as np
import pytest
from matplotlib.figure import Figure

from spiralcap.figures.coils import plot_field_deviation_map, plot_uniformity_profile
from spiralcap.figures.design import (
    plot_limit_utilisation,
    plot_margin_vs_angle,
    plot_margin_vs_frequency,
    plot_margin_vs_power,
    plot_torque_budget,
)


def _axes(ncols: int = 1):
    fig = Figure(figsize=(6.4, 4.0), layout="constrained")
    return fig, fig.subplots(1, ncols) if ncols > 1 else fig.subplots()


def _render(fig: Figure) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=50)
    return buf.getvalue()


def test_margin_vs_frequency_units_markers_and_step_out() -> None:
    fig, ax = _axes()
    f = np.linspace(0.1, 6.0, 60)
    m = 3e-3 - 0.8e-3 * f
    ok = f > 0.5
    a = plot_margin_vs_frequency(
        ax, f, m, feasible=ok, step_out_frequency_hz=3.75, operating_frequency_hz=1.0, label="A"
    )
    b = plot_margin_vs_frequency(ax, f, m + 1e-4, style_index=1, shade=False, label="B")
    _render(fig)
    np.testing.assert_allclose(
        a.line.get_ydata(),
        np.where(ok, m * 1e3, np.nan),
        rtol=0,
        atol=1e-15,
        err_msg="N·m -> mN·m, x1e3 exactly",
    )
    assert a.step_out.get_xdata()[0] == 3.75, "step-out line at the given frequency"
    np.testing.assert_allclose(a.operating.get_ydata(), [(3e-3 - 0.8e-3) * 1e3])
    assert a.infeasible is not None and b.infeasible is None, "each curve its own feasibility"
    assert np.isnan(a.line.get_ydata()[~ok]).all(), "the solid curve only where feasible"
    assert a.below_zero is not None and b.below_zero is None, "negative margin hatched once"
    assert "(Hz)" in ax.get_xlabel() and "(mN·m)" in ax.get_ylabel(), "units on both axes"
    assert a.line.get_linestyle() != b.line.get_linestyle(), "not colour alone"
    assert a.line.get_marker() != b.line.get_marker(), "not colour alone"


def test_margin_vs_angle_marks_optimum_and_design() -> None:
    fig, ax = _axes()
    deg = np.linspace(2, 45, 50)
    m = 3e-3 - 1e-6 * (deg - 20) ** 2
    out = plot_margin_vs_angle(
        ax,
        deg,
        m,
        shortfalls={"too few turns": 30.0 - deg},
        optimum_deg=20.0,
        optimum_margin_Nm=3e-3,
        design_angle_deg=10.0,
    )
    _render(fig)
    assert tuple(out.optimum.get_xydata()[0]) == (20.0, 3.0), "star at (deg, mN·m)"
    assert out.design.get_xdata()[0] == 10.0
    assert len(out.shortfalls) == 1
    span = out.shortfalls[0]
    x0 = span.get_x() if hasattr(span, "get_x") else min(span.get_xy()[:, 0])
    assert x0 == pytest.approx(30.0, abs=1e-12), "span starts at the interpolated crossing"
    assert "(deg)" in ax.get_xlabel() and "(mN·m)" in ax.get_ylabel()


def test_margin_vs_power_front_infeasible_and_labels() -> None:
    fig, ax = _axes()
    p = np.array([250.0, 500.0, 1000.0, 2000.0])
    m = np.array([np.nan, 1e-3, 2e-3, 2e-3])
    out = plot_margin_vs_power(
        ax,
        p,
        m,
        optimal=[False, True, True, True],
        design_power_W=1000.0,
        binding=["", "power", "voltage_x", "voltage_x"],
    )
    _render(fig)
    np.testing.assert_allclose(out.front.get_ydata(), [1.0, 2.0, 2.0])
    assert out.infeasible is not None, "infeasible budgets drawn apart (crosses)"
    assert [t.get_text() for t in out.labels] == ["power", "voltage_x"], (
        "a binding-limit label where the binding set changes, not at every point"
    )
    assert ax.get_xscale() == "log" and "(W)" in ax.get_xlabel()


def test_limit_utilisation_from_objects_and_dicts_agree() -> None:
    from optimize import evaluate
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design
    from spiralcap.serialize import evaluation_to_dict

    ev = evaluate(build_model(load_design()))
    fig, (a1, a2) = _axes(2)
    r1 = plot_limit_utilisation(a1, ev.checks)
    r2 = plot_limit_utilisation(
        a2, evaluation_to_dict(ev)["checks"], labels={"power": "total power"}
    )
    _render(fig)
    w1 = [b.get_width() for b in r1.bars]
    w2 = [b.get_width() for b in r2.bars]
    assert w1 == w2, "result objects and their JSON dicts draw the same bars"
    amb = build_model(load_design()).ambient_temperature_C
    # limits as value / allowed in the row's own form (a hot spot: its rise above ambient over
    # the allowed rise, not °C over °C); requirements as needed / achieved
    expected = [
        100 * (c.value - amb) / (c.allowed - amb)
        if c.unit == "°C"
        else (100 * c.value / c.allowed if c.sense in ("<=", "<") else 100 * c.allowed / c.value)
        for c in ev.checks
        if c.allowed != 0
    ]
    np.testing.assert_allclose(w1, np.minimum(expected, 150.0), rtol=1e-12)
    right = a1.get_xlim()[1]
    assert max(w1) < right <= max(105.0, max(w1) + 1.0) + 1e-9, "axis ends just past the data"
    assert "total power" in [t.get_text() for t in a2.get_yticklabels()]
    assert r1.limit.get_xdata()[0] == 100.0


def test_torque_budget_stacks_required_torque() -> None:
    ev = {"magnetic_torque_Nm": 3.6e-3, "resistive_torque_Nm": 0.8e-3, "thrust_torque_Nm": 0.2e-3}
    fig, ax = _axes()
    out = plot_torque_budget(ax, [("a", ev), ("b", ev)])
    _render(fig)
    assert [p.get_height() for p in out.magnetic] == pytest.approx([3.6, 3.6], abs=1e-12)
    assert [p.get_y() for p in out.thrust] == pytest.approx([0.8, 0.8], abs=1e-12), (
        "thrust stacked on the resistive torque"
    )
    assert out.margins[0].get_text() == "margin 2.6 mN·m", "3.6 - 0.8 - 0.2 by hand"
    assert "(mN·m)" in ax.get_ylabel()


def test_field_deviation_map_contours_circles_colorbar() -> None:
    fig, ax = _axes()
    u = np.linspace(-0.2, 0.2, 41)
    uu, vv = np.meshgrid(u, u)
    dev = -((uu**2 + vv**2) / 0.2**2) * 0.2  # 20 % at r = 0.2 m, 1 % at r = 0.2/sqrt(20)
    out = plot_field_deviation_map(
        ax,
        u,
        u,
        dev,
        uniform_radii_m={0.01: 0.04, 0.05: 0.09},
        workspace_radius_m=0.05,
        title="test",
    )
    _render(fig)
    assert set(out.contours) == {0.01, 0.05}, "±1 % and ±5 % contours drawn"
    assert len(out.circles) == 3 and out.colorbar is not None
    r = np.hypot(*out.circles[0].get_xydata().T)
    np.testing.assert_allclose(r, 40.0, rtol=1e-12, err_msg="sphere circle at its radius, mm")
    assert ax.get_xlabel() == "x (mm)" and ax.get_ylabel() == "z (mm)"
    levels = np.asarray(out.filled.levels)
    np.testing.assert_allclose(levels, -levels[::-1], err_msg="levels symmetric about 0")
    assert out.filled.get_cmap().name == "RdBu_r", "diverging map centred on zero"


def test_uniformity_profile_percent() -> None:
    fig, ax = _axes()
    d = np.linspace(-0.1, 0.1, 21)
    out = plot_uniformity_profile(ax, d, {"a": -(d**2), "b": d**2})
    _render(fig)
    np.testing.assert_allclose(out.lines[0].get_ydata(), -100 * d**2, rtol=1e-15)
    assert len(out.bands) == 4, "±1 % and ±5 % reference lines"
    assert "(%)" in ax.get_ylabel() and "(mm)" in ax.get_xlabel()
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "±1 %" in legend and "±5 %" in legend, "reference lines in the legend"
    lo, hi = ax.get_ylim()
    assert lo < -1.0 and hi < 2.0, "range from the data (1 % at most), not a fixed ±12 %"
    assert out.lines[0].get_linestyle() != out.lines[1].get_linestyle()
