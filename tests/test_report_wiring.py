"""What issues 9, 10 and 11 added, as the report shows it.

- the tissue-uncertainty section appears after the margin section only when the design has
  tissue uncertainty (issue 11), and the built-in report is unchanged;
- the coils section's heating curves, with the end of ``operation.session_min`` marked, from the
  same coil analysis as ``spiralcap coils --json`` (issue 10);
- the margin-against-frequency figure draws both the step-out frequency at the operating field
  and the drive's maximum frequency, where the re-maximised-field margin curve crosses zero
  (issue 10);
- the optimum section shows the keys of the design file ``spiralcap optimize -o`` writes that
  differ from the input (issue 9).
"""

from __future__ import annotations

import functools
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
import tomllib
from cli_outcome import NO_TOLERANCE_SETS
from matplotlib.figure import Figure

from spiralcap.design import load_design
from spiralcap.report.document import Code, FigureBlock, Paragraph

UNCERTAIN = "tissue.uncertainty.scale_sigma_log=0.3"


def _figure(block: FigureBlock) -> Figure:
    fig = Figure(figsize=block.size_in, layout="constrained")
    block.draw(fig)
    fig.canvas.draw()  # lays the figure out as the report does
    return fig


def test_uncertainty_section_only_with_uncertainty(monkeypatch: pytest.MonkeyPatch) -> None:
    from spiralcap.curves import adaptive_power_sweep
    from spiralcap.report.builder import build_report
    from spiralcap.report.data import collect, design_has_uncertainty
    from spiralcap.report.sections import uncertainty

    assert not design_has_uncertainty(load_design()), "the built-in design has no uncertainty"
    # fewer samples than the report's 2^16: the wiring is under test here, not the statistics
    monkeypatch.setattr(uncertainty, "REPORT_SAMPLES", 1 << 10)
    monkeypatch.setattr(uncertainty, "REPORT_SOBOL_BASE", 1 << 6)
    # and the power trade-off at the design's budget only, unrefined (five refined budgets:
    # ~0.3 s more): its section is not under test here; the sweep still runs and is drawn
    monkeypatch.setitem(adaptive_power_sweep.__kwdefaults__, "refinements", 0)
    monkeypatch.setitem(collect.__kwdefaults__, "power_factors", (1.0,))
    # the samples are the nominal capsule's: no tolerance box on the evaluation (issue 36)
    design = load_design(None, [UNCERTAIN, *NO_TOLERANCE_SETS])
    assert design_has_uncertainty(design)
    rep = build_report(design)
    ids = [s.id for s in rep.sections]
    assert "uncertainty" in ids, f"uncertainty section present with {UNCERTAIN}: {ids}"
    assert ids.index("uncertainty") == ids.index("margin") + 1, "right after the margin section"
    u = rep.payload["uncertainty"]
    assert u["samples"] == 1 << 10 and u["uncertain_inputs"] == ["scale"], u
    assert 0.0 <= u["stepout_probability"] <= 1.0
    assert "elapsed_s" not in u, "no run-to-run timings in the report's numbers"
    nominal = rep.payload["evaluate"]["margin_Nm"]
    assert u["nominal_margin_Nm"] == pytest.approx(nominal, rel=1e-9), (
        "the study's nominal margin is the evaluation's margin (same physics, same point; 1e-9)"
    )
    assert 'id="fig-uncertainty"' in rep.html and 'id="uncertainty"' in rep.html


@functools.cache
def _heating_context(sets: tuple[str, ...] = ()) -> Any:
    """(report context, coil analysis) of the built-in design with ``sets``: once per set of
    overrides in this module (the plain design's is read by four tests; nothing here edits
    either)."""
    from spiralcap.analysis.coils import analyse_coils, coils_payload
    from spiralcap.presentation import jsonable
    from spiralcap.report.sections._util import Context

    design = load_design(None, list(sets))
    analysis = analyse_coils(design)
    data = SimpleNamespace(design=design, heating=analysis.heating)
    return Context(data, {"coils": jsonable(coils_payload(analysis))}), analysis


@pytest.mark.parametrize("session_min", [None, 20.0])
def test_heating_curves_in_the_coils_section(session_min: float | None) -> None:
    from spiralcap.report.sections.coils import heating_blocks

    sets = [] if session_min is None else [f"operation.session_min={session_min}"]
    design = load_design(None, sets)
    ctx, analysis = _heating_context(tuple(sets))
    paragraph, block = heating_blocks(ctx)
    assert isinstance(paragraph, Paragraph) and isinstance(block, FigureBlock)
    assert block.id == "fig-heating"
    fig = _figure(block)
    ax = fig.axes[0]
    labels = [line.get_label() for line in ax.get_lines()]
    assert sum("hot spot" in s for s in labels) == 3 and sum("mean" in s for s in labels) == 3
    limit = [line for line in ax.get_lines() if line.get_label() == "hot-spot limit"]
    assert np.allclose(limit[0].get_ydata(), design["limits.coil_temperature_C"])
    session = [line for line in ax.get_lines() if line.get_label() == "end of session"]
    if session_min is None:
        assert session == [], "no session line in steady state"
        assert "steady state" in block.caption
    else:
        assert np.allclose(session[0].get_xdata(), session_min), "session end at its minutes"
        keys = {getattr(p, "key", None) for p in paragraph.parts}
        assert "coils.operating_point.session_s" in keys
        # the hot-spot curve at the end of the session is the JSON's session hot spot (1e-3:
        # the curve is sampled, the number exact)
        hot = max(analysis.operating, key=lambda a: a.hot_spot_temperature_C)
        curve = next(c for c in analysis.heating if c.axis == hot.axis)
        at_end = float(np.interp(60.0 * session_min, curve.time_s, curve.hot_spot_C))
        assert at_end == pytest.approx(hot.session_hot_spot_temperature_C, rel=1e-3), (
            "heating curve at the session end equals the reported end-of-session hot spot "
            "(lumped exponential, rel 1e-3)"
        )


@pytest.mark.parametrize("session_min", [None, 120.0])
def test_heating_shows_the_surface_limit_when_set(session_min: float | None) -> None:
    """Issue 19's touch limit in the heating section: with limits.surface_temperature_C the
    curves of each pair's hottest surface point and the limit are drawn, and the sentence gives
    the hottest surface (the JSON's number, steady or at the session's end) against the key."""
    from spiralcap.report.numbers import Num
    from spiralcap.report.sections.coils import heating_blocks

    sets = ["limits.surface_temperature_C=48"]
    sets += [] if session_min is None else [f"operation.session_min={session_min}"]
    ctx, analysis = _heating_context(tuple(sets))
    paragraph, block = heating_blocks(ctx)
    ax = _figure(block).axes[0]
    lines = {line.get_label(): line for line in ax.get_lines()}
    limit = lines["surface limit"]
    assert np.allclose(limit.get_ydata(), 48.0), "the touch limit at its °C"
    for curve in analysis.heating:
        drawn = lines[f"{curve.axis} pair hottest surface"]
        assert np.allclose(drawn.get_ydata(), curve.surface_max_C), "the hottest-surface curve"
    field = "surface_max_temperature_C" if session_min is None else (
        "session_surface_max_temperature_C"
    )  # fmt: skip
    keys = {p.key: p.value for p in paragraph.parts if isinstance(p, Num) and p.key}
    said = [v for k, v in keys.items() if k.endswith("." + field)]
    worst = max(ctx.value(f"coils.operating_point.axes.{a}.{field}") for a in "xyz")
    assert said == [worst], f"the sentence gives the hottest surface ({field}): {keys}"
    assert worst == pytest.approx(48.0, abs=1e-6), "the touch limit binds the built-in design"
    assert "limits.surface_temperature_C" in block.caption
    _plain, plain_block = heating_blocks(_heating_context()[0])
    assert "surface limit" not in [x.get_label() for x in _figure(plain_block).axes[0].get_lines()]


#: The coil table's row of h_c: at the surface temperature of the row above it (issue 26 a).
H_LABEL = "convection coefficient h_c (area-weighted, at the steady mean surface temperature)"


def test_sizing_table_shows_the_cooling_as_built() -> None:
    """Issue 19 in the report: the coil table carries each pair's hottest surface, effective
    convection coefficient and view factor to the room, tied to the ``coils --json`` numbers."""
    from spiralcap.report.numbers import Num
    from spiralcap.report.sections.coils import _sizing_table

    ctx, _ = _heating_context()
    rows = {str(r[0]): r for r in _sizing_table(ctx).rows}
    axes = ctx.value("coils.axes")
    for label, field in (
        ("steady hottest surface at the current limit", "surface_max_temperature_C"),
        (H_LABEL, "convection_coefficient_W_m2K"),
        ("view factor to the room (radiation leaving the coil set)", "radiation_view_factor"),
    ):  # fmt: skip
        cells = rows[label][2:]
        assert len(cells) == 3 and all(isinstance(c, Num) for c in cells), label
        for cell, ax in zip(cells, axes, strict=True):
            assert cell.key == f"coils.axes.{ax}.{field}", f"{label}: tied to the JSON field"
            assert cell.value == axes[ax][field], f"{label}: the coils --json number"
    h = [c.value for c in rows[H_LABEL][2:]]
    assert all(3.0 <= v <= 9.0 for v in h), f"natural convection 3-9 W/(m²·K) (issue 19): {h}"
    f = [c.value for c in rows["view factor to the room (radiation leaving the coil set)"][2:]]
    assert all(0.0 < v < 1.0 for v in f), f"nested packs see each other: view factor < 1 ({f})"


def test_margin_figure_draws_step_out_and_max_frequency() -> None:
    from optimize import evaluate, prepare
    from spiralcap.assemble import build_model
    from spiralcap.figures.api import margin_vs_frequency

    model = prepare(build_model(load_design()))
    ev = evaluate(model)
    assert not ev.step_out_beyond_search and not ev.max_frequency_beyond_search
    plot = margin_vs_frequency(model, ev)
    d = plot.drawn[0]
    assert d.step_out is not None and d.max_frequency is not None, "both frequencies drawn"
    assert np.allclose(d.step_out.get_xdata(), ev.step_out_frequency_hz)
    assert np.allclose(d.max_frequency.get_xdata(), ev.max_frequency_hz)
    # matplotlib names every custom dash "--"; the dash sequences themselves must differ
    assert d.step_out._unscaled_dash_pattern != d.max_frequency._unscaled_dash_pattern, (
        "the two lines differ in dash pattern (readable in greyscale)"
    )
    legend = [t.get_text() for t in plot.ax.get_legend().get_texts()]
    assert any("step-out at the operating field" in t for t in legend), legend
    assert any("max. frequency" in t and "limit" in t for t in legend), legend
    # independent check of what the dash-dot line marks: the curve (field re-maximised at every
    # frequency) crosses zero at the evaluation's max_frequency_hz, within one grid step
    f, m = d.line.get_xdata(), np.asarray(d.line.get_ydata(), float)
    if d.infeasible is not None:
        m = np.where(np.isfinite(m), m, np.asarray(d.infeasible.get_ydata(), float))
    i = int(np.nonzero(m <= 0)[0][0])
    root = f[i - 1] - m[i - 1] * (f[i] - f[i - 1]) / (m[i] - m[i - 1])
    assert abs(root - ev.max_frequency_hz) < f[1] - f[0], (
        f"margin curve crosses zero at {root:.4g} Hz, max_frequency_hz {ev.max_frequency_hz:.4g}"
        " (within one grid step)"
    )


def _flatten(table: dict[str, Any], prefix: str = "") -> dict[str, Any]:
    out: dict[str, Any] = {}
    for k, v in table.items():
        if isinstance(v, dict):
            out.update(_flatten(v, f"{prefix}{k}."))
        else:
            out[f"{prefix}{k}"] = v
    return out


def test_optimum_section_shows_the_changed_keys_of_the_design_file(tmp_path: Any) -> None:
    from optimize import optimize_design, prepare
    from spiralcap.assemble import build_model
    from spiralcap.assemble.system import optimum_design_toml
    from spiralcap.report.sections._util import Context
    from spiralcap.report.sections.optimum import design_file_blocks

    design = load_design()
    res = optimize_design(prepare(build_model(design)))
    assert res.status == "optimal"
    ctx = Context(SimpleNamespace(design=design, optimization=res), {})
    text, code = design_file_blocks(ctx)
    assert isinstance(code, Code)
    assert "spiralcap optimize DESIGN -o best.toml" in "".join(map(str, text.parts))
    shown = _flatten(tomllib.loads(code.text))
    assert set(shown) == {"capsule.spiral.helical_angle_deg", "operation.frequency_hz"}, shown
    # the written file holds exactly these values and the input's everywhere else
    path = tmp_path / "best.toml"
    path.write_text(optimum_design_toml(design, res), encoding="utf-8")
    best = load_design(path)
    for key in design:
        if key in shown:
            assert best[key] == shown[key], key
        else:
            assert best[key] == design[key], f"{key} unchanged in the written file"
