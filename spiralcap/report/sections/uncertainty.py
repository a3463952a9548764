"""Report section: the design under tissue uncertainty (only when the design declares one).

Self-contained, to be registered in three places (see :func:`collect`, :func:`payload`,
:func:`build`): the report's data collection runs the study, the embedded JSON carries it under
``"uncertainty"``, and :func:`build` returns the section (``None`` without uncertainty).
"""

from __future__ import annotations

from typing import Any

from spiralcap.report.document import FigureBlock, Paragraph, Section, Table
from spiralcap.report.sections._util import Context

#: Samples the report draws: 2^16 keeps the failure probability's 95 % interval within about
#: ±0.2 percentage points at 5 % and the study well under a second.
REPORT_SAMPLES = 1 << 16
REPORT_SOBOL_BASE = 1 << 11


def collect(design: Any, *, workers: int = 1, dask: str | None = None, model: Any = None) -> Any:
    """The uncertainty study of ``design`` (spiralcap.uncertainty.Study), or None without one."""
    from spiralcap.assemble.tissue import build_uncertainty
    from spiralcap.uncertainty import study

    if not build_uncertainty(design).active:
        return None
    return study(
        design,
        samples=REPORT_SAMPLES,
        sobol_base=REPORT_SOBOL_BASE,
        workers=workers,
        dask=dask,
        model=model,
    )


def payload(st: Any) -> dict[str, Any] | None:
    """The study as the embedded JSON's ``"uncertainty"`` entry (None without one)."""
    if st is None:
        return None
    from spiralcap.uncertainty import study_to_dict

    out = study_to_dict(st)
    out.pop("elapsed_s", None)  # the report's numbers must not change from run to run
    out.pop("ran_on", None)
    return out


def _draw(st: Any, with_sobol: bool) -> Any:
    def draw(fig: Any) -> None:
        from spiralcap.figures.uncertainty import plot_margin_distribution, plot_sobol

        if not with_sobol:
            plot_margin_distribution(fig.subplots(), st.result)
            return
        ax1, ax2 = fig.subplots(1, 2, width_ratios=[1.4, 1.0])
        plot_margin_distribution(ax1, st.result)
        plot_sobol(ax2, st.result)

    return draw


def build(ctx: Context, st: Any) -> Section | None:
    """The section, or None when the design has no ``[tissue.uncertainty]``."""
    if st is None:
        return None
    p = "uncertainty"
    inputs = ", ".join(dict.fromkeys(g for _, g in st.uncertainty.factors()))
    intro = Paragraph(
        [
            "The tissue torque is the least certain number in the chain. The design's "
            f"[tissue.uncertainty] table makes these inputs uncertain: {inputs}. ",
            ctx.num(f"{p}.samples"),
            " tissue samples (scrambled Sobol' points, seed ",
            ctx.num(f"{p}.seed"),
            ") perturb every tissue set alike; each sample's worst-case margin is computed by "
            "the same physics functions as the rest of this report, at the operating point. "
            "A sample fails where the capsule steps out of synchrony (negative margin) or its "
            "spiral stretches some wall by less than the minimum strain ",
            ctx.num(f"{p}.failure_probability.min_wall_strain", 100.0, "%"),
            " (no contact is the extreme case: no grip, no screw).",
        ]
    )
    f = f"{p}.failure_probability"
    lo, hi = ctx.value(f"{f}.ci95")
    parts = f"{f}.parts"
    risk = Paragraph(
        [
            "Failure probability ",
            ctx.num(f"{f}.value", 100.0, "%"),
            f" (95 % interval {100 * lo:.3g}-{100 * hi:.3g} %): step-out ",
            ctx.num(f"{parts}.stepout_probability.value", 100.0, "%"),
            ", below the minimum strain ",
            ctx.num(f"{parts}.below_min_strain_probability.value", 100.0, "%"),
            ", of which no contact ",
            ctx.num(f"{parts}.no_grip_probability.value", 100.0, "%"),
            ". 5th-percentile margin ",
            ctx.num(f"{p}.margin_percentiles_Nm.p05", 1e3, "mN·m"),
            " against a nominal ",
            ctx.num(f"{p}.nominal_margin_Nm", 1e3, "mN·m"),
            " (a failed sample counts with at most 0 mN·m: never as a good margin).",
        ],
        kind="alert" if ctx.value(f"{f}.value") > 0.05 else "note",
    )
    rows: list[list[Any]] = [
        [
            k,
            ctx.num(f"{p}.margin_percentiles_Nm.{k}", 1e3, "mN·m"),
            ctx.num(f"{p}.speed_percentiles_m_s.{k}", 1e3, "mm/s"),
        ]
        for k in ("p01", "p05", "p50", "p95")
    ]
    table = Table(
        ["percentile", "worst-case margin", "forward speed"],
        rows,
        id="uncertainty-percentiles",
        caption="Percentiles over the tissue samples. A sample below the minimum wall strain "
        "counts with min(margin, 0); the speed is 0 in every failed sample (step-out or lost "
        "grip).",
    )
    from spiralcap.figures.uncertainty import sobol_panel

    blocks: list[Any] = [intro, risk, table]
    with_sobol = sobol_panel(st.result)
    if st.result.sobol is not None and not with_sobol:
        blocks.append(
            Paragraph(
                f"One uncertain input ({inputs}): it explains all of the margin's variance, so "
                "no Sobol indices are shown."
            )
        )
    if with_sobol:
        names = st.result.sobol.inputs
        blocks.append(
            Table(
                ["uncertain input", "first-order index", "total index"],
                [
                    [
                        n.replace("_", " "),
                        ctx.num(f"{p}.sobol.indices.{n}.first_order"),
                        ctx.num(f"{p}.sobol.indices.{n}.total"),
                    ]
                    for n in names
                ],
                id="uncertainty-sobol",
                caption="Sobol indices of the counted margin (a sample below the minimum strain "
                "counts as min(margin, 0); SALib; Saltelli 2010, Jansen 1999): the "
                "share of the margin's variance each input explains alone (first order) and "
                "with its interactions (total). Correlated fit parameters form one group.",
            )
        )
    distribution = (
        "distribution of the worst-case margin over the tissue samples (histogram, and "
        "cumulative on the right axis); hatched, the failure region (step-out, or below the "
        "minimum strain, counted as min(margin, 0))"
    )
    blocks.append(
        FigureBlock(
            "fig-uncertainty",
            (
                f"Left: {distribution}. Right: which uncertain inputs drive the margin's "
                "spread (Sobol indices with 95 % intervals)."
            )
            if with_sobol
            else distribution[0].upper() + distribution[1:] + ".",
            _draw(st, with_sobol),
            size_in=(10.0, 4.8) if with_sobol else (6.6, 4.8),
        )
    )
    return Section("uncertainty", "Tissue uncertainty", blocks)
