"""Loop and Helmholtz fields against magpylib, the closed-form centre field, CasADi, Maxwell."""

from __future__ import annotations

import casadi as ca
import magpylib
import numpy as np
import pytest
import scipy.constants
from scipy.spatial.transform import Rotation

import coils
from spiralcap.core import backend as bk
from spiralcap.core.constants import MU0_T_m_per_A

#: magpylib uses scipy's mu_0 (CODATA 2022); we use CODATA 2018. Rescale to compare geometry.
MU0_RATIO = MU0_T_m_per_A / scipy.constants.mu_0
_TURN_TO = {
    "x": Rotation.from_euler("y", 90, degrees=True),
    "y": Rotation.from_euler("x", -90, degrees=True),
    "z": None,
}


def magpylib_system(system: coils.ThreeAxisHelmholtz, currents_A) -> magpylib.Collection:
    """The six mean-turn filaments as magpylib Circles carrying N I ampere-turns."""
    loops = []
    for pair, current in zip(system.pairs, currents_A, strict=True):
        e = np.eye(3)[pair.axis_index]
        for sign in (-0.5, 0.5):
            loops.append(
                magpylib.current.Circle(
                    current=pair.turns * current,
                    diameter=2.0 * pair.radius_m,
                    position=sign * pair.separation_m * e,
                    orientation=_TURN_TO[pair.axis],
                )
            )
    return magpylib.Collection(*loops)


def random_system(rng: np.random.Generator) -> coils.ThreeAxisHelmholtz:
    """A nested three-axis system with random radii, turns and separations (thin wire)."""
    r_z = rng.uniform(0.15, 0.35)
    radii = {"z": r_z, "y": r_z * rng.uniform(1.1, 1.3)}
    radii["x"] = radii["y"] * rng.uniform(1.1, 1.3)
    pairs = {
        ax: coils.HelmholtzPair(
            radii[ax],
            int(rng.integers(50, 500)),
            ax,
            separation_m=radii[ax] * rng.uniform(0.8, 1.2),
            wire_diameter_m=1e-3,
        )
        for ax in "xyz"
    }
    return coils.ThreeAxisHelmholtz(**pairs)


def test_pair_centre_field_is_helmholtz_closed_form() -> None:
    for radius, turns in ((0.3, 300), (0.123, 77), (1.7, 1)):
        pair = coils.HelmholtzPair(radius, turns, wire_diameter_m=1e-4)
        expected = (4 / 5) ** 1.5 * MU0_T_m_per_A * turns / radius
        assert pair.centre_field_per_amp_T_per_A == pytest.approx(expected, rel=1e-12), (
            "(4/5)^{3/2} mu0 N / R (Helmholtz 1849 / any textbook), rel 1e-12"
        )
        b = pair.field(np.zeros(3), 2.5)
        assert b[2] == pytest.approx(2.5 * expected, rel=1e-12) and b[0] == b[1] == 0.0, (
            "field() at the centre = g I along the axis, rel 1e-12"
        )


@pytest.mark.parametrize("seed", range(5))
def test_system_field_matches_magpylib(seed: int) -> None:
    rng = np.random.default_rng(seed)
    system = random_system(rng)
    currents = rng.uniform(-3.0, 3.0, 3)
    r_min = min(p.radius_m for p in system.pairs)
    r_max = max(p.radius_m for p in system.pairs)
    inside = rng.uniform(-0.6, 0.6, (300, 3)) * r_min
    on_axes = np.vstack([np.outer(rng.uniform(-1.5, 1.5, 20) * r_max, e) for e in np.eye(3)])
    direction = rng.normal(size=(300, 3))
    direction /= np.linalg.norm(direction, axis=1, keepdims=True)
    outside = direction * rng.uniform(1.6, 4.0, (300, 1)) * r_max
    points = np.vstack([inside, on_axes, outside])
    ours = system.field(points, currents)
    ref = magpylib_system(system, currents).getB(points) * MU0_RATIO
    rel = np.linalg.norm(ours - ref, axis=1) / np.linalg.norm(ref, axis=1)
    assert rel.max() < 1e-9, (
        f"magpylib 6 Circle (Ortner et al. 2023), |dB|/|B| < 1e-9; worst {rel.max():.2e}"
    )


def test_loop_field_matches_magpylib_on_and_off_axis() -> None:
    rng = np.random.default_rng(7)
    radius, z0 = 0.25, 0.04
    rho = np.concatenate([np.zeros(20), rng.uniform(1e-9, 1e-6, 20), rng.uniform(0, 0.8, 200)])
    z = rng.uniform(-0.5, 0.5, rho.size)
    b_rho, b_z = coils.loop_field(radius, z0, rho, z)
    loop = magpylib.current.Circle(current=1.0, diameter=2 * radius, position=(0, 0, z0))
    ref = loop.getB(np.column_stack([rho, np.zeros_like(rho), z])) * MU0_RATIO
    scale = np.hypot(ref[:, 0], ref[:, 2])
    assert (
        np.max(np.abs(b_rho - ref[:, 0]) / scale) < 1e-9
        and np.max(np.abs(b_z - ref[:, 2]) / scale) < 1e-9
    ), "magpylib Circle, rel 1e-9 of |B|"
    assert np.all(b_rho[:20] == 0.0), "B_rho exactly 0 on the axis (symmetry)"


def test_loop_on_axis_is_biot_savart_closed_form() -> None:
    z = np.linspace(-1.0, 1.0, 41)
    b_rho, b_z = coils.loop_field(0.3, 0.1, 0.0, z)
    expected = MU0_T_m_per_A * 0.3**2 / (2 * (0.3**2 + (z - 0.1) ** 2) ** 1.5)
    assert np.allclose(b_z, expected, rtol=1e-13, atol=0), (
        "on-axis mu0 R^2 / (2 (R^2 + z^2)^{3/2}) (Biot-Savart), rel 1e-13"
    )
    assert np.all(b_rho == 0.0), "B_rho exactly 0 on the axis (symmetry)"


def test_filament_pack_converges_to_itself_and_near_thin_coil() -> None:
    kw = {"radius_m": 0.3, "turns": 300, "wire_diameter_m": 2.5e-3}
    thin = coils.HelmholtzPair(**kw)
    p4 = coils.HelmholtzPair(**kw, filaments=(4, 4))
    p6 = coils.HelmholtzPair(**kw, filaments=(6, 6))
    pts = np.array([[0.0, 0.0, 0.0], [0.05, 0.02, 0.08], [0.1, 0.0, 0.0]])
    b4, b6 = p4.field(pts, 1.0), p6.field(pts, 1.0)
    assert np.max(np.abs(b4 - b6)) < 1e-10 * np.abs(b6).max(), (
        "Gauss-Legendre pack quadrature 4x4 vs 6x6 converged, rel 1e-10"
    )
    c_over_r = thin.winding_pack_side_m / thin.radius_m
    assert np.max(np.abs(thin.field(pts, 1.0) - b6)) < c_over_r**2 * np.abs(b6).max(), (
        "thin-filament vs real pack differ at order (c/R)^2 (multipole expansion)"
    )


def test_numpy_and_casadi_agree() -> None:
    rng = np.random.default_rng(3)
    system = random_system(rng)
    f = system.casadi_field_function()
    currents = rng.uniform(-2, 2, 3)
    pts = np.vstack(
        [
            rng.uniform(-0.5, 0.5, (40, 3)) * system.z.radius_m,
            np.zeros((1, 3)),
            [[0, 0, 0.05], [0.05, 0, 0], [1e-9, 0, 0.03]],
        ]
    )
    ref = system.field(pts, currents)
    for p, b in zip(pts, ref, strict=True):
        cas = np.array(f(p, currents)).ravel()
        assert np.max(np.abs(cas - b)) <= 1e-12 * np.linalg.norm(b) + 1e-30, (
            "CasADi AGM path vs numpy/scipy path, rel 1e-12 (CONTRIBUTING)"
        )
        assert np.max(np.abs(system.point_field(p, currents) - b)) <= 1e-12 * np.linalg.norm(b), (
            "compiled single-point CasADi field vs numpy field, 1e-12 relative"
        )
    g = system.casadi_field_matrix_function()
    assert np.allclose(np.array(g(pts[3])), system.field_matrix(pts[3:4])[0], rtol=1e-12, atol=0), (
        "G(p) CasADi vs numpy, rel 1e-12"
    )
    m = np.concatenate([np.linspace(0, 0.99, 50), [0.999999]])
    sym = ca.SX.sym("m")
    agm = ca.Function("ke", [sym], list(bk.ellipke(sym)))
    k_ca, e_ca = (np.array(v).ravel() for v in agm.map(m.size)(m))
    k_np, e_np = bk.ellipke(m)
    assert np.allclose(k_ca, k_np, rtol=1e-12, atol=0) and np.allclose(
        e_ca, e_np, rtol=1e-12, atol=0
    ), "AGM (7 steps) vs scipy ellipk/ellipe, rel 1e-12"


def test_loop_field_runs_on_casadi_symbols() -> None:
    rho, z = ca.SX.sym("rho"), ca.SX.sym("z")
    b_rho, b_z = coils.loop_field(0.2, 0.0, rho, z)
    f = ca.Function(
        "f", [rho, z], [b_rho, b_z, ca.jacobian(ca.vertcat(b_rho, b_z), ca.vertcat(rho, z))]
    )
    for r in (0.0, 1e-12, 1e-6, 0.05):
        br, bz, jac = f(r, 0.07)
        ref = coils.loop_field(0.2, 0.0, r, 0.07)
        assert abs(float(br) - ref[0]) <= 1e-12 * abs(ref[1]) and float(bz) == pytest.approx(
            ref[1], rel=1e-12
        ), "CasADi vs numpy loop_field, 1e-12"
        assert np.all(np.isfinite(np.array(jac))), f"finite Jacobian at rho = {r} (guarded)"


def test_div_and_curl_vanish_inside_workspace() -> None:
    rng = np.random.default_rng(11)
    system = random_system(rng)
    fj = system.casadi_field_jacobian_function()
    currents = rng.uniform(-2, 2, 3)
    r_min = system.z.radius_m
    pts = np.vstack(
        [rng.uniform(-0.5, 0.5, (30, 3)) * r_min, [[0, 0, 0.3 * r_min]], [[1e-10, 0, 0.2 * r_min]]]
    )
    for p in pts:
        b, jac = (np.array(v) for v in fj(p, currents))
        scale = np.linalg.norm(b) / r_min
        assert abs(np.trace(jac)) < 1e-9 * scale, "div B = 0 (Maxwell), < 1e-9 |B|/R"
        assert np.max(np.abs(jac - jac.T)) < 1e-9 * scale, (
            "curl B = 0 in free space (Ampere), antisymmetric part < 1e-9 |B|/R"
        )
        h = 1e-5 * r_min
        fd = np.column_stack(
            [
                (system.field(p + h * e, currents) - system.field(p - h * e, currents))[0] / (2 * h)
                for e in np.eye(3)
            ]
        )
        assert np.max(np.abs(fd - jac)) < 1e-6 * scale, (
            "exact CasADi Jacobian vs central differences of the numpy field, 1e-6 |B|/R"
        )


def test_loop_terms_numpy_matches_casadi_agm_on_both_branches() -> None:
    """loop_terms on numpy (scipy's Cephes K, E; K from 1 - m given exactly) against the same
    formulas on CasADi (the AGM), on and near the axis (series branch of g) and away from it."""
    import casadi as ca

    from coils.loop import SERIES_BELOW, loop_terms

    rng = np.random.default_rng(5)
    radius = np.array([[0.3], [0.35], [0.4]])
    rho = np.concatenate([[0.0, 1e-9, 1e-4], rng.uniform(0.0, 0.6, 400)])
    dz = np.concatenate([[0.0, 0.1, -0.2], rng.uniform(-0.4, 0.4, 400)])
    rho2, dz2 = np.broadcast_to(rho, (3, rho.size)).copy(), np.broadcast_to(dz, (3, dz.size)).copy()
    s_np, bz_np = loop_terms(radius, dz2, rho2, rho2 * rho2)
    r, z, q = ca.SX.sym("r"), ca.SX.sym("z"), ca.SX.sym("q")
    f = ca.Function("terms", [q, z, r], list(loop_terms(q, z, r, r * r)))
    s_ca, bz_ca = (
        np.asarray(v).reshape(rho2.shape)
        for v in f.map(rho2.size)(
            np.broadcast_to(radius, rho2.shape).ravel(), dz2.ravel(), rho2.ravel()
        )
    )
    m = 4 * radius * rho2 / ((radius + rho2) ** 2 + dz2**2)
    assert (m < SERIES_BELOW).sum() >= 3 and (m >= SERIES_BELOW).sum() > 100, "both branches hit"
    b_abs = np.hypot(bz_ca, rho2 * s_ca)
    assert np.all(np.abs(bz_np - bz_ca) <= 1e-12 * b_abs), "numpy vs CasADi AGM B_z, 1e-12 |B|"
    assert np.all(np.abs(rho2 * (s_np - s_ca)) <= 1e-12 * b_abs), (
        "numpy vs CasADi AGM B_rho, 1e-12 |B|"
    )
    assert np.allclose(s_np[:, :3], s_ca[:, :3], rtol=1e-12, atol=0), (
        "B_rho/rho on and next to the axis (series branch), rel 1e-12"
    )


def test_filament_order_does_not_matter(nested_system) -> None:
    """Grouped filaments and a shuffled list of the same filaments give one field."""
    from coils.filaments import FilamentSet

    fs = nested_system.filament_set
    order = np.random.default_rng(8).permutation(len(fs.radii_m))
    shuffled = FilamentSet(
        axes=fs.axes[order],
        radii_m=fs.radii_m[order],
        centres_m=fs.centres_m[order],
        turns=fs.turns[order],
        columns=fs.columns[order],
        column_axes=fs.column_axes,
    )
    pts = np.random.default_rng(9).uniform(-0.2, 0.2, (3000, 3))
    currents = np.array([[1.3], [-0.7], [2.1]])
    a, b = fs.field(pts, currents), shuffled.field(pts, currents)
    assert np.allclose(a, b, rtol=1e-13, atol=1e-13 * np.abs(a).max()), (
        "sum over filaments is order-independent, rel 1e-13"
    )
    assert np.allclose(fs.field_matrix(pts), shuffled.field_matrix(pts), rtol=1e-13, atol=1e-18)


def test_filament_sets_take_keywords_only(nested_system) -> None:
    """The size field comes last in a filament set (after the shared ones of
    coils.filaments.AxisFilaments): a positional call would put it in the wrong place, so none
    is taken."""
    fs = nested_system.filament_set
    with pytest.raises(TypeError):
        type(fs)(fs.axes, fs.radii_m, fs.centres_m, fs.turns, fs.columns, fs.column_axes)


def _thick_solenoid_centre_field(pair: coils.HelmholtzPair) -> float:
    """Centre field per ampere of the two packs with uniform current density, closed form.

    On the axis of a coil of radii a1..a2 between z1 and z2 (from the field point), current
    density J: B = μ0 J/2 [z ln((a2 + sqrt(a2² + z²)) / (a1 + sqrt(a1² + z²)))] from z1 to z2
    (Montgomery, *Solenoid Magnet Design*, 1969, eq. 1.5; the integral of the loop's axial
    field over the section), J = N I / (w h)."""
    w, h, r = pair.winding_pack_width_m, pair.winding_pack_depth_m, pair.radius_m
    a1, a2 = r - 0.5 * h, r + 0.5 * h

    def f(z: float) -> float:
        return z * np.log((a2 + np.hypot(a2, z)) / (a1 + np.hypot(a1, z)))

    half = 0.5 * pair.separation_m
    one = MU0_T_m_per_A * pair.turns / (w * h) / 2.0 * (f(half + 0.5 * w) - f(half - 0.5 * w))
    return 2.0 * one


@pytest.mark.parametrize(
    ("radius", "turns", "wire_mm", "aspect"),
    [(0.43, 400, 3.0, 1.0), (0.35, 350, 2.5, 1.0), (0.28, 300, 2.36, 1.0), (0.2, 500, 2.0, 3.0)],
)
def test_pack_field_per_amp_is_the_thick_solenoid_closed_form(radius, turns, wire_mm, aspect):
    """Issue 26 (e): the pack's centre field per ampere (current spread over the winding pack)
    against the closed form of a thick solenoid (Montgomery 1969), 1e-10; the field model's
    gain (one loop at the mean radius each) is what it says: (4/5)^{3/2} μ0 N / R at s = R."""
    pair = coils.HelmholtzPair(
        radius, turns, wire_diameter_m=wire_mm * 1e-3, pack_aspect=aspect, separation_m=radius
    )
    assert pair.pack_centre_field_per_amp_T_per_A == pytest.approx(
        _thick_solenoid_centre_field(pair), rel=1e-10
    ), "uniform current over the pack vs the thick-solenoid closed form (Montgomery), 1e-10"
    loop = (4 / 5) ** 1.5 * MU0_T_m_per_A * turns / radius
    assert pair.centre_field_per_amp_T_per_A == pytest.approx(loop, rel=1e-12), (
        "the field model's gain is the one-loop Helmholtz closed form, 1e-12"
    )


def test_coils_json_labels_the_loop_gain_and_gives_the_pack_gain(run_cli, capsys) -> None:
    """Issue 26 (e): `coils --json` gives the field model's gain (one loop per coil: the
    field at the current limit is it times the current) and the pack's gain beside it (the
    thick-solenoid closed form, 1e-10)."""
    import json

    from spiralcap.assemble.coils import build_coils
    from spiralcap.design import load_design

    assert run_cli(["coils", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    system = build_coils(load_design(None))
    for pair in system.pairs:
        a = out["axes"][pair.axis]
        loop = (
            MU0_T_m_per_A
            * pair.turns
            * pair.radius_m**2
            / (pair.radius_m**2 + (0.5 * pair.separation_m) ** 2) ** 1.5
        )
        assert a["field_per_amp_T_per_A"] == pytest.approx(loop, rel=1e-12), (
            "field_per_amp is two loops at the mean radius (Biot-Savart on the axis), 1e-12"
        )
        assert a["field_amplitude_T"] == pytest.approx(
            a["field_per_amp_T_per_A"] * out["current_amplitude_A"], rel=1e-12
        ), "the field shown at the current limit is that gain times the current"
        assert a["pack_field_per_amp_T_per_A"] == pytest.approx(
            _thick_solenoid_centre_field(pair), rel=1e-10
        ), "pack_field_per_amp: thick-solenoid closed form (Montgomery), 1e-10"
        assert 1e-4 < 1.0 - a["pack_field_per_amp_T_per_A"] / a["field_per_amp_T_per_A"] < 1e-3, (
            "the pack's gain is a few 1e-4 below the loop's for the built-in pairs"
        )


def test_fields_computed_on_several_threads_are_the_serial_ones() -> None:
    """The numpy path reuses scratch buffers; a Dask worker runs tasks on threads, so each thread
    must have its own (a shared dict gave wrong fields, up to 1.6e20 relative, and errors)."""
    from concurrent.futures import ThreadPoolExecutor

    pairs = [coils.HelmholtzPair(0.3 + 0.01 * i, 300, filaments=(4, 4)) for i in range(4)]
    pts = np.random.default_rng(0).uniform(-0.1, 0.1, (2000, 3))
    ref = [p.filament_set.field(pts, np.array([[1.0]])) for p in pairs]

    def field(i: int) -> np.ndarray:
        return pairs[i % 4].filament_set.field(pts, np.array([[1.0]]))

    with ThreadPoolExecutor(4) as pool:
        out = list(pool.map(field, range(80)))
    for i, b in enumerate(out):
        assert np.array_equal(b, ref[i % 4]), "a field on a thread == the same field serially"
