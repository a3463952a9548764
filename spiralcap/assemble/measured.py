"""Design keys ``coils.{x,y,z}.measured.*`` -> each pair's own ``measured`` field.

A lab's pair as wired to its channel differs from the drawing (turn count, wire, series or
parallel wiring, leads): its measured series resistance and inductance become the pair's
:class:`coils.winding.MeasuredConstants` (:func:`measured_of`, set by
``spiralcap.assemble.coils.build_coils``), and the pair's ``resistance_ohm(T)`` and
``series_inductance_H`` answer them, so every voltage, power, heating, waveform and table
figure that asks the pair uses them (the resistance follows copper's temperature coefficient
from the measuring temperature, IEC 60028). A sizing chooses the coils' geometry and computes R
and L from it, so a design that frees hardware refuses the measured keys
(:func:`check_no_sizing`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from spiralcap.core.errors import InputError

__all__ = ["MEASURED_KEYS", "check_no_sizing", "measured_of"]

_AXES = ("x", "y", "z")
#: The keys that carry a pair's measured constants (temperature_C only qualifies the first).
MEASURED_KEYS = tuple(
    f"coils.{ax}.measured.{leaf}" for ax in _AXES for leaf in ("resistance_ohm", "inductance_H")
)


def measured_of(design: Mapping[str, Any], ax: str) -> Any:
    """Pair ``ax``'s measured constants as the pair's own field
    (:class:`coils.winding.MeasuredConstants`), or None when the design measures nothing of it.

    Raises
    ------
    InputError
        ``coils.A.measured.temperature_C`` without ``coils.A.measured.resistance_ohm``.
    """
    from coils.winding import MeasuredConstants

    key = f"coils.{ax}.measured."
    r, t = design.get(key + "resistance_ohm"), design.get(key + "temperature_C")
    if t is not None and r is None:
        raise InputError(
            key + "temperature_C",
            t,
            f"set together with {key}resistance_ohm (it is that measurement's temperature)",
        )
    inductance = design.get(key + "inductance_H")
    if r is None and inductance is None:
        return None
    return MeasuredConstants(
        resistance_ohm=None if r is None else float(r),
        temperature_C=20.0 if t is None else float(t),
        inductance_H=None if inductance is None else float(inductance),
    )


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
