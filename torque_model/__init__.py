"""Tissue resistive torque of a spiral capsule: the Zhou et al. 2013 model, parameter sets, fit.

Everything physical is SI. The model functions run on floats, numpy arrays and CasADi values
(``from spiralcap.core import backend as bk``); see ``docs/torque-model.md`` for the reading of the
paper's eqs. 2-8 and the calibration of its parameter sets.
"""

from torque_model.data import CAPSULE_ANGLES_DEG, PAPER_CAPSULE, PAPER_POINTS, PaperPoint
from torque_model.engagement import (
    DEFAULT_MIN_WALL_STRAIN,
    contact_radius_m,
    wall_strain,
    weight_friction_torque_Nm,
)
from torque_model.geometry import (
    ContactGeometry,
    capsule_d_prime_m,
    end_contact_moment_m2,
    equivalent_diameter_m,
)
from torque_model.identification import PARAMETER_NAMES, FitResult, identify
from torque_model.model import (
    angular_frequency_rad_s,
    contact_factor_m3,
    contact_factors_m3,
    friction_per_length_N_m,
    hoop_pressure_Pa,
    normal_load_per_length_N_m,
    relaxation_integral_Pa,
    relaxation_modulus_Pa,
    resistive_torque_Nm,
    section_torque_per_length_N,
    strain,
    stress_Pa,
    torque_breakdown_Nm,
)
from torque_model.presets import PRESET_NAMES, preset
from torque_model.tissue import TissueParameters

__all__ = [
    "CAPSULE_ANGLES_DEG",
    "DEFAULT_MIN_WALL_STRAIN",
    "PAPER_CAPSULE",
    "PAPER_POINTS",
    "PARAMETER_NAMES",
    "PRESET_NAMES",
    "ContactGeometry",
    "FitResult",
    "PaperPoint",
    "TissueParameters",
    "angular_frequency_rad_s",
    "capsule_d_prime_m",
    "contact_factor_m3",
    "contact_factors_m3",
    "contact_radius_m",
    "end_contact_moment_m2",
    "equivalent_diameter_m",
    "friction_per_length_N_m",
    "hoop_pressure_Pa",
    "identify",
    "normal_load_per_length_N_m",
    "preset",
    "relaxation_integral_Pa",
    "relaxation_modulus_Pa",
    "resistive_torque_Nm",
    "section_torque_per_length_N",
    "strain",
    "stress_Pa",
    "torque_breakdown_Nm",
    "wall_strain",
    "weight_friction_torque_Nm",
]
