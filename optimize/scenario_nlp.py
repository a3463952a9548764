"""The scenario rows of the design NLP: the CVaR objective ``margin_p05`` and the failure
chance constraint (docs/uncertainty.md).

These are built-in entries of the one design NLP (``optimize.problem.OBJECTIVES["margin_p05"]``
and ``optimize.problem.CONSTRAINTS``): this module builds their expressions and rows as
``(Row, value, allowed, form)`` tuples and imports nothing of :mod:`optimize.problem`, which
wraps them into its terms. The scenario data are parameters of the compiled NLP
(``scenario.<set>.<field>``, ``scenario.beta``, ``scenario.total``,
``scenario.max_failure_probability``, ``scenario.grip_torque_Nm``).

A scenario fails when the capsule steps out or its spiral stretches some tissue set's wall by
less than ``requirements.min_wall_strain`` (no contact is the extreme). Its *effective margin*
is the least of its terms (:func:`scenario_rows`): per tissue set the torque margin
``A − τ_res − τ_thrust`` and the grip margin ``τ_g (ε/ε_min − 1)``; it is negative exactly when
the scenario fails. The minimum is never formed: the Rockafellar-Uryasev epigraph takes one
smooth row per term, ``u_s >= η − term_s``, so IPOPT sees only smooth rows.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from optimize import physics as ph
from optimize.nlp import Row
from spiralcap.core.errors import InputError


@dataclass(frozen=True)
class TissueArrays:
    """Tissue parameters as arrays (one entry per sample): duck-types TissueParameters.

    Attributes
    ----------
    E1_Pa, E2_Pa, E3_Pa : ndarray or CasADi
        Spring moduli per sample, Pa.
    eta1_Pa_s, eta2_Pa_s : ndarray or CasADi
        Dashpot viscosities per sample, Pa·s.
    lumen_diameter_m, wall_thickness_m : ndarray or CasADi
        Lumen diameter and wall thickness per sample, m.
    friction_coefficient : ndarray or CasADi
        Friction coefficient per sample, dimensionless.
    name : str
        Name of the nominal set.
    """

    E1_Pa: Any
    E2_Pa: Any
    E3_Pa: Any
    eta1_Pa_s: Any
    eta2_Pa_s: Any
    lumen_diameter_m: Any
    wall_thickness_m: Any
    friction_coefficient: Any
    name: str = "samples"

    def replace(self, **changes: Any) -> TissueArrays:
        """A copy with some fields changed (as :meth:`TissueParameters.replace`, unchecked:
        the fields may be symbols).

        Parameters
        ----------
        **changes : ndarray, CasADi or str
            New field values by field name, SI as the names say (``lumen_diameter_m=...``, m).

        Returns
        -------
        TissueArrays
            The copy.
        """
        return dataclasses.replace(self, **changes)


#: The tissue moduli that may be zero (TissueParameters allows E = 0: no spring in that arm).
MODULI = ("E1_Pa", "E2_Pa", "E3_Pa")


def zero_moduli(tissue: Any) -> tuple[str, ...]:
    """The moduli of ``tissue`` (a set, or scenario arrays) that are zero everywhere: part of a
    compiled problem's structure, compiled in as the constant 0 (a constant term drops out of
    the derivatives; a zero parameter value leaves 0 x inf in the Hessian of a Maxwell arm).

    Parameters
    ----------
    tissue : TissueParameters or TissueArrays
        The tissue set (Pa), numbers or arrays.

    Returns
    -------
    tuple of str
        Names of its zero moduli, in :data:`MODULI` order.
    """
    return tuple(f for f in MODULI if bool(np.all(np.asarray(getattr(tissue, f)) == 0.0)))


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


def scenario_margins(
    helical_angle_rad: Any, frequency_hz: Any, field_T: Any, c: Any, req: Any, arrays: tuple
) -> list:
    """Per tissue set, the torque margin of every scenario (numpy arrays or CasADi vectors), N·m.

    Parameters
    ----------
    helical_angle_rad : float or CasADi
        Helical angle, rad.
    frequency_hz : float or CasADi
        Rotation frequency, Hz.
    field_T : float or CasADi
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
    avail = ph.available_torque_Nm(field_T, c)
    return [
        avail - (r + t)
        for r, t in ph.required_torques_Nm(helical_angle_rad, frequency_hz, c, arrays, req)
    ]


def scenario_rows(
    helical_angle_rad: Any,
    frequency_hz: Any,
    field_T: Any,
    c: Any,
    req: Any,
    arrays: tuple,
    grip_Nm: Any,
    grip: bool,
) -> list:
    """Every term of a scenario's effective margin: per tissue set its torque margin, then per
    set its grip margin ``grip_Nm · (ε/ε_min − 1)`` (ε the strain the spiral stretches that
    set's wall by, ε_min ``req.min_wall_strain``), N·m.

    A scenario's effective margin is the least of them (:func:`effective_margins`): negative
    exactly when the scenario fails (steps out, or a wall stretched by less than ε_min; no
    contact is the extreme). Each term is smooth in (α, f, B0), so the CVaR epigraph takes one
    row per term and the minimum is never formed in the NLP.

    Parameters
    ----------
    helical_angle_rad : float or CasADi
        Helical angle, rad.
    frequency_hz : float or CasADi
        Rotation frequency, Hz.
    field_T : float or CasADi
        Rotating-field amplitude at the centre, T.
    c : Constants
        The design's constants.
    req : Requirements
        The requirements (axial load, minimum wall strain).
    arrays : tuple of TissueArrays
        Per tissue set, the scenario fields (numpy arrays or CasADi vectors), SI.
    grip_Nm : float or CasADi
        Torque scale of the grip terms, N·m (:attr:`ScenarioSet.grip_torque_Nm`).
    grip : bool
        Flag: the scenarios move the strain (a lumen or wall spread); without it every
        scenario stretches the walls as the nominal sets do, which the nominal wall-strain rows
        already hold at the minimum, and the grip terms are left out (they would only lower
        the margins of scenarios that grip).

    Returns
    -------
    list of ndarray or CasADi
        Torque margins of the sets, then (with ``grip``) grip margins of the sets, N·m.
    """
    margins = scenario_margins(helical_angle_rad, frequency_hz, field_T, c, req, arrays)
    if not grip:
        return margins
    eps_min = req.min_wall_strain
    grips = [grip_Nm * (e / eps_min - 1.0) for e in ph.wall_strains(helical_angle_rad, c, arrays)]
    return [*margins, *grips]


def effective_margins(rows: list, count: int) -> np.ndarray:
    """The least of :func:`scenario_rows`' terms per scenario (numpy), N·m.

    Parameters
    ----------
    rows : list of ndarray
        The terms, N·m.
    count : int
        Number of scenarios.

    Returns
    -------
    ndarray, shape (count,)
        Each scenario's effective margin, N·m (< 0: it fails).
    """
    return np.min(np.stack([np.broadcast_to(np.asarray(x, float), (count,)) for x in rows]), 0)


def _symbolic_margins(ctx: Any) -> list:
    """The scenario rows (torque and grip margins) of the context, / tau_ref, with the
    scenarios as parameters."""
    assert ctx.parameter is not None
    n = ctx.scenarios.count
    zeros = ctx.scenarios.zero_moduli or ((),) * len(ctx.tissues)
    arrays = tuple(
        TissueArrays(
            **{
                name: 0.0 if name in zeros[k] else ctx.parameter(f"scenario.{k}.{name}", (n,))
                for name in FIELDS
            },
            name=tissue.name,
        )
        for k, tissue in enumerate(ctx.tissues)
    )
    rows = scenario_rows(
        ctx.helical_angle_rad,
        ctx.frequency_hz,
        ctx.field_T,
        ctx.constants,
        ctx.requirements,
        arrays,
        ctx.parameter("scenario.grip_torque_Nm") if ctx.scenarios.grip else 0.0,
        ctx.scenarios.grip,
    )
    return [m / ctx.scales.torque_Nm for m in rows]


def _row_names(ctx: Any) -> list[str]:
    """Names of :func:`scenario_rows`' terms: the tissue sets, then ``grip <set>``."""
    grip = [f"grip {t.name}" for t in ctx.tissues] if ctx.scenarios.grip else []
    return [t.name for t in ctx.tissues] + grip


def _excess(ctx: Any, name: str, eta: Any, margins: list) -> Any:
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


def _epigraph_terms(name: str, rows: list[Any], ctx: Any) -> list[tuple]:
    terms = []
    for label, row in zip(_row_names(ctx), rows):
        for s in range(row.shape[0]):
            terms.append(
                (
                    Row(f"{name}[{label}][{s}]", "epigraph", "N·m"),
                    None,
                    None,
                    functools.partial(_row_value, expr=row[s]),
                )
            )
    return terms


def _needs_scenarios(ctx: Any) -> None:
    if ctx.scenarios is None or ctx.variable is None or ctx.parameter is None:
        raise InputError(
            "objective",
            "margin_p05",
            "tissue scenarios: a [tissue.uncertainty] table (optimize.robust.with_scenarios)",
        )


def cvar_objective(ctx: Any) -> tuple[Any, list[tuple]]:
    """F = −CVaR_β / tau_ref with ``t`` as η; rows per scenario and term (tissue set, grip),
    as ``(Row, value, allowed, form)``.

    Parameters
    ----------
    ctx : optimize.problem.Context
        The compiled problem's expressions (with its declarers and scenario structure).

    Returns
    -------
    F : casadi.SX
        The scaled objective to minimise, dimensionless.
    rows : list of tuple
        ``(Row, value, allowed, form)`` per epigraph row.
    """
    _needs_scenarios(ctx)
    assert ctx.parameter is not None
    margins = _symbolic_margins(ctx)
    u = _excess(ctx, "cvar_excess", ctx.t, margins)
    total = ctx.parameter("scenario.total")
    cvar, rows = cvar_rows(margins, ctx.t, u, ctx.parameter("scenario.beta"), total)
    return -cvar, _epigraph_terms("cvar", rows, ctx)


def failure_terms(ctx: Any) -> list[tuple]:
    """``CVaR_p(effective margin) >= 0`` when the model's scenarios ask for it (else no rows):
    it implies P(failure) <= p on the scenarios.

    Parameters
    ----------
    ctx : optimize.problem.Context
        The problem's expressions.

    Returns
    -------
    list of tuple
        ``(Row, value, allowed, form)`` per row: the epigraph rows, then
        ``failure_probability``.
    """
    sc = ctx.scenarios
    if sc is None or not sc.failure_constraint or ctx.variable is None or ctx.parameter is None:
        return []
    p = ctx.parameter("scenario.max_failure_probability")
    eta = ctx.variable("failure_var", 1.0, start=0.0)
    margins = _symbolic_margins(ctx)
    v = _excess(ctx, "failure_excess", eta, margins)
    n = ctx.parameter("scenario.total")
    _, rows = cvar_rows(margins, eta, v, p, n)
    worst = functools.reduce(ca.fmin, margins)
    share = ca.sum1(worst < 0) / n  # reported value only (not differentiated)
    total = ca.sum1(v)

    def form(_value: Any, allowed: Any) -> Any:
        return total / (allowed * n) - eta  # = −CVaR_p / tau_ref

    return [
        *_epigraph_terms("failure_cvar", rows, ctx),
        (Row("failure_probability", "requirement", "1", 1.0), share, p, form),
    ]
