"""Where independent pieces of work run: this process, forked worker processes, or Dask.

The application chooses an executor and passes it down; the domain packages take an argument
shaped like :class:`concurrent.futures.Executor` (``submit``, ``map``) or nothing, and know
nothing of processes. Three kinds, one interface:

- :class:`InProcess`: every call runs here, at once, when it is submitted;
- :func:`process_pool`: a standard-library ``ProcessPoolExecutor`` with the fork context, whose
  workers die with the command (:func:`worker_setup`) and are stopped when the block is left;
- a Dask ``distributed.Client`` (:func:`spiralcap.dask_cluster.dask_client`), which speaks the
  same futures interface.

A task carries everything that decides its result (a seed and an index range, a design), never
"which worker am I", so a study gives the same numbers bit for bit wherever it ran. Functions
that cannot be pickled (closures over a model) reach forked workers through :func:`inherited`.
"""

from __future__ import annotations

import contextlib
import functools
import itertools
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Executor, Future
from typing import Any

from spiralcap.core.errors import InputError, SpiralcapError
from spiralcap.stopping import worker_setup

#: Most local worker processes: more than the machine's cores only wait their turn.
MAX_WORKERS = 64


class WorkerLostError(SpiralcapError):
    """A worker process ended without its result (killed from outside, out of memory)."""

    exit_status = 1


class InProcess(Executor):
    """An executor that runs each call here, when it is submitted (the one-core case)."""

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future:
        future: Future = Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except Exception as exc:  # Ctrl-C and SIGTERM are not caught: they stop the command
            future.set_exception(exc)
        return future


def check_workers(workers: Any, key: str = "--workers") -> int:
    """``workers`` as an int from 1 to :data:`MAX_WORKERS`, else InputError naming ``key``."""
    if isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= MAX_WORKERS:
        raise InputError(
            key,
            workers,
            f"a whole number from 1 to {MAX_WORKERS} (each a forked process; more than the "
            "cores only wait their turn)",
        )
    return workers


def available_cores() -> int:
    """Cores this process may run on (its CPU affinity where the OS tells, else the count)."""
    import os

    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def can_fork() -> bool:
    """True where this process may fork workers: POSIX, the main thread of a process that is not
    itself a pool's worker (a worker's or a Dask task's work runs in that process instead)."""
    import multiprocessing
    import threading

    return (
        "fork" in multiprocessing.get_all_start_methods()
        and not multiprocessing.current_process().daemon
        and threading.current_thread() is threading.main_thread()
    )


@contextlib.contextmanager
def process_pool(processes: int) -> Iterator[Executor]:
    """A fork-context ``ProcessPoolExecutor`` (:class:`InProcess` where :func:`can_fork` is False).

    The workers are forked at the first ``submit`` and stopped when the block is left,
    whatever the way out; a worker killed from outside raises :class:`WorkerLostError` (one
    line, no traceback).

    Parameters
    ----------
    processes : int
        Worker processes (each a fork of this one).

    Yields
    ------
    concurrent.futures.Executor
    """
    if not can_fork():
        yield InProcess()
        return
    import multiprocessing
    import os
    from concurrent.futures import ProcessPoolExecutor
    from concurrent.futures.process import BrokenProcessPool

    pool = ProcessPoolExecutor(
        processes,
        mp_context=multiprocessing.get_context("fork"),
        initializer=worker_setup,
        initargs=(os.getpid(),),
    )
    try:
        yield pool
    except BrokenProcessPool:
        raise WorkerLostError(
            "a worker process was killed from outside; no result written"
        ) from None
    finally:
        _stop_pool(pool)


def _stop_pool(pool: Any) -> None:
    """Stop a ProcessPoolExecutor's workers now (their work is done or not wanted), never
    waiting on the pool's own thread.

    The workers are killed first, so the pool's manager thread finds them gone instead of
    waiting on a pipe a worker holds (it hung so after Ctrl-C, issue 39); the shutdown does
    not wait for that thread, and each worker is reaped with a deadline. A stop request that
    comes meanwhile waits for the end of this (:func:`spiralcap.stopping.deferred`).
    """
    from spiralcap.stopping import deferred

    with deferred():
        procs = list((getattr(pool, "_processes", None) or {}).values())
        for proc in procs:
            if proc.is_alive():
                proc.kill()
        pool.shutdown(wait=False, cancel_futures=True)
        for proc in procs:
            proc.join(2)


_INHERITED: dict[int, Callable[..., Any]] = {}
_KEYS = itertools.count()


def _call_inherited(key: int, *args: Any) -> Any:
    return _INHERITED[key](*args)


@contextlib.contextmanager
def inherited(fn: Callable[..., Any]) -> Iterator[Callable[..., Any]]:
    """``fn`` as a picklable callable for the workers of a :func:`process_pool` entered inside
    this block: they are forked with ``fn`` in memory, so nothing of it is pickled.

    Parameters
    ----------
    fn : callable
        Anything callable here, a closure over a model or figures included.

    Yields
    ------
    callable
        A picklable stand-in: calling it in a worker calls ``fn`` with the same arguments.
    """
    key = next(_KEYS)
    _INHERITED[key] = fn
    try:
        yield functools.partial(_call_inherited, key)
    finally:
        del _INHERITED[key]


def map_tasks(
    fn: Callable[..., Any],
    tasks: Sequence[tuple],
    *,
    workers: int = 1,
    dask: str | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> list[Any]:
    """``[fn(*t) for t in tasks]`` here, on ``workers`` forked processes, or on Dask.

    Parameters
    ----------
    fn : callable
        A module-level function (pickled by name for other processes).
    tasks : sequence of tuples
        The arguments of each call.
    workers : int
        Local worker processes (1: this process). Ignored with ``dask``.
    dask : str, optional
        Address of a running Dask scheduler (``tcp://HOST:8786``).
    progress : callable, optional
        ``progress(done, total)`` after each finished task, in task order.
    """
    n = len(tasks)
    if dask is not None:
        from spiralcap.dask_cluster import dask_client, on_dask

        with dask_client(dask) as client:
            return on_dask(client, dask, fn, tasks, progress)
    here = workers < 2 or n < 2
    with contextlib.nullcontext(InProcess()) if here else process_pool(min(workers, n)) as pool:
        out = []
        for i, r in enumerate(pool.map(fn, *zip(*tasks)) if n else (), start=1):
            out.append(r)
            if progress:
                progress(i, n)
        return out


def where(workers: int = 1, dask: str | None = None) -> str:
    """Words for where the work ran (for output and the report)."""
    if dask is not None:
        return f"Dask cluster at {dask}"
    return f"{workers} local worker processes" if workers > 1 else "this process"
