"""Forked work inside one command (spiralcap.parallel.Forked, map_forked, Standby): the same
results as running the same functions here, errors carried back whole, and a dead worker
reported."""

from __future__ import annotations

import os

import numpy as np
import pytest

from spiralcap.errors import InputError
from spiralcap.parallel import Forked, Standby, can_fork, map_forked

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


#: what a Standby's setup leaves in its process (read by the functions it is sent)
_READY: list[int] = []


def _setup() -> None:
    _READY.append(os.getpid())


def _with_setup(shared: int, x: int) -> tuple[int, int, bool]:
    return shared * x, os.getpid(), bool(_READY)


def _fail(x: int) -> None:
    raise InputError("coils.x.turns", x, "a whole number from 1 to 5000")


def test_standby_runs_setup_there_and_serves_map_and_call() -> None:
    helper = Standby(_setup, processes=2)
    try:
        out = helper.map(_with_setup, 3, list(range(9)))
        assert [v for v, _, _ in out] == [3 * x for x in range(9)], "map: fn(shared, x) in order"
        assert all(ready for _, _, ready in out), "every share sees what setup built (forked)"
        pids = {pid for _, pid, _ in out}
        assert os.getpid() not in pids, "the work ran in the helper and its sibling, not here"
        assert helper.call(_with_setup, 2, 5)[0] == 10, "call: fn(*args) there"
        assert not _READY, "setup ran in the helper only"
        with pytest.raises(InputError) as info:
            helper.call(_fail, 0)
        assert info.value.key == "coils.x.turns", "an error crosses back whole"
        assert helper.map(_with_setup, 1, [4])[0][0] == 4, "the helper serves after an error"
    finally:
        helper.close()
    assert not helper._proc.is_alive(), "closed: the helper has ended"


def test_standby_reports_a_helper_that_died() -> None:
    helper = Standby(_setup)
    try:
        with pytest.raises(RuntimeError, match="exit code 9"):
            helper.call(os._exit, 9)
    finally:
        helper.cancel()
