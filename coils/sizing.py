"""Per-axis electrical and thermal sizing of a three-axis system at one current and frequency.

For each pair at current amplitude I and frequency f: the self-consistent steady thermal state
(:func:`coils.thermal.steady_state`: surface, mean and hot-spot temperatures, resistance at the
mean winding temperature), series L, |Z|, voltage amplitude |Z| I, copper loss R I²/2, heat
capacity and lumped time constant, and the rotating field the pairs make at that current for
the worst heading (at the centre axis k needs A_k = B0 sqrt(1 - n_k²)/g_k, so the heading ⟂
axis k asks the most of it and the worst-case amplitude at current I is min_k g_k I; the axes
within 1e-9 of the minimum are all reported). The total copper loss is that of the heading that
draws the most at the current limit (each heading driven at the largest field its most loaded
axis allows), not all three axes at full current, which no rotating field asks for. What the
voltage, power, temperature and exposure limits then allow is not computed here: it is
:func:`optimize.physics.field_capacity_T`, the one definition of the limits that ``evaluate``
and ``optimize`` use.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from coils.electrical import impedance_ohm
from coils.system import ThreeAxisHelmholtz
from coils.thermal import WindingPack
from coils.thermal_system import mean_rise_at_K, pair_temperatures
from spiralcap.core.checks import guard, instance, nonnegative, positive, temperature, unit_interval
from spiralcap.core.constants import COPPER_TEMPERATURE_COEFFICIENT_per_K

__all__ = ["AxisSizing", "SystemSizing", "WorstHeading", "size_system", "winding_pack"]


@dataclass(frozen=True)
class AxisSizing:
    """Sizing of one pair (both coils in series) at the operating point; names carry units.

    Temperatures are the steady, self-consistent state at this current (NaN if the pair runs
    away thermally); ``time_constant_s`` is the lumped τ of :func:`coils.thermal.transient`.
    ``field_per_amp_T_per_A`` is the field model's centre gain (each coil one loop at its mean
    radius, as a design builds it; ``field_amplitude_T`` is it times the current),
    ``pack_field_per_amp_T_per_A`` the same with the current spread over the winding pack.

    A square pair (``shape`` "square") has its mean turn's side in ``side_m`` and half of it in
    ``radius_m`` (:attr:`coils.SquarePair.radius_m`); a circle has ``side_m`` None.

    Attributes
    ----------
    axis : str
        ``"x"``, ``"y"`` or ``"z"``.
    radius_m : float
        Mean coil radius R, m.
    separation_m : float
        Distance between the coil planes, m.
    turns : int
        Turns of each coil, count.
    wire_diameter_m : float
        Bare copper diameter, m.
    winding_pack_side_m, winding_pack_width_m, winding_pack_depth_m : float
        Side of the square of the pack's area, its axial width and its radial depth, m.
    pack_aspect : float
        Axial width / radial depth of the pack, dimensionless.
    wire_length_m : float
        Wire length of both coils, m.
    copper_mass_kg : float
        Copper mass of both coils, kg.
    field_per_amp_T_per_A : float
        Centre field per ampere of the field model (each coil one loop at its mean radius), T/A.
    pack_field_per_amp_T_per_A : float
        The same with the current spread over the winding pack, T/A.
    current_amplitude_A : float
        The current amplitude this pair is sized at (its amplifier channel's limit), A.
    resistance_20C_ohm, resistance_ohm : float
        Resistance of the pair at 20 °C and at its mean winding temperature, Ω (the pair's
        own: a lab's measured pair answers its measured value).
    self_inductance_H, mutual_inductance_H, inductance_H : float
        Self inductance of one coil, mutual inductance of the two (both from the geometry),
        series inductance of the pair (the pair's own, measured where given), H.
    impedance_ohm : float
        Series R-L impedance magnitude at the drive frequency, Ω.
    voltage_amplitude_V : float
        Drive voltage amplitude, V.
    power_W : float
        Mean copper loss of the pair, W.
    surface_conductance_W_per_K : float
        Surface area times effective coefficient (convection and radiation), W/K.
    surface_temperature_C, mean_temperature_C, hot_spot_temperature_C : float
        Steady mean surface, mean winding and hottest winding temperature, °C (NaN: runaway).
    temperature_rise_K : float
        Hot spot above ambient, K.
    heat_capacity_J_per_K : float
        Heat capacity of both packs, J/K.
    time_constant_s : float
        Lumped thermal time constant, s.
    field_amplitude_T : float
        Centre field at the current amplitude, T.
    surface_max_temperature_C : float
        Hottest point of the pack's faces, °C.
    convection_coefficient_W_m2K : float
        Convective part of the face coefficient, W/(m²·K).
    radiation_view_factor : float
        Fraction of the pack's radiation that reaches the room, dimensionless (1: alone).
    shape : str
        ``"circle"``, ``"square"`` or ``"rectangle"``.
    side_m : float or None
        Mean turn's side of a square pair, m (None: another shape).
    sides_m : tuple of float or None
        Mean turn's sides (a, b) of a rectangular pair, m (None: another shape).
    """

    axis: str
    radius_m: float
    separation_m: float
    turns: int
    wire_diameter_m: float
    winding_pack_side_m: float
    winding_pack_width_m: float
    winding_pack_depth_m: float
    pack_aspect: float
    wire_length_m: float
    copper_mass_kg: float
    field_per_amp_T_per_A: float
    resistance_20C_ohm: float
    resistance_ohm: float
    self_inductance_H: float
    mutual_inductance_H: float
    inductance_H: float
    impedance_ohm: float
    voltage_amplitude_V: float
    power_W: float
    surface_conductance_W_per_K: float
    surface_temperature_C: float
    mean_temperature_C: float
    hot_spot_temperature_C: float
    temperature_rise_K: float
    heat_capacity_J_per_K: float
    time_constant_s: float
    field_amplitude_T: float
    surface_max_temperature_C: float = math.nan
    convection_coefficient_W_m2K: float = math.nan
    radiation_view_factor: float = 1.0
    pack_field_per_amp_T_per_A: float = math.nan
    shape: str = "circle"
    side_m: float | None = None
    sides_m: tuple[float, float] | None = None
    current_amplitude_A: float = math.nan


@dataclass(frozen=True)
class WorstHeading:
    """The heading drawing the most copper loss with its busiest axis at the current limit.

    Attributes
    ----------
    heading : tuple of float
        Unit heading of the rotation axis, dimensionless.
    field_amplitude_T : float
        Rotating field amplitude at which its busiest axis reaches the current limit, T.
    current_amplitudes_A : tuple of float
        Current amplitude of each pair (x, y, z), A.
    total_power_W : float
        Copper loss of the three pairs, W (NaN: a pair runs away).
    """

    heading: tuple[float, float, float]
    field_amplitude_T: float
    current_amplitudes_A: tuple[float, float, float]
    total_power_W: float


@dataclass(frozen=True)
class SystemSizing:
    """Sizing of the three pairs and the worst-heading rotating field at the given current.

    Attributes
    ----------
    frequency_hz : float
        Drive frequency, Hz.
    current_amplitude_A : float
        Current amplitude of every pair (the current limit), A.
    ambient_temperature_C : float
        Air temperature, °C.
    heat_transfer_coefficient_W_m2K : float or None
        Fixed face coefficient, W/(m²·K) (None: the packs' correlations).
    winding_conductivity_W_mK : float
        Effective transverse conductivity of the packs, W/(m·K).
    surface_emissivity : float
        Grey-body emissivity of the winding surface, dimensionless.
    axes : tuple of AxisSizing
        The x, y and z pairs.
    worst_heading : WorstHeading
        The heading with the most copper loss.
    total_power_W : float
        Copper loss at the worst heading, W.
    current_limited_rotating_field_T : float
        Weakest pair's centre field at the current limit, T.
    current_limiting_axes : tuple of str
        The pairs that reach it.
    cooling : str
        Cooling mode of the packs (one of :data:`coils.thermal.CONVECTION_MODES`).
    """

    frequency_hz: float
    current_amplitude_A: float
    ambient_temperature_C: float
    heat_transfer_coefficient_W_m2K: float | None
    winding_conductivity_W_mK: float
    surface_emissivity: float
    axes: tuple[AxisSizing, AxisSizing, AxisSizing]
    worst_heading: WorstHeading
    total_power_W: float
    current_limited_rotating_field_T: float
    current_limiting_axes: tuple[str, ...]
    cooling: str = "fixed"


def winding_pack(
    pair, conductivity_W_mK: float, heat_transfer_coefficient_W_m2K: float, emissivity: float
) -> WindingPack:
    """The :class:`coils.thermal.WindingPack` of a :class:`coils.HelmholtzPair` (or a
    :class:`coils.SquarePair`: a ring of its mean turn's length, the same volume and faces).

    Parameters
    ----------
    pair : HelmholtzPair
        The pair (its pack geometry and packing factor).
    conductivity_W_mK : float
        Effective transverse conductivity of the pack, W/(m·K).
    heat_transfer_coefficient_W_m2K : float
        Face coefficient, W/(m²·K).
    emissivity : float
        Grey-body emissivity of the winding surface, dimensionless.

    Returns
    -------
    WindingPack
        One coil's pack, SI.
    """
    return WindingPack(
        pack_width_m=pair.winding_pack_width_m,
        pack_depth_m=pair.winding_pack_depth_m,
        mean_radius_m=pair.turn_radius_m,
        packing_factor=pair.packing_factor,
        conductivity_W_mK=conductivity_W_mK,
        heat_transfer_coefficient_W_m2K=heat_transfer_coefficient_W_m2K,
        emissivity=emissivity,
    )


@guard(
    system=instance(ThreeAxisHelmholtz, "a coils.ThreeAxisHelmholtz"),
    frequency_hz=nonnegative(scalar=True),
    ambient_temperature_C=temperature(scalar=True),
    heat_transfer_coefficient_W_m2K=positive(optional=True, scalar=True),
    winding_conductivity_W_mK=positive(scalar=True),
    surface_emissivity=unit_interval(scalar=True),
)
def size_system(
    system: ThreeAxisHelmholtz,
    *,
    frequency_hz: float,
    current_amplitude_A: float | tuple[float, ...],
    ambient_temperature_C: float,
    heat_transfer_coefficient_W_m2K: float | None,
    winding_conductivity_W_mK: float = 0.5,
    surface_emissivity: float = 0.9,
    headings: np.ndarray | None = None,
    packs: tuple | None = None,
    view_factors: np.ndarray | None = None,
) -> SystemSizing:
    """Evaluate every pair at one current amplitude and frequency.

    Parameters
    ----------
    system : ThreeAxisHelmholtz
        The coils.
    frequency_hz : float
        Drive frequency, Hz.
    current_amplitude_A : float or tuple of 3 floats
        Current amplitude of every pair, and the current limit, A; or one per pair (x, y, z:
        each pair's own amplifier channel).
    ambient_temperature_C : float
        Air temperature, °C.
    heat_transfer_coefficient_W_m2K : float or None
        Convective coefficient from the winding surface, W/(m²·K) (None: ``packs`` says).
    winding_conductivity_W_mK : float
        Effective transverse conductivity of the packs, W/(m·K).
    surface_emissivity : float
        Grey-body emissivity of the winding surface, dimensionless.
    headings : ndarray, shape (h, 3), optional
        Unit headings for the worst-heading total, dimensionless (default: the three axes).
    packs : tuple of coils.thermal.WindingPack, optional
        The packs as cooled (convection correlations, forced air); default: a fixed
        ``heat_transfer_coefficient_W_m2K``.
    view_factors : ndarray (3, 4), optional
        View factors, dimensionless, rows ``[room, x, y, z]``
        (:func:`coils.viewfactors.view_factors`): the three pairs, all at this current,
        radiate to each other; default: each alone in the room.

    Returns
    -------
    SystemSizing
        Every pair's electrical and thermal state and the worst-heading total, SI.

    Examples
    --------
    Three nested pairs at 10 A and 10 Hz, with 10 W/(m² K) convection in 20 °C air:

    >>> from coils import HelmholtzPair, ThreeAxisHelmholtz, size_system
    >>> coils = ThreeAxisHelmholtz(
    ...     HelmholtzPair(0.4, 400, "x"), HelmholtzPair(0.35, 350, "y"), HelmholtzPair(0.3, 300, "z")
    ... )
    >>> s = size_system(coils, frequency_hz=10.0, current_amplitude_A=10.0,
    ...                 ambient_temperature_C=20.0, heat_transfer_coefficient_W_m2K=10.0)
    >>> x = s.axes[0]
    >>> print(f"x pair: {x.wire_length_m:.0f} m of wire, {x.resistance_ohm:.2f} ohm warm, "
    ...       f"{x.voltage_amplitude_V:.0f} V, {x.power_W:.0f} W, hot spot {x.hot_spot_temperature_C:.1f} C")
    x pair: 2011 m of wire, 7.89 ohm warm, 343 V, 394 W, hot spot 56.1 C
    """
    axes = []
    states = []
    if packs is None:
        if heat_transfer_coefficient_W_m2K is None:
            raise ValueError("size_system needs packs or a heat_transfer_coefficient_W_m2K")
        packs = tuple(
            winding_pack(
                pair,
                winding_conductivity_W_mK,
                heat_transfer_coefficient_W_m2K,
                surface_emissivity,
            )
            for pair in system.pairs
        )
    amps = _pair_currents(current_amplitude_A)
    # each pair's own R and L (a lab's measured pair answers its measured values)
    r20s = [pair.resistance_ohm(20.0) for pair in system.pairs]
    inductances = [pair.series_inductance_H for pair in system.pairs]
    together = pair_temperatures(packs, r20s, amps, ambient_temperature_C, view_factors)
    for k, pair in enumerate(system.pairs):
        pack, r20, st = packs[k], r20s[k], together[k]
        if float(st.runaway) > 0.5:  # no steady state: report NaN, not the bounding iterate
            st = type(st)(*(math.nan,) * 11, runaway=1.0)
        states.append((together[k], r20))
        r = r20 * (1.0 + COPPER_TEMPERATURE_COEFFICIENT_per_K * (float(st.mean_C) - 20.0))
        z = float(impedance_ohm(r, inductances[k], frequency_hz))
        g = pair.centre_field_per_amp_T_per_A
        axes.append(
            AxisSizing(
                axis=pair.axis,
                shape=pair.shape,
                side_m=pair.size_keys.get("side_m"),
                sides_m=pair.size_keys.get("sides_m"),
                radius_m=pair.radius_m,
                separation_m=pair.spacing_m,
                turns=pair.turns,
                wire_diameter_m=pair.wire_diameter_m,
                winding_pack_side_m=pair.winding_pack_side_m,
                winding_pack_width_m=pair.winding_pack_width_m,
                winding_pack_depth_m=pair.winding_pack_depth_m,
                pack_aspect=pair.pack_aspect,
                wire_length_m=pair.wire_length_m,
                copper_mass_kg=pair.copper_mass_kg,
                field_per_amp_T_per_A=g,
                resistance_20C_ohm=r20,
                resistance_ohm=r,
                self_inductance_H=pair.self_inductance_H,
                mutual_inductance_H=pair.mutual_inductance_H,
                inductance_H=inductances[k],
                impedance_ohm=z,
                voltage_amplitude_V=z * amps[k],
                power_W=float(st.power_W),
                surface_conductance_W_per_K=float(pack.surface_area_m2 * st.effective_h_W_m2K),
                surface_temperature_C=float(st.surface_C),
                mean_temperature_C=float(st.mean_C),
                hot_spot_temperature_C=float(st.hot_spot_C),
                temperature_rise_K=float(st.hot_spot_C) - ambient_temperature_C,
                heat_capacity_J_per_K=float(pack.heat_capacity_J_per_K),
                time_constant_s=float(st.time_constant_s),
                surface_max_temperature_C=float(st.surface_max_C),
                convection_coefficient_W_m2K=float(st.convection_W_m2K),
                radiation_view_factor=1.0 if view_factors is None else float(view_factors[k][0]),
                # the set's own centre gain: a calibrated set's (coils.calibration), else g
                field_amplitude_T=float(system.centre_gains_T_per_A[k]) * amps[k],
                pack_field_per_amp_T_per_A=pair.pack_centre_field_per_amp_T_per_A,
                current_amplitude_A=amps[k],
            )
        )
    weakest = min(a.field_amplitude_T for a in axes)
    tied = tuple(a.axis for a in axes if a.field_amplitude_T <= weakest * (1.0 + 1e-9))
    worst = _worst_heading(system, states, amps, ambient_temperature_C, headings)
    return SystemSizing(
        frequency_hz=frequency_hz,
        current_amplitude_A=max(amps),
        ambient_temperature_C=ambient_temperature_C,
        heat_transfer_coefficient_W_m2K=heat_transfer_coefficient_W_m2K,
        winding_conductivity_W_mK=winding_conductivity_W_mK,
        surface_emissivity=surface_emissivity,
        axes=(axes[0], axes[1], axes[2]),
        worst_heading=worst,
        total_power_W=worst.total_power_W,
        current_limited_rotating_field_T=weakest,
        current_limiting_axes=tied,
        cooling=packs[0].convection,
    )


def _pair_currents(current_amplitude_A: float | tuple[float, ...]) -> tuple[float, float, float]:
    """The three pairs' current amplitudes, A: one for all, or one per pair (each > 0, finite)."""
    from spiralcap.core.checks import positive_finite

    if np.ndim(current_amplitude_A) == 0:
        one = positive_finite("current_amplitude_A", current_amplitude_A)
        return (one, one, one)
    amps = tuple(float(a) for a in np.asarray(current_amplitude_A, dtype=float).ravel())
    if len(amps) != 3:
        raise ValueError(
            f"current_amplitude_A = {current_amplitude_A!r}: one current, or three (x, y, z), A"
        )
    for ax, a in zip("xyz", amps):
        positive_finite(f"current_amplitude_A[{ax}]", a)
    return (amps[0], amps[1], amps[2])


def _worst_heading(
    system: ThreeAxisHelmholtz,
    states: list,
    current_A: tuple[float, float, float],
    ambient_C: float,
    headings: np.ndarray | None,
) -> WorstHeading:
    """Per heading: the field at which its busiest axis reaches the current limit, the currents
    (A_k = B0 sqrt(1 - n_k²)/g_k) and their self-consistent copper loss (each pair's faces
    linearised at its state at the current limit: :func:`coils.thermal_system.mean_rise_at_K`);
    the largest loss."""
    h = np.eye(3) if headings is None else np.asarray(headings, dtype=float)
    h = h / np.linalg.norm(h, axis=1, keepdims=True)
    g = np.asarray(system.centre_gains_T_per_A, dtype=float)  # calibrated where calibrated
    per_T = np.sqrt(np.clip(1.0 - h**2, 0.0, 1.0)) / g  # (h, 3) A per T
    with np.errstate(divide="ignore"):  # an axis a heading does not use caps nothing
        field = np.min(np.asarray(current_A)[None, :] / per_T, axis=1)
    currents = field[:, None] * per_T
    loss = np.zeros(h.shape[0])
    for k, (state, r20) in enumerate(states):
        rise = np.asarray(mean_rise_at_K(state, r20, currents[:, k], ambient_C), dtype=float)
        r = r20 * (1.0 + COPPER_TEMPERATURE_COEFFICIENT_per_K * (ambient_C + rise - 20.0))
        bad = float(state.runaway) > 0.5
        loss = loss + np.where(bad, np.nan, 0.5 * r * currents[:, k] ** 2)
    i = int(np.argmax(np.where(np.isnan(loss), np.inf, loss)))  # NaN: thermal runaway
    return WorstHeading(
        heading=(float(h[i, 0]), float(h[i, 1]), float(h[i, 2])),
        field_amplitude_T=float(field[i]),
        current_amplitudes_A=(
            float(currents[i, 0]),
            float(currents[i, 1]),
            float(currents[i, 2]),
        ),
        total_power_W=float(loss[i]),
    )
