"""The engineering report, read as a reader would: one report of the built-in design, shared.

Independent checks: the numbers shown equal the JSON the CLI prints (``spiralcap evaluate
--json``, ``optimize --json``, ``coils --json``); the HTML needs nothing from outside (no URL,
every image a data: URI holding a valid PNG); headless Chromium renders it to a non-blank page;
the PDF has several pages (poppler's pdfinfo, else the page objects counted).
"""

from __future__ import annotations

import base64
import contextlib
import html
import io
import json
import re
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path
from typing import Any

import pytest
from _td_cli import cli_json
from chromium import chromium, dump_dom

from spiralcap.cli import main
from spiralcap.report.numbers import fmt, lookup

MIN_FIGURES = 10
MIN_PDF_PAGES = 8
MAX_PDF_PAGES = 20  # 16 before the bill of materials, clearances (#18) and conclusion (#20)


def _cli_json(*argv: str) -> dict[str, Any]:
    """``spiralcap *argv --json`` (``_td_cli``: run once per process, shared with
    test_report_conclusion.py), without its version."""
    out = cli_json(*argv)
    assert out.pop("spiralcap_version"), "every --json output names the spiralcap version"
    return out


@pytest.fixture(scope="module")
def report(builtin_report: Any) -> dict[str, Any]:
    """The one report run of this module: the built-in design, HTML and PDF, in a folder the
    user made (conftest's ``builtin_report``: two processes, analyses and figures shared out;
    the serial run is compared below)."""
    html_path, pdf_path = builtin_report.html_path, builtin_report.pdf_path
    text = html_path.read_text(encoding="utf-8")
    match = re.search(
        r'<script type="application/json" id="spiralcap-data">\s*(.*?)\s*'
        r"</script>",
        text,
        re.S,
    )
    assert match, "the HTML embeds its numbers as JSON in <script id='spiralcap-data'>"
    return {
        "status": builtin_report.status,
        "stdout": builtin_report.stdout,
        "html_path": html_path,
        "pdf_path": pdf_path,
        "html": text,
        "data": json.loads(match.group(1).replace("<\\/", "</")),
    }


@pytest.fixture(scope="module")
def cli() -> dict[str, Any]:
    """What the CLI prints for the built-in design."""
    return {
        "evaluate": _cli_json("evaluate"),
        "optimize": _cli_json("optimize"),
        "coils": _cli_json("coils"),
    }


class _Collector(HTMLParser):
    """Every tag with its attributes, and the text of every element carrying data-key."""

    def __init__(self) -> None:
        super().__init__()
        self.tags: list[tuple[str, dict[str, str | None]]] = []
        self.numbers: list[dict[str, Any]] = []
        self._open: dict[str, Any] | None = None

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = dict(attrs)
        self.tags.append((tag, a))
        if "data-key" in a:
            self._open = {"key": a["data-key"], "scale": float(a["data-scale"] or 1), "text": ""}

    def handle_data(self, data: str) -> None:
        if self._open is not None:
            self._open["text"] += data

    def handle_endtag(self, tag: str) -> None:
        if self._open is not None and tag == "span":
            self.numbers.append(self._open)
            self._open = None


@pytest.fixture(scope="module")
def parsed(report: dict[str, Any]) -> _Collector:
    p = _Collector()
    p.feed(report["html"])
    return p


def test_report_command_succeeds_and_writes_both_files(report: dict[str, Any]) -> None:
    assert report["status"] == 0, "built-in design is feasible, so the report exits 0"
    assert report["html_path"].is_file() and report["pdf_path"].is_file(), (
        "-o and --pdf written, parent folders created"
    )
    assert "wrote" in report["stdout"]
    leftovers = [
        p.name
        for p in report["html_path"].parent.iterdir()
        if p.name not in ("report.html", "report.pdf")
    ]
    assert leftovers == [], "atomic writes leave no temporary files behind"


def _comparable(html: str, path: Path) -> str:
    """The HTML without what differs between two runs: the time stamp, the output path and
    the analysis times."""
    html = html.replace(str(path), "REPORT.html")
    html = re.sub(r"\d{4}-\d\d-\d\d \d\d:\d\d UTC", "DATE", html)
    html = re.sub(r'("[a-z_]*time_s": )[0-9.e+-]+', r"\1T", html)  # the solver's wall time
    return re.sub(r"Analysis times:[^<]*", "Analysis times: ...", html)


def test_report_in_one_process_is_the_report_on_two(report: dict[str, Any], tmp_path: Path) -> None:
    html_path = tmp_path / "serial.html"
    with contextlib.redirect_stdout(io.StringIO()):
        status = main(["report", "-o", str(html_path), "--workers", "1"])
    assert status == report["status"]
    one = _comparable(html_path.read_text(encoding="utf-8"), html_path)
    two = _comparable(
        report["html"].replace(f" --pdf {report['pdf_path']}", ""), report["html_path"]
    )
    assert one == two, (
        "--workers 1 (everything in this process) and --workers 2 (analyses and figures "
        "forked) write the same report, numbers and SVG figures byte for byte"
    )


def test_html_is_self_contained(report: dict[str, Any], parsed: _Collector) -> None:
    text = report["html"]
    assert not re.search(r"https?://", text, re.I), "no URL anywhere: nothing to fetch"
    assert "<style>" in text and not any(t == "link" for t, _ in parsed.tags), (
        "CSS inline, no <link> elements"
    )
    for tag, attrs in parsed.tags:
        if tag == "script":
            assert "src" not in attrs and attrs.get("type") == "application/json", (
                "the only script is the JSON data block; nothing executes or loads"
            )
        for name in ("src", "href"):
            value = attrs.get(name)
            if value is None:
                continue
            if name == "href":
                assert value.startswith("#"), f"links stay inside the document: {value}"
            else:
                assert value.startswith("data:image/svg+xml;base64,"), (
                    f"src must be an SVG data: URI: {value[:60]}"
                )
    images = [a["src"] for t, a in parsed.tags if t == "img"]
    assert len(images) >= MIN_FIGURES, f"at least {MIN_FIGURES} figures, found {len(images)}"
    ids = {a.get("id") for t, a in parsed.tags if t == "figure"}
    assert {"fig-geometry", "fig-margin-map"} <= ids, "the geometry view and the margin map"
    import xml.etree.ElementTree as ET

    for src in images:
        raw = base64.b64decode(src.split(",", 1)[1], validate=True)
        root = ET.fromstring(raw)
        assert root.tag.endswith("svg"), "every image decodes to an SVG document (vector)"
        assert b"<image" not in raw, "no bitmap inside the SVG figures"


def test_embedded_json_is_the_cli_json(report: dict[str, Any], cli: dict[str, Any]) -> None:
    data = report["data"]
    assert data["evaluate"] == cli["evaluate"], "report 'evaluate' == spiralcap evaluate --json"
    opt_report = {k: v for k, v in data["optimize"].items() if k != "solve_time_s"}
    opt_cli = {k: v for k, v in cli["optimize"].items() if k != "solve_time_s"}
    assert opt_report == opt_cli, "report 'optimize' == spiralcap optimize --json (bar timing)"
    assert data["coils"] == cli["coils"], "report 'coils' == spiralcap coils --json"


def test_every_shown_number_equals_the_cli_number(parsed: _Collector, cli: dict[str, Any]) -> None:
    """Each <span data-key> shows fmt(CLI value x scale), 4 significant figures."""
    keyed = [n for n in parsed.numbers if n["key"].split(".")[0] in cli]
    assert len(keyed) > 100, "the report ties its numbers to the CLI JSON"
    for n in keyed:
        value = lookup(cli, n["key"])
        if n["key"].endswith("solve_time_s"):
            continue
        shown = (
            value * n["scale"]
            if isinstance(value, (int, float)) and not isinstance(value, bool) and n["scale"] != 1.0
            else value
        )
        assert html.unescape(n["text"]) == fmt(shown), (
            f"{n['key']}: report shows {n['text']!r}, CLI gives {value!r} (x{n['scale']})"
        )


def test_all_keyed_numbers_resolve_in_embedded_json(
    report: dict[str, Any], parsed: _Collector
) -> None:
    for n in parsed.numbers:
        value = lookup(report["data"], n["key"])
        shown = (
            value * n["scale"]
            if isinstance(value, (int, float)) and not isinstance(value, bool) and n["scale"] != 1.0
            else value
        )
        assert html.unescape(n["text"]) == fmt(shown), n["key"]


def test_sections_and_summary(report: dict[str, Any]) -> None:
    text = report["html"]
    for title in (
        "Summary",
        "Design inputs",
        "Coil sizing",
        "Tissue resistive torque",
        "Torque margin and step-out",
        "Optimum and binding limits",
        "Trade-offs",
        "Assumptions and sources",
        "Reproducibility",
    ):
        assert title in text, f"section {title!r} present"
    summary = text[text.index('id="summary"') : text.index('id="inputs"')]
    for word in ("Margin", "Speed", "Binding limit"):
        assert re.search(f"<strong>{word}s?:</strong>", summary), f"summary line {word!r}"
    from spiralcap.schema import KEYS

    inputs = text[text.index('id="all-inputs"') :]
    missing = [k for k in KEYS if f"<td>{k}</td>" not in inputs]
    assert missing == [], "every design key is in the inputs table"
    for cite in (
        "Zhou",
        "ICNIRP",
        "Smythe",
        "Simpson",
        "Maxwell",
        "power screw",
        "calibration factor",
    ):
        assert cite.lower() in text.lower(), f"assumptions cite {cite}"
    data = report["data"]
    assert data["design"]["sha256"] in text, "the design hash is printed"
    assert "[limits]" in text and "power_W = " in text, "the design TOML is printed"
    for lib in ("numpy", "scipy", "casadi", "magpylib", "matplotlib", "python"):
        assert lib in data["versions"], f"version of {lib} recorded"


def _chromium() -> str | None:
    return chromium()


_MEASURE = """<script>
(function () {
  const width = document.documentElement.clientWidth;
  const out = [];
  for (const el of document.querySelectorAll("figure img, table, pre")) {
    const r = el.getBoundingClientRect();
    const id = (el.closest("figure, table") || el).id || el.tagName;
    out.push(id + " " + Math.round(r.left) + " " + Math.round(r.right) + " " + width);
  }
  const pre = document.createElement("pre");
  pre.id = "overflow-result";
  pre.textContent = out.join("\\n");
  document.body.appendChild(pre);
})();
</script>"""

#: The wide window: the screenshot's size, and the first width the figures are measured at.
WIDE = (1280, 2000)


def _measured_copy(report: dict[str, Any], folder: Path) -> Path:
    """The report with the measuring script (:data:`_MEASURE`) before ``</body>``: it appends
    its ``<pre id="overflow-result">`` after everything the report shows (the report itself has
    no script)."""
    page = folder / "measured.html"
    page.write_text(report["html"].replace("</body>", _MEASURE + "</body>"), encoding="utf-8")
    return page


def _screenshot_cmd(browser: str, profile: Path, shot: Path) -> list[str]:
    return [
        browser,
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        f"--user-data-dir={profile}",
        "--enable-logging=stderr",
        "--v=0",
        f"--screenshot={shot}",
        f"--window-size={WIDE[0]},{WIDE[1]}",
    ]


@pytest.fixture(scope="module")
def wide_view(
    report: dict[str, Any], tmp_path_factory: pytest.TempPathFactory
) -> tuple[Path, str, str]:
    """One headless Chromium run at :data:`WIDE` on the measured copy of the report (the two
    1280 px checks below; a Chromium start costs ~0.7 s of CPU): (the screenshot, the laid-out
    DOM on stdout, the log on stderr). A Chromium that does not take the screenshot and dump the
    DOM in one run (the old headless mode) is run twice."""
    browser = _chromium()
    if browser is None:
        pytest.skip(
            "no headless Chromium on PATH (Debian: apt-get install chromium); .ci/run installs it"
        )
    tmp = tmp_path_factory.mktemp("chromium")
    shot, page = tmp / "shot.png", _measured_copy(report, tmp)
    cmd = [*_screenshot_cmd(browser, tmp / "profile", shot), "--dump-dom", page.as_uri()]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=180, check=False)
    stdout, stderr = proc.stdout, proc.stderr
    if not shot.is_file() or "overflow-result" not in stdout:
        cmd = [*_screenshot_cmd(browser, tmp / "profile2", shot), page.as_uri()]
        shooting = subprocess.run(cmd, capture_output=True, text=True, timeout=180, check=False)
        stdout = dump_dom(browser, page, WIDE[0], tmp / "profile3").stdout
        stderr = shooting.stderr
    return shot, stdout, stderr


def test_chromium_renders_a_non_blank_page(wide_view: tuple[Path, str, str]) -> None:
    shot, _, stderr = wide_view
    assert shot.is_file(), f"Chromium wrote no screenshot: {stderr[-2000:]}"
    failed = [
        ln
        for ln in stderr.splitlines()
        if re.search(r"net::ERR_|Failed to load resource|Not allowed to load", ln)
    ]
    assert failed == [], f"a resource failed to load: {failed}"
    import numpy as np
    from PIL import Image

    with Image.open(shot) as im:
        pixels = np.asarray(im.convert("RGB"))
    assert pixels.shape[:2] == (WIDE[1], WIDE[0]), "the window size asked for"
    non_white = float(np.mean(np.any(pixels < 240, axis=2)))
    assert non_white > 0.05, f"page not blank: {non_white:.1%} non-white pixels"
    # distinct colours in bins of 16 levels per channel: each pixel's bin as one integer
    # r*256 + g*16 + b (0..4095), counted with bincount (np.unique(axis=0) on 2.6 M rows of
    # three: the same number, ~2.5 s of CPU)
    bins = (pixels // 16).astype(np.int32)
    codes = (bins[..., 0] * 256 + bins[..., 1] * 16 + bins[..., 2]).ravel()
    colours = int(np.count_nonzero(np.bincount(codes, minlength=4096)))
    assert colours >= 8, f"text, rules, callouts and figure colours: {colours} colour bins"


@pytest.mark.parametrize("window", [WIDE[0], 820])
def test_chromium_no_figure_overflows_the_page(
    report: dict[str, Any], tmp_path: Path, window: int, request: pytest.FixtureRequest
) -> None:
    """Lay the page out in Chromium and measure each figure's box against the page width (at
    the wide width, the DOM of the screenshot's run)."""
    if window == WIDE[0]:
        _, stdout, stderr = request.getfixturevalue("wide_view")
    else:
        browser = _chromium()
        if browser is None:
            pytest.skip("no headless Chromium on PATH (Debian: apt-get install chromium)")
        page = _measured_copy(report, tmp_path)  # a copy; the report has no script
        proc = dump_dom(browser, page, window, tmp_path / "profile")
        stdout, stderr = proc.stdout, proc.stderr
    m = re.search(r'<pre id="overflow-result">(.*?)</pre>', stdout, re.S)
    assert m, f"the measuring script ran: {stderr[-1000:]}"
    rows = [ln.split() for ln in html.unescape(m.group(1)).strip().splitlines()]
    figures = [r for r in rows if r[0].startswith("fig-")]
    assert len(figures) >= MIN_FIGURES, f"every figure measured: {len(figures)}"
    over = [r for r in rows if int(r[1]) < 0 or int(r[2]) > int(r[3])]
    assert over == [], f"boxes past the page width at {window} px (id left right width): {over}"


def _pdf_pages(path: Path) -> int:
    if shutil.which("pdfinfo"):
        out = subprocess.run(
            ["pdfinfo", str(path)], capture_output=True, text=True, check=True, timeout=60
        ).stdout
        return int(re.search(r"^Pages:\s+(\d+)", out, re.M).group(1))
    return len(re.findall(rb"/Type\s*/Page\b", path.read_bytes()))


def test_pdf_has_several_pages(report: dict[str, Any]) -> None:
    pdf = report["pdf_path"].read_bytes()
    assert pdf.startswith(b"%PDF-"), "a PDF file"
    pages = _pdf_pages(report["pdf_path"])
    assert MIN_PDF_PAGES <= pages <= MAX_PDF_PAGES, (
        f"a document of at most {MAX_PDF_PAGES} pages: {pages}"
    )
    assert f"({pages} pages)" in report["stdout"], "the command reports the page count"


def _poppler(tool: str) -> str:
    path = shutil.which(tool)
    if path is None:
        pytest.skip(f"poppler's {tool} not on PATH (Debian: apt-get install poppler-utils)")
    return path


def test_pdf_is_a_typeset_document(report: dict[str, Any]) -> None:
    """Proportional fonts, a contents list, the evaluated margin in the text, vector figures."""
    pdf = str(report["pdf_path"])
    fonts = subprocess.run(
        [_poppler("pdffonts"), pdf], capture_output=True, text=True, check=True
    ).stdout
    assert "Libertinus" in fonts, f"a proportional serif body font: {fonts}"
    text = subprocess.run(
        [_poppler("pdftotext"), "-layout", pdf, "-"], capture_output=True, text=True, check=True
    ).stdout
    assert "Contents" in text, "a contents list"
    margin = fmt(report["data"]["optimize"]["margin_Nm"] * 1e3)
    assert f"{margin} mN·m" in text, f"the optimum margin {margin} mN·m is in the text"
    assert re.search(r"Figure \d+", text) and "Table 1" in text, "numbered captions"
    images = subprocess.run(
        [_poppler("pdfimages"), "-list", pdf], capture_output=True, text=True, check=True
    ).stdout.splitlines()[2:]
    assert len(images) <= 2, f"figures are vector graphics (at most two bitmaps): {images}"


def test_pdf_pages_have_nothing_past_the_margins(report: dict[str, Any], tmp_path: Path) -> None:
    """Render every page; the outer 1 cm strip of each must be blank (nothing clipped)."""
    import numpy as np
    from PIL import Image

    subprocess.run(
        [_poppler("pdftoppm"), "-r", "30", "-gray", str(report["pdf_path"]), str(tmp_path / "p")],
        check=True,
        timeout=120,
    )
    pages = sorted(tmp_path.glob("p-*.pgm"))
    assert pages, "pages rendered"
    strip = round(30 / 2.54 * 0.8)  # 0.8 cm at 30 dpi
    for page in pages:
        with Image.open(page) as im:
            px = np.asarray(im)
        edges = [px[:, :strip], px[:, -strip:]]
        dark = max(float(np.mean(e < 200)) for e in edges)
        assert dark == 0.0, f"{page.name}: ink in the side margins ({dark:.2%} of the strip)"


def test_main_job_runs_without_the_cad_extra(builtin_report) -> None:
    """The README's main job (`spiralcap report`, conftest's ``builtin_report``) on an install
    without build123d: it ran with the CAD kernel unimportable (``sys.modules["build123d"] =
    None``, so any ``import build123d`` raises ImportError, in the forked workers too) and wrote
    the whole report."""
    assert builtin_report.status == 0, builtin_report.stdout[-2000:]
    assert builtin_report.html_path.stat().st_size > 100_000, "the report was written"
    assert builtin_report.pdf_path.stat().st_size > 100_000, "the PDF was written"
