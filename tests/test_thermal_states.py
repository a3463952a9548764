"""optimize.thermal_states: the three pairs' thermal states through one compiled CasADi Function.

Reference: coils.thermal_system.pair_temperatures evaluated operation by operation in Python (the
same model; the Function evaluates the same operations in C++, common subexpressions once).
Numbers agree to rounding (1e-12 relative; 1e-9 absolute for the runaway bound's 1e4 K), CasADi
expressions give the same values as the traced model, arrays are the Python model bit for bit.
"""

from __future__ import annotations

import dataclasses

import casadi as ca
import numpy as np
import pytest

from coils.thermal_system import pair_temperatures
from optimize import prepare, thermal_states
from spiralcap.assemble import build_model
from spiralcap.design import load_design

DESIGNS = {
    "built-in (natural air, view factors)": (None, ()),
    "fixed h": (None, ("coils.heat_transfer_coefficient_W_m2K=12",)),
    "forced air, 20 min session": (
        None,
        ("coils.cooling='forced'", "coils.air_speed_m_s=2", "operation.session_min=20"),
    ),
    "square frames (vertical bars)": ("examples/square_coils.toml", ()),
}
#: fields from cold to far past a runaway (T)
FIELDS_T = (0.0, 1e-4, 0.004, 0.0106, 0.03, 0.2)


def _constants(name: str):
    path, overrides = DESIGNS[name]
    return prepare(build_model(load_design(path, list(overrides)))).constants


def _python(c, field_T, amb=20.0):
    per = c.current_per_tesla_A_per_T
    return pair_temperatures(
        c.packs, c.resistance_20C_ohm, [field_T * per[k] for k in range(3)], amb,
        c.view_factors, c.session_s,
    )  # fmt: skip


def _numbers(state) -> dict[str, float]:
    out = {}
    for f in dataclasses.fields(state):
        v = getattr(state, f.name)
        if f.name == "internal":
            out.update(
                {f"internal.{g.name}": float(getattr(v, g.name)) for g in dataclasses.fields(v)}
            )
        else:
            out[f.name] = float(v)
    return out


@pytest.mark.parametrize("name", DESIGNS)
def test_numbers_are_the_python_model_to_rounding(name: str) -> None:
    c = _constants(name)
    for field in FIELDS_T:
        compiled = thermal_states.states(
            field, 20.0, c.current_per_tesla_A_per_T, c.resistance_20C_ohm, c.packs,
            c.view_factors, c.session_s,
        )  # fmt: skip
        for k, (a, b) in enumerate(zip(compiled, _python(c, field))):
            got, want = _numbers(a), _numbers(b)
            assert got.keys() == want.keys()
            for key, w in want.items():
                assert got[key] == pytest.approx(w, rel=1e-12, abs=1e-9), (
                    f"{name}, {field} T, pair {k}: {key} {got[key]!r} (compiled) vs {w!r} "
                    "(Python pair_temperatures), 1e-12 relative"
                )
    assert any(float(s.runaway) == 1.0 for s in _python(c, FIELDS_T[-1])), (
        f"{name}: the last field runs away (the bound branch is checked)"
    )


def test_casadi_expressions_are_the_traced_model() -> None:
    """Symbolic field and ambient: the Function inlined gives the values of the model traced
    directly on the same symbols."""
    c = _constants("forced air, 20 min session")
    b, amb = ca.SX.sym("b"), ca.SX.sym("amb")
    via = thermal_states.states(
        b, amb, c.current_per_tesla_A_per_T, c.resistance_20C_ohm, c.packs, c.view_factors,
        c.session_s,
    )  # fmt: skip
    direct = _python(c, b, amb)
    flat = ca.Function(
        "both",
        [b, amb],
        [ca.vertcat(*(ca.SX(s.hot_spot_C) for s in via)),
         ca.vertcat(*(ca.SX(s.hot_spot_C) for s in direct))],
    )  # fmt: skip
    for field in (0.002, 0.0106, 0.02):
        x, y = (np.asarray(v).ravel() for v in flat(field, 25.0))
        assert np.allclose(x, y, rtol=1e-12, atol=0.0), (
            f"{field} T: hot spots {x} (Function) vs {y} (traced), 1e-12"
        )


def test_long_arrays_are_the_python_model_bit_for_bit() -> None:
    c = _constants("built-in (natural air, view factors)")
    fields = np.linspace(0.0, 0.2, thermal_states.MAP_MAX + 1)
    got = thermal_states.states(
        fields, 20.0, c.current_per_tesla_A_per_T, c.resistance_20C_ohm, c.packs,
        c.view_factors, c.session_s,
    )  # fmt: skip
    for a, b in zip(got, _python(c, fields)):
        assert np.array_equal(np.asarray(a.mean_C), np.asarray(b.mean_C)), (
            "arrays longer than MAP_MAX go to pair_temperatures itself"
        )


@pytest.mark.parametrize("only", [None, 1])
def test_short_arrays_are_their_numbers_alone_bit_for_bit(only) -> None:
    """An element of a short array (a (2, 3) grid of fields, the ambient varying along it) is
    that number solved alone, bit for bit; pair ``only`` alone is its pair of the full call."""
    c = _constants("square frames (vertical bars)")
    fields = np.array([[0.0, 0.004, 0.0106], [0.02, 0.05, 0.2]])
    ambient = np.array([15.0, 20.0, 30.0])
    args = (c.current_per_tesla_A_per_T, c.resistance_20C_ohm, c.packs, c.view_factors)
    grid = thermal_states.states(fields, ambient, *args, c.session_s, only)
    full = thermal_states.states(fields, ambient, *args, c.session_s)
    for k in range(3):
        if only is not None and k != only:
            assert grid[k] is None, "only: the other pairs are None"
            continue
        assert np.array_equal(grid[k].hot_spot_C, full[k].hot_spot_C), "only == the full call"
        assert grid[k].hot_spot_C.shape == fields.shape
        for (i, j), field in np.ndenumerate(fields):
            alone = thermal_states.states(field, ambient[j], *args, c.session_s)[k]
            for name, want in _numbers(alone).items():
                got = _numbers(
                    dataclasses.replace(
                        grid[k],
                        **{f.name: np.asarray(getattr(grid[k], f.name))[i, j]
                           for f in dataclasses.fields(grid[k]) if f.name != "internal"},
                        internal=type(grid[k].internal)(
                            *(np.asarray(getattr(grid[k].internal, g.name))[i, j]
                              for g in dataclasses.fields(grid[k].internal))
                        ),
                    )
                )[name]  # fmt: skip
                assert got == want, f"pair {k}, {field} T, {ambient[j]} °C: {name} bit for bit"
