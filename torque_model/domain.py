"""Where the calibrated torque model rests on the paper's measurements, and how well.

Zhou et al. 2013 measured one capsule shell (11 mm x 26 mm, a 1 mm wire wound over 15 mm, one
start) at helical angles 5-20 deg (capsules No. 1-4), 0.5-3 Hz, in two intestine samples with
lumens of 10.9 and 11.1 mm. The strains those capsules imposed span 1.68 % (No. 4 in sample 3, to three figures)
to 6.45 % (No. 1 in sample 2). Outside these ranges the model extrapolates: it is smooth there,
but nothing measured supports it. :func:`extrapolations` lists each input of a design outside
them; :func:`validation_errors` compares the calibrated model with every torque the paper
states (the 5 deg points never entered the calibration) and :func:`validation_sigma_log` turns
them into the spread of ln(torque) a robust design should allow for.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from spiralcap.core.constants import from_unit
from torque_model.data import CAPSULE_ANGLES_DEG, PAPER_CAPSULE, PAPER_POINTS
from torque_model.engagement import wall_strain
from torque_model.geometry import ContactGeometry
from torque_model.model import resistive_torque_Nm
from torque_model.presets import preset
from torque_model.tissue import TissueParameters

__all__ = [
    "CALIBRATED",
    "Extrapolation",
    "ValidationPoint",
    "calibration_edges",
    "extrapolations",
    "validation_errors",
    "validation_sigma_log",
]

#: Which capsules the paper tested in which sample (section II-C): No. 1-2 in sample 2, all four
#: in sample 3.
_TESTED = {"zhou2013-sample2": (1, 2), "zhou2013-sample3": (1, 2, 3, 4)}


def _paper_strains() -> tuple[float, float]:
    """The least and largest strain the paper's capsules imposed; the least rounded down to the
    three figures the paper gives its lumens to (1.6852 % -> 1.68 %: the exact tube section's
    hull gives 1.6826 %, docs/torque-model.md, so the fourth figure is the D' reading's)."""
    strains = [
        float(wall_strain(from_unit(CAPSULE_ANGLES_DEG[n], "deg"), preset(name), PAPER_CAPSULE))
        for name, capsules in _TESTED.items()
        for n in capsules
    ]
    return math.floor(min(strains) * 1e4) / 1e4, max(strains)


def _lumens() -> tuple[float, float]:
    lumens = [preset(name).lumen_diameter_m for name in _TESTED]
    return min(lumens), max(lumens)


#: Calibrated range of each model input, SI: quantity -> (low, high, unit). Equal ends mean the
#: paper tested one value only.
CALIBRATED: dict[str, tuple[float, float, str]] = {
    "helical_angle_rad": (from_unit(5.0, "deg"), from_unit(20.0, "deg"), "rad"),
    "frequency_hz": (0.5, 3.0, "Hz"),
    "body_diameter_m": (PAPER_CAPSULE.body_diameter_m, PAPER_CAPSULE.body_diameter_m, "m"),
    "wire_diameter_m": (PAPER_CAPSULE.wire_diameter_m, PAPER_CAPSULE.wire_diameter_m, "m"),
    "starts": (1.0, 1.0, "starts"),
    "lumen_diameter_m": (*_lumens(), "m"),
    "wall_strain": (*_paper_strains(), "1"),
}

#: Relative tolerance within which a value counts as inside (an optimum on a calibrated edge).
_EDGE_RTOL = 1e-6


@dataclass(frozen=True)
class Extrapolation:
    """One model input outside the paper's calibrated range.

    Attributes
    ----------
    quantity : str
        The input, named as in :data:`CALIBRATED` (``"helical_angle_rad"``, ``"wall_strain"``).
    value : float
        Its value, SI, in the unit ``unit`` names.
    low, high : float
        The calibrated range, SI, in the unit ``unit`` names.
    unit : str
        SI unit of ``value``, ``low`` and ``high`` (``"1"``: dimensionless).
    where : str
        Which tissue set it concerns (lumen, strain), or ``""``.
    """

    quantity: str
    value: float
    low: float
    high: float
    unit: str
    where: str = ""


def _outside(quantity: str, value: float, where: str = "") -> Extrapolation | None:
    low, high, unit = CALIBRATED[quantity]
    tol = _EDGE_RTOL * max(abs(low), abs(high))
    if low - tol <= value <= high + tol:
        return None
    return Extrapolation(quantity, float(value), low, high, unit, where)


def extrapolations(
    helical_angle_rad: float,
    frequency_hz: float,
    geometry: ContactGeometry,
    tissues: tuple[TissueParameters, ...] | list[TissueParameters],
) -> tuple[Extrapolation, ...]:
    """Every input of a design at an operating point outside the paper's calibrated range.

    Parameters
    ----------
    helical_angle_rad : float
        Helical angle, rad.
    frequency_hz : float
        Rotation frequency, Hz.
    geometry : ContactGeometry
        The capsule (body and wire diameters, m; starts).
    tissues : sequence of TissueParameters
        The tissue sets the design is checked against (lumen, m; wall strain per set).

    Returns
    -------
    tuple of Extrapolation
        Empty when every input lies within the calibration (edges included).
    """
    g = geometry
    found = [
        _outside("helical_angle_rad", helical_angle_rad),
        _outside("frequency_hz", frequency_hz),
        _outside("body_diameter_m", float(g.body_diameter_m)),
        _outside("wire_diameter_m", float(g.wire_diameter_m)),
        _outside("starts", float(g.starts)),
    ]
    for t in tissues:
        found.append(_outside("lumen_diameter_m", t.lumen_diameter_m, t.name))
        found.append(_outside("wall_strain", float(wall_strain(helical_angle_rad, t, g)), t.name))
    return tuple(e for e in found if e is not None)


#: Fraction of a calibrated range's width within which an input counts as on its edge.
EDGE_FRACTION = 0.02


def _on_edge(quantity: str, value: float, where: str = "") -> Extrapolation | None:
    low, high, unit = CALIBRATED[quantity]
    width = high - low
    if width <= 0 or _outside(quantity, value, where) is not None:
        return None
    if min(value - low, high - value) > EDGE_FRACTION * width:
        return None
    return Extrapolation(quantity, float(value), low, high, unit, where)


def calibration_edges(
    helical_angle_rad: float,
    frequency_hz: float,
    geometry: ContactGeometry,
    tissues: tuple[TissueParameters, ...] | list[TissueParameters],
) -> tuple[Extrapolation, ...]:
    """Inputs an optimiser moves (angle, frequency, wall strain) inside the calibrated range
    but on its edge (within :data:`EDGE_FRACTION` of its width from an end): where an optimum
    pressed against the range rests on its last measured point.

    Parameters
    ----------
    helical_angle_rad : float
        Helical angle, rad.
    frequency_hz : float
        Rotation frequency, Hz.
    geometry : ContactGeometry
        The capsule (dimensions, m).
    tissues : sequence of TissueParameters
        The tissue sets (lumen, m; wall strain per set).

    Returns
    -------
    tuple of Extrapolation
        The inputs on an edge (same record as :func:`extrapolations`).
    """
    found = [
        _on_edge("helical_angle_rad", helical_angle_rad),
        _on_edge("frequency_hz", frequency_hz),
    ]
    for t in tissues:  # the lumen is the patient's, not the optimiser's: not an edge it seeks
        found.append(
            _on_edge("wall_strain", float(wall_strain(helical_angle_rad, t, geometry)), t.name)
        )
    return tuple(e for e in found if e is not None)


@dataclass(frozen=True)
class ValidationPoint:
    """The calibrated model against one torque the paper states.

    Attributes
    ----------
    helical_angle_deg : float
        Helical angle, deg.
    frequency_hz : float
        Rotation frequency, Hz.
    paper_Nm : float
        The paper's torque, N·m.
    model_Nm : float
        The calibrated model's torque (sample 2, the paper's capsule), N·m.
    role : str
        ``"calibration"`` or ``"validation"`` (never fitted).
    """

    helical_angle_deg: float
    frequency_hz: float
    paper_Nm: float
    model_Nm: float
    role: str

    @property
    def relative_error(self) -> float:
        """model / paper - 1, dimensionless."""
        return self.model_Nm / self.paper_Nm - 1.0


def validation_errors() -> tuple[ValidationPoint, ...]:
    """The calibrated model (``zhou2013-sample2``, the paper's capsule) at every stated torque.

    Returns
    -------
    tuple of ValidationPoint
        One per :data:`torque_model.PAPER_POINTS` entry (sample 2, capsules No. 1 and 2).
    """
    tissue = preset("zhou2013-sample2")
    return tuple(
        ValidationPoint(
            p.helical_angle_deg,
            p.frequency_hz,
            p.torque_mNm * 1e-3,
            float(
                resistive_torque_Nm(
                    from_unit(p.helical_angle_deg, "deg"), p.frequency_hz, tissue, PAPER_CAPSULE
                )
            ),
            p.role,
        )
        for p in PAPER_POINTS
    )


def validation_sigma_log() -> float:
    """Root-mean-square of ln(model / paper) over the paper's stated torques, dimensionless.

    The spread of ln(torque) the model's own validation implies: a lower bound for
    ``tissue.uncertainty.scale_sigma_log`` in a robust design.

    Returns
    -------
    float
        sqrt(mean(ln(model_i / paper_i)^2)), dimensionless.
    """
    logs = np.log([p.model_Nm / p.paper_Nm for p in validation_errors()])
    return float(np.sqrt(np.mean(logs**2)))
