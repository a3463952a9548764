"""The torques Zhou et al. 2013 state in prose (section II-C); the figures themselves are lost.

Sample 2 with capsule No. 2 (10 deg) is what the paper identified Table I on and what this tool
calibrates on; sample 2 with capsule No. 1 (5 deg) is the paper's validation case and is used
here only to check, never to fit. The paper gives no sample-3 numbers beyond "the same order of
magnitude" as sample 2.
"""

from __future__ import annotations

from dataclasses import dataclass

from torque_model.geometry import ContactGeometry

__all__ = ["CAPSULE_ANGLES_DEG", "PAPER_CAPSULE", "PAPER_POINTS", "PaperPoint"]

#: The paper's capsules (section II-A): a PillCam SB2 shell, 11 mm x 26 mm, with one 1 mm wire
#: wound over 15 mm; only the helical angle differs between capsules No. 1-4.
PAPER_CAPSULE = ContactGeometry(
    body_diameter_m=11e-3,
    body_length_m=26e-3,
    wire_diameter_m=1e-3,
    wound_length_m=15e-3,
    starts=1,
)

#: Helical angle of each of the paper's capsules, deg (section II-A).
CAPSULE_ANGLES_DEG = {1: 5.0, 2: 10.0, 3: 15.0, 4: 20.0}


@dataclass(frozen=True)
class PaperPoint:
    """One torque the paper states in prose.

    Attributes
    ----------
    sample : int
        Intestine sample (2 or 3), an index.
    capsule : int
        Capsule number (1-4), an index.
    helical_angle_deg : float
        Helical angle of that capsule, deg.
    frequency_hz : float
        Rotation frequency, Hz.
    torque_mNm : float
        The torque the text states ("≈"), mN·m.
    role : str
        ``"calibration"`` (may be fitted) or ``"validation"`` (must never enter a fit).
    source : str
        Where in the paper the number is.
    """

    sample: int
    capsule: int
    helical_angle_deg: float
    frequency_hz: float
    torque_mNm: float
    role: str
    source: str


_TEXT = "Zhou 2013, section II-C (lines 210-213): 'from 0.5 to 3 Hz ... in the range of'"

PAPER_POINTS: tuple[PaperPoint, ...] = (
    PaperPoint(2, 2, 10.0, 0.5, 0.6, "calibration", _TEXT + " 0.6-1.8 mN·m"),
    PaperPoint(2, 2, 10.0, 3.0, 1.8, "calibration", _TEXT + " 0.6-1.8 mN·m"),
    PaperPoint(2, 1, 5.0, 0.5, 0.8, "validation", _TEXT + " 0.8 and 2.3 mN·m"),
    PaperPoint(2, 1, 5.0, 3.0, 2.3, "validation", _TEXT + " 0.8 and 2.3 mN·m"),
)
