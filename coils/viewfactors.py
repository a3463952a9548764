"""Diffuse view factors between the winding packs of a three-axis set and the room.

Each coil's winding pack is a ring of rectangular section (axial width w, radial depth d) about
its pair's axis at ±s/2; its four faces (inner and outer cylinder, two annuli) emit diffusely.
The fraction of a pack's emission that reaches each pair's packs, or escapes to the room, is
found by a deterministic ray trace (fixed seed, cosine-weighted directions from points spread
over the faces in proportion to their area, exact ray-cylinder and ray-plane intersections,
numpy-vectorised), computed once per geometry and cached.

Both coils of a pair are mirror images in the pair's mid-plane, and every pack is symmetric in
the other two mid-planes, so the coil at +s/2 stands for its pair. Row k of the result holds
pair k's area-weighted fractions ``[room, x, y, z]`` (the own-pair entry: its own faces and
its partner coil, at its own temperature; the others: the packs it exchanges radiation with).
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = ["RAYS_PER_PAIR", "PackRing", "view_factors"]

#: Rays traced per pair: the sampling error of a fraction F is sqrt(F (1 - F) / n) <= 0.0035.
RAYS_PER_PAIR = 20_000
_SEED = 19


@dataclass(frozen=True)
class PackRing:
    """One pair's pack geometry (SI): axis index, mean radius, coil spacing, width, depth."""

    axis_index: int
    radius_m: float
    separation_m: float
    width_m: float
    depth_m: float


def _perp(axis: int) -> tuple[int, int]:
    return tuple(i for i in range(3) if i != axis)  # type: ignore[return-value]


def _first_hit(
    p: Sequence[np.ndarray], v: Sequence[np.ndarray], rings: Sequence[PackRing]
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
    """a x b of vectors given as coordinate columns (numpy.cross's arithmetic)."""
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


def _emitters(ring: PackRing, n: int, rng: np.random.Generator) -> tuple:
    """Points and unit outward normals (coordinate columns) and weights (face area share per
    ray) on the +s/2 coil."""
    a = ring.axis_index
    u, w = _perp(a)
    r0, d, wd = ring.radius_m, ring.depth_m, ring.width_m
    r1, r2 = r0 - 0.5 * d, r0 + 0.5 * d
    c = 0.5 * ring.separation_m
    annulus = np.pi * (r2 * r2 - r1 * r1)
    faces = (  # (kind, area)
        ("inner", 2.0 * np.pi * r1 * wd),
        ("outer", 2.0 * np.pi * r2 * wd),
        ("low", annulus),
        ("high", annulus),
    )
    total = sum(area for _, area in faces)
    pts: list[list[np.ndarray]] = [[], [], []]
    nrm: list[list[np.ndarray]] = [[], [], []]
    wts = []
    for kind, area in faces:
        m = max(16, round(n * area / total))
        phi = 2.0 * np.pi * rng.random(m)
        cos, sin = np.cos(phi), np.sin(phi)
        p = [np.zeros(m), np.zeros(m), np.zeros(m)]
        nv = [np.zeros(m), np.zeros(m), np.zeros(m)]
        if kind in ("inner", "outer"):
            rc = r1 if kind == "inner" else r2
            sign = -1.0 if kind == "inner" else 1.0
            p[u], p[w] = rc * cos, rc * sin
            p[a] = c + wd * (rng.random(m) - 0.5)
            nv[u], nv[w] = sign * cos, sign * sin
        else:
            rad = np.sqrt(r1 * r1 + rng.random(m) * (r2 * r2 - r1 * r1))
            p[u], p[w] = rad * cos, rad * sin
            p[a] = np.full(m, c + (0.5 if kind == "high" else -0.5) * wd)
            nv[a] = np.full(m, 1.0 if kind == "high" else -1.0)
        for i in range(3):
            pts[i].append(p[i])
            nrm[i].append(nv[i])
        wts.append(np.full(m, area / total / m))
    return (
        tuple(np.concatenate(x) for x in pts),
        tuple(np.concatenate(x) for x in nrm),
        np.concatenate(wts),
    )


def _cosine_directions(normal: Sequence[np.ndarray], rng: np.random.Generator) -> tuple:
    """Lambert (cosine-weighted) directions about each unit normal (coordinate columns)."""
    m = normal[0].shape[0]
    xi1, xi2 = rng.random(m), rng.random(m)
    s = np.sqrt(xi1)
    t1, t2 = _frame(normal)
    c1, c2, c3 = s * np.cos(2.0 * np.pi * xi2), s * np.sin(2.0 * np.pi * xi2), np.sqrt(1.0 - xi1)
    return tuple(c1 * t1[i] + c2 * t2[i] + c3 * normal[i] for i in range(3))


@functools.lru_cache(maxsize=64)
def _traced(rings: tuple[PackRing, ...], rays: int) -> np.ndarray:
    rng = np.random.default_rng(_SEED)
    out = np.zeros((len(rings), 1 + len(rings)))
    for k, ring in enumerate(rings):
        p, nv, wt = _emitters(ring, rays, rng)
        v = _cosine_directions(nv, rng)
        who = _first_hit(p, v, rings)
        out[k, 0] = wt[who < 0].sum()
        for j in range(len(rings)):
            out[k, 1 + j] = wt[who == j].sum()
    out.setflags(write=False)
    return out


def view_factors(rings: Sequence[PackRing], rays: int = RAYS_PER_PAIR) -> np.ndarray:
    """Fractions of each pair's diffuse emission reaching ``[room, pair 0, pair 1, pair 2]``.

    Rows sum to 1; ``[:, 0]`` is the ``radiation_view_factor`` (what leaves the coil set).
    Deterministic (fixed seed) and cached per geometry (values rounded to 1e-12 m).
    """
    key = tuple(
        PackRing(
            int(r.axis_index),
            round(float(r.radius_m), 12),
            round(float(r.separation_m), 12),
            round(float(r.width_m), 12),
            round(float(r.depth_m), 12),
        )
        for r in rings
    )
    return _traced(key, int(rays))
