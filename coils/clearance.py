"""Winding packs as solids: exact signed distance, clearance between pairs, clearance to a bore.

Each coil of a pair is a ring of rectangular section: the set of points whose cylindrical
coordinates about the pair's axis, (ρ, z), lie in the rectangle
``[R - h/2, R + h/2] x [c - w/2, c + w/2]`` (mean radius R, radial depth h, axial width w, mid-plane
at z = c = ±s/2). A solid of revolution's distance from a point is the distance within the
point's meridian half-plane, so the signed distance of a ring is exactly the 2-D signed
distance of (ρ, z) to that rectangle (:func:`ring_signed_distance`; h < 2R keeps the rectangle
off the axis).

Two rings about perpendicular axes have no closed-form distance. :func:`ring_distance_m`
minimises the exact signed distance of ring B over the surface of ring A (the least distance of
two disjoint solids is the least distance of one's surface to the other; negative: they
overlap, by at least that depth): a 720 x 64 grid over A's surface (angle x perimeter of the
section), then the best cells refined by zooming grids until a cell is below 1e-9 m (the distance then to ~1e-12 m).

A square pair's coil is a :class:`Frame`: the square annulus ``h - d/2 <= max(|u|, |v|) <= h + d/2``
(half side h of the mean turn, depth d) extruded over the axial width; its exact signed
distance is the 2-D one of the annulus (the difference of two squares, exact as
max(sdf_outer, -sdf_inner)) extruded exactly (:func:`frame_signed_distance`). A frame is also the
union of four axis-aligned bars, so two frames are exactly as far apart as their closest pair of
bars (box to box in closed form, :func:`frame_distance_m`); a ring and a frame go through the
ring's surface search with the frame's signed distance.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = [
    "Frame",
    "Ring",
    "bore_clearance_m",
    "frame_bars",
    "frame_distance_m",
    "frame_signed_distance",
    "nearest_point_on_frame",
    "nearest_point_on_ring",
    "outer_box_m",
    "pack_clearance_m",
    "pack_clearances_m",
    "pack_closest_points",
    "pack_distance_m",
    "pair_extent_m",
    "pair_packs",
    "pair_rings",
    "ring_distance_m",
    "ring_signed_distance",
    "ring_surface_points",
    "torus_clearance_bound_m",
]

_GRID = (720, 64)
_REFINE_BEST = 4
_REFINE_STEPS = 32


@dataclass(frozen=True)
class Ring:
    """One winding pack as a solid ring (SI).

    Parameters
    ----------
    axis : int
        Axis index: 0, 1, 2 for a ring about x, y, z.
    radius_m : float
        Mean radius R of the section's centre, m.
    centre_m : float
        Axial position c of the section's mid-plane, m.
    width_m : float
        Axial width w of the section, m.
    depth_m : float
        Radial depth h of the section, m (h < 2R).
    """

    axis: int
    radius_m: float
    centre_m: float
    width_m: float
    depth_m: float

    @property
    def volume_m3(self) -> float:
        """2π R w h (Pappus), m³."""
        return 2.0 * math.pi * self.radius_m * self.width_m * self.depth_m


def pair_rings(pair: Any) -> tuple[Ring, Ring]:
    """The two packs of a :class:`coils.HelmholtzPair` at ∓s/2 along its axis.

    Parameters
    ----------
    pair : HelmholtzPair
        The pair (its radius, spacing and winding pack).

    Returns
    -------
    tuple of Ring
        The coil at -s/2 and the coil at +s/2 (SI).
    """
    half = 0.5 * pair.spacing_m
    return tuple(  # type: ignore[return-value]
        Ring(
            pair.axis_index,
            pair.radius_m,
            sign * half,
            pair.winding_pack_width_m,
            pair.winding_pack_depth_m,
        )
        for sign in (-1.0, 1.0)
    )


@dataclass(frozen=True)
class Frame:
    """One square or rectangular winding pack as a solid frame (SI).

    Parameters
    ----------
    axis : int
        Axis index: 0, 1, 2 for a frame about x, y, z (sides along the other two axes).
    side_m : float
        Side a of the mean turn (the section's centre line) along the next axis in cyclic
        order (x: y, y: z, z: x), m.
    centre_m : float
        Axial position c of the section's mid-plane, m.
    width_m : float
        Axial width w of the section, m.
    depth_m : float
        Depth d of the section across each side, m (d < a).
    side_v_m : float, optional
        Side b of the mean turn along the axis after that (x: z, y: x, z: y), m; None: a
        square, b = a.
    """

    axis: int
    side_m: float
    centre_m: float
    width_m: float
    depth_m: float
    side_v_m: float | None = None

    @property
    def sides_m(self) -> tuple[float, float]:
        """The mean turn's sides (a, b) along the next two axes in cyclic order, m."""
        return (self.side_m, self.side_m if self.side_v_m is None else self.side_v_m)

    def halves(self) -> tuple[int, int, float, float, float, float]:
        """The two in-plane axes u < v and the section's outer and inner half extents along
        them, ``(u, v, out_u, out_v, in_u, in_v)``, m.

        Returns
        -------
        u, v : int
            The two axes other than the frame's, indices in ascending order.
        out_u, out_v : float
            Half extents of the frame's outer faces along u and v, (side + d)/2, m.
        in_u, in_v : float
            Half extents of its inner faces (the hole) along u and v, (side - d)/2, m.
        """
        u, v = (k for k in range(3) if k != self.axis)
        a, b = self.sides_m
        along = {(self.axis + 1) % 3: a, (self.axis + 2) % 3: b}
        d = self.depth_m
        return (
            u,
            v,
            0.5 * (along[u] + d),
            0.5 * (along[v] + d),
            0.5 * (along[u] - d),
            0.5 * (along[v] - d),
        )

    @property
    def volume_m3(self) -> float:
        """w ((a + d)(b + d) - (a - d)(b - d)) = 2 (a + b) w d, m³."""
        a, b = self.sides_m
        if self.side_v_m is None:
            return 4.0 * self.side_m * self.width_m * self.depth_m
        return 2.0 * (a + b) * self.width_m * self.depth_m


def pair_packs(pair: Any) -> tuple[Any, Any]:
    """The two packs of a pair at ∓s/2 along its axis as solids: :class:`Ring` for a circular
    pair, :class:`Frame` for a square or rectangular one (the pair's ``pack_solids``).

    Parameters
    ----------
    pair : coils.winding.WoundPair
        The pair (SI lengths).

    Returns
    -------
    tuple of Ring or tuple of Frame
        The coil at -s/2 and the coil at +s/2 (SI).
    """
    return pair.pack_solids()


def _box_sdf_2d(qx: np.ndarray, qy: np.ndarray) -> np.ndarray:
    """Signed distance to a box from q = |p| - half extents (2-D, exact)."""
    outside = np.hypot(np.maximum(qx, 0.0), np.maximum(qy, 0.0))
    return outside + np.minimum(np.maximum(qx, qy), 0.0)


def frame_signed_distance(frame: Frame, points: np.ndarray) -> np.ndarray:
    """Exact signed distance of ``points`` (shape (..., 3), m) to the solid frame, m.

    In the frame's plane the section sweeps the square annulus between the squares of half
    sides h ∓ d/2: max(sdf_outer, -sdf_inner) is its exact signed distance (outside the outer
    square the nearest point is on it, inside the hole on the inner one, within the annulus
    the nearer of the two); extruded over |z - c| <= w/2 exactly (the box formula with the
    2-D distance as one coordinate).

    Parameters
    ----------
    frame : Frame
        The solid (SI lengths).
    points : ndarray, shape (..., 3)
        Points, m.

    Returns
    -------
    ndarray, shape (...)
        Signed distance, m (negative inside).
    """
    p = np.asarray(points, dtype=float)
    return _frame_sd_xyz(frame, (p[..., 0], p[..., 1], p[..., 2]))


def _frame_sd_xyz(frame: Frame, xyz: tuple[np.ndarray, ...]) -> np.ndarray:
    """:func:`frame_signed_distance` of the points whose x, y, z are ``xyz`` (three arrays
    that broadcast together), m."""
    u, v, out_u, out_v, in_u, in_v = frame.halves()
    au, av = np.abs(xyz[u]), np.abs(xyz[v])
    s2 = np.maximum(_box_sdf_2d(au - out_u, av - out_v), -_box_sdf_2d(au - in_u, av - in_v))
    qz = np.abs(xyz[frame.axis] - frame.centre_m) - 0.5 * frame.width_m
    return _box_sdf_2d(s2, qz)


def frame_bars(frame: Frame) -> np.ndarray:
    """The frame as four axis-aligned bars, shape (4, 2, 3): [bar, (low, high) corner, xyz],
    m; two bars run the full outer side, two fit between them (no overlap).

    Parameters
    ----------
    frame : Frame
        The solid (SI lengths).

    Returns
    -------
    ndarray, shape (4, 2, 3)
        Low and high corner of each bar, m.
    """
    a = frame.axis
    u, v, out_u, out_v, in_u, in_v = frame.halves()
    out = np.empty((4, 2, 3))
    out[:, 0, a], out[:, 1, a] = (
        frame.centre_m - 0.5 * frame.width_m,
        frame.centre_m + 0.5 * frame.width_m,
    )
    for i, sign in enumerate((-1.0, 1.0)):
        # bars along v at u = ±h: the full outer length
        out[i, :, u] = np.sort([sign * in_u, sign * out_u])
        out[i, :, v] = (-out_v, out_v)
        # bars along u at v = ±h, between the other two
        out[2 + i, :, v] = np.sort([sign * in_v, sign * out_v])
        out[2 + i, :, u] = (-in_u, in_u)
    return out


def frame_distance_m(a: Frame, b: Frame) -> float:
    """Least distance between two solid frames, m (negative: they overlap, by at least that).

    Exact: the least over their bars' pairs of the axis-aligned box distance
    sqrt(Σ max(gap_i, 0)²), gap_i = max(lo_b - hi_a, lo_a - hi_b); boxes that overlap have all
    gaps <= 0 and their overlap is max_i gap_i (the shortest move that parts them).

    Parameters
    ----------
    a, b : Frame
        The two solids (SI lengths).

    Returns
    -------
    float
        Least distance, m.
    """
    ba, bb = frame_bars(a)[:, None], frame_bars(b)[None, :]
    gap = np.maximum(bb[..., 0, :] - ba[..., 1, :], ba[..., 0, :] - bb[..., 1, :])  # (4, 4, 3)
    apart = np.sqrt(np.sum(np.maximum(gap, 0.0) ** 2, axis=-1))
    signed = np.where(np.all(gap <= 0.0, axis=-1), np.max(gap, axis=-1), apart)
    return float(signed.min())


def _signed_distance(pack: Any, points: np.ndarray) -> np.ndarray:
    """:func:`ring_signed_distance` or :func:`frame_signed_distance` by the pack's kind."""
    if isinstance(pack, Frame):
        return frame_signed_distance(pack, points)
    return ring_signed_distance(pack, points)


def _signed_distance_xyz(pack: Any, xyz: tuple[np.ndarray, ...]) -> np.ndarray:
    """:func:`_signed_distance` of the points whose x, y, z are ``xyz`` (three arrays that
    broadcast together; no (..., 3) array is built), m."""
    if isinstance(pack, Frame):
        return _frame_sd_xyz(pack, xyz)
    return _ring_sd_xyz(pack, xyz)


def _cylindrical(points: np.ndarray, axis: int) -> tuple[np.ndarray, np.ndarray]:
    p = np.asarray(points, dtype=float)
    u, v = (k for k in range(3) if k != axis)
    return np.hypot(p[..., u], p[..., v]), p[..., axis]


def ring_signed_distance(ring: Ring, points: np.ndarray) -> np.ndarray:
    """Exact signed distance of ``points`` (shape (..., 3), m) to the solid ring, m.

    Positive outside, negative inside: the 2-D box distance of (ρ - R, z - c) to the half
    extents (h/2, w/2).

    Parameters
    ----------
    ring : Ring
        The solid ring.
    points : ndarray, shape (..., 3)
        Points, m.

    Returns
    -------
    ndarray, shape (...)
        Signed distance of each point, m.
    """
    p = np.asarray(points, dtype=float)
    return _ring_sd_xyz(ring, (p[..., 0], p[..., 1], p[..., 2]))


def _ring_sd_xyz(ring: Ring, xyz: tuple[np.ndarray, ...]) -> np.ndarray:
    """:func:`ring_signed_distance` of the points whose x, y, z are ``xyz`` (three arrays that
    broadcast together), m; the same operations, in place on the full-size temporaries."""
    u, v = (k for k in range(3) if k != ring.axis)
    qx = np.hypot(xyz[u], xyz[v])
    qx -= ring.radius_m
    np.abs(qx, out=qx)
    qx -= 0.5 * ring.depth_m
    qz = np.abs(xyz[ring.axis] - ring.centre_m) - 0.5 * ring.width_m
    inside = np.maximum(qx, qz)
    np.minimum(inside, 0.0, out=inside)
    np.maximum(qx, 0.0, out=qx)
    outside = np.hypot(qx, np.maximum(qz, 0.0))
    outside += inside
    return outside


def _section_point(ring: Ring, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(ρ, z) of the section boundary at arc length s (mod the perimeter), from the inner-low
    corner counter-clockwise: inner face up, top face out, outer face down, bottom face in."""
    h, w = ring.depth_m, ring.width_m
    per = 2.0 * (h + w)
    s = np.mod(s, per)
    r0, z0 = ring.radius_m - 0.5 * h, ring.centre_m - 0.5 * w
    # the first face whose end lies past s (nested np.where: np.select's choice, fewer calls)
    inner, top, outer = s < w, s < w + h, s < 2 * w + h
    rho = np.where(
        inner, r0, np.where(top, r0 + (s - w), np.where(outer, r0 + h, r0 + h - (s - 2 * w - h)))
    )
    z = np.where(inner, z0 + s, np.where(top, z0 + w, np.where(outer, z0 + w - (s - w - h), z0)))
    return rho, z


def ring_surface_points(ring: Ring, phi: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Points on the ring's surface at angle ``phi`` (rad) and section arc length ``s`` (m);
    ``phi`` and ``s`` broadcast; returns shape (..., 3).

    Parameters
    ----------
    ring : Ring
        The solid ring.
    phi : ndarray
        Angle about the ring's axis, rad.
    s : ndarray
        Arc length along the section's boundary from its inner-low corner, m.

    Returns
    -------
    ndarray, shape (..., 3)
        The surface points, m.
    """
    xyz = _surface_xyz(ring, np.asarray(phi, dtype=float), np.asarray(s, dtype=float))
    out = np.empty((*np.broadcast_shapes(*(c.shape for c in xyz)), 3))
    for k in range(3):
        out[..., k] = xyz[k]
    return out


def _surface_xyz(ring: Ring, phi: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, ...]:
    """x, y, z of :func:`ring_surface_points` as three arrays that broadcast together, m: the
    section point on ``s``'s shape, cos and sin on ``phi``'s (no broadcast copies)."""
    rho, z = _section_point(ring, s)
    u, v = (k for k in range(3) if k != ring.axis)
    xyz = [z, z, z]
    xyz[u], xyz[v] = rho * np.cos(phi), rho * np.sin(phi)
    return tuple(xyz)


def ring_distance_m(a: Ring, b: Ring) -> float:
    """Least distance between two solid rings, m (negative: they overlap).

    Minimum of B's exact signed distance over A's surface: a grid search, then zooming grids
    around the best cells (see the module notes). Converged to well below 1 µm.

    Parameters
    ----------
    a, b : Ring
        The two solid rings.

    Returns
    -------
    float
        Least distance, m (negative: overlap, by at least that depth).
    """
    return _ring_distance(a, b)


def _ring_distance(a: Ring, b: Ring) -> float:
    return _closest(a, b)[0]


def nearest_point_on_ring(ring: Ring, point: np.ndarray) -> np.ndarray:
    """The point of the solid ring nearest ``point`` (shape (3,)), for a point outside it.

    Parameters
    ----------
    ring : Ring
        The solid ring.
    point : ndarray, shape (3,)
        A point outside the ring, m.

    Returns
    -------
    ndarray, shape (3,)
        The nearest point of the ring, m.
    """
    p = np.asarray(point, dtype=float)
    rho, z = _cylindrical(p, ring.axis)
    r_near = np.clip(rho, ring.radius_m - 0.5 * ring.depth_m, ring.radius_m + 0.5 * ring.depth_m)
    z_near = np.clip(z, ring.centre_m - 0.5 * ring.width_m, ring.centre_m + 0.5 * ring.width_m)
    u, v = (k for k in range(3) if k != ring.axis)
    scale = r_near / rho if rho > 0 else 0.0
    out = np.empty(3)
    out[u], out[v], out[ring.axis] = p[u] * scale, p[v] * scale, z_near
    return out


def pack_closest_points(pair_a: Any, pair_b: Any) -> tuple[float, np.ndarray, np.ndarray]:
    """(clearance m, nearest point on A's packs, nearest point on B's packs) of two pairs; the
    points are meaningful when the packs are apart (clearance > 0).

    Parameters
    ----------
    pair_a, pair_b : HelmholtzPair or SquarePair
        Two pairs on different axes.

    Returns
    -------
    clearance_m : float
        Least distance between the packs, m (negative: overlap).
    point_a, point_b : ndarray, shape (3,)
        Nearest points on A's and on B's packs, m.
    """
    ka, kb = pair_packs(pair_a)[1], pair_packs(pair_b)[1]  # see pack_clearance_m
    if isinstance(ka, Ring) and isinstance(kb, Ring):
        d, pa, rb = _closest(ka, kb)
        return d, pa, nearest_point_on_ring(rb, pa)
    if isinstance(ka, Frame) and isinstance(kb, Frame):
        return _frames_closest(ka, kb)
    if isinstance(ka, Ring):
        d, pa, fb = _closest(ka, kb)
        return d, pa, nearest_point_on_frame(fb, pa)
    d, pb, fa = _closest(kb, ka)
    return d, nearest_point_on_frame(fa, pb), pb


def nearest_point_on_frame(frame: Frame, point: np.ndarray) -> np.ndarray:
    """The point of the solid frame nearest ``point``: the nearest of the point clipped into
    each of its bars.

    Parameters
    ----------
    frame : Frame
        The solid (SI lengths).
    point : ndarray, shape (3,)
        A point outside it, m.

    Returns
    -------
    ndarray, shape (3,)
        The nearest point of the frame, m.
    """
    bars = frame_bars(frame)
    p = np.asarray(point, dtype=float)
    near = np.clip(p[None, :], bars[:, 0], bars[:, 1])
    return near[int(np.argmin(np.linalg.norm(near - p, axis=1)))]


def _frames_closest(a: Frame, b: Frame) -> tuple[float, np.ndarray, np.ndarray]:
    """(distance, nearest point on a, nearest point on b) of two frames apart (closest bars;
    along an axis where they overlap, the middle of the shared interval)."""
    ba, bb = frame_bars(a), frame_bars(b)
    best = (math.inf, np.zeros(3), np.zeros(3))
    for lo_a, hi_a in ba:
        for lo_b, hi_b in bb:
            mid = 0.5 * (np.maximum(lo_a, lo_b) + np.minimum(hi_a, hi_b))
            pa = np.where(lo_b > hi_a, hi_a, np.where(lo_a > hi_b, lo_a, mid))
            pb = np.where(lo_b > hi_a, lo_b, np.where(lo_a > hi_b, hi_b, mid))
            d = float(np.linalg.norm(pa - pb))
            if d < best[0]:
                best = (d, pa, pb)
    return frame_distance_m(a, b), best[1], best[2]


def _closest(a: Ring, b: Any) -> tuple[float, np.ndarray, Any]:
    per = 2.0 * (a.width_m + a.depth_m)
    n_phi, n_s = _GRID
    dphi, ds = 2.0 * math.pi / n_phi, per / n_s
    phi = np.arange(n_phi) * dphi
    s = (np.arange(n_s) + 0.5) * ds
    d = _signed_distance_xyz(b, _surface_xyz(a, phi[:, None], s[None, :]))
    best = float(d.min())
    # the signed distance is 1-Lipschitz in space: a cell whose grid value exceeds the best by
    # more than the cell's spatial size cannot hold the minimum
    cell = math.hypot(dphi * (a.radius_m + 0.5 * a.depth_m), ds)
    # the _REFINE_BEST least cells (a partition, not a sort of the whole grid), least first;
    # cells at the same distance (a symmetric pair of rings) in the order of their index
    part = np.argpartition(d, _REFINE_BEST - 1, axis=None)[:_REFINE_BEST]
    least = part[np.lexsort((part, d.flat[part]))]
    flat = [i for i in least if d.flat[i] <= best + cell]
    cells = np.array([np.unravel_index(i, d.shape) for i in flat])
    c_phi, c_s = phi[cells[:, 0]], s[cells[:, 1]]  # every candidate cell zoomed at once
    i0, j0 = np.unravel_index(int(np.argmin(d)), d.shape)
    where = (phi[i0], s[j0])
    h_phi, h_s = dphi, ds
    step = np.linspace(-1.0, 1.0, 9)
    rows = np.arange(len(flat))
    for _ in range(_REFINE_STEPS):
        gp = c_phi[:, None] + h_phi * step  # (K, 9)
        gs = c_s[:, None] + h_s * step
        dd = _signed_distance_xyz(b, _surface_xyz(a, gp[:, :, None], gs[:, None, :]))
        dd = dd.reshape(len(flat), -1)
        k = dd.argmin(axis=1)
        km, mm = np.divmod(k, 9)
        c_phi, c_s = gp[rows, km], gs[rows, mm]
        values = dd[rows, k]
        top = int(np.argmin(values))
        if float(values[top]) < best:
            best, where = float(values[top]), (c_phi[top], c_s[top])
        h_phi, h_s = 0.5 * h_phi, 0.5 * h_s
        if h_phi * (a.radius_m + a.depth_m) < 1e-9 and h_s < 1e-9:
            break
    point = ring_surface_points(a, np.array(where[0]), np.array(where[1]))
    return best, point, b


def pack_clearance_m(pair_a: Any, pair_b: Any) -> float:
    """Least distance between the winding packs of two pairs on different axes, m.

    The packs are solids (:func:`pair_packs`): :func:`ring_distance_m` of one coil of each
    (two frames: :func:`frame_distance_m`; a ring and a frame: the ring's surface search with
    the frame's exact signed distance).
    The four coil combinations are congruent (the mirror x_a -> -x_a swaps A's coils and maps
    B's, whose axis is perpendicular, onto themselves; likewise for B), so one is computed.
    Negative: the packs overlap (by at least that depth).

    Parameters
    ----------
    pair_a, pair_b : HelmholtzPair
        Two pairs on different axes.

    Returns
    -------
    float
        Least distance between their packs, m.
    """
    return pack_distance_m(pair_packs(pair_a)[1], pair_packs(pair_b)[1])


def pack_distance_m(pa: Any, pb: Any) -> float:
    """Least distance between two packs as solids (:class:`Ring` or :class:`Frame`), m:
    :func:`ring_distance_m`, :func:`frame_distance_m`, or for a ring and a frame the ring's
    surface search with the frame's exact signed distance. Negative: they overlap.

    Parameters
    ----------
    pa, pb : Ring or Frame
        The two packs.

    Returns
    -------
    float
        Least distance, m.
    """
    if isinstance(pa, Ring) and isinstance(pb, Ring):
        return ring_distance_m(pa, pb)
    if isinstance(pa, Frame) and isinstance(pb, Frame):
        return frame_distance_m(pa, pb)
    ring, frame = (pa, pb) if isinstance(pa, Ring) else (pb, pa)
    return _closest(ring, frame)[0]


def pack_clearances_m(pairs: Any) -> dict[str, float]:
    """``{"x/y": …, "x/z": …, "y/z": …}`` of :func:`pack_clearance_m` for the three pairs.

    Parameters
    ----------
    pairs : sequence of HelmholtzPair
        The three pairs of a system.

    Returns
    -------
    dict of str to float
        Clearance of each two pairs, m, keyed ``"x/y"``, ``"x/z"``, ``"y/z"``.
    """
    return {
        f"{a.axis}/{b.axis}": pack_clearance_m(a, b) for a, b in itertools.combinations(pairs, 2)
    }


def bore_clearance_m(pairs: Any, bore_radius_m: float) -> float:
    """Least radial room between the inner faces of the packs and a bore, m.

    min over pairs of (R - h/2) - bore radius: the inner face of every pack is a cylinder of
    radius R - h/2 about its axis, the bore a coaxial cylinder (or the workspace sphere, which
    touches that cylinder's radius first at its equator). A square pair's ``radius_m`` is half
    its side: the inner face's sides are a/2 - h/2 from the axis, where a coaxial cylinder
    meets them first (at the middle of each side).

    Parameters
    ----------
    pairs : sequence of HelmholtzPair
        The pairs of a system.
    bore_radius_m : float
        Radius of the bore (or workspace sphere) to keep clear, m.

    Returns
    -------
    float
        Least radial room, m (negative: a pack reaches into the bore).
    """
    return min(p.radius_m - 0.5 * p.winding_pack_depth_m for p in pairs) - bore_radius_m


def torus_clearance_bound_m(mean_turn_gap_m: Any, pair_a: Any, pair_b: Any) -> Any:
    """A smooth lower bound of the clearance: the gap between the mean turns less the two
    sections' half diagonals (each ring lies inside the torus of that tube radius).

    Conservative by at most ((sqrt(w_a² + h_a²) - max(w_a, h_a)) + (same for b)) / 2.

    Parameters
    ----------
    mean_turn_gap_m : float or CasADi
        Least distance between the two pairs' mean turns (centre circles of the sections), m.
    pair_a, pair_b : HelmholtzPair
        The two pairs (their winding pack width and depth).

    Returns
    -------
    float or CasADi
        Lower bound of the pack clearance, m.
    """
    return mean_turn_gap_m - 0.5 * (
        math.hypot(pair_a.winding_pack_width_m, pair_a.winding_pack_depth_m)
        + math.hypot(pair_b.winding_pack_width_m, pair_b.winding_pack_depth_m)
    )


def pair_extent_m(
    axis_index: int, radius_m: Any, separation_m: Any, width_m: Any, depth_m: Any
) -> list[Any]:
    """Half-extent of a pair's two packs, as solids, along x, y and z, m (backend-generic).

    Along the pair's axis the packs reach s/2 + w/2 (outer faces of the two rings); across it,
    R + h/2 (outer radius).

    Parameters
    ----------
    axis_index : int
        The pair's axis (0, 1, 2 for x, y, z), an index.
    radius_m : float or CasADi, or a tuple of two
        Mean winding radius R, m; or the mean turn's reach (half side) along the next two axes
        in cyclic order, m (a rectangle).
    separation_m : float or CasADi
        Distance between the two coils' mid-planes s, m.
    width_m : float or CasADi
        Axial width of a pack w, m.
    depth_m : float or CasADi
        Radial depth of a pack h, m.

    Returns
    -------
    list of float or CasADi
        The three half-extents, m.
    """
    if isinstance(radius_m, tuple):  # reaches along the next two axes in cyclic order
        reach = {(axis_index + 1) % 3: radius_m[0], (axis_index + 2) % 3: radius_m[1]}
        out = [0.5 * separation_m + 0.5 * width_m] * 3
        for i, r in reach.items():
            out[i] = r + 0.5 * depth_m
        return out
    outer = radius_m + 0.5 * depth_m
    return [0.5 * separation_m + 0.5 * width_m if i == axis_index else outer for i in range(3)]


def outer_box_m(pairs: Any) -> np.ndarray:
    """Edge lengths of the smallest axis-aligned box round the coil set's packs, m.

    Parameters
    ----------
    pairs : sequence of HelmholtzPair
        The pairs (``axis_index``, ``radius_m``, ``separation_m``, ``winding_pack_width_m``,
        ``winding_pack_depth_m``), centred on the origin.

    Returns
    -------
    ndarray, shape (3,)
        Twice the largest half-extent along x, y and z over the pairs, m.
    """
    halves = np.array([p.extents_m for p in pairs], dtype=float)
    return 2.0 * halves.max(axis=0)
