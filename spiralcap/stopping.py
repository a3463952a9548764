"""Stop means stop: a signalled command ends within seconds and leaves no process behind.

The ``spiralcap`` command turns SIGTERM and SIGHUP (what ``timeout``, CI runners, schedulers and a
closed terminal send) into :class:`Terminated`, a KeyboardInterrupt, so they unwind like Ctrl-C:
worker processes are stopped (:func:`spiralcap.parallel.process_pool`) and no staged output is
renamed into place. Inside IPOPT the interrupt ends the solve, which raises
:class:`optimize.nlp.SolveInterrupted` (a KeyboardInterrupt) in turn. Each worker asks the kernel to
kill it when its parent dies (``PR_SET_PDEATHSIG``, Linux; elsewhere a thread watching the
parent's pid), so even a parent killed with SIGKILL leaves no worker behind.
"""

from __future__ import annotations

from typing import Any

#: The signal number of the first stop request this process received (0: none).
_REQUESTED = [0]


def requested() -> int:
    """The signal that asked this command to stop (SIGTERM, SIGHUP), 0 if none did."""
    return _REQUESTED[0]


class Terminated(KeyboardInterrupt):
    """The command was asked to stop by a signal (SIGTERM, SIGHUP)."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


def raise_if_requested() -> None:
    """Raise :class:`Terminated` again if a stop signal came before.

    For a loop of many solves in the command's own process, after each: a :class:`Terminated`
    raised where nothing can pass it on (a finaliser, a callback from compiled code) is printed
    as ignored and lost, and the command would run on.
    """
    if _REQUESTED[0]:
        raise Terminated(_REQUESTED[0])


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
        _REQUESTED[0] = signum
        raise Terminated(signum)

    for name in STOP_SIGNALS:
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), stop)


def worker_setup(parent_pid: int) -> None:
    """First thing in a worker process: the default (fatal) action for SIGTERM and SIGHUP, SIGINT
    ignored (the parent stops its workers), and death with the parent (``PR_SET_PDEATHSIG`` = SIGKILL on Linux, a watcher thread
    elsewhere). Exits at once if the parent is already gone."""
    import os
    import signal
    import sys

    for name in STOP_SIGNALS:
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), signal.SIG_DFL)
    # Ctrl-C reaches the whole process group: the parent stops the workers, which say nothing
    signal.signal(signal.SIGINT, signal.SIG_IGN)
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
