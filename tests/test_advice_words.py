"""Advice with content: no 'x → x', a search ceiling said as 'above N', a bound that binds only
where the solution sits on it."""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

from test_report_conclusion import _context, _text

from optimize import BindingLimit
from spiralcap.cli import main
from spiralcap.presentation import ON_BOUND_RTOL, binding, on_bound
from spiralcap.report.sections import summary


def test_a_bound_binds_only_when_the_solution_sits_on_it() -> None:
    assert not on_bound(104.8, 100.0), "104.8 turns is not on a bound of 100 turns"
    assert on_bound(100.0 * (1 + 1e-8), 100.0), "IPOPT's tolerance on an active row"
    assert not on_bound(100.0 * (1 + 2 * ON_BOUND_RTOL), 100.0)
    rows = (
        BindingLimit("turns_x", "1", 104.8, 100.0, 0.5),
        BindingLimit("hot_spot_y", "K", 65.0, 65.0, 0.02),
    )
    assert [b.name for b in binding(rows)] == ["hot_spot_y"]
    assert binding([{"value": 104.8, "allowed": 100.0}]) == ()


def test_a_design_at_its_optimum_is_told_so_in_one_sentence() -> None:
    opt = _context()[1]["optimize"]  # spiralcap optimize --json, shared with the line below
    at = (
        f"capsule.spiral.helical_angle_deg={opt['helical_angle_deg']!r}",
        f"operation.frequency_hz={opt['frequency_hz']!r}",
    )
    ctx, _ = _context(*at)
    text = _text(summary.build(ctx))
    line = next(t for t in text.splitlines() if t.startswith("What to change first."))
    assert "already at its optimum" in line and "→" not in line, line
    moved, _ = _context()
    line = next(
        t for t in _text(summary.build(moved)).splitlines() if t.startswith("What to change")
    )
    assert "helical angle 10 → " in line and "rotation 2 → " in line, line  # no units in _text


def test_compare_says_a_search_ceiling_as_above(tmp_path: Path) -> None:
    design = tmp_path / "strong.toml"
    design.write_text(
        "[tissue]\nscale = 0.1\n[capsule]\nlength_mm = 30\n"
        "[capsule.magnet]\ndiameter_mm = 9\nlength_mm = 20\n"
    )
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["compare", "builtin", str(design)]) == 0
    rows = [r for r in out.getvalue().splitlines() if "step-out frequency" in r]
    assert rows and all(r.rstrip().endswith("above 200") for r in rows), rows
    assert not any("+19" in r for r in rows), "no difference against a ceiling"
