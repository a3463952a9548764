"""Sets of filaments on the x, y and z axes, of any shape, and the field they make.

Every coil in this package is a list of filaments, each with an axis (x, y or z), a size, an
axial centre, a number of turns and the drive current (column) it belongs to. What does not
depend on the shape is written here once (:class:`AxisFilaments`: the constant matrices, the
chunking of numpy points, the numpy or CasADi path); a shape adds its size and its closed-form
field: circular loops here (:class:`FilamentSet`, radii), rectangles and squares in
:mod:`coils.rectangle`.

For a circular filament along axis a, a point p has axial coordinate ζ = p_a and the field per ampere is
B = s (p - ζ e_a) + b_z e_a = s p + (b_z - s ζ) e_a with s = B_ρ/ρ (see :mod:`coils.loop`). Summed
over the filaments of drive column k, with turns N_l,

    B(p) = Σ_k I_k [S_k(p) p + T_k(p) e_{a_k}],  S_k = Σ N_l s_l,  T_k = Σ N_l (b_z,l - s_l ζ_l),

so the field matrix is G(p) = p S^T + diag-like T and B = G(p) I.
"""

from __future__ import annotations

import operator
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import reduce
from typing import Any, ClassVar, Literal

import numpy as np

from coils.loop import loop_terms
from spiralcap.core import backend as bk
from spiralcap.core.backend import Scalar

__all__ = ["AXES", "AxisFilaments", "FilamentSet", "MixedFilamentSet", "gauss_legendre_pack"]

#: A coil axis, as the option strings the pairs and the design use.
Axis = Literal["x", "y", "z"]
AXES: tuple[Axis, Axis, Axis] = ("x", "y", "z")

#: Point-filament pairs per chunk on the numpy path: bounds the temporaries (about 20 arrays
#: of this many floats), whatever the number of filaments.
CHUNK_ELEMENTS = 49152


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


@dataclass(frozen=True, kw_only=True)
class AxisFilaments:
    """Filaments l = 0..L-1 of one shape on the x, y and z axes, and the field they make.

    What a set of filaments has whatever their shape: each lies in the plane p_a = centre of its
    axis a, carries ``turns`` ampere-turns per ampere of the drive current ``columns`` picks,
    and every filament of a drive column shares that column's axis. This class holds them, the
    constant matrices built from them, the chunking of numpy points and the choice between the
    numpy and the CasADi path; a subclass adds the filaments' size (a field named by
    ``_SIZE_KEY``) and the shape's closed-form field: :class:`FilamentSet` (circles) and
    :class:`coils.rectangle.RectangleFilamentSet` (rectangles, squares). Keyword arguments only.

    Parameters
    ----------
    axes : ndarray of int, shape (L,)
        Axis index of each filament (0, 1, 2 for x, y, z).
    centres_m : ndarray, shape (L,)
        Axial coordinate of each filament's plane, m.
    turns : ndarray, shape (L,)
        Ampere-turns per ampere of drive current, a count of turns (fractional for a
        quadrature node).
    columns : ndarray of int, shape (L,)
        Drive current each filament carries (index into the current vector).
    column_axes : tuple of int
        Axis index (0, 1, 2) of each drive column (all its filaments share it).
    """

    axes: np.ndarray
    centres_m: np.ndarray
    turns: np.ndarray
    columns: np.ndarray
    column_axes: tuple[int, ...]
    _mats: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    #: The name of the subclass's field of filament sizes (a radius, a half side), m.
    _SIZE_KEY: ClassVar[str]
    #: Point-filament pairs per chunk of the numpy path (bounds the temporaries).
    _CHUNK_ELEMENTS: ClassVar[int]

    @property
    def n_currents(self) -> int:
        """Number of drive currents, count."""
        return len(self.column_axes)

    def _matrices(self, casadi: bool) -> dict[str, Any]:
        """Constant matrices of the field, numpy or CasADi ``DM`` (built once each).

        ``sel_u``, ``sel_v``, ``sel_w`` (3, L) pick each filament's local coordinates
        u = p_{a+1}, v = p_{a+2}, w = p_a from a point row; ``weights`` (L, k) holds the turns by
        drive column, ``sizes`` and ``centres`` (1, L) the filaments' sizes and planes, m, and
        ``direction`` (k, 3) each column's axis; :meth:`_shape_matrices` adds the shape's own.
        """
        if casadi not in self._mats:
            L, idx = len(self.turns), np.arange(len(self.turns))
            axes = np.asarray(self.axes, dtype=int)
            weights = np.zeros((L, self.n_currents))
            weights[idx, self.columns] = self.turns
            direction = np.zeros((self.n_currents, 3))
            direction[np.arange(self.n_currents), self.column_axes] = 1.0
            mats: dict[str, Any] = {
                "weights": weights,
                "sizes": np.asarray(getattr(self, self._SIZE_KEY), dtype=float)[None, :],
                "centres": np.asarray(self.centres_m, dtype=float)[None, :],
                "direction": direction,
            }
            for name, shift in (("u", 1), ("v", 2), ("w", 0)):
                select = np.zeros((3, L))
                select[(axes + shift) % 3, idx] = 1.0
                mats["sel_" + name] = select
            mats.update(self._shape_matrices(mats))
            if casadi:
                import casadi as ca

                mats = {k: ca.DM(v) for k, v in mats.items()}
            self._mats[casadi] = mats
        return self._mats[casadi]

    def _shape_matrices(self, mats: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """The shape's own constant matrices, from the common ones ``mats`` (none here)."""
        return {}

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
        if bk.is_casadi(points, currents):
            return self._field_rows(points, currents, self._matrices(True))
        return self._by_chunk(points, (3,), self._field_chunk, np.asarray(currents, dtype=float))

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
        return self._by_chunk(points, (3, self.n_currents), self._matrix_chunk)

    def _by_chunk(
        self, points: Any, shape: tuple[int, ...], one: Callable[..., np.ndarray], *args: Any
    ) -> np.ndarray:
        """``one(chunk, *args)``, each of shape (len(chunk), *shape), over chunks of the (n, 3)
        points of about ``_CHUNK_ELEMENTS`` point-filament pairs (at least 64 points), in one
        array."""
        points = np.asarray(points, dtype=float)
        out = np.empty((len(points), *shape))
        step = max(64, self._CHUNK_ELEMENTS // max(len(self.turns), 1))
        for start in range(0, len(points), step):
            out[start : start + step] = one(points[start : start + step], *args)
        return out

    def _field_rows(self, points: Scalar, currents: Scalar, mats: dict[str, Any]) -> Scalar:
        """B, T, at rows of points, m, from the matrices ``mats`` of the same backend
        (the shape's closed form, written once for numpy and CasADi)."""
        raise NotImplementedError

    def _field_chunk(self, points: np.ndarray, currents: np.ndarray) -> np.ndarray:
        """B (n, 3), T, at a chunk of (n, 3) numpy points, m (:meth:`_field_rows` unless the
        shape has a faster numpy path)."""
        return self._field_rows(points, currents, self._matrices(False))

    def _matrix_chunk(self, points: np.ndarray) -> np.ndarray:
        """G (n, 3, n_currents), T/A, at a chunk of (n, 3) numpy points, m."""
        raise NotImplementedError


@dataclass(frozen=True, kw_only=True)
class FilamentSet(AxisFilaments):
    """Circular filaments: the loops of :class:`AxisFilaments` with a radius each.

    The field is the module docstring's S/T form, one code path for numpy and CasADi
    (:meth:`terms`). An own numpy twin of the loop formulas with reused scratch buffers saved
    nothing measurable on any command (issue 38, docs/architecture.md) and was retired.

    Parameters
    ----------
    radii_m : ndarray, shape (L,)
        Filament radii, m.
    axes, centres_m, turns, columns, column_axes : ndarray or tuple
        As in :class:`AxisFilaments`: axis indices, axial centres (m), turns (a count) and drive
        columns of the filaments, and the axis of each column.
    """

    radii_m: np.ndarray

    _SIZE_KEY: ClassVar[str] = "radii_m"
    _CHUNK_ELEMENTS: ClassVar[int] = CHUNK_ELEMENTS

    def _shape_matrices(self, mats: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """``across`` (3, L): 1 on the two coordinates off each filament's axis."""
        return {"across": 1.0 - mats["sel_w"]}

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
        casadi = bk.is_casadi(points)
        if not casadi:
            points = np.asarray(points, dtype=float)
        mats = self._matrices(casadi)
        zeta = points @ mats["sel_w"]
        rho_sq = (points * points) @ mats["across"]
        rho = bk.sqrt_guarded(rho_sq)  # finite derivatives on the axis
        s, b_z = loop_terms(mats["sizes"], zeta - mats["centres"], rho, rho_sq)
        return s @ mats["weights"], (b_z - s * zeta) @ mats["weights"]

    def _field_rows(self, points: Scalar, currents: Scalar, mats: dict[str, Any]) -> Scalar:
        """B = p (S I) + (T I) e_a, T (numpy or CasADi: :meth:`terms`)."""
        S, T = self.terms(points)
        return points * (S @ currents) + (T * currents.T) @ mats["direction"]

    def _matrix_chunk(self, points: np.ndarray) -> np.ndarray:
        """G = p S^T + e_a T^T, shape (n, 3, n_currents), T/A."""
        S, T = self.terms(points)
        direction = self._matrices(False)["direction"]
        return points[:, :, None] * S[:, None, :] + direction.T[None, :, :] * T[:, None, :]


@dataclass(frozen=True)
class MixedFilamentSet:
    """Filament sets of several shapes (circles, rectangles) driven by the same currents: their
    fields add.

    Parameters
    ----------
    parts : tuple
        :class:`FilamentSet` and :class:`coils.rectangle.RectangleFilamentSet` objects with
        the same drive columns (``column_axes``).
    """

    parts: tuple[Any, ...]

    @property
    def column_axes(self) -> tuple[int, ...]:
        """Axis index of each drive column (0, 1, 2 for x, y, z)."""
        return tuple(self.parts[0].column_axes)

    @property
    def n_currents(self) -> int:
        """Number of drive currents."""
        return len(self.column_axes)

    def field(self, points: Scalar, currents: Scalar) -> Scalar:
        return reduce(operator.add, (part.field(points, currents) for part in self.parts))

    def field_matrix(self, points: np.ndarray) -> np.ndarray:
        return reduce(operator.add, (part.field_matrix(points) for part in self.parts))

    # the parts' sum, documented as theirs
    field.__doc__ = AxisFilaments.field.__doc__
    field_matrix.__doc__ = AxisFilaments.field_matrix.__doc__
