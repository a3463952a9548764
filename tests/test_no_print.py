"""Library functions do not print (issue 38): the four domain packages and ``spiralcap.export``
name neither ``print`` nor ``sys.stdout``/``sys.stderr``; progress goes through a ``progress``
callback (``optimize.discrete.relax`` and ``rank`` default to saying nothing). Read from the
source with :mod:`ast`, so the test imports nothing it checks."""

from __future__ import annotations

import ast
import inspect
import typing
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("coils", "capsule", "torque_model", "optimize")
FILES = [
    *sorted(p for pkg in PACKAGES for p in (ROOT / pkg).rglob("*.py")),
    ROOT / "spiralcap" / "export.py",
]


def _prints(path: Path) -> list[str]:
    """Where ``path`` names ``print`` or ``sys.stdout``/``sys.stderr``: 'name at line'."""
    tree = ast.parse(path.read_text(), filename=str(path))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and node.id == "print":
            found.append(f"print at {node.lineno}")
        elif isinstance(node, ast.Attribute) and node.attr in ("stdout", "stderr"):
            if isinstance(node.value, ast.Name) and node.value.id == "sys":
                found.append(f"sys.{node.attr} at {node.lineno}")
    return found


def test_the_files_are_found() -> None:
    assert len(FILES) > 40 and all(p.exists() for p in FILES), "the domain's sources, >40 files"


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_print_in_the_library(path: Path) -> None:
    found = _prints(path)
    assert found == [], (
        f"{path.relative_to(ROOT)}: {found}; a library function reports progress through its "
        "progress callback (issue 38 item 5)"
    )


def test_the_check_sees_print(tmp_path: Path) -> None:
    bad = tmp_path / "bad.py"
    bad.write_text("import sys\ndef f(say=print):\n    sys.stderr.write('x')\n")
    assert _prints(bad) == ["print at 2", "sys.stderr at 3"], "the AST scan finds both forms"


def test_relax_and_rank_say_nothing_by_default() -> None:
    from optimize import discrete

    for fn in (discrete.relax, discrete.rank):
        default = inspect.signature(fn).parameters["progress"].default
        assert default is None, f"{fn.__name__}'s progress defaults to None (no printing)"
    assert typing.Protocol in discrete.Executor.__mro__, "Executor is a typing.Protocol"
