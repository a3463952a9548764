"""evaluate: the field the limits allow, the step-out frequency, and what it reports as failing."""

import json
import math
from dataclasses import replace

import numpy as np
import pytest

from optimize import evaluate, exposure_level_T, margin_grid, prepare
from spiralcap.assemble import build_model
from spiralcap.cli import main
from spiralcap.design import load_design


def _model(*overrides):
    return prepare(build_model(load_design(None, overrides)))


def test_current_limited_field_by_hand():
    m = _model(
        "limits.voltage_V=1e4",  # the largest each key allows (spiralcap.schema)
        "limits.power_W=1e6",
        "limits.coil_temperature_C=250",
        "limits.field_exposure=off",
    )
    ev = evaluate(m)
    g = np.asarray(m.coils.centre_gains_T_per_A)
    expected = m.limits.current_A * g.min()  # every heading: h_k = 1 (docs/optimisation.md, Limits)
    assert ev.field_amplitude_T == pytest.approx(expected, rel=1e-12), (
        "only the current binds: B0 = min_k g_k I_max (centre allocation), 1e-12"
    )
    assert ev.field_limited_by.startswith("current_")


def test_public_exposure_binds_at_4_hz():
    m = _model("limits.field_exposure=public", "operation.frequency_hz=4")
    ev = evaluate(m)
    assert ev.field_amplitude_T == pytest.approx(0.04 / 16, rel=1e-12), (
        "ICNIRP 2010 general public, 1-8 Hz: 4e-2/f^2 T rms = 2.5 mT at 4 Hz, 1e-12"
    )
    assert ev.field_limited_by == "field_exposure"


@pytest.mark.parametrize(
    "kind, f, level",
    [
        ("occupational", 0.5, 0.2),
        ("occupational", 2.0, 0.05),
        ("occupational", 8.0, 3.125e-3),
        ("occupational", 10.0, 2.5e-3),
        ("occupational", 100.0, 1e-3),
        ("public", 2.0, 0.01),
        ("public", 10.0, 5e-4),
        ("public", 40.0, 2e-4),
    ],
)
def test_icnirp_2010_reference_levels(kind, f, level):
    assert float(exposure_level_T(f, kind)) == pytest.approx(level, rel=1e-12), (
        "ICNIRP 2010 Tables 3-4 (held at the 1 Hz value below 1 Hz), 1e-12"
    )


def test_max_frequency_is_where_the_drive_margin_vanishes():
    m = _model()
    ev = evaluate(m)
    f = ev.max_frequency_hz
    assert 0 < f < math.inf and not ev.max_frequency_beyond_search, (
        "the drive's largest frequency is finite and positive for the built-in design"
    )
    at = float(margin_grid(m, ev.helical_angle_rad, f)["margin_Nm"])
    assert abs(at) < 1e-12, "drive margin is zero at max_frequency_hz (brentq, 1e-12 N·m)"
    assert float(margin_grid(m, ev.helical_angle_rad, 0.99 * f)["margin_Nm"]) > 0, (
        "margin is still positive just below the drive's largest frequency"
    )
    assert ev.max_frequency_limited_by == "voltage_x", "inductive voltage of the x pair sets it"
    assert ev.step_out_frequency_hz > ev.max_frequency_hz, (
        "at the operating field the capsule steps out above where the drive runs out"
    )


def test_margin_is_available_minus_required():
    ev = evaluate(_model())
    assert ev.margin_Nm == pytest.approx(
        ev.magnetic_torque_Nm - ev.required_torque_Nm, rel=1e-14
    ), "margin = synchronous torque - required torque (definition), 1e-14"
    assert ev.required_torque_Nm == pytest.approx(
        ev.resistive_torque_Nm + ev.thrust_torque_Nm, rel=1e-14
    ), "required = resistive + thrust (definition), 1e-14"
    assert math.sin(ev.lag_angle_rad) == pytest.approx(
        ev.required_torque_Nm / ev.magnetic_torque_Nm, rel=1e-12
    ), "tau = m B0 sin(delta)"


def test_worst_tissue_is_taken():
    m = _model()
    both = evaluate(m)
    alone = [evaluate(replace(m, tissues=(t,), constants=m.constants)) for t in m.tissues]
    assert both.margin_Nm == pytest.approx(min(e.margin_Nm for e in alone), rel=1e-14), (
        "worst case over tissue sets = the smallest single-set margin"
    )


def test_failing_requirement_is_reported(capsys):
    assert main(["evaluate", "--json", "--set", "requirements.min_speed_mm_s=50"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["feasible"] is False
    failed = [c["key"] for c in out["checks"] if not c["ok"]]
    assert failed == ["requirements.min_speed_mm_s"], "only the speed requirement fails"
    for key in (
        "field_amplitude_T",
        "magnetic_torque_Nm",
        "resistive_torque_Nm",
        "thrust_torque_Nm",
        "margin_Nm",
        "step_out_frequency_hz",
        "speed_m_s",
    ):
        assert isinstance(out[key], float), f"evaluate --json has {key} (README)"


@pytest.mark.parametrize(
    "overrides",
    [
        (),  # the drive voltage of the x pair sets it
        ("limits.voltage_V=400", "limits.field_exposure='public'"),  # exposure sets it
        (
            "coils.cooling='forced'",
            "coils.air_speed_m_s=2",
            "operation.session_min=20",
        ),  # session, forced air
        ("limits.power_W=150",),  # the power cap, flat in f
        ("tissue.scale=3",),  # stiff tissue: the margin crosses low
        ("operation.field_amplitude_mT=5",),  # a fixed field: no bracket from the step-out
    ],
)
def test_frequency_bounds_are_the_whole_grids_first_cell(overrides):
    """The search (Brent's method in log f, optimize.evaluate._first_zero) lands in the same
    cell as scanning the whole 400-point grid, and the margin on that grid does not rise with f
    (the premise of the search: the field caps stay or fall, the tissue torque rises)."""
    import importlib

    from optimize import physics as ph

    ev_mod = importlib.import_module("optimize.evaluate")

    m = _model(*overrides)
    ev = evaluate(m)
    c, amb = m.constants, m.ambient_temperature_C
    lo, hi = ev_mod.SEARCH_RANGE_HZ
    whole, _ = ev_mod.max_frequency_hz(m, ev.helical_angle_rad)  # over the whole range
    assert ev.max_frequency_hz == pytest.approx(whole.frequency_hz, rel=1e-11, abs=0), (
        f"{overrides}: evaluate's search in [operating f, step-out] finds the whole range's "
        "zero, 1e-11"
    )
    assert ev.max_frequency_beyond_search == whole.beyond_search, overrides
    grid = np.geomspace(lo, hi, ev_mod.FREQUENCY_GRID_POINTS)
    field = ph.field_capacity_T(grid, c, m.limits, amb)[0]
    drive = (
        np.asarray(ph.available_torque_Nm(field, c))
        - ev_mod.worst_required(m, ev.helical_angle_rad, grid).total_Nm
    )
    assert np.all(np.diff(drive) <= 1e-12 * np.max(np.abs(drive))), (
        f"{overrides}: the drive margin does not rise with frequency (to 1e-12 of its scale)"
    )
    below = np.nonzero(drive <= 0)[0]
    if below.size == 0:
        assert ev.max_frequency_beyond_search and ev.max_frequency_hz == hi, overrides
        return
    i = below[0]
    assert i > 0, f"{overrides}: the margin is positive at the low end"
    assert grid[i - 1] <= ev.max_frequency_hz <= grid[i], (
        f"{overrides}: max frequency {ev.max_frequency_hz} Hz in the whole grid's first cell "
        f"[{grid[i - 1]}, {grid[i]}] Hz"
    )


def test_first_zero_against_closed_form_roots():
    """optimize.evaluate._first_zero on margins with known roots: ln(5/f) (Brent in log f over
    the whole range) and a margin NaN below 1 Hz, then 2 - f (NaN counts as positive: the grid
    cell search takes over), both to 1e-12 of the root; the ends: negative from the start
    gives 0, positive (or NaN) at the top gives the bound."""
    import importlib

    ev_mod = importlib.import_module("optimize.evaluate")
    lo, hi = ev_mod.SEARCH_RANGE_HZ

    def nan_then_line(f):
        return math.nan if float(f) < 1.0 else 2.0 - float(f)

    cases = [
        (lambda f: math.log(5.0 / float(f)), 5.0),
        (nan_then_line, 2.0),
    ]
    for margin, root in cases:
        bound = ev_mod._first_zero(margin, lo, hi)
        assert not bound.beyond_search
        assert bound.frequency_hz == pytest.approx(root, rel=1e-12), (
            f"closed-form root {root} Hz, 1e-12"
        )
    assert ev_mod._first_zero(lambda f: -1.0, lo, hi).frequency_hz == 0.0, "negative from the start"
    for top in (1.0, math.nan):
        bound = ev_mod._first_zero(lambda f, top=top: top, lo, hi)
        assert bound.beyond_search and bound.frequency_hz == hi, (
            f"margin {top} at the top: the bound"
        )
