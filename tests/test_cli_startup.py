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
    # scipy.optimize is allowed: its brentq finds the field caps (issue 38 retired an own copy
    # that saved its import, 17 % of this command's CPU: under the 20 % a speed piece must save)
    heavy = ("matplotlib", "spiralcap.report", "spiralcap.figures", "scipy.stats")
    assert not {m for m in loaded if m.startswith(heavy)}, "no plotting, report or scipy.stats"


def test_parser_for_one_command_parses_as_the_full_parser() -> None:
    argv = ["coils", "--json", "--set", "coils.x.turns=300", "a.toml"]
    full = vars(cli.build_parser().parse_args(argv))
    one = vars(cli.build_parser("coils").parse_args(argv))
    assert full == one, "same namespace (and the same command module) either way"
    assert set(cli.build_parser("coils")._subparsers._group_actions[0].choices) == set(  # type: ignore[union-attr]
        cli.COMMANDS
    ), "every command is still listed in --help"


def _console(argv: list[str], env_extra: dict[str, str]) -> subprocess.CompletedProcess[str]:
    """Run the installed command's entry point (``spiralcap.cli.console``) in a fresh process;
    it prints the BLAS thread setting it ran with on stderr at exit."""
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.pop("OPENBLAS_NUM_THREADS", None)
    env.update(env_extra)
    script = (
        "import atexit, os, sys\n"
        f"sys.argv = ['spiralcap', *{argv!r}]\n"
        "atexit.register(lambda: print('BLAS', os.environ.get('OPENBLAS_NUM_THREADS'), "
        "file=sys.stderr))\n"
        "from spiralcap import cli\ncli.console()"
    )
    return subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, env=env, cwd=ROOT
    )


def test_console_runs_a_command_single_threaded_unless_told_otherwise() -> None:
    run = _console(["coils", "--json"], {})
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout)["spiralcap_version"], "the command's JSON, whole"
    assert "BLAS 1" in run.stderr, "the spiralcap command sets OPENBLAS_NUM_THREADS=1"
    kept = _console(["coils", "--json"], {"OPENBLAS_NUM_THREADS": "3"})
    assert kept.returncode == 0 and "BLAS 3" in kept.stderr, "a value the user set is kept"


def test_console_bad_input_is_one_line_and_exit_2() -> None:
    run = _console(["evaluate", "--set", "limits.power_W=-5"], {})
    assert run.returncode == 2, run.stderr
    lines = [x for x in run.stderr.splitlines() if not x.startswith("BLAS")]
    assert len(lines) == 1 and "limits.power_W" in lines[0], run.stderr
