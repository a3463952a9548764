"""The assembled design the analyses work on, and the constants they precompute from it.

A :class:`DesignModel` holds domain objects only (SI, no design-file keys). :func:`precompute`
reduces the coils, headings and workspace to the few numbers the margin and the limits need,
so that the same backend-generic expressions serve numpy evaluation, vectorised sweeps and the
CasADi problem.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from spiralcap.core.checks import (
    Spec,
    angle,
    guard,
    nonnegative,
    positive,
    satisfies,
    temperature,
)
from torque_model.engagement import DEFAULT_MIN_WALL_STRAIN


def default_headings() -> np.ndarray:
    """Unit headings standing for "every heading": the 13 cube symmetry directions.

    At the centre the three axis headings alone already give the exact worst case over the
    sphere (per-axis current peaks when the heading is ⟂ that axis; the power, a quadratic form
    in the heading, peaks on an axis); the diagonals add the off-centre field shapes.

    Returns
    -------
    ndarray, shape (13, 3)
        Unit headings (a copy), dimensionless.
    """
    from coils.uniformity import CUBE_DIRECTIONS

    return CUBE_DIRECTIONS.copy()


def workspace_points(radius_m: float) -> np.ndarray:
    """Centre, the six points at ±radius on the axes, and the eight cube corners on the sphere.

    Parameters
    ----------
    radius_m : float
        Radius of the workspace sphere about the coil centre, m (<= 0: the centre alone).

    Returns
    -------
    ndarray, shape (15, 3) or (1, 3)
        The points, m.
    """
    if radius_m <= 0:
        return np.zeros((1, 3))
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    pts = np.vstack(
        [
            np.zeros((1, 3)),
            radius_m * np.vstack([np.eye(3), -np.eye(3)]),
            radius_m * corners / np.sqrt(3.0),
        ]
    )
    return pts


@dataclass(frozen=True)
class Limits:
    """Hardware and exposure limits (SI); ``field_exposure``: 'occupational', 'public', 'off';
    ``surface_temperature_C``: the hottest pack surface (None: no limit).

    Attributes
    ----------
    current_A : float
        Largest current amplitude of any pair, A.
    voltage_V : float
        Largest drive voltage amplitude of any pair, V.
    power_W : float
        Largest total copper loss (worst heading), W.
    coil_temperature_C : float
        Largest hot-spot winding temperature, °C.
    field_exposure : str
        Field exposure limit: ``"occupational"``, ``"public"`` or ``"off"``.
    surface_temperature_C : float or None
        Largest temperature of the hottest pack surface, °C (None: no limit).
    copper_mass_kg : float or None
        Largest copper mass of the three pairs, kg (None: no limit).
    axis_current_A, axis_voltage_V, axis_power_W : ndarray or None
        Per pair (x, y, z), the current amplitude (A), drive voltage amplitude (V) and copper
        loss (W) its own amplifier channel allows; an entry is used only where ``own`` names it
        (``"current_x"``, ...), the global limit elsewhere (None: no pair has its own).
    envelope_m : ndarray or None
        Outer box the coil set must fit, (X, Y, Z) edge lengths, m (None: no envelope).
    axis_apparent_power_VA : ndarray or None
        Per pair, the apparent power V I / 2 its amplifier channel may deliver (V and I the
        amplitudes), VA; used where ``own`` names it (``"apparent_power_x"``).
    own : frozenset of str
        Which per-pair limits are set: ``"current_x"``, ``"voltage_y"``, ``"power_z"``, ...
        (structure: a compiled problem is built for one such set).
    """

    current_A: float
    voltage_V: float
    power_W: float
    coil_temperature_C: float
    field_exposure: str = "occupational"
    surface_temperature_C: float | None = None
    copper_mass_kg: float | None = None
    axis_current_A: Any = None
    axis_voltage_V: Any = None
    axis_power_W: Any = None
    envelope_m: Any = None
    axis_apparent_power_VA: Any = None
    own: frozenset = frozenset()

    def channel(self, kind: str, k: int) -> tuple[str, Any]:
        """(row name, allowed value) of pair ``k``'s ``kind`` limit (``"current"`` or
        ``"voltage"``): its own channel's (``axis_current_x``) where set, else the global one
        (``current_x``).

        Parameters
        ----------
        kind : str
            ``"current"`` or ``"voltage"``.
        k : int
            Pair index (0, 1, 2 for x, y, z), count.

        Returns
        -------
        tuple of (str, float or CasADi)
            The row name and the allowed value, A or V.
        """
        ax = "xyz"[k]
        if f"{kind}_{ax}" in self.own:
            return f"axis_{kind}_{ax}", getattr(self, f"axis_{kind}_{_UNITS[kind]}")[k]
        return f"{kind}_{ax}", getattr(self, f"{kind}_{_UNITS[kind]}")


_UNITS = {"current": "A", "voltage": "V", "power": "W"}


@dataclass(frozen=True)
class Requirements:
    """What the capsule must do: push ``axial_load_N`` at ``min_speed_m_s``, makeable spiral.

    ``min_safety_factor``: available / required torque for every tissue set (1: margin >= 0).
    ``min_clearance_m``: least distance between the winding packs of two pairs and between the
    packs' inner faces and a bore of radius ``bore_radius_m`` (coils.clearance).
    ``min_wall_strain``: least strain the wound section must stretch every tissue set's wall by
    (torque_model.engagement: without it the spiral neither grips nor propels), dimensionless.

    Attributes
    ----------
    axial_load_N : float
        Axial load the capsule pushes, N.
    slip_efficiency : float
        Forward speed / (frequency x lead), dimensionless.
    min_speed_m_s : float
        Least forward speed, m/s.
    min_spiral_turns : float
        Fewest spiral turns over the wound length, count (0: off).
    min_safety_factor : float
        Least available / required torque, dimensionless (a ratio).
    min_clearance_m : float
        Least clearance between packs and to the bore, m.
    bore_radius_m : float
        Radius of the bore the packs keep clear of, m.
    min_wall_strain : float
        Least strain the wound section stretches every tissue set's wall by, dimensionless.
    """

    axial_load_N: float
    slip_efficiency: float
    min_speed_m_s: float
    min_spiral_turns: float
    min_safety_factor: float = 1.0
    min_clearance_m: float = 0.0
    bore_radius_m: float = 0.0
    min_wall_strain: float = DEFAULT_MIN_WALL_STRAIN


@dataclass(frozen=True)
class Tolerances:
    """How far the made capsule and the patient may stray from the design (half-widths, SI).

    The design holds over the box ``value ± tolerance`` of each key: every row is held at its
    own worst corner of that box (:mod:`optimize.tolerance`). Zero switches a key's tolerance off.

    Attributes
    ----------
    helical_angle_rad : float
        ± on the spiral's helical angle (winding), rad.
    spiral_wire_diameter_m : float
        ± on the spiral wire's diameter (wire and bonding), m.
    lumen_diameter_m : float
        ± on every tissue set's lumen (the patient's lumen about the design's), m.
    """

    helical_angle_rad: float = 0.0
    spiral_wire_diameter_m: float = 0.0
    lumen_diameter_m: float = 0.0

    @property
    def any(self) -> bool:
        """Whether any tolerance is set (a box, not a point)."""
        return bool(self.helical_angle_rad or self.spiral_wire_diameter_m or self.lumen_diameter_m)


@dataclass(frozen=True)
class Bounds:
    """Search box of the optimiser and its options.

    ``objective``: "margin" or "ratio" (maximise the torque margin or the safety factor),
    "power" or "copper_mass" (minimise the worst-heading copper loss or the copper mass), or any
    name registered with :func:`optimize.problem.register_objective`.

    Attributes
    ----------
    helical_angle_min_rad, helical_angle_max_rad : float
        Range of the helical angle, rad.
    frequency_min_hz, frequency_max_hz : float
        Range of the rotation frequency, Hz.
    objective : str
        Name of the objective.
    starts : int
        Number of multistart points of the solver.
    """

    helical_angle_min_rad: float
    helical_angle_max_rad: float
    frequency_min_hz: float
    frequency_max_hz: float
    objective: str = "margin"
    starts: int = 4


@dataclass(frozen=True)
class DesignModel:
    """Everything an evaluation or optimisation needs, as domain objects in SI units.

    Parameters
    ----------
    coils : coils.ThreeAxisHelmholtz
        The three pairs.
    capsule : capsule.Capsule
        Body, spiral (its helical angle is the design's operating angle) and magnet.
    tissues : tuple of torque_model.TissueParameters
        Tissue sets; the margin must hold for every one (worst case).
    frequency_hz : float
        Operating rotation frequency, Hz.
    headings : ndarray, shape (h, 3)
        Unit headings the capsule must be steerable along.
    points_m : ndarray, shape (n, 3)
        Workspace points, m, relative to the coil centre.
    winding_temperature_C : float or None
        Copper temperature for the resistance in the voltage and power limits, °C; None (the
        default): the mean winding temperature of the thermal limit state, solved
        self-consistently (:mod:`coils.thermal`).
    ambient_temperature_C : float
        Surrounding air, °C.
    heat_transfer_coefficient_W_m2K : float or None
        Convective coefficient from the winding surface, W/(m²·K); None: from the
        natural-convection correlations (``cooling``, :mod:`coils.convection`).
    cooling : str
        "natural" or "forced" (with ``air_speed_m_s``), when no fixed coefficient is given.
    air_speed_m_s : float
        Forced-air speed, m/s.
    winding_conductivity_W_mK : float
        Effective transverse conductivity of the winding packs, W/(m·K).
    surface_emissivity : float
        Grey-body emissivity of the winding surface, dimensionless.
    session_s : float or None
        Length of a continuous run from ambient, s; None: steady state.
    field_amplitude_T : float or None
        Fixed operating field amplitude at the centre, T; None: the largest the limits allow.
    sizing : optimize.hardware.Sizing or None
        Hardware the optimiser may choose (free variables, standard wires, least bore).
    tolerances : Tolerances
        The box the design must hold over (angle, spiral wire, lumen), SI; zero by default.
    scenarios : optimize.robust.ScenarioSet or None
        Tissue scenarios drawn from the design's uncertainty, for the objectives and rows that
        judge a design over them (``margin_p05``, the step-out probability constraint); their
        numbers are parameters of the compiled problem.
    limits : Limits
        Hardware and exposure limits, SI.
    requirements : Requirements
        What the capsule must do, SI.
    bounds : Bounds
        The optimiser's search box and options.
    constants : Constants or None
        The precomputed constants (:func:`prepare` fills them), or None.
    """

    coils: Any
    capsule: Any
    tissues: tuple
    frequency_hz: float
    headings: np.ndarray
    points_m: np.ndarray
    limits: Limits
    requirements: Requirements
    bounds: Bounds
    winding_temperature_C: float | None = None
    ambient_temperature_C: float = 25.0
    heat_transfer_coefficient_W_m2K: float | None = 10.0
    cooling: str = "natural"
    air_speed_m_s: float = 0.0
    winding_conductivity_W_mK: float = 0.5
    surface_emissivity: float = 0.9
    session_s: float | None = None
    field_amplitude_T: float | None = None
    sizing: Any = None
    tolerances: Tolerances = Tolerances()
    scenarios: Any = field(default=None, compare=False, repr=False)
    constants: Any = field(default=None, compare=False, repr=False)


#: The numbers of a model checked at the public entry points (``check_model``): where each
#: lives (its attribute path on the model: these are model fields in SI, not design keys), and
#: its rule; symbols pass (an NLP's parameters), optional ones may be None.
_MODEL_NUMBERS = (
    (("frequency_hz",), positive()),
    (("ambient_temperature_C",), temperature()),
    (("winding_temperature_C",), temperature(optional=True)),
    (("field_amplitude_T",), nonnegative(optional=True)),
    (("session_s",), positive(optional=True)),
    (("limits", "current_A"), positive()),
    (("limits", "voltage_V"), positive()),
    (("limits", "power_W"), positive()),
    (("limits", "coil_temperature_C"), temperature()),
    (("limits", "surface_temperature_C"), temperature(optional=True)),
    (("limits", "copper_mass_kg"), positive(optional=True)),
    (("requirements", "axial_load_N"), nonnegative()),
    (("requirements", "slip_efficiency"), Spec(low=0.0, high=1.0, low_open=True)),
    (("requirements", "min_speed_m_s"), nonnegative()),
    (("requirements", "min_spiral_turns"), nonnegative()),
    (("requirements", "min_safety_factor"), positive()),
    (("requirements", "min_clearance_m"), nonnegative()),
    (("requirements", "bore_radius_m"), nonnegative()),
    # > 0: the grip rows divide by it (the design key's range starts at 1e-4)
    (("requirements", "min_wall_strain"), positive()),
    (("bounds", "helical_angle_min_rad"), angle()),
    (("bounds", "helical_angle_max_rad"), angle()),
    (("bounds", "frequency_min_hz"), positive()),
    (("bounds", "frequency_max_hz"), positive()),
)


def check_model(name: str, model: Any) -> None:
    """Refuse what is not a :class:`DesignModel` (TypeError) or one whose numbers are nonsense
    (InputError naming ``model.limits.current_A`` and its value): the rule of the ``model``
    argument of the public functions (:func:`spiralcap.core.checks.guard`).

    Parameters
    ----------
    name : str
        The argument's name, which each error's key starts with (``model``, ...).
    model : DesignModel
        The value to check: its type, its numbers (frequency, temperatures, limits,
        requirements, bounds; each by its rule) and each pair's own channel limits where it
        has one.
    """
    if not isinstance(model, DesignModel):
        raise TypeError(
            f"{name} = {model!r:.80}: an optimize.DesignModel (spiralcap.assemble.build_model) "
            "is needed"
        )
    for path, spec in _MODEL_NUMBERS:
        value: Any = model
        for part in path:
            value = getattr(value, part)
        spec.check(f"{name}.{'.'.join(path)}", value)
    lim = model.limits
    for kind, unit in (
        ("current", "A"),
        ("voltage", "V"),
        ("power", "W"),
        ("apparent_power", "VA"),
    ):
        own = getattr(lim, f"axis_{kind}_{unit}")
        for k, ax in enumerate("xyz"):  # a pair's own channel, where it has one
            if f"{kind}_{ax}" in lim.own:
                positive().check(f"{name}.limits.axis_{kind}_{unit}[{ax}]", own[k])


#: the rule of a ``model`` argument of the public functions
MODEL = satisfies(check_model)


class PhysicsMemo:
    """What :mod:`optimize.physics` already solved for one :class:`Constants` (its ``memo``).

    Owned by the constants it belongs to (a new :class:`Constants`, ``replace`` included,
    starts empty), never shared between two, so the physics module keeps no state of its own.
    It pickles empty: a model sent to a worker carries no memo.

    Attributes
    ----------
    states : dict
        :func:`optimize.physics.pair_states` by field and ambient (°C, W, s; a field node of an
        NLP being built included).
    """

    def __init__(self) -> None:
        self.states: dict = {}

    def __reduce__(self) -> tuple:
        return (PhysicsMemo, ())


@dataclass(frozen=True)
class Constants:
    """Numbers the margin and limits need, reduced from a :class:`DesignModel`.

    ``current_per_tesla_A_per_T[k]``: current amplitude axis k needs per tesla of rotating field
    for the worst heading, max over headings of sqrt(1 - n_k²) / g_k.
    ``power_weights_per_T2[h, k]``: (1 - n_k²) / (2 g_k²) for heading h, so that the copper
    loss per T² of heading h is Σ_k w_hk R_k (the resistance depends on the limits).
    ``packs``: the thermal description of each pair (:class:`coils.thermal.WindingPack`);
    ``resistance_20C_ohm``: pair resistances at 20 °C; ``winding_temperature_C``: a fixed copper
    temperature for the voltage/power resistance, or None (self-consistent);
    ``session_s``: run length, s, or None (steady).
    ``view_factors[k]``: pair k's diffuse view factors ``[room, x, y, z]``
    (:func:`coils.viewfactors.view_factors`), or None (each pair alone in the room).
    ``workspace_factor``: weakest field the magnet sees during a turn, over every workspace point
    and heading, per tesla of centre amplitude (minor semi-axis of the field ellipse).
    ``copper_mass_kg[k]``: copper of pair k (both coils), wire length x area x density.
    ``heading_current_per_tesla_A_per_T[h, k]``: sqrt(1 - n_hk²) / g_k, the current amplitude
    axis k carries per tesla for heading h (``current_per_tesla_A_per_T`` is its column max);
    with calibrated coils (:class:`coils.calibration.CalibratedHelmholtz`) the amplitudes of
    the allocation through the calibrated centre matrix A^-1 (and the power weights their
    squares over 2), not through the diagonal gains.
    ``mass_kg``: the capsule's mass, whose weight rests on the wall (torque_model.engagement).

    Every field may hold CasADi values (the NLP builds it from parameters and, when sizing,
    from hardware variables: :mod:`optimize.compiled`, :mod:`optimize.hardware`).

    Attributes
    ----------
    gains_T_per_A : ndarray, shape (3,)
        Centre field per ampere of each pair, T/A.
    resistance_20C_ohm : ndarray, shape (3,)
        Pair resistances at 20 °C, Ω.
    inductance_H : ndarray, shape (3,)
        Series inductance of each pair, H.
    packs : tuple of coils.thermal.WindingPack
        The thermal description of each pair.
    current_per_tesla_A_per_T : ndarray, shape (3,)
        Worst-heading current amplitude per tesla of each pair, A/T.
    power_weights_per_T2 : ndarray, shape (h, 3)
        Weights w_hk = (1 - n_k²) / (2 g_k²), A²/T²: the copper loss of heading h is
        Σ_k w_hk R_k B0², W.
    workspace_factor : float
        Weakest field seen over the workspace per tesla of centre amplitude, dimensionless.
    moment_Am2 : float
        Magnet moment, A·m².
    body_diameter_m, body_length_m : float
        Capsule body diameter and overall length, m.
    wire_diameter_m, wound_length_m, helix_diameter_m : float
        Spiral wire diameter, wound length and helix diameter, m.
    copper_mass_kg : ndarray, shape (3,)
        Copper of each pair, kg.
    heading_current_per_tesla_A_per_T : ndarray, shape (h, 3)
        Current amplitude per tesla of each pair for each heading, A/T.
    starts : int
        Number of spiral starts, count.
    winding_temperature_C : float or None
        Fixed copper temperature for the voltage/power resistance, °C (None: self-consistent).
    session_s : float or None
        Run length, s (None: steady).
    view_factors : ndarray, shape (3, 4), or None
        Diffuse view factors of each pair, dimensionless (None: each alone in the room).
    mass_kg : float
        The capsule's mass, whose weight rests on the wall, kg.
    memo : PhysicsMemo
        What the physics already solved for these constants (field caps, T; pair states): the
        callers' memo, not an argument, not compared.
    """

    gains_T_per_A: np.ndarray
    resistance_20C_ohm: np.ndarray
    inductance_H: np.ndarray
    packs: tuple
    current_per_tesla_A_per_T: np.ndarray
    power_weights_per_T2: np.ndarray
    workspace_factor: float
    moment_Am2: float
    body_diameter_m: float
    body_length_m: float
    wire_diameter_m: float
    wound_length_m: float
    helix_diameter_m: float
    copper_mass_kg: np.ndarray
    heading_current_per_tesla_A_per_T: Any = None
    starts: int = 1
    winding_temperature_C: Any = None
    session_s: Any = None
    view_factors: Any = None
    mass_kg: Any = 0.0
    memo: PhysicsMemo = field(default_factory=PhysicsMemo, init=False, compare=False, repr=False)


def packs_of(model: DesignModel) -> tuple:
    """The :class:`coils.thermal.WindingPack` of each pair of ``model`` (its cooling options).

    Parameters
    ----------
    model : DesignModel
        The design (its coils and cooling options).

    Returns
    -------
    tuple of coils.thermal.WindingPack
        One per pair (x, y, z), SI.
    """
    from coils.thermal import WindingPack

    h = model.heat_transfer_coefficient_W_m2K
    return tuple(
        WindingPack(
            pack_width_m=p.winding_pack_width_m,
            pack_depth_m=p.winding_pack_depth_m,
            mean_radius_m=p.turn_radius_m,
            packing_factor=p.packing_factor,
            conductivity_W_mK=model.winding_conductivity_W_mK,
            heat_transfer_coefficient_W_m2K=0.0 if h is None else float(h),
            emissivity=model.surface_emissivity,
            vertical_axis=p.axis == "z",
            air_speed_m_s=float(model.air_speed_m_s),
            convection="fixed" if h is not None else model.cooling,
            vertical_bar_height_m=p.vertical_bar_height_m,
        )
        for p in model.coils.pairs
    )


def pack_rings(coils: Any) -> list[Any]:
    """The three pairs' winding packs as :class:`coils.viewfactors.PackRing` (a square pair:
    :class:`coils.viewfactors.PackFrame`), the geometry the view factors are traced on.

    Parameters
    ----------
    coils : coils.ThreeAxisHelmholtz
        The coil set.

    Returns
    -------
    list of coils.viewfactors.PackRing or PackFrame
        One per pair, SI.
    """
    return [p.view_pack() for p in coils.pairs]


def view_factors_of(coils: Any) -> Any:
    """Diffuse view factors ``[room, x, y, z]`` of the three pairs (a ray trace).

    Parameters
    ----------
    coils : coils.ThreeAxisHelmholtz
        The coil set.

    Returns
    -------
    ndarray, shape (3, 4)
        View factors, dimensionless.
    """
    from coils.viewfactors import view_factors

    return view_factors(pack_rings(coils))


def precompute(model: DesignModel) -> Constants:
    """Reduce coils, headings and workspace to the constants of the margin and the limits.

    Parameters
    ----------
    model : DesignModel
        The design.

    Returns
    -------
    Constants
        The reduced constants, SI.
    """
    import capsule as cap

    pairs = model.coils.pairs
    g = np.asarray(model.coils.centre_gains_T_per_A, dtype=float)
    # each pair's own R and L (a lab's measured pair answers its measured values)
    r20 = np.array([p.resistance_ohm(20.0) for p in pairs])
    ind = np.array([p.series_inductance_H for p in pairs])
    packs = packs_of(model)
    n2 = np.asarray(model.headings, dtype=float) ** 2  # (h, 3)
    s = np.sqrt(np.clip(1.0 - n2, 0.0, 1.0))  # (h, 3)
    per_heading = s / g
    actuation = getattr(model.coils, "actuation_matrix_T_per_A", None)
    if actuation is not None:  # calibrated coils (coils.calibration): A^-1 of the real set
        from coils.rotating import allocation

        per_heading = np.array([allocation(actuation, h, 1.0)[0] for h in model.headings])
    current_per_T = np.max(per_heading, axis=0)
    field = model.coils.field_matrix(model.points_m)  # the same points for every heading
    factor = min(
        float(np.min(model.coils.rotating_field_semi_axes_T(model.points_m, h, 1.0, field)[0]))
        for h in model.headings
    )
    body, spiral = model.capsule.body, model.capsule.spiral
    return Constants(
        gains_T_per_A=g,
        resistance_20C_ohm=r20,
        inductance_H=ind,
        packs=packs,
        current_per_tesla_A_per_T=current_per_T,
        power_weights_per_T2=s**2 / (2.0 * g**2) if actuation is None else 0.5 * per_heading**2,
        workspace_factor=factor,
        moment_Am2=float(model.capsule.magnet.moment_Am2),
        body_diameter_m=body.diameter_m,
        body_length_m=body.length_m,
        wire_diameter_m=spiral.wire_diameter_m,
        wound_length_m=spiral.wound_length_m,
        helix_diameter_m=float(cap.helix_diameter_m(body.diameter_m, spiral.wire_diameter_m)),
        copper_mass_kg=np.array([p.copper_mass_kg for p in pairs]),
        heading_current_per_tesla_A_per_T=per_heading,
        starts=int(spiral.starts),
        winding_temperature_C=model.winding_temperature_C,
        session_s=model.session_s,
        view_factors=view_factors_of(model.coils),
        mass_kg=float(model.capsule.mass_kg),
    )


@guard(model=MODEL)
def prepare(model: DesignModel) -> DesignModel:
    """The model with its :class:`Constants` computed (returned unchanged if already there).

    Parameters
    ----------
    model : DesignModel
        The design.

    Returns
    -------
    DesignModel
        The same design with ``constants`` set.

    Examples
    --------
    The built-in design (``spiralcap evaluate`` with no file), assembled and prepared:

    >>> from optimize import prepare
    >>> from spiralcap.assemble import build_model
    >>> from spiralcap.design import load_design
    >>> model = prepare(build_model(load_design(None, [])))
    >>> print(model.constants is not None, model.limits.current_A, "A")
    True 15.0 A
    """
    if model.constants is not None:
        return model
    from dataclasses import replace

    return replace(model, constants=precompute(model))
