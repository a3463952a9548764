"""The one definition of the margin, the requirements and the limits.

Every function here is written once against :mod:`spiralcap.backend` and takes the operating
variables — helical angle ``alpha`` (rad), rotation frequency ``f`` (Hz), rotating-field
amplitude at the centre ``B0`` (T) — as floats, numpy arrays (vectorised sweeps) or CasADi
symbols (the optimiser). :mod:`optimize.evaluate` and :mod:`optimize.problem` both build on it,
so ``evaluate`` at the optimiser's answer reports the optimiser's margin.

Limits are written ``value(f, B0) <= allowed`` with ``value`` proportional to ``B0**power``;
the largest field a frequency allows is therefore ``min over limits of
(allowed / value(f, 1)) ** (1 / power)``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import capsule as cap
import torque_model as tm
from optimize.system import Constants, Limits, Requirements
from spiralcap import backend as bk

#: ICNIRP (2010) "Guidelines for limiting exposure to time-varying electric and magnetic fields
#: (1 Hz to 100 kHz)", Health Phys. 99(6):818-836, Tables 3 and 4: reference levels for the
#: magnetic flux density (rms), T, as (a, b, c): a/f² for 1-8 Hz, b/f for 8-25 Hz, c above 25 Hz
#: (up to 300 Hz occupational, 50 Hz public; the next band is not needed at these frequencies).
ICNIRP2010_LEVELS_T = {"occupational": (0.2, 2.5e-2, 1e-3), "public": (4e-2, 5e-3, 2e-4)}


def exposure_level_T(frequency_hz: Any, kind: str) -> Any:
    """ICNIRP 2010 reference level (rms flux density, T) at ``frequency_hz``.

    The guideline starts at 1 Hz; below it the 1 Hz value is held (conservative and continuous).
    The rms of a circularly rotating field equals its amplitude, so the level bounds ``B0``.
    """
    a, b, c = ICNIRP2010_LEVELS_T[kind]
    f = bk.fmax(frequency_hz, 1.0)
    return bk.where(f < 8.0, a / (f * f), bk.where(f < 25.0, b / f, c))


@dataclass(frozen=True)
class LimitTerm:
    """One limit at one operating point: ``value <= allowed`` (units in ``unit``)."""

    name: str
    key: str
    unit: str
    value: Any
    allowed: Any
    power: int

    @property
    def utilisation(self) -> Any:
        """value / allowed (1 means the limit binds)."""
        return self.value / self.allowed


_AXES = ("x", "y", "z")


def limit_terms(
    frequency_hz: Any, field_T: Any, c: Constants, limits: Limits, ambient_temperature_C: float
) -> list[LimitTerm]:
    """Every hardware and exposure limit at rotation frequency ``f`` and centre field ``B0``.

    Per axis k the worst-heading current amplitude is ``I_k = B0 * current_per_tesla[k]``; its
    drive voltage ``|R_k + j 2πf L_k| I_k`` (coils.voltage_amplitude_V), its steady temperature
    ``ambient + (R_k I_k² / 2) / G_k`` (coils.copper_loss_W, coils.temperature_rise_K); the total
    copper loss is that of the worst heading; the exposure level is ICNIRP 2010's.
    """
    import coils

    terms: list[LimitTerm] = []
    rise_allowed = limits.coil_temperature_C - ambient_temperature_C
    for k, ax in enumerate(_AXES):
        current = field_T * float(c.current_per_tesla_A_per_T[k])
        r, ind = float(c.resistance_ohm[k]), float(c.inductance_H[k])
        terms.append(
            LimitTerm(f"current_{ax}", "limits.current_A", "A", current, limits.current_A, 1)
        )
        terms.append(
            LimitTerm(
                f"voltage_{ax}",
                "limits.voltage_V",
                "V",
                coils.voltage_amplitude_V(r, ind, frequency_hz, current),
                limits.voltage_V,
                1,
            )
        )
        rise = coils.temperature_rise_K(
            coils.copper_loss_W(r, current), float(c.conductance_W_per_K[k])
        )
        terms.append(
            LimitTerm(
                f"temperature_rise_{ax}", "limits.coil_temperature_C", "K", rise, rise_allowed, 2
            )
        )
    terms.append(
        LimitTerm(
            "power",
            "limits.power_W",
            "W",
            field_T * field_T * c.power_per_tesla2_W_per_T2,
            limits.power_W,
            2,
        )
    )
    if limits.field_exposure != "off":
        terms.append(
            LimitTerm(
                "field_exposure",
                "limits.field_exposure",
                "T",
                field_T,
                exposure_level_T(frequency_hz, limits.field_exposure),
                1,
            )
        )
    return terms


def field_capacity_T(
    frequency_hz: Any, c: Constants, limits: Limits, ambient_temperature_C: float
) -> tuple[Any, list[Any], list[LimitTerm]]:
    """Largest centre field each limit allows at ``f`` (numpy only): (min, caps, unit terms)."""
    import numpy as np

    unit = limit_terms(frequency_hz, 1.0, c, limits, ambient_temperature_C)
    with np.errstate(divide="ignore"):  # an axis no heading uses carries no current: no cap
        caps = [
            np.divide(t.allowed, np.asarray(t.value, dtype=float)) ** (1.0 / t.power) for t in unit
        ]
    return np.minimum.reduce(np.broadcast_arrays(*caps)), caps, unit


def available_torque_Nm(field_T: Any, c: Constants) -> Any:
    """Largest synchronous torque over the workspace: m · B0 · (weakest-field factor)."""
    return cap.max_synchronous_torque_Nm(c.moment_Am2, field_T * c.workspace_factor)


def required_torques_Nm(
    helical_angle_rad: bk.Scalar,
    frequency_hz: bk.Scalar,
    c: Constants,
    tissues: tuple,
    req: Requirements,
) -> list[tuple[bk.Scalar, bk.Scalar]]:
    """(resistive, thrust) torque for every tissue set, N·m.

    Resistive: the Zhou 2013 tissue model (torque_model.resistive_torque_Nm). Thrust: the screw
    torque to push ``req.axial_load_N`` (capsule.thrust_torque_Nm) with that tissue's friction.
    """
    geometry = tm.ContactGeometry(
        c.body_diameter_m, c.body_length_m, c.wire_diameter_m, c.wound_length_m, c.starts
    )
    out = []
    for tissue in tissues:
        res = tm.resistive_torque_Nm(helical_angle_rad, frequency_hz, tissue, geometry)
        thr = cap.thrust_torque_Nm(
            req.axial_load_N, c.helix_diameter_m, helical_angle_rad, tissue.friction_coefficient
        )
        out.append((res, thr))
    return out


def speed_m_s(helical_angle_rad: Any, frequency_hz: Any, c: Constants, req: Requirements) -> Any:
    """Forward speed: slip efficiency × frequency × spiral lead (capsule.forward_speed_m_s)."""
    return cap.forward_speed_m_s(
        frequency_hz, cap.lead_m(helical_angle_rad, c.helix_diameter_m), req.slip_efficiency
    )


def spiral_turns(helical_angle_rad: Any, c: Constants) -> Any:
    """Full turns the spiral makes over its wound length (capsule.spiral_turns)."""
    return cap.spiral_turns(helical_angle_rad, c.helix_diameter_m, c.wound_length_m)
