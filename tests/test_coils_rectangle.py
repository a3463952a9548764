"""Rectangular coil pairs (issue 38): field against magpylib, the zero-curvature spacing, the
inductances against numeric Neumann integrals, numpy against CasADi, the a = b case against the
square pair, the solids and cooling, and the CLI (evaluate, a sizing with free z turns)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

import coils
from coils.clearance import frame_distance_m, frame_signed_distance
from coils.rectangle import (
    grover_rectangle_inductance_H,
    helmholtz_spacing_ratio,
    rectangle_axial_field_T_per_A,
    rectangle_field_local,
    rectangle_mutual_inductance_H,
)
from coils.square_pair import rectangle_gmd_m
from coils.viewfactors import view_factors
from spiralcap import cli
from spiralcap.core.constants import MU0_T_m_per_A

ROOT = Path(__file__).resolve().parents[1]
SQUARE_EXAMPLE = ROOT / "examples" / "square_coils.toml"
RECT_EXAMPLE = ROOT / "examples" / "rectangle_coils.toml"
SIDES = (0.80, 0.62)  # the rectangle


def _pair(axis: str = "z", sides=SIDES, **kw) -> coils.RectanglePair:
    return coils.RectanglePair(sides_m=sides, turns=300, axis=axis, wire_diameter_m=2.36e-3, **kw)


def _global_vertices(axis: int, a: float, b: float, c: float) -> np.ndarray:
    """The mean turn's corners in global coordinates, built here from the issue's words: side a
    along the next axis in cyclic order, b along the one after, counter-clockwise about +axis
    (the cyclic frame (u, v, w) is right-handed)."""
    u, v = (axis + 1) % 3, (axis + 2) % 3
    out = np.zeros((5, 3))
    for i, (su, sv) in enumerate([(1, -1), (1, 1), (-1, 1), (-1, -1), (1, -1)]):
        out[i, u], out[i, v], out[i, axis] = su * a / 2, sv * b / 2, c
    return out


def _magpylib_pair(pair: coils.RectanglePair, current_A: float):
    import magpylib

    a, b = pair.sides_m
    half = pair.separation_m / 2
    return magpylib.Collection(
        *(
            magpylib.current.Polyline(
                current=pair.turns * current_A,
                vertices=_global_vertices(pair.axis_index, a, b, c),
            )
            for c in (-half, half)
        )
    )


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_field_grid_matches_magpylib_rectangles(axis: str) -> None:
    pair = _pair(axis)
    grid = np.linspace(-0.25, 0.25, 7)
    points = np.stack(np.meshgrid(grid, grid, grid, indexing="ij"), axis=-1).reshape(-1, 3)
    ours = pair.field(points, 2.0)
    ref = _magpylib_pair(pair, 2.0).getB(points)
    centre = np.linalg.norm(pair.field(np.zeros(3), 2.0))
    # magpylib uses CODATA 2022 mu_0, spiralcap CODATA 2018: 1e-9 apart
    assert np.max(np.abs(ours - ref)) <= 1e-6 * centre, (
        "magpylib.current.Polyline rectangles (N turns at the mean turn) on a 7^3 grid, "
        "within 1e-6 of the centre field"
    )
    assert ref[len(points) // 2, pair.axis_index] > 0, "field along +axis at the centre"


def test_rectangle_centre_field_closed_form() -> None:
    a, b = SIDES
    expected = 2 * MU0_T_m_per_A * math.hypot(a, b) / (math.pi * a * b)
    got = rectangle_field_local(a / 2, b / 2, 0.0, 0.0, 0.0)[2]
    assert got == pytest.approx(expected, rel=1e-14), (
        "centre of a rectangle loop: 2 mu0 sqrt(a^2 + b^2) / (pi a b) per ampere, 1e-14"
    )
    z = 0.17
    on_axis = rectangle_field_local(a / 2, b / 2, 0.0, 0.0, z)[2]
    assert rectangle_axial_field_T_per_A(a, b, z) == pytest.approx(on_axis, rel=1e-13), (
        "the on-axis closed form = the four segments on the axis, 1e-13"
    )


@pytest.mark.parametrize("sides", [SIDES, (0.62, 0.80), (0.5, 1.2)])
def test_default_spacing_flattens_the_centre_field(sides) -> None:
    """d²B/dz² at the centre by central differences of magpylib's field: ~0 at the default
    spacing, and clearly not at 10 % more or less."""
    pair = _pair("z", sides)
    a = sides[0]

    def second_difference(p: coils.RectanglePair, step: float) -> float:
        pts = np.array([[0, 0, -step], [0, 0, 0], [0, 0, step]])
        bz = _magpylib_pair(p, 1.0).getB(pts)[:, 2]
        return float((bz[0] - 2 * bz[1] + bz[2]) / step**2 * a**2 / bz[1])

    def curvature(p: coils.RectanglePair) -> float:  # Richardson: the h^2 (z^4) term removed
        return (4 * second_difference(p, 0.01 * a) - second_difference(p, 0.02 * a)) / 3

    flat = curvature(pair)
    off = [curvature(_pair("z", sides, separation_m=pair.separation_m * f)) for f in (0.9, 1.1)]
    assert abs(flat) < 1e-5, (
        f"normalised d2B/dz2 a^2 / B at the default spacing {flat:.2e}: below 1e-5 "
        "(magpylib field, central differences at 1 and 2 % of a, Richardson)"
    )
    assert min(abs(c) for c in off) > 100 * abs(flat), "+-10 % spacing curves the field 100x more"


def test_square_case_of_the_spacing_and_the_pair() -> None:
    assert helmholtz_spacing_ratio(0.7, 0.7) == pytest.approx(0.5445, abs=1e-4), (
        "a = b: Firester's square Helmholtz spacing 0.5445 a (1966), to 1e-4"
    )
    sq = coils.SquarePair(0.62, 300, "y", wire_diameter_m=2.36e-3, filaments=(3, 2))
    rect = coils.RectanglePair(
        sides_m=(0.62, 0.62),
        turns=300,
        axis="y",
        wire_diameter_m=2.36e-3,
        separation_m=sq.separation_m,
        filaments=(3, 2),
    )
    pts = np.random.default_rng(3).uniform(-0.3, 0.3, (50, 3))
    assert np.array_equal(rect.field(pts, 1.5), sq.field(pts, 1.5)), (
        "a = b rectangle: the square's field bit for bit (the same segment formula)"
    )
    assert rect.mutual_inductance_H == pytest.approx(sq.mutual_inductance_H, rel=1e-13)
    assert rect.mean_turn_length_m == sq.mean_turn_length_m
    assert rect.self_inductance_H == sq.self_inductance_H, (
        "a = b: the square's pack self inductance, the same section average exactly"
    )
    gmd = rectangle_gmd_m(sq.winding_pack_width_m, sq.winding_pack_depth_m)
    assert rect.self_inductance_H == pytest.approx(
        300**2 * coils.square_pair.grover_square_inductance_H(0.62, gmd), rel=2.5e-3
    ), "a = b: Grover's square with the GMD (every filament at side a), within its 2.5e-3"


# --- inductance -------------------------------------------------------------------------------


def neumann_numeric_H(a1, b1, a2, b2, z, panels=48, nodes=16) -> float:
    """Neumann's double line integral of two coaxial rectangles (corners built here), by
    panelled Gauss-Legendre quadrature on every pair of parallel sides."""
    x, w = np.polynomial.legendre.leggauss(nodes)
    t = ((np.arange(panels)[:, None] + 0.5 * (x[None, :] + 1)) / panels).ravel()
    wt = np.tile(0.5 * w, panels) / panels
    va, vb = _global_vertices(2, a1, b1, 0.0), _global_vertices(2, a2, b2, z)
    total = 0.0
    for i in range(4):
        pa = va[i] + t[:, None] * (va[i + 1] - va[i])
        for j in range(4):
            dot = float(np.dot(va[i + 1] - va[i], vb[j + 1] - vb[j]))
            if dot == 0.0:
                continue
            pb = vb[j] + t[:, None] * (vb[j + 1] - vb[j])
            r = np.sqrt(((pa[:, None, :] - pb[None, :, :]) ** 2).sum(-1))
            total += dot * float(wt @ (1.0 / r) @ wt)
    return MU0_T_m_per_A / (4 * math.pi) * total


def test_mutual_inductance_vs_numeric_neumann() -> None:
    exact = rectangle_mutual_inductance_H(0.31, 0.4, 0.25, 0.35, 0.2)
    assert exact == pytest.approx(neumann_numeric_H(0.62, 0.8, 0.5, 0.7, 0.2, 4, 16), rel=1e-9), (
        "Neumann double integral by Gauss-Legendre, rel 1e-9"
    )


def _thin_grover(a: float, b: float, g: float) -> float:
    """Grover's rectangle (1946, ch. 5; DESIGN.md 4.1) with a GMD g in place of the wire radius
    (the (a + b)/4 term dropped), typed here from the formula."""
    d = math.hypot(a, b)
    return (MU0_T_m_per_A / math.pi) * (
        a * math.log(2 * a / g)
        + b * math.log(2 * b / g)
        + 2 * d
        - a * math.asinh(a / b)
        - b * math.asinh(b / a)
        - 2 * (a + b)
    )


def test_grover_rectangle_vs_numeric_neumann() -> None:
    """A conductor of GMD g: its self inductance is the mutual inductance of two filaments g
    apart, here the rectangle and its copy g along the axis, integrated numerically."""
    a, b = 0.62, 0.80
    errors = []
    for g in (0.01 * a, 0.003 * a):
        numeric = neumann_numeric_H(a, b, a, b, g)
        if g == 0.01 * a:  # panels of 2 g: the quadrature resolves the near-singular kernel
            assert grover_rectangle_inductance_H(a, b, g) == pytest.approx(numeric, rel=2e-5), (
                f"the side-by-side Neumann form with GMD g = {g:.3g} m vs the numeric double "
                "integral, rel 2e-5 (O(g^2): the opposite sides sit sqrt(b^2 + g^2) apart there)"
            )
        errors.append(abs(_thin_grover(a, b, g) / numeric - 1))
    assert errors[0] < 3e-3 and errors[1] < 6e-4, (
        f"Grover's thin rectangle vs the numeric integral: {errors} (O(g/a), Grover 1946)"
    )
    assert errors[1] < 0.5 * errors[0], "and its error shrinks with g/a"


def volume_self_inductance_H(a, b, width, depth, turns, n) -> float:
    """N^2 x the mean over n x n cells of the exact rectangle-to-rectangle M (a cell with
    itself: Grover's thin rectangle with the cell's GMD); converges as 1/n^2."""
    xr = (np.arange(n) + 0.5) * depth / n - depth / 2
    xz = (np.arange(n) + 0.5) * width / n - width / 2
    dr, z = (v.ravel() for v in np.meshgrid(xr, xz, indexing="ij"))
    same = np.eye(dr.size, dtype=bool)
    hu, hv = a / 2 + dr, b / 2 + dr
    m = rectangle_mutual_inductance_H(
        hu[:, None], hv[:, None], hu[None, :], hv[None, :], np.where(same, 1.0, z[:, None] - z)
    )
    g = rectangle_gmd_m(width / n, depth / n)
    own = np.array([_thin_grover(2 * u, 2 * v, g) for u, v in zip(hu, hv)])
    return turns**2 * (np.where(same, 0.0, m).sum() + own.sum()) / dr.size**2


@pytest.mark.parametrize(
    ("sides", "aspect"), [(SIDES, 1.0), (SIDES, 0.4), ((0.5, 1.2), 3.0), ((1.2, 0.45), 0.3)]
)
def test_pack_self_inductance_vs_volume_integral(sides, aspect: float) -> None:
    pair = _pair("z", sides, pack_aspect=aspect)
    w, d = pair.winding_pack_width_m, pair.winding_pack_depth_m
    coarse, fine = (volume_self_inductance_H(*sides, w, d, 300, n) for n in (12, 24))
    reference = (4 * fine - coarse) / 3
    assert pair.self_inductance_H == pytest.approx(reference, rel=1e-4), (
        "the section average of the exact rectangle-to-rectangle M (GMD for the singular part) "
        f"vs the filament-sum volume integral (Richardson 12/24), rel 1e-4 at sides {sides}, "
        f"aspect {aspect}"
    )
    grover = 300**2 * grover_rectangle_inductance_H(*sides, rectangle_gmd_m(w, d))
    assert grover == pytest.approx(reference, rel=2.5e-3), (
        "Grover's rectangle with the pack's GMD (every filament at the mean turn's sides) vs "
        f"the volume integral, within its known 2.5e-3 at aspect {aspect}"
    )


def test_pack_mutual_inductance_near_the_mean_turns() -> None:
    pair = _pair("z")
    thin = 300**2 * rectangle_mutual_inductance_H(0.4, 0.31, 0.4, 0.31, pair.spacing_m)
    assert pair.mutual_inductance_H == pytest.approx(thin, rel=5e-3), (
        "pack-averaged M within 0.5 % of the mean turns' M (pack << spacing)"
    )


def test_numpy_and_casadi_agree() -> None:
    args = (0.4, 0.31, 0.05, -0.07, 0.12)
    syms = [ca.SX.sym(f"s{i}") for i in range(5)]
    f = ca.Function("f", syms, list(rectangle_field_local(*syms)))
    for got, want in zip(f(*args), rectangle_field_local(*args), strict=True):
        assert float(got) == pytest.approx(float(want), rel=1e-12, abs=1e-20), "field, 1e-12"
    a, n, s, w, d = (ca.SX.sym(k) for k in "answd")
    key = (coils.RectanglePair, 0.62 / 0.80)
    sym = coils.RectanglePair.terms(coils.RectanglePair.scaled_sizes(key, a), n, s, w, d)
    vals = (0.80, 300.0, 0.38, 0.04, 0.05)
    num = coils.RectanglePair.terms((0.80, 0.62), *vals[1:])
    for k, v in sym.items():
        got = float(ca.Function("g", [a, n, s, w, d], [v])(*vals))
        assert got == pytest.approx(float(num[k]), rel=1e-12), f"{k}: numpy and CasADi, 1e-12"
    system = coils.ThreeAxisHelmholtz(
        coils.SquarePair(0.95, 400, "x", wire_diameter_m=3e-3),
        _pair("y", (0.62, 0.5)),
        _pair("z"),
    )
    pts = np.random.default_rng(1).uniform(-0.2, 0.2, (20, 3))
    cur = np.array([1.0, -2.0, 0.5])
    fn = system.casadi_field_function()
    cas = np.vstack([np.asarray(fn(p, cur)).ravel() for p in pts])
    assert np.max(np.abs(cas - system.field(pts, cur))) < 1e-12 * np.abs(cas).max(), (
        "mixed square/rectangle set: numpy vs CasADi field, 1e-12"
    )


# --- solids, cooling -------------------------------------------------------------------------


def test_frames_as_boxes_and_their_distance() -> None:
    """A rectangular frame's signed distance and frame-to-frame distance against dense samples
    of its four bars built here from the sides."""
    y = _pair("y", (0.9, 0.7))
    z = _pair("z", (0.6, 0.75))
    fy, fz = y.pack_solids()[1], z.pack_solids()[1]
    a, b = 0.9, 0.7  # y pair: a along z, b along x
    h = y.winding_pack_depth_m
    pts = np.array([[b / 2, fy.centre_m, 0.0], [0.0, fy.centre_m, a / 2], [0, fy.centre_m, 0]])
    sd = frame_signed_distance(fy, pts)
    assert sd[0] == pytest.approx(-h / 2) and sd[1] == pytest.approx(-h / 2), (
        "the mean turn lies mid-pack: b/2 along x, a/2 along z"
    )
    assert sd[2] == pytest.approx(min(a, b) / 2 - h / 2), "the centre: half the shorter side"
    rng = np.random.default_rng(0)
    samples = rng.uniform(-0.6, 0.6, (40000, 3))
    inside = samples[frame_signed_distance(fz, samples) <= 0]
    nearest = np.min(np.maximum(frame_signed_distance(fy, inside), 0.0))
    exact = frame_distance_m(fy, fz)
    assert exact <= nearest + 1e-12 and nearest - exact < 0.03, (
        "frame-to-frame distance: no sampled point of one frame is nearer the other (samples "
        "within 3 cm)"
    )
    assert fy.volume_m3 == pytest.approx(2 * (a + b) * y.winding_pack_width_m * h, rel=1e-12)


def test_cooling_and_view_factors_of_a_rectangle() -> None:
    from coils.thermal import _with_vertical_bars

    x = _pair("x", (0.62, 0.8))
    assert x.vertical_bar_height_m == 0.8, "x pair: its second side (along z) stands vertical"
    assert _pair("y", (0.62, 0.8)).vertical_bar_height_m == 0.62, "y pair: its first side"
    assert _pair("z").vertical_bar_height_m == 0.0, "a z frame lies flat"
    from coils.thermal import WindingPack

    pack = WindingPack(0.04, 0.04, x.turn_radius_m, 0.7, 0.5, 5.0, 0.9, vertical_bar_height_m=0.8)
    h_ring = 3.0
    h = _with_vertical_bars(pack, h_ring, 60.0, 25.0)
    h_bar = _with_vertical_bars(
        WindingPack(0.04, 0.04, 0.8 / math.pi, 0.7, 0.5, 5.0, 0.9, vertical_bar_height_m=0.8),
        0.0,
        60.0,
        25.0,
    )
    assert h == pytest.approx(h_ring + 0.8 / (0.62 + 0.8) * (h_bar - h_ring), rel=1e-12), (
        "the vertical bars weigh by their share of the mean turn, b/(a + b)"
    )
    sq = coils.SquarePair(0.62, 300, "z", wire_diameter_m=2.36e-3)
    same = coils.RectanglePair(sides_m=(0.62, 0.62), turns=300, axis="z", wire_diameter_m=2.36e-3)
    others = [coils.SquarePair(0.95, 400, "x", wire_diameter_m=3e-3).view_pack()]
    others.append(coils.SquarePair(0.78, 350, "y", wire_diameter_m=2.5e-3).view_pack())
    vf_sq = view_factors([*others, sq.view_pack()], rays=2048)
    vf_rect = view_factors([*others, same.view_pack()], rays=2048)
    assert np.array_equal(vf_sq, vf_rect), "a = b rectangle: the square's view factors exactly"
    vf = view_factors([*others, _pair("z", (0.62, 0.8)).view_pack()], rays=2048)
    assert np.allclose(vf.sum(axis=1), 1.0), "each row sums to 1"


# --- the CLI ------------------------------------------------------------------------------------


def _rect_design(tmp_path: Path) -> Path:
    text = SQUARE_EXAMPLE.read_text().replace(
        '[coils.z]\nshape = "square"\nside_m = 0.62',
        '[coils.z]\nshape = "rectangle"\nsides_m = [0.62, 0.80]',
    )
    assert "sides_m = [0.62, 0.80]" in text
    path = tmp_path / "rect.toml"
    path.write_text(text)
    return path


def test_cli_evaluate_and_coils_json(tmp_path, capsys) -> None:
    import jsonschema

    design = str(_rect_design(tmp_path))
    assert cli.main(["evaluate", design]) == 0, "evaluate of the square example, z a rectangle"
    capsys.readouterr()
    assert cli.main(["coils", design, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    schema = json.loads((ROOT / "docs" / "json" / "coils.schema.json").read_text())
    jsonschema.validate(out, schema)
    z = out["axes"]["z"]
    assert z["shape"] == "rectangle" and z["sides_m"] == [0.62, 0.80], "the sides, as given"
    assert "side_m" not in z, "no square side on a rectangle"


def test_cli_bad_rectangle_keys(tmp_path, capsys) -> None:
    design = str(_rect_design(tmp_path))
    assert cli.main(["evaluate", design, "--set", "coils.z.sides_m=[0.62, 3.0]"]) == 2
    err = capsys.readouterr().err
    assert "coils.z.sides_m" in err and "Traceback" not in err, "one line naming the key"
    assert cli.main(["evaluate", design, "--set", "coils.z.sides_m=[0.80, 0.62]"]) == 2
    err = capsys.readouterr().err
    assert "coils.z.sides_m" in err and "overlap" in err, "the long side across the y frames"


def test_cli_sizing_with_free_z_turns(tmp_path, capsys) -> None:
    design = str(_rect_design(tmp_path))
    out = tmp_path / "sized.toml"
    args = ["optimize", design, "--free", "coils.z.turns=100:600", "--json", "-o", str(out)]
    args += ["--set", "optimize.starts=1"]  # one IPOPT start: what is checked is the hardware
    assert cli.main(args) == 0, "a sizing with free z turns of the rectangle design"
    res = json.loads(capsys.readouterr().out)
    assert res["hardware"]["discrete"]["coils.z.turns"] >= 100
    assert "sides_m = [0.62, 0.8]" in out.read_text(), "the sized design keeps the sides"


def _rect_model(sets=()):
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    return build_model(load_design(str(RECT_EXAMPLE), list(sets)))


def test_export_to_magpylib_of_rectangles_on_every_axis() -> None:
    """Rectangles on x, y and z: to_magpylib's closed Polylines (spiralcap.export) against
    spiralcap's field, pair by pair (the cyclic orientation of the sides on each axis)."""
    from spiralcap.export import to_magpylib

    system = coils.ThreeAxisHelmholtz(
        _pair("x", (1.0, 0.7)), _pair("y", (0.6, 0.9)), _pair("z", (0.5, 0.8), filaments=(2, 2))
    )
    points = np.random.default_rng(4).uniform(-0.15, 0.15, (40, 3))
    for k, currents in enumerate(np.eye(3)):
        got = to_magpylib(system, currents_A=tuple(currents)).getB(points)
        ref = system.field(points, currents)
        err = np.max(np.linalg.norm(got - ref, axis=1)) / np.max(np.linalg.norm(ref, axis=1))
        assert err < 1e-6, f"pair {k}: magpylib Polyline rectangles vs spiralcap, rel 1e-6"


@pytest.mark.slow
def test_step_frames_have_the_rectangle_volume_and_distances(tmp_path, capsys) -> None:
    b3d = pytest.importorskip("build123d")

    step = tmp_path / "rect.step"
    assert cli.main(["coils", str(RECT_EXAMPLE), "--step", str(step), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    solids = {c.label: c for c in b3d.import_step(str(step)).children}
    z = _rect_model().coils.z
    a, b = z.sides_m
    expected = 2 * (a + b) * z.winding_pack_width_m * z.winding_pack_depth_m * 1e9
    assert solids["coil_z+"].volume == pytest.approx(expected, rel=1e-6), (
        "a rectangular frame's volume 2 (a + b) w h (mm³), 1e-6"
    )
    box = solids["coil_z+"].bounding_box()
    h = z.winding_pack_depth_m * 1e3
    assert box.size.X == pytest.approx(a * 1e3 + h, abs=1e-6), "side a + h along x (z pair)"
    assert box.size.Y == pytest.approx(b * 1e3 + h, abs=1e-6), "side b + h along y"
    for key in ("x/z", "y/z"):
        p, q = key.split("/")
        kernel = min(
            solids[f"coil_{p}{s}"].distance_to(solids[f"coil_{q}{t}"]) for s in "-+" for t in "-+"
        )
        assert out["pack_clearances_m"][key] * 1e3 == pytest.approx(kernel, abs=1e-3), (
            f"{key}: spiralcap's frame distance vs OpenCASCADE's on the STEP solids, 1 µm"
        )
    bom = {r["axis"]: r for r in out["bill_of_materials"]}["z"]
    from spiralcap.analysis.bom import LEAD_ALLOWANCE_PER_COIL_m

    assert bom["wire_length_m"] == pytest.approx(
        2 * 300 * 2 * (a + b) + 2 * LEAD_ALLOWANCE_PER_COIL_m
    ), "bill of materials: 2 N · 2(a + b) plus the leads"
