"""Benchmark: the report of the built-in design against one ``spiralcap optimize``, end to end.

Run: python benchmarks/bench_report.py
Issue 12 targets: the HTML report costs at most 2x one ``spiralcap optimize`` call end to end
(fresh processes, imports included); the PDF adds at most 1 s. Also prints where the report's
time goes (analysis stages, drawing the figures, the HTML, typesetting the PDF), measured in
one process. Asserts nothing; timings are medians of a few runs on this machine.

The package's bytecode is compiled first (``compileall``), as ``pip install .`` does: both
commands are timed as an installed copy runs, not as the first import of a checkout with
``PYTHONDONTWRITEBYTECODE`` set (which recompiles every module in every process). The report
runs with its default ``--workers`` (the cores available, at most 4) and with ``--workers 1``.
"""

from __future__ import annotations

import os
import statistics
import tempfile
import time
from pathlib import Path

from _timing import median_time, run_cli

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    import compileall

    for pkg in ("spiralcap", "optimize", "coils", "capsule", "torque_model"):
        compileall.compile_dir(str(ROOT / pkg), quiet=1)
    with tempfile.TemporaryDirectory() as tmp:
        html, pdf = str(Path(tmp) / "r.html"), str(Path(tmp) / "r.pdf")
        runs = {
            "opt": lambda: run_cli("optimize"),
            "html": lambda: run_cli("report", "-o", html, "--quiet"),
            "one": lambda: run_cli("report", "-o", html, "--quiet", "--workers", "1"),
            "pdf": lambda: run_cli("report", "-o", html, "--pdf", pdf, "--quiet"),
        }
        times: dict[str, list[float]] = {k: [] for k in runs}
        for _ in range(5):  # interleaved, so a change of load on the machine hits all alike
            for k, fn in runs.items():
                times[k].append(median_time(fn, 1)[0])
        t_opt, t_html, t_one, t_pdf = (statistics.median(times[k]) for k in runs)
    print(f"spiralcap optimize (end to end)        : {t_opt:6.2f} s")
    print(
        f"spiralcap report -o r.html             : {t_html:6.2f} s  = {t_html / t_opt:4.2f} x "
        "optimize (target <= 2)"
    )
    print(
        f"  the same with --workers 1            : {t_one:6.2f} s  = {t_one / t_opt:4.2f} x optimize "
        f"({os.cpu_count()} cores here)"
    )
    print(
        f"spiralcap report -o r.html --pdf r.pdf : {t_pdf:6.2f} s  PDF adds {t_pdf - t_html:+.2f} s "
        "(target <= 1 s)"
    )

    from spiralcap.design import load_design
    from spiralcap.report.builder import report_payload
    from spiralcap.report.data import collect
    from spiralcap.report.html import render_html
    from spiralcap.report.pdf import render_pdf
    from spiralcap.report.render import render_figures
    from spiralcap.report.sections import Context, build_sections

    design = load_design()
    data = collect(design)  # warm: CasADi graphs built, caches filled
    t0 = time.perf_counter()
    data = collect(design)
    t_collect = time.perf_counter() - t0
    payload = report_payload(data)
    sections = build_sections(Context(data, payload), "bench")
    t_fig, svgs = median_time(lambda: render_figures(sections), 3)
    from spiralcap.report.builder import front_matter

    front = front_matter(design, "0" * 64, "today", "bench")
    t_html_r, _ = median_time(lambda: render_html(front, sections, payload, "", svgs), 3)
    t_pdf_r, (pdf_bytes, pages) = median_time(lambda: render_pdf(front, sections, "", svgs), 3)
    print("\nin one process (warm):")
    for stage, t in data.timings_s.items():
        print(f"  analysis: {stage:<14} {t:6.3f} s")
    print(f"  analysis total          {t_collect:6.3f} s")
    print(f"  {len(svgs)} figures drawn (SVG) {t_fig:6.3f} s")
    print(f"  HTML rendered           {t_html_r:6.3f} s")
    print(
        f"  PDF typeset (Typst)     {t_pdf_r:6.3f} s  ({pages} pages, {len(pdf_bytes) / 1e3:.0f} kB)"
    )


if __name__ == "__main__":
    main()
