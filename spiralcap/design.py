"""Design files: read TOML, apply ``--set`` overrides, validate every key, write the example.

A :class:`Design` is an immutable flat mapping from dotted keys (``coils.x.radius_m``) to
values, in the units the key names. The built-in example design is the schema's defaults.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import sys
import tempfile
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import Any

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10
    import tomli as tomllib

from spiralcap.errors import DataError, InputError
from spiralcap.schema import KEYS, defaults, validate_value


class Design(Mapping[str, Any]):
    """An immutable, validated design: dotted key -> value (units in the key names)."""

    def __init__(self, values: Mapping[str, Any], source: str = "built-in example") -> None:
        merged = defaults()
        for key, value in values.items():
            merged[key] = validate_value(key, value)
        self._values = dict(sorted(merged.items()))
        self.source = source

    def __getitem__(self, key: str) -> Any:
        return self._values[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._values)

    def __len__(self) -> int:
        return len(self._values)

    def with_values(self, values: Mapping[str, Any]) -> Design:
        """A new design with ``values`` replacing or adding keys (each validated)."""
        return Design({**self._values, **values}, source=self.source)

    def to_toml(self) -> str:
        """The full design as TOML (every key, defaults included), in table order."""
        return _to_toml(self._values)

    def sha256(self) -> str:
        """Hash of the design's canonical JSON form: same hash, same design."""
        blob = json.dumps(self._values, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(blob.encode()).hexdigest()


def _flatten(table: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    flat: dict[str, Any] = {}
    for key, value in table.items():
        dotted = f"{prefix}{key}"
        if isinstance(value, dict):
            flat.update(_flatten(value, dotted + "."))
        else:
            flat[dotted] = value
    return flat


def parse_set(expr: str) -> tuple[str, Any]:
    """Parse one ``--set dotted.key=value``; the value is read as a TOML value or a bare string."""
    key, sep, raw = expr.partition("=")
    key, raw = key.strip(), raw.strip()
    if not sep or not key or not raw:
        raise InputError("--set", expr, "the form dotted.key=value, e.g. coils.x.turns=300")
    try:
        value = tomllib.loads(f"v = {raw}")["v"]
    except tomllib.TOMLDecodeError:
        value = raw  # a bare word such as --set tissue.preset=zhou2013-sample3
    if isinstance(value, str) and value.lower() in {"nan", "+nan", "-nan"}:
        value = math.nan
    return key, value


def load_design(
    path: str | os.PathLike[str] | None = None, overrides: Iterable[str] = ()
) -> Design:
    """Read a design file (the built-in example when ``path`` is None) and apply overrides.

    Raises
    ------
    DataError
        The file is missing or is not valid TOML (the message names the line).
    InputError
        An unknown key, a wrong type or a value outside what the key allows.
    """
    values: dict[str, Any] = {}
    source = "built-in example"
    if path is not None:
        p = Path(path)
        try:
            text = p.read_text(encoding="utf-8")
        except OSError as exc:
            raise DataError(f"{p}: cannot read the design file ({exc.strerror or exc})") from None
        try:
            values = _flatten(tomllib.loads(text))
        except tomllib.TOMLDecodeError as exc:
            raise DataError(f"{p}: not valid TOML: {exc}") from None
        source = str(p)
    for expr in overrides:
        key, value = parse_set(expr)
        values[key] = value
    return Design(values, source=source)


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


def write_text_atomic(path: str | os.PathLike[str], text: str | bytes) -> Path:
    """Write a file all at once: to a temporary file beside it, then rename (no half files).

    Parent folders are created as needed.

    Raises
    ------
    DataError
        The folder cannot be created or the file cannot be written (one line, exit 2).
    """
    p = Path(path)
    data = text.encode("utf-8") if isinstance(text, str) else text
    try:
        p.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=p.parent, prefix=f".{p.name}.", suffix=".part")
    except OSError as exc:
        raise DataError(f"{p}: cannot write here ({exc.strerror or exc})") from None
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; give the file ordinary permissions
        os.replace(tmp, p)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise DataError(f"{p}: cannot write ({exc.strerror or exc})") from None
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return p
