"""Every figure of the report, drawn from the Python API (``spiralcap.figures``).

Run ``python examples/gallery.py [OUT_DIR]`` (default ``gallery/``): it builds the built-in
design's model, evaluates and optimises it, and writes one SVG per report figure -- the same
functions the report draws with, called on the library's own objects::

    from optimize import evaluate, optimize_design
    from spiralcap import figures
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    design = load_design()
    model = build_model(design)
    ev, res = evaluate(model), optimize_design(model)
    figures.margin_vs_frequency(model, ev, res).figure.savefig("margin.svg")

Each function takes an optional ``ax=`` (or ``fig=`` for the multi-panel ones) to draw into a
figure of your own, and returns a ``Plot(figure, ax, drawn)`` with what it drew.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any


def main(
    out_dir: str = "gallery",
    *,
    power_factors: tuple[float, ...] | None = None,
    refinements: int | None = None,
    fmt: str = "svg",
    uncertainty_samples: int = 1 << 14,
) -> list[Path]:
    """Write every report figure of the built-in design into ``out_dir``; return the paths."""
    import matplotlib

    from optimize import evaluate, optimize_design, prepare
    from spiralcap import figures
    from spiralcap.analysis.coils import analyse_coils
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design
    from spiralcap.figures.style import REPORT_RC
    from spiralcap.uncertainty import study

    design = load_design()
    model = prepare(build_model(design))
    ev, res = evaluate(model), optimize_design(model)
    # the report's uncertainty figure needs a [tissue.uncertainty] table: two inputs
    uncertain = design.with_values(
        {"tissue.uncertainty.scale_sigma_log": 0.3, "tissue.uncertainty.friction_sigma_log": 0.2}
    )
    ws = float(design["workspace.radius_m"])
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    plots = {
        "geometry": lambda: figures.geometry(model, workspace_radius_m=ws),
        "field-maps": lambda: figures.field_maps(model, workspace_radius_m=ws),
        "field-profiles": lambda: figures.uniformity_profile(model),
        "heating": lambda: figures.heating(analyse_coils(design, model)),
        "tissue-torque": lambda: figures.tissue_torque(model, ev, res),
        "margin-frequency": lambda: figures.margin_vs_frequency(model, ev, res),
        "margin-map": lambda: figures.margin_map(model, res, ev),
        "torque-budget": lambda: figures.torque_budget(ev, res),
        "utilisation": lambda: figures.limit_utilisation(res),
        "margin-angle": lambda: figures.margin_vs_angle(model, res, ev),
        "margin-power": lambda: figures.margin_vs_power(
            design, factors=power_factors, refinements=refinements
        ),
        "uncertainty": lambda: figures.tissue_uncertainty(
            study(uncertain, samples=uncertainty_samples, sobol_base=256).result
        ),
        "stray-field": lambda: _stray_field(figures, design, model),
        "calibration": lambda: figures.calibration_residuals(_calibration_check(design)),
    }
    written = []
    with matplotlib.rc_context(REPORT_RC):
        for name, make in plots.items():
            plot = make()
            path = out / f"{name}.{fmt}"
            plot.figure.savefig(path, format=fmt)
            written.append(path)
    return written


def _stray_field(figures: Any, design: Any, model: Any) -> Any:
    """The stray-field map at the operating field, out to 1.25 x the farthest 0.5 mT point."""
    from spiralcap.analysis.coils import analyse_coils

    analysis = analyse_coils(design, model)
    half = 1.25 * max(analysis.stray.fade_distance_m.values())
    return figures.stray_field_map(model, analysis.operating_field_T, half)


def _calibration_check(design: Any) -> Any:
    """The built-in design calibrated from ``examples/field_survey.csv`` and checked against it
    (what ``spiralcap calibrate examples/field_survey.csv -o cal.toml`` and the report do)."""
    import numpy as np

    from coils.calibration import fit_calibration
    from spiralcap.analysis.calibration import calibration_check
    from spiralcap.assemble import build_model
    from spiralcap.assemble.coils import build_coils
    from spiralcap.survey import read_survey_csv

    path = Path(__file__).resolve().with_name("field_survey.csv")
    survey = read_survey_csv(path)
    coils = build_coils(design)
    fit = fit_calibration(
        survey, coils.field_matrix(survey.points_m), coils.field_matrix(np.zeros((1, 3)))[0]
    )
    maps = fit.calibration.maps
    calibrated = design.with_values(
        {
            **{f"calibration.map_{ax}": maps[k].tolist() for k, ax in enumerate("xyz")},
            "calibration.background_field_uT": (fit.calibration.background_T * 1e6).tolist(),
            "calibration.survey_csv": str(path),
        }
    )
    return calibration_check(calibrated, build_model(calibrated))


if __name__ == "__main__":
    for p in main(sys.argv[1] if len(sys.argv) > 1 else "gallery"):
        print(f"wrote {p}")
