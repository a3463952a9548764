"""Fixtures shared by the test modules."""

from __future__ import annotations

import contextlib
import importlib
import io
import os
import sys
import types
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

# As the ``spiralcap`` console does (spiralcap.cli.console): one BLAS thread, set before numpy is
# first imported. The in-process tests run the commands through ``cli.main``, which does not set
# it; with OpenBLAS's default threads each xdist worker's small matrix calls spin a second thread
# after every call, on a machine whose cores the workers already fill.
for _var in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import pytest  # noqa: E402

import coils  # noqa: E402
from spiralcap import cli  # noqa: E402


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


#: Modules whose tests take longest or wait longest (full reports, Dask clusters, signals sent
#: seconds in), collected first in this order. pytest-xdist's worksteal gives each worker a
#: contiguous half of the collection and lets an idle worker take tests from the end of the
#: other's: with the long tests first, both workers end on short ones instead of one finishing a
#: 10-second test while the other idles. The signal tests come after the other long modules,
#: never in a run's first seconds while the other worker is still starting up: they time how
#: fast a command answers SIGTERM, and the start-up is the busiest moment of the run.
_LONG_FIRST = (
    "test_uncertainty_cli.py",
    "test_report_runaway.py",
    "test_report_injection.py",
    "test_report_layout.py",
    "test_report.py",  # after the layout check: the built-in report shared, on one worker
    "test_dask_no_workers.py",
    "test_sizing_speed.py",
    "test_signals.py",
)


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """The tests of :data:`_LONG_FIRST` first, in its order; the rest as collected."""

    def rank(item: pytest.Item) -> int:
        name = item.path.name
        return _LONG_FIRST.index(name) if name in _LONG_FIRST else len(_LONG_FIRST)

    items.sort(key=rank)  # stable: the order within a module is kept


@dataclass(frozen=True)
class BuiltinReport:
    """One ``spiralcap report`` run of the built-in design, HTML and PDF."""

    status: int
    stdout: str
    html_path: Path
    pdf_path: Path


@pytest.fixture(scope="session")
def builtin_report(tmp_path_factory: pytest.TempPathFactory) -> BuiltinReport:
    """The built-in design's report, written once per test process and read by the report's
    tests and its layout check (nothing writes beside it): ``spiralcap report -o ... --pdf ...
    --workers 2`` (analyses and figures forked) into a folder the user made (spiralcap makes no
    folder: spiralcap.outputs), with the CAD kernel (the ``cad`` extra) unimportable."""
    out = tmp_path_factory.mktemp("report") / "nested" / "folder"
    out.mkdir(parents=True)
    html_path, pdf_path = out / "report.html", out / "report.pdf"
    buf = io.StringIO()
    # the README's main job needs no CAD kernel: build123d unimportable while it runs (an
    # ``import build123d`` raises ImportError; test_coils_buildable.py reads the outcome)
    with pytest.MonkeyPatch.context() as mp, contextlib.redirect_stdout(buf):
        mp.setitem(sys.modules, "build123d", None)
        status = cli.main(
            ["report", "-o", str(html_path), "--pdf", str(pdf_path), "--workers", "2"]
        )
    return BuiltinReport(status, buf.getvalue(), html_path, pdf_path)


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
