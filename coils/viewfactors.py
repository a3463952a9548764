"""Diffuse view factors between the winding packs of a three-axis set and the room.

Each coil's winding pack is a ring of rectangular section (axial width w, radial depth d) about
its pair's axis at ±s/2; its four faces (inner and outer cylinder, two annuli) emit diffusely.
The fraction of a pack's emission that reaches each pair's packs, or escapes to the room, is
found by a deterministic quasi-Monte Carlo ray trace: the first :data:`RAYS_PER_PAIR` points of
the 5-D Halton sequence (bases 2, 3, 5, 7, 11) pick a face in proportion to its area, a point on
it and a cosine-weighted direction; exact ray-cylinder and ray-plane intersections,
numpy-vectorised; computed once per geometry and cached. The same points serve every geometry,
so the fractions move with the packs in steps of 1/n (a ray crossing an edge), not by a
re-drawn sample. Against a 2-million-ray random trace of the built-in packs the 8192 Halton
rays are within 0.0026 (20 000 random rays: 0.0044; tests/test_coils_cooling.py checks 0.03
against an independent tracer).

A square pair's coil is a frame of four bars (:class:`PackFrame`): the same trace with the
slab test on axis-aligned boxes and points on its four kinds of faces (inner, outer, lower and
upper, by area).

Both coils of a pair are mirror images in the pair's mid-plane, and every pack is symmetric in
the other two mid-planes, so the coil at +s/2 stands for its pair. Row k of the result holds
pair k's area-weighted fractions ``[room, x, y, z]`` (the own-pair entry: its own faces and
its partner coil, at its own temperature; the others: the packs it exchanges radiation with).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["RAYS_PER_PAIR", "PackFrame", "PackRing", "view_factors"]

#: Rays traced per pair (Halton points 1..n).
RAYS_PER_PAIR = 8192
#: The Halton bases of the five coordinates: face, azimuth, position on the face, and the
#: direction's two (cos² of the polar angle, azimuth about the normal).
_BASES = (2, 3, 5, 7, 11)


@dataclass(frozen=True)
class PackRing:
    """One pair's pack geometry (SI): axis index, mean radius, coil spacing, width, depth.

    Attributes
    ----------
    axis_index : int
        Axis index of the pair: 0, 1, 2 for x, y, z.
    radius_m : float
        Mean coil radius, m.
    separation_m : float
        Distance between the coil planes, m.
    width_m, depth_m : float
        Axial width and radial depth of each pack, m.
    """

    axis_index: int
    radius_m: float
    separation_m: float
    width_m: float
    depth_m: float


@dataclass(frozen=True)
class PackFrame:
    """One square or rectangular pair's pack geometry (SI): axis index, side of the mean turn,
    coil spacing, width, depth, and the second side of a rectangle (a frame of four bars about
    the axis, sides along the other two axes).

    Attributes
    ----------
    axis_index : int
        Axis index of the pair: 0, 1, 2 for x, y, z.
    side_m : float
        Side of each coil's mean turn (the centre line of the pack), m.
    separation_m : float
        Distance between the coil planes (the packs' mid-planes, at ±s/2), m.
    width_m, depth_m : float
        Axial width of each pack and its depth across each side, m.
    side_v_m : float or None
        A rectangle's side along (a+2) % 3 (``side_m`` runs along (a+1) % 3), m; None: a square.
    """

    axis_index: int
    side_m: float
    separation_m: float
    width_m: float
    depth_m: float
    side_v_m: float | None = None

    @property
    def radius_m(self) -> float:
        """Half the side (the length scale of the tracer's tolerances), m."""
        return 0.5 * self.side_m

    def halves(self) -> tuple[float, float, float, float]:
        """Outer and inner half extents of the section along u = (a+1) % 3 and w = (a+2) % 3,
        ``(out_u, out_w, in_u, in_w)``, m (side_v_m None: a square).

        Returns
        -------
        out_u, out_w : float
            Half extents of the frame's outer faces along u and w, (side + depth)/2, m.
        in_u, in_w : float
            Half extents of its inner faces (the hole) along u and w, (side - depth)/2, m.
        """
        a = self.side_m
        b = a if self.side_v_m is None else self.side_v_m
        d = self.depth_m
        return 0.5 * (a + d), 0.5 * (b + d), 0.5 * (a - d), 0.5 * (b - d)


def _bars(frame: PackFrame, centre: float) -> list[tuple[np.ndarray, np.ndarray]]:
    """The frame's coil at axial ``centre`` as four non-overlapping axis-aligned boxes
    (low corner, high corner)."""
    a = frame.axis_index
    u, w = (a + 1) % 3, (a + 2) % 3
    out_u, out_w, in_u, in_w = frame.halves()
    out = []
    for sign in (-1.0, 1.0):
        for along, across, half, lo_x, hi_x in (
            (w, u, out_w, in_u, out_u),
            (u, w, in_u, in_w, out_w),
        ):
            lo, hi = np.empty(3), np.empty(3)
            lo[a], hi[a] = centre - 0.5 * frame.width_m, centre + 0.5 * frame.width_m
            lo[across], hi[across] = sorted((sign * lo_x, sign * hi_x))
            lo[along], hi[along] = -half, half
            out.append((lo, hi))
    return out


def _frame_hit(
    frame: PackFrame, p: Sequence[np.ndarray], v: Sequence[np.ndarray], tiny: float
) -> np.ndarray:
    """Distance along each ray to where it first enters either coil of the frame (inf: never):
    the slab test on each of the eight bars, an entry counted when it lies ahead (> tiny)."""
    n = p[0].shape[0]
    t_best = np.full(n, np.inf)
    inv = [1.0 / vi for vi in v]
    for centre in (-0.5 * frame.separation_m, 0.5 * frame.separation_m):
        for lo, hi in _bars(frame, centre):
            t_near = np.full(n, -np.inf)
            t_far = np.full(n, np.inf)
            for i in range(3):
                t1 = (lo[i] - p[i]) * inv[i]
                t2 = (hi[i] - p[i]) * inv[i]
                # a ray parallel to the slab: inside it for all t or never (nan from 0 * inf)
                t1 = np.where(np.isnan(t1), -np.inf, t1)
                t2 = np.where(np.isnan(t2), np.inf, t2)
                np.maximum(t_near, np.minimum(t1, t2), out=t_near)
                np.minimum(t_far, np.maximum(t1, t2), out=t_far)
            ok = (t_near <= t_far) & (t_near > tiny)
            np.minimum(t_best, t_near, out=t_best, where=ok)
    return t_best


def _perp(axis: int) -> tuple[int, int]:
    return tuple(i for i in range(3) if i != axis)  # type: ignore[return-value]


def _first_hit(
    p: Sequence[np.ndarray], v: Sequence[np.ndarray], rings: Sequence[PackRing | PackFrame]
) -> np.ndarray:
    """Index of the pair whose pack each ray (origin p, direction v) enters first; -1: none.

    ``p`` and ``v`` are their three coordinate columns (contiguous arrays). Per ray the least
    positive distance to any face of any coil (annuli at their planes, cylinders at both
    roots); a pair's two coils share their cylinders' roots (they differ only in the axial
    window), so those are solved once per pair. Candidates are folded in with
    ``np.minimum(..., where=ok)`` (no masked copies).
    """
    n = p[0].shape[0]
    best = np.full(n, np.inf)
    who = np.full(n, -1)
    tiny = 1e-9 * max(r.radius_m for r in rings)
    with np.errstate(divide="ignore", invalid="ignore"):
        for j, ring in enumerate(rings):
            if isinstance(ring, PackFrame):
                t_frame = _frame_hit(ring, p, v, tiny)
                closer = t_frame < best
                np.copyto(best, t_frame, where=closer)
                who[closer] = j
                continue
            a = ring.axis_index
            u, w = _perp(a)
            pa, pu, pw = p[a], p[u], p[w]
            va, vu, vw = v[a], v[u], v[w]
            r1, r2 = ring.radius_m - 0.5 * ring.depth_m, ring.radius_m + 0.5 * ring.depth_m
            qa = vu**2 + vw**2
            qb = 2.0 * (pu * vu + pw * vw)
            pr = pu**2 + pw**2
            two_qa = 2.0 * qa
            qa_ok = qa > 0.0
            roots = []  # (t, axial coordinate, valid) of the cylinders' four roots
            for rad in (r1, r2):
                disc = qb * qb - 4.0 * qa * (pr - rad * rad)
                root = np.sqrt(np.maximum(disc, 0.0))
                hit = (disc >= 0.0) & qa_ok
                for sign in (-1.0, 1.0):
                    t = (-qb + sign * root) / two_qa
                    roots.append((t, pa + t * va, hit & (t > tiny)))
            t_ring = np.full(n, np.inf)
            r1_sq, r2_sq = r1 * r1, r2 * r2
            for centre in (-0.5 * ring.separation_m, 0.5 * ring.separation_m):
                lo, hi = centre - 0.5 * ring.width_m, centre + 0.5 * ring.width_m
                for plane in (lo, hi):  # annular faces
                    t = (plane - pa) / va
                    ru = pu + t * vu
                    rw = pw + t * vw
                    rr = ru * ru + rw * rw
                    ok = (t > tiny) & (rr >= r1_sq) & (rr <= r2_sq)
                    np.minimum(t_ring, t, out=t_ring, where=ok)
                for t, z, valid in roots:  # cylindrical faces
                    ok = valid & (z >= lo) & (z <= hi)
                    np.minimum(t_ring, t, out=t_ring, where=ok)
            closer = t_ring < best
            np.copyto(best, t_ring, where=closer)
            who[closer] = j
    return who


def _cross(a: Sequence[np.ndarray], b: Sequence[np.ndarray]) -> tuple[np.ndarray, ...]:
    """a x b of vectors given as coordinate columns."""
    return (
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    )


def _frame(normal: Sequence[np.ndarray]) -> tuple[tuple[np.ndarray, ...], tuple[np.ndarray, ...]]:
    """Two unit tangents completing the unit normals (coordinate columns) to right-handed
    frames."""
    x_helper = np.abs(normal[0]) < 0.9  # (1, 0, 0) unless the normal lies near x: (0, 1, 0)
    helper = (np.where(x_helper, 1.0, 0.0), np.where(x_helper, 0.0, 1.0), np.zeros_like(normal[0]))
    t1 = _cross(normal, helper)
    norm = np.sqrt(t1[0] * t1[0] + t1[1] * t1[1] + t1[2] * t1[2])
    t1 = (t1[0] / norm, t1[1] / norm, t1[2] / norm)
    return t1, _cross(normal, t1)


def radical_inverse(index: np.ndarray, base: int) -> np.ndarray:
    """Van der Corput radical inverse of non-negative integers in ``base`` (Halton's
    coordinates): the digits of ``index`` mirrored about the radix point.

    Parameters
    ----------
    index : ndarray of int
        Sequence indices, count (>= 0).
    base : int
        Radix, a prime (count).

    Returns
    -------
    ndarray of float
        The radical inverses in [0, 1), dimensionless.
    """
    i = np.array(index, dtype=np.int64)
    out = np.zeros(i.shape)
    scale = 1.0
    while np.any(i > 0):
        scale /= base
        out += scale * (i % base)
        i //= base
    return out


def halton_points(n: int) -> np.ndarray:
    """Points 1..n of the Halton sequence in :data:`_BASES` (n x 5; point 0, the origin, left
    out).

    Parameters
    ----------
    n : int
        Number of points.

    Returns
    -------
    ndarray, shape (n, 5)
        Points in [0, 1)⁵, dimensionless, read-only.
    """
    index = np.arange(1, n + 1)
    pts = np.stack([radical_inverse(index, b) for b in _BASES], axis=1)
    pts.setflags(write=False)
    return pts


def _emitters(ring: PackRing, u: np.ndarray) -> tuple:
    """Points and unit outward normals (coordinate columns) on the +s/2 coil's faces, one per
    row of ``u`` (n x 3 in [0, 1): face by area, azimuth, position across the face)."""
    a = ring.axis_index
    v, w = _perp(a)
    r0, d, wd = ring.radius_m, ring.depth_m, ring.width_m
    r1, r2 = r0 - 0.5 * d, r0 + 0.5 * d
    c = 0.5 * ring.separation_m
    annulus = np.pi * (r2 * r2 - r1 * r1)
    areas = np.array([2.0 * np.pi * r1 * wd, 2.0 * np.pi * r2 * wd, annulus, annulus])
    # 0 inner cylinder, 1 outer cylinder, 2 lower annulus, 3 upper annulus
    face = np.minimum(np.searchsorted(np.cumsum(areas) / areas.sum(), u[:, 0], side="right"), 3)
    phi = 2.0 * np.pi * u[:, 1]
    cos, sin = np.cos(phi), np.sin(phi)
    cylinder = face < 2
    upper = face == 3
    radius = np.where(
        cylinder, np.where(face == 0, r1, r2), np.sqrt(r1 * r1 + u[:, 2] * (r2 * r2 - r1 * r1))
    )
    p: list[np.ndarray] = [np.empty(0)] * 3
    nv: list[np.ndarray] = [np.empty(0)] * 3
    p[v], p[w] = radius * cos, radius * sin
    p[a] = np.where(cylinder, c + wd * (u[:, 2] - 0.5), c + np.where(upper, 0.5, -0.5) * wd)
    sign = np.where(cylinder, np.where(face == 0, -1.0, 1.0), 0.0)
    nv[v], nv[w] = sign * cos, sign * sin
    nv[a] = np.where(cylinder, 0.0, np.where(upper, 1.0, -1.0))
    return tuple(p), tuple(nv)


def _pick_side(x: np.ndarray, lengths: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Which of four sides of ``lengths`` a uniform ``x`` in [0, 1) falls on (in proportion
    to length), and the position t in [-1, 1] along it; four equal sides by 4x directly."""
    if np.all(lengths == lengths[0]):
        along4 = 4.0 * x
        side = np.minimum(along4.astype(int), 3)
        return side, 2.0 * (along4 - side) - 1.0
    ends = np.cumsum(lengths)
    s = x * ends[-1]
    side = np.minimum(np.searchsorted(ends, s, side="right"), 3)
    return side, 2.0 * (s - (ends - lengths)[side]) / lengths[side] - 1.0


def _frame_emitters(frame: PackFrame, u: np.ndarray) -> tuple:
    """As :func:`_emitters` on the +s/2 coil of a square or rectangular frame (sides a along
    u, b along w): inner and outer faces (2 (a + b ∓ 2d) w each), lower and upper faces
    (2 (a + b) d each), a point uniform on the chosen face (position along the face's
    perimeter, then across it)."""
    a = frame.axis_index
    ua, wa = (a + 1) % 3, (a + 2) % 3
    side = frame.side_m
    side_v = side if frame.side_v_m is None else frame.side_v_m
    d, wd = frame.depth_m, frame.width_m
    out_u, out_w, in_u, in_w = frame.halves()
    c = 0.5 * frame.separation_m
    areas = np.array(
        [
            2.0 * ((side - d) + (side_v - d)) * wd,
            2.0 * ((side + d) + (side_v + d)) * wd,
            2.0 * (side + side_v) * d,
            2.0 * (side + side_v) * d,
        ]
    )
    # 0 inner faces, 1 outer faces, 2 lower face, 3 upper face
    face = np.minimum(np.searchsorted(np.cumsum(areas) / areas.sum(), u[:, 0], side="right"), 3)
    flat = face >= 2
    # the side (0..3: u = +h, w = +h, u = -h, w = -h) and the position t along it, in [-1, 1]:
    # a wall's sides are b, a, b, a long (inner: less d, outer: plus d); the flat faces' bars
    # are b + d, a - d, b + d, a - d long (sides 0 and 2 run the full outer length, 1 and 3 fit
    # between them)
    normal_in = np.array([in_u, in_w, in_u, in_w])
    normal_out = np.array([out_u, out_w, out_u, out_w])
    wall_in, wall_out = normal_in[[1, 0, 1, 0]], normal_out[[1, 0, 1, 0]]
    inner = face == 0
    side_in, t_in = _pick_side(u[:, 1], wall_in)
    side_out, t_out = _pick_side(u[:, 1], wall_out)
    flat_reach = np.array([out_w, in_u, out_w, in_u])
    flat_side, t_flat = _pick_side(u[:, 1], 2.0 * flat_reach)
    wall_side = np.where(inner, side_in, side_out)
    which = np.where(flat, flat_side, wall_side)
    t = np.where(flat, t_flat, np.where(inner, t_in, t_out))
    half = np.where(inner, normal_in[which], normal_out[which])
    # on a flat face: across the side's bar from its inner to its outer edge
    offset = np.where(flat, normal_in[which] + d * u[:, 2], half)
    reach = np.where(flat, flat_reach[which], np.where(inner, wall_in[which], wall_out[which]))
    sign_n = np.where(which < 2, 1.0, -1.0)
    normal_u = np.where(which % 2 == 0, sign_n, 0.0)
    normal_w = np.where(which % 2 == 1, sign_n, 0.0)
    pu = normal_u * offset + (1.0 - np.abs(normal_u)) * (-sign_n * t * reach)
    pw = normal_w * offset + (1.0 - np.abs(normal_w)) * (sign_n * t * reach)
    p: list[np.ndarray] = [np.empty(0)] * 3
    nv: list[np.ndarray] = [np.empty(0)] * 3
    p[ua], p[wa] = pu, pw
    p[a] = np.where(flat, c + np.where(face == 3, 0.5, -0.5) * wd, c + wd * (u[:, 2] - 0.5))
    inward = np.where(face == 0, -1.0, 1.0)
    nv[ua] = np.where(flat, 0.0, inward * normal_u)
    nv[wa] = np.where(flat, 0.0, inward * normal_w)
    nv[a] = np.where(flat, np.where(face == 3, 1.0, -1.0), 0.0)
    return tuple(p), tuple(nv)


def _cosine_directions(normal: Sequence[np.ndarray], u: np.ndarray) -> tuple:
    """Lambert (cosine-weighted) directions about each unit normal (coordinate columns), from
    ``u`` (n x 2 in [0, 1): cos² of the polar angle, azimuth about the normal)."""
    xi1, xi2 = u[:, 0], u[:, 1]
    s = np.sqrt(xi1)
    t1, t2 = _frame(normal)
    c1, c2, c3 = s * np.cos(2.0 * np.pi * xi2), s * np.sin(2.0 * np.pi * xi2), np.sqrt(1.0 - xi1)
    return tuple(c1 * t1[i] + c2 * t2[i] + c3 * normal[i] for i in range(3))


def _traced(rings: tuple[PackRing | PackFrame, ...], rays: int) -> np.ndarray:
    u = halton_points(rays)
    out = np.zeros((len(rings), 1 + len(rings)))
    for k, ring in enumerate(rings):
        emit = _frame_emitters if isinstance(ring, PackFrame) else _emitters
        p, nv = emit(ring, u[:, :3])  # type: ignore[arg-type]
        who = _first_hit(p, _cosine_directions(nv, u[:, 3:]), rings)
        out[k, 0] = np.count_nonzero(who < 0) / rays
        for j in range(len(rings)):
            out[k, 1 + j] = np.count_nonzero(who == j) / rays
    out.setflags(write=False)
    return out


def _rounded(r: PackRing | PackFrame) -> PackRing | PackFrame:
    """The pack with its lengths rounded to 1e-12 m (the cache key)."""
    if isinstance(r, PackFrame):
        side_v = None if r.side_v_m is None else round(float(r.side_v_m), 12)
        return PackFrame(
            int(r.axis_index),
            round(float(r.side_m), 12),
            round(float(r.separation_m), 12),
            round(float(r.width_m), 12),
            round(float(r.depth_m), 12),
            side_v,
        )
    return PackRing(
        int(r.axis_index),
        round(float(r.radius_m), 12),
        round(float(r.separation_m), 12),
        round(float(r.width_m), 12),
        round(float(r.depth_m), 12),
    )


def view_factors(rings: Sequence[PackRing | PackFrame], rays: int = RAYS_PER_PAIR) -> np.ndarray:
    """Fractions of each pair's diffuse emission reaching ``[room, pair 0, pair 1, pair 2]``.

    Rows sum to 1; ``[:, 0]`` is the ``radiation_view_factor`` (what leaves the coil set).
    Deterministic (Halton points; the geometry rounded to 1e-12 m). Not cached: a memo of the
    traces saved 1-3 % of any command (issue 38, docs/architecture.md).

    Parameters
    ----------
    rings : sequence of PackRing
        The three pairs' packs, in pair order.
    rays : int
        Number of rays traced per pair.

    Returns
    -------
    ndarray, shape (3, 4)
        View factors, dimensionless; row k is pair k's ``[room, pair 0, pair 1, pair 2]``.
    """
    key = tuple(_rounded(r) for r in rings)
    return _traced(key, int(rays))
