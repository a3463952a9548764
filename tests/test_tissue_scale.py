"""Issue 20.4: ``tissue.scale`` multiplies the resistive torque of every tissue set the design
is checked against -- the preset (with overrides) and every worst-case preset alike.

Independent check: Zhou 2013's torque is the contact factor times the theta-integral of the
relaxation modulus, and the modulus is linear in (E1, E2, E3) with the exponents holding only
E/eta ratios, so scaling all five by k scales the torque by k exactly (to rounding, 1e-9).
"""

from __future__ import annotations

import json

import pytest
from cli_outcome import run

from optimize import physics as ph
from optimize.system import prepare
from spiralcap.assemble import build_model
from spiralcap.design import load_design


def _evaluate(*sets: str) -> dict:
    argv = ["evaluate", "--json"]
    for s in sets:
        argv += ["--set", s]
    rc, out, err = run(argv)
    assert rc == 0, err
    return json.loads(out)


def test_cli_resistive_torque_scales_by_tissue_scale():
    one = _evaluate("tissue.scale=1")
    more = _evaluate("tissue.scale=1.5")
    assert (one["helical_angle_deg"], one["frequency_hz"]) == (
        more["helical_angle_deg"],
        more["frequency_hz"],
    ), "same operating point"
    weight = one["weight_friction_Nm"]
    assert more["weight_friction_Nm"] == pytest.approx(weight, rel=1e-12), (
        "the friction of the capsule's weight is not a tissue stiffness"
    )
    assert more["resistive_torque_Nm"] - weight == pytest.approx(
        1.5 * (one["resistive_torque_Nm"] - weight), rel=1e-9
    ), "the tissue model's part of the resistive torque scales with tissue.scale (1e-9)"
    assert more["thrust_torque_Nm"] == pytest.approx(one["thrust_torque_Nm"], rel=1e-12), (
        "the screw's thrust torque (axial load, friction) is not a tissue stiffness"
    )


@pytest.mark.parametrize("worst", [["zhou2013-sample3"], ["zhou2013-sample3", "zhou2013-sample2"]])
def test_every_tissue_set_is_scaled_worst_case_presets_too(worst):
    """Each set's resistive torque at the same (alpha, f) is 1.5 x that at scale 1 (1e-9)."""
    names = json.dumps(worst)
    models = [
        prepare(
            build_model(
                load_design(None, [f"tissue.worst_case_presets={names}", f"tissue.scale={k}"])
            )
        )
        for k in (1.0, 1.5)
    ]
    assert len(models[0].tissues) == 1 + len(worst)
    alpha, f = 0.25, 1.7
    torques = [
        [r for r, _ in ph.required_torques_Nm(alpha, f, m.constants, m.tissues, m.requirements)]
        for m in models
    ]
    for base, scaled, tissue in zip(torques[0], torques[1], models[1].tissues):
        weight = float(ph.weight_friction_Nm(models[1].constants, tissue))
        assert float(scaled) - weight == pytest.approx(1.5 * (float(base) - weight), rel=1e-9), (
            f"{tissue.name}: resistive torque x 1.5 (linear in the moduli, Zhou 2013 eq. 2-8)"
        )
        assert "tissue.scale 1.5" in tissue.name, "the set says it is scaled"


def test_tissue_scale_out_of_range_is_refused():
    rc, _, err = run(["evaluate", "--set", "tissue.scale=0"])
    assert rc == 2 and "tissue.scale" in err and len(err.strip().splitlines()) == 1
