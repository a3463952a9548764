"""Does an identification deserve trust? A fit's own verdict on how well the model follows the data.

:func:`torque_model.identify` always returns the best parameters it found; this module says
whether they mean anything. The verdict ``follows_data`` (``spiralcap fit --json``:
``model_follows_data``) rests on one test of the residual pattern against the noise, and on two
physical facts:

1. **Lack-of-fit F test** (:func:`lack_of_fit`), on the residuals of ln torque at p < 0.01
   (:data:`LACK_OF_FIT_ALPHA`). With replicate points (several rows at one frequency and
   angle), the classical pure-error test (Draper & Smith, *Applied Regression Analysis*, 3rd
   ed., section 2.1): F = (SS_lack / (m - k)) / (SS_pure / (n - m)), m distinct points, k the
   parameters the data fit (:attr:`~torque_model.identification.FitResult.effective_parameters`).
   Without replicates the noise is estimated from an empirical **reference curve**, ln tau
   quadratic in ln f with an intercept per helical angle (linear least squares), and the test
   is F = (SSE_model / (n - k)) / (SSE_ref / (n - p_ref)) against F(n - k, n - p_ref): the model
   does not follow the data when its residual variance significantly exceeds that of a smooth
   curve that can take any monotone or bent shape (a torque rising as f^1.5, falling with f, ...).
   With too few points for either test (n - k or n - p_ref = 0), nothing can be said:
   ``follows_data`` is False and the words say "not tested".
2. **Noise level.** A scatter of the data (the test's noise estimate, or the fit's residual
   standard deviation when untested) above :data:`MAX_RESIDUAL_STD` is beyond what a bench
   repeats (Zhou et al. 2013, Fig. 9 error bars ~5-10 %): no test has power
   at that scatter, so the model is not said to follow.
3. **Direction.** The model's torque can only rise with frequency (I(omega) = sum omega eta
   (1 - exp(-2 pi E/(omega eta))) + 2 pi E3 is increasing in omega), so data whose torque
   falls with frequency (Spearman rho < -0.5 at one angle) cannot be followed at all.

An optimiser that stopped without converging is a problem too (``spiralcap fit`` then exits 3).
Reported without deciding: the fraction of the data's relative spread about the best constant
torque the fit explains, 1 - (s/s0)² (a flat curve is followed yet explains nothing), and the
Wald-Wolfowitz runs of residual signs ordered by frequency.

**Plausibility** (``plausible``, separate): the measured torques against what the built-in
presets predict at the same frequencies, angles and capsule: more than :data:`PLAUSIBLE_FACTOR`
apart suggests the wrong unit (N·m or µN·m given as mN·m) or another capsule; fitted
pinned-down moduli and viscosities more than that factor outside the presets' range are flagged
too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from torque_model.tissue import VISCOELASTIC_FIELDS

__all__ = [
    "LACK_OF_FIT_ALPHA",
    "PLAUSIBLE_FACTOR",
    "VERDICTS",
    "FitQuality",
    "LackOfFit",
    "assess_fit",
    "lack_of_fit",
]

#: The verdicts of :class:`FitQuality`, in words.
VERDICTS = (
    "the model follows these data",
    "the model follows these data, but the values are implausible",
    "the model does not follow these data",
    "too few points to test whether the model follows these data",
)
#: Significance level of the lack-of-fit F test: the model does not follow the data at p below it.
LACK_OF_FIT_ALPHA = 0.01
#: Round-off floor of a residual sum of squares, per point: (1e-12 relative)².
_SSE_FLOOR = 1e-24
#: Residual standard deviation (relative) above which a fit is poor whatever the spread: bench
#: torques repeat to a few per cent (Zhou et al. 2013, Fig. 9 error bars ~5-10 %).
MAX_RESIDUAL_STD = 0.20
#: Torques or constants more than this factor from the presets' are flagged implausible.
PLAUSIBLE_FACTOR = 30.0


@dataclass(frozen=True)
class LackOfFit:
    """The lack-of-fit F test of one fit (module notes, item 1).

    Attributes
    ----------
    test : str
        ``"pure error"`` (replicates), ``"reference curve"`` or ``"none"`` (too few points).
    f_statistic : float
        F, dimensionless (0 when not tested).
    dof_numerator, dof_denominator : int
        Its degrees of freedom, counts.
    p_value : float
        P(F' >= F) under the model, a probability (1 when not tested).
    reference_residual_std : float
        The noise estimate the model is tested against: the pure-error or reference-curve
        residual standard deviation of ln torque, dimensionless (0 when not tested).
    """

    test: str
    f_statistic: float
    dof_numerator: int
    dof_denominator: int
    p_value: float
    reference_residual_std: float

    @property
    def tested(self) -> bool:
        """Whether the data allowed a test at all."""
        return self.test != "none"

    @property
    def passed(self) -> bool:
        """Tested, and no significant lack of fit (p >= :data:`LACK_OF_FIT_ALPHA`)."""
        return self.tested and self.p_value >= LACK_OF_FIT_ALPHA


@dataclass(frozen=True)
class FitQuality:
    """The verdict on one fit.

    Attributes
    ----------
    follows_data : bool
        The model follows the data: converged, the lack-of-fit test passed, the scatter within
        :data:`MAX_RESIDUAL_STD`, the torque not falling with frequency. When False, the fitted
        values must not be read as tissue properties.
    lack_of_fit : LackOfFit
        The lack-of-fit F test.
    plausible : bool
        Torques and fitted constants within :data:`PLAUSIBLE_FACTOR` of the presets'.
    residual_std : float
        s, relative residual standard deviation of the fit (dimensionless).
    constant_model_std : float
        s0, the same for the best constant torque (the data's relative spread).
    explained_fraction : float
        1 - (s/s0)², at most 1 (0 or below: no better than a constant).
    optimizer_converged : bool
        The optimiser's own success flag.
    runs : int
        Runs of equal residual sign, ordered by frequency, count.
    runs_z : float
        Wald-Wolfowitz z of ``runs``, dimensionless (0 when there are too few points or one
        sign only); reported, not part of the verdict (the F test judges the residual pattern).
    frequency_trend : float
        Spearman rank correlation of torque with frequency (within each angle, averaged),
        dimensionless.
    torque_ratio_to_presets : dict[str, float]
        Median measured / preset-predicted torque, per preset, ratio.
    problems : tuple[str, ...]
        Each failed question in words (empty: none).
    verdict : str
        In words: one of :data:`VERDICTS`.
    """

    follows_data: bool
    lack_of_fit: LackOfFit
    plausible: bool
    residual_std: float
    constant_model_std: float
    explained_fraction: float
    optimizer_converged: bool
    runs: int
    runs_z: float
    frequency_trend: float
    torque_ratio_to_presets: dict[str, float]
    problems: tuple[str, ...]
    verdict: str


def _runs(signs: np.ndarray) -> tuple[int, float]:
    n1, n2 = int(np.sum(signs > 0)), int(np.sum(signs <= 0))
    runs = 1 + int(np.sum(signs[1:] != signs[:-1])) if signs.size else 0
    n = n1 + n2
    if n1 == 0 or n2 == 0 or n < 6:
        return runs, 0.0
    mean = 2.0 * n1 * n2 / n + 1.0
    var = 2.0 * n1 * n2 * (2.0 * n1 * n2 - n) / (n * n * (n - 1.0))
    return runs, (runs - mean) / math.sqrt(var) if var > 0 else 0.0


def _spearman(x: np.ndarray, y: np.ndarray) -> float:
    if x.size < 3:
        return 0.0
    rx = np.argsort(np.argsort(x)).astype(float)
    ry = np.argsort(np.argsort(y)).astype(float)
    sx, sy = rx.std(), ry.std()
    return float(np.mean((rx - rx.mean()) * (ry - ry.mean())) / (sx * sy)) if sx and sy else 0.0


def _log_residuals(fit: Any) -> np.ndarray:
    """ln(model) - ln(data) at every point (the relative residual to first order)."""
    return np.log(np.asarray(fit.predicted_Nm, dtype=float)) - np.log(
        np.asarray(fit.torque_Nm, dtype=float)
    )


def _f_test(
    test: str, sse_model: float, dof_model: int, sse_ref: float, dof_ref: int, n: int
) -> LackOfFit:
    from scipy import stats

    floor = _SSE_FLOOR * n
    num, den = max(sse_model, floor) / dof_model, max(sse_ref, floor) / dof_ref
    F = num / den
    p = float(stats.f.sf(F, dof_model, dof_ref))
    return LackOfFit(test, F, dof_model, dof_ref, p, math.sqrt(max(sse_ref, 0.0) / dof_ref))


def lack_of_fit(fit: Any) -> LackOfFit:
    """The lack-of-fit F test of a fit: pure error with replicates, else a reference curve.

    Parameters
    ----------
    fit : FitResult
        The identification (frequencies in Hz, angles in rad, torques in N·m).

    Returns
    -------
    LackOfFit
        ``test == "none"`` when the points leave no degree of freedom for either test.
    """
    f = np.asarray(fit.frequency_hz, dtype=float)
    angle = np.asarray(fit.helical_angle_rad, dtype=float)
    ln_y = np.log(np.asarray(fit.torque_Nm, dtype=float))
    e = _log_residuals(fit)
    n, k = e.size, int(fit.effective_parameters)
    sse = float(e @ e)
    _, group = np.unique(np.stack([angle, f], axis=1), axis=0, return_inverse=True)
    group = np.asarray(group).reshape(-1)
    m = int(group.max()) + 1 if n else 0
    if n > m > k:  # replicates: the classical pure-error test
        means = np.bincount(group, weights=ln_y) / np.bincount(group)
        ss_pure = float(np.sum((ln_y - means[group]) ** 2))
        return _f_test("pure error", max(sse - ss_pure, 0.0), m - k, ss_pure, n - m, n)
    _, by_angle = np.unique(angle, return_inverse=True)
    ln_f = np.log(f)
    X = np.column_stack([np.eye(int(by_angle.max()) + 1)[by_angle], ln_f, ln_f**2])
    coef, *_ = np.linalg.lstsq(X, ln_y, rcond=None)
    p_ref = int(np.linalg.matrix_rank(X))
    if n - p_ref <= 0 or n - k <= 0:
        return LackOfFit("none", 0.0, 0, 0, 1.0, 0.0)
    r_ref = X @ coef - ln_y
    return _f_test("reference curve", sse, n - k, float(r_ref @ r_ref), n - p_ref, n)


def _follow_problems(fit: Any, lof: LackOfFit, s: float, trend: float) -> list[str]:
    """Why the model does not follow the data, in words (empty: it does)."""
    problems: list[str] = []
    if trend < -0.5:
        problems.append(
            f"the torque falls with frequency (rank correlation {trend:.2f}); the model's "
            "torque can only rise with frequency"
        )
    if not lof.tested:
        problems.append(
            "too few points to test the model's shape: the lack-of-fit test needs more points "
            "than fitted parameters and than the reference curve's (an intercept per helical "
            "angle and two)"
        )
    elif not lof.passed:
        problems.append(
            f"lack of fit: the residuals ({100 * s:.3g} %) exceed the noise the {lof.test} "
            f"shows ({100 * lof.reference_residual_std:.3g} %): F = {lof.f_statistic:.3g} on "
            f"({lof.dof_numerator}, {lof.dof_denominator}) degrees of freedom, "
            f"p = {lof.p_value:.2g} < {LACK_OF_FIT_ALPHA:g}"
        )
    noise = lof.reference_residual_std if lof.tested else s
    if noise > MAX_RESIDUAL_STD:
        problems.append(
            f"the data scatter by {100 * noise:.3g} % ({'the ' + lof.test if lof.tested else 'the fit'}"
            f"'s residual std), beyond the {100 * MAX_RESIDUAL_STD:.3g} % a bench repeats: no "
            "test can tell the model's shape at this scatter"
        )
    if not fit.success:
        problems.append(f"the optimiser did not converge ({fit.message.rstrip('.')})")
    return problems


def _plausibility(fit: Any, presets: dict[str, Any] | None) -> tuple[dict[str, float], list[str]]:
    """Median measured / preset torque per preset, and the implausibilities in words."""
    from torque_model.model import resistive_torque_Nm
    from torque_model.presets import PRESET_NAMES, preset

    y = np.asarray(fit.torque_Nm, dtype=float)
    f = np.asarray(fit.frequency_hz, dtype=float)
    angle = np.asarray(fit.helical_angle_rad, dtype=float)
    sets = presets or {name: preset(name) for name in PRESET_NAMES}
    ratios: dict[str, float] = {}
    for name, p in sets.items():
        ref = fit.tissue.replace(**{k: getattr(p, k) for k in VISCOELASTIC_FIELDS})
        pred = np.asarray(resistive_torque_Nm(angle, f, ref, fit.geometry), dtype=float)
        ratios[name] = float(np.median(y / pred))
    problems: list[str] = []
    if not any(1 / PLAUSIBLE_FACTOR <= r <= PLAUSIBLE_FACTOR for r in ratios.values()):
        best = min(ratios.values(), key=lambda r: abs(math.log(r)))
        problems.append(
            f"the torques are {best:.3g} times what the built-in presets give for this capsule "
            "and these frequencies; check the unit (mN·m) and the capsule geometry"
        )
    for k in VISCOELASTIC_FIELDS:
        ref_values = [getattr(p, k) for p in sets.values()]
        lo = min(v for v in ref_values if v > 0) / PLAUSIBLE_FACTOR
        hi = max(ref_values) * PLAUSIBLE_FACTOR
        v = getattr(fit.tissue, k)
        if v > 0 and not lo <= v <= hi and k not in fit.not_pinned_down:
            problems.append(
                f"{k} = {v:.3g} lies outside the presets' range x/÷ {PLAUSIBLE_FACTOR:g}"
            )
    return ratios, problems


def assess_fit(fit: Any, presets: dict[str, Any] | None = None) -> FitQuality:
    """Judge a :class:`~torque_model.identification.FitResult` (see the module notes).

    Parameters
    ----------
    fit : FitResult
        The identification to judge (relative residuals assumed, as :func:`identify`'s default).
    presets : dict[str, TissueParameters], optional
        Reference sets for plausibility; default the built-in presets.

    Returns
    -------
    FitQuality
    """
    y = np.asarray(fit.torque_Nm, dtype=float)
    f = np.asarray(fit.frequency_hz, dtype=float)
    angle = np.asarray(fit.helical_angle_rad, dtype=float)
    model = np.asarray(fit.predicted_Nm, dtype=float)
    n, dof = y.size, max(int(fit.dof), 1)
    rel = (model - y) / y
    s = math.sqrt(float(rel @ rel) / dof)
    c = float(np.sum(1.0 / y) / np.sum(1.0 / y**2))  # best constant under relative residuals
    rel0 = (c - y) / y
    s0 = math.sqrt(float(rel0 @ rel0) / max(n - 1, 1))
    explained = 1.0 - (s / s0) ** 2 if s0 > 0 else 0.0
    order = np.lexsort((f, angle))
    runs, z = _runs(np.sign(rel[order]))
    trends = [_spearman(f[angle == a], y[angle == a]) for a in np.unique(angle)]
    trend = float(np.mean(trends)) if trends else 0.0
    lof = lack_of_fit(fit)
    problems = _follow_problems(fit, lof, s, trend)
    follows = not problems
    ratios, implausible = _plausibility(fit, presets)
    if follows:
        verdict = VERDICTS[1] if implausible else VERDICTS[0]
    else:
        verdict = VERDICTS[3] if not lof.tested and len(problems) == 1 else VERDICTS[2]
    return FitQuality(
        follows_data=follows,
        lack_of_fit=lof,
        plausible=not implausible,
        residual_std=s,
        constant_model_std=s0,
        explained_fraction=explained,
        optimizer_converged=bool(fit.success),
        runs=runs,
        runs_z=z,
        frequency_trend=trend,
        torque_ratio_to_presets=ratios,
        problems=tuple(problems + implausible),
        verdict=verdict,
    )
