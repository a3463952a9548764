"""Sweeps: the vectorised path equals point-by-point evaluation; CSV and errors."""

import csv

import numpy as np

from spiralcap.cli import main
from spiralcap.design import load_design
from spiralcap.sweep import parse_over, sweep


def test_vectorised_equals_point_by_point():
    design = load_design()
    axes = [
        parse_over("capsule.spiral.helical_angle_deg=5:20:4"),
        parse_over("limits.power_W=300:2000:3"),
    ]
    fast = sweep(design, axes)
    assert fast.mode.startswith("evaluate (vectorised")
    # force the slow path by adding a key that needs a rebuild, held at its default
    slow = sweep(design, [*axes, parse_over("coils.x.turns=400:400:1")])
    assert np.allclose(fast.outputs["margin_Nm"], slow.outputs["margin_Nm"], rtol=1e-12), (
        "vectorised sweep equals evaluate() point by point (1e-12 relative)"
    )
    assert (fast.outputs["feasible"] == slow.outputs["feasible"]).all()


def test_sweep_csv_and_json(tmp_path, capsys):
    out = tmp_path / "deep" / "grid.csv"
    assert main(["sweep", "--over", "operation.frequency_hz=0.5:3:6", "--csv", str(out)]) == 0
    with out.open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 6 and "margin_Nm" in rows[0], "one CSV row per grid point"
    capsys.readouterr()


def test_bad_over_exits_2(capsys):
    assert main(["sweep", "--over", "operation.frequency_hz=0.5:3"]) == 2
    assert "--over" in capsys.readouterr().err
    assert main(["sweep", "--over", "operation.frequency_hz=-1:3:4"]) == 2
    assert "operation.frequency_hz" in capsys.readouterr().err
