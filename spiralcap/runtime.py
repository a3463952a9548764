"""How this process runs: one command and exit (the ``spiralcap`` program), or a library.

CPython's cyclic garbage collector walks every live object on each full pass; with CasADi's
graphs and matplotlib loaded that is about 100 000 objects, and the report's saved figures
leave about 40 000 objects of cyclic garbage. A bounded job can pause the collector
(:func:`cyclic_gc_paused`); the ``spiralcap`` program, which exits after its one command,
then leaves that garbage to the operating system instead of collecting it (:data:`ONE_SHOT`).
"""

from __future__ import annotations

import contextlib
import gc
from collections.abc import Iterator

#: True when the process exits after the current command (set by ``spiralcap.cli.console``);
#: False when spiralcap is used from Python, where memory must be handed back.
ONE_SHOT = False


@contextlib.contextmanager
def cyclic_gc_paused() -> Iterator[None]:
    """Pause the cyclic garbage collector for a bounded job (reference counting still frees
    memory). On leaving, the collector is resumed as it was, unless :data:`ONE_SHOT`, where
    the process is about to end and collecting would only cost time (about 0.08 s after a
    report)."""
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled and not ONE_SHOT:
            gc.enable()
