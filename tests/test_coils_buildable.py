"""Issue 18: coils that can be built: packs as solids, clearances, copper mass, bill of materials.

Independent checks: the clearances against a brute-force signed-distance computation written here
(dense points on the faces of one pack of each pair against the other pack's exact distance, the
other way round from coils.clearance) and, with the cad extra, against OpenCASCADE's own
distance; the copper mass against turns x 2πR x wire section x density by hand and the CAD
volume; the STEP file read back by the CAD kernel.
"""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest
from cli_outcome import LEAST_POWER, NO_TOLERANCES, SIX_KEYS, run_json

from coils.clearance import (
    Ring,
    pack_clearance_m,
    ring_distance_m,
    torus_clearance_bound_m,
)
from optimize.hardware import mean_turn_gap_m
from spiralcap import cli
from spiralcap.assemble import build_model
from spiralcap.design import load_design


def _sdf(points: np.ndarray, axis: int, radius: float, centre: float, w: float, h: float):
    """Signed distance to a ring of rectangular section, written out again for the test:
    outside, the distance in the meridian plane to the nearest point of the rectangle; inside,
    minus the distance to the nearest face."""
    others = [k for k in range(3) if k != axis]
    rho = np.sqrt(points[:, others[0]] ** 2 + points[:, others[1]] ** 2)
    z = points[:, axis]
    near_rho = np.clip(rho, radius - h / 2, radius + h / 2)
    near_z = np.clip(z, centre - w / 2, centre + w / 2)
    outside = np.hypot(rho - near_rho, z - near_z)
    inside = np.minimum.reduce(
        [rho - (radius - h / 2), radius + h / 2 - rho, z - (centre - w / 2), centre + w / 2 - z]
    )
    return np.where(outside > 0, outside, -inside)


def _face_points(pair, n_phi: int = 2000, n_side: int = 40) -> list[np.ndarray]:
    """Points on the four faces of each coil of ``pair`` (uniform in angle and along the side)."""
    axis = pair.axis_index
    others = [k for k in range(3) if k != axis]
    w, h, r = pair.winding_pack_width_m, pair.winding_pack_depth_m, pair.radius_m
    phi = np.linspace(0, 2 * np.pi, n_phi, endpoint=False)[:, None]
    t = np.linspace(-0.5, 0.5, n_side)[None, :]
    out = []
    for centre in (-pair.separation_m / 2, pair.separation_m / 2):
        for rho, z in (
            (r - h / 2 + 0 * t, centre + w * t),  # inner face
            (r + h / 2 + 0 * t, centre + w * t),  # outer face
            (r + h * t, centre - w / 2 + 0 * t),  # annular faces
            (r + h * t, centre + w / 2 + 0 * t),
        ):
            rho_b, z_b, phi_b = np.broadcast_arrays(rho, z, phi)
            p = np.zeros((*rho_b.shape, 3))
            p[..., others[0]] = rho_b * np.cos(phi_b)
            p[..., others[1]] = rho_b * np.sin(phi_b)
            p[..., axis] = z_b
            out.append(p.reshape(-1, 3))
    return out


def brute_force_clearance_m(pa, pb) -> float:
    """Least over B's face points of A's signed distance (both coils of each pair)."""
    best = np.inf
    for pts in _face_points(pb):
        for centre in (-pa.separation_m / 2, pa.separation_m / 2):
            d = _sdf(
                pts,
                pa.axis_index,
                pa.radius_m,
                centre,
                pa.winding_pack_width_m,
                pa.winding_pack_depth_m,
            )
            best = min(best, float(d.min()))
    return best


#: One IPOPT start (default 4) for the sizings below: what they check (clearances, mass limits,
#: binding rows, exit 3) is set by the hardware, and every sizing here gives the same optimum
#: (to 1e-9) and the same refusals from one start as from four, measured; a quarter of the
#: angle solves per candidate.
ONE_START = ["--set", "optimize.starts=1"]


@pytest.fixture(scope="module")
def builtin_coils() -> dict:
    """``spiralcap coils --json`` of the built-in design, run once for the tests that read it."""
    return run_json(["coils"])


def _run_json(args, capsys) -> dict:
    capsys.readouterr()
    assert cli.main(args) == 0, f"spiralcap {' '.join(args)} exits 0"
    return json.loads(capsys.readouterr().out)


def test_issue_example_overlap_is_found() -> None:
    """The issue's numbers for the old built-in coils (0.40/0.35/0.30 m, 2.5 mm wire): x and y
    packs share (0.1783, 0.195, -0.3242) m, overlap ~9.4 mm, y/z ~6 mm, x/z 45.6 mm apart."""
    from coils import HelmholtzPair

    pairs = [
        HelmholtzPair(r, n, ax, wire_diameter_m=2.5e-3)
        for ax, r, n in (("x", 0.40, 400), ("y", 0.35, 350), ("z", 0.30, 300))
    ]
    x, y, z = pairs
    p = np.array([[0.1783, 0.195, -0.3242]])
    inside = [
        min(_sdf(p, q.axis_index, q.radius_m, c, q.winding_pack_side_m, q.winding_pack_side_m)[0]
            for c in (-q.separation_m / 2, q.separation_m / 2))
        for q in (x, y)
    ]  # fmt: skip
    assert max(inside) < 0, "the issue's point lies inside the x and the y pack"
    assert pack_clearance_m(x, y) == pytest.approx(-9.5e-3, abs=0.3e-3), "x/y overlap (issue)"
    assert pack_clearance_m(y, z) == pytest.approx(-6.0e-3, abs=0.3e-3), "y/z overlap (issue)"
    assert pack_clearance_m(x, z) == pytest.approx(45.6e-3, abs=0.3e-3), "x/z gap (issue)"


def test_builtin_clearances_against_brute_force(builtin_coils) -> None:
    out = builtin_coils
    need = out["min_clearance_m"]
    assert need == pytest.approx(0.010), "coils.min_clearance_mm default 10 mm"
    model = build_model(load_design(None))
    pairs = {p.axis: p for p in model.coils.pairs}
    for key, value in out["pack_clearances_m"].items():
        a, b = key.split("/")
        brute = brute_force_clearance_m(pairs[a], pairs[b])
        assert value == pytest.approx(brute, abs=0.5e-3), (
            f"{key}: tool vs brute-force signed distance over the other pack's faces (0.5 mm)"
        )
        assert value >= need, f"{key}: the built-in packs keep {need * 1e3:g} mm"
    assert out["bore_clearance_m"] >= need, "the inner faces clear the bore"


def test_ring_distance_symmetric_and_bound_conservative() -> None:
    a = Ring(0, 0.4, 0.2, 0.06, 0.03)
    b = Ring(1, 0.33, -0.165, 0.02, 0.05)
    assert ring_distance_m(a, b) == pytest.approx(ring_distance_m(b, a), abs=1e-7), (
        "A's surface against B's distance and the other way round: the same least distance"
    )
    model = build_model(load_design(None))
    for pa, pb in itertools.combinations(model.coils.pairs, 2):
        bound = torus_clearance_bound_m(mean_turn_gap_m(pa, pb), pa, pb)
        exact = pack_clearance_m(pa, pb)
        slack = sum(
            (math.hypot(p.winding_pack_width_m, p.winding_pack_depth_m)
             - max(p.winding_pack_width_m, p.winding_pack_depth_m)) / 2
            for p in (pa, pb)
        )  # fmt: skip
        assert bound <= exact + 1e-9, "the torus bound never exceeds the exact clearance"
        assert exact - bound <= slack + 1e-6, "conservative by at most (diag - max side)/2 each"


def test_six_key_least_power_sizing_keeps_the_clearance(tmp_path, capsys) -> None:
    out_toml = tmp_path / "sized.toml"
    _run_json(
        ["optimize", "--json", "-o", str(out_toml), *SIX_KEYS, *LEAST_POWER, *ONE_START], capsys
    )
    sized = _run_json(["coils", str(out_toml), "--json"], capsys)
    model = build_model(load_design([str(out_toml)]))
    pairs = {p.axis: p for p in model.coils.pairs}
    for key, value in sized["pack_clearances_m"].items():
        a, b = key.split("/")
        assert value >= 0.010 * (1 - 1e-6), f"{key}: sized packs keep 10 mm ({value * 1e3:.2f})"
        assert value == pytest.approx(brute_force_clearance_m(pairs[a], pairs[b]), abs=0.5e-3), (
            f"{key}: tool vs brute-force signed distance (0.5 mm)"
        )
    ev = _run_json(["evaluate", str(out_toml), "--json"], capsys)
    assert ev["safety_factor"] >= 2.0 * (1 - 1e-6), "the sizing still meets safety factor 2"


def test_copper_mass_limit_binds_in_sizing(tmp_path, capsys) -> None:
    out_toml = tmp_path / "sized.toml"
    res = _run_json(
        [
            "optimize",
            "--json",
            "-o",
            str(out_toml),
            *SIX_KEYS,
            *LEAST_POWER,
            *ONE_START,
            "--set",
            "limits.copper_mass_kg=100",  # 80 kg cannot meet SF 2 (cooling, grip, weight)
        ],
        capsys,
    )
    assert res["copper_mass_kg"] <= 100.0 * (1 + 1e-9), "at or below the 100 kg limit"
    assert "copper_mass" in [b["name"] for b in res["binding_limits"]], (
        "the mass limit binds, with its multiplier"
    )
    ev = _run_json(["evaluate", str(out_toml), "--json"], capsys)
    assert ev["safety_factor"] >= 2.0 * (1 - 1e-6), "still safety factor 2"
    assert ev["copper_mass_kg"] <= 100.0 * (1 + 1e-9), "evaluate agrees"


def test_copper_mass_60kg_is_infeasible_as_cooled_and_says_so(tmp_path, capsys) -> None:
    """Issue 18 asked for a least-power sizing under 60 kg at safety factor 2; that number was
    set before the cooling as built (natural convection ~6 W/(m²·K) instead of 10, packs
    radiating onto each other), the friction of the capsule's weight and the grip requirement
    (the spiral must stretch sample 3's wall by 1.68 %, which holds the angle at or below 20.13°
    where the tissue torque is higher). Now the least copper that meets safety factor 2 with the
    six keys free is ~87.6 kg (every hot spot at its limit), so 80 kg must exit 3 naming the
    mass and write nothing; the binding-limit case is tested at 100 kg above."""
    least = _run_json(
        [
            "optimize",
            "--json",
            "-o",
            str(tmp_path / "least.toml"),
            *SIX_KEYS,
            "--set",
            "optimize.objective=copper_mass",
            "--set",
            "requirements.min_safety_factor=2",
            *NO_TOLERANCES,  # the numbers of issue 18, before issue 36's box
            *ONE_START,
        ],
        capsys,
    )
    assert 80.0 < least["copper_mass_kg"] < 100.0, (
        f"least copper at SF 2 as cooled: {least['copper_mass_kg']:.2f} kg, between the 80 kg "
        "(infeasible) and the 100 kg of the binding test"
    )
    hot = {b["name"] for b in least["binding_limits"]}
    assert {"hot_spot_x", "hot_spot_y", "hot_spot_z"} <= hot, (
        f"the least copper is set by the winding hot spots (the cooling), binding: {sorted(hot)}"
    )
    ev = _run_json(["evaluate", str(tmp_path / "least.toml"), "--json"], capsys)
    assert ev["safety_factor"] >= 2.0 * (1 - 1e-6) and ev["feasible"] is True
    out = tmp_path / "sized.toml"
    args = [
        "optimize",
        "-o",
        str(out),
        *SIX_KEYS,
        *LEAST_POWER,
        *ONE_START,
        "--set",
        "limits.copper_mass_kg=80",
    ]
    assert cli.main(args) == 3, "80 kg cannot meet safety factor 2 as cooled: exit 3"
    text = capsys.readouterr().out
    assert "limits.copper_mass_kg" in text and "80 kg" in text, text
    assert not out.exists(), "nothing written for an infeasible sizing"
    import re

    need = re.search(r"need at least ([0-9.]+) kg of copper", text)
    assert need, f"the message gives the least copper the requirements need: {text}"
    assert 80.0 < float(need.group(1)) <= least["copper_mass_kg"], (
        f"that least copper ({need.group(1)} kg, the continuous relaxation) lies between the "
        f"limit and the least-copper sizing's discrete {least['copper_mass_kg']:.2f} kg"
    )
    assert "244" not in text, "not the starting hardware's copper (244 kg) as 'the closest'"


def test_copper_mass_against_turns_by_hand(builtin_coils) -> None:
    out = builtin_coils
    total = 0.0
    for row in out["bill_of_materials"]:
        a = out["axes"][row["axis"]]
        by_hand = (
            8890.0
            * (2 * a["turns"] * 2 * math.pi * a["radius_m"])
            * math.pi
            * (a["wire_diameter_m"] / 2) ** 2
        )
        assert a["copper_mass_kg"] == pytest.approx(by_hand, rel=0.01), (
            "density 8890 kg/m³ x 2N 2πR x π d²/4 (1 %)"
        )
        leads = row["lead_allowance_m"] * 8890.0 * math.pi * (a["wire_diameter_m"] / 2) ** 2
        assert row["copper_mass_kg"] == pytest.approx(by_hand + leads, rel=1e-9), (
            "bill of materials: the winding plus the stated lead allowance"
        )
        assert row["wire_length_m"] == pytest.approx(
            2 * a["turns"] * 2 * math.pi * a["radius_m"] + row["lead_allowance_m"], rel=1e-12
        )
        total += a["copper_mass_kg"]
    assert out["copper_mass_kg"] == pytest.approx(total, rel=1e-12), "total of the pairs"


def test_bill_of_materials_drive_points(builtin_coils) -> None:
    out = builtin_coils
    for row in out["bill_of_materials"]:
        a = out["axes"][row["axis"]]
        op = out["operating_point"]["axes"][row["axis"]]
        assert row["operating"]["current_amplitude_A"] == pytest.approx(op["current_A"], rel=1e-9)
        z = math.hypot(op["resistance_ohm"], 2 * math.pi * out["frequency_hz"] * a["inductance_H"])
        assert row["operating"]["voltage_amplitude_V"] == pytest.approx(
            z * op["current_A"], rel=1e-9
        ), "|R + jωL| I at the operating point (R at its mean winding temperature)"
        for point in ("operating", "at_limits"):
            d = row[point]
            assert d["apparent_power_VA"] == pytest.approx(
                d["voltage_amplitude_V"] * d["current_amplitude_A"] / 2, rel=1e-12
            ), "S = V I / 2 for amplitudes"
        assert row["at_limits"]["current_amplitude_A"] == pytest.approx(a["max_current_A"])
        assert row["at_limits"]["voltage_amplitude_V"] <= 150.0 * (1 + 1e-9), "voltage limit"
        assert "IEC 60317" in row["wire_standard"] and "grade 2" in row["enamel"]


def test_coils_text_shows_clearances_and_bill_of_materials(capsys) -> None:
    capsys.readouterr()
    assert cli.main(["coils"]) == 0
    text = capsys.readouterr().out
    assert "x/y:" in text and "bill of materials" in text and "Cu_kg" in text


@pytest.mark.parametrize(
    ("args", "named"),
    [
        (["--set", "coils.min_clearance_mm=-1"], "coils.min_clearance_mm"),
        (["--set", "coils.min_clearance_mm=5000"], "coils.min_clearance_mm"),
        (["--set", "coils.x.pack_aspect=0.1"], "coils.x.pack_aspect"),
        (["--set", "coils.z.pack_aspect=9"], "coils.z.pack_aspect"),
        (["--set", "limits.copper_mass_kg=-3"], "limits.copper_mass_kg"),
        (["--step", "coils.txt"], "--step"),
    ],
)
def test_bad_input_exits_2_naming_it(args, named, capsys) -> None:
    assert cli.main(["coils", *args]) == 2
    err = capsys.readouterr().err
    assert named in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_step_to_an_unwritable_path_exits_2_before_any_work(tmp_path, capsys) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("x")
    target = blocker / "coils.step"  # inside a file: cannot be written
    stl = tmp_path / "coils.stl"
    assert cli.main(["coils", "--step", str(target), "--stl", str(stl)]) == 2
    err = capsys.readouterr().err
    assert "--step" in err and "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"], "nothing written"


def test_step_without_the_cad_extra_says_how_to_install(monkeypatch, tmp_path, capsys) -> None:
    import spiralcap.cad as cad

    monkeypatch.setattr(cad, "cad_kernel_available", lambda: False)
    assert cli.main(["coils", "--step", str(tmp_path / "c.step")]) == 2
    err = capsys.readouterr().err
    assert 'pip install "spiralcap[cad]"' in err and "--step" in err
    assert list(tmp_path.iterdir()) == [], "nothing written"


def test_step_read_back_six_named_solids_of_the_right_volume(
    tmp_path, capsys, builtin_coils
) -> None:
    """Issue 18: the STEP file read back by the CAD kernel (OpenCASCADE through build123d):
    six solids (+ the workspace when asked), each of volume 2πR·w·h (0.5 %), no two with a
    common volume, and the kernel's own distance between the packs = the tool's clearance."""
    b3d = pytest.importorskip("build123d")
    step, stl = tmp_path / "coils.step", tmp_path / "coils.stl"
    assert cli.main(["coils", "--step", str(step), "--stl", str(stl), "--cad-workspace"]) == 0
    capsys.readouterr()
    assert stl.stat().st_size > 10_000, "an STL mesh was written"
    back = b3d.import_step(str(step))
    solids = {c.label: c for c in back.children}
    assert sorted(solids) == sorted(
        [f"coil_{ax}{s}" for ax in "xyz" for s in "-+"] + ["workspace"]
    ), "six named packs and the workspace"
    _check_volumes_and_copper(solids, builtin_coils)
    _check_apart_as_the_tool_says(solids, builtin_coils)


def _check_volumes_and_copper(solids: dict, builtin_coils: dict) -> None:
    """Each pack 2πR·w·h (0.5 %), the workspace sphere, and the copper mass from the volumes."""
    model = build_model(load_design(None))
    for pair in model.coils.pairs:
        expected = (
            2 * math.pi * pair.radius_m * pair.winding_pack_width_m * pair.winding_pack_depth_m
        ) * 1e9  # mm³
        for s in "-+":
            vol = solids[f"coil_{pair.axis}{s}"].volume
            assert vol == pytest.approx(expected, rel=0.005), "2πR·w·h, 0.5 %"
    assert solids["workspace"].volume == pytest.approx(4 / 3 * math.pi * 50.0**3, rel=0.005)
    masses = builtin_coils["axes"]
    for pair in model.coils.pairs:
        cad_volume_m3 = sum(solids[f"coil_{pair.axis}{s}"].volume for s in "-+") * 1e-9
        from_cad = cad_volume_m3 * pair.packing_factor * 8890.0
        assert masses[pair.axis]["copper_mass_kg"] == pytest.approx(from_cad, rel=0.01), (
            "copper mass = CAD volume of the two packs x packing factor x 8890 kg/m³ (1 %)"
        )


def _check_apart_as_the_tool_says(solids: dict, builtin_coils: dict) -> None:
    """No two packs share a volume; the kernel's distances are the tool's clearances."""
    packs = [solids[f"coil_{ax}{s}"] for ax in "xyz" for s in "-+"]
    for a, b in itertools.combinations(packs, 2):
        common = (a & b).volume if (a & b) is not None else 0.0
        assert common < 1e-6 * min(a.volume, b.volume), "no two packs share a volume"
    out = builtin_coils
    for key, value in out["pack_clearances_m"].items():
        p, q = key.split("/")
        kernel = min(
            solids[f"coil_{p}{s}"].distance_to(solids[f"coil_{q}{t}"]) for s in "-+" for t in "-+"
        )
        assert value * 1e3 == pytest.approx(kernel, abs=0.5), (
            f"{key}: tool vs OpenCASCADE BRepExtrema distance of the exported solids (0.5 mm)"
        )


def test_free_radii_aspect_and_turns_keep_the_clearance(tmp_path, capsys) -> None:
    """Radii, aspects and turns of two pairs free (least power, safety factor 2): the sizing
    pushes the packs together until the clearance rows bind, and the built design keeps
    coils.min_clearance_mm by the independent brute-force distance."""
    out_toml = tmp_path / "sized.toml"
    free = [
        "--free",
        "coils.x.radius_m=0.35:0.5",
        "--free",
        "coils.y.radius_m=0.3:0.45",
        "--free",
        "coils.x.pack_aspect=0.5:3",
        "--free",
        "coils.y.pack_aspect=0.5:3",
        "--free",
        "coils.x.turns=100:800",
        "--free",
        "coils.y.turns=100:800",
    ]
    res = _run_json(
        ["optimize", "--json", "-o", str(out_toml), *free, *LEAST_POWER, *ONE_START], capsys
    )
    binding = {b["name"] for b in res["binding_limits"]}
    assert binding & {"clearance_xy", "clearance_yz"}, "a clearance row binds, with a multiplier"
    model = build_model(load_design([str(out_toml)]))
    pairs = {p.axis: p for p in model.coils.pairs}
    for a, b in (("x", "y"), ("x", "z"), ("y", "z")):
        brute = brute_force_clearance_m(pairs[a], pairs[b])
        assert brute >= 0.010 - 0.5e-3, f"{a}/{b}: {brute * 1e3:.2f} mm by brute force"
    assert res["safety_factor"] >= 2.0 * (1 - 1e-6)


def test_impossible_clearance_or_mass_exits_3_naming_it(capsys) -> None:
    sized = ["optimize", *SIX_KEYS, *LEAST_POWER, *ONE_START]
    assert cli.main([*sized, "--set", "coils.min_clearance_mm=60"]) == 3
    assert "coils.min_clearance_mm" in capsys.readouterr().out
    assert cli.main([*sized, "--set", "limits.copper_mass_kg=5"]) == 3
    assert "limits.copper_mass_kg" in capsys.readouterr().out
