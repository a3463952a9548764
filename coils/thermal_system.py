"""The three pairs heating together: steady or at the end of a session, radiating to each other.

Each pair's faces radiate to the room and to the other pairs' packs (view factors of
:mod:`coils.viewfactors`), which are at their own temperatures. The coupling is solved by one
Jacobi sweep: every pair alone first (the others at ambient), then each pair with the others'
surfaces from that first pass. The coupling is weak (a pack's temperature moves its
neighbours' by F h_r / (h_c + h_r) ≈ 0.1 of its own rise), so the neglected second sweep is
~1 % of the few kelvin the coupling adds (tests). Backend-generic, fixed operations.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from coils.thermal import (
    COPPER_TEMPERATURE_COEFFICIENT_per_K,
    Surroundings,
    WindingPack,
    radiant_surroundings,
    session_linearisation_C,
    steady_state,
    transient,
)
from spiralcap import backend as bk

__all__ = [
    "PairTemperatures",
    "end_state",
    "first_pass_surfaces_C",
    "lumped_time_constant_s",
    "pair_temperatures",
    "surroundings",
]


@dataclass(frozen=True)
class PairTemperatures:
    """One pair at the end of the run (steady, or at the end of the session); °C, W, W/(m²·K).

    ``surface_C`` is the mean face temperature, ``surface_max_C`` the hottest face point;
    ``env`` the radiant surroundings it was solved with, ``linearise_C`` the surface temperature
    its faces were linearised at (session) and ``steady`` the steady state in those
    surroundings.
    """

    surface_C: Any
    surface_max_C: Any
    mean_C: Any
    hot_spot_C: Any
    power_W: Any
    convection_W_m2K: Any
    effective_h_W_m2K: Any
    time_constant_s: Any
    env: Surroundings
    steady: Any
    linearise_C: Any


def lumped_time_constant_s(
    pack: WindingPack, resistance_20C_ohm: Any, current_A: Any, steady: Any
) -> Any:
    """τ = C / (1/R_th - α R20 I²/2) of the mean rise with the steady faces (negative: runaway)."""
    from coils.thermal import _internal

    heff = steady.effective_h_W_m2K
    r_th = _internal(pack, heff).mean + 1.0 / (heff * pack.surface_area_m2)
    p1 = COPPER_TEMPERATURE_COEFFICIENT_per_K * resistance_20C_ohm * 0.5 * current_A * current_A
    return pack.heat_capacity_J_per_K / (1.0 / r_th - p1)


def end_state(
    pack: WindingPack,
    resistance_20C_ohm: Any,
    current_A: Any,
    ambient_C: Any,
    env: Surroundings | None,
    session_s: Any,
) -> PairTemperatures:
    """One pair in fixed surroundings: steady (``session_s`` None) or at the session's end."""
    st = steady_state(pack, resistance_20C_ohm, current_A, ambient_C, env)
    tau = lumped_time_constant_s(pack, resistance_20C_ohm, current_A, st)
    if session_s is None:
        return PairTemperatures(
            st.surface_C,
            st.surface_max_C,
            st.mean_C,
            st.hot_spot_C,
            st.power_W,
            st.convection_W_m2K,
            st.effective_h_W_m2K,
            tau,
            env if env is not None else Surroundings(ambient_C),
            st,
            st.surface_C,
        )
    tau_safe = bk.where(tau > 0.0, tau, 1e30)
    lin = session_linearisation_C(st, tau_safe, session_s, ambient_C)
    run = transient(pack, resistance_20C_ohm, current_A, ambient_C, session_s, lin, env)
    from coils.thermal import convection_coefficient_W_m2K

    hc = convection_coefficient_W_m2K(pack, lin, ambient_C)
    return PairTemperatures(
        run.surface_C,
        run.surface_max_C,
        run.mean_C,
        run.hot_spot_C,
        run.power_W,
        hc,
        None,
        tau,
        env if env is not None else Surroundings(ambient_C),
        st,
        lin,
    )


def first_pass_surfaces_C(
    packs: tuple,
    resistances_20C_ohm: Any,
    currents_A: Any,
    ambient_C: Any,
    view_factors: Any,
    session_s: Any = None,
    skip: int | None = None,
) -> list[Any]:
    """Mean surface temperature of each pair alone (the others at ambient), °C; ``skip``: 0."""
    out: list[Any] = []
    for j in range(3):
        if j == skip:
            out.append(0.0)
            continue
        alone = Surroundings(ambient_C, 1.0 - view_factors[j][1 + j])
        run = end_state(
            packs[j], resistances_20C_ohm[j], currents_A[j], ambient_C, alone, session_s
        )
        out.append(run.surface_C)
    return out


def surroundings(
    packs: tuple,
    resistances_20C_ohm: Any,
    currents_A: Any,
    ambient_C: Any,
    view_factors: Any,
    session_s: Any = None,
) -> list[Surroundings | None]:
    """Radiant surroundings of each pair from the first pass (None without view factors)."""
    if view_factors is None:
        return [None, None, None]
    surfaces = first_pass_surfaces_C(
        packs, resistances_20C_ohm, currents_A, ambient_C, view_factors, session_s
    )
    return [radiant_surroundings(view_factors, k, surfaces, ambient_C) for k in range(3)]


def pair_temperatures(
    packs: tuple,
    resistances_20C_ohm: Any,
    currents_A: Any,
    ambient_C: Any,
    view_factors: Any,
    session_s: Any = None,
    only: int | None = None,
) -> list[PairTemperatures | None]:
    """The three pairs at ``currents_A`` (one each), radiating to each other (one Jacobi sweep).

    ``view_factors``: rows ``[room, x, y, z]`` per pair (:func:`coils.viewfactors.
    view_factors`), or None (each pair alone in the room). ``only``: solve the coupled pass for
    that pair alone (the others' first pass is still needed); the other entries are None.
    """
    want = range(3) if only is None else (only,)
    if view_factors is None:
        return [
            end_state(packs[k], resistances_20C_ohm[k], currents_A[k], ambient_C, None, session_s)
            if k in want
            else None
            for k in range(3)
        ]
    surfaces = first_pass_surfaces_C(
        packs, resistances_20C_ohm, currents_A, ambient_C, view_factors, session_s, only
    )
    out: list[PairTemperatures | None] = []
    for k in range(3):
        if k not in want:
            out.append(None)
            continue
        env = radiant_surroundings(view_factors, k, surfaces, ambient_C)
        out.append(
            end_state(packs[k], resistances_20C_ohm[k], currents_A[k], ambient_C, env, session_s)
        )
    return out
