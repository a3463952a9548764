"""Where independent pieces of work run: this process, local worker processes, or Dask.

:func:`map_tasks` calls ``fn(*task)`` for every task and returns the results in task order,
whatever runs them, so a study gives the same numbers bit for bit on one core, on ``--workers
N`` processes or on a Dask distributed cluster (``--dask tcp://HOST:8786``). The tasks carry
everything that decides their result (a seed and an index range, a design), never "which worker
am I". Dask is an optional extra (``pip install ".[dask]"``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from spiralcap.errors import InputError

#: Seconds to wait for a Dask scheduler before giving up with a one-line error.
CONNECT_TIMEOUT_S = 3
INSTALL_HINT = 'the optional Dask extra: pip install ".[dask]" (or dask[distributed])'


def check_workers(workers: Any, key: str = "--workers") -> int:
    """``workers`` as an int >= 1, else InputError naming ``key``."""
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise InputError(key, workers, "a whole number >= 1")
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
            futures = [client.submit(fn, *t, pure=False) for t in tasks]
            if progress:
                from distributed import as_completed

                for i, _ in enumerate(as_completed(futures), start=1):
                    progress(i, n)
            try:
                return list(client.gather(futures))
            except Exception as exc:  # a worker or the scheduler could not run the task
                why = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
                raise InputError(
                    "--dask",
                    dask,
                    "a cluster whose scheduler and workers run this spiralcap version and its "
                    f"dependencies (the cluster failed: {why[:160]})",
                ) from None
    out = []
    if workers > 1 and n > 1:
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(max_workers=min(workers, n)) as pool:
            for i, r in enumerate(pool.map(fn, *zip(*tasks)), start=1):
                out.append(r)
                if progress:
                    progress(i, n)
        return out
    for i, t in enumerate(tasks, start=1):
        out.append(fn(*t))
        if progress:
            progress(i, n)
    return out


def where(workers: int = 1, dask: str | None = None) -> str:
    """Words for where the work ran (for output and the report)."""
    if dask is not None:
        return f"Dask cluster at {dask}"
    return f"{workers} local worker processes" if workers > 1 else "this process"
