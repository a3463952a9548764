"""The shortcuts the speed work took change no number (benchmarks/bench_sizing.py).

- coils.thermal.steady_state on a Python float, a numpy scalar, a 0-d array and inside a vector
  gives the same bits (the scalar path runs on floats; elementwise IEEE arithmetic is exact).
- evaluate / optimize_design with ``frequency_bounds=False`` (sweep rows, the discrete search's
  neighbours) equal the full call in everything but the skipped step-out and highest-frequency
  searches.
- margin_grid on an angle x frequency grid solves the field capacity once per distinct
  frequency, and the field caps kept in the constants' own memo (``Constants.memo``): the same bits
  as solving every grid point afresh.
- a Constants' memo is its own: a copy (``replace``), a pickled model start empty.
"""

import dataclasses
import math

import numpy as np
import pytest

from coils import thermal as th
from optimize import evaluate, optimize_design, prepare
from spiralcap.assemble import build_model
from spiralcap.design import load_design

_SKIPPED = {
    "step_out_frequency_hz",
    "max_frequency_hz",
    "max_frequency_limited_by",
    "step_out_beyond_search",
    "max_frequency_beyond_search",
}


@pytest.fixture(scope="module")
def model():
    return prepare(build_model(load_design()))


def test_steady_state_scalar_types_and_vector_agree(model):
    c = model.constants
    currents = [0.5, 4.0, 11.0, 30.0, 400.0]  # 400 A: runaway (the bound branch)
    for k in range(3):
        vec = th.steady_state(c.packs[k], c.resistance_20C_ohm[k], np.array(currents), 20.0)
        for i, cur in enumerate(currents):
            for arg in (cur, np.float64(cur), np.array(cur)):
                one = th.steady_state(c.packs[k], c.resistance_20C_ohm[k], arg, 20.0)
                for f in dataclasses.fields(one):
                    a = float(getattr(one, f.name))
                    b = float(np.asarray(getattr(vec, f.name))[i])
                    # issue 19: the convection correlations, Robin series and eigenvalues use
                    # pow/exp/sin/cos/arctan, which numpy evaluates with SIMD kernels on
                    # arrays and libm on scalars: the two may differ in the last bit
                    assert a == pytest.approx(b, rel=1e-14, abs=1e-14), (
                        f"axis {k}, {cur} A as {type(arg).__name__}: {f.name} {a!r} (scalar) "
                        f"vs {b!r} (vector element); the scalar path must agree to rounding"
                    )


def test_evaluate_without_frequency_bounds_is_the_full_evaluation(model):
    full = evaluate(model)
    quick = evaluate(model, frequency_bounds=False)
    assert math.isnan(quick.step_out_frequency_hz) and math.isnan(quick.max_frequency_hz)
    for f in dataclasses.fields(full):
        if f.name in _SKIPPED:
            continue
        assert getattr(quick, f.name) == getattr(full, f.name), (
            f"{f.name}: frequency_bounds=False must change only the skipped searches"
        )


def test_optimize_without_frequency_bounds_same_optimum(model):
    full = optimize_design(model)
    quick = optimize_design(model, frequency_bounds=False)
    same = ("status", "helical_angle_rad", "frequency_hz", "field_amplitude_T", "margin_Nm")
    for name in (*same, "objective_value", "current_amplitudes_A"):
        assert getattr(quick, name) == getattr(full, name), (
            f"{name}: the optimum must not depend on frequency_bounds (bit for bit)"
        )
    assert [b.name for b in quick.binding_limits] == [b.name for b in full.binding_limits]


def test_capacity_per_distinct_frequency_same_bits(model):
    from optimize import margin_grid
    from optimize import physics as ph

    b = model.bounds
    a = np.linspace(b.helical_angle_min_rad, b.helical_angle_max_rad, 7)
    f = np.geomspace(0.05, 40.0, 11)
    aa, ff = np.meshgrid(a, f)
    c, limits, amb = model.constants, model.limits, model.ambient_temperature_C
    grid = margin_grid(model, aa, ff, capacity=True).field_amplitude_T  # 11 solves
    fresh = ph.field_capacity_T(ff, c, limits, amb)  # every grid point's caps solved
    assert np.array_equal(grid, fresh[0]), (
        "capacity per distinct frequency == every grid point solved, bit for bit"
    )
    assert fresh[0].shape == aa.shape


def test_power_cap_is_the_plain_search_on_the_allowed_side(model):
    """Each budget's power cap equals a plain search on the total loss, bit for bit, and its
    loss is within the budget."""
    from optimize import physics as ph

    c, amb = model.constants, model.ambient_temperature_C
    for budget in (250.0, 700.0, 1000.0, 1414.2, 4000.0):
        memo = float(ph._power_cap_T(c, budget, amb))
        plain = float(
            ph._bisect_field_T(lambda b: ph.total_loss_W(b, c, amb), np.asarray(budget), ())
        )
        assert memo == plain, f"{budget} W: power cap == plain search, bit for bit"
        assert ph.total_loss_W(memo, c, amb) <= budget, "the cap is on the allowed side"


def test_coil_analysis_with_the_callers_model_is_the_same(model):
    """analyse_coils reuses a model the caller built (the report's): the same payload."""
    from spiralcap.analysis.coils import analyse_coils, coils_payload

    design = load_design()
    assert coils_payload(analyse_coils(design, model)) == coils_payload(analyse_coils(design))


def test_voltage_cap_of_a_frequency_does_not_depend_on_the_others(model):
    """Each frequency of a vectorised voltage-cap solve keeps its own first converged iterate:
    the cap at f is the same alone or among 60 others (curves == evaluate at a point)."""
    from optimize import physics as ph

    c, amb, volt = model.constants, model.ambient_temperature_C, model.limits.voltage_V
    f = np.geomspace(0.05, 60.0, 61)
    for k in range(3):
        together = ph._voltage_cap_solve(k, f, c, volt, amb)
        alone = [float(ph._voltage_cap_solve(k, float(x), c, volt, amb)) for x in f]
        assert np.allclose(together, alone, rtol=1e-12, atol=0.0), (
            f"axis {k}: vector == scalar caps (to rounding: SIMD vs libm transcendentals in the "
            "cooling model, issue 19)"
        )


def test_physics_memo_belongs_to_its_constants(model):
    """The memo lives with the constants it was solved for (no module-level cache): a replaced
    Constants starts empty, a pickled one arrives empty."""
    import pickle

    from optimize import physics as ph

    def sizes() -> dict:
        return {n: len(v) for n, v in vars(ph).items() if isinstance(v, dict | list | set)}

    c = model.constants
    before = sizes()
    ph.field_capacity_T(0.5, c, model.limits, model.ambient_temperature_C)
    ph.pair_states(0.01, c, model.ambient_temperature_C)
    assert c.memo.states, "filled in the constants' own memo"
    assert sizes() == before, "optimize.physics keeps nothing in module-level containers"
    other = dataclasses.replace(c, mass_kg=c.mass_kg)
    assert other.memo is not c.memo and not other.memo.states, "a replaced Constants: its own memo"
    again = pickle.loads(pickle.dumps(c)).memo
    assert not again.states, "a pickled Constants carries no memo"


@pytest.mark.parametrize(
    "overrides", [(), ("operation.session_min=20",), ("coils.winding_temperature_C=60",)]
)
def test_heading_losses_of_numbers_are_each_heading_alone_bit_for_bit(overrides):
    """Numbers take every heading at once (optimize.physics._heading_losses_of_numbers): each
    heading's loss is Σ_k R_k(I_hk) I_hk² / 2 with the resistance of that current alone."""
    from optimize import physics as ph

    m = prepare(build_model(load_design(None, list(overrides))))
    c, amb = m.constants, m.ambient_temperature_C
    a = np.asarray(c.heading_current_per_tesla_A_per_T)
    for field in (0.0, 0.003, 0.0106, 0.05):
        states = ph.pair_states(field, c, amb) if c.winding_temperature_C is None else [None] * 3
        for h, got in enumerate(ph.heading_losses_W(field, c, amb)):
            want = 0.0
            for k in range(3):
                if a[h, k] > 0:
                    cur = field * float(a[h, k])
                    r = ph.winding_resistance_ohm(cur, k, c, amb, states[k])
                    want = want + 0.5 * r * cur * cur
            assert got == want, f"{overrides}, {field} T, heading {h}: {got!r} == {want!r}"


@pytest.mark.parametrize(
    "overrides", [(), ("limits.power_W=300", "limits.surface_temperature_C=60")]
)
def test_frequency_free_caps_solved_once_are_the_same_bits(overrides):
    """A search over frequency solves the caps that do not depend on f once
    (optimize.physics.frequency_free_caps_T): the capacity is the same bits at every f."""
    from optimize import physics as ph

    m = prepare(build_model(load_design(None, list(overrides))))
    c, limits, amb = m.constants, m.limits, m.ambient_temperature_C
    known = ph.frequency_free_caps_T(c, limits, amb)
    assert any(k.startswith("hot_spot_") for k in known) and ("power" in known or not overrides), (
        f"the searched caps are there: {sorted(known)}"
    )
    for f in (0.05, 1.0, 3.7, np.geomspace(0.1, 40.0, 9)):
        plain = ph.field_capacity_T(f, c, limits, amb)
        fast = ph.field_capacity_T(f, c, limits, amb, known)
        assert np.array_equal(plain[0], fast[0]), f"{overrides} at {f} Hz: the same bits"
        for a, b, t in zip(plain[1], fast[1], plain[2]):
            assert np.array_equal(np.broadcast_to(a, np.shape(b)), b), f"{t.name} at {f} Hz"
