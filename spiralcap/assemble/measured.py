"""Design keys ``coils.{x,y,z}.measured.*`` -> the measured R (at 20 °C) and L of each pair.

A lab's pair as wired to its channel differs from the drawing (turn count, wire, series or
parallel wiring, leads): its measured series resistance and inductance replace the computed
ones in every voltage, power, heating and waveform figure (``optimize.system.precompute``). The
resistance is brought to 20 °C with copper's temperature coefficient (IEC 60028,
:func:`coils.electrical.copper_resistivity_ohm_m`). A sizing chooses the coils' geometry and
computes R and L from it, so a design that frees hardware refuses the measured keys.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from spiralcap.core.errors import InputError

__all__ = ["MEASURED_KEYS", "check_no_sizing", "measured_constants", "measured_temperature_C"]

_AXES = ("x", "y", "z")
#: The keys that carry a pair's measured constants (temperature_C only qualifies the first).
MEASURED_KEYS = tuple(
    f"coils.{ax}.measured.{leaf}" for ax in _AXES for leaf in ("resistance_ohm", "inductance_H")
)


def measured_temperature_C(design: Mapping[str, Any], ax: str) -> float:
    """The temperature of pair ``ax``'s measured resistance, °C (absent: 20)."""
    value = design.get(f"coils.{ax}.measured.temperature_C")
    return 20.0 if value is None else float(value)


def measured_constants(design: Mapping[str, Any]) -> tuple[Any, Any]:
    """(R at 20 °C in Ω, L in H) per pair as 3-tuples with None where not measured; (None,
    None) when nothing is measured.

    Raises
    ------
    InputError
        ``coils.A.measured.temperature_C`` without ``coils.A.measured.resistance_ohm``.
    """
    from coils.electrical import copper_resistivity_ohm_m

    for ax in _AXES:
        key = f"coils.{ax}.measured."
        if (
            design.get(key + "temperature_C") is not None
            and design.get(key + "resistance_ohm") is None
        ):
            raise InputError(
                key + "temperature_C",
                design.get(key + "temperature_C"),
                f"set together with {key}resistance_ohm (it is that measurement's temperature)",
            )
    if all(design.get(k) is None for k in MEASURED_KEYS):
        return None, None
    r20: list[float | None] = []
    ind: list[float | None] = []
    for ax in _AXES:
        r = design.get(f"coils.{ax}.measured.resistance_ohm")
        t = measured_temperature_C(design, ax)
        ratio = float(copper_resistivity_ohm_m(20.0) / copper_resistivity_ohm_m(t))
        r20.append(None if r is None else float(r) * ratio)
        inductance = design.get(f"coils.{ax}.measured.inductance_H")
        ind.append(None if inductance is None else float(inductance))
    return tuple(r20), tuple(ind)


def check_no_sizing(design: Mapping[str, Any], free: Mapping[str, Any]) -> None:
    """Refuse measured constants or a calibration in a design whose sizing frees hardware.

    The sizing computes every pair's resistance, inductance and field per ampere from the
    geometry it chooses (``optimize.hardware``), so neither a measurement nor a calibration of
    the coils in the room would be what it sizes.

    Raises
    ------
    InputError
        Naming the first measured or calibration key set, the freed key and what to do.
    """
    if not free:
        return
    from spiralcap.assemble.calibration import CALIBRATION_KEYS

    freed = "optimize.free." + next(iter(free))
    for key in (*MEASURED_KEYS, *CALIBRATION_KEYS):
        if design.get(key) is not None:
            raise InputError(
                key,
                design[key],
                f"no value in a sizing ({freed} is freed): the sizing computes every pair's R, L "
                "and field per ampere from the geometry it chooses; size without the measured "
                "and calibration keys, then measure the coils you build",
            )
