"""Gaussmeter survey CSV files (``spiralcap calibrate``, the report's calibration section).

ETH mag_manip's convention: one row per probe position and current setting, columns ``x_m,
y_m, z_m`` (probe position from the coil centre, m), ``I_x_A, I_y_A, I_z_A`` (pair currents, A)
and ``Bx_T, By_T, Bz_T`` (the reading, T), in any order; any other column is refused (units are
in the names: a column in mT or mm is a different column, not a silent factor of 1000). Blank
lines and lines starting with ``#`` are skipped.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any

from spiralcap.core.errors import DataError, csv_number

__all__ = ["COLUMNS", "read_survey_csv"]

COLUMNS = ("x_m", "y_m", "z_m", "I_x_A", "I_y_A", "I_z_A", "Bx_T", "By_T", "Bz_T")
#: Largest pair current a survey row may hold, A (limits.current_A's range).
MAX_CURRENT_A = 1e3
#: Largest field component a survey row may hold, T (no air-cored coil set makes 10 T).
MAX_FIELD_T = 10.0
#: Farthest probe coordinate read, m (the model's room; calibrate refuses far less).
MAX_POSITION_M = 100.0
#: Most survey rows read.
MAX_ROWS = 1_000_000


def read_survey_csv(path: str | Path) -> Any:
    """The survey as a :class:`coils.calibration.Survey` (SI), every cell checked.

    Raises
    ------
    DataError
        Unreadable file, a missing, repeated or unknown column, a cell that is empty, not a
        finite number or out of range (naming file line, data row and column), or no rows.
    """
    import numpy as np

    from coils.calibration import Survey
    from spiralcap.design import read_text_file

    p = Path(path)
    text = read_text_file(p, "survey file")
    lines = [
        (i + 1, line)
        for i, line in enumerate(text.splitlines())
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not lines:
        raise DataError(f"{p}: no header row (expected columns {', '.join(COLUMNS)})")
    header_no, header_text = lines[0]
    header = [h.strip() for h in _split(header_text, f"{p} line {header_no}")]
    _check_header(header, f"{p} line {header_no}")
    if len(lines) - 1 > MAX_ROWS:
        raise DataError(f"{p}: {len(lines) - 1} data rows; at most {MAX_ROWS}")
    order = [header.index(c) for c in COLUMNS]
    table = np.empty((len(lines) - 1, len(COLUMNS)))
    for row_no, (line_no, line) in enumerate(lines[1:], start=1):
        where = f"{p} line {line_no} (data row {row_no})"
        cells = _split(line, where)
        if len(cells) != len(header):
            raise DataError(f"{where}: {len(cells)} cells for {len(header)} columns")
        for j, idx in enumerate(order):
            table[row_no - 1, j] = _cell(cells[idx].strip(), COLUMNS[j], where)
    if len(table) == 0:
        raise DataError(f"{p}: a header but no data rows")
    return Survey(table[:, 0:3], table[:, 3:6], table[:, 6:9])


def _check_header(header: list[str], where: str) -> None:
    for col in header:
        if col not in COLUMNS:
            raise DataError(
                f"{where}: column {col[:40]!r} is not a survey column (allowed: "
                f"{', '.join(COLUMNS)}; units are in the names, nothing else is read)"
            )
        if header.count(col) > 1:
            raise DataError(f"{where}: column {col!r} appears more than once")
    missing = [c for c in COLUMNS if c not in header]
    if missing:
        raise DataError(f"{where}: missing column(s) {', '.join(missing)}")


def _cell(raw: str, col: str, where: str) -> float:
    value = csv_number(raw, col, where)
    if col.endswith("_m") and abs(value) > MAX_POSITION_M:
        raise DataError(
            f"{where}, column {col}: {raw} m; at most {MAX_POSITION_M:g} m from the centre (a "
            "position in mm belongs in metres here)"
        )
    if col.startswith("I_") and abs(value) > MAX_CURRENT_A:
        raise DataError(f"{where}, column {col}: {raw} A; at most {MAX_CURRENT_A:g} A in size")
    if col.startswith("B") and abs(value) > MAX_FIELD_T:
        raise DataError(
            f"{where}, column {col}: {raw} T; at most {MAX_FIELD_T:g} T in size (a field in mT "
            "or uT belongs in tesla here)"
        )
    return value


def _split(line: str, where: str) -> list[str]:
    """One CSV line as cells; a malformed line is a DataError naming the line."""
    try:
        return next(csv.reader([line]), [])
    except csv.Error as exc:
        raise DataError(f"{where}: not a CSV row ({exc})") from None
