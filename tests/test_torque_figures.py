"""spiralcap.figures.torque: functions draw on a given Axes and return their artists."""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure

import torque_model as tm
from spiralcap.figures.torque import plot_fit, plot_torque_vs_frequency


def test_plot_torque_vs_frequency_returns_artists() -> None:
    ax = Figure().add_subplot()
    drawn = plot_torque_vs_frequency(ax, tm.preset("zhou2013-sample2"), (5.0, 10.0))
    assert len(drawn.curves) == 2, "one model curve per angle"
    assert len(drawn.points) == len(tm.PAPER_POINTS), "the paper's sample-2 points overlaid"
    assert "Hz" in ax.get_xlabel() and "mN" in ax.get_ylabel(), "units on the axes"
    x, y = drawn.curves[1].get_data()
    expected = (
        np.asarray(
            tm.resistive_torque_Nm(
                math.radians(10), x, tm.preset("zhou2013-sample2"), tm.PAPER_CAPSULE
            )
        )
        * 1e3
    )
    assert np.allclose(y, expected), "curve is the model in mN·m"


def test_plot_fit_returns_artists() -> None:
    base = tm.preset("zhou2013-sample2")
    f = np.linspace(0.5, 3, 8)
    fit = tm.identify(
        f,
        np.asarray(tm.resistive_torque_Nm(0.17, f, base, tm.PAPER_CAPSULE)),
        0.17,
        base,
        tm.PAPER_CAPSULE,
    )
    ax = Figure().add_subplot()
    drawn = plot_fit(ax, fit)
    assert len(drawn.curves) == 1 and len(drawn.points) == 1
    assert "Hz" in ax.get_xlabel() and "mN" in ax.get_ylabel()
