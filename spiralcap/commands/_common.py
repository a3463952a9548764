"""Arguments and output shared by the analysis commands."""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Mapping, Sequence
from typing import Any

from spiralcap.design import Design, load_design


def add_design_arguments(
    parser: argparse.ArgumentParser, *, positional: bool = True, json_flag: bool = True
) -> None:
    """DESIGN (optional; the built-in example when omitted), repeatable --set, and --json."""
    if positional:
        parser.add_argument(
            "design",
            nargs="?",
            metavar="DESIGN",
            help="design TOML file (default: the built-in example)",
        )
    else:
        parser.add_argument(
            "--design", metavar="DESIGN", help="design TOML file (default: the built-in example)"
        )
    parser.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="override a design key after the file, e.g. coils.x.turns=300",
    )
    if json_flag:
        parser.add_argument("--json", action="store_true", help="print JSON instead of text")


def design_from_args(args: argparse.Namespace) -> Design:
    """Load the design named by the arguments and apply the --set overrides."""
    return load_design(getattr(args, "design", None), args.overrides)


def _jsonable(value: Any) -> Any:
    if isinstance(value, Mapping):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if hasattr(value, "tolist"):
        return _jsonable(value.tolist())
    if isinstance(value, float) and not math.isfinite(value):
        return None if math.isnan(value) else ("inf" if value > 0 else "-inf")
    return value


def print_json(payload: Mapping[str, Any]) -> None:
    """Print a mapping as JSON (numpy values converted, NaN as null), with the spiralcap version."""
    from spiralcap import __version__

    json.dump(_jsonable({"spiralcap_version": __version__, **payload}), sys.stdout, indent=2)
    sys.stdout.write("\n")


def format_table(headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """A plain-text table: numbers to 4 significant figures, columns aligned."""

    def cell(v: Any) -> str:
        if isinstance(v, float):
            return f"{v:.4g}"
        return str(v)

    cells = [[cell(v) for v in row] for row in rows]
    widths = [
        max(len(h), *(len(r[i]) for r in cells)) if cells else len(h) for i, h in enumerate(headers)
    ]
    line = "  ".join(h.ljust(w) for h, w in zip(headers, widths))
    out = [line, "  ".join("-" * w for w in widths)]
    out += ["  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in cells]
    return "\n".join(out)
