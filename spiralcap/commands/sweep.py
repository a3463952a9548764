"""``spiralcap sweep``: evaluate or re-optimise across a grid of design keys."""

from __future__ import annotations

import argparse
import csv
import io
import sys

from spiralcap.commands._common import (
    add_design_arguments,
    check_outputs,
    design_from_args,
    design_paths,
    print_json,
)
from spiralcap.errors import InputError


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_design_arguments(parser)
    parser.add_argument(
        "--over",
        action="append",
        required=True,
        metavar="KEY=START:STOP:N",
        help="sweep a numeric design key over N values (repeat for a grid)",
    )
    parser.add_argument(
        "--optimize",
        action="store_true",
        help="re-optimise at every grid point instead of evaluating",
    )
    parser.add_argument(
        "--workers",
        type=int,
        default=1,
        metavar="N",
        help="worker processes for --optimize sweeps (default 1)",
    )
    parser.add_argument("--csv", metavar="FILE", help="write the table as CSV to FILE")


def _progress(done: int, total: int) -> None:
    width = 30
    filled = int(width * done / total)
    sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {done}/{total}")
    if done == total:
        sys.stderr.write("\n")
    sys.stderr.flush()


def _rows(result) -> tuple[list[str], list[list]]:
    header = [*result.inputs, *result.outputs]
    cols = [*result.inputs.values(), *result.outputs.values()]
    return header, [
        [c[i].item() if hasattr(c[i], "item") else c[i] for c in cols] for i in range(len(cols[0]))
    ]


def run(args: argparse.Namespace) -> int:
    from spiralcap.design import write_text_atomic
    from spiralcap.sweep import parse_over, sweep

    check_outputs({"--csv": args.csv}, design_paths(args))
    if not 1 <= args.workers <= 64:
        raise InputError("--workers", args.workers, "a whole number in [1, 64]")
    design = design_from_args(args)
    axes = [parse_over(o) for o in args.over]
    if len({a.key for a in axes}) != len(axes):
        raise InputError("--over", args.over, "each key at most once")
    progress = _progress if sys.stderr.isatty() else None
    result = sweep(design, axes, optimize=args.optimize, workers=args.workers, progress=progress)
    header, rows = _rows(result)
    if args.csv:
        buf = io.StringIO()
        writer = csv.writer(buf)
        writer.writerow(header)
        writer.writerows(rows)
        write_text_atomic(args.csv, buf.getvalue())
    if args.json:
        print_json(
            {
                "design": design.source,
                "mode": result.mode,
                "over": {a.key: a.values for a in axes},
                "points": [dict(zip(header, r)) for r in rows],
            }
        )
    elif not args.csv:
        from spiralcap.commands._common import format_table

        shown = rows if len(rows) <= 200 else rows[:200]
        print(format_table(header, shown))
        if len(rows) > 200:
            print(f"... {len(rows) - 200} more rows (use --csv FILE or --json)")
    else:
        print(f"wrote {len(rows)} rows to {args.csv} ({result.mode})")
    return 0
