"""Stop means stop: a signalled command ends within seconds, writes nothing and leaves no process.

The ``spiralcap`` command turns SIGTERM, SIGHUP and SIGINT (what ``timeout``, CI runners,
schedulers, a closed terminal and Ctrl-C send) into :class:`Terminated`, a KeyboardInterrupt,
so they unwind alike: worker processes are stopped (:func:`spiralcap.parallel.process_pool`) and
no staged output is renamed into place. Inside IPOPT the interrupt ends the solve, which raises
:class:`optimize.nlp.SolveInterrupted` (a KeyboardInterrupt) in turn. Each worker asks the kernel
to kill it when its parent dies (``PR_SET_PDEATHSIG``, Linux; elsewhere a thread watching the
parent's pid), so even a parent killed with SIGKILL leaves no worker behind.

The request is recorded once, before anything is raised (:func:`requested`), so it cannot be
lost where the exception is: raised inside an import that catches it, in a finaliser or a
callback from compiled code (printed as ignored), or turned into another error. It is checked
again at each stage boundary (:func:`raise_if_requested`), immediately before any output is
committed (:func:`committing`, in :func:`spiralcap.outputs.write_files_atomic`) and at the end
of :func:`spiralcap.cli.main`, which answers any way out of a stopped command (an error, a
traceback, success) with exit 128 + the signal number and one line.

The commit is the point of no return: a request that arrives while the outputs are renamed
into place, or after, no longer stops the command (its outputs are complete and in place); it
finishes, exits with its own status, and says on stderr that the stop came after the outputs
were written. So exit 130/143 always means nothing was written, exit 0 that everything was.
"""

from __future__ import annotations

import contextlib
from collections.abc import Callable, Iterator
from typing import Any

#: The signal number of the first stop request this process received (0: none).
_REQUESTED = [0]
#: [deferring, committing, committed, settled]: a stop waits for the end of a short block that
#: must not be cut (staging the outputs); the outputs are being, or have been, put in place;
#: the command has taken the stop into account (it is saying so and leaving).
_COMMIT = [False, False, False, False]
#: Seconds between the reminders of a stop request that was not honoured yet (:func:`_again`).
AGAIN_S = 0.25


def requested() -> int:
    """The signal that asked this command to stop (SIGTERM, SIGHUP, SIGINT), 0 if none did."""
    return _REQUESTED[0]


def record(signum: int) -> None:
    """Record a stop request (the first one is kept)."""
    if not _REQUESTED[0]:
        _REQUESTED[0] = int(signum)


def committed() -> bool:
    """Whether this run's outputs have been put in place (a stop no longer undoes them)."""
    return _COMMIT[2]


def new_run() -> None:
    """Forget the commit of an earlier run in this process (:func:`spiralcap.cli.main` calls it
    first; a stop request is never forgotten)."""
    _COMMIT[:] = [False, False, False, False]


class Terminated(KeyboardInterrupt):
    """The command was asked to stop by a signal (SIGTERM, SIGHUP, SIGINT)."""

    def __init__(self, signum: int) -> None:
        super().__init__(signum)
        self.signum = signum


def raise_if_requested() -> None:
    """Raise :class:`Terminated` again if a stop signal came before (and the outputs are not
    committed yet).

    At every stage boundary, and after each solve of a loop of many: a :class:`Terminated`
    raised where nothing can pass it on (a finaliser, a callback from compiled code) is printed
    as ignored and lost, and the command would run on.
    """
    if _REQUESTED[0] and not any(_COMMIT):
        raise Terminated(_REQUESTED[0])


def checked(callback: Callable[..., None] | None) -> Callable[..., None]:
    """``callback`` (a progress callback, or None: nothing) with a stage boundary before each
    call: a stop request that came before, its exception lost on the way, raises here."""

    def call(*args: Any) -> None:
        raise_if_requested()
        if callback is not None:
            callback(*args)

    return call


@contextlib.contextmanager
def deferred() -> Iterator[None]:
    """A short block a stop must not cut (staging files whose names the block's caller removes
    on the way out): a request that comes inside is recorded, and raised at its end."""
    before = _COMMIT[0]
    _COMMIT[0] = True
    try:
        yield
    finally:
        _COMMIT[0] = before
    raise_if_requested()


@contextlib.contextmanager
def committing() -> Iterator[None]:
    """The block that puts the outputs in place: a stop request that came before raises
    :class:`Terminated` on entry (nothing is written); one that comes inside the block or after
    it is recorded only (the outputs are completed, and the command ends normally).

    Inside a block that failed, the run counts as not committed.
    """
    raise_if_requested()
    _COMMIT[1] = True
    try:
        yield
    except BaseException:
        _COMMIT[1] = False
        raise
    _COMMIT[1], _COMMIT[2] = False, True


#: Signals the command turns into :class:`Terminated`.
STOP_SIGNALS = ("SIGTERM", "SIGHUP", "SIGINT")


def _stop(signum: int, _frame: Any) -> None:
    """The handler: record the request; raise :class:`Terminated` unless the outputs are being
    or have been committed. After the first request every stop signal takes its default action
    again, so a second one ends a command that is slow to clean up at once; and the request is
    raised again every :data:`AGAIN_S` until the command takes it (:func:`_again`)."""
    import signal

    first = not _REQUESTED[0]
    record(signum)
    if first and _QUIET[0] and not any(_COMMIT[1:]):
        _quiet_stderr()
    if first:
        for name in STOP_SIGNALS:
            if hasattr(signal, name):
                signal.signal(getattr(signal, name), signal.SIG_DFL)
        if hasattr(signal, "setitimer"):
            signal.signal(signal.SIGALRM, _again)
            signal.setitimer(signal.ITIMER_REAL, AGAIN_S, AGAIN_S)
    if not any(_COMMIT):
        raise Terminated(_REQUESTED[0])


def _again(_signum: int, _frame: Any) -> None:
    """The reminder: a stop request whose exception was swallowed (an import that turns it into
    an ImportError another import catches, a library's ``except BaseException``) is raised again,
    until the command has taken it (:func:`settle`) or committed its outputs."""
    if _REQUESTED[0] and not any(_COMMIT):
        raise Terminated(_REQUESTED[0])


def settle() -> None:
    """The command has taken the stop request into account (or ended without one): no
    reminder is raised any more (:func:`spiralcap.cli.main`, as it says how the run ended)."""
    import signal

    _COMMIT[3] = True
    _restore_stderr()
    if _REQUESTED[0] and hasattr(signal, "setitimer"):
        try:
            signal.setitimer(signal.ITIMER_REAL, 0.0)
        except (OSError, ValueError):  # pragma: no cover -- not the main interpreter
            pass


#: A copy of file descriptor 2 while it is pointed at the null device (-1: it is not).
_SAVED_STDERR = [-1]
#: Whether a stop request quietens stderr (:func:`stop_on_signals`).
_QUIET = [False]


def _quiet_stderr() -> None:
    """From a stop request (before the commit) until the command says how it ended, file
    descriptor 2 goes to the null device: what libraries print as they are cut short (CasADi's
    ``KeyboardInterruptException`` warning from IPOPT's callback, an exception Python reports
    as ignored in a finaliser) is not the command's, whose one line follows (:func:`settle`)."""
    import os
    import sys

    if _SAVED_STDERR[0] >= 0:
        return
    try:
        sys.stderr.flush()
        saved = os.dup(2)
        null = os.open(os.devnull, os.O_WRONLY)
    except (OSError, ValueError, AttributeError):  # no real stderr: nothing to quieten
        return
    os.dup2(null, 2)
    os.close(null)
    _SAVED_STDERR[0] = saved


def _restore_stderr() -> None:
    """File descriptor 2 back where it was (after :func:`_quiet_stderr`)."""
    import os
    import sys

    saved = _SAVED_STDERR[0]
    if saved < 0:
        return
    try:
        sys.stderr.flush()  # what was said meanwhile goes to the null device
    except (OSError, ValueError, AttributeError):
        pass
    os.dup2(saved, 2)
    os.close(saved)
    _SAVED_STDERR[0] = -1


def ignore_stops() -> None:
    """SIGTERM, SIGHUP and SIGINT ignored from here on (the command's outcome is decided)."""
    import signal

    for name in STOP_SIGNALS:
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), signal.SIG_IGN)


def stop_on_signals(*, quiet: bool = False) -> None:
    """In the ``spiralcap`` command: SIGTERM, SIGHUP and SIGINT are recorded and raise
    :class:`Terminated` in the main thread, once; a second one while it cleans up ends the
    process at once (the default action; its workers then end through ``PR_SET_PDEATHSIG``).

    With ``quiet`` (the command, whose :func:`spiralcap.cli.main` calls :func:`settle` and
    then says how it ended), stderr is quietened from the request on (:func:`_quiet_stderr`).
    """
    import signal

    _QUIET[0] = quiet
    for name in STOP_SIGNALS:
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), _stop)


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
