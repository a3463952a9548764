"""Arguments and output shared by the analysis commands."""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections.abc import Mapping, Sequence
from typing import Any

from spiralcap.core.errors import InputError
from spiralcap.design import Design, load_design
from spiralcap.outputs import WRITE_THROUGH, check_output, note_input, note_output, special_file


def add_design_arguments(
    parser: argparse.ArgumentParser, *, positional: bool = True, json_flag: bool = True
) -> None:
    """DESIGN... (none: the built-in example; several: later files override earlier ones key by
    key), repeatable --set, and --json."""
    help_ = (
        "design TOML file(s); with several, later files override earlier ones key by key "
        "(default: the built-in example)"
    )
    if positional:
        parser.add_argument("design", nargs="*", metavar="DESIGN", help=help_)
    else:
        parser.add_argument(
            "--design", nargs="+", action="extend", default=[], metavar="DESIGN", help=help_
        )
    parser.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="override a design key after the file(s), e.g. coils.x.turns=300; KEY=none "
        "clears it (its default, or unset)",
    )
    if json_flag:
        parser.add_argument("--json", action="store_true", help="print JSON instead of text")


def allow_negative_numbers(parser: argparse.ArgumentParser) -> None:
    """Let option values that start with a minus sign and are numbers or comma-separated lists of
    numbers (``--heading -1,0,0``, ``--frequency -1e-3``) be values, not options.

    argparse takes a word for an option unless it matches its negative-number pattern (a plain
    ``-1`` or ``-.5``); the parser's pattern is widened to lists and exponents. Safe while no
    option of the parser looks like a negative number itself.
    """
    import re

    parser._negative_number_matcher = re.compile(
        r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?(,[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?)*$"
    )


def whole_number(text: str) -> int:
    """argparse type of a count option: a whole number, also written as ``1e5`` (the bounds are
    checked by the command, naming the option, before any work)."""
    try:
        return int(text)
    except ValueError:
        pass
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if not (math.isfinite(value) and value == int(value)):
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number")
    return int(value)


def design_paths(args: argparse.Namespace) -> list[str]:
    """The design files the arguments name, in order (empty: the built-in example)."""
    given = getattr(args, "design", None)
    if given is None:
        return []
    return [given] if isinstance(given, str) else list(given)


def design_from_args(args: argparse.Namespace) -> Design:
    """Load the design files named by the arguments (layered) and apply the --set overrides."""
    return load_design(design_paths(args) or None, args.overrides)


def check_outputs(outputs: Mapping[str, str | None], inputs: Sequence[str] = ()) -> None:
    """Refuse output paths that cannot be written, before any computation.

    Call first in a command's ``run``. Each output (``{"-o": path, "--pdf": None, ...}``) must
    pass :func:`spiralcap.outputs.check_output` (not a symbolic link, in an existing writable
    folder, not a folder, block device or socket, not a read-only file; a character device or
    FIFO such as ``/dev/null`` is written into); outputs must be distinct files and none may
    be an input file.

    Raises
    ------
    InputError
        Naming the option and the path, with what is wrong.
    """
    seen: dict[str, str] = {}
    sources = {os.path.realpath(x): x for x in inputs}
    for flag, path in outputs.items():
        if path is None:
            continue
        if check_output(flag, str(path)) is not None:
            continue  # a device or FIFO: written into, nothing is created beside it
        real = os.path.realpath(path)
        if real in sources:
            raise InputError(flag, path, f"a file other than the input {sources[real]}")
        if real in seen:
            raise InputError(flag, path, f"a different file from {seen[real]}")
        seen[real] = flag
    for x in inputs:
        note_input(x, "an input of this run")
    for flag, path in outputs.items():
        if path is not None and special_file(str(path)) not in WRITE_THROUGH:
            note_output(flag, str(path))  # also a file a design names (covariance_from)


def _plain(value: Any) -> Any:
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if hasattr(value, "tolist"):
        return _plain(value.tolist())
    return value


def _nonfinite(value: Any) -> str | None:
    """ "unbounded" if ``value`` is or holds an infinity, "undefined" if a NaN, else None."""
    if isinstance(value, float):
        if math.isnan(value):
            return "undefined"
        return "unbounded" if math.isinf(value) else None
    if isinstance(value, list):
        kinds = {_nonfinite(v) for v in value if not isinstance(v, Mapping)} - {None}
        return "undefined" if "undefined" in kinds else (kinds.pop() if kinds else None)
    return None


def _finite(value: Any) -> Any:
    """JSON with one type per field: a number with no finite value is left out, and a flag
    ``<name>_unbounded: true`` (an infinity) or ``<name>_undefined: true`` (a NaN) given in
    its place (docs/json/README.md)."""
    if isinstance(value, Mapping):
        out: dict[str, Any] = {}
        for k, v in value.items():
            kind = _nonfinite(v)
            if kind is None:
                out[k] = _finite(v)
            else:
                out[f"{k}_{kind}"] = True
        return out
    if isinstance(value, list):
        return [_finite(v) for v in value]
    return value


def _jsonable(value: Any) -> Any:
    return _finite(_plain(value))


def print_json(payload: Mapping[str, Any]) -> None:
    """Print a mapping as JSON with the spiralcap version: numpy values converted, every number
    finite (a number with no finite value is replaced by a ``<name>_unbounded`` /
    ``<name>_undefined`` flag)."""
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
