"""Design files: read TOML, apply ``--set`` overrides, validate every key, write the example.

A :class:`Design` is an immutable flat mapping from dotted keys (``coils.x.radius_m``) to
values, in the units the key names. The built-in example design is the schema's defaults.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import stat
import sys
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib

from spiralcap.core.errors import DataError, InputError, short_text
from spiralcap.outputs import (  # noqa: F401 -- where commands have always imported them
    WRITE_THROUGH,
    note_input,
    special_file,
    write_files_atomic,
    write_text_atomic,
)
from spiralcap.schema import KEYS, defaults, validate_value


class Design(Mapping[str, Any]):
    """An immutable, validated design: dotted key -> value (units in the key names)."""

    def __init__(
        self,
        values: Mapping[str, Any],
        source: str = "built-in example",
        origins: Mapping[str, str] | None = None,
    ) -> None:
        merged = defaults()
        for key, value in values.items():
            merged[key] = validate_value(key, value)
        self._values = dict(sorted(merged.items()))
        self.source = source
        #: key -> the design file it was read from (keys from --set or defaults are absent):
        #: a relative path a key holds is resolved against the folder of that file.
        self.origins: dict[str, str] = {k: str(v) for k, v in (origins or {}).items()}

    def __getitem__(self, key: str) -> Any:
        return self._values[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def with_values(self, values: Mapping[str, Any]) -> Design:
        """A new design with ``values`` replacing or adding keys (each validated)."""
        origins = {k: v for k, v in self.origins.items() if k not in values}
        return Design({**self._values, **values}, source=self.source, origins=origins)

    def path_of(self, key: str) -> Path | None:
        """The path the string key ``key`` names, a relative one resolved against the folder of
        the design file that set it (layered or not); from ``--set``, the current folder."""
        value = self._values.get(key)
        if not isinstance(value, str):
            return None
        p = Path(value).expanduser()
        origin = self.origins.get(key)
        if not p.is_absolute() and origin:
            p = Path(origin).parent / p
        return p

    def to_toml(self) -> str:
        """The full design as TOML (every key, defaults included), in table order."""
        return _to_toml(self._values)

    def sha256(self) -> str:
        """Hash of the design's canonical JSON form: same hash, same design."""
        blob = json.dumps(self._values, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(blob.encode()).hexdigest()


def _flatten(
    table: Mapping[str, Any], where: str, prefix: str = "", depth: int = 1
) -> dict[str, Any]:
    """Dotted key -> value of a parsed TOML table; a key of more than :data:`MAX_NESTING` parts
    (``a.b.c...`` written with dots builds nested tables the bracket scan does not see) is a
    one-line DataError before any deeper recursion."""
    flat: dict[str, Any] = {}
    for key, value in table.items():
        dotted = f"{prefix}{key}"
        if isinstance(value, dict):
            if depth >= MAX_NESTING:
                raise DataError(
                    f"{where}: a key nested more than {MAX_NESTING} levels deep "
                    f"({short_text(dotted, 80)}...); design keys have at most {KEY_DEPTH}"
                )
            flat.update(_flatten(value, where, dotted + ".", depth + 1))
        else:
            flat[dotted] = value
    return flat


def parse_set(expr: str) -> tuple[str, Any]:
    """Parse one ``--set dotted.key=value``; the value is read as a TOML value or a bare string."""
    try:
        expr.encode("utf-8")
    except UnicodeEncodeError:  # bytes of the command line that are not UTF-8 (surrogates)
        raise InputError("--set", expr, "text in UTF-8 (this holds bytes that are not)") from None
    key, sep, raw = expr.partition("=")
    key, raw = key.strip(), raw.strip()
    if not sep or not key or not raw:
        raise InputError("--set", expr, "the form dotted.key=value, e.g. coils.x.turns=300")
    try:
        value = _parse_toml(f"v = {raw}", f"--set {key}")["v"]
    except DataError as exc:
        if "not valid TOML" not in str(exc):
            raise InputError("--set", expr, str(exc).split(": ", 1)[1]) from None
        value = raw  # a bare word such as --set tissue.preset=zhou2013-sample3
    if isinstance(value, str) and value.lower() in {"nan", "+nan", "-nan"}:
        value = math.nan
    return key, value


#: Largest design or data file read, bytes (a design file is a few kB; this bounds memory).
MAX_FILE_BYTES = 4_000_000
#: Deepest nesting of arrays and tables a design file may have (the schema needs 3).
MAX_NESTING = 32
#: Most dots between the parts of keys on one line of a design file (a dotted key
#: ``a.b.c...`` of many parts makes the TOML parser build a table per part, in quadratic time).
MAX_KEY_DOTS = 4 * MAX_NESTING
#: Most dot-separated parts of a declared design key.
KEY_DEPTH = max(k.count(".") + 1 for k in KEYS)
#: Most digits of an integer in a design file (the largest count the schema allows has 6).
MAX_INT_DIGITS = 30

_BOMS = (
    (b"\xef\xbb\xbf", "utf-8"),
    (b"\xff\xfe\x00\x00", "utf-32-le"),
    (b"\x00\x00\xfe\xff", "utf-32-be"),
    (b"\xff\xfe", "utf-16-le"),
    (b"\xfe\xff", "utf-16-be"),
)


def read_text_file(path: str | os.PathLike[str], what: str = "design file") -> str:
    """Read a text file as Unicode, never crashing on what it holds.

    UTF-8 with or without a byte-order mark is read; UTF-16 and UTF-32 are read when they
    start with their byte-order mark (Windows editors write them so). Anything else -- another
    encoding, a binary file, a file larger than :data:`MAX_FILE_BYTES` -- is refused.

    Raises
    ------
    DataError
        One line naming the file, and the line and column of the first bad byte where known.
    """
    p = Path(path)
    try:
        if p.is_dir():
            raise DataError(f"{p}: cannot read the {what} (it is a folder)")
        # O_NONBLOCK: opening a FIFO with no writer returns at once instead of blocking; the
        # descriptor's own fstat then decides (the name may have been swapped since)
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0))
        try:
            st = os.fstat(fd)
            if not stat.S_ISREG(st.st_mode):
                raise DataError(
                    f"{p}: cannot read the {what} (not a regular file: a device, FIFO or socket)"
                )
            note_input(p, f"the {what}", st)  # never an output of the same run
            if hasattr(os, "set_blocking"):
                os.set_blocking(fd, True)
            with os.fdopen(fd, "rb", closefd=False) as fh:
                data = fh.read(MAX_FILE_BYTES + 1)
        finally:
            os.close(fd)
    except OSError as exc:
        raise DataError(f"{p}: cannot read the {what} ({exc.strerror or exc})") from None
    if len(data) > MAX_FILE_BYTES:
        raise DataError(
            f"{p}: the {what} is larger than {MAX_FILE_BYTES // 1_000_000} MB; "
            "is it the right file?"
        )
    encoding = "utf-8"
    if b"\x00" in data and not data.startswith((b"\xff\xfe", b"\xfe\xff", b"\x00\x00\xfe\xff")):
        line = data[: data.index(b"\x00")].count(b"\n") + 1
        raise DataError(f"{p} line {line}: a NUL byte; this is a binary file, not a {what}")
    for bom, enc in _BOMS:
        if data.startswith(bom):
            data, encoding = data[len(bom) :], enc
            break
    try:
        text = data.decode(encoding)
    except UnicodeDecodeError as exc:
        before = data[: exc.start]
        line = before.count(b"\n") + 1
        col = exc.start - (before.rfind(b"\n") + 1) + 1
        raise DataError(
            f"{p} line {line}, column {col}: not {encoding.upper()} text (byte "
            f"0x{data[exc.start]:02x}); save the {what} as UTF-8"
        ) from None
    if "\x00" in text:
        line = text[: text.index("\x00")].count("\n") + 1
        raise DataError(f"{p} line {line}: a NUL character; this is a binary file, not a {what}")
    return text


def _check_limits(text: str, where: str) -> None:
    """Refuse nesting deeper than :data:`MAX_NESTING`, integers longer than
    :data:`MAX_INT_DIGITS` and lines of more than :data:`MAX_KEY_DOTS` key dots before the
    parser meets them (it would recurse, convert or build nested tables without bound). A light
    scan: brackets, digits and dots outside strings and comments (the dot of a float such as
    ``1.5`` is not a key dot)."""
    depth = run = dots = 0
    quote: str | None = None
    comment = number_dot = False
    line = 1
    for i, ch in enumerate(text):
        if ch == "\n":
            line += 1
            comment = number_dot = False
            quote = None if quote in ('"', "'") else quote
            run = dots = 0
            continue
        if comment or (quote and ch != quote):
            continue
        if quote:
            quote = None
            continue
        if ch.isdigit():
            run += 1
            _check_count(
                run,
                MAX_INT_DIGITS,
                f"{where} line {line}: a number of more than",
                "digits; no design value needs that many",
            )
            continue
        if ch == ".":
            if run and not number_dot and text[i + 1 : i + 2].isdigit():
                number_dot = True  # the dot of a float
            else:
                dots += 1
                _check_count(
                    dots,
                    MAX_KEY_DOTS,
                    f"{where} line {line}: keys with more than",
                    f"dots (design keys have at most {KEY_DEPTH} parts)",
                )
        elif ch != "_":
            number_dot = False
        if ch != "_":
            run = 0
        if ch in "\"'":
            quote = ch
        elif ch == "#":
            comment = True
        elif ch in "[{":
            depth += 1
            _check_count(
                depth,
                MAX_NESTING,
                f"{where} line {line}: arrays or tables nested more than",
                "deep",
            )
        elif ch in "]}":
            depth = max(depth - 1, 0)


def _check_count(count: int, limit: int, before: str, after: str) -> None:
    if count > limit:
        raise DataError(f"{before} {limit} {after}")


def _parse_toml(text: str, where: str) -> dict[str, Any]:
    """Parse TOML inside the limits above; every failure is a one-line DataError."""
    _check_limits(text, where)
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise DataError(f"{where}: not valid TOML: {exc}") from None
    except (ValueError, RecursionError, MemoryError) as exc:  # parser limits
        raise DataError(f"{where}: cannot be read as TOML ({type(exc).__name__})") from None


def _located(exc: InputError, path: Path, text: str, key: str) -> InputError:
    """An InputError from a file's value, as one line that names the file and the key's line."""
    leaf = key.rpartition(".")[2]
    line = next(
        (
            n
            for n, row in enumerate(text.splitlines(), start=1)
            if row.split("=", 1)[0].strip().strip("\"'") in (leaf, key)
        ),
        None,
    )
    where = f"{path} line {line}" if line else str(path)
    return InputError(exc.key, exc.value, exc.allowed, where=where)


def load_design(
    path: str | os.PathLike[str] | Sequence[str | os.PathLike[str]] | None = None,
    overrides: Iterable[str] = (),
) -> Design:
    """Read design files (the built-in example when none), later ones overriding earlier ones
    key by key, then apply the ``--set`` overrides.

    Parameters
    ----------
    path : path, sequence of paths, or None
        One design file or several (``base.toml``, ``fitted.toml``): each file's keys replace
        the same keys of the files before it; keys a later file does not set are kept.
    overrides : iterable of str
        ``dotted.key=value`` expressions applied after every file.

    Raises
    ------
    DataError
        A file is missing, unreadable, not UTF-8/16/32 text, beyond the parser limits, or not
        valid TOML; or a value in it is not allowed (the message names the file and line).
    InputError
        An unknown key, a wrong type or a value outside what the key allows, from ``--set``.
    """
    if path is None:
        paths: list[Path] = []
    elif isinstance(path, (str, os.PathLike)):
        paths = [Path(path)]
    elif isinstance(path, Sequence) and all(isinstance(x, (str, os.PathLike)) for x in path):
        paths = [Path(x) for x in path]
    else:
        raise TypeError(f"path = {path!r:.120}: a design file's path, a list of them, or None")
    if isinstance(overrides, (str, bytes)) or not isinstance(overrides, Iterable):
        raise TypeError(f"overrides = {overrides!r:.120}: a list of 'dotted.key=value' texts")
    overrides = list(overrides)
    if not all(isinstance(x, str) for x in overrides):
        raise TypeError(f"overrides = {overrides!r:.120}: a list of 'dotted.key=value' texts")
    values: dict[str, Any] = {}
    origins: dict[str, str] = {}
    for p in paths:
        text = read_text_file(p)
        layer = _flatten(_parse_toml(text, str(p)), str(p))
        for key, value in layer.items():
            try:
                values[key] = validate_value(key, value)
            except InputError as exc:
                raise _located(exc, p, text, key) from None
            origins[key] = str(p)
    source = " + ".join(str(p) for p in paths) if paths else "built-in example"
    for expr in overrides:
        key, value = parse_set(expr)
        origins.pop(key, None)
        if is_clear(value):  # --set KEY=none: the key as if never set (its default, or unset)
            if key not in KEYS:
                validate_value(key, value)  # an unknown key: the one-line error, with a hint
            values.pop(key, None)
            continue
        values[key] = value
    design = Design(values, source=source, origins=origins)
    _note_named_inputs(design)
    return design


def _note_named_inputs(design: Design) -> None:
    """Every file the design names (:data:`PATH_KEYS`) is an input of this run, read or not:
    never an output of the same run."""
    for key in PATH_KEYS:
        named = design.path_of(key)
        if named is not None:
            note_input(named, f"the file {key} names")


#: Keys whose value is a path to a file the design reads (relative to the file that sets it).
PATH_KEYS = ("tissue.uncertainty.covariance_from", "calibration.survey_csv")


#: The word that clears a key with ``--set KEY=none`` (no key takes it as a value).
CLEAR = "none"


def is_clear(value: Any) -> bool:
    """Whether a ``--set`` value is the bare word ``none``: clear the key (the files' value and
    any earlier ``--set`` are dropped; the key takes its default, or is unset if optional)."""
    return isinstance(value, str) and value.strip().lower() == CLEAR


def read_toml_file(path: str | os.PathLike[str], what: str = "design file") -> dict[str, Any]:
    """A TOML file through the guarded reader: a regular file only (a FIFO, a device or a folder
    is refused without opening it for long), at most :data:`MAX_FILE_BYTES`, UTF-8/16/32 text,
    nesting and integer size within :data:`MAX_NESTING` and :data:`MAX_INT_DIGITS`.

    Raises
    ------
    DataError
        One line naming the file and what is wrong with it.
    """
    return _parse_toml(read_text_file(path, what), str(path))


def _fmt(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (int, str)):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(_fmt(v) for v in value) + "]"
    raise TypeError(f"cannot write {value!r} as TOML")


def _to_toml(values: Mapping[str, Any], comments: bool = False) -> str:
    order = list(KEYS) + sorted(k for k in values if k not in KEYS)
    # keys declared in later schema blocks join their table (a TOML table is declared once)
    tables = list(dict.fromkeys(k.rpartition(".")[0] for k in order))
    order.sort(key=lambda k: tables.index(k.rpartition(".")[0]))
    lines: list[str] = []
    table = None
    for key in order:
        if key not in values and not (comments and key in KEYS):
            continue
        head, _, leaf = key.rpartition(".")
        if head != table:
            lines += ["", f"[{head}]"]
            table = head
        if comments and key in KEYS:
            lines.append(f"# {KEYS[key].help}; {KEYS[key].allowed}")
        if key in values:
            lines.append(f"{leaf} = {_fmt(values[key])}")
        else:
            lines.append(f"# {leaf} =   (optional; unset by default)")
    return "\n".join(lines).lstrip("\n") + "\n"


def example_toml() -> str:
    """The built-in example design as commented TOML (what ``spiralcap init`` writes)."""
    head = (
        "# spiralcap design file. SI-style units are in every key name.\n"
        "# Any key left out takes the default shown here.\n"
        "# Built-in example: nested three-axis Helmholtz coils around a human abdomen,\n"
        "# a PillCam SB2-size capsule with a 10 deg spiral, Zhou et al. 2013 sample-2\n"
        "# tissue.\n\n"
    )
    return head + _to_toml(defaults(), comments=True)
