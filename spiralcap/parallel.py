"""Where independent pieces of work run: this process, local worker processes, or Dask.

:func:`map_tasks` calls ``fn(*task)`` for every task and returns the results in task order,
whatever runs them, so a study gives the same numbers bit for bit on one core, on ``--workers
N`` processes or on a Dask distributed cluster (``--dask tcp://HOST:8786``). The tasks carry
everything that decides their result (a seed and an index range, a design), never "which worker
am I". Dask is an optional extra (``pip install ".[dask]"``).
"""

from __future__ import annotations

import weakref
from collections.abc import Callable, Sequence
from typing import Any

from spiralcap.errors import InputError

#: Seconds to wait for a Dask scheduler before giving up with a one-line error.
CONNECT_TIMEOUT_S = 3
#: Seconds a Dask scheduler may have no workers, while tasks wait, before that is an error.
NO_WORKERS_S = 10.0
#: Seconds between asking the scheduler how many workers it has.
WORKER_POLL_S = 0.5
INSTALL_HINT = 'the optional Dask extra: pip install ".[dask]" (or dask[distributed])'


#: Most local worker processes: each is a fork of this process; more than the machine's cores
#: only wait their turn (and every one holds its own copy of the model).
MAX_WORKERS = 64


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


def dask_client(address: str, key: str = "--dask") -> Any:
    """A connected ``distributed.Client`` (the caller closes it).

    Raises
    ------
    InputError
        Dask is not installed (how to install it), or no scheduler answers at ``address``
        within :data:`CONNECT_TIMEOUT_S` seconds.
    """
    if not isinstance(address, str) or not address.strip():
        raise InputError(key, address, "a scheduler address such as tcp://HOST:8786")
    try:
        from distributed import Client
    except ImportError:
        raise InputError(key, address, f"needs {INSTALL_HINT}") from None
    import logging

    logging.getLogger("distributed").setLevel(logging.CRITICAL)  # the error below says it all
    problem = _probe(address)
    if problem is None:
        try:
            return Client(address, timeout=f"{CONNECT_TIMEOUT_S}s", set_as_default=False)
        except Exception as exc:  # anything the connection raises is "not reachable"
            problem = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    raise InputError(
        key,
        address,
        f"a reachable Dask scheduler (tcp://HOST:8786); none answered within "
        f"{CONNECT_TIMEOUT_S} s ({problem})",
    )


def _probe(address: str) -> str | None:
    """Open and close one Dask comm to ``address``: None if a scheduler answers, else why not.

    Done before creating a ``Client`` because a half-built client hangs for seconds on exit.
    """
    import asyncio

    from distributed.comm import connect

    async def once() -> None:
        comm = await connect(address, timeout=CONNECT_TIMEOUT_S)
        await comm.close()

    try:
        asyncio.run(asyncio.wait_for(once(), CONNECT_TIMEOUT_S + 1))
    except Exception as exc:  # refused, timed out, not a Dask comm, malformed address
        return str(exc).splitlines()[0][:120] if str(exc) else type(exc).__name__
    return None


def map_tasks(
    fn: Callable[..., Any],
    tasks: Sequence[tuple],
    *,
    workers: int = 1,
    dask: str | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> list[Any]:
    """``[fn(*t) for t in tasks]``, run here, in ``workers`` processes, or on a Dask cluster.

    Parameters
    ----------
    fn : callable
        A module-level function (it is pickled by name for other processes).
    tasks : sequence of tuples
        The arguments of each call.
    workers : int
        Local worker processes (1: this process). Ignored with ``dask``.
    dask : str, optional
        Address of a running Dask scheduler (``tcp://HOST:8786``).
    progress : callable, optional
        ``progress(done, total)`` after each finished task.
    """
    n = len(tasks)
    if dask is not None:
        with dask_client(dask) as client:
            return _on_dask(client, dask, fn, tasks, progress)
    out = []
    if workers > 1 and n > 1:
        import os
        from concurrent.futures import ProcessPoolExecutor

        pool = ProcessPoolExecutor(
            max_workers=min(workers, n), initializer=worker_setup, initargs=(os.getpid(),)
        )
        try:
            for i, r in enumerate(pool.map(fn, *zip(*tasks)), start=1):
                out.append(r)
                if progress:
                    progress(i, n)
        except BaseException:  # an error, Ctrl-C, SIGTERM: stop the workers, do not wait
            _stop_pool(pool)
            raise
        pool.shutdown()
        return out
    for i, t in enumerate(tasks, start=1):
        out.append(fn(*t))
        if progress:
            progress(i, n)
    return out


def _workers_of(client: Any) -> int:
    info = client.scheduler_info()
    return int(info.get("n_workers", len(info.get("workers", {}))))


def _on_dask(
    client: Any,
    address: str,
    fn: Callable[..., Any],
    tasks: Sequence[tuple],
    progress: Callable[[int, int], None] | None,
) -> list[Any]:
    """The tasks on a Dask cluster, in task order. A cluster with no workers (none started yet,
    or all gone mid-run) for :data:`NO_WORKERS_S` seconds is an error, not an endless wait."""
    import time

    n = len(tasks)
    futures = [client.submit(fn, *t, pure=False) for t in tasks]
    try:
        reported = 0
        idle_since: float | None = None
        next_check = 0.0
        while True:
            done = sum(f.done() for f in futures)
            if progress and done > reported:
                for i in range(reported + 1, done + 1):
                    progress(i, n)
                reported = done
            if done == n or any(f.status == "error" for f in futures):
                break
            now = time.monotonic()
            if now >= next_check:
                next_check = now + WORKER_POLL_S
                if _workers_of(client) > 0:
                    idle_since = None
                elif idle_since is None:
                    idle_since = now
                elif now - idle_since > NO_WORKERS_S:
                    raise InputError(
                        "--dask",
                        address,
                        f"a Dask cluster with workers (the scheduler has had none for "
                        f"{NO_WORKERS_S:g} s; {n - done} of {n} tasks not run)",
                    )
            time.sleep(0.02)
        try:
            return list(client.gather(futures))
        except Exception as exc:  # a worker or the scheduler could not run the task
            why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise InputError(
                "--dask",
                address,
                "a cluster whose scheduler and workers run this spiralcap version and its "
                f"dependencies (the cluster failed: {why[:160]})",
            ) from None
    finally:
        client.cancel([f for f in futures if not f.done()])


def where(workers: int = 1, dask: str | None = None) -> str:
    """Words for where the work ran (for output and the report)."""
    if dask is not None:
        return f"Dask cluster at {dask}"
    return f"{workers} local worker processes" if workers > 1 else "this process"


# ---------------------------------------------------------------------------------------------
# Stopping: workers never outlive the command.
#
# The ``spiralcap`` command turns SIGTERM and SIGHUP (what ``timeout``, CI runners, schedulers
# and a closed terminal send) into :class:`Terminated`, a KeyboardInterrupt, so they unwind like
# Ctrl-C: the worker processes are stopped (:func:`map_tasks`, :class:`Forked`) and no staged
# output is renamed into place. Each worker also asks the kernel to kill it when its parent
# dies (``PR_SET_PDEATHSIG``, Linux; elsewhere a thread watching the parent's pid), so even a
# parent killed with SIGKILL leaves no worker behind.


class Terminated(KeyboardInterrupt):
    """The command was asked to stop by a signal (SIGTERM, SIGHUP)."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


#: Signals the command turns into :class:`Terminated`.
STOP_SIGNALS = ("SIGTERM", "SIGHUP")


def stop_on_signals() -> None:
    """In the ``spiralcap`` command: SIGTERM and SIGHUP raise :class:`Terminated` in the main
    thread, once; a second one while it cleans up ends the process at once (the default
    action; its workers then end through ``PR_SET_PDEATHSIG``)."""
    import signal

    def stop(signum: int, _frame: Any) -> None:
        for name in STOP_SIGNALS:
            if hasattr(signal, name):
                signal.signal(getattr(signal, name), signal.SIG_DFL)
        raise Terminated(signum)

    for name in STOP_SIGNALS:
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), stop)


def worker_setup(parent_pid: int) -> None:
    """First thing in a worker process: the default (fatal) action for SIGTERM and SIGHUP, and
    death with the parent (``PR_SET_PDEATHSIG`` = SIGKILL on Linux, a watcher thread
    elsewhere). Exits at once if the parent is already gone."""
    import os
    import signal
    import sys

    for name in STOP_SIGNALS:
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), signal.SIG_DFL)
    if sys.platform.startswith("linux"):
        import ctypes

        PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
        except (OSError, AttributeError):
            _watch_parent(parent_pid)
    else:
        _watch_parent(parent_pid)
    if os.getppid() != parent_pid:  # the parent died before the line above took effect
        os._exit(1)


def _watch_parent(parent_pid: int) -> None:
    import os
    import threading
    import time

    def watch() -> None:
        while os.getppid() == parent_pid:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch, name="spiralcap-parent-watch", daemon=True).start()


def _stop_pool(pool: Any) -> None:
    """Stop a ProcessPoolExecutor's workers now (the results are not wanted)."""
    procs = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for proc in procs:
        if proc.is_alive():
            proc.kill()
    for proc in procs:
        proc.join(5)


# ---------------------------------------------------------------------------------------------
# Forked work inside one command: results computed in this process's own memory image.
#
# The report runs its independent analyses, and then its figures, on the machine's cores. Forked
# children start in a few milliseconds with everything already imported and computed (no
# pickling of inputs, closures allowed); only results come back, pickled through a pipe. Fork
# exists on Linux and macOS; elsewhere (Windows) :func:`can_fork` is False and the callers run
# the same functions in this process, with the same results.


def can_fork() -> bool:
    """True where worker processes can be forked (POSIX)."""
    import multiprocessing

    return "fork" in multiprocessing.get_all_start_methods()


def available_cores() -> int:
    """Cores this process may run on (its CPU affinity where the OS tells, else the count)."""
    import os

    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def _outcome(fn: Callable[..., Any], *args: Any) -> tuple[bool, Any]:
    """(True, fn(*args)), or (False, (the exception, its traceback)) to raise in the parent."""
    try:
        return True, fn(*args)
    except BaseException as exc:
        import traceback

        return False, (exc, traceback.format_exc())


def _send(conn: Any, outcome: tuple[bool, Any]) -> None:
    try:
        conn.send(outcome)
    except Exception as exc:  # the result or the error did not pickle
        conn.send((False, (None, f"{type(exc).__name__}: {exc}")))


def _received(outcome: tuple[bool, Any]) -> Any:
    """The value of a child's outcome, or its exception raised here."""
    ok, value = outcome
    if ok:
        return value
    exc, text = value
    if isinstance(exc, BaseException):
        raise exc
    raise RuntimeError(f"a worker process failed: {text.strip().splitlines()[-1]}")


def _died(proc: Any) -> tuple[bool, Any]:
    proc.join()  # reaped: its exit code is known
    return False, (None, f"the worker process ended with exit code {proc.exitcode}")


def _child(send: Any, parent_pid: int, fn: Callable[..., Any], args: tuple) -> None:
    worker_setup(parent_pid)
    _send(send, _outcome(fn, *args))
    send.close()


#: Forked jobs whose result has not been taken: stopped if this process exits without them.
_LIVE: weakref.WeakSet[Forked | Standby] = weakref.WeakSet()
_LIVE_ATEXIT: list[bool] = []


def _cancel_live() -> None:
    for job in list(_LIVE):
        job.cancel()


class Forked:
    """``fn(*args)`` running in a forked child process; :meth:`result` waits for its value.

    ``fn`` may be a closure (nothing is pickled on the way in); the value (or the exception
    raised) must pickle on the way back.
    """

    def __init__(self, fn: Callable[..., Any], *args: Any) -> None:
        import multiprocessing

        self._recv, send = multiprocessing.get_context("fork").Pipe(duplex=False)
        self._proc = _start(self, _child, send, fn, args)

    def cancel(self) -> None:
        """Stop the child (its result is not wanted) and wait for it to end."""
        _LIVE.discard(self)
        self._proc.terminate()
        self._proc.join()
        self._recv.close()

    def result(self) -> Any:
        """The child's return value; its exception is raised here if it raised one."""
        try:
            outcome = self._recv.recv()
        except EOFError:
            outcome = _died(self._proc)
        except BaseException:  # Ctrl-C or SIGTERM while waiting: the result is not wanted
            self.cancel()
            raise
        self._recv.close()
        self._proc.join()
        _LIVE.discard(self)
        return _received(outcome)


def _start(owner: Forked | Standby, target: Callable[..., Any], conn: Any, *args: Any) -> Any:
    """Fork and start ``target(conn, this pid, *args)``; ``owner`` is stopped at exit if still
    running. The child's end of the pipe, ``conn``, is closed here."""
    import multiprocessing
    import os
    import warnings

    proc = multiprocessing.get_context("fork").Process(
        target=target, args=(conn, os.getpid(), *args)
    )
    with warnings.catch_warnings():
        # Python >= 3.12 warns that forking a process with threads (OpenBLAS's pool) may
        # deadlock; the children only compute (numpy, CasADi, matplotlib) and OpenBLAS
        # re-initialises its pool after fork (pthread_atfork)
        warnings.simplefilter("ignore", DeprecationWarning)
        proc.start()
    conn.close()
    _LIVE.add(owner)
    if not _LIVE_ATEXIT:
        import atexit

        # runs before multiprocessing's own exit handler, which would wait for the child
        atexit.register(_cancel_live)
        _LIVE_ATEXIT.append(True)
    return proc


def _serve(conn: Any, parent_pid: int, setup: Callable[[], Any], processes: int) -> None:
    """:class:`Standby`'s child: ``setup()``, then requests until "stop" (or the pipe closes)."""
    import functools

    worker_setup(parent_pid)
    _outcome(setup)  # a failure loses nothing: the requests then do that work themselves
    while True:
        try:
            request = conn.recv()
        except (EOFError, OSError):
            break
        if request[0] == "stop":
            break
        if request[0] == "map":
            _, fn, shared, items = request
            _send(conn, _outcome(map_forked, functools.partial(fn, shared), items, processes))
        else:
            _, fn, args = request
            _send(conn, _outcome(fn, *args))
    conn.close()


class Standby:
    """A forked helper that gets ready while this process goes on, then takes work.

    ``setup()`` runs in the child at once, on another core (sizing compiles there the
    fixed-hardware problem its neighbours need while this process solves the relaxation).
    :meth:`map` then runs ``fn(shared, x)`` for every item on the child and ``processes - 1``
    siblings forked from it (:func:`map_forked`: all of them hold what ``setup`` built), and
    :meth:`call` runs ``fn(*args)`` there. Requests and results are pickled: ``fn`` is a
    module-level function. The same values as the same calls made here.
    """

    def __init__(self, setup: Callable[[], Any], processes: int = 2) -> None:
        import multiprocessing

        self._conn, child_conn = multiprocessing.get_context("fork").Pipe(duplex=True)
        self._proc = _start(self, _serve, child_conn, setup, max(processes, 1))

    def map(self, fn: Callable[[Any, Any], Any], shared: Any, items: Sequence[Any]) -> list[Any]:
        """``[fn(shared, x) for x in items]``, run by the helper and its siblings."""
        return self._ask(("map", fn, shared, list(items)))

    def call(self, fn: Callable[..., Any], *args: Any) -> Any:
        """``fn(*args)``, run by the helper."""
        return self._ask(("call", fn, args))

    def _ask(self, request: tuple) -> Any:
        try:
            self._conn.send(request)
            outcome = self._conn.recv()
        except (EOFError, BrokenPipeError):
            outcome = _died(self._proc)
        except BaseException:  # Ctrl-C or SIGTERM while waiting: the answer is not wanted
            self.cancel()
            raise
        return _received(outcome)

    def close(self) -> None:
        """Let the helper end (it is waited for)."""
        if self._proc.is_alive():
            try:
                self._conn.send(("stop",))
            except OSError:
                pass
            self._proc.join(5)
        self.cancel()

    def cancel(self) -> None:
        """Stop the helper now and wait for it to end."""
        _LIVE.discard(self)
        if self._proc.is_alive():
            self._proc.terminate()
        self._proc.join()
        self._conn.close()


def _may_fork_here() -> bool:
    import multiprocessing
    import threading

    return (
        can_fork()
        and not multiprocessing.current_process().daemon
        and threading.current_thread() is threading.main_thread()
    )


def standby_on_free_core(setup: Callable[[], Any]) -> Standby | None:
    """A :class:`Standby` running ``setup`` where this process may fork and has a second core
    (as :func:`map_free_cores`); None elsewhere (the caller does the work itself)."""
    if not _may_fork_here() or available_cores() < 2:
        return None
    try:
        return Standby(setup, min(available_cores(), 2))
    except OSError:  # no process to spare (resource limits): the caller does the work itself
        return None


def map_free_cores(fn: Callable[[Any], Any], items: Sequence[Any]) -> list[Any]:
    """``[fn(x) for x in items]`` on up to two cores (:func:`map_forked`) where this process may
    fork: the main thread of a non-daemon process (not a Dask worker's task thread); else here.
    Sizing maps its buildable neighbours with it (``optimize.discrete.set_neighbour_map``)."""
    if not _may_fork_here():
        return [fn(x) for x in items]
    return map_forked(fn, items, min(available_cores(), 2))


def map_forked(fn: Callable[[Any], Any], items: Sequence[Any], processes: int) -> list[Any]:
    """``[fn(x) for x in items]`` on this process and ``processes - 1`` forked children.

    Items are handed out one at a time from a shared counter, in order, to whichever process is
    free (the slow ones do not hold the others up); results come back in ``items`` order.
    """
    n = len(items)
    if processes < 2 or n < 2 or not can_fork():
        return [fn(x) for x in items]
    import multiprocessing

    counter = multiprocessing.get_context("fork").Value("i", 0)

    def claim() -> int:
        with counter.get_lock():
            i = int(counter.value)
            counter.value = i + 1
        return i

    def work() -> dict[int, Any]:
        done = {}
        while (i := claim()) < n:
            done[i] = fn(items[i])
        return done

    children = [Forked(work) for _ in range(min(processes, n) - 1)]
    failure: BaseException | None = None
    try:
        results = work()
    except KeyboardInterrupt:  # Ctrl-C, SIGTERM: stop the children, do not wait for them
        for child in children:
            child.cancel()
        raise
    except BaseException as exc:  # the children are waited for all the same
        failure, results = exc, {}
    for j, child in enumerate(children):
        try:
            results.update(child.result())
        except KeyboardInterrupt:
            for other in children[j + 1 :]:
                other.cancel()
            raise
        except BaseException as exc:
            failure = failure or exc
    if failure is not None:
        raise failure
    return [results[i] for i in range(n)]
