"""The one definition of the margin, the requirements and the limits.

Every function here is written once against :mod:`spiralcap.core.backend` and takes the operating
variables — helical angle ``alpha`` (rad), rotation frequency ``f`` (Hz), rotating-field
amplitude at the centre ``B0`` (T) — as floats, numpy arrays (vectorised sweeps) or CasADi
symbols (the optimiser). :mod:`optimize.evaluate` and :mod:`optimize.problem` both build on it,
so ``evaluate`` at the optimiser's answer reports the optimiser's margin.

Limits are written ``value(f, B0) <= allowed``, most with ``value`` proportional to
``B0**power``, so the largest field a frequency allows is ``min over limits of
(allowed / value(f, 1)) ** (1 / power)``; the one that is not a power law (the hot spot at the
end of a session, ``power`` None) is inverted by bisection on the same expression.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

import capsule as cap
import torque_model as tm
from optimize.system import Constants, Limits, Requirements
from spiralcap.core import backend as bk
from spiralcap.core.checks import choice, guard, positive

#: ICNIRP (2010) "Guidelines for limiting exposure to time-varying electric and magnetic fields
#: (1 Hz to 100 kHz)", Health Phys. 99(6):818-836, Tables 3 and 4: reference levels for the
#: magnetic flux density (rms), T, as (a, b, c): a/f² for 1-8 Hz, b/f for 8-25 Hz, c above 25 Hz
#: (up to 300 Hz occupational, 50 Hz public; the next band is not needed at these frequencies).
ICNIRP2010_LEVELS_T = {"occupational": (0.2, 2.5e-2, 1e-3), "public": (4e-2, 5e-3, 2e-4)}


@guard(frequency_hz=positive(), kind=choice("occupational", "public"))
def exposure_level_T(frequency_hz: Any, kind: str) -> Any:
    """ICNIRP 2010 reference level (rms flux density, T) at ``frequency_hz``.

    The guideline starts at 1 Hz; below it the 1 Hz value is held (conservative and continuous).
    The rms of a circularly rotating field equals its amplitude, so the level bounds ``B0``.

    Parameters
    ----------
    frequency_hz : float, array or CasADi
        Rotation frequency, Hz.
    kind : str
        ``"occupational"`` or ``"public"``.

    Returns
    -------
    float, array or CasADi
        Reference level, T (rms).

    Examples
    --------
    ICNIRP 2010's occupational level at 4 Hz (a / f² below 8 Hz) and above 25 Hz (flat), and the
    general public's at 4 Hz:

    >>> from optimize import exposure_level_T
    >>> for f, kind in ((4.0, "occupational"), (50.0, "occupational"), (4.0, "public")):
    ...     print(f"{kind} at {f:g} Hz: {float(exposure_level_T(f, kind)) * 1e3:.3f} mT")
    occupational at 4 Hz: 12.500 mT
    occupational at 50 Hz: 1.000 mT
    public at 4 Hz: 2.500 mT
    """
    a, b, c = ICNIRP2010_LEVELS_T[kind]
    f = bk.fmax(frequency_hz, 1.0)
    return bk.where(f < 8.0, a / (f * f), bk.where(f < 25.0, b / f, c))


@dataclass(frozen=True)
class LimitTerm:
    """One limit at one operating point: ``value <= allowed`` (units in ``unit``).

    Attributes
    ----------
    name : str
        Name of the limit (``current_x``, ``power``, ``hot_spot_z``, ...).
    unit : str
        Unit symbol of ``value`` and ``allowed`` (A, V, W, K, T).
    value : float, array or CasADi
        The limited quantity, in the unit ``unit`` names.
    allowed : float, array or CasADi
        Its limit, in the unit ``unit`` names.
    power : int or None
        Exponent of B0 in ``value`` (a count; None: not a power law).
    """

    name: str
    unit: str
    value: Any
    allowed: Any
    power: int | None

    @property
    def utilisation(self) -> Any:
        """value / allowed, dimensionless (1 means the limit binds)."""
        return self.value / self.allowed


_AXES = ("x", "y", "z")


def _field_key(x: Any) -> Any:
    if bk.is_casadi(x):
        return ("node", x.element_hash()) if x.numel() == 1 else None
    if np.ndim(x) == 0:
        return ("num", float(x))
    return None


def pair_states(
    field_T: Any, c: Constants, ambient_temperature_C: Any, only: int | None = None
) -> list[Any]:
    """:class:`coils.thermal_system.PairTemperatures` of the three pairs at centre field
    ``field_T``, each at its worst-heading current, radiating to each other (steady, or at the
    end of the session); ``only``: that pair alone (the others None, same numbers).

    Parameters
    ----------
    field_T : float or CasADi
        Rotating-field amplitude at the centre, T.
    c : Constants
        The design's constants.
    ambient_temperature_C : float or CasADi
        Ambient air, °C.
    only : int, optional
        Index of the one pair to solve (0, 1, 2), or None for all three.

    Returns
    -------
    list of coils.thermal_system.PairTemperatures or None
        One per pair (x, y, z); °C, W, s.
    """
    from optimize import thermal_states

    # kept in the constants' own memo (Constants.memo.states): within one NLP build the same
    # field node asks twice (the limits and the loss rows); with numbers the same scalar field
    # recurs across the caps
    memo: dict = getattr(getattr(c, "memo", None), "states", {})
    fk, ak = _field_key(field_T), _field_key(ambient_temperature_C)
    key = None if fk is None or ak is None else (fk, ak)
    if key is not None:
        hit = memo.get(key)
        if hit is not None:
            return hit
        if only is not None:
            hit = memo.get((*key, only))
            if hit is not None:
                return hit
    states = thermal_states.states(
        field_T,
        ambient_temperature_C,
        c.current_per_tesla_A_per_T,
        c.resistance_20C_ohm,
        c.packs,
        c.view_factors,
        c.session_s,
        only,
    )
    if key is not None:
        if len(memo) > 512:
            memo.clear()
        memo[key if only is None else (*key, only)] = states
    return states


def pair_state(current_A: Any, k: int, c: Constants, ambient_temperature_C: Any) -> Any:
    """Pair k of :func:`pair_states` at the field where its worst heading carries ``current_A``
    (the other pairs at their worst-heading currents of that field).

    Parameters
    ----------
    current_A : float or CasADi
        Worst-heading current amplitude of pair k, A.
    k : int
        Index of the pair (0, 1, 2 for x, y, z).
    c : Constants
        The design's constants.
    ambient_temperature_C : float or CasADi
        Ambient air, °C.

    Returns
    -------
    coils.thermal_system.PairTemperatures
        Pair k's temperatures, °C.
    """
    per = c.current_per_tesla_A_per_T
    field = current_A / bk.fmax(per[k], 1e-300)
    return pair_states(field, c, ambient_temperature_C, only=k)[k]


def winding_temperatures_C(
    current_A: Any, k: int, c: Constants, ambient_temperature_C: Any
) -> tuple[Any, Any, Any]:
    """(surface, mean, hot spot) of axis k at a current amplitude, °C: steady or session end.

    Parameters
    ----------
    current_A : float or CasADi
        Current amplitude of pair k, A.
    k : int
        Index of the pair (0, 1, 2 for x, y, z).
    c : Constants
        The design's constants.
    ambient_temperature_C : float or CasADi
        Ambient air, °C.

    Returns
    -------
    surface_C, mean_C, hot_spot_C : float or CasADi
        Mean face, mean winding and hottest winding temperature, °C.
    """
    s = pair_state(current_A, k, c, ambient_temperature_C)
    return s.surface_C, s.mean_C, s.hot_spot_C


def winding_resistance_ohm(
    current_A: Any, k: int, c: Constants, ambient_temperature_C: Any, state: Any = None
) -> Any:
    """Resistance of pair k carrying ``current_A``, Ω: at its own mean winding temperature.

    Self-consistent with the heating (steady, or at the end of the session), or at
    ``c.winding_temperature_C`` if the design fixes the copper temperature. ``state``: pair
    k's :class:`coils.thermal_system.PairTemperatures` at the field's worst-heading current, if
    the current is a lighter heading's (its faces linearised there,
    :func:`coils.thermal_system.mean_rise_at_K`).

    Parameters
    ----------
    current_A : float, array or CasADi
        Current amplitude of pair k, A.
    k : int
        Index of the pair (0, 1, 2 for x, y, z).
    c : Constants
        The design's constants.
    ambient_temperature_C : float or CasADi
        Ambient air, °C.
    state : coils.thermal_system.PairTemperatures, optional
        Pair k's state at the field's worst-heading current (for a lighter heading's current).

    Returns
    -------
    float, array or CasADi
        Resistance of the pair, Ω.
    """
    if c.winding_temperature_C is not None:
        return _resistance_at(None, k, c)
    if state is None:
        mean_C = winding_temperatures_C(current_A, k, c, ambient_temperature_C)[1]
    else:
        from coils.thermal_system import mean_rise_at_K

        rise = mean_rise_at_K(state, c.resistance_20C_ohm[k], current_A, ambient_temperature_C)
        mean_C = ambient_temperature_C + rise
    return _resistance_at(mean_C, k, c)


def _resistance_at(mean_C: Any, k: int, c: Constants) -> Any:
    """R of pair k at the mean winding temperature ``mean_C`` (or the design's fixed one)."""
    from coils.electrical import copper_resistivity_ohm_m
    from spiralcap.core.constants import COPPER_RESISTIVITY_20C_ohm_m

    temp = mean_C if c.winding_temperature_C is None else c.winding_temperature_C
    return c.resistance_20C_ohm[k] * copper_resistivity_ohm_m(temp) / COPPER_RESISTIVITY_20C_ohm_m


def hot_spot_rise_K(current_A: Any, k: int, c: Constants, ambient_temperature_C: float) -> Any:
    """Hot-spot rise of axis k above ambient at current amplitude ``current_A``, K.

    Steady (``c.session_s`` None): :func:`coils.thermal.steady_state` (self-consistent
    resistance, convection and radiation to the room and the other pairs). With a session:
    conduction in the pack from ambient to the end of the session (:func:`coils.thermal.
    transient`). Beyond thermal runaway the rise is a finite upper bound far above any limit
    (coils.thermal.steady_state). Increasing in the current.

    Parameters
    ----------
    current_A : float, array or CasADi
        Current amplitude of axis k, A.
    k : int
        Index of the pair (0, 1, 2 for x, y, z).
    c : Constants
        The design's constants.
    ambient_temperature_C : float
        Ambient air, °C.

    Returns
    -------
    float, array or CasADi
        Hot-spot rise above ambient, K.
    """
    return winding_temperatures_C(current_A, k, c, ambient_temperature_C)[2] - ambient_temperature_C


def _number(x: Any) -> float | None:
    """``x`` as a float if it is a plain number (numpy or CasADi constant), else None."""
    if bk.is_casadi(x):
        return float(x) if x.numel() == 1 and x.is_constant() else None
    if np.ndim(x) != 0:
        return None
    return float(x)


def heading_losses_W(
    field_T: Any,
    c: Constants,
    ambient_temperature_C: Any,
    states: list | None = None,
) -> list[Any]:
    """Copper loss of every heading, Σ_k R_k(I_hk) I_hk² / 2, W (backend-generic).

    I_hk = B0 · ``c.heading_current_per_tesla_A_per_T[h, k]`` (sqrt(1 - n_hk²) / g_k), each
    pair at its own self-consistent resistance (:func:`winding_resistance_ohm`). With numbers,
    every heading at once, pair by pair. (A memo of the resistances of recurring currents, keyed
    on CasADi node hashes, saved nothing measurable and was retired: issue 38.)

    Parameters
    ----------
    field_T : float or CasADi
        Rotating-field amplitude at the centre, T.
    c : Constants
        The design's constants.
    ambient_temperature_C : float or CasADi
        Ambient air, °C.
    states : list of PairTemperatures, optional
        The three pairs' states at ``field_T`` if the caller has them.

    Returns
    -------
    list of float or CasADi
        Copper loss of each heading, W.
    """
    a = c.heading_current_per_tesla_A_per_T
    if states is None and c.winding_temperature_C is None:
        states = pair_states(field_T, c, ambient_temperature_C)
    if states is None:
        states = [None, None, None]
    if isinstance(a, np.ndarray) and _number(field_T) is not None:
        if _number(ambient_temperature_C) is not None:
            return _heading_losses_of_numbers(field_T, c, ambient_temperature_C, states)
    out: list[Any] = []
    rows = a.tolist() if isinstance(a, np.ndarray) else None  # numbers: plain floats, same values
    for h in range(a.shape[0]):
        loss: Any = 0.0
        for k in range(3):
            per_amp = rows[h][k] if rows is not None else a[h, k]
            num = per_amp if rows is not None else _number(per_amp)
            if num is not None and num <= 0:
                continue
            cur = field_T * per_amp
            r = winding_resistance_ohm(cur, k, c, ambient_temperature_C, states[k])
            loss = loss + 0.5 * r * cur * cur
        out.append(loss)
    return out


def _heading_losses_of_numbers(
    field_T: Any, c: Constants, ambient_temperature_C: Any, states: list
) -> list[float]:
    """:func:`heading_losses_W` with numbers: every heading at once, pair by pair (the same
    operations on each heading's current, elementwise: the same bits)."""
    a = np.asarray(c.heading_current_per_tesla_A_per_T, dtype=float)
    field = float(field_T)
    total = np.zeros(a.shape[0])
    for k in range(3):
        cur = field * a[:, k]
        r = np.asarray(
            winding_resistance_ohm(cur, k, c, ambient_temperature_C, states[k]), dtype=float
        )
        total = total + np.where(a[:, k] > 0, 0.5 * r * cur * cur, 0.0)
    return total.tolist()


def total_loss_W(
    field_T: Any,
    c: Constants,
    ambient_temperature_C: Any,
    states: list | None = None,
) -> Any:
    """Copper loss of the heading that draws the most, max_h Σ_k R_k(I_hk) I_hk² / 2, W.

    See :func:`heading_losses_W`; the resistance is each pair's at its own mean winding
    temperature at that current (steady or at the end of the session).

    Parameters
    ----------
    field_T : float or CasADi
        Rotating-field amplitude at the centre, T.
    c : Constants
        The design's constants.
    ambient_temperature_C : float or CasADi
        Ambient air, °C.
    states : list of PairTemperatures, optional
        The three pairs' states at ``field_T`` if the caller has them.

    Returns
    -------
    float or CasADi
        Worst-heading copper loss, W.
    """
    worst: Any = None
    for loss in heading_losses_W(field_T, c, ambient_temperature_C, states):
        worst = loss if worst is None else bk.fmax(worst, loss)
    return worst


def limit_terms(
    frequency_hz: Any,
    field_T: Any,
    c: Constants,
    limits: Limits,
    ambient_temperature_C: Any,
    *,
    loss_W: Any = None,
) -> list[LimitTerm]:
    """Every hardware and exposure limit at rotation frequency ``f`` and centre field ``B0``.

    Per axis k the worst-heading current amplitude is ``I_k = B0 * current_per_tesla[k]``; its
    drive voltage ``|R_k + j 2πf L_k| I_k`` (coils.voltage_amplitude_V) with R_k from
    :func:`winding_resistance_ohm`, each pair at its own self-consistent mean winding
    temperature; the total copper loss is that of the worst heading (:func:`total_loss_W`); the
    exposure level is ICNIRP 2010's.

    The temperature limit applies to the winding hot spot, steady or at the end of a session
    (:func:`hot_spot_rise_K`): term ``hot_spot_k``, the rise above ambient in K, not a power law
    of the field (``power`` None).

    Every argument may be a number, a numpy array or a CasADi value (the NLP builds the same
    terms with its variables and parameters). ``loss_W``: the worst-heading loss if the caller
    has it already (the sizing NLP's epigraph variable); default :func:`total_loss_W`.

    Parameters
    ----------
    frequency_hz : float, array or CasADi
        Rotation frequency f, Hz.
    field_T : float, array or CasADi
        Rotating-field amplitude at the centre B0, T.
    c : Constants
        The design's constants.
    limits : Limits
        The limits, SI.
    ambient_temperature_C : float or CasADi
        Ambient air, °C.
    loss_W : float or CasADi, optional
        Worst-heading copper loss if already known, W.

    Returns
    -------
    list of LimitTerm
        One term per limit and axis, each in its own unit.
    """
    terms: list[LimitTerm] = []
    fixed_r = c.winding_temperature_C is not None  # then every term but the hot spot is a power law
    amb = ambient_temperature_C
    states = pair_states(field_T, c, amb)  # the three pairs together, one thermal solve
    for k in range(3):
        terms += _pair_terms(k, frequency_hz, field_T, c, limits, amb, states[k])
    terms.append(
        LimitTerm(
            "power",
            "W",
            total_loss_W(field_T, c, amb, states) if loss_W is None else loss_W,
            limits.power_W,
            2 if fixed_r else None,
        )
    )
    if limits.field_exposure != "off":
        terms.append(
            LimitTerm(
                "field_exposure",
                "T",
                field_T,
                exposure_level_T(frequency_hz, limits.field_exposure),
                1,
            )
        )
    return terms


def _pair_terms(
    k: int,
    frequency_hz: Any,
    field_T: Any,
    c: Constants,
    limits: Limits,
    ambient_temperature_C: Any,
    state: Any,
) -> list[LimitTerm]:
    """Pair k's rows of :func:`limit_terms`: current and drive voltage (its own amplifier
    channel's where set), its channel's copper loss (where set), hot spot and surface."""
    import coils

    ax = _AXES[k]
    fixed_r = c.winding_temperature_C is not None
    per_amp = c.current_per_tesla_A_per_T[k]
    current = field_T * per_amp
    r = _resistance_at(state.mean_C, k, c)
    name, allowed = limits.channel("current", k)
    out = [LimitTerm(name, "A", current, allowed, 1)]
    name, allowed = limits.channel("voltage", k)
    volts = coils.voltage_amplitude_V(r, c.inductance_H[k], frequency_hz, current)
    out.append(LimitTerm(name, "V", volts, allowed, 1 if fixed_r else None))
    if f"power_{ax}" in limits.own:  # the pair's own amplifier channel: its copper loss
        loss = 0.5 * r * current * current
        out.append(
            LimitTerm(f"axis_power_{ax}", "W", loss, limits.axis_power_W[k], 2 if fixed_r else None)
        )
    if f"apparent_power_{ax}" in limits.own:  # the channel's apparent power V I / 2
        va = 0.5 * volts * current
        allowed = limits.axis_apparent_power_VA[k]
        power = 2 if fixed_r else None
        out.append(LimitTerm(f"axis_apparent_power_{ax}", "VA", va, allowed, power))
    amb = ambient_temperature_C
    rise = state.hot_spot_C - amb  # hot_spot_rise_K, from the same solve
    out.append(LimitTerm(f"hot_spot_{ax}", "K", rise, limits.coil_temperature_C - amb, None))
    if limits.surface_temperature_C is not None:
        surface = state.surface_max_C - amb
        allowed = limits.surface_temperature_C - amb
        out.append(LimitTerm(f"surface_temperature_{ax}", "K", surface, allowed, None))
    return out


def _bisect_field_T(
    value: Any, allowed: Any, shape: tuple[int, ...], steps: int = 80
) -> np.ndarray:
    """Largest B0 with ``value(B0) <= allowed`` for a value increasing in B0 (numpy).

    Bracket [lo, hi] with hi doubled from 1 mT until it violates, then bisection to machine
    precision (80 halvings of a bracket at most 2^60 wide); a single limit value (the usual
    case: the hot spot and the power depend on B0 alone) by Brent's method in the same bracket
    (:func:`_brent_below`, ~10 evaluations instead of ~80).
    """
    lo = np.zeros(shape)
    hi = np.full(shape, 1e-3)
    for _ in range(60):
        over = ~(np.asarray(value(hi), dtype=float) <= allowed)  # NaN (runaway) is over
        if np.all(over):
            break
        lo = np.where(over, lo, hi)
        hi = np.where(over, hi, 2.0 * hi)
    if lo.size == 1 and np.all(over):  # one limit value: Brent's method in the bracket
        return np.full(shape, _brent_below(value, float(allowed), float(lo), float(hi)))
    for _ in range(steps):
        mid = 0.5 * (lo + hi)
        ok = np.asarray(value(mid), dtype=float) <= allowed
        lo, hi = np.where(ok, mid, lo), np.where(ok, hi, mid)
    return lo


def _brent_below(value: Any, allowed: float, lo: float, hi: float) -> float:
    """Root of value(b) = allowed in [lo, hi] (value(lo) <= allowed < value(hi)) by Brent's
    method to machine precision, returned on the allowed side (value(b) <= allowed)."""
    from scipy.optimize import brentq

    def excess(b: float) -> float:
        v = float(np.asarray(value(b), dtype=float))
        return v - allowed if np.isfinite(v) else abs(allowed) + 1.0  # NaN (runaway) is over

    if excess(lo) > 0:
        return lo
    root = float(brentq(excess, lo, hi, xtol=1e-300, rtol=8.9e-16, maxiter=200, disp=False))
    while root > lo and excess(root) > 0:  # step back onto the allowed side
        root = float(np.nextafter(root, lo))
    return root


def _hot_spot_cap_T(
    k: int, c: Constants, allowed_K: Any, ambient_temperature_C: float, surface: bool = False
) -> Any:
    """Largest centre field the hot-spot (``surface``: the hottest face point) limit of axis k
    allows (bisection)."""
    allowed = np.asarray(allowed_K, dtype=float)
    per_amp = float(c.current_per_tesla_A_per_T[k])
    if per_amp <= 0:  # an axis no heading uses carries no current: no cap
        return np.full(allowed.shape, np.inf)

    def value(b: Any) -> Any:
        if surface:
            s = pair_state(b * per_amp, k, c, ambient_temperature_C)
            return s.surface_max_C - ambient_temperature_C
        return hot_spot_rise_K(b * per_amp, k, c, ambient_temperature_C)

    return _bisect_field_T(value, allowed, allowed.shape)


def _power_cap_T(c: Constants, allowed_W: Any, ambient_temperature_C: float) -> Any:
    """Largest centre field the copper-power limit allows (bisection; depends on B0 only)."""
    allowed = np.asarray(allowed_W, dtype=float)
    amb = float(ambient_temperature_C)

    def loss(b: Any) -> Any:  # a single field as a float (the scalar path of the thermal model)
        return total_loss_W(b if np.ndim(b) != 0 else float(b), c, amb)

    return _bisect_field_T(loss, allowed, allowed.shape)


def _channel_power_cap_T(k: int, c: Constants, allowed_W: Any, ambient_temperature_C: float) -> Any:
    """Largest centre field pair k's own channel power limit allows, R(I) I² / 2 <= P
    (bisection; the resistance at the pair's self-consistent mean temperature)."""
    allowed = np.asarray(allowed_W, dtype=float)
    per_amp = float(c.current_per_tesla_A_per_T[k])
    if per_amp <= 0:
        return np.full(allowed.shape, np.inf)

    def value(b: Any) -> Any:
        current = b * per_amp
        return 0.5 * winding_resistance_ohm(current, k, c, ambient_temperature_C) * current**2

    return _bisect_field_T(value, allowed, allowed.shape)


def _apparent_power_cap_T(
    k: int, frequency_hz: Any, c: Constants, allowed_VA: Any, ambient_temperature_C: float
) -> Any:
    """Largest centre field pair k's channel apparent power allows, |Z(R(I))| I² / 2 <= S
    (bisection, vectorised over f; the resistance at the pair's self-consistent mean
    temperature)."""
    from coils.electrical import impedance_ohm

    f = np.asarray(frequency_hz, dtype=float)
    allowed = np.asarray(allowed_VA, dtype=float)
    shape = np.broadcast_shapes(f.shape, allowed.shape)
    per_amp = float(c.current_per_tesla_A_per_T[k])
    if per_amp <= 0:
        return np.full(shape, np.inf)
    ind = float(c.inductance_H[k])

    def value(b: Any, freq: Any) -> Any:
        current = b * per_amp
        r = np.asarray(winding_resistance_ohm(current, k, c, ambient_temperature_C), dtype=float)
        return 0.5 * np.asarray(impedance_ohm(r, ind, freq), dtype=float) * current * current

    if int(np.prod(shape)) == 1:  # one value (any shape of size 1): the scalar search
        f1, a1 = float(f.ravel()[0]), float(allowed.ravel()[0])
        return np.full(shape, _bisect_field_T(lambda b: value(b, f1), a1, ()))
    return _bisect_field_T(lambda b: value(b, f), np.broadcast_to(allowed, shape), shape)


def _voltage_cap_T(
    k: int, frequency_hz: Any, c: Constants, allowed_V: Any, ambient_temperature_C: float
) -> Any:
    """Largest centre field the drive voltage of axis k allows, |Z(R(I))| I = V (numpy;
    :func:`_voltage_cap_solve`)."""
    f = np.asarray(frequency_hz, dtype=float)
    volt = np.asarray(allowed_V, dtype=float)
    return _voltage_cap_solve(k, f, c, volt, ambient_temperature_C)


def _voltage_cap_solve(
    k: int, frequency_hz: Any, c: Constants, allowed_V: Any, ambient_temperature_C: float
) -> Any:
    """:func:`_voltage_cap_T` solved.

    R(I) rises with the current (self-consistent heating), so the root in I lies between
    hi = V/|Z(R(0))| and lo = V/|Z(R(hi))|; a secant kept inside that bracket (bisecting where
    the bracket has not halved in two steps) finds it, vectorised over f. Each element stops
    at its first iterate with a residual below 1e-12 V (or a bracket 1e-14 wide) and keeps it,
    so an element's cap does not depend on the others solved with it: the same bits as that
    frequency solved alone.
    """
    from coils.electrical import impedance_ohm

    per_amp = float(c.current_per_tesla_A_per_T[k])
    f = np.asarray(frequency_hz, dtype=float)
    volt = np.asarray(allowed_V, dtype=float)
    shape = np.broadcast_shapes(f.shape, volt.shape)
    if per_amp <= 0:
        return np.full(shape, np.inf)
    ind = float(c.inductance_H[k])
    amb = ambient_temperature_C

    def excess(i: Any) -> Any:
        r = np.asarray(winding_resistance_ohm(i, k, c, amb), dtype=float)
        return np.asarray(impedance_ohm(r, ind, f), dtype=float) * i - volt

    r_cold = winding_resistance_ohm(0.0, k, c, amb)
    hi = np.array(np.broadcast_to(volt / np.asarray(impedance_ohm(r_cold, ind, f)), shape))
    e_hi = excess(hi)  # >= 0: R only grows with the current
    # V/|Z(R(hi))| undershoots: |Z(R(lo))| lo <= |Z(R(hi))| lo = V, a tight lower end
    lo = hi * volt / (e_hi + volt)
    e_lo = np.minimum(excess(lo), 0.0)
    x0, ex0, x1, ex1 = lo, e_lo, hi, e_hi
    i1 = hi
    result = np.array(hi)
    done = np.zeros(shape, dtype=bool)
    widths = [hi - lo, hi - lo]
    for _ in range(200):  # secant kept in the bracket; bisect where it has not halved in 2 steps
        den = np.where(ex1 != ex0, ex1 - ex0, 1.0)
        i1 = np.where(ex1 != ex0, x1 - ex1 * (x1 - x0) / den, 0.5 * (lo + hi))
        slow = (hi - lo) > 0.5 * widths[-2]
        i1 = np.where((i1 > lo) & (i1 < hi) & ~slow, i1, 0.5 * (lo + hi))
        e1 = excess(i1)
        converged = ~((np.abs(e1) > 1e-12 * volt) & (hi - lo > 1e-14 * hi))
        result = np.where(converged & ~done, i1, result)  # each element's first converged iterate
        done = done | converged
        if np.all(done):
            break
        widths.append(hi - lo)
        hi, lo = np.where(e1 > 0, i1, hi), np.where(e1 > 0, lo, i1)
        x0, ex0, x1, ex1 = x1, ex1, i1, e1
    else:
        result = np.where(done, result, i1)
    return result / per_amp


def field_capacity_T(
    frequency_hz: Any,
    c: Constants,
    limits: Limits,
    ambient_temperature_C: float,
    known: dict[str, Any] | None = None,
) -> tuple[Any, list[Any], list[LimitTerm]]:
    """Largest centre field each limit allows at ``f`` (numpy only): (min, caps, unit terms).

    Power-law terms invert in closed form; the session hot-spot term (``power`` None) by a
    vectorised bisection on the same expression (:func:`_bisect_field_T`).

    Parameters
    ----------
    frequency_hz : float or ndarray
        Rotation frequency, Hz.
    c : Constants
        The design's constants.
    limits : Limits
        The limits, SI.
    ambient_temperature_C : float
        Ambient air, °C.
    known : dict of str to ndarray, optional
        Caps already solved by limit name, T (:func:`frequency_free_caps_T` of the same
        design, limits and ambient, for a search over frequency).

    Returns
    -------
    field_T : ndarray
        Largest centre field all limits allow, T.
    caps_T : list of ndarray
        The field each limit allows, T, in the order of ``terms``.
    terms : list of LimitTerm
        The limit terms at B0 = 1 T.
    """
    unit = limit_terms(frequency_hz, 1.0, c, limits, ambient_temperature_C)
    caps = []
    for t in unit:
        cap = None if known is None else known.get(t.name)
        caps.append(cap if cap is not None else _cap_T(t, frequency_hz, c, ambient_temperature_C))
    return np.minimum.reduce(np.broadcast_arrays(*caps)), caps, unit


def _searched_without_f(t: LimitTerm) -> bool:
    """A limit whose cap needs a search and depends on B0 alone, not on f: the hot spot and
    the hottest face point, the copper power, a channel's power."""
    return t.power is None and (
        t.name == "power" or t.name.startswith(("hot_spot_", "surface_temperature_", "axis_power_"))
    )


def frequency_free_caps_T(
    c: Constants, limits: Limits, ambient_temperature_C: float
) -> dict[str, Any]:
    """The caps :func:`field_capacity_T` finds by a search that does not depend on the
    frequency, by limit name: solved once for a search over frequency (``known``).

    Parameters
    ----------
    c : Constants
        The design's constants.
    limits : Limits
        The limits, SI.
    ambient_temperature_C : float
        Ambient air, °C.

    Returns
    -------
    dict of str to ndarray
        The largest centre field each of those limits allows, T.
    """
    unit = limit_terms(1.0, 1.0, c, limits, ambient_temperature_C)  # these terms do not read f
    return {
        t.name: _cap_T(t, 1.0, c, ambient_temperature_C) for t in unit if _searched_without_f(t)
    }


def _cap_T(t: LimitTerm, frequency_hz: Any, c: Constants, ambient_temperature_C: float) -> Any:
    """The largest centre field limit term ``t`` (at B0 = 1 T) allows, T."""
    if t.power is None and t.name.startswith(("hot_spot_", "surface_temperature_")):
        return _hot_spot_cap_T(  # depends on B0 only, not on f
            _AXES.index(t.name[-1]),
            c,
            t.allowed,
            ambient_temperature_C,
            surface=t.name.startswith("surface_"),
        )
    if t.power is None and t.name == "power":
        return _power_cap_T(c, t.allowed, ambient_temperature_C)
    if t.power is None and t.name.startswith("axis_power_"):
        return _channel_power_cap_T(_AXES.index(t.name[-1]), c, t.allowed, ambient_temperature_C)
    if t.power is None and t.name.startswith("axis_apparent_power_"):
        k = _AXES.index(t.name[-1])
        return _apparent_power_cap_T(k, frequency_hz, c, t.allowed, ambient_temperature_C)
    if t.power is None:  # voltage with the self-consistent resistance
        return _voltage_cap_T(
            _AXES.index(t.name[-1]), frequency_hz, c, t.allowed, ambient_temperature_C
        )
    with np.errstate(divide="ignore"):  # an axis no heading uses carries no current: no cap
        return np.divide(t.allowed, np.asarray(t.value, dtype=float)) ** (1.0 / t.power)


@dataclass(frozen=True)
class FieldCapacity:
    """The largest centre field the limits allow at one frequency, and the limit that sets it.

    Attributes
    ----------
    field_T : float
        Largest centre field the limits allow, T.
    limited_by : str
        Name of the limit that sets it.
    caps_T : dict of str to float
        The field each limit allows, T.
    """

    field_T: float
    limited_by: str
    caps_T: dict[str, float]


def field_capacity(
    frequency_hz: float,
    c: Constants,
    limits: Limits,
    ambient_temperature_C: float,
    known: dict[str, Any] | None = None,
) -> FieldCapacity:
    """:func:`field_capacity_T` at one frequency with the binding limit named (computed once).

    Parameters
    ----------
    frequency_hz : float
        Rotation frequency, Hz.
    c : Constants
        The design's constants.
    limits : Limits
        The limits, SI.
    ambient_temperature_C : float
        Ambient air, °C.
    known : dict of str to ndarray, optional
        Caps already solved by limit name, T (:func:`frequency_free_caps_T`).

    Returns
    -------
    FieldCapacity
        The field (T) and the binding limit.
    """
    best, caps, terms = field_capacity_T(frequency_hz, c, limits, ambient_temperature_C, known)
    values = [float(x) for x in caps]
    i = int(np.argmin(values))
    return FieldCapacity(
        field_T=float(best),
        limited_by=terms[i].name,
        caps_T={t.name: v for t, v in zip(terms, values)},
    )


def available_torque_Nm(field_T: Any, c: Constants) -> Any:
    """Largest synchronous torque over the workspace: m · B0 · (weakest-field factor).

    Parameters
    ----------
    field_T : float, array or CasADi
        Rotating-field amplitude at the centre, T.
    c : Constants
        The design's constants (magnet moment, workspace factor).

    Returns
    -------
    float, array or CasADi
        Available torque, N·m.
    """
    return cap.max_synchronous_torque_Nm(c.moment_Am2, field_T * c.workspace_factor)


def contact_geometry(c: Constants) -> tm.ContactGeometry:
    """The capsule as the tissue model sees it (symbols pass through for free hardware).

    Parameters
    ----------
    c : Constants
        The design's constants.

    Returns
    -------
    torque_model.ContactGeometry
        Body, wire and wound length in m, the number of starts.
    """
    return tm.ContactGeometry(
        c.body_diameter_m, c.body_length_m, c.wire_diameter_m, c.wound_length_m, c.starts
    )


def required_torques_Nm(
    helical_angle_rad: bk.Scalar,
    frequency_hz: bk.Scalar,
    c: Constants,
    tissues: tuple,
    req: Requirements,
) -> list[tuple[bk.Scalar, bk.Scalar]]:
    """(resistive, thrust) torque for every tissue set, N·m.

    Resistive: the Zhou 2013 tissue model (torque_model.resistive_torque_Nm) plus the friction
    of the capsule's weight lying on the wall (torque_model.weight_friction_torque_Nm, which the
    paper's vertical bench left out). Thrust: the screw torque to push ``req.axial_load_N``
    (capsule.thrust_torque_Nm) with that tissue's friction.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle, rad.
    frequency_hz : float, array or CasADi
        Rotation frequency, Hz.
    c : Constants
        The design's constants.
    tissues : tuple of TissueParameters
        The tissue sets.
    req : Requirements
        The requirements (axial load).

    Returns
    -------
    list of (float, float)
        (resistive, thrust) torque per tissue set, N·m (floats, arrays or CasADi).
    """
    return required_torques_at(helical_angle_rad, c, tissues, req)(frequency_hz)


def required_torques_at(
    helical_angle_rad: bk.Scalar, c: Constants, tissues: tuple, req: Requirements
) -> Callable[[bk.Scalar], list[tuple[bk.Scalar, bk.Scalar]]]:
    """:func:`required_torques_Nm` as a function of the frequency alone, its frequency-free
    parts (the contact geometry, D', the weight's friction, the thrust) worked out once: for a
    search over frequency at one angle.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle, rad.
    c : Constants
        The design's constants.
    tissues : tuple of TissueParameters
        The tissue sets.
    req : Requirements
        The requirements (axial load).

    Returns
    -------
    callable
        ``at(frequency_hz)``: (resistive, thrust) torque per tissue set, N·m, at a frequency in
        Hz (float, array or CasADi), the same numbers as :func:`required_torques_Nm`.
    """
    geometry = contact_geometry(c)
    d_prime = tm.capsule_d_prime_m(helical_angle_rad, geometry)  # the same for every set
    fixed = [
        (
            tissue,
            weight_friction_Nm(c, tissue),
            cap.thrust_torque_Nm(
                req.axial_load_N, c.helix_diameter_m, helical_angle_rad, tissue.friction_coefficient
            ),
        )
        for tissue in tissues
    ]

    def at(frequency_hz: bk.Scalar) -> list[tuple[bk.Scalar, bk.Scalar]]:
        return [
            (
                tm.resistive_torque_Nm(helical_angle_rad, frequency_hz, tissue, geometry, d_prime)
                + friction,
                thrust,
            )
            for tissue, friction, thrust in fixed
        ]

    return at


def weight_friction_Nm(c: Constants, tissue: Any) -> Any:
    """Friction of the capsule's weight on ``tissue``'s wall, N·m (torque_model.engagement).

    Parameters
    ----------
    c : Constants
        The design's constants (capsule mass, kg; body and wire diameters, m).
    tissue : TissueParameters
        The tissue set (its friction coefficient).

    Returns
    -------
    float or CasADi
        Friction torque of the capsule's weight, N·m.
    """
    radius = tm.contact_radius_m(c.body_diameter_m, c.wire_diameter_m)
    return tm.weight_friction_torque_Nm(c.mass_kg, tissue.friction_coefficient, radius)


def wall_strains(helical_angle_rad: bk.Scalar, c: Constants, tissues: tuple) -> list[bk.Scalar]:
    """Strain the wound section stretches each tissue set's wall by (engagement where > 0).

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle, rad.
    c : Constants
        The design's constants (capsule and spiral dimensions, m).
    tissues : tuple of TissueParameters
        The tissue sets (lumen and wall, m).

    Returns
    -------
    list
        One strain per tissue set, dimensionless (torque_model.wall_strain).
    """
    geometry = contact_geometry(c)
    d_prime = tm.capsule_d_prime_m(helical_angle_rad, geometry)  # the same for every set
    return [tm.wall_strain(helical_angle_rad, t, geometry, d_prime) for t in tissues]


def speed_m_s(helical_angle_rad: Any, frequency_hz: Any, c: Constants, req: Requirements) -> Any:
    """Forward speed: slip efficiency × frequency × spiral lead (capsule.forward_speed_m_s).

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle, rad.
    frequency_hz : float, array or CasADi
        Rotation frequency, Hz.
    c : Constants
        The design's constants.
    req : Requirements
        The requirements (slip efficiency).

    Returns
    -------
    float, array or CasADi
        Forward speed, m/s.
    """
    return cap.forward_speed_m_s(
        frequency_hz, cap.lead_m(helical_angle_rad, c.helix_diameter_m), req.slip_efficiency
    )


def spiral_turns(helical_angle_rad: Any, c: Constants) -> Any:
    """Full turns the spiral makes over its wound length (capsule.spiral_turns).

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle, rad.
    c : Constants
        The design's constants.

    Returns
    -------
    float, array or CasADi
        Turns over the wound length, count (fractional).
    """
    return cap.spiral_turns(helical_angle_rad, c.helix_diameter_m, c.wound_length_m)


# --- tolerances: every row at its own worst corner (issue 36) ------------------------------------
#
# A design holds over the box angle ± da, spiral wire ± dw, every lumen ± dl (optimize.system.
# Tolerances). Each row below is monotone in the three (tests/test_tolerances.py checks it on a
# grid), so it is written at the corner where it is weakest: the wall strain at the widest lumen,
# the thinnest wire and the steepest angle (D' falls as the angle rises); the required torque at
# the narrowest lumen and the thickest wire (more strain, a wider helix for the thrust and a
# larger crest radius for the weight's friction), and at both angle ends, the larger of the two
# (the tissue torque falls with the angle while the thrust rises); the speed at the flattest angle
# and the thinnest wire (the shortest lead); the spiral turns at the steepest angle and the
# thickest wire (the longest lead); the self-lock at the steepest angle; the spiral's
# turn-to-turn clearance at the flattest angle and the thickest wire. With zero tolerances each
# is the nominal expression itself, bit for bit.


def _tolerance(tol: Any, name: str) -> Any:
    """``tol.<name>``, 0 when there is no tolerance box."""
    return 0.0 if tol is None else getattr(tol, name)


def wire_corner(c: Constants, tol: Any, sign: int) -> Constants:
    """``c`` with the spiral wire at ``sign`` × its tolerance (the helix follows), m.

    Parameters
    ----------
    c : Constants
        The design's constants.
    tol : Tolerances or None
        The tolerance box (SI).
    sign : int
        +1 the thickest wire, -1 the thinnest (a sign, dimensionless).

    Returns
    -------
    Constants
        The constants at that wire (``c`` itself without a wire tolerance).
    """
    from dataclasses import replace

    dw = _tolerance(tol, "spiral_wire_diameter_m")
    if dw == 0.0:
        return c
    return replace(
        c,
        wire_diameter_m=c.wire_diameter_m + sign * dw,
        helix_diameter_m=c.helix_diameter_m + sign * dw,
    )


def lumen_corner(tissues: tuple, tol: Any, sign: int) -> tuple:
    """Every tissue set with its lumen at ``sign`` × the lumen tolerance (names kept).

    Parameters
    ----------
    tissues : tuple of TissueParameters
        The tissue sets.
    tol : Tolerances or None
        The tolerance box (SI).
    sign : int
        +1 the widest lumen, -1 the narrowest (a sign, dimensionless).

    Returns
    -------
    tuple of TissueParameters
        The sets at that lumen (``tissues`` itself without a lumen tolerance).
    """
    dl = _tolerance(tol, "lumen_diameter_m")
    if dl == 0.0:
        return tissues
    return tuple(t.replace(lumen_diameter_m=t.lumen_diameter_m + sign * dl) for t in tissues)


def angle_corner(helical_angle_rad: Any, tol: Any, sign: int) -> Any:
    """The helical angle at ``sign`` × its tolerance, rad (+1 the steepest, -1 the flattest).

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle, rad.
    tol : Tolerances or None
        The tolerance box (SI).
    sign : int
        +1 the steepest, -1 the flattest (a sign, dimensionless).

    Returns
    -------
    float, array or CasADi
        The corner's angle, rad (the angle itself without an angle tolerance).
    """
    da = _tolerance(tol, "helical_angle_rad")
    return helical_angle_rad if da == 0.0 else helical_angle_rad + sign * da


def required_torque_corners_Nm(
    helical_angle_rad: Any,
    frequency_hz: Any,
    c: Constants,
    tissues: tuple,
    req: Requirements,
    tol: Any,
) -> list[list[tuple[Any, Any]]]:
    """:func:`required_torques_Nm` at the torque's worst corners: the thickest wire, the
    narrowest lumen, and each end of the angle's tolerance (flattest first; one corner, the
    angle itself, without an angle tolerance).

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle, rad.
    frequency_hz : float, array or CasADi
        Rotation frequency, Hz.
    c : Constants
        The design's constants.
    tissues : tuple of TissueParameters
        The tissue sets.
    req : Requirements
        The requirements (axial load).
    tol : Tolerances or None
        The tolerance box (SI).

    Returns
    -------
    list of list of (float, float)
        Per angle corner, (resistive, thrust) per tissue set, N·m.
    """
    return required_torque_corners_at(helical_angle_rad, c, tissues, req, tol)(frequency_hz)


def required_torque_corners_at(
    helical_angle_rad: Any, c: Constants, tissues: tuple, req: Requirements, tol: Any
) -> Callable[[Any], list[list[tuple[Any, Any]]]]:
    """:func:`required_torque_corners_Nm` as a function of the frequency alone, the corners
    and each one's frequency-free parts (:func:`required_torques_at`) worked out once.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle, rad.
    c : Constants
        The design's constants.
    tissues : tuple of TissueParameters
        The tissue sets.
    req : Requirements
        The requirements (axial load).
    tol : Tolerances or None
        The tolerance box (SI).

    Returns
    -------
    callable
        ``at(frequency_hz)``: per angle corner, (resistive, thrust) per tissue set, N·m, at a
        frequency in Hz, the same numbers as :func:`required_torque_corners_Nm`.
    """
    cw, ts = wire_corner(c, tol, +1), lumen_corner(tissues, tol, -1)
    if _tolerance(tol, "helical_angle_rad") == 0.0:
        corners = [required_torques_at(helical_angle_rad, cw, ts, req)]
    else:
        corners = [
            required_torques_at(angle_corner(helical_angle_rad, tol, s), cw, ts, req)
            for s in (-1, +1)
        ]

    def at(frequency_hz: Any) -> list[list[tuple[Any, Any]]]:
        return [corner(frequency_hz) for corner in corners]

    return at


def worst_required_torques_Nm(
    helical_angle_rad: Any,
    frequency_hz: Any,
    c: Constants,
    tissues: tuple,
    req: Requirements,
    tol: Any,
) -> list[Any]:
    """Required torque (resistive + thrust) per tissue set at its worst corner of the
    tolerance box, N·m: the larger of the two angle ends of :func:`required_torque_corners_Nm`,
    written ``flat + max(steep - flat, 0)`` so that the NLP lifts the ``max`` into an epigraph
    variable (every row bounds the required torque from above: exact and smooth).

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle, rad.
    frequency_hz : float, array or CasADi
        Rotation frequency, Hz.
    c : Constants
        The design's constants.
    tissues : tuple of TissueParameters
        The tissue sets.
    req : Requirements
        The requirements.
    tol : Tolerances or None
        The tolerance box (SI).

    Returns
    -------
    list of float, array or CasADi
        Required torque per tissue set, N·m.
    """
    corners = required_torque_corners_Nm(helical_angle_rad, frequency_hz, c, tissues, req, tol)
    totals = [[r + t for r, t in corner] for corner in corners]
    if len(totals) == 1:
        return totals[0]
    k = _TORQUE_LIFT_Nm  # the lifted variable in mN·m: IPOPT's tolerances at the torque's scale
    return [flat + k * bk.positive_part((steep - flat) / k) for flat, steep in zip(*totals)]


#: Scale of the lifted torque difference of :func:`worst_required_torques_Nm` (the NLP's
#: epigraph variables are O(0.1) of their unit: a torque of a few mN·m is O(1) in mN·m), N·m.
_TORQUE_LIFT_Nm = 1e-3


def toleranced_wall_strains(
    helical_angle_rad: bk.Scalar, c: Constants, tissues: tuple, tol: Any
) -> list[bk.Scalar]:
    """:func:`wall_strains` at the strain's worst corner: the steepest angle, the thinnest wire,
    the widest lumen.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle, rad.
    c : Constants
        The design's constants.
    tissues : tuple of TissueParameters
        The tissue sets.
    tol : Tolerances or None
        The tolerance box (SI).

    Returns
    -------
    list
        One strain per tissue set, dimensionless.
    """
    return wall_strains(
        angle_corner(helical_angle_rad, tol, +1),
        wire_corner(c, tol, -1),
        lumen_corner(tissues, tol, +1),
    )


def toleranced_speed_m_s(
    helical_angle_rad: Any, frequency_hz: Any, c: Constants, req: Requirements, tol: Any
) -> Any:
    """:func:`speed_m_s` at its worst corner: the flattest angle, the thinnest wire, m/s.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle, rad.
    frequency_hz : float, array or CasADi
        Rotation frequency, Hz.
    c : Constants
        The design's constants.
    req : Requirements
        The requirements (slip efficiency).
    tol : Tolerances or None
        The tolerance box (SI).

    Returns
    -------
    float, array or CasADi
        Forward speed, m/s.
    """
    return speed_m_s(
        angle_corner(helical_angle_rad, tol, -1), frequency_hz, wire_corner(c, tol, -1), req
    )


def toleranced_spiral_turns(helical_angle_rad: Any, c: Constants, tol: Any) -> Any:
    """:func:`spiral_turns` at its worst corner: the steepest angle, the thickest wire.

    Parameters
    ----------
    helical_angle_rad : float, array or CasADi
        Helical angle, rad.
    c : Constants
        The design's constants.
    tol : Tolerances or None
        The tolerance box (SI).

    Returns
    -------
    float, array or CasADi
        Turns over the wound length, count (fractional).
    """
    return spiral_turns(angle_corner(helical_angle_rad, tol, +1), wire_corner(c, tol, +1))
