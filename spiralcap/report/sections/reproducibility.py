"""Section 9: how to reproduce the report -- versions, the design as TOML and its hash."""

from __future__ import annotations

from spiralcap.report.document import Code, Paragraph, Section, Table
from spiralcap.report.numbers import fmt
from spiralcap.report.sections._util import Context


def build(ctx: Context, command: str) -> Section:
    """The reproducibility section; ``command`` is the command line that made the report."""
    data = ctx.data
    versions = Table(
        ["software", "version"],
        [[k, v] for k, v in data.versions.items()],
        caption="Software versions",
        id="versions",
    )
    timing = ", ".join(f"{k} {fmt(v, 2)} s" for k, v in data.timings_s.items())
    return Section(
        "reproducibility",
        "Reproducibility",
        [
            Paragraph(
                [
                    f"Made by: {command}. Design source: {data.design.source}. "
                    "The design's SHA-256 (of its canonical JSON form; same hash, same design): "
                    f"{ctx.value('design.sha256')}."
                ]
            ),
            Paragraph(
                [
                    "The numbers of this report are embedded in it as JSON (the element "
                    "<script id=\"spiralcap-data\">): the 'evaluate' and 'optimize' entries are "
                    "exactly what `spiralcap evaluate --json` and `spiralcap optimize --json` "
                    "print for this design, 'coils' what `spiralcap coils --json` prints. "
                    f"Analysis times: {timing}."
                ]
            ),
            versions,
            Code(
                data.design.to_toml(),
                caption="The full design (every key, defaults included); "
                "save it as design.toml and run "
                "`spiralcap report design.toml -o report.html`.",
            ),
        ],
    )
