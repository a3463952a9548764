"""Can the coil set be built: pack clearances, room to the bore, copper mass (exact, numpy).

The checks :func:`optimize.evaluate` reports and the discrete sizing step applies to every
candidate: the least distance between the winding packs of two pairs as solids
(:func:`coils.clearance.pack_clearance_m`) and between the packs' inner faces and the bore
(:func:`coils.clearance.bore_clearance_m`), each at least ``requirements.min_clearance_m``, and
the total copper mass at most ``limits.copper_mass_kg`` when that limit is set.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

__all__ = ["BUILD_CHECK_NAMES", "BuildCheck", "build_checks", "copper_masses_kg"]

#: check name -> pair of pairs
CLEARANCE_NAMES = {"x/y": "clearance_xy", "x/z": "clearance_xz", "y/z": "clearance_yz"}
#: every check :func:`build_checks` can return
BUILD_CHECK_NAMES = frozenset((*CLEARANCE_NAMES.values(), "bore_clearance", "copper_mass"))


class BuildCheck(NamedTuple):
    """One buildability check (the fields of :class:`optimize.evaluate.Check`)."""

    name: str
    unit: str
    value: float
    allowed: float
    sense: str
    ok: bool


def copper_masses_kg(model: Any) -> tuple[float, float, float]:
    """Copper mass of each pair (both coils), density x wire length x bare section, kg."""
    from spiralcap.constants import COPPER_DENSITY_kg_m3

    return tuple(  # type: ignore[return-value]
        float(COPPER_DENSITY_kg_m3 * p.wire_length_m * p.wire_area_m2) for p in model.coils.pairs
    )


def build_checks(model: Any, rtol: float = 1e-6) -> list[BuildCheck]:
    """The buildability checks of ``model`` (a :class:`optimize.DesignModel`):
    ``clearance_xy``, ``clearance_xz``, ``clearance_yz``,
    ``bore_clearance`` (m, >= the least clearance) and ``copper_mass`` (kg, <= the limit, only
    with ``limits.copper_mass_kg``)."""
    from coils.clearance import bore_clearance_m, pack_clearances_m

    Check = BuildCheck
    need = float(model.requirements.min_clearance_m)
    slack = rtol * max(need, 1e-3)
    out = []
    for pair, value in pack_clearances_m(model.coils.pairs).items():
        out.append(Check(CLEARANCE_NAMES[pair], "m", value, need, ">=", value >= need - slack))
    bore = bore_clearance_m(model.coils.pairs, model.requirements.bore_radius_m)
    out.append(Check("bore_clearance", "m", bore, need, ">=", bore >= need - slack))
    limit = model.limits.copper_mass_kg
    if limit is not None:
        mass = float(np.sum(copper_masses_kg(model)))
        out.append(Check("copper_mass", "kg", mass, limit, "<=", mass <= limit * (1 + rtol)))
    return out
