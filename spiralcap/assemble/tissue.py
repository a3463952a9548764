"""Design -> tissue parameter sets: the chosen preset with its overrides, then the worst cases."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import torque_model
from torque_model import TissueParameters


def _overrides() -> dict[str, tuple[str, float]]:
    """tissue.* override keys (design units) -> TissueParameters field and factor to SI, from
    the schema's unit table: every numeric ``tissue.*`` key whose SI name is a field."""
    from dataclasses import fields

    from spiralcap.schema import KEYS, si_name, to_si

    names = {f.name for f in fields(TissueParameters)}
    return {
        key.removeprefix("tissue."): (si_name(key), to_si(key, 1.0))
        for key, spec in KEYS.items()
        if key.startswith("tissue.") and spec.kind is float and si_name(key) in names
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
    for key, (field, factor) in _overrides().items():
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
