"""Square coil pairs: fields against magpylib polylines, CasADi, inductance, resistance."""

from __future__ import annotations

import math

import casadi as ca
import magpylib
import numpy as np
import pytest
import scipy.constants

import coils
from coils.square import (
    SquareFilamentSet,
    parallel_filaments_mutual_H,
    square_mutual_inductance_H,
)
from coils.square_pair import grover_square_inductance_H, rectangle_gmd_m
from spiralcap.core.constants import MU0_T_m_per_A
from spiralcap.core.errors import InputError

#: magpylib uses scipy's mu_0 (CODATA 2022); we use CODATA 2018. Rescale to compare geometry.
MU0_RATIO = MU0_T_m_per_A / scipy.constants.mu_0
#: The x/y/z sides of the issue's nested square set, m.
SIDES_M = {"x": 0.95, "y": 0.78, "z": 0.62}


def square_vertices(axis: int, half_side: float, centre: float) -> np.ndarray:
    """The closed polyline of a square on ``axis``: counter-clockwise seen from +axis, sides
    along the other two axes (independent of coils.square's local-frame bookkeeping)."""
    corners = [(1, -1), (1, 1), (-1, 1), (-1, -1), (1, -1)]
    out = np.zeros((5, 3))
    u, v = (axis + 1) % 3, (axis + 2) % 3
    for i, (a, b) in enumerate(corners):
        out[i, u], out[i, v], out[i, axis] = a * half_side, b * half_side, centre
    return out


def magpylib_pair(pair: coils.SquarePair, current_A: float) -> magpylib.Collection:
    """The pair's two mean turns as magpylib Polylines carrying N I ampere-turns."""
    return magpylib.Collection(
        *(
            magpylib.current.Polyline(
                current=pair.turns * current_A,
                vertices=square_vertices(pair.axis_index, pair.half_side_m, sign * pair.spacing_m),
            )
            for sign in (-0.5, 0.5)
        )
    )


def one_filament(axis: int, half_side: float, centre: float) -> SquareFilamentSet:
    return SquareFilamentSet(
        axes=np.array([axis]),
        half_sides_m=np.array([half_side]),
        centres_m=np.array([centre]),
        turns=np.array([1.0]),
        columns=np.array([0]),
        column_axes=(axis,),
    )


def off_axis_grid(size: float) -> np.ndarray:
    """A 9 x 9 x 9 grid over [-size, size]^3 shifted off every axis and mid-plane."""
    t = np.linspace(-size, size, 9) + 0.0137 * size
    return np.stack(np.meshgrid(t, t, t, indexing="ij"), axis=-1).reshape(-1, 3)


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_square_filament_matches_magpylib_polyline(axis: int) -> None:
    half, centre = 0.31, -0.07
    fs = one_filament(axis, half, centre)
    points = off_axis_grid(0.8)
    ours = fs.field(points, np.array([[1.0]]))
    line = magpylib.current.Polyline(current=1.0, vertices=square_vertices(axis, half, centre))
    theirs = line.getB(points) * MU0_RATIO
    err = np.linalg.norm(ours - theirs, axis=1) / np.linalg.norm(theirs, axis=1)
    assert err.max() < 1e-9, (
        f"magpylib Polyline (Biot-Savart of straight segments), rel 1e-9 per point; max {err.max():.2e}"
    )
    G = fs.field_matrix(points)
    assert np.allclose(G[:, :, 0], ours, rtol=1e-13, atol=0.0), "field_matrix = field at 1 A"


def test_square_filament_centre_field_closed_form() -> None:
    for half in (0.1, 0.475, 2.0):
        b = one_filament(2, half, 0.0).field(np.zeros((1, 3)), np.array([[1.0]]))[0]
        expected = 2.0 * math.sqrt(2.0) * MU0_T_m_per_A / (math.pi * 2.0 * half)
        assert b[2] == pytest.approx(expected, rel=1e-14) and b[0] == b[1] == 0.0, (
            "centre of a square loop of side a: 2 sqrt(2) mu0 I / (pi a) (textbook), rel 1e-14"
        )


def test_square_field_numpy_and_casadi_agree() -> None:
    pair = coils.SquarePair(0.78, 120, "y", wire_diameter_m=1.5e-3, filaments=(2, 3))
    fs = pair.filament_set
    point = ca.SX.sym("p", 1, 3)
    current = ca.SX.sym("i", 1, 1)
    f = ca.Function("b", [point, current], [fs.field(point, current)])
    rng = np.random.default_rng(3)
    points = rng.uniform(-0.3, 0.3, (40, 3))
    ours = fs.field(points, np.array([[1.7]]))
    theirs = np.vstack([np.asarray(f(p[None, :], 1.7)) for p in points])
    scale = np.linalg.norm(ours, axis=1, keepdims=True)
    assert np.max(np.abs(ours - theirs) / scale) < 1e-12, "numpy vs CasADi paths, rel 1e-12"


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_issue_sides_centre_field_and_spacing(axis: str) -> None:
    side = SIDES_M[axis]
    pair = coils.SquarePair(side, 250, axis, wire_diameter_m=2.0e-3, filaments=(4, 4))
    assert pair.spacing_m == pytest.approx(0.5445 * side, rel=1e-15), (
        "default separation 0.5445 x side (square Helmholtz spacing, Firester 1966)"
    )
    theirs = float(magpylib_pair(pair, 1.0).getB(np.zeros(3))[pair.axis_index]) * MU0_RATIO
    ours = pair.centre_field_per_amp_T_per_A
    assert ours == pytest.approx(theirs, rel=1e-3), (
        "magpylib Polyline squares at the mean side, rel 1e-3 (pack of 4 x 4 filaments)"
    )
    thin = coils.SquarePair(side, 250, axis, wire_diameter_m=2.0e-3)
    s, a = thin.spacing_m, side
    closed = (
        4
        * MU0_T_m_per_A
        * 250
        * a
        * a
        / (math.pi * (a * a + s * s) * math.sqrt(a * a / 2 + s * s / 4))
    )
    assert thin.centre_field_per_amp_T_per_A == pytest.approx(closed, rel=1e-13), (
        "one filament per coil: four finite wires at sqrt(a^2 + s^2)/2 (Biot-Savart), rel 1e-13"
    )
    b = thin.field(np.zeros(3), 2.0)
    assert b[thin.axis_index] == pytest.approx(2.0 * closed, rel=1e-13), "field() at the centre"


def test_square_helmholtz_spacing_zeroes_the_second_derivative() -> None:
    """d²B_z/dz² at the centre vanishes at s = 0.5445 a (Firester 1966, four digits)."""
    from scipy.optimize import brentq

    def curvature(ratio: float) -> float:
        pair = coils.SquarePair(1.0, 10, "z", separation_m=ratio, wire_diameter_m=1e-3)
        h = 1e-3
        b = pair.field(np.array([[0.0, 0.0, -h], [0.0, 0.0, 0.0], [0.0, 0.0, h]]), 1.0)[:, 2]
        return (b[0] - 2 * b[1] + b[2]) / (h * h * b[1])

    root = brentq(curvature, 0.5, 0.6, xtol=1e-10)
    assert root == pytest.approx(coils.SQUARE_HELMHOLTZ_RATIO, abs=5e-5), (
        f"square Helmholtz spacing 0.5445 a (Firester 1966), abs 5e-5; root {root:.6f}"
    )


def test_mixed_system_field_is_the_sum_of_its_pairs() -> None:
    x = coils.SquarePair(0.95, 200, "x", wire_diameter_m=2e-3, filaments=(2, 2))
    y = coils.HelmholtzPair(0.30, 150, "y", wire_diameter_m=2e-3, filaments=(2, 2))
    z = coils.SquarePair(0.62, 180, "z", wire_diameter_m=2e-3)
    system = coils.ThreeAxisHelmholtz(x, y, z)
    points = off_axis_grid(0.2)
    currents = np.array([1.3, -0.4, 2.2])
    total = system.field(points, currents)
    parts = sum(p.field(points, i) for p, i in zip(system.pairs, currents, strict=True))
    assert np.allclose(total, parts, rtol=1e-13, atol=1e-20), "superposition of the pairs"
    G = system.field_matrix(points)
    assert np.allclose(G @ currents, total, rtol=1e-13, atol=1e-20), "B = G(p) I"
    f = system.casadi_field_function()
    casadi = np.vstack([np.asarray(f(p, currents)).ravel() for p in points[:50]])
    assert np.max(np.abs(casadi - total[:50])) < 1e-12 * np.abs(total).max(), (
        "numpy vs CasADi field of a mixed set, 1e-12"
    )
    gains = system.centre_gains_T_per_A
    assert gains[0] == x.centre_field_per_amp_T_per_A and gains[1] == y.centre_field_per_amp_T_per_A


# --- electrical -----------------------------------------------------------------------------


def _segments(half: float, z: float) -> list[tuple[np.ndarray, np.ndarray]]:
    v = square_vertices(2, half, z)
    return [(v[i], v[i + 1]) for i in range(4)]


def neumann_numeric_H(h1: float, h2: float, z: float, nodes: int = 160) -> float:
    """Neumann's double line integral of two squares by Gauss-Legendre on every pair of sides."""
    x, w = np.polynomial.legendre.leggauss(nodes)
    t, wt = 0.5 * (x + 1.0), 0.5 * w
    total = 0.0
    for a0, a1 in _segments(h1, 0.0):
        pa = a0 + t[:, None] * (a1 - a0)
        for b0, b1 in _segments(h2, z):
            dot = float(np.dot(a1 - a0, b1 - b0))
            if dot == 0.0:
                continue
            pb = b0 + t[:, None] * (b1 - b0)
            r = np.linalg.norm(pa[:, None, :] - pb[None, :, :], axis=2)
            total += dot * float(wt @ (1.0 / r) @ wt)
    return MU0_T_m_per_A / (4 * math.pi) * total


@pytest.mark.parametrize(("h1", "h2", "z"), [(0.3, 0.3, 0.3), (0.475, 0.39, 0.05), (0.2, 0.5, 0.4)])
def test_square_mutual_inductance_vs_numeric_neumann(h1: float, h2: float, z: float) -> None:
    assert square_mutual_inductance_H(h1, h2, z) == pytest.approx(
        neumann_numeric_H(h1, h2, z), rel=1e-8
    ), "Neumann double integral by Gauss-Legendre quadrature, rel 1e-8"


def test_parallel_filaments_equal_and_aligned() -> None:
    """Aligned equal filaments: (mu0/2pi)[l asinh(l/d) - sqrt(l^2 + d^2) + d] (Grover eq. 3.1)."""
    length, d = 0.8, 0.05
    expected = (
        MU0_T_m_per_A
        / (2 * math.pi)
        * (length * math.asinh(length / d) - math.hypot(length, d) + d)
    )
    assert parallel_filaments_mutual_H(length, length, 0.0, d) == pytest.approx(
        expected, rel=1e-13
    ), "Grover (1946) eq. 3.1, rel 1e-13"


def _thin_grover(a: float, g: float) -> float:
    """Grover's square of side a, GMD g << a: (2 mu0 a/pi)[ln(a/g) - 0.774 + g/a] (1946, ch. 5)."""
    return 2 * MU0_T_m_per_A * a / math.pi * (math.log(a / g) - 0.774 + g / a)


def volume_self_inductance_H(side: float, width: float, depth: float, turns: int, n: int) -> float:
    """N^2 x the mean over n x n cells of the square-to-square mutual inductance; a cell with
    itself: Grover's thin square with the cell's GMD. Converges as 1/n^2."""
    xr = (np.arange(n) + 0.5) * depth / n - depth / 2
    xz = (np.arange(n) + 0.5) * width / n - width / 2
    h, z = (v.ravel() for v in np.meshgrid(side / 2 + xr, xz, indexing="ij"))
    same = np.eye(h.size, dtype=bool)
    m = square_mutual_inductance_H(
        h[:, None], h[None, :], np.where(same, 1.0, z[:, None] - z[None, :])
    )
    g = rectangle_gmd_m(width / n, depth / n)
    own = np.array([_thin_grover(2 * hi, g) for hi in h])
    return turns**2 * (np.where(same, 0.0, m).sum() + own.sum()) / h.size**2


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_self_inductance_grover_and_volume_integral(axis: str) -> None:
    side = SIDES_M[axis]
    pair = coils.SquarePair(side, 300, axis, wire_diameter_m=2.0e-3)
    w, d = pair.winding_pack_width_m, pair.winding_pack_depth_m
    g = rectangle_gmd_m(w, d)
    assert g == pytest.approx(0.447049 * w, rel=1e-6), "Maxwell's GMD of a square, 0.447049 a"
    grover = 300**2 * _thin_grover(side, g)
    assert pair.self_inductance_H == pytest.approx(grover, rel=0.03), (
        "Grover's square-loop formula with the pack's GMD (1946, ch. 5), rel 3 %"
    )
    assert pair.self_inductance_H == pytest.approx(grover, rel=1.5e-3), "(and in fact 1.5e-3)"
    coarse, fine = (volume_self_inductance_H(side, w, d, 300, n) for n in (12, 24))
    reference = (4 * fine - coarse) / 3
    assert pair.self_inductance_H == pytest.approx(reference, rel=0.03), (
        "filament-sum volume integral of the exact square-to-square M (Richardson 12/24), rel 3 %"
    )
    assert pair.self_inductance_H == pytest.approx(reference, rel=1e-4), "(and in fact rel 1e-4)"
    # the pair's mutual inductance: the same exact M over both packs, thin-filament limit
    thin = 300**2 * square_mutual_inductance_H(side / 2, side / 2, pair.spacing_m)
    assert pair.mutual_inductance_H == pytest.approx(thin, rel=5e-3), (
        "pack-averaged M within 0.5 % of the mean turns' M (pack << spacing)"
    )
    assert pair.series_inductance_H == 2 * pair.self_inductance_H + 2 * pair.mutual_inductance_H


@pytest.mark.parametrize("aspect", [0.3, 3.0])
def test_self_inductance_of_flat_and_tall_packs_vs_volume_integral(aspect: float) -> None:
    """Away from a square section Grover's GMD form (every filament at side a) drifts by up to
    2.5e-3; the section average of the exact M stays within 1e-4 of the volume integral."""
    pair = coils.SquarePair(0.62, 300, "z", wire_diameter_m=2.0e-3, pack_aspect=aspect)
    w, d = pair.winding_pack_width_m, pair.winding_pack_depth_m
    coarse, fine = (volume_self_inductance_H(0.62, w, d, 300, n) for n in (12, 24))
    reference = (4 * fine - coarse) / 3
    assert pair.self_inductance_H == pytest.approx(reference, rel=1e-4), (
        f"filament-sum volume integral (Richardson 12/24), rel 1e-4 at aspect {aspect}"
    )
    grover = 300**2 * grover_square_inductance_H(0.62, rectangle_gmd_m(w, d))
    assert pair.self_inductance_H == pytest.approx(grover, rel=0.03), "Grover with the GMD, 3 %"


def test_grover_square_exact_form_and_numpy_casadi() -> None:
    a, g = 0.8, 0.01
    exact = grover_square_inductance_H(a, g)
    assert exact == pytest.approx(_thin_grover(a, g), rel=5e-4), (
        "finite-g form -> Grover's (2 mu0 a/pi)[ln(a/g) - 0.774 + g/a] as g/a -> 0, rel 5e-4"
    )
    sym = ca.SX.sym("a")
    f = ca.Function("L", [sym], [grover_square_inductance_H(sym, rectangle_gmd_m(0.02, 0.03))])
    value = float(f(a))
    assert value == pytest.approx(
        grover_square_inductance_H(a, rectangle_gmd_m(0.02, 0.03)), rel=1e-12
    ), "numpy vs CasADi, rel 1e-12"


def test_resistance_length_and_copper_mass_by_hand() -> None:
    from spiralcap.core.constants import COPPER_DENSITY_kg_m3, COPPER_RESISTIVITY_20C_ohm_m

    pair = coils.SquarePair(0.95, 321, "x", wire_diameter_m=1.8e-3)
    section = math.pi * 1.8e-3**2 / 4
    assert pair.wire_length_m == pytest.approx(2 * 4 * 0.95 * 321, rel=1e-15), "2 x 4 x side x N"
    assert pair.resistance_ohm(20.0) == pytest.approx(
        COPPER_RESISTIVITY_20C_ohm_m * 2 * 4 * 0.95 * 321 / section, rel=1e-14
    ), "rho l / A at 20 C (IEC 60028), rel 1e-14"
    mass = COPPER_DENSITY_kg_m3 * pair.wire_length_m * pair.wire_area_m2
    assert mass == pytest.approx(COPPER_DENSITY_kg_m3 * 2 * 4 * 0.95 * 321 * section, rel=0.015), (
        "density x 2 x 4 x side x turns x wire section, rel 1.5 %"
    )


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({"side_m": -1.0, "turns": 10}, "side_m"),
        ({"side_m": 0.5, "turns": 0}, "turns"),
        ({"side_m": 0.5, "turns": 10, "axis": "w"}, "axis"),
        ({"side_m": 0.05, "turns": 2000, "wire_diameter_m": 3e-3}, "wire_diameter_m"),
        (
            {"side_m": 0.5, "turns": 400, "separation_m": 0.02, "wire_diameter_m": 3e-3},
            "separation_m",
        ),
        ({"side_m": 0.5, "turns": 10, "pack_aspect": 9.0}, "pack_aspect"),
    ],
)
def test_square_pair_rejects_bad_parameters(kwargs: dict, key: str) -> None:
    with pytest.raises(InputError) as err:
        coils.SquarePair(**kwargs)
    assert err.value.key == key, str(err.value)


def test_square_pair_uniform_region_is_not_taken_as_axisymmetric() -> None:
    """The ±1 % sphere of a square pair alone, checked on random points just inside and on
    the limiting ray just outside (a square pair has no axial symmetry: its sphere is found on
    the full ray lattice)."""
    pair = coils.SquarePair(0.78, 100, "y", wire_diameter_m=1e-3)
    region = coils.uniform_region(pair, 0.01)
    assert 0.0 < region.radius_m < pair.radius_m
    rng = np.random.default_rng(11)
    dirs = rng.normal(size=(20000, 3))
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    inside = coils.uniformity(pair, 0.999 * region.radius_m * dirs)
    assert np.max(np.abs(inside)) <= 0.01, "every random point 0.1 % inside is within 1 %"
    out = coils.uniformity(pair, 1.001 * region.radius_m * region.limiting_ray[None, :])
    assert abs(out[0]) > 0.01, "just outside along the limiting ray it is not"
    # the field is not axisymmetric: the deviation differs between the side and corner planes
    r = region.radius_m
    side_plane = coils.uniformity(pair, np.array([[r, 0.0, 0.0]]))[0]
    corner_plane = coils.uniformity(pair, np.array([[r / np.sqrt(2), 0.0, r / np.sqrt(2)]]))[0]
    assert abs(side_plane - corner_plane) > 1e-4, "square, not round"
