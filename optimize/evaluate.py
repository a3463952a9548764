"""A design at one operating point: the field the coils can make, the torques, the margin.

The coils are driven at the largest rotating-field amplitude every limit allows at the
operating frequency, for the worst heading; the margin is the weakest synchronous torque over
the workspace minus the largest required torque (resistive + thrust) over the tissue sets.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from optimize import physics as ph
from optimize._roots import brentq
from optimize.system import DesignModel, prepare

#: Relative tolerance with which requirements are judged met (an optimum sits on its bounds).
FEASIBILITY_RTOL = 1e-6


@dataclass(frozen=True)
class Check:
    """One requirement or limit: ``value`` against ``allowed`` (``sense`` '<=' or '>=')."""

    name: str
    key: str
    unit: str
    value: float
    allowed: float
    sense: str
    ok: bool


@dataclass(frozen=True)
class Evaluation:
    """Immutable result of :func:`evaluate` (SI units; names say the unit)."""

    helical_angle_rad: float
    frequency_hz: float
    field_amplitude_T: float
    field_limited_by: str
    workspace_factor: float
    current_amplitudes_A: tuple[float, float, float]
    magnetic_torque_Nm: float
    resistive_torque_Nm: float
    thrust_torque_Nm: float
    required_torque_Nm: float
    worst_tissue: str
    margin_Nm: float
    safety_factor: float
    lag_angle_rad: float
    step_out_frequency_hz: float
    speed_m_s: float
    spiral_turns: float
    checks: tuple[Check, ...]
    feasible: bool

    @property
    def helical_angle_deg(self) -> float:
        """Helical angle in degrees."""
        return float(np.degrees(self.helical_angle_rad))

    def failed(self) -> list[Check]:
        """The requirements and limits that do not hold."""
        return [c for c in self.checks if not c.ok]


def _three(values: Any) -> tuple[float, float, float]:
    """The x, y, z values of a length-3 array as floats."""
    x, y, z = (float(v) for v in values)
    return x, y, z


def worst_required(model: DesignModel, alpha, f):
    """Worst tissue's (resistive, thrust, total, index) at (alpha, f); broadcasts over arrays."""
    model = prepare(model)
    c = model.constants
    pairs = ph.required_torques_Nm(alpha, f, c, model.tissues, model.requirements)
    totals = np.stack([np.asarray(r + t, dtype=float) for r, t in pairs])
    worst = np.argmax(totals, axis=0)
    res = np.choose(worst, [np.asarray(r, dtype=float) for r, _ in pairs])
    thr = np.choose(worst, [np.asarray(t, dtype=float) for _, t in pairs])
    return res, thr, np.max(totals, axis=0), worst


def margin_grid(model: DesignModel, alpha_rad, frequency_hz) -> dict[str, np.ndarray]:
    """Margin, safety factor, speed and feasibility on broadcast arrays of (alpha, f).

    The vectorised core of :func:`evaluate` (same definitions), for sweeps and initial guesses.
    """
    model = prepare(model)
    c = model.constants
    alpha, f = np.broadcast_arrays(np.asarray(alpha_rad, float), np.asarray(frequency_hz, float))
    field, _, _ = ph.field_capacity_T(f, c, model.limits, model.ambient_temperature_C)
    avail = np.asarray(ph.available_torque_Nm(field, c), dtype=float)
    _, _, required, _ = worst_required(model, alpha, f)
    speed = np.asarray(ph.speed_m_s(alpha, f, c, model.requirements), dtype=float)
    turns = np.asarray(ph.spiral_turns(alpha, c), dtype=float)
    req = model.requirements
    ok = (
        (avail - required >= -FEASIBILITY_RTOL * required)
        & (speed >= req.min_speed_m_s * (1 - FEASIBILITY_RTOL))
        & (turns >= req.min_spiral_turns * (1 - FEASIBILITY_RTOL))
    )
    return {
        "margin_Nm": avail - required,
        "safety_factor": avail / required,
        "field_amplitude_T": field,
        "speed_m_s": speed,
        "spiral_turns": turns,
        "feasible": ok,
    }


def step_out_frequency_hz(
    model: DesignModel, alpha_rad: float, f_lo: float = 0.01, f_hi: float = 200.0
) -> float:
    """Lowest frequency at which the margin reaches zero at this helical angle (inf if none).

    The field the coils can make falls with frequency (inductive voltage, exposure) while the
    tissue torque rises, so beyond this frequency the magnet cannot keep synchronous.
    """
    model = prepare(model)
    grid = np.geomspace(f_lo, f_hi, 400)
    m = margin_grid(model, alpha_rad, grid)["margin_Nm"]
    if m[0] <= 0:
        return 0.0
    below = np.nonzero(m <= 0)[0]
    if below.size == 0:
        return float("inf")
    i = below[0]
    return float(
        brentq(
            lambda f: float(margin_grid(model, alpha_rad, f)["margin_Nm"]),
            grid[i - 1],
            grid[i],
            xtol=1e-10,
            rtol=1e-12,
        )
    )


def evaluate(
    model: DesignModel, helical_angle_rad: float | None = None, frequency_hz: float | None = None
) -> Evaluation:
    """Evaluate the design at its operating point (or at the given angle and frequency)."""
    model = prepare(model)
    c, req = model.constants, model.requirements
    alpha = (
        model.capsule.spiral.helical_angle_rad
        if helical_angle_rad is None
        else float(helical_angle_rad)
    )
    f = model.frequency_hz if frequency_hz is None else float(frequency_hz)
    field, caps, unit_terms = ph.field_capacity_T(f, c, model.limits, model.ambient_temperature_C)
    field = float(field)
    binding = unit_terms[int(np.argmin([float(x) for x in caps]))].name
    avail = float(ph.available_torque_Nm(field, c))
    res, thr, required, worst = (float(np.asarray(v)) for v in worst_required(model, alpha, f))
    margin = avail - required
    speed = float(ph.speed_m_s(alpha, f, c, req))
    turns = float(ph.spiral_turns(alpha, c))
    checks = _checks(model, f, field, margin, required, speed, turns)
    lag = float(np.arcsin(required / avail)) if 0 < required <= avail else float("nan")
    return Evaluation(
        helical_angle_rad=alpha,
        frequency_hz=f,
        field_amplitude_T=field,
        field_limited_by=binding,
        workspace_factor=c.workspace_factor,
        current_amplitudes_A=_three(field * c.current_per_tesla_A_per_T),
        magnetic_torque_Nm=avail,
        resistive_torque_Nm=res,
        thrust_torque_Nm=thr,
        required_torque_Nm=required,
        worst_tissue=model.tissues[int(worst)].name,
        margin_Nm=margin,
        safety_factor=avail / required,
        lag_angle_rad=lag,
        step_out_frequency_hz=step_out_frequency_hz(model, alpha),
        speed_m_s=speed,
        spiral_turns=turns,
        checks=tuple(checks),
        feasible=all(ch.ok for ch in checks),
    )


def _checks(
    model: DesignModel,
    f: float,
    field: float,
    margin: float,
    required: float,
    speed: float,
    turns: float,
) -> list[Check]:
    req, tol = model.requirements, FEASIBILITY_RTOL
    out = [
        Check("margin", "margin_Nm", "N·m", margin, 0.0, ">=", margin >= -tol * required),
        Check(
            "speed",
            "requirements.min_speed_mm_s",
            "m/s",
            speed,
            req.min_speed_m_s,
            ">=",
            speed >= req.min_speed_m_s * (1 - tol),
        ),
    ]
    if req.min_spiral_turns > 0:
        out.append(
            Check(
                "spiral_turns",
                "requirements.min_spiral_turns",
                "turns",
                turns,
                req.min_spiral_turns,
                ">=",
                turns >= req.min_spiral_turns * (1 - tol),
            )
        )
    for t in ph.limit_terms(f, field, model.constants, model.limits, model.ambient_temperature_C):
        value, allowed = float(t.value), float(t.allowed)
        out.append(Check(t.name, t.key, t.unit, value, allowed, "<=", value <= allowed * (1 + tol)))
    return out
