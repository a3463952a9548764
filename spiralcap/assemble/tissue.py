"""Design -> tissue parameter sets: the chosen preset with its overrides, then the worst cases."""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import torque_model
from spiralcap.core.constants import from_unit
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


#: The patient's anatomy: keys that apply to every tissue set the design is checked against.
ANATOMY_KEYS = ("lumen_diameter_mm", "wall_thickness_mm")


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
        First the preset with every explicit material override (``E1_kPa`` ... ``eta2_kPa_s``,
        ``friction_coefficient``) applied (named after the preset, with the overridden keys
        listed), then one preset for each name in ``tissue.worst_case_presets`` with its own
        material constants. The anatomy (``tissue.lumen_diameter_mm``,
        ``tissue.wall_thickness_mm``), when given, is the patient's: it applies to every set.
        Every set's moduli and viscosities are times ``tissue.scale`` (a deterministic
        multiplier on every resistive torque).
    """
    base_name = design.get("tissue.preset", "zhou2013-sample2")
    base = torque_model.preset(base_name)
    material: dict[str, float] = {}
    anatomy: dict[str, float] = {}
    given: list[str] = []
    for key, (field, factor) in _overrides().items():
        value = design.get(f"tissue.{key}")
        if value is None:
            continue
        if key in ANATOMY_KEYS:
            anatomy[field] = float(value) * factor
        else:
            material[field] = float(value) * factor
            given.append(key)
    if given:
        base = base.replace(name=f"{base_name} + tissue.{{{', '.join(given)}}}", **material)
    tissues = [base]
    for name in design.get("tissue.worst_case_presets", []) or []:
        tissues.append(torque_model.preset(name))
    if anatomy:  # the patient's lumen and wall, whichever material the set describes
        tissues = [t.replace(**anatomy) for t in tissues]
    scale = tissue_scale(design)
    if scale != 1.0:  # every set alike: the resistive torque is linear in the factor
        tissues = [t.scaled(scale, f"{t.name} × tissue.scale {scale:g}") for t in tissues]
    return tissues


def tissue_scale(design: Mapping[str, Any]) -> float:
    """The design's ``tissue.scale``, the factor on every tissue set's constants (1: not set).

    Parameters
    ----------
    design : mapping
        A validated design (``spiralcap.design.Design``).

    Returns
    -------
    float
        The factor, dimensionless.
    """
    return float(design.get("tissue.scale", 1.0))


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
        lumen_diameter_sigma_m=from_unit(
            float(design.get(_UNC + "lumen_diameter_sigma_mm", 0.0)), "mm"
        ),
        wall_thickness_sigma_m=from_unit(
            float(design.get(_UNC + "wall_thickness_sigma_mm", 0.0)), "mm"
        ),
        covariance_log=cov,
    )


#: Largest variance of a log-parameter a covariance may hold: the sigma keys stop at 2 (a factor
#: e^2 ~ 7 per standard deviation), so a fitted covariance is bounded the same way.
MAX_LOG_VARIANCE = 4.0
#: Smallest largest-variance a covariance must have: below a relative uncertainty of 1e-6 it is
#: no uncertainty at all (and subnormal numbers would leave it with no factor to sample).
MIN_LOG_VARIANCE = 1e-12


def _read_covariance(design: Mapping[str, Any], path: str) -> tuple[tuple[float, ...], ...]:
    """``tissue.fit.covariance_log`` of the file ``covariance_from`` names, read through the
    guarded reader of the design files and checked before any use.

    Raises
    ------
    InputError
        One line naming ``tissue.uncertainty.covariance_from`` and the file: unreadable (not a
        regular file, too large, not text, too deep, not TOML), no covariance, not 5 x 5
        numbers, not finite, not symmetric, not positive semi-definite, all zero, or a variance
        above :data:`MAX_LOG_VARIANCE`.
    """
    from pathlib import Path

    import numpy as np

    from spiralcap.core.errors import DataError, InputError
    from spiralcap.design import read_toml_file

    key = _UNC + "covariance_from"
    p = Path(path)
    resolve = getattr(design, "path_of", None)
    if resolve is not None:
        p = resolve(key) or p
    try:
        table = read_toml_file(p, "covariance file")
    except DataError as exc:
        why = str(exc).removeprefix(str(p)).lstrip(": ")  # the path is named once, as the value
        raise InputError(
            key, str(p), f"a readable TOML file from `spiralcap fit -o` ({why})"
        ) from None

    fit = table.get("tissue", {})
    fit = fit.get("fit", {}) if isinstance(fit, dict) else None
    raw = fit.get("covariance_log") if isinstance(fit, dict) else None
    problem = _entries_problem(raw) or _matrix_problem(np.asarray(raw, dtype=float))
    if problem is not None:
        raise InputError(key, str(p), problem)
    return tuple(tuple(float(x) for x in row) for row in np.asarray(raw, dtype=float))


def _entries_problem(raw: Any) -> str | None:
    """Why ``raw`` is not a 5 x 5 table of finite numbers (None: it is)."""
    if raw is None:
        return (
            "a file from `spiralcap fit -o` with tissue.fit.covariance_log (the fit writes it "
            "only when the data pin down a fitted parameter; try `fit --only scale`)"
        )
    ok = (
        isinstance(raw, list)
        and len(raw) == 5
        and all(isinstance(r, list) and len(r) == 5 for r in raw)
        and all(isinstance(x, (int, float)) and not isinstance(x, bool) for r in raw for x in r)
    )
    if not ok:
        return "tissue.fit.covariance_log must be 5 x 5 numbers (E1, E2, E3, eta1, eta2)"
    if not all(math.isfinite(float(x)) for r in raw for x in r):
        return "tissue.fit.covariance_log with finite entries (no inf, no nan)"
    return None


def _matrix_problem(cov: Any) -> str | None:
    """Why the 5 x 5 matrix ``cov`` is not a usable covariance of log-parameters (None: it is):
    variances in range, symmetric, positive semi-definite."""
    import numpy as np

    diag = np.diag(cov)
    if diag.min() < 0:
        return "a positive semi-definite tissue.fit.covariance_log (a negative variance on its diagonal)"
    if diag.max() > MAX_LOG_VARIANCE:
        return (
            f"tissue.fit.covariance_log with variances of ln(parameter) up to {MAX_LOG_VARIANCE:g} "
            f"(a standard deviation of 2, as the *_sigma_log keys; largest given "
            f"{diag.max():.3g})"
        )
    if diag.max() < MIN_LOG_VARIANCE:
        return (
            f"tissue.fit.covariance_log with at least one variance of {MIN_LOG_VARIANCE:g} or "
            f"more (a relative uncertainty of 1e-6; largest given {diag.max():.3g})"
        )
    # every entry is bounded by the diagonal (|c_ij| <= sqrt(c_ii c_jj) in a PSD matrix), so the
    # checks below work on numbers of order 1: no overflow, no LinAlgError
    bound = np.sqrt(np.outer(diag, diag))
    if np.any(np.abs(cov) > bound * (1 + 1e-9) + 1e-300):
        return (
            "a positive semi-definite tissue.fit.covariance_log (an off-diagonal entry exceeds "
            "sqrt(c_ii c_jj))"
        )
    if not np.allclose(cov, cov.T, rtol=1e-8, atol=1e-14 * float(diag.max())):
        return "a symmetric tissue.fit.covariance_log"
    lam = np.linalg.eigvalsh(0.5 * (cov + cov.T))
    if lam.min() < -1e-10 * float(lam.max()):
        return (
            "a positive semi-definite tissue.fit.covariance_log (smallest eigenvalue "
            f"{lam.min():.3g})"
        )
    return None
