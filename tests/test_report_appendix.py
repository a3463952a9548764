"""The report's appendix of design inputs is readable: no word broken letter by letter.

Issue #20 item 7: in the HTML at 1280 px the "state" column was so narrow that "default" broke
into "de/fa/ult". The appendix section alone is rendered (the report's own CSS and Typst), laid
out in headless Chromium, and every word of every cell is measured: a word whose text range
has more than one line box is broken.
"""

from __future__ import annotations

import html
import re
import shutil
import subprocess
from pathlib import Path
from types import SimpleNamespace

import pytest
from chromium import chromium, dump_dom

from spiralcap.design import load_design
from spiralcap.report.document import FrontMatter
from spiralcap.report.sections import inputs
from spiralcap.report.sections._util import Context

FRONT = FrontMatter("appendix", "", "", "", "now", "built-in", "0" * 64, "0")

_MEASURE = r"""<script>
(function () {
  const out = [];
  const table = document.getElementById("inputs-table");
  const rows = table.querySelectorAll("tr");
  const widths = {};
  for (const tr of rows) {
    tr.querySelectorAll("th, td").forEach(function (cell, col) {
      const w = cell.getBoundingClientRect().width;
      widths[col] = Math.min(widths[col] === undefined ? 1e9 : widths[col], w);
      const walker = document.createTreeWalker(cell, NodeFilter.SHOW_TEXT);
      let node;
      while ((node = walker.nextNode())) {
        const re = /[^\s\-\/]+/g;
        let m;
        while ((m = re.exec(node.data))) {
          const range = document.createRange();
          range.setStart(node, m.index);
          range.setEnd(node, m.index + m[0].length);
          const lines = new Set(Array.from(range.getClientRects()).map(r => Math.round(r.top)));
          if (lines.size > 1) out.push("BROKEN " + col + " " + m[0]);
        }
      }
    });
  }
  for (const col in widths) out.push("WIDTH " + col + " " + Math.round(widths[col]));
  out.push("PAGE " + document.documentElement.clientWidth);
  const pre = document.createElement("pre");
  pre.id = "measure-result";
  pre.textContent = out.join("\n");
  document.body.appendChild(pre);
})();
</script>"""


def _chromium() -> str | None:
    return chromium()


LONG_VALUES = [
    "report.title=" + " ".join(["a design review title of many words"] * 5),
    "tissue.fit.covariance_log="
    + str([[1.783788684361974e-05 * (1 + i + j) for j in range(5)] for i in range(5)]),
]
"""Values a design holds that are longer than any column should be wide: a long title, the
covariance `spiralcap fit -o` writes (a design layered with a fit's output holds one)."""


def _appendix(sets: tuple[str, ...] = ()):
    return inputs.build_appendix(Context(SimpleNamespace(design=load_design(None, list(sets))), {}))


@pytest.mark.parametrize("sets", [(), tuple(LONG_VALUES)], ids=["builtin", "long-values"])
@pytest.mark.parametrize("window", [1280, 820])
def test_appendix_words_whole_in_chromium(
    tmp_path: Path, window: int, sets: tuple[str, ...]
) -> None:
    browser = _chromium()
    if browser is None:
        pytest.skip("no headless Chromium on PATH (Debian: apt-get install chromium)")
    from spiralcap.report.html import render_html

    page = tmp_path / "appendix.html"
    text = render_html(FRONT, [_appendix(sets)], {}, "footer", {})
    page.write_text(text.replace("</body>", _MEASURE + "</body>"), encoding="utf-8")
    proc = dump_dom(browser, page, window, tmp_path / "profile")
    m = re.search(r'<pre id="measure-result">(.*?)</pre>', proc.stdout, re.S)
    assert m, f"the measuring script ran: {proc.stderr[-1000:]}"
    lines = html.unescape(m.group(1)).strip().splitlines()
    broken = [ln for ln in lines if ln.startswith("BROKEN") and not ln.startswith("BROKEN 0 ")]
    assert broken == [], (
        f"words broken inside value, unit, state or meaning cells at {window} px: {broken[:10]}"
    )
    widths = {int(c): int(w) for _, c, w in (ln.split() for ln in lines if ln.startswith("WIDTH"))}
    assert widths[3] >= 50, f"the state column holds 'default' and 'CHANGED': {widths}"
    if window >= 1280:
        assert widths[0] >= 200, f"the key column shows a key on one line at 1280 px: {widths}"
        keys_broken = [ln for ln in lines if ln.startswith("BROKEN 0 ")]
        short = [ln for ln in keys_broken if len(ln.split()[2]) <= 30]
        assert short == [], f"keys up to 30 characters stay whole at 1280 px: {short}"
    page_width = int(next(ln for ln in lines if ln.startswith("PAGE")).split()[1])
    assert sum(widths.values()) <= page_width, "the table fits the page"


@pytest.mark.parametrize("sets", [(), tuple(LONG_VALUES)], ids=["builtin", "long-values"])
def test_appendix_pdf_keeps_the_state_words_whole(tmp_path: Path, sets: tuple[str, ...]) -> None:
    pdftotext = shutil.which("pdftotext")
    if pdftotext is None:
        pytest.skip("no pdftotext (poppler-utils)")
    from spiralcap.report.pdf import render_pdf

    section = _appendix(sets)
    pdf, _ = render_pdf(FRONT, [section], "footer", {})
    path = tmp_path / "appendix.pdf"
    path.write_bytes(pdf)
    text = subprocess.run(
        [pdftotext, "-raw", str(path), "-"], capture_output=True, text=True, check=True
    ).stdout
    (table,) = section.blocks
    rows = table.pdf_rows if table.pdf_rows is not None else table.rows
    for state in ("default", "CHANGED"):
        expected = sum(r[3] == state for r in rows)
        found = len(re.findall(rf"(?<![\w-]){state}(?![\w-])", text))
        assert found >= expected, f"'{state}' whole in the PDF ({found} of {expected} rows)"
    assert not re.search(r"\bde\s*\n\s*fa", text), "no 'de/fa/ult' in the PDF"
    lines = [ln for ln in text.splitlines() if ln.strip()]
    single = [ln for ln in lines if len(ln.split()) == 1]
    assert len(single) < 0.25 * len(lines), (
        "no long value squeezes the meaning column to a word a line "
        f"({len(single)} of {len(lines)} lines hold one word)"
    )
