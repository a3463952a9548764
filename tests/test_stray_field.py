"""Stray field, exposure crossings and the field grid over any box (issue 37).

The fade distances are checked with magpylib (an independent Biot-Savart code through
``spiralcap.export.to_magpylib``): just inside the distance the largest |B| over a turn reaches
0.5 mT, just outside it does not. The exposure crossings against a root of
``optimize.physics.exposure_level_T`` found here by bisection.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from spiralcap.cli import main


@pytest.fixture(scope="module")
def operating():
    from optimize import prepare
    from optimize.evaluate import operating_field_T
    from spiralcap.analysis.stray import stray_field
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    model = prepare(build_model(load_design()))
    field = float(operating_field_T(model, model.frequency_hz))
    return model, field, stray_field(model, field)


def _magpylib_peak_T(model, field_T, points_m) -> np.ndarray:
    """Largest |B| over a turn (720 phases) and every heading, magpylib's field per ampere."""
    from spiralcap.export import to_magpylib

    per_amp = np.stack(
        [to_magpylib(model, currents_A=np.eye(3)[k]).getB(points_m) for k in range(3)], axis=-1
    )  # (n, 3 comp, 3 pairs)
    t = np.linspace(0.0, 2.0 * np.pi, 720, endpoint=False)
    peak = np.zeros(len(points_m))
    for h in model.headings:
        amps, phases = model.coils.rotating_allocation(h, field_T)
        currents = amps * np.cos(t[:, None] + phases)  # (t, 3)
        b = np.einsum("nck,tk->ntc", per_amp, currents)
        peak = np.maximum(peak, np.linalg.norm(b, axis=-1).max(axis=1))
    return peak


def test_fade_distances_against_magpylib(operating) -> None:
    model, field, stray = operating
    for k, ax in enumerate("xyz"):
        d = stray.fade_distance_m[ax]
        assert 0.3 < d < stray.reach_m, f"{ax}: a finite fade distance beyond the coils ({d} m)"
        e = np.eye(3)[k]
        pts = np.array([s * r * e for s in (1.0, -1.0) for r in (d * 0.995, d * 1.005)])
        peak = _magpylib_peak_T(model, field, pts)
        inside = max(peak[0], peak[2])
        assert inside >= 0.5e-3, f"{ax}: 0.5 % inside the distance magpylib gives {inside} T"
        assert peak[1] < 0.5e-3 and peak[3] < 0.5e-3, (
            f"{ax}: 0.5 % beyond it magpylib gives {peak[1]}, {peak[3]} T < 0.5 mT (ICNIRP 2009)"
        )


def test_exposure_crossings_are_roots_of_the_icnirp_levels(operating) -> None:
    from optimize.physics import exposure_level_T
    from spiralcap.analysis.stray import exposure_crossing_hz

    _, field, stray = operating
    for kind in ("occupational", "public"):
        lo, hi = 1.0, 1e4  # the level falls with f: bisect level(f) = B0
        for _ in range(200):
            mid = math.sqrt(lo * hi)
            lo, hi = (mid, hi) if float(exposure_level_T(mid, kind)) >= field else (lo, mid)
        assert stray.exposure_crossing_hz[kind] == pytest.approx(lo, rel=1e-9), (
            f"{kind}: root of ICNIRP 2010's level = B0 by bisection, 1e-9"
        )
    assert exposure_crossing_hz(0.3, "occupational") == 0.0, "above 0.2 T: every frequency"
    assert exposure_crossing_hz(1e-4, "occupational") == math.inf, "below 1 mT: none"
    assert exposure_crossing_hz(2e-3, "occupational") == pytest.approx(12.5), "b / f branch"


def test_coils_reports_the_stray_field(capsys) -> None:
    assert main(["coils"]) == 0
    text = capsys.readouterr().out
    assert "falls below 0.5 mT (ICNIRP 2009, implanted devices) beyond x" in text
    assert "occupational above 4.34 Hz; public above 1.94 Hz" in text, "sqrt(a / B0) of each"


def test_field_grid_over_a_box_against_magpylib(tmp_path, capsys) -> None:
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design
    from spiralcap.export import to_magpylib

    path = tmp_path / "g.csv"
    argv = ["coils", "--field-grid", str(path), "--grid-box-mm", "-600,600,100,300,0,0"]
    assert main([*argv, "--grid-step-mm", "100"]) == 0
    capsys.readouterr()
    table = np.loadtxt(path, delimiter=",", skiprows=1)
    assert table.shape == (13 * 3, 12), "13 x 3 x 1 points, 100 mm apart, centred in the box"
    assert table[:, 0].min() == pytest.approx(-0.6) and table[:, 0].max() == pytest.approx(0.6)
    assert set(np.round(table[:, 1], 9)) == {0.1, 0.2, 0.3} and np.all(table[:, 2] == 0)
    model = build_model(load_design())
    pick = table[[0, 7, 20, 38]]
    for k in range(3):
        ref = to_magpylib(model, currents_A=np.eye(3)[k]).getB(pick[:, :3])
        np.testing.assert_allclose(
            pick[:, 3 + 3 * k : 6 + 3 * k],
            ref,
            rtol=1e-6,
            atol=1e-12,
            err_msg=f"pair {'xyz'[k]} per ampere vs magpylib, 1e-6",
        )
    assert main(["coils", "--field-grid", str(path), "--grid-box-mm", "1,0,0,0,0,0"]) == 2
    assert "X0 <= X1" in capsys.readouterr().err
