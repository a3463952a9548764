"""The coils leave spiralcap: a magpylib Collection and the field per ampere on a grid.

Independent source: magpylib 6 (Ortner et al. 2023, ``magpylib.current.Circle``), a thin-loop
model built only from what ``spiralcap coils --json`` prints (radius, separation, turns).
"""

from __future__ import annotations

import json
from pathlib import Path

import magpylib
import numpy as np
import pytest

from spiralcap.assemble import build_model
from spiralcap.cli import main
from spiralcap.design import load_design
from spiralcap.export import grid_columns, to_magpylib

AXES = "xyz"


@pytest.fixture(scope="module")
def grid_and_json(tmp_path_factory: pytest.TempPathFactory) -> tuple[dict, dict]:
    import contextlib
    import io

    tmp = tmp_path_factory.mktemp("grid")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["coils", "--json", "--field-grid", str(tmp / "g.csv")]) == 0
    payload = json.loads(out.getvalue())
    table = np.loadtxt(tmp / "g.csv", delimiter=",", skiprows=1)
    header = (tmp / "g.csv").read_text().split("\n", 1)[0].split(",")
    assert header == grid_columns()
    return {name: table[:, i] for i, name in enumerate(header)}, payload


def _thin_loop_pair(axis: dict) -> magpylib.Collection:
    """Two mean-turn loops of N ampere-turns per ampere at +-s/2 along the pair's axis."""
    from scipy.spatial.transform import Rotation

    turn = {
        "x": Rotation.from_euler("y", 90, degrees=True),
        "y": Rotation.from_euler("x", -90, degrees=True),
        "z": None,
    }[axis["axis"]]
    e = np.eye(3)[AXES.index(axis["axis"])]
    return magpylib.Collection(
        *(
            magpylib.current.Circle(
                current=float(axis["turns"]),
                diameter=2.0 * axis["radius_m"],
                position=sign * axis["separation_m"] * e,
                orientation=turn,
            )
            for sign in (-0.5, 0.5)
        )
    )


def test_grid_centre_field_per_ampere_matches_a_thin_loop_magpylib_model(grid_and_json) -> None:
    grid, payload = grid_and_json
    centre = np.flatnonzero(
        (np.abs(grid["x_m"]) < 1e-12)
        & (np.abs(grid["y_m"]) < 1e-12)
        & (np.abs(grid["z_m"]) < 1e-12)
    )
    assert centre.size == 1, "the default grid has the centre as a point"
    for k in AXES:
        ref = _thin_loop_pair(payload["axes"][k]).getB(np.zeros(3))
        ours = np.array([grid[f"B{c}_per_A_{k}_T_per_A"][centre[0]] for c in AXES])
        err = np.linalg.norm(ours - ref) / np.linalg.norm(ref)
        assert err < 2e-3, (
            f"{k} pair: centre field per ampere vs magpylib thin loops from `coils --json` "
            f"(mean turn, the pack's finite section differs), rel 2e-3; got {err:.2e}"
        )


def test_to_magpylib_reproduces_the_grid(grid_and_json) -> None:
    grid, _ = grid_and_json
    model = build_model(load_design(None))
    points = np.column_stack([grid["x_m"], grid["y_m"], grid["z_m"]])[::5]
    for k, currents in zip(AXES, np.eye(3), strict=True):
        collection = to_magpylib(model, currents_A=tuple(currents))
        assert len(collection.children) == 6, "six coils"
        ref = np.column_stack([grid[f"B{c}_per_A_{k}_T_per_A"][::5] for c in AXES])
        got = collection.getB(points)
        err = np.max(np.linalg.norm(got - ref, axis=1)) / np.max(np.linalg.norm(ref, axis=1))
        assert err < 1e-6, (
            f"{k} pair: magpylib Collection of spiralcap's filaments vs the grid, rel 1e-6 "
            f"(mu_0 CODATA 2022 vs 2018 differ by 1e-9); got {err:.2e}"
        )


def test_to_magpylib_scales_with_the_currents() -> None:
    model = build_model(load_design(None))
    p = np.array([[0.01, -0.02, 0.03]])
    one = [to_magpylib(model, currents_A=tuple(e)).getB(p) for e in np.eye(3)]
    mixed = to_magpylib(model, currents_A=(2.0, -1.5, 0.5)).getB(p)
    np.testing.assert_allclose(
        mixed,
        2.0 * one[0] - 1.5 * one[1] + 0.5 * one[2],
        rtol=1e-12,
        atol=1e-18,
        err_msg="superposition (linear field), rel 1e-12",
    )


def test_npz_holds_the_same_columns(tmp_path: Path, grid_and_json, capsys) -> None:
    grid, _ = grid_and_json
    assert main(["coils", "--field-grid", str(tmp_path / "g.npz")]) == 0
    capsys.readouterr()
    with np.load(tmp_path / "g.npz") as npz:
        assert sorted(npz.files) == sorted(grid_columns())
        for name in grid_columns():
            np.testing.assert_array_equal(npz[name], grid[name], err_msg=name)


@pytest.mark.parametrize(
    "argv",
    [
        ["--field-grid", "{tmp}/g.txt"],
        ["--field-grid", "{tmp}/g.csv", "--grid-step-mm", "0"],
        ["--field-grid", "{tmp}/g.csv", "--grid-step-mm", "0.01"],
        ["--grid-step-mm", "5"],
    ],
)
def test_bad_grid_arguments_exit_2_and_write_nothing(tmp_path: Path, argv, capsys) -> None:
    assert main(["coils", *(a.format(tmp=tmp_path) for a in argv)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1, (out, err)
    assert list(tmp_path.iterdir()) == []


def test_square_pairs_travel_as_closed_polylines() -> None:
    """Square pairs (coils.{ax}.shape = 'square'): each filament a closed magpylib Polyline;
    magpylib's Biot-Savart of straight segments against spiralcap's square-filament field."""
    sets = [f'coils.{ax}.shape="square"' for ax in AXES]
    sets += ["coils.x.side_m=0.9", "coils.y.side_m=0.7", "coils.z.side_m=0.5"]
    model = build_model(load_design(None, sets))
    points = np.random.default_rng(3).uniform(-0.15, 0.15, (60, 3))
    for k, currents in zip(AXES, np.eye(3), strict=True):
        collection = to_magpylib(model, currents_A=tuple(currents))
        got = collection.getB(points)
        ref = model.coils.field(points, currents)
        err = np.max(np.linalg.norm(got - ref, axis=1)) / np.max(np.linalg.norm(ref, axis=1))
        assert err < 1e-6, f"{k} square pair: magpylib Polylines vs spiralcap, rel 1e-6; {err:.2e}"
