"""The design NLP: helical angle, rotation frequency and field amplitude, with named rows.

Variables (physical, scaled inside :mod:`optimize.nlp`): ``helical_angle_rad`` (ref 10°),
``frequency_hz`` (ref 1 Hz), ``field_scaled`` (the field / B_ref) and the epigraph variable
``t`` (margin / tau_ref, or the safety factor). The three coil current amplitudes are exact linear functions of the field once
the headings are fixed (``I_k = B0 · max_n sqrt(1 - n_k²) / g_k``), so they are expressions
with their own limits rather than three more variables (which would only add flat directions).

Everything that is a number of the design — the precomputed :class:`Constants`, the
:class:`Limits`, the :class:`Requirements`, the ambient temperature and the scales — is a named
parameter, so one compiled solver serves a whole sweep over limits and requirements. Only the
structure (objective, tissue sets' names, exposure kind, spiral starts, relaxation) is compiled
in; the tissue numbers are parameters too.

Every limit comes from :func:`optimize.physics.limit_terms` (one definition); every row is
``g <= 0`` and carries its allowed value, so IPOPT's multipliers convert to engineering
sensitivities ``d objective / d allowed``.

Extending the problem (hook): ``register_objective(name, spec)`` adds an objective and
``register_constraint(builder)`` adds rows; both receive the :class:`Context` of backend-generic
expressions and return :class:`Term` objects. In the compiled problem the context can also
declare auxiliary variables and parameters (``ctx.variable``, ``ctx.parameter``), and carries
the structure of the model's tissue scenarios (``ctx.scenarios``; :mod:`optimize.robust` uses
all three for its CVaR objective and step-out constraint). The core is not touched.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np

import capsule as cap
from optimize import physics as ph
from optimize import scenario_nlp
from optimize.nlp import Row
from optimize.system import DesignModel
from spiralcap.core import backend as bk
from spiralcap.core.constants import from_unit

ALPHA_REF_rad = 0.1745329251994330  # 10 degrees
F_REF_hz = 1.0
#: The screw must stay this far from self-locking (capsule.self_lock_margin_rad), rad.
SELF_LOCK_MIN_MARGIN_rad = from_unit(1.0, "deg")
#: Speed reference of the speed row when no minimum speed is asked, m/s.
_SPEED_FLOOR_m_s = 1e-4


@dataclass(frozen=True)
class Scales:
    """Reference magnitudes that make the variables and the objective O(1).

    Attributes
    ----------
    field_T : float
        Reference field B_ref, T.
    torque_Nm : float
        Reference torque tau_ref, N·m.
    power_W : float
        Reference copper loss, W.
    mass_kg : float
        Reference copper mass, kg.
    """

    field_T: float
    torque_Nm: float
    power_W: float = 1.0
    mass_kg: float = 1.0


@dataclass(frozen=True)
class Term:
    """One row before it is written: ``form(value, allowed) <= 0``.

    ``form`` is the normalised comparison (e.g. ``value / allowed - 1``); keeping ``allowed``
    separate lets the solver report d(objective)/d(allowed) per row.

    Attributes
    ----------
    row : Row
        The row's name, kind and unit.
    value : float or CasADi
        The bounded quantity, in the unit ``row.unit`` names.
    allowed : float, CasADi or None
        Its bound, in the unit ``row.unit`` names (None: an objective row).
    form : callable
        ``form(value, allowed)``, the normalised row (dimensionless), ``<= 0`` when it holds.
    """

    row: Row
    value: Any
    allowed: Any
    form: Callable[[Any, Any], Any]

    @property
    def g(self) -> Any:
        """The row's expression (``<= 0`` when it holds).

        Returns
        -------
        float or CasADi
            The normalised row, dimensionless.
        """
        return self.form(self.value, self.allowed)


@dataclass(frozen=True)
class Context:
    """Backend-generic expressions objective and constraint builders work with (SI).

    Attributes
    ----------
    helical_angle_rad : float or CasADi
        Helical angle, rad.
    frequency_hz : float or CasADi
        Rotation frequency, Hz.
    field_T : float or CasADi
        Rotating-field amplitude at the centre, T.
    t : float or CasADi
        Epigraph variable: margin / tau_ref or the safety factor, dimensionless.
    constants : Constants
        The design's constants (numbers or parameters).
    limits : Limits
        The limits (numbers or parameters).
    requirements : Requirements
        The requirements (numbers or parameters).
    tissues : tuple of TissueParameters
        The tissue sets.
    ambient_temperature_C : float or CasADi
        Ambient air, °C.
    scales : Scales
        Reference magnitudes.
    available_Nm : float or CasADi
        Available synchronous torque, N·m.
    required_Nm : tuple of float or CasADi
        Required torque (resistive + thrust) per tissue set, N·m.
    relax : tuple of float or CasADi, optional
        Slacks (speed, turns, safety) of the relaxed problem, dimensionless; None otherwise.
    variable, parameter : callable, optional
        Declare an auxiliary variable or parameter in the compiled problem.
    scenarios : object, optional
        The structure of the model's tissue scenarios.
    loss_W : float or CasADi, optional
        Worst-heading copper loss at the field, W.
    tolerances : Tolerances, optional
        The tolerance box, SI (None: none).
    """

    helical_angle_rad: Any
    frequency_hz: Any
    field_T: Any
    t: Any
    constants: Any
    limits: Any
    requirements: Any
    tissues: tuple
    ambient_temperature_C: Any
    scales: Any
    available_Nm: Any
    required_Nm: tuple  # per tissue: resistive + thrust
    relax: Any = None  # (speed, turns, safety) slacks in the relaxed problem
    #: In the compiled problem: ``variable(name, ref, lo, hi)`` declares an auxiliary scaled
    #: variable (returns its physical expression) and ``parameter(name, shape)`` a parameter
    #: (returns its symbol); None on plain numbers (:func:`expressions`).
    variable: Callable[..., Any] | None = None
    parameter: Callable[..., Any] | None = None
    #: The structure of the model's tissue scenarios (``DesignModel.scenarios.structure``:
    #: how many per tissue set, which rows), or None; their numbers are parameters.
    scenarios: Any = None
    loss_W: Any = None  # worst-heading copper loss at the field (self-consistent resistance)
    #: The tolerance box (optimize.system.Tolerances, numbers) every row is held over at its own
    #: worst corner; None: none.
    tolerances: Any = None


@dataclass(frozen=True)
class ObjectiveSpec:
    """An objective: ``build(ctx) -> (F to minimise, epigraph terms)``.

    ``sense`` +1 maximises the reported value, -1 minimises it; the reported value is
    ``report(ctx)``; ``scale(ctx)`` converts F back (U = -sense · scale · F for the sensitivities);
    ``uses_t``: whether the epigraph variable is part of it (else it is fixed at 0).

    Attributes
    ----------
    build : callable
        ``build(ctx) -> (F, terms)``: scaled objective (dimensionless) and its rows.
    sense : float
        +1 (maximise the reported value) or -1 (minimise), dimensionless.
    unit : str
        Unit symbol of the reported value (``"N·m"``, ``"W"``, ``"kg"``, ``"1"``).
    scale : callable
        ``scale(scales)``, the reported value per unit of F, in the unit ``unit`` names.
    uses_t : bool
        Flag: the epigraph variable is part of the objective.
    """

    build: Callable[[Context], tuple[Any, list[Term]]]
    sense: float
    unit: str
    scale: Callable[[Any], Any]
    uses_t: bool = True


def _upper(value: Any, allowed: Any) -> Any:
    return value / allowed - 1.0


def _margin(ctx: Context) -> tuple[Any, list[Term]]:
    tau = ctx.scales.torque_Nm
    terms = [
        Term(
            Row(f"margin[{tis.name}]", "objective", "N·m"),
            need,
            None,
            lambda need, _: ctx.t - (ctx.available_Nm - need) / tau,
        )
        for tis, need in zip(ctx.tissues, ctx.required_Nm)
    ]
    return -ctx.t, terms


def _ratio(ctx: Context) -> tuple[Any, list[Term]]:
    tau = ctx.scales.torque_Nm
    terms = [
        Term(
            Row(f"ratio[{tis.name}]", "objective", "1"),
            need,
            None,
            lambda need, _: (ctx.t * need - ctx.available_Nm) / tau,
        )
        for tis, need in zip(ctx.tissues, ctx.required_Nm)
    ]
    return -ctx.t, terms


def copper_power_W(ctx: Context) -> Any:
    """Worst-heading copper loss at the field, W (the ``power`` limit's value).

    Each pair's resistance is at its own mean winding temperature at the operating current
    (steady, or at the end of the session; optimize.physics.total_loss_W), not at the limit.

    Parameters
    ----------
    ctx : Context
        The expressions at the operating point.

    Returns
    -------
    float or CasADi
        Worst-heading copper loss, W.
    """
    return ctx.loss_W


def copper_mass_kg(ctx: Context) -> Any:
    """Copper of the three pairs, kg.

    Parameters
    ----------
    ctx : Context
        The expressions at the operating point.

    Returns
    -------
    float or CasADi
        Copper mass, kg.
    """
    m = ctx.constants.copper_mass_kg
    return m[0] + m[1] + m[2]


def _power(ctx: Context) -> tuple[Any, list[Term]]:
    return copper_power_W(ctx) / ctx.scales.power_W, []


def _mass(ctx: Context) -> tuple[Any, list[Term]]:
    # a small power term makes the field unique when the copper is fixed (mass flat in B0)
    return copper_mass_kg(ctx) / ctx.scales.mass_kg + 1e-3 * copper_power_W(
        ctx
    ) / ctx.scales.power_W, []


def _margin_p05(ctx: Context) -> tuple[Any, list[Term]]:
    # CVaR_0.05 of the scenarios' effective margin (optimize.scenario_nlp; docs/uncertainty.md)
    obj, rows = scenario_nlp.cvar_objective(ctx)
    return obj, [Term(*r) for r in rows]


def _failure_probability(ctx: Context) -> list[Term]:
    # requirements.max_failure_probability: CVaR_p(effective margin) >= 0 (no rows without it)
    return [Term(*r) for r in scenario_nlp.failure_terms(ctx)]


OBJECTIVES: dict[str, ObjectiveSpec] = {
    "margin": ObjectiveSpec(_margin, 1.0, "N·m", lambda s: s.torque_Nm),
    "ratio": ObjectiveSpec(_ratio, 1.0, "1", lambda s: 1.0),
    "power": ObjectiveSpec(_power, -1.0, "W", lambda s: s.power_W, uses_t=False),
    "copper_mass": ObjectiveSpec(_mass, -1.0, "kg", lambda s: s.mass_kg, uses_t=False),
    "margin_p05": ObjectiveSpec(_margin_p05, 1.0, "N·m", lambda s: s.torque_Nm),
}
CONSTRAINTS: list[Callable[[Context], list[Term]]] = [_failure_probability]


def register_objective(name: str, spec: ObjectiveSpec) -> None:
    """Add (or replace) an objective the solver can be asked for by ``Bounds.objective``.

    Parameters
    ----------
    name : str
        Objective name (``Bounds.objective``).
    spec : ObjectiveSpec
        How to build it.
    """
    OBJECTIVES[name] = spec


def register_constraint(builder: Callable[[Context], list[Term]]) -> None:
    """Add rows to every problem: ``builder(ctx)`` returns :class:`Term` objects (``<= 0``).

    Parameters
    ----------
    builder : callable
        ``builder(ctx) -> list of Term``.
    """
    if builder not in CONSTRAINTS:
        CONSTRAINTS.append(builder)


def _safety_row(_sf: Any, min_sf: Any, *, need: Any, available: Any, tau: Any, slack: Any) -> Any:
    # (min_sf · need - available) / tau: no division by the need, which is zero (and the
    # safety factor unbounded) when nothing resists the capsule
    return (min_sf * need - available) / tau - slack


def core_terms(ctx: Context) -> list[Term]:
    """Limits, requirements (the wall strain of every tissue set among them) and the self-lock
    rows every problem has. The spiral-turn slack of the relaxed problem also relaxes the wall
    strain: both are the spiral's geometry.

    Parameters
    ----------
    ctx : Context
        The expressions at the operating point.

    Returns
    -------
    list of Term
        Safety-factor, limit, speed, spiral-turn, wall-strain and self-lock rows.
    """
    c, req, tol = ctx.constants, ctx.requirements, ctx.tolerances
    relax = ctx.relax if ctx.relax is not None else (0.0, 0.0, 0.0)
    tau = ctx.scales.torque_Nm
    out: list[Term] = []
    for tis, need in zip(ctx.tissues, ctx.required_Nm):
        out.append(
            Term(
                Row(f"safety_factor[{tis.name}]", "requirement", "1", -1.0),
                ctx.available_Nm / need,
                req.min_safety_factor,
                functools.partial(
                    _safety_row, need=need, available=ctx.available_Nm, tau=tau, slack=relax[2]
                ),
            )
        )
    for term in ph.limit_terms(
        ctx.frequency_hz, ctx.field_T, c, ctx.limits, ctx.ambient_temperature_C, loss_W=ctx.loss_W
    ):
        out.append(Term(Row(term.name, "limit", term.unit), term.value, term.allowed, _upper))
    out.append(
        Term(
            Row("speed", "requirement", "m/s", -1.0),
            ph.toleranced_speed_m_s(ctx.helical_angle_rad, ctx.frequency_hz, c, req, tol),
            req.min_speed_m_s,
            lambda v, a: (a - v) / bk.fmax(a, _SPEED_FLOOR_m_s) - relax[0],
        )
    )
    out.append(
        Term(
            Row("spiral_turns", "requirement", "turns", -1.0),
            ph.toleranced_spiral_turns(ctx.helical_angle_rad, c, tol),
            req.min_spiral_turns,
            lambda v, a: a / v - 1.0 - relax[1],
        )
    )
    for tis, strain in zip(
        ctx.tissues, ph.toleranced_wall_strains(ctx.helical_angle_rad, c, ctx.tissues, tol)
    ):
        out.append(  # engagement: the spiral must stretch every tissue set's wall
            Term(
                Row(f"wall_strain[{tis.name}]", "requirement", "1", -1.0),
                strain,
                req.min_wall_strain,
                lambda v, a: 1.0 - v / a - relax[1],
            )
        )
    for tis in ctx.tissues:
        out.append(
            Term(
                Row(f"self_lock[{tis.name}]", "requirement", "rad", -1.0),
                cap.self_lock_margin_rad(
                    ph.angle_corner(ctx.helical_angle_rad, tol, +1), tis.friction_coefficient
                ),
                SELF_LOCK_MIN_MARGIN_rad,
                lambda v, a: a - v,
            )
        )
    return out


def make_context(
    x: Any,
    model: DesignModel,
    scales: Any,
    *,
    constants: Any = None,
    limits: Any = None,
    requirements: Any = None,
    ambient_temperature_C: Any = None,
    relax: Any = None,
    variable: Callable[..., Any] | None = None,
    parameter: Callable[..., Any] | None = None,
    scenarios: Any = None,
    loss_W: Any = None,
) -> Context:
    """The :class:`Context` at physical variables ``x = (alpha, f, B0, t)``.

    ``loss_W``: the worst-heading copper loss expression if the caller has one (the sizing
    NLP's epigraph variable); default :func:`optimize.physics.total_loss_W` at the field.

    Parameters
    ----------
    x : sequence of float or CasADi
        Physical (alpha rad, f Hz, B0 T, t dimensionless).
    model : DesignModel
        The design.
    scales : Scales
        Reference magnitudes.
    constants, limits, requirements : optional
        Symbolic or other values replacing the model's (objects).
    ambient_temperature_C : float or CasADi, optional
        Ambient air, °C (default: the model's).
    relax : tuple of float or CasADi, optional
        Slacks of the relaxed problem, dimensionless.
    variable, parameter : callable, optional
        Declarers of the compiled problem.
    scenarios : object, optional
        The structure of the tissue scenarios.
    loss_W : float or CasADi, optional
        Worst-heading copper loss, W.

    Returns
    -------
    Context
        The expressions, SI.
    """
    c = model.constants if constants is None else constants
    req = model.requirements if requirements is None else requirements
    alpha, f, field, t = x[0], x[1], x[2], x[3]
    tol = getattr(model, "tolerances", None)  # each row at its own worst corner of the box
    needs = tuple(ph.worst_required_torques_Nm(alpha, f, c, model.tissues, req, tol))
    amb = model.ambient_temperature_C if ambient_temperature_C is None else ambient_temperature_C
    if loss_W is None:
        loss_W = ph.total_loss_W(field, c, amb)
    return Context(
        helical_angle_rad=alpha,
        frequency_hz=f,
        field_T=field,
        t=t,
        constants=c,
        limits=model.limits if limits is None else limits,
        requirements=req,
        tissues=model.tissues,
        ambient_temperature_C=amb,
        scales=scales,
        available_Nm=ph.available_torque_Nm(field, c),
        required_Nm=needs,
        relax=relax,
        variable=variable,
        parameter=parameter,
        scenarios=scenarios,
        loss_W=loss_W,
        tolerances=tol,
    )


def all_terms(ctx: Context, objective: str) -> tuple[Any, list[Term]]:
    """Objective F (to minimise) and every term: objective rows, core rows, registered rows.

    In the relaxed problem (``ctx.relax`` set) F is the sum of the slacks and the objective's
    own rows are left out (its ``build`` is not called); a registered row of kind
    "requirement" gets its own slack there (variable ``slack[<row>]``), so a requirement a hook
    adds is diagnosed like the core ones.

    Parameters
    ----------
    ctx : Context
        The expressions at the operating point.
    objective : str
        Objective name.

    Returns
    -------
    objective : float or CasADi
        Scaled objective F to minimise, dimensionless.
    terms : list of Term
        Every row.
    """
    spec = OBJECTIVES[objective]
    if ctx.relax is None:
        obj, own = spec.build(ctx)
        terms = [*own]
    else:
        obj, terms = ctx.relax[0] + ctx.relax[1] + ctx.relax[2], []
    terms += core_terms(ctx)
    for builder in CONSTRAINTS:
        for term in builder(ctx):
            if (
                ctx.relax is not None
                and ctx.variable is not None
                and term.row.kind == "requirement"
            ):
                slack = ctx.variable(f"slack[{term.row.name}]", 1.0, 0.0, np.inf)
                term = replace(term, form=functools.partial(_slackened, form=term.form, s=slack))
                obj = obj + slack
            terms.append(term)
    return obj, terms


def _slackened(value: Any, allowed: Any, *, form: Callable[[Any, Any], Any], s: Any) -> Any:
    return form(value, allowed) - s


def expressions(
    x: Any, model: DesignModel, scales: Scales, *, relax: Any = None, objective: str | None = None
) -> tuple[Any, list[Any], list[Row]]:
    """Objective and rows ``g <= 0`` at *scaled* ``x = (a, r, b, t)``, floats or CasADi.

    The numbers of the model are plain values here (the oracle and the tests use it); the
    compiled solver builds the same terms with parameters (:func:`optimize.solve.compile_problem`).

    Parameters
    ----------
    x : sequence of float or CasADi
        Scaled (alpha, f, B0, t), dimensionless.
    model : DesignModel
        The design (with its constants).
    scales : Scales
        Reference magnitudes.
    relax : tuple, optional
        Slacks of the relaxed problem, dimensionless.
    objective : str, optional
        Objective name (default: the model's).

    Returns
    -------
    objective : float or CasADi
        Scaled objective, dimensionless.
    rows : list of float or CasADi
        Each row ``g``, dimensionless (``<= 0`` holds).
    names : list of Row
        The rows' names, kinds and units.
    """
    phys = (x[0] * ALPHA_REF_rad, x[1] * F_REF_hz, x[2] * scales.field_T, x[3])
    ctx = make_context(phys, model, scales, relax=relax)
    obj, terms = all_terms(ctx, objective or model.bounds.objective)
    return obj, [t.g for t in terms], [t.row for t in terms]


# --- parameters -------------------------------------------------------------------------------


def _numeric_fields(obj: Any) -> dict[str, Any]:
    out = {}
    for fl in fields(obj):
        v = getattr(obj, fl.name)
        if isinstance(v, np.ndarray) or (isinstance(v, float) and not isinstance(v, bool)):
            out[fl.name] = v
    return out


def symbolic(builder: Any, prefix: str, obj: Any) -> Any:
    """``obj`` (a frozen dataclass) with every float / array field a named parameter.

    Parameters
    ----------
    builder : NLPBuilder
        The problem being built.
    prefix : str
        Parameter name prefix (``"limits"``, ...).
    obj : dataclass
        A frozen dataclass of numbers (SI, units in the field names).

    Returns
    -------
    dataclass
        The same with each float or array field a parameter symbol, in the unit its name carries.
    """
    kw = {
        name: builder.parameter(f"{prefix}.{name}", np.shape(v))
        for name, v in _numeric_fields(obj).items()
    }
    return replace(obj, **kw)


def parameter_values(prefix: str, obj: Any) -> dict[str, Any]:
    """The values of :func:`symbolic`'s parameters for ``obj``.

    Parameters
    ----------
    prefix : str
        Parameter name prefix.
    obj : dataclass
        A frozen dataclass of numbers (SI, units in the field names).

    Returns
    -------
    dict of str to float or ndarray
        Value by parameter name, in the unit each name carries.
    """
    return {f"{prefix}.{name}": v for name, v in _numeric_fields(obj).items()}


def exposure_allowed_T(model: DesignModel, frequency_hz: float) -> float:
    """The exposure level at ``frequency_hz`` (the only limit whose allowed value moves with f).

    Parameters
    ----------
    model : DesignModel
        The design.
    frequency_hz : float
        Rotation frequency, Hz.

    Returns
    -------
    float
        ICNIRP reference level, T (NaN when exposure is off).
    """
    if model.limits.field_exposure == "off":
        return float("nan")
    return float(ph.exposure_level_T(frequency_hz, model.limits.field_exposure))
