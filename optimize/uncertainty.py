"""A design under uncertain tissue: Monte Carlo of the worst-case margin, step-out, Sobol indices.

The uncertain inputs are independent *latent* standard normals ``z`` (one per active source),
drawn as quasi-random uniforms ``u`` (scipy.stats.qmc: scrambled Sobol' or Halton, Owen 1998)
and mapped by the inverse normal CDF, ``z = Φ⁻¹(u)``. They perturb every tissue set of the
design alike (the same patient for every set; the margin stays a worst case over sets):

- ``scale_sigma_log``: one log-normal factor ``exp(σ z)`` on all five moduli and viscosities
  (the calibration's uncertainty, docs/torque-model.md);
- ``sigma_log[i]``: an independent log-normal factor on E1, E2, E3, eta1, eta2 each;
- ``covariance_log``: correlated log-factors ``L z`` with ``L Lᵀ = Σ`` (Σ: the covariance of
  the log-parameters a ``spiralcap fit`` identified; ``L`` from its eigen-decomposition, so a
  singular but positive semi-definite Σ works, Higham 2002 "Accuracy and stability", §10.3);
- ``friction_sigma_log``: a log-normal factor on the friction coefficient;
- ``lumen_diameter_sigma_m``, ``wall_thickness_sigma_m``: additive normal offsets, truncated so
  the thinnest set keeps 10 % of its nominal value (inverse-CDF of the truncated normal).

Every sample is evaluated by :func:`optimize.physics.required_torques_Nm` on arrays — the one
definition of the tissue and thrust torques the evaluation and the optimiser use — with the
field the coils can make at the operating point (:func:`optimize.physics.field_capacity_T`).
The capsule steps out when the worst-case margin is negative; it then makes no headway, so the
speed of a sample is the design's speed when the margin holds and 0 when it does not.

Reproducibility: sample ``i`` is the ``i``-th point of one seeded sequence, whatever chunk and
worker computes it (:func:`chunk_margins` fast-forwards the sequence; the pseudo-random
``"random"`` method seeds each fixed-size chunk from ``(seed, chunk index)``).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import special

from optimize import physics as ph
from optimize.scenario_nlp import TissueArrays
from optimize.system import DesignModel, prepare
from spiralcap.core.errors import InputError

#: Samples per chunk: a power of two (balanced Sobol' blocks); fixed, so results do not depend
#: on how many workers share the chunks.
CHUNK = 1 << 15
#: Rows evaluated at once (64 KB per temporary array).
BLOCK = 1 << 13
METHODS = ("sobol", "halton", "random")
VISCOELASTIC = ("E1_Pa", "E2_Pa", "E3_Pa", "eta1_Pa_s", "eta2_Pa_s")
#: Short names of the five viscoelastic parameters (design keys without unit).
SHORT = ("E1", "E2", "E3", "eta1", "eta2")
_U_EPS = 1e-12
_FLOOR = 0.1  # truncation of the additive geometry offsets: keep 10 % of the nominal


@dataclass(frozen=True)
class TissueUncertainty:
    """Uncertainty of the tissue parameters (SI; sigmas of natural logs or of lengths in m).

    ``covariance_log`` is the 5 x 5 covariance of ln(E1, E2, E3, eta1, eta2) (tuple of rows),
    or ``None``. Defaults: no uncertainty.

    Attributes
    ----------
    scale_sigma_log : float
        Standard deviation of ln k of one common factor k on the five constants, dimensionless.
    sigma_log : tuple of float
        Standard deviations of ln E1, ln E2, ln E3, ln eta1, ln eta2, independent, dimensionless.
    friction_sigma_log : float
        Standard deviation of ln mu, dimensionless.
    lumen_diameter_sigma_m : float
        Standard deviation of an additive lumen-diameter offset, m.
    wall_thickness_sigma_m : float
        Standard deviation of an additive wall-thickness offset, m.
    covariance_log : tuple of tuple of float or None
        5 x 5 covariance of the log constants, dimensionless (None: none).
    """

    scale_sigma_log: float = 0.0
    sigma_log: tuple[float, float, float, float, float] = (0.0, 0.0, 0.0, 0.0, 0.0)
    friction_sigma_log: float = 0.0
    lumen_diameter_sigma_m: float = 0.0
    wall_thickness_sigma_m: float = 0.0
    covariance_log: tuple[tuple[float, ...], ...] | None = None

    def __post_init__(self) -> None:
        for name in (
            "scale_sigma_log",
            "friction_sigma_log",
            "lumen_diameter_sigma_m",
            "wall_thickness_sigma_m",
        ):
            _check_sigma(name, getattr(self, name))
        if len(self.sigma_log) != 5:
            raise InputError("sigma_log", self.sigma_log, "five sigmas (E1, E2, E3, eta1, eta2)")
        for short, s in zip(SHORT, self.sigma_log):
            _check_sigma(f"{short}_sigma_log", s)
        if self.covariance_log is not None:
            covariance_factor(np.asarray(self.covariance_log, dtype=float))

    def factors(self) -> list[tuple[str, str]]:
        """The active latent dimensions as (source, Sobol group), in sampling order.

        Returns
        -------
        list of (str, str)
            (source, Sobol group) of each latent dimension.
        """
        out = []
        if self.scale_sigma_log > 0:
            out.append(("scale", "scale"))
        out += [(s, s) for s, sig in zip(SHORT, self.sigma_log) if sig > 0]
        if self.covariance_log is not None:
            k = covariance_factor(np.asarray(self.covariance_log, dtype=float)).shape[1]
            out += [(f"fit{j}", "fit covariance") for j in range(k)]
        if self.friction_sigma_log > 0:
            out.append(("friction", "friction"))
        if self.lumen_diameter_sigma_m > 0:
            out.append(("lumen", "lumen_diameter"))
        if self.wall_thickness_sigma_m > 0:
            out.append(("wall", "wall_thickness"))
        return out

    @property
    def active(self) -> bool:
        """Flag: any input is uncertain."""
        return bool(self.factors())


def _check_sigma(name: str, value: Any) -> None:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
        raise InputError(name, value, "a finite standard deviation >= 0")


def covariance_factor(cov: np.ndarray, key: str = "covariance_log") -> np.ndarray:
    """``L`` (5 x r) with ``L Lᵀ = cov``, from the eigen-decomposition (r: numerical rank).

    Raises
    ------
    InputError
        Not 5 x 5, not finite, not symmetric, or an eigenvalue below ``-1e-10 · max|λ|`` (not
        positive semi-definite).

    Parameters
    ----------
    cov : ndarray, shape (5, 5)
        Covariance of the log constants, dimensionless.
    key : str
        Name an error gives.

    Returns
    -------
    ndarray, shape (5, r)
        The factor L, dimensionless.
    """
    if cov.shape != (5, 5):
        raise InputError(key, cov.shape, "a 5 x 5 matrix over E1, E2, E3, eta1, eta2")
    if not np.all(np.isfinite(cov)):
        raise InputError(key, "non-finite entries", "finite covariances (every parameter pinned)")
    if not np.allclose(cov, cov.T, rtol=1e-8, atol=1e-14 * float(np.abs(cov).max() or 1.0)):
        raise InputError(key, "not symmetric", "a symmetric covariance matrix")
    lam, vec = np.linalg.eigh(0.5 * (cov + cov.T))
    top = float(np.abs(lam).max()) if lam.size else 0.0
    if lam.min() < -1e-10 * max(top, 1e-300):
        raise InputError(
            key, f"smallest eigenvalue {lam.min():.3g}", "a positive semi-definite covariance"
        )
    keep = lam > 1e-12 * max(top, 1e-300)
    return vec[:, keep] * np.sqrt(lam[keep])


def perturbed_tissues(tissues: tuple, unc: TissueUncertainty, u: np.ndarray) -> tuple:
    """Each nominal tissue set perturbed by the latent uniforms ``u`` (n x d), as arrays.

    Parameters
    ----------
    tissues : tuple of TissueParameters
        The nominal sets.
    unc : TissueUncertainty
        What is uncertain; ``d = len(unc.factors())``.
    u : ndarray, shape (n, d)
        Uniforms in (0, 1), dimensionless, one column per latent factor.

    Returns
    -------
    tuple of TissueArrays
        One per nominal set, each field an (n,) array, SI (Pa, Pa·s, m; friction
        dimensionless).
    """
    u = np.clip(np.asarray(u, dtype=float), _U_EPS, 1.0 - _U_EPS)
    n = u.shape[0]
    z = special.ndtri(u)
    names = [name for name, _ in unc.factors()]
    col = {name: z[:, j] for j, name in enumerate(names)}
    log_k = np.zeros((5, n))
    if "scale" in col:
        log_k += unc.scale_sigma_log * col["scale"]
    for i, (short, sig) in enumerate(zip(SHORT, unc.sigma_log)):
        if sig > 0:
            log_k[i] += sig * col[short]
    if unc.covariance_log is not None:
        L = covariance_factor(np.asarray(unc.covariance_log, dtype=float))
        if L.shape[1]:  # rank 0 (every variance negligible): no fitted factor
            zc = np.stack([col[f"fit{j}"] for j in range(L.shape[1])])
            log_k += L @ zc
    k = np.exp(log_k)
    mu_k = np.exp(unc.friction_sigma_log * col["friction"]) if "friction" in col else 1.0
    d_lumen = _truncated_offset(
        u[:, names.index("lumen")] if "lumen" in col else None,
        unc.lumen_diameter_sigma_m,
        min(t.lumen_diameter_m for t in tissues),
    )
    d_wall = _truncated_offset(
        u[:, names.index("wall")] if "wall" in col else None,
        unc.wall_thickness_sigma_m,
        min(t.wall_thickness_m for t in tissues),
    )
    out = []
    for t in tissues:
        vals = {f: getattr(t, f) * k[i] for i, f in enumerate(VISCOELASTIC)}
        out.append(
            TissueArrays(
                **vals,
                lumen_diameter_m=t.lumen_diameter_m + d_lumen,
                wall_thickness_m=t.wall_thickness_m + d_wall,
                friction_coefficient=t.friction_coefficient * mu_k,
                name=t.name,
            )
        )
    return tuple(out)


def _truncated_offset(u: np.ndarray | None, sigma: float, nominal: float) -> Any:
    """Normal offset N(0, σ²) truncated below at ``-(1 - _FLOOR)·nominal`` (inverse CDF)."""
    if u is None or sigma <= 0:
        return 0.0
    lo = special.ndtr(-(1.0 - _FLOOR) * nominal / sigma)
    return sigma * special.ndtri(lo + u * (1.0 - lo))


@dataclass(frozen=True)
class MarginProblem:
    """Everything needed to evaluate the worst-case margin of one design for sampled tissues.

    Small and picklable: it is what a worker process or a Dask worker receives.

    Attributes
    ----------
    helical_angle_rad : float
        Helical angle, rad.
    frequency_hz : float
        Rotation frequency, Hz.
    available_torque_Nm : float
        Available synchronous torque, N·m.
    speed_m_s : float
        Forward speed when the capsule keeps up, m/s.
    constants : Constants
        The design's constants.
    requirements : Requirements
        The requirements.
    tissues : tuple of TissueParameters
        The nominal tissue sets.
    uncertainty : TissueUncertainty
        What is uncertain.
    """

    helical_angle_rad: float
    frequency_hz: float
    available_torque_Nm: float
    speed_m_s: float
    constants: Any
    requirements: Any
    tissues: tuple
    uncertainty: TissueUncertainty

    @property
    def dimension(self) -> int:
        """Number of latent factors, count."""
        return len(self.uncertainty.factors())

    def margins_Nm(self, u: np.ndarray) -> np.ndarray:
        """Worst-case margin (over the tissue sets) for each row of latent uniforms ``u``, N·m.

        Evaluated in blocks of :data:`BLOCK` rows: temporaries stay below glibc's mmap threshold
        (Dask's nanny sets ``MALLOC_TRIM_THRESHOLD_``, which makes every larger array an
        mmap + page faults, twice as slow); each sample is element-wise, so blocks change nothing.

        Parameters
        ----------
        u : ndarray, shape (n, d)
            Latent uniforms in (0, 1), dimensionless.

        Returns
        -------
        ndarray, shape (n,)
            Worst-case margin per sample, N·m.
        """
        u = np.asarray(u, dtype=float)
        if u.shape[0] <= BLOCK:
            return self._margins(u)
        return np.concatenate([self._margins(u[i : i + BLOCK]) for i in range(0, len(u), BLOCK)])

    def _margins(self, u: np.ndarray) -> np.ndarray:
        return self._outcomes(u)[:, 0]

    def _outcomes(self, u: np.ndarray) -> np.ndarray:
        arrays = perturbed_tissues(self.tissues, self.uncertainty, u)
        pairs = ph.required_torques_Nm(
            self.helical_angle_rad, self.frequency_hz, self.constants, arrays, self.requirements
        )
        need = np.max(np.stack([np.asarray(r + t, dtype=float) for r, t in pairs]), axis=0)
        strains = ph.wall_strains(self.helical_angle_rad, self.constants, arrays)
        least = np.min(
            np.stack([np.broadcast_to(np.asarray(s, float), need.shape) for s in strains]), 0
        )
        return np.stack([self.available_torque_Nm - need, least], axis=1)

    def outcomes(self, u: np.ndarray) -> np.ndarray:
        """Worst-case margin and least wall strain (over the tissue sets) of each sample.

        Evaluated in blocks of :data:`BLOCK` rows, as :meth:`margins_Nm`.

        Parameters
        ----------
        u : ndarray, shape (n, d)
            Latent uniforms in (0, 1), dimensionless.

        Returns
        -------
        ndarray, shape (n, 2)
            Column 0 the worst-case margin (as modelled, grip or not), N·m; column 1 the least
            strain the spiral stretches a tissue set's wall by, dimensionless (<= 0: no
            contact).
        """
        u = np.asarray(u, dtype=float)
        if u.shape[0] <= BLOCK:
            return self._outcomes(u)
        return np.concatenate([self._outcomes(u[i : i + BLOCK]) for i in range(0, len(u), BLOCK)])

    def counted_margins_Nm(self, u: np.ndarray) -> np.ndarray:
        """The margin each sample counts with (:func:`counted_margins`): a sample below the
        minimum strain never counts as a good margin.

        Parameters
        ----------
        u : ndarray, shape (n, d)
            Latent uniforms in (0, 1), dimensionless.

        Returns
        -------
        ndarray, shape (n,)
            Counted worst-case margin per sample, N·m.
        """
        o = self.outcomes(u)
        return counted_margins(o[:, 0], o[:, 1], self.min_wall_strain)

    @property
    def min_wall_strain(self) -> float:
        """The least wall strain a sample must reach to grip (requirements.min_wall_strain),
        dimensionless."""
        return float(self.requirements.min_wall_strain)

    def nominal_margin_Nm(self) -> float:
        """The deterministic worst-case margin (the nominal tissue sets), N·m; NaN where the
        spiral does not touch some nominal wall (no contact: the model has no margin there, as
        :func:`optimize.evaluate`).

        Returns
        -------
        float
            The nominal worst-case margin, N·m.
        """
        pairs = ph.required_torques_Nm(
            self.helical_angle_rad,
            self.frequency_hz,
            self.constants,
            self.tissues,
            self.requirements,
        )
        strains = ph.wall_strains(self.helical_angle_rad, self.constants, self.tissues)
        if min(float(e) for e in strains) <= 0.0:
            return math.nan
        return self.available_torque_Nm - max(float(r + t) for r, t in pairs)


def margin_problem(
    model: DesignModel,
    uncertainty: TissueUncertainty,
    helical_angle_rad: float | None = None,
    frequency_hz: float | None = None,
    *,
    field_T: float | None = None,
) -> MarginProblem:
    """The :class:`MarginProblem` of ``model`` at its operating point (or the given one).

    The field is ``field_T``, else the model's set field (``operation.field_amplitude_mT``,
    capped at what the limits allow), else the largest every limit allows at the frequency —
    as :func:`optimize.evaluate`.

    Parameters
    ----------
    model : DesignModel
        The design.
    uncertainty : TissueUncertainty
        What is uncertain.
    helical_angle_rad : float, optional
        Helical angle, rad (default: the capsule's).
    frequency_hz : float, optional
        Rotation frequency, Hz (default: the model's).
    field_T : float, optional
        Centre field amplitude, T.

    Returns
    -------
    MarginProblem
        The picklable problem, SI.
    """
    model = prepare(model)
    c = model.constants
    alpha = (
        model.capsule.spiral.helical_angle_rad if helical_angle_rad is None else helical_angle_rad
    )
    f = model.frequency_hz if frequency_hz is None else frequency_hz
    if field_T is None:
        field_T, _, _ = ph.field_capacity_T(f, c, model.limits, model.ambient_temperature_C)
        if model.field_amplitude_T is not None:  # a set field, capped as evaluate caps it
            field_T = min(float(model.field_amplitude_T), float(field_T))
    return MarginProblem(
        helical_angle_rad=float(alpha),
        frequency_hz=float(f),
        available_torque_Nm=float(ph.available_torque_Nm(float(field_T), c)),
        speed_m_s=float(ph.speed_m_s(alpha, f, c, model.requirements)),
        constants=c,
        requirements=model.requirements,
        tissues=tuple(model.tissues),
        uncertainty=uncertainty,
    )


def latent_uniforms(d: int, start: int, count: int, seed: int, method: str = "sobol") -> np.ndarray:
    """Points ``start .. start+count-1`` of the seeded sequence, shape (count, d), in (0, 1).

    ``"sobol"`` and ``"halton"`` are scrambled low-discrepancy sequences (scipy.stats.qmc),
    fast-forwarded to ``start``; ``"random"`` draws each :data:`CHUNK`-sized block from
    ``numpy.random.default_rng((seed, block))`` (``start`` must then be a multiple of CHUNK).

    Parameters
    ----------
    d : int
        Number of latent dimensions.
    start : int
        Index of the first point.
    count : int
        Number of points.
    seed : int
        Seed of the sequence.
    method : str
        ``"sobol"``, ``"halton"`` or ``"random"``.

    Returns
    -------
    ndarray, shape (count, d)
        Uniforms in (0, 1), dimensionless.
    """
    if method == "random":
        if start % CHUNK:
            raise InputError("start", start, f"a multiple of {CHUNK} for method 'random'")
        rng = np.random.default_rng((seed, start // CHUNK))
        return rng.random((count, d))
    if method not in METHODS:
        raise InputError("method", method, "one of " + ", ".join(METHODS))
    from scipy.stats import qmc

    engine_cls = qmc.Sobol if method == "sobol" else qmc.Halton
    try:
        engine = engine_cls(d, scramble=True, rng=np.random.default_rng(seed))
    except TypeError:  # scipy < 1.15
        engine = engine_cls(d, scramble=True, seed=np.random.default_rng(seed))
    if start:
        engine.fast_forward(start)
    if method == "sobol":
        # whole power-of-two blocks keep Sobol' balanced; the tail block is cut afterwards
        n = 1 << max(int(count - 1).bit_length(), 0) if start == 0 else count
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # a continuation block is not 2**m
            return engine.random(max(n, count))[:count]
    return engine.random(count)


def chunk_outcomes(
    problem: MarginProblem, start: int, count: int, seed: int, method: str
) -> np.ndarray:
    """Margins and strains of samples ``start .. start+count-1`` (the unit of work sent to a
    worker): :meth:`MarginProblem.outcomes`.

    Parameters
    ----------
    problem : MarginProblem
        The design and its uncertainty.
    start : int
        Index of the first sample.
    count : int
        Number of samples.
    seed : int
        Seed of the sequence.
    method : str
        Sampling method (:data:`METHODS`).

    Returns
    -------
    ndarray, shape (count, 2)
        Worst-case margin (N·m) and least wall strain (dimensionless) of each sample.
    """
    u = latent_uniforms(problem.dimension, start, count, seed, method)
    return problem.outcomes(u)


def batch_outcomes(
    problem: MarginProblem, pieces: tuple[tuple[int, int], ...], seed: int, method: str
) -> np.ndarray:
    """:func:`chunk_outcomes` of several (start, count) chunks, concatenated (one task).

    Parameters
    ----------
    problem : MarginProblem
        The design and its uncertainty.
    pieces : tuple of (int, int)
        (start index, count) of each chunk.
    seed : int
        Seed of the sequence.
    method : str
        Sampling method.

    Returns
    -------
    ndarray, shape (n, 2)
        The chunks' margins (N·m) and least strains (dimensionless) in order.
    """
    return np.concatenate([chunk_outcomes(problem, s, n, seed, method) for s, n in pieces])


def batches(samples: int, per_task: int = 8) -> list[tuple[tuple[int, int], ...]]:
    """The chunks of ``samples`` grouped ``per_task`` to a task (fewer round trips).

    Parameters
    ----------
    samples : int
        Number of samples.
    per_task : int
        Number of chunks per task.

    Returns
    -------
    list of tuple of (int, int)
        Per task, (start index, count) of its chunks.
    """
    c = chunks(samples)
    return [tuple(c[i : i + per_task]) for i in range(0, len(c), per_task)]


def chunks(samples: int) -> list[tuple[int, int]]:
    """(start, count) of each fixed-size chunk of ``samples``.

    Parameters
    ----------
    samples : int
        Number of samples.

    Returns
    -------
    list of (int, int)
        (start index, count) of each chunk.
    """
    return [(s, min(CHUNK, samples - s)) for s in range(0, samples, CHUNK)]


@dataclass(frozen=True)
class SobolIndices:
    """First-order and total Sobol indices of the margin per uncertain input (SALib).

    Attributes
    ----------
    inputs : tuple of str
        The uncertain inputs (Sobol groups).
    first_order, total : tuple of float
        First-order and total index of each input, dimensionless (fractions of the variance).
    first_order_conf, total_conf : tuple of float
        Their 95 % confidence half-widths, dimensionless.
    base_samples : int
        Number of base samples of the Saltelli design.
    """

    inputs: tuple[str, ...]
    first_order: tuple[float, ...]
    first_order_conf: tuple[float, ...]
    total: tuple[float, ...]
    total_conf: tuple[float, ...]
    base_samples: int


@dataclass(frozen=True)
class Probability:
    """A share of the samples and its Wilson 95 % interval.

    Attributes
    ----------
    value : float
        Share of the samples, a probability.
    ci95 : (float, float)
        Wilson score 95 % interval, a probability each.
    count : int
        Number of samples in it, count.
    """

    value: float
    ci95: tuple[float, float]
    count: int

    @classmethod
    def of(cls, mask: np.ndarray) -> Probability:
        """The share of True in ``mask`` with its Wilson interval.

        Parameters
        ----------
        mask : ndarray of bool
            One flag per sample.

        Returns
        -------
        Probability
            The share, a probability.
        """
        k, n = int(np.count_nonzero(mask)), int(mask.size)
        return cls(k / n, wilson_interval(k, n), k)


@dataclass(frozen=True)
class UncertaintyResult:
    """Distribution of the worst-case margin and speed over the sampled tissues (SI).

    A sample **fails** when the capsule steps out (worst-case margin < 0) or its spiral
    stretches some tissue set's wall by less than ``requirements.min_wall_strain`` (no contact
    is the extreme case): :func:`failed`. The margin statistics and the Sobol indices use each
    sample's *counted* margin (:func:`counted_margins`: a sample below the minimum strain counts
    with ``min(margin, 0)``, never as a good margin); the speed is 0 in every failed sample.

    Attributes
    ----------
    samples : int
        Number of tissue samples.
    seed : int
        Seed of the sequence.
    method : str
        Sampling method.
    nominal_margin_Nm : float
        Worst-case margin of the nominal sets, N·m.
    available_torque_Nm : float
        Available synchronous torque, N·m.
    speed_nominal_m_s : float
        Forward speed when the capsule keeps up, m/s.
    stepout_probability : float
        Share of samples with a negative margin, a probability.
    stepout_ci95 : (float, float)
        Wilson 95 % interval of that probability.
    margin_percentiles_Nm : dict of str to float
        Percentiles (``p01``, ``p05``, ``p50``, ``p95``) of the counted margin, N·m.
    speed_percentiles_m_s : dict of str to float
        Speed percentiles (0 in a failed sample), m/s.
    margin_mean_Nm, margin_std_Nm : float
        Mean and standard deviation of the counted margin, N·m.
    sobol : SobolIndices or None
        Sensitivity indices of the counted margin, when asked for.
    margins_Nm : ndarray
        Every sample's counted margin in sample order, N·m.
    no_grip_probability : float
        Share of samples whose spiral does not touch some tissue set's wall (strain <= 0), a
        probability.
    failure : Probability
        Share of failed samples (step-out or below the minimum strain).
    stepout : Probability
        Share of samples with a negative margin (as ``stepout_probability``).
    below_min_strain : Probability
        Share of samples below the minimum strain in some set (no contact included).
    no_grip : Probability
        Share of samples without contact in some set.
    min_wall_strain : float
        The minimum strain the samples were judged against, dimensionless.
    closed_form : dict of str to float
        The exact probabilities (a probability each) where a closed form exists (:func:`grip_loss_probability`:
        ``no_grip`` always, ``below_min_strain`` without wall-thickness uncertainty).
    strains : ndarray
        Every sample's least wall strain in sample order, dimensionless.
    """

    samples: int
    seed: int
    method: str
    nominal_margin_Nm: float
    available_torque_Nm: float
    speed_nominal_m_s: float
    stepout_probability: float
    stepout_ci95: tuple[float, float]
    margin_percentiles_Nm: dict[str, float]
    speed_percentiles_m_s: dict[str, float]
    margin_mean_Nm: float
    margin_std_Nm: float
    sobol: SobolIndices | None
    margins_Nm: np.ndarray = field(repr=False, compare=False)
    no_grip_probability: float = 0.0
    failure: Probability = Probability(0.0, (0.0, 1.0), 0)
    stepout: Probability = Probability(0.0, (0.0, 1.0), 0)
    below_min_strain: Probability = Probability(0.0, (0.0, 1.0), 0)
    no_grip: Probability = Probability(0.0, (0.0, 1.0), 0)
    min_wall_strain: float = 0.0
    closed_form: dict[str, float] = field(default_factory=dict)
    strains: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False, compare=False)

    @property
    def failure_probability(self) -> float:
        """Share of failed samples, a probability."""
        return self.failure.value


#: How the margin statistics count a failed sample (text, JSON and the report say it).
MARGIN_COUNTING = (
    "a sample below the minimum wall strain (no contact included) counts with its margin "
    "clipped to at most 0, min(margin, 0): a failed sample never counts as a good margin; a "
    "sample that steps out keeps its negative margin"
)
#: The failure definition, in words.
FAILURE_DEFINITION = (
    "a sample fails when the capsule steps out (worst-case margin < 0) or its spiral "
    "stretches some tissue set's wall by less than requirements.min_wall_strain (no contact "
    "is the extreme case)"
)


def grip_threshold(min_wall_strain: float) -> float:
    """The strain below which a sample has lost its grip: ``requirements.min_wall_strain`` less
    the tolerance :func:`optimize.evaluate` judges requirements with (an optimum sits on its
    strain row to the solver's tolerance), dimensionless.

    Parameters
    ----------
    min_wall_strain : float
        The minimum strain, dimensionless.

    Returns
    -------
    float
        The threshold, dimensionless.
    """
    from optimize.evaluate import FEASIBILITY_RTOL

    return float(min_wall_strain) * (1.0 - FEASIBILITY_RTOL)


def counted_margins(margins: Any, strains: Any, min_wall_strain: float) -> np.ndarray:
    """The margin a sample counts with: ``min(margin, 0)`` below the minimum strain, else the
    margin (a failed sample is never a good margin).

    Parameters
    ----------
    margins : array_like
        Worst-case margins (as modelled), N·m.
    strains : array_like
        Least wall strains, dimensionless.
    min_wall_strain : float
        The minimum strain, dimensionless.

    Returns
    -------
    ndarray
        Counted margins, N·m.
    """
    m = np.asarray(margins, dtype=float)
    return np.where(np.asarray(strains) < grip_threshold(min_wall_strain), np.minimum(m, 0.0), m)


def failed(margins: Any, strains: Any, min_wall_strain: float) -> np.ndarray:
    """Which samples fail: a negative margin or a least strain below the minimum.

    Parameters
    ----------
    margins : array_like
        Worst-case margins, N·m.
    strains : array_like
        Least wall strains, dimensionless.
    min_wall_strain : float
        The minimum strain, dimensionless.

    Returns
    -------
    ndarray of bool
        True where the sample fails.
    """
    return (np.asarray(margins) < 0) | (np.asarray(strains) < grip_threshold(min_wall_strain))


PERCENTILES = (("p01", 1.0), ("p05", 5.0), ("p50", 50.0), ("p95", 95.0))


def wilson_interval(k: int, n: int, z: float = 1.959963984540054) -> tuple[float, float]:
    """Wilson score 95 % interval of a binomial proportion k/n (Wilson 1927).

    Parameters
    ----------
    k : int
        Number of successes.
    n : int
        Number of trials.
    z : float
        Normal quantile of the interval, dimensionless (1.96 for 95 %).

    Returns
    -------
    (float, float)
        Lower and upper bound of the proportion, a probability.
    """
    p = k / n
    den = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / den
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    lo = 0.0 if k == 0 else max(0.0, centre - half)
    hi = 1.0 if k == n else min(1.0, centre + half)
    return lo, hi


def summarise(
    problem: MarginProblem,
    outcomes: np.ndarray,
    seed: int,
    method: str,
    sobol: SobolIndices | None = None,
) -> UncertaintyResult:
    """The statistics of the sampled outcomes (in sample order).

    Parameters
    ----------
    problem : MarginProblem
        The design and its uncertainty.
    outcomes : ndarray, shape (n, 2)
        Worst-case margin (N·m) and least wall strain (dimensionless) of each sample
        (:meth:`MarginProblem.outcomes`).
    seed : int
        Seed of the sequence.
    method : str
        Sampling method.
    sobol : SobolIndices, optional
        Sensitivity indices to attach.

    Returns
    -------
    UncertaintyResult
        The statistics, SI.
    """
    outcomes = np.asarray(outcomes, dtype=float).reshape(-1, 2)
    raw, strains = outcomes[:, 0], outcomes[:, 1]
    eps = problem.min_wall_strain
    margins = counted_margins(raw, strains, eps)
    n = margins.size
    stepout = Probability.of(raw < 0)
    fail = failed(raw, strains, eps)
    speeds = np.where(fail, 0.0, problem.speed_m_s)
    q = np.percentile(margins, [p for _, p in PERCENTILES])
    qs = np.percentile(speeds, [p for _, p in PERCENTILES])
    no_grip = Probability.of(strains <= 0)
    closed = {"no_grip": grip_loss_probability(problem, 0.0)}
    if problem.uncertainty.wall_thickness_sigma_m <= 0:
        closed["below_min_strain"] = grip_loss_probability(problem, grip_threshold(eps))
    return UncertaintyResult(
        samples=n,
        seed=seed,
        method=method,
        nominal_margin_Nm=problem.nominal_margin_Nm(),
        available_torque_Nm=problem.available_torque_Nm,
        speed_nominal_m_s=problem.speed_m_s,
        stepout_probability=stepout.value,
        stepout_ci95=stepout.ci95,
        margin_percentiles_Nm={k: float(v) for (k, _), v in zip(PERCENTILES, q)},
        speed_percentiles_m_s={k: float(v) for (k, _), v in zip(PERCENTILES, qs)},
        margin_mean_Nm=float(margins.mean()),
        margin_std_Nm=float(margins.std(ddof=1)) if n > 1 else 0.0,
        sobol=sobol,
        margins_Nm=margins,
        no_grip_probability=no_grip.value,
        failure=Probability.of(fail),
        stepout=stepout,
        below_min_strain=Probability.of(strains < grip_threshold(eps)),
        no_grip=no_grip,
        min_wall_strain=eps,
        closed_form=closed,
        strains=strains,
    )


def no_grip_probability(problem: MarginProblem) -> float:
    """Probability that a sampled lumen is as wide as the spiral's D' in some tissue set
    (:func:`grip_loss_probability` at strain 0; exact).

    Parameters
    ----------
    problem : MarginProblem
        The design at its operating point and its uncertainty.

    Returns
    -------
    float
        The probability, dimensionless, in [0, 1].
    """
    return grip_loss_probability(problem, 0.0)


def grip_loss_probability(problem: MarginProblem, strain: float) -> float:
    """Probability that a sample stretches some tissue set's wall by less than ``strain``.

    Exact where only the lumen moves the strain (no wall-thickness uncertainty, or
    ``strain = 0``, whose sign does not depend on the wall). Set k's strain is
    (D' − L_k − δ)/(L_k + δ + d_k) with one lumen offset δ for every set, a normal N(0, σ²)
    truncated below at −(1 − floor)·(least nominal lumen) (:func:`perturbed_tissues`); it is
    below ``strain`` when δ > x_k = (D' − L_k − strain·(L_k + d_k))/(1 + strain). So the
    probability is P(δ > min_k x_k) = 1 − (Φ(x/σ) − Φ(lo/σ))/(1 − Φ(lo/σ)).

    Parameters
    ----------
    problem : MarginProblem
        The design at its operating point and its uncertainty.
    strain : float
        The strain threshold, dimensionless (0: contact).

    Returns
    -------
    float
        The probability, dimensionless, in [0, 1].
    """
    import torque_model as tm

    g = ph.contact_geometry(problem.constants)
    d_prime = float(
        tm.equivalent_diameter_m(
            problem.helical_angle_rad, g.body_diameter_m, g.wire_diameter_m, g.starts
        )
    )
    x = min(
        (d_prime - t.lumen_diameter_m - strain * (t.lumen_diameter_m + t.wall_thickness_m))
        / (1.0 + strain)
        for t in problem.tissues
    )
    lumens = [float(t.lumen_diameter_m) for t in problem.tissues]
    sigma = problem.uncertainty.lumen_diameter_sigma_m
    if sigma <= 0:
        return 1.0 if x < 0 or (strain == 0 and x <= 0) else 0.0
    lo = special.ndtr(-(1.0 - _FLOOR) * min(lumens) / sigma)
    cdf = (special.ndtr(x / sigma) - lo) / (1.0 - lo)
    return float(min(max(1.0 - cdf, 0.0), 1.0))


def sobol_indices(
    problem: MarginProblem, base_samples: int = 1 << 12, seed: int = 0
) -> SobolIndices:
    """First-order and total Sobol indices of the margin (SALib: Saltelli 2010, Jansen 1999).

    The latent uniforms are the SALib inputs; the factors of a fitted covariance form one group
    ("fit covariance"), so every group is independent of the others and the indices are
    well defined. ``base_samples`` (a power of two) gives ``base_samples·(groups + 2)`` runs.

    Parameters
    ----------
    problem : MarginProblem
        The design and its uncertainty.
    base_samples : int
        Number of base samples (a power of two).
    seed : int
        Seed of the Saltelli design and the bootstrap.

    Returns
    -------
    SobolIndices
        First-order and total indices, dimensionless.
    """
    from SALib.analyze import sobol as sa_analyze
    from SALib.sample import sobol as sa_sample

    factors = problem.uncertainty.factors()
    if not factors:
        raise InputError("uncertainty", "none", "at least one uncertain input")
    groups = [g for _, g in factors]
    unique = list(dict.fromkeys(groups))
    if len(unique) == 1:  # one input explains everything (if anything moves); SALib needs two
        probe = problem.counted_margins_Nm(
            np.linspace(0.05, 0.95, 9)[:, None] * np.ones(len(factors))
        )
        value = (1.0,) if np.ptp(probe) > 0 else (0.0,)
        return SobolIndices(tuple(unique), value, (0.0,), value, (0.0,), base_samples)
    spec = {
        "num_vars": len(factors),
        "names": [n for n, _ in factors],
        "bounds": [[0.0, 1.0]] * len(factors),
        "groups": groups,
    }
    x = sa_sample.sample(spec, base_samples, calc_second_order=False, seed=seed)
    y = problem.counted_margins_Nm(x)
    if not np.ptp(y) > 0:  # no input moves the margin (no torque required): nothing to share
        zero = (0.0,) * len(unique)
        return SobolIndices(tuple(unique), zero, zero, zero, zero, base_samples)
    # SALib seeds its bootstrap only `if seed:` (seed 0 would draw from the global state, so
    # the confidence intervals would differ run to run); a Generator is always seeded, and for
    # seed > 0 draws exactly what the int would
    rng = np.random.default_rng(seed)
    res = sa_analyze.analyze(spec, y, calc_second_order=False, seed=rng, print_to_console=False)

    def tup(a: Any) -> tuple[float, ...]:
        return tuple(float(v) for v in np.asarray(a).ravel())

    return SobolIndices(
        tuple(unique),
        tup(res["S1"]),
        tup(res["S1_conf"]),
        tup(res["ST"]),
        tup(res["ST_conf"]),
        base_samples,
    )


def run_local(
    problem: MarginProblem, samples: int, seed: int = 0, method: str = "sobol"
) -> np.ndarray:
    """All ``samples`` outcomes in this process, chunk by chunk (what the executors reproduce).

    Parameters
    ----------
    problem : MarginProblem
        The design and its uncertainty.
    samples : int
        Number of samples.
    seed : int
        Seed of the sequence.
    method : str
        Sampling method.

    Returns
    -------
    ndarray, shape (samples, 2)
        Worst-case margin (N·m) and least wall strain (dimensionless) of each sample.
    """
    check_samples(samples)
    return np.concatenate([chunk_outcomes(problem, s, n, seed, method) for s, n in chunks(samples)])


def check_seed(seed: Any, key: str = "--seed") -> int:
    """``seed`` as an int from 0 to :data:`MAX_SEED`, else InputError naming ``key``.

    Parameters
    ----------
    seed : int
        The seed to check.
    key : str
        Name an error gives.

    Returns
    -------
    int
        The seed as a Python int.
    """
    if (
        isinstance(seed, bool)
        or not isinstance(seed, (int, np.integer))
        or not 0 <= seed <= MAX_SEED
    ):
        raise InputError(key, seed, f"a whole number from 0 to {MAX_SEED} (numpy's seed range)")
    return int(seed)


#: Most tissue samples of one study: every sample's margin and speed stay in memory (16 bytes
#: each, ~1 GB here); the step-out probability's sampling error is ~1e-4 already at 2^20.
MAX_SAMPLES = 1 << 26
SAMPLES_WHY = "every sample's margin stays in memory, ~1 GB at the bound"
#: Most Sobol base samples: SALib evaluates base·(groups + 2) points at once (2^16 base samples
#: of ten inputs: ~0.1 GB of inputs), and the indices' intervals shrink only as 1/sqrt(base).
MAX_SOBOL_BASE = 1 << 16
#: Largest seed (numpy's legacy seed range, as optimize.scenario_seed).
MAX_SEED = 2**32 - 1


def check_samples(samples: Any, key: str = "--samples") -> int:
    """``samples`` as an int from 1 to :data:`MAX_SAMPLES`, else InputError naming ``key``.

    Parameters
    ----------
    samples : int
        The number of samples to check.
    key : str
        Name an error gives.

    Returns
    -------
    int
        The number of samples as an int.
    """
    if (
        isinstance(samples, bool)
        or not isinstance(samples, (int, np.integer))
        or not 1 <= samples <= MAX_SAMPLES
    ):
        raise InputError(key, samples, f"a whole number from 1 to {MAX_SAMPLES} ({SAMPLES_WHY})")
    return int(samples)


def closed_form_stepout_probability(problem: MarginProblem) -> float:
    """1 − Φ(ln k*/σ) for scale-only uncertainty of ONE tissue set (independent check).

    The resistive torque is linear in a common factor k on the five constants
    (TissueParameters.scaled) and the thrust torque does not depend on them, so the margin is
    ``m(k) = A − k τ_res − τ_g − τ_thrust`` (τ_g the weight friction, not a tissue constant) and
    vanishes at ``k* = (A − τ_thrust − τ_g)/τ_res``; with
    ``ln k ~ N(0, σ²)``, P(m < 0) = P(k > k*) = 1 − Φ(ln k*/σ).

    Parameters
    ----------
    problem : MarginProblem
        One tissue set with scale-only uncertainty.

    Returns
    -------
    float
        Step-out probability, a probability.
    """
    if len(problem.tissues) != 1 or problem.uncertainty.factors() != [("scale", "scale")]:
        raise InputError("uncertainty", "more than the scale factor", "scale only, one set")
    ((res, thr),) = ph.required_torques_Nm(
        problem.helical_angle_rad,
        problem.frequency_hz,
        problem.constants,
        problem.tissues,
        problem.requirements,
    )
    # the friction of the capsule's weight is not a tissue constant: it does not scale with k
    weight = float(ph.weight_friction_Nm(problem.constants, problem.tissues[0]))
    k_star = (problem.available_torque_Nm - float(thr) - weight) / (float(res) - weight)
    if k_star <= 0:
        return 1.0
    # the normal survival function Φ(-z) as scipy.special.ndtr: scipy.stats costs 0.3 s to import
    return float(special.ndtr(-math.log(k_star) / problem.uncertainty.scale_sigma_log))
