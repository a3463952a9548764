"""Square pairs as built (issue 30): clearances, view factors, convection, design keys, CLI."""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import numpy as np
import pytest
from cli_outcome import run, run_json

import coils
from coils.clearance import (
    Frame,
    Ring,
    frame_distance_m,
    frame_signed_distance,
    pack_clearance_m,
    pack_closest_points,
    pair_packs,
    ring_surface_points,
)
from coils.convection import vertical_bar_convection_W_m2K, vertical_plate_nusselt
from coils.thermal import WindingPack, convection_coefficient_W_m2K
from coils.viewfactors import PackFrame, view_factors
from spiralcap.core.constants import COPPER_DENSITY_kg_m3

SQUARE_X = ["--set", "coils.x.shape=square", "--set", "coils.x.side_m=0.95"]


# --- an independent geometry: a frame as four boxes ------------------------------------------


def boxes(frame: Frame) -> list[tuple[np.ndarray, np.ndarray]]:
    """The frame as four overlapping boxes, each bar the full outer length (independent of
    coils.clearance.frame_bars, which tiles the frame without overlap)."""
    a = frame.axis
    u, v = [i for i in range(3) if i != a]
    h_out, h_in = (frame.side_m + frame.depth_m) / 2, (frame.side_m - frame.depth_m) / 2
    out = []
    for across, along in ((u, v), (v, u)):
        for sign in (-1, 1):
            lo, hi = np.zeros(3), np.zeros(3)
            lo[a], hi[a] = frame.centre_m - frame.width_m / 2, frame.centre_m + frame.width_m / 2
            lo[across], hi[across] = sorted((sign * h_in, sign * h_out))
            lo[along], hi[along] = -h_out, h_out
            out.append((lo, hi))
    return out


def union_distance(frame: Frame, points: np.ndarray) -> np.ndarray:
    """Distance from points outside the frame: the least distance to any of its boxes (exact
    for a union, outside it); 0 inside."""
    return boxes_distance(boxes(frame), points)


def boxes_distance(box_list: list[tuple[np.ndarray, np.ndarray]], points: np.ndarray):
    """Least distance from each point to any box (lo, hi) of ``box_list``: per box the norm of
    the per-axis gaps max(lo - p, p - hi, 0); the least squared distance, then one root (the
    root is monotonic: the same least). In blocks of points to bound the memory."""
    lo = np.array([b[0] for b in box_list])  # (boxes, 3)
    hi = np.array([b[1] for b in box_list])
    points = np.asarray(points, dtype=float)
    out = np.empty(len(points))
    for start in range(0, len(points), 262_144):
        p = points[start : start + 262_144]
        sq = np.zeros((len(p), len(lo)))
        for k in range(3):
            gap = np.maximum(np.maximum(lo[:, k] - p[:, k, None], p[:, k, None] - hi[:, k]), 0.0)
            sq += gap * gap
        out[start : start + len(p)] = np.sqrt(np.min(sq, axis=1))
    return out


def union_gap_m(
    box_a: list[tuple[np.ndarray, np.ndarray]], box_b: list[tuple[np.ndarray, np.ndarray]]
) -> float:
    """Least distance between two disjoint unions of boxes, exact: the least box-to-box
    distance (for two axis-aligned boxes, the norm of the per-axis gaps max(lo2 - hi1,
    lo1 - hi2, 0)). What a dense sample of one union's surface against the other's boxes
    converges to, without the sample's spacing."""
    best = np.inf
    for (lo1, hi1), (lo2, hi2) in itertools.product(box_a, box_b):
        gap = np.maximum(np.maximum(lo2 - hi1, lo1 - hi2), 0.0)
        best = min(best, float(np.linalg.norm(gap)))
    return best


def pair_boxes(pair) -> list[tuple[np.ndarray, np.ndarray]]:
    """Both frames of a square pair as four overlapping boxes each (:func:`boxes`)."""
    return [b for frame in pair_packs(pair) for b in boxes(frame)]


def inside_any(box_list: list[tuple[np.ndarray, np.ndarray]], points: np.ndarray):
    """Whether each point lies in a closed box (lo, hi) of ``box_list``: where the distance to
    their union is 0, decided by comparisons instead of the distance (the same decision)."""
    inside = np.zeros(len(points), dtype=bool)
    for lo, hi in box_list:
        inside |= np.all((points >= lo) & (points <= hi), axis=1)
    return inside


def surface_samples(frame: Frame, n: int, rng: np.random.Generator) -> tuple[np.ndarray, ...]:
    """Points uniform on the frame's outer surface, with outward normals: points uniform on
    every face of every box by area, kept where a step out along the normal leaves the union."""
    pts, normals = [], []
    for lo, hi in boxes(frame):
        for axis in range(3):
            for side, bound in ((-1.0, lo), (1.0, hi)):
                others = [i for i in range(3) if i != axis]
                area = np.prod(hi[others] - lo[others])
                m = max(int(n * area), 1)
                p = rng.uniform(lo, hi, (m, 3))
                p[:, axis] = bound[axis]
                normal = np.zeros((m, 3))
                normal[:, axis] = side
                keep = ~inside_any(boxes(frame), p + 1e-7 * normal)  # union distance > 0
                pts.append(p[keep])
                normals.append(normal[keep])
    return np.vstack(pts), np.vstack(normals)


# --- clearances ------------------------------------------------------------------------------


def test_frame_signed_distance_against_the_union_of_boxes() -> None:
    frame = Frame(1, 0.78, 0.21, 0.05, 0.04)
    rng = np.random.default_rng(1)
    points = rng.uniform(-0.6, 0.6, (20000, 3))
    d = frame_signed_distance(frame, points)
    outside = d > 0
    ref = union_distance(frame, points[outside])
    assert np.allclose(d[outside], ref, rtol=0, atol=1e-14), (
        "outside: least distance to the four boxes (exact for a union), abs 1e-14"
    )
    assert np.all(union_distance(frame, points[~outside]) == 0.0), "inside where the boxes are"
    # inside: depth = distance to the nearest surface point (dense sample, its spacing)
    inner = points[~outside][:40]
    surf, _ = surface_samples(frame, 1_000_000, rng)
    from scipy.spatial import cKDTree

    depth = cKDTree(surf).query(inner)[0]  # exact nearest sample (Euclidean), as a full scan
    assert np.allclose(-d[~outside][:40], depth, atol=1.5e-3), (
        "inside: minus the distance to the surface (brute force on a ~0.5 mm sample)"
    )


def test_frame_distance_against_brute_force() -> None:
    a = Frame(0, 0.95, 0.26, 0.06, 0.06)
    b = Frame(1, 0.78, -0.21, 0.05, 0.05)
    # brute force over every pair of the frames' overlapping boxes: the exact least distance
    # (was: a ~0.7 mm sample of A's surface against B's boxes, within 2 mm; the sample's limit)
    brute = union_gap_m(boxes(a), boxes(b))
    exact = frame_distance_m(a, b)
    assert 0 < exact and exact == pytest.approx(brute, rel=1e-9), (
        f"least distance of A's boxes to B's boxes (every pair, exact), 1e-9; {exact:.6f} m"
    )
    # a pair of frames that overlap reports a negative clearance
    c = Frame(1, 0.93, 0.0, 0.06, 0.06)
    assert frame_distance_m(a, c) < 0.0, "intersecting frames: negative"


def test_mixed_ring_frame_clearance_against_brute_force() -> None:
    square = coils.SquarePair(0.95, 400, "x", wire_diameter_m=3e-3)
    circle = coils.HelmholtzPair(0.35, 350, "y", wire_diameter_m=2.5e-3)
    exact = pack_clearance_m(square, circle)
    ring = pair_packs(circle)[1]
    assert isinstance(ring, Ring)
    phi = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    s = np.linspace(0, 2 * (ring.width_m + ring.depth_m), 400, endpoint=False)
    pts = ring_surface_points(ring, phi[:, None], s[None, :]).reshape(-1, 3)
    brute = min(float(np.min(union_distance(f, pts))) for f in pair_packs(square))
    assert exact <= brute + 1e-9 and brute - exact < 1e-3, (
        f"ring surface sampled against the frames' boxes, within 1 mm; exact {exact:.6f} m"
    )
    d, pa, pb = pack_closest_points(square, circle)
    assert d == exact and np.linalg.norm(pa - pb) == pytest.approx(d, abs=1e-6), (
        "the closest points are the clearance apart"
    )


def test_nested_square_set_clearances_and_bore() -> None:
    sides = {"x": 0.95, "y": 0.78, "z": 0.62}
    pairs = {ax: coils.SquarePair(sides[ax], 300, ax, wire_diameter_m=2.5e-3) for ax in "xyz"}
    from coils.clearance import bore_clearance_m, pack_clearances_m

    gaps = pack_clearances_m(list(pairs.values()))
    for key, gap in gaps.items():
        a, b = key.split("/")
        fa, fb = pair_packs(pairs[a])[1], pair_packs(pairs[b])[1]
        # exact least distance of the two pairs' box unions (was: a ~1 mm surface sample of
        # one frame against the other pair's boxes, within 3 mm; the sample's limit)
        independent = union_gap_m(pair_boxes(pairs[a]), pair_boxes(pairs[b]))
        assert independent > 0 and gap == pytest.approx(independent, rel=1e-9), (
            f"{key}: clearance = the least distance of the pairs' union of boxes (exact), 1e-9"
        )
        assert gap == frame_distance_m(fa, fb)
    depth = pairs["z"].winding_pack_depth_m
    assert bore_clearance_m(list(pairs.values()), 0.1) == pytest.approx(
        0.62 / 2 - depth / 2 - 0.1, rel=1e-14
    ), "inner face of the smallest frame: a/2 - h/2 from the axis, less the bore radius"


# --- cooling ---------------------------------------------------------------------------------


def _room_fraction_independent(frame: PackFrame, others: list, n: int = 5000) -> float:
    """Pair's view factor to the room by random rays (hemisphere weighted 2 cos θ) marched on
    the union-of-boxes distance: not the Halton trace's sampling, nor its slab test."""
    rng = np.random.default_rng(7)
    geo = [
        Frame(f.axis_index, f.side_m, s * 0.5 * f.separation_m, f.width_m, f.depth_m)
        for f in [frame, *others]
        for s in (-1, 1)
    ]
    all_boxes = [b for g in geo for b in boxes(g)]
    surf, normals = surface_samples(geo[1], 40 * n, rng)
    pick = rng.choice(len(surf), n, replace=False)
    p, nv = surf[pick], normals[pick]
    v = rng.normal(size=(n, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    cos = np.sum(v * nv, axis=1)
    v = np.where(cos[:, None] < 0, -v, v)
    weight = 2.0 * np.abs(cos)
    x = p + 1e-5 * nv
    t = np.zeros(n)
    alive = np.ones(n, dtype=bool)
    hit = np.zeros(n, dtype=bool)
    for _ in range(800):
        pts = x[alive] + t[alive, None] * v[alive]
        d = boxes_distance(all_boxes, pts)  # the least over every frame's boxes
        idx = np.flatnonzero(alive)
        hit[idx[d < 2e-6]] = True
        gone = (d < 2e-6) | (np.linalg.norm(pts, axis=1) > 3.0)
        alive[idx[gone]] = False
        t[idx[~gone]] += np.maximum(d[~gone], 2e-6)
        if not alive.any():
            break
    return float(np.sum(weight * ~hit) / np.sum(weight))


def test_square_view_factors_against_an_independent_trace() -> None:
    frames = [
        PackFrame(0, 0.95, 0.5445 * 0.95, 0.06, 0.06),
        PackFrame(1, 0.78, 0.5445 * 0.78, 0.05, 0.05),
        PackFrame(2, 0.62, 0.5445 * 0.62, 0.045, 0.045),
    ]
    f = view_factors(frames)
    assert np.allclose(f.sum(axis=1), 1.0, atol=1e-12), "every ray lands somewhere"
    for k in range(3):
        others = [fr for j, fr in enumerate(frames) if j != k]
        ref = _room_fraction_independent(frames[k], others)
        assert f[k, 0] == pytest.approx(ref, abs=0.03), (
            f"pair {'xyz'[k]}: view factor to the room vs random rays marched on the "
            "union-of-boxes distance (issue 19's 0.03)"
        )
    alone = view_factors([frames[2]])
    assert alone[0, 1] > 0.0 and alone[0, 0] < 1.0, "a frame sees its own inner faces"


def test_vertical_bar_convection_by_hand_and_blend() -> None:
    from coils.convection import air_properties

    w, d, height, ts, ta = 0.06, 0.05, 0.95, 70.0, 25.0
    air = air_properties(0.5 * (ts + ta))
    ra = 9.80665 / (0.5 * (ts + ta) + 273.15) * np.hypot(ts - ta, 0.1) * height**3
    ra /= air.kinematic_viscosity_m2_s * air.diffusivity_m2_s
    by_hand = vertical_plate_nusselt(ra, air.prandtl) * air.conductivity_W_mK / height
    assert vertical_bar_convection_W_m2K(w, d, height, ts, ta) == pytest.approx(
        by_hand, rel=1e-12
    ), "Churchill & Chu (1975a) vertical plate over the bar's height (Incropera 9.26)"
    base = dict(
        pack_width_m=w,
        pack_depth_m=d,
        mean_radius_m=2.0 * height / np.pi,  # a square frame of side `height`: 4a / (2 pi)
        packing_factor=0.7,
        conductivity_W_mK=0.5,
        heat_transfer_coefficient_W_m2K=0.0,
        emissivity=0.9,
        convection="natural",
    )
    ring = convection_coefficient_W_m2K(WindingPack(**base), ts, ta)
    frame = convection_coefficient_W_m2K(WindingPack(**base, vertical_bar_height_m=height), ts, ta)
    assert frame == pytest.approx(0.5 * (ring + by_hand), rel=1e-12), (
        "a vertical square frame: half horizontal bars (the ring's cylinder), half vertical bars "
        "(the vertical bars' share of the mean turn, 2a / 4a)"
    )
    import casadi as ca

    hs = ca.SX.sym("h")
    sym = convection_coefficient_W_m2K(WindingPack(**base, vertical_bar_height_m=hs), ts, ta)
    fn = ca.Function("h", [hs], [sym])
    assert float(fn(height)) == pytest.approx(frame, rel=1e-12), "numpy vs CasADi, 1e-12"
    assert float(fn(0.0)) == pytest.approx(ring, rel=1e-15), "height 0: the ring's value"


# --- design keys and the CLI -----------------------------------------------------------------


@pytest.mark.parametrize(
    ("argv", "key"),
    [
        (["--set", "coils.x.shape=square"], "coils.x.side_m"),
        (["--set", "coils.y.side_m=0.8"], "coils.y.side_m"),
        (["--set", "coils.z.shape=square", "--set", "coils.z.side_m=7"], "coils.z.side_m"),
        (["--set", "coils.z.shape=hexagon"], "coils.z.shape"),
        (["--set", "coils.y.shape=square", "--set", "coils.y.side_m=0.74"], "coils.y.side_m"),
    ],
)
def test_bad_square_input_exits_2_naming_the_key(argv: list[str], key: str) -> None:
    for command in ("coils", "evaluate"):
        rc, out, err = run([command, *argv])
        assert rc == 2 and key in err and err.count("\n") <= 1 and not out, err


def test_free_square_side_with_a_circle_radius_is_refused_with_exit_2() -> None:
    rc, _, err = run(["optimize", *SQUARE_X, "--free", "coils.x.radius_m=0.3:0.5"])
    assert rc == 2 and "optimize.free.coils.x.radius_m" in err and "coils.x.side_m" in err, err


@pytest.fixture(scope="module")
def square_x_coils() -> dict:
    """``spiralcap coils`` with the square x pair, run once for the tests that read it."""
    return run_json(["coils", *SQUARE_X])


@pytest.fixture(scope="module")
def example_evaluate() -> dict:
    """``spiralcap evaluate`` of the example square set, run once for the tests that read it."""
    return run_json(["evaluate", EXAMPLE])


def test_square_x_pair_in_coils_and_evaluate(square_x_coils: dict) -> None:
    x = square_x_coils["axes"]["x"]
    pair = coils.SquarePair(0.95, 400, "x", wire_diameter_m=3e-3)
    assert x["shape"] == "square" and x["side_m"] == 0.95 and x["radius_m"] == 0.475
    assert x["separation_m"] == pytest.approx(0.5445 * 0.95, rel=1e-15), "0.5445 x side"
    assert x["field_per_amp_T_per_A"] == pair.centre_field_per_amp_T_per_A
    section = np.pi * 3e-3**2 / 4
    by_hand = COPPER_DENSITY_kg_m3 * 2 * 4 * 0.95 * 400 * section
    assert x["copper_mass_kg"] == pytest.approx(by_hand, rel=0.015), (
        "density x 2 x 4 x side x turns x wire section, rel 1.5 %"
    )
    assert x["self_inductance_H"] == pair.self_inductance_H
    ev = run_json(["evaluate", *SQUARE_X])
    assert ev["feasible"] is True
    names = {c["name"] for c in ev["checks"]}
    assert {"clearance_xy", "clearance_xz", "bore_clearance"} <= names


# --- the example square set ------------------------------------------------------------------

EXAMPLE = str(Path(__file__).resolve().parents[1] / "examples" / "square_coils.toml")


def test_square_example_evaluates_with_exact_clearances(example_evaluate: dict) -> None:
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    ev = example_evaluate
    assert ev["feasible"] is True, "the example square set meets every check"
    model = build_model(load_design(EXAMPLE))
    assert all(p.shape == "square" for p in model.coils.pairs)
    checks = {c["name"]: c["value"] for c in ev["checks"]}
    for name, (a, b) in {
        "clearance_xy": (0, 1),
        "clearance_xz": (0, 2),
        "clearance_yz": (1, 2),
    }.items():
        pa, pb = model.coils.pairs[a], model.coils.pairs[b]
        # exact (was: a ~1 mm surface sample against the other frames' boxes, within 3 mm)
        independent = union_gap_m(pair_boxes(pa), pair_boxes(pb))
        assert independent > 0 and checks[name] == pytest.approx(independent, rel=1e-9), (
            f"{name}: the least distance of the pairs' union of boxes (independent, exact), 1e-9"
        )


def test_square_example_step_reads_back_six_solids_apart(tmp_path, capsys) -> None:
    b3d = pytest.importorskip("build123d")
    from spiralcap import cli
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    step = tmp_path / "square.step"
    assert cli.main(["coils", EXAMPLE, "--step", str(step), "--json"]) == 0
    clearances = json.loads(capsys.readouterr().out)["pack_clearances_m"]
    back = b3d.import_step(str(step))
    solids = {c.label: c for c in back.children}
    assert sorted(solids) == sorted(f"coil_{ax}{s}" for ax in "xyz" for s in "-+"), "six packs"
    model = build_model(load_design(EXAMPLE))
    for pair in model.coils.pairs:
        expected = 4 * pair.side_m * pair.winding_pack_width_m * pair.winding_pack_depth_m * 1e9
        for s in "-+":
            assert solids[f"coil_{pair.axis}{s}"].volume == pytest.approx(expected, rel=1e-6), (
                "frame volume 4 a w h (mm³), 1e-6"
            )
    packs = list(solids.values())
    for a, b in itertools.combinations(packs, 2):
        common = (a & b).volume if (a & b) is not None else 0.0
        assert common < 1e-6 * min(a.volume, b.volume), "no two packs share a volume"
    for key, value in clearances.items():
        p, q = key.split("/")
        kernel = min(
            solids[f"coil_{p}{s}"].distance_to(solids[f"coil_{q}{t}"]) for s in "-+" for t in "-+"
        )
        assert value * 1e3 == pytest.approx(kernel, abs=1e-3), (
            f"{key}: tool vs OpenCASCADE BRepExtrema distance of the exported frames (1 µm)"
        )


def test_bill_of_materials_and_report_rows_of_a_square_pair(square_x_coils: dict) -> None:
    from spiralcap.analysis.bom import LEAD_ALLOWANCE_PER_COIL_m
    from spiralcap.report.document import Paragraph
    from spiralcap.report.sections._util import Context
    from spiralcap.report.sections.coils import _build_paragraph, _sizing_table

    payload = square_x_coils
    bom = {r["axis"]: r for r in payload["bill_of_materials"]}["x"]
    assert bom["wire_length_m"] == pytest.approx(2 * 400 * 4 * 0.95 + 2 * LEAD_ALLOWANCE_PER_COIL_m)
    ctx = Context(data=None, payload={"coils": payload})
    table = _sizing_table(ctx)
    assert table.rows[0][2:] == ["square", "circle", "circle"], "the shape row leads"
    assert table.rows[1][3] == "–" and float(table.rows[1][2].value) == 0.95, "a square's side"
    paragraph = _build_paragraph(ctx)
    assert isinstance(paragraph, Paragraph)
    assert any("solid rings and square frames" in str(p) for p in paragraph.parts)


@pytest.mark.parametrize("command", ["coils", "evaluate"])
def test_square_outputs_match_their_schemas(command: str, request) -> None:
    jsonschema = pytest.importorskip("jsonschema")
    docs = Path(__file__).resolve().parents[1] / "docs" / "json"
    schema = json.loads((docs / f"{command}.schema.json").read_text())
    payload = (
        request.getfixturevalue("example_evaluate")
        if command == "evaluate"
        else run_json([command, EXAMPLE])
    )
    jsonschema.validate(payload, schema)


def test_optimum_of_the_square_example_is_reproduced_by_evaluate(tmp_path) -> None:
    """``optimize`` at fixed hardware on a square set: the optimum it writes is what
    ``evaluate`` finds (same margin), with the binding hot spot exactly at its limit."""
    out = tmp_path / "best.toml"
    res = run_json(["optimize", EXAMPLE, "-o", str(out)])
    assert res["status"] == "optimal", res["message"]
    ev = run_json(["evaluate", str(out)])
    checks = {c["name"]: c for c in ev["checks"]}
    binding = [b for b in res["binding_limits"] if b["name"].startswith("hot_spot")]
    assert binding, f"a hot spot binds at the optimum: {res['binding_limits']}"
    for b in binding:
        check = checks[b["name"]]
        assert check["value"] == pytest.approx(check["allowed"], rel=1e-4), (
            f"{b['name']}: evaluate's hot spot at the optimum = the limit the NLP held, rel 1e-4"
        )
    assert ev["margin_Nm"] == pytest.approx(res["margin_Nm"], rel=1e-4), "same margin"


def test_compare_sweep_and_waveforms_take_square_sets() -> None:
    from cli_outcome import bad_numbers, sound

    _, out, _ = sound(["compare", "builtin", EXAMPLE, "--json"], allowed=(0,))
    assert not bad_numbers(json.loads(out)), "circle vs square set compared, every number finite"
    _, out, _ = sound(
        ["sweep", EXAMPLE, "--over", "coils.x.side_m=0.92:1.0:2", "--json"], allowed=(0,)
    )
    rows = json.loads(out)
    assert not bad_numbers(rows)
    _, out, _ = sound(
        [
            "waveforms",
            *SQUARE_X,
            "--set",  # not at the voltage limit (a plane change overshoots a bound voltage)
            "limits.voltage_V=200",
            "--heading",
            "1,0,0",
            "--heading",
            "0,1,0",
            "--dwell-s",
            "1",
            "--json",
        ],
        allowed=(0,),
    )
    assert not bad_numbers(json.loads(out))


def test_help_says_a_square_pair_does_not_use_radius() -> None:
    from spiralcap.schema import KEYS

    for ax in "xyz":
        help_ = KEYS[f"coils.{ax}.radius_m"].help
        assert "square" in help_ and "does not use it" in help_ and f"coils.{ax}.side_m" in help_
        assert KEYS[f"coils.{ax}.shape"].default == "circle"
        assert (KEYS[f"coils.{ax}.side_m"].lo, KEYS[f"coils.{ax}.side_m"].hi) == (0.02, 4.0)
    rc, out, _ = run(["coils", *SQUARE_X])
    assert rc == 0 and "x (square)" in out and "radius_or_side_m" in out
