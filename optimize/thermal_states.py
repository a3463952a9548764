"""The three pairs' thermal states through one CasADi ``Function`` per thermal structure.

:func:`coils.thermal_system.pair_temperatures` is written once against the backend and is
hundreds of operations deep (a Newton solve per pair, three estimates, the coupling). Called
one operation at a time from Python it dominated the field-capacity searches (each voltage or
hot-spot cap evaluates it tens of times) and every NLP build (one symbolic trace each).

:func:`states` traces it once per *thermal structure* (each pack's cooling mode, orientation,
coil count and whether it has vertical bars; whether view factors and a session are given)
into a ``Function`` of one flat vector (field, ambient, currents per tesla, resistances, the
packs' numbers, view factors, session). Then:

- numbers (Python or numpy scalars) call its common-subexpression-eliminated form: the same
  operations evaluated in C++, equal to the Python evaluation to rounding (~1e-13 relative;
  ``tests/test_thermal_states.py``);
- CasADi expressions call the traced form, which CasADi inlines: the same expression graph as
  tracing ``pair_temperatures`` on them;
- arrays go to ``pair_temperatures`` itself (numpy is already vectorised).

The memo is :func:`functools.lru_cache` on the structure, like ``compile_problem``'s: the
physics modules keep no state.
"""

from __future__ import annotations

import functools
from typing import Any

import casadi as ca
import numpy as np

from spiralcap.core import backend as bk

#: WindingPack fields that are numbers of the flat input, per pack (the height only with bars)
_PACK_NUMBERS = (
    "pack_width_m",
    "pack_depth_m",
    "mean_radius_m",
    "packing_factor",
    "conductivity_W_mK",
    "heat_transfer_coefficient_W_m2K",
    "emissivity",
    "air_speed_m_s",
)
#: PairTemperatures fields in the flat output, per pair, in the class's order: these twelve,
#: then ``internal`` as its three offsets (``_INTERNAL``), then ``tangent_h_W_m2K``
_OUT_FIELDS = (
    "surface_C",
    "surface_max_C",
    "mean_C",
    "hot_spot_C",
    "power_W",
    "convection_W_m2K",
    "effective_h_W_m2K",
    "time_constant_s",
    "thermal_resistance_K_per_W",
    "sink_rise_K",
    "session_ratio",
    "runaway",
)
_INTERNAL = ("centre", "mean", "surface_max")
_PER_PAIR = len(_OUT_FIELDS) + len(_INTERNAL) + 1


def _has_bars(height: Any) -> bool:
    return not (isinstance(height, (int, float)) and height == 0.0)


def _structure(packs: tuple, view_factors: Any, session_s: Any) -> tuple:
    return (
        tuple(
            (p.convection, bool(p.vertical_axis), int(p.coils), _has_bars(p.vertical_bar_height_m))
            for p in packs
        ),
        view_factors is None,
        session_s is None,
    )


def _flat_inputs(
    field_T: Any,
    ambient_C: Any,
    per_A_per_T: Any,
    resistances_20C_ohm: Any,
    packs: tuple,
    view_factors: Any,
    session_s: Any,
) -> list[Any]:
    """The flat input's entries in :func:`_traced`'s order."""
    items = [field_T, ambient_C, *(per_A_per_T[k] for k in range(3))]
    items += [resistances_20C_ohm[k] for k in range(3)]
    for p in packs:
        items += [getattr(p, n) for n in _PACK_NUMBERS]
        if _has_bars(p.vertical_bar_height_m):
            items.append(p.vertical_bar_height_m)
    if view_factors is not None:
        items += [view_factors[j][i] for j in range(3) for i in range(4)]
    if session_s is not None:
        items.append(session_s)
    return items


@functools.lru_cache(maxsize=32)
def _traced(structure: tuple) -> tuple[ca.Function, ca.Function]:
    """(traced, cse) Functions of the flat input for ``structure``."""
    from coils.thermal import WindingPack
    from coils.thermal_system import pair_temperatures

    pack_keys, no_views, steady = structure
    n = 8 + sum(len(_PACK_NUMBERS) + bars for *_, bars in pack_keys)
    n += 0 if no_views else 12
    n += 0 if steady else 1
    x = ca.SX.sym("x", n)
    it = iter(x[i] for i in range(n))
    field, ambient = next(it), next(it)
    per = [next(it) for _ in range(3)]
    r20 = [next(it) for _ in range(3)]
    packs = []
    for convection, vertical, coils, bars in pack_keys:
        numbers = {name: next(it) for name in _PACK_NUMBERS}
        packs.append(
            WindingPack(
                **numbers,
                vertical_axis=vertical,
                convection=convection,
                coils=coils,
                vertical_bar_height_m=next(it) if bars else 0.0,
            )
        )
    views = None if no_views else [[next(it) for _ in range(4)] for _ in range(3)]
    session = None if steady else next(it)
    states = pair_temperatures(
        tuple(packs), r20, [field * per[k] for k in range(3)], ambient, views, session
    )
    out = []
    for s in states:
        out += [ca.SX(getattr(s, name)) for name in _OUT_FIELDS]
        out += [ca.SX(getattr(s.internal, name)) for name in _INTERNAL]
        out.append(ca.SX(s.tangent_h_W_m2K))
    flat = ca.vertcat(*out)
    return (
        ca.Function("pair_temperatures", [x], [flat]),
        ca.Function("pair_temperatures_cse", [x], [ca.cse(flat)]),
    )


def _unflat(values: Any) -> list[Any]:
    """Three PairTemperatures from the flat output (a list of floats or an SX column)."""
    from coils.thermal import _Internal
    from coils.thermal_system import PairTemperatures

    n = len(_OUT_FIELDS)
    out = []
    for k in range(3):
        v = [values[i] for i in range(k * _PER_PAIR, (k + 1) * _PER_PAIR)]
        named = dict(zip(_OUT_FIELDS, v))
        out.append(
            PairTemperatures(**named, internal=_Internal(*v[n : n + 3]), tangent_h_W_m2K=v[n + 3])
        )
    return out


def states(
    field_T: Any,
    ambient_C: Any,
    per_A_per_T: Any,
    resistances_20C_ohm: Any,
    packs: tuple,
    view_factors: Any,
    session_s: Any = None,
    only: int | None = None,
) -> list[Any]:
    """:func:`coils.thermal_system.pair_temperatures` of the three pairs at centre field
    ``field_T`` (pair k carries ``field_T * per_A_per_T[k]``), through the compiled Function
    of its structure for numbers and CasADi expressions (all three pairs whatever ``only``).

    Parameters
    ----------
    field_T : float or CasADi
        Centre field amplitude, T (an array: ``pair_temperatures`` itself).
    ambient_C : float or CasADi
        Ambient air, °C.
    per_A_per_T : sequence of float or CasADi
        Each pair's worst-heading current per tesla, A/T.
    resistances_20C_ohm : sequence of float or CasADi
        Each pair's resistance at 20 °C, Ω.
    packs : tuple of coils.thermal.WindingPack
        The x, y and z pairs' packs.
    view_factors : (3, 4) rows or None
        View factors ``[room, x, y, z]`` per pair, dimensionless (None: each alone).
    session_s : float, CasADi or None
        Session length, s (None: steady state).
    only : int, optional
        For arrays: index of the one pair to solve (0, 1, 2; the others None), or None for all
        three.

    Returns
    -------
    list of coils.thermal_system.PairTemperatures
        One per pair (x, y, z); °C, W, W/(m²·K), s, K/W.
    """
    items = _flat_inputs(
        field_T, ambient_C, per_A_per_T, resistances_20C_ohm, packs, view_factors, session_s
    )
    if bk.is_casadi(*items):
        traced = _traced(_structure(packs, view_factors, session_s))[0]
        return _unflat(traced(ca.vertcat(*items)))
    try:
        x = np.array(items, dtype=float)
    except (TypeError, ValueError):  # arrays of several lengths
        x = None
    if x is None or x.shape != (len(items),):  # arrays: numpy is already vectorised
        from coils.thermal_system import pair_temperatures

        return pair_temperatures(
            packs,
            resistances_20C_ohm,
            [field_T * per_A_per_T[k] for k in range(3)],
            ambient_C,
            view_factors,
            session_s,
            only,
        )
    fast = _traced(_structure(packs, view_factors, session_s))[1]
    return _unflat(fast(x).full().ravel().tolist())


__all__ = ["states"]
