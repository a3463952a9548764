"""Reports that several test modules read, built once per test process.

:func:`sizing_report` is the six-key least-power sizing report: the layout check
(``test_report_layout.py``) reads its PDF, the words check (``test_words.py``) its HTML. A
``functools.cache`` rather than a fixture: a session fixture imported into two modules is two
fixtures to pytest, and would be built twice.
"""

from __future__ import annotations

import functools
from typing import Any

import pytest

#: Turns and wire of every pair freed, least copper power at safety factor 2, and the grip held
#: low (``min_wall_strain`` 0.005) so that the spiral-turns requirement binds at one turn.
SIZING = (
    *(f"optimize.free.coils.{ax}.turns=[100, 800]" for ax in "xyz"),
    *(f"optimize.free.coils.{ax}.wire_diameter_mm=[0.8, 3.0]" for ax in "xyz"),
    "optimize.objective=power",
    "requirements.min_safety_factor=2",
    "requirements.min_wall_strain=0.005",
)


@functools.cache
def sizing_report() -> Any:
    """The :data:`SIZING` report (HTML and PDF, in this process: forking the analyses costs
    ~0.7 s more CPU and gives the same report, test_report.py) with its power sweep at one
    budget (the design's; half of it added a harder six-key sizing, ~2.5 s of CPU) and no
    adaptive refinement. Its own pages are the sizing tables; the full power table (five
    budgets) is laid out in the built-in and robust reports of
    ``test_report_layout.py``."""
    from spiralcap.curves import adaptive_power_sweep
    from spiralcap.design import load_design
    from spiralcap.report.builder import build_report
    from spiralcap.report.data import collect

    with pytest.MonkeyPatch.context() as mp:
        mp.setitem(adaptive_power_sweep.__kwdefaults__, "refinements", 0)
        mp.setitem(collect.__kwdefaults__, "power_factors", (1.0,))
        report = build_report(load_design(None, list(SIZING)), pdf=True, workers=1)
    assert report.pdf is not None, "the sizing report was asked for its PDF"
    return report
