"""Notebook views of spiralcap's results: an HTML table and the main figure.

:mod:`optimize.views` holds the registry; :mod:`spiralcap.assemble` registers the views below
by import path (``NOTEBOOK_VIEWS``), so ``evaluate(model)``, ``optimize_design(model)``, the coil analysis
(:func:`spiralcap.analysis.coils.analyse_coils`) and the uncertainty study
(:func:`spiralcap.uncertainty.study`) show as a table in Jupyter and draw with ``.plot(ax=None)``
through :mod:`spiralcap.figures.api` (python-control's convention), returning its ``Plot``.
"""

from __future__ import annotations

import html
import math
from collections.abc import Sequence
from typing import Any


def _num(value: Any) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, float)):
        return "–" if not math.isfinite(value) else f"{value:.4g}"
    return str(value)


def table(
    title: str, rows: Sequence[Sequence[Any]], headers: Sequence[str] = ("quantity", "value")
) -> str:
    """An HTML table (every text escaped) with a caption."""
    head = "".join(f"<th>{html.escape(h)}</th>" for h in headers)
    body = "".join(
        "<tr>" + "".join(f"<td>{html.escape(_num(c))}</td>" for c in row) + "</tr>" for row in rows
    )
    return (
        f"<table><caption>{html.escape(title)}</caption><thead><tr>{head}</tr></thead>"
        f"<tbody>{body}</tbody></table>"
    )


def _checks_table(checks: Sequence[Any]) -> str:
    from spiralcap.presentation import readable

    def value(c: Any) -> Any:
        return NO_CONTACT if c.value != c.value else c.value  # NaN: the margin, no contact

    return table(
        "requirements and limits (SI)",
        [(readable(c.name), value(c), c.sense, c.allowed, c.unit, c.ok) for c in checks],
        ("check", "value", "", "allowed", "unit", "ok"),
    )


#: What the view shows for the margin where the spiral does not touch some wall.
NO_CONTACT = "none: no contact with the wall"
#: Grip words of the view (``Evaluation.grip``).
_GRIP = {
    "ok": "yes",
    "below minimum": "below requirements.min_wall_strain (the model extrapolates)",
    "none": "no: the spiral does not touch every wall",
}


def _evaluation_rows(ev: Any) -> list[tuple[str, Any]]:
    touches = getattr(ev, "grip", "ok") != "none"
    return [
        ("helical angle (°)", ev.helical_angle_deg),
        ("rotation frequency (Hz)", ev.frequency_hz),
        ("rotating field (mT)", ev.field_amplitude_T * 1e3),
        ("grip (wall strain)", _GRIP[getattr(ev, "grip", "ok")]),
        ("torque margin (mN·m)", ev.margin_Nm * 1e3 if touches else NO_CONTACT),
        ("safety factor", ev.safety_factor if touches else NO_CONTACT),
        ("forward speed (mm/s)", ev.speed_m_s * 1e3),
        ("step-out frequency (Hz)", ev.step_out_frequency_hz if touches else NO_CONTACT),
        ("copper (kg)", ev.copper_mass_kg),
        ("meets every requirement and limit", ev.feasible),
    ]


class _EvaluationView:
    def html(self, ev: Any) -> str:
        return table("spiralcap evaluation", _evaluation_rows(ev)) + _checks_table(ev.checks)

    def plot(self, ev: Any, ax: Any = None) -> Any:
        from spiralcap.figures.api import limit_utilisation

        return limit_utilisation(ev, ax=ax)


class _OptimizationView:
    def html(self, res: Any) -> str:
        from spiralcap.presentation import binding as on_bound
        from spiralcap.presentation import readable

        rows = [("status", res.status), ("objective", res.objective)]
        rows += [(k, v) for k, v in _evaluation_rows(res.evaluation) if k != rows[0][0]]
        binding = [
            (readable(b.name), b.value, b.allowed, b.unit) for b in on_bound(res.binding_limits)
        ]
        out = table("spiralcap optimum", rows)
        if binding:
            out += table("binding limits (SI)", binding, ("limit", "value", "allowed", "unit"))
        return out

    def plot(self, res: Any, ax: Any = None) -> Any:
        from spiralcap.figures.api import limit_utilisation

        return limit_utilisation(res.evaluation, ax=ax)


class _CoilAnalysisView:
    def html(self, analysis: Any) -> str:
        rows = [
            (
                t.axis,
                t.current_A,
                t.power_W,
                t.surface_temperature_C,
                t.hot_spot_temperature_C,
                limit.max_current_A,
                limit.max_current_limited_by,
            )
            for t, limit in zip(analysis.operating, analysis.axis_limits, strict=True)
        ]
        return table(
            f"spiralcap coil analysis at the operating field "
            f"{analysis.operating_field_T * 1e3:.4g} mT",
            rows,
            (
                "pair",
                "current (A)",
                "power (W)",
                "surface (°C)",
                "hot spot (°C)",
                "I max (A)",
                "by",
            ),
        )

    def plot(self, analysis: Any, ax: Any = None) -> Any:
        from spiralcap.figures.api import heating

        return heating(analysis, ax=ax)


class _UncertaintyStudyView:
    def html(self, st: Any) -> str:
        r = st.result
        rows: list[tuple[str, Any]] = [
            ("samples", r.samples),
            (
                "nominal margin (mN·m)",
                "none (no contact)"
                if r.nominal_margin_Nm != r.nominal_margin_Nm  # NaN: no contact, no margin
                else r.nominal_margin_Nm * 1e3,
            ),
            ("failure probability (step-out or lost grip)", r.failure_probability),
            ("step-out probability", r.stepout_probability),
            ("below-minimum-strain probability", r.below_min_strain.value),
        ]
        rows += [(f"margin {k} (mN·m)", v * 1e3) for k, v in r.margin_percentiles_Nm.items()]
        rows.append(("ran", f"{st.where}, {st.elapsed_s:.3g} s"))
        return table("spiralcap tissue-uncertainty study", rows)

    def plot(self, st: Any, ax: Any = None) -> Any:
        from spiralcap.figures.api import Plot, tissue_uncertainty

        if ax is None:
            return tissue_uncertainty(st.result)
        from spiralcap.figures.uncertainty import plot_margin_distribution

        return Plot(ax.figure, ax, plot_margin_distribution(ax, st.result))


EVALUATION = _EvaluationView()
OPTIMIZATION = _OptimizationView()
COIL_ANALYSIS = _CoilAnalysisView()
UNCERTAINTY_STUDY = _UncertaintyStudyView()
