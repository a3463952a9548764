"""Immutable results of the optimiser: the optimum, what binds, and what is out of reach.

Constraints are named by the optimiser's own row names (``current_x``, ``speed``,
``safety_factor[<tissue>]``, ``helical_angle_max``, ...); the application maps names to
design-file keys.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from optimize.evaluate import Evaluation
from optimize.views import Viewable


@dataclass(frozen=True)
class BindingLimit:
    """An active constraint at the optimum and what relaxing it would gain.

    ``sensitivity`` is d(objective)/d(allowed value) in the objective's unit (N·m for the margin,
    1 for the safety factor, W for the power, kg for the copper mass) per SI unit of the limit
    (A, V, W, K, T, m/s, turn, rad, Hz). ``relax_sign`` is +1 where relaxing means raising the
    value (a current limit, an upper bound) and -1 where it means lowering it (a minimum speed, a
    lower bound); ``objective_sense`` +1 for an objective maximised, -1 for one minimised, so
    :attr:`gain_per_unit_relaxed` is the improvement relaxing by one unit buys (>= 0).
    """

    name: str
    unit: str
    value: float
    allowed: float
    sensitivity: float
    relax_sign: float = 1.0
    objective_sense: float = 1.0

    @property
    def gain_per_unit_relaxed(self) -> float:
        """Objective improvement per SI unit of relaxation."""
        return self.sensitivity * self.relax_sign * self.objective_sense


@dataclass(frozen=True)
class Shortfall:
    """A requirement no design inside the limits can meet, and the closest it gets."""

    name: str
    unit: str
    needed: float
    best: float

    @property
    def short_by(self) -> float:
        """|needed - best| (in ``unit``): how far the closest design stays from the need (a
        minimum reached from below, or a maximum such as a step-out probability from above)."""
        return abs(self.needed - self.best)


@dataclass(frozen=True)
class OptimizationResult(Viewable):
    """Result of :func:`optimize.optimize_design` (SI inside; names carry units).

    ``status`` is 'optimal' or 'infeasible'. ``evaluation`` is :func:`optimize.evaluate` at the
    optimum, so the two always report the same margin and limit values. ``objective_value`` is
    the objective in its unit; ``field_is_set`` says the optimum's field is below the largest the
    limits allow (objectives ``power`` and ``copper_mass``), so a saved design must carry it.
    ``solution_x`` / ``solution_lam_g``: the raw optimum, a warm start for a neighbouring solve.
    """

    _view_kind: ClassVar[str] = "optimization"

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
    objective_value: float = float("nan")
    field_is_set: bool = False
    hardware: Any = None
    solution_x: Any = field(default=None, compare=False, repr=False)
    solution_lam_g: Any = field(default=None, compare=False, repr=False)
    #: How the tissue scenarios were solved and checked (:class:`optimize.active_set.
    #: ScenarioSolve`); None without scenarios.
    scenario_solve: Any = field(default=None, compare=False, repr=False)

    @property
    def helical_angle_deg(self) -> float:
        """Optimal helical angle, degrees."""
        return float(np.degrees(self.helical_angle_rad))

    @property
    def feasible(self) -> bool:
        """True when status is 'optimal'."""
        return self.status == "optimal"


@dataclass(frozen=True)
class HardwareResult:
    """What a sizing run chose: the continuous relaxation and the discrete design (SI, by name).

    ``relaxed`` / ``relaxed_objective``: the continuous optimum (turns and wires not yet
    standard) — a bound on what any discrete design can reach; ``discrete`` /
    ``discrete_objective``: the best buildable neighbour (whole turns, standard wire),
    re-optimised over the operating point. ``candidates`` tried, ``feasible`` among them,
    ``outer_iterations`` of the frozen factors (docs/optimisation.md).
    """

    relaxed: dict[str, float]
    relaxed_objective: float
    discrete: dict[str, float]
    discrete_objective: float
    candidates: int
    feasible: int
    outer_iterations: int

    @property
    def rounding_cost(self) -> float:
        """|relaxed − discrete| objective: what whole turns and standard wire cost."""
        return abs(self.relaxed_objective - self.discrete_objective)
