"""``spiralcap init PATH``: write the built-in example design with comments."""

from __future__ import annotations

import argparse
from pathlib import Path

from spiralcap.core.errors import InputError
from spiralcap.design import example_toml, write_text_atomic


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("path", metavar="PATH", help="where to write the design TOML")
    parser.add_argument("--force", action="store_true", help="overwrite an existing file")


def run(args: argparse.Namespace) -> int:
    from spiralcap.commands._common import check_outputs

    path = Path(args.path)
    check_outputs({"PATH": args.path})
    if path.exists() and not args.force:
        raise InputError("PATH", str(path), "a file that does not exist yet (or pass --force)")
    write_text_atomic(path, example_toml())
    print(f"wrote {path}")
    return 0
