"""``spiralcap uncertainty``: output, bad input (exit 2), fit covariance round trip, Dask = local."""

import json

import numpy as np
import pytest

from spiralcap.cli import main

SIGMA = ["--set", "tissue.uncertainty.scale_sigma_log=0.3"]


def _closed_port() -> int:
    """A TCP port nothing listens on: one the OS just handed out and took back (no fixed
    number that another program may be using)."""
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_json_has_the_promised_fields(capsys, tmp_path):
    png = tmp_path / "u.png"
    out = _json(
        capsys,
        [
            "uncertainty",
            *SIGMA,
            "--set",
            "tissue.uncertainty.friction_sigma_log=0.2",
            "--samples",
            "5000",
            "--sobol-samples",
            "256",
            "--plot",
            str(png),
            "--json",
        ],
    )
    assert out["samples"] == 5000
    lo, hi = out["stepout_probability_ci95"]
    assert lo <= out["stepout_probability"] <= hi
    assert set(out["margin_percentiles_Nm"]) == {"p01", "p05", "p50", "p95"}
    assert set(out["speed_percentiles_m_s"]) == {"p01", "p05", "p50", "p95"}
    assert set(out["sobol"]["indices"]) == {"scale", "friction"}
    assert png.stat().st_size > 10_000


@pytest.mark.parametrize(
    ("argv", "named"),
    [
        (["--set", "tissue.uncertainty.scale_sigma_log=-0.1"], "scale_sigma_log"),
        ([*SIGMA, "--samples", "0"], "--samples"),
        ([*SIGMA, "--seed", "-1"], "--seed"),
        ([*SIGMA, "--workers", "0"], "--workers"),
        ([*SIGMA, "--sobol-samples", "100"], "--sobol-samples"),
        ([], "tissue.uncertainty"),
        ([*SIGMA, "--dask", f"tcp://127.0.0.1:{_closed_port()}"], "--dask"),
    ],
)
def test_bad_input_exits_2_naming_it(capsys, monkeypatch, argv, named):
    # the closed port: the bounded wait and its message are tested, not the product's 3 s
    monkeypatch.setattr("spiralcap.dask_cluster.CONNECT_TIMEOUT_S", 0.5)
    assert main(["uncertainty", *argv]) == 2
    err = capsys.readouterr().err
    assert named in err and len(err.strip().splitlines()) == 1, err


def test_missing_dask_says_how_to_install(capsys, monkeypatch):
    import builtins

    real = builtins.__import__

    def no_distributed(name, *a, **k):
        if name == "distributed" or name.startswith("distributed."):
            raise ImportError(name)
        return real(name, *a, **k)

    monkeypatch.setattr(builtins, "__import__", no_distributed)
    assert main(["uncertainty", *SIGMA, "--dask", "tcp://127.0.0.1:8786"]) == 2
    assert 'pip install ".[dask]"' in capsys.readouterr().err


def _write_cov(tmp_path, cov, name="fit.toml"):
    rows = ",\n".join("[" + ", ".join(repr(float(x)) for x in r) + "]" for r in cov)
    p = tmp_path / name
    p.write_text(f"[tissue]\nE1_kPa = 40.0\n[tissue.fit]\ncovariance_log = [\n{rows}\n]\n")
    return p


@pytest.mark.parametrize(
    ("cov", "why"),
    [
        (-np.eye(5), "semi-definite"),
        ([*np.eye(4).tolist(), [0, 0, 0, 0]], "5 x 5"),
        (np.diag([1, 1, 1, 1, 1.0]) + np.triu(np.ones((5, 5)), 1), "symmetric"),
    ],
)
def test_bad_covariance_file_exits_2(capsys, tmp_path, cov, why):
    p = _write_cov(tmp_path, np.asarray(cov, dtype=float).tolist() if why != "5 x 5" else cov)
    code = main(["uncertainty", "--set", f"tissue.uncertainty.covariance_from='{p}'"])
    err = capsys.readouterr().err
    assert code == 2 and "tissue.uncertainty.covariance_from" in err and why in err, err


def test_fit_output_feeds_covariance_from(capsys, tmp_path):
    import torque_model as tm

    t = tm.preset("zhou2013-sample2")
    f = np.geomspace(0.01, 50, 30)
    rng = np.random.default_rng(1)
    y = (
        tm.resistive_torque_Nm(np.radians(10), f, t, tm.PAPER_CAPSULE)
        * 1e3
        # 0.5 % noise: every variance of ln(parameter) within the reader's bound of 4
        * (1 + 0.005 * rng.standard_normal(30))
    )
    csv = tmp_path / "bench.csv"
    csv.write_text("frequency_hz,torque_mNm\n" + "".join(f"{a},{b}\n" for a, b in zip(f, y)))
    fit_toml = tmp_path / "fit.toml"
    assert main(["fit", str(csv), "-o", str(fit_toml)]) == 0
    capsys.readouterr()
    assert "covariance_log" in fit_toml.read_text()
    out = _json(
        capsys,
        [
            "uncertainty",
            str(fit_toml),
            "--set",
            f"tissue.uncertainty.covariance_from='{fit_toml}'",
            "--samples",
            "4096",
            "--sobol-samples",
            "0",
            "--json",
        ],
    )
    assert any(n.startswith("fit") for n in out["uncertain_inputs"])
    assert 0.0 <= out["stepout_probability"] <= 1.0


@pytest.mark.slow
def test_dask_local_cluster_gives_the_local_results(capsys, monkeypatch):
    distributed = pytest.importorskip("distributed")
    import spiralcap.sweep as sweep_module
    from spiralcap.design import load_design
    from spiralcap.sweep import parse_over, sweep

    argv = [
        "uncertainty",
        *SIGMA,
        "--set",
        "tissue.uncertainty.lumen_diameter_sigma_mm=0.3",
        "--samples",
        "70000",
        "--sobol-samples",
        "0",
        "--json",
    ]
    local = _json(capsys, argv)
    two = _json(capsys, [*argv, "--workers", "2"])
    # one IPOPT start for the cold points and the sizing's relaxation (of the default 4): the
    # subject is that each side gives the same numbers bit for bit, whatever it solved; the
    # chunks still start cold and go on warm, the sizing still ranks its neighbours (-1.7 s)
    design = load_design(None, ["optimize.starts=1"])
    axes = [parse_over("requirements.axial_load_mN=20:80:2")]
    sweep_local = sweep(design, axes, optimize=True)
    robust = design.with_values(
        {
            "optimize.objective": "margin_p05",
            "optimize.scenarios": 128,
            "tissue.uncertainty.scale_sigma_log": 0.3,
            "tissue.uncertainty.lumen_diameter_sigma_mm": 0.3,
            "requirements.min_spiral_turns": 0,
        }
    )
    # two chunks, each a cold point and a warm-started one: the chunk cut to 2 points (16 in
    # use; the chunks are cut in this process, the cluster runs them as given), 4 points, 8
    # solves on each side instead of 36 (18 points in chunks of 16 and 2)
    monkeypatch.setattr(sweep_module, "OPTIMIZE_CHUNK", 2)
    robust_axes = [parse_over("requirements.axial_load_mN=20:80:4")]
    robust_local = sweep(robust, robust_axes, optimize=True)
    from dataclasses import replace

    from optimize import FreeVariable, Sizing, optimize_design
    from spiralcap.assemble import build_model

    free = (FreeVariable("x.turns", 100, 800), FreeVariable("x.wire_diameter_m", 0.8e-3, 3e-3))
    sizing = replace(build_model(design), sizing=Sizing(free))
    sized_local = optimize_design(sizing)
    # one worker process: the tasks leave this process and come back all the same (pickled,
    # run in a fresh interpreter, the chunks as cut here), and the results cannot depend on
    # which worker ran which task; a second worker started a second interpreter and compiled
    # every NLP structure again (~3 s of CPU: 7.2 -> 4.3 s in the workers)
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0"
    ) as cluster:
        on_dask = _json(capsys, [*argv, "--dask", cluster.scheduler_address])
        sweep_dask = sweep(design, axes, optimize=True, dask=cluster.scheduler_address)
        robust_dask = sweep(robust, robust_axes, optimize=True, dask=cluster.scheduler_address)
        with distributed.Client(cluster) as client:  # a sizing's neighbours on the cluster
            sized_dask = optimize_design(sizing, executor=client)
        import math

        from spiralcap.core.errors import InputError
        from spiralcap.parallel import map_tasks

        with pytest.raises(InputError, match="--dask"):  # a failing task: one line, not a trace
            map_tasks(math.sqrt, [(-1.0,)], dask=cluster.scheduler_address)
    for other in (two, on_dask):
        for key in ("stepout_probability", "margin_percentiles_Nm", "margin_mean_Nm"):
            assert other[key] == local[key], f"{key}: bit-identical to the local run"
    for col, values in sweep_local.outputs.items():
        assert np.array_equal(values, sweep_dask.outputs[col]), f"sweep --optimize {col} on Dask"
    for col, values in robust_local.outputs.items():
        assert np.array_equal(
            values, robust_dask.outputs[col], equal_nan=values.dtype.kind == "f"
        ), f"robust sweep --optimize (margin_p05, working-set loop) {col} on Dask"
    assert replace(sized_dask, solve_time_s=0.0) == replace(sized_local, solve_time_s=0.0), (
        "a sizing with its neighbours on Dask (optimize_design(..., executor=client)) is the "
        "sizing here, bit for bit"
    )
