"""`spiralcap report` inputs and outcomes that need no full report run (cheap, in-process)."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest

from spiralcap.cli import main
from spiralcap.commands import report as report_cmd


def _run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main(argv)
    return status, out.getvalue(), err.getvalue()


@pytest.mark.parametrize(
    ("extra", "needle"),
    [
        (["--set", "coils.x.turnz=3"], "coils.x.turnz"),
        (["--set", "limits.power_W=-5"], "limits.power_W"),
        (["--set", "optimize.frequency_min_hz=9"], "optimize.frequency_max_hz"),
        (["--workers", "0"], "--workers"),
        (["--pdf", "report.txt"], "--pdf"),
        (["no-such-design.toml"], "no-such-design.toml"),
    ],
)
def test_bad_input_exits_2_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, extra: list[str], needle: str
) -> None:
    monkeypatch.chdir(tmp_path)
    status, _, err = _run(["report", *extra, "-o", "report.html"])
    assert status == 2, f"bad input exits 2 (got {status}; {err})"
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("spiralcap report: error:"), err
    assert needle in lines[0], f"the message names {needle}: {lines[0]}"
    assert list(tmp_path.rglob("*")) == [], "nothing written"


@pytest.mark.parametrize("output", ["report.txt", "report", "folder.html"])
def test_output_path_must_be_an_html_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, output: str
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "folder.html").mkdir()
    status, _, err = _run(["report", "-o", output])
    assert status == 2 and "-o" in err, err


def test_output_may_not_overwrite_the_design_file(tmp_path: Path) -> None:
    design = tmp_path / "d.html"
    design.write_text("[limits]\npower_W = 1000.0\n", encoding="utf-8")
    before = design.read_bytes()
    status, _, err = _run(["report", str(design), "-o", str(design)])
    assert status == 2 and "design file" in err, err
    assert design.read_bytes() == before, "the design file is untouched"


def test_pdf_and_html_must_differ(tmp_path: Path) -> None:
    with pytest.raises(Exception, match="--pdf"):
        report_cmd.check_output_paths(str(tmp_path / "r.html"), str(tmp_path / "r.html"), None)


def test_infeasible_design_writes_the_report_and_exits_3(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The exit status mirrors `spiralcap optimize` (3); the file is still written."""
    fake = SimpleNamespace(
        html="<!DOCTYPE html><p>NO FEASIBLE DESIGN</p>",
        pdf=b"%PDF-1.4",
        page_count=1,
        figure_count=0,
        feasible=False,
        status_message="infeasible: requirements.min_speed_mm_s",
    )
    import spiralcap.report

    monkeypatch.setattr(spiralcap.report, "build_report", lambda *a, **k: fake)
    out = tmp_path / "r.html"
    status, _, err = _run(["report", "-o", str(out), "--pdf", str(tmp_path / "r.pdf")])
    assert status == report_cmd.EXIT_INFEASIBLE == 3
    assert "no feasible design" in err and "min_speed" in err
    assert out.read_text(encoding="utf-8") == fake.html
    assert (tmp_path / "r.pdf").read_bytes() == fake.pdf


def _json(argv: list[str]) -> dict[str, Any]:
    status, out, _ = _run(argv)
    assert status in (0, 3)
    return json.loads(out)


def test_infeasible_sections_say_so_plainly() -> None:
    """Summary and optimum of an infeasible optimisation, from the CLI's own JSON."""
    from spiralcap.report.html import render_html
    from spiralcap.report.sections import Context, optimum, summary

    overrides = ["--set", "requirements.min_speed_mm_s=50"]
    payload = {
        "evaluate": _json(["evaluate", "--json", *overrides]),
        "optimize": _json(["optimize", "--json", *overrides]),
    }
    assert payload["optimize"]["status"] == "infeasible", "50 mm/s is out of reach"
    ctx = Context(SimpleNamespace(optimize_json=payload["optimize"]), payload)
    sections = [summary.build(ctx), optimum.build(ctx)]
    from spiralcap.report.document import FrontMatter

    front = FrontMatter("t", "", "", "", "today", "built-in", "0" * 64, "0")
    page = render_html(front, sections, payload)
    assert "NO FEASIBLE DESIGN" in page and "Infeasible" in page
    assert 'id="shortfalls"' in page and "requirements.min_speed_mm_s" in page
    assert 'data-key="optimize.shortfalls.0.best"' in page
    assert "data:image/svg+xml;base64," in page, "the utilisation figure still renders"
