"""``spiralcap calibrate FIELD.csv [DESIGN...] -o cal.toml``: the lab's coils from a field survey.

The CSV follows ETH mag_manip's calibration data: one row per probe position and current
setting, columns ``x_m, y_m, z_m`` (probe position from the coil centre, m), ``I_x_A, I_y_A,
I_z_A`` (the pair currents, A) and ``Bx_T, By_T, Bz_T`` (the gaussmeter's reading, T), in any
order; any other column is refused (units are in the names: a column in mT or mm is a
different column, not a silent factor of 1000). Blank lines and lines starting with ``#`` are
skipped.

The fit (:func:`coils.calibration.fit_calibration`): each pair's modelled field shape times a
3 x 3 map near the identity, plus a constant background, by linear least squares, every 5th
row held out for a check. ``-o cal.toml`` writes the ``[calibration]`` table; layered on the
design (``spiralcap evaluate DESIGN cal.toml``) every command then drives the coils through the
calibrated actuation matrix.
"""

from __future__ import annotations

import argparse
import json
import os
from typing import Any

from spiralcap.commands._common import (
    add_design_arguments,
    check_outputs,
    design_from_args,
    format_table,
    print_json,
)
from spiralcap.core.errors import DataError
from spiralcap.survey import COLUMNS, read_survey_csv

#: Probe positions must lie within this fraction of the innermost pair's radius from the centre
#: (closer to the windings the filament model of the pack is not what the probe sees).
POSITION_FRACTION = 0.8
_AXES = ("x", "y", "z")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "survey",
        metavar="FIELD.csv",
        help="gaussmeter survey: columns " + ", ".join(COLUMNS) + " (SI, nothing else)",
    )
    add_design_arguments(parser)
    parser.add_argument(
        "-o",
        "--output",
        metavar="FILE.toml",
        help="write the [calibration] table as TOML, to layer on the design",
    )


def _check_positions(survey: Any, system: Any, where: str) -> None:
    """Every probe position inside the innermost pair (:data:`POSITION_FRACTION` of its radius)."""
    import numpy as np

    reach = POSITION_FRACTION * min(float(p.radius_m) for p in system.pairs)
    dist = np.linalg.norm(survey.points_m, axis=1)
    far = int(np.argmax(dist))
    if dist[far] > reach:
        raise DataError(
            f"{where}, data row {far + 1}: a probe {dist[far] * 1e3:.4g} mm from the centre; "
            f"the survey must stay within {reach * 1e3:.4g} mm ({POSITION_FRACTION:g} of the "
            "innermost pair's radius: nearer the windings the model is not the field)"
        )


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from coils.calibration import fit_calibration
    from spiralcap.assemble.calibration import nominal
    from spiralcap.assemble.coils import build_coils

    check_outputs({"-o": args.output}, [args.survey, *(args.design or [])])
    design = design_from_args(args)
    survey = read_survey_csv(args.survey)
    system = nominal(build_coils(design))
    _check_positions(survey, system, args.survey)
    fit = fit_calibration(
        survey,
        system.field_matrix(survey.points_m),
        system.field_matrix(np.zeros((1, 3)))[0],
        what=args.survey,
    )
    if args.output:
        from spiralcap.design import write_text_atomic

        write_text_atomic(args.output, calibration_toml(fit, args.survey, args.output))
    if args.json:
        print_json(calibration_payload(fit, args.survey, design.source))
    else:
        print(calibration_text(fit, args.survey, design.source))
        if args.output:
            print(f"wrote {args.output}")
    return 0


def _axes(values: Any) -> dict[str, float]:
    return {ax: float(v) for ax, v in zip(_AXES, values, strict=True)}


def calibration_payload(fit: Any, survey_path: str, source: str) -> dict[str, Any]:
    """The JSON of ``spiralcap calibrate --json`` (docs/json/calibrate.schema.json), SI."""
    cal = fit.calibration
    return {
        "survey": str(survey_path),
        "design": source,
        "rows": fit.rows,
        "holdout_rows": int(fit.holdout_rows.sum()),
        "actuation_matrix_T_per_A": fit.actuation_matrix_T_per_A.tolist(),
        "model_actuation_matrix_T_per_A": fit.model_actuation_T_per_A.tolist(),
        "background_field_T": [float(v) for v in cal.background_T],
        "gain_factors": _axes(fit.gain_factors),
        "axis_tilts_deg": _axes(fit.axis_tilts_deg),
        "maps": {ax: cal.maps[k].tolist() for k, ax in enumerate(_AXES)},
        "residual_rms_T": fit.residual_rms_T,
        "residual_max_T": fit.residual_max_T,
        "holdout_rms_T": fit.holdout_rms_T,
        "noise_estimate_T": fit.noise_T,
    }


def calibration_text(fit: Any, survey_path: str, source: str) -> str:
    """The text output: the fit's quality, then per pair gain, tilt and actuation column."""
    import numpy as np

    a = fit.actuation_matrix_T_per_A
    lines = [
        f"survey: {survey_path} ({fit.rows} rows, every 5th held out for the check); "
        f"design: {source}",
        f"residual RMS {fit.residual_rms_T * 1e6:.3g} uT per component, largest "
        f"{fit.residual_max_T * 1e6:.3g} uT; held-out rows {fit.holdout_rms_T * 1e6:.3g} uT",
        "background field "
        + ", ".join(f"{c} {v * 1e6:+.3g}" for c, v in zip(_AXES, fit.calibration.background_T))
        + " uT",
        "",
    ]
    rows = [
        [
            ax,
            f"{fit.gain_factors[k]:.4f}",
            f"{fit.axis_tilts_deg[k]:.3f}",
            ", ".join(f"{v * 1e3:+.5f}" for v in a[:, k]),
            f"{np.linalg.norm(fit.model_actuation_T_per_A[:, k]) * 1e3:.5f}",
        ]
        for k, ax in enumerate(_AXES)
    ]
    lines.append(
        format_table(
            ["pair", "gain", "tilt_deg", "field per amp at centre (x, y, z) mT/A", "model mT/A"],
            rows,
        )
    )
    return "\n".join(lines)


def _matrix(m: Any) -> str:
    return "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in row) + "]" for row in m) + "]"


def calibration_toml(fit: Any, survey_path: str, output_path: str) -> str:
    """The ``[calibration]`` table to layer on the design, with the survey as a record.

    ``survey_csv`` is written relative to the output's folder (a design file's relative path is
    read relative to that file), absolute if the two are on different drives.
    """
    cal = fit.calibration
    try:
        survey = os.path.relpath(
            os.path.abspath(survey_path), os.path.dirname(os.path.abspath(output_path))
        )
    except ValueError:
        survey = os.path.abspath(survey_path)
    lines = [
        f"# spiralcap calibrate of {json.dumps(str(survey_path))}: {fit.rows} rows, residual RMS "
        f"{fit.residual_rms_T * 1e6:.3g} uT (held-out rows {fit.holdout_rms_T * 1e6:.3g} uT)",
        "# layered on the design (spiralcap evaluate DESIGN THIS.toml), the coils' field per",
        "# ampere is each map times the modelled one; the actuation matrix at the centre is",
        "# "
        + "; ".join(
            f"{ax}: ({', '.join(f'{v * 1e3:.5g}' for v in fit.actuation_matrix_T_per_A[:, k])}) "
            "mT/A"
            for k, ax in enumerate(_AXES)
        ),
        "",
        "[calibration]",
    ]
    for k, ax in enumerate(_AXES):
        lines.append(f"map_{ax} = {_matrix(cal.maps[k])}")
    lines.append(
        "background_field_uT = [" + ", ".join(repr(float(v) * 1e6) for v in cal.background_T) + "]"
    )
    lines += [
        "# the survey the maps were fitted to (a record; the report re-reads it)",
        f"survey_csv = {_toml_string(survey)}",
        f"residual_rms_uT = {fit.residual_rms_T * 1e6!r}",
        f"holdout_rms_uT = {fit.holdout_rms_T * 1e6!r}",
        f"rows = {fit.rows}",
    ]
    return "\n".join(lines) + "\n"


def _toml_string(text: str) -> str:
    """``text`` as a TOML basic string (the json escapes are TOML's)."""
    return json.dumps(text, ensure_ascii=False)
