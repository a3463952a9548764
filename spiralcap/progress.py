"""Progress for long commands: stage names, rate and time left, on a terminal only.

:func:`progress_bar` wraps tqdm (a well-kept library, already a dependency) and yields a
``progress(done, total)`` callback, the form :func:`spiralcap.sweep.sweep` calls; when stderr
is not a terminal (pipes, CI, tests) it yields None and prints nothing. :func:`stages` does the
same for a sequence of named stages (the report's analyses).
"""

from __future__ import annotations

import sys
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
