"""``spiralcap waveforms``: currents, voltages and field for a heading sequence (issue 10)."""

import json
from pathlib import Path

import numpy as np
import pytest

from spiralcap.assemble import build_coils
from spiralcap.cli import main
from spiralcap.design import load_design

HEADINGS = ["--heading", "1,0,0", "--heading", "0,1,0", "--heading", "0.6,0,0.8"]


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("wf")
    csv = tmp / "w.csv"
    argv = ["waveforms", *HEADINGS, "--dwell-s", "2", "--ramp-s", "0.5", "--csv", str(csv)]
    status = main([*argv, "--json"])
    return status, csv


def test_sequence_within_limits_and_csv_columns(run, capsys):
    status, csv = run
    assert status == 0
    header = csv.read_text().splitlines()[0]
    assert header == (
        "t_s,heading_index,current_x_A,current_y_A,current_z_A,voltage_x_V,voltage_y_V,"
        "voltage_z_V,field_x_T,field_y_T,field_z_T"
    )


def test_currents_rebuild_a_constant_field_in_each_plane(run):
    _, csv = run
    d = np.loadtxt(csv, delimiter=",", skiprows=1)
    t, idx, cur, field = d[:, 0], d[:, 1].astype(int), d[:, 2:5], d[:, 8:11]
    system = build_coils(load_design(None))
    # field of the coils themselves at the centre (filament sum), independent of G^-1
    g = np.array([system.field(np.zeros((1, 3)), np.eye(3)[k])[0] for k in range(3)]).T
    rebuilt = cur @ g.T
    b0 = np.linalg.norm(rebuilt, axis=1)
    assert np.allclose(b0, b0[0], rtol=1e-3), "issue 10: constant amplitude B0 (1e-3)"
    assert np.allclose(rebuilt, field, rtol=0, atol=1e-7 * b0[0]), (
        "CSV field = G I (9 digits in the CSV)"
    )
    heads = np.array([[1, 0, 0], [0, 1, 0], [0.6, 0, 0.8]])
    for i, n in enumerate(heads):
        held = (idx == i) & (t - 2.0 * i > 0.5)  # after the change of plane
        assert np.all(np.abs(rebuilt[held] @ n) < 1e-7 * b0[0]), (
            "field in the plane normal to the heading during the dwell"
        )
        b = rebuilt[held]
        turn = np.cross(b[:-1], b[1:]) @ n
        assert np.all(turn > 0), "turning right-handedly about the heading"


def test_voltage_is_r_i_plus_l_di_dt_by_finite_differences(run, capsys):
    _, csv = run
    d = np.loadtxt(csv, delimiter=",", skiprows=1)
    t, cur, volt = d[:, 0], d[:, 2:5], d[:, 5:8]
    # R (mean winding temperature at the operating point) and L as the command reports them
    argv = ["waveforms", *HEADINGS, "--dwell-s", "2", "--ramp-s", "0.5", "--json"]
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    r = np.array([out["resistance_ohm"][a] for a in "xyz"])
    ind = np.array([out["inductance_H"][a] for a in "xyz"])
    didt = np.gradient(cur, t, axis=0, edge_order=2)
    expected = cur * r + didt * ind
    scale = np.max(np.abs(volt), axis=0)
    assert np.all(np.abs(volt - expected) <= 0.02 * scale), (
        "issue 10: each voltage = R i + L di/dt with finite-difference di/dt (2 %)"
    )


def test_fast_switch_exceeds_the_voltage_and_exits_3_after_writing(tmp_path, capsys):
    csv = tmp_path / "fast.csv"
    argv = ["waveforms", "--heading", "1,0,0", "--heading", "0,1,0", "--dwell-s", "1"]
    status = main([*argv, "--ramp-s", "0.05", "--csv", str(csv)])
    err = capsys.readouterr().err
    assert status == 3, err
    assert csv.exists() and "voltage of the x pair" in err and "t = " in err, err


@pytest.mark.parametrize(
    ("extra", "option"),
    [
        (["--heading", "0,0,0", "--dwell-s", "1"], "--heading"),
        (["--heading", "1,0,0", "--dwell-s", "0"], "--dwell-s"),
        (["--heading", "1,0,0", "--dwell-s", "1", "--ramp-s", "2"], "--ramp-s"),
        (["--heading", "x,0,0", "--dwell-s", "1"], "--heading"),
    ],
)
def test_bad_input_exits_2_naming_the_option(tmp_path: Path, capsys, extra, option):
    csv = tmp_path / "never.csv"
    assert main(["waveforms", *extra, "--csv", str(csv)]) == 2
    err = capsys.readouterr().err
    assert option in err and err.count("\n") == 1, err
    assert not csv.exists(), "nothing written on bad input"
