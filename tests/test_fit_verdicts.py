"""Issue 26 items 4 and 5: a fit writes material, not anatomy, and its verdicts follow the evidence.

``fit -o`` writes the five constants into ``[tissue]`` and the bench's geometry as a record under
``[tissue.fit]``; ``fit --json`` says ``model_follows_data`` (lack-of-fit F test at p < 0.01,
docs/torque-model.md section 5) and ``pinned_down``; a fit that did not converge writes nothing
and exits 3.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from cli_outcome import run, run_json, sound

import torque_model as tm
import torque_model.identification as ti
from spiralcap.design import load_design
from torque_model.fit_quality import assess_fit, lack_of_fit

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
SAMPLE2 = tm.preset("zhou2013-sample2")
F11 = np.linspace(0.5, 3.0, 11)
A10 = math.radians(10.0)


def _csv(path: Path, freq: np.ndarray, torque_mNm: np.ndarray) -> Path:
    rows = "".join(f"{float(f)!r},{float(t)!r}\n" for f, t in zip(freq, torque_mNm, strict=True))
    path.write_text("frequency_hz,torque_mNm\n" + rows, encoding="utf-8")
    return path


def _model_mNm(freq: np.ndarray, noise: float, seed: int, k: float = 1.0) -> np.ndarray:
    """Sample 2 (constants x k) on the paper's capsule No. 2 (10 deg), relative noise."""
    truth = SAMPLE2.scaled(k, "truth") if k != 1.0 else SAMPLE2
    clean = np.asarray(tm.resistive_torque_Nm(A10, freq, truth, tm.PAPER_CAPSULE)) * 1e3
    return clean * (1.0 + noise * np.random.default_rng(seed).standard_normal(freq.size))


def _power_law_mNm(freq: np.ndarray, noise: float) -> np.ndarray:
    """torque proportional to f^1.5, sample 2's mean level: a shape the model cannot take."""
    level = float(np.mean(_model_mNm(freq, 0.0, 0)))
    shape = freq**1.5 / np.mean(freq**1.5)
    return level * shape * (1.0 + noise * np.random.default_rng(3).standard_normal(freq.size))


# --- item 4: a fit writes material, not anatomy ------------------------------------------------


def test_layering_a_fit_keeps_the_designs_lumen(tmp_path: Path) -> None:
    csv = _csv(tmp_path / "bench.csv", F11, _model_mNm(F11, 0.02, 20, k=1.3))
    fitted = tmp_path / "f.toml"
    code, _, err = run(["fit", str(csv), "--only", "scale", "-o", str(fitted)])
    assert code == 0, err
    mine = tmp_path / "my.toml"
    mine.write_text("[tissue]\nlumen_diameter_mm = 9.5\n", encoding="utf-8")
    layered = run_json(["torque", str(mine), str(fitted)])
    direct = run_json(["torque", str(fitted), "--set", "tissue.lumen_diameter_mm=9.5"])
    layered.pop("design"), direct.pop("design")
    assert layered == direct, (
        "torque my.toml f.toml == torque f.toml --set tissue.lumen_diameter_mm=9.5: the fit "
        "never replaces the design's lumen (issue 26 item 4)"
    )
    table = tomllib.loads(fitted.read_text(encoding="utf-8"))["tissue"]
    assert set(table) == {"E1_kPa", "E2_kPa", "E3_kPa", "eta1_kPa_s", "eta2_kPa_s", "fit"}, (
        "[tissue] holds the five constants and the [tissue.fit] record only"
    )
    design = load_design([mine, fitted])
    assert design["tissue.lumen_diameter_mm"] == 9.5
    assert design.get("tissue.wall_thickness_mm") is None, "wall: the preset's, not the bench's"
    assert design.get("tissue.friction_coefficient") is None, "friction: not the bench's"
    assert design["tissue.fit.bench_lumen_diameter_mm"] == pytest.approx(
        SAMPLE2.lumen_diameter_m * 1e3, rel=1e-12
    ), "the bench's lumen is recorded (sample 2: 10.9 mm)"
    assert design["tissue.fit.bench_helical_angles_deg"] == [10.0]
    assert design["tissue.fit.bench_frequency_range_hz"] == [0.5, 3.0]


def test_written_file_round_trips_through_the_design_loader(tmp_path: Path) -> None:
    csv = _csv(tmp_path / "bench.csv", F11, _model_mNm(F11, 0.02, 20, k=1.3))
    fitted = tmp_path / "f.toml"
    code, _, err = run(["fit", str(csv), "--only", "scale", "-o", str(fitted)])
    assert code == 0, err
    out = run_json(["fit", str(csv), "--only", "scale"])
    design = load_design(fitted)
    for key, value in out["tissue"].items():
        assert design[f"tissue.{key}"] == value, f"tissue.{key}: written as fitted (exact)"
    for key, value in out["bench"].items():
        assert design[f"tissue.fit.bench_{key}"] == value, f"tissue.fit.bench_{key}: recorded"
    cov = np.asarray(design["tissue.fit.covariance_log"])
    var = out["parameters"]["scale"]["standard_error_log"] ** 2
    assert np.allclose(cov, var, rtol=1e-9), "the covariance is still written (Var(ln s) 1 1^T)"
    code, text, err = run(
        [
            "uncertainty",
            str(fitted),
            "--set",
            f"tissue.uncertainty.covariance_from='{fitted}'",
            "--samples",
            "256",
            "--sobol-samples",
            "0",
            "--json",
        ]
    )
    assert code == 0, err
    assert json.loads(text)["uncertain_inputs"] == ["fit covariance"], "covariance_from works"


# --- item 5: verdicts that follow the evidence -------------------------------------------------


@pytest.mark.parametrize("only", [None, "scale"], ids=["five constants", "scale"])
def test_model_data_with_2_percent_noise_is_followed(tmp_path: Path, only: str | None) -> None:
    csv = _csv(tmp_path / "bench.csv", F11, _model_mNm(F11, 0.02, 20, k=1.3))
    out = run_json(["fit", str(csv), *(["--only", only] if only else [])])
    lof = out["fit_quality"]["lack_of_fit"]
    assert out["model_follows_data"] is True and out["fit_quality"]["follows_data"] is True, (
        f"points from the model with 2 % noise: no lack of fit (F test p = {lof['p_value']:.3g})"
    )
    assert lof["test"] == "reference curve" and lof["tested"] and lof["passed"]
    assert lof["p_value"] >= 0.01
    code, text, _ = run(["fit", str(csv), *(["--only", only] if only else [])])
    assert code == 0 and "The model follows these data" in text
    assert "DOES NOT FOLLOW" not in text


def test_a_shape_the_model_cannot_take_is_not_followed(tmp_path: Path) -> None:
    csv = _csv(tmp_path / "bench.csv", F11, _power_law_mNm(F11, 0.02))
    out = run_json(["fit", str(csv), "--only", "scale"])
    lof = out["fit_quality"]["lack_of_fit"]
    assert out["model_follows_data"] is False, (
        "torque ~ f^1.5 fitted with the scale alone: the residual variance far exceeds the "
        "reference curve's (2 % noise), lack-of-fit F test p < 0.01"
    )
    assert lof["tested"] and not lof["passed"] and lof["p_value"] < 0.01
    assert out["pinned_down"] == {"scale": True}, "one number is still narrowly bounded"
    code, text, _ = run(["fit", str(csv), "--only", "scale"])
    assert code == 0 and "THE MODEL DOES NOT FOLLOW THESE DATA" in text
    assert "lack of fit" in text and "assume the model is right" in text, (
        "a narrow interval under a wrong shape is said to rest on the model"
    )
    assert "The model follows" not in text


def test_constants_the_data_cannot_separate_are_not_pinned_down(tmp_path: Path) -> None:
    csv = _csv(tmp_path / "bench.csv", F11, _model_mNm(F11, 0.02, 20))
    out = run_json(["fit", str(csv)])
    assert out["model_follows_data"] is True, "the curve is the model's own"
    assert not any(out["pinned_down"].values()), (
        "a 0.5-3 Hz curve fixes about two combinations of five constants (docs section 5): "
        f"none pinned down, got {out['pinned_down']}"
    )
    assert out["pinned_down"] == {k: v["pinned_down"] for k, v in out["parameters"].items()}
    code, text, _ = run(["fit", str(csv)])
    assert code == 0
    assert "The model follows these data" in text and "NOT PINNED DOWN by these data" in text


def test_the_issue_six_point_fit_converges_and_is_followed() -> None:
    """Issue 26: five constants on six points with 2.6 % residual stopped at max_nfev (condition
    number 1e15) and printed 'does not follow'; with the cost judged, it converges."""
    f6 = np.linspace(0.5, 3.0, 6)
    y = _model_mNm(f6, 0.03, 7) * 1e-3
    fit = tm.identify(f6, y, A10, SAMPLE2, tm.PAPER_CAPSULE)
    assert fit.success, fit.message
    quality = assess_fit(fit)
    assert quality.follows_data, quality.problems


def test_a_fit_accepted_on_its_cost_predicts_as_the_converged_one() -> None:
    """Budget 80: the best start stops with the parameters drifting along a null direction; 50
    more evaluations lower the cost by < 1e-6, so the fit is accepted on its cost -- and its
    curve is the fully converged fit's (gtol, 200 + 1000 evaluations) to 1e-6."""
    f6 = np.linspace(0.5, 3.0, 6)
    y = _model_mNm(f6, 0.03, 7) * 1e-3
    full = tm.identify(f6, y, A10, SAMPLE2, tm.PAPER_CAPSULE, profile_bounds=False)
    short = tm.identify(f6, y, A10, SAMPLE2, tm.PAPER_CAPSULE, profile_bounds=False, max_nfev=80)
    assert short.success and short.message.startswith("cost converged"), short.message
    assert short.cost == pytest.approx(full.cost, rel=1e-6), "the cost is the minimum's (1e-6)"
    assert np.allclose(short.predicted_Nm, full.predicted_Nm, rtol=1e-6, atol=0), (
        "the written constants give the converged fit's curve (1e-6)"
    )


def test_forced_non_convergence_exits_3_and_writes_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    f6 = np.linspace(0.5, 3.0, 6)
    csv = _csv(tmp_path / "bench.csv", f6, _model_mNm(f6, 0.03, 7))
    monkeypatch.setattr(ti, "_START_NFEV", 5)
    monkeypatch.setattr(ti, "_MAX_NFEV", 5)
    monkeypatch.setattr(ti, "_CHECK_NFEV_MIN", 10)
    toml, png = tmp_path / "f.toml", tmp_path / "f.png"
    _, text, err = sound(["fit", str(csv), "-o", str(toml), "--plot", str(png)], allowed=(3,))
    assert "did not converge" in err and "nothing written" in err, err
    assert "NOT CONVERGED" in text
    assert not toml.exists() and not png.exists(), "exit 3: nothing written"
    _, out, _ = sound(["fit", str(csv), "--json"], allowed=(3,))
    doc = json.loads(out)
    assert doc["success"] is False and doc["model_follows_data"] is False
    assert "evaluations" in doc["message"], "the message says the budget ran out"
    schema = json.loads((ROOT / "docs" / "json" / "fit.schema.json").read_text(encoding="utf-8"))
    try:
        import jsonschema
    except ModuleNotFoundError:  # optional test dependency: the schema tests skip too
        return
    jsonschema.validate(doc, schema)


def test_reference_curve_test_against_an_independent_fit() -> None:
    """The reference curve's residuals from numpy.polyfit (one angle: an intercept, ln f,
    (ln f)^2), and F = (SSE_model / (n - k)) / (SSE_ref / (n - 3)) by hand."""
    y = _power_law_mNm(F11, 0.02) * 1e-3
    fit = tm.identify(F11, y, A10, SAMPLE2, tm.PAPER_CAPSULE, free=("scale",))
    lof = lack_of_fit(fit)
    coef = np.polyfit(np.log(F11), np.log(y), 2)
    r_ref = np.polyval(coef, np.log(F11)) - np.log(y)
    e = np.log(fit.predicted_Nm) - np.log(y)
    F = (e @ e / (F11.size - 1)) / (r_ref @ r_ref / (F11.size - 3))
    assert lof.f_statistic == pytest.approx(F, rel=1e-9), "F by hand with numpy.polyfit (1e-9)"
    assert (lof.dof_numerator, lof.dof_denominator) == (10, 8)


def test_replicates_use_the_pure_error_test() -> None:
    """Three points at each of six frequencies: the classical test (Draper & Smith 2.1), with
    the pure error from the spread about each frequency's mean, computed here by hand."""
    f = np.repeat(np.linspace(0.5, 3.0, 6), 3)
    y = _model_mNm(f, 0.02, 5) * 1e-3
    fit = tm.identify(f, y, A10, SAMPLE2, tm.PAPER_CAPSULE, free=("scale",))
    lof = lack_of_fit(fit)
    ln_y = np.log(y).reshape(6, 3)
    ss_pure = float(np.sum((ln_y - ln_y.mean(axis=1, keepdims=True)) ** 2))
    e = np.log(fit.predicted_Nm) - np.log(y)
    F = ((e @ e - ss_pure) / (6 - 1)) / (ss_pure / (18 - 6))
    assert lof.test == "pure error" and lof.f_statistic == pytest.approx(F, rel=1e-9)
    assert assess_fit(fit).follows_data, "model data with 2 % noise pass the pure-error test"
    y15 = f**1.5 * 1e-3 * (1 + 0.02 * np.random.default_rng(5).standard_normal(f.size))
    bad = tm.identify(f, y15, A10, SAMPLE2, tm.PAPER_CAPSULE, free=("scale",))
    assert lack_of_fit(bad).p_value < 0.01, "f^1.5 fails the pure-error test"


def test_too_few_points_are_not_tested(tmp_path: Path) -> None:
    f3 = np.array([0.5, 1.5, 3.0])
    csv = _csv(tmp_path / "three.csv", f3, _model_mNm(f3, 0.02, 1))
    out = run_json(["fit", str(csv), "--only", "scale"])
    assert out["fit_quality"]["lack_of_fit"]["tested"] is False, (
        "three points at one angle: the reference curve has three parameters, no dof left"
    )
    assert out["model_follows_data"] is False, "a verdict needs evidence"
    assert out["fit_quality"]["verdict"].startswith("too few points")
    code, text, _ = run(["fit", str(csv), "--only", "scale"])
    assert code == 0 and "NOT TESTED whether the model follows" in text
    assert "DOES NOT FOLLOW" not in text and "The model follows" not in text


def test_noiseless_model_data_on_many_angles_fit_and_layer(tmp_path: Path) -> None:
    """70 points from the model itself over 70 helical angles, 8 digits (a review's case): the fit
    reproduces them (relative rms residual far below any bench noise) and is accepted although
    its cost still creeps down; the file it writes records at most 64 angles and loads."""
    angles = np.linspace(5.0, 15.0, 70)
    freq = 0.5 + (np.arange(70) % 10) * 17.5 / 69  # written to 6 decimals: a 1e-7 floor
    torque = [
        float(tm.resistive_torque_Nm(math.radians(a), f, SAMPLE2, tm.PAPER_CAPSULE)) * 1e3
        for a, f in zip(angles, freq, strict=True)
    ]
    rows = "".join(
        f"{f:.6f},{t:.8g},{a:.6f}\n" for f, t, a in zip(freq, torque, angles, strict=True)
    )
    csv = tmp_path / "bench.csv"
    csv.write_text("frequency_hz,torque_mNm,helical_angle_deg\n" + rows, encoding="utf-8")
    out = tmp_path / "fit.toml"
    code, _, err = run(["fit", str(csv), "-o", str(out)])
    assert code == 0 and out.exists(), err
    recorded = tomllib.loads(out.read_text())["tissue"]["fit"]["bench_helical_angles_deg"]
    assert len(recorded) == 64 and recorded[0] == 5.0 and recorded[-1] == 15.0, (
        "at most 64 angles recorded, both ends kept"
    )
    ev = run_json(["evaluate", str(out)])
    assert ev["margin_Nm"] is not None, "the written file loads as a design"
