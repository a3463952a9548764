"""Identify the five viscoelastic constants from bench torque-frequency data (Zhou 2013, III-C).

The paper minimised the summed squared error with a trust-region reflective method; this is the
same family (``scipy.optimize.least_squares(method="trf")``) with three choices made explicit:

- unknowns are the logarithms of E1, E2, E3, eta1, eta2 (positive, and scaled alike whatever
  their magnitude), bounded in :data:`DEFAULT_BOUNDS` -- or of any subset of them and a common
  ``scale`` on the others (``free=("scale",)``: the calibration factor alone, all a 0.5-3 Hz
  curve can pin down), the rest held at the base tissue's values;
- residuals are relative, (model - measured) / measured, so a curve from 0.5 to 3 mN·m weighs
  every point alike (``relative=False`` gives the paper's absolute errors);
- lumen, wall thickness and friction stay those of the base tissue.

Four starts of 200 evaluations each; the best, when its budget ran out (parameters drifting
along a null direction at a constant cost), is carried on and judged on its cost
(``_converge``): ``success`` says whether the fit converged, and a fit that did not is not a
fit (``spiralcap fit`` writes nothing and exits 3).

The torque factorises exactly as G(alpha) x I(omega; E, eta) (:func:`torque_model.model.
contact_factors_m3`), so the geometry is evaluated once per point; I and its Jacobian both come
from the model's one :func:`~torque_model.model.relaxation_integral_Pa` (values on the numpy
path, the exact Jacobian by CasADi's algorithmic differentiation of the same function). Uncertainty: s^2 (J^T J)^-1 in log-parameters (J from the solution, s^2 the residual
variance on n - k degrees of freedom, k free parameters); 95 % intervals are Wald intervals in
the log, p x/÷ exp(t(0.975, n-k) se(log p)), so they stay positive (a parameter along a null
direction has none: not identifiable). A parameter is *not pinned down* when its interval spans
more than a factor e either way (t se(log p) > 1), when it
lies along a null direction of J^T J (singular values below 1e-10 of the largest), when it is
correlated with another at |r| > 0.99, or when it sits at a bound.

Note on what the data can say: every helical angle only rescales G, so curves at several angles
add no information on the five constants beyond a single curve (they check the geometry), and a
curve over 0.5-3 Hz usually fixes about three combinations (the low-frequency modulus
E1 + E3 when arm 1 relaxes slowly, the viscous slope eta2, a curvature), not five parameters.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal, NamedTuple

import numpy as np

from spiralcap.core.errors import DataError, InputError
from torque_model.geometry import ContactGeometry
from torque_model.model import contact_factor_m3, relaxation_integral_Pa
from torque_model.tissue import VISCOELASTIC_FIELDS, TissueParameters

__all__ = ["DEFAULT_BOUNDS", "FREE_NAMES", "PARAMETER_NAMES", "FitResult", "identify"]

#: How the fit gets its Jacobian: exact (the model's, by CasADi) or scipy's finite differences.
JacobianMethod = Literal["analytic", "2-point", "3-point"]

#: The identified parameters, SI names, in the order of every array in :class:`FitResult`.
PARAMETER_NAMES = VISCOELASTIC_FIELDS

#: What :func:`identify` can fit: a common ``scale`` on the constants held at the base tissue's
#: values, and each constant itself.
FREE_NAMES = ("scale", *PARAMETER_NAMES)

#: Default bounds (SI): moduli 1 Pa - 1 GPa, viscosities 1 Pa·s - 10 GPa·s, scale 1e-6 - 1e6.
DEFAULT_BOUNDS: dict[str, tuple[float, float]] = {
    "scale": (1e-6, 1e6),
    "E1_Pa": (1.0, 1e9),
    "E2_Pa": (1.0, 1e9),
    "E3_Pa": (1.0, 1e9),
    "eta1_Pa_s": (1.0, 1e10),
    "eta2_Pa_s": (1.0, 1e10),
}

REL_CI_LIMIT = 1.0
CORRELATION_LIMIT = 0.99
SINGULAR_RCOND = 1e-10
_N_STARTS = 4
#: Evaluation budget of each start (and of each profile re-fit).
_START_NFEV = 200
#: Further evaluations for the best start when its budget ran out (``_converge``).
_MAX_NFEV = 1000
#: A run out of budget is continued for this fraction of it more, to see if the cost still falls.
_CHECK_NFEV_FRACTION = 0.2
_CHECK_NFEV_MIN = 50
#: Relative cost drop over that continuation below which the cost has converged.
COST_RTOL = 1e-6
#: Root-mean-square residual (relative to the torque) at or below which a fit has reproduced
#: its data: far below any bench's noise, where the cost's relative drop only chases digits.
RESIDUAL_FLOOR = 1e-6


@dataclass(frozen=True)
class FitResult:
    """Outcome of :func:`identify`: values, uncertainty, what is not pinned down, residuals.

    Attributes
    ----------
    tissue : TissueParameters
        The base tissue with the fitted parameters applied (name ``"fit"``).
    free : tuple of str
        The fitted parameters, names from :data:`FREE_NAMES`, in the order of ``correlation``;
        the constants not named are the base tissue's, times ``scale`` when it is free.
    values, standard_errors : dict[str, float]
        Fitted value and standard error (delta method, ``value x se_log``) of each free
        parameter, SI (Pa, Pa·s; ``scale`` dimensionless); ``inf`` where the data do not
        determine the parameter, ``nan`` with no residual degree of freedom.
    standard_errors_log : dict[str, float]
        Standard error of the natural log of each free parameter (the fit's own coordinates),
        dimensionless.
    ci95 : dict[str, tuple[float, float]]
        95 % interval ``value x/÷ exp(t se_log)`` in the unit of ``values`` (Pa, Pa·s;
        ``scale`` dimensionless): always positive; ``(0, inf)`` for a
        parameter that is not identifiable (:attr:`identifiable`).
    flags : dict[str, tuple[str, ...]]
        Why a parameter is not pinned down (empty tuple: pinned down); other parameters are
        named by their :data:`FREE_NAMES` name.
    correlation : numpy.ndarray
        k x k correlation matrix of the log free parameters, dimensionless (nan where
        undefined).
    covariance_log : numpy.ndarray or None
        5 x 5 covariance of ln(E1, E2, E3, eta1, eta2), dimensionless, carried by the
        pinned-down free parameters only (rows and columns of what the data leave loose are
        zero; a free ``scale`` moves all constants it multiplies together); ``None`` when
        nothing is pinned down.
    frequency_hz, helical_angle_rad, torque_Nm, predicted_Nm : numpy.ndarray
        The data points, and the fitted model at them: Hz, rad, N·m, N·m.
    residuals : numpy.ndarray
        Fit residuals, relative ((model - data)/data, dimensionless) or in N·m as
        ``relative`` says.
    relative : bool
        Whether residuals are relative.
    residual_std : float
        s, the residual standard deviation on ``dof`` degrees of freedom (in the unit of
        ``residuals``: dimensionless or N·m).
    dof : int
        Points minus free parameters, count.
    effective_parameters : int
        The numerical rank of J over the free parameters not at a bound (singular values above
        :data:`SINGULAR_RCOND` of the largest), count: how many combinations the data actually
        fit, for the lack-of-fit test (:mod:`torque_model.fit_quality`).
    condition_number : float
        Of J^T J in log-parameters, dimensionless.
    cost : float
        Half the sum of squared residuals (dimensionless, or N·m² when not ``relative``).
    success : bool
        The optimiser's convergence flag.
    message : str
        The optimiser's words on how it ended.
    geometry : ContactGeometry
        Capsule geometry used, for :meth:`predict_Nm`.
    """

    tissue: TissueParameters
    free: tuple[str, ...]
    values: dict[str, float]
    standard_errors: dict[str, float]
    standard_errors_log: dict[str, float]
    ci95: dict[str, tuple[float, float]]
    flags: dict[str, tuple[str, ...]]
    correlation: np.ndarray
    covariance_log: np.ndarray | None
    frequency_hz: np.ndarray
    helical_angle_rad: np.ndarray
    torque_Nm: np.ndarray
    predicted_Nm: np.ndarray
    residuals: np.ndarray
    relative: bool
    residual_std: float
    dof: int
    effective_parameters: int
    condition_number: float
    cost: float
    success: bool
    message: str
    geometry: ContactGeometry

    @property
    def pinned_down(self) -> tuple[str, ...]:
        """Free parameters the data determine (no flag)."""
        return tuple(n for n in self.free if not self.flags[n])

    @property
    def not_pinned_down(self) -> tuple[str, ...]:
        """Free parameters the data do not determine (at least one flag)."""
        return tuple(n for n in self.free if self.flags[n])

    def identifiable(self, name: str) -> bool:
        """Whether the data bound ``name`` at all (a finite, positive 95 % interval).

        Parameters
        ----------
        name : str
            A free parameter, from :data:`FREE_NAMES`.

        Returns
        -------
        bool
            True when its 95 % interval is finite and positive.
        """
        lo, hi = self.ci95[name]
        return lo > 0 and math.isfinite(hi)

    def predict_Nm(self, frequency_hz: Any, helical_angle_rad: Any) -> Any:
        """The fitted model's torque at other frequencies (Hz) and angles (rad), N·m.

        Parameters
        ----------
        frequency_hz : float or array
            Rotation frequency, Hz.
        helical_angle_rad : float or array
            Helical angle, rad (broadcasts against ``frequency_hz``).

        Returns
        -------
        float or array
            Resistive torque of the fitted tissue on :attr:`geometry`, N·m.
        """
        from torque_model.model import resistive_torque_Nm

        return resistive_torque_Nm(helical_angle_rad, frequency_hz, self.tissue, self.geometry)


class _Constants(NamedTuple):
    """The five viscoelastic constants alone (floats or CasADi), in :data:`PARAMETER_NAMES` order."""

    E1_Pa: Any
    E2_Pa: Any
    E3_Pa: Any
    eta1_Pa_s: Any
    eta2_Pa_s: Any


class _RelaxationIntegral:
    """I(omega) of eq. 4 over one turn at fixed frequencies, and dI/dlog(p), from the model.

    Both come from :func:`torque_model.model.relaxation_integral_Pa`: values on its numpy path,
    the n x 5 Jacobian in log-parameters q = log p by CasADi's algorithmic differentiation of
    the same expression (compiled once per fit).

    The expression is built for one symbolic frequency and mapped over the distinct
    frequencies of the data (a bench repeats a few), so its size does not grow with the data:
    a bench file of 200,000 rows costs arrays of 200,000 x 5 numbers, not a graph of millions
    of nodes (issue 39: 2.2 GB and a minute to build for a 4 MB file).
    """

    def __init__(self, freq: np.ndarray) -> None:
        import casadi as ca

        self.freq = freq
        self._unique, self._index = np.unique(freq, return_inverse=True)
        m = self._unique.size
        q = ca.SX.sym("log_p", len(PARAMETER_NAMES))
        f = ca.SX.sym("frequency_hz")
        integral = relaxation_integral_Pa(f, _Constants(*ca.vertsplit(ca.exp(q))))
        one: Any = ca.Function("dI_dlogp", [q, f], [ca.densify(ca.jacobian(integral, q))])
        # q is shared by every frequency (not repeated m times); the result is 1 x 5m
        fn = one.map("dI_dlogp_map", "serial", m, [0], [])
        # Called a thousand times per fit: through a buffer, without DM conversions.
        self._q = np.zeros(len(PARAMETER_NAMES))
        self._f = np.ascontiguousarray(self._unique, dtype=float)
        self._jac = np.zeros(m * len(PARAMETER_NAMES))
        self._buffer, self._trigger = fn.buffer()
        self._buffer.set_arg(0, self._q.data)
        self._buffer.set_arg(1, self._f.data)
        self._buffer.set_res(0, self._jac.data)

    def value(self, p: np.ndarray) -> np.ndarray:
        """I at p = (E1, E2, E3, eta1, eta2) (SI), shape (n,), Pa."""
        return np.asarray(relaxation_integral_Pa(self.freq, _Constants(*p)), dtype=float)

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        """dI/dlog(p) at q = log p, shape (n, 5), Pa."""
        self._q[:] = q
        self._trigger()
        # one row of 5 per distinct frequency, then one per data point
        return self._jac.reshape(-1, len(PARAMETER_NAMES))[self._index]


def _as_points(name: str, values: Any, n: int | None) -> np.ndarray:
    arr = np.atleast_1d(np.asarray(values, dtype=float)).ravel()
    if n is not None and arr.size == 1:
        arr = np.full(n, arr[0])
    if n is not None and arr.size != n:
        raise DataError(f"{name}: {arr.size} values for {n} data points")
    return arr


def _check_data(freq: np.ndarray, torque: np.ndarray, angle: np.ndarray) -> None:
    for name, arr, positive in (
        ("frequency_hz", freq, True),
        ("torque_Nm", torque, True),
        ("helical_angle_rad", angle, True),
    ):
        for i, v in enumerate(arr):
            if not math.isfinite(v) or (positive and v <= 0):
                raise DataError(f"point {i + 1}: {name} = {v!r}: a finite number > 0")
    bad = np.flatnonzero(angle >= math.pi / 2)
    if bad.size:
        raise DataError(f"point {bad[0] + 1}: helical_angle_rad = {angle[bad[0]]!r}: below pi/2")


def identify(
    frequency_hz: Sequence[float] | np.ndarray,
    torque_Nm: Sequence[float] | np.ndarray,
    helical_angle_rad: float | Sequence[float] | np.ndarray,
    base_tissue: TissueParameters,
    geometry: ContactGeometry,
    *,
    relative: bool = True,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    jacobian: JacobianMethod = "analytic",
    profile_bounds: bool = True,
    free: Sequence[str] | None = None,
    max_nfev: int | None = None,
) -> FitResult:
    """Fit E1, E2, E3, eta1, eta2 (or the subset ``free``) to measured torque (bounded TRF).

    Parameters
    ----------
    frequency_hz : array_like
        Rotation frequency of each point, Hz (> 0).
    torque_Nm : array_like
        Measured resistive torque of each point, N·m (> 0).
    helical_angle_rad : float or array_like
        Helical angle of the capsule of each point (one value for all), rad; several capsules
        are fitted jointly.
    base_tissue : TissueParameters
        Supplies the fixed lumen, wall thickness and friction, the constants not fitted, and
        the starting point.
    geometry : ContactGeometry
        The capsule (as :func:`torque_model.resistive_torque_Nm`).
    relative : bool
        Relative residuals (default) or absolute ones in N·m.
    bounds : mapping, optional
        ``{name: (low, high)}`` in SI (Pa, Pa·s; ``scale`` dimensionless) for any of
        :data:`FREE_NAMES`; others from :data:`DEFAULT_BOUNDS`.
    jacobian : {"analytic", "2-point", "3-point"}
        Exact Jacobian (default) or scipy's finite differences (the benchmark's reference).
    profile_bounds : bool
        Also test, by re-fitting with each parameter held at each bound, whether the data can
        exclude the bound (profile F-test at 95 %); adds two small fits per free parameter.
    free : sequence of str, optional
        The parameters to fit, names from :data:`FREE_NAMES` (default: the five constants).
        ``"scale"`` multiplies every constant *not* named, held in the base tissue's ratios:
        ``free=("scale",)`` fits only the calibration factor of the base set.
    max_nfev : int, optional
        Further evaluations (a count) for the best start when its own budget (:data:`_START_NFEV`, or
        ``max_nfev`` if smaller) ran out (default :data:`_MAX_NFEV`); a run that uses them up
        too is judged on its cost (``_converge``): ``success`` False when it had not converged.

    Returns
    -------
    FitResult

    Raises
    ------
    DataError
        Fewer points than free parameters, arrays of unequal length, or a point with a
        non-finite or non-positive frequency, torque or angle (named by its 1-based index).
    InputError
        An unknown bound or free name, an empty bound interval, ``scale`` with all five
        constants, or an unknown ``jacobian``.
    """
    names = _free_names(free)
    freq = _as_points("frequency_hz", frequency_hz, None)
    n = freq.size
    torque = _as_points("torque_Nm", torque_Nm, n)
    angle = _as_points("helical_angle_rad", helical_angle_rad, n)
    n_par = len(names)
    if n < n_par:
        raise DataError(
            f"{n} data points for {n_par} parameters ({', '.join(names)}): need at least {n_par}"
        )
    _check_data(freq, torque, angle)
    if jacobian not in ("analytic", "2-point", "3-point"):
        raise InputError("jacobian", jacobian, "'analytic', '2-point' or '3-point'")
    lo, hi = _bounds(bounds, names)
    G = np.asarray(contact_factor_m3(angle, base_tissue, geometry), dtype=float)
    if np.any(G <= 0):
        i = int(np.flatnonzero(G <= 0)[0])
        raise DataError(
            f"point {i + 1}: the capsule does not touch a lumen of "
            f"{base_tissue.lumen_diameter_m * 1e3:g} mm: no torque to fit"
        )
    scale = 1.0 / torque if relative else np.full(n, 1.0 / np.median(torque))

    integral = _RelaxationIntegral(freq)
    p0 = np.array([max(getattr(base_tissue, k), 1e-3) for k in PARAMETER_NAMES])
    A, c = _log_map(names, p0)

    def residuals(q: np.ndarray) -> np.ndarray:
        return (G * integral.value(np.exp(c + A @ q)) - torque) * scale

    weight = (G * scale)[:, None]

    def jac(q: np.ndarray) -> np.ndarray:
        out = integral.jacobian(c + A @ q) @ A
        out *= weight  # in place: one n x free matrix per call, not three
        return out

    fit_jac = jac if jacobian == "analytic" else jacobian
    budget = _MAX_NFEV if max_nfev is None else int(max_nfev)
    sols = [
        _solve(residuals, fit_jac, q0, lo, hi, min(_START_NFEV, budget))
        for q0 in _starts(names, p0, integral, torque, G, scale, lo, hi)
    ]
    best = min(sols, key=lambda sol: sol.cost)
    # a converged start as good to COST_RTOL is preferred to a lower run that had not converged
    done = [sol for sol in sols if sol.success and sol.cost <= best.cost * (1.0 + COST_RTOL)]
    if done:
        best = min(done, key=lambda sol: sol.cost)
    else:
        best = _converge(residuals, fit_jac, best, lo, hi, budget)
    order = _slow_arm_first(names, best.x, lo, hi)
    best.x, best.active_mask = best.x[order], best.active_mask[order]
    profile = _profile_to_bounds(residuals, fit_jac, best, lo, hi, n) if profile_bounds else None
    return _result(
        best,
        names,
        A,
        c,
        freq,
        angle,
        torque,
        G,
        scale,
        relative,
        lo,
        hi,
        base_tissue,
        geometry,
        jac(best.x),
        profile,
    )


def _free_names(free: Sequence[str] | None) -> tuple[str, ...]:
    """The free parameters in :data:`FREE_NAMES` order, checked."""
    if free is None:
        return tuple(PARAMETER_NAMES)
    wanted = list(free)
    allowed = "one or more of " + ", ".join(FREE_NAMES)
    if not wanted:
        raise InputError("free", wanted, allowed)
    for name in wanted:
        if name not in FREE_NAMES:
            raise InputError("free", name, allowed)
        if wanted.count(name) > 1:
            raise InputError("free", name, "each parameter named once")
    if "scale" in wanted and all(k in wanted for k in PARAMETER_NAMES):
        raise InputError(
            "free",
            ",".join(wanted),
            "scale with at most four of the five constants (it multiplies the constants not named)",
        )
    return tuple(k for k in FREE_NAMES if k in wanted)


def _log_map(names: tuple[str, ...], p0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``A`` (5 x k) and ``c`` (5) with ln(E1, E2, E3, eta1, eta2) = c + A q, q = ln(free)."""
    A = np.zeros((len(PARAMETER_NAMES), len(names)))
    c = np.log(p0)
    for j, name in enumerate(names):
        if name == "scale":
            for i, const in enumerate(PARAMETER_NAMES):
                A[i, j] = 0.0 if const in names else 1.0
        else:
            i = PARAMETER_NAMES.index(name)
            A[i, j] = 1.0
            c[i] = 0.0
    return A, c


def _solve(
    fun: Any, jac: Any, q0: np.ndarray, lo: np.ndarray, hi: np.ndarray, max_nfev: int
) -> Any:
    """One bounded TRF run from ``q0`` with at most ``max_nfev`` evaluations.

    The run's final Jacobian (n x free numbers) is dropped: the fit keeps every start's run and
    recomputes the Jacobian at the one it takes, so a bench file of 200,000 rows does not hold
    one 8 MB matrix per start.
    """
    from scipy import optimize  # ~0.25 s to import: only when fitting

    sol = optimize.least_squares(
        fun,
        q0,
        jac=jac,
        bounds=(lo, hi),
        method="trf",
        xtol=1e-9,
        ftol=1e-9,
        gtol=1e-9,
        max_nfev=max_nfev,
    )
    sol.jac = None
    return sol


def _converge(fun: Any, jac: Any, sol: Any, lo: np.ndarray, hi: np.ndarray, budget: int) -> Any:
    """Carry a run stopped by its evaluation budget on to convergence, or say it did not.

    scipy stops on a small step (``xtol``), a small relative drop of the cost (``ftol``) or a
    small scaled gradient (``gtol``). Along a direction the data do not determine (a null
    direction of J^T J, the usual case for five constants on a 0.5-3 Hz curve) none of these
    may trigger while the parameters drift at a constant cost, and the budget runs out. Such a
    run is continued with ``budget`` more evaluations, then :data:`_CHECK_NFEV_FRACTION` of it
    more (at least :data:`_CHECK_NFEV_MIN`, time for the trust region to grow back): when that
    last stretch lowers the cost by less than :data:`COST_RTOL` (relative), the cost has
    converged and the run is accepted (``success`` True, ``message`` saying so) -- the fitted
    curve is the minimum's to that tolerance (the residual standard deviation to half of it),
    and the parameters that still move are the ones flagged as not pinned down. Otherwise
    ``success`` stays False with scipy's message and the drop measured -- unless the fit
    reproduces its data to :data:`RESIDUAL_FLOOR` (relative rms), where the relative drop of
    a cost near zero says nothing: accepted, the message saying so.
    """
    if sol.status != 0:  # converged (> 0) or refused by scipy (< 0): nothing to carry on
        return sol
    sol = _solve(fun, jac, np.clip(sol.x, lo, hi), lo, hi, budget)
    if sol.status != 0:
        return sol
    extra = max(_CHECK_NFEV_MIN, int(budget * _CHECK_NFEV_FRACTION))
    more = _solve(fun, jac, np.clip(sol.x, lo, hi), lo, hi, extra)
    if more.status != 0:  # converged by scipy's own criteria on the extra evaluations
        return more
    drop = (sol.cost - more.cost) / sol.cost if sol.cost > 0 else 0.0
    rms = float(np.sqrt(np.mean(np.square(more.fun))))
    if rms <= RESIDUAL_FLOOR:
        more.success = True
        more.message = (
            f"the data reproduced: relative rms residual {rms:.1e} (<= {RESIDUAL_FLOOR:g}); "
            "only parameters the data do not determine still moved"
        )
        return more
    if drop < COST_RTOL:
        more.success = True
        more.message = (
            f"cost converged: {extra} further evaluations lowered it by {drop:.1e} (relative, "
            f"< {COST_RTOL:g}); only parameters the data do not determine still moved"
        )
        return more
    more.message = (
        f"{str(sol.message).rstrip('.')} (the last {extra} evaluations still lowered the cost "
        f"by {drop:.1e}, relative)"
    )
    return more


def _slow_arm_first(
    names: tuple[str, ...], q: np.ndarray, lo: np.ndarray, hi: np.ndarray
) -> list[int]:
    """Index order putting the slower Maxwell arm first (eta1/E1 >= eta2/E2).

    The model is symmetric under swapping the arms; Tables I and II list the slow arm first.
    Only when both arms are free; the order is kept if the swapped values would leave the
    bounds.
    """
    keep = list(range(len(names)))
    arm = ("E1_Pa", "E2_Pa", "eta1_Pa_s", "eta2_Pa_s")
    if not all(k in names for k in arm):
        return keep
    e1, e2, h1, h2 = (names.index(k) for k in arm)
    swap = keep.copy()
    swap[e1], swap[e2], swap[h1], swap[h2] = e2, e1, h2, h1
    slow_first = (q[h1] - q[e1]) >= (q[h2] - q[e2])
    inside = bool(np.all(q[swap] >= lo) and np.all(q[swap] <= hi))
    return keep if slow_first or not inside else swap


def _profile_to_bounds(
    fun: Any, jac: Any, best: Any, lo: np.ndarray, hi: np.ndarray, n: int
) -> dict[int, list[str]]:
    """For each parameter, the bounds the data cannot exclude (profile F-test, 95 %).

    The parameter is held at a bound and the other four re-fitted (from the best fit); if the
    summed squared residual rises by less than s^2 F(0.95; 1, n - 5), the bound is inside the
    parameter's 95 % profile interval: the data do not pin it down on that side.
    """
    n_par = best.x.size
    dof = n - n_par
    if dof <= 0:
        return {}
    ssr = 2.0 * best.cost
    from scipy import stats  # ~0.3 s to import: only when fitting

    threshold = ssr / dof * float(stats.f.ppf(0.95, 1, dof))
    out: dict[int, list[str]] = {}
    for i in range(n_par):
        free = [j for j in range(n_par) if j != i]
        for side, value in (("lower", lo[i]), ("upper", hi[i])):
            q = best.x.copy()
            q[i] = value

            def f_sub(z: np.ndarray, q: np.ndarray = q, free: list[int] = free) -> np.ndarray:
                q = q.copy()
                q[free] = z
                return fun(q)

            def j_sub(z: np.ndarray, q: np.ndarray = q, free: list[int] = free) -> np.ndarray:
                q = q.copy()
                q[free] = z
                return jac(q)[:, free]

            sub_jac = jac if isinstance(jac, str) else j_sub  # "2-point": finite differences

            if free:
                pad = 1e-9 * (hi[free] - lo[free])
                z0 = np.clip(best.x[free], lo[free] + pad, hi[free] - pad)
                ssr_at_bound = (
                    2.0 * _solve(f_sub, sub_jac, z0, lo[free], hi[free], _START_NFEV).cost
                )
            else:  # one free parameter: nothing to re-fit
                r = fun(q)
                ssr_at_bound = float(r @ r)
            if ssr_at_bound - ssr < threshold:
                out.setdefault(i, []).append(side)
    return out


def _bounds(
    bounds: Mapping[str, tuple[float, float]] | None, names: tuple[str, ...]
) -> tuple[np.ndarray, np.ndarray]:
    merged = dict(DEFAULT_BOUNDS)
    for key, pair in (bounds or {}).items():
        if key not in merged:
            raise InputError(f"bounds.{key}", pair, "one of " + ", ".join(FREE_NAMES))
        merged[key] = pair
    lo = np.array([merged[k][0] for k in names], dtype=float)
    hi = np.array([merged[k][1] for k in names], dtype=float)
    for k, a, b in zip(names, lo, hi, strict=True):
        if not (0 < a < b < math.inf):
            raise InputError(f"bounds.{k}", (a, b), "0 < low < high < inf")
    return np.log(lo), np.log(hi)


def _starts(
    names: tuple[str, ...],
    p0: np.ndarray,
    integral: _RelaxationIntegral,
    torque: np.ndarray,
    G: np.ndarray,
    scale: np.ndarray,
    lo: np.ndarray,
    hi: np.ndarray,
) -> list[np.ndarray]:
    """The base set rescaled by the best common factor, then fixed log-perturbations of it."""
    m = G * integral.value(p0) * scale
    y = torque * scale
    k = float(m @ y / (m @ m))
    q0 = np.array(
        [math.log(k) if n == "scale" else math.log(p0[PARAMETER_NAMES.index(n)] * k) for n in names]
    )
    rng = np.random.default_rng(20130501)
    starts = [q0] + [q0 + rng.normal(0.0, 1.5, q0.size) for _ in range(_N_STARTS - 1)]
    pad = 1e-9 * (hi - lo)
    return [np.clip(q, lo + pad, hi - pad) for q in starts]


class _Spread(NamedTuple):
    """Uncertainty of the log free parameters at the solution (see the module notes)."""

    cov_log: np.ndarray  # s^2 (J^T J)^+ (null directions left out)
    se_log: np.ndarray  # standard error of ln p; inf along a null direction
    corr: np.ndarray  # correlation of the ln p; nan where undefined
    in_null: np.ndarray  # bool: the parameter has a component along a null direction
    condition: float  # of J^T J


def _spread(J: np.ndarray, weighted_residuals: np.ndarray, dof: int) -> _Spread:
    """s^2 (J^T J)^-1 by the SVD of J, with null directions (singular values below
    :data:`SINGULAR_RCOND` of the largest) left out and their parameters marked."""
    n_par = J.shape[1]
    s2 = float(weighted_residuals @ weighted_residuals) / dof if dof > 0 else math.nan
    _, sv, Vt = np.linalg.svd(J, full_matrices=False)
    sv_max = sv[0] if sv.size and sv[0] > 0 else 1.0
    null = sv <= SINGULAR_RCOND * sv_max
    inv_sq = np.where(null, 0.0, 1.0 / np.where(null, 1.0, sv) ** 2)
    cov_log = (Vt.T * inv_sq) @ Vt * s2
    in_null = np.any(np.abs(Vt[null]) > 1e-6, axis=0) if null.any() else np.zeros(n_par, bool)
    var_log = np.diag(cov_log).copy()
    var_log[in_null] = math.inf
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov_log / np.sqrt(np.outer(np.diag(cov_log), np.diag(cov_log)))
    corr[in_null, :] = np.nan
    corr[:, in_null] = np.nan
    cond = float((sv_max / sv[-1]) ** 2) if sv[-1] > 0 else math.inf
    return _Spread(cov_log, np.sqrt(var_log), corr, in_null, cond)


def _rank(J: np.ndarray) -> int:
    """Numerical rank: singular values above :data:`SINGULAR_RCOND` of the largest."""
    if J.size == 0:
        return 0
    sv = np.linalg.svd(J, compute_uv=False)
    return int(np.sum(sv > SINGULAR_RCOND * sv[0])) if sv[0] > 0 else 0


def _interval_flags(in_null: bool, se_log: float, t: float, dof: int) -> list[str]:
    """Why one parameter's interval says it is not pinned down (empty: it is)."""
    why = []
    if in_null:
        why.append("J^T J singular along it")
    if dof <= 0:
        why.append("no residual degree of freedom: uncertainty unknown")
    elif not in_null and t * se_log > REL_CI_LIMIT:
        spread = t * se_log  # ln of the factor: beyond 10⁶ a number says nothing more
        if spread > math.log(1e6):
            why.append("95 % interval spans more than a factor 10⁶ either way")
        else:
            why.append(f"95 % interval spans a factor {math.exp(spread):.3g} either way")
    return why


def _flags(
    names: tuple[str, ...],
    spread: _Spread,
    t: float,
    dof: int,
    at_bound: np.ndarray,
    profile: dict[int, list[str]] | None,
) -> dict[str, tuple[str, ...]]:
    """Every free parameter's reasons for not being pinned down (module notes)."""
    flags: dict[str, tuple[str, ...]] = {}
    for i, name in enumerate(names):
        why = _interval_flags(bool(spread.in_null[i]), float(spread.se_log[i]), t, dof)
        if at_bound[i]:
            why.append("at a bound")
        sides = (profile or {}).get(i, [])
        if sides:
            why.append(
                f"profile reaches the {' and '.join(sides)} bound{'s' if len(sides) > 1 else ''}"
            )
        partners = [
            names[j]
            for j in range(len(names))
            if j != i and abs(spread.corr[i, j]) > CORRELATION_LIMIT
        ]
        if partners:
            why.append("|correlation| > 0.99 with " + ", ".join(partners))
        flags[name] = tuple(why)
    return flags


def _result(
    sol: Any,
    names: tuple[str, ...],
    A: np.ndarray,
    c: np.ndarray,
    freq: np.ndarray,
    angle: np.ndarray,
    torque: np.ndarray,
    G: np.ndarray,
    scale: np.ndarray,
    relative: bool,
    lo: np.ndarray,
    hi: np.ndarray,
    base: TissueParameters,
    geometry: ContactGeometry,
    J: np.ndarray,
    profile: dict[int, list[str]] | None,
) -> FitResult:
    n, n_par = J.shape
    p = np.exp(sol.x)
    dof = n - n_par
    spread = _spread(J, sol.fun, dof)
    from scipy import stats

    t = float(stats.t.ppf(0.975, dof)) if dof > 0 else math.nan
    at_bound = (
        (sol.active_mask != 0) | (sol.x - lo < 1e-6 * (hi - lo)) | (hi - sol.x < 1e-6 * (hi - lo))
    )
    flags = _flags(names, spread, t, dof, at_bound, profile)
    pinned = np.array([not flags[k] for k in names])
    cov5 = None
    if pinned.any():
        Ap = A[:, pinned]
        cov5 = Ap @ spread.cov_log[np.ix_(pinned, pinned)] @ Ap.T
        cov5 = 0.5 * (cov5 + cov5.T)
    p5 = np.exp(c + A @ sol.x)
    tissue = base.replace(name="fit", **dict(zip(PARAMETER_NAMES, p5.tolist(), strict=True)))
    pred = G * np.asarray(relaxation_integral_Pa(freq, _Constants(*p5)), dtype=float)
    with np.errstate(over="ignore", invalid="ignore"):
        half = np.exp(t * spread.se_log)
    ci95 = {
        k: ((float(v / h), float(v * h)) if math.isfinite(v * h) and v / h > 0 else (0.0, math.inf))
        for k, v, h in zip(names, p, half, strict=True)
    }
    s2 = float(sol.fun @ sol.fun) / dof if dof > 0 else math.nan
    return FitResult(
        tissue=tissue,
        free=names,
        values=dict(zip(names, p.tolist(), strict=True)),
        standard_errors=dict(zip(names, (p * spread.se_log).tolist(), strict=True)),
        standard_errors_log=dict(zip(names, spread.se_log.tolist(), strict=True)),
        ci95=ci95,
        flags=flags,
        correlation=spread.corr,
        covariance_log=cov5,
        frequency_hz=freq,
        helical_angle_rad=angle,
        torque_Nm=torque,
        predicted_Nm=pred,
        residuals=sol.fun if relative else sol.fun / scale,
        relative=relative,
        residual_std=math.sqrt(s2) if dof > 0 else math.nan,
        dof=dof,
        effective_parameters=_rank(J[:, ~at_bound]),
        condition_number=spread.condition,
        cost=float(sol.cost),
        success=bool(sol.success),
        message=str(sol.message),
        geometry=geometry,
    )
