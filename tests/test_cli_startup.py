"""Fast start (issue 13): a command loads its own module and what it uses, nothing heavier.

Run in a fresh interpreter so the test suite's own imports do not hide what the CLI loads.
Timings live in ``benchmarks/bench_startup.py``; here only what is imported.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from spiralcap import cli

ROOT = Path(__file__).resolve().parents[1]


def _modules_after(code: str) -> set[str]:
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    script = f"{code}\nimport json, sys\nprint(json.dumps(sorted(sys.modules)), file=sys.stderr)"
    run = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, env=env, cwd=ROOT
    )
    assert run.returncode == 0, run.stderr
    return set(json.loads(run.stderr.strip().splitlines()[-1]))


def test_coils_json_loads_only_the_coils_command_and_no_heavy_library() -> None:
    loaded = _modules_after(
        "import contextlib, io\nfrom spiralcap import cli\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n    cli.main(['coils', '--json'])"
    )
    commands = {m for m in loaded if m.startswith("spiralcap.commands.")}
    assert commands <= {
        "spiralcap.commands._common",
        "spiralcap.commands._plot",
        "spiralcap.commands.coils",
    }, f"only the coils command's modules: {sorted(commands)}"
    heavy = ("matplotlib", "spiralcap.report", "spiralcap.figures", "scipy.optimize", "scipy.stats")
    assert not {m for m in loaded if m.startswith(heavy)}, "no plotting, report or scipy solvers"


def test_parser_for_one_command_parses_as_the_full_parser() -> None:
    argv = ["coils", "--json", "--set", "coils.x.turns=300", "a.toml"]
    full = vars(cli.build_parser().parse_args(argv))
    one = vars(cli.build_parser("coils").parse_args(argv))
    assert full == one, "same namespace (and the same command module) either way"
    assert set(cli.build_parser("coils")._subparsers._group_actions[0].choices) == set(  # type: ignore[union-attr]
        cli.COMMANDS
    ), "every command is still listed in --help"
