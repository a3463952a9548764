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

__all__ = [
    "BUILD_CHECK_NAMES",
    "BuildCheck",
    "build_checks",
    "buildable_ok",
    "copper_masses_kg",
    "envelope_checks",
]

#: check name -> pair of pairs
CLEARANCE_NAMES = {"x/y": "clearance_xy", "x/z": "clearance_xz", "y/z": "clearance_yz"}
#: every check :func:`build_checks` can return
#: the envelope checks, one per axis of the room's box (``limits.envelope_mm``)
ENVELOPE_NAMES = ("envelope_x", "envelope_y", "envelope_z")
BUILD_CHECK_NAMES = frozenset(
    (*CLEARANCE_NAMES.values(), "bore_clearance", "copper_mass", *ENVELOPE_NAMES)
)


class BuildCheck(NamedTuple):
    """One buildability check (the fields of :class:`optimize.evaluate.Check`).

    Attributes
    ----------
    name : str
        Name of the check (:data:`BUILD_CHECK_NAMES`).
    unit : str
        Unit symbol of ``value`` and ``allowed`` (``"m"`` or ``"kg"``).
    value : float
        The checked quantity, in the unit ``unit`` names.
    allowed : float
        Its bound, in the unit ``unit`` names.
    sense : str
        ``">="`` or ``"<="``.
    ok : bool
        Flag: the check holds.
    """

    name: str
    unit: str
    value: float
    allowed: float
    sense: str
    ok: bool


def copper_masses_kg(model: Any) -> tuple[float, float, float]:
    """Copper mass of each pair (both coils), density x wire length x bare section, kg.

    Parameters
    ----------
    model : DesignModel
        The design (its coils).

    Returns
    -------
    tuple of float
        Copper of the x, y and z pairs, kg.
    """
    return tuple(  # type: ignore[return-value]
        float(p.copper_mass_kg) for p in model.coils.pairs
    )


def build_checks(model: Any, rtol: float = 1e-6) -> list[BuildCheck]:
    """The buildability checks of ``model`` (a :class:`optimize.DesignModel`):
    ``clearance_xy``, ``clearance_xz``, ``clearance_yz``,
    ``bore_clearance`` (m, >= the least clearance) and ``copper_mass`` (kg, <= the limit, only
    with ``limits.copper_mass_kg``).

    Parameters
    ----------
    model : DesignModel
        The design.
    rtol : float
        Relative slack granted to each bound, dimensionless.

    Returns
    -------
    list of BuildCheck
        The clearance checks (m) and the copper-mass check (kg).
    """
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
    return out + envelope_checks(model, rtol)


def envelope_checks(model: Any, rtol: float = 1e-6) -> list[BuildCheck]:
    """The coil set's outer box against ``limits.envelope_mm``, one check per axis (m, <=);
    none without an envelope.

    Parameters
    ----------
    model : DesignModel
        The design.
    rtol : float
        Relative slack granted to each bound, dimensionless.

    Returns
    -------
    list of BuildCheck
        ``envelope_x``, ``envelope_y``, ``envelope_z`` (edge length of the set's box, m).
    """
    from coils.clearance import outer_box_m

    env = model.limits.envelope_m
    if env is None:
        return []
    box = outer_box_m(model.coils.pairs)
    return [
        BuildCheck(name, "m", float(v), float(a), "<=", bool(v <= a * (1 + rtol)))
        for name, v, a in zip(ENVELOPE_NAMES, box, np.asarray(env, dtype=float))
    ]


def buildable_ok(model: Any, rtol: float = 1e-6) -> bool:
    """``all(c.ok for c in build_checks(model, rtol))``, the cheap checks first and each pack
    clearance decided by a proven lower bound where that suffices (the exact distance, a
    zooming search, only where the bound falls short): the same answer, bit for bit.

    The bound: each pack lies in the torus about its mean turn of tube radius half its
    section's diagonal, so clearance >= gap(mean turns) - (diag_a + diag_b)/2
    (:func:`coils.clearance.torus_clearance_bound_m`); the gap is the least over GAP_SAMPLES points
    of A's mean turn of the exact distance to B's (:func:`optimize.hardware.mean_turn_gap_m`),
    and a distance is 1-Lipschitz, so the true gap is at least that less the half spacing of
    the points along A's circle (an arc of pi R_a / GAP_SAMPLES).

    Parameters
    ----------
    model : DesignModel
        The design.
    rtol : float
        Relative slack granted to each bound, dimensionless.

    Returns
    -------
    bool
        Flag: every build check holds.
    """
    import itertools
    import math

    from coils.clearance import bore_clearance_m, pack_clearance_m, torus_clearance_bound_m
    from optimize.hardware import GAP_SAMPLES, mean_turn_gap_m

    need = float(model.requirements.min_clearance_m)
    slack = rtol * max(need, 1e-3)
    pairs = model.coils.pairs
    limit = model.limits.copper_mass_kg
    if limit is not None and not float(np.sum(copper_masses_kg(model))) <= limit * (1 + rtol):
        return False
    if not bore_clearance_m(pairs, model.requirements.bore_radius_m) >= need - slack:
        return False
    if not all(c.ok for c in envelope_checks(model, rtol)):
        return False
    for a, b in itertools.combinations(pairs, 2):
        rings = a.RING and b.RING  # a frame's corner leaves the torus
        gap = mean_turn_gap_m(a, b) - math.pi * a.radius_m / GAP_SAMPLES
        if rings and torus_clearance_bound_m(gap, a, b) >= need - slack:
            continue
        if not pack_clearance_m(a, b) >= need - slack:
            return False
    return True
