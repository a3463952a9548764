"""The capsule reaches the torque model as one ContactGeometry; no product numbers as defaults."""

from __future__ import annotations

import dataclasses
import inspect
import math

import pytest

import capsule
import torque_model as tm
from spiralcap.core.errors import InputError
from spiralcap.design import load_design
from torque_model import geometry, identification, model

#: Parameters that describe the capsule: none may have a default value in a physics signature.
CAPSULE_PARAMETERS = {
    "body_diameter_m",
    "body_length_m",
    "wire_diameter_m",
    "wound_length_m",
    "starts",
    "geometry",
    "diameter_m",
    "length_m",
    "shell_thickness_m",
}


@pytest.mark.parametrize(
    "fn",
    [
        model.resistive_torque_Nm,
        model.torque_breakdown_Nm,
        model.contact_factors_m3,
        model.contact_factor_m3,
        geometry.equivalent_diameter_m,
        identification.identify,
        capsule.Body,
        capsule.Spiral,
        tm.ContactGeometry,
    ],
)
def test_no_capsule_defaults_in_physics_signatures(fn) -> None:
    defaults = {
        name: p.default
        for name, p in inspect.signature(fn).parameters.items()
        if name in CAPSULE_PARAMETERS and p.default is not inspect.Parameter.empty
    }
    assert not defaults, f"{fn.__qualname__}: capsule defaults {defaults} (the schema holds them)"


@pytest.mark.parametrize(
    ("field", "value", "key"),
    [
        ("body_diameter_m", 0.0, "body_diameter_m"),
        ("wound_length_m", math.nan, "wound_length_m"),
        ("starts", 0, "starts"),
        ("starts", 1.5, "starts"),
    ],
)
def test_contact_geometry_names_the_bad_value(field: str, value: float, key: str) -> None:
    with pytest.raises(InputError) as err:
        dataclasses.replace(tm.PAPER_CAPSULE, **{field: value})
    assert err.value.key == key


def test_built_in_design_is_the_papers_capsule() -> None:
    """The schema's default capsule is the paper's PillCam SB2 (Zhou et al. 2013, II-A)."""
    from spiralcap.commands.torque import geometry_from_design

    built = dataclasses.astuple(geometry_from_design(load_design()))
    paper = dataclasses.astuple(tm.PAPER_CAPSULE)
    assert built == pytest.approx(paper, rel=1e-15), (
        "11 x 26 mm, 1 mm wire over 15 mm, one start (Zhou 2013 II-A), rel 1e-15 after mm -> m"
    )
