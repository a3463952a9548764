"""The import graph of the project's own modules: no cycles, and the layers of CONTRIBUTING.md.

Every ``import`` statement counts, at module level or inside a function (a function-level
import is still a dependency, only a later one). Read from the source with :mod:`ast`, so the
test imports nothing it checks.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("spiralcap", "coils", "capsule", "torque_model", "optimize")
DOMAIN = ("coils", "capsule", "torque_model", "optimize")
#: What a domain package may import from the application package (CONTRIBUTING.md, Layout).
CORE = {
    "spiralcap",
    "spiralcap.core",
    "spiralcap.core.backend",
    "spiralcap.core.constants",
    "spiralcap.core.errors",
    "spiralcap.core.checks",
}


def _modules() -> dict[str, Path]:
    out = {}
    for pkg in PACKAGES:
        for path in (ROOT / pkg).rglob("*.py"):
            parts = path.relative_to(ROOT).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            out[name] = path
    return out


MODULES = _modules()


def _package_of(name: str) -> str:
    path = MODULES[name]
    return name if path.name == "__init__.py" else name.rpartition(".")[0]


def _imports(name: str) -> set[str]:
    """The project modules ``name`` imports (submodules named in ``from a import b`` count)."""
    tree = ast.parse(MODULES[name].read_text(), filename=str(MODULES[name]))
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = _package_of(name).split(".")
                anchor = anchor[: len(anchor) - (node.level - 1)]
                base = ".".join([*anchor, base] if base else anchor)
            targets = []
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                targets.append(sub if sub in MODULES else base)
        else:
            continue
        for target in targets:
            while target and target not in MODULES:  # "a.b.c" where only "a.b" is ours
                target = target.rpartition(".")[0]
            if target and target != name:
                found.add(target)
    return found


@functools.cache
def _graph() -> dict[str, set[str]]:
    """Module -> the project modules it imports (parsed when a test first asks)."""
    return {name: _imports(name) for name in MODULES}


def _cycles() -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(_graph()[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(_graph()):
        if v not in index:
            visit(v)
    return out


def test_graph_is_read() -> None:
    assert "optimize.physics" in _graph() and "torque_model" in _graph()["optimize.physics"], (
        "the parser sees 'import torque_model as tm' in optimize/physics.py"
    )
    assert "torque_model.presets" in _graph()["torque_model"], "package __init__ re-exports count"


def test_no_import_cycles() -> None:
    cycles = _cycles()
    assert not cycles, f"import cycles (module-level or inside functions): {cycles}"


@pytest.mark.parametrize("package", DOMAIN)
def test_domain_packages_import_only_the_core_of_spiralcap(package: str) -> None:
    leaks = {
        f"{name} -> {target}"
        for name, targets in _graph().items()
        if name == package or name.startswith(package + ".")
        for target in targets
        if target.split(".")[0] == "spiralcap" and target not in CORE
    }
    assert not leaks, f"{package} imports the spiralcap application beyond its core: {leaks}"


def test_report_imports_nothing_from_commands() -> None:
    leaks = {
        f"{name} -> {target}"
        for name, targets in _graph().items()
        if name.startswith("spiralcap.report")
        for target in targets
        if target.startswith("spiralcap.commands")
    }
    assert not leaks, f"the report imports the CLI: {leaks}"


def test_no_design_file_key_inside_optimize() -> None:
    """optimize/ names its rows and checks; the application maps them to design keys
    (spiralcap.assemble.system.constraint_key / check_key), so no key string lives there."""
    import ast

    from spiralcap.schema import KEYS

    tables = {k.split(".", 1)[0] + "." for k in KEYS}
    found = []
    for path in sorted((ROOT / "optimize").glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                text = node.value
                if " " not in text and any(text.startswith(t) for t in tables) and text in KEYS:
                    found.append(f"{path.name}:{node.lineno}: {text}")
    assert not found, f"design-file keys inside optimize/ (issue 13): {found}"
