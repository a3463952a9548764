"""Progress for long commands: stage names, rate and time left, on a terminal only.

:func:`progress_bar` wraps tqdm (a well-kept library, already a dependency) and yields a
``progress(done, total)`` callback, the form :func:`spiralcap.sweep.sweep` calls; when stderr
is not a terminal (pipes, CI, tests) it yields None and prints nothing. :func:`stages` does the
same for a sequence of named stages (the report's analyses). :func:`working` is for a job of
unknown length (an optimisation: robust, or sizing hardware): after a couple of seconds it shows
the elapsed time and the current stage, refreshed while the job runs.
"""

from __future__ import annotations

import shutil
import sys
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any


def _on_terminal() -> bool:
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


@contextmanager
def progress_bar(
    description: str, *, unit: str = "point", enabled: bool | None = None
) -> Iterator[Callable[[int, int], None] | None]:
    """A ``progress(done, total)`` callback drawing a tqdm bar (rate, time left) on stderr.

    Yields None when stderr is not a terminal (or ``enabled`` is False).
    """
    if not (_on_terminal() if enabled is None else enabled):
        yield None
        return
    from tqdm import tqdm

    bar: Any = None

    def update(done: int, total: int) -> None:
        nonlocal bar
        if bar is None:
            bar = tqdm(total=total, desc=description, unit=unit, file=sys.stderr, leave=True)
        bar.update(done - bar.n)

    try:
        yield update
    finally:
        if bar is not None:
            bar.close()


@contextmanager
def stages(
    names: tuple[str, ...], *, description: str = "report", enabled: bool | None = None
) -> Iterator[Callable[[str], None] | None]:
    """A ``say(stage)`` callback: a tqdm bar over named stages showing the current stage name,
    the rate and the time left. Yields None when stderr is not a terminal.
    """
    if not (_on_terminal() if enabled is None else enabled):
        yield None
        return
    from tqdm import tqdm

    bar = tqdm(total=len(names), desc=description, unit="stage", file=sys.stderr, leave=True)
    seen: list[str] = []

    def say(stage: str) -> None:
        if seen:
            bar.update(1)
        seen.append(stage)
        bar.set_postfix_str(stage)

    try:
        yield say
    finally:
        if seen:
            bar.update(len(names) - bar.n)
        bar.close()


#: A job shorter than this shows no progress at all (seconds).
WORKING_DELAY_S = 2.0


@contextmanager
def working(
    description: str,
    *,
    delay_s: float = WORKING_DELAY_S,
    enabled: bool | None = None,
    tick_s: float = 0.5,
) -> Iterator[Callable[[str], None] | None]:
    """A ``say(stage)`` callback for a job of unknown length: once it has run ``delay_s``, a
    tqdm line on stderr with the description, the elapsed time and the current stage, refreshed
    every ``tick_s`` by a helper thread until the job ends. Yields None off a terminal.
    """
    if not (_on_terminal() if enabled is None else enabled):
        yield None
        return
    from tqdm import tqdm

    lock = threading.Lock()
    stop = threading.Event()
    state: dict[str, Any] = {"bar": None, "stage": ""}
    t0 = time.monotonic()

    def draw() -> None:
        with lock:
            if state["bar"] is None:
                if time.monotonic() - t0 < delay_s:
                    return
                size = shutil.get_terminal_size((100, 24))
                bar = tqdm(
                    total=None,
                    desc=description,
                    file=sys.stderr,
                    leave=True,
                    bar_format="{desc}: {elapsed} elapsed{postfix}",
                    # a terminal that reports no size (0 x 0) would hide the line
                    ncols=size.columns or 100,
                    nrows=size.lines or 24,
                    delay=1e-9,  # no line at construction: the first is drawn below
                )
                bar.start_t -= time.monotonic() - t0  # the job's time, not the line's
                state["bar"] = bar
            bar = state["bar"]
            bar.set_postfix_str(state["stage"], refresh=False)
            bar.refresh()

    def tick() -> None:
        while not stop.wait(tick_s):
            draw()

    def say(stage: str) -> None:
        with lock:  # drawn at the next tick (a stage a millisecond long is not redrawn)
            state["stage"] = stage

    thread = threading.Thread(target=tick, name="spiralcap-progress", daemon=True)
    thread.start()
    try:
        yield say
    finally:
        stop.set()
        thread.join()
        with lock:
            if state["bar"] is not None:
                state["bar"].close()
