"""Why no design is feasible, said inside the model's domain (issue 36 item 5).

:func:`optimize.optimize_design` explains an infeasible problem at the closest design that
still grips (every wall strain >= ``requirements.min_wall_strain``; ``optimize.grip_bound``):
its shortfalls are that design's own evaluation. Here that design is named with the keys that
reproduce it in ``spiralcap evaluate``, and the advice lists design changes that stay inside
the model (the spiral wire, the magnet, the coil turns, the limit that caps the field) before
relaxing a requirement, and says that lowering the grip row leaves what the paper measured.
One function per text: the CLI and the report print the same words.
"""

from __future__ import annotations

from typing import Any

from spiralcap.core.constants import to_unit

#: Relative distance within which a wall strain counts as held at its minimum (the grip binds).
_TIGHT = 1e-3


def explained_at_values(res: Any) -> dict[str, float]:
    """The design keys (design units) that put ``spiralcap evaluate`` at the design an
    infeasible result is explained at: its helical angle and frequency, and its field where
    the solver chose it (a set or least-power field), else the field the limits allow."""
    ev = res.evaluation
    values = {
        "capsule.spiral.helical_angle_deg": to_unit(ev.helical_angle_rad, "deg"),
        "operation.frequency_hz": float(ev.frequency_hz),
    }
    if ev.field_limited_by == "fixed":
        values["operation.field_amplitude_mT"] = to_unit(float(ev.field_amplitude_T), "mT")
    return values


def grips(res: Any) -> bool:
    """Whether the design an infeasible result is explained at stretches every wall by at
    least ``requirements.min_wall_strain`` (its strain checks hold)."""
    strain = [c for c in res.evaluation.checks if c.name.startswith("wall_strain[")]
    return all(c.ok for c in strain)


def grip_binds(res: Any) -> bool:
    """Whether a wall strain sits at its minimum there (the grip holds the angle down)."""
    return any(
        c.name.startswith("wall_strain[") and abs(c.value / c.allowed - 1.0) <= _TIGHT
        for c in res.evaluation.checks
    )


def explained_at_line(res: Any) -> str:
    """``  explained at the closest design that grips: helical angle 12.04 deg, 1.335 Hz,
    1.922 mT (wall strain >= 1.68 %); spiralcap evaluate --set ... gives these numbers``."""
    ev = res.evaluation
    need = next((c.allowed for c in ev.checks if c.name.startswith("wall_strain[")), float("nan"))
    where = (
        "the closest design that grips"
        if grips(res)
        else "the helical angle that stretches the walls most (none grips)"
    )
    sets = " ".join(f"--set {k}={v!r}" for k, v in explained_at_values(res).items())
    head = (
        f"  explained at {where}: helical angle {ev.helical_angle_deg:.4g} deg, "
        f"{ev.frequency_hz:.4g} Hz, {ev.field_amplitude_T * 1e3:.4g} mT (every wall strain "
        f"{'>=' if grips(res) else 'below'} {100 * need:.3g} %)"
    )
    if not at_design_hardware(res):  # a sizing's closest hardware: the keys alone do not do
        return head
    checked = {c.name for c in ev.checks}
    if all(s.name in checked for s in res.shortfalls):
        return f"{head}; `spiralcap evaluate` with {sets} gives these numbers"
    return f"{head}; `spiralcap evaluate` with {sets} evaluates it (scenario rows aside)"


def at_design_hardware(res: Any) -> bool:
    """Whether an infeasible result stands at the design's own hardware (the fixed-hardware
    explanation, ``optimize.solve``'s message), so its angle, frequency and field keys alone
    reproduce it in ``evaluate``; a sizing's closest design has other hardware."""
    return str(res.message).startswith("infeasible: no design inside the limits meets")


def _names(res: Any) -> set[str]:
    return {s.name.split("[", 1)[0] for s in res.shortfalls}


def advice(res: Any) -> list[str]:
    """What to change, in order: the design inside the model (spiral wire, magnet, coil turns,
    the limit that caps the field), then a requirement; the grip row last, named as leaving
    the paper's measured strains. One sentence each."""
    names = _names(res)
    out: list[str] = []
    if "wall_strain" in names:
        out.append(
            "a thicker spiral wire (capsule.spiral.wire_diameter_mm) or a capsule nearer the "
            "lumen (capsule.diameter_mm) stretches the wall more at every helical angle"
        )
    elif grip_binds(res) and names & {"speed", "margin", "safety_factor"}:
        out.append(
            "a thicker spiral wire (capsule.spiral.wire_diameter_mm) grips at a steeper helical "
            "angle: more advance per turn, so the speed is met at a lower frequency, where the "
            "tissue resists less"
        )
    if names & {"margin", "safety_factor", "solver"}:
        out.append(
            "a stronger magnet (capsule.magnet.diameter_mm, capsule.magnet.length_mm, "
            "capsule.magnet.grade) or more field per ampere (coils.x.turns, coils.y.turns, "
            "coils.z.turns)" + _cap_words(res)
        )
    if "speed" in names and not grip_binds(res):
        out.append("a steeper spiral (optimize.helical_angle_max_deg) or a higher frequency bound")
    limits = _limit_keys(res)
    if limits:
        out.append(
            f"the hardware itself exceeds {', '.join(limits)}: other coil hardware (coils.*, "
            "or --free to size it) or a higher limit"
        )
    if any(not _is_limit(s) for s in res.shortfalls):  # a requirement is short too
        out.append(
            "relaxing a requirement (requirements.*) comes last; lowering "
            "requirements.min_wall_strain below the paper's least measured strain leaves the "
            "model's calibrated domain (it extrapolates)"
        )
    return out


def _limit_keys(res: Any) -> list[str]:
    """The ``limits.*`` keys among the shortfalls (a limit the closest design still breaks:
    the hardware's own copper mass, envelope, clearance), each once."""
    return list(dict.fromkeys(_key(s) for s in res.shortfalls if _is_limit(s)))


def _key(shortfall: Any) -> str:
    from spiralcap.assemble.system import constraint_key

    return constraint_key(shortfall.name) or shortfall.name


def _is_limit(shortfall: Any) -> bool:
    """A shortfall that is a limit the hardware breaks (not a requirement out of reach)."""
    return _key(shortfall).startswith(("limits.", "coils.min_"))


def _cap_words(res: Any) -> str:
    """``, or raising limits.x.power_W, which caps the field there`` (a limit only)."""
    from spiralcap.assemble.system import constraint_key

    name = res.evaluation.field_limited_by
    key = constraint_key(name) if name else ""
    return f", or raising {key}, which caps the field there" if key.startswith("limits.") else ""


def advice_lines(res: Any) -> list[str]:
    """:func:`advice` as the CLI's indented lines, numbered in the order to try them."""
    return ["  what would help, in this order:"] + [
        f"    {i}. {text}" for i, text in enumerate(advice(res), 1)
    ]
