"""The spiral must grip the wall; the capsule's weight rubs on it; the anatomy is the patient's.

A capsule whose equivalent diameter D' does not exceed the lumen gets no tissue torque from the
Zhou 2013 model (eq. 6 clipped at zero) and cannot screw itself forward; such a design must not
read as safe, and no optimiser may settle where the spiral only grazes the wall
(``requirements.min_wall_strain``, an NLP row). Independent references: the strain and D' at
their boundary on numpy and CasADi, the weight friction and the capsule mass by hand (a volume
integral by scipy quadrature), the paper's stated torques.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace

import casadi as ca
import numpy as np
import pytest
from cli_outcome import NO_TOLERANCE_SETS, run, run_json
from scipy import integrate

import capsule as cap
import torque_model as tm
from optimize import optimize_design
from optimize import physics as ph
from optimize.system import prepare
from spiralcap.assemble import build_model
from spiralcap.design import load_design
from spiralcap.schema import KEYS

#: The new user's capsule (issue report): 9 mm x 24 mm, 5 x 8 mm magnet, 0.8 mm spiral at 12
#: deg, a 9.5 mm lumen, a 70 V / 40 A / 4.5 kW drive. D' = 9.296 mm < 9.5 mm.
SMALL = [
    "capsule.diameter_mm=9",
    "capsule.length_mm=24",
    "capsule.magnet.diameter_mm=5",
    "capsule.magnet.length_mm=8",
    "capsule.spiral.wire_diameter_mm=0.8",
    "capsule.spiral.helical_angle_deg=12",
    "tissue.lumen_diameter_mm=9.5",
    "limits.voltage_V=70",
    "limits.current_A=40",
    "limits.power_W=4500",
]


#: One IPOPT start (default 4) where the subject is the grip, not the angle's starts: the sizings
#: below give the same optimum (objective to 1e-12) and the refusals the same text (numbers to
#: 1e-10) from one start as from four, measured.
ONE_START = ["--set", "optimize.starts=1"]


def _sets(values: list[str]) -> list[str]:
    return [a for v in values for a in ("--set", v)]


def test_strain_at_its_boundary_numpy_and_casadi_agree():
    """D' = lumen +- eps: the strain changes sign there, numpy and CasADi agree to 1e-12, and
    the tissue torque is zero exactly where the spiral does not touch."""
    g = tm.PAPER_CAPSULE
    alpha = math.radians(12.0)
    d_prime = float(tm.equivalent_diameter_m(alpha, g.body_diameter_m, g.wire_diameter_m, 1))
    a = ca.SX.sym("a")
    for eps in (-1e-7, 1e-7):
        tissue = replace(tm.preset("zhou2013-sample2"), lumen_diameter_m=d_prime + eps)
        num = float(tm.wall_strain(alpha, tissue, g))
        sym = float(ca.Function("s", [a], [tm.wall_strain(a, tissue, g)])(alpha))
        assert abs(num - sym) <= 1e-12, "wall strain: numpy and CasADi paths agree to 1e-12"
        expected = -eps / (d_prime + eps + tissue.wall_thickness_m)
        assert num == pytest.approx(expected, rel=1e-6, abs=1e-15), (
            "eq. 6 at D_after = D': (D' - lumen) / (lumen + wall), by hand"
        )
        torque = float(tm.torque_breakdown_Nm(alpha, 1.0, tissue, g)["wound"])
        if eps > 0:
            assert num < 0 and torque == 0.0, "lumen wider than D': no wound-section torque"
        else:
            assert num > 0 and torque > 0.0, "lumen narrower than D': the spiral presses in"


def test_weight_friction_and_mass_by_hand():
    """mu m g (D/2 + d_w) with the mass from a quadrature of the capsule's outer volume."""
    d, length, d_mag, l_mag = 11e-3, 26e-3, 6e-3, 10e-3
    r = d / 2

    def area(z: float) -> float:  # cross-section at z along the axis, hemispherical ends
        if z < r:
            return math.pi * (r * r - (r - z) ** 2)
        if z > length - r:
            return math.pi * (r * r - (z - length + r) ** 2)
        return math.pi * r * r

    volume, _ = integrate.quad(area, 0.0, length, points=[r, length - r], epsabs=1e-16)
    magnet = math.pi / 4 * d_mag**2 * l_mag
    mass = 7500.0 * magnet + 1300.0 * (volume - magnet)
    assert float(cap.mass_from_parts_kg(d, length, magnet)) == pytest.approx(mass, rel=1e-9), (
        "capsule mass from its parts against a quadrature of its outer volume, 1e-9"
    )
    design = load_design()
    model = prepare(build_model(design))
    assert model.capsule.mass_kg == pytest.approx(mass, rel=1e-9), "the built-in capsule's mass"
    by_hand = 0.28 * mass * 9.80665 * (r + 1e-3)
    tissue = model.tissues[0]
    assert float(ph.weight_friction_Nm(model.constants, tissue)) == pytest.approx(
        by_hand, rel=1e-12
    ), "mu m g (D/2 + d_w) for sample 2 (mu 0.28), by hand"
    res = ph.required_torques_Nm(0.2, 1.0, model.constants, model.tissues, model.requirements)
    stretch = tm.resistive_torque_Nm(0.2, 1.0, tissue, ph.contact_geometry(model.constants))
    assert float(res[0][0]) == pytest.approx(float(stretch) + by_hand, rel=1e-12), (
        "resistive torque = the paper's tissue model + the weight friction (added once)"
    )


def test_measured_mass_overrides_the_estimate():
    model = prepare(build_model(load_design(None, ["capsule.mass_g=5"])))
    assert model.constants.mass_kg == pytest.approx(5e-3, rel=1e-15), "capsule.mass_g in kg"


def test_the_new_users_capsule_is_not_safe():
    """evaluate: infeasible naming the engagement (both sets), no speed, tissue torque 0 but
    resistance from the capsule's weight."""
    ev = run_json(["evaluate", *_sets(SMALL)])
    assert ev["feasible"] is False and ev["engaged"] is False
    failed = {c["name"] for c in ev["checks"] if not c["ok"]}
    assert {"wall_strain[zhou2013-sample2]", "wall_strain[zhou2013-sample3]"} <= failed, failed
    keys = {c["key"] for c in ev["checks"] if c["name"].startswith("wall_strain")}
    assert keys == {"requirements.min_wall_strain"}, "the checks are keyed by the requirement"
    assert ev["speed_m_s"] == 0.0, "a spiral that does not grip does not screw forward"
    assert ev["resistive_torque_Nm"] == pytest.approx(ev["weight_friction_Nm"], rel=1e-12)
    assert ev["resistive_torque_Nm"] > 0, "resistance never 0 while the capsule lies on tissue"
    rc, out, _ = run(["evaluate", *_sets(SMALL)])
    assert rc == 0 and "NOT TOUCHED" in out and "no grip" in out


def test_optimiser_cannot_reach_a_grazing_design():
    """At the paper's lumen the angle that maximises the margin makes the spiral graze; the
    row holds the strain at the requirement instead."""
    model = build_model(load_design(None, ["requirements.min_wall_strain=0.03"]))
    res = optimize_design(model)
    assert res.status == "optimal"
    strains = res.evaluation.wall_strains
    assert min(strains) == pytest.approx(0.03, rel=1e-6), "the strain row binds at 0.03"
    assert any(b.name.startswith("wall_strain[") for b in res.binding_limits)


def test_infeasible_when_grip_and_speed_conflict():
    rc, out, _ = run(["optimize", *_sets(SMALL), *ONE_START])
    assert rc == 3 and "requirements.min_wall_strain binds" in out, out


@pytest.mark.slow
@pytest.mark.parametrize("objective", ["power", "copper_mass"])
def test_sizing_grips_every_tissue_set(objective, tmp_path):
    """A sizing of the small capsule in a 9.1 mm lumen: the sized design stretches every set's
    wall by at least the requirement and evaluates feasible.

    Every pair's turns free (was: turns and wire, the six keys): the subject is the grip rows
    inside a sizing, not the wire's neighbour search (test_coils_buildable.py and
    test_square_sizing.py size the wire); both sets' wall_strain rows bind at the optimum
    either way, for each objective (measured), at 1.1 s and 0.65 s of CPU instead of 2.7 s
    and 1.9 s."""
    out = tmp_path / "sized.toml"
    sets = [s for s in SMALL if "lumen" not in s] + [
        "tissue.lumen_diameter_mm=9.1",
        f"optimize.objective={objective}",
        # nominal rows: a 9.1 mm lumen leaves the small capsule no room for a tolerance box
        "tolerances.helical_angle_deg=0",
        "tolerances.spiral_wire_diameter_mm=0",
        "tolerances.lumen_diameter_mm=0",
    ]
    turns = [a for ax in "xyz" for a in ("--free", f"coils.{ax}.turns=100:800")]
    rc, text, err = run(["optimize", *turns, *_sets(sets), *ONE_START, "-o", str(out)])
    assert rc == 0, text + err
    ev = run_json(["evaluate", str(out)])
    assert ev["feasible"] is True and ev["engaged"] is True
    need = tm.DEFAULT_MIN_WALL_STRAIN
    assert min(ev["wall_strains"]) >= need * (1 - 1e-6), "every set's wall stretched >= 1.68 %"


def test_lumen_reaches_every_tissue_set():
    one = run_json(["torque"])
    two = run_json(["torque", "--set", "tissue.lumen_diameter_mm=10.5"])
    for a, b in zip([one, *one["worst_case"]], [two, *two["worst_case"]]):
        assert b["lumen_diameter_mm"] == pytest.approx(10.5, rel=1e-12)
        assert b["torque_mNm"][0] > a["torque_mNm"][0], f"{b['tissue']}: narrower lumen, more"
    model = build_model(load_design(None, ["tissue.lumen_diameter_mm=10.5"]))
    assert {t.lumen_diameter_m for t in model.tissues} == {10.5e-3}
    assert {t.friction_coefficient for t in model.tissues} == {0.28, 0.51}, (
        "material constants stay per tissue set"
    )


def test_uncertainty_samples_centre_on_the_patients_lumen():
    from optimize.uncertainty import TissueUncertainty, perturbed_tissues

    model = build_model(load_design(None, ["tissue.lumen_diameter_mm=10.5"]))
    unc = TissueUncertainty(lumen_diameter_sigma_m=0.3e-3)
    u = np.linspace(0.001, 0.999, 4001)[:, None]
    for arrays in perturbed_tissues(model.tissues, unc, u):
        assert np.median(arrays.lumen_diameter_m) == pytest.approx(10.5e-3, rel=1e-9), (
            "every set's samples centre on the design's lumen"
        )


@pytest.fixture(scope="module")
def builtin_evaluation() -> dict:
    """``spiralcap evaluate --json`` of the built-in design, run once for the module."""
    return run_json(["evaluate"])


def test_extrapolation_is_named(builtin_evaluation):
    inside = builtin_evaluation
    assert inside["extrapolations"] == [], "the built-in design lies in the paper's range"
    out = run_json(["evaluate", "--set", "capsule.spiral.helical_angle_deg=25"])
    names = {e["quantity"] for e in out["extrapolations"]}
    assert "helical_angle_rad" in names
    rc, text, _ = run(["evaluate", "--set", "capsule.spiral.helical_angle_deg=25"])
    assert rc == 0
    assert "EXTRAPOLATES" in text and "helical angle 25°" in text


def test_validation_spread_from_the_papers_numbers():
    """The four stated torques against the calibrated model (docs/torque-model.md section 4:
    -4.7 %, +4.3 %, +8.3 %, +23.6 %) and the rms log error they imply."""
    from torque_model.domain import validation_errors, validation_sigma_log

    errors = [round(p.relative_error, 3) for p in validation_errors()]
    assert errors == [-0.047, 0.043, 0.083, 0.236], "the paper's four points, 1e-3"
    by_hand = math.sqrt(sum(math.log(1 + e) ** 2 for e in errors) / 4)
    assert validation_sigma_log() == pytest.approx(by_hand, abs=2e-3)


def test_default_min_strain_includes_the_papers_least():
    """Issue 36 item 6: the default admits the paper's own lowest measured case, capsule No. 4
    (20 deg) in sample 3 (lumen 11.1 mm, wall 1 mm, Zhou 2013 section II), by either reading of
    D': this model's (the code's wall_strain, 1.6852 %) and the exact tube section's convex hull
    (D' = 11.3036 mm, docs/torque-model.md section 1: (11.3036 - 11.1) / 12.1 = 1.6826 %, the
    issue's 1.6825 %); and it is that case to three figures (rounded down), not lower."""
    from torque_model.domain import CALIBRATED

    ours = float(
        tm.wall_strain(math.radians(20.0), tm.preset("zhou2013-sample3"), tm.PAPER_CAPSULE)
    )
    hull = (11.3036 - 11.1) / (11.1 + 1.0)
    assert ours == pytest.approx(0.016852, abs=1e-6), "eq. 6 at D' = 11.3039 mm, 1e-6"
    need = KEYS["requirements.min_wall_strain"].default
    assert need == tm.DEFAULT_MIN_WALL_STRAIN == CALIBRATED["wall_strain"][0]
    assert need <= min(ours, hull), "the paper's lowest measured case grips by both readings"
    assert min(ours, hull) - need < 1e-4, "the case to three figures, rounded down"
    # and the CLI agrees: the paper's capsule No. 4 in sample 3 meets the default grip row
    sets = ["capsule.spiral.helical_angle_deg=20", "tissue.preset=zhou2013-sample3"]
    sets += NO_TOLERANCE_SETS  # the paper's capsule as measured, not a toleranced design
    ev = run_json(["evaluate", *_sets([*sets, "tissue.worst_case_presets=[]"])])
    grip = [c for c in ev["checks"] if c["name"].startswith("wall_strain")]
    assert grip and all(c["ok"] for c in grip), grip


@pytest.mark.parametrize(
    "arg", ["requirements.min_wall_strain=0", "capsule.mass_g=0", "capsule.mass_g=-3"]
)
def test_bad_input(arg):
    rc, out, err = run(["evaluate", "--set", arg])
    assert rc == 2 and len(err.strip().splitlines()) == 1 and arg.split("=")[0] in err
    assert out == ""


def test_evaluate_json_carries_strains(builtin_evaluation):
    ev = builtin_evaluation
    assert len(ev["wall_strains"]) == len(ev["tissue_names"]) == 2
    assert json.dumps(ev)  # serialisable


def test_optimum_on_a_calibrated_edge_is_flagged():
    """The built-in optimum holds sample 3's strain at 1.68 %, the paper's least (to three
    figures), and says so."""
    rc, out, _ = run(["optimize"])
    assert rc == 0 and "calibrated edge of: wall strain 1.68 %" in out, out


def test_no_grip_probability_against_sampling():
    """P(no grip) in closed form against the share of sampled lumens as wide as D' (the same
    truncated normal, 2e5 samples: within 4 binomial standard deviations)."""
    from optimize.uncertainty import (
        TissueUncertainty,
        margin_problem,
        no_grip_probability,
        perturbed_tissues,
    )

    model = prepare(build_model(load_design(None, ["tissue.lumen_diameter_mm=11.1"])))
    unc = TissueUncertainty(lumen_diameter_sigma_m=0.5e-3)
    problem = margin_problem(model, unc)
    exact = no_grip_probability(problem)
    rng = np.random.default_rng(1)
    u = rng.random((200_000, 1))
    strains = [
        tm.wall_strain(problem.helical_angle_rad, t, ph.contact_geometry(model.constants))
        for t in perturbed_tissues(model.tissues, unc, u)
    ]
    sampled = float(np.mean(np.min(np.stack(strains), axis=0) <= 0))
    sd = math.sqrt(exact * (1 - exact) / u.shape[0])
    assert 0.1 < exact < 0.9, "a case where the grip is in doubt"
    assert abs(sampled - exact) <= 4 * sd, "closed form vs sampling, 4 sigma"


def test_infeasible_text_names_each_tissue_row() -> None:
    """Two tissue sets short of the same key: one line each, the set named (not twice the same
    line)."""
    rc, out, _ = run(["optimize", "--set", "tissue.lumen_diameter_mm=100", *ONE_START])
    assert rc == 3
    lines = [ln for ln in out.splitlines() if "requirements.min_wall_strain (" in ln]
    assert len(lines) == 2 and len(set(lines)) == 2, lines
    assert any("zhou2013-sample2" in ln for ln in lines) and any("sample3" in ln for ln in lines)
