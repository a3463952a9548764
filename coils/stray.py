"""The stray field of a rotating-field drive: the largest |B| over a turn, and where it fades.

At a point p the currents I(t) = a cos ωt + b sin ωt of one heading's allocation make
B(p, t) = P cos ωt + Q sin ωt with P = G(p) a, Q = G(p) b: an ellipse whose largest |B| over a
turn is its major semi-axis, the square root of the larger eigenvalue of the Gram matrix of P
and Q (no projection: every component counts for a device in the room). Over a set of headings
the peak is the largest of theirs. :func:`fade_distance_m` walks out from the centre along a
direction and returns the distance beyond which that peak stays below a level (the 0.5 mT ICNIRP
2009 gives for implanted devices such as pacemakers).

No I/O; numpy only (a post-processing of an operating point).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = ["allocation_vectors", "fade_distance_m", "peak_field_T"]

#: Samples along a ray (out to the search radius) before the crossing is refined.
RAY_SAMPLES = 400


def allocation_vectors(amplitudes_A: Any, phases_rad: Any) -> tuple[np.ndarray, np.ndarray]:
    """(a, b) of I(t) = a cos ωt + b sin ωt from I_k = A_k cos(ωt + φ_k), A.

    Parameters
    ----------
    amplitudes_A : array_like, shape (3,)
        Current amplitudes A_k, A.
    phases_rad : array_like, shape (3,)
        Phases φ_k, rad.

    Returns
    -------
    a, b : ndarray, shape (3,)
        Cosine and sine coefficients, A.
    """
    amps = np.asarray(amplitudes_A, dtype=float)
    phases = np.asarray(phases_rad, dtype=float)
    return amps * np.cos(phases), -amps * np.sin(phases)


def peak_field_T(
    field_matrix_T_per_A: np.ndarray, allocations: Sequence[tuple[np.ndarray, np.ndarray]]
) -> np.ndarray:
    """Largest |B| over a turn at each point, over every allocation, T.

    Parameters
    ----------
    field_matrix_T_per_A : ndarray, shape (n, 3, 3)
        G(p) at the points, T/A.
    allocations : sequence of (a, b)
        Cosine and sine current coefficients of each heading, A.

    Returns
    -------
    ndarray, shape (n,)
        max over headings and over a turn of |B(p, t)|, T.
    """
    g = np.asarray(field_matrix_T_per_A, dtype=float)
    peak = np.zeros(len(g))
    for a, b in allocations:
        p, q = g @ np.asarray(a, float), g @ np.asarray(b, float)
        pp, qq, pq = (np.einsum("ij,ij->i", x, y) for x, y in ((p, p), (q, q), (p, q)))
        major = 0.5 * (pp + qq) + np.sqrt((0.5 * (pp - qq)) ** 2 + pq * pq)
        peak = np.maximum(peak, np.sqrt(major))
    return peak


def fade_distance_m(
    field_matrix: Any,
    allocations: Sequence[tuple[np.ndarray, np.ndarray]],
    direction: Any,
    level_T: float,
    reach_m: float,
) -> float:
    """Distance from the centre along ``direction`` beyond which the peak |B| stays < level, m.

    The ray is sampled at :data:`RAY_SAMPLES` points out to ``reach_m``; the last sample at or
    above the level and the next one bracket the crossing, refined by bisection to 1e-6 of the
    reach. The field of air coils falls as a dipole's, |B| ~ r^-3, beyond the windings, so
    ``reach_m`` a few coil sizes out brackets the last crossing.

    Parameters
    ----------
    field_matrix : callable
        ``field_matrix(points_m) -> (n, 3, 3)`` in T/A (a coil set's ``field_matrix``).
    allocations : sequence of (a, b)
        Cosine and sine current coefficients of each heading, A.
    direction : array_like, shape (3,)
        The ray's direction (normalised here), dimensionless.
    level_T : float
        The level, T.
    reach_m : float
        How far out to search, m.

    Returns
    -------
    float
        The fade distance, m: 0 if the peak is below the level everywhere on the ray, ``inf``
        if it is still above the level at ``reach_m``.
    """
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    r = np.linspace(0.0, reach_m, RAY_SAMPLES + 1)

    def peak(radii: np.ndarray) -> np.ndarray:
        return peak_field_T(field_matrix(np.outer(radii, d)), allocations)

    above = np.nonzero(peak(r) >= level_T)[0]
    if above.size == 0:
        return 0.0
    last = int(above[-1])
    if last == len(r) - 1:
        return float("inf")
    lo, hi = float(r[last]), float(r[last + 1])
    while hi - lo > 1e-6 * reach_m:
        mid = 0.5 * (lo + hi)
        if peak(np.array([mid]))[0] >= level_T:
            lo = mid
        else:
            hi = mid
    return hi
