"""Section 4: tissue resistive torque against frequency (Zhou 2013 model, calibrated sets)."""

from __future__ import annotations

from typing import Any

from spiralcap.core.constants import from_unit
from spiralcap.report.document import Cell, FigureBlock, Paragraph, Ref, Section, Table
from spiralcap.report.sections._util import Context

#: Tissue-set rows: (field of TissueParameters.as_design_table(), label, unit).
_SET_ROWS = (
    ("E1_kPa", "spring modulus E1", "kPa"),
    ("E2_kPa", "spring modulus E2", "kPa"),
    ("E3_kPa", "spring modulus E3", "kPa"),
    ("eta1_kPa_s", "dashpot viscosity η1", "kPa·s"),
    ("eta2_kPa_s", "dashpot viscosity η2", "kPa·s"),
    ("lumen_diameter_mm", "undeformed lumen D_before", "mm"),
    ("wall_thickness_mm", "wall thickness d", "mm"),
    ("friction_coefficient", "friction coefficient μ", "–"),
)


def tissue_payload(data: Any) -> dict[str, Any]:
    """The tissue numbers the report shows (embedded in the HTML's JSON).

    The sets are the design's (``TissueParameters.as_design_table``); the model torques at the
    paper's points come from :func:`torque_model.resistive_torque_Nm` with the paper's capsule
    geometry (``torque_model.PAPER_CAPSULE``) and the calibrated preset of that sample.
    """
    import torque_model as tm
    from torque_model.parameters.zhou2013 import CALIBRATION_FACTOR

    points = []
    for p in tm.PAPER_POINTS:
        tissue = tm.preset(f"zhou2013-sample{p.sample}")
        model = float(
            tm.resistive_torque_Nm(
                from_unit(p.helical_angle_deg, "deg"), p.frequency_hz, tissue, tm.PAPER_CAPSULE
            )
        )
        points.append(
            {
                "sample": p.sample,
                "capsule": p.capsule,
                "helical_angle_deg": p.helical_angle_deg,
                "frequency_hz": p.frequency_hz,
                "paper_torque_mNm": p.torque_mNm,
                "model_torque_mNm": model * 1e3,
                "role": p.role,
                "source": p.source,
            }
        )
    from torque_model.domain import validation_errors, validation_sigma_log

    errors = [v.relative_error for v in validation_errors()]
    design = data.design
    return {
        "calibration_factor": CALIBRATION_FACTOR,
        "sets": [{"name": t.name, **t.as_design_table()} for t in data.model.tissues],
        "paper_points": points,
        "validation": {
            "largest_error_percent": 100 * max(errors, key=abs),
            "sigma_log": validation_sigma_log(),
            "design_scale_sigma_log": float(
                design.get("tissue.uncertainty.scale_sigma_log", 0.0) or 0.0
            ),
        },
        "domain": {
            "entered": _domain_words(data.evaluation),
            "optimum": _domain_words(getattr(data.optimization, "evaluation", None)),
        },
        "min_wall_strain": float(data.model.requirements.min_wall_strain),
    }


def _domain_words(ev: Any) -> list[str]:
    """Each model input outside the paper's calibration at an evaluation, in words."""
    from spiralcap.presentation import extrapolation_words

    if ev is None:
        return []
    return [extrapolation_words(e) for e in ev.extrapolations]


def _dedupe_legend(ax: Any, **kwargs: Any) -> None:
    handles, labels = ax.get_legend_handles_labels()
    seen: dict[str, Any] = {}
    for h, lab in zip(handles, labels, strict=True):
        seen.setdefault(lab, h)
    ax.legend(list(seen.values()), list(seen), **kwargs)


def _draw(data: Any) -> Any:
    ev, res = data.evaluation, data.optimization

    def draw(fig: Any) -> None:
        import torque_model as tm
        from spiralcap.figures.api import tissue_torque
        from spiralcap.figures.torque import plot_torque_vs_frequency

        left, right = fig.subplots(1, 2)
        plot_torque_vs_frequency(left, tm.preset("zhou2013-sample2"))
        left.set_title("paper's capsules (11 × 26 mm), sample 2")
        _dedupe_legend(left, loc="upper left", fontsize=8, ncols=2)

        tissue_torque(data.model, ev, res, ax=right)

    return draw


#: The design's material keys: set, the first tissue set is no longer the calibrated preset.
_MATERIAL_KEYS = ("scale", "E1_kPa", "E2_kPa", "E3_kPa", "eta1_kPa_s", "eta2_kPa_s")


def provenance(design: Any) -> str:
    """Where the tissue constants come from, in words for a caption: "calibrated" only for the
    published sets (the paper's calibration, docs/torque-model.md), "fitted on a bench" with
    whether its data pinned them down (``tissue.fit.not_pinned_down`` from ``spiralcap fit
    -o``), "set in the design" for constants entered by hand. A fit that does not pin its
    constants down is never called calibrated (issue 36)."""
    given = [k for k in _MATERIAL_KEYS if k != "scale" and design.get(f"tissue.{k}") is not None]
    loose = design.get("tissue.fit.not_pinned_down")
    fitted = design.get("tissue.fit.fitted") or design.get("tissue.fit.bench_frequency_range_hz")
    if not given and not fitted:
        scaled = (design.get("tissue.scale") or 1.0) != 1.0
        return "the calibrated presets" + (" times tissue.scale" if scaled else "")
    if not fitted:
        return (
            "the first set's constants set in the design ("
            + ", ".join(f"tissue.{k}" for k in given)
            + "), not from the paper's calibration"
        )
    if loose:
        return (
            "the first set fitted on a bench whose data do NOT pin down "
            + ", ".join(loose)
            + " (those constants are not unique)"
        )
    if loose is None:
        return "the first set fitted on a bench (whether its data pin the constants down is not recorded)"
    return "the first set fitted on a bench, every fitted constant pinned down by its data"


def build(ctx: Context) -> Section:
    """The tissue-torque section."""
    t = "tissue"
    sets = ctx.value(f"{t}.sets")
    rows: list[list[Cell]] = []
    for field, label, unit in _SET_ROWS:
        rows.append([label, unit] + [ctx.num(f"{t}.sets.{i}.{field}") for i in range(len(sets))])
    set_table = Table(
        ["parameter", "unit", *[s["name"] for s in sets]],
        rows,
        caption=f"Tissue parameter sets used ({provenance(ctx.data.design)}; the margin must "
        "hold for every one)",
        wrap=0,
        id="tissue-table",
    )
    prow: list[list[Cell]] = []
    for i, p in enumerate(ctx.value(f"{t}.paper_points")):
        prow.append(
            [
                f"sample {p['sample']}, No. {p['capsule']}",
                ctx.num(f"{t}.paper_points.{i}.helical_angle_deg", unit="°"),
                ctx.num(f"{t}.paper_points.{i}.frequency_hz", unit="Hz"),
                ctx.num(f"{t}.paper_points.{i}.paper_torque_mNm", unit="mN·m"),
                ctx.num(f"{t}.paper_points.{i}.model_torque_mNm", unit="mN·m"),
                p["role"],
            ]
        )
    point_table = Table(
        ["capsule", "helical angle", "frequency", "paper (≈)", "model", "role"],
        prow,
        caption="The paper's stated torques and the model",
        id="paper-points",
    )
    intro = Paragraph(
        [
            "The intestine resists the capsule's rotation with a torque from its viscoelastic wall "
            "(Zhou et al. 2013, eqs. 2–8: strain of the wall stretched over the spiral, a "
            "five-element relaxation, thin-walled hoop pressure, Coulomb friction). The published "
            "moduli and viscosities, read in SI, give a torque far below the measured one; every "
            "modulus and viscosity is therefore multiplied by one calibration factor, ",
            ctx.num(f"{t}.calibration_factor"),
            ", fitted on sample 2 with capsule No. 2 only; "
            "the capsule No. 1 points are validation and never enter the fit "
            "(docs/torque-model.md). The factor leaves the shape against frequency as published; ",
            Ref("fig-tissue-torque"),
            " sets the model beside the paper's points and shows this design's capsule.",
        ]
    )
    fig = FigureBlock(
        "fig-tissue-torque",
        "Tissue resistive torque against rotation frequency. Left: the paper's capsules "
        "(helical angles 5–20°) in the calibrated sample-2 tissue, with the torques the paper "
        "states (markers only: filled circles calibration, open squares validation; the model is "
        "drawn as lines without markers). Right: this design's capsule "
        "geometry in each of its tissue sets, at the helical angle as entered and at the "
        f"{ctx.optimum}; vertical lines mark the two operating frequencies.",
        _draw(ctx.data),
        size_in=(9.0, 4.6),
    )
    return Section(
        "tissue",
        "Tissue resistive torque",
        [intro, _grip(ctx), fig, set_table, point_table, _validation(ctx), _domain(ctx)],
    )


def _grip(ctx: Context) -> Paragraph:
    """Engagement and the weight: what the paper's bench left out."""
    return Paragraph(
        [
            "The model resists only where the spiral stretches the wall, and a spiral that does "
            "not stretch it cannot grip it to screw the capsule forward: the design must stretch "
            "every tissue set's lumen by at least ",
            ctx.num("tissue.min_wall_strain", 100.0, "%"),
            " (requirements.min_wall_strain; the least the paper's capsules imposed). The "
            "paper's intestine stood vertical; in a patient the capsule lies on the wall, and the "
            "friction of its weight (μ m g at the spiral's crest) is added to every set's "
            "resistive torque.",
        ]
    )


def _validation(ctx: Context) -> Paragraph:
    """The model's own validation error and the spread it implies for a robust design."""
    v = "tissue.validation"
    return Paragraph(
        [
            "Against the torques the paper states, the calibrated model is off by up to ",
            ctx.num(f"{v}.largest_error_percent", unit="%"),
            " (capsule No. 1, 5°, at 3 Hz, a point never fitted); the root-mean-square error of "
            "ln(torque) over the four points is ",
            ctx.num(f"{v}.sigma_log"),
            ". A robust design should allow at least that spread, "
            "tissue.uncertainty.scale_sigma_log ≥ ",
            ctx.num(f"{v}.sigma_log"),
            "; this design uses ",
            ctx.num(f"{v}.design_scale_sigma_log"),
            ".",
        ]
    )


def _domain(ctx: Context) -> Paragraph:
    """Where the model extrapolates, at the design as entered and at the optimum."""
    parts: list[Any] = [
        "The paper calibrated the model on 11 mm capsules with 1 mm single-start spirals at "
        "5–20°, 0.5–3 Hz, lumens of 10.9–11.1 mm and wall strains of 1.68–6.45 %. "
    ]
    for label, path in (
        ("As entered", "tissue.domain.entered"),
        (f"At the {ctx.optimum}", "tissue.domain.optimum"),
    ):
        words = ctx.value(path)
        if words:
            parts.append(f"{label} the model extrapolates: {'; '.join(words)}. ")
        else:
            parts.append(f"{label} every input lies inside that range. ")
    return Paragraph(parts)
