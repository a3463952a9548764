"""Notebook-ready results: an HTML table in Jupyter and ``.plot(ax=None)`` through the figures
API, for evaluate, optimize_design, the coil analysis and the uncertainty study."""

from __future__ import annotations

import html.parser
from typing import Any

import pytest

from optimize import evaluate, optimize_design
from optimize.views import view_of
from spiralcap.analysis.coils import analyse_coils
from spiralcap.assemble import build_model
from spiralcap.design import load_design
from spiralcap.figures.api import Plot
from spiralcap.uncertainty import study


class _Cells(html.parser.HTMLParser):
    """The text of every table cell, and whether the tags balance."""

    def __init__(self) -> None:
        super().__init__()
        self.cells: list[str] = []
        self.open: list[str] = []
        self._in_cell = False

    def handle_starttag(self, tag: str, attrs: Any) -> None:
        self.open.append(tag)
        self._in_cell = tag in ("td", "th")
        if self._in_cell:
            self.cells.append("")

    def handle_endtag(self, tag: str) -> None:
        assert self.open and self.open.pop() == tag, f"unbalanced </{tag}>"
        self._in_cell = False

    def handle_data(self, data: str) -> None:
        if self._in_cell:
            self.cells[-1] += data


@pytest.fixture(scope="module")
def results() -> dict[str, Any]:
    design = load_design(None, ["tissue.uncertainty.scale_sigma_log=0.3"])
    model = build_model(design)
    return {
        "evaluation": evaluate(model),
        "optimization": optimize_design(build_model(load_design(None))),
        "coil analysis": analyse_coils(design, model),
        "uncertainty study": study(design, samples=256, sobol_base=0),
    }


@pytest.mark.parametrize(
    "which", ["evaluation", "optimization", "coil analysis", "uncertainty study"]
)
def test_result_shows_as_a_table_and_plots(results: dict[str, Any], which: str) -> None:
    from matplotlib.figure import Figure

    result = results[which]
    page = result._repr_html_()
    assert isinstance(page, str) and "<table" in page, f"{which}: an HTML table"
    parser = _Cells()
    parser.feed(page)
    assert not parser.open and len(parser.cells) >= 4, f"{which}: a well-formed table"
    drawn = result.plot()
    assert isinstance(drawn, Plot) and drawn.ax in drawn.figure.axes, f"{which}: a Plot"
    ax = Figure().subplots()
    onto = result.plot(ax=ax)
    assert isinstance(onto, Plot) and onto.ax is ax, f"{which}: drawn on the axes given"
    assert ax.has_data() or ax.patches or ax.lines, f"{which}: something drawn on it"


def test_the_tables_carry_the_results_numbers(results: dict[str, Any]) -> None:
    ev = results["evaluation"]
    parser = _Cells()
    parser.feed(ev._repr_html_())
    assert f"{ev.margin_Nm * 1e3:.4g}" in parser.cells, "the margin in mN·m, 4 figures"
    res = results["optimization"]
    parser = _Cells()
    parser.feed(res._repr_html_())
    assert res.status in parser.cells and f"{res.helical_angle_deg:.4g}" in parser.cells


def test_an_unregistered_kind_has_no_view() -> None:
    assert view_of("no such result") is None
