"""Figures that do not mislead (issue #20 item 6): own model curve per data set, waveforms."""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure

import torque_model as tm


def test_torque_plot_draws_each_paper_capsule_at_its_own_angle() -> None:
    from spiralcap.figures.torque import plot_torque_vs_frequency

    ax = Figure().subplots()
    drawn = plot_torque_vs_frequency(ax, tm.preset("zhou2013-sample2"), (10.0,))
    labels = [c.get_label() for c in drawn.curves]
    assert any("α = 5°" in lab for lab in labels), (
        "paper capsule No. 1 is alpha = 5 deg (Zhou 2013): its points need the 5 deg model "
        f"curve, not the 10 deg one: {labels}"
    )
    for pts in drawn.points:
        assert "α = " in pts.get_label(), "each data set is labelled with its helical angle"
    f = np.linspace(0.25, 3.5, 66)
    five = next(c for c in drawn.curves if "α = 5°" in c.get_label())
    ref = tm.resistive_torque_Nm(
        math.radians(5), f, tm.preset("zhou2013-sample2"), tm.PAPER_CAPSULE
    )
    assert np.allclose(five.get_ydata(), np.asarray(ref) * 1e3, rtol=1e-12)
    for p in (p for p in tm.PAPER_POINTS if p.sample == 2):
        curve = next(c for c in drawn.curves if f"α = {p.helical_angle_deg:g}°" in c.get_label())
        point = next(s for s in drawn.points if f"No. {p.capsule}," in s.get_label())
        colour = point.get_edgecolor()[0] if p.role != "calibration" else point.get_facecolor()[0]
        from matplotlib.colors import to_rgba

        assert np.allclose(colour, to_rgba(curve.get_color())), (
            f"No. {p.capsule} drawn in the colour of its own angle's curve"
        )


def test_waveform_sequence_one_panel_per_plane_change() -> None:
    from coils.waveforms import heading_waveforms
    from spiralcap.figures.thermal import draw_waveform_sequence

    headings = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    w = heading_waveforms(
        np.eye(3) * 1e-3,
        np.ones(3),
        np.full(3, 1e-2),
        headings,
        amplitude_T=5e-3,
        frequency_hz=2.0,
        dwell_s=20.0,
        ramp_s=0.5,
    )
    fig = Figure(figsize=(9, 9), layout="constrained")
    drawn = draw_waveform_sequence(fig, w, current_limit_A=10.0, voltage_limit_V=100.0)
    assert len(drawn.windows) == 2, "two plane changes: two zoomed columns"
    for j, (t0, t1) in enumerate(drawn.window_s):
        change = (j + 1) * 20.0
        assert t0 < change < change + 0.5 < t1, "the window holds the change and its ramp"
        assert (t1 - t0) * 2.0 <= 5.0, "a few cycles (at most 5 periods of 0.5 s), not 40"
    env = drawn.overview[0].get_ydata()  # x pair's current amplitude
    assert env[0] < 1e-9 and env[-1] > 4.0, "overview: the x pair steps up at the first change"


def test_margin_map_levels_over_the_feasible_range_and_regions_named() -> None:
    from optimize import evaluate, margin_grid, prepare
    from spiralcap.assemble import build_model
    from spiralcap.curves import frequency_range_hz, margin_map
    from spiralcap.design import load_design
    from spiralcap.figures.sweep import plot_margin_map

    model = prepare(build_model(load_design()))
    ev = evaluate(model)
    grid = margin_map(model, float(frequency_range_hz(model, ev.step_out_frequency_hz).max()))
    m = grid.margin_Nm * 1e3
    assert grid.failing is not None
    assert (grid.failing[grid.feasible] == "").all(), "a feasible point names no failure"
    named = ~grid.feasible & (m >= 0)
    assert (grid.failing[named] != "").all(), "every infeasible point that holds is named"
    # independent: the speed requirement, v = f * pitch * slip (speed_m_s), fails at low f only
    req = model.requirements
    speed_bad = grid.failing == f"speed < {req.min_speed_m_s * 1e3:.3g} mm/s"
    assert speed_bad.any()
    aa, ff = np.meshgrid(np.radians(grid.helical_angle_deg), grid.frequency_hz)
    g = margin_grid(model, aa, ff)
    assert (g.speed_m_s[speed_bad] < req.min_speed_m_s).all()
    ax = Figure(figsize=(7, 4.6), layout="constrained").subplots()
    drawn = plot_margin_map(
        ax,
        grid.helical_angle_deg,
        grid.frequency_hz,
        grid.margin_Nm,
        feasible=grid.feasible,
        failing=grid.failing,
    )
    levels = np.asarray(drawn.filled.levels)
    feasible_m = m[grid.feasible]
    assert levels[0] >= 0 and levels[0] <= feasible_m.min() + 1e-12, (
        "the first colour level at or below the least feasible margin, not at -18 mN·m"
    )
    assert levels[-1] >= feasible_m.max() and levels.size >= 6, "levels span the feasible range"
    assert m.min() < 0 and drawn.regions[0] == "margin < 0: steps out", (
        "negative margin: one region, named"
    )
    assert set(drawn.regions[1:]) == {n for n in grid.failing.ravel() if n}
    texts = {t.get_text() for t in ax.texts}
    assert set(drawn.regions[1:]) <= texts and "steps out" in texts, "each region named on the map"


def test_no_sobol_panel_with_one_input(tmp_path) -> None:
    from spiralcap.design import load_design
    from spiralcap.report.document import FigureBlock, Paragraph, Table
    from spiralcap.report.sections import uncertainty as sec
    from spiralcap.report.sections._util import Context

    design = load_design(None, ["tissue.uncertainty.scale_sigma_log=0.3"])
    st = sec.collect(design)
    section = sec.build(Context(None, {"uncertainty": sec.payload(st)}), st)
    assert section is not None
    assert "uncertainty-sobol" not in {b.id for b in section.blocks if isinstance(b, Table)}, (
        "one input: its Sobol indices are 1 by construction, no table of them"
    )
    (block,) = [b for b in section.blocks if isinstance(b, FigureBlock)]
    fig = Figure(figsize=block.size_in)
    block.draw(fig)
    assert len(fig.axes) == 2, "histogram and its CDF twin only: no single bar at 1"
    assert "Right:" not in block.caption
    assert any(
        "One uncertain input" in str(b.parts) for b in section.blocks if isinstance(b, Paragraph)
    )


def test_margin_frequency_vertical_lines_named_on_the_lines() -> None:
    from spiralcap.figures.design import plot_margin_vs_frequency

    ax = Figure().subplots()
    f = np.linspace(0.2, 10, 50)
    for k, (name, so, mx) in enumerate((("as entered", 6.0, 4.1), ("optimum", 7.9, 4.7))):
        plot_margin_vs_frequency(
            ax,
            f,
            (4.0 - f) * 1e-3,
            step_out_frequency_hz=so,
            max_frequency_hz=mx,
            label=f"{name}, α = 10°",
            style_index=k,
            shade=k == 0,
        )
    texts = [t.get_text() for t in ax.texts]
    for expected in (
        "step-out, as entered: 6 Hz",
        "drive max., as entered: 4.1 Hz",
        "step-out, optimum: 7.9 Hz",
        "drive max., optimum: 4.7 Hz",
    ):
        assert expected in texts, f"each vertical line labelled on the line (greyscale): {texts}"


def test_tissue_torque_legend_of_a_design_layered_with_a_fit() -> None:
    """A design layered with `spiralcap fit -o` output overrides eight tissue keys; its tissue
    set's name listed them all, and the legend took the width of the report's two-panel
    figure (constrained layout collapsed the axes: a UserWarning, an error here)."""
    from matplotlib.figure import Figure

    from spiralcap import figures
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    fitted = [
        "tissue.E1_kPa=55.77",
        "tissue.E2_kPa=8663",
        "tissue.E3_kPa=5.67",
        "tissue.eta1_kPa_s=20221",
        "tissue.eta2_kPa_s=102.8",
        "tissue.lumen_diameter_mm=10.9",
        "tissue.wall_thickness_mm=1.0",
        "tissue.friction_coefficient=0.28",
    ]
    model = build_model(load_design(None, fitted))
    assert len(model.tissues[0].name) > 90, "the full name lists every overridden material key"
    fig = Figure(figsize=(9.0, 4.6), layout="constrained")  # the report's size
    _, ax = fig.subplots(1, 2)
    figures.tissue_torque(model, ax=ax)
    labels = ax.get_legend_handles_labels()[1]
    # lumen and wall are the patient's anatomy (every set), not named: six material keys
    assert labels[0] == "zhou2013-sample2 + 6 tissue keys, α = 10° (design)", labels
    assert max(map(len, labels)) < 60, labels
    fig.get_layout_engine().execute(fig)  # no "axes sizes collapsed" warning (an error here)
    assert ax.get_position().width > 0.25, "the panel keeps its share of the figure"
    from spiralcap.figures.torque import plot_torque_vs_frequency  # `spiralcap torque --plot`

    one = Figure().subplots()
    plot_torque_vs_frequency(one, model.tissues[0], (10.0,), paper_points=())
    assert one.get_title() == "tissue zhou2013-sample2 + 6 tissue keys", one.get_title()


def test_both_frequency_curves_are_each_angles_curve_alone() -> None:
    """``frequency_curves`` solves the design's and the optimum's curves as one grid (the field
    capacity once per frequency): each equals :func:`spiralcap.curves.curve` at its own angle
    alone, bit for bit, and the optimum's angle differs from the design's."""
    import optimize
    from spiralcap.assemble import build_model
    from spiralcap.curves import curve, frequency_curves
    from spiralcap.design import load_design

    model = optimize.prepare(build_model(load_design()))
    ev, res = optimize.evaluate(model), optimize.optimize_design(model)
    assert res.helical_angle_rad != ev.helical_angle_rad, "two different angles"
    pair = frequency_curves(model, ev, res)
    assert pair[1] is not None
    for got, alpha in zip(pair, (ev.helical_angle_rad, res.helical_angle_rad), strict=True):
        alone = curve(model, alpha, got.x, got.x)
        for name in ("margin_Nm", "feasible", "speed_slack_m_s", "turns_slack"):
            assert np.array_equal(getattr(got, name), getattr(alone, name)), (
                f"{name} at {math.degrees(alpha):.3f} deg: the curve solved alone, bit for bit"
            )
