"""Does an identification deserve trust? A fit's own verdict on how well the model follows the data.

:func:`torque_model.identify` always returns the best parameters it found; this module says
whether they mean anything. Four independent questions, each answered from the
:class:`~torque_model.identification.FitResult` alone:

1. **Fit against spread.** The residual standard deviation s (relative residuals) against the
   spread of the data about the best *constant* torque, s0 (the same relative residuals, one
   parameter). ``explained = 1 - (s/s0)²`` is a relative-residual R²
   (Draper & Smith, *Applied Regression Analysis*, 3rd ed., section 1.4). A model that
   follows the data explains most of its spread and leaves s at the noise level.
2. **Optimiser termination.** scipy's ``least_squares`` success flag: a fit stopped by the
   evaluation budget is not a minimum.
3. **Systematic residuals.** Residual signs ordered by frequency: too few runs of equal sign
   (Wald-Wolfowitz runs test, z < -2, about a 2.3 % one-sided level) means the curve bends
   differently from the data. And the model's torque can only rise with frequency
   (I(omega) = sum omega eta (1 - exp(-2 pi E/(omega eta))) + 2 pi E3 is increasing in
   omega), so data whose torque falls with frequency (Spearman rho < -0.5 at one angle) cannot
   be followed at all.
4. **Plausibility.** The measured torques against what the built-in presets predict at the
   same frequencies, angles and capsule: more than :data:`PLAUSIBLE_FACTOR` apart suggests the
   wrong unit (N·m or µN·m given as mN·m) or another capsule; fitted moduli and viscosities more
   than that factor outside the presets' range are flagged too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from torque_model.tissue import VISCOELASTIC_FIELDS

__all__ = ["PLAUSIBLE_FACTOR", "FitQuality", "assess_fit"]

#: A fit explaining less than this fraction of the data's relative spread does not follow it.
MIN_EXPLAINED = 0.75
#: Residual standard deviation (relative) above which a fit is poor whatever the spread: bench
#: torques repeat to a few per cent (Zhou et al. 2013, Fig. 9 error bars ~5-10 %).
MAX_RESIDUAL_STD = 0.20
#: Runs-test z below which residual signs are judged systematic.
RUNS_Z_LIMIT = -2.0
#: Torques or constants more than this factor from the presets' are flagged implausible.
PLAUSIBLE_FACTOR = 30.0


@dataclass(frozen=True)
class FitQuality:
    """The verdict on one fit.

    Attributes
    ----------
    follows_data : bool
        The model follows the data: fit against spread, termination and residual pattern all
        pass. When False, the fitted values must not be read as tissue properties.
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
        sign only).
    frequency_trend : float
        Spearman rank correlation of torque with frequency (within each angle, averaged),
        dimensionless.
    torque_ratio_to_presets : dict[str, float]
        Median measured / preset-predicted torque, per preset, ratio.
    problems : tuple[str, ...]
        Each failed question in words (empty: none).
    """

    follows_data: bool
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
    from torque_model.model import resistive_torque_Nm
    from torque_model.presets import PRESET_NAMES, preset

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

    problems: list[str] = []
    if trend < -0.5:
        problems.append(
            f"the torque falls with frequency (rank correlation {trend:.2f}); the model's "
            "torque can only rise with frequency"
        )
    if s > MAX_RESIDUAL_STD or explained < MIN_EXPLAINED:
        problems.append(
            f"residual std {100 * s:.3g} % against a spread of {100 * s0:.3g} % about a "
            f"constant torque ({100 * max(explained, 0.0):.3g} % of it explained)"
        )
    if not fit.success:
        problems.append(f"the optimiser did not converge ({fit.message.rstrip('.')})")
    if z < RUNS_Z_LIMIT:
        problems.append(
            f"systematic residuals: {runs} runs of one sign over {n} points (runs-test z = {z:.2f})"
        )
    follows = not problems

    sets = presets or {name: preset(name) for name in PRESET_NAMES}
    base = fit.tissue
    ratios: dict[str, float] = {}
    for name, p in sets.items():
        ref = base.replace(**{k: getattr(p, k) for k in VISCOELASTIC_FIELDS})
        pred = np.asarray(resistive_torque_Nm(angle, f, ref, fit.geometry), dtype=float)
        ratios[name] = float(np.median(y / pred))
    plausible = True
    if not any(1 / PLAUSIBLE_FACTOR <= r <= PLAUSIBLE_FACTOR for r in ratios.values()):
        plausible = False
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
            plausible = False
            problems.append(
                f"{k} = {v:.3g} lies outside the presets' range x/÷ {PLAUSIBLE_FACTOR:g}"
            )
    return FitQuality(
        follows_data=follows,
        plausible=plausible,
        residual_std=s,
        constant_model_std=s0,
        explained_fraction=explained,
        optimizer_converged=bool(fit.success),
        runs=runs,
        runs_z=z,
        frequency_trend=trend,
        torque_ratio_to_presets=ratios,
        problems=tuple(problems),
    )
