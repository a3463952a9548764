"""Design -> tissue parameter sets: the chosen preset with its overrides, then the worst cases."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import torque_model
from torque_model import TissueParameters

#: tissue.* override keys (design units) -> TissueParameters field and factor to SI.
_OVERRIDES: dict[str, tuple[str, float]] = {
    "E1_kPa": ("E1_Pa", 1e3),
    "E2_kPa": ("E2_Pa", 1e3),
    "E3_kPa": ("E3_Pa", 1e3),
    "eta1_kPa_s": ("eta1_Pa_s", 1e3),
    "eta2_kPa_s": ("eta2_Pa_s", 1e3),
    "lumen_diameter_mm": ("lumen_diameter_m", 1e-3),
    "wall_thickness_mm": ("wall_thickness_m", 1e-3),
    "friction_coefficient": ("friction_coefficient", 1.0),
}


def build_tissues(design: Mapping[str, Any]) -> list[TissueParameters]:
    """The tissue sets a design asks for, in SI.

    Parameters
    ----------
    design : Mapping[str, Any]
        A validated design (``spiralcap.design.Design``): ``tissue.preset``, the optional
        ``tissue.E1_kPa`` ... ``tissue.friction_coefficient`` overrides, and
        ``tissue.worst_case_presets``.

    Returns
    -------
    list of TissueParameters
        First the preset with every explicit ``tissue.*`` override applied (named after the
        preset, with the overridden keys listed), then one unmodified preset for each name in
        ``tissue.worst_case_presets``.
    """
    base_name = design.get("tissue.preset", "zhou2013-sample2")
    base = torque_model.preset(base_name)
    changes: dict[str, float] = {}
    given: list[str] = []
    for key, (field, factor) in _OVERRIDES.items():
        value = design.get(f"tissue.{key}")
        if value is not None:
            changes[field] = float(value) * factor
            given.append(key)
    if given:
        base = base.replace(name=f"{base_name} + tissue.{{{', '.join(given)}}}", **changes)
    tissues = [base]
    for name in design.get("tissue.worst_case_presets", []) or []:
        tissues.append(torque_model.preset(name))
    return tissues
