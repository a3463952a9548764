"""Forked work inside one command (spiralcap.parallel.Forked, map_forked): the same results as
running the same functions here, errors carried back whole, and a dead worker reported."""

from __future__ import annotations

import os

import numpy as np
import pytest

from spiralcap.errors import InputError
from spiralcap.parallel import Forked, can_fork, map_forked

pytestmark = pytest.mark.skipif(not can_fork(), reason="fork is POSIX-only")


def test_forked_returns_the_value_of_a_closure() -> None:
    data = np.arange(10.0)  # a closure over this process's memory: nothing pickled going in
    job = Forked(lambda k: (os.getpid(), float(data.sum() * k)), 3)
    pid, value = job.result()
    assert value == 135.0, "Forked(fn, 3).result() is fn(3) (sum 0..9 = 45, times 3)"
    assert pid != os.getpid(), "the work ran in another process"


def test_forked_raises_the_workers_input_error_unchanged() -> None:
    def bad() -> None:
        raise InputError("limits.power_W", -1.0, "a finite number > 0", where="a.toml line 3")

    with pytest.raises(InputError) as info:
        Forked(bad).result()
    e = info.value
    assert (e.key, e.value, e.allowed, e.where) == (
        "limits.power_W",
        -1.0,
        "a finite number > 0",
        "a.toml line 3",
    ), "an InputError crosses the process boundary with its key, value, allowed and where"
    assert str(e) == "a.toml line 3: limits.power_W = -1.0: a finite number > 0"


def test_forked_reports_a_worker_that_died() -> None:
    with pytest.raises(RuntimeError, match="exit code 7"):
        Forked(os._exit, 7).result()


def test_forked_waits_for_the_exit_status_of_a_dying_worker() -> None:
    """The pipe closes before the child has exited: its status is waited for, never read
    early as None (issue 22: "exit code None" under load)."""

    def close_then_exit() -> None:
        import time

        os.closerange(3, 4096)  # the result pipe among them: the parent sees EOF now
        time.sleep(0.5)
        os._exit(7)

    with pytest.raises(RuntimeError, match="exit code 7"):
        Forked(close_then_exit).result()


def test_map_forked_matches_the_serial_map_in_order() -> None:
    items = list(range(23))

    def fn(i: int) -> tuple[int, int]:
        return i * i, os.getpid()

    out = map_forked(fn, items, 3)
    assert [v for v, _ in out] == [i * i for i in items], "results come back in item order"
    assert map_forked(fn, items, 1) == [(i * i, os.getpid()) for i in items], "1: all here"


def test_map_forked_raises_when_a_share_fails() -> None:
    def fn(i: int) -> int:
        if i == 5:
            raise InputError("item", i, "not 5")
        return i

    with pytest.raises(InputError, match="item = 5"):
        map_forked(fn, list(range(12)), 2)
