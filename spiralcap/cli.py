"""The ``spiralcap`` console script: one argparse parser, subcommands kept in one table.

Each subcommand lives in ``spiralcap/commands/<name>.py`` with ``add_arguments(parser)`` and
``run(args) -> int``. Command modules import the domain packages inside ``run`` only, so building
the parser stays cheap and ``spiralcap init`` never pays for CasADi or matplotlib.
"""

from __future__ import annotations

import argparse
import errno
import importlib
import sys
from typing import NoReturn

from spiralcap import __version__
from spiralcap.core.errors import SpiralcapError
from spiralcap.outputs import run_files

#: name -> (module under spiralcap.commands, one-line help)
COMMANDS: dict[str, tuple[str, str]] = {
    "init": ("init", "write the built-in example design, with comments, to a file"),
    "coils": ("coils", "per-axis coil sizing: field per amp, R, L, voltage, power, heating"),
    "capsule": ("capsule", "capsule figures: magnet moment, spiral pitch, speed, thrust torque"),
    "torque": ("torque", "tissue resistive torque against rotation frequency"),
    "fit": ("fit", "identify tissue parameters from bench torque measurements (CSV)"),
    "calibrate": ("calibrate", "fit the coils' field to a gaussmeter survey (CSV): cal.toml"),
    "evaluate": ("evaluate", "the design at its operating point: field, torques, margin, limits"),
    "optimize": ("optimize", "choose helical angle, frequency and coil currents for most margin"),
    "waveforms": ("waveforms", "coil currents, voltages and field for a sequence of headings"),
    "sweep": ("sweep", "evaluate or re-optimise across a grid of design keys"),
    "uncertainty": ("uncertainty", "step-out probability and margin spread over uncertain tissue"),
    "report": ("report", "write the engineering report (self-contained HTML, optional PDF)"),
    "compare": ("compare", "two or more designs side by side: changed keys, margins, limits"),
}


def one_line(text: str) -> str:
    """``text`` with control characters escaped (``\\n``, ``\\r``, ``\\x1b``): one line."""
    return "".join(ch if ch.isprintable() or ch == " " else repr(ch)[1:-1] for ch in text)


#: ASCII spellings of the characters the text output uses, for a stream that cannot encode them
#: (``PYTHONIOENCODING=ascii``, an old terminal): ``mN·m`` -> ``mN m``, ``°C`` -> ``deg C``.
ASCII_SPELLINGS = {
    "\u00b7": " ",  # middle dot between units
    "\u00b0": "deg",
    "\u00d7": "x",
    "\u00b1": "+/-",
    "\u00b5": "u",  # micro sign
    "\u00b2": "^2",
    "\u00b3": "^3",
    "\u2212": "-",
    "\u2013": "-",
    "\u2014": "-",
    "\u2264": "<=",
    "\u2265": ">=",
    "\u2248": "~",
    "\u2192": "->",
    "\u2026": "...",
    "\u2018": "'",
    "\u2019": "'",
    "\u201c": '"',
    "\u201d": '"',
    "\u221e": "inf",
    "\u221a": "sqrt",
    "\u03a9": "Ohm",
    "\u0394": "Delta",
    "\u03b1": "alpha",
    "\u03b2": "beta",
    "\u03b7": "eta",
    "\u03bc": "mu",
    "\u03c0": "pi",
    "\u03c1": "rho",
    "\u03c3": "sigma",
    "\u03c4": "tau",
    "\u03c9": "omega",
    "\u03b8": "theta",
    "\u03c6": "phi",
}
ASCII_ERRORS = "spiralcap-ascii"


def _ascii_spelling(char: str, before: str, after: str) -> str:
    """The ASCII spelling of ``char`` between ``before`` and ``after`` (one character each, or
    empty): a word is set apart from letters and digits (``37°`` -> ``37 deg``, ``°C`` ->
    ``deg C``); a Greek mu before a unit letter is the micro prefix (``μm`` -> ``um``)."""
    import unicodedata

    if char == "\u03bc" and after.isalpha():
        return "u"
    text = ASCII_SPELLINGS.get(char)
    if text is None:
        text = unicodedata.normalize("NFKD", char).encode("ascii", "ignore").decode() or "?"
    if len(text) > 1 and text[0].isalpha():
        text = (" " if before.isalnum() else "") + text + (" " if after.isalnum() else "")
    return text


def _ascii_errors(exc: UnicodeError) -> tuple[str, int]:
    """A codec error handler: every character the stream cannot encode in its ASCII spelling."""
    if not isinstance(exc, UnicodeEncodeError):
        raise exc
    text, start, end = exc.object, exc.start, exc.end
    out = [
        _ascii_spelling(text[i], text[i - 1 : i], text[i + 1 : i + 2]) for i in range(start, end)
    ]
    return "".join(out), end


def ascii_fallback(stream: object, defaults: tuple[str, ...] = ("strict",)) -> None:
    """Make ``stream`` write ASCII spellings of the units (``mN m``, ``deg C``) when its encoding
    cannot encode them and its error handler is the default (``PYTHONIOENCODING=ascii``); a
    stream that can, or one the user gave another handler (``ascii:replace``), is left as it is.

    Parameters
    ----------
    stream : text stream
        ``sys.stdout`` or ``sys.stderr`` (anything with ``encoding``, ``errors`` and
        ``reconfigure``; other objects are left alone).
    defaults : tuple of str
        The error handlers taken as Python's default for this stream (``strict`` for stdout;
        ``backslashreplace`` too for stderr, which Python gives it unasked).
    """
    import codecs

    encoding = getattr(stream, "encoding", None)
    if not encoding or getattr(stream, "errors", "strict") not in defaults:
        return
    try:
        "".join(ASCII_SPELLINGS).encode(encoding)
        return
    except UnicodeEncodeError:
        pass
    except LookupError:  # an encoding Python does not know: nothing to adapt
        return
    try:
        codecs.lookup_error(ASCII_ERRORS)
    except LookupError:
        codecs.register_error(ASCII_ERRORS, _ascii_errors)
    reconfigure = getattr(stream, "reconfigure", None)
    if reconfigure is not None:
        try:
            reconfigure(errors=ASCII_ERRORS)
        except (ValueError, OSError):  # a closed or detached stream
            pass


class _Parser(argparse.ArgumentParser):
    """argparse with usage errors on one line (``spiralcap evaluate: error: ...``), exit 2."""

    def error(self, message: str) -> NoReturn:
        text = one_line(" ".join(message.split()))
        self.exit(2, f"{self.prog}: error: {text} (see `{self.prog} --help`)\n")


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The full parser; subcommand modules add their own arguments.

    With ``only`` (a name in :data:`COMMANDS`) every subcommand is still listed, but only that
    one's module is imported and given its arguments: what :func:`main` needs to run it.
    """
    parser = _Parser(
        prog="spiralcap",
        description="Design tool for magnetically actuated spiral-type capsule endoscopes.",
    )
    parser.add_argument("--version", action="version", version=f"spiralcap {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, (module, help_) in COMMANDS.items():
        p = sub.add_parser(name, help=help_, description=help_)
        if only is not None and name != only:
            continue
        mod = importlib.import_module(f"spiralcap.commands.{module}")
        mod.add_arguments(p)
        p.set_defaults(_module=mod)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point: parse, run, and turn every expected error into one line and an exit status.

    A stop request (:mod:`spiralcap.stopping`) wins over whatever the command did after it,
    unless its outputs were already committed: a stopped command exits 128 + the signal number
    with one line, however it ended (an error, a traceback, success).
    """
    from spiralcap import stopping

    stopping.new_run()
    _SAID[0] = False
    ascii_fallback(sys.stdout)
    ascii_fallback(sys.stderr, ("strict", "backslashreplace"))
    words = sys.argv[1:] if argv is None else argv
    # The top-level parser has only options, so its first other word names the subcommand.
    command = next((w for w in words if not w.startswith("-")), None)
    name = command if command in COMMANDS else ""
    try:
        parser = build_parser(command if command in COMMANDS else None)
        args = parser.parse_args(argv)
        with run_files():  # every file this run reads is refused as one of its outputs
            status = int(args._module.run(args) or 0)
        sys.stdout.flush()  # a full disk behind stdout is found here, not at exit
    except BaseException as exc:  # each kind is answered, or raised again, below
        stopping.settle()
        status = _stopped(name, exc) or _failed(name, exc)
    stopping.settle()
    return _after(name, status)


def _prefix(command: str) -> str:
    return f"spiralcap {command}" if command else "spiralcap"


def stop_status() -> int:
    """128 + the recorded stop signal if this run was stopped before its outputs were committed,
    else 0."""
    from spiralcap import stopping

    signum = stopping.requested()
    return 128 + signum if signum and not stopping.committed() else 0


def _stop_line(command: str, signum: int) -> int:
    import signal

    name = signal.Signals(signum).name
    what = "interrupted" if signum == signal.SIGINT else f"stopped by {name}"
    print(f"{_prefix(command)}: {what}", file=sys.stderr)
    _SAID[0] = True
    return 128 + signum


#: Whether this run has said how a stop request ended it (its one line).
_SAID = [False]


def _stopped(command: str, exc: BaseException) -> int:
    """The exit status of a run that ``exc`` ended because it was stopped (0: it was not): a
    recorded stop request (whatever ``exc`` is: an import, a compiled solver or a library may
    turn the interrupt into another error), or a KeyboardInterrupt."""
    import signal

    if stop_status():
        return _stop_line(command, stop_status() - 128)
    if isinstance(exc, KeyboardInterrupt):
        # inside IPOPT the signal ends the solve, which raises its own KeyboardInterrupt
        return _stop_line(command, int(getattr(exc, "signum", 0) or signal.SIGINT))
    return 0


def _failed(command: str, exc: BaseException) -> int:
    """The exit status of a run that ``exc`` ended, with its one line; an unexpected exception
    is raised again (a traceback is a bug)."""
    if isinstance(exc, SpiralcapError):
        print(f"{_prefix(command)}: error: {one_line(str(exc))}", file=sys.stderr)
        return exc.exit_status
    if isinstance(exc, BrokenPipeError):  # output piped into `head` and closed early
        sys.stderr.close()
        return 0
    if isinstance(exc, OSError) and exc.errno in _FULL:  # stdout on a full disk (``> /dev/full``)
        _discard_stdout()
        print(
            f"{_prefix(command)}: error: cannot write the output ({exc.strerror})",
            file=sys.stderr,
        )
        return 2
    raise exc


def _after(command: str, status: int) -> int:
    """The final status: a stop request that came before the outputs were committed turns any
    status into 128 + its signal (one line; said once); one that came after is noted, and the
    command's own status kept (its outputs are complete)."""
    from spiralcap import stopping

    signum = stopping.requested()
    if not signum or status == 128 + signum:
        return status
    if not stopping.committed():
        return _stop_line(command, signum)
    import signal

    print(
        f"{_prefix(command)}: {signal.Signals(signum).name} came after the outputs were "
        "written; they are complete",
        file=sys.stderr,
    )
    _SAID[0] = True
    return status


#: errno values of a write that found no room (full disk, quota, file size limit, I/O error).
_FULL = {errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EIO}


def _discard_stdout() -> None:
    """Point file descriptor 1 at the null device, so the unwritten rest of stdout's buffer
    goes nowhere at exit instead of failing a second time."""
    import os

    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):  # no real stdout (tests capture it)
        pass


def console() -> None:  # pragma: no cover -- the installed ``spiralcap`` command
    """The ``spiralcap`` command: :func:`main` with SIGTERM, SIGHUP and SIGINT stopping it
    (:mod:`spiralcap.stopping`), BLAS single-threaded, then exit with its status (a stopped
    command at once, without waiting for threads)."""
    import os

    # spiralcap's matrices are small: extra BLAS threads would only spin after each call (a
    # third of the CPU time of `optimize`) and take a core from the report's worker processes.
    # Set before numpy is first imported; a value the user set is kept.
    for var in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")
    from spiralcap.stopping import stop_on_signals

    stop_on_signals(quiet=True)  # SIGTERM, SIGHUP, SIGINT: workers stopped, nothing written
    try:
        status = main()
    except KeyboardInterrupt:  # a stop's reminder that came as main was saying how it ended
        from spiralcap.stopping import settle

        settle()
        command = next((w for w in sys.argv[1:] if not w.startswith("-")), "")
        status = _stop_line(command if command in COMMANDS else "", (stop_status() or 130) - 128)
    from spiralcap.stopping import ignore_stops, requested

    # the outcome is decided and said: a stop that comes while the interpreter exits changes
    # nothing (it would otherwise meet the default action Python restores there: killed by the
    # signal, no line, though the outputs are complete)
    ignore_stops()
    if requested() and not _SAID[0]:  # one that came as main returned: said now
        command = next((w for w in sys.argv[1:] if not w.startswith("-")), "")
        status = _after(command if command in COMMANDS else "", status)
    if stop_status():
        # stopped: nothing was committed and every worker is killed; leave now, without the
        # exit handlers that join the threads of a killed pool (they can block)
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
        os._exit(status)
    sys.exit(status)


if __name__ == "__main__":  # pragma: no cover
    console()
