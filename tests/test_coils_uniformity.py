"""Uniform region of an ideal Helmholtz pair and of a three-axis system; its direction."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

import coils
from spiralcap.core.errors import InputError


def on_axis_deviation(z_over_r: float) -> float:
    """B_z(z)/B_z(0) - 1 on the axis of an ideal pair (R = 1, s = 1), Biot-Savart closed form."""

    def bz(z: float) -> float:
        return (1 + (z - 0.5) ** 2) ** -1.5 + (1 + (z + 0.5) ** 2) ** -1.5

    return bz(z_over_r) / bz(0.0) - 1


@pytest.fixture(scope="module")
def ideal() -> coils.HelmholtzPair:
    return coils.HelmholtzPair(1.0, 1, "z", wire_diameter_m=1e-4)


@pytest.mark.parametrize(("tolerance", "design_md"), [(0.01, 0.31), (0.05, 0.49)])
def test_ideal_pair_region_is_set_on_the_axis(ideal, tolerance: float, design_md: float) -> None:
    region = coils.uniform_region(ideal, tolerance)
    axis_root = brentq(lambda z: on_axis_deviation(z) + tolerance, 0.05, 0.9, xtol=1e-14)
    assert region.radius_m == pytest.approx(axis_root, rel=1e-9), (
        "on-axis Biot-Savart closed form root (brentq), rel 1e-9"
    )
    assert abs(region.limiting_ray[2]) == pytest.approx(1.0, abs=1e-9), "limited on the axis"
    assert region.radius_m == pytest.approx(design_md, abs=0.005), (
        f"the usual figure for an ideal pair is about {design_md} R; within 0.005 R"
    )


def test_ideal_pair_midplane_is_more_uniform(ideal) -> None:
    rho = np.linspace(0.0, 0.5, 501)
    dev = coils.uniformity(ideal, np.column_stack([rho, 0 * rho, 0 * rho]))
    first = rho[np.argmax(np.abs(dev) > 0.01)]
    assert 0.37 < first < 0.39, "midplane +-1 % edge about 0.378 R, beyond the axial 0.314 R"
    assert np.all(dev[1:] < 0), "the field magnitude falls off in the midplane too"


def test_system_region_depends_on_field_direction(nested_system) -> None:
    system = nested_system
    per_axis = [coils.uniform_region_radius_m(system, 0.01, direction=e) for e in np.eye(3)]
    alone = [coils.uniform_region_radius_m(p, 0.01) for p in system.pairs]
    assert np.allclose(per_axis, alone, rtol=1e-9), (
        "one pair driven: the system's region is that pair's alone, rel 1e-9"
    )
    assert np.allclose(np.array(alone) / [0.4, 0.35, 0.3], alone[0] / 0.4, rtol=1e-9), (
        "scale invariance of a thin pair: radius / R is the same, rel 1e-9"
    )
    worst = coils.uniform_region(system, 0.01)
    assert worst.radius_m == pytest.approx(per_axis[2], rel=1e-12) and np.allclose(
        np.abs(worst.field_direction), [0, 0, 1]
    ), "worst static direction is along the smallest pair (z)"
    diag = [
        coils.uniform_region_radius_m(system, 0.01, direction=d) for d in ([1, 1, 0], [1, -1, 0])
    ]
    assert diag[0] == pytest.approx(diag[1], rel=1e-6), (
        "mirror symmetry y -> -y: same radius, rel 1e-6 (refined ray search)"
    )
    currents = np.array([1.0, 1.0, 0.0]) / system.centre_gains_T_per_A
    assert coils.uniform_region_radius_m(system, 0.01, currents_A=currents) == pytest.approx(
        diag[0], rel=1e-9
    ), "currents n_k/g_k are what direction= uses"
    pts = np.random.default_rng(2).normal(size=(200, 3))
    pts *= 0.999 * worst.radius_m / np.linalg.norm(pts, axis=1, keepdims=True)
    assert np.all(np.abs(coils.uniformity(system, pts, [0, 0, 1.0])) <= 0.01), (
        "every point inside the reported sphere is within tolerance"
    )


def test_off_axis_region_matches_the_previous_search_and_brentq(nested_system) -> None:
    """The vectorised direction search against the Nelder-Mead search it replaced and brentq."""
    system = nested_system
    # Radii from the Nelder-Mead refinement (xatol 1e-4 in direction) before the search was vectorised.
    nelder_mead = {(1, 0, 1): 0.10761101917857879, (1, 1, 1): 0.11333061585693169}
    for direction, old in nelder_mead.items():
        region = coils.uniform_region(system, 0.01, direction=direction)
        assert old * (1 - 2e-9) <= region.radius_m <= old * (1 + 1e-12), (
            "same radius as the Nelder-Mead search to 2e-9 (never larger: a tighter minimum)"
        )
        currents = np.asarray(direction, float) / system.centre_gains_T_per_A
        u = region.limiting_ray

        def excess(r: float, u=u, currents=currents) -> float:
            return abs(coils.uniformity(system, [r * u], currents)[0]) - 0.01

        root = brentq(excess, 0.5 * region.radius_m, 1.5 * region.radius_m, xtol=1e-15)
        assert region.radius_m == pytest.approx(root, rel=1e-12), (
            "radius is the brentq root of |dev| = tol along the limiting ray, rel 1e-12"
        )
        rng = np.random.default_rng(4)
        near = u + 1e-3 * rng.normal(size=(20, 3))
        near /= np.linalg.norm(near, axis=1, keepdims=True)
        dev = coils.uniformity(system, 0.999999 * region.radius_m * near, currents)
        assert np.all(np.abs(dev) <= 0.01), "no nearby ray leaves the tolerance before the radius"


# Radii and limiting rays from the previous search, run one tolerance per call, each pair alone
# and the system's axis directions searched over all 3-D rays (before the shared-tolerance
# search, the reuse of similar pairs and the one-pair-driven shortcut): (radius_m, ray).
_PREVIOUS = {
    "thick": {
        "system_0.01": (0.047970351700354415, (0.0, 0.0, 1.0)),
        "x_0.01": (0.11173364431066424, (6.123233995736766e-17, 1.0, 0.0)),
        "y_0.01": (0.08380023323299696, (0.0, 6.123233995736766e-17, 1.0)),
        "z_0.01": (0.04797035170035464, (0.0, 0.0, 1.0)),
        "system_0.05": (0.09490918820214797, (0.0, 0.0, 1.0)),
        "x_0.05": (0.19331788061043279, (6.123233995736766e-17, 1.0, 0.0)),
        "y_0.05": (0.14498841045782446, (0.0, 6.123233995736766e-17, 1.0)),
        "z_0.05": (0.09490918820214798, (0.0, 0.0, 1.0)),
    },
    "close": {
        "system_0.01": (0.05318225349776609, (0.0, 0.0, 1.0)),
        "x_0.01": (0.09412380755944981, (1.0, 0.0, 0.0)),
        "y_0.01": (0.06170455410030815, (0.0, 1.0, 0.0)),
        "z_0.01": (0.05318225349776593, (0.0, 0.0, 1.0)),
        "system_0.05": (0.11864252309155537, (0.0, 1.0, 0.0)),
        "x_0.05": (0.14653650370548238, (1.0, 0.0, 0.0)),
        "y_0.05": (0.11864252309155568, (0.0, 1.0, 0.0)),
        "z_0.05": (0.1287585311580255, (1.0, 0.0, 6.123233995736766e-17)),
    },
}


def _system(name: str) -> coils.ThreeAxisHelmholtz:
    H = coils.HelmholtzPair
    if name == "thick":  # thick packs, spacing off Helmholtz: some pairs limited in the midplane
        return coils.ThreeAxisHelmholtz(
            H(0.4, 400, "x", separation_m=0.44, wire_diameter_m=4e-3, filaments=(2, 3)),
            H(0.3, 400, "y", separation_m=0.33, wire_diameter_m=3e-3, filaments=(2, 3)),
            H(0.25, 300, "z", separation_m=0.22, wire_diameter_m=2e-3, filaments=(2, 2)),
        )
    return coils.ThreeAxisHelmholtz(  # equal radii, unequal spacing: the worst axis is z or y
        H(0.3, 100, "x"), H(0.3, 100, "y", separation_m=0.27), H(0.3, 100, "z", separation_m=0.36)
    )


@pytest.mark.parametrize("name", sorted(_PREVIOUS))
def test_shared_tolerance_search_matches_the_previous_search(name: str) -> None:
    """Both tolerances in one search (one scan per ray, roots and refinements in lockstep)."""
    system, previous, tols = _system(name), _PREVIOUS[name], (0.01, 0.05)
    found = {
        **{f"system_{t}": r for t, r in zip(tols, coils.uniform_regions(system, tols))},
        **{
            f"{p.axis}_{t}": r
            for p, regions in zip(system.pairs, coils.pair_uniform_regions(system.pairs, tols))
            for t, r in zip(tols, regions)
        },
    }
    for key, (radius, ray) in previous.items():
        assert found[key].radius_m == pytest.approx(radius, rel=1e-12), (
            f"{name} {key}: radius as the previous one-tolerance search, rel 1e-12"
        )
        assert np.allclose(found[key].limiting_ray, ray, rtol=0, atol=1e-12), (
            f"{name} {key}: same limiting ray as the previous search, abs 1e-12"
        )


def test_similar_pairs_are_searched_once(nested_system, monkeypatch) -> None:
    """Pairs equal in units of their radius: one search, scaled and rotated, as searched alone."""
    import sys

    module = sys.modules["coils.uniformity"]
    tols = (0.01, 0.05)
    alone = [coils.pair_uniform_regions([p], tols)[0] for p in nested_system.pairs]
    calls = []
    search = module._radius_axisymmetric
    monkeypatch.setattr(
        module, "_radius_axisymmetric", lambda *a, **k: calls.append(a) or search(*a, **k)
    )
    together = coils.pair_uniform_regions(nested_system.pairs, tols)
    assert len(calls) == 1, "the three nested pairs are similar (R, N and spacing scale alike)"
    for one, many in zip(alone, together):
        for a, b in zip(one, many):
            assert b.radius_m == pytest.approx(a.radius_m, rel=1e-12), (
                "reused radius equals the pair's own search, rel 1e-12"
            )
            assert np.allclose(b.limiting_ray, a.limiting_ray, atol=1e-12), "same ray, abs 1e-12"
            assert np.array_equal(b.field_direction, a.field_direction), "along the pair's axis"
    calls.clear()
    thick = coils.pair_uniform_regions(_system("thick").pairs, tols)
    assert len(calls) == 3 and len(thick) == 3, "packs not similar bit for bit: each searched"


def test_pair_regions_must_be_for_the_same_tolerances(nested_system) -> None:
    pairs = coils.pair_uniform_regions(nested_system.pairs, (0.01,))
    with pytest.raises(InputError, match="pair_regions"):
        coils.uniform_regions(nested_system, (0.05,), pair_regions=pairs)


@pytest.mark.parametrize("name", ["thick", "close"])
def test_ranking_block_by_block_equals_the_whole_grid(name: str, monkeypatch) -> None:
    """The direction ranking stops scanning outward early; the candidates are the whole grid's."""
    import sys

    module = sys.modules["coils.uniformity"]
    system, tols = _system(name), (0.002, 0.01, 0.05, 0.2)
    gains = system.centre_gains_T_per_A
    currents = [n / gains for n in module._SYMMETRY_DIRECTIONS]
    r_max = min(p.radius_m for p in system.pairs)
    early = module._rank_directions(system, currents, tols, r_max)
    monkeypatch.setattr(module, "_RANK_BLOCK", module._RADIAL_STEPS)
    assert early == module._rank_directions(system, currents, tols, r_max), (
        "same candidate directions as ranking on the whole radial grid"
    )
