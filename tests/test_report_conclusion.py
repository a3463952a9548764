"""The report's conclusion is computed from the results (issue #20 item 7), not canned text."""

from __future__ import annotations

import copy
import functools
import math
import re
from typing import Any

import pytest
from _td_cli import cli_json

from spiralcap.design import load_design
from spiralcap.report.document import Paragraph, Section
from spiralcap.report.numbers import Num, fmt
from spiralcap.report.sections import conclusion, summary
from spiralcap.report.sections._util import Context


@functools.cache
def _payload(sets: tuple[str, ...]) -> dict[str, Any]:
    """``spiralcap evaluate/optimize --json`` of the built-in design with ``sets`` and the
    conclusion computed from them: once per set of overrides in this module (the plain built-in
    design is read by five tests)."""
    args = [a for s in sets for a in ("--set", s)]
    # (``_td_cli``: the built-in design's are shared with test_report.py in one process)
    ev, opt = cli_json("evaluate", *args), cli_json("optimize", *args)
    design = load_design(None, list(sets))
    return {
        "evaluate": ev,
        "optimize": opt,
        "conclusion": conclusion.conclusion_payload(ev, opt, design, None),
    }


def _context(*sets: str) -> tuple[Context, dict[str, Any]]:
    payload = copy.deepcopy(_payload(sets))  # each test its own copy: none sees another's edits
    return Context(None, payload), payload


def _text(section: Section) -> str:
    out = []
    for b in section.blocks:
        if isinstance(b, Paragraph):
            out.append(
                "".join(
                    p.text if isinstance(p, Num) else getattr(p, "text", str(p)) for p in b.parts
                )
            )
    return "\n".join(out)


def test_conclusion_numbers_from_independent_formulas() -> None:
    ctx, payload = _context()
    c, ev = payload["conclusion"], payload["evaluate"]
    x = c["exposure"]
    f, b0 = ev["frequency_hz"], ev["field_amplitude_T"]
    assert f < 8
    assert x["occupational_level_T"] == pytest.approx(0.2 / f**2, rel=1e-12), (
        "ICNIRP 2010 Table 3, occupational 1-8 Hz: 0.2/f^2 T"
    )
    assert x["public_level_T"] == pytest.approx(0.04 / f**2, rel=1e-12), (
        "ICNIRP 2010 Table 4, general public 1-8 Hz: 4e-2/f^2 T"
    )
    assert x["field_rate_T_per_s"] == pytest.approx(2 * math.pi * f * b0, rel=1e-12), (
        "a vector of constant length B0 turning at omega changes at omega B0"
    )
    assert c["tissue_torque_headroom"] == pytest.approx(
        ev["margin_Nm"] / ev["resistive_torque_Nm"], rel=1e-12
    )
    hs = [h["headroom"] for h in c["checks_by_headroom"]]
    assert hs == sorted(hs), "checks ordered nearest-to-failing first"
    text = _text(conclusion.build(ctx))
    assert "As entered, yes" in text
    assert "occupational" in text and "operator" in text and "patient" in text
    assert "IEC 60601-2-33" in text and "medical exposure" in text


def test_conclusion_follows_the_design() -> None:
    ctx, payload = _context("operation.frequency_hz=6")
    text = _text(conclusion.build(ctx))
    assert payload["evaluate"]["feasible"] is False
    assert "As entered, no" in text and "Fix what fails" in text, text
    failing = [c["key"] for c in payload["evaluate"]["checks"] if not c["ok"]]
    assert all(k in text for k in failing), "every failing check named by its key"
    ok_ctx, _ = _context()
    assert _text(conclusion.build(ok_ctx)) != text


def test_summary_leads_with_the_design_as_entered() -> None:
    ctx, _ = _context()
    section = summary.build(ctx)
    first = section.blocks[0]
    assert isinstance(first, Paragraph) and "As entered" in str(first.parts[0])
    rest = [b for b in section.blocks[1:] if not (isinstance(b, Paragraph) and b.kind == "alert")]
    warned = [b for b in section.blocks[1:3] if isinstance(b, Paragraph) and b.kind == "alert"]
    assert all("Warning" in str(b.parts[0]) for b in warned), "only warnings sit between"
    second = rest[0]
    assert isinstance(second, Paragraph) and "Proposed change" in str(second.parts[0])


def test_conclusion_numbers_resolve_in_the_payload() -> None:
    ctx, payload = _context()
    from spiralcap.report.numbers import lookup

    for b in conclusion.build(ctx).blocks:
        for p in getattr(b, "parts", []):
            if isinstance(p, Num) and p.key is not None:
                value = lookup(payload, p.key)
                shown = value * p.scale if p.scale != 1.0 else value
                assert p.text == fmt(shown), p.key
    assert not re.search(r"e-1\d %", _text(conclusion.build(ctx))), "no rounding noise shown"


def test_sized_hardware_is_part_of_the_proposed_change() -> None:
    """A design with freed hardware: the summary and the conclusion name each sized key as
    entered and as sized (the values the optimum's JSON holds), not 'the same hardware'."""
    from types import SimpleNamespace

    sets = (
        "optimize.objective=power",
        "requirements.min_safety_factor=2",
        "optimize.free.coils.x.turns=[50, 2000]",
        "optimize.free.coils.x.wire_diameter_mm=[0.5, 5]",
        # one start: the naming of the sized keys is under test, not the multi-start search
        # (4 starts size the same 542 turns of 2.8 mm wire)
        "optimize.starts=1",
    )
    _, payload = _context(*sets)
    ctx = Context(SimpleNamespace(design=load_design(None, list(sets))), payload)
    sized = payload["optimize"]["hardware"]["discrete"]
    assert set(sized) == {"coils.x.turns", "coils.x.wire_diameter_mm"}
    expected = [
        f"coils.x.turns 400 → {sized['coils.x.turns']:.6g}",  # built-in: 400 turns, 3.0 mm wire
        f"coils.x.wire_diameter_mm 3 → {sized['coils.x.wire_diameter_mm']:.6g}",
    ]
    assert sized["coils.x.turns"] != 400, "the least-power x pair is not the built-in one"
    summary_text, conclusion_text = _text(summary.build(ctx)), _text(conclusion.build(ctx))
    assert "same hardware" not in summary_text, summary_text
    for change in expected:
        assert change in summary_text and change in conclusion_text, (change, conclusion_text)
    assert "Adopt the proposed operating point and hardware" in conclusion_text
    assert "inside the same hardware" in _text(summary.build(_context()[0]))
