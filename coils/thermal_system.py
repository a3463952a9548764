"""The three pairs heating together: steady or at the end of a session, radiating to each other.

Each pair's faces radiate to the room and to the other pairs' packs (view factors of
:mod:`coils.viewfactors`), which are at their own temperatures. Every pair is first solved
alone (its own pair's share F_self of the emission returns to it, the rest leaves to the room
at ambient). The other pairs then add the flux ε σ (1 - F_self)(T_r⁴ - T_a⁴) to its faces,
T_r from :func:`coils.thermal.radiant_surroundings` of their surfaces; those come from a quick
estimate of each pair alone (:func:`coils.thermal.surface_estimate_C`) warmed to first order
by the others in turn. The pair answers the added flux through the tangent slope of its face
loss, with the copper resistance following the mean temperature: steady, the whole pack rises
by flux/g / (1 - α R20 I²/2 · R_tan); at the end of a session by the lumped fraction
1 - e^(-t/τ) of that. Against the fixed point of the exact coupled balance this sweep is
within 0.3 K of the 6-9 K the coupling adds to the built-in packs at 12 A (a little low:
tests/test_coils_cooling.py).

The secant linearisation of the faces at a pair's state also gives its loss at a lighter
heading's current (:func:`mean_rise_at_K`): exact at the worst heading's current it was solved
at. Backend-generic, fixed operations.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from coils.thermal import (
    _KELVIN,
    COPPER_TEMPERATURE_COEFFICIENT_per_K,
    STEFAN_BOLTZMANN_W_m2K4,
    Surroundings,
    WindingPack,
    _Faces,
    _internal,
    _resistance_ohm,
    convection_coefficient_W_m2K,
    radiant_surroundings,
    session_linearisation_C,
    steady_state,
    surface_estimate_C,
    transient,
)
from spiralcap.core import backend as bk

__all__ = ["PairTemperatures", "end_state", "mean_rise_at_K", "pair_temperatures"]


@dataclass(frozen=True)
class PairTemperatures:
    """One pair at the end of the run (steady, or at the end of the session); °C, W, W/(m²·K).

    ``surface_C`` is the mean face temperature, ``surface_max_C`` the hottest face point,
    ``convection_W_m2K`` the faces' area-weighted convective h_c at ``surface_C`` (with the other
    pairs radiating: at the coupled surface; h_c at the pair's surface alone is 2-3 % lower for
    the built-in pairs). Linearisation (for :func:`mean_rise_at_K` and the coupling):
    ``effective_h_W_m2K`` (h_c + h_r at the faces, of the pair alone: the coupling answers the
    other pairs' flux with the tangent slope there), ``thermal_resistance_K_per_W`` R_th (mean
    above the sink per watt), ``sink_rise_K`` θ_env from the other pairs, ``session_ratio`` (mean
    rise reached / its linear steady value; 1 at steady state), ``runaway`` (1: no steady
    state).

    Attributes
    ----------
    surface_C, surface_max_C, mean_C, hot_spot_C : float, array or CasADi
        Mean face, hottest face point, mean winding and hottest winding temperature, °C.
    power_W : float, array or CasADi
        Copper loss of the pair, W.
    convection_W_m2K, effective_h_W_m2K : float, array or CasADi
        Convective and effective (convection + radiation) face coefficient, W/(m²·K).
    time_constant_s : float, array or CasADi
        Lumped time constant of the mean rise, s.
    thermal_resistance_K_per_W : float, array or CasADi
        R_th, mean winding above the sink per watt, K/W.
    sink_rise_K : float, array or CasADi
        θ_env, the sink's rise above ambient from the other pairs, K.
    session_ratio : float, array or CasADi
        Mean rise reached / its linear steady value, dimensionless (1 at steady state).
    runaway : float, array or CasADi
        Flag, 1.0 where no steady state exists, else 0.0.
    internal : object, optional
        The Robin offsets above the mean face at ``effective_h_W_m2K`` (K/W), when kept.
    tangent_h_W_m2K : float, array or CasADi, optional
        Tangent slope of the face loss per unit area, W/(m²·K), when kept.
    """

    surface_C: Any
    surface_max_C: Any
    mean_C: Any
    hot_spot_C: Any
    power_W: Any
    convection_W_m2K: Any
    effective_h_W_m2K: Any
    time_constant_s: Any
    thermal_resistance_K_per_W: Any
    sink_rise_K: Any
    session_ratio: Any
    runaway: Any
    internal: Any = None
    tangent_h_W_m2K: Any = None


def _lumped(pack: WindingPack, heff: Any, p1: Any, inner: Any = None) -> tuple[Any, Any, Any]:
    """(R_th, τ, internal offsets) of the pack with faces h_eff and loss slope p₁ = dP/dT
    (``inner``: the Robin offsets at h_eff if the caller has them)."""
    inner = _internal(pack, heff) if inner is None else inner
    r_th = inner.mean + 1.0 / (heff * pack.surface_area_m2)
    return r_th, pack.heat_capacity_J_per_K / (1.0 / r_th - p1), inner


def _ratio(rise: Any, linear: Any) -> Any:
    """rise / linear, 1 where the linear rise is 0 (no current)."""
    some = bk.abs(linear) > 1e-300
    return bk.where(some, rise / bk.where(some, linear, 1.0), 1.0)


def _tangent_h(pack: WindingPack, ambient_C: Any, env: Surroundings | None, surface_C: Any) -> Any:
    """d(face loss)/dT_s per m², W/(m²·K): how the faces answer an added flux."""
    faces = _Faces(pack, ambient_C, env if env is not None else Surroundings(ambient_C))
    hc = faces.convection(surface_C)
    return faces.slope_W_per_K(surface_C, hc, faces.convection_slope(surface_C)) / faces.area


def end_state(
    pack: WindingPack,
    resistance_20C_ohm: Any,
    current_A: Any,
    ambient_C: Any,
    env: Surroundings | None,
    session_s: Any,
) -> PairTemperatures:
    """One pair in fixed radiant surroundings: steady (``session_s`` None) or at session end.

    Parameters
    ----------
    pack : WindingPack
        The pair's packs and their cooling.
    resistance_20C_ohm : float, array or CasADi
        Pair resistance at 20 °C, Ω.
    current_A : float, array or CasADi
        Current amplitude, A.
    ambient_C : float, array or CasADi
        Ambient air, °C.
    env : Surroundings or None
        Fixed radiant surroundings (None: alone in the room).
    session_s : float, array, CasADi or None
        Session length, s (None: steady state).

    Returns
    -------
    PairTemperatures
        The pair at the end of the run (°C, W, W/(m²·K), s, K/W).
    """
    st = steady_state(pack, resistance_20C_ohm, current_A, ambient_C, env)
    half_i2 = 0.5 * current_A * current_A
    p1 = COPPER_TEMPERATURE_COEFFICIENT_per_K * resistance_20C_ohm * half_i2
    r_th, tau, _ = _lumped(pack, st.effective_h_W_m2K, p1, st.internal)
    p_a = _resistance_ohm(resistance_20C_ohm, ambient_C) * half_i2
    if session_s is None:
        linear = r_th * p_a / bk.fmax(1.0 - p1 * r_th, 1e-12)
        return PairTemperatures(
            st.surface_C,
            st.surface_max_C,
            st.mean_C,
            st.hot_spot_C,
            st.power_W,
            st.convection_W_m2K,
            st.effective_h_W_m2K,
            tau,
            r_th,
            0.0,
            _ratio(st.mean_C - ambient_C, linear),
            st.runaway,
            st.internal,
            _tangent_h(pack, ambient_C, env, st.surface_C),
        )
    tau_safe = bk.where(tau > 0.0, tau, 1e30)
    lin = session_linearisation_C(st, tau_safe, session_s, ambient_C)
    run = transient(pack, resistance_20C_ohm, current_A, ambient_C, session_s, lin, env)
    _, heff, _ = _Faces(
        pack, ambient_C, env if env is not None else Surroundings(ambient_C)
    ).linearised(lin)
    r_lin, tau_lin, inner_lin = _lumped(pack, heff, p1)
    steady_rise = r_lin * p_a / bk.fmax(1.0 - p1 * r_lin, 1e-12)
    return PairTemperatures(
        run.surface_C,
        run.surface_max_C,
        run.mean_C,
        run.hot_spot_C,
        run.power_W,
        convection_coefficient_W_m2K(pack, run.surface_C, ambient_C),
        heff,
        tau_lin,
        r_lin,
        0.0,
        _ratio(run.mean_C - ambient_C, steady_rise),
        st.runaway,
        inner_lin,
        _tangent_h(pack, ambient_C, env, lin),
    )


def _added_flux(pack: WindingPack, env: Surroundings, ambient_C: Any) -> Any:
    """Flux the other pairs add to the faces, ε σ (1 - F_self)(T_r⁴ - T_a⁴), W/m²."""
    ta = ambient_C + _KELVIN
    tr = env.radiant_C + _KELVIN
    return (
        pack.emissivity
        * STEFAN_BOLTZMANN_W_m2K4
        * env.radiating_fraction
        * (tr * tr * tr * tr - ta * ta * ta * ta)
    )


def _coupled(
    alone: PairTemperatures,
    pack: WindingPack,
    resistance_20C_ohm: Any,
    current_A: Any,
    ambient_C: Any,
    env: Surroundings,
    session_s: Any,
) -> PairTemperatures:
    """``alone`` with the other pairs' radiation added (linearised at ``alone``)."""
    flux = _added_flux(pack, env, ambient_C)
    heff = alone.effective_h_W_m2K
    gtan = alone.tangent_h_W_m2K  # the faces answer an added flux with their tangent slope
    theta_env = flux / heff
    p1 = COPPER_TEMPERATURE_COEFFICIENT_per_K * resistance_20C_ohm * 0.5 * current_A * current_A
    r_th, tau, inner = _lumped(pack, heff, p1, alone.internal)
    reached = 1.0 if session_s is None else 1.0 - bk.exp(-session_s / bk.where(tau > 0, tau, 1e30))
    r_tan = inner.mean + 1.0 / (gtan * pack.surface_area_m2)
    d_mean = flux / gtan / bk.fmax(1.0 - p1 * r_tan, 1e-12) * reached
    d_power = p1 * d_mean
    d_surface = flux / gtan * reached + d_power / (gtan * pack.surface_area_m2)
    mean = alone.mean_C + d_mean
    p_a = _resistance_ohm(resistance_20C_ohm, ambient_C) * 0.5 * current_A * current_A
    steady_rise = (theta_env + r_th * p_a) / bk.fmax(1.0 - p1 * r_th, 1e-12)
    surface = alone.surface_C + d_surface
    return PairTemperatures(
        surface,
        alone.surface_max_C + d_surface + inner.surface_max * d_power,
        mean,
        alone.hot_spot_C + d_surface + inner.centre * d_power,
        alone.power_W + d_power,
        convection_coefficient_W_m2K(pack, surface, ambient_C),  # h_c at the coupled surface
        heff,
        alone.time_constant_s,
        r_th,
        theta_env,
        _ratio(mean - ambient_C, steady_rise),
        alone.runaway,
        inner,
        gtan,
    )


def pair_temperatures(
    packs: tuple,
    resistances_20C_ohm: Any,
    currents_A: Any,
    ambient_C: Any,
    view_factors: Any,
    session_s: Any = None,
    only: int | None = None,
) -> list[Any]:
    """The three pairs at ``currents_A`` (one each), radiating to each other.

    ``view_factors``: rows ``[room, x, y, z]`` per pair (:func:`coils.viewfactors.
    view_factors`), or None (each pair alone in the room). The neighbours' surfaces come from
    :func:`coils.thermal.surface_estimate_C`. ``only``: solve that pair alone (the others'
    entries None; the same numbers as the full call).

    Parameters
    ----------
    packs : tuple of WindingPack
        The x, y and z pairs' packs.
    resistances_20C_ohm : sequence of float or CasADi
        Each pair's resistance at 20 °C, Ω.
    currents_A : sequence of float or CasADi
        Each pair's current amplitude, A.
    ambient_C : float or CasADi
        Ambient air, °C.
    view_factors : ndarray, shape (3, 4), or None
        View factors, dimensionless, rows ``[room, x, y, z]`` per pair (None: each alone).
    session_s : float, array, CasADi or None
        Session length, s (None: steady state).
    only : int, optional
        Index of the one pair to solve (0, 1, 2), or None for all three.

    Returns
    -------
    list of PairTemperatures or None
        One per pair (x, y, z); None for the pairs ``only`` leaves out.
    """
    want = range(3) if only is None else (only,)
    if view_factors is None:
        return [
            end_state(packs[k], resistances_20C_ohm[k], currents_A[k], ambient_C, None, session_s)
            if k in want
            else None
            for k in range(3)
        ]
    alone: list[PairTemperatures | None] = []
    estimates: list[Any] = []
    for j in range(3):
        own = Surroundings(ambient_C, 1.0 - view_factors[j][1 + j])
        args = (packs[j], resistances_20C_ohm[j], currents_A[j], ambient_C, own)
        alone.append(end_state(*args, session_s) if j in want else None)
        estimates.append(surface_estimate_C(*args, session_s))
    # each neighbour warmed by the others in turn (first order, its faces' tangent slope)
    warmed = []
    for j in range(3):
        own = Surroundings(ambient_C, 1.0 - view_factors[j][1 + j])
        env_j = radiant_surroundings(view_factors, j, estimates, ambient_C)
        flux = _added_flux(packs[j], env_j, ambient_C)
        warmed.append(estimates[j] + flux / _tangent_h(packs[j], ambient_C, own, estimates[j]))
    estimates = warmed
    out: list[Any] = []
    for k in range(3):
        if k not in want:
            out.append(None)
            continue
        env = radiant_surroundings(view_factors, k, estimates, ambient_C)
        own_state = alone[k]
        assert own_state is not None
        out.append(
            _coupled(
                own_state,
                packs[k],
                resistances_20C_ohm[k],
                currents_A[k],
                ambient_C,
                env,
                session_s,
            )
        )
    return out


def mean_rise_at_K(
    state: PairTemperatures, resistance_20C_ohm: Any, current_A: Any, ambient_C: Any
) -> Any:
    """Mean winding rise of a pair at another current, with its faces linearised at ``state``.

    θ = ratio · (θ_env + R_th P_a) / (1 - p₁ R_th), P_a = R(T_a) I²/2, p₁ = α R20 I²/2: the
    steady balance of the linearised faces (times the share of it the session reaches at the
    state's current). Equal to ``state``'s mean rise at ``state``'s own current.

    Parameters
    ----------
    state : PairTemperatures
        The pair's state whose faces are linearised.
    resistance_20C_ohm : float, array or CasADi
        Pair resistance at 20 °C, Ω.
    current_A : float, array or CasADi
        The other current amplitude, A.
    ambient_C : float, array or CasADi
        Ambient air, °C.

    Returns
    -------
    float, array or CasADi
        Mean winding rise above ambient, K.
    """
    half_i2 = 0.5 * current_A * current_A
    p1 = COPPER_TEMPERATURE_COEFFICIENT_per_K * resistance_20C_ohm * half_i2
    p_a = _resistance_ohm(resistance_20C_ohm, ambient_C) * half_i2
    r_th = state.thermal_resistance_K_per_W
    return state.session_ratio * (state.sink_rise_K + r_th * p_a) / bk.fmax(1.0 - p1 * r_th, 1e-12)
