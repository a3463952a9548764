"""The three pairs' thermal states through one CasADi ``Function`` per thermal structure.

:func:`coils.thermal_system.pair_temperatures` is written once against the backend and is
hundreds of operations deep (a Newton solve per pair, three estimates, the coupling). Called
one operation at a time from Python it dominated the field-capacity searches (each voltage or
hot-spot cap evaluates it tens of times) and every NLP build (one symbolic trace each).

:func:`states` traces it once per *thermal structure* (each pack's cooling mode, orientation,
coil count and whether it has vertical bars; whether view factors and a session are given)
into a ``Function`` of one flat vector (field, ambient, currents per tesla, resistances, the
packs' numbers, view factors, session). Then:

- numbers, and arrays of at most :data:`MAP_MAX` elements, call its
  common-subexpression-eliminated form (mapped over the elements; only pair ``only``'s
  outputs where the caller asks for one): the same operations evaluated in C++, equal to the
  Python evaluation to rounding (~1e-13 relative; ``tests/test_thermal_states.py``), and an
  element of an array the same bits as that number alone;
- CasADi expressions call the traced form, which CasADi inlines: the same expression graph as
  tracing ``pair_temperatures`` on them;
- longer arrays go to ``pair_temperatures`` itself (numpy's vectorised model costs about the
  same per call whatever the length).

The memo is :func:`functools.lru_cache` on the structure, like ``compile_problem``'s: the
physics modules keep no state.
"""

from __future__ import annotations

import functools
from typing import Any

import casadi as ca
import numpy as np

from coils.thermal import PACK_NUMBER_FIELDS
from spiralcap.core import backend as bk

#: WindingPack fields that are numbers of the flat input, per pack (the height only with bars)
_PACK_NUMBERS = PACK_NUMBER_FIELDS[:-1]
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


#: Arrays up to this many elements go through the compiled Function (``map``: 8-15 µs per
#: element, one pair or three, against 2.3-6 ms per call for numpy's vectorised model, which
#: costs about the same whatever the length); longer ones through numpy.
MAP_MAX = 128


@functools.lru_cache(maxsize=32)
def _traced(structure: tuple) -> ca.Function:
    """The model traced on the flat input of ``structure``: one output column (three pairs)."""
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
    return ca.Function("pair_temperatures", [x], [ca.vertcat(*out)])


@functools.lru_cache(maxsize=128)
def _numeric(structure: tuple, only: int | None) -> ca.Function:
    """The outputs of pair ``only`` (None: all three) of :func:`_traced`, each common
    subexpression once (``casadi.cse``): what numbers are evaluated with."""
    f = _traced(structure)
    x = f.sx_in(0)
    flat = f(x)
    if only is not None:
        flat = flat[only * _PER_PAIR : (only + 1) * _PER_PAIR]
    return ca.Function("pair_temperatures_cse", [x], [ca.cse(flat)])


def _unflat(values: Any, pairs: Any = range(3)) -> list[Any]:
    """Three PairTemperatures (None where ``pairs`` leaves one out) from the flat output of
    ``pairs`` (a sequence of numbers or arrays, or an SX column)."""
    from coils.thermal import _Internal
    from coils.thermal_system import PairTemperatures

    n = len(_OUT_FIELDS)
    out: list[Any] = [None, None, None]
    for j, k in enumerate(pairs):
        v = [values[i] for i in range(j * _PER_PAIR, (j + 1) * _PER_PAIR)]
        named = dict(zip(_OUT_FIELDS, v))
        out[k] = PairTemperatures(
            **named, internal=_Internal(*v[n : n + 3]), tangent_h_W_m2K=v[n + 3]
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
    of its structure for numbers, short arrays and CasADi expressions.

    Parameters
    ----------
    field_T : float, array or CasADi
        Centre field amplitude, T.
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
        Index of the one pair to solve (0, 1, 2; the others None; CasADi expressions: all
        three), or None for all three.

    Returns
    -------
    list of coils.thermal_system.PairTemperatures or None
        One per pair (x, y, z); °C, W, W/(m²·K), s, K/W; floats for numbers, arrays of the
        inputs' broadcast shape for arrays.
    """
    items = _flat_inputs(
        field_T, ambient_C, per_A_per_T, resistances_20C_ohm, packs, view_factors, session_s
    )
    structure = _structure(packs, view_factors, session_s)
    if bk.is_casadi(*items):
        return _unflat(_traced(structure)(ca.vertcat(*items)))
    pairs = range(3) if only is None else (only,)
    try:
        x = np.array(items, dtype=float)
    except (TypeError, ValueError):  # arrays of several shapes: broadcast them
        x = np.array(np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in items)))
    if x.ndim == 1:  # numbers: Python floats out
        return _unflat(_numeric(structure, only)(x).full().ravel().tolist(), pairs)
    shape = x.shape[1:]
    if 0 < x[0].size <= MAP_MAX:  # (an empty array: numpy, whose shapes hold)
        columns = _numeric(structure, only).map(x[0].size)(x.reshape(len(items), -1)).full()
        return _unflat([row.reshape(shape) for row in columns], pairs)
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


__all__ = ["MAP_MAX", "states"]
