"""Parameter sets (Zhou 2013 Tables I-II), TissueParameters, and design -> tissue assembly."""

from __future__ import annotations

import pytest

import torque_model as tm
from spiralcap.core.errors import InputError
from spiralcap.design import load_design
from torque_model.parameters import zhou2013


def test_presets_are_published_tables_times_factor() -> None:
    k = zhou2013.CALIBRATION_FACTOR
    for name, table in (
        ("zhou2013-sample2", zhou2013.SAMPLE2),
        ("zhou2013-sample3", zhou2013.SAMPLE3),
    ):
        t = tm.preset(name)
        assert t.name == name
        assert t.E1_Pa == pytest.approx(table["E1_kPa"] * 1e3 * k, rel=1e-12), (
            f"{name}: E1 = Table value (kPa) x k (docs/torque-model.md section 3)"
        )
        assert t.eta2_Pa_s == pytest.approx(table["eta2_kPa_s"] * 1e3 * k, rel=1e-12)
        assert t.lumen_diameter_m == pytest.approx(table["lumen_diameter_mm"] * 1e-3)
        assert t.friction_coefficient == table["friction_coefficient"], "mu as published"


def test_published_values() -> None:
    assert zhou2013.SAMPLE2["E2_kPa"] == 18.64 and zhou2013.SAMPLE2["eta1_kPa_s"] == 43.51, (
        "Zhou 2013 Table I"
    )
    assert zhou2013.SAMPLE3["E1_kPa"] == 0.0348 and zhou2013.SAMPLE3["eta2_kPa_s"] == 0.2489, (
        "Zhou 2013 Table II"
    )
    assert zhou2013.SAMPLE2["friction_coefficient"] == 0.28, "section II-C: mu = 0.28"
    assert zhou2013.SAMPLE3["lumen_diameter_mm"] == 11.1, "section II-B: 11.1 mm"


def test_unknown_missing_and_bad_keys_rejected() -> None:
    with pytest.raises(InputError, match="E4_kPa"):
        zhou2013.check_parameter_set({**zhou2013.SAMPLE2, "E4_kPa": 1.0}, "test")
    missing = dict(zhou2013.SAMPLE2)
    del missing["eta1_kPa_s"]
    with pytest.raises(InputError, match="eta1_kPa_s"):
        zhou2013.check_parameter_set(missing, "test")
    with pytest.raises(InputError, match="E1_kPa"):
        zhou2013.check_parameter_set({**zhou2013.SAMPLE2, "E1_kPa": -1.0}, "test")
    with pytest.raises(InputError, match=r"tissue\.preset"):
        tm.preset("zhou2013-sample9")


def test_tissue_parameters_validate() -> None:
    t = tm.preset("zhou2013-sample2")
    assert t.replace(E1_Pa=0.0).E1_Pa == 0.0, "a zero spring is allowed (schema: E >= 0)"
    with pytest.raises(InputError, match="eta1_Pa_s"):
        t.replace(eta1_Pa_s=0.0)
    with pytest.raises(InputError, match="lumen_diameter_m"):
        t.replace(lumen_diameter_m=float("nan"))
    assert tm.TissueParameters.from_design_table(t.as_design_table(), t.name) == t, (
        "design-unit table round trip"
    )


def test_build_tissues_default_overrides_and_worst_cases() -> None:
    from spiralcap.assemble.tissue import build_tissues

    primary, *others = build_tissues(load_design())
    assert primary == tm.preset("zhou2013-sample2"), "default design: the sample-2 preset"
    assert others == [tm.preset("zhou2013-sample3")], "default worst case: also sample 3"
    design = load_design(
        overrides=[
            "tissue.preset=zhou2013-sample3",
            "tissue.E1_kPa=12.5",
            "tissue.eta2_kPa_s=3",
            "tissue.lumen_diameter_mm=10.5",
            "tissue.wall_thickness_mm=1.2",
            "tissue.friction_coefficient=0.4",
            "tissue.E2_kPa=0",
            "tissue.E3_kPa=7",
            "tissue.eta1_kPa_s=100",
            'tissue.worst_case_presets=["zhou2013-sample2", "zhou2013-sample3"]',
        ]
    )
    first, *rest = build_tissues(design)
    assert (first.E1_Pa, first.E2_Pa, first.E3_Pa) == (12.5e3, 0.0, 7e3), "kPa -> Pa"
    assert (first.eta1_Pa_s, first.eta2_Pa_s) == (100e3, 3e3), "kPa·s -> Pa·s"
    assert first.lumen_diameter_m == pytest.approx(
        10.5e-3
    ) and first.wall_thickness_m == pytest.approx(1.2e-3), "mm -> m"
    assert first.friction_coefficient == 0.4
    assert first.name.startswith("zhou2013-sample3"), "named after its preset"
    assert [t.name for t in rest] == ["zhou2013-sample2", "zhou2013-sample3"]
