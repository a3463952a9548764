"""The one factor that carries the published Zhou 2013 sets onto the model as implemented here.

Under the reading of docs/torque-model.md the torque is linear in a common factor k on every
modulus and viscosity (all exponents hold E/eta ratios only), so k is a one-parameter linear
least-squares problem in relative error:

    minimise sum_i (k m_i / y_i - 1)^2   =>   k = sum(r_i) / sum(r_i^2),  r_i = m_i / y_i,

with m_i the torque of the published set and y_i the paper's torque at the calibration points
(sample 2, capsule No. 2, 0.5 and 3 Hz). The validation points never enter.
"""

from __future__ import annotations

import numpy as np

from spiralcap.core.constants import from_unit
from torque_model.data import PAPER_CAPSULE, PAPER_POINTS, PaperPoint
from torque_model.model import resistive_torque_Nm
from torque_model.parameters import zhou2013

__all__ = ["calibration_points", "fit_calibration_factor", "published_tissue"]


def published_tissue(sample: int):
    """The set exactly as published (Table I or II, factor 1), as TissueParameters.

    Parameters
    ----------
    sample : int
        Intestine sample of Zhou 2013, 2 or 3 (an index, not a count).

    Returns
    -------
    TissueParameters
        The published constants in SI (Pa, Pa·s, m), uncalibrated.
    """
    values = {2: zhou2013.SAMPLE2, 3: zhou2013.SAMPLE3}[sample]
    return zhou2013.calibrated_tissue(values, f"zhou2013-sample{sample}-published", factor=1.0)


def calibration_points() -> tuple[PaperPoint, ...]:
    """The paper points the factor is fitted on (sample 2, role "calibration").

    Returns
    -------
    tuple of PaperPoint
        The calibration points of :data:`torque_model.data.PAPER_POINTS`.
    """
    return tuple(p for p in PAPER_POINTS if p.role == "calibration" and p.sample == 2)


def fit_calibration_factor() -> float:
    """k minimising the summed squared relative error at the calibration points (dimensionless).

    Returns
    -------
    float
        The factor, dimensionless; :data:`torque_model.parameters.zhou2013.CALIBRATION_FACTOR`
        stores it.
    """
    tissue = published_tissue(2)
    pts = calibration_points()
    r = np.array(
        [
            float(
                resistive_torque_Nm(
                    from_unit(p.helical_angle_deg, "deg"), p.frequency_hz, tissue, PAPER_CAPSULE
                )
            )
            / (p.torque_mNm * 1e-3)
            for p in pts
        ]
    )
    return float(r.sum() / (r * r).sum())
