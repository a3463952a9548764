"""Which requirement fails where, on a grid of ``optimize.margin_grid`` (maps name regions)."""

from __future__ import annotations

from typing import Any

import numpy as np


def _grid_field(grid: Any, name: str) -> np.ndarray:
    value = grid[name] if isinstance(grid, dict) else getattr(grid, name)
    return np.asarray(value)


#: The region where the spiral does not touch some wall (the model has no physics there).
NO_CONTACT = "no contact: no margin"
#: Said after the grip requirement where the spiral touches but stretches less than it: the
#: tissue model extrapolates below the strains the paper measured.
BELOW_MINIMUM = ": extrapolated"


def failing_requirements(model: Any, helical_angle_rad: np.ndarray, grid: Any) -> np.ndarray:
    """The first requirement not met at each point of a ``margin_grid`` (``""``: none).

    In the order no contact (:data:`NO_CONTACT`: the margin is NaN there), self-locking,
    grip below the minimum strain (named as extrapolated), spiral turns, speed, set field, safety factor, with
    :data:`optimize.evaluate.FEASIBILITY_RTOL` as ``feasible`` allows; a point whose only
    failure is a negative margin (it steps out) gets ``""``: the map draws that region itself.
    Any other infeasible point left unnamed is ``"a requirement not met"``.
    """
    from optimize.evaluate import FEASIBILITY_RTOL, least_wall_strain, self_lock_margin

    req = model.requirements
    margin = _grid_field(grid, "margin_Nm").astype(float)
    ok = _grid_field(grid, "feasible").astype(bool)
    speed = _grid_field(grid, "speed_m_s").astype(float)
    turns = _grid_field(grid, "spiral_turns").astype(float)
    sf = _grid_field(grid, "safety_factor").astype(float)
    field = _grid_field(grid, "field_amplitude_T").astype(float)
    rtol = FEASIBILITY_RTOL

    def text(value: Any, fmt: str, unit: str = "") -> str:
        # a swept requirement is an array: name it without a number
        return f" < {value:{fmt}}{unit}" if np.ndim(value) == 0 else " below the requirement"

    strain = np.asarray(least_wall_strain(model, helical_angle_rad), float)
    checks = [
        (NO_CONTACT, strain <= 0),  # no physics there: margin NaN, speed 0
        ("spiral self-locks", np.asarray(self_lock_margin(model, helical_angle_rad), float) <= 0),
        (
            "wall strain (grip)"
            + text(np.asarray(req.min_wall_strain) * 100, ".3g", " %")
            + BELOW_MINIMUM,
            strain < np.asarray(req.min_wall_strain) * (1 - rtol),
        ),
        (
            "spiral turns" + text(req.min_spiral_turns, "g"),
            turns < np.asarray(req.min_spiral_turns) * (1 - rtol),
        ),
        (
            "speed" + text(np.asarray(req.min_speed_m_s) * 1e3, ".3g", " mm/s"),
            speed < np.asarray(req.min_speed_m_s) * (1 - rtol),
        ),
    ]
    if model.field_amplitude_T is not None:
        checks.append(
            (
                "set field above what the drive holds",
                field < model.field_amplitude_T * (1 - 10 * rtol),
            )
        )
    checks.append(
        (
            "safety factor" + text(req.min_safety_factor, "g"),
            (sf < np.asarray(req.min_safety_factor) * (1 - rtol)) & (margin >= 0),
        )
    )
    out = np.full(margin.shape, "", dtype=object)
    for name, bad in checks:
        out[(out == "") & bad] = name
    out[(out == "") & ~ok & (margin >= 0)] = "a requirement not met"
    return out
