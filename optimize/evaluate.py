"""A design at one operating point: the field the coils can make, the torques, the margin.

The coils are driven at the largest rotating-field amplitude every limit allows at the
operating frequency, for the worst heading; the margin is the weakest synchronous torque over
the workspace minus the largest required torque (resistive + thrust) over the tissue sets.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, NamedTuple

import numpy as np

from optimize import physics as ph
from optimize._roots import brentq
from optimize.system import DesignModel, prepare
from optimize.views import Viewable

#: Relative tolerance with which requirements are judged met (an optimum sits on its bounds).
FEASIBILITY_RTOL = 1e-6
#: Frequencies the step-out search covers, Hz: below the first the capsule is taken as unable to
#: turn at all; a step-out above the second is reported as that bound.
STEP_OUT_SEARCH_HZ = (0.01, 200.0)


@dataclass(frozen=True)
class Check:
    """One requirement or limit: ``value`` against ``allowed`` (``sense`` '<=', '>=', '<').

    In the form of the design key it checks, SI units: a winding hot spot as its temperature
    in °C against ``limits.coil_temperature_C`` (the optimiser's row is the rise above ambient);
    the self-lock as α + atan μ against 90°. ``utilisation``: how close it is to binding in the
    row's own form (value / allowed of a limit, a temperature rise over the allowed rise;
    needed / achieved of a requirement; 1 binds), NaN where it has no such ratio (the margin).
    """

    name: str
    unit: str
    value: float
    allowed: float
    sense: str
    ok: bool
    utilisation: float = float("nan")


def _build_utilisation(value: float, allowed: float, sense: str) -> float:
    """Utilisation of a buildability check: value / allowed of a limit, needed / achieved of a
    least clearance (infinite where packs touch or overlap)."""
    if sense == "<=":
        return value / allowed
    return allowed / value if value > 0 else math.inf


@dataclass(frozen=True)
class Evaluation(Viewable):
    """Immutable result of :func:`evaluate` (SI units; names say the unit)."""

    _view_kind: ClassVar[str] = "evaluation"

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
    step_out_beyond_search: bool
    max_frequency_hz: float
    max_frequency_limited_by: str
    max_frequency_beyond_search: bool
    speed_m_s: float
    spiral_turns: float
    checks: tuple[Check, ...]
    feasible: bool
    copper_masses_kg: tuple[float, float, float] = (math.nan, math.nan, math.nan)

    @property
    def copper_mass_kg(self) -> float:
        """Copper of the three pairs, kg."""
        return float(sum(self.copper_masses_kg))

    @property
    def helical_angle_deg(self) -> float:
        """Helical angle in degrees."""
        return float(np.degrees(self.helical_angle_rad))

    def failed(self) -> list[Check]:
        """The requirements and limits that do not hold."""
        return [c for c in self.checks if not c.ok]


class WorstRequired(NamedTuple):
    """The worst tissue's required torque at each point (arrays broadcast like the inputs)."""

    resistive_Nm: np.ndarray
    thrust_Nm: np.ndarray
    total_Nm: np.ndarray
    tissue_index: np.ndarray


def worst_required(model: DesignModel, alpha: Any, f: Any) -> WorstRequired:
    """Worst tissue's resistive, thrust and total torque and its index at (alpha, f)."""
    model = prepare(model)
    c = model.constants
    pairs = ph.required_torques_Nm(alpha, f, c, model.tissues, model.requirements)
    totals = np.stack([np.asarray(r + t, dtype=float) for r, t in pairs])
    worst = np.argmax(totals, axis=0)
    res = np.choose(worst, [np.asarray(r, dtype=float) for r, _ in pairs])
    thr = np.choose(worst, [np.asarray(t, dtype=float) for _, t in pairs])
    return WorstRequired(res, thr, np.max(totals, axis=0), worst)


@dataclass(frozen=True)
class MarginGrid:
    """:func:`margin_grid` on broadcast arrays of (alpha, f); SI, names carry units."""

    margin_Nm: np.ndarray
    safety_factor: np.ndarray
    field_amplitude_T: np.ndarray
    speed_m_s: np.ndarray
    spiral_turns: np.ndarray
    feasible: np.ndarray

    def __getitem__(self, name: str) -> np.ndarray:
        """Column by name (``grid["margin_Nm"]``), for code written against the old dict."""
        return getattr(self, name)


def margin_grid(
    model: DesignModel, alpha_rad: Any, frequency_hz: Any, *, capacity: bool = False
) -> MarginGrid:
    """Margin, safety factor, speed and feasibility on broadcast arrays of (alpha, f).

    The vectorised core of :func:`evaluate` (same definitions), for sweeps and initial guesses.
    The field is the largest every limit allows, or the model's set field
    (``model.field_amplitude_T``) where it is given and ``capacity`` is False — capped at what
    the limits allow, with the point marked infeasible where the set field exceeds it.
    """
    model = prepare(model)
    c = model.constants
    alpha, f = np.broadcast_arrays(np.asarray(alpha_rad, float), np.asarray(frequency_hz, float))
    field = _capacity_T(model, f)
    within = np.ones(field.shape, dtype=bool)
    if model.field_amplitude_T is not None and not capacity:
        within = model.field_amplitude_T <= field * (1 + FEASIBILITY_RTOL)
        field = np.minimum(field, model.field_amplitude_T)
    avail = np.asarray(ph.available_torque_Nm(field, c), dtype=float)
    required = worst_required(model, alpha, f).total_Nm
    speed = np.asarray(ph.speed_m_s(alpha, f, c, model.requirements), dtype=float)
    turns = np.asarray(ph.spiral_turns(alpha, c), dtype=float)
    req = model.requirements
    with np.errstate(divide="ignore"):  # nothing required: an unbounded safety factor
        ratio = np.where(required > 0, avail / np.where(required > 0, required, 1.0), np.inf)
    sf = req.min_safety_factor
    ok = (
        within
        & (self_lock_margin(model, alpha) > 0)
        & (avail - sf * required >= -FEASIBILITY_RTOL * sf * required)
        & (speed >= req.min_speed_m_s * (1 - FEASIBILITY_RTOL))
        & (turns >= req.min_spiral_turns * (1 - FEASIBILITY_RTOL))
    )
    return MarginGrid(
        margin_Nm=avail - required,
        safety_factor=ratio,
        field_amplitude_T=field,
        speed_m_s=speed,
        spiral_turns=turns,
        feasible=ok,
    )


def _capacity_T(model: DesignModel, f: np.ndarray) -> np.ndarray:
    """:func:`optimize.physics.field_capacity_T` at every frequency of ``f``, solved once per
    distinct frequency (an angle x frequency grid repeats each one per angle). Bit for bit the
    same: every cap is solved element by element, and the voltage cap's shared stopping test
    sees the same set of distinct elements."""
    c, limits, amb = model.constants, model.limits, model.ambient_temperature_C
    numbers = (limits.current_A, limits.voltage_V, limits.power_W, limits.coil_temperature_C, amb)
    if f.ndim == 0 or any(np.ndim(x) != 0 for x in numbers):  # limits swept alongside f
        return np.asarray(ph.field_capacity_T(f, c, limits, amb)[0], dtype=float)
    distinct, inverse = np.unique(f, return_inverse=True)
    if distinct.size == f.size:
        return np.asarray(ph.field_capacity_T(f, c, limits, amb)[0], dtype=float)
    field = np.asarray(ph.field_capacity_T(distinct, c, limits, amb)[0], dtype=float)
    return np.broadcast_to(field, distinct.shape)[inverse.ravel()].reshape(f.shape)


def self_lock_margin(model: DesignModel, alpha_rad):
    """pi/2 - (alpha + atan mu) for the most frictional tissue set, rad (<= 0: self-locks).

    At or below zero the screw self-locks: turning it cannot push the load, and the thrust
    torque F (D/2) tan(alpha + atan mu) (Shigley's power screw) turns negative, which would
    otherwise read as a larger margin.
    """
    import capsule as cap

    mu = max(float(t.friction_coefficient) for t in model.tissues)
    return cap.self_lock_margin_rad(np.asarray(alpha_rad, dtype=float), mu)


def self_lock_check(model: DesignModel, alpha_rad: float) -> Check:
    """The self-locking check: alpha + atan mu (most frictional tissue) must stay below 90 deg."""
    margin = float(self_lock_margin(model, alpha_rad))
    lead = float(np.pi / 2 - margin)  # alpha + atan mu
    return Check("self_lock", "rad", lead, float(np.pi / 2), "<", margin > 0, lead / (np.pi / 2))


#: Frequency range searched for the step-out and the drive's largest frequency, Hz.
SEARCH_RANGE_HZ = (0.01, 200.0)
STEP_OUT_SEARCH_HZ = SEARCH_RANGE_HZ  # the name the JSON layer reads


def operating_field_T(model: DesignModel, frequency_hz):
    """The centre field the coils are driven at: the fixed one, or the largest the limits allow."""
    model = prepare(model)
    if model.field_amplitude_T is not None:
        return np.broadcast_to(float(model.field_amplitude_T), np.shape(frequency_hz)).astype(float)
    field, _, _ = ph.field_capacity_T(
        frequency_hz, model.constants, model.limits, model.ambient_temperature_C
    )
    return field


@dataclass(frozen=True)
class FrequencyBound:
    """Where a margin reaches zero along frequency: ``beyond_search`` if it does not below
    ``frequency_hz`` (then the search bound); 0 if the margin is negative from the start."""

    frequency_hz: float
    beyond_search: bool


def _first_zero(margin, f_lo: float, f_hi: float) -> FrequencyBound:
    grid = np.geomspace(f_lo, f_hi, 400)
    m = np.asarray(margin(grid), dtype=float)
    if m[0] <= 0:
        return FrequencyBound(0.0, False)
    below = np.nonzero(m <= 0)[0]
    if below.size == 0:
        return FrequencyBound(float(f_hi), True)
    i = below[0]
    root = brentq(
        lambda f: float(margin(np.asarray(f))), grid[i - 1], grid[i], xtol=1e-12, rtol=1e-14
    )
    return FrequencyBound(float(root), False)


def step_out_frequency_hz(
    model: DesignModel,
    alpha_rad: float,
    field_T: float | None = None,
    f_lo: float = SEARCH_RANGE_HZ[0],
    f_hi: float = SEARCH_RANGE_HZ[1],
) -> FrequencyBound:
    """Frequency at which the magnet steps out at the operating field.

    The capsule keeps synchronous while the largest synchronous torque at the field it is
    driven with (``field_T``; default the operating field at the operating frequency) exceeds
    the required torque, which rises with frequency (tissue viscosity); the step-out is where
    the two are equal. Evaluating at this frequency with ``operation.field_amplitude_mT`` fixed
    at that field gives zero margin.
    """
    model = prepare(model)
    c = model.constants
    if field_T is None:
        field_T = float(operating_field_T(model, model.frequency_hz))
    avail = float(ph.available_torque_Nm(field_T, c))

    def margin(f):
        return avail - worst_required(model, alpha_rad, f).total_Nm

    return _first_zero(margin, f_lo, f_hi)


def max_frequency_hz(
    model: DesignModel,
    alpha_rad: float,
    f_lo: float = SEARCH_RANGE_HZ[0],
    f_hi: float = SEARCH_RANGE_HZ[1],
) -> tuple[FrequencyBound, str]:
    """Highest frequency at which the drive still holds a positive margin, and what limits it.

    The field is re-maximised at every frequency (it falls with frequency through the
    inductive voltage and the exposure level while the tissue torque rises); returns the bound
    and the limit that sets the field there.
    """
    model = prepare(model)
    c = model.constants

    def margin(f):
        field, _, _ = ph.field_capacity_T(f, c, model.limits, model.ambient_temperature_C)
        return (
            np.asarray(ph.available_torque_Nm(field, c))
            - worst_required(model, alpha_rad, f).total_Nm
        )

    bound = _first_zero(margin, f_lo, f_hi)
    at = bound.frequency_hz if bound.frequency_hz > 0 else f_lo
    cap = ph.field_capacity(at, c, model.limits, model.ambient_temperature_C)
    return bound, cap.limited_by


def evaluate(
    model: DesignModel,
    helical_angle_rad: float | None = None,
    frequency_hz: float | None = None,
    *,
    field_amplitude_T: float | None = None,
    frequency_bounds: bool = True,
) -> Evaluation:
    """Evaluate the design at its operating point (or at the given angle, frequency, field).

    The field is ``field_amplitude_T`` if given, else the model's set field
    (``model.field_amplitude_T``), else the largest every limit allows at the frequency; a set
    field is checked against the limits like any other operating value.
    ``frequency_bounds=False`` skips the step-out and highest-frequency searches (NaN there; no
    check depends on them): for candidates only compared by margin and feasibility.
    """
    model = prepare(model)
    c, req = model.constants, model.requirements
    alpha = (
        model.capsule.spiral.helical_angle_rad
        if helical_angle_rad is None
        else float(helical_angle_rad)
    )
    f = model.frequency_hz if frequency_hz is None else float(frequency_hz)
    if field_amplitude_T is None:
        field_amplitude_T = model.field_amplitude_T
    if field_amplitude_T is None:
        cap = ph.field_capacity(f, c, model.limits, model.ambient_temperature_C)
        field, binding = cap.field_T, cap.limited_by
    else:
        field, binding = float(field_amplitude_T), "fixed"
    avail = float(ph.available_torque_Nm(field, c))
    res, thr, required, worst = (float(np.asarray(v)) for v in worst_required(model, alpha, f))
    margin = avail - required
    speed = float(ph.speed_m_s(alpha, f, c, req))
    turns = float(ph.spiral_turns(alpha, c))
    from optimize.buildcheck import build_checks, copper_masses_kg

    checks = [
        *_checks(model, f, field, margin, required, speed, turns),
        self_lock_check(model, alpha),
        # a clearance is needed / achieved, the copper mass value / allowed (1 binds)
        *(
            Check(*c, _build_utilisation(c.value, c.allowed, c.sense))
            for c in build_checks(model, FEASIBILITY_RTOL)
        ),
    ]
    # the lag behind the field at which the magnet's torque m B sin(lag) meets the load; 90 deg
    # (the most it can give) when the load exceeds it: the magnet then cannot stay synchronous
    lag = float(np.arcsin(min(max(required / avail, 0.0), 1.0))) if avail > 0 else np.pi / 2
    if frequency_bounds:
        step_out = step_out_frequency_hz(model, alpha, field)
        fmax, fmax_by = max_frequency_hz(model, alpha)
    else:
        step_out = fmax = FrequencyBound(float("nan"), False)
        fmax_by = ""
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
        safety_factor=avail / required if required > 0 else float("inf"),
        lag_angle_rad=lag,
        step_out_frequency_hz=step_out.frequency_hz,
        step_out_beyond_search=step_out.beyond_search,
        max_frequency_hz=fmax.frequency_hz,
        max_frequency_limited_by=fmax_by,
        max_frequency_beyond_search=fmax.beyond_search,
        speed_m_s=speed,
        spiral_turns=turns,
        checks=tuple(checks),
        feasible=all(ch.ok for ch in checks),
        copper_masses_kg=copper_masses_kg(model),
    )


def _three(v: Any) -> tuple[float, float, float]:
    return (float(v[0]), float(v[1]), float(v[2]))


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
        Check(
            "margin",
            "N·m",
            margin,
            0.0,
            ">=",
            margin >= -tol * required,
            _needed_over(required, margin + required),  # required / available torque
        ),
        Check(
            "speed",
            "m/s",
            speed,
            req.min_speed_m_s,
            ">=",
            speed >= req.min_speed_m_s * (1 - tol),
            _needed_over(req.min_speed_m_s, speed),
        ),
    ]
    if req.min_safety_factor != 1.0:
        sf = margin / required + 1.0
        out.append(
            Check(
                "safety_factor",
                "1",
                sf,
                req.min_safety_factor,
                ">=",
                sf >= req.min_safety_factor * (1 - tol),
                _needed_over(req.min_safety_factor, sf),
            )
        )
    if req.min_spiral_turns > 0:
        out.append(
            Check(
                "spiral_turns",
                "turns",
                turns,
                req.min_spiral_turns,
                ">=",
                turns >= req.min_spiral_turns * (1 - tol),
                _needed_over(req.min_spiral_turns, turns),
            )
        )
    amb = float(model.ambient_temperature_C)
    for t in ph.limit_terms(f, field, model.constants, model.limits, amb):
        value, allowed = float(t.value), float(t.allowed)
        ok = value <= allowed * (1 + tol)
        util = value / allowed if allowed != 0 else float("nan")
        if t.unit == "K":  # a temperature rise above ambient: shown as the temperature, °C
            out.append(Check(t.name, "°C", value + amb, allowed + amb, "<=", ok, util))
        else:
            out.append(Check(t.name, t.unit, value, allowed, "<=", ok, util))
    return out


def _needed_over(needed: float, achieved: float) -> float:
    """needed / achieved of a requirement (1 binds, above 1 fails); inf when nothing achieved."""
    return needed / achieved if achieved > 0 else (0.0 if needed <= 0 else float("inf"))
