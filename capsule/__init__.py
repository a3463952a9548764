"""Capsule domain: body, spiral, magnet, magnetic torque and propulsion kinematics (SI).

Functions of the optimisation variables (helical angle, frequency, field amplitude) are written
once against :mod:`spiralcap.core.backend` and run on floats, numpy arrays and CasADi SX/MX alike:
:func:`helix_diameter_m`, :func:`lead_m`, :func:`spiral_turns`, :func:`footprint_width_m`,
:func:`max_helical_angle_for_turns_rad`, :func:`min_helical_angle_for_clearance_rad`,
:func:`max_synchronous_torque_Nm`, :func:`synchronous_torque_Nm`, :func:`lag_angle_rad`,
:func:`forward_speed_m_s`, :func:`thrust_torque_Nm`. The dataclasses hold plain floats.
"""

from capsule.body import GEOMETRY_RTOL, Body
from capsule.magnet import (
    GRADE_REMANENCE_RANGE_T,
    GRADE_REMANENCE_T,
    Magnet,
    magnet_fit_check,
    magnet_fit_problem,
    remanence_for_grade,
)
from capsule.mass import (
    CONTENTS_DENSITY_kg_m3,
    NDFEB_DENSITY_kg_m3,
    body_volume_m3,
    mass_from_parts_kg,
)
from capsule.model import Capsule, CapsuleFigures, geometry_problems
from capsule.propulsion import forward_speed_m_s, self_lock_margin_rad, thrust_torque_Nm
from capsule.spiral import (
    MAX_WIRE_TO_BODY_DIAMETER,
    Spiral,
    footprint_width_m,
    helix_diameter_m,
    lead_m,
    max_helical_angle_for_turns_rad,
    min_helical_angle_for_clearance_rad,
    spiral_turns,
)
from capsule.torque import (
    lag_angle_rad,
    magnetic_torque_Nm,
    max_synchronous_torque_Nm,
    synchronous_torque_Nm,
)

__all__ = [
    "GEOMETRY_RTOL",
    "GRADE_REMANENCE_RANGE_T",
    "GRADE_REMANENCE_T",
    "MAX_WIRE_TO_BODY_DIAMETER",
    "Body",
    "CONTENTS_DENSITY_kg_m3",
    "Capsule",
    "CapsuleFigures",
    "Magnet",
    "NDFEB_DENSITY_kg_m3",
    "Spiral",
    "body_volume_m3",
    "footprint_width_m",
    "forward_speed_m_s",
    "geometry_problems",
    "helix_diameter_m",
    "lag_angle_rad",
    "lead_m",
    "magnet_fit_check",
    "magnet_fit_problem",
    "magnetic_torque_Nm",
    "mass_from_parts_kg",
    "max_helical_angle_for_turns_rad",
    "max_synchronous_torque_Nm",
    "min_helical_angle_for_clearance_rad",
    "remanence_for_grade",
    "self_lock_margin_rad",
    "spiral_turns",
    "synchronous_torque_Nm",
    "thrust_torque_Nm",
]
