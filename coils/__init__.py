"""Helmholtz coils, circular, square and rectangular: exact loop fields, three-axis systems, rotating-field allocation,
electrical and thermal sizing, and field uniformity. SI units throughout; imports only the
spiralcap core (backend, constants, errors)."""

from coils.electrical import (
    copper_loss_W,
    copper_resistivity_ohm_m,
    impedance_ohm,
    temperature_rise_K,
    voltage_amplitude_V,
)
from coils.loop import coaxial_mutual_inductance_H, loop_field
from coils.pair import HelmholtzPair
from coils.rectangle_pair import RectanglePair
from coils.rotating import heading_frame
from coils.sizing import AxisSizing, SystemSizing, size_system
from coils.square_pair import SQUARE_HELMHOLTZ_RATIO, SquarePair
from coils.system import ThreeAxisHelmholtz
from coils.uniformity import (
    UniformRegion,
    pair_uniform_regions,
    uniform_region,
    uniform_region_radius_m,
    uniform_regions,
    uniformity,
)
from coils.winding import MeasuredConstants

__all__ = [
    "SQUARE_HELMHOLTZ_RATIO",
    "AxisSizing",
    "HelmholtzPair",
    "MeasuredConstants",
    "RectanglePair",
    "SquarePair",
    "SystemSizing",
    "ThreeAxisHelmholtz",
    "UniformRegion",
    "coaxial_mutual_inductance_H",
    "copper_loss_W",
    "copper_resistivity_ohm_m",
    "heading_frame",
    "impedance_ohm",
    "loop_field",
    "pair_uniform_regions",
    "size_system",
    "temperature_rise_K",
    "uniform_region",
    "uniform_region_radius_m",
    "uniform_regions",
    "uniformity",
    "voltage_amplitude_V",
]
