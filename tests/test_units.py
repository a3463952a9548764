"""The one table of units: every design key's SI name and factor, and the bounds every number has."""

from __future__ import annotations

import math

import pytest

from spiralcap.core.constants import design_unit, from_si
from spiralcap.design import load_design
from spiralcap.schema import KEYS, si_values, to_si


@pytest.mark.parametrize(
    "key, si_name, factor",
    [
        ("requirements.axial_load_mN", "axial_load_N", 1e-3),
        ("requirements.min_speed_mm_s", "min_speed_m_s", 1e-3),
        ("tissue.eta1_kPa_s", "eta1_Pa_s", 1e3),
        ("tissue.E2_kPa", "E2_Pa", 1e3),
        ("capsule.spiral.helical_angle_deg", "helical_angle_rad", math.pi / 180),
        ("tissue.lumen_diameter_mm", "lumen_diameter_m", 1e-3),
        ("coils.x.radius_m", "radius_m", 1.0),
        ("limits.coil_temperature_C", "coil_temperature_C", 1.0),
        ("coils.x.turns", "turns", 1.0),
    ],
)
def test_si_name_and_factor_from_the_suffix(key, si_name, factor):
    spec = KEYS[key]
    assert spec.si_name == si_name
    assert spec.si_factor == pytest.approx(factor, rel=1e-15), "SI prefixes (BIPM SI brochure)"


def test_new_keys_get_their_conversion_from_the_name():
    assert design_unit("coils.x.field_amplitude_mT") == ("_mT", "_T", 1e-3)
    assert design_unit("report.duration_min") == ("_min", "_s", 60.0)
    assert design_unit("a.b.helical_angle_deg")[2] == pytest.approx(math.pi / 180, rel=1e-16)
    assert design_unit("a.b.packing_factor") == ("", "", 1.0)


def test_every_numeric_key_has_a_physical_range():
    unbounded = [
        k for k, s in KEYS.items() if s.kind in (float, int) and (s.lo is None or s.hi is None)
    ]
    assert not unbounded, f"numeric keys without a finite range (use _between): {unbounded}"
    for k, s in KEYS.items():
        if s.kind is float and s.lo is not None:
            assert "range" in s.help or s.hi <= 1.0 or k.endswith("slip_efficiency"), (
                f"{k}: say why the range is what it is in the help text"
            )


def test_from_si_inverts_to_si_exactly_for_decimal_prefixes():
    for key in ("tissue.lumen_diameter_mm", "tissue.E1_kPa", "requirements.axial_load_mN"):
        for v in (10.9, 11.1, 42.8376, 0.28, 50.0):
            assert from_si(to_si(key, v), KEYS[key].si_factor) == v, f"{key} {v} round trip"


def test_tissue_overrides_follow_the_table():
    from spiralcap.assemble.tissue import build_tissues

    d = load_design(None, ["tissue.eta2_kPa_s=12.5", "tissue.lumen_diameter_mm=12"])
    t = build_tissues(d)[0]
    si = si_values(d, "tissue.")
    assert t.eta2_Pa_s == si["eta2_Pa_s"] == 12.5e3
    assert t.lumen_diameter_m == si["lumen_diameter_m"] == pytest.approx(12e-3, rel=1e-15)
