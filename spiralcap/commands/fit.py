"""``spiralcap fit DATA.csv``: identify the tissue's five viscoelastic constants from bench data.

``--only scale`` (or any subset, ``--only scale,E1``) fits the named parameters with the rest
held at the design's tissue: ``scale`` multiplies the constants not named, in their preset
ratios -- the calibration factor, all a 0.5-3 Hz curve can pin down.

The CSV has a header row with ``frequency_hz`` and ``torque_mNm`` and, optionally,
``helical_angle_deg`` (else every row takes the design's ``capsule.spiral.helical_angle_deg``);
other columns are ignored, blank lines and lines starting with ``#`` are skipped.

The bench is described apart from the patient (issue 36): its lumen, wall thickness, friction,
capsule and spiral wire diameters come from ``--bench-*`` options, else from header lines of the
data file (``# bench_lumen_diameter_mm = 10.9``, the ``tissue.fit.bench_*`` record's names),
else from the bench the design's ``tissue.preset`` was measured on (its lumen, wall and
friction, the paper's capsule ``torque_model.PAPER_CAPSULE``). The patient's anatomy
(``tissue.lumen_diameter_mm``) and capsule never enter the fit: the same bench data give the
same constants with or without a patient's ``--design``. The design gives the material the
fit starts from and holds (its preset, material overrides and ``tissue.scale``).

A fit writes material, not anatomy: the result's ``tissue`` table (and ``[tissue]`` of
``-o FILE.toml``) holds the five fitted constants only, so layering the file on a design
(``evaluate my.toml FILE.toml``) changes its material and never its lumen, wall or friction;
the bench's geometry is a record under ``[tissue.fit]`` (``bench_*`` keys, not read by the
model). A fit whose optimiser did not converge writes nothing and exits 3.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
from array import array
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from spiralcap.commands._common import (
    add_design_arguments,
    check_outputs,
    design_from_args,
    design_paths,
    format_table,
    print_json,
)
from spiralcap.core.constants import from_unit, to_unit
from spiralcap.core.errors import DataError, csv_number

REQUIRED = ("frequency_hz", "torque_mNm")
#: Torques a bench can measure on a capsule, mN·m: 1 nN·m to 100 N·m (beyond: a unit mistake).
TORQUE_RANGE_mNm = (1e-6, 1e5)
#: Highest rotation frequency read, Hz (the design keys' range).
FREQUENCY_MAX_hz = 100.0
#: Lowest rotation frequency read, Hz (the range of operation.frequency_hz; a frequency such as
#: 1e-200 Hz would overflow the fit's time scales).
FREQUENCY_MIN_hz = 1e-3
OPTIONAL = ("helical_angle_deg",)

#: SI field -> (design key without "tissue.", factor SI -> design unit, unit text)
_DISPLAY = {
    "scale": ("scale", 1.0, "-"),
    "E1_Pa": ("E1_kPa", 1e-3, "kPa"),
    "E2_Pa": ("E2_kPa", 1e-3, "kPa"),
    "E3_Pa": ("E3_kPa", 1e-3, "kPa"),
    "eta1_Pa_s": ("eta1_kPa_s", 1e-3, "kPa·s"),
    "eta2_Pa_s": ("eta2_kPa_s", 1e-3, "kPa·s"),
}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "data",
        metavar="DATA.csv",
        help="bench data: columns frequency_hz, torque_mNm [, helical_angle_deg]",
    )
    add_design_arguments(parser, positional=False)
    parser.add_argument(
        "-o",
        "--output",
        metavar="FILE.toml",
        help="write the fitted [tissue] table as TOML (a design-file fragment)",
    )
    parser.add_argument(
        "--plot", metavar="FILE.png", help="draw the data and the fitted curves (png, pdf or svg)"
    )
    add_bench_arguments(parser)
    parser.add_argument(
        "--only",
        metavar="NAMES",
        help="fit only these, comma-separated: scale, E1, E2, E3, eta1, eta2 (the rest stay the "
        "design's; scale multiplies the constants not named), e.g. --only scale",
    )


#: The bench's description: ``--bench-*`` option / data-file header name -> (the design key
#: whose range it takes, the SI factor from its unit).
BENCH_KEYS: dict[str, tuple[str, float]] = {
    "lumen_diameter_mm": ("tissue.lumen_diameter_mm", 1e-3),
    "wall_thickness_mm": ("tissue.wall_thickness_mm", 1e-3),
    "friction_coefficient": ("tissue.friction_coefficient", 1.0),
    "capsule_diameter_mm": ("capsule.diameter_mm", 1e-3),
    "wire_diameter_mm": ("capsule.spiral.wire_diameter_mm", 1e-3),
}
#: The ``--bench-*`` option of each bench name.
BENCH_OPTIONS = {
    "lumen_diameter_mm": "--bench-lumen-mm",
    "wall_thickness_mm": "--bench-wall-mm",
    "friction_coefficient": "--bench-friction",
    "capsule_diameter_mm": "--bench-capsule-mm",
    "wire_diameter_mm": "--bench-wire-mm",
}


def add_bench_arguments(parser: argparse.ArgumentParser) -> None:
    """``--bench-lumen-mm`` ... ``--bench-wire-mm``: the bench, apart from the patient."""
    words = {
        "lumen_diameter_mm": "inner diameter of the bench sample's lumen, mm",
        "wall_thickness_mm": "wall thickness of the bench sample, mm",
        "friction_coefficient": "capsule-mucosa friction coefficient on the bench",
        "capsule_diameter_mm": "diameter of the capsule measured on the bench, mm",
        "wire_diameter_mm": "spiral wire diameter of the bench capsule, mm",
    }
    for name, option in BENCH_OPTIONS.items():
        parser.add_argument(
            option,
            dest=f"bench_{name}",
            type=float,
            default=None,
            metavar="X",
            help=f"{words[name]} (else the data file's '# bench_{name} = X' line, else the "
            "bench of the design's tissue.preset: its own lumen, wall and friction, the "
            "paper's 11 mm capsule with a 1 mm wire)",
        )


def read_bench_header(path: str | Path) -> dict[str, float]:
    """The bench keys a data file states in its comment lines (``# bench_lumen_diameter_mm =
    10.9``), design units.

    Raises
    ------
    DataError
        A ``bench_`` name that is not one of :data:`BENCH_KEYS`, a value that is not a
        number, or one outside the range of its design key; the message names the line.
    """
    from spiralcap.design import read_text_file
    from spiralcap.schema import KEYS

    out: dict[str, float] = {}
    for no, line in enumerate(read_text_file(Path(path), "data file").splitlines(), start=1):
        body = line.strip().lstrip("#").strip()
        if not line.lstrip().startswith("#") or not body.startswith("bench_"):
            continue
        name, sep, raw = body.partition("=")
        name = name.strip().removeprefix("bench_")
        where = f"{path} line {no}"
        if not sep or name not in BENCH_KEYS:
            allowed = ", ".join(f"bench_{k}" for k in BENCH_KEYS)
            raise DataError(
                f"{where}: {_short(body)!r}; a bench header line is NAME = X, NAME one of {allowed}"
            )
        try:
            value = float(raw.strip())
        except ValueError:
            raise DataError(
                f"{where}: bench_{name} = {_short(raw.strip())!r} is not a number"
            ) from None
        key = KEYS[BENCH_KEYS[name][0]]
        if not (math.isfinite(value) and key.check(value)):
            raise DataError(f"{where}: bench_{name} = {value:g}; {key.allowed}")
        if name in out:  # which of two values is meant cannot be guessed
            raise DataError(f"{where}: bench_{name} given a second time")
        out[name] = value
    return out


@dataclass(frozen=True)
class Bench:
    """The bench a fit describes: the tissue sample (the design's material on the bench's
    lumen, wall and friction) and the capsule, SI; ``sources`` says where each bench value
    came from (an option, the data file's header, the preset's bench)."""

    tissue: Any
    geometry: Any
    sources: dict[str, str]


def bench_from(design: Any, options: dict[str, float | None], header: dict[str, float]) -> Bench:
    """The bench: each value from its ``--bench-*`` option, else the data file's header, else
    the bench of the design's ``tissue.preset`` (its own lumen, wall and friction, the paper's
    capsule), never the patient's anatomy or capsule.

    Raises
    ------
    InputError
        A ``--bench-*`` value outside the range of its design key.
    """
    from dataclasses import replace

    import torque_model as tm
    from spiralcap.assemble.tissue import build_tissues
    from spiralcap.core.errors import InputError
    from spiralcap.schema import KEYS

    preset = design.get("tissue.preset", "zhou2013-sample2")
    material = build_tissues(design)[0]  # the design's material (the patient's anatomy after)
    own = tm.preset(preset)
    paper = tm.PAPER_CAPSULE
    default_si = {
        "lumen_diameter_mm": own.lumen_diameter_m,
        "wall_thickness_mm": own.wall_thickness_m,
        "friction_coefficient": material.friction_coefficient,
        "capsule_diameter_mm": paper.body_diameter_m,
        "wire_diameter_mm": paper.wire_diameter_m,
    }
    si: dict[str, float] = {}
    sources: dict[str, str] = {}
    for name, (key, factor) in BENCH_KEYS.items():
        given = options.get(name)
        if given is not None and not (math.isfinite(given) and KEYS[key].check(given)):
            raise InputError(BENCH_OPTIONS[name], given, KEYS[key].allowed)
        if given is not None:
            si[name], sources[name] = given * factor, BENCH_OPTIONS[name]
        elif name in header:
            si[name], sources[name] = header[name] * factor, "the data file's header"
        else:
            capsule = name in ("capsule_diameter_mm", "wire_diameter_mm")
            si[name] = default_si[name]
            sources[name] = "the paper's capsule" if capsule else f"{preset}'s bench"
    tissue = replace(
        material,
        lumen_diameter_m=si["lumen_diameter_mm"],
        wall_thickness_m=si["wall_thickness_mm"],
        friction_coefficient=si["friction_coefficient"],
    )
    geometry = replace(
        paper, body_diameter_m=si["capsule_diameter_mm"], wire_diameter_m=si["wire_diameter_mm"]
    )
    return Bench(tissue, geometry, sources)


def bench_words(bench: Bench) -> str:
    """``lumen 10.9 mm, wall 1 mm, friction 0.28 (zhou2013-sample2's bench); capsule 11 mm
    with a 1 mm spiral wire (the paper's capsule)``: the bench the fit used, with sources."""
    t, g = bench.tissue, bench.geometry
    parts = [
        ("lumen", f"{t.lumen_diameter_m * 1e3:.4g} mm", "lumen_diameter_mm"),
        ("wall", f"{t.wall_thickness_m * 1e3:.4g} mm", "wall_thickness_mm"),
        ("friction", f"{t.friction_coefficient:.4g}", "friction_coefficient"),
        ("capsule", f"{g.body_diameter_m * 1e3:.4g} mm", "capsule_diameter_mm"),
        ("spiral wire", f"{g.wire_diameter_m * 1e3:.4g} mm", "wire_diameter_mm"),
    ]
    return ", ".join(f"{what} {value} ({bench.sources[name]})" for what, value, name in parts)


def parse_only(text: str | None) -> tuple[str, ...] | None:
    """``--only`` as :data:`torque_model.FREE_NAMES` names (None: the five constants).

    Accepts the short names (``E1``), the design keys (``E1_kPa``) and ``scale``.

    Raises
    ------
    InputError
        An unknown or repeated name, or ``scale`` with all five constants.
    """
    from spiralcap.core.errors import InputError
    from torque_model.identification import FREE_NAMES

    if text is None:
        return None
    by_name = {}
    for si, (key, _, _) in _DISPLAY.items():
        by_name[key.lower()] = si
        by_name[key.split("_")[0].lower()] = si
    allowed = "comma-separated names from scale, E1, E2, E3, eta1, eta2"
    out: list[str] = []
    for raw in text.split(","):
        name = by_name.get(raw.strip().lower())
        if name is None or name in out:
            raise InputError("--only", text, allowed + " (each once)")
        out.append(name)
    if not out:
        raise InputError("--only", text, allowed)
    if "scale" in out and all(k in out for k in FREE_NAMES[1:]):
        raise InputError("--only", text, "scale with at most four of the five constants")
    return tuple(out)


def read_bench_csv(path: str | Path) -> dict[str, Any]:
    """Read and check a bench CSV: column name -> values, a float array (frequency Hz, torque
    mN·m, angle deg).

    Raises
    ------
    DataError
        The file cannot be read, a required column is missing, or a cell is empty, not a
        number, not finite, or out of range; the message names the file line, the 1-based data
        row and the column.
    """
    p = Path(path)
    from spiralcap.design import read_text_file

    text = read_text_file(p, "data file")
    # one line at a time, the numbers into compact arrays: a file at the size cap (4 MB,
    # 200,000 rows) costs a few MB here, not a list of every line (issue 39)
    lines = _data_lines(text)
    first = next(lines, None)
    if first is None:
        raise DataError(f"{p}: no header row (expected columns {', '.join(REQUIRED)})")
    header_line, header_text = first
    header = [h.strip() for h in _split(header_text, f"{p} line {header_line}")]
    for col in REQUIRED:
        if col not in header:
            raise DataError(
                f"{p} line {header_line}: missing column {col!r} "
                f"(header has {_short(', '.join(repr(_short(h, 40)) for h in header), 300)})"
            )
    wanted = [c for c in REQUIRED + OPTIONAL if c in header]
    for col in wanted:
        if header.count(col) > 1:  # which of two torque columns is meant cannot be guessed
            raise DataError(f"{p} line {header_line}: column {col!r} appears more than once")
    columns = [(col, header.index(col), array("d")) for col in wanted]
    for row_no, (line_no, line) in enumerate(lines, start=1):
        where = f"{p} line {line_no} (data row {row_no})"
        cells = _split(line, where)
        for col, idx, values in columns:
            raw = cells[idx].strip() if idx < len(cells) else ""
            values.append(_cell(raw, col, where))
    if not columns[0][2]:
        raise DataError(f"{p}: a header but no data rows")
    import numpy as np

    return {col: np.frombuffer(values, dtype=float) for col, _, values in columns}


def _data_lines(text: str) -> Iterator[tuple[int, str]]:
    """(1-based line number, line) of each line of ``text`` that is not blank or a comment,
    one at a time, split where :meth:`str.splitlines` splits (a text with one of its rarer line
    ends, a lone carriage return, a form feed or a Unicode line separator, by it at once)."""
    rare = ("\v", "\f", "\x1c", "\x1d", "\x1e", "\x85", "\u2028", "\u2029")
    if any(c in text for c in rare) or text.count("\r") != text.count("\r\n"):
        lines: Iterable[str] = text.splitlines()
    else:
        lines = _lines_of(text)
    for i, line in enumerate(lines, start=1):
        if line.strip() and not line.lstrip().startswith("#"):
            yield i, line


def _lines_of(text: str) -> Iterator[str]:
    """The lines of ``text`` (ends ``\n`` or ``\r\n``) without copying it whole."""
    start, end = 0, len(text)
    while start < end:
        stop = text.find("\n", start)
        stop = end if stop < 0 else stop
        yield text[start:stop].removesuffix("\r")
        start = stop + 1


def _short(raw: str, limit: int = 60) -> str:
    return raw if len(raw) <= limit else raw[: limit - 3] + "..."


def _split(line: str, where: str) -> list[str]:
    """One CSV line as cells; a malformed line (a cell beyond the csv module's field limit of
    131,072 characters, a stray quote) is a DataError naming the line."""
    try:
        return next(csv.reader([line]), [])
    except csv.Error as exc:
        raise DataError(f"{where}: not a CSV row ({exc})") from None


def _cell(raw: str, col: str, where: str) -> float:
    value = csv_number(raw, col, where)
    if col == "frequency_hz" and value < FREQUENCY_MIN_hz:
        raise DataError(
            f"{where}, column {col}: {_short(raw)} Hz; at least {FREQUENCY_MIN_hz:g} Hz "
            "(as operation.frequency_hz)"
        )
    if col == "torque_mNm" and not TORQUE_RANGE_mNm[0] <= value <= TORQUE_RANGE_mNm[1]:
        raise DataError(
            f"{where}, column {col}: {raw} mN·m; a bench torque is in "
            f"[{TORQUE_RANGE_mNm[0]:g}, {TORQUE_RANGE_mNm[1]:g}] mN·m (> 0: relative residuals)"
        )
    if col == "frequency_hz" and value > FREQUENCY_MAX_hz:
        raise DataError(
            f"{where}, column {col}: {raw} Hz; at most {FREQUENCY_MAX_hz:g} Hz "
            "(as operation.frequency_hz)"
        )
    if col == "helical_angle_deg" and not 0 < value < 90:
        raise DataError(f"{where}, column {col}: {raw} deg; must be in (0, 90)")
    return value


#: Exit status of a fit whose optimiser did not converge (as an infeasible design).
EXIT_NOT_CONVERGED = 3


def run(args: argparse.Namespace) -> int:
    import sys

    import numpy as np

    import torque_model as tm
    from spiralcap.assemble.tissue import tissue_scale
    from spiralcap.commands.torque import check_plot_path
    from torque_model.fit_quality import assess_fit

    if args.plot:
        check_plot_path(args.plot)
    free = parse_only(getattr(args, "only", None))
    check_outputs({"-o": args.output, "--plot": args.plot}, [args.data, *design_paths(args)])
    design = design_from_args(args)
    data = read_bench_csv(args.data)
    n = len(data["frequency_hz"])
    names = [_DISPLAY[k][0].split("_")[0] for k in (free or tm.PARAMETER_NAMES)]
    if n < len(names):
        raise DataError(
            f"{args.data}: {n} data rows for {len(names)} parameters ({', '.join(names)}); "
            f"need at least {len(names)} (--only scale needs one)"
        )
    angle_deg = np.asarray(
        data.get("helical_angle_deg", [design["capsule.spiral.helical_angle_deg"]] * n), dtype=float
    )
    options = {name: getattr(args, f"bench_{name}", None) for name in BENCH_KEYS}
    bench = bench_from(design, options, read_bench_header(args.data))
    _check_angles(bench.geometry, angle_deg, args.data)
    base = bench.tissue
    scale = tissue_scale(design)
    result = tm.identify(
        np.asarray(data["frequency_hz"]),
        np.asarray(data["torque_mNm"]) * 1e-3,
        from_unit(angle_deg, "deg"),
        base,
        bench.geometry,
        free=free,
        bounds=scaled_bounds(scale),
    )
    quality = assess_fit(result)
    outputs: dict[str, str | bytes] = {}
    if args.output and result.success:
        outputs[args.output] = tissue_toml(result, args.data, quality, scale)
    if args.plot and result.success:
        from spiralcap.figures.torque import figure_bytes, plot_fit

        outputs[args.plot] = figure_bytes(plot_fit, args.plot, result)[0]
    if outputs:
        from spiralcap.design import write_files_atomic

        write_files_atomic(outputs)  # both or neither
    if args.json:
        payload = fit_payload(result, args.data, design.source, quality, scale)
        print_json({**payload, "bench_sources": bench.sources})
    else:
        _print_text(result, args.data, design.source, bench_words(bench), quality, scale)
        for path in outputs:
            print(f"wrote {path}")
    if not result.success:
        print(
            "spiralcap fit: the optimiser did not converge "
            f"({result.message.rstrip('.')}); nothing written",
            file=sys.stderr,
        )
        return EXIT_NOT_CONVERGED
    return 0


def _check_angles(geometry: Any, angle_deg: Any, data_path: str) -> None:
    """Each helical angle of the data must make a spiral on the bench capsule whose turns do
    not touch and whose cut D' describes (``capsule.min_helical_angle_rad``)."""
    import capsule as cap
    from spiralcap.assemble.system import MIN_MODEL_ANGLE_deg

    g = geometry
    helix = cap.helix_diameter_m(g.body_diameter_m, g.wire_diameter_m)
    least = max(
        MIN_MODEL_ANGLE_deg,
        to_unit(cap.min_helical_angle_for_clearance_rad(helix, g.wire_diameter_m, g.starts), "deg"),
    )
    for a in sorted({float(x) for x in angle_deg}):
        if not least <= a < 90:
            raise DataError(
                f"{data_path}: helical_angle_deg = {a:g}; on the bench capsule "
                f"({g.body_diameter_m * 1e3:g} mm, a {g.wire_diameter_m * 1e3:g} mm wire) an "
                f"angle >= {least:.3g} deg (below it the spiral's turns touch or the paper's "
                "profile conversion no longer holds)"
            )


def _notes(flags: tuple[str, ...]) -> list[str]:
    """A parameter's flags with other parameters named by their design keys (E3_kPa)."""
    import re

    def key(m: re.Match[str]) -> str:
        return _DISPLAY[m.group(0)][0]

    pattern = re.compile("|".join(re.escape(k) for k in sorted(_DISPLAY, key=len, reverse=True)))
    return [pattern.sub(key, f) for f in flags]


def constants_table(result: Any, design_scale: float = 1.0) -> dict[str, float]:
    """The five constants of the fit as ``tissue.*`` design keys (kPa, kPa·s).

    All five, fitted or held (times ``scale`` when it is fitted), as the fit returns them:
    the fitted curve needs every one, a held constant taken from whatever preset a layered design
    names would change the curve, and ``tissue.scale`` would also multiply the worst-case
    presets. Lumen, wall thickness and friction are the bench's (:func:`bench_record`).

    A design's ``tissue.*`` constants are before its ``tissue.scale``, which multiplies every
    tissue set: the fitted material is divided by the fitting design's ``design_scale``, so the
    keys set on that design give the fitted curve (written as the fit returns them, a design
    with ``tissue.scale = 2`` would double them again).
    """
    full = result.tissue.as_design_table()
    return {
        _DISPLAY[k][0]: float(full[_DISPLAY[k][0]]) / design_scale for k in tm_parameter_names()
    }


def scaled_bounds(design_scale: float) -> dict[str, tuple[float, float]] | None:
    """The fit's bounds on the five constants times the design's ``tissue.scale`` (None at 1:
    the defaults). The fit works on the scaled material and :func:`constants_table` divides it
    by the scale again, so what ``-o`` writes stays inside the bounds the design keys accept."""
    if design_scale == 1.0:
        return None
    from torque_model.identification import DEFAULT_BOUNDS

    return {
        k: (lo * design_scale, hi * design_scale)
        for k, (lo, hi) in DEFAULT_BOUNDS.items()
        if k != "scale"
    }


#: Most helical angles ``tissue.fit.bench_helical_angles_deg`` records (the schema's bound).
MAX_RECORDED_ANGLES = 64


def bench_record(result: Any) -> dict[str, Any]:
    """The bench the constants were fitted on (design units), for ``[tissue.fit]`` ``bench_*``.

    A record only: lumen, wall thickness and friction of the bench sample, the capsule and wire
    diameters, the helical angles (at most 64, spread over the data's range with both ends,
    when the bench had more) and the frequency range of the data.
    """
    import numpy as np

    full = result.tissue.as_design_table()
    angles = sorted({float(f"{to_unit(float(a), 'deg'):.12g}") for a in result.helical_angle_rad})
    if len(angles) > MAX_RECORDED_ANGLES:  # the key holds 64: spread over the range, ends kept
        pick = np.linspace(0, len(angles) - 1, MAX_RECORDED_ANGLES).round().astype(int)
        angles = [angles[i] for i in pick]
    freq = np.asarray(result.frequency_hz, dtype=float)
    return {
        "lumen_diameter_mm": float(full["lumen_diameter_mm"]),
        "wall_thickness_mm": float(full["wall_thickness_mm"]),
        "friction_coefficient": float(full["friction_coefficient"]),
        "capsule_diameter_mm": float(f"{result.geometry.body_diameter_m * 1e3:.12g}"),
        "wire_diameter_mm": float(f"{result.geometry.wire_diameter_m * 1e3:.12g}"),
        "helical_angles_deg": angles,
        "frequency_range_hz": [float(freq.min()), float(freq.max())],
    }


def fit_payload(
    result: Any,
    data_path: str,
    design_source: str,
    quality: Any = None,
    design_scale: float = 1.0,
) -> dict[str, Any]:
    """The fit as a JSON-ready mapping (design units: kPa, kPa·s, mm, mN·m).

    Every interval is the log-space one (positive); a parameter the data do not bound at all
    has ``identifiable`` false and no ``ci95``. ``tissue`` holds the five constants only (what
    ``-o`` writes into ``[tissue]``: before the fitting design's ``design_scale``,
    :func:`constants_table`), ``bench`` the bench's record; ``model_follows_data`` and
    ``pinned_down`` are the verdicts (with ``quality``, a
    :class:`torque_model.fit_quality.FitQuality`).
    """
    params = {}
    for name in result.free:
        key, factor, unit = _DISPLAY[name]
        entry: dict[str, Any] = {
            "value": result.values[name] * factor,
            "unit": unit,
            "standard_error": result.standard_errors[name] * factor,
            "standard_error_log": result.standard_errors_log[name],
            "identifiable": result.identifiable(name),
            "pinned_down": not result.flags[name],
            "flags": _notes(result.flags[name]),
        }
        if result.identifiable(name):
            lo, hi = result.ci95[name]
            entry["ci95"] = [lo * factor, hi * factor]
        params[key] = entry
    out: dict[str, Any] = {
        "tissue": constants_table(result, design_scale),
        "bench": bench_record(result),
        "fitted": [_DISPLAY[n][0] for n in result.free],
        "parameters": params,
        "pinned_down": {_DISPLAY[n][0]: not result.flags[n] for n in result.free},
        "not_pinned_down": [_DISPLAY[n][0] for n in result.not_pinned_down],
        "data": {
            "frequency_hz": result.frequency_hz,
            "helical_angle_deg": [to_unit(float(a), "deg") for a in result.helical_angle_rad],
            "torque_mNm": result.torque_Nm * 1e3,
            "fitted_torque_mNm": result.predicted_Nm * 1e3,
            "relative_residual": (result.predicted_Nm - result.torque_Nm) / result.torque_Nm,
        },
        "residual_std": residual_std(result),
        "residual_std_basis": "rms" if result.dof <= 0 else "dof",
        "relative_residuals": result.relative,
        "dof": result.dof,
        "effective_parameters": result.effective_parameters,
        "condition_number": result.condition_number,
        "success": result.success,
        "message": result.message,
        "data_file": str(data_path),
        "design": design_source,
    }
    if quality is not None:
        out["model_follows_data"] = bool(quality.follows_data)
        out["fit_quality"] = fit_quality_payload(quality)
    return out


def residual_std(result: Any) -> float:
    """s on the residual degrees of freedom; with none left (as many rows as parameters) the
    root-mean-square residual instead (s itself has no estimate then)."""
    import numpy as np

    if result.dof > 0 and math.isfinite(result.residual_std):
        return float(result.residual_std)
    r = np.asarray(result.residuals, dtype=float)
    return float(np.sqrt(np.mean(r * r))) if r.size else 0.0


def _num(value: float, factor: float = 1.0) -> str:
    """A table number, or in words when it has no finite value (no nan, no inf printed)."""
    if math.isnan(value):
        return "unknown"
    if math.isinf(value):
        return "unbounded"
    return f"{value * factor:.4g}"


def fit_quality_payload(quality: Any) -> dict[str, Any]:
    """:class:`torque_model.fit_quality.FitQuality` as JSON (``verdict`` in words, the
    lack-of-fit test with ``tested`` and ``passed``)."""
    from dataclasses import asdict

    out = asdict(quality)
    out["problems"] = list(quality.problems)
    lof = quality.lack_of_fit
    out["lack_of_fit"] = {
        **asdict(lof),
        "tested": lof.tested,
        "passed": lof.passed,
        "alpha": _lof_alpha(),
    }
    return out


def _lof_alpha() -> float:
    from torque_model.fit_quality import LACK_OF_FIT_ALPHA

    return LACK_OF_FIT_ALPHA


def tissue_toml(result: Any, data_path: str, quality: Any = None, design_scale: float = 1.0) -> str:
    """The fit as a design-file fragment: ``[tissue]`` the five constants (before the fitting
    design's ``tissue.scale``, :func:`constants_table`), ``[tissue.fit]`` the bench's record
    (``bench_*``, not read by the model) and the covariance, with provenance."""
    loose = ", ".join(_DISPLAY[n][0] for n in result.not_pinned_down) or "none"
    fitted = ", ".join(_DISPLAY[n][0] for n in result.free)
    lines = [
        f"# spiralcap fit of {json.dumps(str(data_path))}: {result.frequency_hz.size} points, "
        f"residual std {residual_std(result):.3g} (relative)",
    ]
    lines.append(f"# optimiser: {result.message}")
    if quality is not None:
        lines.append(f"# verdict: {quality.verdict}")
    lines += [
        f"# fitted: {fitted}; the other constants are the design's tissue"
        + (" times scale" if "scale" in result.free else ""),
        f"# not pinned down by the data: {loose}",
        "# [tissue] holds the material only: layered on a design (spiralcap evaluate my.toml",
        "# THIS.toml) it keeps the design's lumen, wall and friction; the bench's are recorded",
        "# under [tissue.fit] and not used by the model.",
    ]
    if design_scale != 1.0:
        lines += [
            f"# The fitting design's tissue.scale ({design_scale:g}) multiplies every tissue set:",
            "# the constants below are the fitted material divided by it, so that on a design",
            "# with that scale they give the fitted curve (on one without it, set scale too).",
        ]
    lines += ["", "[tissue]"]
    lines += [f"{k} = {float(v)!r}" for k, v in constants_table(result, design_scale).items()]
    lines += ["", "[tissue.fit]", "# the bench the constants were fitted on (a record)"]
    lines.append("fitted = [" + ", ".join(f'"{_DISPLAY[n][0]}"' for n in result.free) + "]")
    lines.append(
        "not_pinned_down = ["
        + ", ".join(f'"{_DISPLAY[n][0]}"' for n in result.not_pinned_down)
        + "]"
    )
    for key, value in bench_record(result).items():
        text = (
            "[" + ", ".join(repr(float(x)) for x in value) + "]"
            if isinstance(value, list)
            else repr(float(value))
        )
        lines.append(f"bench_{key} = {text}")
    lines += covariance_toml(result)
    return "\n".join(lines) + "\n"


def covariance_log(result: Any) -> Any:
    """The 5 x 5 covariance of ln(E1, E2, E3, eta1, eta2) the pinned-down parameters carry.

    ``s² (JᵀJ)⁻¹`` of the pinned-down free parameters mapped onto the five constants
    (torque_model.identification, ``FitResult.covariance_log``): rows and columns of constants
    held fixed or left loose by the data are zero, a fitted ``scale`` moves the constants it
    multiplies together. None when the data pin nothing down.
    """
    import numpy as np

    cov = result.covariance_log
    return None if cov is None or not np.all(np.isfinite(cov)) else np.asarray(cov, dtype=float)


def covariance_toml(result: Any) -> list[str]:
    """``covariance_log`` lines of ``[tissue.fit]`` (tissue.uncertainty.covariance_from).

    Layout: ``covariance_log``, a 5 x 5 list of rows over ln(E1, E2, E3, eta1, eta2), inside
    the ``[tissue.fit]`` table :func:`tissue_toml` opens; the parameters it covers are named in
    the comment above it.
    """
    cov = covariance_log(result)
    head = ["", "# covariance of ln(E1, E2, E3, eta1, eta2) from the fit, for"]
    head.append("# tissue.uncertainty.covariance_from = <this file>")
    if cov is None:
        loose = ", ".join(_DISPLAY[n][0] for n in result.not_pinned_down) or "residual dof"
        return [*head, f"# not written: the data do not pin down {loose}"]
    pinned = ", ".join(_DISPLAY[n][0] for n in result.pinned_down)
    head.append(f"# carried by what the data pin down: {pinned}; rows and columns of constants")
    head.append("# held fixed or not pinned down are zero (give those a *_sigma_log if uncertain)")
    rows = ",\n".join("  [" + ", ".join(repr(float(x)) for x in r) + "]" for r in cov)
    return [*head, f"covariance_log = [\n{rows},\n]"]


def tm_parameter_names() -> tuple[str, ...]:
    """The five constants' SI names (torque_model.PARAMETER_NAMES)."""
    from torque_model.identification import PARAMETER_NAMES

    return tuple(PARAMETER_NAMES)


def _interval_text(result: Any, name: str, factor: float) -> str:
    """A parameter's 95 % interval in the table, or why it has none."""
    if result.identifiable(name):
        lo, hi = result.ci95[name]
        return f"[{lo * factor:.4g}, {hi * factor:.4g}]"
    if result.dof <= 0:
        return "unknown (no residual degree of freedom)"
    return "not identifiable"


def _parameter_rows(result: Any) -> list[list[Any]]:
    rows = []
    for name in result.free:
        key, factor, unit = _DISPLAY[name]
        rows.append(
            [
                key,
                result.values[name] * factor,
                unit,
                math.exp(result.standard_errors_log[name]) if result.identifiable(name) else "-",
                _interval_text(result, name, factor),
                "NOT pinned down" if result.flags[name] else "pinned down",
            ]
        )
    return rows


#: Most data rows the text output lists (the rest: ``--json``).
MAX_TEXT_ROWS = 200


def _residual_rows(result: Any, limit: int | None = None) -> list[list[Any]]:
    """The data rows with their fitted torque and relative residual (the first ``limit``)."""
    end = result.frequency_hz.size if limit is None else limit
    points = zip(
        result.frequency_hz[:end],
        result.helical_angle_rad[:end],
        result.torque_Nm[:end],
        result.predicted_Nm[:end],
        strict=True,
    )
    return [
        [
            i + 1,
            float(f),
            to_unit(float(a), "deg"),
            float(y) * 1e3,
            float(m) * 1e3,
            100.0 * (float(m) - float(y)) / float(y),
        ]
        for i, (f, a, y, m) in enumerate(points)
    ]


def _verdict_lines(result: Any, quality: Any) -> list[str]:
    """The verdict in plain words: whether the model follows the data (the lack-of-fit test),
    then what is pinned down -- one story, as the JSON's ``model_follows_data`` and
    ``pinned_down`` tell it."""
    if quality is None:
        return []
    lof = quality.lack_of_fit
    loose = [_DISPLAY[n][0] for n in result.not_pinned_down]
    pinned = [_DISPLAY[n][0] for n in result.pinned_down]
    problems = [f"  - {why}" for why in quality.problems]
    if not result.success:
        return [
            "NOT CONVERGED -- nothing written; the values above are the optimiser's last point, "
            "not a fit:",
            *problems,
        ]
    if quality.verdict == "too few points to test whether the model follows these data":
        return ["NOT TESTED whether the model follows these data:", *problems]
    if not quality.follows_data:
        narrow = (
            f" The narrow intervals of {', '.join(pinned)} assume the model is right."
            if pinned
            else ""
        )
        return [
            "THE MODEL DOES NOT FOLLOW THESE DATA -- the values above are the best this model's "
            f"shape can do, not tissue properties.{narrow}",
            *problems,
        ]
    lines = [
        f"The model follows these data: lack-of-fit F test against the {lof.test} (noise "
        f"{100 * lof.reference_residual_std:.3g} %), F = {lof.f_statistic:.3g}, "
        f"p = {lof.p_value:.2g} >= {_lof_alpha():g}."
    ]
    if not quality.plausible:
        lines += ["IMPLAUSIBLE: the model follows these data, but:", *problems]
    if loose:
        lines.append(
            f"NOT PINNED DOWN by these data: {', '.join(loose)} -- the values above reproduce "
            "the measured curve but are not unique; do not read them as tissue properties."
        )
    else:
        lines.append(f"Pinned down by these data: {', '.join(pinned)}.")
    return lines


def _print_text(
    result: Any,
    data_path: str,
    design_source: str,
    bench: str,
    quality: Any = None,
    design_scale: float = 1.0,
) -> None:
    print(
        f"tissue identification from {data_path} ({result.frequency_hz.size} points, "
        f"{result.dof} residual degree{'' if result.dof == 1 else 's'} of freedom; material "
        f"from the design: {design_source})"
    )
    print(f"bench used (a record under [tissue.fit], not written into [tissue]): {bench}")
    headers = ["parameter", "value", "unit", "std error ×/÷", "95 % interval", "status"]
    print(format_table(headers, _parameter_rows(result)))
    held = [_DISPLAY[k][0] for k in tm_parameter_names() if k not in result.free]
    if held:
        times = " (times scale)" if "scale" in result.free else ""
        print(f"held at the design's tissue{times}: {', '.join(held)}")
    for name in result.not_pinned_down:
        print(f"  {_DISPLAY[name][0]}: " + "; ".join(_notes(result.flags[name])))
    if design_scale != 1.0:
        print(
            f"the values above are the fitted material; the design's tissue.scale "
            f"({design_scale:g}) multiplies every tissue set, so -o and the JSON 'tissue' table "
            "hold them divided by it (on this design they give the fitted curve)"
        )
    for line in _verdict_lines(result, quality):
        print(line)
    print()
    rows = _residual_rows(result, MAX_TEXT_ROWS)
    print(
        format_table(
            ["row", "frequency_hz", "helical_angle_deg", "torque_mNm", "fitted_mNm", "residual_%"],
            rows,
        )
    )
    if result.frequency_hz.size > len(rows):
        print(f"... {result.frequency_hz.size - len(rows)} more rows (--json gives every row)")
    basis = "" if result.dof > 0 else ", root mean square: no residual degree of freedom is left"
    print(
        f"residual std {100 * residual_std(result):.3g} % (relative{basis}); optimiser: "
        f"{result.message}"
    )
    print(
        "to use: layer -o FILE on a design (spiralcap evaluate my.toml FILE: the material "
        "changes, the design's lumen, wall and friction stay), or --set tissue.KEY=VALUE for "
        "each key of the JSON 'tissue' table"
    )
