"""Issue 22, "JSON and reproducibility": each command's --json output validates against its
schema in docs/json across the fuzz cases that used to drop required fields or print null, and
the text output prints no "nan"."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from cli_outcome import run

jsonschema = pytest.importorskip("jsonschema")

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs" / "json"
CSV = ROOT / "examples" / "bench_synthetic_sample2.csv"
RUNAWAY = [
    "--set",
    "coils.x.wire_diameter_mm=0.05",
    "--set",
    "limits.current_A=1000",
    "--set",
    "coils.winding_conductivity_W_mK=0.01",
]
SCALE = ["--set", "tissue.uncertainty.scale_sigma_log=0.3", "--set", "optimize.scenarios=64"]


def _five_rows(tmp: Path) -> str:
    rows = [ln for ln in CSV.read_text().splitlines() if ln and not ln.startswith("#")]
    p = tmp / "five.csv"
    p.write_text("\n".join(rows[:6]) + "\n")  # header + 5 rows: as many rows as parameters
    return str(p)


CASES = [
    ("coils", ["coils", *RUNAWAY]),
    ("coils", ["coils", "--set", "coils.x.wire_diameter_mm=0.05"]),
    ("coils", ["coils", "--set", "limits.current_A=1000"]),
    ("coils", ["coils", "--set", "limits.field_exposure='off'"]),
    ("fit", ["fit", "FIVE"]),
    (
        "uncertainty",
        [
            "uncertainty",
            "--samples",
            "256",
            "--sobol-samples",
            "64",
            "--set",
            "tissue.uncertainty.E1_sigma_log=0.3",
            "--set",
            "tissue.uncertainty.friction_sigma_log=0.2",
            "--set",
            "tissue.uncertainty.lumen_diameter_sigma_mm=0.5",
        ],
    ),
    ("optimize", ["optimize", "--set", "optimize.objective='margin_p05'", *SCALE]),
    ("optimize", ["optimize", "--set", "requirements.max_failure_probability=0.2", *SCALE]),
    ("evaluate", ["evaluate", *RUNAWAY]),
]


def _validate(name: str, doc: dict) -> list[str]:
    schema = json.loads((DOCS / f"{name}.schema.json").read_text())
    v = jsonschema.Draft202012Validator(schema)
    return [f"{'/'.join(map(str, e.path))}: {e.message[:160]}" for e in v.iter_errors(doc)]


def _nulls(value, path="$") -> list[str]:
    if value is None:
        return [path]
    if isinstance(value, dict):
        return [p for k, v in value.items() for p in _nulls(v, f"{path}.{k}")]
    if isinstance(value, list):
        return [p for i, v in enumerate(value) for p in _nulls(v, f"{path}[{i}]")]
    return []


@pytest.fixture
def each_solve_once(monkeypatch):
    """The ``--json`` run and the text run of one case solve the same design: the optimiser's
    entry points (``optimize.optimize_design``, ``spiralcap.robust.robust_optimum``,
    deterministic) are solved once per test, by their arguments' content (their pickle; the
    progress callback aside), so the text run prints the result the JSON run computed."""
    import pickle

    import optimize
    import spiralcap.robust as robust

    memo: dict[bytes, object] = {}

    def once(real):
        def solve(*args, **kw):
            key = pickle.dumps(
                (real.__name__, args, {k: v for k, v in kw.items() if k != "progress"})
            )
            if key not in memo:
                memo[key] = real(*args, **kw)
            return memo[key]

        return solve

    monkeypatch.setattr(optimize, "optimize_design", once(optimize.optimize_design))
    monkeypatch.setattr(robust, "robust_optimum", once(robust.robust_optimum))


@pytest.mark.slow
@pytest.mark.usefixtures("each_solve_once")
@pytest.mark.parametrize(("name", "argv"), CASES, ids=[" ".join(a)[:70] for _, a in CASES])
def test_json_matches_schema_and_text_has_no_nan(tmp_path, name, argv):
    argv = [_five_rows(tmp_path) if a == "FIVE" else a for a in argv]
    _, out, _ = _run([*argv, "--json"])
    doc = json.loads(out)
    assert not _nulls(doc), f"{argv}: null in {_nulls(doc)[:5]}"
    errors = _validate(name, doc)
    assert not errors, f"{argv}: " + "; ".join(errors[:5])
    _, text, _ = _run(argv)
    assert not re.search(r"\bnan\b", text, re.IGNORECASE), f"{argv}: 'nan' in the text output"
    if name == "fit":
        assert "residual_std" in doc and doc["residual_std"] >= 0
    if name == "optimize":
        constrained = "requirements.max_failure_probability=0.2" in argv
        assert ("max_failure_probability" in doc["robust"]) == constrained, doc["robust"]


def _run(argv: list[str]) -> tuple[int, str, str]:
    """Exit 0 or 3, no traceback and no warning (the JSON may hold _undefined flags where its
    schema allows them, so cli_outcome.sound's stricter number check is not used)."""
    rc, out, err = run(argv)
    assert rc in (0, 3), f"{argv}: exit {rc}; {err[-400:]}"
    assert "Traceback" not in err and "Warning" not in err, err
    return rc, out, err
