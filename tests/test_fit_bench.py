"""Issue 36 item 6: ``fit`` describes the bench apart from the patient, and the report never
calls constants the bench data did not pin down calibrated.

Independent reference: with ``--only scale`` the torque is linear in the scale (every modulus
and viscosity times it; the bench is vertical, no weight term), so the fit's relative least
squares has the closed form s = sum(m/y) / sum((m/y)^2), m the model at scale 1 on the bench
tissue (lumen, wall, friction) and the paper's capsule, y the measured torque.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from cli_outcome import run

import torque_model as tm

DATA = Path(__file__).resolve().parents[1] / "examples" / "bench_synthetic_sample2.csv"
#: The issue's patient: a 9 mm capsule with a 2.25 mm wire in a 10.5 mm lumen.
PATIENT = [
    "capsule.diameter_mm=9",
    "capsule.spiral.wire_diameter_mm=2.25",
    "tissue.lumen_diameter_mm=10.5",
]


def _sets(values: list[str]) -> list[str]:
    return [a for v in values for a in ("--set", v)]


def _fit(*argv: str) -> dict:
    rc, out, err = run(["fit", *argv, "--only", "scale", "--json"])
    assert rc == 0, err
    return json.loads(out)


def closed_form_scale(lumen_mm: float, path: Path = DATA) -> float:
    """Relative least squares of a scale on the bench (sample 2's material, wall, friction; the
    paper's capsule), by hand."""
    lines = [ln for ln in path.read_text().splitlines() if ln.strip() and not ln.startswith("#")]
    rows = list(csv.DictReader(lines))
    tissue = replace(tm.preset("zhou2013-sample2"), lumen_diameter_m=lumen_mm * 1e-3)
    y = np.array([float(r["torque_mNm"]) * 1e-3 for r in rows])
    angle = np.array([float(r["helical_angle_deg"]) for r in rows])
    freq = np.array([float(r["frequency_hz"]) for r in rows])
    m = np.empty_like(y)
    for a in np.unique(angle):  # the frequencies of one angle in one array call
        at = angle == a
        m[at] = tm.resistive_torque_Nm(math.radians(a), freq[at], tissue, tm.PAPER_CAPSULE)
    q = m / y
    return float(q.sum() / (q * q).sum())


def test_same_bench_data_same_scale_with_or_without_a_patient():
    """The issue's case: 0.977 without --design, 2.69 with the patient's. Now the patient's
    capsule and lumen never enter: one scale, the preset's bench (10.9 mm) named."""
    alone = _fit(str(DATA))
    patient = _fit(str(DATA), *_sets(PATIENT))
    s = alone["parameters"]["scale"]["value"]
    assert patient["parameters"]["scale"]["value"] == pytest.approx(s, rel=1e-12)
    assert s == pytest.approx(closed_form_scale(10.9), rel=1e-6), "closed form, 1e-6"
    for doc in (alone, patient):
        assert doc["bench"]["lumen_diameter_mm"] == pytest.approx(10.9, rel=1e-12)
        assert doc["bench"]["capsule_diameter_mm"] == pytest.approx(11.0, rel=1e-12)
        assert doc["bench_sources"]["lumen_diameter_mm"] == "zhou2013-sample2's bench"
        assert doc["bench_sources"]["capsule_diameter_mm"] == "the paper's capsule"


def test_bench_from_header_or_option(tmp_path):
    """``# bench_lumen_diameter_mm = 11.1`` in the data file and ``--bench-lumen-mm 11.1`` give
    the closed-form scale at 11.1 mm; the text header names the lumen used and where from; the
    option wins over the header."""
    headed = tmp_path / "bench.csv"
    headed.write_text("# bench_lumen_diameter_mm = 11.1\n" + DATA.read_text())
    expected = closed_form_scale(11.1)
    by_header = _fit(str(headed), *_sets(PATIENT))
    by_option = _fit(str(DATA), "--bench-lumen-mm", "11.1")
    for doc in (by_header, by_option):
        assert doc["parameters"]["scale"]["value"] == pytest.approx(expected, rel=1e-6)
        assert doc["bench"]["lumen_diameter_mm"] == pytest.approx(11.1, rel=1e-12)
    assert by_header["bench_sources"]["lumen_diameter_mm"] == "the data file's header"
    assert by_option["bench_sources"]["lumen_diameter_mm"] == "--bench-lumen-mm"
    rc, text, _ = run(["fit", str(headed), "--only", "scale"])
    assert rc == 0 and "lumen 11.1 mm (the data file's header)" in text, text
    wins = _fit(str(headed), "--bench-lumen-mm", "10.9")
    assert wins["bench"]["lumen_diameter_mm"] == pytest.approx(10.9, rel=1e-12)


@pytest.mark.parametrize(
    ("line", "words"),
    [
        ("# bench_lumen_mm = 11", "bench_lumen_diameter_mm"),
        ("# bench_wall_thickness_mm = x", "not a number"),
    ],
)
def test_bad_bench_header_exits_2(tmp_path, line, words):
    bad = tmp_path / "bad.csv"
    bad.write_text(line + "\n" + DATA.read_text())
    rc, out, err = run(["fit", str(bad), "--only", "scale"])
    assert rc == 2 and out == "" and len(err.strip().splitlines()) == 1 and words in err, err


def test_bad_bench_option_exits_2():
    rc, out, err = run(["fit", str(DATA), "--bench-lumen-mm", "0.5"])
    assert rc == 2 and "--bench-lumen-mm" in err and "[1, 100]" in err and out == ""


def test_a_fit_not_pinned_down_is_never_called_calibrated(tmp_path):
    """-o records what the data did not pin down; the report's tissue caption then says so and
    never 'calibrated'; a pinned-down fit is captioned as fitted, the presets as calibrated."""
    from spiralcap.design import load_design
    from spiralcap.report.sections.tissue import provenance

    full = tmp_path / "full.toml"
    assert run(["fit", str(DATA), "-o", str(full)])[0] == 0
    design = load_design(full)
    loose = design["tissue.fit.not_pinned_down"]
    assert loose, "the five constants from 0.5-3 Hz: some are not pinned down"
    words = provenance(design)
    assert "calibrated" not in words and "NOT pin down" in words and loose[0] in words, words
    scale = tmp_path / "scale.toml"
    assert run(["fit", str(DATA), "--only", "scale", "-o", str(scale)])[0] == 0
    pinned = load_design(scale)
    assert pinned["tissue.fit.not_pinned_down"] == [] and pinned["tissue.fit.fitted"] == ["scale"]
    assert "calibrated" not in provenance(pinned) and "pinned down" in provenance(pinned)
    assert provenance(load_design()) == "the calibrated presets"
