"""Each model's evaluation and optimum computed once per test process (issue 38, item 7).

Several tests run commands that evaluate and optimise the same model (the built-in design is
optimised by ``optimize``, by ``compare`` for its first design, by a report's comparison
section, ...). :func:`solved_once` replaces ``optimize.evaluate`` and
``optimize.optimize_design`` (the names the commands import when they run) by versions that
remember each result by the model's content: the pickle of the prepared model (so a model
built twice from the same design, prepared or not, is one entry), with the extension hooks
registered at the time (``optimize.problem.CONSTRAINTS``: a registered row changes the optimum,
not the model). Both functions are deterministic, so a remembered result is the result a new
call would give; a model that differs in anything is solved afresh. Only calls with the model
alone are remembered (a ``progress`` callback, which changes no result, is passed on a miss);
any other argument (a point, a warm start, an executor) goes to the real function.

The results are frozen dataclasses, never mutated by the tests that read them. The cache is
module-level, so test files run by one pytest(-xdist) worker share it.
"""

from __future__ import annotations

import contextlib
import hashlib
import pickle
from collections.abc import Callable, Iterator
from typing import Any

import pytest

#: (step, model content, hooks) -> result
_SOLVED: dict[tuple[str, str, tuple[int, ...]], Any] = {}


def _content(model: Any) -> tuple[Any, str]:
    """The prepared model and the SHA-256 of its pickle."""
    import optimize

    prepared = optimize.prepare(model)
    return prepared, hashlib.sha256(pickle.dumps(prepared)).hexdigest()


def _hooks() -> tuple[int, ...]:
    from optimize import problem as pb

    return tuple(id(f) for f in pb.CONSTRAINTS)


def _once(step: str, real: Callable[..., Any]) -> Callable[..., Any]:
    def call(model: Any, *args: Any, **kw: Any) -> Any:
        if args or set(kw) - {"progress"}:
            return real(model, *args, **kw)
        prepared, digest = _content(model)
        key = (step, digest, _hooks())
        if key not in _SOLVED:
            _SOLVED[key] = real(prepared, **kw)
        return _SOLVED[key]

    call._te_memo_real = real  # type: ignore[attr-defined]
    return call


@contextlib.contextmanager
def solved_once_here() -> Iterator[None]:
    """Within the block, ``optimize.evaluate`` and ``optimize.optimize_design`` remember."""
    import optimize

    if hasattr(optimize.optimize_design, "_te_memo_real"):  # already inside such a block
        yield
        return
    real = (optimize.evaluate, optimize.optimize_design)
    optimize.evaluate = _once("evaluate", real[0])
    optimize.optimize_design = _once("optimize", real[1])
    try:
        yield
    finally:
        optimize.evaluate, optimize.optimize_design = real


@pytest.fixture
def solved_once() -> Iterator[None]:
    """A test that runs commands which evaluate or optimise a model another test (or command)
    of this process already did: each result read from :data:`_SOLVED`."""
    with solved_once_here():
        yield


def optimum(model: Any) -> Any:
    """``optimize.optimize_design(model)``, remembered (for a test's own reference solve)."""
    import optimize

    with solved_once_here():
        return optimize.optimize_design(model)


def evaluation(model: Any) -> Any:
    """``optimize.evaluate(model)``, remembered."""
    import optimize

    with solved_once_here():
        return optimize.evaluate(model)
