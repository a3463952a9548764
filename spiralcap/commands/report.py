"""``spiralcap report [DESIGN] -o report.html [--pdf report.pdf]``: the engineering report.

Runs the evaluation and the optimisation of the design (the same functions, and the same JSON
dicts, as ``spiralcap evaluate --json`` and ``spiralcap optimize --json``), the coil sizing of
``spiralcap coils --json``, a few sweeps for the trade-off figures, and writes one
self-contained HTML file (figures, styles and the numbers as JSON embedded; nothing fetched)
and, on request, a PDF typeset by Typst (the ``typst`` pip package) from the same document.

Exit status: 0 when the report is written and the optimiser found a feasible design; 3 (as
``spiralcap optimize``) when the report is written but no design meets every requirement inside
the limits -- the report then says so in its first lines; 2 for bad input, with nothing written.
"""

from __future__ import annotations

import argparse
import shlex
import sys
import time
from pathlib import Path

from spiralcap.commands._common import (
    add_design_arguments,
    check_outputs,
    design_from_args,
    design_paths,
    whole_number,
)
from spiralcap.core.errors import InputError

#: Exit status when the report is written but the design is infeasible (as ``optimize``).
EXIT_INFEASIBLE = 3
#: The analysis stages the progress bar names (as :func:`spiralcap.report.data.collect` says).
REPORT_STAGES = (
    "evaluate",
    "optimize",
    "coil sizing",
    "margin curves",
    "power sweep",
    "field maps",
)
_HTML_SUFFIXES = (".html", ".htm")
#: Default ``--workers``: the cores available, up to this many (the analyses run in one other
#: process, then the figures are shared out; more processes than that buy little).
AUTO_WORKERS_MAX = 4


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
        help="also write the report as a typeset PDF (Typst, from the pip package)",
    )
    parser.add_argument(
        "--workers",
        type=whole_number,
        default=None,
        metavar="N",
        help="processes to share the analyses and figures over (default: the cores this "
        f"process may use, at most {AUTO_WORKERS_MAX}; 1 runs everything in this process; the "
        "report is the same either way)",
    )
    parser.add_argument(
        "--compare",
        metavar="DESIGN2",
        help="a second design file to set beside this one (a comparison section)",
    )
    parser.add_argument("--quiet", action="store_true", help="print nothing on success")
    parser.epilog = (
        "exit status: 0 report written, design feasible; 3 report written, but no "
        "design meets every requirement inside the limits (as `spiralcap "
        "optimize`); 2 bad input, nothing written"
    )


def check_output_paths(output: str, pdf: str | None, design_path: str | list[str] | None) -> None:
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
    sources = [design_path] if isinstance(design_path, str) else list(design_path or [])
    for src in sources:
        for flag, path in (("-o", output), ("--pdf", pdf)):
            if path is not None and Path(path).resolve() == Path(src).resolve():
                raise InputError(flag, path, "a file other than the design file")
    check_outputs({"-o": output, "--pdf": pdf}, sources)


def run(args: argparse.Namespace) -> int:
    """Build and write the report; see the module notes for the exit status."""
    t0 = time.perf_counter()
    if args.workers is None:
        from spiralcap.parallel import available_cores

        args.workers = min(available_cores(), AUTO_WORKERS_MAX)
    if not 1 <= args.workers <= 64:
        raise InputError("--workers", args.workers, "a whole number in [1, 64]")
    check_output_paths(args.output, args.pdf, getattr(args, "design", None))
    design = design_from_args(args)
    compare = None
    if args.compare is not None:
        from spiralcap.design import load_design

        compare = load_design(None if args.compare == "builtin" else args.compare)

    from spiralcap.design import write_files_atomic
    from spiralcap.progress import stages
    from spiralcap.report import build_report
    from spiralcap.stopping import checked

    names = REPORT_STAGES + (("comparison",) if compare is not None else ()) + ("figures", "HTML")
    names += ("PDF",) if args.pdf is not None else ()
    with stages(names, description="report", enabled=None if not args.quiet else False) as say:
        report = build_report(
            design,
            pdf=args.pdf is not None,
            workers=args.workers,
            command=_command_line(args),
            progress=checked(say),
            compare=compare,
        )
    outputs: dict[str, str | bytes] = {args.output: report.html}
    if args.pdf is not None and report.pdf is not None:
        outputs[args.pdf] = report.pdf
    write_files_atomic(outputs)  # both or neither; a new file gets the umask's mode
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


def _command_line(args: argparse.Namespace) -> str:
    parts = ["spiralcap", "report"]
    parts += design_paths(args)
    for o in args.overrides:
        parts += ["--set", o]
    parts += ["-o", str(args.output)]
    if args.pdf:
        parts += ["--pdf", str(args.pdf)]
    if args.compare:
        parts += ["--compare", str(args.compare)]
    return shlex.join(parts)
