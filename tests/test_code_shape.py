"""Functions a newcomer reads on one screen (CONTRIBUTING.md): cyclomatic complexity at most 20
in the four domain packages and the application (figure drawing aside), and no function of
``optimize/`` over 100 lines. Measured by radon (the McCabe count it shares with flake8's
mccabe), on the source, without importing it."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

radon_complexity = pytest.importorskip("radon.complexity")

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("coils", "capsule", "torque_model", "optimize", "spiralcap")
#: Figure drawing: one function lays out one figure, panel by panel (CONTRIBUTING.md).
DRAWING = ("spiralcap/figures/",)
MAX_COMPLEXITY = 20
MAX_LINES = 100


def _sources() -> list[Path]:
    return sorted(p for pkg in PACKAGES for p in (ROOT / pkg).rglob("*.py"))


def test_no_function_above_complexity_20() -> None:
    over = []
    for path in _sources():
        rel = path.relative_to(ROOT).as_posix()
        if rel.startswith(DRAWING):
            continue
        for block in radon_complexity.cc_visit(path.read_text()):
            if block.complexity > MAX_COMPLEXITY:
                over.append(f"{rel}:{block.lineno} {block.name} ({block.complexity})")
    assert not over, f"cyclomatic complexity above {MAX_COMPLEXITY} (radon): {over}"


def test_no_function_in_optimize_over_100_lines() -> None:
    long = []
    for path in sorted((ROOT / "optimize").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                lines = node.end_lineno - node.lineno + 1  # type: ignore[operator]
                if lines > MAX_LINES:
                    long.append(f"{path.name}:{node.lineno} {node.name} ({lines} lines)")
    assert not long, f"functions of optimize/ over {MAX_LINES} lines: {long}"
