"""Hardware that cannot work, decided without its NLP (sizing's neighbours in copper order).

A fixed-hardware design is feasible only if some operating point (helical angle α, frequency
f, centre field B0) meets every row. Two facts bound B0 from below without the coils:

1. every tissue's safety-factor row asks ``m · w · B0 >= SF · need_i(α, f)`` (m the magnet's
   moment, w the workspace field factor), so ``B0 >= SF · R_min / (m · w)`` with ``R_min`` the
   least worst-tissue required torque over the (α, f) the requirements allow (the search box,
   speed, spiral turns, the grip on every wall; the self-lock rows only shrink that set, so
   they are left out);
2. ``R_min`` depends on the capsule, the tissues and the requirements only: the same for every
   neighbour whose free hardware is coils alone, so it is found once per sizing
   (:func:`least_required_torque_Nm`: the best point of a dense grid, polished by SLSQP).

The current, hot-spot, surface-temperature and copper-loss rows only grow with B0 (more current,
more heat), so if one of them is already violated at that least field the design is infeasible
at every operating point (:func:`out_of_reach`); the voltage and exposure rows also depend on f
and are not used. Margins of 1e-6 relative on both steps keep the answer on the side of the
NLP's own tolerances (1e-10): whatever is screened out, the NLP would not solve.
tests/test_sizing_speed.py checks every buildable neighbour of three sizings against its full
solve.
"""

from __future__ import annotations

import numpy as np

from optimize import physics as ph
from optimize.system import DesignModel, prepare

__all__ = ["RTOL", "least_required_torque_Nm", "out_of_reach", "screens"]

#: Relative margin on the least required torque and on each limit before a design is ruled out.
RTOL = 1e-6
#: Grid of the search for the least required torque (angle x log-frequency points).
_GRID = 96
#: Rows that grow with the centre field alone (the voltage and exposure rows depend on f too).
_FIELD_ONLY = ("current_", "hot_spot_", "surface_temperature_", "power")


#: Objectives whose sizings the screen pays for: least copper drives the coils down to their
#: field-only limits, where many neighbours break one (46 % of a six-key sizing at safety factor
#: 2.5). A margin or least-power sizing's neighbours seldom do: there the screen ruled nothing
#: out and cost its least torque (scipy's SLSQP and its import, 0.2-0.3 s of 2.5 s).
SCREENED_OBJECTIVES = ("copper_mass",)


def screens(model: DesignModel) -> bool:
    """Whether neighbours of ``model``'s sizing share one least required torque worth finding:
    the objective is one of :data:`SCREENED_OBJECTIVES`, the free hardware is coils only (no
    magnet or spiral key) and no tissue scenarios set the need. The screen never changes the
    sized result, only what is solved (``tests/test_sizing_speed.py``).

    Parameters
    ----------
    model : DesignModel
        A design model, SI (its ``sizing`` and ``scenarios`` are read).

    Returns
    -------
    bool
        Flag: the screen applies (False without free hardware).
    """
    sizing = model.sizing
    if sizing is None or (model.scenarios is not None and model.scenarios.whole):
        return False
    if model.bounds.objective not in SCREENED_OBJECTIVES:
        return False
    return all(v.name.split(".", 1)[0] in ("x", "y", "z") for v in sizing.free)


def least_required_torque_Nm(model: DesignModel) -> float:
    """The least worst-tissue required torque over the (α, f) the requirements allow, N·m.

    A dense grid over the search box (angle x log frequency) and SLSQP from its best point in
    each angle band (the problem need not be convex in the angle), with the speed and
    spiral-turn requirements and the grip (the least wall strain) relaxed by :data:`RTOL`; the smallest value found, minus
    :data:`RTOL` of it (a lower bound to the polish's tolerance). ``inf`` where no point of the
    grid meets the speed and turn requirements (nothing is then ruled out by it).

    Parameters
    ----------
    model : DesignModel
        A fixed-hardware design (``sizing`` None), SI: its capsule, tissues, requirements and
        search box are read (prepared here).

    Returns
    -------
    float
        The least worst-tissue required torque less :data:`RTOL` of it, N·m; ``inf`` if no
        grid point meets the speed, spiral-turn and grip requirements.
    """
    from scipy.optimize import minimize

    from optimize.evaluate import least_wall_strain, worst_required

    model = prepare(model)
    b, c, req = model.bounds, model.constants, model.requirements
    lo_f, hi_f = np.log(b.frequency_min_hz), np.log(b.frequency_max_hz)
    alphas = np.linspace(b.helical_angle_min_rad, b.helical_angle_max_rad, _GRID)
    A, LF = np.meshgrid(alphas, np.linspace(lo_f, hi_f, _GRID), indexing="ij")
    v_min = req.min_speed_m_s * (1.0 - RTOL)
    n_min = req.min_spiral_turns * (1.0 - RTOL)

    tol = model.tolerances  # the rows as the NLP holds them, each at its worst corner

    def speed(a, lf):
        return np.asarray(ph.toleranced_speed_m_s(a, np.exp(lf), c, req, tol), dtype=float)

    def turns(a):
        return np.asarray(ph.toleranced_spiral_turns(a, c, tol), dtype=float)

    def need(a, lf):
        # the flattest angle's corner alone: a smooth lower bound on the NLP's required torque
        # (the larger of both angle ends, whose minimum sits on their kink)
        if tol.any:
            corner = ph.required_torque_corners_Nm(a, np.exp(lf), c, model.tissues, req, tol)[0]
            return np.max([np.asarray(r + t, dtype=float) for r, t in corner], axis=0)
        return np.asarray(worst_required(model, a, np.exp(lf)).total_Nm, dtype=float)

    s_min = req.min_wall_strain * (1.0 - RTOL)

    def grip(a):  # the least wall strain over the tissue sets (the spiral grips every wall)
        return np.asarray(least_wall_strain(model, a), dtype=float)

    ok = (speed(A, LF) >= v_min) & (turns(A) >= n_min) & (grip(A) >= s_min)
    grid = np.where(ok, need(A, LF), np.inf)
    best = float(grid.min())
    if not np.isfinite(best):
        return float("inf")
    scale = abs(best) if best != 0.0 else 1.0
    speed_ref = max(req.min_speed_m_s, 1e-12)
    constraints = [
        {"type": "ineq", "fun": lambda z: (float(speed(z[0], z[1])) - v_min) / speed_ref},
        {"type": "ineq", "fun": lambda z: float(turns(z[0])) - n_min},
        {"type": "ineq", "fun": lambda z: (float(grip(z[0])) - s_min) / req.min_wall_strain},
    ]
    box = [(b.helical_angle_min_rad, b.helical_angle_max_rad), (lo_f, hi_f)]
    for band in np.array_split(np.arange(_GRID), max(b.starts, 1)):
        sub = grid[band]
        if not np.isfinite(sub.min()):
            continue
        i, j = np.unravel_index(np.argmin(sub), sub.shape)
        res = minimize(
            lambda z: float(need(z[0], z[1])) / scale,
            [A[band][i, j], LF[band][i, j]],
            method="SLSQP",
            bounds=box,
            constraints=constraints,
            options={"ftol": 1e-14, "maxiter": 200},
        )
        z = np.clip(res.x, [lo for lo, _ in box], [hi for _, hi in box])
        if (
            speed(z[0], z[1]) >= v_min * (1.0 - 1e-9)
            and turns(z[0]) >= n_min * (1.0 - 1e-9)
            and grip(z[0]) >= s_min * (1.0 - 1e-9)
        ):
            best = min(best, float(need(z[0], z[1])))
    return best - RTOL * abs(best)


def out_of_reach(model: DesignModel, least_required_Nm: float) -> str | None:
    """The limit row the fixed-hardware ``model`` already breaks at the least field its
    requirements need, ``SF · R_min / (m · w)`` (then no operating point is feasible); None if
    none does (the NLP decides).

    Parameters
    ----------
    model : DesignModel
        A fixed-hardware design (``sizing`` None), SI (prepared here).
    least_required_Nm : float
        The least required torque ``R_min`` (:func:`least_required_torque_Nm` of the sizing),
        N·m; ``inf`` or <= 0 rules nothing out.

    Returns
    -------
    str or None
        The name of the first field-only limit row (current, hot spot, surface temperature,
        copper loss) broken beyond :data:`RTOL` (or not finite) at that field; None if none is.
    """
    if not np.isfinite(least_required_Nm) or least_required_Nm <= 0.0:
        return None
    model = prepare(model)
    c = model.constants
    per_tesla = float(ph.available_torque_Nm(1.0, c))  # m · w: available torque per tesla
    if not per_tesla > 0.0:
        return None
    sf = max(float(model.requirements.min_safety_factor), 0.0)
    field = sf * least_required_Nm / per_tesla
    f = model.bounds.frequency_min_hz  # only the field's rows are read
    for term in ph.limit_terms(f, field, c, model.limits, model.ambient_temperature_C):
        if not term.name.startswith(_FIELD_ONLY):
            continue
        value, allowed = float(np.asarray(term.value)), float(np.asarray(term.allowed))
        if not np.isfinite(value) or value > allowed + RTOL * abs(allowed):
            return term.name
    return None
