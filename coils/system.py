"""Three orthogonal Helmholtz pairs: field, field matrix, CasADi functions, rotating fields."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from coils.filaments import AXES, FilamentSet, MixedFilamentSet
from coils.rotating import allocation, ellipse_semi_axes
from coils.winding import WoundPair
from spiralcap.core.errors import InputError

__all__ = ["PAIR_TYPES", "PointEvaluator", "ThreeAxisHelmholtz"]

#: The pair classes a three-axis set is made of (circles, squares, rectangles, mixed freely).
PAIR_TYPES = (WoundPair,)


def _points(points_m: Any) -> np.ndarray:
    p = np.atleast_2d(np.asarray(points_m, dtype=float))
    if p.ndim != 2 or p.shape[1] != 3:
        raise InputError("points_m", np.shape(points_m), "an array of shape (n, 3)")
    return p


def _currents(currents_A: Any) -> np.ndarray:
    i = np.asarray(currents_A, dtype=float)
    if i.shape != (3,):
        raise InputError("currents_A", np.shape(currents_A), "three currents (x, y, z), A")
    return i


def _joined(sets: list[Any], columns: list[int]) -> Any:
    """Filament sets of one kind (class) as one set, set i driven by column ``columns[i]``:
    every per-filament field of the class concatenated in order."""
    cls = type(sets[0])
    values: dict[str, Any] = {"column_axes": (0, 1, 2)}
    values["columns"] = np.concatenate([np.full(len(s.turns), k) for k, s in zip(columns, sets)])
    for f in dataclasses.fields(cls):
        if f.init and f.name not in values:
            values[f.name] = np.concatenate([getattr(s, f.name) for s in sets])
    return cls(**values)


class PointEvaluator:
    """Low-overhead repeated calls of a compiled CasADi Function on numpy vectors.

    Uses CasADi's ``Function.buffer()``: inputs and outputs are fixed numpy arrays the Function
    reads and writes in place, so a call costs a copy-in, the evaluation and a copy-out. Not
    thread-safe (one buffer per evaluator).

    Parameters
    ----------
    function : casadi.Function
        The compiled function, object (its inputs and outputs in the units it names).
    """

    def __init__(self, function: Any) -> None:
        self.function = function
        self._inputs = [np.zeros(function.nnz_in(i)) for i in range(function.n_in())]
        self._outputs = [np.zeros(function.nnz_out(i)) for i in range(function.n_out())]
        self._buffer, self._trigger = function.buffer()
        for i, a in enumerate(self._inputs):
            self._buffer.set_arg(i, a.data)
        for i, a in enumerate(self._outputs):
            self._buffer.set_res(i, a.data)

    def __call__(self, *args: Any) -> np.ndarray | tuple[np.ndarray, ...]:
        """Evaluate; arguments and results flattened column-major (CasADi order).

        Parameters
        ----------
        *args : array_like
            One flat array per input of the function, in the unit its name carries.

        Returns
        -------
        ndarray or tuple of ndarray
            One flat copy per output, in the unit its name carries.
        """
        for dst, src in zip(self._inputs, args, strict=True):
            dst[:] = src
        self._trigger()
        outs = tuple(o.copy() for o in self._outputs)
        return outs[0] if len(outs) == 1 else outs


@dataclass(frozen=True)
class ThreeAxisHelmholtz:
    """Three orthogonal Helmholtz pairs sharing one centre (the origin); B(p) = G(p) I.

    Parameters
    ----------
    x, y, z : HelmholtzPair, SquarePair or RectanglePair
        The pairs along each axis (shapes mixed freely); each pair's ``axis``
        must match its slot.

    Raises
    ------
    InputError
        A pair missing or on the wrong axis (named ``x``, ``y`` or ``z``).

    Examples
    --------
    Three nested pairs; the field is linear in the currents, B(p) = G(p) I:

    >>> import numpy as np
    >>> from coils import HelmholtzPair, ThreeAxisHelmholtz
    >>> coils = ThreeAxisHelmholtz(
    ...     HelmholtzPair(0.4, 400, "x"), HelmholtzPair(0.35, 350, "y"), HelmholtzPair(0.3, 300, "z")
    ... )
    >>> print(np.round(np.asarray(coils.centre_gains_T_per_A) * 1e3, 5))  # mT/A, each (4/5)^1.5 mu0 N/R
    [0.89918 0.89918 0.89918]
    >>> B = coils.field(np.array([[0.0, 0.0, 0.05]]), np.array([10.0, 0.0, 0.0]))
    >>> print(np.round(B * 1e3, 4) + 0.0)  # mT at 5 cm up the z axis, 10 A in the x pair
    [[8.9908 0.     0.    ]]
    """

    x: WoundPair
    y: WoundPair
    z: WoundPair

    def __post_init__(self) -> None:
        for name in AXES:
            pair = getattr(self, name)
            if not isinstance(pair, PAIR_TYPES) or pair.axis != name:
                raise InputError(
                    name,
                    pair,
                    f"a coil pair (coils.HelmholtzPair, SquarePair, RectanglePair) with axis={name!r}",
                )

    @property
    def pairs(self) -> tuple[Any, Any, Any]:
        """The (x, y, z) pairs."""
        return (self.x, self.y, self.z)

    @cached_property
    def filament_set(self) -> Any:
        """All filaments of the three pairs; drive column k is pair k.

        The pairs' filament sets joined by kind (:func:`_joined`): all circles, one
        :class:`coils.filaments.FilamentSet`; with other shapes, one set per kind (circles
        first, in the order the pairs bring them) whose fields add (:class:`MixedFilamentSet`).
        """
        kinds: dict[type, list[int]] = {}
        for k, p in enumerate(self.pairs):
            kinds.setdefault(type(p.filament_set), []).append(k)
        order = sorted(kinds.items(), key=lambda kv: (kv[0] is not FilamentSet, kv[1][0]))
        parts = [_joined([self.pairs[k].filament_set for k in ks], ks) for _, ks in order]
        return parts[0] if len(parts) == 1 else MixedFilamentSet(tuple(parts))

    # --- field ---------------------------------------------------------------------------------
    def field(self, points_m: Any, currents_A: Any) -> np.ndarray:
        """Field of the three pairs, T.

        Parameters
        ----------
        points_m : array_like, shape (n, 3)
            Field points, m.
        currents_A : array_like, shape (3,)
            Currents of the x, y, z pairs, A.

        Returns
        -------
        ndarray, shape (n, 3)
            Magnetic flux density, T.
        """
        return self.filament_set.field(_points(points_m), _currents(currents_A)[:, None])

    def field_matrix(self, points_m: Any) -> np.ndarray:
        """G(p), shape (n, 3, 3), T/A: column k is the field of pair k per ampere.

        Parameters
        ----------
        points_m : array_like, shape (n, 3)
            Field points, m.

        Returns
        -------
        ndarray, shape (n, 3, 3)
            Field per ampere of each pair, T/A.
        """
        return self.filament_set.field_matrix(_points(points_m))

    @cached_property
    def centre_gains_T_per_A(self) -> np.ndarray:
        """Centre field per ampere of the x, y, z pairs, shape (3,), T/A."""
        return np.array([p.centre_field_per_amp_T_per_A for p in self.pairs])

    # --- CasADi --------------------------------------------------------------------------------
    @cached_property
    def _casadi_symbols(self) -> tuple[Any, Any, Any]:
        import casadi as ca

        point = ca.SX.sym("point_m", 3)
        currents = ca.SX.sym("currents_A", 3)
        field = self.filament_set.field(point.T, currents).T
        return point, currents, ca.densify(field)

    def casadi_field_function(self) -> Any:
        """CasADi Function ``coil_field(point_m[3], currents_A[3]) -> field_T[3]`` (SX, exact).

        Returns
        -------
        casadi.Function
            The field function, object (inputs in m and A, output in T).
        """
        import casadi as ca

        p, i, b = self._casadi_symbols
        return ca.Function("coil_field", [p, i], [b], ["point_m", "currents_A"], ["field_T"])

    def casadi_field_jacobian_function(self) -> Any:
        """CasADi Function ``(point_m, currents_A) -> (field_T[3], dfield_dpoint_T_per_m[3x3])``.

        The Jacobian J[i, j] = ∂B_i/∂p_j is exact (algorithmic differentiation).

        Returns
        -------
        casadi.Function
            The field and Jacobian function, object (inputs in m and A, outputs in T and T/m).
        """
        import casadi as ca

        p, i, b = self._casadi_symbols
        jac = ca.densify(ca.jacobian(b, p))
        return ca.Function(
            "coil_field_jacobian",
            [p, i],
            [b, jac],
            ["point_m", "currents_A"],
            ["field_T", "dfield_dpoint_T_per_m"],
        )

    def casadi_field_matrix_function(self) -> Any:
        """CasADi Function ``coil_field_matrix(point_m[3]) -> G_T_per_A[3x3]`` with B = G I.

        Returns
        -------
        casadi.Function
            The field-matrix function, object (input in m, output in T/A).
        """
        import casadi as ca

        p, i, b = self._casadi_symbols
        return ca.Function(
            "coil_field_matrix", [p], [ca.densify(ca.jacobian(b, i))], ["point_m"], ["G_T_per_A"]
        )

    @cached_property
    def point_field(self) -> PointEvaluator:
        """Fast single-point field: ``system.point_field(point_m, currents_A) -> (3,)`` in T."""
        return PointEvaluator(self.casadi_field_function())

    # --- rotating field ------------------------------------------------------------------------
    def rotating_current_per_tesla_A_per_T(self, heading: Any) -> np.ndarray:
        """Centre current amplitude per tesla of rotating field, sqrt(1 - n_k²)/g_k, A/T.

        Multiply by a (possibly CasADi) amplitude B0 to get the allocation of
        :meth:`rotating_allocation` without leaving the backend.

        Parameters
        ----------
        heading : array_like, shape (3,)
            Rotation axis n (normalised here).

        Returns
        -------
        ndarray, shape (3,)
            Current amplitude per tesla of each pair, A/T.
        """
        return self.rotating_allocation(heading, 1.0)[0]

    def rotating_allocation(
        self, heading: Any, amplitude_T: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """Currents making at the centre a field of amplitude B0 turning about ``heading``.

        Parameters
        ----------
        heading : array_like, shape (3,)
            Rotation axis n (right-handed sense), normalised here.
        amplitude_T : float
            Field amplitude B0, T.

        Returns
        -------
        amplitudes_A, phases_rad : ndarray, shape (3,)
            Amplitudes A_k, A, and phases φ_k, rad, of I_k(t) = A_k cos(2π f t + φ_k);
            A_k = B0 sqrt(1 - n_k²) / g_k.
        """
        return allocation(np.diag(self.centre_gains_T_per_A), heading, amplitude_T)

    def rotating_allocation_at(
        self, point_m: Any, heading: Any, amplitude_T: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """As :meth:`rotating_allocation` but exact at ``point_m``, solving with the full G(p).

        Parameters
        ----------
        point_m : array_like, shape (3,)
            Where the rotating field must be exact, m.
        heading : array_like, shape (3,)
            Rotation axis n, dimensionless (normalised here).
        amplitude_T : float
            Field amplitude B0, T.

        Returns
        -------
        amplitudes_A : ndarray, shape (3,)
            Current amplitudes, A.
        phases_rad : ndarray, shape (3,)
            Current phases, rad.
        """
        return allocation(self.field_matrix(point_m)[0], heading, amplitude_T)

    def rotating_currents(
        self, heading: Any, amplitude_T: float, frequency_hz: float, t_s: Any
    ) -> np.ndarray:
        """Currents of the centre allocation at times ``t_s``, shape (len(t), 3), A.

        Parameters
        ----------
        heading : array_like, shape (3,)
            Rotation axis n, dimensionless (normalised here).
        amplitude_T : float
            Field amplitude B0, T.
        frequency_hz : float
            Rotation frequency f, Hz.
        t_s : array_like, shape (m,)
            Times, s.

        Returns
        -------
        ndarray, shape (m, 3)
            Current of each pair at each time, A.

        Examples
        --------
        A 5 mT field rotating about z at 2 Hz: the x and y pairs a quarter period apart, z idle:

        >>> import numpy as np
        >>> from coils import HelmholtzPair, ThreeAxisHelmholtz
        >>> coils = ThreeAxisHelmholtz(
        ...     HelmholtzPair(0.4, 400, "x"), HelmholtzPair(0.35, 350, "y"), HelmholtzPair(0.3, 300, "z")
        ... )
        >>> I = coils.rotating_currents([0.0, 0.0, 1.0], 5e-3, 2.0, [0.0, 0.125])
        >>> print(np.round(I, 3) + 0.0)  # A; 5 mT / 0.899 mT/A = 5.561 A
        [[5.561 0.    0.   ]
         [0.    5.561 0.   ]]
        """
        amps, phases = self.rotating_allocation(heading, amplitude_T)
        t = np.atleast_1d(np.asarray(t_s, dtype=float))
        return amps * np.cos(2.0 * np.pi * frequency_hz * t[:, None] + phases)

    def rotating_field_semi_axes_T(
        self,
        points_m: Any,
        heading: Any,
        amplitude_T: float,
        field_matrix_T_per_A: Any = None,
    ) -> tuple[np.ndarray, np.ndarray]:
        """Field ellipse ⟂ heading at each point under the *centre* allocation, T.

        Parameters
        ----------
        points_m : array_like, shape (n, 3)
            Field points, m.
        heading : array_like, shape (3,)
            Rotation axis n, dimensionless (normalised here).
        amplitude_T : float
            Field amplitude B0 at the centre, T.
        field_matrix_T_per_A : ndarray, shape (n, 3, 3), optional
            :meth:`field_matrix` at ``points_m``, T/A, if the caller has it (one per set of
            points for every heading).

        Returns
        -------
        minor_T, major_T : ndarray, shape (n,)
            Smallest and largest in-plane field during one turn, T (minor is what the capsule
            magnet is sure to see; minor/B0 is the workspace derating).
        """
        amps, phases = self.rotating_allocation(heading, amplitude_T)
        G = self.field_matrix(points_m) if field_matrix_T_per_A is None else field_matrix_T_per_A
        return ellipse_semi_axes(G @ (amps * np.cos(phases)), G @ (-amps * np.sin(phases)), heading)
