"""Text in a report is data, never code (issue 22): titles, authors and file names of any content.

The PDF: every string reaches Typst through ``sys.inputs`` (a JSON array the template reads), so a
title holding ``TITLE``, ``#read(...)`` or quotes compiles, shows literally and reads no file.
The HTML: text is escaped for its context; the embedded JSON has ``<``, ``>`` and ``&`` as JSON
escapes, so a spec-conformant HTML parser (html5lib) hands back the same JSON.
Checked on small documents over arbitrary text (hypothesis), and through ``spiralcap report``
(in-process, ``spiralcap.cli.main``) on the issue's cases.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import unicodedata
from pathlib import Path
from typing import Any

import html5lib
import pytest
from cli_outcome import run
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from spiralcap.report.document import FrontMatter, Paragraph, Section
from spiralcap.report.html import render_html
from spiralcap.report.pdf import render_pdf, typst_source

MARKER = "MARKER-7f3a9c-the-content-of-a-local-file"

#: Pieces that broke out of the old spliced Typst / HTML (issue 22) or would in a naive escaper.
INJECTIONS = [
    "TITLE",
    "AUTHOR",
    "#TITLE",
    "HEADER_RIGHT",
    "FOOTER",
    '#read("marker.txt")',
    '")#read("marker.txt")#("',
    '" + read("marker.txt") + "',
    "#read(\\u{22}marker.txt\\u{22})",
    "<!--<script>",
    "</script>",
    "<![CDATA[",
    "&amp;",
    "\\",
    '"',
    "$x^2$",
    "#import",
    "] [",
    "*a* _b_",
    "// c",
    "@ref",
    "<lbl>",
    "#T.at(0)",
    "T.at(0)",
    '#let T = ("x",)',
    "\u2028",
    "é ß µ° ±",
]

# text pdftotext gives back as written: printable ASCII, Latin-1 letters, a few symbols
_ALPHABET = st.characters(
    codec="utf-8",
    categories=["L", "N", "P", "S", "Zs"],
    max_codepoint=0x24F,
)
_TEXT = st.lists(
    st.one_of(st.sampled_from(INJECTIONS), st.text(_ALPHABET, max_size=10)), min_size=1, max_size=8
).map("".join)


def _flat(text: str) -> str:
    """Whitespace collapsed, ligatures unfolded (pdftotext writes line breaks and may keep fi)."""
    return " ".join(unicodedata.normalize("NFKC", text).split())


def _pdf_text(pdf: bytes, where: Path) -> str:
    path = where / "t.pdf"
    path.write_bytes(pdf)
    return subprocess.run(
        ["pdftotext", "-enc", "UTF-8", str(path), "-"], capture_output=True, check=True
    ).stdout.decode("utf-8")


def _script_json(page: str) -> Any:
    """The embedded data as an HTML5 parser sees it (html5lib, the WHATWG algorithm)."""
    doc = html5lib.parse(page, treebuilder="etree", namespaceHTMLElements=False)
    scripts = [e for e in doc.iter("script") if e.get("id") == "spiralcap-data"]
    assert len(scripts) == 1, "one data block, closed where the renderer closed it"
    return json.loads(scripts[0].text or "")


def _html_text(page: str, tag: str) -> str:
    doc = html5lib.parse(page, treebuilder="etree", namespaceHTMLElements=False)
    el = next(doc.iter(tag))
    return "".join(el.itertext())


@pytest.fixture(scope="module")
def marker_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    d = tmp_path_factory.mktemp("marker")
    (d / "marker.txt").write_text(MARKER, encoding="utf-8")
    return d


needs_pdftotext = pytest.mark.skipif(
    shutil.which("pdftotext") is None, reason="poppler's pdftotext not on PATH"
)


@needs_pdftotext
@settings(
    max_examples=25,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(title=_TEXT.filter(lambda t: t.strip()), author=_TEXT, source=_TEXT)
def test_any_title_author_and_file_name_is_data(
    marker_dir: Path, title: str, author: str, source: str
) -> None:
    front = FrontMatter(title, "", author, "", "today", source, "0" * 64, "0")
    sections = [Section("one", title, [Paragraph([author, " / ", source])])]
    source_code, inputs = typst_source(front, sections, title, {})
    for piece in ("read", "marker", "<!--", "script", "TITLE #", "AUTHOR"):
        assert piece not in source_code, f"{piece!r} of a text reached the Typst source"
    assert {title, author or "spiralcap", source} <= set(json.loads(inputs["text"])), "as data"
    old = Path.cwd()
    os.chdir(marker_dir)  # a relative read("marker.txt") would find the file
    try:
        pdf, pages = render_pdf(front, sections, title, {})
    finally:
        os.chdir(old)
    assert pdf.startswith(b"%PDF-") and pages >= 1
    text = _pdf_text(pdf, marker_dir)
    assert MARKER not in text, "no file is read into the PDF"
    assert _flat(title) in _flat(text), f"the title shows literally: {title!r}"

    page = render_html(front, sections, {"title": title, "file": source}, title, {})
    assert _script_json(page) == {"title": title, "file": source}, "the JSON parses as written"
    assert _html_text(page, "h1") == title and _html_text(page, "title") == title


#: The issue's two cases (a Typst ``#read`` breaking out of a string, and an HTML comment opening
#: a script), in one title: one report run checks both.
ISSUE_TITLE = 'TITLE #read("/etc/hostname") ")#read("marker.txt")#(" <!--<script>'
#: The design's file name: the template's placeholder words, and a byte that is not UTF-8 (shown
#: as '?'), as Python hands such an argv byte to ``main`` (``os.fsdecode``, a surrogate escape).
#: One report run checks both.
DESIGN_NAME = os.fsdecode(b"TITLE AUTHOR n\xffm.toml")
SHOWN_NAME = "TITLE AUTHOR n?m.toml"


@pytest.fixture(scope="module")
def issue_report(tmp_path_factory: pytest.TempPathFactory) -> tuple[tuple[int, str, str], Path]:
    """``spiralcap report`` (in-process, ``spiralcap.cli.main``) run in a folder holding
    ``marker.txt`` on a design file named :data:`DESIGN_NAME` whose title is
    :data:`ISSUE_TITLE` (its author the same after ``AUTHOR``): (status, stdout, stderr), folder."""
    tmp = tmp_path_factory.mktemp("issue")
    (tmp / "marker.txt").write_text(MARKER, encoding="utf-8")
    (tmp / DESIGN_NAME).write_text(
        f"[report]\ntitle = {json.dumps(ISSUE_TITLE)}\n"
        f"author = {json.dumps('AUTHOR ' + ISSUE_TITLE)}\n",
        encoding="utf-8",
    )
    from spiralcap.curves import adaptive_power_sweep
    from spiralcap.report.data import collect

    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(tmp)  # a relative read("marker.txt") would find the file
        # the power trade-off at the design's budget only, unrefined (five refined budgets:
        # ~0.3 s more); the sweep still runs and is drawn, and its text is not under test
        mp.setitem(adaptive_power_sweep.__kwdefaults__, "refinements", 0)
        mp.setitem(collect.__kwdefaults__, "power_factors", (1.0,))
        outcome = run(["report", DESIGN_NAME, "-o", "r.html", "--pdf", "r.pdf", "--workers", "1"])
    return outcome, tmp


@needs_pdftotext
def test_report_command_takes_the_issue_cases_as_text(issue_report: tuple[Any, Path]) -> None:
    (rc, _, err), tmp = issue_report
    title = ISSUE_TITLE
    assert rc == 0, err[-2000:]
    assert "Traceback" not in err, err[-2000:]
    text = _pdf_text((tmp / "r.pdf").read_bytes(), tmp)
    assert MARKER not in text, "no local file's content in the PDF"
    flat = _flat(text)
    assert _flat(title) in flat and _flat(f"AUTHOR {title}") in flat, "typeset literally"
    assert SHOWN_NAME in text, "the file name shows as written (its non-UTF-8 byte as ?)"
    page = (tmp / "r.html").read_text(encoding="utf-8")
    data = _script_json(page)
    assert data["design"]["values"]["report.title"] == title
    assert _html_text(page, "h1") == title


def test_bytes_that_are_not_utf8_never_crash_the_report(
    issue_report: tuple[Any, Path], tmp_path: Path
) -> None:
    """A file name that is not UTF-8 is shown with '?' (the report run above, whose design file
    name holds the byte 0xff); a --set value that is not is refused."""
    (rc, _, err), tmp = issue_report
    assert rc == 0 and "Traceback" not in err, err[-2000:]
    page = (tmp / "r.html").read_text(encoding="utf-8")  # valid UTF-8
    assert _script_json(page)["design"]["source"] == SHOWN_NAME, "the byte shown as ?"
    rc, _, err = run(
        ["report", "--set", os.fsdecode(b"report.title='a\xffb'"), "-o", str(tmp_path / "s.html")]
    )
    _, *rest = err.strip().splitlines() or [""]
    assert rc == 2 and not rest and "--set" in err, err
    assert "UTF-8" in err and not (tmp_path / "s.html").exists()
