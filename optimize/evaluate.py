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
from optimize.system import MODEL, DesignModel, prepare
from optimize.views import Viewable
from spiralcap.core.checks import angle, finite, guard, nonnegative, positive
from spiralcap.core.constants import to_unit
from torque_model.domain import calibration_edges, extrapolations

#: the rule for a ``model`` argument of the public functions here
_MODEL = MODEL

#: Relative tolerance with which requirements are judged met (an optimum sits on its bounds).
FEASIBILITY_RTOL = 1e-6
#: Frequencies the step-out search covers, Hz: below the first the capsule is taken as unable to
#: turn at all; a step-out above the second is reported as that bound.
STEP_OUT_SEARCH_HZ = (0.01, 200.0)


#: Grip of a point (:func:`grip_state`): the spiral stretches every wall by at least
#: ``requirements.min_wall_strain``; by less (the model extrapolates below what the paper
#: measured: infeasible); or it does not touch some wall (no contact: no margin, no speed).
GRIP_OK, GRIP_BELOW, GRIP_NONE = "ok", "below minimum", "none"


@guard(least_strain=finite(), min_wall_strain=nonnegative())
def grip_state(least_strain: Any, min_wall_strain: Any) -> np.ndarray:
    """:data:`GRIP_OK`, :data:`GRIP_BELOW` or :data:`GRIP_NONE` at each point.

    Parameters
    ----------
    least_strain : float or ndarray
        The least wall strain over the tissue sets, dimensionless (<= 0: no contact).
    min_wall_strain : float or ndarray
        ``requirements.min_wall_strain``, dimensionless (judged with
        :data:`FEASIBILITY_RTOL`, as the strain check is).

    Returns
    -------
    ndarray of str
        The grip at each point, a label (dimensionless), broadcast like the inputs.
    """
    s = np.asarray(least_strain, dtype=float)
    ok = s >= np.asarray(min_wall_strain, dtype=float) * (1 - FEASIBILITY_RTOL)
    return np.where(s > 0, np.where(ok, GRIP_OK, GRIP_BELOW), GRIP_NONE)


@dataclass(frozen=True)
class Check:
    """One requirement or limit: ``value`` against ``allowed`` (``sense`` '<=', '>=', '<').

    In the form of the design key it checks, SI units: a winding hot spot as its temperature
    in °C against ``limits.coil_temperature_C`` (the optimiser's row is the rise above ambient);
    the self-lock as α + atan μ against 90°. ``utilisation``: how close it is to binding in the
    row's own form (value / allowed of a limit, a temperature rise over the allowed rise;
    needed / achieved of a requirement; 1 binds), NaN where it has no such ratio (the margin).

    Attributes
    ----------
    name : str
        Name of the requirement or limit.
    unit : str
        Unit symbol of ``value`` and ``allowed`` (SI: A, V, W, °C, N·m, m/s, rad, ...).
    value : float
        The checked quantity, in the unit ``unit`` names.
    allowed : float
        Its bound, in the unit ``unit`` names.
    sense : str
        ``"<="``, ``">="`` or ``"<"``: how ``value`` must relate to ``allowed``.
    ok : bool
        Flag: the check holds.
    utilisation : float
        How close it is to binding, dimensionless (1 binds; NaN: no such ratio).
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
    """Immutable result of :func:`evaluate` (SI units; names say the unit).

    Attributes
    ----------
    helical_angle_rad : float
        Helical angle of the spiral, rad.
    frequency_hz : float
        Rotation frequency, Hz.
    field_amplitude_T : float
        Rotating-field amplitude at the centre, T.
    field_limited_by : str
        The limit that sets the field (``"fixed"`` for a set field).
    workspace_factor : float
        Weakest field over the workspace per tesla at the centre, dimensionless.
    current_amplitudes_A : tuple of float
        Worst-heading current amplitude of each pair, A.
    magnetic_torque_Nm, resistive_torque_Nm, thrust_torque_Nm, required_torque_Nm : float
        Available synchronous torque, the worst tissue's resistive and thrust torque and their
        sum, N·m.
    worst_tissue : str
        Name of the tissue set that needs the most torque.
    margin_Nm : float
        Available minus required torque, N·m; NaN where the spiral does not touch some tissue
        set's wall (no contact: the model has no physics there, :attr:`grip` ``"none"``).
    safety_factor : float
        Available / required torque, dimensionless (a ratio); NaN where ``margin_Nm`` is.
    lag_angle_rad : float
        Angle the magnet lags the field by, rad (pi/2 where it cannot keep up).
    step_out_frequency_hz : float
        Frequency at which the magnet steps out at this field, Hz.
    step_out_beyond_search : bool
        Flag: no step-out within the search range (then its upper end).
    max_frequency_hz : float
        Highest frequency with a positive margin at the largest allowed field, Hz.
    max_frequency_limited_by : str
        The limit that sets the field there.
    max_frequency_beyond_search : bool
        Flag: the margin stays positive over the search range.
    speed_m_s : float
        Forward speed, m/s.
    spiral_turns : float
        Turns of the spiral over the wound length, count (fractional).
    checks : tuple of Check
        Every requirement and limit.
    feasible : bool
        Flag: every check holds.
    copper_masses_kg : tuple of float
        Copper of each pair, kg.
    wall_strains : tuple of float
        Strain the wound section stretches each tissue set's wall by, dimensionless (<= 0:
        no contact).
    tissue_names : tuple of str
        Names of the tissue sets, in the order of ``wall_strains``.
    weight_friction_Nm : float
        Friction of the capsule's weight in the worst tissue set's required torque, N·m.
    extrapolations : tuple of torque_model.domain.Extrapolation
        Model inputs outside the paper's calibrated range.
    calibration_edges : tuple
        Model inputs inside that range but on its edge (torque_model.domain.calibration_edges).

    Examples
    --------
    What :func:`evaluate` returns for the built-in design at its operating point (10°, 2 Hz) with the field its limits allow:

    >>> from optimize import evaluate, prepare
    >>> from spiralcap.assemble import build_model
    >>> from spiralcap.design import load_design
    >>> model = prepare(build_model(load_design(None, [])))
    >>> ev = evaluate(model, frequency_bounds=False)
    >>> print(f"{ev.field_amplitude_T * 1e3:.3f} mT ({ev.field_limited_by}), "
    ...       f"margin {ev.margin_Nm * 1e3:.3f} mN m, safety factor {ev.safety_factor:.3f}")
    10.627 mT (hot_spot_y), margin 1.332 mN m, safety factor 1.708
    """

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
    #: Strain the wound section stretches each tissue set's wall by, in ``tissue_names`` order
    #: (<= 0: the spiral does not touch that wall), dimensionless.
    wall_strains: tuple[float, ...] = ()
    tissue_names: tuple[str, ...] = ()
    #: The friction of the capsule's weight in the worst tissue set's required torque, N·m.
    weight_friction_Nm: float = 0.0
    #: Model inputs outside the paper's calibrated range (torque_model.domain.Extrapolation).
    extrapolations: tuple = ()
    #: Model inputs inside that range but on its edge (torque_model.domain.calibration_edges).
    calibration_edges: tuple = ()

    @property
    def engaged(self) -> bool:
        """Whether the spiral stretches every tissue set's wall (else it cannot screw forward)."""
        return all(s > 0 for s in self.wall_strains)

    @property
    def grip(self) -> str:
        """:data:`GRIP_OK`, :data:`GRIP_BELOW` (below ``requirements.min_wall_strain``) or
        :data:`GRIP_NONE` (no contact with some wall), from the strain checks."""
        if not self.wall_strains or min(self.wall_strains) <= 0:
            return GRIP_NONE
        strain_ok = all(c.ok for c in self.checks if c.name.startswith("wall_strain["))
        return GRIP_OK if strain_ok else GRIP_BELOW

    @property
    def copper_mass_kg(self) -> float:
        """Copper of the three pairs, kg."""
        return float(sum(self.copper_masses_kg))

    @property
    def helical_angle_deg(self) -> float:
        """Helical angle, deg."""
        return float(to_unit(self.helical_angle_rad, "deg"))

    def failed(self) -> list[Check]:
        """The requirements and limits that do not hold.

        Returns
        -------
        list of Check
            The checks with ``ok`` False.
        """
        return [c for c in self.checks if not c.ok]


class WorstRequired(NamedTuple):
    """The worst tissue's required torque at each point (arrays broadcast like the inputs).

    Attributes
    ----------
    resistive_Nm, thrust_Nm, total_Nm : ndarray
        The worst tissue's resistive, thrust and total torque, N·m.
    tissue_index : ndarray of int
        Index of that tissue set in ``model.tissues``.
    """

    resistive_Nm: np.ndarray
    thrust_Nm: np.ndarray
    total_Nm: np.ndarray
    tissue_index: np.ndarray


@guard(model=_MODEL, helical_angle_rad=angle(), frequency_hz=positive())
def worst_required(model: DesignModel, helical_angle_rad: Any, frequency_hz: Any) -> WorstRequired:
    """Worst tissue's resistive, thrust and total torque and its index at an angle and frequency.

    Parameters
    ----------
    model : DesignModel
        The design.
    helical_angle_rad : float or ndarray
        Helical angle, rad.
    frequency_hz : float or ndarray
        Rotation frequency, Hz (broadcasts against ``helical_angle_rad``).

    Returns
    -------
    WorstRequired
        Torques in N·m and the tissue index, broadcast like the inputs.

    Examples
    --------
    >>> import math
    >>> from optimize import prepare, worst_required
    >>> from spiralcap.assemble import build_model
    >>> from spiralcap.design import load_design
    >>> model = prepare(build_model(load_design(None, [])))
    >>> w = worst_required(model, math.radians(45.0), 2.0)
    >>> print(f"{w.total_Nm * 1e3:.4f} mN m = {w.resistive_Nm * 1e3:.4f} resistive + {w.thrust_Nm * 1e3:.4f} thrust")
    1.9133 mN m = 0.9590 resistive + 0.9543 thrust
    """
    model = prepare(model)
    pairs = _worst_corner_pairs(model, helical_angle_rad, frequency_hz)
    totals = np.stack([np.asarray(r + t, dtype=float) for r, t in pairs])
    worst = np.argmax(totals, axis=0)
    res = np.choose(worst, [np.asarray(r, dtype=float) for r, _ in pairs])
    thr = np.choose(worst, [np.asarray(t, dtype=float) for _, t in pairs])
    return WorstRequired(res, thr, np.max(totals, axis=0), worst)


def _worst_corner_pairs(model: DesignModel, alpha: Any, f: Any) -> list[tuple[Any, Any]]:
    """(resistive, thrust) per tissue set at its worst corner of the tolerance box
    (:func:`optimize.physics.required_torque_corners_Nm`: of the two angle ends, the one that
    needs more torque), numpy."""
    corners = ph.required_torque_corners_Nm(
        alpha, f, model.constants, model.tissues, model.requirements, model.tolerances
    )
    return _worst_of_corners(corners)


def _worst_of_corners(corners: list[list[tuple[Any, Any]]]) -> list[tuple[Any, Any]]:
    """(resistive, thrust) per tissue set at the angle corner that needs more torque, of
    :func:`optimize.physics.required_torque_corners_Nm`'s corners, numpy."""
    if len(corners) == 1:
        return corners[0]
    out = []
    for (r0, t0), (r1, t1) in zip(*corners):
        steep = np.asarray(r1 + t1, dtype=float) > np.asarray(r0 + t0, dtype=float)
        out.append((np.where(steep, r1, r0), np.where(steep, t1, t0)))
    return out


def _worst_total_at(model: DesignModel, alpha: float):
    """``f -> worst_required(model, alpha, f).total_Nm`` (N·m at a frequency in Hz), the
    torque's frequency-free parts at the angle worked out once
    (:func:`optimize.physics.required_torque_corners_at`): for a search over frequency."""
    torques = ph.required_torque_corners_at(
        alpha, model.constants, model.tissues, model.requirements, model.tolerances
    )

    def total_Nm(f: Any) -> np.ndarray:
        pairs = _worst_of_corners(torques(f))
        return np.max(np.stack([np.asarray(r + t, dtype=float) for r, t in pairs]), axis=0)

    return total_Nm


@dataclass(frozen=True)
class MarginGrid:
    """:func:`margin_grid` on broadcast arrays of (alpha, f); SI, names carry units.

    Attributes
    ----------
    margin_Nm : ndarray
        Torque margin, N·m; NaN where the spiral does not touch some wall (:attr:`grip`
        ``"none"``: the model has no physics there).
    safety_factor : ndarray
        Available / required torque, dimensionless; NaN where ``margin_Nm`` is.
    field_amplitude_T : ndarray
        Rotating-field amplitude at the centre, T.
    speed_m_s : ndarray
        Forward speed, m/s.
    spiral_turns : ndarray
        Spiral turns over the wound length, count (fractional).
    feasible : ndarray of bool
        Mask: every requirement and limit holds.
    wall_strain : ndarray or None
        Least wall strain over the tissue sets, dimensionless.
    grip : ndarray of str or None
        :func:`grip_state` at each point, a label (dimensionless): ``"ok"``,
        ``"below minimum"``, ``"none"``.
    model_margin_Nm : ndarray or None
        The margin the formulas give everywhere, N·m, no contact included (there the tissue
        term is the weight's friction and the thrust only): for starting points and searches
        that need a number at every point, never a design's margin.
    model_safety_factor : ndarray or None
        The safety factor the formulas give everywhere, dimensionless (as
        ``model_margin_Nm``).
    """

    margin_Nm: np.ndarray
    safety_factor: np.ndarray
    field_amplitude_T: np.ndarray
    speed_m_s: np.ndarray
    spiral_turns: np.ndarray
    feasible: np.ndarray
    wall_strain: np.ndarray | None = None  # the least over the tissue sets
    grip: np.ndarray | None = None
    model_margin_Nm: np.ndarray | None = None
    model_safety_factor: np.ndarray | None = None

    def __getitem__(self, name: str) -> np.ndarray:
        """Column by name (``grid["margin_Nm"]``), for code written against the old dict."""
        return getattr(self, name)


@guard(model=_MODEL, helical_angle_rad=angle(), frequency_hz=positive())
def margin_grid(
    model: DesignModel, helical_angle_rad: Any, frequency_hz: Any, *, capacity: bool = False
) -> MarginGrid:
    """Margin, safety factor, speed and feasibility on broadcast arrays of angle and frequency.

    The vectorised core of :func:`evaluate` (same definitions), for sweeps and initial guesses.
    The field is the largest every limit allows, or the model's set field
    (``model.field_amplitude_T``) where it is given and ``capacity`` is False — capped at what
    the limits allow, with the point marked infeasible where the set field exceeds it.

    Parameters
    ----------
    model : DesignModel
        The design.
    helical_angle_rad : float or ndarray
        Helical angle, rad.
    frequency_hz : float or ndarray
        Rotation frequency, Hz (broadcasts against ``helical_angle_rad``).
    capacity : bool
        Flag: use the largest field the limits allow even where the model sets a field.

    Returns
    -------
    MarginGrid
        The columns on the broadcast shape, SI.

    Examples
    --------
    The built-in design at 30° and 45°, 2 Hz, in one call:

    >>> import numpy as np
    >>> from optimize import margin_grid, prepare
    >>> from spiralcap.assemble import build_model
    >>> from spiralcap.design import load_design
    >>> model = prepare(build_model(load_design(None, [])))
    >>> grid = margin_grid(model, np.radians([30.0, 45.0]), 2.0)
    >>> print(np.round(grid.margin_Nm * 1e3, 4), np.round(grid.speed_m_s * 1e3, 2))  # mN m, mm/s
    [1.6781 1.299 ] [21.29 36.99]
    """
    model = prepare(model)
    c = model.constants
    alpha, f = np.broadcast_arrays(
        np.asarray(helical_angle_rad, float), np.asarray(frequency_hz, float)
    )
    field = _capacity_T(model, f)
    within = np.ones(field.shape, dtype=bool)
    if model.field_amplitude_T is not None and not capacity:
        within = model.field_amplitude_T <= field * (1 + FEASIBILITY_RTOL)
        field = np.minimum(field, model.field_amplitude_T)
    avail = np.asarray(ph.available_torque_Nm(field, c), dtype=float)
    required = worst_required(model, alpha, f).total_Nm
    strain = least_wall_strain(model, alpha)
    tol = model.tolerances  # each row at its own worst corner of the tolerance box
    speed = np.asarray(ph.toleranced_speed_m_s(alpha, f, c, model.requirements, tol), dtype=float)
    speed = np.where(strain > 0, speed, 0.0)  # a spiral that does not grip does not screw
    turns = np.asarray(ph.toleranced_spiral_turns(alpha, c, tol), dtype=float)
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
        & (strain >= req.min_wall_strain * (1 - FEASIBILITY_RTOL))
    )
    margin = avail - required
    contact = strain > 0  # no contact with some wall: no margin (the model has no physics)
    return MarginGrid(
        margin_Nm=np.where(contact, margin, np.nan),
        safety_factor=np.where(contact, ratio, np.nan),
        field_amplitude_T=field,
        speed_m_s=speed,
        spiral_turns=turns,
        feasible=ok,
        wall_strain=strain,
        grip=grip_state(strain, req.min_wall_strain),
        model_margin_Nm=margin,
        model_safety_factor=ratio,
    )


def least_wall_strain(model: DesignModel, helical_angle_rad: Any) -> np.ndarray:
    """The least strain the wound section stretches any tissue set's wall by (numpy).

    Parameters
    ----------
    model : DesignModel
        The design (capsule and tissue sets).
    helical_angle_rad : float or array
        Helical angle, rad.

    Returns
    -------
    ndarray
        min over tissue sets of torque_model.wall_strain, dimensionless (<= 0: no grip).
    """
    model = prepare(model)
    strains = ph.toleranced_wall_strains(
        np.asarray(helical_angle_rad, dtype=float), model.constants, model.tissues, model.tolerances
    )
    return np.min(np.stack([np.asarray(s, dtype=float) for s in strains]), axis=0)


@dataclass(frozen=True)
class GripBound:
    """The steepest helical angle inside the optimiser's box at which the spiral still grips
    (every tissue set's wall strain >= ``requirements.min_wall_strain``).

    Attributes
    ----------
    helical_angle_max_rad : float
        That angle, rad (the box's upper bound where the grip holds across it; its lower
        bound where the grip is out of reach: the most strain there is).
    reachable : bool
        Flag: some angle in the box grips.
    least_strain_at_max : float
        The least wall strain over the tissue sets at that angle, dimensionless.
    """

    helical_angle_max_rad: float
    reachable: bool
    least_strain_at_max: float


@guard(model=_MODEL)
def grip_bound(model: DesignModel) -> GripBound:
    """Where the spiral stops gripping along the helical angle (:class:`GripBound`).

    The strain falls as the angle grows (a steeper spiral's cut is narrower, so D' is smaller:
    docs/torque-model.md section 1), so the grip holds on ``[lo, alpha*]``, alpha* the root of
    least strain = ``requirements.min_wall_strain`` (Brent's method), inside the box of
    ``model.bounds``.

    Parameters
    ----------
    model : DesignModel
        The design (capsule, tissue sets, requirement and angle bounds).

    Returns
    -------
    GripBound
        The steepest gripping angle, rad, and whether any angle grips.
    """
    model = prepare(model)
    lo, hi = model.bounds.helical_angle_min_rad, model.bounds.helical_angle_max_rad
    need = float(model.requirements.min_wall_strain)

    def excess(alpha: float) -> float:
        return float(least_wall_strain(model, alpha)) - need

    if excess(lo) < 0:  # the most strain is at lo: out of reach but for the tolerance
        return GripBound(lo, excess(lo) >= -FEASIBILITY_RTOL * need, excess(lo) + need)
    if excess(hi) >= 0:
        return GripBound(hi, True, excess(hi) + need)
    from scipy.optimize import brentq  # here: a command that never searches does not load it

    root = brentq(excess, lo, hi, xtol=1e-13, rtol=1e-14)
    while excess(root) < 0 and root > lo:  # the root's side that grips (one ulp at a time)
        root = math.nextafter(root, lo)
    return GripBound(root, True, excess(root) + need)


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


def self_lock_margin(model: DesignModel, helical_angle_rad):
    """pi/2 - (alpha + atan mu) for the most frictional tissue set, rad (<= 0: self-locks).

    At or below zero the screw self-locks: turning it cannot push the load, and the thrust
    torque F (D/2) tan(alpha + atan mu) (Shigley's power screw) turns negative, which would
    otherwise read as a larger margin.

    Parameters
    ----------
    model : DesignModel
        The design (its tissue sets' friction).
    helical_angle_rad : float or ndarray
        Helical angle, rad.

    Returns
    -------
    float or ndarray
        Margin to self-locking, rad.
    """
    import capsule as cap

    mu = max(float(t.friction_coefficient) for t in model.tissues)
    steepest = ph.angle_corner(np.asarray(helical_angle_rad, dtype=float), model.tolerances, +1)
    return cap.self_lock_margin_rad(steepest, mu)


def self_lock_check(model: DesignModel, helical_angle_rad: float) -> Check:
    """The self-locking check: alpha + atan mu (most frictional tissue) must stay below 90 deg.

    Parameters
    ----------
    model : DesignModel
        The design.
    helical_angle_rad : float
        Helical angle, rad.

    Returns
    -------
    Check
        ``self_lock``: alpha + atan mu against pi/2, rad.
    """
    margin = float(self_lock_margin(model, helical_angle_rad))
    lead = float(np.pi / 2 - margin)  # alpha + atan mu
    return Check("self_lock", "rad", lead, float(np.pi / 2), "<", margin > 0, lead / (np.pi / 2))


#: Frequency range searched for the step-out and the drive's largest frequency, Hz.
SEARCH_RANGE_HZ = (0.01, 200.0)
STEP_OUT_SEARCH_HZ = SEARCH_RANGE_HZ  # the name the JSON layer reads


def operating_field_T(model: DesignModel, frequency_hz):
    """The centre field the coils are driven at: the fixed one, or the largest the limits allow.

    Parameters
    ----------
    model : DesignModel
        The design.
    frequency_hz : float or ndarray
        Rotation frequency, Hz.

    Returns
    -------
    ndarray
        Centre field amplitude, T, shaped like ``frequency_hz``.
    """
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
    ``frequency_hz`` (then the search bound); 0 if the margin is negative from the start.

    Attributes
    ----------
    frequency_hz : float
        The frequency where the margin reaches zero, Hz.
    beyond_search : bool
        Flag: it does not within the search range.
    """

    frequency_hz: float
    beyond_search: bool


#: Points of the geometric grid over the search range whose first cell with a non-positive
#: margin brackets a frequency bound (2.5 % apart over 0.01-200 Hz).
FREQUENCY_GRID_POINTS = 400


class _NaNMarginError(ArithmeticError):
    """A margin came out NaN inside a search (there the grid's cell search decides)."""


def _first_zero(
    margin, f_lo: float, f_hi: float, inside: tuple[float, float] | None = None
) -> FrequencyBound:
    """Where ``margin(f)`` first reaches zero on [f_lo, f_hi]: Brent's method in log f.

    Both margins searched do not rise with frequency: the field each limit allows stays or
    falls (the drive's impedance grows with f, the exposure limits fall), and the tissue's
    torque grows (the relaxation integral ω η (1 - exp(-2π E/(ω η))) rises with ω). So once
    the margin is positive at ``f_lo`` and not positive at ``f_hi``, its one sign change is the
    first zero, and Brent's method on log f over the whole range finds it (about 14
    evaluations of the margin at one frequency). ``inside``: a narrower (a, b) within the range
    that probably brackets it; if the margin is positive at a and not at b, the search keeps
    to it (the same zero, fewer evaluations), else it takes the whole range. A NaN margin met
    on the way (NaN counts as positive) hands the search to :func:`_first_zero_on_grid`, the
    first cell of the geometric grid whose upper point is not positive
    (``tests/test_evaluate.py`` checks the answer against the whole grid's first cell).
    """
    grid = np.geomspace(f_lo, f_hi, FREQUENCY_GRID_POINTS)

    def value(f: float) -> float:
        return float(margin(np.asarray(f)))

    bracket = _bracket(value, grid, inside)
    if isinstance(bracket, FrequencyBound):
        return bracket

    def in_log(u: float) -> float:
        m = value(math.exp(u))
        if math.isnan(m):
            raise _NaNMarginError(u)
        return m

    from scipy.optimize import brentq  # here: a command that never searches does not load it

    try:
        # xtol 1e-12 in log f: 1e-12 of the frequency, reported to 1e-9
        a, b = math.log(bracket[0]), math.log(bracket[1])
        root = brentq(in_log, a, b, xtol=1e-12, rtol=1e-14)
    except _NaNMarginError:
        return _first_zero_on_grid(value, grid)
    return FrequencyBound(math.exp(root), False)


def _bracket(
    value, grid: np.ndarray, inside: tuple[float, float] | None
) -> tuple[float, float] | FrequencyBound:
    """(a, b), Hz, with ``value`` positive at a and not at b: ``inside`` if it is one and lies
    in the grid's range, else the grid's ends; or the bound itself where the margin is not
    positive at the low end (0) or is at the high end (the range's top, beyond the search)."""
    if inside is not None and grid[0] <= inside[0] < inside[1] <= grid[-1]:
        if value(inside[0]) > 0 and value(inside[1]) <= 0:
            return float(inside[0]), float(inside[1])
    if value(grid[0]) <= 0:
        return FrequencyBound(0.0, False)
    if not value(grid[-1]) <= 0:  # NaN counts as positive
        return FrequencyBound(float(grid[-1]), True)
    return float(grid[0]), float(grid[-1])


def _first_zero_on_grid(value, grid: np.ndarray) -> FrequencyBound:
    """:func:`_first_zero` where the margin is NaN somewhere: Brent's method in the first cell of
    ``grid`` whose upper point has a margin <= 0 (NaN counts as positive), found by bisection
    over the grid's indices (the margin does not rise with f); the ends are known to be
    positive (low) and not positive (high)."""
    lo, hi = 0, grid.size - 1
    while hi - lo > 1:  # margin > 0 at lo, <= 0 at hi
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if value(grid[mid]) <= 0 else (mid, hi)
    from scipy.optimize import brentq

    root = brentq(value, grid[hi - 1], grid[hi], xtol=1e-12, rtol=1e-14)
    return FrequencyBound(float(root), False)


@guard(
    model=_MODEL,
    helical_angle_rad=angle(scalar=True),
    field_T=nonnegative(optional=True, scalar=True),
    f_lo=positive(scalar=True),
    f_hi=positive(scalar=True),
)
def step_out_frequency_hz(
    model: DesignModel,
    helical_angle_rad: float,
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

    Parameters
    ----------
    model : DesignModel
        The design.
    helical_angle_rad : float
        Helical angle, rad.
    field_T : float, optional
        Centre field amplitude the capsule is driven with, T.
    f_lo, f_hi : float
        Search range, Hz.

    Returns
    -------
    FrequencyBound
        The step-out frequency, Hz.

    Examples
    --------
    Where the built-in design's capsule steps out at its operating field:

    >>> import math
    >>> from optimize import prepare, step_out_frequency_hz
    >>> from spiralcap.assemble import build_model
    >>> from spiralcap.design import load_design
    >>> model = prepare(build_model(load_design(None, [])))
    >>> bound = step_out_frequency_hz(model, math.radians(10.0))
    >>> print(f"{bound.frequency_hz:.3f} Hz, beyond the search: {bound.beyond_search}")
    4.316 Hz, beyond the search: False
    """
    model = prepare(model)
    c = model.constants
    if field_T is None:
        field_T = float(operating_field_T(model, model.frequency_hz))
    avail = float(ph.available_torque_Nm(field_T, c))
    required_Nm = _worst_total_at(model, helical_angle_rad)

    def margin(f):
        return avail - required_Nm(f)

    return _first_zero(margin, f_lo, f_hi)


@guard(
    model=_MODEL,
    helical_angle_rad=angle(scalar=True),
    f_lo=positive(scalar=True),
    f_hi=positive(scalar=True),
)
def max_frequency_hz(
    model: DesignModel,
    helical_angle_rad: float,
    f_lo: float = SEARCH_RANGE_HZ[0],
    f_hi: float = SEARCH_RANGE_HZ[1],
) -> tuple[FrequencyBound, str]:
    """Highest frequency at which the drive still holds a positive margin, and what limits it.

    The field is re-maximised at every frequency (it falls with frequency through the
    inductive voltage and the exposure level while the tissue torque rises); returns the bound
    and the limit that sets the field there.

    Parameters
    ----------
    model : DesignModel
        The design.
    helical_angle_rad : float
        Helical angle, rad.
    f_lo, f_hi : float
        Search range, Hz.

    Returns
    -------
    bound : FrequencyBound
        The highest frequency with a positive margin, Hz.
    limited_by : str
        The limit that sets the field there.
    """
    return _max_frequency(prepare(model), helical_angle_rad, f_lo, f_hi)


def _max_frequency(
    model: DesignModel,
    alpha: float,
    f_lo: float,
    f_hi: float,
    inside: tuple[float, float] | None = None,
) -> tuple[FrequencyBound, str]:
    """:func:`max_frequency_hz` of a prepared model, the search kept to ``inside`` where that
    brackets it (:func:`_first_zero`)."""
    c = model.constants
    known = ph.frequency_free_caps_T(c, model.limits, model.ambient_temperature_C)
    required_Nm = _worst_total_at(model, alpha)

    def margin(f):
        field, _, _ = ph.field_capacity_T(f, c, model.limits, model.ambient_temperature_C, known)
        return np.asarray(ph.available_torque_Nm(field, c)) - required_Nm(f)

    bound = _first_zero(margin, f_lo, f_hi, inside)
    at = bound.frequency_hz if bound.frequency_hz > 0 else f_lo
    cap = ph.field_capacity(at, c, model.limits, model.ambient_temperature_C, known)
    return bound, cap.limited_by


@guard(
    model=_MODEL,
    helical_angle_rad=angle(optional=True, scalar=True),
    frequency_hz=positive(optional=True, scalar=True),
    field_amplitude_T=nonnegative(optional=True, scalar=True),
)
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

    Parameters
    ----------
    model : DesignModel
        The design.
    helical_angle_rad : float, optional
        Helical angle, rad (default: the capsule's).
    frequency_hz : float, optional
        Rotation frequency, Hz (default: the model's).
    field_amplitude_T : float, optional
        Centre field amplitude, T (default: the model's set field or the largest allowed).
    frequency_bounds : bool
        Flag: also search the step-out and highest frequencies.

    Returns
    -------
    Evaluation
        Every figure and check at that operating point, SI.

    """
    model = prepare(model)
    c = model.constants
    alpha = (
        model.capsule.spiral.helical_angle_rad
        if helical_angle_rad is None
        else float(helical_angle_rad)
    )
    f = model.frequency_hz if frequency_hz is None else float(frequency_hz)
    field, binding = _operating_field(model, f, field_amplitude_T)
    avail = float(ph.available_torque_Nm(field, c))
    res, thr, required, worst = (float(np.asarray(v)) for v in worst_required(model, alpha, f))
    strains, speed, turns = _spiral_rows(model, alpha, f)
    margin = _margin_if_contact(avail - required, strains)
    from optimize.buildcheck import build_checks, copper_masses_kg

    checks = [
        *_checks(model, f, field, margin, required, speed, turns),
        *strain_checks(model, strains),
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
    # no contact: no margin, so no frequency where it reaches zero (NaN; the searches skipped)
    step_out, fmax, fmax_by = _frequency_bounds(
        model, alpha, field, frequency_bounds and min(strains) > 0, _capped_at(binding, f)
    )
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
        safety_factor=_margin_if_contact(avail / required if required > 0 else math.inf, strains),
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
        wall_strains=strains,
        tissue_names=tuple(t.name for t in model.tissues),
        weight_friction_Nm=_weight_friction_Nm(model, int(worst)),
        extrapolations=_domain_flags(extrapolations, model, alpha, f),
        calibration_edges=_domain_flags(calibration_edges, model, alpha, f),
    )


def _margin_if_contact(value: float, strains: tuple[float, ...]) -> float:
    """``value`` (a margin, N·m, or a safety factor) where the spiral touches every wall, else
    NaN: with no contact the model has no physics, so there is no margin."""
    return value if min(strains) > 0 else math.nan


def _spiral_rows(model: DesignModel, alpha: float, f: float) -> tuple[tuple, float, float]:
    """(wall strain per tissue set, speed, spiral turns), each at its own worst corner of the
    tolerance box (optimize.physics; nominal without one); no grip, no speed."""
    c, req, tol = model.constants, model.requirements, model.tolerances
    strains = tuple(float(x) for x in ph.toleranced_wall_strains(alpha, c, model.tissues, tol))
    # a spiral that does not stretch every wall does not grip it: no screw, no speed
    speed = float(ph.toleranced_speed_m_s(alpha, f, c, req, tol)) if min(strains) > 0 else 0.0
    return strains, speed, float(ph.toleranced_spiral_turns(alpha, c, tol))


def _weight_friction_Nm(model: DesignModel, tissue: int) -> float:
    """The capsule weight's friction on tissue set ``tissue`` at the thickest wire, N·m."""
    c = ph.wire_corner(model.constants, model.tolerances, +1)
    return float(ph.weight_friction_Nm(c, model.tissues[tissue]))


def _domain_flags(flags: Any, model: DesignModel, alpha: float, f: float) -> tuple:
    """``flags`` (torque_model.domain's extrapolations or calibration edges) at the design and
    at the corners of its tolerance box that the rows are held at: the angle at each end of its
    band, the wall strain at its own worst corner (steepest angle, thinnest wire, widest
    lumen). The wire and the lumen themselves are judged at the design's values (the paper
    tested one wire: a tolerance on it is not a new wire). A corner adds a flag for an input
    and tissue set the design's own values do not flag."""
    c, tol = model.constants, model.tolerances
    found = {
        (e.quantity, e.where): e for e in flags(alpha, f, ph.contact_geometry(c), model.tissues)
    }
    if not tol.any:
        return tuple(found.values())
    corners = [
        (ph.angle_corner(alpha, tol, -1), c, model.tissues, ("helical_angle_rad",)),
        (
            ph.angle_corner(alpha, tol, +1),
            ph.wire_corner(c, tol, -1),
            ph.lumen_corner(model.tissues, tol, +1),
            ("helical_angle_rad", "wall_strain"),
        ),
    ]
    for a, cc, tissues, quantities in corners:
        for e in flags(a, f, ph.contact_geometry(cc), tissues):
            if e.quantity in quantities:
                found.setdefault((e.quantity, e.where), e)
    return tuple(found.values())


def _operating_field(model: DesignModel, f: float, field_T: float | None) -> tuple[float, str]:
    """(field, what sets it): the given or the model's set field ("fixed"), else the largest
    every limit allows at ``f`` and the limit that sets it."""
    if field_T is None:
        field_T = model.field_amplitude_T
    if field_T is not None:
        return float(field_T), "fixed"
    cap = ph.field_capacity(f, model.constants, model.limits, model.ambient_temperature_C)
    return cap.field_T, cap.limited_by


def _capped_at(binding: str, f: float) -> float | None:
    """The operating frequency ``f``, Hz, if the operating field is the largest the limits
    allow there (``binding`` names a limit), else None (a fixed field)."""
    return None if binding == "fixed" else f


def _frequency_bounds(
    model: DesignModel,
    alpha: float,
    field: float,
    search: bool,
    capped_at_hz: float | None = None,
) -> tuple[FrequencyBound, FrequencyBound, str]:
    """(step-out at the field, the drive's highest frequency, what limits it); NaN and ""
    without the searches.

    ``capped_at_hz``: the frequency f0 at which ``field`` is the largest the limits allow.
    Then the highest frequency f* lies in [f0, step-out] where the margin at f0 is positive:
    above f0 the allowed field is at most ``field`` (the caps do not rise with f), so the
    torque the tissue needs at f* is at most the magnet's torque at ``field``, met at the
    step-out (the tissue torque rises with f). The search tries that bracket first, its top
    widened by 0.1 % (a field that does not fall puts f* at the step-out itself).
    """
    if not search:
        nan = FrequencyBound(float("nan"), False)
        return nan, nan, ""
    lo_hz, hi_hz = SEARCH_RANGE_HZ
    step_out = step_out_frequency_hz(model, alpha, field)
    inside = None
    if capped_at_hz is not None and not step_out.beyond_search:
        inside = (capped_at_hz, min(step_out.frequency_hz * 1.001, hi_hz))
    fmax, fmax_by = _max_frequency(model, alpha, lo_hz, hi_hz, inside)
    return step_out, fmax, fmax_by


def strain_checks(model: DesignModel, strains: tuple[float, ...]) -> list[Check]:
    """The engagement requirement: each tissue set's wall strain against
    ``requirements.min_wall_strain`` (check ``wall_strain[<tissue>]``, needed / achieved).

    Parameters
    ----------
    model : DesignModel
        The design (its tissue sets and ``requirements.min_wall_strain``).
    strains : tuple of float
        Wall strain of each tissue set, dimensionless.

    Returns
    -------
    list of Check
        One ``wall_strain[<tissue>]`` check per set (dimensionless values).
    """
    need = model.requirements.min_wall_strain
    return [
        Check(
            f"wall_strain[{t.name}]",
            "1",
            s,
            need,
            ">=",
            s >= need * (1 - FEASIBILITY_RTOL),
            _needed_over(need, s),
        )
        for t, s in zip(model.tissues, strains)
    ]


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
