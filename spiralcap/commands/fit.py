"""``spiralcap fit DATA.csv``: identify the tissue's five viscoelastic constants from bench data.

``--only scale`` (or any subset, ``--only scale,E1``) fits the named parameters with the rest
held at the design's tissue: ``scale`` multiplies the constants not named, in their preset
ratios -- the calibration factor, all a 0.5-3 Hz curve can pin down.

The CSV has a header row with ``frequency_hz`` and ``torque_mNm`` and, optionally,
``helical_angle_deg`` (else every row takes the design's ``capsule.spiral.helical_angle_deg``);
other columns are ignored, blank lines and lines starting with ``#`` are skipped. Lumen, wall
thickness and friction come from the design's tissue. The result's ``tissue`` table holds valid
``tissue.*`` design keys: ``--set tissue.KEY=VALUE`` for each, or ``-o FILE.toml``, reproduces
the fitted model.
"""

from __future__ import annotations

import argparse
import csv
import math
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
from spiralcap.errors import DataError

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
    parser.add_argument(
        "--only",
        metavar="NAMES",
        help="fit only these, comma-separated: scale, E1, E2, E3, eta1, eta2 (the rest stay the "
        "design's; scale multiplies the constants not named), e.g. --only scale",
    )


def parse_only(text: str | None) -> tuple[str, ...] | None:
    """``--only`` as :data:`torque_model.FREE_NAMES` names (None: the five constants).

    Accepts the short names (``E1``), the design keys (``E1_kPa``) and ``scale``.

    Raises
    ------
    InputError
        An unknown or repeated name, or ``scale`` with all five constants.
    """
    from spiralcap.errors import InputError
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


def read_bench_csv(path: str | Path) -> dict[str, list[float]]:
    """Read and check a bench CSV: column name -> values (frequency Hz, torque mN·m, angle deg).

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
    lines = [
        (i + 1, line)
        for i, line in enumerate(text.splitlines())
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not lines:
        raise DataError(f"{p}: no header row (expected columns {', '.join(REQUIRED)})")
    header_line, header_text = lines[0]
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
    out: dict[str, list[float]] = {c: [] for c in wanted}
    for row_no, (line_no, line) in enumerate(lines[1:], start=1):
        where = f"{p} line {line_no} (data row {row_no})"
        cells = _split(line, where)
        for col in wanted:
            idx = header.index(col)
            raw = cells[idx].strip() if idx < len(cells) else ""
            out[col].append(_cell(raw, col, where))
    if not out[REQUIRED[0]]:
        raise DataError(f"{p}: a header but no data rows")
    return out


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
    if raw == "":
        raise DataError(f"{where}, column {col}: empty cell")
    try:
        value = float(raw)
    except ValueError:
        raise DataError(f"{where}, column {col}: {_short(raw)!r} is not a number") from None
    if not math.isfinite(value):
        raise DataError(f"{where}, column {col}: {raw!r} is not a finite number")
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


def run(args: argparse.Namespace) -> int:
    import numpy as np

    import torque_model as tm
    from spiralcap.assemble.tissue import build_tissues
    from spiralcap.commands.torque import check_plot_path, geometry_from_design

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
    _check_angles(design, angle_deg, args.data)
    base = build_tissues(design)[0]
    result = tm.identify(
        np.asarray(data["frequency_hz"]),
        np.asarray(data["torque_mNm"]) * 1e-3,
        np.radians(angle_deg),
        base,
        geometry_from_design(design),
        free=free,
    )
    table = result.tissue.as_design_table()
    outputs: dict[str, str | bytes] = {}
    if args.output:
        outputs[args.output] = tissue_toml(table, args.data, result)
    if args.plot:
        from spiralcap.figures.torque import figure_bytes, plot_fit

        outputs[args.plot] = figure_bytes(plot_fit, args.plot, result)[0]
    if outputs:
        from spiralcap.design import write_files_atomic

        write_files_atomic(outputs)  # both or neither
    from torque_model.fit_quality import assess_fit

    quality = assess_fit(result)
    if args.json:
        payload = fit_payload(result, table, args.data, design.source)
        payload["fit_quality"] = fit_quality_payload(quality)
        print_json(payload)
        return 0
    _print_text(result, args.data, design.source, base.name, quality)
    for path in (args.output, args.plot):
        if path:
            print(f"wrote {path}")
    return 0


def _check_angles(design: Any, angle_deg: Any, data_path: str) -> None:
    """Each helical angle of the data must make a capsule ``evaluate`` would accept."""
    from spiralcap.assemble import build_capsule
    from spiralcap.errors import InputError

    for a in sorted({float(x) for x in angle_deg}):
        try:
            build_capsule(design.with_values({"capsule.spiral.helical_angle_deg": a}))
        except InputError as exc:
            raise DataError(f"{data_path}: helical_angle_deg = {a:g}: {exc.allowed}") from None


def _notes(flags: tuple[str, ...]) -> list[str]:
    """A parameter's flags with other parameters named by their design keys (E3_kPa)."""
    import re

    def key(m: re.Match[str]) -> str:
        return _DISPLAY[m.group(0)][0]

    pattern = re.compile("|".join(re.escape(k) for k in sorted(_DISPLAY, key=len, reverse=True)))
    return [pattern.sub(key, f) for f in flags]


def fit_payload(
    result: Any, table: dict[str, float], data_path: str, design_source: str
) -> dict[str, Any]:
    """The fit as a JSON-ready mapping (design units: kPa, kPa·s, mm, mN·m).

    Every interval is the log-space one (positive); a parameter the data do not bound at all
    has ``identifiable`` false and no ``ci95``.
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
    return {
        "tissue": table,
        "fitted": [_DISPLAY[n][0] for n in result.free],
        "parameters": params,
        "not_pinned_down": [_DISPLAY[n][0] for n in result.not_pinned_down],
        "data": {
            "frequency_hz": result.frequency_hz,
            "helical_angle_deg": [math.degrees(a) for a in result.helical_angle_rad],
            "torque_mNm": result.torque_Nm * 1e3,
            "fitted_torque_mNm": result.predicted_Nm * 1e3,
            "relative_residual": (result.predicted_Nm - result.torque_Nm) / result.torque_Nm,
        },
        "residual_std": residual_std(result),
        "residual_std_basis": "rms" if result.dof <= 0 else "dof",
        "relative_residuals": result.relative,
        "dof": result.dof,
        "condition_number": result.condition_number,
        "success": result.success,
        "message": result.message,
        "data_file": str(data_path),
        "design": design_source,
    }


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
    """:class:`torque_model.fit_quality.FitQuality` as JSON (``verdict`` in words)."""
    from dataclasses import asdict

    out = asdict(quality)
    out["problems"] = list(quality.problems)
    out["verdict"] = (
        "the model does not follow these data"
        if not quality.follows_data
        else (
            "the model follows these data"
            + ("" if quality.plausible else ", but the values are implausible")
        )
    )
    return out


def tissue_toml(table: dict[str, float], data_path: str, result: Any) -> str:
    """The fitted tissue as a design-file ``[tissue]`` table, with provenance comments."""
    loose = ", ".join(_DISPLAY[n][0] for n in result.not_pinned_down) or "none"
    fitted = ", ".join(_DISPLAY[n][0] for n in result.free)
    lines = [
        f"# spiralcap fit of {data_path}: {result.frequency_hz.size} points, "
        f"residual std {residual_std(result):.3g} (relative)",
        f"# fitted: {fitted}; the other constants are the design's tissue"
        + (" times scale" if "scale" in result.free else ""),
        f"# not pinned down by the data: {loose}",
        "",
        "[tissue]",
    ]
    lines += [f"{k} = {float(v)!r}" for k, v in table.items()]
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
    """``[tissue.fit]`` lines with ``covariance_log`` (tissue.uncertainty.covariance_from).

    Layout: ``[tissue.fit]`` holding ``covariance_log``, a 5 x 5 list of rows over ln(E1, E2,
    E3, eta1, eta2); the parameters it covers are named in the comment above it.
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
    return [*head, "[tissue.fit]", f"covariance_log = [\n{rows},\n]"]


def tm_parameter_names() -> tuple[str, ...]:
    """The five constants' SI names (torque_model.PARAMETER_NAMES)."""
    from torque_model.identification import PARAMETER_NAMES

    return tuple(PARAMETER_NAMES)


def _print_text(
    result: Any, data_path: str, design_source: str, base_name: str, quality: Any = None
) -> None:
    print(
        f"tissue identification from {data_path} ({result.frequency_hz.size} points, "
        f"{result.dof} residual degree{'' if result.dof == 1 else 's'} of freedom; lumen, wall "
        "and friction from "
        f"{base_name}, design: {design_source})"
    )
    rows = []
    for name in result.free:
        key, factor, unit = _DISPLAY[name]
        lo, hi = result.ci95[name]
        rows.append(
            [
                key,
                result.values[name] * factor,
                unit,
                math.exp(result.standard_errors_log[name]) if result.identifiable(name) else "-",
                f"[{lo * factor:.4g}, {hi * factor:.4g}]"
                if result.identifiable(name)
                else "unknown (no residual degree of freedom)"
                if result.dof <= 0
                else "not identifiable",
                "NOT pinned down" if result.flags[name] else "pinned down",
            ]
        )
    print(
        format_table(
            ["parameter", "value", "unit", "std error ×/÷", "95 % interval", "status"], rows
        )
    )
    held = [_DISPLAY[k][0] for k in tm_parameter_names() if k not in result.free]
    if held:
        times = " (times scale)" if "scale" in result.free else ""
        print(f"held at the design's tissue{times}: {', '.join(held)}")
    for name in result.not_pinned_down:
        print(f"  {_DISPLAY[name][0]}: " + "; ".join(_notes(result.flags[name])))
    fixed = result.tissue.as_design_table()
    print(
        f"fixed: lumen_diameter_mm = {fixed['lumen_diameter_mm']:.4g}, wall_thickness_mm = "
        f"{fixed['wall_thickness_mm']:.4g}, friction_coefficient = "
        f"{fixed['friction_coefficient']:.4g}"
    )
    loose = [_DISPLAY[n][0] for n in result.not_pinned_down]
    follows = quality is None or quality.follows_data
    if not follows:
        print(
            "THE MODEL DOES NOT FOLLOW THESE DATA -- the values above are the optimiser's last "
            "point, not tissue properties:"
        )
        for why in quality.problems:
            print(f"  - {why}")
    elif quality is not None and not quality.plausible:
        print("IMPLAUSIBLE: the model follows these data, but:")
        for why in quality.problems:
            print(f"  - {why}")
    if loose and follows:
        print(
            f"NOT PINNED DOWN by these data: {', '.join(loose)} -- the values above reproduce "
            "the measured curve but are not unique; do not read them as tissue properties."
        )
    res_rows = [
        [
            i + 1,
            float(f),
            math.degrees(float(a)),
            float(y) * 1e3,
            float(m) * 1e3,
            100.0 * (float(m) - float(y)) / float(y),
        ]
        for i, (f, a, y, m) in enumerate(
            zip(
                result.frequency_hz,
                result.helical_angle_rad,
                result.torque_Nm,
                result.predicted_Nm,
                strict=True,
            )
        )
    ]
    print()
    print(
        format_table(
            ["row", "frequency_hz", "helical_angle_deg", "torque_mNm", "fitted_mNm", "residual_%"],
            res_rows,
        )
    )
    basis = "" if result.dof > 0 else ", root mean square: no residual degree of freedom is left"
    print(
        f"residual std {100 * residual_std(result):.3g} % (relative{basis}); optimiser: "
        f"{result.message}"
    )
    print("to use: --set tissue.KEY=VALUE for each key of the JSON 'tissue' table, or -o FILE")
