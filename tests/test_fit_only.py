"""``spiralcap fit --only``, positive intervals and the covariance written only for what is pinned.

Issue #20 item 3: identification that stays physical.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from cli_outcome import run, run_json

import torque_model as tm

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

SAMPLE2 = tm.preset("zhou2013-sample2")
EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
FIVE = ("E1_kPa", "E2_kPa", "E3_kPa", "eta1_kPa_s", "eta2_kPa_s")


def _run(_capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    return run(list(argv))


def _json(_capsys: pytest.CaptureFixture[str], *argv: str) -> dict:
    return run_json(list(argv))


def _scaled_sample2_csv(tmp_path: Path, k: float, noise: float) -> tuple[Path, np.ndarray]:
    """Torque of sample 2 with all five constants x k at 10 deg, 0.5-3 Hz, relative noise."""
    f = np.linspace(0.5, 3.0, 11)
    truth = SAMPLE2.replace(**{n: getattr(SAMPLE2, n) * k for n in tm.PARAMETER_NAMES})
    clean = np.asarray(tm.resistive_torque_Nm(math.radians(10), f, truth, tm.PAPER_CAPSULE))
    y = clean * 1e3 * (1 + noise * np.random.default_rng(20).standard_normal(f.size))
    path = tmp_path / "bench.csv"
    path.write_text(
        "frequency_hz,torque_mNm\n" + "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(f, y)),
        encoding="utf-8",
    )
    model = np.asarray(tm.resistive_torque_Nm(math.radians(10), f, SAMPLE2, tm.PAPER_CAPSULE))
    return path, y / (model * 1e3)


def test_only_scale_recovers_the_factor(tmp_path: Path, capsys) -> None:
    csv, ratio = _scaled_sample2_csv(tmp_path, 1.3, noise=0.02)
    out = _json(capsys, "fit", str(csv), "--only", "scale")
    scale = out["parameters"]["scale"]
    assert out["fitted"] == ["scale"] and list(out["parameters"]) == ["scale"]
    assert scale["value"] == pytest.approx(1.3, rel=0.03), (
        "data made from sample 2 x 1.3 (2 % noise): fit --only scale recovers 1.3 within 3 % "
        "(issue #20)"
    )
    # Independent: min sum (s m_i/y_i - 1)^2 has the closed form s = sum(1/r) / sum(1/r^2)
    # with r_i = y_i/m_i (docs/torque-model.md section 3, the calibration factor).
    closed = float(np.sum(1 / ratio) / np.sum(1 / ratio**2))
    assert scale["value"] == pytest.approx(closed, rel=1e-6), (
        "one-parameter relative least squares = its closed form (1e-6)"
    )
    lo, hi = scale["ci95"]
    assert 0 < lo < 1.3 < hi and scale["pinned_down"] and scale["identifiable"]
    for key in FIVE:
        preset = getattr(SAMPLE2, key.replace("_kPa_s", "_Pa_s").replace("_kPa", "_Pa")) * 1e-3
        assert out["tissue"][key] == pytest.approx(preset * scale["value"], rel=1e-12), (
            f"{key}: the preset times the fitted scale (the ratios held)"
        )


def test_only_a_subset_holds_the_rest(tmp_path: Path, capsys) -> None:
    csv, _ = _scaled_sample2_csv(tmp_path, 1.3, noise=0.01)
    out = _json(capsys, "fit", str(csv), "--only", "scale,E1")
    assert out["fitted"] == ["scale", "E1_kPa"]
    s = out["parameters"]["scale"]["value"]
    for key in ("E2_kPa", "E3_kPa", "eta1_kPa_s", "eta2_kPa_s"):
        preset = getattr(SAMPLE2, key.replace("_kPa_s", "_Pa_s").replace("_kPa", "_Pa")) * 1e-3
        assert out["tissue"][key] == pytest.approx(preset * s, rel=1e-12), f"{key} held x scale"
    assert out["tissue"]["E1_kPa"] == out["parameters"]["E1_kPa"]["value"]
    out = _json(capsys, "fit", str(csv), "--only", "eta2_kPa_s")
    assert list(out["parameters"]) == ["eta2_kPa_s"], "design-key names accepted too"
    for key in ("E1_kPa", "E2_kPa", "E3_kPa", "eta1_kPa_s"):
        preset = getattr(SAMPLE2, key.replace("_kPa_s", "_Pa_s").replace("_kPa", "_Pa")) * 1e-3
        assert out["tissue"][key] == pytest.approx(preset, rel=1e-12), f"{key} held at preset"


@pytest.fixture(scope="module")
def full_fit() -> tuple[dict, int, str]:
    """``fit`` of the example bench file with every constant free, run once for this module:
    its ``--json`` document and its text run (exit status, stdout), which several tests read."""
    csv = str(EXAMPLES / "bench_synthetic_sample2.csv")
    code, text, _ = run(["fit", csv])
    return run_json(["fit", csv]), code, text


def test_full_fit_intervals_are_positive(full_fit) -> None:
    out, code, text = full_fit
    for key, p in out["parameters"].items():
        if p["identifiable"]:
            assert p["ci95"][0] > 0 and p["ci95"][1] > p["ci95"][0], (
                f"{key}: a positive parameter's interval has a positive lower end (log-space)"
            )
            assert p["ci95"][0] <= p["value"] <= p["ci95"][1]
        else:
            assert "ci95" not in p, f"{key}: 'not identifiable' instead of an interval"
    assert any(not p["identifiable"] for p in out["parameters"].values()), (
        "a 0.5-3 Hz curve leaves some constant unidentifiable (docs/torque-model.md section 5)"
    )
    assert code == 0 and "not identifiable" in text
    assert not re.search(r"\[-", text), "no negative interval end in the table"


def test_rich_fit_intervals_cover_truth_and_stay_positive() -> None:
    truth = SAMPLE2.replace(E1_Pa=2e4, E2_Pa=5e4, E3_Pa=1e4, eta1_Pa_s=1e4, eta2_Pa_s=2.5e3)
    f = np.geomspace(0.05, 20.0, 30)
    clean = np.asarray(tm.resistive_torque_Nm(0.17, f, truth, tm.PAPER_CAPSULE))
    y = clean * (1 + 0.002 * np.random.default_rng(11).normal(size=f.size))
    fit = tm.identify(f, y, 0.17, SAMPLE2, tm.PAPER_CAPSULE)
    for name in tm.PARAMETER_NAMES:
        lo, hi = fit.ci95[name]
        assert 0 < lo < fit.values[name] < hi < math.inf
        ratio = lo * hi / fit.values[name] ** 2
        assert ratio == pytest.approx(1.0, rel=1e-9), f"{name}: interval symmetric in the log"


def test_covariance_only_for_what_is_pinned(tmp_path: Path, capsys) -> None:
    csv, _ = _scaled_sample2_csv(tmp_path, 1.3, noise=0.02)
    toml = tmp_path / "fit.toml"
    code, _, err = _run(capsys, "fit", str(csv), "--only", "scale", "-o", str(toml))
    assert code == 0, err
    out = _json(capsys, "fit", str(csv), "--only", "scale")
    cov = np.asarray(tomllib.loads(toml.read_text())["tissue"]["fit"]["covariance_log"])
    var = out["parameters"]["scale"]["standard_error_log"] ** 2
    assert np.allclose(cov, var * np.ones((5, 5)), rtol=1e-9), (
        "a fitted scale moves all five constants together: Var(ln s) 1 1^T"
    )
    # The full fit of a 0.5-3 Hz curve pins nothing down: no covariance at all.
    full = tmp_path / "full.toml"
    code, _, err = _run(
        capsys, "fit", str(EXAMPLES / "bench_synthetic_sample2.csv"), "-o", str(full)
    )
    assert code == 0, err
    table = tomllib.loads(full.read_text())
    assert "covariance_log" not in table["tissue"]["fit"], "nothing pinned down: no covariance"
    # The scale covariance feeds tissue.uncertainty.covariance_from (finite margins).
    code, text, err = _run(
        capsys,
        "uncertainty",
        str(toml),
        "--set",
        f"tissue.uncertainty.covariance_from='{toml}'",
        "--samples",
        "512",
        "--sobol-samples",
        "0",
        "--json",
    )
    assert code == 0, err
    res = json.loads(text)
    assert res["uncertain_inputs"] == ["fit covariance"]
    p = res["margin_percentiles_Nm"]
    assert all(math.isfinite(v) for v in p.values()) and p["p05"] < p["p50"] < p["p95"], (
        "finite margins spread by the fitted scale's variance (the NaN margins of issue #20 gone)"
    )


def test_notes_name_parameters_as_the_table(full_fit) -> None:
    out, code, text = full_fit
    assert code == 0
    notes = text + json.dumps([p["flags"] for p in out["parameters"].values()])
    assert not re.search(r"\b(E[123]|eta[12])_Pa", notes), (
        "notes name parameters by their design keys (kPa), as the table does"
    )


def test_paper_points_fit_the_scale(capsys) -> None:
    out = _json(capsys, "fit", str(EXAMPLES / "paper_points_sample2.csv"), "--only", "scale")
    assert out["parameters"]["scale"]["value"] == pytest.approx(1.0, abs=0.15), (
        "the presets are calibrated on these points (k = 356.98 on No. 2): scale near 1"
    )


@pytest.mark.parametrize("only", ["E9", "scale,scale", "", "scale,E1,E2,E3,eta1,eta2"], ids=repr)
def test_bad_only(capsys, only: str) -> None:
    code, _, err = _run(
        capsys, "fit", str(EXAMPLES / "bench_synthetic_sample2.csv"), "--only", only
    )
    assert code == 2 and "--only" in err and len(err.strip().splitlines()) == 1, err
