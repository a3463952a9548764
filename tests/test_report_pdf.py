"""The Typst renderer on small documents: text is never read as markup; references resolve.

Checks run on the PDF's text (poppler's pdftotext) and Typst's own compile, no figures drawn.
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from spiralcap.report.document import (
    Equation,
    FrontMatter,
    Link,
    Paragraph,
    Ref,
    Section,
    Table,
)
from spiralcap.report.numbers import Num
from spiralcap.report.pdf import render_pdf, typst_source

NASTY = 'x #import "evil.typ": * $a^2$ \\ " ] [ <lbl> @ref *bold* _it_ // c'


def _front(title: str = "T") -> FrontMatter:
    return FrontMatter(title, NASTY, "A. Engineer", "B", "today", NASTY, "0" * 64, "0")


def test_text_with_markup_characters_is_typeset_literally(tmp_path: Path) -> None:
    sections = [
        Section(
            "one",
            NASTY,
            [
                Paragraph([NASTY, " ", Num(0.0026389, "k", 1e3, "mN·m")]),
                Paragraph([Link("back", "one"), " ", Ref("missing-anchor")], kind="alert"),
                Table(["a", "b (W)"], [[NASTY, Num(3.0, unit="W")]], caption=NASTY, id="t1"),
                Equation("m = B_r V / mu_0", "m = B_r·V/μ0", "moment"),
            ],
        )
    ]
    pdf, pages = render_pdf(_front(NASTY), sections, NASTY, {})
    assert pdf.startswith(b"%PDF-") and pages >= 1
    source, figures = typst_source(_front(), sections, "", {})
    assert set(figures) == {"text"} and "#import" not in source and "evil" not in source, (
        "every text reaches Typst as data (sys.inputs), none is spliced into the source"
    )
    if shutil.which("pdftotext") is None:
        pytest.skip("poppler's pdftotext not on PATH")
    path = tmp_path / "t.pdf"
    path.write_bytes(pdf)
    text = subprocess.run(
        ["pdftotext", str(path), "-"], capture_output=True, text=True, check=True
    ).stdout
    assert '#import "evil.typ"' in text, "the text shows as written, not imported"
    assert "2.639 mN·m" in text and "Table 1" in text
    assert "missing-anchor" in text, "a reference to a missing anchor is written as text"


def test_front_matter_keys_reach_the_title_page() -> None:
    from spiralcap.core.errors import InputError
    from spiralcap.design import load_design
    from spiralcap.report.builder import TITLE, front_matter

    d = load_design(None, ["report.author=A. Engineer", "report.revision='C'"])
    front = front_matter(d, "0" * 64, "today", "1")
    assert (front.title, front.author, front.revision, front.project) == (
        TITLE,
        "A. Engineer",
        "C",
        "",
    )
    with pytest.raises(InputError, match=r"report\.revision"):
        load_design(None, ["report.revision=3"])  # a number is not a line of text
