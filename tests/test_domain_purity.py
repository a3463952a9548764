"""The four domain packages know nothing of processes, pids, signals or threads (issue 27).

Where work runs is the application's choice (``spiralcap.parallel``): a domain function takes an
executor-shaped argument (``submit``, ``map``) or nothing. Read from the source with :mod:`ast`
(imports inside functions included), so the test imports nothing it checks.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOMAIN = ("coils", "capsule", "torque_model", "optimize")
#: Modules that start, name or signal processes and threads.
FORBIDDEN_MODULES = {
    "_thread",
    "asyncio",
    "concurrent",
    "multiprocessing",
    "signal",
    "subprocess",
    "threading",
}
#: ``os`` functions about processes (fork, pids, signals, cores).
FORBIDDEN_OS = {
    "cpu_count",
    "fork",
    "forkpty",
    "getpid",
    "getppid",
    "kill",
    "killpg",
    "popen",
    "register_at_fork",
    "sched_getaffinity",
    "spawnl",
    "spawnv",
    "system",
    "wait",
    "waitpid",
}
FILES = sorted(p for pkg in DOMAIN for p in (ROOT / pkg).rglob("*.py"))


def _uses(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(), filename=str(path))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [a.name for a in node.names if a.name.split(".")[0] in FORBIDDEN_MODULES]
        elif isinstance(node, ast.ImportFrom) and node.module:
            if node.module.split(".")[0] in FORBIDDEN_MODULES:
                found.append(node.module)
            if node.module == "os":
                found += [f"os.{a.name}" for a in node.names if a.name in FORBIDDEN_OS]
        elif isinstance(node, ast.Attribute) and node.attr in FORBIDDEN_OS:
            if isinstance(node.value, ast.Name) and node.value.id == "os":
                found.append(f"os.{node.attr}")
    return found


def test_the_domain_files_are_found() -> None:
    assert len(FILES) > 40 and all(any(p.parent.name == d for p in FILES) for d in DOMAIN)


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_process_pid_signal_or_thread_in_the_domain(path: Path) -> None:
    used = _uses(path)
    assert used == [], (
        f"{path.relative_to(ROOT)} uses {used}: domain packages take an executor argument "
        "and leave processes, pids, signals and threads to the application (spiralcap.parallel)"
    )


def test_the_check_sees_what_it_forbids(tmp_path: Path) -> None:
    bad = tmp_path / "bad.py"
    bad.write_text(
        "import os\nfrom concurrent.futures import ThreadPoolExecutor\n"
        "def f():\n    import multiprocessing\n    return os.getpid(), os.fork\n"
    )
    assert sorted(_uses(bad)) == ["concurrent.futures", "multiprocessing", "os.fork", "os.getpid"]
