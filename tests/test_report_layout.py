"""The typeset PDF lays out clean: no two words printed over each other, on three reports.

The check reads each page's words and their boxes with poppler's ``pdftotext -bbox``
(:mod:`tests.pdf_layout`) and fails on any pair whose boxes share more than a third of the
smaller box: a squeezed table column (its header words over each other), a long design key
over its value, two figure labels over each other. Each report is built once per module: the
built-in design, a six-key least-power sizing (turns and wire of every pair freed; built once
per process in ``_treports_shared``, shared with test_words.py) and a robust
optimum of a design with fitted tissue parameters.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from _treports_shared import sizing_report
from pdf_layout import OVERLAP_SHARE, collisions, have_pdftotext, pages_words

from spiralcap.design import load_design
from spiralcap.report.builder import build_report

pytestmark = pytest.mark.skipif(not have_pdftotext(), reason="poppler's pdftotext not on PATH")

ROOT = Path(__file__).resolve().parents[1]
#: The built-in report with its appendix fits this many pages (16 before issues 36-37 added the
#: tolerance intervals and the stray field with its figure).
MAX_PAGES_BUILTIN = 17


def _report(tmp: Path, paths: list[Path] | None, overrides: list[str]) -> Path:
    # in this process: forking the analyses (--workers 2) costs ~0.7 s more CPU and writes the
    # same report (test_report.py::test_report_in_one_process_is_the_report_on_two)
    report = build_report(load_design(paths, overrides), pdf=True, workers=1)
    assert report.pdf is not None
    out = tmp / "report.pdf"
    out.write_bytes(report.pdf)
    return out


@pytest.fixture(scope="module")
def builtin(builtin_report: Any) -> Path:
    """The built-in report's PDF (conftest's ``builtin_report``, shared with test_report.py)."""
    return builtin_report.pdf_path


@pytest.fixture(scope="module")
def sizing(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The six-key least-power sizing report's PDF (``_treports_shared.sizing_report``, whose
    HTML test_words.py reads)."""
    out = tmp_path_factory.mktemp("sizing") / "report.pdf"
    out.write_bytes(sizing_report().pdf)
    return out


@pytest.fixture(scope="module")
def robust_fitted(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from spiralcap.cli import main

    tmp = tmp_path_factory.mktemp("robust")
    fitted = tmp / "fitted.toml"
    bench = ROOT / "examples" / "bench_synthetic_sample2.csv"
    assert main(["fit", str(bench), "-o", str(fitted)]) == 0
    robust = [
        "tissue.uncertainty.scale_sigma_log=0.3",
        "optimize.objective=margin_p05",
        "optimize.scenarios=256",
    ]
    return _report(tmp, [fitted], robust)


def _clean(pdf: Path) -> list[str]:
    return [str(c) for c in collisions(pages_words(pdf))]


@pytest.mark.parametrize("which", ["builtin", "sizing", "robust_fitted"])
def test_no_words_printed_over_each_other(which: str, request: pytest.FixtureRequest) -> None:
    pdf = request.getfixturevalue(which)
    found = _clean(pdf)
    assert not found, (
        f"{which}: words whose boxes share more than {OVERLAP_SHARE:.0%} of the smaller one "
        "(pdftotext -bbox): " + "; ".join(found)
    )


def test_builtin_report_fits_its_pages_and_leads_with_a_one_page_summary(builtin: Path) -> None:
    pages = pages_words(builtin)
    assert len(pages) <= MAX_PAGES_BUILTIN, f"{len(pages)} pages, at most {MAX_PAGES_BUILTIN}"
    first = " ".join(w.text for w in pages[0])
    second = " ".join(w.text for w in pages[1][:40])
    for words in ("Summary", "As entered.", "What to change first.", "Bill of materials"):
        assert words in first, f"{words!r} on the first page"
    assert "Contents" in second and "Contents" not in first, "the contents open page 2"


def test_the_checker_finds_words_printed_over_each_other(tmp_path: Path) -> None:
    """The check itself: a Typst page with two words set on the same spot, and one without."""
    import typst

    def page(body: str) -> list[str]:
        pdf = tmp_path / "t.pdf"
        pdf.write_bytes(typst.compile(body.encode(), format="pdf"))
        return _clean(pdf)

    assert page("#place(dx: 10pt)[quantity]#place(dx: 14pt)[unit]") != [], "overprint found"
    assert page("quantity unit optimum\n\nquantity unit") == [], "a clean line passes"
