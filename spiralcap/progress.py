"""Progress for long commands: stage names, rate and time left, on a terminal only.

:func:`progress_bar` wraps tqdm (a well-kept library, already a dependency) and yields a
``progress(done, total)`` callback, the form :func:`spiralcap.sweep.sweep` calls; when stderr
is not a terminal (pipes, CI, a log file) it yields a :class:`PlainProgress`: nothing for a job
shorter than 10 s, then a plain line at most every 10 % or 10 s. :func:`stages` does the
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


def _os_stream(stream: Any) -> bool:
    """Whether ``stream`` writes to a file descriptor (a pipe, a log file), not to an in-process
    buffer (Python code capturing the output of :func:`spiralcap.cli.main`)."""
    try:
        stream.fileno()
    except (AttributeError, ValueError, OSError):  # io.UnsupportedOperation is both
        return False
    return True


@contextmanager
def progress_bar(
    description: str, *, unit: str = "point", enabled: bool | None = None
) -> Iterator[Callable[[int, int], None] | None]:
    """A ``progress(done, total)`` callback drawing a tqdm bar (rate, time left) on stderr.

    When stderr is not a terminal it yields a :class:`PlainProgress` (plain lines, none for a
    short job); None when ``enabled`` is False.
    """
    if enabled is None and not _on_terminal():
        yield PlainProgress(description, unit=unit) if _os_stream(sys.stderr) else None
        return
    if enabled is False:
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


class PlainProgress:
    """A ``progress(done, total)`` callback for a stream that is not a terminal (a pipe, a CI
    log): silent for the first ``after_s`` seconds, then one line such as
    ``evaluating: 75000 of 250000 points (30 %), 22 s`` each time another ``step_pct`` percent
    is done or ``every_s`` seconds have passed since the last line, whichever comes first, and
    a last line at the end once any was written.

    Parameters
    ----------
    description : str
        What is being done (``evaluating``).
    unit : str
        What is counted, singular (``point``).
    stream : text stream, optional
        Where the lines go (default: ``sys.stderr`` at each call).
    clock : callable, optional
        Seconds from an arbitrary origin (default :func:`time.monotonic`).
    after_s, every_s : float
        Quiet time at the start, and the longest time between lines (s).
    step_pct : int
        Percent done between lines (%).
    """

    def __init__(
        self,
        description: str,
        *,
        unit: str = "point",
        stream: Any = None,
        clock: Callable[[], float] = time.monotonic,
        after_s: float = 10.0,
        every_s: float = 10.0,
        step_pct: int = 10,
    ) -> None:
        self.description, self.unit, self.stream, self.clock = description, unit, stream, clock
        self.after_s, self.every_s, self.step_pct = after_s, every_s, step_pct
        self.start = clock()
        self.last_s: float | None = None
        self.last_step = -1
        self.lines = 0

    def __call__(self, done: int, total: int) -> None:
        now = self.clock()
        elapsed = now - self.start
        if elapsed < self.after_s or total <= 0:
            return
        step = (100 * done // total) // self.step_pct
        due = step > self.last_step or self.last_s is None or now - self.last_s >= self.every_s
        if done >= total and self.lines == 0:
            return  # finished before the first line was due: nothing to say
        if due:
            pct = 100 * done // total
            units = self.unit if total == 1 else f"{self.unit}s"
            line = f"{self.description}: {done} of {total} {units} ({pct} %), {elapsed:.0f} s"
            print(line, file=self.stream or sys.stderr, flush=True)
            self.last_s, self.last_step = now, step
            self.lines += 1


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
