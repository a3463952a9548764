"""Every command's --json output against its schema in docs/json (JSON Schema 2020-12).

The schemas fix one type per field; the edge cases (no torque required, an infeasible design,
parameters the data do not bound) are the ones that used to print null or "inf".
"""

from __future__ import annotations

import functools
import json
from pathlib import Path

import pytest
from cli_outcome import ZERO_TORQUE, bad_numbers, sound

jsonschema = pytest.importorskip("jsonschema")

DOCS = Path(__file__).resolve().parents[1] / "docs" / "json"
CSV = str(Path(__file__).resolve().parents[1] / "examples" / "bench_synthetic_sample2.csv")

CASES = [
    ("evaluate", ["evaluate"]),
    ("evaluate", ["evaluate", *ZERO_TORQUE]),
    ("evaluate", ["evaluate", "--set", "limits.current_A=0.01"]),
    ("evaluate", ["evaluate", "--set", "capsule.spiral.helical_angle_deg=80"]),
    # no contact (issue 36): margin, safety factor and step-out absent with their flags
    (
        "evaluate",
        [
            "evaluate",
            "--set",
            "tissue.lumen_diameter_mm=11.3",
            "--set",
            "capsule.spiral.helical_angle_deg=25",
        ],
    ),
    (
        "sweep",
        [
            "sweep",
            "--over",
            "capsule.spiral.helical_angle_deg=15:25:3",
            "--set",
            "tissue.lumen_diameter_mm=11.3",
        ],
    ),
    ("optimize", ["optimize"]),
    ("optimize", ["optimize", "--set", "limits.current_A=0.01"]),
    # coils: validated in test_robustness.test_single_heading_coils_have_no_nan_or_inf (slow)
    ("capsule", ["capsule"]),
    ("torque", ["torque", "--frequency", "0.5", "2", "50"]),
    ("fit", ["fit", CSV]),
    ("calibrate", ["calibrate", str(Path(CSV).with_name("field_survey.csv"))]),
    ("fit", ["fit", CSV, "--only", "scale,E1"]),
    ("fit", ["fit", CSV, "--only", "scale"]),
    ("fit", ["fit", CSV.replace("bench_synthetic", "paper_points"), "--only", "scale"]),
    ("sweep", ["sweep", "--over", "operation.frequency_hz=0.5:3:3", *ZERO_TORQUE]),
    ("sweep", ["sweep", "--over", "coils.x.turns=300:400:2"]),
    ("sweep", ["sweep", "--optimize", "--over", "limits.current_A=0.01:15:2"]),
    ("waveforms", ["waveforms", "--heading", "1,0,0", "--heading", "0,1,0", "--dwell-s", "2"]),
    ("compare", ["compare", "builtin", "builtin", "--set", "2:limits.power_W=3000"]),
    (
        "uncertainty",
        [
            "uncertainty",
            "--samples",
            "256",
            "--sobol-samples",
            "64",
            "--set",
            "tissue.uncertainty.scale_sigma_log=0.3",
        ],
    ),
]


@functools.cache  # checked and built once per schema (stateless: iter_errors per document)
def validator(name: str):
    schema = json.loads((DOCS / f"{name}.schema.json").read_text())
    cls = jsonschema.validators.validator_for(schema)
    cls.check_schema(schema)
    return cls(schema)


@pytest.mark.parametrize("name, argv", CASES, ids=[" ".join(a)[:60] for _, a in CASES])
def test_output_matches_its_schema(name, argv):
    _, out, _ = sound([*argv, "--json"], allowed=(0, 3))
    doc = json.loads(out)
    errors = sorted(validator(name).iter_errors(doc), key=lambda e: list(e.path))
    assert not errors, f"{argv}: " + "; ".join(
        f"{'/'.join(map(str, e.path))}: {e.message}" for e in errors[:5]
    )
    assert not bad_numbers(doc)


def test_every_command_with_json_has_a_schema():
    from spiralcap.cli import COMMANDS, build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    with_json = {
        name for name, p in sub.choices.items() if any(o.dest == "json" for o in p._actions)
    }
    missing = {n for n in with_json if not (DOCS / f"{n}.schema.json").exists()}
    assert set(COMMANDS) >= with_json
    assert not missing, f"commands with --json but no schema in docs/json: {sorted(missing)}"
