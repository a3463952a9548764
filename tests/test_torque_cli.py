"""``spiralcap torque`` and ``spiralcap fit``: output, the fit -> --set round trip, bad data."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from cli_outcome import run, run_json

import torque_model as tm
from spiralcap.assemble.tissue import build_tissues
from spiralcap.design import load_design

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
SAMPLE2 = tm.preset("zhou2013-sample2")


def _run(_capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    return run(list(argv))


def _json(_capsys: pytest.CaptureFixture[str], *argv: str) -> dict:
    return run_json(list(argv))


def _write_csv(
    path: Path, freq: np.ndarray, torque_mNm: np.ndarray, angle_deg: np.ndarray | None = None
) -> Path:
    head = "frequency_hz,torque_mNm" + (",helical_angle_deg" if angle_deg is not None else "")
    rows = [head]
    for i, (f, t) in enumerate(zip(freq, torque_mNm, strict=True)):
        rows.append(
            f"{float(f)!r},{float(t)!r}"
            + (f",{float(angle_deg[i])!r}" if angle_deg is not None else "")
        )
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


def test_torque_json_matches_model(capsys) -> None:
    data = _json(capsys, "torque")
    assert data["frequency_hz"] == [0.5, 1.0, 1.5, 2.0, 2.5, 3.0], "default 0.5..3 Hz"
    assert data["helical_angle_deg"] == 10.0 and data["tissue"] == "zhou2013-sample2"
    model = tm.resistive_torque_Nm(
        math.radians(10), np.array(data["frequency_hz"]), SAMPLE2, tm.PAPER_CAPSULE
    )
    assert np.allclose(data["torque_Nm"], model, rtol=1e-12), "CLI = torque_model (1e-12)"
    assert np.allclose(data["torque_mNm"], np.asarray(data["torque_Nm"]) * 1e3, rtol=1e-12)


def test_torque_options(capsys) -> None:
    five = _json(
        capsys,
        "torque",
        "--set",
        "capsule.spiral.helical_angle_deg=5",
        "--frequency",
        "3",
        "--set",
        'tissue.worst_case_presets=["zhou2013-sample3"]',
    )
    assert five["frequency_hz"] == [3.0]
    assert five["torque_mNm"][0] == pytest.approx(2.843, rel=1e-3), (
        "capsule No. 1 at 3 Hz, docs/torque-model.md section 4 table"
    )
    assert five["worst_case"][0]["tissue"] == "zhou2013-sample3"
    assert five["worst_case"][0]["torque_mNm"][0] == pytest.approx(2.632, rel=1e-3), (
        "sample 3, No. 1, 3 Hz: docs section 4"
    )
    code, out, _ = _run(capsys, "torque")
    assert code == 0 and "0.5719" in out and "mN" in out, "text table in mN·m"


def test_torque_bad_frequency(capsys) -> None:
    code, _, err = _run(capsys, "torque", "--frequency", "-1")
    assert code == 2 and "--frequency" in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1, "one-line error (CONTRIBUTING)"


def test_torque_plot(tmp_path: Path, capsys) -> None:
    png = tmp_path / "t.png"
    code, _, err = _run(capsys, "torque", "--plot", str(png))
    assert code == 0, err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", "a PNG file"


def _synthetic_csv(tmp_path: Path) -> Path:
    f = np.tile(np.linspace(0.5, 3.0, 11), 2)
    a = np.repeat([5.0, 10.0], 11)
    y = np.asarray(tm.resistive_torque_Nm(np.radians(a), f, SAMPLE2, tm.PAPER_CAPSULE)) * 1e3
    y = y * (1 + 0.02 * np.random.default_rng(4).normal(size=y.size))
    return _write_csv(tmp_path / "bench.csv", f, y, a)


def test_fit_round_trip_through_set(tmp_path: Path, capsys) -> None:
    csv_path = _synthetic_csv(tmp_path)
    design_args = ["--set", "tissue.friction_coefficient=0.3"]
    fit = _json(capsys, "fit", str(csv_path), *design_args)
    table = fit["tissue"]
    assert set(table) == {"E1_kPa", "E2_kPa", "E3_kPa", "eta1_kPa_s", "eta2_kPa_s"}, (
        "the material only: lumen, wall and friction are the bench's record (issue 26 item 4)"
    )
    assert fit["bench"]["friction_coefficient"] == 0.3, "the bench's friction, as a record"
    sets = [f"tissue.{k}={float(v)!r}" for k, v in table.items()]
    design = load_design(overrides=[design_args[1], *sets])
    tissue = build_tissues(design)[0]
    freq = np.asarray(fit["data"]["frequency_hz"])
    angle = np.radians(fit["data"]["helical_angle_deg"])
    again = np.asarray(tm.resistive_torque_Nm(angle, freq, tissue, tm.PAPER_CAPSULE)) * 1e3
    assert np.allclose(again, fit["data"]["fitted_torque_mNm"], rtol=1e-12), (
        "--set tissue.KEY=VALUE for each fitted key on the fitting design reproduces the fitted "
        "curve (1e-12)"
    )
    set_args = [arg for s in sets for arg in ("--set", s)]
    torque = _json(capsys, "torque", *design_args, *set_args, "--frequency", "1.25")
    assert torque["torque_mNm"][0] == pytest.approx(
        float(tm.resistive_torque_Nm(math.radians(10), 1.25, tissue, tm.PAPER_CAPSULE)) * 1e3,
        rel=1e-12,
    )


@pytest.mark.parametrize("only", [None, "E1", "scale"], ids=["all five", "E1", "scale"])
def test_fit_on_a_scaled_design_gives_the_fitted_curve_on_that_design(
    tmp_path: Path, capsys, only: str | None
) -> None:
    """A design's tissue constants are before its ``tissue.scale`` (which multiplies every
    tissue set): a fit on a design with scale 1.3 writes the fitted material divided by 1.3, so
    the -o file layered on that design, and the JSON 'tissue' keys set on it, give the fitted
    curve to 1e-12 (the torque model run independently of the fit). Written undivided, the
    held constants came back 1.3 x too stiff."""
    csv_path = _synthetic_csv(tmp_path)
    out = tmp_path / "fit.toml"
    only_args = ["--only", only] if only else []
    fit = _json(
        capsys, "fit", str(csv_path), "--set", "tissue.scale=1.3", *only_args, "-o", str(out)
    )
    freq = np.asarray(fit["data"]["frequency_hz"])
    angle = np.radians(fit["data"]["helical_angle_deg"])
    scaled = tmp_path / "scaled.toml"
    scaled.write_text("[tissue]\nscale = 1.3\n", encoding="utf-8")
    sets = [f"tissue.{k}={float(v)!r}" for k, v in fit["tissue"].items()]
    for how, design in (
        ("-o layered on the design", load_design([scaled, out])),
        ("the JSON keys set on the design", load_design(overrides=["tissue.scale=1.3", *sets])),
    ):
        tissue = build_tissues(design)[0]
        again = np.asarray(tm.resistive_torque_Nm(angle, freq, tissue, tm.PAPER_CAPSULE)) * 1e3
        assert np.allclose(again, fit["data"]["fitted_torque_mNm"], rtol=1e-12), (
            f"{how} gives the fitted curve (1e-12)"
        )
    assert "tissue.scale (1.3)" in out.read_text(encoding="utf-8"), "the file says why"


def test_fit_output_toml_and_plot(tmp_path: Path, capsys) -> None:
    csv_path = _synthetic_csv(tmp_path)
    out_toml, png = tmp_path / "fitted.toml", tmp_path / "fit.png"
    code, text, err = _run(capsys, "fit", str(csv_path), "-o", str(out_toml), "--plot", str(png))
    assert code == 0, err
    assert "NOT PINNED DOWN" in text and "kPa" in text, "text names unpinned params, units"
    fit = _json(capsys, "fit", str(csv_path))
    table = build_tissues(load_design(out_toml))[0].as_design_table()
    assert {k: table[k] for k in fit["tissue"]} == pytest.approx(fit["tissue"], rel=1e-15), (
        "-o TOML loaded as a design file gives the fitted constants"
    )
    assert png.read_bytes()[:4] == b"\x89PNG"


def test_fit_example_file(capsys) -> None:
    fit = _json(capsys, "fit", str(EXAMPLES / "bench_synthetic_sample2.csv"))
    rel = np.asarray(fit["data"]["relative_residual"])
    assert np.sqrt(np.mean(rel**2)) < 0.04, "example made with 3 % noise fits to the noise"
    assert fit["not_pinned_down"], "a 0.5-3 Hz curve cannot pin all five down (docs section 5)"
    for entry in fit["parameters"].values():
        assert entry["pinned_down"] == (not entry["flags"])


BAD = [
    ("frequency_hz,torque_mNm\n0.5,0.6\n1,abc\n", "line 3 (data row 2), column torque_mNm"),
    ("frequency_hz,torque_mNm\n0.5,0.6\n1,nan\n", "line 3 (data row 2), column torque_mNm"),
    ("frequency_hz,torque_mNm\n0.5,0.6\n0,0.7\n", "line 3 (data row 2), column frequency_hz"),
    ("frequency_hz,torque_mNm\n-1,0.6\n1,0.7\n", "line 2 (data row 1), column frequency_hz"),
    ("frequency_hz,torque_mNm\n0.5,-0.6\n", "line 2 (data row 1), column torque_mNm"),
    ("frequency_hz,torque_mNm\n0.5,\n", "column torque_mNm: empty cell"),
    ("# c\nfrequency_hz,torque\n0.5,0.6\n", "line 2: missing column 'torque_mNm'"),
    ("frequency_hz,torque_mNm,helical_angle_deg\n0.5,0.6,95\n", "column helical_angle_deg"),
    ("frequency_hz,torque_mNm\n0.5,0.6\n1,0.8\n2,1.2\n3,1.8\n", "4 data rows for 5 parameters"),
    ("", "no header row"),
    ("frequency_hz,torque_mNm\n", "no data rows"),
]


@pytest.mark.parametrize(("text", "message"), BAD, ids=[m for _, m in BAD])
def test_fit_bad_data(tmp_path: Path, capsys, text: str, message: str) -> None:
    path = tmp_path / "bad.csv"
    path.write_text(text, encoding="utf-8")
    code, _, err = _run(capsys, "fit", str(path))
    assert code == 2, err
    assert message in err, f"error names the row/column: {err!r}"
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, "one line, no traceback"


def test_fit_missing_file_and_bad_plot_name(tmp_path: Path, capsys) -> None:
    code, _, err = _run(capsys, "fit", str(tmp_path / "nope.csv"))
    assert code == 2 and "nope.csv" in err and "cannot read" in err
    code, _, err = _run(
        capsys,
        "fit",
        str(EXAMPLES / "bench_synthetic_sample2.csv"),
        "--plot",
        str(tmp_path / "x.gif"),
    )
    assert code == 2 and "--plot" in err


def test_paper_points_example_refused(capsys) -> None:
    code, _, err = _run(capsys, "fit", str(EXAMPLES / "paper_points_sample2.csv"))
    assert code == 2 and "4 data rows for 5 parameters" in err
