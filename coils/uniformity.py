"""Field uniformity: relative deviation of |B| from its centre value, and the uniform sphere.

The uniform-region radius is found along rays from the centre: for each ray the first radius
at which |deviation| exceeds the tolerance (a scan on a radial grid, then a bracketed root; all
rays in the same array calls), and the sphere radius is the smallest over the rays. The rays
are a Fibonacci lattice on the sphere plus the axes and the face and body diagonals, where the
extremes of a symmetric system lie. Several tolerances share one search
(:func:`uniform_regions`): one scan of the deviation serves them all and their roots and
refinements run in the same calls. A pair alone is axisymmetric (one meridian half-plane), and
pairs that are the same in units of their radius are searched once
(:func:`pair_uniform_regions`)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from coils.system import PAIR_TYPES, ThreeAxisHelmholtz
from spiralcap.core.checks import Spec, finite, guard
from spiralcap.core.errors import InputError, check_positive

__all__ = [
    "UniformRegion",
    "pair_uniform_regions",
    "uniform_region",
    "uniform_region_radius_m",
    "uniform_regions",
    "uniformity",
]

#: The 13 symmetry directions of a cube, unit vectors: the axes, the six face diagonals and the
#: four body diagonals (up to sign); also the default headings (optimize.system).
CUBE_DIRECTIONS = np.array(
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
CUBE_DIRECTIONS /= np.linalg.norm(CUBE_DIRECTIONS, axis=1, keepdims=True)
CUBE_DIRECTIONS.flags.writeable = False
_SYMMETRY_DIRECTIONS = CUBE_DIRECTIONS
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
    if isinstance(coils, PAIR_TYPES):
        current = 1.0 if currents_A is None else float(currents_A)
        return lambda p: coils.field(p, current)
    if isinstance(coils, ThreeAxisHelmholtz):
        currents = np.asarray(currents_A, dtype=float)
        if currents.shape != (3,) or not np.all(np.isfinite(currents)) or not np.any(currents):
            raise InputError("currents_A", currents_A, "three finite currents, not all zero")
        return lambda p: coils.field(p, currents)
    raise InputError(
        "system",
        type(coils).__name__,
        "a coil pair (HelmholtzPair, SquarePair, RectanglePair) or ThreeAxisHelmholtz",
    )


def _deviation(
    field: Callable[[np.ndarray], np.ndarray], points: np.ndarray, centre_T: float | None = None
) -> np.ndarray:
    if centre_T is None:
        centre_T = float(np.linalg.norm(field(np.zeros((1, 3)))[0]))
    return np.linalg.norm(field(points), axis=1) / centre_T - 1.0


@guard(points_m=finite(), currents_A=finite(optional=True))
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
        Relative deviation of the field magnitude from the centre value, dimensionless.

    Examples
    --------
    5 cm from the centre of a 0.3 m pair, on its axis and across it: the field falls on the axis
    and rises across it, as the fourth-order term of a Helmholtz pair says:

    >>> import numpy as np
    >>> from coils import HelmholtzPair, uniformity
    >>> dev = uniformity(HelmholtzPair(0.3, 300, "z"), np.array([[0, 0, 0.05], [0.05, 0, 0]]))
    >>> print(np.round(dev * 100, 4))  # %
    [-0.0862 -0.0342]
    """
    points = np.atleast_2d(np.asarray(points_m, dtype=float))
    return _deviation(_field_function(system, currents_A), points)


def _scan(
    field: Callable[[np.ndarray], np.ndarray],
    rays: np.ndarray,
    radii: np.ndarray,
    centre_T: float,
) -> np.ndarray:
    """|deviation| on the grid rays x radii in one field call, shape (rays, radii)."""
    pts = (radii[None, :, None] * rays[:, None, :]).reshape(-1, 3)
    return np.abs(_deviation(field, pts, centre_T)).reshape(len(rays), len(radii))


def _brackets(
    absdev: np.ndarray,
    tolerance: np.ndarray,
    radii: np.ndarray,
    r_max: float,
    cut: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Grid bracket [lo, hi] of each ray's first crossing of its tolerance (r_max, r_max if none).

    ``cut`` (per ray): only the radii up to index ``cut`` count for that ray.
    """
    outside = absdev > tolerance[:, None]
    if cut is not None:
        outside &= np.arange(absdev.shape[1])[None, :] <= cut[:, None]
    hit = outside.any(axis=1)
    first = np.argmax(outside, axis=1)
    hi = np.where(hit, radii[first], r_max)
    lo = np.where(first > 0, radii[np.maximum(first - 1, 0)], 0.0)
    lo = np.where(hit, lo, r_max)
    return lo, hi


def _first_crossing(
    field: Callable[[np.ndarray], np.ndarray],
    tolerance: float | np.ndarray,
    r_max: float,
    rays: np.ndarray,
    r_scan: float | np.ndarray | None = None,
    centre_T: float | None = None,
) -> np.ndarray:
    """First radius along each ray where |deviation| > tolerance (r_max if none), m.

    All rays at once, each with its own tolerance and scan limit if given as arrays: the radial
    grid of ``_RADIAL_STEPS`` steps up to ``r_max`` (for each ray cut after its ``r_scan``
    when given: rays with no crossing before it report r_max) in one field call, then the
    bracketed root of every ray together (:func:`_bracketed_root`).
    """
    if centre_T is None:
        centre_T = float(np.linalg.norm(field(np.zeros((1, 3)))[0]))
    tol = np.broadcast_to(np.asarray(tolerance, dtype=float), (len(rays),))
    radii = np.linspace(0.0, r_max, _RADIAL_STEPS + 1)[1:]
    cut = None
    if r_scan is not None:
        cut = np.searchsorted(radii, np.broadcast_to(np.asarray(r_scan, dtype=float), len(rays)))
        radii = radii[: int(cut.max()) + 1]
    lo, hi = _brackets(_scan(field, rays, radii, centre_T), tol, radii, r_max, cut)
    return _bracketed_root(field, tol, rays, lo, hi, centre_T, r_max)


def _bracketed_root(
    field: Callable[[np.ndarray], np.ndarray],
    tolerance: np.ndarray,
    rays: np.ndarray,
    lo: np.ndarray,
    hi: np.ndarray,
    centre_T: float,
    r_max: float,
) -> np.ndarray:
    """Root of |deviation(r u)| = tolerance in [lo, hi] for every ray u at once, m.

    Illinois false position (Dowell & Jarratt, BIT 11, 1971), vectorised over the rays (each
    with its own tolerance): the bracket [lo, hi] (inside at lo, outside at hi) shrinks on both
    sides superlinearly; the iteration stops when every bracket is narrower than ``_ROOT_XTOL``
    r_max, or falls back to bisection after ``_ROOT_MAX_ITER``. Returns the inner end lo
    (inside the tolerance).
    """

    def f(r: np.ndarray, u: np.ndarray, t: np.ndarray) -> np.ndarray:
        return np.abs(_deviation(field, r[:, None] * u, centre_T)) - t

    xtol = _ROOT_XTOL * r_max
    lo, hi = lo.copy(), hi.copy()
    todo = np.nonzero(hi - lo > xtol)[0]
    if todo.size == 0:
        return lo
    tol = tolerance[todo]
    f_lo = np.where(lo[todo] > 0.0, f(lo[todo], rays[todo], tol), -tol)
    f_hi = f(hi[todo], rays[todo], tol)
    side = np.zeros(todo.size, dtype=int)  # +1 if hi moved last, -1 if lo moved last
    for it in range(_ROOT_MAX_ITER + _BISECTIONS):
        a, b = lo[todo], hi[todo]
        if it < _ROOT_MAX_ITER:
            x = b - f_hi * (b - a) / (f_hi - f_lo)
            x = np.where((x > a) & (x < b), x, 0.5 * (a + b))
        else:
            x = 0.5 * (a + b)
        fx = f(x, rays[todo], tol)
        out = fx > 0.0
        hi[todo] = np.where(out, x, b)
        lo[todo] = np.where(out, a, x)
        f_lo = np.where(out, np.where(side > 0, 0.5 * f_lo, f_lo), fx)
        f_hi = np.where(out, fx, np.where(side < 0, 0.5 * f_hi, f_hi))
        side = np.where(out, 1, -1)
        keep = hi[todo] - lo[todo] > xtol
        if not keep.any():
            break
        todo, f_lo, f_hi, side, tol = todo[keep], f_lo[keep], f_hi[keep], side[keep], tol[keep]
    return lo


#: Direction refinement: a (2k+1)² grid in the tangent plane of the worst lattice ray, zoomed
#: by k per level from a half-width of 0.1 (about 6 degrees, the lattice spacing / 2).
_REFINE_HALF_WIDTH = 0.1
_REFINE_K = 4
_REFINE_LEVELS = 8


def _lattice_and_refine(
    field: Callable[[np.ndarray], np.ndarray],
    tolerances: tuple[float, ...],
    r_max: float,
    lattice: np.ndarray,
    start: np.ndarray,
    grid: np.ndarray,
    half: float,
    rays_at: Callable[[np.ndarray, np.ndarray], np.ndarray],
    refine: bool = True,
) -> list[tuple[float, np.ndarray]]:
    """Smallest first-crossing radius (m) and its ray for each tolerance, in shared field calls.

    One radial scan of the ``lattice`` rays serves every tolerance, and the bracketed roots of
    all tolerances run together. Then each tolerance's crossing radius is minimised over
    directions near its worst lattice ray u0 (parameter ``start[k]`` of lattice ray k): the rays
    ``rays_at(u0, centre + half * grid)``, each with its bracketed root; the grid is re-centred
    on its best direction and shrunk ``_REFINE_K``-fold per level, ``_REFINE_LEVELS`` levels.
    Only crossings below the best so far matter, so each level scans the radii up to it. The
    tolerances' refinements run in lockstep, so every level is one scan and one root search.
    Each tolerance's answer is the one a search of that tolerance alone gives.
    """
    centre_T = float(np.linalg.norm(field(np.zeros((1, 3)))[0]))
    tols = np.asarray(tolerances, dtype=float)
    n = len(lattice)
    radii = np.linspace(0.0, r_max, _RADIAL_STEPS + 1)[1:]
    absdev = _scan(field, lattice, radii, centre_T)
    tol_rays = np.repeat(tols, n)
    lo, hi = _brackets(np.tile(absdev, (len(tols), 1)), tol_rays, radii, r_max)
    crossing = _bracketed_root(
        field, tol_rays, np.tile(lattice, (len(tols), 1)), lo, hi, centre_T, r_max
    ).reshape(len(tols), n)
    tie = _ROOT_XTOL * r_max  # crossings closer than the root tolerance are ties: first ray wins
    best_k = [int(np.argmax(c <= c.min() + tie)) for c in crossing]
    best_r = [float(crossing[i, k]) for i, k in enumerate(best_k)]
    origin = [lattice[k] for k in best_k]
    best_u = list(origin)
    centre = [start[k] for k in best_k]
    step = r_max / _RADIAL_STEPS
    active = [i for i in range(len(tols)) if refine and best_r[i] < r_max]
    m = len(grid)
    for _ in range(_REFINE_LEVELS if active else 0):
        params = [centre[i] + half * grid for i in active]
        rays = np.vstack([rays_at(origin[i], p) for i, p in zip(active, params)])
        found = _first_crossing(
            field,
            np.repeat(tols[active], m),
            r_max,
            rays,
            r_scan=np.repeat([best_r[i] + step for i in active], m),
            centre_T=centre_T,
        )
        for j, i in enumerate(active):
            block = found[j * m : (j + 1) * m]
            k = int(np.argmin(block))
            if block[k] < best_r[i] - tie:
                best_r[i], best_u[i], centre[i] = float(block[k]), rays[j * m + k], params[j][k]
        half /= _REFINE_K
    return list(zip(best_r, best_u))


def _tangent_frame(u0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    e1 = np.cross(u0, np.eye(3)[int(np.argmin(np.abs(u0)))])
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(u0, e1)


def _radius(
    field: Callable[[np.ndarray], np.ndarray],
    tolerances: tuple[float, ...],
    r_max: float,
    refine: bool = True,
) -> list[tuple[float, np.ndarray]]:
    """Smallest first-crossing radius over the rays (m) and its ray, for each tolerance.

    The ray lattice (:func:`_rays`); with ``refine`` the crossing radius is then minimised over
    directions near the worst lattice ray, so the answer does not hang on the lattice spacing
    (about 10 degrees): a grid of (2k+1)² directions in the ray's tangent plane, zoomed k-fold
    per level from a half-width of 0.1 down to 0.1 / k**(levels - 1) (~6e-6 rad)
    (:func:`_lattice_and_refine`).
    """
    steps = np.linspace(-1.0, 1.0, 2 * _REFINE_K + 1)
    a, b = (g.ravel() for g in np.meshgrid(steps, steps, indexing="ij"))

    def rays_at(u0: np.ndarray, ab: np.ndarray) -> np.ndarray:
        e1, e2 = _tangent_frame(u0)
        rays = u0 + ab[:, :1] * e1 + ab[:, 1:] * e2
        return rays / np.linalg.norm(rays, axis=1, keepdims=True)

    lattice = _rays()
    start = np.zeros((len(lattice), 2))
    grid = np.column_stack([a, b])
    return _lattice_and_refine(
        field, tolerances, r_max, lattice, start, grid, _REFINE_HALF_WIDTH, rays_at, refine
    )


#: Meridian lattice of an axisymmetric field (a pair alone): polar angles 0..180 deg.
_MERIDIAN_RAYS = 181


def _radius_axisymmetric(
    field: Callable[[np.ndarray], np.ndarray],
    tolerances: tuple[float, ...],
    r_max: float,
    axis: int,
) -> list[tuple[float, np.ndarray]]:
    """As :func:`_radius` for a field symmetric about ``axis``: rays in one meridian half-plane.

    |B| depends only on the polar angle θ from the axis, so the sphere's extreme is on a ray
    of one half-plane: a 1-degree lattice in θ, then the same zoomed refinement in θ alone.
    """
    e_axis, e_perp = np.eye(3)[axis], np.eye(3)[(axis + 1) % 3]

    def rays_at(_u0: np.ndarray, theta: np.ndarray) -> np.ndarray:
        t = theta[:, 0]
        return np.cos(t)[:, None] * e_axis + np.sin(t)[:, None] * e_perp

    thetas = np.linspace(0.0, np.pi, _MERIDIAN_RAYS)
    steps = np.linspace(-1.0, 1.0, 2 * _REFINE_K + 1)
    return _lattice_and_refine(
        field,
        tolerances,
        r_max,
        rays_at(e_axis, thetas[:, None]),
        thetas[:, None],
        steps[:, None],
        float(thetas[1] - thetas[0]),
        rays_at,
    )


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
        Unit direction from the centre along which the deviation first reaches the tolerance,
        dimensionless.
    field_direction : ndarray, shape (3,)
        Unit direction of the centre field for which the radius holds (the worst one tried),
        dimensionless.
    """

    radius_m: float
    tolerance: float
    limiting_ray: np.ndarray
    field_direction: np.ndarray


#: Radial steps per block of the direction ranking (the grid is scanned outward block by block).
_RANK_BLOCK = 20


def _rank_directions(
    system: ThreeAxisHelmholtz, currents: list[np.ndarray], tols: tuple[float, ...], r_max: float
) -> list[list[int]]:
    """Per tolerance, the field directions within one grid step of the worst on the scan grid.

    The worst direction's first crossing (smallest over the rays) is ranked on the ray lattice
    x radial grid, with G(p) and |B| of every direction in one product per block of radii.
    Blocks go outward until every tolerance has its earliest crossing i and the radii up to
    i + 1 (all a direction needs to be within one step of it); crossings further out change no
    candidate, so the answer is that of the whole grid.
    """
    rays = _rays()
    radii = np.linspace(0.0, r_max, _RADIAL_STEPS + 1)[1:]
    C = np.column_stack(currents)
    centre = np.linalg.norm(system.centre_gains_T_per_A[:, None] * C, axis=0)
    blocks: list[np.ndarray] = []
    done = 0
    while done < len(radii):
        stop = min(done + _RANK_BLOCK, len(radii))
        pts = (radii[None, done:stop, None] * rays[:, None, :]).reshape(-1, 3)
        B = system.field_matrix(pts) @ C  # (points, 3, directions)
        dev = np.sqrt(np.einsum("ijk,ijk->ik", B, B)) / centre - 1.0
        blocks.append(np.abs(dev).T.reshape(len(currents), len(rays), stop - done))
        done = stop
        absdev = np.concatenate(blocks, axis=2)
        earliest = [np.nonzero((absdev > tol).any(axis=(0, 1)))[0] for tol in tols]
        if all(e.size and e[0] + 1 < done for e in earliest):
            break
    step = radii[0]
    out = []
    for tol in tols:
        outside = absdev > tol
        first = np.where(outside.any(axis=2), np.argmax(outside, axis=2), len(radii) - 1)
        coarse = radii[first].min(axis=1)
        out.append([k for k, r in enumerate(coarse) if r <= coarse.min() + step])
    return out


def _pair_similarity_key(pair: Any) -> tuple[bytes, ...]:
    """The pair's filaments in units of its radius, and their relative turns (and its shape,
    for a square pair: its half sides in units of ``radius_m``, the half side).

    |B|/|B(0)| of a pair at p is a function of p / R and of this key alone (Biot-Savart is
    scale-free and the current cancels), up to the rotation taking its axis to another (a
    cyclic permutation of the axes, which maps a square's local frame onto another's).
    """
    fs = pair.filament_set
    r = pair.radius_m
    if pair.RING:
        return (
            (fs.radii_m / r).tobytes(),
            (fs.centres_m / r).tobytes(),
            (fs.turns / fs.turns[0]).tobytes(),
        )
    key = (
        b"square",
        (fs.half_sides_m / r).tobytes(),
        (fs.centres_m / r).tobytes(),
        (fs.turns / fs.turns[0]).tobytes(),
    )
    extra = getattr(fs, "half_sides_v_m", None)  # a rectangle's second half sides
    return key if extra is None else (b"rectangle", *key[1:], (extra / r).tobytes())


@guard(tolerances=Spec(low=0.0, high=1.0, low_open=True, high_open=True))
def pair_uniform_regions(pairs: Any, tolerances: Any) -> tuple[tuple[UniformRegion, ...], ...]:
    """:func:`uniform_region` of each pair at each tolerance, ``[pair][tolerance]``.

    All tolerances of a pair share one search (:func:`_lattice_and_refine`). Pairs whose
    filaments are the same in units of their radius (:func:`_pair_similarity_key`, compared
    bit for bit) are searched once: the field of one is the other's scaled and rotated, so its
    radii scale with R and its rays map by the cyclic permutation of the axes.

    Parameters
    ----------
    pairs : sequence of HelmholtzPair
        The pairs, each on its own.
    tolerances : sequence of float
        Allowed relative deviations, dimensionless (0.01 for ±1 %).

    Returns
    -------
    tuple of tuple of UniformRegion
        ``[pair][tolerance]``, radii in m.
    """
    tols = tuple(check_positive("tolerance", t) for t in tolerances)
    done: dict[tuple[bytes, ...], tuple[Any, tuple[UniformRegion, ...]]] = {}
    out = []
    for pair in pairs:
        if not isinstance(pair, PAIR_TYPES):
            raise InputError(
                "pairs",
                type(pair).__name__,
                "coil pairs (HelmholtzPair, SquarePair, RectanglePair)",
            )
        key = _pair_similarity_key(pair)
        axis = pair.axis_index
        if key in done:
            model, regions = done[key]
            scale = pair.radius_m / model.radius_m
            shift = axis - model.axis_index
            mine = tuple(
                UniformRegion(
                    min(r.radius_m * scale, pair.radius_m),
                    r.tolerance,
                    np.roll(r.limiting_ray, shift),
                    np.eye(3)[axis],
                )
                for r in regions
            )
        else:
            field = _field_function(pair, None)
            if pair.RING:
                found = _radius_axisymmetric(field, tols, pair.radius_m, axis)
            else:  # a frame is not axisymmetric: the full ray lattice
                found = _radius(field, tols, pair.radius_m)
            mine = tuple(UniformRegion(r, t, u, np.eye(3)[axis]) for (r, u), t in zip(found, tols))
            done[key] = (pair, mine)
        out.append(mine)
    return tuple(out)


def _single_axis(currents: np.ndarray) -> int | None:
    """The axis k if only pair k carries current, else None."""
    on = np.nonzero(currents)[0]
    return int(on[0]) if len(on) == 1 else None


@guard(tolerances=Spec(low=0.0, high=1.0, low_open=True, high_open=True))
def uniform_regions(
    system_or_pair: Any,
    tolerances: Any,
    currents_A: Any = None,
    direction: Any = None,
    pair_regions: tuple[tuple[UniformRegion, ...], ...] | None = None,
) -> tuple[UniformRegion, ...]:
    """:func:`uniform_region` at several tolerances, sharing the field evaluations.

    One scan of the deviation along each ray serves every tolerance, and the root searches
    and direction refinements of all tolerances run in the same array calls; each result is
    the one :func:`uniform_region` gives for that tolerance alone. A field direction along one
    axis drives that pair alone, an axisymmetric field: its region is the pair's
    (:func:`pair_uniform_regions`, or ``pair_regions[axis]`` when given for these
    tolerances) if that lies inside the smallest coil, as the system's search is capped there.

    Parameters
    ----------
    system_or_pair : ThreeAxisHelmholtz or HelmholtzPair
        The coils.
    tolerances : sequence of float
        Allowed relative deviations, dimensionless (0.01 for ±1 %).
    currents_A : array_like (3,), optional
        System currents, A. If omitted, ``direction`` sets them.
    direction : array_like (3,), optional
        Field direction at the centre, dimensionless (see :func:`uniform_region`).
    pair_regions : tuple of tuple of UniformRegion, optional
        :func:`pair_uniform_regions` of the system's pairs at these tolerances, if known.

    Returns
    -------
    tuple of UniformRegion
        One per tolerance, radii in m.
    """
    tols = tuple(check_positive("tolerance", t) for t in tolerances)
    if isinstance(system_or_pair, PAIR_TYPES):
        return pair_uniform_regions([system_or_pair], tols)[0]
    if not isinstance(system_or_pair, ThreeAxisHelmholtz):
        raise InputError(
            "system_or_pair", type(system_or_pair).__name__, "a HelmholtzPair or ThreeAxisHelmholtz"
        )
    system = system_or_pair
    _check_pair_regions(pair_regions, tols)
    r_max = min(p.radius_m for p in system.pairs)
    gains = system.centre_gains_T_per_A
    currents = _drive_currents(currents_A, direction, gains)
    candidates = [[0] for _ in tols]
    if len(currents) > 1:
        # Rank the directions on the scan grid alone, then refine every direction within one
        # grid step of the worst (per tolerance).
        candidates = _rank_directions(system, currents, tols, r_max)
    found = _search_directions(system, currents, candidates, tols, r_max, pair_regions)
    out = []
    for i, tol in enumerate(tols):
        radius, ray, worst = min(((*found[i, k], k) for k in candidates[i]), key=lambda x: x[0])
        b0 = currents[worst] * gains
        out.append(UniformRegion(radius, tol, ray, b0 / np.linalg.norm(b0)))
    return tuple(out)


def _check_pair_regions(pair_regions: Any, tols: tuple[float, ...]) -> None:
    """InputError unless ``pair_regions`` is None or the three pairs' regions at ``tols``."""
    if pair_regions is not None and (
        len(pair_regions) != 3
        or any(len(regs) != len(tols) for regs in pair_regions)
        or any(r.tolerance != t for regs in pair_regions for r, t in zip(regs, tols))
    ):
        raise InputError(
            "pair_regions", "mismatched", "pair_uniform_regions(system.pairs, tolerances)"
        )


def _drive_currents(currents_A: Any, direction: Any, gains: np.ndarray) -> list[np.ndarray]:
    """The currents (A) of each field direction searched: the given currents, the given
    direction, or the 13 static-field symmetry directions."""
    if currents_A is not None:
        return [np.asarray(currents_A, dtype=float)]
    if direction is not None:
        n = np.asarray(direction, dtype=float)
        if n.shape != (3,) or not np.all(np.isfinite(n)) or not np.any(n):
            raise InputError("direction", direction, "three finite numbers, not all zero")
        return [n / gains]
    return [n / gains for n in _SYMMETRY_DIRECTIONS]


def _search_directions(
    system: ThreeAxisHelmholtz,
    currents: list[np.ndarray],
    candidates: list[list[int]],
    tols: tuple[float, ...],
    r_max: float,
    pair_regions: Any,
) -> dict[tuple[int, int], tuple[float, np.ndarray]]:
    """(tolerance index, direction index) -> (radius, limiting ray): every candidate direction
    searched once for all the tolerances it is a candidate of (a single-axis direction takes
    its pair's region when that lies inside the smallest coil)."""
    found: dict[tuple[int, int], tuple[float, np.ndarray]] = {}
    for k in sorted(set().union(*candidates)):
        mine = [i for i, c in enumerate(candidates) if k in c]
        axis = _single_axis(currents[k])
        if axis is not None:
            if pair_regions is None:
                pair_regions = pair_uniform_regions(system.pairs, tols)
            regions = [pair_regions[axis][i] for i in mine]
            if all(r.radius_m < r_max for r in regions):
                found.update({(i, k): (r.radius_m, r.limiting_ray) for i, r in zip(mine, regions)})
                continue
        field = _field_function(system, currents[k])
        for i, res in zip(mine, _radius(field, tuple(tols[i] for i in mine), r_max)):
            found[i, k] = res
    return found


@guard(tolerance=Spec(low=0.0, high=1.0, low_open=True, high_open=True, scalar=True))
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

    Examples
    --------
    The ±1 % sphere of a circular pair and the ray that ends it (along the axis):

    >>> from coils import HelmholtzPair, uniform_region
    >>> region = uniform_region(HelmholtzPair(0.3, 300, "z"), 0.01)
    >>> print(f"{region.radius_m * 1e3:.1f} mm, limited along {region.limiting_ray}")
    94.1 mm, limited along [0. 0. 1.]
    """
    return uniform_regions(system_or_pair, [tolerance], currents_A, direction)[0]


@guard(tolerance=Spec(low=0.0, high=1.0, low_open=True, high_open=True, scalar=True))
def uniform_region_radius_m(
    system_or_pair: Any, tolerance: float, currents_A: Any = None, direction: Any = None
) -> float:
    """Radius of the largest centred sphere in which | |B|/|B(0)| - 1 | <= tolerance, m.

    See :func:`uniform_region` (same parameters) for the search and the defaults; for a
    system with neither ``currents_A`` nor ``direction`` this is the worst over 13 static
    field directions.

    Parameters
    ----------
    system_or_pair : ThreeAxisHelmholtz or HelmholtzPair
        The coils.
    tolerance : float
        Allowed relative deviation, dimensionless (0.01 for ±1 %).
    currents_A : array_like (3,), optional
        System currents, A.
    direction : array_like (3,), optional
        Field direction at the centre, dimensionless.

    Returns
    -------
    float
        Radius of the uniform sphere, m.

    Examples
    --------
    An ideal circular pair is within ±1 % out to about 0.31 R and ±5 % to about 0.49 R:

    >>> from coils import HelmholtzPair, uniform_region_radius_m
    >>> pair = HelmholtzPair(0.3, 300, "z")
    >>> for tol in (0.01, 0.05):
    ...     print(f"{tol:.0%}: {uniform_region_radius_m(pair, tol) / 0.3:.3f} R")
    1%: 0.314 R
    5%: 0.488 R
    """
    return uniform_region(system_or_pair, tolerance, currents_A, direction).radius_m
