"""The collector pause of bounded jobs (spiralcap.runtime): resumed for library callers, left
paused only when the process ends after its one command."""

from __future__ import annotations

import gc

import pytest

from spiralcap import runtime


def test_pause_resumes_the_collector_for_library_callers() -> None:
    assert gc.isenabled()
    with runtime.cyclic_gc_paused():
        assert not gc.isenabled(), "paused inside the job"
    assert gc.isenabled(), "resumed after it: memory goes back to a long-running caller"


def test_pause_resumes_after_an_error() -> None:
    with pytest.raises(ValueError), runtime.cyclic_gc_paused():
        raise ValueError("inside")
    assert gc.isenabled()


def test_pause_nested_in_a_pause_leaves_it_paused() -> None:
    with runtime.cyclic_gc_paused():
        with runtime.cyclic_gc_paused():
            pass
        assert not gc.isenabled(), "the inner job does not resume what the outer paused"
    assert gc.isenabled()


def test_one_shot_process_is_left_paused(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(runtime, "ONE_SHOT", True)
    try:
        with runtime.cyclic_gc_paused():
            pass
        assert not gc.isenabled(), "the process ends next: collecting would only cost time"
    finally:
        gc.enable()
