"""The ring-surface parametrisation behind the exact pack-clearance search (issue 38, item 7).

Independent check: the section's boundary walked here by linear interpolation between its
four corners (np.interp on the cumulative arc length), against coils.clearance's face-by-face
formula, at random arc lengths, at the corners themselves and past one perimeter (the
parametrisation is periodic); the 3-D points against their cylindrical coordinates.
"""

from __future__ import annotations

import numpy as np

from coils.clearance import Ring, ring_signed_distance, ring_surface_points

RING = Ring(axis=1, radius_m=0.21, centre_m=-0.043, width_m=0.031, depth_m=0.017)


def walked_section(ring: Ring, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(ρ, z) at arc length s from the inner-low corner counter-clockwise, by interpolating
    between the corners: inner-low, inner-high, outer-high, outer-low, inner-low."""
    r0, r1 = ring.radius_m - 0.5 * ring.depth_m, ring.radius_m + 0.5 * ring.depth_m
    z0, z1 = ring.centre_m - 0.5 * ring.width_m, ring.centre_m + 0.5 * ring.width_m
    rho_c = np.array([r0, r0, r1, r1, r0])
    z_c = np.array([z0, z1, z1, z0, z0])
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(rho_c), np.diff(z_c)))])
    t = np.mod(s, arc[-1])
    return np.interp(t, arc, rho_c), np.interp(t, arc, z_c)


def test_surface_points_walk_the_section_boundary() -> None:
    per = 2.0 * (RING.width_m + RING.depth_m)
    w, h = RING.width_m, RING.depth_m
    rng = np.random.default_rng(38)
    corners = np.array([0.0, w, w + h, 2 * w + h])
    s = np.concatenate([rng.uniform(-per, 2 * per, 500), corners, corners + per])
    phi = rng.uniform(0.0, 2.0 * np.pi, s.size)
    pts = ring_surface_points(RING, phi, s)
    rho_ref, z_ref = walked_section(RING, s)
    u, v = 0, 2  # the axes other than the ring's (y)
    assert np.allclose(np.hypot(pts[:, u], pts[:, v]), rho_ref, rtol=0, atol=1e-15), (
        "radius of each surface point = the walked boundary's ρ (interpolated corners, 1e-15 m)"
    )
    assert np.allclose(pts[:, RING.axis], z_ref, rtol=0, atol=1e-15), (
        "axial coordinate = the walked boundary's z (interpolated corners, 1e-15 m)"
    )
    assert np.allclose(np.arctan2(pts[:, v], pts[:, u]), np.angle(np.exp(1j * phi)), atol=1e-12), (
        "angle about the axis = phi (mod 2π, 1e-12 rad)"
    )
    assert np.max(np.abs(ring_signed_distance(RING, pts))) < 1e-15, (
        "every surface point at signed distance 0 (exact box distance, 1e-15 m)"
    )


def test_surface_points_broadcast_angle_by_arc_length() -> None:
    phi = np.linspace(0.0, 2.0 * np.pi, 7, endpoint=False)
    s = np.linspace(0.0, 0.09, 5)
    grid = ring_surface_points(RING, phi[:, None], s[None, :])
    flat = ring_surface_points(RING, np.repeat(phi, s.size), np.tile(s, phi.size))
    assert grid.shape == (7, 5, 3), "a (7, 1) angle by a (1, 5) arc length: (7, 5, 3) points"
    assert np.array_equal(grid.reshape(-1, 3), flat), (
        "broadcast grid = the same points listed one by one (bit for bit)"
    )
