"""``spiralcap report`` of designs whose coil pairs run away thermally at the current limit
(issue 22): the report is written and says so, with no traceback (as a process: the exit status
and stderr are the promise)."""

from __future__ import annotations

import subprocess
from pathlib import Path

import html5lib
import pytest
from proc_util import SPIRALCAP


@pytest.mark.slow
@pytest.mark.parametrize(
    ("setting", "pairs", "statuses"),
    [
        ("coils.x.wire_diameter_mm=0.05", "the x pair", (0, 3)),  # infeasible too: exit 3
        ("limits.current_A=1000", "the x, y, z pairs", (0,)),
    ],
)
def test_report_says_a_pair_runs_away(
    tmp_path: Path, setting: str, pairs: str, statuses: tuple[int, ...]
) -> None:
    proc = subprocess.run(
        [*SPIRALCAP, "report", "--set", setting, "-o", "r.html", "--workers", "1"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert proc.returncode in statuses, proc.stderr[-2000:]
    assert "Traceback" not in proc.stderr, proc.stderr
    doc = html5lib.parse(
        (tmp_path / "r.html").read_text(encoding="utf-8"),
        treebuilder="etree",
        namespaceHTMLElements=False,
    )
    text = " ".join(" ".join(p.itertext()) for p in doc.iter("p"))
    text = " ".join(text.split())
    assert "Thermal runaway" in text, "the coil section names the runaway"
    assert f"limit (limits.current_A) {pairs} would run away thermally" in text, text[:400]
