"""Fixtures shared by the test modules."""

from __future__ import annotations

import importlib
import types
from collections.abc import Callable
from pathlib import Path

import pytest

import coils
from spiralcap import cli


def pytest_configure(config: pytest.Config) -> None:
    """Once, in the process that starts the test workers: the package's sources compiled to
    bytecode. The CLI tests start about 150 fresh interpreters; where the environment forbids
    writing bytecode (PYTHONDONTWRITEBYTECODE, as on CI's runner) each compiled every module it
    imports again (0.1-0.3 s of each). They read this cache (checked against the sources'
    times and sizes) and write none."""
    if hasattr(config, "workerinput"):  # an xdist worker: the controller did it
        return
    import compileall

    root = Path(__file__).resolve().parents[1]
    for package in ("spiralcap", "optimize", "coils", "capsule", "torque_model", "examples"):
        compileall.compile_dir(root / package, quiet=2)


@pytest.fixture
def run_cli() -> Callable[[list[str] | None], int]:
    """``spiralcap.cli.main``: ``run_cli(["coils", "--json"])`` returns the exit status."""
    return cli.main


@pytest.fixture
def assemble() -> types.ModuleType:
    """``spiralcap.assemble``, the design -> domain-object builders."""
    return importlib.import_module("spiralcap.assemble")


@pytest.fixture
def build_coils() -> Callable:
    """``spiralcap.assemble.coils.build_coils``."""
    return importlib.import_module("spiralcap.assemble.coils").build_coils


@pytest.fixture(scope="session")
def nested_system() -> coils.ThreeAxisHelmholtz:
    """The built-in design's coils: nested pairs of radius 0.4, 0.35, 0.3 m and 400, 350, 300
    turns (thin 2.5 mm wire, Helmholtz spacing)."""
    return coils.ThreeAxisHelmholtz(
        coils.HelmholtzPair(0.4, 400, "x"),
        coils.HelmholtzPair(0.35, 350, "y"),
        coils.HelmholtzPair(0.3, 300, "z"),
    )


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    """A run that collected no test fails (exit 1), never exits 5: CI must not pass, or be
    mistaken for a configuration problem, because the tests were not found."""
    if exitstatus == pytest.ExitCode.NO_TESTS_COLLECTED:
        session.exitstatus = pytest.ExitCode.TESTS_FAILED
