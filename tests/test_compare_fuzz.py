"""``spiralcap compare`` over every kind of key a design file may hold (issue 22, issue 20 item 5):
exit 0, no traceback, and ``--json`` valid against docs/json/compare.schema.json with one type
per field -- an optional key set in one design only, strings and arrays, a ``[tissue.fit]``
covariance, a zero required torque, ``margin_p05`` designs that ``optimize`` accepts."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from _te_memo import solved_once  # noqa: F401 (the fixture: each model solved once)
from cli_outcome import ZERO_TORQUE, sound, weightless

jsonschema = pytest.importorskip("jsonschema")

SCHEMA = json.loads(
    (Path(__file__).resolve().parents[1] / "docs/json/compare.schema.json").read_text()
)
P05 = ["--set", "optimize.objective='margin_p05'", "--set", "optimize.scenarios=64"]
SCALE = ["--set", "tissue.uncertainty.scale_sigma_log=0.3"]
#: Set in every design (so no changed key): one IPOPT start per optimum instead of 4. These
#: tests are about compare's JSON and text, not the multi-start search; every case's comparison
#: is the 4-start one but for the designs' hashes (checked: numbers within 1e-5, the same rows,
#: statuses and lines), and a quarter of the solves.
ONE_START = ["--set", "optimize.starts=1"]


def _fitted(tmp_path: Path) -> str:
    """A base design layered with `fit -o`-style output: [tissue] values and [tissue.fit]."""
    cov = (np.eye(5) * 0.04).tolist()
    p = tmp_path / "fitted_layered.toml"
    p.write_text(
        "[limits]\npower_W = 2000.0\n[tissue]\nE1_kPa = 40.0\neta2_kPa_s = 70.0\n"
        f"[tissue.fit]\ncovariance_log = {cov}\n"
    )
    return str(p)


def _p05_file(tmp_path: Path) -> str:
    p = tmp_path / "p05.toml"
    p.write_text(
        "[optimize]\nobjective = 'margin_p05'\nscenarios = 64\n"
        "[tissue.uncertainty]\nscale_sigma_log = 0.3\n"
    )
    return str(p)


CASES: list = [
    ["--set", "2:limits.power_W=800"],
    ["--set", "2:tissue.E1_kPa=50"],  # optional key set in one design only
    ["--set", "1:tissue.E1_kPa=50", "--set", "2:tissue.eta1_kPa_s=900"],
    ["--set", "2:tissue.preset=zhou2013-sample3"],  # a string key
    ["--set", "2:tissue.worst_case_presets=[]"],  # an array key
    ["--set", "2:tissue.worst_case_presets=['zhou2013-sample3']"],
    ["--set", "2:workspace.headings=[[1,0,0],[0,1,0]]"],  # nested arrays
    ["--set", "2:requirements.min_spiral_turns=0"],  # the spiral-turns check gone
    ["--set", "1:requirements.min_spiral_turns=0"],
    ["--set", "2:limits.field_exposure='off'"],
    ["--set", "2:limits.current_A=0.01"],  # infeasible optimum
    ["--set", "2:capsule.spiral.helical_angle_deg=80"],  # self-locking
    ZERO_TORQUE,  # the spiral touches no wall in both (only the weight resists)
    [
        "--set",
        "2:requirements.axial_load_mN=0",
        "--set",
        "2:tissue.lumen_diameter_mm=30",
        "--set",
        "2:tissue.worst_case_presets=[]",
    ],  # touches no wall in one only
    ["--set", "2:report.title='A title'"],
    [
        "--set",
        "2:requirements.max_failure_probability=0.2",
        "--set",
        "2:optimize.scenarios=64",
        "--set",
        "2:tissue.uncertainty.scale_sigma_log=0.3",
    ],
    [*P05, *SCALE],  # margin_p05 in both
    [
        "--set",
        "2:optimize.objective='margin_p05'",
        "--set",
        "2:optimize.scenarios=64",
        "--set",
        "2:tissue.uncertainty.scale_sigma_log=0.3",
    ],
    ["--set", "2:optimize.objective='power'"],
    ["--set", "2:coils.x.wire_diameter_mm=0.05"],  # thermal runaway at the current limit
    ["--set", "2:operation.frequency_hz=0.5", "--set", "1:operation.frequency_hz=20"],
    ["--set", "2:tissue.uncertainty.E1_sigma_log=0.5"],
    ["--set", "1:limits.field_exposure='off'"],
    ["--set", "2:coils.y.turns=200", "--set", "2:coils.z.radius_m=0.25"],
    ["--set", "2:capsule.magnet.shape='ring'", "--set", "2:capsule.magnet.inner_diameter_mm=2"],
    ["--set", "2:optimize.free.coils.x.turns=[200, 600]"],
    ["--set", "2:operation.field_amplitude_mT=5"],
    ["--set", "2:tissue.uncertainty.covariance_from='nowhere.toml'"],  # not read by compare
    ["--set", "2:report.author='Ada'", "--set", "1:report.revision='B'"],
]


def _ids() -> list[str]:
    return [" ".join(getattr(c, "values", [c])[0])[:70] for c in CASES]


@pytest.mark.slow
@pytest.mark.usefixtures("solved_once")
@pytest.mark.parametrize("extra", CASES, ids=_ids())
def test_compare_json_is_schema_valid(extra):
    _check(["compare", "builtin", "builtin", *extra, *ONE_START])


@pytest.mark.slow
@pytest.mark.usefixtures("solved_once")
@pytest.mark.parametrize("which", ["fitted", "p05", "both"])
def test_compare_files_with_fit_and_margin_p05_tables(tmp_path, which):
    """`compare base.toml fitted_layered.toml` exits 0 (#20 item 5); a margin_p05 design that
    optimize accepts is compared, not refused for a missing [tissue.uncertainty]."""
    base = tmp_path / "base.toml"
    base.write_text("[limits]\npower_W = 2000.0\n")
    other = {"fitted": [_fitted(tmp_path)], "p05": [_p05_file(tmp_path)]}.get(
        which, [_fitted(tmp_path), _p05_file(tmp_path)]
    )
    doc = _check(["compare", str(base), *other, *ONE_START])
    keys = {k["key"] for k in doc["changed_keys"]}
    if which != "p05":
        assert "tissue.fit.covariance_log" in keys
    # the text form too (a covariance is a list of lists)
    _rc, out, _ = sound(["compare", str(base), *other, *ONE_START], allowed=(0,))
    assert "nan" not in out.lower().split() and "None" not in out
    if which != "p05":  # the 5x5 matrix shown by its shape and diagonal, not 25 numbers
        row = next(line for line in out.splitlines() if "tissue.fit.covariance_log" in line)
        assert "5×5, diagonal [" in row and len(row) < 140, row
        table = out.split("\n\n")[1]  # the changed-key table (the first line names the files)
        assert max(map(len, table.splitlines())) < 140, "no 25-number cell widens every line"


def _check(argv: list[str]) -> dict:
    """The JSON (against the schema, no null or non-finite number) and the text of one
    comparison, computed once: ``compare``'s own printers on the same Comparison."""
    import contextlib
    import io

    from cli_outcome import bad_numbers

    from spiralcap.commands._common import print_json
    from spiralcap.commands.compare import format_comparison
    from spiralcap.compare import comparison_to_dict

    c = _compared(tuple(argv))
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        print_json(comparison_to_dict(c))
    doc = json.loads(buf.getvalue())
    assert not bad_numbers(doc), bad_numbers(doc)
    errors = list(jsonschema.Draft202012Validator(SCHEMA).iter_errors(doc))
    assert not errors, f"{argv}: " + "; ".join(
        f"{'/'.join(map(str, e.path))}: {e.message[:150]}" for e in errors[:5]
    )
    for section in ("changed_keys", "evaluate", "optimize"):
        for row in doc[section]:
            assert None not in row.get("values", []) and None not in row["shown"]
            if "values" in row:
                assert all(isinstance(v, float) for v in row["values"]), row
    text = format_comparison(c)
    assert " nan" not in text.lower() and "None" not in text, text
    return doc


def _compared(argv: tuple[str, ...]):
    from spiralcap.cli import build_parser
    from spiralcap.commands.compare import load_designs
    from spiralcap.compare import compare_designs

    args = build_parser().parse_args(list(argv))
    return compare_designs(load_designs(args.designs, args.overrides))


def test_zero_torque_rows_are_typed():
    """A design whose spiral touches no wall has no margin and no safety factor (NaN, issue 36:
    no margin where the model has no physics): no number list mixes NaN with numbers, the row
    says which design has none, and "–" is shown for it."""
    from optimize import evaluate, prepare
    from spiralcap.assemble import build_model
    from spiralcap.compare import comparison_to_dict, evaluation_rows
    from spiralcap.design import load_design

    rows = evaluation_rows(
        [evaluate(prepare(build_model(load_design()))), evaluate(weightless(ZERO_TORQUE))]
    )
    sf = next(r for r in rows if r.quantity == "safety factor")
    from spiralcap.compare import _typed

    typed = _typed(sf.values)
    assert "values" not in typed and typed["values_undefined"] is True, typed
    assert typed["shown"][1] == "–" and typed["defined"] == [True, False], typed
    assert callable(comparison_to_dict)
