"""Conduction in a rectangular winding-pack section cooled by h on all four faces (backend-generic).

The section |x| <= a, |y| <= b (a the smaller half-side) with conductivity k, uniform
volumetric heat q(t) and Robin faces -k ∂θ/∂n = h (θ - θ_sink). Every function is written once
against :mod:`spiralcap.core.backend` with a fixed number of operations (no branch on values), so the
NLP differentiates it and numpy and CasADi agree to rounding.

Eigenvalues. β_m tan β_m = Bi = h a / k, β_m in (mπ, mπ + π/2), by Newton's method on
β - mπ - atan(Bi/β) (increasing, concave) from mπ + atan(Bi/(mπ)) (m >= 1) or atan(sqrt Bi)
(m = 0); 5 fixed steps reach 1e-13 for 1e-4 <= Bi <= 1e4 (tests).

Steady state (:func:`robin_statics`). The exact solution as a single series (Carslaw &
Jaeger, *Conduction of Heat in Solids*, 2nd ed., §6.3 with Robin faces): the slab solution
in x minus Σ_m s_m cos(μ_m x) cosh(μ_m y)/D_m, μ_m = β_m/a, s_m = N_m/μ_m²,
N_m = 2 sin β_m/(β_m + sin β_m cos β_m), D_m = cosh(μ_m b) + (β_m/Bi) sinh(μ_m b); the terms
fall as e^(-μ_m b) with b >= a, 3 terms are exact to ~1e-7.

Transient (:func:`robin_transient`). Product modes cos(μ_m x) cos(ν_n y) (the symmetric 3 x 3
of them), each an exact exponential for a constant source, plus one lumped mode per reported
quantity carrying the rest of the steady response with the rate of the slowest mode left out
(exact at t = 0 and at steady state; the mode-acceleration method). The source follows the
mean temperature (copper resistance linear in T): integrated by the exponential
Runge-Kutta scheme ETD2RK (Cox & Matthews, J. Comput. Phys. 176:430, 2002) in 24 equal steps,
which keeps the steady state exactly. A uniform step of the sink temperature (radiation from
other packs) is superposed exactly the same way.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from spiralcap.core import backend as bk

__all__ = ["RobinStatics", "RobinTransient", "eigenvalues", "robin_statics", "robin_transient"]


_NEWTON = 5
_STATIC_TERMS = 3
_MODES = 3
_STEPS = 24


def eigenvalues(biot: Any, count: int) -> list[Any]:
    """The first ``count`` roots β_m of β tan β = Bi (backend-generic).

    Parameters
    ----------
    biot : float or CasADi
        Biot number Bi = h a / k, dimensionless.
    count : int
        Number of roots wanted, count.

    Returns
    -------
    list of float or CasADi
        β_0 < β_1 < ..., dimensionless (β_m in (mπ, mπ + π/2)).
    """
    out = []
    for m in range(count):
        base = m * bk.pi
        beta = bk.arctan(bk.sqrt(biot)) if m == 0 else base + bk.arctan(biot / base)
        for _ in range(_NEWTON):
            g = beta - base - bk.arctan(biot / beta)
            dg = 1.0 + biot / (beta * beta + biot * biot)
            beta = beta - g / dg
        out.append(beta)
    return out


def _projection(beta: Any) -> Any:
    """Coefficient of cos(β x/a) in the expansion of 1 on [0, a]."""
    return 2.0 * bk.sin(beta) / (beta + bk.sin(beta) * bk.cos(beta))


@dataclass(frozen=True)
class RobinStatics:
    """Steady rises above the sink per unit q'''/k (m²): centre, mean, mean face, hottest face.

    Attributes
    ----------
    centre, mean, surface_mean, surface_max : float or CasADi
        Steady rise above the sink divided by q'''/k at the centre, over the section, over the
        faces and at the hottest face point, m² (multiply by q'''/k in K/m² for K).
    """

    centre: Any
    mean: Any
    surface_mean: Any
    surface_max: Any


def _halves(width_m: Any, depth_m: Any) -> tuple[Any, Any]:
    return 0.5 * bk.fmin(width_m, depth_m), 0.5 * bk.fmax(width_m, depth_m)


def _statics(width_m: Any, depth_m: Any, h_W_m2K: Any, k_W_mK: Any) -> tuple[Any, ...]:
    """Steady (centre, mean, mean face, long-face midpoint, short-face midpoint) per q/k."""
    a, b = _halves(width_m, depth_m)
    bi = h_W_m2K * a / k_W_mK
    film = a * a / bi
    centre = 0.5 * a * a + film
    mean = a * a / 3.0 + film
    face_a = film  # midpoint of a long face (x = a)
    face_b = centre  # midpoint of a short face (y = b)
    for beta in eigenvalues(bi, _STATIC_TERMS):
        mu = beta / a
        s = _projection(beta) / (mu * mu)
        z = mu * b
        e = bk.exp(-z)
        th = (1.0 - e * e) / (1.0 + e * e)
        sech = 2.0 * e / (1.0 + e * e)
        inv = 1.0 / (1.0 + beta / bi * th)
        centre = centre - s * sech * inv
        face_a = face_a - s * bk.cos(beta) * sech * inv
        face_b = face_b - s * inv
        mean = mean - s * (bk.sin(beta) / beta) * th / z * inv
    return centre, mean, a * a * b / (bi * (a + b)), face_a, face_b


def robin_statics(width_m: Any, depth_m: Any, h_W_m2K: Any, k_W_mK: Any) -> RobinStatics:
    """Exact steady rises of the w x d section (see the module notes), times q/k.

    Parameters
    ----------
    width_m, depth_m : float or CasADi
        Axial width and radial depth of the section, m.
    h_W_m2K : float or CasADi
        Heat transfer coefficient on all four faces, W/(m²·K).
    k_W_mK : float or CasADi
        Effective conductivity of the pack, W/(m·K).

    Returns
    -------
    RobinStatics
        The steady rises per unit q'''/k, m².
    """
    centre, mean, surface_mean, face_a, face_b = _statics(width_m, depth_m, h_W_m2K, k_W_mK)
    return RobinStatics(centre, mean, surface_mean, bk.fmax(face_a, face_b))


@dataclass(frozen=True)
class RobinTransient:
    """Rises above ambient at time t (K): centre, mean, mean face and hottest face point.

    Attributes
    ----------
    centre, mean, surface_mean, surface_max : float or CasADi
        Rise above ambient at the centre, over the section, over the faces and at the hottest
        face point, K.
    """

    centre: Any
    mean: Any
    surface_mean: Any
    surface_max: Any


def _phi(z: Any) -> tuple[Any, Any]:
    """(e^z - 1)/z and (e^z - 1 - z)/z² for z <= 0, continuous through z = 0."""
    small = bk.abs(z) < 1e-4
    zs = bk.where(small, -1.0, z)
    em1 = bk.exp(zs) - 1.0
    phi1 = bk.where(small, 1.0 + z / 2.0 + z * z / 6.0, em1 / zs)
    phi2 = bk.where(small, 0.5 + z / 6.0 + z * z / 24.0, (em1 - zs) / (zs * zs))
    return phi1, phi2


def robin_transient(
    width_m: Any,
    depth_m: Any,
    h_W_m2K: Any,
    k_W_mK: Any,
    heat_capacity_J_m3K: Any,
    source_W_m3: Any,
    source_slope_W_m3K: Any,
    sink_rise_K: Any,
    time_s: Any,
) -> RobinTransient:
    """Heating of the section from ambient (θ = 0) for ``time_s`` seconds.

    The source is q = ``source_W_m3`` + ``source_slope_W_m3K`` · (mean rise); the faces see a
    sink ``sink_rise_K`` above ambient from t = 0. Temperatures are rises above ambient.

    Parameters
    ----------
    width_m, depth_m : float or CasADi
        Axial width and radial depth of the section, m.
    h_W_m2K : float or CasADi
        Heat transfer coefficient on all four faces, W/(m²·K).
    k_W_mK : float or CasADi
        Effective conductivity of the pack, W/(m·K).
    heat_capacity_J_m3K : float or CasADi
        Volumetric heat capacity ρ c of the pack, J/(m³·K).
    source_W_m3 : float or CasADi
        Volumetric heat at ambient temperature, W/m³.
    source_slope_W_m3K : float or CasADi
        Growth of the volumetric heat per kelvin of mean rise (copper resistance), W/(m³·K).
    sink_rise_K : float or CasADi
        Step of the sink temperature above ambient from t = 0, K.
    time_s : float or CasADi
        Heating time, s.

    Returns
    -------
    RobinTransient
        The rises above ambient at ``time_s``, K.
    """
    a, b = _halves(width_m, depth_m)
    bi_a, bi_b = h_W_m2K * a / k_W_mK, h_W_m2K * b / k_W_mK
    diff = k_W_mK / heat_capacity_J_m3K
    betas, gammas = eigenvalues(bi_a, _MODES + 1), eigenvalues(bi_b, _MODES)
    # per mode: rate λ, source gain N/ρc, and its value in each observable
    rates, gains, obs = [], [], []
    for m in range(_MODES):
        bm = betas[m]
        for n in range(_MODES):
            gn = gammas[n]
            lam = diff * ((bm / a) ** 2 + (gn / b) ** 2)
            nmn = _projection(bm) * _projection(gn)
            mean_m, mean_n = bk.sin(bm) / bm, bk.sin(gn) / gn
            rates.append(lam)
            gains.append(1.0 / heat_capacity_J_m3K)
            obs.append(
                (
                    nmn,
                    nmn * mean_m * mean_n,
                    nmn * (b * bk.cos(bm) * mean_n + a * bk.cos(gn) * mean_m) / (a + b),
                    nmn * bk.cos(bm),
                    nmn * bk.cos(gn),
                )
            )
    slow_left_out = diff * ((betas[_MODES] / a) ** 2 + (gammas[0] / b) ** 2)
    # exact steady rise per unit q (q/k times the statics) and per unit sink (1)
    exact = _statics(width_m, depth_m, h_W_m2K, k_W_mK)
    residual = []
    uniform_left = []
    for i in range(5):
        kept = 0.0
        kept_uniform = 0.0
        for j in range(len(rates)):
            kept = kept + obs[j][i] / (k_W_mK * (rates[j] / diff))
            kept_uniform = kept_uniform + obs[j][i]
        residual.append(exact[i] / k_W_mK - kept)
        uniform_left.append(1.0 - kept_uniform)

    def sink_part(t: Any, i: int) -> Any:
        """Response of observable i to a unit sink step: 1 - Σ N O e^(-λ t) (all modes)."""
        left = 0.0
        for j in range(len(rates)):
            left = left + obs[j][i] * bk.exp(-rates[j] * t)
        return 1.0 - left - uniform_left[i] * bk.exp(-slow_left_out * t)

    dt = time_s / _STEPS
    coef = []
    for lam in [*rates, slow_left_out]:
        z = -lam * dt
        p1, p2 = _phi(z)
        coef.append((bk.exp(z), p1 * dt, p2 * dt))
    nmodes = len(rates)

    def mean_rise(c: list[Any], r: list[Any], t: Any) -> Any:
        out = r[1] + sink_rise_K * sink_part(t, 1)
        for j in range(nmodes):
            out = out + obs[j][1] * c[j]
        return out

    def source(c: list[Any], r: list[Any], t: Any) -> Any:
        # beyond thermal runaway the feedback would overflow: bounded at a 1e5 K mean rise
        return source_W_m3 + source_slope_W_m3K * bk.fmin(mean_rise(c, r, t), 1e5)

    c = [0.0 * time_s for _ in range(nmodes)]
    r = [0.0 * time_s for _ in range(5)]  # lumped rest per observable: dr/dt = λ (R q - r)
    t = 0.0 * time_s
    for _ in range(_STEPS):
        q0 = source(c, r, t)
        ca = [coef[j][0] * c[j] + coef[j][1] * gains[j] * q0 for j in range(nmodes)]
        e, p1, p2 = coef[nmodes]
        ra = [e * r[i] + p1 * slow_left_out * residual[i] * q0 for i in range(5)]
        q1 = source(ca, ra, t + dt)
        c = [ca[j] + coef[j][2] * gains[j] * (q1 - q0) for j in range(nmodes)]
        r = [ra[i] + p2 * slow_left_out * residual[i] * (q1 - q0) for i in range(5)]
        t = t + dt
    vals = []
    for i in range(5):
        v = r[i] + sink_rise_K * sink_part(time_s, i)
        for j in range(nmodes):
            v = v + obs[j][i] * c[j]
        vals.append(v)
    return RobinTransient(vals[0], vals[1], vals[2], bk.fmax(vals[3], vals[4]))
