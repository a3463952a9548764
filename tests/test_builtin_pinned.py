"""The built-in design's ``evaluate``, ``coils`` and ``optimize`` JSON, pinned to 1e-9.

``tests/data/builtin_pinned.json`` holds the outputs of ``spiralcap evaluate --json``,
``spiralcap coils --json`` and ``spiralcap optimize --json`` on the built-in design as computed
before the refactors of the batch field, the uniform-region search, the capsule geometry of the
torque model and the identification's Jacobian, minus the wall time and IPOPT iteration count. The
refactors must not change any number: every pinned leaf must still be there and agree to 1e-9
relative (1e-15 absolute floor for exact zeros).

A change of physics made on purpose updates the file; regenerate it with
``python tests/test_builtin_pinned.py`` and say in the commit which numbers moved and why.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Any

import pytest

from spiralcap import cli

PINNED = Path(__file__).parent / "data" / "builtin_pinned.json"
COMMANDS = ("evaluate", "coils", "optimize")
UNPINNED = ("solve_time_s", "iterations")
REL, ABS = 1e-9, 1e-15


def _run(command: str, capsys: Any | None = None) -> dict[str, Any]:
    if capsys is None:  # regeneration from the command line
        import contextlib
        import io

        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            assert cli.main([command, "--json"]) == 0
        text = buf.getvalue()
    else:
        capsys.readouterr()
        assert cli.main([command, "--json"]) == 0, f"spiralcap {command} --json exits 0"
        text = capsys.readouterr().out
    out = json.loads(text)
    for key in UNPINNED:
        out.pop(key, None)
    return out


def _leaves(value: Any, path: str = "") -> dict[str, Any]:
    if isinstance(value, dict):
        out: dict[str, Any] = {}
        for k, v in value.items():
            out.update(_leaves(v, f"{path}.{k}" if path else k))
        return out
    if isinstance(value, list):
        out = {}
        for i, v in enumerate(value):
            out.update(_leaves(v, f"{path}[{i}]"))
        return out
    return {path: value}


@pytest.mark.parametrize("command", COMMANDS)
def test_builtin_design_unchanged(command: str, capsys: pytest.CaptureFixture[str]) -> None:
    pinned = _leaves(json.loads(PINNED.read_text())[command])
    now = _leaves(_run(command, capsys))
    missing = sorted(set(pinned) - set(now))
    assert not missing, f"{command}: pinned outputs no longer reported: {missing}"
    for path, old in pinned.items():
        new = now[path]
        if isinstance(old, float) and isinstance(new, (int, float)):
            assert math.isclose(new, old, rel_tol=REL, abs_tol=ABS), (
                f"{command} {path}: {new!r} != pinned {old!r} (rel {REL}, abs {ABS}; "
                "pinned before the refactors)"
            )
        else:
            assert new == old, f"{command} {path}: {new!r} != pinned {old!r}"


if __name__ == "__main__":  # regenerate the pinned file
    PINNED.write_text(json.dumps({c: _run(c) for c in COMMANDS}, indent=1, sort_keys=True) + "\n")
    print(f"wrote {PINNED}", file=sys.stderr)
