"""Build the report of a design: run the analyses, assemble the sections, render HTML and PDF."""

from __future__ import annotations

import contextlib
import datetime as _dt
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from spiralcap.design import Design
from spiralcap.report.document import FigureBlock, FrontMatter, Section
from spiralcap.report.sections import Context, build_sections

TITLE = "spiralcap engineering report"
#: Version of the embedded JSON's layout (``format`` entry).
DATA_FORMAT = "spiralcap-report/1"


@dataclass(frozen=True)
class Report:
    """A rendered report: the HTML text, the PDF bytes (if asked for) and what they hold."""

    html: str
    pdf: bytes | None
    page_count: int
    figure_count: int
    feasible: bool
    status_message: str
    payload: dict[str, Any]
    sections: tuple[Section, ...]


def report_payload(data: Any) -> dict[str, Any]:
    """The JSON embedded in the HTML: the CLI's dicts and the report's other numbers."""
    from spiralcap import __version__
    from spiralcap.presentation import jsonable as _jsonable
    from spiralcap.report.sections import uncertainty
    from spiralcap.report.sections.conclusion import conclusion_payload
    from spiralcap.report.sections.tissue import tissue_payload
    from spiralcap.report.sections.tradeoffs import power_sweep_payload

    design = data.design
    extra: dict[str, Any] = {}
    if data.uncertainty is not None:  # only with tissue uncertainty: the layout is unchanged
        extra["uncertainty"] = uncertainty.payload(data.uncertainty)
    from spiralcap.report.sections import calibration

    check = calibration.calibration_check(design, data.model)
    if check is not None:  # only with a [calibration] table
        extra["calibration"] = calibration.payload(check)
    return _jsonable(
        {
            "format": DATA_FORMAT,
            "spiralcap_version": __version__,
            "design": {"source": design.source, "sha256": design.sha256(), "values": dict(design)},
            "evaluate": data.evaluate_json,
            "optimize": data.optimize_json,
            "coils": data.coils_json,
            "coils_source": data.coils_note,
            "tissue": tissue_payload(data),
            "tradeoffs": {"power_sweep": power_sweep_payload(data)},
            **extra,
            "conclusion": conclusion_payload(
                data.evaluate_json, data.optimize_json, design, extra.get("uncertainty")
            ),
            "versions": data.versions,
        }
    )


def front_matter(design: Design, sha: str, date: str, version: str) -> FrontMatter:
    """The title page from the ``report.*`` keys (title defaults to :data:`TITLE`)."""
    return FrontMatter(
        title=design.get("report.title") or TITLE,
        project=design.get("report.project") or "",
        author=design.get("report.author") or "",
        revision=design.get("report.revision") or "",
        date=date,
        design_source=str(design.source),
        design_sha256=sha,
        version=version,
    )


def build_report(
    design: Design,
    *,
    pdf: bool = False,
    workers: int = 1,
    command: str = "spiralcap report",
    progress: Callable[[str], None] | None = None,
    compare: Design | None = None,
) -> Report:
    """Analyse ``design`` and render its report.

    Parameters
    ----------
    design : Design
        A validated design.
    pdf : bool
        Also render the PDF (Typst, from the same sections and figures).
    workers : int
        Processes to use: the analyses (:func:`spiralcap.report.data.collect`) and the figures
        (:func:`spiralcap.report.render.render_figures`) are shared out over them; 1 runs
        everything in this process. The report is the same either way.
    command : str
        The command line to print in the reproducibility section.
    progress : callable, optional
        Called with the name of each analysis stage.
    compare : Design, optional
        A second design to set beside this one (its evaluation and optimisation, the keys that
        differ) in a comparison section.

    Returns
    -------
    Report

    Raises
    ------
    spiralcap.core.errors.InputError
        The design is inconsistent (cross-key checks of :func:`spiralcap.assemble.build_model`).
    """
    say = progress or (lambda _stage: None)
    return _build(design, pdf, workers, command, say, progress, compare)


def _build(
    design: Design,
    pdf: bool,
    workers: int,
    command: str,
    say: Callable[[str], None],
    progress: Callable[[str], None] | None,
    compare: Design | None,
) -> Report:
    from spiralcap.report.data import CoilStage, collect
    from spiralcap.report.html import render_html
    from spiralcap.report.render import DrawnElsewhere, render_figures

    early: list[DrawnElsewhere] = []  # the coil figures, when the analyses run elsewhere
    with contextlib.ExitStack() as stack:  # the early drawing's process, stopped on leaving

        def draw_coil_figures(coils: CoilStage) -> None:
            # the analyses run in a forked process: load matplotlib here and draw the figures
            # that need only the coil analysis in another, so both cores stay busy whichever
            # finishes first (drawing them here would leave a core idle once the analyses end)
            from spiralcap.parallel import inherited, process_pool
            from spiralcap.report.render import draw_svgs, preload
            from spiralcap.report.sections.coils import coil_figures

            preload()
            figures = coil_figures(coils)
            job = stack.enter_context(inherited(lambda: draw_svgs(figures)))
            pool = stack.enter_context(process_pool(1))
            early.append(DrawnElsewhere(frozenset(figures), pool.submit(job)))

        data = collect(
            design,
            workers=workers,
            progress=progress,
            compare=compare,
            while_waiting=draw_coil_figures,
        )
        payload = report_payload(data)
        sections = build_sections(Context(data, payload), command)
        stamp = _dt.datetime.now(_dt.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
        sha = payload["design"]["sha256"]
        front = front_matter(design, sha, stamp, payload["spiralcap_version"])
        footer = f"{front.title} · {design.source} · SHA-256 {sha[:12]}…"
        say("figures")
        svgs = render_figures(sections, workers=workers, elsewhere=early[0] if early else None)
    say("HTML")
    html = render_html(front, sections, payload, footer, svgs)
    pdf_bytes, pages = None, 0
    if pdf:
        from spiralcap.report.pdf import render_pdf

        say("PDF")
        pdf_bytes, pages = render_pdf(front, sections, footer, svgs)
    figures = sum(isinstance(b, FigureBlock) for s in sections for b in s.blocks)
    res = data.optimization
    return Report(
        html=html,
        pdf=pdf_bytes,
        page_count=pages,
        figure_count=figures,
        feasible=res.status == "optimal",
        status_message=res.message,
        payload=payload,
        sections=tuple(sections),
    )
