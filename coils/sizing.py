"""Per-axis electrical and thermal sizing of a three-axis system at one current and frequency.

For each pair at current amplitude I and frequency f: R at the winding temperature, series L,
|Z|, voltage amplitude |Z| I, copper loss R I²/2, temperature rise P/G (convective surface),
and the rotating field the pairs make at that current for the worst heading (at the centre axis
k needs A_k = B0 sqrt(1 - n_k²)/g_k, so the heading ⟂ axis k asks the most of it and the
worst-case amplitude at current I is min_k g_k I; the axes within 1e-9 of the minimum are all
reported). What the voltage, power, temperature and exposure limits then allow is not computed
here: it is :func:`optimize.physics.field_capacity_T`, the one definition of the limits that
``evaluate`` and ``optimize`` use (``spiralcap coils`` prints it).
"""

from __future__ import annotations

from dataclasses import dataclass

from coils.electrical import copper_loss_W, impedance_ohm, temperature_rise_K
from coils.system import ThreeAxisHelmholtz

__all__ = ["AxisSizing", "SystemSizing", "size_system"]


@dataclass(frozen=True)
class AxisSizing:
    """Sizing of one pair (both coils in series) at the operating point; names carry units."""

    axis: str
    radius_m: float
    separation_m: float
    turns: int
    wire_diameter_m: float
    winding_pack_side_m: float
    wire_length_m: float
    field_per_amp_T_per_A: float
    resistance_ohm: float
    self_inductance_H: float
    mutual_inductance_H: float
    inductance_H: float
    impedance_ohm: float
    voltage_amplitude_V: float
    power_W: float
    thermal_conductance_W_per_K: float
    temperature_rise_K: float
    coil_temperature_C: float
    field_amplitude_T: float


@dataclass(frozen=True)
class SystemSizing:
    """Sizing of the three pairs and the worst-heading rotating field at the given current."""

    frequency_hz: float
    current_amplitude_A: float
    winding_temperature_C: float
    ambient_temperature_C: float
    heat_transfer_coefficient_W_m2K: float
    axes: tuple[AxisSizing, AxisSizing, AxisSizing]
    total_power_W: float
    current_limited_rotating_field_T: float
    current_limiting_axes: tuple[str, ...]


def size_system(
    system: ThreeAxisHelmholtz,
    *,
    frequency_hz: float,
    current_amplitude_A: float,
    winding_temperature_C: float,
    ambient_temperature_C: float,
    heat_transfer_coefficient_W_m2K: float,
) -> SystemSizing:
    """Evaluate every pair at one current amplitude and frequency.

    Parameters
    ----------
    system : ThreeAxisHelmholtz
        The coils.
    frequency_hz : float
        Drive frequency, Hz.
    current_amplitude_A : float
        Current amplitude of every pair, and the current limit, A.
    winding_temperature_C : float
        Copper temperature for the resistance, °C.
    ambient_temperature_C : float
        Air temperature, °C.
    heat_transfer_coefficient_W_m2K : float
        Convective coefficient from the winding surface, W/(m²·K).

    Returns
    -------
    SystemSizing
    """
    axes = []
    for pair in system.pairs:
        r = pair.resistance_ohm(winding_temperature_C)
        z = float(impedance_ohm(r, pair.series_inductance_H, frequency_hz))
        g = pair.centre_field_per_amp_T_per_A
        cond = pair.thermal_conductance_W_per_K(heat_transfer_coefficient_W_m2K)
        power = float(copper_loss_W(r, current_amplitude_A))
        rise = float(temperature_rise_K(power, cond))
        axes.append(
            AxisSizing(
                axis=pair.axis,
                radius_m=pair.radius_m,
                separation_m=pair.spacing_m,
                turns=pair.turns,
                wire_diameter_m=pair.wire_diameter_m,
                winding_pack_side_m=pair.winding_pack_side_m,
                wire_length_m=pair.wire_length_m,
                field_per_amp_T_per_A=g,
                resistance_ohm=r,
                self_inductance_H=pair.self_inductance_H,
                mutual_inductance_H=pair.mutual_inductance_H,
                inductance_H=pair.series_inductance_H,
                impedance_ohm=z,
                voltage_amplitude_V=z * current_amplitude_A,
                power_W=power,
                thermal_conductance_W_per_K=cond,
                temperature_rise_K=rise,
                coil_temperature_C=ambient_temperature_C + rise,
                field_amplitude_T=g * current_amplitude_A,
            )
        )
    weakest = min(a.field_amplitude_T for a in axes)
    tied = tuple(a.axis for a in axes if a.field_amplitude_T <= weakest * (1.0 + 1e-9))
    return SystemSizing(
        frequency_hz=frequency_hz,
        current_amplitude_A=current_amplitude_A,
        winding_temperature_C=winding_temperature_C,
        ambient_temperature_C=ambient_temperature_C,
        heat_transfer_coefficient_W_m2K=heat_transfer_coefficient_W_m2K,
        axes=(axes[0], axes[1], axes[2]),
        total_power_W=sum(a.power_W for a in axes),
        current_limited_rotating_field_T=weakest,
        current_limiting_axes=tied,
    )
