"""The engineering report: one self-contained HTML file (and optionally a PDF) per design.

>>> from spiralcap.design import load_design           # doctest: +SKIP
>>> from spiralcap.report import build_report          # doctest: +SKIP
>>> report = build_report(load_design(), pdf=True)     # doctest: +SKIP
>>> report.page_count                                   # doctest: +SKIP

Layout: :mod:`~spiralcap.report.data` runs the analyses, :mod:`~spiralcap.report.sections`
turns their JSON dicts into a renderer-neutral :mod:`~spiralcap.report.document`, and
:mod:`~spiralcap.report.html` / :mod:`~spiralcap.report.pdf` render it.
"""

from spiralcap.report.builder import DATA_FORMAT, Report, build_report

__all__ = ["DATA_FORMAT", "Report", "build_report"]
