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
from spiralcap.errors import SpiralcapError

#: name -> (module under spiralcap.commands, one-line help)
COMMANDS: dict[str, tuple[str, str]] = {
    "init": ("init", "write the built-in example design, with comments, to a file"),
    "coils": ("coils", "per-axis coil sizing: field per amp, R, L, voltage, power, heating"),
    "capsule": ("capsule", "capsule figures: magnet moment, spiral pitch, speed, thrust torque"),
    "torque": ("torque", "tissue resistive torque against rotation frequency"),
    "fit": ("fit", "identify tissue parameters from bench torque measurements (CSV)"),
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
    """Entry point: parse, run, and turn every expected error into one line and an exit status."""
    words = sys.argv[1:] if argv is None else argv
    # The top-level parser has only options, so its first other word names the subcommand.
    command = next((w for w in words if not w.startswith("-")), None)
    parser = build_parser(command if command in COMMANDS else None)
    args = parser.parse_args(argv)
    try:
        status = int(args._module.run(args) or 0)
        sys.stdout.flush()  # a full disk behind stdout is found here, not at exit
        return status
    except SpiralcapError as exc:
        print(f"spiralcap {args.command}: error: {one_line(str(exc))}", file=sys.stderr)
        return exc.exit_status
    except BrokenPipeError:  # output piped into `head` and closed early: not an error
        sys.stderr.close()
        return 0
    except OSError as exc:  # stdout on a full disk (``> /dev/full``): an error, never success
        if exc.errno not in _FULL:
            raise
        _discard_stdout()
        print(
            f"spiralcap {args.command}: error: cannot write the output ({exc.strerror})",
            file=sys.stderr,
        )
        return 2
    except KeyboardInterrupt as exc:  # Ctrl-C, or SIGTERM/SIGHUP (stopping.Terminated)
        import signal

        from spiralcap.stopping import requested

        # inside IPOPT the signal ends the solve, which raises its own KeyboardInterrupt
        signum = int(getattr(exc, "signum", 0) or requested() or signal.SIGINT)
        name = signal.Signals(signum).name
        what = "interrupted" if signum == signal.SIGINT else f"stopped by {name}"
        print(f"spiralcap {args.command}: {what}", file=sys.stderr)
        return 128 + signum


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
    """The ``spiralcap`` command: :func:`main` with SIGTERM and SIGHUP stopping it like Ctrl-C
    (:mod:`spiralcap.stopping`), BLAS single-threaded, then exit with its status."""
    import os

    # spiralcap's matrices are small: extra BLAS threads would only spin after each call (a
    # third of the CPU time of `optimize`) and take a core from the report's worker processes.
    # Set before numpy is first imported; a value the user set is kept.
    for var in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")
    from spiralcap.stopping import stop_on_signals

    stop_on_signals()  # SIGTERM, SIGHUP unwind like Ctrl-C: workers stopped, nothing half-written
    sys.exit(main())


if __name__ == "__main__":  # pragma: no cover
    console()
