"""A Dask cluster as a place to run tasks: connect (one line if nothing answers), and run a
study's tasks there in order with a watchdog (a cluster with no workers is an error, not an
endless wait). Dask is an optional extra (``pip install ".[dask]"``); the executor choice is
:mod:`spiralcap.parallel`'s.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from spiralcap.core.errors import InputError, SpiralcapError

#: Seconds to wait for a Dask scheduler before giving up with a one-line error.
CONNECT_TIMEOUT_S = 3
#: Seconds a Dask scheduler may have no workers, while tasks wait, before that is an error.
NO_WORKERS_S = 10.0
#: Seconds between asking the scheduler how many workers it has.
WORKER_POLL_S = 0.5
INSTALL_HINT = 'the optional Dask extra: pip install ".[dask]" (or dask[distributed])'


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


def _workers_of(client: Any) -> int:
    info = client.scheduler_info()
    return int(info.get("n_workers", len(info.get("workers", {}))))


def on_dask(
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
        except SpiralcapError:  # the task's own error (bad input, bad data): as run locally
            raise
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
