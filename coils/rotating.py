"""Rotating-field current allocation and the field ellipse it makes elsewhere.

A field of amplitude B0 turning right-handedly about a unit heading n,
B(t) = B0 (u cos ωt + v sin ωt) with u ⟂ n and v = n x u, is made by currents
I(t) = a cos ωt + b sin ωt with G a = B0 u, G b = B0 v, where G is the field matrix at the point
(diagonal at the centre of a three-axis Helmholtz system). Each current is reported as
I_k(t) = A_k cos(ωt + φ_k): A_k = sqrt(a_k² + b_k²), φ_k = atan2(-b_k, a_k). At the centre this
gives A_k = B0 sqrt(1 - n_k²) / g_k.
"""

from __future__ import annotations

import numpy as np

from spiralcap.core.checks import finite, guard
from spiralcap.core.errors import InputError

__all__ = ["allocation", "ellipse_semi_axes", "heading_frame"]


@guard(heading=finite())
def heading_frame(heading: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit heading n and a right-handed pair u, v = n x u spanning the plane ⟂ n.

    u is the coordinate axis least aligned with n (the first of ties), made orthogonal to n.

    Parameters
    ----------
    heading : array_like, shape (3,)
        Rotation axis, any length > 0 (dimensionless).

    Raises
    ------
    InputError
        ``heading`` not three finite numbers of non-zero length.

    Returns
    -------
    n, u, v : ndarray, shape (3,)
        Orthonormal right-handed frame, dimensionless.

    Examples
    --------
    >>> from coils import heading_frame
    >>> n, u, v = heading_frame([0.0, 0.0, 2.0])
    >>> print(n, u, v)
    [0. 0. 1.] [1. 0. 0.] [0. 1. 0.]
    """
    h = np.asarray(heading, dtype=float)
    norm = float(np.linalg.norm(h)) if h.shape == (3,) else 0.0
    if not (np.isfinite(norm) and norm > 0.0):
        raise InputError("heading", heading, "three finite numbers, not all zero")
    n = h / norm
    a = np.zeros(3)
    a[int(np.argmin(np.abs(n)))] = 1.0
    u = a - (a @ n) * n
    u /= np.linalg.norm(u)
    return n, u, np.cross(n, u)


def allocation(
    field_matrix_T_per_A: np.ndarray, heading: np.ndarray, amplitude_T: float
) -> tuple[np.ndarray, np.ndarray]:
    """Current amplitudes and phases that make the rotating field where G applies.

    Parameters
    ----------
    field_matrix_T_per_A : ndarray, shape (3, 3)
        G with B = G I at the point, T/A.
    heading : array_like, shape (3,)
        Rotation axis n, dimensionless (normalised here).
    amplitude_T : float
        Field amplitude B0, T.

    Returns
    -------
    amplitudes_A : ndarray, shape (3,)
        Current amplitudes A_k, A.
    phases_rad : ndarray, shape (3,)
        Phases φ_k of I_k(t) = A_k cos(ωt + φ_k), rad.
    """
    _, u, v = heading_frame(heading)
    coeffs = np.linalg.solve(field_matrix_T_per_A, np.column_stack([u, v])) * amplitude_T
    a, b = coeffs[:, 0], coeffs[:, 1]
    return np.hypot(a, b), np.arctan2(-b, a)


def ellipse_semi_axes(
    field_cos_T: np.ndarray, field_sin_T: np.ndarray, heading: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Semi-axes of the ellipse P cos ωt + Q sin ωt projected onto the plane ⟂ heading.

    The squared semi-axes are the eigenvalues of the 2 x 2 Gram matrix of the projected P, Q;
    the smaller is taken as det / larger to avoid cancellation.

    Parameters
    ----------
    field_cos_T, field_sin_T : ndarray, shape (n, 3)
        Field vectors P and Q, T.
    heading : array_like, shape (3,)
        Rotation axis n, dimensionless (normalised here).

    Returns
    -------
    minor_T, major_T : ndarray, shape (n,)
        Smallest and largest field magnitude in the plane ⟂ n during one turn, T.
    """
    n, _, _ = heading_frame(heading)
    p = field_cos_T - np.outer(field_cos_T @ n, n)
    q = field_sin_T - np.outer(field_sin_T @ n, n)
    pp, qq, pq = (np.einsum("ij,ij->i", x, y) for x, y in ((p, p), (q, q), (p, q)))
    half_trace = 0.5 * (pp + qq)
    big = half_trace + np.sqrt((0.5 * (pp - qq)) ** 2 + pq * pq)
    det = np.maximum(pp * qq - pq * pq, 0.0)
    small = np.divide(det, big, out=np.zeros_like(big), where=big > 0)
    return np.sqrt(small), np.sqrt(big)
