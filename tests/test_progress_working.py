"""Issue 20.8: progress on a terminal for an optimisation longer than a couple of seconds."""

from __future__ import annotations

import contextlib
import io
import time

from spiralcap.progress import working


def test_working_shows_elapsed_time_and_stage_after_its_delay() -> None:
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        with working("optimize", enabled=True, delay_s=0.05, tick_s=0.02) as say:
            assert say is not None
            say("continuous relaxation, outer iteration 1")
            time.sleep(0.3)
    text = err.getvalue()
    assert "optimize" in text and "elapsed" in text, text
    assert "continuous relaxation, outer iteration 1" in text, "the stage is shown"


def test_working_is_silent_for_a_short_job_and_off_a_terminal() -> None:
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        with working("optimize", enabled=True, delay_s=5.0, tick_s=0.01) as say:
            assert say is not None
            say("quick")
            time.sleep(0.05)
    assert err.getvalue() == "", "a job shorter than the delay prints nothing"
    with working("optimize", enabled=False) as say:
        assert say is None, "nothing drawn off a terminal"


def test_sizing_reports_its_stages() -> None:
    from optimize import optimize_design
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    design = load_design(
        None,
        [
            "optimize.free.coils.x.turns=[100, 800]",
            "optimize.free.coils.x.wire_diameter_mm=[0.8, 3.0]",
        ],
    )
    said: list[str] = []
    res = optimize_design(build_model(design), progress=said.append)
    assert res.status == "optimal"
    assert any(s.startswith("continuous relaxation") for s in said), said
    assert any("neighbour 1 of" in s for s in said), said
