"""Immutable results of the optimiser: the optimum, what binds, and what is out of reach.

Constraints are named by the optimiser's own row names (``current_x``, ``speed``,
``safety_factor[<tissue>]``, ``helical_angle_max``, ...); the application maps names to
design-file keys.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

from optimize.evaluate import Evaluation
from optimize.views import Viewable
from spiralcap.core.constants import to_unit


@dataclass(frozen=True)
class BindingLimit:
    """An active constraint at the optimum and what relaxing it would gain.

    ``sensitivity`` is d(objective)/d(allowed value) in the objective's unit (N·m for the margin,
    1 for the safety factor, W for the power, kg for the copper mass) per SI unit of the limit
    (A, V, W, K, T, m/s, turn, rad, Hz). ``relax_sign`` is +1 where relaxing means raising the
    value (a current limit, an upper bound) and -1 where it means lowering it (a minimum speed, a
    lower bound); ``objective_sense`` +1 for an objective maximised, -1 for one minimised, so
    :attr:`gain_per_unit_relaxed` is the improvement relaxing by one unit buys (>= 0).

    Attributes
    ----------
    name : str
        Row name of the constraint.
    unit : str
        Unit symbol of ``value`` and ``allowed`` (SI).
    value : float
        The constrained quantity at the optimum, in the unit ``unit`` names.
    allowed : float
        Its bound, in the unit ``unit`` names.
    sensitivity : float
        d(objective)/d(allowed), in the objective's unit (N·m, W, kg; dimensionless for the
        safety factor) per unit of ``unit``.
    relax_sign : float
        +1 or -1, dimensionless: the direction that relaxes the constraint.
    objective_sense : float
        +1 (maximised) or -1 (minimised), dimensionless.
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
        """Objective improvement per SI unit of relaxation, in the objective's unit (N·m, W, kg;
        dimensionless for the safety factor) per unit of the limit (``unit``)."""
        return self.sensitivity * self.relax_sign * self.objective_sense


@dataclass(frozen=True)
class Shortfall:
    """A requirement no design inside the limits can meet, and the closest it gets.

    Attributes
    ----------
    name : str
        Row name of the requirement.
    unit : str
        Unit symbol of ``needed`` and ``best`` (SI).
    needed : float
        What the requirement asks, in the unit ``unit`` names.
    best : float
        The closest any design inside the limits gets, in the unit ``unit`` names.
    """

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

    Attributes
    ----------
    status : str
        ``"optimal"`` or ``"infeasible"``.
    objective : str
        Name of the objective.
    helical_angle_rad : float
        Optimal helical angle, rad.
    frequency_hz : float
        Optimal rotation frequency, Hz.
    field_amplitude_T : float
        Centre field amplitude at the optimum, T.
    margin_Nm : float
        Torque margin, N·m.
    safety_factor : float
        Available / required torque, dimensionless.
    current_amplitudes_A : tuple of float
        Worst-heading current amplitude of each pair, A.
    current_phases_rad : tuple
        Per heading, the centre allocation: the three current amplitudes (A) and phases (rad).
    headings : tuple of tuple of float
        The unit headings, dimensionless.
    speed_m_s : float
        Forward speed, m/s.
    step_out_frequency_hz : float
        Step-out frequency at the optimum's field, Hz.
    binding_limits : tuple of BindingLimit
        The active constraints.
    shortfalls : tuple of Shortfall
        Requirements out of reach (infeasible only).
    solver_status : str
        IPOPT's return status.
    iterations : int
        IPOPT iterations over every start tried, count.
    starts : int
        Number of starting points solved.
    solve_time_s : float
        Wall time of the solve, s.
    evaluation : Evaluation
        :func:`optimize.evaluate` at the optimum.
    message : str
        One line on the outcome.
    objective_value : float
        The objective, in its unit (N·m, W, kg; dimensionless for the safety factor).
    field_is_set : bool
        Flag: the optimum's field is below the largest the limits allow.
    hardware : HardwareResult or None
        The sizing outcome, when hardware was free.
    solution_x : dict of str to float or None
        The raw optimum by variable name, in the unit each name carries (``helical_angle_rad``,
        ``frequency_hz``, ``field_T``, ``t_value`` in the objective's unit), a warm start.
    solution_lam_g : ndarray or None
        Its row multipliers, dimensionless (scaled rows), a warm start.
    scenario_solve : ScenarioSolve or None
        How the tissue scenarios were solved and checked.
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
        """Optimal helical angle, deg."""
        return float(to_unit(self.helical_angle_rad, "deg"))

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

    Attributes
    ----------
    relaxed : dict of str to float
        Continuous optimum of the free hardware, by name, the unit in each name.
    relaxed_objective : float
        Its objective, in the objective's unit (N·m, W, kg; dimensionless for the safety
        factor).
    discrete : dict of str to float
        The best buildable neighbour, by name, the unit in each name.
    discrete_objective : float
        Its objective, in the objective's unit (N·m, W, kg; dimensionless for the safety
        factor).
    candidates : int
        Number of neighbours tried.
    feasible : int
        Number of those that were feasible.
    outer_iterations : int
        Number of outer iterations of the frozen factors.
    settled : bool
        Flag: the frozen factors settled within their tolerances (else the relaxed numbers are
        those of the last round, its rows a little off their fixed point; every neighbour is
        still checked exactly).
    copper_declined : dict or None
        Where a least-power sizing gave up copper that bought too little power
        (:func:`optimize.discrete.leaner`): the least-power design's ``copper_kg`` (kg) and
        ``objective`` (W), and ``hardware`` (by name, the unit in each name); None otherwise.
    """

    relaxed: dict[str, float]
    relaxed_objective: float
    discrete: dict[str, float]
    discrete_objective: float
    candidates: int
    feasible: int
    outer_iterations: int
    settled: bool = True
    copper_declined: dict | None = None

    @property
    def rounding_cost(self) -> float:
        """|relaxed − discrete| objective: what whole turns and standard wire cost, in the
        objective's unit (N·m, W, kg; dimensionless for the safety factor)."""
        return abs(self.relaxed_objective - self.discrete_objective)
