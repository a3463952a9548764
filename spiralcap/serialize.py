"""Result objects -> plain dicts with units in every key: the one source for JSON and the report."""

from __future__ import annotations

import math
from typing import Any

_AXES = ("x", "y", "z")


def _checks(checks) -> list[dict[str, Any]]:
    return [
        {
            "name": c.name,
            "key": c.key,
            "unit": c.unit,
            "value": c.value,
            "allowed": c.allowed,
            "sense": c.sense,
            "ok": c.ok,
        }
        for c in checks
    ]


def evaluation_to_dict(ev) -> dict[str, Any]:
    """JSON-ready figures of an :class:`optimize.Evaluation`."""
    return {
        "helical_angle_deg": ev.helical_angle_deg,
        "frequency_hz": ev.frequency_hz,
        "field_amplitude_T": ev.field_amplitude_T,
        "field_limited_by": ev.field_limited_by,
        "workspace_field_factor": ev.workspace_factor,
        "current_amplitudes_A": dict(zip(_AXES, ev.current_amplitudes_A)),
        "magnetic_torque_Nm": ev.magnetic_torque_Nm,
        "resistive_torque_Nm": ev.resistive_torque_Nm,
        "thrust_torque_Nm": ev.thrust_torque_Nm,
        "required_torque_Nm": ev.required_torque_Nm,
        "worst_tissue": ev.worst_tissue,
        "margin_Nm": ev.margin_Nm,
        "safety_factor": ev.safety_factor,
        "lag_angle_deg": math.degrees(ev.lag_angle_rad),
        "step_out_frequency_hz": ev.step_out_frequency_hz,
        "step_out_beyond_search": ev.step_out_beyond_search,
        "max_frequency_hz": ev.max_frequency_hz,
        "max_frequency_limited_by": ev.max_frequency_limited_by,
        "max_frequency_beyond_search": ev.max_frequency_beyond_search,
        "speed_m_s": ev.speed_m_s,
        "spiral_turns": ev.spiral_turns,
        "feasible": ev.feasible,
        "checks": _checks(ev.checks),
    }


def optimization_to_dict(res) -> dict[str, Any]:
    """JSON-ready figures of an :class:`optimize.OptimizationResult`."""
    return {
        "status": res.status,
        "message": res.message,
        "objective": res.objective,
        "helical_angle_deg": res.helical_angle_deg,
        "frequency_hz": res.frequency_hz,
        "field_amplitude_T": res.field_amplitude_T,
        "margin_Nm": res.margin_Nm,
        "safety_factor": res.safety_factor,
        "current_amplitudes_A": dict(zip(_AXES, res.current_amplitudes_A)),
        "current_allocation": [
            {
                "heading": list(h),
                "amplitudes_A": dict(zip(_AXES, a)),
                "phases_deg": dict(zip(_AXES, (math.degrees(p) for p in ph))),
            }
            for h, (a, ph) in zip(res.headings, res.current_phases_rad)
        ],
        "speed_m_s": res.speed_m_s,
        "step_out_frequency_hz": res.step_out_frequency_hz,
        "binding_limits": [
            {
                "name": b.name,
                "key": b.key,
                "unit": b.unit,
                "value": b.value,
                "allowed": b.allowed,
                "sensitivity_per_unit": b.sensitivity,
                "gain_per_unit_relaxed": b.gain_per_unit_relaxed,
                "relaxing_means": "raising" if b.relax_sign > 0 else "lowering",
                "gain_unit": ("N·m/" if res.objective == "margin" else "1/") + b.unit,
            }
            for b in res.binding_limits
        ],
        "shortfalls": [
            {
                "name": s.name,
                "key": s.key,
                "unit": s.unit,
                "needed": s.needed,
                "best": s.best,
                "short_by": s.short_by,
            }
            for s in res.shortfalls
        ],
        "solver_status": res.solver_status,
        "iterations": res.iterations,
        "starts": res.starts,
        "solve_time_s": res.solve_time_s,
        "evaluation": evaluation_to_dict(res.evaluation),
    }
