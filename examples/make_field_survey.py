"""Write ``examples/field_survey.csv``: a synthetic gaussmeter survey of the built-in coils.

The coils are perturbed the way a real set differs from its drawing -- the x pair's field 7 %
weak (``gain 0.93``: fewer turns than drawn), the y pair turned 1.5 degrees about z on its
frame, the z pair 4 % strong -- and the room adds a background field of (30, -20, 45) uT. The
field is computed by magpylib (:func:`spiralcap.export.to_magpylib`, an independent
Biot-Savart code) at 27 probe positions (a 3 x 3 x 3 grid, 50 mm apart) for 10 current
settings, with 3 uT of Gaussian probe noise (seed 37). Run it from the repository root::

    python examples/make_field_survey.py
    spiralcap calibrate examples/field_survey.csv -o cal.toml
    spiralcap evaluate cal.toml          # the built-in design, calibrated (layered on it)
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

#: The perturbation: (x gain, y pair's turn about z in degrees, z gain), background (T), noise (T).
GAINS = (0.93, 1.0, 1.04)
Y_TURN_DEG = 1.5
BACKGROUND_T = np.array([30e-6, -20e-6, 45e-6])
NOISE_T = 3e-6
#: Current settings (A): all off, each pair alone, pairs together, mixed signs.
SETTINGS_A = np.array(
    [
        [0, 0, 0],
        [5, 0, 0],
        [0, 5, 0],
        [0, 0, 5],
        [5, 5, 0],
        [0, 5, 5],
        [5, 0, 5],
        [5, 5, 5],
        [-5, 3, 2],
        [2, -4, 5],
    ],
    dtype=float,
)
COLUMNS = ("x_m", "y_m", "z_m", "I_x_A", "I_y_A", "I_z_A", "Bx_T", "By_T", "Bz_T")


def perturbed_coils(model: object, currents_A: np.ndarray) -> object:
    """The built-in coils as magpylib objects, perturbed as above, carrying ``currents_A``."""
    from spiralcap.export import to_magpylib

    coils = to_magpylib(model, currents_A=tuple(np.asarray(currents_A) * GAINS))
    for coil in coils.children[2:4]:  # the y pair's two coils
        coil.rotate_from_angax(Y_TURN_DEG, "z", anchor=0)
    return coils


def probe_grid(step_m: float = 0.05) -> np.ndarray:
    """27 probe positions on a 3 x 3 x 3 grid centred on the coils, m."""
    axis = np.array([-step_m, 0.0, step_m])
    return np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), axis=-1).reshape(-1, 3)


def survey_table(seed: int = 37) -> np.ndarray:
    """The survey rows (positions, currents, noisy fields), shape (270, 9), SI."""
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    model = build_model(load_design())
    points = probe_grid()
    rng = np.random.default_rng(seed)
    rows = []
    for currents in SETTINGS_A:
        field = perturbed_coils(model, currents).getB(points) + BACKGROUND_T
        field = field + rng.normal(0.0, NOISE_T, field.shape)
        rows.append(np.column_stack([points, np.broadcast_to(currents, points.shape), field]))
    return np.concatenate(rows)


def main(argv: list[str]) -> int:
    out = Path(argv[1]) if len(argv) > 1 else Path(__file__).with_name("field_survey.csv")
    np.savetxt(
        out, survey_table(), delimiter=",", fmt="%.10g", header=",".join(COLUMNS), comments=""
    )
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
