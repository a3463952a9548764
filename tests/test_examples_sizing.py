"""The sizing examples run as a user would run them and print what they promise."""

import re
import runpy
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_least_power_example_prints_the_bill_of_materials(capsys):
    runpy.run_path(str(EXAMPLES / "size_coils_least_power.py"), run_name="__main__")
    out = capsys.readouterr().out
    sf = float(re.search(r"safety factor ([\d.]+)", out).group(1))
    power = float(re.search(r"([\d.]+) W\n", out).group(1))
    assert sf >= 2.0 - 1e-9, "the sized coils meet the asked safety factor of 2"
    from optimize import optimize_design
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    entered = optimize_design(
        build_model(
            load_design(None, ["optimize.objective=power", "requirements.min_safety_factor=2"])
        )
    ).objective_value
    assert power < entered, f"less copper power than the as-entered windings ({entered:.5g} W)"
    rows = [line.split() for line in out.splitlines() if line.strip()[:2] in ("x ", "y ", "z ")]
    assert [r[0] for r in rows] == ["x", "y", "z"] and all(len(r) == 13 for r in rows), (
        "the bill of materials table (spiralcap.analysis.bom.bom_table)"
    )
    assert all(float(r[1]) == int(r[1]) for r in rows), "whole turns"


def test_copper_tradeoff_example_plots(tmp_path, capsys):
    out = tmp_path / "cvs.png"
    ns = runpy.run_path(str(EXAMPLES / "size_copper_vs_safety.py"))
    ns["main"]([str(out), "--points", "2", "--pairs", "x"])
    text = capsys.readouterr().out
    masses = [float(m) for m in re.findall(r"copper\s+([\d.]+) kg", text)]
    assert len(masses) == 2 and masses[0] < masses[1], "more safety needs more copper"
    assert out.stat().st_size > 10_000
