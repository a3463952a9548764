"""Two or more designs side by side: the keys that differ, their evaluations and optimisations.

:func:`compare_designs` evaluates and optimises every design (the same functions as
``spiralcap evaluate`` and ``optimize``) and returns a typed :class:`Comparison` that the
``spiralcap compare`` command prints and the report's comparison section shows. Values are
kept in SI; every :class:`Row` knows how it is shown (unit and factor from
:mod:`spiralcap.presentation`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from spiralcap.design import Design
from spiralcap.presentation import readable, shown

#: Relative difference below which two values count as equal.
SAME_RTOL = 1e-9


@dataclass(frozen=True)
class KeyDifference:
    """A design key whose value differs between the designs (values as in the design files)."""

    key: str
    values: tuple[Any, ...]


@dataclass(frozen=True)
class Row:
    """One compared quantity: SI values per design, how it is shown, and whether they differ."""

    quantity: str
    si_unit: str
    values: tuple[Any, ...]
    differs: bool

    @property
    def unit(self) -> str:
        """The unit the row is shown in (mN·m for N·m, mT for T, ...)."""
        return shown(self.si_unit)[0]

    def shown_values(self) -> tuple[Any, ...]:
        """The values in :attr:`unit`."""
        factor = shown(self.si_unit)[1]
        return tuple(
            v * factor if isinstance(v, (int, float)) and not isinstance(v, bool) else v
            for v in self.values
        )


@dataclass(frozen=True)
class Above:
    """A value a search stopped short of: only known to be above ``bound`` (the step-out
    search's ceiling), shown as ``above 200`` and never differenced as if it were a value."""

    bound: float

    def __str__(self) -> str:
        return f"above {shown_value(self.bound, exact=False)}"


def _searched(hz: float, beyond: bool) -> float | Above:
    """A frequency from a bounded search: the value, or :class:`Above` its ceiling."""
    from optimize.evaluate import STEP_OUT_SEARCH_HZ

    top = STEP_OUT_SEARCH_HZ[1]
    if math.isnan(hz) and not beyond:  # no search: no contact, no margin to reach zero
        return math.nan
    if beyond or not math.isfinite(hz) or hz >= top:
        return Above(float(hz) if math.isfinite(hz) and hz < top else float(top))
    return hz


@dataclass(frozen=True)
class Comparison:
    """Designs side by side: labels, changed keys, rows at the operating point and optimum."""

    labels: tuple[str, ...]
    sources: tuple[str, ...]
    sha256: tuple[str, ...]
    changed_keys: tuple[KeyDifference, ...]
    evaluated: tuple[Row, ...]
    optimised: tuple[Row, ...]
    evaluations: tuple[Any, ...]
    optimizations: tuple[Any, ...]


def _differs(values: Sequence[Any]) -> bool:
    first = values[0]
    for v in values[1:]:
        if isinstance(v, float) and isinstance(first, float):
            if not (math.isclose(v, first, rel_tol=SAME_RTOL, abs_tol=1e-300) or v == first):
                return True
        elif v != first:
            return True
    return False


def _row(quantity: str, si_unit: str, values: Sequence[Any]) -> Row:
    vals = tuple(
        float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else v for v in values
    )
    return Row(quantity, si_unit, vals, _differs(vals))


#: The evaluation's own rows: (quantity, SI unit, attribute of the evaluation).
_EVALUATION_ROWS = (
    ("helical angle", "deg", "helical_angle_deg"),
    ("rotation frequency", "Hz", "frequency_hz"),
    ("torque margin", "N·m", "margin_Nm"),
    ("safety factor", "", "safety_factor"),
    ("rotating field at the centre", "T", "field_amplitude_T"),
    ("field limited by", "", "field_limited_by"),
    ("magnetic torque", "N·m", "magnetic_torque_Nm"),
    ("required torque", "N·m", "required_torque_Nm"),
    ("forward speed", "m/s", "speed_m_s"),
)
#: Frequencies from a bounded search: (quantity, attribute, its beyond-the-search flag).
_SEARCHED_ROWS = (
    ("step-out frequency", "step_out_frequency_hz", "step_out_beyond_search"),
    ("drive's maximum frequency", "max_frequency_hz", "max_frequency_beyond_search"),
)


def evaluation_rows(evaluations: Sequence[Any]) -> tuple[Row, ...]:
    """Margin, safety factor, field, torques, speed, step-out and every check, per design."""

    def value_of(e: Any, name: str) -> Any:
        value = getattr(e, name)
        return readable(value) if name == "field_limited_by" else value  # no internal labels

    rows = [
        _row(quantity, unit, [value_of(e, name) for e in evaluations])
        for quantity, unit, name in _EVALUATION_ROWS
    ] + [
        _row(quantity, "Hz", [_searched(getattr(e, hz), getattr(e, beyond)) for e in evaluations])
        for quantity, hz, beyond in _SEARCHED_ROWS
    ]
    for k, axis in enumerate("xyz"):
        rows.append(
            _row(f"current, {axis} pair", "A", [e.current_amplitudes_A[k] for e in evaluations])
        )
    for name in _check_names(evaluations):
        found = [next((c for c in e.checks if c.name == name), None) for e in evaluations]
        unit = next(c.unit for c in found if c is not None)
        label = (
            "self-locking: α + atan μ (must stay below 90°)"
            if name == "self_lock"
            else readable(name)
        )
        rows.append(_row(label, unit, [None if c is None else c.value for c in found]))
    rows.append(_row("feasible", "", [e.feasible for e in evaluations]))
    return tuple(rows)


def _check_names(evaluations: Sequence[Any]) -> list[str]:
    """The checks of any of the evaluations, in first-seen order, but the margin, the speed
    and the currents (rows of their own)."""
    names: list[str] = []
    for e in evaluations:
        for c in e.checks:
            own_row = c.name in ("margin", "speed") or c.name.startswith("current_")
            if c.name not in names and not own_row:
                names.append(c.name)
    return names


def objective_text(result: Any) -> str:
    """``copper power, minimised: 162.7 W``: what an optimum optimised, valued in its unit (the
    designs of one comparison may optimise different objectives, so this row is text)."""
    from spiralcap.presentation import objective_words
    from spiralcap.report.numbers import fmt

    what, unit, factor, sense = objective_words(result.objective)
    value = fmt(result.objective_value * factor)
    return f"{what}, {sense}: {value}{' ' + unit if unit else ''}"


def optimisation_rows(results: Sequence[Any]) -> tuple[Row, ...]:
    """Status, the objective (its value in its own unit), the chosen variables, margin,
    speed, copper and the binding limits of each optimum."""
    from spiralcap.presentation import binding

    return (
        _row("status", "", [r.status for r in results]),
        _row("objective", "", [objective_text(r) for r in results]),
        _row("helical angle", "deg", [r.helical_angle_deg for r in results]),
        _row("rotation frequency", "Hz", [r.frequency_hz for r in results]),
        _row("rotating field at the centre", "T", [r.field_amplitude_T for r in results]),
        _row("torque margin", "N·m", [r.margin_Nm for r in results]),
        _row("safety factor", "", [r.safety_factor for r in results]),
        _row("forward speed", "m/s", [r.speed_m_s for r in results]),
        _row(
            "step-out frequency",
            "Hz",
            [_searched(r.step_out_frequency_hz, False) for r in results],
        ),
        *[
            _row(f"current, {axis} pair", "A", [r.current_amplitudes_A[k] for r in results])
            for k, axis in enumerate("xyz")
        ],
        _row("copper mass", "kg", [r.evaluation.copper_mass_kg for r in results]),
        _row(
            "binding limits",
            "",
            [
                "; ".join(readable(b.name) for b in binding(r.binding_limits)) or "none"
                for r in results
            ],
        ),
    )


def changed_keys(designs: Sequence[Design]) -> tuple[KeyDifference, ...]:
    """Every key whose value is not the same in all designs (unset keys count as None)."""
    keys: list[str] = []
    for d in designs:
        for k in dict(d):
            if k not in keys:
                keys.append(k)
    out = []
    for k in keys:
        values = tuple(d.get(k) for d in designs)
        if any(v != values[0] for v in values[1:]):
            out.append(KeyDifference(k, values))
    return tuple(out)


def compare_designs(designs: Sequence[Design], labels: Sequence[str] | None = None) -> Comparison:
    """Evaluate and optimise each design and set them side by side.

    Parameters
    ----------
    designs : sequence of Design
        Two or more validated designs.
    labels : sequence of str, optional
        Column names (default: each design's source).

    Returns
    -------
    Comparison

    Raises
    ------
    spiralcap.core.errors.InputError
        A design is inconsistent (:func:`spiralcap.assemble.build_model`).
    """
    from optimize import evaluate, optimize_design, prepare
    from spiralcap.assemble import build_model
    from spiralcap.robust import optimization_model

    evaluations, results = [], []
    for d in designs:
        model = prepare(build_model(d))
        evaluations.append(evaluate(model))
        # optimised as `spiralcap optimize` does: over tissue scenarios for margin_p05 and
        # max_failure_probability
        results.append(optimize_design(optimization_model(d, model)))
    names = tuple(labels) if labels is not None else tuple(str(d.source) for d in designs)
    return Comparison(
        labels=names,
        sources=tuple(str(d.source) for d in designs),
        sha256=tuple(d.sha256() for d in designs),
        changed_keys=changed_keys(designs),
        evaluated=evaluation_rows(evaluations),
        optimised=optimisation_rows(results),
        evaluations=tuple(evaluations),
        optimizations=tuple(results),
    )


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def shown_value(value: Any, exact: bool = True) -> str:
    """A design value or a compared quantity as text: numbers exactly as given (4 significant
    figures when that is exact; always 4 with ``exact=False``), lists in brackets, booleans
    yes/no, unset or undefined as "–"."""
    from spiralcap.report.numbers import fmt

    if value is None:
        return "–"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(shown_value(v, exact) for v in value) + "]"
    if _is_number(value):
        if isinstance(value, float) and not math.isfinite(value):
            return fmt(value).replace("—", "–")
        short = fmt(value)
        if not exact:
            return short
        try:
            exact = float(short) == float(value)
        except ValueError:
            exact = False
        return short if exact else repr(value)
    return str(value)


def _typed(values: Sequence[Any]) -> dict[str, Any]:
    """One type per field: ``shown`` (text, always) and ``defined`` (whether each design has a
    value), plus ``values`` (numbers, when every design has a finite number), ``flags``
    (booleans, when all are booleans) or ``text`` (strings, when all are strings)."""
    out: dict[str, Any] = {
        "shown": [shown_value(v) for v in values],
        "defined": [v is not None and not (_is_number(v) and math.isnan(v)) for v in values],
    }
    if all(_is_number(v) for v in values):
        if all(math.isfinite(v) for v in values):
            out["values"] = [float(v) for v in values]
        elif any(math.isinf(v) for v in values) and not any(math.isnan(v) for v in values):
            out["values_unbounded"] = True
        else:
            out["values_undefined"] = True
    elif all(isinstance(v, bool) for v in values):
        out["flags"] = list(values)
    elif all(isinstance(v, str) for v in values):
        out["text"] = list(values)
    return out


def comparison_to_dict(c: Comparison) -> dict[str, Any]:
    """JSON-ready form: SI values with units in the row entries, one type per field.

    Each changed key and each row has ``shown`` (every value as text) and ``defined``; numbers
    are in ``values`` when every design has a finite one, booleans in ``flags``, strings in
    ``text`` (docs/json/compare.schema.json).
    """

    def rows(rs: Sequence[Row]) -> list[dict[str, Any]]:
        return [
            {
                "quantity": r.quantity,
                "unit": r.si_unit,
                "differs": r.differs,
                **_typed(r.values),
            }
            for r in rs
        ]

    return {
        "designs": [
            {"label": lab, "source": src, "sha256": sha}
            for lab, src, sha in zip(c.labels, c.sources, c.sha256, strict=True)
        ],
        "changed_keys": [
            {
                "key": k.key,
                "set": [v is not None for v in k.values],
                **{name: v for name, v in _typed(k.values).items() if name != "defined"},
            }
            for k in c.changed_keys
        ],
        "evaluate": rows(c.evaluated),
        "optimize": rows(c.optimised),
        "margin_Nm": {
            "evaluate": [e.margin_Nm for e in c.evaluations],
            "optimize": [r.margin_Nm for r in c.optimizations],
        },
    }
