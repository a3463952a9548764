"""Capsule geometry: body, spiral relations (Zhou et al. 2013 II.A convention), magnet fit."""

from __future__ import annotations

import math

import numpy as np
import pytest

import capsule
from spiralcap.core.errors import InputError

D_H = 12e-3  # 11 mm PillCam SB2 + 1 mm wire (Zhou et al. 2013, section II.A)
L_W = 15e-3  # wound length of the paper's capsules
#: The paper's PillCam SB2 shell, 11 x 26 mm (Zhou et al. 2013 II.A); 0.5 mm wall (assumed).
PAPER_BODY = {"diameter_m": 11e-3, "length_m": 26e-3, "shell_thickness_m": 0.5e-3}
#: The paper's spiral: one 1 mm wire over 15 mm (II.A).
PAPER_SPIRAL = {"wire_diameter_m": 1e-3, "wound_length_m": 15e-3, "starts": 1}


def paper_body() -> capsule.Body:
    return capsule.Body(**PAPER_BODY)


def paper_spiral(helical_angle_rad, **changes) -> capsule.Spiral:
    return capsule.Spiral(helical_angle_rad, **{**PAPER_SPIRAL, **changes})


def test_pillcam_sb2_body() -> None:
    b = paper_body()
    assert (b.diameter_m, b.length_m) == (11e-3, 26e-3), (
        "PillCam SB2 11 x 26 mm (Zhou et al. 2013 II.A), exact"
    )
    assert b.radius_m == b.end_radius_m == 5.5e-3, "hemispherical ends: radius D/2, exact"
    assert b.cylinder_length_m == pytest.approx(15e-3, rel=1e-12), (
        "26 - 11 = 15 mm, the paper's wound length (II.A), rel 1e-12"
    )
    assert b.inner_radius_m == pytest.approx(5e-3, rel=1e-12), "5.5 - 0.5 mm by hand, rel 1e-12"


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"diameter_m": 0.0}, "diameter_m"),
        ({"diameter_m": -1e-3}, "diameter_m"),
        ({"length_m": 11e-3}, "length_m"),
        ({"length_m": float("nan")}, "length_m"),
        ({"shell_thickness_m": 5.5e-3}, "shell_thickness_m"),
        ({"shell_thickness_m": 0.0}, "shell_thickness_m"),
    ],
)
def test_body_rejects_bad_sizes(kwargs: dict, name: str) -> None:
    with pytest.raises(InputError) as err:
        capsule.Body(**{**PAPER_BODY, **kwargs})
    assert err.value.key == name, f"InputError must name {name} (CONTRIBUTING: errors name key)"


def test_lead_is_advance_of_a_helix_at_the_helical_angle() -> None:
    """Independent source: the parametric helix (R cos t, R sin t, c t) has tangent angle
    atan(c / R) to the cross-section plane; its advance per revolution is 2 pi c."""
    for deg in (5.0, 10.0, 15.0, 20.0, 45.0):
        alpha = math.radians(deg)
        lead = capsule.lead_m(alpha, D_H)
        c = lead / (2 * math.pi)
        t = 0.7
        tangent = np.array([-D_H / 2 * math.sin(t), D_H / 2 * math.cos(t), c])
        angle = math.asin(tangent[2] / np.linalg.norm(tangent))
        assert angle == pytest.approx(alpha, rel=1e-12), (
            f"helix tangent angle vs alpha at {deg} deg (parametric helix), rel 1e-12"
        )
        assert lead == pytest.approx(math.pi * D_H * math.tan(alpha), rel=1e-15), (
            "pi D_h tan(alpha), unrolled helix, rel 1e-15"
        )
    assert capsule.lead_m(math.radians(10), D_H) == pytest.approx(6.6473706e-3, rel=1e-7), (
        "hand value pi * 12 mm * tan(10 deg) = 6.6473706 mm, rel 1e-7"
    )


def test_helix_diameter_is_wire_centre_line() -> None:
    assert capsule.helix_diameter_m(11e-3, 1e-3) == pytest.approx(12e-3, rel=1e-15), (
        "D + d_w for a wire lying on the body (Zhou et al. 2013 II.A), rel 1e-15"
    )


def test_footprint_is_width_of_oblique_cut_of_the_wire() -> None:
    """Independent source: a point (x, 0, 0) of the cross-section plane is inside a wire of
    radius r whose axis is at alpha to the plane iff its distance |x| sin(alpha) to the axis
    <= r; solve the boundary numerically."""
    from scipy.optimize import brentq

    r = 0.5e-3
    for deg in (5.0, 10.0, 20.0, 60.0):
        alpha = math.radians(deg)
        axis = np.array([math.cos(alpha), 0.0, math.sin(alpha)])
        x_edge = brentq(
            lambda x, axis=axis: np.linalg.norm(np.cross([x, 0, 0], axis)) - r, 0.0, 1.0
        )
        assert capsule.footprint_width_m(alpha, 2 * r) == pytest.approx(2 * x_edge, rel=1e-9), (
            f"d_w/sin(alpha) vs numerical section of a round wire at {deg} deg, rel 1e-9"
        )


def test_turns_and_footprint_fall_as_the_angle_grows() -> None:
    alpha = np.radians(np.linspace(2.0, 60.0, 200))
    turns = capsule.spiral_turns(alpha, D_H, L_W)
    width = capsule.footprint_width_m(alpha, 1e-3)
    assert np.all(np.diff(turns) < 0), (
        "Zhou et al. 2013 II.A/II.C: smaller angle, more turns (strictly monotone, exact)"
    )
    assert np.all(np.diff(width) < 0), (
        "Zhou et al. 2013 II.C: smaller angle, larger raised section (strictly monotone, exact)"
    )
    # The paper's four capsules: 5, 10, 15, 20 deg on 15 mm, all at least one turn.
    paper = capsule.spiral_turns(np.radians([5.0, 10.0, 15.0, 20.0]), D_H, L_W)
    assert np.all(paper > 1.0), (
        "Fig. 1 of Zhou et al. 2013 shows >= one turn on every capsule (hand: 4.55 ... 1.09)"
    )


def test_max_angle_for_turns_round_trips() -> None:
    for n in (0.5, 1.0, 2.0, 4.0):
        a = capsule.max_helical_angle_for_turns_rad(D_H, L_W, n)
        assert capsule.spiral_turns(a, D_H, L_W) == pytest.approx(n, rel=1e-12), (
            f"turns at atan(L_w/(n pi D_h)) equal n = {n} (definition of turns), rel 1e-12"
        )
    assert capsule.max_helical_angle_for_turns_rad(D_H, L_W, 0.0) == pytest.approx(math.pi / 2), (
        "min_turns = 0 switches the rule off: pi/2 (atan2(L_w, 0)), rel 1e-6, no warning"
    )


def test_clearance_angle_makes_neighbouring_wires_touch() -> None:
    for starts in (1, 2, 3):
        a = capsule.min_helical_angle_for_clearance_rad(D_H, 1e-3, starts)
        gap = capsule.lead_m(a, D_H) / starts * math.cos(a)
        assert gap == pytest.approx(1e-3, rel=1e-12), (
            f"perpendicular spacing (lead/n) cos(alpha) = d_w at the limit, n = {starts}, rel 1e-12"
        )


def test_spiral_dataclass_convenience() -> None:
    body = paper_body()
    s = paper_spiral(math.radians(10.0), starts=2)
    assert s.helix_diameter_m(body) == pytest.approx(D_H, rel=1e-15), "D + d_w, rel 1e-15"
    assert s.wire_spacing_m(body) == pytest.approx(s.lead_m(body) / 2, rel=1e-15), (
        "axial pitch between wires = lead / starts (Zhou et al. 2013 II.A), rel 1e-15"
    )
    assert s.helical_angle_deg == pytest.approx(10.0, rel=1e-15), "rad -> deg, rel 1e-15"
    for value in (np.float64(0.2), np.array(0.2), np.float32(0.2)):
        assert paper_spiral(value).helical_angle_rad == pytest.approx(0.2, rel=1e-7), (
            "an optimiser's numpy scalar result is a valid angle (float32 rounding, rel 1e-7)"
        )
    for bad in (
        {"helical_angle_rad": 0.0},
        {"helical_angle_rad": math.pi / 2},
        {"helical_angle_rad": True},
        {"helical_angle_rad": np.array([0.1, 0.2])},
        {"helical_angle_rad": 0.1, "wire_diameter_m": 0.0},
        {"helical_angle_rad": 0.1, "starts": 0},
    ):
        with pytest.raises(InputError):
            capsule.Spiral(**{**PAPER_SPIRAL, **bad})


def _fits_by_distance_to_axis_segment(r_in: float, l_cyl: float, d: float, length: float) -> bool:
    """Independent formulation: the cavity is every point within r_in of the axis segment
    [-l_cyl/2, l_cyl/2] (a convex 'stadium' solid); a coaxial cylinder fits iff its rim
    corner (d/2, l/2) does."""
    dz = max(0.5 * length - 0.5 * l_cyl, 0.0)
    return math.hypot(0.5 * d, dz) <= r_in


def test_magnet_fit_matches_distance_to_axis_segment() -> None:
    body = paper_body()
    rng = np.random.default_rng(7)
    for d, length in rng.uniform([0.5e-3, 0.5e-3], [12e-3, 30e-3], size=(400, 2)):
        m = capsule.Magnet(d, length, 1.3)
        expected = _fits_by_distance_to_axis_segment(
            body.inner_radius_m, body.cylinder_length_m, d, length
        )
        assert (capsule.magnet_fit_problem(body, m) is None) == expected, (
            f"fit of {d * 1e3:.3f} x {length * 1e3:.3f} mm vs stadium-solid distance test, exact"
        )


def test_magnet_fit_names_the_size_at_fault() -> None:
    body = paper_body()
    assert capsule.magnet_fit_problem(body, capsule.Magnet(6e-3, 10e-3, 1.3)) is None, (
        "default 6 x 10 mm magnet fits a 10 mm cavity (hand)"
    )
    wide = capsule.magnet_fit_problem(body, capsule.Magnet(20e-3, 10e-3, 1.3))
    long_ = capsule.magnet_fit_problem(body, capsule.Magnet(6e-3, 30e-3, 1.3))
    assert wide is not None and "diameter" in wide, wide
    assert long_ is not None and "length" in long_ and "diameter" not in long_, long_
    # Edge: full-width magnet may be as long as the cylindrical part (hand: 10 x 15 mm).
    assert capsule.magnet_fit_problem(body, capsule.Magnet(10e-3, 15e-3, 1.3)) is None, (
        "10 x 15 mm just fits (corner on the hemisphere joint), rel tol 1e-9"
    )
    assert capsule.magnet_fit_problem(body, capsule.Magnet(10e-3, 15.01e-3, 1.3)) is not None


def test_geometry_problems_of_a_capsule() -> None:
    body, magnet = paper_body(), capsule.Magnet(6e-3, 10e-3, 1.3)
    fields = {
        f
        for f, _ in capsule.geometry_problems(
            body,
            paper_spiral(math.radians(1.0), wire_diameter_m=3e-3, wound_length_m=16e-3),
            capsule.Magnet(20e-3, 10e-3, 1.3),
        )
    }
    assert fields == {
        "magnet.diameter_m",
        "spiral.wire_diameter_m",
        "spiral.wound_length_m",
        "spiral.helical_angle_rad",
    }, fields
    with pytest.raises(InputError) as err:
        capsule.Capsule(body, paper_spiral(0.2, wound_length_m=20e-3), magnet)
    assert err.value.key == "spiral.wound_length_m"
