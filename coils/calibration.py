"""A lab's coils as measured: the calibration model, its least-squares fit, the calibrated set.

Model (DESIGN.md 4.1; the per-pair linear map of ETH's mag_manip and oresat-helmholtz, reduced to
what a gaussmeter survey pins down):

    B(p, I) = b0 + sum_k M_k G_k(p) I_k

with G_k(p) the modelled field per ampere of pair k (T/A), M_k a 3 x 3 map near the identity
(gain and small rotation of the real pair against the model) and b0 a constant background field
(the Earth's, the building's), T. The model is linear in (b0, M_k), and each field component c
is its own regression on the same ten regressors ``[1, G_k(p)_j I_k for k, j]``: one
``numpy.linalg.lstsq`` with three right-hand sides. The actuation matrix at the workspace centre
is A = [M_k G_k(0)] (column k: the field per ampere of pair k there), and a circular rotating
field needs I(t) = A^-1 B(t) (:class:`CalibratedHelmholtz`).

What a survey pins down: column k of M_k (the direction the pair's field mostly points) from any
current setting that drives pair k; the other columns of M_k only through the pair's off-axis
field away from the centre, about 1e-4 of its main field inside a Helmholtz workspace, so not
at all against a gaussmeter's noise. The fit therefore carries the model's own premise, M_k
near the identity, as a Gaussian prior (each entry of M_k - I with standard deviation
:data:`PRIOR_SIGMA`, weighted against the noise the plain fit's residuals estimate): still one
linear least-squares solve, with nine extra rows per component. Entries the data see are the
data's; the others stay at the identity, where they hardly move the field anyway.
Data that leave a coefficient undefined
-- fewer than four independent current settings (with the background), or fewer than three
probe positions -- are refused with one line saying what to add.

Domain: a map more than :data:`MAP_DOMAIN` (Frobenius) from the identity is not a calibration of
the modelled pair (a pair wired backwards, a wrong channel): it is refused, as the design key
that carries it.

No I/O: the survey arrives as arrays, the CSV is read by ``spiralcap.commands.calibrate``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np

from coils.rotating import allocation
from coils.system import ThreeAxisHelmholtz
from spiralcap.core.constants import to_unit
from spiralcap.core.errors import DataError, InputError

__all__ = [
    "MAP_DOMAIN",
    "CalibratedHelmholtz",
    "CalibrationFit",
    "CoilCalibration",
    "Survey",
    "fit_calibration",
    "gains_and_tilts",
    "holdout_mask",
]

#: Largest Frobenius distance of a pair's map M_k from the identity the model accepts (a gain
#: of 0.5-1.5 or a tilt of up to ~20 degrees; a pair wired backwards is -I, at distance 3.5).
MAP_DOMAIN = 0.5
#: Prior standard deviation of each entry of M_k - I (a 5 % gain error, a 3 degree tilt): the
#: entries a survey cannot see (the off-axis columns near a uniform centre) stay near the identity.
PRIOR_SIGMA = 0.05
#: Every how many-th row (the 5th, 10th, ...) is held out to check the fit on rows it did not see.
HOLDOUT_EVERY = 5
#: Relative singular value below which a combination of coefficients counts as not determined.
RANK_TOLERANCE = 1e-9
_AXES = ("x", "y", "z")


@dataclass(frozen=True)
class Survey:
    """A gaussmeter survey: one row per probe position and current setting (SI).

    Attributes
    ----------
    points_m : ndarray, shape (n, 3)
        Probe positions, m.
    currents_A : ndarray, shape (n, 3)
        Currents of the x, y, z pairs, A.
    fields_T : ndarray, shape (n, 3)
        Measured flux density, T.
    """

    points_m: np.ndarray
    currents_A: np.ndarray
    fields_T: np.ndarray


@dataclass(frozen=True)
class CoilCalibration:
    """The fitted maps and background (what a design's ``[calibration]`` table carries).

    Attributes
    ----------
    maps : ndarray, shape (3, 3, 3)
        ``maps[k]`` is M_k of pair k (x, y, z), dimensionless.
    background_T : ndarray, shape (3,)
        Constant background field b0, T.
    """

    maps: np.ndarray
    background_T: np.ndarray

    def __post_init__(self) -> None:
        maps = np.asarray(self.maps, dtype=float)
        if maps.shape != (3, 3, 3) or not np.all(np.isfinite(maps)):
            raise InputError("calibration.maps", np.shape(self.maps), "three finite 3 x 3 maps")
        for k, ax in enumerate(_AXES):
            distance = float(np.linalg.norm(maps[k] - np.eye(3)))
            if distance > MAP_DOMAIN:
                raise InputError(
                    f"calibration.map_{ax}",
                    maps[k].round(4).tolist(),
                    f"a map within {MAP_DOMAIN:g} of the identity (Frobenius; this one is "
                    f"{distance:.3g} away: the survey's {ax} pair is not the modelled one -- "
                    "wired backwards, another channel, or a different coil)",
                )

    def apply(self, field_matrix_T_per_A: np.ndarray) -> np.ndarray:
        """The calibrated field matrices: column k becomes M_k G_k(p), shape (n, 3, 3), T/A.

        Parameters
        ----------
        field_matrix_T_per_A : ndarray, shape (n, 3, 3)
            Modelled G(p), T/A.

        Returns
        -------
        ndarray, shape (n, 3, 3)
            Calibrated field per ampere, T/A.
        """
        g = np.asarray(field_matrix_T_per_A, dtype=float)
        return np.einsum("kcj,njk->nck", np.asarray(self.maps, dtype=float), g)


def gains_and_tilts(
    actuation_T_per_A: np.ndarray, model_actuation_T_per_A: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Per pair: the gain |A_k| / |G_k(0)| and the tilt between A_k and G_k(0).

    Parameters
    ----------
    actuation_T_per_A, model_actuation_T_per_A : ndarray, shape (3, 3)
        Calibrated and modelled centre field per ampere (column k: pair k), T/A.

    Returns
    -------
    gains : ndarray, shape (3,)
        Per pair, dimensionless.
    tilts_deg : ndarray, shape (3,)
        Per pair, deg.
    """
    a = np.asarray(actuation_T_per_A, dtype=float)
    g = np.asarray(model_actuation_T_per_A, dtype=float)
    na, ng = np.linalg.norm(a, axis=0), np.linalg.norm(g, axis=0)
    cos = np.sum(a * g, axis=0) / (na * ng)
    return na / ng, to_unit(np.arccos(np.clip(cos, -1.0, 1.0)), "deg")


def holdout_mask(rows: int, every: int = HOLDOUT_EVERY) -> np.ndarray:
    """Rows held out of the check fit: every ``every``-th (indices every-1, 2 every-1, ...).

    Parameters
    ----------
    rows : int
        Survey rows, count.
    every : int
        Hold out one row in this many, count.

    Returns
    -------
    ndarray of bool, shape (rows,)
        True for a held-out row (dimensionless).
    """
    return (np.arange(rows) % every) == every - 1


def _design_matrix(field_matrix_T_per_A: np.ndarray, currents_A: np.ndarray) -> np.ndarray:
    """The regressors ``[1, G_k(p)_j I_k]`` (k, j in order), shape (n, 10), T."""
    g = np.asarray(field_matrix_T_per_A, dtype=float)  # (n, 3 comp, 3 pairs)
    cols = [np.ones(len(g))]
    for k in range(3):
        for j in range(3):
            cols.append(g[:, j, k] * currents_A[:, k])
    return np.column_stack(cols)


def _scaled(x: np.ndarray) -> np.ndarray:
    """Regressors divided pair by pair by the largest column of that pair (the background
    column by its own norm): a column that is zero in the data stays (numerically) zero."""
    out = x.copy()
    out[:, 0] /= max(float(np.linalg.norm(x[:, 0])), 1e-300)
    for k in range(3):
        block = slice(1 + 3 * k, 4 + 3 * k)
        out[:, block] /= max(float(np.max(np.linalg.norm(x[:, block], axis=0))), 1e-300)
    return out


def _check_rank(survey: Survey, x: np.ndarray, what: str) -> None:
    """Refuse data that leave a coefficient undefined, saying what to add.

    Raises
    ------
    DataError
        Too few independent current settings, too few probe positions, or another
        degeneracy (named).
    """
    rows = len(x)
    settings = np.column_stack([np.ones(rows), survey.currents_A])
    s = np.linalg.svd(
        settings / np.maximum(np.linalg.norm(settings, axis=0), 1e-300), compute_uv=False
    )
    have = int(np.sum(s > RANK_TOLERANCE * s[0]))
    if have < 4:
        raise DataError(
            f"{what}: the current settings drive {have - 1} independent combination(s) of "
            "the three pairs; add settings that drive each of the x, y and z pairs on its own "
            "(and one with all three off): 4 independent settings with the background at least"
        )
    positions = len(np.unique(np.round(survey.points_m, 9), axis=0))
    s = np.linalg.svd(_scaled(x), compute_uv=False)
    rank = int(np.sum(s > RANK_TOLERANCE * s[0]))
    if positions < 3 or rank < x.shape[1]:
        raise DataError(
            f"{what}: {positions} distinct probe positions leave {x.shape[1] - rank} of the 30 "
            "map and background coefficients undefined; add probe positions spread over the "
            "workspace off the coil axes (27 on a 3 x 3 x 3 grid is a good survey)"
        )
    if rows <= x.shape[1]:
        raise DataError(
            f"{what}: {rows} rows for {x.shape[1]} coefficients per field component; add rows "
            "(more positions or current settings) so the fit has residuals to check"
        )


@dataclass(frozen=True)
class CalibrationFit:
    """A calibration fitted to a survey, with its residuals (SI).

    Attributes
    ----------
    calibration : CoilCalibration
        The fitted maps and background, from every row.
    actuation_matrix_T_per_A : ndarray, shape (3, 3)
        Column k: the calibrated field per ampere of pair k at the workspace centre, T/A.
    model_actuation_T_per_A : ndarray, shape (3, 3)
        The same from the uncalibrated model, G(0), T/A.
    predicted_T : ndarray, shape (n, 3)
        The calibrated model at every survey row, T.
    residuals_T : ndarray, shape (n, 3)
        Measured minus predicted, T.
    holdout_rows : ndarray of bool, shape (n,)
        The rows left out of the check fit.
    holdout_rms_T : float
        RMS over the held-out rows' components of the fit made without them, T.
    survey : Survey
        The data.
    noise_T : float
        The noise estimate that weighted the identity prior (plain least squares' RMS), T.
    """

    calibration: CoilCalibration
    actuation_matrix_T_per_A: np.ndarray
    model_actuation_T_per_A: np.ndarray
    predicted_T: np.ndarray
    residuals_T: np.ndarray
    holdout_rows: np.ndarray
    holdout_rms_T: float
    survey: Survey
    noise_T: float

    @property
    def rows(self) -> int:
        """Survey rows (probe positions x current settings), count."""
        return len(self.residuals_T)

    @property
    def residual_rms_T(self) -> float:
        """RMS of every component of every row's residual, T."""
        return float(np.sqrt(np.mean(self.residuals_T**2)))

    @property
    def residual_max_T(self) -> float:
        """Largest residual magnitude |B_measured - B_model| of any row, T."""
        return float(np.max(np.linalg.norm(self.residuals_T, axis=1)))

    @property
    def gain_factors(self) -> np.ndarray:
        """|A_k| / |G_k(0)| per pair, dimensionless: real centre field per ampere / model's."""
        return gains_and_tilts(self.actuation_matrix_T_per_A, self.model_actuation_T_per_A)[0]

    @property
    def axis_tilts_deg(self) -> np.ndarray:
        """Angle between each pair's real centre field and the model's, degrees."""
        return gains_and_tilts(self.actuation_matrix_T_per_A, self.model_actuation_T_per_A)[1]


def _lstsq(x: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Least squares on column-scaled regressors, shape (10, 3) coefficients."""
    scale = np.linalg.norm(x, axis=0)
    scale[scale == 0.0] = 1.0
    beta = np.linalg.lstsq(x / scale, b, rcond=None)[0]
    return beta / scale[:, None]


def prior_rows(noise_T: float) -> tuple[np.ndarray, np.ndarray]:
    """The prior M_k ~ I as nine extra rows per component: (9, 10) regressors, (9, 3) targets.

    Row (k, j) says ``w M_k[c, j] = w δ_cj`` with weight w = noise / :data:`PRIOR_SIGMA`, T:
    a map entry PRIOR_SIGMA from the identity costs as much as one row's noise.

    Parameters
    ----------
    noise_T : float
        The noise estimate, T.

    Returns
    -------
    regressors : ndarray, shape (9, 10)
        Prior rows over [b0, M entries], T.
    targets : ndarray, shape (9, 3)
        Their right-hand sides per field component, T.
    """
    w = float(noise_T) / PRIOR_SIGMA
    x = np.zeros((9, 10))
    x[:, 1:] = w * np.eye(9)
    target = np.zeros((9, 3))
    for k in range(3):
        for j in range(3):
            target[3 * k + j, j] = w
    return x, target


def _solve(x: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, float]:
    """Coefficients (10, 3) with the identity prior; and the noise estimate it used, T.

    The noise is the RMS residual of the plain least-squares fit (each component has ten
    coefficients, so its residuals estimate the noise with (rows - 10) degrees of freedom).
    """
    plain = _lstsq(x, b)
    dof = max(len(x) - x.shape[1], 1)
    noise = float(np.sqrt(np.sum((b - x @ plain) ** 2) / (3 * dof)))
    px, pb = prior_rows(max(noise, 1e-300))
    return _lstsq(np.vstack([x, px]), np.vstack([b, pb])), noise


def _calibration(beta: np.ndarray) -> CoilCalibration:
    """Coefficients (10, 3): row 0 the background, rows 1 + 3k + j column j of M_k."""
    maps = np.stack([beta[1 + 3 * k : 4 + 3 * k, :].T for k in range(3)])
    return CoilCalibration(maps, beta[0].copy())


def fit_calibration(
    survey: Survey,
    field_matrices_T_per_A: np.ndarray,
    centre_field_matrix_T_per_A: np.ndarray,
    *,
    what: str = "survey",
) -> CalibrationFit:
    """Fit b0 and the maps M_k to a survey by linear least squares, with a held-out check.

    Parameters
    ----------
    survey : Survey
        Probe positions (m), currents (A) and measured fields (T), one row each.
    field_matrices_T_per_A : ndarray, shape (n, 3, 3)
        The modelled G(p) at each row's position, T/A.
    centre_field_matrix_T_per_A : ndarray, shape (3, 3)
        The modelled G(0) at the workspace centre, T/A.
    what : str
        How errors name the data (the CSV's path).

    Returns
    -------
    CalibrationFit
        Maps and background from every row; the held-out RMS from a fit without every
        :data:`HOLDOUT_EVERY`-th row.

    Raises
    ------
    DataError
        Rank-deficient data (what to add is said), or a fitted map outside its domain.
    """
    x = _design_matrix(field_matrices_T_per_A, np.asarray(survey.currents_A, dtype=float))
    b = np.asarray(survey.fields_T, dtype=float)
    _check_rank(survey, x, what)
    held = holdout_mask(len(x))
    train = ~held
    _check_rank(
        Survey(survey.points_m[train], survey.currents_A[train], b[train]),
        x[train],
        f"{what} (without its held-out rows)",
    )
    beta, noise = _solve(x, b)
    try:
        calibration = _calibration(beta)
    except InputError as exc:
        raise DataError(f"{what}: the fitted {exc.key} is not {exc.allowed}") from None
    held_res = b[held] - x[held] @ _solve(x[train], b[train])[0]
    predicted = x @ beta
    g0 = np.asarray(centre_field_matrix_T_per_A, dtype=float)
    return CalibrationFit(
        calibration=calibration,
        actuation_matrix_T_per_A=calibration.apply(g0[None])[0],
        model_actuation_T_per_A=g0,
        predicted_T=predicted,
        residuals_T=b - predicted,
        holdout_rows=held,
        holdout_rms_T=float(np.sqrt(np.mean(held_res**2))),
        survey=survey,
        noise_T=noise,
    )


@dataclass(frozen=True)
class CalibratedHelmholtz(ThreeAxisHelmholtz):
    """A three-axis set with each pair's field through its calibration map: G_k -> M_k G_k.

    The field, the field matrix, the CasADi field functions and the rotating-field allocation
    (which inverts the calibrated centre matrix A, so the field turns circularly about the
    heading in the real coils) all use the calibrated field. The background b0 is not part of
    the coils' field: :attr:`background_T` is there for whoever drives the coils to cancel
    (``coils.waveforms``).

    Parameters
    ----------
    x, y, z : HelmholtzPair or SquarePair
        The pairs, as :class:`coils.ThreeAxisHelmholtz`.
    calibration : CoilCalibration
        The maps and the background.
    """

    calibration: CoilCalibration | None = None

    def __post_init__(self) -> None:
        super().__post_init__()
        if not isinstance(self.calibration, CoilCalibration):
            raise InputError("calibration", self.calibration, "a coils.CoilCalibration")

    @property
    def _cal(self) -> CoilCalibration:
        assert self.calibration is not None  # checked in __post_init__
        return self.calibration

    @property
    def background_T(self) -> np.ndarray:
        """The survey's constant background field b0, shape (3,), T."""
        return np.asarray(self._cal.background_T, dtype=float)

    def field_matrix(self, points_m: Any) -> np.ndarray:
        """Calibrated G(p), shape (n, 3, 3), T/A: column k is M_k G_k(p).

        Parameters
        ----------
        points_m : array_like, shape (n, 3)
            Field points, m.

        Returns
        -------
        ndarray, shape (n, 3, 3)
            Calibrated field per ampere of each pair, T/A.
        """
        return self._cal.apply(super().field_matrix(points_m))

    def field(self, points_m: Any, currents_A: Any) -> np.ndarray:
        """Calibrated field of the three pairs (the background not included), T.

        Parameters
        ----------
        points_m : array_like, shape (n, 3)
            Field points, m.
        currents_A : array_like, shape (3,)
            Currents of the x, y, z pairs, A.

        Returns
        -------
        ndarray, shape (n, 3)
            Magnetic flux density of the coils, T.
        """
        current = np.asarray(currents_A, dtype=float)
        if current.shape != (3,):
            raise InputError("currents_A", np.shape(currents_A), "three currents (x, y, z), A")
        return self.field_matrix(points_m) @ current

    @cached_property
    def actuation_matrix_T_per_A(self) -> np.ndarray:
        """Calibrated centre matrix A, shape (3, 3), T/A (column k: pair k per ampere)."""
        return self.field_matrix(np.zeros((1, 3)))[0]

    @cached_property
    def centre_gains_T_per_A(self) -> np.ndarray:
        """|A_k|: the calibrated centre field per ampere of each pair, shape (3,), T/A."""
        return np.linalg.norm(self.actuation_matrix_T_per_A, axis=0)

    @cached_property
    def _casadi_symbols(self) -> tuple[Any, Any, Any]:
        import casadi as ca

        point = ca.SX.sym("point_m", 3)
        currents = ca.SX.sym("currents_A", 3)
        nominal = self.filament_set.field(point.T, currents).T
        g = ca.jacobian(nominal, currents)  # exact: the field is linear in the currents
        maps = np.asarray(self._cal.maps, dtype=float)
        columns = [ca.mtimes(ca.DM(maps[k]), g[:, k]) for k in range(3)]
        field = ca.mtimes(ca.horzcat(*columns), currents)
        return point, currents, ca.densify(field)

    def rotating_allocation(
        self, heading: Any, amplitude_T: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """Currents making at the centre, in the calibrated coils, a circular rotating field.

        Parameters
        ----------
        heading : array_like, shape (3,)
            Rotation axis n (right-handed sense), normalised here.
        amplitude_T : float
            Field amplitude B0, T.

        Returns
        -------
        amplitudes_A, phases_rad : ndarray, shape (3,)
            Amplitudes (A) and phases (rad) of I_k(t) = A_k cos(2π f t + φ_k), from A^-1.
        """
        return allocation(self.actuation_matrix_T_per_A, heading, amplitude_T)


def calibrated(system: ThreeAxisHelmholtz, calibration: CoilCalibration) -> CalibratedHelmholtz:
    """``system`` with its pairs' fields through ``calibration``'s maps.

    Parameters
    ----------
    system : ThreeAxisHelmholtz
        The modelled coils.
    calibration : CoilCalibration
        The maps (dimensionless) and background (T).

    Returns
    -------
    CalibratedHelmholtz
        The same pairs, calibrated.
    """
    return CalibratedHelmholtz(system.x, system.y, system.z, calibration)
