"""``spiralcap ... --json`` outputs that several test modules read, each run once per test
process (a ``functools.cache``: an xdist worker running two of these modules runs the command
once). Each call parses the stored text again, so every caller gets its own copy to edit."""

from __future__ import annotations

import contextlib
import functools
import io
import json
from typing import Any


@functools.cache
def _stdout(argv: tuple[str, ...]) -> str:
    from spiralcap.cli import main

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        status = main([*argv, "--json"])
    assert status == 0, f"spiralcap {' '.join(argv)} --json exited {status}"
    return buf.getvalue()


def cli_json(*argv: str) -> dict[str, Any]:
    """``spiralcap *argv --json`` parsed (exit 0 asserted): a fresh dict on every call."""
    return json.loads(_stdout(tuple(argv)))
