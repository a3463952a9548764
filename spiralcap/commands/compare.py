"""``spiralcap compare A.toml B.toml [...] [--json]``: designs side by side.

Prints the design keys that differ, then the evaluation and the optimisation of each design in
the report's units (mN·m, mT, mm/s), rows whose values differ marked with ``*`` and the
difference to the first design. Exit status 0; 2 for bad input.
"""

from __future__ import annotations

import argparse
import math

from spiralcap.core.errors import InputError

#: Most designs one comparison sets side by side.
MAX_DESIGNS = 16


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """DESIGN... (two or more; ``builtin`` for the built-in example), --set, --json."""
    parser.add_argument(
        "designs",
        nargs="+",
        metavar="DESIGN",
        help="design TOML files to compare (two or more; 'builtin' for the built-in example)",
    )
    parser.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="[N:]KEY=VALUE",
        help="override a key in every design, or in design N only (1-based): 2:limits.power_W=3000",
    )
    parser.add_argument("--json", action="store_true", help="print JSON instead of text")


def load_designs(paths: list[str], overrides: list[str]) -> list:
    """The designs named on the command line with their ``--set`` overrides applied."""
    from spiralcap.design import load_design

    if not 2 <= len(paths) <= MAX_DESIGNS:
        raise InputError(
            "DESIGN",
            f"{len(paths)} designs" if len(paths) > MAX_DESIGNS else paths,
            f"two to {MAX_DESIGNS} design files (or 'builtin'): each is optimised, and a wider "
            "table cannot be read side by side",
        )
    per: list[list[str]] = [[] for _ in paths]
    for o in overrides:
        head, sep, rest = o.partition(":")
        if sep and head.isdigit() and "=" in rest and "=" not in head:
            n = int(head)
            if not 1 <= n <= len(paths):
                raise InputError("--set", o, f"a design number from 1 to {len(paths)}")
            per[n - 1].append(rest)
        else:
            for lst in per:
                lst.append(o)
    return [
        load_design(None if p == "builtin" else p, ov) for p, ov in zip(paths, per, strict=True)
    ]


def _cell(v, exact: bool = False) -> str:
    from spiralcap.compare import shown_value

    if isinstance(v, (list, tuple)) and v and all(isinstance(r, (list, tuple)) for r in v):
        return _matrix_cell(v)
    return shown_value(v, exact)


def _matrix_cell(m) -> str:
    """A matrix key (``tissue.fit.covariance_log``) in a terminal column: its shape and
    diagonal to 4 figures, not 25 numbers in one cell (``--json`` has every entry)."""
    from spiralcap.compare import shown_value

    n, k = len(m), max(len(r) for r in m)
    diagonal = [r[i] if i < len(r) else None for i, r in enumerate(m)]
    return f"{n}×{k}, diagonal {shown_value(diagonal, exact=False)}"


def format_table(headers: list[str], rows: list[list[str]], left: int = 2) -> str:
    """Columns aligned: the first ``left`` columns to the left, the numbers to the right."""
    widths = [max([len(h)] + [len(r[i]) for r in rows]) for i, h in enumerate(headers)]

    def line(cells: list[str]) -> str:
        return "  ".join(
            c.ljust(w) if i < left else c.rjust(w)
            for i, (c, w) in enumerate(zip(cells, widths, strict=True))
        ).rstrip()

    return "\n".join([line(headers), "  ".join("-" * w for w in widths), *map(line, rows)])


def format_comparison(c) -> str:
    """Readable side-by-side text of a :class:`spiralcap.compare.Comparison`."""
    lines = ["designs: " + ", ".join(f"[{i + 1}] {s}" for i, s in enumerate(c.sources)), ""]
    labels = [f"[{i + 1}]" for i in range(len(c.labels))]
    if c.changed_keys:
        lines.append(
            format_table(
                ["changed key", *labels],
                [[k.key, *[_cell(v, exact=True) for v in k.values]] for k in c.changed_keys],
                left=1,
            )
        )
    else:
        lines.append("the designs have the same values for every key")
    for title, rows in (
        ("at the operating point as entered", c.evaluated),
        ("at the optimum", c.optimised),
    ):
        lines += ["", title]
        body = []
        for r in rows:
            vals = r.shown_values()
            delta = ""
            if r.differs and all(isinstance(v, float) and math.isfinite(v) for v in vals):
                delta = f"{vals[-1] - vals[0]:+.4g}"
            body.append(
                [
                    ("* " if r.differs else "  ") + r.quantity,
                    r.unit or "–",
                    *[_cell(v) for v in vals],
                    delta,
                ]
            )
        lines.append(format_table(["quantity", "unit", *labels, f"{labels[-1]} − [1]"], body))
    lines += ["", "* the values differ"]
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    from spiralcap.commands._common import print_json
    from spiralcap.compare import compare_designs, comparison_to_dict

    designs = load_designs(args.designs, args.overrides)
    c = compare_designs(designs)
    if args.json:
        print_json(comparison_to_dict(c))
    else:
        print(format_comparison(c))
    return 0
