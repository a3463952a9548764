"""Issue 22, "unbounded or unguarded inputs": every file a design names goes through the guarded
reader, relative paths resolve against the file that names them, and a covariance is checked
for finiteness, symmetry, positive semi-definiteness and magnitude before any use."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from tests.cli_outcome import run, sound

COV = "tissue.uncertainty.covariance_from"
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _cov_file(path, cov) -> str:
    rows = ",\n".join("  [" + ", ".join(repr(float(x)) for x in r) + "]" for r in cov)
    path.write_text(f"[tissue.fit]\ncovariance_log = [\n{rows},\n]\n")
    return str(path)


def _spiralcap(*argv: str, timeout: float = 60, cwd=None) -> subprocess.CompletedProcess:
    """The CLI as a subprocess: what it writes to stderr is seen whole (C code included)."""
    return subprocess.run(
        [sys.executable, "-m", "spiralcap.cli", *argv],
        capture_output=True,
        text=True,
        timeout=timeout,
        cwd=cwd,
        env={**os.environ, "PYTHONWARNINGS": "default", "PYTHONPATH": ROOT},
    )


def _one_line_exit_2(proc: subprocess.CompletedProcess, *words: str) -> None:
    lines = proc.stderr.splitlines()
    assert proc.returncode == 2, (proc.returncode, proc.stderr[-800:])
    assert len(lines) == 1, f"exit 2 needs exactly one stderr line, got {lines}"
    for w in words:
        assert w in lines[0], f"{w!r} not in {lines[0]!r}"
    assert "Warning" not in proc.stderr and "Traceback" not in proc.stderr


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_covariance_from_a_fifo_is_refused_within_seconds(tmp_path):
    fifo = tmp_path / "cov.fifo"
    os.mkfifo(fifo)
    proc = _spiralcap("uncertainty", "--samples", "64", "--set", f"{COV}='{fifo}'", timeout=30)
    _one_line_exit_2(proc, COV, "cov.fifo", "not a regular file")


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="needs /dev/zero")
def test_covariance_from_dev_zero_is_refused():
    proc = _spiralcap("uncertainty", "--samples", "64", "--set", f"{COV}='/dev/zero'", timeout=30)
    _one_line_exit_2(proc, COV, "/dev/zero", "not a regular file")


@pytest.mark.parametrize(
    ("content", "why"),
    [
        (b'[tissue.fit]\ncovariance_log = "\xe9"\n', "not UTF-8"),
        (b"a = " + b"[" * 200 + b"]" * 200 + b"\n", "nested more than"),
        (b"a = " + b"9" * 5000 + b"\n", "digits"),
        (b"tissue = 5\n", "tissue.fit.covariance_log"),
        (b"[tissue]\nfit = [1, 2]\n", "tissue.fit.covariance_log"),
        (b"[tissue.fit]\ncovariance_log = [[1, 2], [3]]\n", "5 x 5"),
        (b"[tissue.fit]\ncovariance_log = ['a', 'b', 'c', 'd', 'e']\n", "5 x 5"),
        (b"not toml at all = = =\n", "TOML"),
    ],
)
def test_unreadable_covariance_files_are_one_line(tmp_path, content, why):
    p = tmp_path / "cov.toml"
    p.write_bytes(content)
    _rc, _, err = sound(["uncertainty", "--samples", "64", "--set", f"{COV}='{p}'"], allowed=(2,))
    assert COV in err and "cov.toml" in err and why in err, err


@pytest.mark.parametrize(
    ("cov", "why"),
    [
        (np.eye(5) * 1e308, "up to 4"),
        (np.full((5, 5), 1e308), "up to 4"),
        (np.eye(5) * 1e25, "up to 4"),
        (np.eye(5) * 4.5, "up to 4"),
        (np.where(np.eye(5) > 0, np.inf, 0.0), "finite"),
        (np.where(np.eye(5) > 0, np.nan, 0.0), "finite"),
        (np.zeros((5, 5)), "at least one variance of 1e-12"),
        (np.eye(5) * 5e-324, "at least one variance of 1e-12"),
        (np.eye(5) * 1e-300, "at least one variance of 1e-12"),
        (-np.eye(5), "semi-definite"),
        (np.eye(5) * 0.1 + np.diag([0.05] * 4, 1), "symmetric"),
        # each |c_ij| <= sqrt(c_ii c_jj), yet not PSD: eigenvalue 1 - 2 * 0.9 < 0 ... of a 3-cycle
        (
            np.block(
                [
                    [np.array([[1, 0.9, -0.9], [0.9, 1, 0.9], [-0.9, 0.9, 1]]), np.zeros((3, 2))],
                    [np.zeros((2, 3)), np.eye(2)],
                ]
            ),
            "semi-definite",
        ),
    ],
)
def test_bad_covariances_exit_2_naming_the_file(tmp_path, cov, why):
    """#20 item 3 / #22: no LinAlgError, no RuntimeWarning, no NaN percentiles; the error
    names covariance_from and the file, never "tissue.uncertainty = 'none'". In-process (the
    refusal is Python's, before any solve): pytest's ``filterwarnings = error`` turns any
    warning into a failure, ``sound`` asserts one line and no traceback; the same refusal as a
    process (stderr seen whole) is in ``test_a_bad_covariance_is_one_line_as_a_process``."""
    p = _bad_cov_file(tmp_path, cov)
    _rc, _, err = sound(["uncertainty", "--samples", "64", "--set", f"{COV}='{p}'"], allowed=(2,))
    for w in (COV, "cov.toml", why):
        assert w in err, f"{w!r} not in {err!r}"
    assert "Warning" not in err and "'none'" not in err, err


def test_a_bad_covariance_is_one_line_as_a_process(tmp_path):
    """One refusal of the parametrised cases above (the not-semi-definite 3-cycle: the
    eigenvalue check) as a process: exit 2, one stderr line, no warning (PYTHONWARNINGS)."""
    c3 = np.array([[1, 0.9, -0.9], [0.9, 1, 0.9], [-0.9, 0.9, 1]])
    cov = np.block([[c3, np.zeros((3, 2))], [np.zeros((2, 3)), np.eye(2)]])
    p = _bad_cov_file(tmp_path, cov)
    proc = _spiralcap("uncertainty", "--samples", "64", "--set", f"{COV}='{p}'")
    _one_line_exit_2(proc, COV, "cov.toml", "semi-definite")
    assert "'none'" not in proc.stderr


def _bad_cov_file(tmp_path, cov) -> str:
    p = tmp_path / "cov.toml"
    p.write_text(
        "[tissue.fit]\ncovariance_log = ["
        + ", ".join("[" + ", ".join(_toml_float(x) for x in r) + "]" for r in cov)
        + "]\n"
    )
    return str(p)


def _toml_float(x: float) -> str:
    if np.isnan(x):
        return "nan"
    if np.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(float(x))


def test_relative_covariance_from_resolves_against_the_file_naming_it(tmp_path, monkeypatch):
    """Two layered design files in different folders: the relative path in the second one is
    read from the second one's folder, whatever the current folder holds."""
    base_dir, fit_dir, elsewhere = tmp_path / "base", tmp_path / "fit", tmp_path / "cwd"
    for d in (base_dir, fit_dir, elsewhere):
        d.mkdir()
    (base_dir / "base.toml").write_text("[limits]\npower_W = 600.0\n")
    (fit_dir / "layer.toml").write_text("[tissue.uncertainty]\ncovariance_from = 'cov.toml'\n")
    _cov_file(fit_dir / "cov.toml", np.eye(5) * 0.04)
    # a different covariance where a cwd-relative reading would find it
    _cov_file(elsewhere / "cov.toml", np.eye(5) * 1e25)
    monkeypatch.chdir(elsewhere)
    from spiralcap.assemble.tissue import build_uncertainty
    from spiralcap.design import load_design

    design = load_design([base_dir / "base.toml", fit_dir / "layer.toml"])
    unc = build_uncertainty(design)
    assert np.allclose(unc.covariance_log, np.eye(5) * 0.04), "read the cwd's cov.toml"
    # and from the command line (in-process, run in the other folder: the chdir above)
    sound(
        [
            "uncertainty",
            str(base_dir / "base.toml"),
            str(fit_dir / "layer.toml"),
            "--samples",
            "256",
            "--sobol-samples",
            "0",
            "--json",
        ],
        allowed=(0,),
    )
    # a --set value is relative to the current folder
    design = load_design(
        [base_dir / "base.toml", fit_dir / "layer.toml"], [f"{COV}='{fit_dir / 'cov.toml'}'"]
    )
    assert np.allclose(build_uncertainty(design).covariance_log, np.eye(5) * 0.04)


def test_a_single_design_file_in_another_folder(tmp_path, monkeypatch):
    d = tmp_path / "d"
    d.mkdir()
    (d / "design.toml").write_text("[tissue.uncertainty]\ncovariance_from = 'cov.toml'\n")
    _cov_file(d / "cov.toml", np.eye(5) * 0.09)
    monkeypatch.chdir(tmp_path)
    from spiralcap.assemble.tissue import build_uncertainty
    from spiralcap.design import load_design

    unc = build_uncertainty(load_design("d/design.toml"))
    assert np.allclose(unc.covariance_log, np.eye(5) * 0.09)


# --- bounds before work, outputs checked first (issue 22 items 5) ------------------------------

LONG = "a" * 300


@pytest.mark.parametrize(
    ("argv", "option"),
    [
        (["uncertainty", "--samples", "1e13"], "--samples"),
        (["uncertainty", "--samples", "10000000000000"], "--samples"),
        (["uncertainty", "--samples", "0"], "--samples"),
        (["uncertainty", "--sobol-samples", "1e9"], "--sobol-samples"),
        (["uncertainty", "--sobol-samples", "3"], "--sobol-samples"),
        (["uncertainty", "--seed", "1e300"], "--seed"),
        (["uncertainty", "--seed", "-1"], "--seed"),
        (["uncertainty", "--workers", "1e6"], "--workers"),
        (["sweep", "--over", "limits.power_W=500:900:2", "--workers", "100000"], "--workers"),
        (["report", "-o", "r.html", "--workers", "1e9"], "--workers"),
        (["uncertainty", "--samples", "2.5"], "--samples"),
        (["compare", *["builtin"] * 17], "DESIGN"),
        (["torque", "--frequency", *["1"] * 10_001], "--frequency"),
    ],
)
def test_count_options_are_bounded_before_work(tmp_path, monkeypatch, argv, option):
    monkeypatch.chdir(tmp_path)
    _, _, err = sound([*argv, "--set", "tissue.uncertainty.scale_sigma_log=0.3"], allowed=(2,))
    assert option in err, err
    assert os.listdir(tmp_path) == [], "nothing written"


def test_samples_bound_names_its_reason():
    _, _, err = sound(
        ["uncertainty", "--samples", "1e13", "--set", "tissue.uncertainty.scale_sigma_log=0.3"],
        allowed=(2,),
    )
    assert "--samples" in err and "67108864" in err and "memory" in err, err


@pytest.mark.parametrize(
    "argv",
    [
        ["coils"],
        ["sweep", "--over", "limits.power_W=500:900:2"],
        ["waveforms", "--heading", "1,0,0", "--dwell-s", "1"],
        ["uncertainty", "--samples", "64", "--set", "tissue.uncertainty.scale_sigma_log=0.3"],
        ["torque"],
        ["fit", str(os.path.join(ROOT, "examples", "bench_synthetic_sample2.csv"))],
    ],
    ids=lambda a: a[0],
)
@pytest.mark.parametrize("plot", [LONG + ".png", "a.png/", "sub/" + LONG + "/f.png", "UNWRITABLE"])
def test_plot_paths_are_refused_before_any_computation(tmp_path, monkeypatch, argv, plot):
    """A file name over 255 bytes, a trailing slash, a folder where nothing can be created:
    exit 2 naming --plot, before the computation (no traceback, nothing written)."""
    monkeypatch.chdir(tmp_path)
    if plot == "UNWRITABLE":
        if not os.path.isdir("/proc/self"):
            pytest.skip("needs /proc (a folder nobody can create files in, root included)")
        plot = "/proc/f.png"
    calls: list[str] = []
    import spiralcap.assemble as assemble

    real = assemble.build_model
    monkeypatch.setattr(assemble, "build_model", lambda *a, **k: calls.append("b") or real(*a, **k))
    _, _, err = sound([*argv, "--plot", plot], allowed=(2,))
    assert "--plot" in err, err
    assert not calls, "the output was checked after work began"
    assert os.listdir(tmp_path) == [], "nothing written"


def test_a_long_but_valid_file_name_is_written(tmp_path):
    name = "b" * 251 + ".png"  # 255 bytes: the staging file's name must fit too
    sound(["coils", "--plot", str(tmp_path / name)], allowed=(0,))
    assert os.listdir(tmp_path) == [name]


def test_unwritable_output_of_uncertainty_is_refused_first(tmp_path):
    if not os.path.isdir("/proc/self"):
        pytest.skip("needs /proc")
    _, _, err = sound(
        ["uncertainty", "--set", "tissue.uncertainty.scale_sigma_log=0.3", "--plot", "/proc/u.png"],
        allowed=(2,),
    )
    assert "--plot" in err and "/proc" in err


# --- tracebacks and warnings (subprocess: the promise is about stderr) ---------------------------


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["waveforms", "--heading", "1,0,0", "--dwell-s", "5e-324"], ["--dwell-s"]),
        (["waveforms", "--heading", "1,0,0", "--dwell-s", "1", "--ramp-s", "5e-324"], ["--ramp-s"]),
        (["torque", "--frequency", "1e308"], ["--frequency", "100 Hz"]),
        (["torque", "--frequency", "1e-200"], ["--frequency"]),
    ],
)
def test_tiny_and_huge_numbers_are_one_line(argv, words):
    proc = _spiralcap(*argv)
    _one_line_exit_2(proc, *words)


def test_fit_row_at_1e_200_hz_and_an_overlong_cell(tmp_path):
    tiny = tmp_path / "tiny.csv"
    tiny.write_text("frequency_hz,torque_mNm\n1e-200,0.3\n0.5,0.9\n1,1.2\n2,2.0\n3,2.5\n4,3\n")
    _one_line_exit_2(_spiralcap("fit", str(tiny)), "tiny.csv", "frequency_hz", "0.001 Hz")
    for cell in ("9" * 140_000, '"' + "9" * 140_000 + '"'):
        long = tmp_path / "long.csv"
        long.write_text(f"frequency_hz,torque_mNm\n1,{cell}\n")
        proc = _spiralcap("fit", str(long))
        _one_line_exit_2(proc, "long.csv", "line 2")
        assert len(proc.stderr) < 600, "the cell is not echoed whole"


def test_waveforms_heading_in_the_form_help_shows():
    """`--heading -1,0,0` (a reversed axis, as `--help` writes it), not only `--heading=-1,0,0`.
    In-process (argparse's reading of the argument is the subject; pytest's ``filterwarnings =
    error`` fails the run on any warning, stricter than the empty stderr checked too)."""
    rc, out, err = run(
        ["waveforms", "--heading", "-1,0,0", "--heading", "0,-1,0", "--dwell-s", "1", "--json"]
    )
    assert rc == 0, err
    import json

    doc = json.loads(out)
    assert np.allclose(doc["headings"], [[-1, 0, 0], [0, -1, 0]]), doc["headings"]
    assert err == ""


def test_huge_heading_is_a_direction_like_workspace_headings():
    """In-process: an overflow in the normalisation would be a RuntimeWarning, which pytest's
    ``filterwarnings = error`` turns into a failure (the empty stderr is checked as well)."""
    rc, out, err = run(["waveforms", "--heading", "1e200,1e200,0", "--dwell-s", "1", "--json"])
    assert rc == 0 and err == "", err
    import json

    h = json.loads(out)["headings"][0]
    assert np.allclose(h, [2**-0.5, 2**-0.5, 0.0]), h
    rc_same, same, _ = run(["waveforms", "--heading", "1,1,0", "--dwell-s", "1", "--json"])
    a, b = json.loads(out), json.loads(same)
    assert rc_same == 0 and a["peaks"] == b["peaks"], "the same direction as 1,1,0"


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_a_design_file_that_is_a_fifo_is_refused_within_seconds(tmp_path):
    fifo = tmp_path / "design.toml"
    os.mkfifo(fifo)
    _one_line_exit_2(_spiralcap("evaluate", str(fifo), timeout=30), "design.toml", "regular file")
    data = tmp_path / "bench.csv"
    os.mkfifo(data)
    _one_line_exit_2(_spiralcap("fit", str(data), timeout=30), "bench.csv", "regular file")


def test_optimum_written_elsewhere_keeps_its_covariance(tmp_path, monkeypatch):
    """`optimize -o` into another folder: the relative covariance_from is written absolute,
    so the written design reads the same covariance."""
    d, out = tmp_path / "d", tmp_path / "out"
    d.mkdir()
    out.mkdir()  # outputs go into existing folders only
    (d / "design.toml").write_text("[tissue.uncertainty]\ncovariance_from = 'cov.toml'\n")
    _cov_file(d / "cov.toml", np.eye(5) * 0.09)
    monkeypatch.chdir(tmp_path)
    sound(["optimize", "d/design.toml", "-o", str(out / "opt.toml")], allowed=(0,))
    from spiralcap.assemble.tissue import build_uncertainty
    from spiralcap.design import load_design

    monkeypatch.chdir(d)
    unc = build_uncertainty(load_design(out / "opt.toml"))
    assert np.allclose(unc.covariance_log, np.eye(5) * 0.09)
