"""Tolerances as requirements (issue 36, item 3): every row held at its own worst corner.

Checked against independent computations: the rows' monotonicity on grids (which corner is
worst is measured, not assumed); the optimum evaluated at the eight corners of its box as eight
separate designs with no tolerance of their own; a brute-force angle x frequency grid of the
worst of those eight designs; the feasible intervals against full evaluations just inside and
just outside each end.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import replace

import numpy as np
import pytest
import tomllib

import torque_model as tm
from optimize import evaluate, margin_grid, optimize_design, prepare
from optimize import physics as ph
from optimize.system import Tolerances
from optimize.tolerance import _RESOLUTION, feasible_intervals
from spiralcap import cli
from spiralcap.assemble import build_model
from spiralcap.assemble.system import optimum_values
from spiralcap.design import load_design

#: The issue's case: a patient lumen of 11.0 mm, 0.5 deg / 0.02 mm / 0.1 mm.
ISSUE = [
    "tissue.lumen_diameter_mm=11.0",
    "tolerances.helical_angle_deg=0.5",
    "tolerances.spiral_wire_diameter_mm=0.02",
    "tolerances.lumen_diameter_mm=0.1",
]
ZERO = [
    "tolerances.helical_angle_deg=0",
    "tolerances.spiral_wire_diameter_mm=0",
    "tolerances.lumen_diameter_mm=0",
]


@pytest.fixture(scope="module")
def issue_case():
    design = load_design(None, ISSUE)
    model = prepare(build_model(design))
    res = optimize_design(model)
    assert res.status == "optimal", res.message
    return design, model, res


def _corner_model(design, res, da: float, dw: float, dl: float):
    """The optimum as its own design at one corner: the corner's values set, no tolerances."""
    values = optimum_values(design, res)
    values = {
        **values,
        "capsule.spiral.helical_angle_deg": values["capsule.spiral.helical_angle_deg"] + da,
        "capsule.spiral.wire_diameter_mm": design["capsule.spiral.wire_diameter_mm"] + dw,
        "tissue.lumen_diameter_mm": design["tissue.lumen_diameter_mm"] + dl,
        **{k.split("=")[0]: 0.0 for k in ZERO},
    }
    return prepare(build_model(design.with_values(values)))


def _corners(design):
    da = design["tolerances.helical_angle_deg"]
    dw = design["tolerances.spiral_wire_diameter_mm"]
    dl = design["tolerances.lumen_diameter_mm"]
    return list(itertools.product((-da, da), (-dw, dw), (-dl, dl)))


# --- which corner is worst: measured on grids ---------------------------------------------------


def test_rows_are_monotone_in_the_toleranced_keys():
    """On a grid of angles 3-40 deg, wires 0.6-1.4 mm, lumens 10-12 mm and 0.3-5 Hz: the strain
    falls with the angle and the lumen and rises with the wire; the resistive torque rises with
    the wire and falls with the lumen; the thrust rises with the angle and the wire; the speed
    rises with the angle and the wire; the spiral turns fall with both (finite differences on
    the grid, every step; the premise of holding each row at one corner)."""
    c0 = prepare(build_model(load_design(None, ZERO))).constants
    t0 = tm.preset("zhou2013-sample2")
    req = prepare(build_model(load_design(None, ZERO))).requirements
    a = np.radians(np.linspace(3.0, 40.0, 75))
    wires = np.linspace(0.6e-3, 1.4e-3, 9)
    lumens = np.linspace(10.0e-3, 12.0e-3, 9)
    freqs = np.array([0.3, 1.0, 5.0])
    strain = np.empty((a.size, wires.size, lumens.size))
    res = np.empty((a.size, wires.size, lumens.size, freqs.size))
    thrust = np.empty((a.size, wires.size))
    speed = np.empty((a.size, wires.size))
    turns = np.empty((a.size, wires.size))
    for j, w in enumerate(wires):
        c = replace(c0, wire_diameter_m=w, helix_diameter_m=c0.body_diameter_m + w)
        for k, lum in enumerate(lumens):
            tis = t0.replace(lumen_diameter_m=lum)
            strain[:, j, k] = ph.wall_strains(a, c, (tis,))[0]
            for m, f in enumerate(freqs):
                ((r, _),) = ph.required_torques_Nm(a, f, c, (tis,), req)
                res[:, j, k, m] = r
        ((_, thr),) = ph.required_torques_Nm(a, 1.0, c, (t0,), req)
        thrust[:, j] = thr
        speed[:, j] = ph.speed_m_s(a, 1.0, c, req)
        turns[:, j] = ph.spiral_turns(a, c)
    assert np.all(np.diff(strain, axis=0) < 0), "strain falls with the angle (D' shrinks)"
    assert np.all(np.diff(strain, axis=1) > 0), "strain rises with the wire"
    assert np.all(np.diff(strain, axis=2) < 0), "strain falls with the lumen"
    assert np.all(np.diff(res, axis=1) >= 0), "tissue torque does not fall with the wire"
    assert np.all(np.diff(res, axis=2) <= 0), "tissue torque does not rise with the lumen"
    assert np.all(np.diff(res, axis=0) <= 0), "tissue torque does not rise with the angle"
    assert np.all(np.diff(thrust, axis=0) > 0) and np.all(np.diff(thrust, axis=1) > 0), (
        "thrust F (D_h/2) tan(alpha + atan mu) rises with the angle and the wire"
    )
    assert np.all(np.diff(speed, axis=0) > 0) and np.all(np.diff(speed, axis=1) > 0)
    assert np.all(np.diff(turns, axis=0) < 0) and np.all(np.diff(turns, axis=1) < 0)


def test_required_torque_is_worst_at_an_end_of_the_angle_band():
    """The tissue torque falls with the angle while the thrust rises: their sum is held at the
    larger of the band's two ends. Sampled at 41 angles inside each 1 deg band over 3-40 deg
    and axial loads 0-1 N, no inner angle needs more than the larger end (1e-12 relative)."""
    base = prepare(build_model(load_design(None, ZERO)))
    c = base.constants
    for load in (0.0, 0.05, 0.3, 1.0):
        req = replace(base.requirements, axial_load_N=load)
        for centre in np.radians(np.linspace(3.5, 39.5, 37)):
            inner = centre + np.radians(np.linspace(-0.5, 0.5, 41))
            need = np.max(
                [
                    np.asarray(r + t)
                    for r, t in ph.required_torques_Nm(inner, 1.0, c, base.tissues, req)
                ],
                axis=0,
            )
            assert np.max(need) <= max(need[0], need[-1]) * (1 + 1e-12), (
                f"load {load} N, {math.degrees(centre):.1f} deg: an inner angle needs more"
            )


# --- the issue's case ----------------------------------------------------------------------------


def test_issue_optimum_near_the_brute_force(issue_case):
    """Issue 36's brute force: best worst-corner margin about 1.7 mN·m near 17 deg, 0.9 Hz."""
    _, _, res = issue_case
    assert res.margin_Nm == pytest.approx(1.7e-3, abs=0.1e-3), "about 1.7 mN·m (the issue)"
    assert 16.0 < res.helical_angle_deg < 18.5 and 0.75 < res.frequency_hz < 1.0


def test_issue_optimum_is_feasible_at_all_eight_corners(issue_case):
    """Each corner of 0.5 deg / 0.02 mm / 0.1 mm about the optimum, evaluated as its own design
    with no tolerances (angle, wire and lumen set to the corner's): feasible, and the least
    margin of the eight is the optimiser's (1e-6: the margin row is held at its worst corner)."""
    design, _, res = issue_case
    margins = []
    for da, dw, dl in _corners(design):
        ev = evaluate(_corner_model(design, res, da, dw, dl), frequency_bounds=False)
        assert ev.feasible, f"corner ({da:+g} deg, {dw:+g} mm, {dl:+g} mm): {ev.failed()}"
        margins.append(ev.margin_Nm)
    assert min(margins) == pytest.approx(res.margin_Nm, rel=1e-6), (
        "the worst of the eight corners' margins is the optimum's margin (1e-6)"
    )


@pytest.mark.slow
def test_issue_optimum_matches_a_brute_force_over_the_eight_corners(issue_case):
    """An independent search: the eight corner designs (no tolerances of their own) on one
    angle x frequency grid (12-25 deg by 0.02 deg, 0.5-1.5 Hz, 101 points), each at the field
    its limits allow; a point is feasible when all eight are, its margin the least of the
    eight. The optimum is at least the grid's best (1e-6) and within a grid cell of it."""
    design, _, res = issue_case
    step = 0.02
    a_deg = 12.0 + step * np.arange(650)  # 12-25 deg
    f = np.linspace(0.5, 1.5, 101)
    worst = np.full((a_deg.size, f.size), np.inf)
    ok = np.ones_like(worst, dtype=bool)
    # the corners -da and +da of one wire and lumen are one design at angles 2 da apart: its
    # grid over 12 - da to 25 + da (da a whole number of steps) holds both, each a slice
    da = design["tolerances.helical_angle_deg"]
    shift = round(da / step)
    assert shift * step == pytest.approx(da, abs=1e-12), "the angle tolerance is whole steps"
    span = 12.0 - da + step * np.arange(a_deg.size + 2 * shift)
    for dw, dl in {(dw, dl) for _, dw, dl in _corners(design)}:
        m = _corner_model(design, res, 0.0, dw, dl)
        g = margin_grid(m, np.radians(span)[:, None], f[None, :], capacity=True)
        for lo in (0, 2 * shift):  # the corner at -da, then at +da
            worst = np.minimum(worst, g.margin_Nm[lo : lo + a_deg.size])
            ok &= g.feasible[lo : lo + a_deg.size]
    best = np.unravel_index(np.argmax(np.where(ok, worst, -np.inf)), worst.shape)
    grid_best = worst[best]
    assert res.margin_Nm >= grid_best * (1 - 1e-6), (
        f"optimum {res.margin_Nm:.6e} >= grid best {grid_best:.6e} N·m (1e-6)"
    )
    assert res.margin_Nm <= grid_best * (1 + 5e-3), "and not beyond the grid's resolution"
    assert abs(a_deg[best[0]] - res.helical_angle_deg) < 0.1
    assert abs(f[best[1]] - res.frequency_hz) < 0.02


def test_feasible_intervals_against_evaluations(issue_case):
    """Each key's interval: a full evaluation of the design with that key moved to just inside
    an end (three times the search's resolution) is feasible, just outside infeasible on the named row, with the
    key's own tolerance off and the other two kept (their rows at their worst corners)."""
    design, model, res = issue_case
    ivs = feasible_intervals(model, res.helical_angle_rad, res.frequency_hz, res.field_amplitude_T)
    assert all(iv.holds for iv in ivs), "the optimum holds its whole box"
    base = optimum_values(design, res)
    keys = {
        "helical_angle_rad": ("capsule.spiral.helical_angle_deg", "tolerances.helical_angle_deg"),
        "spiral_wire_diameter_m": (
            "capsule.spiral.wire_diameter_mm",
            "tolerances.spiral_wire_diameter_mm",
        ),
        "lumen_diameter_m": ("tissue.lumen_diameter_mm", "tolerances.lumen_diameter_mm"),
    }
    for iv in ivs:
        key, tol_key = keys[iv.key]
        factor = 180 / math.pi if iv.key == "helical_angle_rad" else 1e3
        nominal = (
            base[key] if key in base else design[key]
        )  # the lumen's interval is an offset from it
        offset = iv.key == "lumen_diameter_m"
        step = 3 * _RESOLUTION[iv.key] * factor
        for end, sign, row in ((iv.low, -1, iv.low_limited_by), (iv.high, +1, iv.high_limited_by)):
            value = (nominal + end * factor) if offset else end * factor
            for shift, want in ((-sign * step, True), (sign * step, False)):
                moved = {**base, key: value + shift, tol_key: 0.0}
                # the optimiser's box must clear a thick wire's turn floor to build at all
                moved["optimize.helical_angle_min_deg"] = 5.0
                m = build_model(design.with_values(moved))
                ev = evaluate(m, frequency_bounds=False)
                assert ev.feasible is want, (key, end, shift, ev.failed())
                if not want:
                    assert row in {c.name for c in ev.failed()}, (key, row, ev.failed())


# --- defaults and input -------------------------------------------------------------------------


def test_init_writes_nonzero_defaults_and_the_builtin_design_stays_feasible(tmp_path, capsys):
    path = tmp_path / "d.toml"
    assert cli.main(["init", str(path)]) == 0
    tol = tomllib.loads(path.read_text())["tolerances"]
    assert tol["helical_angle_deg"] > 0 and tol["spiral_wire_diameter_mm"] > 0
    assert tol["lumen_diameter_mm"] > 0
    ev = evaluate(build_model(load_design(str(path))))
    assert ev.feasible, f"the built-in design within its default tolerances: {ev.failed()}"
    res = optimize_design(build_model(load_design(str(path))))
    assert res.status == "optimal"


def test_zero_tolerances_are_the_nominal_design():
    """0 is allowed and switches the box off: the built-in optimum of before issue 36 (pinned
    at 925e794: 19.65 deg, 2.3163059720816 mN·m) comes back."""
    # the minimum strain of before issue 36 too (1.7 %; its default is now 1.68 %)
    res = optimize_design(
        build_model(load_design(None, [*ZERO, "requirements.min_wall_strain=0.017"]))
    )
    assert res.status == "optimal"
    assert res.margin_Nm == pytest.approx(2.3163059720816e-3, rel=1e-9)
    assert res.helical_angle_deg == pytest.approx(19.65, abs=0.01)


def test_a_wider_box_costs_margin_and_holds_its_corners():
    """Doubling the angle tolerance (1 deg) costs margin against 0.5 deg on the built-in
    design (the rows only tighten), and its optimum still evaluates feasible at the eight
    corners of the wider box."""
    narrow = optimize_design(build_model(load_design()))
    wide_design = load_design(None, ["tolerances.helical_angle_deg=1.0"])
    wide = optimize_design(build_model(wide_design))
    assert wide.status == "optimal" and wide.margin_Nm < narrow.margin_Nm
    values = optimum_values(wide_design, wide)
    for da, dw, dl in _corners(wide_design):
        corner = {
            **values,
            "capsule.spiral.helical_angle_deg": values["capsule.spiral.helical_angle_deg"] + da,
            "capsule.spiral.wire_diameter_mm": 1.0 + dw,
            **{k.split("=")[0]: 0.0 for k in ZERO},
        }
        m = build_model(wide_design.with_values(corner))
        # every set keeps its own lumen: move each by dl
        m = replace(
            m,
            tissues=tuple(
                t.replace(lumen_diameter_m=t.lumen_diameter_m + dl * 1e-3) for t in m.tissues
            ),
        )
        ev = evaluate(m, frequency_bounds=False)
        assert ev.feasible, f"corner {da:+g} deg {dw:+g} mm {dl:+g} mm: {ev.failed()}"


@pytest.mark.parametrize(
    "sets, key",
    [
        (["tolerances.helical_angle_deg=6"], "tolerances.helical_angle_deg"),
        (["tolerances.lumen_diameter_mm=-0.1"], "tolerances.lumen_diameter_mm"),
        (["tolerances.spiral_wire_diameter_mm=1.0"], "tolerances.spiral_wire_diameter_mm"),
        (
            ["capsule.spiral.helical_angle_deg=0.4", "tolerances.helical_angle_deg=0.5"],
            "tolerances.helical_angle_deg",
        ),
    ],
)
def test_bad_tolerance_is_one_line_exit_2(sets, key, capsys):
    args = ["evaluate", *(a for s in sets for a in ("--set", s))]
    assert cli.main(args) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and key in err, err


def test_the_optimiser_keeps_the_flattest_corner_on_the_model():
    """The least helical angle is raised so that the band's flattest end stays on the
    model's floor (1.8 deg): a 2 deg lower bound with 0.5 deg of tolerance searches from 2.3."""
    model = build_model(load_design())
    assert math.degrees(model.bounds.helical_angle_min_rad) == pytest.approx(2.3, abs=1e-9)
    assert model.tolerances == Tolerances(math.radians(0.5), 0.02e-3, 0.05e-3)


# --- item 7: a least-power sizing buys no copper for nothing -------------------------------------

#: The z pair's turns, wire and pack shape free, least power at safety factor 2: the worst
#: heading lies in the x-y plane, where z carries no current, so z's copper hardly moves the
#: power (the issue's case: copper in z for a fraction of a per cent).
Z_FREE = {
    "optimize.free.coils.z.turns": [100, 2000],
    "optimize.free.coils.z.wire_diameter_mm": [0.8, 5.0],
    "optimize.free.coils.z.pack_aspect": [0.25, 4.0],
    "optimize.objective": "power",
    "requirements.min_safety_factor": 2.0,
}


@pytest.mark.slow
def test_least_power_sizing_declines_copper_that_buys_too_little(monkeypatch):
    """Without the rule the least-power sizing puts more than 10 % more copper in than a
    design within 1 % of its power needs; with it (the default) the sizing takes that leaner
    design: its copper, summed by hand from the written pairs, is at least 10 % below, its
    power (evaluated at the written field) within 1 % of the least power, and it holds the
    safety factor at every corner of its tolerance box."""
    from optimize import discrete
    from optimize.buildcheck import copper_masses_kg
    from optimize.discrete import size_design
    from spiralcap.core.constants import COPPER_DENSITY_kg_m3

    design = load_design().with_values(Z_FREE)
    model = prepare(build_model(design))
    # The sizing without the rule is the first step of the sizing with it: size_design(model,
    # SizingOptions(lean=None)) returns the very result the default sizing hands to the rule
    # (discrete.leaner) before the rule runs. Read there, not sized a second time.
    handed = []

    def leaner(model, res, *args, **kwargs):
        handed.append(res)
        return discrete_leaner(model, res, *args, **kwargs)

    discrete_leaner = discrete.leaner
    monkeypatch.setattr(discrete, "leaner", leaner)
    lean = size_design(model)
    monkeypatch.undo()
    (plain,) = handed  # the rule ran once, on the least-power sizing alone
    assert plain.status == lean.status == "optimal"
    kg0, kg1 = plain.evaluation.copper_mass_kg, lean.evaluation.copper_mass_kg
    assert kg0 > 1.10 * kg1, f"the least power alone spends {kg0:.4g} kg against {kg1:.4g} kg"
    assert lean.objective_value <= 1.01 * plain.objective_value * (1 + 1e-9), (
        "the leaner design's power is within 1 % of the least power"
    )
    assert lean.hardware.copper_declined["copper_kg"] == pytest.approx(kg0, rel=1e-12)
    written = build_model(design.with_values(optimum_values(design, lean)))
    pairs = written.coils.pairs
    by_hand = sum(
        COPPER_DENSITY_kg_m3
        * 2
        * p.turns
        * 2
        * math.pi
        * p.radius_m
        * math.pi
        * p.wire_diameter_m**2
        / 4
        for p in pairs
    )
    assert by_hand == pytest.approx(sum(copper_masses_kg(written)), rel=1e-9)
    assert by_hand == pytest.approx(kg1, rel=1e-9), "copper of the written design, by hand"
    ev = evaluate(written, frequency_bounds=False)
    assert ev.feasible and ev.safety_factor >= 2 * (1 - 1e-6)
    power = next(c.value for c in ev.checks if c.name == "power")
    assert power == pytest.approx(lean.objective_value, rel=1e-6), "its power as evaluated"
    values = optimum_values(design, lean)
    for da, dw, dl in _corners(design):
        corner = {
            **values,
            "capsule.spiral.helical_angle_deg": values["capsule.spiral.helical_angle_deg"] + da,
            "capsule.spiral.wire_diameter_mm": 1.0 + dw,
            **{k.split("=")[0]: 0.0 for k in ZERO},
        }
        m = build_model(design.with_values(corner))
        m = replace(
            m,
            tissues=tuple(
                t.replace(lumen_diameter_m=t.lumen_diameter_m + dl * 1e-3) for t in m.tissues
            ),
        )
        ev = evaluate(m, frequency_bounds=False)
        assert ev.feasible, f"sized design, corner {da:+g} deg {dw:+g} mm {dl:+g} mm: {ev.failed()}"


@pytest.mark.slow
def test_a_sizing_of_the_spiral_wire_holds_its_box():
    """The spiral wire freed (0.5-1.5 mm, margin): the sized design, evaluated at the eight
    corners of its box as eight designs with no tolerances (each set's lumen moved), is
    feasible everywhere and its least corner margin is the optimum's (1e-6); the wire's
    corners and the turn clearance act on a wire that is an NLP variable."""
    design = load_design().with_values(
        {"optimize.free.capsule.spiral.wire_diameter_mm": [0.5, 1.5]}
    )
    res = optimize_design(build_model(design))
    assert res.status == "optimal", res.message
    values = optimum_values(design, res)
    margins = []
    for da, dw, dl in _corners(design):
        corner = {
            **values,
            "capsule.spiral.helical_angle_deg": values["capsule.spiral.helical_angle_deg"] + da,
            "capsule.spiral.wire_diameter_mm": values["capsule.spiral.wire_diameter_mm"] + dw,
            **{k.split("=")[0]: 0.0 for k in ZERO},
        }
        m = build_model(design.with_values(corner))
        m = replace(
            m,
            tissues=tuple(
                t.replace(lumen_diameter_m=t.lumen_diameter_m + dl * 1e-3) for t in m.tissues
            ),
        )
        ev = evaluate(m, frequency_bounds=False)
        assert ev.feasible, f"corner {da:+g} deg {dw:+g} mm {dl:+g} mm: {ev.failed()}"
        margins.append(ev.margin_Nm)
    assert min(margins) == pytest.approx(res.margin_Nm, rel=1e-6)
