"""``spiralcap sweep``: evaluate or re-optimise across a grid of design keys."""

from __future__ import annotations

import argparse
import csv
import io
import math
from typing import Any

from spiralcap.commands._common import (
    add_design_arguments,
    check_outputs,
    design_from_args,
    design_paths,
    print_json,
)
from spiralcap.core.errors import InputError


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
    from spiralcap.commands.uncertainty import add_execution_arguments

    add_execution_arguments(parser)  # --workers N | --dask ADDRESS (for --optimize sweeps)
    parser.add_argument(
        "--csv", metavar="FILE", help="write the table as CSV to FILE (SI columns, as --json)"
    )
    parser.add_argument(
        "--plot",
        metavar="FIGURE.png",
        help="also draw the sweep (.png, .svg or .pdf): one key -> the outputs against it; "
        "two keys -> a margin map with the infeasible region and the step-out boundary",
    )


#: SI output column -> (column shown in the text table, factor): the report's units.
_SHOWN = {
    "margin_Nm": ("margin_mNm", 1e3),
    "field_amplitude_T": ("field_mT", 1e3),
    "speed_m_s": ("speed_mm_s", 1e3),
}


def _shown_rows(header: list[str], rows: list[list]) -> tuple[list[str], list[list]]:
    """The table in engineering units (mN·m, mT, mm/s); names say the unit."""
    cols = [(_SHOWN.get(h, (h, 1.0))) for h in header]
    out = []
    for r in rows:
        out.append(
            [
                "–"  # an unbuildable point has no numbers: a dash, not "nan"
                if isinstance(v, float) and math.isnan(v)
                else v * f
                if f != 1.0 and isinstance(v, (int, float)) and not isinstance(v, bool)
                else v
                for v, (_, f) in zip(r, cols, strict=True)
            ]
        )
    return [c for c, _ in cols], out


def _rows(result) -> tuple[list[str], list[list]]:
    header = [*result.inputs, *result.outputs]
    cols = [*result.inputs.values(), *result.outputs.values()]
    return header, [
        [c[i].item() if hasattr(c[i], "item") else c[i] for c in cols] for i in range(len(cols[0]))
    ]


def _check_options(args: argparse.Namespace) -> None:
    """The output paths, ``--workers`` and ``--dask`` checked (InputError, exit 2)."""
    check_outputs({"--csv": args.csv, "--plot": args.plot}, design_paths(args))
    if not 1 <= args.workers <= 64:
        raise InputError("--workers", args.workers, "a whole number in [1, 64]")
    if args.dask is not None and not args.optimize:
        raise InputError("--dask", args.dask, "only with --optimize (evaluation sweeps run here)")


def _checked_axes(args: argparse.Namespace) -> list[Any]:
    """The ``--over`` axes, with ``--plot`` checked against them (InputError, exit 2)."""
    from spiralcap.sweep import parse_over

    axes = [parse_over(o) for o in args.over]
    if len({a.key for a in axes}) != len(axes):
        raise InputError("--over", args.over, "each key at most once")
    if args.plot:
        from spiralcap.commands._plot import check_figure_path

        check_figure_path("--plot", args.plot)
        if len(axes) > 2:
            raise InputError("--plot", args.plot, "a sweep over one or two keys (--over)")
    return axes


def run(args: argparse.Namespace) -> int:
    from spiralcap.design import write_files_atomic
    from spiralcap.sweep import sweep

    _check_options(args)
    design = design_from_args(args)
    axes = _checked_axes(args)
    from spiralcap.progress import progress_bar
    from spiralcap.stopping import checked

    stage = "re-optimising" if args.optimize else "evaluating"
    with progress_bar(stage, unit="point") as progress:
        result = sweep(
            design,
            axes,
            optimize=args.optimize,
            workers=args.workers,
            progress=checked(progress),
            dask=args.dask,
        )
    header, rows = _rows(result)
    outputs: dict[str, str | bytes] = {}
    if args.plot:
        outputs[args.plot] = _plot_bytes(args.plot, design, result, len(axes))
    if args.csv:
        buf = io.StringIO()
        writer = csv.writer(buf)
        writer.writerow(header)
        writer.writerows(rows)
        outputs[args.csv] = buf.getvalue()
    if outputs:
        write_files_atomic(outputs)  # both or neither
    _print(args, design, result, axes, header, rows)
    return 0


def _plot_bytes(path: str, design: Any, result: Any, n_axes: int) -> bytes:
    from spiralcap.commands._plot import figure_bytes
    from spiralcap.figures.sweep import draw_sweep
    from spiralcap.sweep import failing_requirements

    size = (6.4, 4.6) if n_axes == 2 else (6.4, 7.0)
    failing = failing_requirements(design, result) if len(result.axes) == 2 else None
    return figure_bytes(path, lambda fig: draw_sweep(fig, result, failing), size)[0]


def _print(
    args: argparse.Namespace, design: Any, result: Any, axes: list[Any], header: list, rows: list
) -> None:
    """The sweep as JSON, as a table (200 rows at most), or a line saying what was written."""
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

        shown_header, shown_rows = _shown_rows(header, rows)
        shown = shown_rows if len(shown_rows) <= 200 else shown_rows[:200]
        print(format_table(shown_header, shown))
        if len(rows) > 200:
            print(f"... {len(rows) - 200} more rows (use --csv FILE or --json)")
    else:
        print(f"wrote {len(rows)} rows to {args.csv} ({result.mode})")
    if args.plot and not args.json:
        print(f"wrote {args.plot}")
