"""The design NLP: helical angle, rotation frequency and field amplitude for the largest margin.

Variables (scaled to O(1)): ``alpha = a·ALPHA_REF``, ``f = r·F_REF``, ``B0 = b·B_ref``, and the
epigraph variable ``t`` (margin / tau_ref, or the safety factor). The three coil current
amplitudes are exact linear functions of ``B0`` once the headings are fixed
(``I_k = B0 · max_n sqrt(1 - n_k²) / g_k``; the phases follow from each heading), so they are
carried as expressions with their own limits rather than as three more variables, which would only
add flat directions. Every expression comes from :mod:`optimize.physics`, the same functions
:func:`optimize.evaluate.evaluate` uses.

Constraints are written ``g(x) <= 0`` and normalised by their allowed value, so IPOPT's
multipliers convert to engineering sensitivities,
``d margin / d allowed = λ · tau_ref / allowed``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from optimize import physics as ph
from optimize.system import DesignModel

ALPHA_REF_rad = 0.1745329251994330  # 10 degrees
F_REF_hz = 1.0


@dataclass(frozen=True)
class ConstraintInfo:
    """What one row of g means: its name, design key, unit and how to read its multiplier."""

    name: str
    key: str
    unit: str
    kind: str  # "margin", "limit", "requirement"
    allowed: float  # allowed value (limits, requirements) in SI; 0 for margin rows
    sign: float  # +1: relaxing the key raises the allowed value; -1: it lowers the need


@dataclass(frozen=True)
class Scales:
    """Reference magnitudes that make the variables and the objective O(1)."""

    field_T: float
    torque_Nm: float


def expressions(
    x: Any, model: DesignModel, scales: Scales, *, relax: Any = None, objective: str | None = None
) -> tuple[Any, list[Any], list[ConstraintInfo]]:
    """Objective (to minimise) and constraints ``g <= 0`` for scaled variables ``x``.

    ``x`` is indexable with 4 entries (a, r, b, t): CasADi SX or floats. With ``relax`` (3 slack
    entries for speed, spiral turns and margin) the requirement rows are relaxed by the slacks and
    the objective becomes their sum: the phase that finds how far a requirement is out of reach.
    """
    c, req, lim = model.constants, model.requirements, model.limits
    alpha, f, field, t = x[0] * ALPHA_REF_rad, x[1] * F_REF_hz, x[2] * scales.field_T, x[3]
    avail = ph.available_torque_Nm(field, c)
    rows: list[Any] = []
    info: list[ConstraintInfo] = []
    objective = objective or model.bounds.objective
    for tissue, (res, thr) in zip(
        model.tissues, ph.required_torques_Nm(alpha, f, c, model.tissues, req)
    ):
        need = res + thr
        if relax is not None:
            rows.append((need - avail) / scales.torque_Nm - relax[2])
        elif objective == "ratio":
            rows.append((t * need - avail) / scales.torque_Nm)
        else:
            rows.append(t - (avail - need) / scales.torque_Nm)
        info.append(
            ConstraintInfo(f"margin[{tissue.name}]", "margin_Nm", "N·m", "margin", 0.0, 1.0)
        )
    for term in ph.limit_terms(f, field, c, lim, model.ambient_temperature_C):
        rows.append(term.value / term.allowed - 1.0)
        allowed = term.allowed if isinstance(term.allowed, float) else float("nan")
        info.append(ConstraintInfo(term.name, term.key, term.unit, "limit", allowed, 1.0))
    if req.min_speed_m_s > 0:
        slack = relax[0] if relax is not None else 0.0
        rows.append(1.0 - ph.speed_m_s(alpha, f, c, req) / req.min_speed_m_s - slack)
        info.append(
            ConstraintInfo(
                "speed",
                "requirements.min_speed_mm_s",
                "m/s",
                "requirement",
                req.min_speed_m_s,
                -1.0,
            )
        )
    if req.min_spiral_turns > 0:
        slack = relax[1] if relax is not None else 0.0
        rows.append(req.min_spiral_turns / ph.spiral_turns(alpha, c) - 1.0 - slack)
        info.append(
            ConstraintInfo(
                "spiral_turns",
                "requirements.min_spiral_turns",
                "turns",
                "requirement",
                req.min_spiral_turns,
                -1.0,
            )
        )
    if relax is not None:
        obj = relax[0] + relax[1] + relax[2]
    else:
        obj = -t
    return obj, rows, info


def variable_bounds(model: DesignModel, scales: Scales) -> tuple[list[float], list[float]]:
    """Box bounds of the scaled variables (a, r, b, t)."""
    b = model.bounds
    inf = float("inf")
    lo = [b.helical_angle_min_rad / ALPHA_REF_rad, b.frequency_min_hz / F_REF_hz, 0.0, -inf]
    hi = [b.helical_angle_max_rad / ALPHA_REF_rad, b.frequency_max_hz / F_REF_hz, inf, inf]
    return lo, hi


def exposure_allowed_T(model: DesignModel, frequency_hz: float) -> float:
    """The exposure level at ``frequency_hz`` (the only limit whose allowed value moves with f)."""
    if model.limits.field_exposure == "off":
        return float("nan")
    return float(ph.exposure_level_T(frequency_hz, model.limits.field_exposure))
