"""The touch-temperature warning: a pack surface hotter than IEC 60601-1 allows for its contact.

``limits.surface_temperature_C`` is optional: without it no optimiser row or check keeps the
pack surfaces cool, and a design can pass with surfaces at 80 °C. IEC 60601-1 (3rd ed.,
Table 24, metal parts the patient may touch) allows 43 °C for contact of 10 min or more, 48 °C
for 1-10 min and 51 °C under 1 min. The contact time is the run length,
``operation.session_min`` (absent: steady operation, contact of 10 min or more).
:func:`touch_warning` names the pairs whose hottest surface at the operating field is above the
limit for that time, for ``evaluate``, ``coils`` and the report to print as a warning (a
warning, not a failed check: the limit is the user's to set).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

#: IEC 60601-1 (3rd ed.) Table 24, metal parts in contact with the patient: the highest surface
#: temperature for contact of 10 min or more, 1-10 min and under 1 min, °C.
IEC60601_LONG_CONTACT_C = 43.0
IEC60601_HELD_PART_C = 48.0
IEC60601_BRIEF_CONTACT_C = 51.0
_AXES = ("x", "y", "z")


@dataclass(frozen=True)
class TouchWarning:
    """Pairs whose hottest pack surface (°C, at the operating field) is above ``limit_C``."""

    surfaces_C: dict[str, float]
    hot_pairs: tuple[str, ...]
    limit_C: float = IEC60601_HELD_PART_C
    contact: str = "of 1-10 min"

    def words(self) -> str:
        """One sentence: which pairs, how hot, the standard and the key that makes it a limit."""
        hot = ", ".join(f"{ax} {self.surfaces_C[ax]:.3g} °C" for ax in self.hot_pairs)
        names = self.hot_pairs
        which = names[0] if len(names) == 1 else ", ".join(names[:-1]) + f" and {names[-1]}"
        pairs = "pair's surface reaches" if len(names) == 1 else "pairs' surfaces reach"
        return (
            f"warning: the {which} {pairs} {hot}, above the "
            f"{self.limit_C:g} °C IEC 60601-1 allows metal in contact {self.contact} "
            "(Table 24); no "
            "limits.surface_temperature_C is set, so nothing keeps them cooler (set it, e.g. "
            f"--set limits.surface_temperature_C={self.limit_C:g}, to make it a design limit)"
        )


def touch_limit_C(session_s: float | None) -> tuple[float, str]:
    """IEC 60601-1 Table 24's limit for metal in contact for ``session_s`` (None: steady), °C.

    Parameters
    ----------
    session_s : float or None
        Contact time, s (the run length ``operation.session_min``; None: steady operation).

    Returns
    -------
    limit_C : float
        43 °C for 10 min or more (or steady), 48 °C for 1-10 min, 51 °C under 1 min.
    contact : str
        The contact time in words (``"of 10 min or more"``).
    """
    if session_s is None or session_s >= 600.0:
        return IEC60601_LONG_CONTACT_C, "of 10 min or more"
    if session_s >= 60.0:
        return IEC60601_HELD_PART_C, "of 1-10 min"
    return IEC60601_BRIEF_CONTACT_C, "under 1 min"


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
        surface is above the limit :func:`touch_limit_C` gives for the run length.
    """
    from optimize.physics import pair_states
    from optimize.system import prepare

    if model.limits.surface_temperature_C is not None:
        return None
    model = prepare(model)
    states = pair_states(float(field_T), model.constants, model.ambient_temperature_C)
    surfaces = {ax: float(s.surface_max_C) for ax, s in zip(_AXES, states, strict=True)}
    limit, contact = touch_limit_C(model.session_s)
    hot = tuple(ax for ax in _AXES if surfaces[ax] > limit)
    return TouchWarning(surfaces, hot, limit, contact) if hot else None


def evaluation_warnings(model: Any, evaluation: Any) -> list[str]:
    """The warnings ``spiralcap evaluate`` prints (and its JSON's ``warnings``): the touch
    temperature at the evaluated field."""
    w = touch_warning(model, float(evaluation.field_amplitude_T))
    return [w.words()] if w is not None else []
