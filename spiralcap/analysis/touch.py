"""The touch-temperature warning: a pack surface hotter than IEC 60601-1 allows a held part.

``limits.surface_temperature_C`` is optional: without it no optimiser row or check keeps the
pack surfaces cool, and a design can pass with surfaces at 80 °C. IEC 60601-1 (3rd ed.,
Table 23/24) allows 48 °C for a part of medical equipment held 1-10 min; a coil pack the
operator or the patient can touch is such a part. :func:`touch_warning` names the pairs whose
hottest surface at the operating field is above that, for ``evaluate``, ``coils`` and the
report to print as a warning (a warning, not a failed check: the limit is the user's to set).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

#: IEC 60601-1 Table 23/24: the highest surface temperature of a part held 1-10 min, °C.
IEC60601_HELD_PART_C = 48.0
_AXES = ("x", "y", "z")


@dataclass(frozen=True)
class TouchWarning:
    """Pairs whose hottest pack surface (°C, at the operating field) is above ``limit_C``."""

    surfaces_C: dict[str, float]
    hot_pairs: tuple[str, ...]
    limit_C: float = IEC60601_HELD_PART_C

    def words(self) -> str:
        """One sentence: which pairs, how hot, the standard and the key that makes it a limit."""
        hot = ", ".join(f"{ax} {self.surfaces_C[ax]:.3g} °C" for ax in self.hot_pairs)
        names = self.hot_pairs
        which = names[0] if len(names) == 1 else ", ".join(names[:-1]) + f" and {names[-1]}"
        pairs = "pair's surface reaches" if len(names) == 1 else "pairs' surfaces reach"
        return (
            f"warning: the {which} {pairs} {hot}, above the "
            f"{self.limit_C:g} °C IEC 60601-1 allows a part held 1-10 min; no "
            "limits.surface_temperature_C is set, so nothing keeps them cooler (set it, e.g. "
            f"--set limits.surface_temperature_C={self.limit_C:g}, to make it a design limit)"
        )


def touch_warning(model: Any, field_T: float) -> TouchWarning | None:
    """The warning for ``model`` at the rotating field ``field_T`` (T), or None.

    Parameters
    ----------
    model : optimize.DesignModel
        The design (its coils, cooling, session and limits).
    field_T : float
        Centre field amplitude at the operating point, T (each pair at its worst-heading
        current, as the hot-spot check).

    Returns
    -------
    TouchWarning or None
        None when ``limits.surface_temperature_C`` is set (the check then says it) or no pack
        surface is above :data:`IEC60601_HELD_PART_C`.
    """
    from optimize.physics import pair_states
    from optimize.system import prepare

    if model.limits.surface_temperature_C is not None:
        return None
    model = prepare(model)
    states = pair_states(float(field_T), model.constants, model.ambient_temperature_C)
    surfaces = {ax: float(s.surface_max_C) for ax, s in zip(_AXES, states, strict=True)}
    hot = tuple(ax for ax in _AXES if surfaces[ax] > IEC60601_HELD_PART_C)
    return TouchWarning(surfaces, hot) if hot else None


def evaluation_warnings(model: Any, evaluation: Any) -> list[str]:
    """The warnings ``spiralcap evaluate`` prints (and its JSON's ``warnings``): the touch
    temperature at the evaluated field."""
    w = touch_warning(model, float(evaluation.field_amplitude_T))
    return [w.words()] if w is not None else []
