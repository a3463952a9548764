"""How far each toleranced key may stray from a design before a requirement fails.

The design holds over its tolerance box (:class:`optimize.system.Tolerances`): every row at its
own worst corner (:mod:`optimize.physics`). :func:`feasible_intervals` says how much room is
left: each toleranced key (the helical angle, the spiral wire, the lumen) is varied alone, with
its own tolerance off and the other two keys anywhere within theirs (every row at its worst
corner of the other two), at the design's frequency and field, and the interval around the
design's value where every row that depends on the three keys holds is returned with the row
that ends it on each side. The limits (current, voltage, heat, exposure) depend on the field
and the frequency alone, not on these keys, so they do not bound an interval.

The rows are those of :func:`optimize.evaluate.evaluate`, judged with the same relative
tolerance (:data:`optimize.evaluate.FEASIBILITY_RTOL`): the margin (or the safety factor), the
wall strain of every tissue set, the forward speed (0 where the spiral does not grip), the
spiral turns, the self-lock and the spiral's turns kept apart (the geometry rule of
:func:`capsule.geometry_problems`, which a thicker wire or a flatter angle can break); the wire
is searched up to the tool's plausibility bound (``capsule.MAX_WIRE_TO_BODY_DIAMETER``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import capsule as cap
from optimize import physics as ph
from optimize.system import DesignModel, Tolerances, prepare
from spiralcap.core.constants import from_unit

#: The keys varied, as :class:`Tolerances` fields (SI), in the order reported.
KEYS = ("helical_angle_rad", "spiral_wire_diameter_m", "lumen_diameter_m")
#: How far each search goes from the design's value at most (SI: rad, m, m) and how finely the
#: end of an interval is found (the same units).
_REACH = {
    "helical_angle_rad": from_unit(30.0, "deg"),
    "spiral_wire_diameter_m": 2e-3,
    "lumen_diameter_m": 5e-3,
}
_RESOLUTION = {
    "helical_angle_rad": from_unit(1e-3, "deg"),
    "spiral_wire_diameter_m": 1e-7,
    "lumen_diameter_m": 1e-7,
}
#: The least helical angle searched (the tissue model's profile conversion holds above ~1.8°).
_MIN_ANGLE_rad = from_unit(2.0, "deg")
#: The most the search lets the angle reach (a screw thread well short of axial).
_MAX_ANGLE_rad = from_unit(80.0, "deg")


@dataclass(frozen=True)
class FeasibleInterval:
    """Where one toleranced key keeps the design feasible, the others within their tolerances.

    Attributes
    ----------
    key : str
        The :class:`Tolerances` field varied (``helical_angle_rad``, ``spiral_wire_diameter_m``,
        ``lumen_diameter_m``).
    nominal : float
        The design's value, SI (rad, m; for the lumen the offset 0, every set's own lumen).
    tolerance : float
        The design's tolerance on it, SI (rad, m).
    low, high : float
        The interval's ends, SI (the lumen's as an offset from every set's own lumen, m);
        NaN when the design fails at its own value.
    low_limited_by, high_limited_by : str
        The row that fails just beyond each end (``"wall_strain[zhou2013-sample3]"``,
        ``"speed"``, ...), or ``"search"`` when the search reached its end first.
    """

    key: str
    nominal: float
    tolerance: float
    low: float
    high: float
    low_limited_by: str
    high_limited_by: str

    @property
    def holds(self) -> bool:
        """Whether the interval holds the whole tolerance band (value ± tolerance)."""
        return bool(
            self.low <= self.nominal - self.tolerance * (1 - 1e-9)
            and self.high >= self.nominal + self.tolerance * (1 - 1e-9)
        )


def row_slacks(
    model: DesignModel, helical_angle_rad: float, frequency_hz: float, field_T: float
) -> dict[str, float]:
    """Every row that depends on the toleranced keys, as a relative slack (>= -rtol holds).

    Each at its own worst corner of ``model.tolerances``; the same rows and forms as the
    checks of :func:`optimize.evaluate.evaluate`.

    Parameters
    ----------
    model : DesignModel
        The design (prepared).
    helical_angle_rad : float
        Helical angle, rad.
    frequency_hz : float
        Rotation frequency, Hz.
    field_T : float
        Centre field amplitude, T.

    Returns
    -------
    dict of str to float
        Relative slack by row name, dimensionless (>= 0 holds; the self-lock in rad).
    """
    c, req, tol = model.constants, model.requirements, model.tolerances
    corners = ph.required_torque_corners_Nm(
        helical_angle_rad, frequency_hz, c, model.tissues, req, tol
    )
    need = max(float(r + t) for corner in corners for r, t in corner)
    avail = float(ph.available_torque_Nm(field_T, c))
    sf = req.min_safety_factor
    out: dict[str, float] = {}
    name = "margin" if sf == 1.0 else "safety_factor"
    out[name] = (avail - sf * need) / (sf * need) if need > 0 else math.inf
    strains = [
        float(s) for s in ph.toleranced_wall_strains(helical_angle_rad, c, model.tissues, tol)
    ]
    for t, s in zip(model.tissues, strains):
        out[f"wall_strain[{t.name}]"] = s / req.min_wall_strain - 1.0
    speed = float(ph.toleranced_speed_m_s(helical_angle_rad, frequency_hz, c, req, tol))
    speed = speed if min(strains) > 0 else 0.0
    if req.min_speed_m_s > 0:
        out["speed"] = speed / req.min_speed_m_s - 1.0
    if req.min_spiral_turns > 0:
        out["spiral_turns"] = (
            float(ph.toleranced_spiral_turns(helical_angle_rad, c, tol)) / (req.min_spiral_turns)
            - 1.0
        )
    mu = max(float(t.friction_coefficient) for t in model.tissues)
    steepest = ph.angle_corner(helical_angle_rad, tol, +1)
    out["self_lock"] = math.pi / 2 - steepest - math.atan(mu)  # > 0 holds (as evaluate)
    thick = ph.wire_corner(c, tol, +1)  # neighbouring turns apart (capsule.geometry_problems)
    floor = cap.min_helical_angle_for_clearance_rad(
        thick.helix_diameter_m, thick.wire_diameter_m, c.starts
    )
    out["spiral_clearance"] = float(ph.angle_corner(helical_angle_rad, tol, -1) / floor) - 1.0
    return out


def _failing(slacks: dict[str, float]) -> str:
    """The first row that fails (the self-lock at <= 0, the others below -rtol), or ''."""
    from optimize.evaluate import FEASIBILITY_RTOL

    for name, s in slacks.items():
        if (name == "self_lock" and not s > 0) or (
            name != "self_lock" and not s >= -FEASIBILITY_RTOL
        ):
            return name
    return ""


def _variant(model: DesignModel, key: str, value: float) -> tuple[DesignModel, float]:
    """(model, angle) with ``key`` at ``value`` (the lumen: an offset) and its tolerance off."""
    tol = replace(model.tolerances, **{key: 0.0})
    alpha = model.capsule.spiral.helical_angle_rad
    if key == "helical_angle_rad":
        return replace(model, tolerances=tol), value
    if key == "spiral_wire_diameter_m":
        c = replace(
            model.constants,
            wire_diameter_m=value,
            helix_diameter_m=(model.constants.body_diameter_m + value),
        )
        return replace(model, tolerances=tol, constants=c), alpha
    tissues = tuple(t.replace(lumen_diameter_m=t.lumen_diameter_m + value) for t in model.tissues)
    return replace(model, tolerances=tol, tissues=tissues), alpha


def _limits(model: DesignModel, key: str, nominal: float) -> tuple[float, float]:
    """The search's ends for ``key`` (SI): a positive wire and lumen, a screw-thread angle."""
    reach = _REACH[key]
    if key == "helical_angle_rad":
        return max(_MIN_ANGLE_rad, nominal - reach), min(_MAX_ANGLE_rad, nominal + reach)
    if key == "spiral_wire_diameter_m":  # up to the tool's plausibility bound on the wire
        most = cap.MAX_WIRE_TO_BODY_DIAMETER * float(model.constants.body_diameter_m)
        return max(nominal * 1e-3, nominal - reach), min(nominal + reach, most)
    narrowest = min(t.lumen_diameter_m for t in model.tissues)
    return max(-0.9 * narrowest, -reach), reach


def _edge(fails: Any, inside: float, outside: float, resolution: float) -> tuple[float, str]:
    """Bisection between a value that holds and one that fails: (the last that holds, the row
    that fails just beyond it)."""
    why = fails(outside)
    while abs(outside - inside) > resolution:
        mid = 0.5 * (inside + outside)
        row = fails(mid)
        if row:
            outside, why = mid, row
        else:
            inside = mid
    return inside, why


def _side(
    fails: Any, nominal: float, end: float, step: float, resolution: float
) -> tuple[float, str]:
    """The interval's end from ``nominal`` towards ``end``: steps doubling from ``step`` until a
    row fails (then bisection) or the search's end holds (``"search"``)."""
    sign = 1.0 if end > nominal else -1.0
    inside = nominal
    while True:
        trial = nominal + sign * step
        if sign * (trial - end) >= 0:
            if not fails(end):
                return end, "search"
            return _edge(fails, inside, end, resolution)
        if fails(trial):
            return _edge(fails, inside, trial, resolution)
        inside, step = trial, 2.0 * step


def feasible_intervals(
    model: DesignModel,
    helical_angle_rad: float,
    frequency_hz: float,
    field_T: float,
) -> tuple[FeasibleInterval, ...]:
    """Each toleranced key's feasible interval around the design, the others within their
    tolerances (module docstring).

    Parameters
    ----------
    model : DesignModel
        The design.
    helical_angle_rad : float
        The design's helical angle, rad.
    frequency_hz : float
        The operating frequency, Hz.
    field_T : float
        The operating field amplitude at the centre, T.

    Returns
    -------
    tuple of FeasibleInterval
        One per key of :data:`KEYS`, SI.
    """
    model = prepare(model)
    model = replace(
        model,
        capsule=replace(
            model.capsule,
            spiral=replace(model.capsule.spiral, helical_angle_rad=float(helical_angle_rad)),
        ),
    )
    nominals = {
        "helical_angle_rad": float(helical_angle_rad),
        "spiral_wire_diameter_m": float(model.constants.wire_diameter_m),
        "lumen_diameter_m": 0.0,
    }
    out = []
    for key in KEYS:
        nominal, tol = nominals[key], float(getattr(model.tolerances, key))

        def fails(value: float, key: str = key) -> str:
            variant, alpha = _variant(model, key, value)
            return _failing(row_slacks(variant, alpha, frequency_hz, field_T))

        if fails(nominal):
            nan = float("nan")
            out.append(
                FeasibleInterval(key, nominal, tol, nan, nan, fails(nominal), fails(nominal))
            )
            continue
        lo_end, hi_end = _limits(model, key, nominal)
        step = max(tol, 0.01 * _REACH[key])
        lo, lo_by = _side(fails, nominal, lo_end, step, _RESOLUTION[key])
        hi, hi_by = _side(fails, nominal, hi_end, step, _RESOLUTION[key])
        out.append(FeasibleInterval(key, nominal, tol, lo, hi, lo_by, hi_by))
    return tuple(out)


__all__ = ["KEYS", "FeasibleInterval", "Tolerances", "feasible_intervals", "row_slacks"]
