"""The compiled design NLP: one IPOPT solver per problem *structure*, memoised by value.

A :class:`Structure` is what is compiled in (objective, tissue sets' names, exposure kind, spiral
starts, relaxation, warm-start options, registered hooks, free hardware, how many tissue
scenarios); every number of the
design is a parameter filled by :meth:`CompiledProblem.parameters`. ``compile_problem`` is an
LRU cache on the frozen structure (no ``id()`` keys), so sweeps and repeated solves reuse it.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, replace
from typing import Any

import casadi as ca
import numpy as np

from coils.thermal import PACK_NUMBER_FIELDS
from optimize import hardware as hw
from optimize import problem as pb
from optimize.nlp import CompiledNLP, NLPBuilder
from optimize.scenario_nlp import FIELDS as TISSUE_FIELDS
from optimize.scenario_nlp import TissueArrays, zero_moduli
from optimize.system import DesignModel
from spiralcap.core import backend as bk

IPOPT_OPTIONS = {
    "ipopt.print_level": 0,
    "print_time": False,
    "calc_lam_p": False,  # parameter sensitivities come from nlp.Solution (named)
    "ipopt.sb": "yes",
    "ipopt.tol": 1e-10,
    "ipopt.constr_viol_tol": 1e-10,
    "ipopt.max_iter": 300,
    # the starts are good grid points: a smaller initial barrier saves iterations
    "ipopt.mu_init": 1e-3,
}
_WARM_OPTIONS = {
    **IPOPT_OPTIONS,
    "ipopt.warm_start_init_point": "yes",
    "ipopt.mu_init": 1e-6,
    "ipopt.warm_start_bound_push": 1e-9,
    "ipopt.warm_start_mult_bound_push": 1e-9,
}
_SLACKS = ("slack_speed", "slack_turns", "slack_safety")


@dataclass(frozen=True)
class Structure:
    """What is compiled into a problem (everything else is a parameter).

    Attributes
    ----------
    objective : str
        Objective name.
    tissues : tuple of (str, tuple of str)
        Each tissue set's name (it names the rows) and which of its moduli are zero (compiled
        in as 0, as a constant term drops out; a zero as a parameter value leaves 0/0 in the
        Hessian); its other numbers are parameters (``tissue.{k}.{field}``), so another
        stiffness, lumen or friction reuses the problem.
    field_exposure : str
        Exposure limit kind (``"occupational"``, ``"public"``, ``"off"``).
    spiral_starts : int
        Number of spiral starts.
    relaxed : bool
        Flag: the relaxed problem (slacks on the requirements).
    warm : bool
        Flag: IPOPT's warm-start options.
    hooks : tuple
        The registered constraint builders and the objective spec (objects).
    hardware : HardwareStructure or None
        Which hardware is free (sizing), or None.
    headings : int
        Number of headings.
    fixed_winding_temperature : bool
        Flag: the design fixes the copper temperature.
    session : bool
        Flag: a finite session instead of the steady state.
    scenarios : object
        The structure of the tissue scenarios, or None.
    convection : str
        Cooling mode (one of :data:`coils.thermal.CONVECTION_MODES`).
    surface_limit : bool
        Flag: a surface-temperature limit is set.
    own_limits : frozenset of str
        The per-pair amplifier limits set (``Limits.own``: ``"voltage_y"``, ...).
    envelope : bool
        Flag: the coil set must fit an envelope (``limits.envelope_mm``).
    vertical_bars : tuple of bool
        Per pair (x, y, z), flag: a square frame in a vertical plane (its vertical bars'
        cooling, ``WindingPack.vertical_bar_height_m``, is in the rows; a ring has none).
    tolerances : Tolerances or None
        The tolerance box, SI (compiled in: it shifts the tissue sets' lumens).
    """

    objective: str
    tissues: tuple
    field_exposure: str
    spiral_starts: int
    relaxed: bool = False
    warm: bool = False
    hooks: tuple = ()
    hardware: hw.HardwareStructure | None = None
    headings: int = 13
    fixed_winding_temperature: bool = False
    session: bool = False
    scenarios: Any = None  # DesignModel.scenarios.structure (counts, which rows)
    convection: str = "fixed"  # coils.thermal.CONVECTION_MODES
    surface_limit: bool = False  # limits.surface_temperature_C set
    own_limits: frozenset = frozenset()  # per-pair amplifier limits set
    envelope: bool = False  # limits.envelope_mm set
    vertical_bars: tuple = (False, False, False)  # pairs with vertical bars (square frames)
    #: The tolerance box (optimize.system.Tolerances, numbers): each row at its worst corner.
    tolerances: Any = None


def structure_of(
    model: DesignModel,
    *,
    relaxed: bool = False,
    warm: bool = False,
    hardware: hw.HardwareStructure | None = None,
) -> Structure:
    """The :class:`Structure` of ``model``'s problem.

    Parameters
    ----------
    model : DesignModel
        The design (prepared).
    relaxed : bool
        Flag: the relaxed problem.
    warm : bool
        Flag: warm-start options.
    hardware : HardwareStructure, optional
        Which hardware is free, when sizing.

    Returns
    -------
    Structure
        What the compiled problem depends on.
    """
    return Structure(
        model.bounds.objective,
        tuple((t.name, zero_moduli(t)) for t in model.tissues),
        model.limits.field_exposure,
        int(model.capsule.spiral.starts),
        relaxed,
        warm,
        (tuple(pb.CONSTRAINTS), pb.OBJECTIVES[model.bounds.objective]),
        hardware,
        len(model.headings),
        model.winding_temperature_C is not None,
        model.session_s is not None,
        model.scenarios.structure if model.scenarios is not None else None,
        "fixed" if model.heat_transfer_coefficient_W_m2K is not None else model.cooling,
        model.limits.surface_temperature_C is not None,
        model.limits.own,
        model.limits.envelope_m is not None,
        tuple(bool(p.vertical_bar_height_m) for p in model.constants.packs),
        model.tolerances if model.tolerances.any else None,
    )


@dataclass(frozen=True)
class CompiledProblem:
    """A compiled design NLP and how to fill its parameters from a model.

    Attributes
    ----------
    structure : Structure
        What was compiled in.
    nlp : CompiledNLP
        The compiled NLP.
    """

    structure: Structure
    nlp: CompiledNLP

    def parameters(
        self, model: DesignModel, scales: pb.Scales, extra: dict[str, Any] | None = None
    ) -> np.ndarray:
        """The parameter vector of ``model`` (prepared) with ``scales`` (and sizing values).

        Parameters
        ----------
        model : DesignModel
            The design (prepared).
        scales : Scales
            Reference magnitudes.
        extra : dict, optional
            More parameter values by name (sizing), each in the unit its name carries.

        Returns
        -------
        ndarray
            The parameter vector, each entry in the unit its parameter's name carries.
        """
        values = {
            **(extra or {}),
            **constant_values(model.constants),
            **_limit_values(model.limits),
            **pb.parameter_values("requirement", model.requirements),
            **pb.parameter_values("scale", scales),
            "ambient_temperature_C": model.ambient_temperature_C,
            **_tissue_values(model.tissues),
        }
        if model.scenarios is not None:
            values.update(model.scenarios.parameter_values())
        return self.nlp.parameter_vector(
            {k: v for k, v in values.items() if k in self.nlp.param_slices}
        )


def _limit_values(limits: Any) -> dict[str, Any]:
    """The ``limit.*`` parameter values; a per-pair limit not set (NaN) is filled with 1 (its
    entry is in no row)."""
    values = pb.parameter_values("limit", limits)
    return {
        k: np.nan_to_num(np.asarray(v, dtype=float), nan=1.0) if k.startswith("limit.axis_") else v
        for k, v in values.items()
    }


@functools.lru_cache(maxsize=64)
def compile_problem(structure: Structure) -> CompiledProblem:
    """Build and compile the NLP of ``structure`` (memoised by value).

    The warm-start variant shares the cold problem's expression graph and derivative
    functions (:meth:`optimize.nlp.CompiledNLP.with_options`): only IPOPT's options differ, so
    the NLP is built and differentiated once per structure whichever starts a caller uses.

    Parameters
    ----------
    structure : Structure
        What to compile in.

    Returns
    -------
    CompiledProblem
        The compiled problem.
    """
    if structure.warm:
        cold = compile_problem(replace(structure, warm=False))
        return CompiledProblem(structure, cold.nlp.with_options(_WARM_OPTIONS))
    return CompiledProblem(structure, _build(structure).compile(IPOPT_OPTIONS))


def _build(structure: Structure) -> NLPBuilder:
    """:func:`_build_rows` with every contact strain's ``max(·, 0)`` that moves with the
    variables an epigraph variable (:meth:`optimize.nlp.NLPBuilder.positive_part`): the optimum
    of a spiral that just stops touching the wall sits on that corner."""
    b = NLPBuilder()
    with bk.positive_part_lifted(b.positive_part):
        return _build_rows(b, structure)


def _build_rows(b: NLPBuilder, structure: Structure) -> NLPBuilder:
    """The named variables, parameters, rows and objective of ``structure``'s NLP."""
    inf = np.inf
    alpha = b.variable("helical_angle_rad", pb.ALPHA_REF_rad)
    f = b.variable("frequency_hz", pb.F_REF_hz)
    field_scaled = b.variable("field_scaled", 1.0, 0.0, inf)
    t = b.variable("t", 1.0)
    relax = tuple(b.variable(n, 1.0, 0.0, inf) for n in _SLACKS) if structure.relaxed else None
    from optimize.system import Limits, Requirements

    hs = structure.hardware
    loss = None
    if hs is None:
        c = _symbolic_constants(b, structure)
    else:
        c, hw_expr, quantities = hw.symbolic_constants(
            b, hs, structure.spiral_starts, structure.convection
        )
        c = _with_thermal_parameters(b, structure, c)
        loss = quantities[3]["power_W"]
    lim = Limits(
        current_A=b.parameter("limit.current_A"),
        voltage_V=b.parameter("limit.voltage_V"),
        power_W=b.parameter("limit.power_W"),
        coil_temperature_C=b.parameter("limit.coil_temperature_C"),
        field_exposure=structure.field_exposure,
        surface_temperature_C=(
            b.parameter("limit.surface_temperature_C") if structure.surface_limit else None
        ),
        **_axis_limit_parameters(b, structure),
    )
    req = pb.symbolic(b, "requirement", Requirements(0.0, 0.0, 0.0, 0.0))
    scales = pb.symbolic(b, "scale", pb.Scales(1.0, 1.0))
    ambient = b.parameter("ambient_temperature_C")
    # a template model carries the structure; its numbers are the parameters
    template = _Template(
        _tissue_parameters(b, structure.tissues), lim, req, ambient, tolerances=structure.tolerances
    )
    ctx = pb.make_context(
        (alpha, f, field_scaled * scales.field_T, t),
        template,  # type: ignore[arg-type]
        scales,
        constants=c,
        relax=relax,
        variable=b.variable,
        parameter=b.parameter,
        scenarios=structure.scenarios,
        loss_W=loss,
    )
    obj, terms = pb.all_terms(ctx, structure.objective)
    if hs is not None:
        terms += hw.geometry_terms(b, hs, hw_expr, quantities, ctx)
    for term in terms:
        g = term.g
        if term.allowed is None:
            b.constrain(term.row, g)
            continue
        # d row / d allowed, differentiated on the row's form alone (value and bound as
        # symbols) and then filled in: the same expression, without walking the value's graph
        value = ca.SX(term.value)
        v, a = ca.SX.sym("v", value.shape), ca.SX.sym("a")
        dg = ca.substitute([ca.jacobian(term.form(v, a), a)], [v, a], [value, ca.SX(term.allowed)])[
            0
        ]
        b.constrain(term.row, g, term.allowed, dg, term.value)
    b.minimize(obj)
    return b


def _tissue_parameters(b: NLPBuilder, sets: tuple) -> tuple[TissueArrays, ...]:
    """The tissue sets as parameters ``tissue.{k}.{field}`` (SI, the field's unit), a zero
    modulus as the constant 0, named as the model's sets (the rows carry the names); filled by
    :func:`_tissue_values`."""
    return tuple(
        TissueArrays(
            **{f: 0.0 if f in zeros else b.parameter(f"tissue.{k}.{f}") for f in TISSUE_FIELDS},
            name=name,
        )
        for k, (name, zeros) in enumerate(sets)
    )


def _tissue_values(tissues: tuple) -> dict[str, float]:
    """The ``tissue.{k}.{field}`` parameter values of the model's tissue sets."""
    return {
        f"tissue.{k}.{f}": float(getattr(t, f))
        for k, t in enumerate(tissues)
        for f in TISSUE_FIELDS
    }


def _axis_limit_parameters(b: NLPBuilder, structure: Structure) -> dict[str, Any]:
    """The per-pair amplifier limits and the envelope as parameters, where the structure has
    them (``Limits`` fields; the numbers filled by :func:`_limit_values`)."""
    own = structure.own_limits
    out: dict[str, Any] = {"own": own}
    kinds = (("current", "A"), ("voltage", "V"), ("power", "W"), ("apparent_power", "VA"))
    for kind, unit in kinds:
        if any(name.startswith(kind + "_") for name in own):
            out[f"axis_{kind}_{unit}"] = b.parameter(f"limit.axis_{kind}_{unit}", (3,))
    if structure.envelope:
        out["envelope_m"] = b.parameter("limit.envelope_m", (3,))
    return out


@dataclass(frozen=True)
class _Template:
    tissues: tuple
    limits: Any
    requirements: Any
    ambient_temperature_C: Any
    constants: Any = None
    tolerances: Any = None


#: Constants fields that are per-pair vectors (3,); the heading table is (headings, 3).
_VECTOR_FIELDS = (
    "gains_T_per_A",
    "resistance_20C_ohm",
    "inductance_H",
    "current_per_tesla_A_per_T",
    "copper_mass_kg",
)
_SCALAR_FIELDS = (
    "workspace_factor",
    "moment_Am2",
    "body_diameter_m",
    "body_length_m",
    "wire_diameter_m",
    "wound_length_m",
    "helix_diameter_m",
    "mass_kg",
)
#: WindingPack fields that are parameters, one value per pair (coils.thermal.WindingPack).
PACK_FIELDS = PACK_NUMBER_FIELDS


def constant_values(c: Any) -> dict[str, Any]:
    """The values of the ``constant.*`` parameters for numeric :class:`Constants` ``c``.

    Parameters
    ----------
    c : Constants
        Numeric constants.

    Returns
    -------
    dict of str to float or ndarray
        Value by parameter name (``constant.*``), in the unit each name carries.
    """
    out: dict[str, Any] = {
        f"constant.{n}": np.asarray(getattr(c, n), float) for n in _VECTOR_FIELDS
    }
    out.update({f"constant.{n}": float(getattr(c, n)) for n in _SCALAR_FIELDS})
    out["constant.heading_current_per_tesla_A_per_T"] = np.asarray(
        c.heading_current_per_tesla_A_per_T, float
    )
    for n in PACK_FIELDS:
        out[f"constant.pack.{n}"] = np.array([float(getattr(p, n)) for p in c.packs])
    out["constant.view_factors"] = np.asarray(c.view_factors, float).ravel()
    if c.winding_temperature_C is not None:
        out["constant.winding_temperature_C"] = float(c.winding_temperature_C)
    if c.session_s is not None:
        out["constant.session_s"] = float(c.session_s)
    return out


def _heading_table(b: NLPBuilder, name: str, headings: int) -> Any:
    flat = b.parameter(name, (headings, 3))  # row-major: [3 h + k]
    return ca.reshape(flat, 3, headings).T


def _with_thermal_parameters(b: NLPBuilder, structure: Structure, c: Any) -> Any:
    """``c`` with the winding temperature / session as parameters where the structure has them."""
    return replace(
        c,
        winding_temperature_C=(
            b.parameter("constant.winding_temperature_C")
            if structure.fixed_winding_temperature
            else None
        ),
        session_s=b.parameter("constant.session_s") if structure.session else None,
    )


def _symbolic_constants(b: NLPBuilder, structure: Structure) -> Any:
    """Constants of a fixed design as named parameters (packs included)."""
    from coils.thermal import WindingPack
    from optimize.system import Constants

    kw: dict[str, Any] = {n: b.parameter(f"constant.{n}", (3,)) for n in _VECTOR_FIELDS}
    kw.update({n: b.parameter(f"constant.{n}") for n in _SCALAR_FIELDS})
    pack = {n: b.parameter(f"constant.pack.{n}", (3,)) for n in PACK_FIELDS}
    table = _heading_table(b, "constant.heading_current_per_tesla_A_per_T", structure.headings)
    c = Constants(
        **kw,
        packs=tuple(
            WindingPack(
                **{n: pack[n][k] for n in PACK_FIELDS if n != "vertical_bar_height_m"},
                vertical_bar_height_m=(
                    pack["vertical_bar_height_m"][k] if structure.vertical_bars[k] else 0.0
                ),
                convection=structure.convection,
                vertical_axis=k == 2,
            )
            for k in range(3)
        ),
        view_factors=hw.view_factor_rows(b.parameter("constant.view_factors", (12,))),
        power_weights_per_T2=0.5 * table * table,
        heading_current_per_tesla_A_per_T=table,
        starts=structure.spiral_starts,
    )
    return _with_thermal_parameters(b, structure, c)
