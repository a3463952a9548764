"""A lab's measured pairs beside the computed ones (``spiralcap coils``, the report).

For each pair that carries measured constants (its ``measured`` field, from the design keys
``coils.{x,y,z}.measured.*``): the measured resistance (at its measuring
temperature) and inductance, the values computed from the pair's geometry at the same
temperature, and the deviation measured / computed - 1. A deviation beyond
:data:`DEVIATION_WARNING` is a warning naming the likely causes.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

__all__ = ["DEVIATION_WARNING", "MeasuredPair", "measured_pairs", "measured_payload"]

#: Deviation of a measured constant from the computed one beyond which ``coils`` warns.
DEVIATION_WARNING = 0.15
_CAUSES = (
    "likely causes: the turn count, the wire size, series or parallel wiring of the two "
    "coils, the leads"
)


@dataclass(frozen=True)
class MeasuredPair:
    """One pair's measured constants beside the computed ones (SI; None: not measured).

    Attributes
    ----------
    axis : str
        ``"x"``, ``"y"`` or ``"z"``.
    temperature_C : float
        Temperature of the resistance measurement, °C.
    resistance_ohm, computed_resistance_ohm : float or None
        Measured and computed series resistance at ``temperature_C``, Ω.
    inductance_H, computed_inductance_H : float or None
        Measured and computed series inductance, H.
    """

    axis: str
    temperature_C: float
    resistance_ohm: float | None
    computed_resistance_ohm: float
    inductance_H: float | None
    computed_inductance_H: float

    @property
    def resistance_deviation(self) -> float | None:
        """measured / computed - 1 of the resistance (None: not measured), dimensionless."""
        r = self.resistance_ohm
        return None if r is None else r / self.computed_resistance_ohm - 1.0

    @property
    def inductance_deviation(self) -> float | None:
        """measured / computed - 1 of the inductance (None: not measured), dimensionless."""
        ind = self.inductance_H
        return None if ind is None else ind / self.computed_inductance_H - 1.0

    def warnings(self) -> list[str]:
        """One line per constant beyond :data:`DEVIATION_WARNING` of the computed one."""
        out = []
        for what, dev, computed, unit in (
            ("resistance", self.resistance_deviation, self.computed_resistance_ohm, "Ω"),
            ("inductance", self.inductance_deviation, self.computed_inductance_H, "H"),
        ):
            if dev is not None and abs(dev) > DEVIATION_WARNING:
                where = f" at {self.temperature_C:g} °C" if what == "resistance" else ""
                out.append(
                    f"warning: the {self.axis} pair's measured {what} is {abs(dev) * 100:.3g} % "
                    f"{'above' if dev > 0 else 'below'} the {computed:.4g} {unit} computed from "
                    f"its geometry{where}; {_CAUSES} (the measured value is the one used)"
                )
        return out


def measured_pairs(coils: Any) -> tuple[MeasuredPair, ...]:
    """The measured pairs of a coil set (only those whose pair carries ``measured``), each
    beside what its geometry gives.

    Parameters
    ----------
    coils : coils.ThreeAxisHelmholtz
        The coil set as built from the design (each pair's ``measured``,
        :class:`coils.winding.MeasuredConstants`, and its ``computed_*`` twins).

    Returns
    -------
    tuple of MeasuredPair
        One per measured pair, in x, y, z order.
    """
    out = []
    for pair in coils.pairs:
        m = pair.measured
        if m is None:
            continue
        out.append(
            MeasuredPair(
                axis=pair.axis,
                temperature_C=m.temperature_C,
                resistance_ohm=m.resistance_ohm,
                computed_resistance_ohm=float(pair.computed_resistance_ohm(m.temperature_C)),
                inductance_H=m.inductance_H,
                computed_inductance_H=float(pair.computed_series_inductance_H),
            )
        )
    return tuple(out)


def measured_payload(m: MeasuredPair) -> dict[str, Any]:
    """``axes.<p>.measured`` of ``spiralcap coils --json``: what was measured, the computed
    value beside it and the deviation (keys only for the constants measured)."""
    out: dict[str, Any] = {}
    if m.resistance_ohm is not None:
        out.update(
            resistance_ohm=m.resistance_ohm,
            temperature_C=m.temperature_C,
            computed_resistance_ohm=m.computed_resistance_ohm,
            resistance_deviation=m.resistance_deviation,
        )
    if m.inductance_H is not None:
        out.update(
            inductance_H=m.inductance_H,
            computed_inductance_H=m.computed_inductance_H,
            inductance_deviation=m.inductance_deviation,
        )
    return out
