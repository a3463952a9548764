"""Electrical and thermal relations of a coil drive, backend-generic.

Each function takes floats, numpy arrays or CasADi values (the optimiser passes a CasADi
frequency and current amplitude) and is written once against :mod:`spiralcap.core.backend`. Currents
and voltages are sinusoidal *amplitudes* (peak, not RMS).
"""

from __future__ import annotations

from typing import Any

from spiralcap.core import backend as bk
from spiralcap.core.checks import guard, nonnegative, positive, temperature
from spiralcap.core.constants import (
    COPPER_RESISTIVITY_20C_ohm_m,
    COPPER_TEMPERATURE_COEFFICIENT_per_K,
)

__all__ = [
    "copper_loss_W",
    "copper_resistivity_ohm_m",
    "impedance_ohm",
    "temperature_rise_K",
    "voltage_amplitude_V",
]


@guard(temperature_C=temperature())
def copper_resistivity_ohm_m(temperature_C: Any) -> Any:
    """Resistivity of annealed copper, Ω·m: ρ20 (1 + α20 (T - 20 °C)) (IEC 60028).

    Parameters
    ----------
    temperature_C : float, array or CasADi
        Copper temperature, °C.

    Returns
    -------
    float, array or CasADi
        Resistivity, Ω·m.

    Examples
    --------
    Annealed copper at 20 °C and at 100 °C (temperature coefficient 0.00393 /K):

    >>> from coils import copper_resistivity_ohm_m
    >>> print(f"{copper_resistivity_ohm_m(20.0):.4e} {copper_resistivity_ohm_m(100.0):.4e} ohm m")
    1.7241e-08 2.2662e-08 ohm m
    """
    return COPPER_RESISTIVITY_20C_ohm_m * (
        1.0 + COPPER_TEMPERATURE_COEFFICIENT_per_K * (temperature_C - 20.0)
    )


@guard(resistance_ohm=nonnegative(), inductance_H=nonnegative(), frequency_hz=nonnegative())
def impedance_ohm(resistance_ohm: Any, inductance_H: Any, frequency_hz: Any) -> Any:
    """Magnitude of the series R-L impedance, |R + jωL| = sqrt(R² + (2π f L)²), Ω.

    Parameters
    ----------
    resistance_ohm : float, array or CasADi
        Series resistance, Ω.
    inductance_H : float, array or CasADi
        Series inductance, H.
    frequency_hz : float, array or CasADi
        Drive frequency, Hz.

    Returns
    -------
    float, array or CasADi
        Impedance magnitude, Ω.

    Examples
    --------
    2 Ω and 10 mH at 50 Hz: |R + j 2π f L| = sqrt(4 + 3.1416²):

    >>> from coils import impedance_ohm
    >>> print(f"{impedance_ohm(2.0, 0.01, 50.0):.4f} ohm")
    3.7242 ohm
    """
    reactance = 2.0 * bk.pi * frequency_hz * inductance_H
    return bk.sqrt(resistance_ohm * resistance_ohm + reactance * reactance)


@guard(
    resistance_ohm=nonnegative(),
    inductance_H=nonnegative(),
    frequency_hz=nonnegative(),
    current_amplitude_A=nonnegative(),
)
def voltage_amplitude_V(
    resistance_ohm: Any, inductance_H: Any, frequency_hz: Any, current_amplitude_A: Any
) -> Any:
    """Drive-voltage amplitude |Z| I for a sinusoidal current of amplitude I, V.

    Parameters
    ----------
    resistance_ohm : float, array or CasADi
        Series resistance, Ω.
    inductance_H : float, array or CasADi
        Series inductance, H.
    frequency_hz : float, array or CasADi
        Drive frequency, Hz.
    current_amplitude_A : float, array or CasADi
        Current amplitude (peak), A.

    Returns
    -------
    float, array or CasADi
        Voltage amplitude, V.

    Examples
    --------
    The same winding driven at 10 A amplitude:

    >>> from coils import voltage_amplitude_V
    >>> print(f"{voltage_amplitude_V(2.0, 0.01, 50.0, 10.0):.2f} V")
    37.24 V
    """
    return impedance_ohm(resistance_ohm, inductance_H, frequency_hz) * current_amplitude_A


@guard(resistance_ohm=nonnegative(), current_amplitude_A=nonnegative())
def copper_loss_W(resistance_ohm: Any, current_amplitude_A: Any) -> Any:
    """Mean copper loss of a sinusoidal current, R I² / 2 (I the amplitude), W.

    Parameters
    ----------
    resistance_ohm : float, array or CasADi
        Resistance, Ω.
    current_amplitude_A : float, array or CasADi
        Current amplitude (peak), A.

    Returns
    -------
    float, array or CasADi
        Mean power dissipated, W.

    Examples
    --------
    A 2 Ω winding at 10 A amplitude dissipates R I² / 2:

    >>> from coils import copper_loss_W
    >>> print(f"{copper_loss_W(2.0, 10.0):.1f} W")
    100.0 W
    """
    return 0.5 * resistance_ohm * current_amplitude_A * current_amplitude_A


@guard(power_W=nonnegative(), thermal_conductance_W_per_K=positive())
def temperature_rise_K(power_W: Any, thermal_conductance_W_per_K: Any) -> Any:
    """Steady temperature rise ΔT = P / G of a lumped body losing heat through conductance G, K.

    Parameters
    ----------
    power_W : float, array or CasADi
        Dissipated power, W.
    thermal_conductance_W_per_K : float, array or CasADi
        Conductance to ambient, W/K.

    Returns
    -------
    float, array or CasADi
        Temperature rise, K.

    Examples
    --------
    100 W into a surface that sheds 2 W/K:

    >>> from coils import temperature_rise_K
    >>> print(f"{temperature_rise_K(100.0, 2.0):.1f} K")
    50.0 K
    """
    return power_W / thermal_conductance_W_per_K
