"""A set of coaxial-loop filaments along the x, y or z axis, and the field they make.

Every coil in this package is a list of circular filaments, each with an axis (x, y or z), a
radius, an axial centre, a number of turns and the drive current (column) it belongs to. The
field of all of them at once is assembled here, once, for numpy point arrays and for CasADi
row vectors alike.

For a filament along axis a, a point p has axial coordinate ζ = p_a and the field per ampere is
B = s (p - ζ e_a) + b_z e_a = s p + (b_z - s ζ) e_a with s = B_ρ/ρ (see :mod:`coils.loop`). Summed
over the filaments of drive column k, with turns N_l,

    B(p) = Σ_k I_k [S_k(p) p + T_k(p) e_{a_k}],  S_k = Σ N_l s_l,  T_k = Σ N_l (b_z,l - s_l ζ_l),

so the field matrix is G(p) = p S^T + diag-like T and B = G(p) I.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from coils.loop import ROW_SCRATCH, loop_terms, loop_terms_rows
from spiralcap.core import backend as bk
from spiralcap.core.backend import Scalar

__all__ = ["AXES", "FilamentSet", "gauss_legendre_pack"]

#: A coil axis, as the option strings the pairs and the design use.
Axis = Literal["x", "y", "z"]
AXES: tuple[Axis, Axis, Axis] = ("x", "y", "z")

#: The last scratch of the numpy path (see FilamentSet._workspace): (sizes, buffers).
_WORK: dict[str, Any] = {}

#: Point-filament pairs per chunk on the numpy path: bounds the scratch (about 7 MB) and keeps
#: it reused, whatever the number of filaments.
CHUNK_ELEMENTS = 49152


def _each_chunk(n_points: int, step: int, fn: Callable[[int], None]) -> None:
    """``fn(start)`` for every chunk start, in order."""
    for start in range(0, n_points, step):
        fn(start)


def _groups(axes: np.ndarray) -> tuple[list[int], int] | None:
    """(axis of each group, filaments per group) if the filaments come in contiguous runs of
    equal length, one run per axis (every pair and system here); else None."""
    axes = np.asarray(axes)
    starts = np.flatnonzero(np.r_[True, axes[1:] != axes[:-1]])
    counts = np.diff(np.r_[starts, axes.size])
    order = axes[starts].tolist()
    if len(set(order)) != len(order) or np.any(counts != counts[0]):
        return None
    return order, int(counts[0])


def _chunk(n_filaments: int) -> int:
    """Points per chunk: about CHUNK_ELEMENTS point-filament pairs (8192 points for six loops)."""
    return max(64, CHUNK_ELEMENTS // max(n_filaments, 1))


def gauss_legendre_pack(
    side_m: float, counts: tuple[int, int], width_m: float | None = None
) -> tuple[np.ndarray, ...]:
    """Gauss-Legendre nodes and weights over a winding pack of radial depth ``side_m``.

    Parameters
    ----------
    side_m : float
        Radial depth of the pack (the side of a square pack), m.
    counts : (int, int)
        Number of nodes across the radial and the axial extent.
    width_m : float, optional
        Axial width of the pack, m (default: ``side_m``, a square).

    Returns
    -------
    d_radial_m, d_axial_m, weight : ndarray, shape (counts[0] * counts[1],)
        Offsets of the nodes from the pack centre, m, and weights summing to 1.
    """
    xr, wr = np.polynomial.legendre.leggauss(counts[0])
    xz, wz = np.polynomial.legendre.leggauss(counts[1])
    width = side_m if width_m is None else width_m
    dr, dz = np.meshgrid(0.5 * side_m * xr, 0.5 * width * xz, indexing="ij")
    w = np.outer(wr, wz) / 4.0
    return dr.ravel(), dz.ravel(), w.ravel()


@dataclass(frozen=True)
class FilamentSet:
    """Filaments l = 0..L-1 with axis, radius, axial centre, turns and drive column.

    Parameters
    ----------
    axes : ndarray of int, shape (L,)
        Axis index of each filament (0, 1, 2 for x, y, z).
    radii_m : ndarray, shape (L,)
        Filament radii, m.
    centres_m : ndarray, shape (L,)
        Axial coordinate of each filament's plane, m.
    turns : ndarray, shape (L,)
        Ampere-turns per ampere of drive current (may be fractional for a quadrature node).
    columns : ndarray of int, shape (L,)
        Drive current each filament carries (index into the current vector).
    column_axes : tuple of int
        Axis index (0, 1, 2) of each drive column (all its filaments share it).
    """

    axes: np.ndarray
    radii_m: np.ndarray
    centres_m: np.ndarray
    turns: np.ndarray
    columns: np.ndarray
    column_axes: tuple[int, ...]
    _mats: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    @property
    def n_currents(self) -> int:
        """Number of drive currents, count."""
        return len(self.column_axes)

    def _matrices(self, casadi: bool) -> dict[str, Scalar]:
        if casadi not in self._mats:
            L, ncol = len(self.radii_m), self.n_currents
            along = np.zeros((3, L))
            along[self.axes, np.arange(L)] = 1.0
            weights = np.zeros((L, ncol))
            weights[np.arange(L), self.columns] = self.turns
            direction = np.zeros((ncol, 3))
            direction[np.arange(ncol), self.column_axes] = 1.0
            mats: dict[str, Any] = {
                "along": along,
                "across": 1.0 - along,
                "weights": weights,
                "radii": self.radii_m[None, :],
                "centres": self.centres_m[None, :],
                "direction": direction,
            }
            if casadi:
                import casadi as ca

                mats = {k: ca.DM(v) for k, v in mats.items()}
            self._mats[casadi] = mats
        return self._mats[casadi]

    def terms(self, points: Scalar) -> tuple[Scalar, Scalar]:
        """S and T of the module docstring at each point.

        Parameters
        ----------
        points : ndarray (n, 3) or CasADi (1, 3)
            Field points (rows), m.

        Returns
        -------
        S, T : ndarray (n, n_currents) or CasADi (1, n_currents)
            S in T/(A·m), T in T/A.
        """
        if not bk.is_casadi(points):
            P = np.ascontiguousarray(np.asarray(points, dtype=float).T)
            S, T = self._terms_rows(P)
            return S.T.copy(), T.T.copy()
        mats = self._matrices(True)
        zeta = points @ mats["along"]
        rho_sq = (points * points) @ mats["across"]
        rho = bk.sqrt_guarded(rho_sq)  # finite derivatives on the axis
        s, b_z = loop_terms(mats["radii"], zeta - mats["centres"], rho, rho_sq)
        return s @ mats["weights"], (b_z - s * zeta) @ mats["weights"]

    def _terms_rows(
        self, P: np.ndarray, work: dict[str, np.ndarray] | None = None
    ) -> tuple[np.ndarray, np.ndarray]:
        """S and T as (n_currents, n) rows for points given as (3, n) rows (numpy path).

        ρ² and ρ are computed once per axis (3 rows) and shared by every filament on that axis
        (both coils of a pair and all their quadrature nodes); the filament terms come from
        :func:`coils.loop.loop_terms_rows` with one row per filament. All filaments of a drive
        column share its axis a_k, so T_k = Σ N_l b_z,l - p_{a_k} S_k. ``work`` holds the
        buffers of :meth:`_workspace` for this n (results are views into it).
        """
        rows = self._rows()
        w = self._workspace(P.shape[1]) if work is None else work
        P_sq, rho_sq3, rho3 = w["P_sq"], w["rho_sq3"], w["rho3"]
        np.multiply(P, P, out=P_sq)
        np.subtract(P_sq.sum(axis=0), P_sq, out=rho_sq3)  # distance² from the x, y, z axes
        np.sqrt(rho_sq3, out=rho3)
        n = P.shape[1]
        if rows["groups"] is not None:  # g axes of k filaments each: broadcast, no gathers
            axes, k = rows["groups"]
            g = len(axes)
            dz = w["dz"].reshape(g, k, n)
            np.subtract(P[axes, None, :], rows["centres"].reshape(g, k, 1), out=dz)
            s, b_z = loop_terms_rows(
                rows["radii"].reshape(g, k, 1),
                dz,
                rho3[axes, None, :],
                rho_sq3[axes, None, :],
                w["scratch"].reshape(ROW_SCRATCH, g, k, n),
            )
            s, b_z = s.reshape(-1, n), b_z.reshape(-1, n)
        else:
            dz, rho, rho_sq = w["dz"], w["rho"], w["rho_sq"]
            np.take(P, self.axes, axis=0, out=dz)
            dz -= rows["centres"]
            np.take(rho3, self.axes, axis=0, out=rho)
            np.take(rho_sq3, self.axes, axis=0, out=rho_sq)
            s, b_z = loop_terms_rows(rows["radii"], dz, rho, rho_sq, w["scratch"])
        S, T, tmp = w["S"], w["T"], w["tmp"]
        np.matmul(rows["weights"], s, out=S)
        np.matmul(rows["weights"], b_z, out=T)
        np.take(P, rows["column_axes"], axis=0, out=tmp)
        tmp *= S
        T -= tmp
        return S, T

    def _workspace(self, n: int) -> dict[str, np.ndarray]:
        """Buffers for :meth:`_terms_rows` on n points, reused chunk after chunk.

        Scratch only (no content survives a call), so the last one built is
        kept and handed to any filament set of the same sizes: repeated small calls skip the
        allocation, and a big batch keeps its pages.
        """
        L, k = len(self.radii_m), self.n_currents
        key = (L, k, n)
        cached = _WORK.get("last")
        if cached is not None and cached[0] == key:
            return cached[1]
        shapes = {
            "P": (3, n),
            "P_sq": (3, n),
            "rho_sq3": (3, n),
            "rho3": (3, n),
            "dz": (L, n),
            "rho": (L, n),
            "rho_sq": (L, n),
            "scratch": (ROW_SCRATCH, L, n),
            "S": (k, n),
            "T": (k, n),
            "tmp": (k, n),
            "B": (3, n),
        }
        sizes = [math.prod(shape) for shape in shapes.values()]
        flat = np.empty(sum(sizes))  # one allocation, carved into contiguous views
        ends = np.cumsum(sizes)
        work = {
            name: flat[end - size : end].reshape(shape)
            for (name, shape), size, end in zip(shapes.items(), sizes, ends, strict=True)
        }
        _WORK["last"] = (key, work)
        return work

    def _rows(self) -> dict[str, np.ndarray]:
        if "rows" not in self._mats:
            weights = np.zeros((self.n_currents, len(self.radii_m)))
            weights[self.columns, np.arange(len(self.radii_m))] = self.turns
            self._mats["rows"] = {
                "radii": np.asarray(self.radii_m, dtype=float)[:, None],
                "centres": np.asarray(self.centres_m, dtype=float)[:, None],
                "weights": weights,
                "column_axes": np.asarray(self.column_axes, dtype=np.intp),
                "groups": _groups(self.axes),
                "direction": self._matrices(False)["direction"].T.copy(),
            }
        return self._mats["rows"]

    def field(self, points: Scalar, currents: Scalar) -> Scalar:
        """Field B = G(p) I, T, for numpy (n, 3) points or a CasADi (1, 3) row.

        Parameters
        ----------
        points : ndarray (n, 3) or CasADi (1, 3)
            Field points, m.
        currents : ndarray or CasADi, shape (n_currents, 1)
            Drive currents as a column, A.

        Returns
        -------
        ndarray (n, 3) or CasADi (1, 3)
            Magnetic flux density, T.
        """
        if bk.is_casadi(points):
            S, T = self.terms(points)
            direction = self._matrices(True)["direction"]
            return points * (S @ currents) + (T * currents.T) @ direction
        points = np.asarray(points, dtype=float)
        currents = np.asarray(currents, dtype=float)
        direction = self._rows()["direction"]
        out = np.empty((len(points), 3))
        step = _chunk(len(self.radii_m))

        def one(start: int) -> None:
            chunk = points[start : start + step]
            work = self._workspace(len(chunk))
            P, B = work["P"], work["B"]
            np.copyto(P, chunk.T)
            S, T = self._terms_rows(P, work)
            np.multiply(P, currents.T @ S, out=B)
            T *= currents
            B += direction @ T
            out[start : start + step] = B.T

        _each_chunk(len(points), step, one)
        return out

    def field_matrix(self, points: np.ndarray) -> np.ndarray:
        """G(p), shape (n, 3, n_currents), T/A, with B(p) = G(p) @ I (numpy path).

        Parameters
        ----------
        points : ndarray, shape (n, 3)
            Field points, m.

        Returns
        -------
        ndarray, shape (n, 3, n_currents)
            Field per ampere of each drive current, T/A.
        """
        out = np.empty((len(points), 3, self.n_currents))
        direction = self._rows()["direction"]
        step = _chunk(len(self.radii_m))

        def one(start: int) -> None:
            chunk = points[start : start + step]
            work = self._workspace(len(chunk))
            P = work["P"]
            np.copyto(P, chunk.T)
            S, T = self._terms_rows(P, work)
            G = P[:, None, :] * S[None, :, :] + direction[:, :, None] * T[None, :, :]
            out[start : start + step] = G.transpose(2, 0, 1)

        _each_chunk(len(points), step, one)
        return out
