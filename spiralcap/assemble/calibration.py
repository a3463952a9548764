"""Design keys ``calibration.*`` -> :class:`coils.calibration.CoilCalibration` on the coils.

A design with any of ``calibration.map_{x,y,z}`` or ``calibration.background_field_uT`` (from
``spiralcap calibrate -o cal.toml``, layered: ``spiralcap evaluate my.toml cal.toml``) gets
:class:`coils.calibration.CalibratedHelmholtz` coils: every field, allocation and figure then
uses the calibrated field per ampere. The record keys (``survey_csv``, ``residual_rms_uT``,
``holdout_rms_uT``, ``rows``) do not switch it on.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["CALIBRATION_KEYS", "apply_calibration", "calibration_of", "nominal"]

#: The keys that carry the calibration (the others under ``calibration.`` are records).
CALIBRATION_KEYS = (
    "calibration.map_x",
    "calibration.map_y",
    "calibration.map_z",
    "calibration.background_field_uT",
)


def calibration_of(design: Mapping[str, Any]) -> Any:
    """The design's :class:`coils.calibration.CoilCalibration`, or None when it sets none.

    A map left out is the identity, a background left out zero.
    """
    if all(design.get(k) is None for k in CALIBRATION_KEYS):
        return None
    from coils.calibration import CoilCalibration

    maps = np.stack(
        [np.asarray(design.get(f"calibration.map_{ax}") or np.eye(3), float) for ax in "xyz"]
    )
    background = design.get("calibration.background_field_uT") or [0.0, 0.0, 0.0]
    return CoilCalibration(maps, np.asarray(background, dtype=float) * 1e-6)


def apply_calibration(design: Mapping[str, Any], system: Any) -> Any:
    """``system`` calibrated by the design's ``[calibration]`` table (unchanged without one)."""
    calibration = calibration_of(design)
    if calibration is None:
        return system
    from coils.calibration import calibrated

    return calibrated(system, calibration)


def nominal(system: Any) -> Any:
    """The modelled coils of ``system``, without any calibration (a ThreeAxisHelmholtz)."""
    from coils.system import ThreeAxisHelmholtz

    if type(system) is ThreeAxisHelmholtz:
        return system
    return ThreeAxisHelmholtz(system.x, system.y, system.z)
