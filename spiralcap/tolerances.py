"""Each toleranced key's feasible interval around a design, in design-key units and words.

:func:`optimize.tolerance.feasible_intervals` varies the helical angle, the spiral wire and the
lumen one at a time (the other two anywhere within their tolerances) at the design's frequency
and field; this module turns its SI records into rows the CLI text, the JSON and the report
share: the design key, its value and tolerance, the interval and the requirement that ends it
on each side.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from spiralcap.core.constants import design_unit, to_unit
from spiralcap.keymap import design_key

#: What the intervals hold (said in the text, the JSON and the report).
VARIED = (
    "each key varied alone, the other two anywhere within their tolerances (every requirement "
    "at its own worst corner of them), at the design's frequency and field"
)

#: optimize.tolerance key -> (its model field of :data:`spiralcap.keymap.FIELD_KEYS`, label);
#: the design key, the tolerance key, the unit and the factor follow from the field (:func:`_key`)
_FIELDS = {
    "helical_angle_rad": ("spiral.helical_angle_rad", "helical angle"),
    "spiral_wire_diameter_m": ("spiral.wire_diameter_m", "spiral wire"),
    "lumen_diameter_m": ("tissue.lumen_diameter_m", "lumen"),
}


def _key(name: str) -> tuple[str, str, str, float, str]:
    """(design key, tolerance key, unit, SI -> unit factor, label) of an optimize.tolerance key:
    ``helical_angle_rad`` -> ``capsule.spiral.helical_angle_deg``, ``tolerances.helical_angle_deg``,
    ``deg``, 180/pi (the unit table), ``helical angle``."""
    field, label = _FIELDS[name]
    key = design_key(field)
    suffix, si_suffix, _ = design_unit(key)
    tolerance_key = "tolerances." + name.removesuffix(si_suffix) + suffix
    return key, tolerance_key, suffix[1:], to_unit(1.0, suffix[1:]), label


_KEYS = {name: _key(name) for name in _FIELDS}


@dataclass(frozen=True)
class IntervalRow:
    """One toleranced key's feasible interval in its design key's unit.

    Attributes
    ----------
    key : str
        The design key varied (``capsule.spiral.helical_angle_deg``, ...).
    tolerance_key : str
        Its tolerance's key (``tolerances.helical_angle_deg``, ...).
    unit : str
        The key's unit (``deg``, ``mm``).
    nominal : float
        The design's value (the lumen: the one every tissue set shares, or 0 when the sets keep
        their own lumens and the interval is an offset from each), in ``unit``.
    tolerance : float
        The key's tolerance, in ``unit``.
    low, high : float
        The interval, in ``unit`` (NaN when the design fails at its own value).
    low_limited_by, high_limited_by : str
        The requirement (optimiser row name) that fails just beyond each end, or ``"search"``.
    offset : bool
        Flag: ``nominal``, ``low`` and ``high`` are offsets from every set's own lumen.
    holds : bool
        Flag: the interval holds the whole band value ± tolerance.
    """

    key: str
    tolerance_key: str
    unit: str
    nominal: float
    tolerance: float
    low: float
    high: float
    low_limited_by: str
    high_limited_by: str
    offset: bool
    holds: bool


def _shared_lumen_m(model: Any) -> float | None:
    """The lumen every tissue set shares, m, or None when they differ."""
    lumens = {t.lumen_diameter_m for t in model.tissues}
    return lumens.pop() if len(lumens) == 1 else None


def interval_rows(
    model: Any, helical_angle_rad: float, frequency_hz: float, field_T: float
) -> tuple[IntervalRow, ...]:
    """:func:`optimize.tolerance.feasible_intervals` in design-key units.

    Parameters
    ----------
    model : optimize.DesignModel
        The design.
    helical_angle_rad : float
        Its helical angle, rad.
    frequency_hz : float
        Its operating frequency, Hz.
    field_T : float
        Its operating field at the centre, T.

    Returns
    -------
    tuple of IntervalRow
        Angle, spiral wire, lumen.
    """
    from optimize.tolerance import feasible_intervals

    shared = _shared_lumen_m(model)
    out = []
    for iv in feasible_intervals(model, helical_angle_rad, frequency_hz, field_T):
        key, tol_key, unit, factor, _ = _KEYS[iv.key]
        base = 0.0
        if iv.key == "lumen_diameter_m" and shared is not None:
            base = shared
        out.append(
            IntervalRow(
                key=key,
                tolerance_key=tol_key,
                unit=unit,
                nominal=(base + iv.nominal) * factor,
                tolerance=iv.tolerance * factor,
                low=(base + iv.low) * factor,
                high=(base + iv.high) * factor,
                low_limited_by=iv.low_limited_by,
                high_limited_by=iv.high_limited_by,
                offset=iv.key == "lumen_diameter_m" and shared is None,
                holds=iv.holds,
            )
        )
    return tuple(out)


def evaluation_rows(model: Any, ev: Any) -> tuple[IntervalRow, ...]:
    """:func:`interval_rows` at an evaluation's operating point.

    Parameters
    ----------
    model : optimize.DesignModel
        The design evaluated.
    ev : optimize.Evaluation
        Its evaluation (angle, frequency, field).

    Returns
    -------
    tuple of IntervalRow
        Angle, spiral wire, lumen.
    """
    return interval_rows(model, ev.helical_angle_rad, ev.frequency_hz, ev.field_amplitude_T)


def optimum_rows(design: Any, res: Any) -> tuple[IntervalRow, ...]:
    """:func:`interval_rows` at an optimum: the design with the optimum's values set (its
    angle, frequency, field where set and sized hardware, as ``optimize -o`` writes it).

    Parameters
    ----------
    design : spiralcap.design.Design
        The design optimised.
    res : optimize.OptimizationResult
        Its optimum (status ``optimal``).

    Returns
    -------
    tuple of IntervalRow
        Angle, spiral wire, lumen; empty without an optimum.
    """
    if res.status != "optimal":
        return ()
    from spiralcap.assemble import build_model
    from spiralcap.assemble.system import optimum_values

    model = build_model(design.with_values(optimum_values(design, res)))
    return evaluation_rows(model, res.evaluation)


def _end_words(name: str) -> str:
    """The requirement that ends an interval, in words with its design key."""
    from spiralcap.presentation import readable

    if name == "search":
        return "beyond the search"
    return readable(name)


def _g(x: float) -> str:
    return f"{x:.4g}"


def text_lines(rows: tuple[IntervalRow, ...]) -> list[str]:
    """The intervals as text lines (``holds for lumens 10.33-11.1 mm``), the first naming what
    was varied; empty without rows.

    Parameters
    ----------
    rows : tuple of IntervalRow
        The intervals.

    Returns
    -------
    list of str
        Lines for the CLI's text output.
    """
    if not rows:
        return []
    lines = [
        "tolerances          every requirement above is held at its own worst corner of the "
        "[tolerances] box (its strains, speed, turns and margin are those corners'); the room "
        f"left, {VARIED}:"
    ]
    for r in rows:
        label = _LABELS[r.key]
        asked = (
            f"± {_g(r.tolerance)} {r.unit} about every set's own lumen"
            if r.offset
            else f"{_g(r.nominal)} ± {_g(r.tolerance)} {r.unit}"
        )
        if not math.isfinite(r.low):
            lines.append(
                f"  {label:<15}{asked}: FAILS at the design's own value "
                f"({_end_words(r.low_limited_by)})"
            )
            continue
        span = (
            f"offsets {r.low:+.4g} to {r.high:+.4g} {r.unit}"
            if r.offset
            else f"{_g(r.low)}-{_g(r.high)} {r.unit}"
        )
        verdict = "holds for" if r.holds else "DOES NOT HOLD its band; holds only for"
        lines.append(
            f"  {label:<15}{asked}: {verdict} {span} (below: "
            f"{_end_words(r.low_limited_by)}; above: {_end_words(r.high_limited_by)})"
        )
    return lines


_LABELS = {v[0]: v[4] for v in _KEYS.values()}


def to_dict(rows: tuple[IntervalRow, ...]) -> dict[str, Any]:
    """The intervals for the JSON outputs (``tolerance_intervals``).

    Parameters
    ----------
    rows : tuple of IntervalRow
        The intervals.

    Returns
    -------
    dict
        ``varied`` (what the intervals hold) and ``keys`` (one record per key, values in the
        key's unit; ``low`` and ``high`` absent where the design fails at its own value), each
        with the design keys behind the ends.
    """
    from spiralcap.assemble.system import constraint_key

    def ends(r: IntervalRow) -> dict[str, float]:  # absent where the design fails at its value
        return {"low": r.low, "high": r.high} if math.isfinite(r.low) else {}

    return {
        "varied": VARIED,
        "keys": [
            {
                "key": r.key,
                "tolerance_key": r.tolerance_key,
                "unit": r.unit,
                "nominal": r.nominal,
                "tolerance": r.tolerance,
                "feasible_at_nominal": math.isfinite(r.low),
                **ends(r),
                "low_limited_by": r.low_limited_by,
                "high_limited_by": r.high_limited_by,
                "low_limited_by_key": constraint_key(r.low_limited_by),
                "high_limited_by_key": constraint_key(r.high_limited_by),
                "offset_from_each_tissue_set": r.offset,
                "holds": r.holds,
            }
            for r in rows
        ],
    }
