"""Fixtures shared by the test modules."""

from __future__ import annotations

import importlib
import types
from collections.abc import Callable

import pytest

import coils
from spiralcap import cli


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
