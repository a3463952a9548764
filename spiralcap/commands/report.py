"""``spiralcap report [DESIGN] -o report.html [--pdf report.pdf]``: the engineering report.

Runs the evaluation and the optimisation of the design (the same functions, and the same JSON
dicts, as ``spiralcap evaluate --json`` and ``spiralcap optimize --json``), the coil sizing of
``spiralcap coils --json``, a few sweeps for the trade-off figures, and writes one
self-contained HTML file (figures, styles and the numbers as JSON embedded; nothing fetched)
and, on request, a PDF made with matplotlib alone.

Exit status: 0 when the report is written and the optimiser found a feasible design; 3 (as
``spiralcap optimize``) when the report is written but no design meets every requirement inside
the limits -- the report then says so in its first lines; 2 for bad input, with nothing written.
"""

from __future__ import annotations

import argparse
import os
import shlex
import sys
import time
from pathlib import Path

from spiralcap.commands._common import add_design_arguments, design_from_args
from spiralcap.errors import InputError

#: Exit status when the report is written but the design is infeasible (as ``optimize``).
EXIT_INFEASIBLE = 3
_HTML_SUFFIXES = (".html", ".htm")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """DESIGN, --set, -o/--output (required), --pdf, --workers, --quiet."""
    add_design_arguments(parser, json_flag=False)
    parser.add_argument(
        "-o",
        "--output",
        required=True,
        metavar="REPORT.html",
        help="where to write the self-contained HTML report (folders are created as needed)",
    )
    parser.add_argument(
        "--pdf",
        metavar="REPORT.pdf",
        help="also write the report as PDF (matplotlib only; no external tools)",
    )
    parser.add_argument(
        "--workers",
        type=int,
        default=1,
        metavar="N",
        help="worker processes for the power-budget re-optimisation sweep (default 1)",
    )
    parser.add_argument("--quiet", action="store_true", help="print nothing on success")
    parser.epilog = (
        "exit status: 0 report written, design feasible; 3 report written, but no "
        "design meets every requirement inside the limits (as `spiralcap "
        "optimize`); 2 bad input, nothing written"
    )


def check_output_paths(output: str, pdf: str | None, design_path: str | None) -> None:
    """Reject output paths before any work is done.

    Raises
    ------
    InputError
        ``-o`` not ending in .html/.htm, ``--pdf`` not ending in .pdf, a path that is an
        existing folder, the two outputs the same file, or an output that is the design file.
    """
    out = Path(output)
    if out.suffix.lower() not in _HTML_SUFFIXES:
        raise InputError("-o", output, "a file name ending in .html or .htm")
    if out.is_dir():
        raise InputError("-o", output, "a file path, not an existing folder")
    if pdf is not None:
        p = Path(pdf)
        if p.suffix.lower() != ".pdf":
            raise InputError("--pdf", pdf, "a file name ending in .pdf")
        if p.is_dir():
            raise InputError("--pdf", pdf, "a file path, not an existing folder")
        if p.resolve() == out.resolve():
            raise InputError("--pdf", pdf, "a different file from -o")
    if design_path is not None:
        src = Path(design_path).resolve()
        for flag, path in (("-o", output), ("--pdf", pdf)):
            if path is not None and Path(path).resolve() == src:
                raise InputError(flag, path, "a file other than the design file")


def run(args: argparse.Namespace) -> int:
    """Build and write the report; see the module notes for the exit status."""
    t0 = time.perf_counter()
    if args.workers < 1:
        raise InputError("--workers", args.workers, "a whole number >= 1")
    check_output_paths(args.output, args.pdf, getattr(args, "design", None))
    design = design_from_args(args)

    from spiralcap.design import write_text_atomic
    from spiralcap.report import build_report

    report = build_report(
        design, pdf=args.pdf is not None, workers=args.workers, command=_command_line(args)
    )
    written = [write_text_atomic(args.output, report.html)]
    if args.pdf is not None:
        assert report.pdf is not None  # built with pdf=True
        written.append(write_text_atomic(args.pdf, report.pdf))
    for path in written:
        _shareable(path)
    elapsed = time.perf_counter() - t0
    if not args.quiet:
        print(
            f"wrote {args.output} ({report.figure_count} figures, "
            f"{len(report.html) / 1e6:.2f} MB) in {elapsed:.1f} s"
        )
        if args.pdf is not None:
            print(f"wrote {args.pdf} ({report.page_count} pages)")
    if not report.feasible:
        print(
            f"spiralcap report: no feasible design: {report.status_message}; the report "
            "says so (exit status 3)",
            file=sys.stderr,
        )
        return EXIT_INFEASIBLE
    return 0


def _shareable(path: Path) -> None:
    """Give a written report the permissions of a normally created file (umask applied).

    ``write_text_atomic`` goes through ``tempfile.mkstemp``, which creates files readable by
    the owner only; a report is meant to be handed on.
    """
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(path, 0o666 & ~umask)


def _command_line(args: argparse.Namespace) -> str:
    parts = ["spiralcap", "report"]
    if getattr(args, "design", None):
        parts.append(str(args.design))
    for o in args.overrides:
        parts += ["--set", o]
    parts += ["-o", str(args.output)]
    if args.pdf:
        parts += ["--pdf", str(args.pdf)]
    return shlex.join(parts)
