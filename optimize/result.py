"""Immutable results of the optimiser: the optimum, what binds, and what is out of reach."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from optimize.evaluate import Evaluation


@dataclass(frozen=True)
class BindingLimit:
    """An active constraint at the optimum and what relaxing it would gain.

    ``sensitivity`` is d(objective)/d(allowed value) in the objective's unit (N·m for the margin,
    1 for the safety factor) per SI unit of the limit (A, V, W, K, T, m/s, turn, rad, Hz).
    ``relax_sign`` is +1 where relaxing means raising the value (a current limit, an upper
    bound) and -1 where it means lowering it (a minimum speed, a lower bound), so
    :attr:`gain_per_unit_relaxed` is what relaxing by one unit buys (>= 0).
    """

    name: str
    key: str
    unit: str
    value: float
    allowed: float
    sensitivity: float
    relax_sign: float = 1.0

    @property
    def gain_per_unit_relaxed(self) -> float:
        """Objective gained per SI unit of relaxation."""
        return self.sensitivity * self.relax_sign


@dataclass(frozen=True)
class Shortfall:
    """A requirement no design inside the limits can meet, and the closest it gets."""

    name: str
    key: str
    unit: str
    needed: float
    best: float

    @property
    def short_by(self) -> float:
        """needed - best (in ``unit``)."""
        return self.needed - self.best


@dataclass(frozen=True)
class OptimizationResult:
    """Result of :func:`optimize.optimize_design` (SI inside; names carry units).

    ``status`` is 'optimal' or 'infeasible'. ``evaluation`` is :func:`optimize.evaluate` at the
    optimum, so the two always report the same margin and limit values.
    """

    status: str
    objective: str
    helical_angle_rad: float
    frequency_hz: float
    field_amplitude_T: float
    margin_Nm: float
    safety_factor: float
    current_amplitudes_A: tuple[float, float, float]
    current_phases_rad: tuple[tuple[tuple[float, float, float], tuple[float, float, float]], ...]
    headings: tuple[tuple[float, float, float], ...]
    speed_m_s: float
    step_out_frequency_hz: float
    binding_limits: tuple[BindingLimit, ...]
    shortfalls: tuple[Shortfall, ...]
    solver_status: str
    iterations: int
    starts: int
    solve_time_s: float
    evaluation: Evaluation
    message: str

    @property
    def helical_angle_deg(self) -> float:
        """Optimal helical angle, degrees."""
        return float(np.degrees(self.helical_angle_rad))

    @property
    def feasible(self) -> bool:
        """True when status is 'optimal'."""
        return self.status == "optimal"
