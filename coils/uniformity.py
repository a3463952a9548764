"""Field uniformity: relative deviation of |B| from its centre value, and the uniform sphere.

The uniform-region radius is found along rays from the centre: for each ray the first radius
at which |deviation| exceeds the tolerance (a scan on a radial grid, then a bracketed root; all
rays in the same array calls), and the sphere radius is the smallest over the rays. The rays are a Fibonacci lattice on the sphere plus
the axes and the face and body diagonals, where the extremes of a symmetric system lie.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from coils.pair import HelmholtzPair
from coils.system import ThreeAxisHelmholtz
from spiralcap.errors import InputError, check_positive

__all__ = ["UniformRegion", "uniform_region", "uniform_region_radius_m", "uniformity"]

#: The axes, the six face diagonals and the four body diagonals (up to sign).
_SYMMETRY_DIRECTIONS = np.array(
    [
        [1, 0, 0],
        [0, 1, 0],
        [0, 0, 1],
        [1, 1, 0],
        [1, -1, 0],
        [1, 0, 1],
        [1, 0, -1],
        [0, 1, 1],
        [0, 1, -1],
        [1, 1, 1],
        [1, 1, -1],
        [1, -1, 1],
        [-1, 1, 1],
    ],
    dtype=float,
)
_SYMMETRY_DIRECTIONS /= np.linalg.norm(_SYMMETRY_DIRECTIONS, axis=1, keepdims=True)
_FIBONACCI_RAYS = 400
_RADIAL_STEPS = 200
_BISECTIONS = 40
#: Bracketed root: width below this fraction of r_max, within this many false-position steps.
_ROOT_XTOL = 1e-14
_ROOT_MAX_ITER = 30


def _rays() -> np.ndarray:
    k = np.arange(_FIBONACCI_RAYS) + 0.5
    z = 1.0 - 2.0 * k / _FIBONACCI_RAYS
    phi = np.pi * (1.0 + 5.0**0.5) * k
    r = np.sqrt(1.0 - z * z)
    fib = np.column_stack([r * np.cos(phi), r * np.sin(phi), z])
    return np.vstack([_SYMMETRY_DIRECTIONS, -_SYMMETRY_DIRECTIONS, fib])


def _field_function(coils: Any, currents_A: Any) -> Callable[[np.ndarray], np.ndarray]:
    if isinstance(coils, HelmholtzPair):
        current = 1.0 if currents_A is None else float(currents_A)
        return lambda p: coils.field(p, current)
    if isinstance(coils, ThreeAxisHelmholtz):
        currents = np.asarray(currents_A, dtype=float)
        if currents.shape != (3,) or not np.all(np.isfinite(currents)) or not np.any(currents):
            raise InputError("currents_A", currents_A, "three finite currents, not all zero")
        return lambda p: coils.field(p, currents)
    raise InputError("system", type(coils).__name__, "a HelmholtzPair or ThreeAxisHelmholtz")


def _deviation(
    field: Callable[[np.ndarray], np.ndarray], points: np.ndarray, centre_T: float | None = None
) -> np.ndarray:
    if centre_T is None:
        centre_T = float(np.linalg.norm(field(np.zeros((1, 3)))[0]))
    return np.linalg.norm(field(points), axis=1) / centre_T - 1.0


def uniformity(system: Any, points_m: Any, currents_A: Any = None) -> np.ndarray:
    """Relative deviation |B(p)| / |B(0)| - 1 at each point (dimensionless).

    Parameters
    ----------
    system : ThreeAxisHelmholtz or HelmholtzPair
        The coils (centre at the origin).
    points_m : array_like, shape (n, 3)
        Field points, m.
    currents_A : array_like (3,) for a system, float for a pair (default 1 A)
        Drive currents, A.

    Returns
    -------
    ndarray, shape (n,)
        Deviation of the field magnitude from the centre value.
    """
    points = np.atleast_2d(np.asarray(points_m, dtype=float))
    return _deviation(_field_function(system, currents_A), points)


def _first_crossing(
    field: Callable[[np.ndarray], np.ndarray],
    tolerance: float,
    r_max: float,
    rays: np.ndarray,
    r_scan: float | None = None,
) -> np.ndarray:
    """First radius along each ray where |deviation| > tolerance (r_max if none), m.

    All rays at once: the radial grid of ``_RADIAL_STEPS`` steps up to ``r_max`` (cut after
    ``r_scan`` when given: rays with no crossing before it report r_max) in one field call, then
    the bracketed root of every ray together (:func:`_bracketed_root`).
    """
    centre = float(np.linalg.norm(field(np.zeros((1, 3)))[0]))
    radii = np.linspace(0.0, r_max, _RADIAL_STEPS + 1)[1:]
    if r_scan is not None:
        radii = radii[: int(np.searchsorted(radii, r_scan)) + 1]
    pts = (radii[None, :, None] * rays[:, None, :]).reshape(-1, 3)
    outside = (np.abs(_deviation(field, pts, centre)) > tolerance).reshape(len(rays), len(radii))
    hit = outside.any(axis=1)
    first = np.argmax(outside, axis=1)
    hi = np.where(hit, radii[first], r_max)
    lo = np.where(first > 0, radii[np.maximum(first - 1, 0)], 0.0)
    lo = np.where(hit, lo, r_max)
    return _bracketed_root(field, tolerance, rays, lo, hi, centre, r_max)


def _bracketed_root(
    field: Callable[[np.ndarray], np.ndarray],
    tolerance: float,
    rays: np.ndarray,
    lo: np.ndarray,
    hi: np.ndarray,
    centre_T: float,
    r_max: float,
) -> np.ndarray:
    """Root of |deviation(r u)| = tolerance in [lo, hi] for every ray u at once, m.

    Illinois false position (Dowell & Jarratt, BIT 11, 1971), vectorised over the rays: the
    bracket [lo, hi] (inside at lo, outside at hi) shrinks on both sides superlinearly; the
    iteration stops when every bracket is narrower than ``_ROOT_XTOL`` r_max, or falls back to
    bisection after ``_ROOT_MAX_ITER``. Returns the inner end lo (inside the tolerance).
    """

    def f(r: np.ndarray, u: np.ndarray) -> np.ndarray:
        return np.abs(_deviation(field, r[:, None] * u, centre_T)) - tolerance

    xtol = _ROOT_XTOL * r_max
    lo, hi = lo.copy(), hi.copy()
    todo = np.nonzero(hi - lo > xtol)[0]
    if todo.size == 0:
        return lo
    f_lo = np.where(lo[todo] > 0.0, f(lo[todo], rays[todo]), -tolerance)
    f_hi = f(hi[todo], rays[todo])
    side = np.zeros(todo.size, dtype=int)  # +1 if hi moved last, -1 if lo moved last
    for it in range(_ROOT_MAX_ITER + _BISECTIONS):
        a, b = lo[todo], hi[todo]
        if it < _ROOT_MAX_ITER:
            x = b - f_hi * (b - a) / (f_hi - f_lo)
            x = np.where((x > a) & (x < b), x, 0.5 * (a + b))
        else:
            x = 0.5 * (a + b)
        fx = f(x, rays[todo])
        out = fx > 0.0
        hi[todo] = np.where(out, x, b)
        lo[todo] = np.where(out, a, x)
        f_lo = np.where(out, np.where(side > 0, 0.5 * f_lo, f_lo), fx)
        f_hi = np.where(out, fx, np.where(side < 0, 0.5 * f_hi, f_hi))
        side = np.where(out, 1, -1)
        keep = hi[todo] - lo[todo] > xtol
        if not keep.any():
            break
        todo, f_lo, f_hi, side = todo[keep], f_lo[keep], f_hi[keep], side[keep]
    return lo


#: Direction refinement: a (2k+1)² grid in the tangent plane of the worst lattice ray, zoomed
#: by k per level from a half-width of 0.1 (about 6 degrees, the lattice spacing / 2).
_REFINE_HALF_WIDTH = 0.1
_REFINE_K = 4
_REFINE_LEVELS = 8


def _radius(
    field: Callable[[np.ndarray], np.ndarray], tolerance: float, r_max: float, refine: bool = True
) -> tuple[float, np.ndarray]:
    """Smallest first-crossing radius over the rays (m) and the ray where it occurs.

    With ``refine`` the crossing radius is then minimised over directions near the worst
    lattice ray, so the answer does not hang on the lattice spacing (about 10 degrees): a grid
    of (2k+1)² directions in the ray's tangent plane, each with its bracketed root, all in
    array calls; the grid is re-centred on its best direction and shrunk k-fold per level, down
    to a half-width of 0.1 / k**(levels - 1) (~6e-6 rad). Only crossings below the best so far
    matter, so each level scans the radii up to it.
    """
    rays = _rays()
    crossing = _first_crossing(field, tolerance, r_max, rays)
    tie = _ROOT_XTOL * r_max  # crossings closer than the root tolerance are ties: first ray wins
    best = int(np.argmax(crossing <= crossing.min() + tie))
    u0 = rays[best]
    best_r, best_u = float(crossing[best]), u0
    if not refine or best_r >= r_max:
        return best_r, best_u
    e1 = np.cross(u0, np.eye(3)[int(np.argmin(np.abs(u0)))])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(u0, e1)
    steps = np.linspace(-1.0, 1.0, 2 * _REFINE_K + 1)
    a, b = (g.ravel() for g in np.meshgrid(steps, steps, indexing="ij"))
    centre = np.zeros(2)
    half = _REFINE_HALF_WIDTH
    step = r_max / _RADIAL_STEPS
    for _ in range(_REFINE_LEVELS):
        ab = centre + half * np.column_stack([a, b])
        rays = u0 + ab[:, :1] * e1 + ab[:, 1:] * e2
        rays /= np.linalg.norm(rays, axis=1, keepdims=True)
        crossing = _first_crossing(field, tolerance, r_max, rays, r_scan=best_r + step)
        k = int(np.argmin(crossing))
        if crossing[k] < best_r - tie:
            best_r, best_u, centre = float(crossing[k]), rays[k], ab[k]
        half /= _REFINE_K
    return best_r, best_u


#: Meridian lattice of an axisymmetric field (a pair alone): polar angles 0..180 deg.
_MERIDIAN_RAYS = 181


def _radius_axisymmetric(
    field: Callable[[np.ndarray], np.ndarray], tolerance: float, r_max: float, axis: int
) -> tuple[float, np.ndarray]:
    """As :func:`_radius` for a field symmetric about ``axis``: rays in one meridian half-plane.

    |B| depends only on the polar angle θ from the axis, so the sphere's extreme is on a ray
    of one half-plane: a 1-degree lattice in θ, then the same zoomed refinement in θ alone.
    """
    e_axis, e_perp = np.eye(3)[axis], np.eye(3)[(axis + 1) % 3]

    def rays_at(theta: np.ndarray) -> np.ndarray:
        return np.cos(theta)[:, None] * e_axis + np.sin(theta)[:, None] * e_perp

    thetas = np.linspace(0.0, np.pi, _MERIDIAN_RAYS)
    crossing = _first_crossing(field, tolerance, r_max, rays_at(thetas))
    tie = _ROOT_XTOL * r_max
    best = int(np.argmax(crossing <= crossing.min() + tie))
    best_r, best_theta = float(crossing[best]), float(thetas[best])
    if best_r >= r_max:
        return best_r, rays_at(np.array([best_theta]))[0]
    half = thetas[1] - thetas[0]
    steps = np.linspace(-1.0, 1.0, 2 * _REFINE_K + 1)
    step = r_max / _RADIAL_STEPS
    centre = best_theta
    for _ in range(_REFINE_LEVELS):
        theta = centre + half * steps
        crossing = _first_crossing(field, tolerance, r_max, rays_at(theta), r_scan=best_r + step)
        k = int(np.argmin(crossing))
        if crossing[k] < best_r - tie:
            best_r, best_theta, centre = float(crossing[k]), float(theta[k]), float(theta[k])
        half /= _REFINE_K
    return best_r, rays_at(np.array([best_theta]))[0]


@dataclass(frozen=True)
class UniformRegion:
    """Result of :func:`uniform_region`.

    Attributes
    ----------
    radius_m : float
        Radius of the largest centred sphere within tolerance, m.
    tolerance : float
        Relative tolerance used.
    limiting_ray : ndarray, shape (3,)
        Unit direction from the centre along which the deviation first reaches the tolerance.
    field_direction : ndarray, shape (3,)
        Unit direction of the centre field for which the radius holds (the worst one tried).
    """

    radius_m: float
    tolerance: float
    limiting_ray: np.ndarray
    field_direction: np.ndarray


@lru_cache(maxsize=1)
def _scan_matrix(system: ThreeAxisHelmholtz) -> np.ndarray:
    """G(p) on the ray lattice x radial grid, shape (rays * radii, 3, 3), T/A.

    Cached for the last system (frozen, hashable; ~6 MB): both tolerances rank the field
    directions on the same scan, so G on its ~85,000 points is computed once.
    """
    rays = _rays()
    r_max = min(p.radius_m for p in system.pairs)
    radii = np.linspace(0.0, r_max, _RADIAL_STEPS + 1)[1:]
    G = system.field_matrix((radii[None, :, None] * rays[:, None, :]).reshape(-1, 3))
    G.flags.writeable = False
    return G


def uniform_region(
    system_or_pair: Any, tolerance: float, currents_A: Any = None, direction: Any = None
) -> UniformRegion:
    """The largest centred sphere in which | |B|/|B(0)| - 1 | <= tolerance, and where it ends.

    Parameters
    ----------
    system_or_pair : ThreeAxisHelmholtz or HelmholtzPair
        The coils. For a pair the field is along its axis and its size does not matter.
    tolerance : float
        Allowed relative deviation (0.01 for ±1 %).
    currents_A : array_like (3,), optional
        System currents, A. If omitted, ``direction`` sets them.
    direction : array_like (3,), optional
        Field direction at the centre (currents n_k / g_k). If both are omitted, the worst
        over the axes, face diagonals and body diagonals (13 static-field directions): all are
        ranked on the ray lattice's radial grid, and those within one grid step of the worst
        are refined.

    Returns
    -------
    UniformRegion
        Radius capped at the smallest coil radius (the search stops there).
    """
    tol = check_positive("tolerance", tolerance)
    if isinstance(system_or_pair, HelmholtzPair):
        field = _field_function(system_or_pair, None)
        radius, ray = _radius_axisymmetric(
            field, tol, system_or_pair.radius_m, system_or_pair.axis_index
        )
        return UniformRegion(radius, tol, ray, np.eye(3)[system_or_pair.axis_index])
    if not isinstance(system_or_pair, ThreeAxisHelmholtz):
        raise InputError(
            "system_or_pair", type(system_or_pair).__name__, "a HelmholtzPair or ThreeAxisHelmholtz"
        )
    r_max = min(p.radius_m for p in system_or_pair.pairs)
    gains = system_or_pair.centre_gains_T_per_A
    if currents_A is not None:
        currents = [np.asarray(currents_A, dtype=float)]
    elif direction is not None:
        n = np.asarray(direction, dtype=float)
        if n.shape != (3,) or not np.all(np.isfinite(n)) or not np.any(n):
            raise InputError("direction", direction, "three finite numbers, not all zero")
        currents = [n / gains]
    else:
        currents = [n / gains for n in _SYMMETRY_DIRECTIONS]
    candidates = [0]
    if len(currents) > 1:
        # Rank the directions on the scan grid alone, with G(p) computed once for all of them,
        # then refine every direction within one grid step of the worst.
        rays = _rays()
        radii = np.linspace(0.0, r_max, _RADIAL_STEPS + 1)[1:]
        G = _scan_matrix(system_or_pair)
        coarse = []
        for c in currents:
            b = G @ c
            dev = np.sqrt(np.einsum("ij,ij->i", b, b)) / np.linalg.norm(gains * c) - 1.0
            outside = (np.abs(dev) > tol).reshape(len(rays), len(radii))
            first = np.where(outside.any(axis=1), np.argmax(outside, axis=1), len(radii) - 1)
            coarse.append(radii[first].min())
        step = radii[0]
        candidates = [k for k, r in enumerate(coarse) if r <= min(coarse) + step]
    results = [
        (*_radius(_field_function(system_or_pair, currents[k]), tol, r_max), k) for k in candidates
    ]
    radius, ray, worst = min(results, key=lambda x: x[0])
    b0 = currents[worst] * gains
    return UniformRegion(radius, tol, ray, b0 / np.linalg.norm(b0))


def uniform_region_radius_m(
    system_or_pair: Any, tolerance: float, currents_A: Any = None, direction: Any = None
) -> float:
    """Radius of the largest centred sphere in which | |B|/|B(0)| - 1 | <= tolerance, m.

    See :func:`uniform_region` (same parameters) for the search and the defaults; for a
    system with neither ``currents_A`` nor ``direction`` this is the worst over 13 static
    field directions.
    """
    return uniform_region(system_or_pair, tolerance, currents_A, direction).radius_m
