"""Design over tissue scenarios: a CVaR objective and a step-out probability constraint.

Both are hooks of the one design NLP (:func:`optimize.problem.register_objective`,
:func:`optimize.problem.register_constraint`), so they are compiled, solved, warm-started and
diagnosed by the common path (:func:`optimize.optimize_design`): multipliers, binding limits,
and the relaxed problem that names an unreachable requirement.

``optimize.objective = "margin_p05"`` maximises the lower 5 % tail of the worst-case margin over
``S`` tissue scenarios drawn from the design's uncertainty (:mod:`optimize.uncertainty`,
scrambled Sobol' points, so the tail is sampled evenly). The 5th percentile itself
(value-at-risk) is a non-smooth, non-convex function of the scenario margins; its
Rockafellar-Uryasev (2000) CVaR bound is smooth in epigraph form and is what IPOPT maximises:

    CVaR_β(m) = max over η of  η − (1/(β S)) Σ_s u_s,   u_s >= η − m_s(x),  u_s >= 0,

with ``β = 0.05``; the epigraph variable ``t`` of the problem is ``η`` (at the optimum the
β-quantile, the in-sample p05, of the scenario margins) and CVaR <= p05, so the claim is
conservative. ``m_s`` is the worst over the design's tissue sets for scenario s (one ``u_s`` per
scenario, one row per set). The nominal sets keep their safety-factor rows (margin >= 0).

``requirements.max_stepout_probability = p`` adds, for any objective, the row
``stepout_probability``: ``CVaR_p(m) >= 0`` (Nemirovski & Shapiro 2006: the convex conservative
approximation of the chance constraint ``P(m < 0) <= p``), with its own ``η'`` and ``v_s``; its
allowed value is ``p`` itself, so its multiplier is d objective / d p, and its reported value is
the scenarios' step-out share.

Scenario data are parameters (``scenario.<set>.<field>``, one S-vector per tissue field and
set; ``scenario.beta``, ``scenario.max_stepout_probability``): only the counts are compiled in
(:class:`ScenarioStructure`), so another seed, another uncertainty or a sweep re-solves the same
compiled solver.

Scenario count: the empirical CDF at the 5th percentile has standard deviation
``sqrt(β(1 − β)/S)`` (binomial); ``S = 1024`` (a power of two: a balanced Sobol' block) keeps it
at 0.7 percentage points for pseudo-random scenarios and below that for Sobol' points, with 51
scenarios in the tail, while the NLP stays small (S + 4 variables). The quantile's own error is
that CDF error divided by the density at p05: where the margin's spread is large against its
p05 (a heavy lower tail), more scenarios are needed, and the out-of-sample check says so.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace
from typing import Any

import casadi as ca
import numpy as np

from optimize import physics as ph
from optimize import problem as pb
from optimize.nlp import Row
from optimize.system import DesignModel, prepare
from spiralcap.core.errors import InputError

BETA = 0.05
DEFAULT_SCENARIOS = 1024
#: The tissue fields a scenario perturbs (one parameter vector per field and tissue set).
FIELDS = (
    "E1_Pa",
    "E2_Pa",
    "E3_Pa",
    "eta1_Pa_s",
    "eta2_Pa_s",
    "lumen_diameter_m",
    "wall_thickness_m",
    "friction_coefficient",
)


@dataclass(frozen=True)
class ScenarioStructure:
    """What of the scenarios is compiled in: how many, for how many tissue sets, which rows.

    Attributes
    ----------
    count : int
        Number of scenarios compiled in.
    sets : int
        Number of nominal tissue sets.
    stepout_constraint : bool
        Flag: the step-out probability row is part of the problem.
    """

    count: int
    sets: int
    stepout_constraint: bool


@dataclass(frozen=True, eq=False)
class ScenarioSet:
    """Tissue scenarios of a design (``DesignModel.scenarios``), SI.

    ``tissues``: one :class:`optimize.uncertainty.TissueArrays` per nominal tissue set, each
    field an array of ``count`` scenarios; ``latent_u``: the latent uniforms they come from
    (count x d, to reproduce them); ``beta``: the tail of the CVaR objective;
    ``max_stepout_probability``: the chance constraint's ``p`` (None: no constraint).

    Attributes
    ----------
    tissues : tuple of TissueArrays
        Per nominal set, each tissue field an array of ``count`` scenarios, SI (Pa, Pa·s, m).
    latent_u : ndarray, shape (count, d)
        The latent uniforms in (0, 1), dimensionless.
    seed : int
        Seed of the scrambled Sobol' points.
    beta : float
        Tail fraction of the CVaR objective, dimensionless.
    max_stepout_probability : float or None
        The chance constraint's p, a probability (None: no constraint).
    index : ndarray of int or None
        For a working set, the indices of its scenarios in the whole set.
    total : int or None
        For a working set, the number of scenarios of the whole set.
    """

    tissues: tuple
    latent_u: np.ndarray
    seed: int
    beta: float = BETA
    max_stepout_probability: float | None = None
    #: A working set (:mod:`optimize.active_set`): which scenarios of the whole set these are,
    #: and how many the whole set has (the CVaR sums are normalised by it). None: the whole set.
    index: np.ndarray | None = None
    total: int | None = None

    @property
    def count(self) -> int:
        """Number of scenarios (of this set or working set), count."""
        return int(self.latent_u.shape[0])

    @property
    def whole(self) -> bool:
        """True for the whole scenario set, False for a working set of it."""
        return self.index is None

    def working(self, index: np.ndarray) -> ScenarioSet:
        """The working set of the scenarios ``index`` of this (whole) set: the CVaR sums over
        it keep the whole set's normalisation ``1/(β S)``.

        Parameters
        ----------
        index : ndarray of int
            Indices of the scenarios to keep.

        Returns
        -------
        ScenarioSet
            The working set.
        """
        idx = np.asarray(index, dtype=np.intp)
        tissues = tuple(
            replace(t, **{n: np.broadcast_to(getattr(t, n), (self.count,))[idx] for n in FIELDS})
            for t in self.tissues
        )
        return replace(
            self, tissues=tissues, latent_u=self.latent_u[idx], index=idx, total=self.count
        )

    @property
    def structure(self) -> ScenarioStructure:
        """The compiled-in part (hashable)."""
        return ScenarioStructure(
            self.count, len(self.tissues), self.max_stepout_probability is not None
        )

    def parameter_values(self) -> dict[str, Any]:
        """Values of the scenario parameters by name (unused names are ignored).

        Returns
        -------
        dict of str to float or ndarray
            Value by parameter name (``scenario.*``), in the unit each name carries (``E1_Pa``, ...;
            ``beta`` and the probability dimensionless, ``total`` a count).
        """
        p = self.max_stepout_probability
        out: dict[str, Any] = {
            "scenario.total": float(self.total if self.total is not None else self.count),
            "scenario.beta": self.beta,
            "scenario.max_stepout_probability": 1.0 if p is None else p,
        }
        for k, t in enumerate(self.tissues):
            for name in FIELDS:
                v = np.asarray(getattr(t, name), dtype=float)
                out[f"scenario.{k}.{name}"] = np.broadcast_to(v, (self.count,))
        return out


def with_scenarios(
    model: DesignModel,
    uncertainty: Any,
    *,
    scenarios: int = DEFAULT_SCENARIOS,
    seed: int = 0,
    beta: float = BETA,
    max_stepout_probability: float | None = None,
) -> DesignModel:
    """``model`` carrying ``scenarios`` Sobol' tissue scenarios of ``uncertainty``.

    ``uncertainty``: :class:`optimize.uncertainty.TissueUncertainty` (at least one input).

    Raises
    ------
    InputError
        No uncertain input, fewer than 2 scenarios, or ``p`` outside (0, 1).

    Parameters
    ----------
    model : DesignModel
        The design.
    uncertainty : TissueUncertainty
        The tissue uncertainty to draw from.
    scenarios : int
        Number of scenarios, >= 2.
    seed : int
        Seed of the scrambled Sobol' points.
    beta : float
        Tail fraction of the CVaR objective, dimensionless.
    max_stepout_probability : float, optional
        Largest step-out probability allowed, a probability in (0, 1).

    Returns
    -------
    DesignModel
        The model with ``scenarios`` set.
    """
    from optimize import uncertainty as uq

    if not uncertainty.active:
        raise InputError("uncertainty", "none", "an uncertain input for tissue scenarios")
    if isinstance(scenarios, bool) or not isinstance(scenarios, int) or scenarios < 2:
        raise InputError("scenarios", scenarios, "a whole number >= 2")
    p = max_stepout_probability
    if p is not None and not (0.0 < p < 1.0):
        raise InputError("max_stepout_probability", p, "a probability in (0, 1)")
    u = uq.latent_uniforms(len(uncertainty.factors()), 0, scenarios, seed, "sobol")
    arrays = uq.perturbed_tissues(model.tissues, uncertainty, u)
    return replace(model, scenarios=ScenarioSet(arrays, u, seed, beta, p))


# --- the hooks --------------------------------------------------------------------------------


def cvar_rows(
    margins: list[Any], eta: Any, u: Any, beta: Any, total: Any = None
) -> tuple[Any, list[Any]]:
    """Rockafellar-Uryasev epigraph: (CVaR_β expression, rows ``<= 0``).

    ``margins``: one (S x 1) expression per tissue set (scenario margins, any scale);
    ``eta``: scalar; ``u``: S variables bounded below by 0; ``total``: the scenario count of the
    normalisation (a working set's whole set; default S).

    Parameters
    ----------
    margins : list of casadi.SX
        Per tissue set, the (S x 1) scenario margins, in the caller's scale (margin / tau_ref,
        dimensionless, in the design NLP).
    eta : casadi.SX
        The quantile variable η, in the unit of ``margins`` (dimensionless here).
    u : casadi.SX
        S excess variables >= 0, in the unit of ``margins`` (dimensionless in the design NLP).
    beta : float or casadi.SX
        Tail fraction, dimensionless.
    total : float or casadi.SX, optional
        Number of scenarios of the normalisation (a count; default S).

    Returns
    -------
    cvar : casadi.SX
        CVaR_β, in the unit of ``margins`` (dimensionless in the design NLP).
    rows : list of casadi.SX
        Rows ``<= 0``, in the unit of ``margins`` (dimensionless in the design NLP).
    """
    n = u.shape[0] if total is None else total
    rows = [eta - m - u for m in margins]
    return eta - ca.sum1(u) / (beta * n), rows


def scenario_margins(alpha: Any, f: Any, field: Any, c: Any, req: Any, arrays: tuple) -> list:
    """Per tissue set, the margin of every scenario (numpy arrays or CasADi vectors), N·m.

    Parameters
    ----------
    alpha : float or CasADi
        Helical angle, rad.
    f : float or CasADi
        Rotation frequency, Hz.
    field : float or CasADi
        Rotating-field amplitude at the centre, T.
    c : Constants
        The design's constants.
    req : Requirements
        The requirements.
    arrays : tuple of TissueArrays
        Per tissue set, the scenario fields (numpy arrays or CasADi vectors), SI.

    Returns
    -------
    list of ndarray or CasADi
        Per tissue set, each scenario's margin, N·m.
    """
    avail = ph.available_torque_Nm(field, c)
    return [avail - (r + t) for r, t in ph.required_torques_Nm(alpha, f, c, arrays, req)]


#: The last context's symbolic margins: the objective and the step-out row share one graph.
_SHARED: list[Any] = [None, None]


def _symbolic_margins(ctx: pb.Context) -> list:
    """The scenario margins of the context, / tau_ref, with the scenarios as parameters (one
    expression graph per context, shared by the CVaR objective and the step-out row)."""
    if _SHARED[0] is ctx:
        return _SHARED[1]
    _SHARED[0], _SHARED[1] = ctx, _margins_of(ctx)
    return _SHARED[1]


def _margins_of(ctx: pb.Context) -> list:
    from optimize.uncertainty import TissueArrays

    n = ctx.scenarios.count
    arrays = tuple(
        TissueArrays(
            **{name: ctx.parameter(f"scenario.{k}.{name}", (n,)) for name in FIELDS},  # type: ignore[misc]
            name=tissue.name,
        )
        for k, tissue in enumerate(ctx.tissues)
    )
    margins = scenario_margins(
        ctx.alpha, ctx.frequency, ctx.field, ctx.constants, ctx.requirements, arrays
    )
    return [m / ctx.scales.torque_Nm for m in margins]


def _excess(ctx: pb.Context, name: str, eta: Any, margins: list) -> Any:
    """S variables ``name[s] >= 0``, started at ``max(eta − min over sets m_s, 0)`` (their rows
    hold at the start), as one column."""
    assert ctx.variable is not None
    start = ca.fmax(eta - functools.reduce(ca.fmin, margins), 0.0)
    n = margins[0].shape[0]
    return ca.vertcat(
        *(ctx.variable(f"{name}[{i}]", 1.0, 0.0, math.inf, start[i]) for i in range(n))
    )


def _row_value(_value: Any, _allowed: Any, *, expr: Any) -> Any:
    return expr


def _epigraph_terms(name: str, rows: list[Any], ctx: pb.Context) -> list[pb.Term]:
    terms = []
    for tissue, row in zip(ctx.tissues, rows):
        for s in range(row.shape[0]):
            terms.append(
                pb.Term(
                    Row(f"{name}[{tissue.name}][{s}]", "epigraph", "N·m"),
                    None,
                    None,
                    functools.partial(_row_value, expr=row[s]),
                )
            )
    return terms


def _needs_scenarios(ctx: pb.Context) -> None:
    if ctx.scenarios is None or ctx.variable is None or ctx.parameter is None:
        raise InputError(
            "objective",
            "margin_p05",
            "tissue scenarios: a [tissue.uncertainty] table (optimize.robust.with_scenarios)",
        )


def _cvar_objective(ctx: pb.Context) -> tuple[Any, list[pb.Term]]:
    """F = −CVaR_β / tau_ref with ``t`` as η; rows per scenario and tissue set."""
    _needs_scenarios(ctx)
    assert ctx.parameter is not None
    margins = _symbolic_margins(ctx)
    u = _excess(ctx, "cvar_excess", ctx.t, margins)
    total = ctx.parameter("scenario.total")
    cvar, rows = cvar_rows(margins, ctx.t, u, ctx.parameter("scenario.beta"), total)
    return -cvar, _epigraph_terms("cvar", rows, ctx)


def _stepout_terms(ctx: pb.Context) -> list[pb.Term]:
    """``CVaR_p(margin) >= 0`` when the model's scenarios ask for it (else no rows)."""
    sc = ctx.scenarios
    if sc is None or not sc.stepout_constraint or ctx.variable is None or ctx.parameter is None:
        return []
    p = ctx.parameter("scenario.max_stepout_probability")
    eta = ctx.variable("stepout_var", 1.0, start=0.0)
    margins = _symbolic_margins(ctx)
    v = _excess(ctx, "stepout_excess", eta, margins)
    n = ctx.parameter("scenario.total")
    _, rows = cvar_rows(margins, eta, v, p, n)
    worst = functools.reduce(ca.fmin, margins)
    share = ca.sum1(worst < 0) / n  # reported value only (not differentiated)
    total = ca.sum1(v)

    def form(_value: Any, allowed: Any) -> Any:
        return total / (allowed * n) - eta  # = −CVaR_p / tau_ref

    return [
        *_epigraph_terms("stepout_cvar", rows, ctx),
        pb.Term(Row("stepout_probability", "requirement", "1", 1.0), share, p, form),
    ]


pb.register_objective(
    "margin_p05", pb.ObjectiveSpec(_cvar_objective, 1.0, "N·m", lambda s: s.torque_Nm)
)
pb.register_constraint(_stepout_terms)


# --- what the optimum claims on its own scenarios ---------------------------------------------


def cvar(m: np.ndarray, beta: float, total: int | None = None) -> float:
    """Rockafellar-Uryasev CVaR_β of the values ``m`` normalised by ``total`` scenarios
    (default ``m.size``): ``max_η η − Σ (η − m)^+ / (β total)``, at ``η`` the ``ceil(β total)``-th
    smallest value.

    Parameters
    ----------
    m : ndarray
        The values, in the caller's unit (N·m for margins; the result's name carries it).
    beta : float
        Tail fraction, dimensionless.
    total : int, optional
        Number of scenarios of the normalisation (default ``m.size``).

    Returns
    -------
    float
        CVaR_β, in the unit of ``m`` (N·m for margins; the caller's name carries it).
    """
    n = m.size if total is None else total
    k = beta * n
    s = np.sort(np.asarray(m, dtype=float))
    eta = s[min(max(math.ceil(k - 1e-9), 1), s.size) - 1]
    return float(eta - np.sum(np.maximum(eta - s, 0.0)) / k)


@dataclass(frozen=True)
class InSample:
    """The worst-case margin over a design's own scenarios at an operating point (SI).

    ``margin_p05_Nm``: 5th percentile (the in-sample claim of ``margin_p05``); ``cvar_Nm``:
    the Rockafellar-Uryasev CVaR_β, the mean of the worst ``beta`` share (the last scenario
    weighed in part where β S is not whole: what the objective ``margin_p05`` maximises, so it
    equals the optimum's ``objective_value``); ``stepout_probability``: share with a negative
    margin.

    Attributes
    ----------
    scenarios : int
        Number of scenarios.
    seed : int
        Seed they were drawn with.
    beta : float
        Tail fraction of the CVaR, dimensionless.
    margin_p05_Nm : float
        5th percentile of the worst-case margin, N·m.
    cvar_Nm : float
        Rockafellar-Uryasev CVaR_β, the mean of the worst ``beta`` share, N·m.
    stepout_probability : float
        Share of scenarios with a negative margin, a probability.
    margins_Nm : ndarray
        Worst-case margin of every scenario, N·m.
    """

    scenarios: int
    seed: int
    beta: float
    margin_p05_Nm: float
    cvar_Nm: float
    stepout_probability: float
    margins_Nm: np.ndarray


def in_sample(model: DesignModel, result: Any) -> InSample:
    """:class:`InSample` of ``model``'s scenarios at ``result``'s angle, frequency and field.

    Parameters
    ----------
    model : DesignModel
        The design with its scenarios.
    result : OptimizationResult
        The optimum (its angle, frequency and field).

    Returns
    -------
    InSample
        The in-sample figures, N·m.
    """
    model = prepare(model)
    sc = model.scenarios
    if sc is None:
        raise InputError("model.scenarios", "none", "a model with tissue scenarios")
    per_set = scenario_margins(
        result.helical_angle_rad,
        result.frequency_hz,
        result.field_amplitude_T,
        model.constants,
        model.requirements,
        sc.tissues,
    )
    m = np.min(np.stack([np.asarray(x, dtype=float) for x in per_set]), axis=0)
    return InSample(
        scenarios=sc.count,
        seed=sc.seed,
        beta=sc.beta,
        margin_p05_Nm=float(np.percentile(m, 100 * BETA)),
        cvar_Nm=cvar(m, sc.beta),
        stepout_probability=float(np.mean(m < 0)),
        margins_Nm=m,
    )
