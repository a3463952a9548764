"""Issue 39, item 6, "the public API refuses nonsense": every public function of the four domain
packages checks its physical inputs (finite, sign, type) and raises ValueError (the project's
InputError) or TypeError naming the argument, never a silent or NaN answer, and never a
ZeroDivisionError, KeyError or AttributeError from deep inside.

What counts as nonsense is decided here from the argument's physical meaning (its name's unit),
not read back from the guards: a NaN or an infinity anywhere, or a number no quantity here comes
near (1e308, whose square overflows); a string, a bool or None for a number; a negative length, frequency, mass, resistance, inductance, power, moment or load; a
helical angle outside (0, 90°). Each public function is first called with sensible values (it
must answer), then hypothesis draws misuse calls (few examples, no deadline: fast).
"""

from __future__ import annotations

import functools
import inspect
import math
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import capsule
import coils
import optimize
import torque_model as tm

PACKAGES = (coils, capsule, torque_model := tm, optimize)
SETTINGS = settings(
    max_examples=12,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
ALLOWED = (ValueError, TypeError)


@pytest.fixture(scope="module")
def things():
    return _things()


@functools.cache
def _things():
    """The objects the public functions take: a prepared model, its coils, a tissue set and the
    paper's capsule geometry."""
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    model = optimize.prepare(build_model(load_design(None)))
    return {
        "model": model,
        "system": model.coils,
        "pair": model.coils.pairs[2],
        "tissue": tm.preset("zhou2013-sample2"),
        "geometry": tm.PAPER_CAPSULE,
        "result": None,
        "body": model.capsule.body,
        "spiral": model.capsule.spiral,
        "magnet": model.capsule.magnet,
    }


#: function name -> sensible arguments (strings name an object of ``things``)
VALID: dict[str, dict[str, object]] = {
    # coils
    "coaxial_mutual_inductance_H": {"radius1_m": 0.3, "radius2_m": 0.3, "distance_m": 0.15},
    "copper_loss_W": {"resistance_ohm": 5.0, "current_amplitude_A": 10.0},
    "copper_resistivity_ohm_m": {"temperature_C": 40.0},
    "heading_frame": {"heading": [0.0, 0.0, 1.0]},
    "impedance_ohm": {"resistance_ohm": 5.0, "inductance_H": 0.3, "frequency_hz": 2.0},
    "loop_field": {"radius_m": 0.3, "z0_m": 0.0, "rho_m": 0.05, "z_m": 0.02},
    "temperature_rise_K": {"power_W": 100.0, "thermal_conductance_W_per_K": 5.0},
    "voltage_amplitude_V": {
        "resistance_ohm": 5.0,
        "inductance_H": 0.3,
        "frequency_hz": 2.0,
        "current_amplitude_A": 10.0,
    },
    "uniformity": {
        "system": "system",
        "points_m": [[0.0, 0.0, 0.01]],
        "currents_A": [1.0, 0.5, 0.0],
    },
    "uniform_region": {"system_or_pair": "pair", "tolerance": 0.05},
    "uniform_region_radius_m": {"system_or_pair": "pair", "tolerance": 0.05},
    "uniform_regions": {"system_or_pair": "pair", "tolerances": [0.05]},
    "pair_uniform_regions": {"pairs": "pairs", "tolerances": [0.05]},
    "size_system": {
        "system": "system",
        "frequency_hz": 2.0,
        "current_amplitude_A": 10.0,
        "ambient_temperature_C": 25.0,
        "heat_transfer_coefficient_W_m2K": 10.0,
    },
    # capsule
    "body_volume_m3": {"diameter_m": 0.011, "length_m": 0.026},
    "footprint_width_m": {"helical_angle_rad": 0.2, "wire_diameter_m": 0.001},
    "forward_speed_m_s": {"frequency_hz": 2.0, "lead_m": 0.003, "slip_efficiency": 0.5},
    "geometry_problems": {"body": "body", "spiral": "spiral", "magnet": "magnet"},
    "helix_diameter_m": {"body_diameter_m": 0.011, "wire_diameter_m": 0.001},
    "lag_angle_rad": {"load_torque_Nm": 1e-3, "moment_Am2": 0.1, "field_amplitude_T": 0.01},
    "lead_m": {"helical_angle_rad": 0.2, "helix_diameter_m": 0.012},
    "magnet_fit_check": {"body": "body", "magnet": "magnet"},
    "magnet_fit_problem": {"body": "body", "magnet": "magnet"},
    "magnetic_torque_Nm": {"moment_Am2_vec": [0.1, 0.0, 0.0], "field_T_vec": [0.0, 0.01, 0.0]},
    "mass_from_parts_kg": {"diameter_m": 0.011, "length_m": 0.026, "magnet_volume_m3": 1e-7},
    "max_helical_angle_for_turns_rad": {
        "helix_diameter_m": 0.012,
        "wound_length_m": 0.015,
        "min_turns": 1.0,
    },
    "max_synchronous_torque_Nm": {"moment_Am2": 0.1, "field_amplitude_T": 0.01},
    "min_helical_angle_for_clearance_rad": {
        "helix_diameter_m": 0.012,
        "wire_diameter_m": 0.001,
        "starts": 1,
    },
    "remanence_for_grade": {"grade": "N42"},
    "self_lock_margin_rad": {"helical_angle_rad": 0.2, "friction_coefficient": 0.3},
    "spiral_turns": {"helical_angle_rad": 0.2, "helix_diameter_m": 0.012, "wound_length_m": 0.015},
    "synchronous_torque_Nm": {"moment_Am2": 0.1, "field_amplitude_T": 0.01, "lag_angle_rad": 0.3},
    "thrust_torque_Nm": {
        "axial_load_N": 0.05,
        "helix_diameter_m": 0.012,
        "helical_angle_rad": 0.2,
        "friction_coefficient": 0.3,
    },
    # torque_model
    "angular_frequency_rad_s": {"frequency_hz": 2.0},
    "capsule_d_prime_m": {"helical_angle_rad": 0.2, "geometry": "geometry"},
    "contact_factor_m3": {"helical_angle_rad": 0.2, "tissue": "tissue", "geometry": "geometry"},
    "contact_factors_m3": {"helical_angle_rad": 0.2, "tissue": "tissue", "geometry": "geometry"},
    "contact_radius_m": {"body_diameter_m": 0.011, "wire_diameter_m": 0.001},
    "end_contact_moment_m2": {
        "body_diameter_m": 0.011,
        "lumen_diameter_m": 0.0109,
        "wall_thickness_m": 0.001,
    },
    "equivalent_diameter_m": {
        "helical_angle_rad": 0.2,
        "body_diameter_m": 0.011,
        "wire_diameter_m": 0.001,
        "starts": 1,
    },
    "friction_per_length_N_m": {"frequency_hz": 2.0, "strain_": 0.03, "tissue": "tissue"},
    "hoop_pressure_Pa": {"stress": 1e3, "wall_thickness_m": 0.001, "diameter_after_m": 0.0115},
    "normal_load_per_length_N_m": {"frequency_hz": 2.0, "strain_": 0.03, "tissue": "tissue"},
    "preset": {"name": "zhou2013-sample3"},
    "relaxation_integral_Pa": {"frequency_hz": 2.0, "tissue": "tissue"},
    "relaxation_modulus_Pa": {"time_s": 0.1, "tissue": "tissue"},
    "resistive_torque_Nm": {
        "helical_angle_rad": 0.2,
        "frequency_hz": 2.0,
        "tissue": "tissue",
        "geometry": "geometry",
    },
    "section_torque_per_length_N": {
        "frequency_hz": 2.0,
        "diameter_after_m": 0.0115,
        "tissue": "tissue",
    },
    "strain": {"diameter_after_m": 0.0115, "lumen_diameter_m": 0.0109, "wall_thickness_m": 0.001},
    "stress_Pa": {"azimuth_rad": 0.5, "frequency_hz": 2.0, "strain_": 0.03, "tissue": "tissue"},
    "torque_breakdown_Nm": {
        "helical_angle_rad": 0.2,
        "frequency_hz": 2.0,
        "tissue": "tissue",
        "geometry": "geometry",
    },
    "wall_strain": {"helical_angle_rad": 0.2, "tissue": "tissue", "geometry": "geometry"},
    "weight_friction_torque_Nm": {
        "mass_kg": 0.004,
        "friction_coefficient": 0.3,
        "contact_radius_m_": 0.0055,
    },
    # optimize
    "evaluate": {"model": "model", "helical_angle_rad": 0.2, "frequency_hz": 2.0},
    "exposure_level_T": {"frequency_hz": 2.0, "kind": "public"},
    "margin_grid": {"model": "model", "helical_angle_rad": 0.2, "frequency_hz": 2.0},
    "grip_state": {"least_strain": 0.02, "min_wall_strain": 0.0168},
    "grip_bound": {"model": "model"},
    "max_frequency_hz": {"model": "model", "helical_angle_rad": 0.2},
    "step_out_frequency_hz": {"model": "model", "helical_angle_rad": 0.2},
    "worst_required": {"model": "model", "helical_angle_rad": 0.2, "frequency_hz": 2.0},
    "prepare": {"model": "model"},
}
#: public functions not in VALID, and why
EXEMPT = {
    "identify": "a least-squares fit over measured arrays: tests/test_torque_identification.py",
    "optimize_design": "an IPOPT solve; its model argument is type-checked (test below)",
    "with_operating_point": "needs an optimum; its arguments are type-checked (test below)",
}

#: arguments that may be negative (coordinates, signed stresses and angles of other kinds)
SIGNED = {
    "distance_m",
    "z0_m",
    "z_m",
    "stress",
    "azimuth_rad",
    "lag_angle_rad",
    "strain_",
    "moment_Am2_vec",
    "field_T_vec",
    "points_m",
    "heading",
    "temperature_C",
    "ambient_temperature_C",
}
#: unit suffixes of quantities that cannot be negative
UNSIGNED_SUFFIXES = (
    "_m",
    "_m3",
    "_hz",
    "_kg",
    "_ohm",
    "_H",
    "_W",
    "_A",
    "_Am2",
    "_T",
    "_N",
    "_Nm",
    "_s",
    "_W_per_K",
    "_W_m2K",
    "_W_mK",
    "friction_coefficient",
    "slip_efficiency",
    "tolerance",
    "tolerances",
    "min_turns",
    "starts",
)
ANGLES = {"helical_angle_rad"}


def _public_functions() -> dict[str, object]:
    out = {}
    for pkg in PACKAGES:
        for name in pkg.__all__:
            obj = getattr(pkg, name)
            if inspect.isfunction(obj):
                out[name] = obj
    return out


FUNCTIONS = _public_functions()


def _resolve(value: object, things: dict) -> object:
    if value == "pairs":
        return things["system"].pairs
    return things[value] if isinstance(value, str) and value in things else value


def _nonsense(param: str, valid: object) -> list[object]:
    """What no physical argument named ``param`` may be (see the module notes)."""
    # 1e308 is finite but its square is not; 10**400 is no float at all
    bad: list[object] = [math.nan, math.inf, -math.inf, "1.0", True, 1e308, -1e308, 10**400]
    if not isinstance(valid, (int, float)):  # an array argument: a NaN inside it
        bad = [[math.nan, 0.0, 1.0], "1.0", [0.0, "a"]]
    elif param in ANGLES:
        bad += [-0.1, 0.0, 2.0, math.pi / 2]
    elif param not in SIGNED and param.endswith(UNSIGNED_SUFFIXES):
        bad += [-1.0, -1e-9]
    return bad


def _numeric_params(name: str) -> list[str]:
    return [p for p, v in VALID[name].items() if not isinstance(v, str) and v is not None]


def test_every_public_function_is_covered():
    missing = sorted(set(FUNCTIONS) - set(VALID) - set(EXEMPT))
    assert not missing, f"public functions with no sensible call or exemption here: {missing}"


@pytest.mark.parametrize("name", sorted(VALID))
def test_sensible_call_answers(name, things):
    args = {k: _resolve(v, things) for k, v in VALID[name].items()}
    out = FUNCTIONS[name](**args)
    numeric = isinstance(out, (int, float)) or (
        isinstance(out, np.ndarray) and out.dtype.kind in "biuf"
    )
    values = [out] if numeric else []  # labels (grip_state's "ok") are not numbers
    for v in values:  # a sensible call gives finite numbers
        assert np.all(np.isfinite(np.asarray(v, dtype=float))), (name, out)


def _misuse(name: str, things: dict, data) -> None:
    numeric = _numeric_params(name)
    objects = [p for p, v in VALID[name].items() if isinstance(v, str) and v in things]
    choices = [(p, v) for p in numeric for v in _nonsense(p, VALID[name][p])]
    choices += [(p, v) for p in objects for v in ("text", 3.0, None)]
    if not choices:
        return
    param, bad = data.draw(st.sampled_from(choices), label="argument, value")
    args = {k: _resolve(v, things) for k, v in VALID[name].items()}
    args[param] = bad
    with pytest.raises(ALLOWED) as info:
        FUNCTIONS[name](**args)
    assert param in str(info.value), (
        f"{name}({param}={bad!r}): the error names the argument: {info.value}"
    )


@pytest.mark.parametrize("name", sorted(VALID))
@SETTINGS
@given(data=st.data())
def test_misuse_raises_value_or_type_error_naming_the_argument(name, data):
    _misuse(name, _things(), data)


def test_issue_examples(things):
    """The issue's cases: a negative frequency gave a finite 2.7 mN·m margin, a NaN angle a NaN
    margin, a string angle was accepted."""
    model = things["model"]
    with pytest.raises(ValueError, match=r"frequency_hz = -1\.0"):
        optimize.evaluate(model, frequency_hz=-1.0)
    with pytest.raises(ValueError, match="helical_angle_rad = nan"):
        optimize.evaluate(model, helical_angle_rad=float("nan"))
    with pytest.raises(TypeError, match="helical_angle_rad"):
        optimize.evaluate(model, helical_angle_rad="0.2")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="kind = 'bogus'"):
        optimize.exposure_level_T(2.0, "bogus")


def test_a_model_with_nonsense_numbers_is_refused_naming_the_field(things):
    """A model built by hand (dataclasses.replace) with a negative current limit, a NaN
    frequency or a text load: the error names the model's field, not a NaN margin."""
    from dataclasses import replace

    model = things["model"]
    cases = [
        (replace(model, limits=replace(model.limits, current_A=-1.0)), "model.limits.current_A"),
        (replace(model, frequency_hz=math.nan), "model.frequency_hz"),
        (
            replace(model, requirements=replace(model.requirements, axial_load_N="0.05")),
            "model.requirements.axial_load_N",
        ),
        (
            replace(model, bounds=replace(model.bounds, helical_angle_max_rad=2.0)),
            "model.bounds.helical_angle_max_rad",
        ),
    ]
    for bad, field in cases:
        for fn in (optimize.evaluate, optimize.optimize_design, optimize.prepare):
            with pytest.raises(ALLOWED, match=re.escape(field)):
                fn(bad)


@pytest.mark.parametrize("bad", ["model", None, 3.0, {"coils": 1}])
def test_optimiser_entry_points_refuse_what_is_not_a_model(bad):
    for fn in (optimize.optimize_design, optimize.prepare, optimize.evaluate):
        with pytest.raises(TypeError, match="model"):
            fn(bad)
    with pytest.raises(TypeError, match="model"):
        optimize.with_operating_point(bad, None)


def test_symbolic_values_pass_and_cost_nothing():
    """The guards let CasADi symbols through (the NLP is built on them) and a call from inside
    the domain packages is not checked again."""
    import casadi as ca

    a = ca.SX.sym("a")
    out = capsule.lead_m(a, 0.012)
    assert isinstance(out, ca.SX)
    f = ca.Function("f", [a], [out])
    assert float(f(0.2)) == pytest.approx(math.pi * 0.012 * math.tan(0.2), rel=1e-12), (
        "lead = pi D tan(alpha) (DESIGN.md 4.2), 1e-12"
    )


def _application_calls():
    from spiralcap.analysis.coils import analyse_coils
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design
    from spiralcap.figures import api
    from spiralcap.sweep import parse_over, sweep

    return {
        "load_design(path)": lambda bad: load_design(bad),
        "load_design(overrides)": lambda bad: load_design(None, bad),
        "build_model(design)": lambda bad: build_model(bad),
        "analyse_coils(design)": lambda bad: analyse_coils(bad),
        "sweep(design)": lambda bad: sweep(bad, []),
        "parse_over(expr)": lambda bad: parse_over(bad),
        "margin_vs_frequency(model)": lambda bad: api.margin_vs_frequency(bad, None),
        "torque_budget(evaluation)": lambda bad: api.torque_budget(bad),
        "geometry(model)": lambda bad: api.geometry(bad),
    }


@SETTINGS
@given(
    call=st.sampled_from(sorted(_application_calls())),
    bad=st.one_of(
        st.integers(), st.floats(allow_nan=True), st.none(), st.lists(st.integers(), min_size=1)
    ),
)
def test_application_entry_points_refuse_what_they_cannot_use(call, bad):
    """spiralcap's own public entry points: a wrong object is one TypeError/ValueError naming
    the argument (was: 'int' object is not iterable, AttributeError deep in a figure)."""
    arg = call.split("(")[1].rstrip(")")
    if call == "load_design(path)" and bad is None:  # None: the built-in example, allowed
        return
    with pytest.raises(ALLOWED) as info:
        _application_calls()[call](bad)
    assert arg in str(info.value), f"{call} with {bad!r}: {info.value}"
