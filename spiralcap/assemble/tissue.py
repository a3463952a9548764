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
        ``tissue.worst_case_presets``, and ``tissue.scale``.

    Returns
    -------
    list of TissueParameters
        First the preset with every explicit ``tissue.*`` override applied (named after the
        preset, with the overridden keys listed), then one unmodified preset for each name in
        ``tissue.worst_case_presets``; every set's moduli and viscosities times
        ``tissue.scale`` (a deterministic multiplier on every resistive torque).
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
    scale = float(design.get("tissue.scale", 1.0))
    if scale != 1.0:  # every set alike: the resistive torque is linear in the factor
        tissues = [t.scaled(scale, f"{t.name} × tissue.scale {scale:g}") for t in tissues]
    return tissues


# --- tissue uncertainty (issue 11) ------------------------------------------------------------

_UNC = "tissue.uncertainty."


def build_uncertainty(design: Mapping[str, Any]) -> Any:
    """The design's ``[tissue.uncertainty]`` table as :class:`optimize.uncertainty.TissueUncertainty`.

    ``covariance_from`` is read here (relative paths from the design file's folder): the file's
    ``tissue.fit.covariance_log`` (written by ``spiralcap fit -o``) must be a 5 x 5 symmetric
    positive semi-definite matrix.

    Raises
    ------
    InputError
        Naming ``tissue.uncertainty.covariance_from`` when the file is missing, has no
        covariance, or the covariance is not 5 x 5, finite, symmetric and PSD.
    """
    from optimize.uncertainty import SHORT, TissueUncertainty

    cov = None
    path = design.get(_UNC + "covariance_from")
    if path is not None:
        cov = _read_covariance(design, path)
    return TissueUncertainty(
        scale_sigma_log=float(design.get(_UNC + "scale_sigma_log", 0.0)),
        sigma_log=tuple(float(design.get(f"{_UNC}{p}_sigma_log", 0.0)) for p in SHORT),  # type: ignore[arg-type]
        friction_sigma_log=float(design.get(_UNC + "friction_sigma_log", 0.0)),
        lumen_diameter_sigma_m=float(design.get(_UNC + "lumen_diameter_sigma_mm", 0.0)) * 1e-3,
        wall_thickness_sigma_m=float(design.get(_UNC + "wall_thickness_sigma_mm", 0.0)) * 1e-3,
        covariance_log=cov,
    )


def _read_covariance(design: Mapping[str, Any], path: str) -> tuple[tuple[float, ...], ...]:
    import math
    from pathlib import Path

    import numpy as np

    from optimize.uncertainty import covariance_factor
    from spiralcap.errors import InputError

    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib

    key = _UNC + "covariance_from"
    p = Path(path)
    source = getattr(design, "source", "")
    if not p.is_absolute() and source and Path(source).is_file():
        p = Path(source).parent / p
    try:
        table = tomllib.loads(p.read_text(encoding="utf-8"))
    except OSError as exc:
        raise InputError(key, path, f"a readable file ({exc.strerror or exc})") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(key, path, f"a TOML file ({exc})") from None
    raw = table.get("tissue", {}).get("fit", {}).get("covariance_log")
    if raw is None:
        raise InputError(
            key,
            path,
            "a file from `spiralcap fit -o` with tissue.fit.covariance_log (the fit writes it "
            "only when it pins down all five parameters)",
        )
    ok = (
        isinstance(raw, list)
        and len(raw) == 5
        and all(isinstance(r, list) and len(r) == 5 for r in raw)
        and all(isinstance(x, (int, float)) and not isinstance(x, bool) for r in raw for x in r)
    )
    if not ok:
        raise InputError(
            key, path, "tissue.fit.covariance_log must be 5 x 5 numbers (E1, E2, E3, eta1, eta2)"
        )
    cov = np.asarray(raw, dtype=float)
    if not all(math.isfinite(x) for x in cov.ravel()):
        raise InputError(key, path, "a covariance with finite entries")
    try:
        covariance_factor(cov, key)
    except InputError as exc:
        raise InputError(key, path, f"{exc.allowed} ({exc.value})") from None
    return tuple(tuple(float(x) for x in row) for row in cov)
