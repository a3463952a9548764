"""Design evaluation and CasADi/IPOPT optimisation of spiral angle, frequency, field and hardware.

>>> from spiralcap.assemble import build_model          # doctest: +SKIP
>>> from optimize import evaluate, optimize_design       # doctest: +SKIP
>>> result = optimize_design(build_model(design))        # doctest: +SKIP
"""

from optimize.evaluate import (
    Check,
    Evaluation,
    FrequencyBound,
    GripBound,
    MarginGrid,
    WorstRequired,
    evaluate,
    grip_bound,
    grip_state,
    margin_grid,
    max_frequency_hz,
    step_out_frequency_hz,
    worst_required,
)
from optimize.hardware import FreeVariable, Sizing
from optimize.optimum import optimize_design
from optimize.physics import ICNIRP2010_LEVELS_T, exposure_level_T
from optimize.result import BindingLimit, HardwareResult, OptimizationResult, Shortfall
from optimize.solve import with_operating_point
from optimize.system import Bounds, DesignModel, Limits, Requirements, prepare

# registers the objective margin_p05 and the step-out probability rows (problem hooks)
from optimize import robust as _robust  # noqa: F401  isort: skip

__all__ = [
    "ICNIRP2010_LEVELS_T",
    "BindingLimit",
    "Bounds",
    "Check",
    "DesignModel",
    "Evaluation",
    "FreeVariable",
    "FrequencyBound",
    "GripBound",
    "HardwareResult",
    "Limits",
    "MarginGrid",
    "OptimizationResult",
    "Requirements",
    "Shortfall",
    "Sizing",
    "WorstRequired",
    "evaluate",
    "exposure_level_T",
    "grip_bound",
    "grip_state",
    "margin_grid",
    "max_frequency_hz",
    "optimize_design",
    "prepare",
    "step_out_frequency_hz",
    "with_operating_point",
    "worst_required",
]
