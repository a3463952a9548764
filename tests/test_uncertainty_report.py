"""The report's uncertainty section builds from a study and draws its figure."""

from matplotlib.figure import Figure

from spiralcap.design import load_design
from spiralcap.report.document import FigureBlock, Table
from spiralcap.report.sections import uncertainty as sec
from spiralcap.report.sections._util import Context


def test_section_only_with_uncertainty(tmp_path):
    assert sec.collect(load_design()) is None
    assert sec.build(Context(None, {}), None) is None
    design = load_design(
        None,
        [
            "tissue.uncertainty.scale_sigma_log=0.3",
            "tissue.uncertainty.friction_sigma_log=0.2",
        ],
    )
    st = sec.collect(design)
    payload = {"uncertainty": sec.payload(st)}
    section = sec.build(Context(None, payload), st)
    assert section is not None and section.id == "uncertainty"
    tables = [b for b in section.blocks if isinstance(b, Table)]
    assert {t.id for t in tables} == {"uncertainty-percentiles", "uncertainty-sobol"}
    (fig_block,) = [b for b in section.blocks if isinstance(b, FigureBlock)]
    fig = Figure(figsize=fig_block.size_in)
    fig_block.draw(fig)
    fig.savefig(tmp_path / "u.png")
    assert len(fig.axes) == 3, "histogram, its CDF twin axis, Sobol bars"
