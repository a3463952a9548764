"""The conclusion a design review asks for, computed from the results (not canned text).

Is the design safe as entered, what binds, what to change first, what fails first under
uncertainty -- and which exposure levels apply to whom. Every number is in the embedded JSON's
``"conclusion"`` entry (:func:`conclusion_payload`), computed here from the evaluation, the
optimisation and the tissue-uncertainty study the rest of the report shows.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from spiralcap.report.document import Inline, Link, Paragraph, Section, Strong
from spiralcap.report.sections._util import Context, readable
from spiralcap.report.sections.summary import change_first

#: Above this failure probability (step-out or lost grip) the uncertainty section raises an
#: alert; the conclusion
#: calls the design unsafe under tissue uncertainty at the same level.
STEPOUT_ALERT = 0.05

#: Peripheral-nerve-stimulation threshold of a long magnetic-field change, T/s: the rheobase
#: of the hyperbolic threshold dB/dt = 20 (1 + 0.36 ms / t) T/s of ICNIRP's statement on MR
#: procedures (2004), on which IEC 60601-2-33's gradient limits rest.
PNS_RHEOBASE_T_PER_S = 20.0

#: A check within this relative distance of its bound is at its limit (as binding limits are).
BINDING_RTOL = 1e-6

#: References the conclusion cites, listed after the assumptions section's [1]-[12].
REFERENCES: tuple[str, ...] = (
    '[13] ICNIRP, "Medical magnetic resonance (MR) procedures: protection of patients", '
    "Health Physics 87(2):197-216, 2004.",
    "[14] IEC 60601-2-33, Medical electrical equipment - Part 2-33: Particular requirements "
    "for the basic safety and essential performance of magnetic resonance equipment for "
    "medical diagnosis (gradient output limited by peripheral nerve stimulation).",
)


def headroom(check: Mapping[str, Any], required_torque_Nm: float) -> float | None:
    """How far a check is from failing, as a fraction of what it is measured against.

    ``value >= allowed``: (value - allowed) / |allowed|; ``value <= allowed``: (allowed -
    value) / |allowed|. The margin (allowed 0) is measured against the required torque (how
    much the required torque may rise before the capsule steps out); another check with
    ``allowed == 0`` against pi/2 (the self-locking angle margin, rad). None when undefined.
    """
    value, allowed, sense = check.get("value"), check.get("allowed"), check.get("sense", "")
    if not isinstance(value, (int, float)) or not isinstance(allowed, (int, float)):
        return None
    if math.isnan(value):  # the margin where the spiral does not touch: no margin, no headroom
        return None
    if check.get("name") == "margin":
        return value / required_torque_Nm if required_torque_Nm > 0 else None
    # checks_by_headroom rounds a relative 1e-6 to 0: "at its limit", as the binding list does
    scale = abs(allowed) if allowed != 0 else (math.pi / 2 if check.get("unit") == "rad" else 0)
    if scale == 0:
        return None
    h = (value - allowed) / scale if sense.startswith(">") else (allowed - value) / scale
    return 0.0 if abs(h) < BINDING_RTOL else h


def conclusion_payload(
    evaluation: Mapping[str, Any],
    optimization: Mapping[str, Any],
    design: Mapping[str, Any],
    uncertainty: Mapping[str, Any] | None,
) -> dict[str, Any]:
    """The conclusion's numbers, from the ``evaluate`` and ``optimize`` JSON of the report."""
    from optimize.physics import exposure_level_T

    required = float(evaluation["required_torque_Nm"])
    rows = []
    for c in evaluation["checks"]:
        h = headroom(c, required)
        if h is not None:
            rows.append({"name": c["name"], "key": c["key"], "ok": c["ok"], "headroom": h})
    rows.sort(key=lambda r: r["headroom"])
    resistive = float(evaluation["resistive_torque_Nm"])
    margin = evaluation.get("margin_Nm")  # absent or None: no contact, no margin
    margin = float(margin) if isinstance(margin, (int, float)) else math.nan
    objective = optimization.get("objective_value")
    gains = []
    if optimization.get("status") == "optimal" and isinstance(objective, (int, float)):
        for b in optimization.get("binding_limits", []):
            allowed, gain = b.get("allowed"), b.get("gain_per_unit_relaxed")
            if (
                isinstance(allowed, (int, float))
                and isinstance(gain, (int, float))
                and allowed != 0
                and objective != 0
            ):
                gains.append(
                    {
                        "name": b["name"],
                        "key": b["key"],
                        "relaxing_means": b.get("relaxing_means", "relaxing"),
                        # % of the objective per 1 % of the bound relaxed (the JSON unit)
                        "objective_percent_per_percent": gain * abs(allowed) / abs(objective),
                    }
                )
    gains.sort(key=lambda g: -g["objective_percent_per_percent"])
    f = float(evaluation["frequency_hz"])
    b0 = float(evaluation["field_amplitude_T"])
    occupational = float(exposure_level_T(f, "occupational"))
    public = float(exposure_level_T(f, "public"))
    out: dict[str, Any] = {
        "safe_as_entered": bool(evaluation["feasible"]),
        "checks_by_headroom": rows,
        "tissue_torque_headroom": margin / resistive
        if resistive > 0 and math.isfinite(margin)
        else None,
        "limit_gains": gains,
        "exposure": {
            "field_exposure": design.get("limits.field_exposure"),
            "frequency_hz": f,
            "field_amplitude_T": b0,
            "occupational_level_T": occupational,
            "public_level_T": public,
            "occupational_fraction": b0 / occupational,
            "public_fraction": b0 / public,
            "field_rate_T_per_s": 2.0 * math.pi * f * b0,
            "pns_rheobase_T_per_s": PNS_RHEOBASE_T_PER_S,
        },
    }
    if uncertainty is not None:
        p = float(uncertainty["stepout_probability"])
        out["stepout_probability"] = p
        # a failure is a step-out or a lost grip (below the minimum wall strain)
        p = float(uncertainty["failure_probability"]["value"])
        out["failure_probability"] = p
        out["safe_under_uncertainty"] = bool(evaluation["feasible"]) and p <= STEPOUT_ALERT
    return out


def _has(ctx: Context, path: str) -> bool:
    from spiralcap.report.numbers import lookup

    try:
        lookup(ctx.payload, path)
    except KeyError:
        return False
    return True


def _is_safe(ctx: Context) -> Paragraph:
    c, e = "conclusion", "evaluate"
    safe = ctx.value(f"{c}.safe_as_entered")
    failing = [r for r in ctx.value(f"{c}.checks_by_headroom") if not r["ok"]]
    parts: list[Inline] = [Strong("Is it safe? ")]
    if safe:
        parts += [
            "As entered, yes: every requirement and limit holds, with a worst-case margin of ",
            ctx.num(f"{e}.margin_Nm", 1e3, "mN·m"),
            f" against the {ctx.value(f'{e}.worst_tissue')} tissue",
        ]
    else:
        parts += [
            "As entered, no: it fails ",
            ", ".join(f"{readable(r['name'])} ({r['key']})" for r in failing) or "a check",
        ]
    kind = "ok" if safe else "alert"
    if _has(ctx, f"{c}.failure_probability"):
        p = ctx.value(f"{c}.failure_probability")
        parts += [
            "; over the tissue uncertainty it fails (steps out or loses its grip) with "
            "probability ",
            ctx.num(f"{c}.failure_probability", 100.0, "%"),
            (" (above 5 %: not safe enough)" if p > STEPOUT_ALERT else ""),
        ]
        if not ctx.value(f"{c}.safe_under_uncertainty"):
            kind = "alert"
    parts.append(".")
    return Paragraph(parts, kind=kind)


def _what_binds(ctx: Context) -> Paragraph:
    c = "conclusion"
    rows = ctx.value(f"{c}.checks_by_headroom")
    parts: list[Inline] = [Strong("What binds. "), "As entered, the nearest limits are "]
    near = [(i, r) for i, r in enumerate(rows) if r["ok"]][:3]
    for k, (i, r) in enumerate(near):
        if k:
            parts.append(", " if k < len(near) - 1 else " and ")
        if r["headroom"] == 0:
            parts.append(f"{readable(r['name'])} ({r['key']}, at its limit)")
            continue
        parts += [
            f"{readable(r['name'])} ({r['key']}, ",
            ctx.num(f"{c}.checks_by_headroom.{i}.headroom", 100.0, "%"),
            " headroom)",
        ]
    parts.append(". ")
    binding = ctx.value("optimize.binding_limits") or []
    if ctx.value("optimize.status") == "optimal":
        if binding:
            names = ", ".join(f"{readable(b['name'])} ({b['key']})" for b in binding)
            parts.append(f"At the optimum these bind: {names}.")
        else:
            parts.append("At the optimum no limit binds.")
    else:
        parts.append("No design inside the limits meets every requirement (section Optimum).")
    return Paragraph(parts)


def _fails_first(ctx: Context) -> Paragraph:
    c = "conclusion"
    parts: list[Inline] = [Strong("What would fail first under uncertainty. ")]
    rows = [r for r in ctx.value(f"{c}.checks_by_headroom") if r["ok"]]
    headroom = ctx.value(f"{c}.tissue_torque_headroom")
    if headroom is not None and headroom < 0:
        parts.append(
            "As entered the capsule already steps out: the worst-case tissue torque exceeds "
            "what the magnet delivers at the operating point. "
        )
    elif headroom is not None:
        parts += [
            "The tissue torque is the least certain input: the capsule steps out once the "
            "worst-case tissue's resistive torque rises ",
            ctx.num(f"{c}.tissue_torque_headroom", 100.0, "%"),
            " above the model's value. ",
        ]
    others = [r for r in rows if r["name"] != "margin"]
    if others:
        i = ctx.value(f"{c}.checks_by_headroom").index(others[0])
        first = f"{readable(others[0]['name'])} ({others[0]['key']})"
        if others[0]["headroom"] == 0:
            parts.append(
                f"Of the hardware limits and requirements, {first} is at its limit: it sets the "
                "field as entered, so any drift against it (ambient, copper resistance, supply) "
                "is met only by a lower field, and so a smaller margin. "
            )
        else:
            parts += [
                f"Of the hardware limits and requirements, {first} has the least headroom (",
                ctx.num(f"{c}.checks_by_headroom.{i}.headroom", 100.0, "%"),
                "). ",
            ]
    if _has(ctx, f"{c}.failure_probability"):
        parts += [
            "Sampling the design's [tissue.uncertainty], the capsule fails with probability ",
            ctx.num("uncertainty.failure_probability.value", 100.0, "%"),
            " (steps out ",
            ctx.num("uncertainty.failure_probability.parts.stepout_probability.value", 100.0, "%"),
            ", below the minimum wall strain ",
            ctx.num(
                "uncertainty.failure_probability.parts.below_min_strain_probability.value",
                100.0,
                "%",
            ),
            ") and the 5th-percentile margin is ",
            ctx.num("uncertainty.margin_percentiles_Nm.p05", 1e3, "mN·m"),
            " (",
            Link("section Tissue uncertainty", "uncertainty"),
            ").",
        ]
    else:
        parts.append(
            "The design has no [tissue.uncertainty] table: add one (spiralcap uncertainty) to "
            "put a probability on step-out."
        )
    return Paragraph(parts)


def _exposure(ctx: Context) -> Paragraph:
    x = "conclusion.exposure"
    chosen = ctx.value(f"{x}.field_exposure")
    parts: list[Inline] = [
        Strong("Who the exposure levels protect. "),
        "ICNIRP 2010 [2] sets reference levels for non-medical exposure: the occupational "
        "levels for workers exposed in their job under known conditions (the operator and the "
        "staff at the coils), the general-public levels for everyone else present "
        "(accompanying persons, other staff). At the workspace centre the rotating field is ",
        ctx.num(f"{x}.field_amplitude_T", 1e3, "mT"),
        " at ",
        ctx.num(f"{x}.frequency_hz", unit="Hz"),
        ": ",
        ctx.num(f"{x}.occupational_fraction", 100.0, "%"),
        " of the occupational level (",
        ctx.num(f"{x}.occupational_level_T", 1e3, "mT"),
        ") and ",
        ctx.num(f"{x}.public_fraction", 100.0, "%"),
        " of the public level (",
        ctx.num(f"{x}.public_level_T", 1e3, "mT"),
        "). The levels apply where people are; near the windings the field is higher than at "
        "the centre, so map it there before the coils are run with people present. ",
        *(
            [
                "The centre field exceeds the public level: keep people who are not "
                "occupationally exposed away from the coils while they run. "
            ]
            if ctx.value(f"{x}.public_fraction") > 1
            else []
        ),
        (
            f"The design applies the {chosen} level (limits.field_exposure) to the centre "
            "field as a design cap. "
            if chosen != "off"
            else "limits.field_exposure is 'off': no reference level caps the field. "
        ),
        "The patient is not protected by these levels: the patient's exposure is a medical "
        "exposure, outside the scope of ICNIRP's exposure limits and weighed by benefit "
        "against risk under the medical-device standards. The closest reference for a "
        "time-varying field applied to a patient is the limit on its rate of change set by "
        "peripheral nerve stimulation, a threshold of about ",
        ctx.num(f"{x}.pns_rheobase_T_per_s", unit="T/s"),
        " for long stimuli (ICNIRP 2004 [13], the basis of IEC 60601-2-33's gradient limits "
        "[14]); the rotating field here changes at 2πfB0 = ",
        ctx.num(f"{x}.field_rate_T_per_s", unit="T/s"),
        ". This is a reference point for the device's risk file, not a compliance statement.",
    ]
    return Paragraph(parts)


def build(ctx: Context) -> Section:
    """The conclusion section (its references [13]-[14] are listed with the assumptions')."""
    return Section(
        "conclusion",
        "Conclusion",
        [
            _is_safe(ctx),
            _what_binds(ctx),
            change_first(ctx),
            _fails_first(ctx),
            _exposure(ctx),
        ],
    )
