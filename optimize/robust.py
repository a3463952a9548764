"""Design over tissue scenarios: a CVaR objective and a failure probability constraint.

Both are built-in entries of the one design NLP (``optimize.problem.OBJECTIVES["margin_p05"]``
and ``optimize.problem.CONSTRAINTS``, their rows in :mod:`optimize.scenario_nlp`), so they are
compiled, solved, warm-started and diagnosed by the common path
(:func:`optimize.optimize_design`): multipliers, binding limits, and the relaxed problem that
names an unreachable requirement. This module draws the scenarios (:func:`with_scenarios`) and
says what an optimum claims on them (:func:`in_sample`).

A scenario **fails** when the capsule steps out or its spiral stretches some tissue set's wall
by less than ``requirements.min_wall_strain`` (no contact is the extreme). Its effective margin
``m_s`` is the least of its torque margins and its grip margins ``τ_g (ε/ε_min − 1)``
(:func:`optimize.scenario_nlp.scenario_rows`; ``τ_g`` = :func:`grip_torque_Nm`): negative exactly
when the scenario fails, so lost grip is a failure for the objective and the constraint alike.

``optimize.objective = "margin_p05"`` maximises the lower 5 % tail of ``m`` over ``S`` tissue
scenarios drawn from the design's uncertainty (:mod:`optimize.uncertainty`, scrambled Sobol'
points, so the tail is sampled evenly). The 5th percentile itself (value-at-risk) is a
non-smooth, non-convex function of the scenario margins; its Rockafellar-Uryasev (2000) CVaR
bound is smooth in epigraph form and is what IPOPT maximises:

    CVaR_β(m) = max over η of  η − (1/(β S)) Σ_s u_s,   u_s >= η − term_s(x),  u_s >= 0,

with ``β = 0.05``, one row per scenario and term (each tissue set's torque margin and grip
margin: the minimum is never formed); the epigraph variable ``t`` of the problem is ``η``, and
CVaR <= p05, so the claim is conservative. The nominal sets keep their safety-factor and
wall-strain rows.

``requirements.max_failure_probability = p`` adds, for any objective, the row
``failure_probability``: ``CVaR_p(m) >= 0`` (Nemirovski & Shapiro 2006: the convex conservative
approximation of the chance constraint ``P(m < 0) <= p``, i.e. P(failure) <= p on the
scenarios), with its own ``η'`` and ``v_s``; its allowed value is ``p`` itself, so its multiplier
is d objective / d p, and its reported value is the scenarios' failure share. Where only the
grip fails, ``CVaR_p(τ_g(ε/ε_min − 1)) >= 0`` does not depend on ``τ_g`` (CVaR is positively
homogeneous).

Scenario data are parameters (``scenario.<set>.<field>``, one S-vector per tissue field and
set; ``scenario.beta``, ``scenario.max_failure_probability``, ``scenario.grip_torque_Nm``): only
the counts are compiled in (:class:`ScenarioStructure`), so another seed, another uncertainty
or a sweep re-solves the same compiled solver.

Scenario count: the empirical CDF at the 5th percentile has standard deviation
``sqrt(β(1 − β)/S)`` (binomial); ``S = 1024`` (a power of two: a balanced Sobol' block) keeps it
at 0.7 percentage points for pseudo-random scenarios and below that for Sobol' points, with 51
scenarios in the tail, while the NLP stays small (S + 4 variables). The quantile's own error is
that CDF error divided by the density at p05: where the margin's spread is large against its
p05 (a heavy lower tail), more scenarios are needed, and the out-of-sample check says so.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from optimize import physics as ph
from optimize.scenario_nlp import (  # noqa: F401  (re-exported: the scenario rows live there)
    FIELDS,
    cvar_rows,
    effective_margins,
    scenario_margins,
    scenario_rows,
    zero_moduli,
)
from optimize.system import DesignModel, prepare
from spiralcap.core.errors import InputError

BETA = 0.05
DEFAULT_SCENARIOS = 1024


@dataclass(frozen=True)
class ScenarioStructure:
    """What of the scenarios is compiled in: how many, for how many tissue sets, which rows.

    Attributes
    ----------
    count : int
        Number of scenarios compiled in.
    sets : int
        Number of nominal tissue sets.
    failure_constraint : bool
        Flag: the failure probability row is part of the problem.
    grip : bool
        Flag: the grip rows are part of the problem (the scenarios move the wall strain).
    zero_moduli : tuple of tuple of str
        Per set, the moduli zero in every scenario (compiled in as 0,
        :func:`optimize.scenario_nlp.zero_moduli`).
    """

    count: int
    sets: int
    failure_constraint: bool
    grip: bool = True
    zero_moduli: tuple = ()


@dataclass(frozen=True, eq=False)
class ScenarioSet:
    """Tissue scenarios of a design (``DesignModel.scenarios``), SI.

    ``tissues``: one :class:`optimize.uncertainty.TissueArrays` per nominal tissue set, each
    field an array of ``count`` scenarios; ``latent_u``: the latent uniforms they come from
    (count x d, to reproduce them); ``beta``: the tail of the CVaR objective;
    ``max_failure_probability``: the chance constraint's ``p`` (None: no constraint);
    ``grip_torque_Nm``: the torque a relative strain excess is weighed with in the scenario's
    effective margin (:func:`scenario_rows`).

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
    max_failure_probability : float or None
        The chance constraint's p, a probability (None: no constraint).
    grip_torque_Nm : float
        Torque scale of the grip rows, N·m (:func:`grip_torque_Nm`).
    grip : bool
        Flag: the scenarios move the wall strain (a lumen or wall-thickness spread), so the
        problem has grip rows.
    index : ndarray of int or None
        For a working set, the indices of its scenarios in the whole set.
    total : int or None
        For a working set, the number of scenarios of the whole set.
    """

    tissues: tuple
    latent_u: np.ndarray
    seed: int
    beta: float = BETA
    max_failure_probability: float | None = None
    grip_torque_Nm: float = 1e-3
    #: Whether the scenarios move the wall strain (a lumen or wall spread): only then can a
    #: scenario lose its grip while the nominal sets hold theirs, and only then are the grip
    #: rows part of the problem.
    grip: bool = True
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
            self.count,
            len(self.tissues),
            self.max_failure_probability is not None,
            self.grip,
            tuple(zero_moduli(t) for t in self.tissues),
        )

    def parameter_values(self) -> dict[str, Any]:
        """Values of the scenario parameters by name (unused names are ignored).

        Returns
        -------
        dict of str to float or ndarray
            Value by parameter name (``scenario.*``), in the unit each name carries (``E1_Pa``, ...;
            ``beta`` and the probability dimensionless, ``total`` a count).
        """
        p = self.max_failure_probability
        out: dict[str, Any] = {
            "scenario.total": float(self.total if self.total is not None else self.count),
            "scenario.beta": self.beta,
            "scenario.max_failure_probability": 1.0 if p is None else p,
            "scenario.grip_torque_Nm": self.grip_torque_Nm,
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
    max_failure_probability: float | None = None,
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
    max_failure_probability : float, optional
        Largest failure probability allowed (step-out or a wall stretched by less than
        ``requirements.min_wall_strain``), a probability in (0, 1).

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
    p = max_failure_probability
    if p is not None and not (0.0 < p < 1.0):
        raise InputError("max_failure_probability", p, "a probability in (0, 1)")
    u = uq.latent_uniforms(len(uncertainty.factors()), 0, scenarios, seed, "sobol")
    arrays = uq.perturbed_tissues(model.tissues, uncertainty, u)
    grip = uncertainty.lumen_diameter_sigma_m > 0 or uncertainty.wall_thickness_sigma_m > 0
    sc = ScenarioSet(arrays, u, seed, beta, p, grip_torque_Nm(model), grip)
    return replace(model, scenarios=sc)


def grip_torque_Nm(model: DesignModel) -> float:
    """The torque scale of the grip rows: the nominal sets' largest resistive torque (tissue and
    weight friction, no thrust) at the centre of the search box (angle and frequency), N·m.

    A constant of the scenario set: the rows do not depend on the solver's scaling, and no limit
    or requirement moves it (a sweep over them re-solves the same scenarios with the same rows).

    Parameters
    ----------
    model : DesignModel
        The design.

    Returns
    -------
    float
        The torque scale, N·m (> 0).
    """
    b = model.bounds
    alpha = 0.5 * (b.helical_angle_min_rad + b.helical_angle_max_rad)
    f = 0.5 * (b.frequency_min_hz + b.frequency_max_hz)
    pairs = ph.required_torques_Nm(
        alpha, f, prepare(model).constants, model.tissues, model.requirements
    )
    return max(max(float(r) for r, _ in pairs), 1e-9)


# --- the hooks --------------------------------------------------------------------------------


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
    """The margins over a design's own scenarios at an operating point (SI).

    ``margin_p05_Nm``: 5th percentile of the counted margin (a scenario below the minimum
    wall strain counts as min(margin, 0), as :mod:`optimize.uncertainty` counts fresh samples,
    so it compares with the out-of-sample p05); ``cvar_Nm``: the Rockafellar-Uryasev CVaR_β of
    the effective margin (:func:`effective_margins`), the mean of the worst ``beta`` share (the
    last scenario weighed in part where β S is not whole: what the objective ``margin_p05``
    maximises, so it equals the optimum's ``objective_value``); ``failure_probability``: share
    of failed scenarios; ``stepout_probability`` and ``below_min_strain_probability``: its
    parts.

    Attributes
    ----------
    scenarios : int
        Number of scenarios.
    seed : int
        Seed they were drawn with.
    beta : float
        Tail fraction of the CVaR, dimensionless.
    margin_p05_Nm : float
        5th percentile of the counted worst-case margin, N·m.
    cvar_Nm : float
        Rockafellar-Uryasev CVaR_β of the effective margin, N·m.
    stepout_probability : float
        Share of scenarios with a negative torque margin, a probability.
    margins_Nm : ndarray
        Effective margin of every scenario (< 0: it fails), N·m.
    failure_probability : float
        Share of failed scenarios (step-out or below the minimum strain), a probability.
    below_min_strain_probability : float
        Share of scenarios below the minimum strain in some set, a probability.
    """

    scenarios: int
    seed: int
    beta: float
    margin_p05_Nm: float
    cvar_Nm: float
    stepout_probability: float
    margins_Nm: np.ndarray
    failure_probability: float = 0.0
    below_min_strain_probability: float = 0.0


def scenario_outcomes(
    model: DesignModel, helical_angle_rad: float, frequency_hz: float, field_T: float
) -> tuple:
    """Per scenario of ``model``: the worst torque margin (N·m), the least wall strain and the
    effective margin (N·m), at the operating point.

    Parameters
    ----------
    model : DesignModel
        The design with its scenarios (prepared).
    helical_angle_rad : float
        Helical angle, rad.
    frequency_hz : float
        Rotation frequency, Hz.
    field_T : float
        Rotating-field amplitude at the centre, T.

    Returns
    -------
    (ndarray, ndarray, ndarray)
        Worst torque margin (N·m), least strain (dimensionless), effective margin (N·m).
    """
    sc = model.scenarios
    c, req = model.constants, model.requirements
    n, k = sc.count, len(sc.tissues)
    rows = scenario_rows(
        helical_angle_rad, frequency_hz, field_T, c, req, sc.tissues, sc.grip_torque_Nm, sc.grip
    )
    torque = effective_margins(rows[:k], n)
    strains = effective_margins(ph.wall_strains(helical_angle_rad, c, sc.tissues), n)
    return torque, strains, effective_margins(rows, n)


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
    from optimize.uncertainty import counted_margins, failed, grip_threshold

    model = prepare(model)
    sc = model.scenarios
    if sc is None:
        raise InputError("model.scenarios", "none", "a model with tissue scenarios")
    torque, strains, m = scenario_outcomes(
        model, result.helical_angle_rad, result.frequency_hz, result.field_amplitude_T
    )
    eps = model.requirements.min_wall_strain
    counted = counted_margins(torque, strains, eps)
    return InSample(
        scenarios=sc.count,
        seed=sc.seed,
        beta=sc.beta,
        margin_p05_Nm=float(np.percentile(counted, 100 * BETA)),
        cvar_Nm=cvar(m, sc.beta),
        stepout_probability=float(np.mean(torque < 0)),
        margins_Nm=m,
        failure_probability=float(np.mean(failed(torque, strains, eps))),
        below_min_strain_probability=float(np.mean(strains < grip_threshold(eps))),
    )
