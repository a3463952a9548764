"""Coil currents, drive voltages and centre field for a sequence of capsule headings.

Each heading n_i is held for ``dwell_s`` with a field of amplitude B0 turning right-handedly
about it at frequency f, B(t) = B0 (u cos ωt + v sin ωt) with (u, v, n) a right-handed frame
(:func:`coils.rotating.heading_frame` for the first heading) and ω t one continuous phase.
Between headings the whole frame is turned, during the first ``ramp_s`` of the next dwell,
about n_{i-1} x n_i by the angle between them times the quintic smooth step
s(τ) = 10τ³ - 15τ⁴ + 6τ⁵ (zero first and second derivative at both ends, so currents and
voltages stay continuous). Currents I = G⁻¹ (B - b0) with G the field matrix at the centre
(calibrated coils: the calibrated actuation matrix) and b0 a background the coils cancel
(zero unless given); voltages V = R I + L dI/dt with each pair's series resistance and
inductance (orthogonal pairs have no mutual inductance) and dI/dt = G⁻¹ dB/dt from the analytic derivative
dB/dt = B0 [Ω x (u cos ωt + v sin ωt) + ω (v cos ωt - u sin ωt)], Ω the frame's angular velocity.
No I/O; numpy only (this is a post-processing of an operating point, not optimised).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from coils.rotating import heading_frame

__all__ = ["LimitSample", "WaveformCheck", "Waveforms", "check_waveforms", "heading_waveforms"]


@dataclass(frozen=True)
class Waveforms:
    """Sampled waveforms (SI): ``time_s`` (n,), ``heading_index`` (n,), (n, 3) arrays.

    Attributes
    ----------
    time_s : ndarray, shape (n,)
        Sample times, s.
    heading_index : ndarray of int, shape (n,)
        Index of the heading each sample belongs to.
    current_A : ndarray, shape (n, 3)
        Current of each pair, A.
    voltage_V : ndarray, shape (n, 3)
        Drive voltage of each pair, R I + L dI/dt, V.
    field_T : ndarray, shape (n, 3)
        Centre field, T.
    headings : ndarray, shape (h, 3)
        Unit rotation axes, dimensionless.
    resistance_ohm : ndarray, shape (3,)
        Series resistance of each pair, Ω.
    inductance_H : ndarray, shape (3,)
        Series inductance of each pair, H.
    amplitude_T : float
        Field amplitude B0, T.
    frequency_hz : float
        Rotation frequency, Hz.
    dwell_s : float
        Time each heading is held, s.
    ramp_s : float
        Duration of each change of rotation plane, s.
    """

    time_s: np.ndarray
    heading_index: np.ndarray
    current_A: np.ndarray
    voltage_V: np.ndarray
    field_T: np.ndarray
    headings: np.ndarray
    resistance_ohm: np.ndarray
    inductance_H: np.ndarray
    amplitude_T: float
    frequency_hz: float
    dwell_s: float
    ramp_s: float


def _smooth_step(tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    t = np.clip(tau, 0.0, 1.0)
    return t**3 * (10.0 - 15.0 * t + 6.0 * t * t), 30.0 * t * t * (1.0 - t) ** 2


def _rotate(x: np.ndarray, axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rodrigues: rotate vectors x (n, 3) about unit ``axis`` by ``angle`` (n,)."""
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    return x * c + np.cross(axis, x) * s + np.outer(x @ axis, axis) * (1.0 - c)


def heading_waveforms(
    field_matrix_T_per_A: np.ndarray,
    resistance_ohm: np.ndarray,
    inductance_H: np.ndarray,
    headings: np.ndarray,
    *,
    amplitude_T: float,
    frequency_hz: float,
    dwell_s: float,
    ramp_s: float,
    samples_per_period: int = 200,
    background_T: np.ndarray | None = None,
) -> Waveforms:
    """Sample the three currents, voltages and the centre field over the heading sequence.

    Parameters
    ----------
    field_matrix_T_per_A : ndarray, shape (3, 3)
        G with B = G I at the centre, T/A.
    resistance_ohm, inductance_H : array_like, shape (3,)
        Series resistance (Ω) and inductance (H) of each pair.
    headings : array_like, shape (h, 3)
        Rotation axes, any non-zero length, dimensionless.
    amplitude_T : float
        Field amplitude B0, T.
    frequency_hz : float
        Rotation frequency, Hz.
    dwell_s : float
        Time each heading is held (the change of plane included), s.
    ramp_s : float
        Duration of each change of rotation plane, 0 < ramp <= dwell, s.
    samples_per_period : int
        Number of samples per rotation period (also at least 200 per ramp).
    background_T : array_like, shape (3,), optional
        A constant background field the coils cancel (a calibration's b0), T: the currents
        then make B(t) - b0, so that the field in the room, coils plus background, is B(t).

    Returns
    -------
    Waveforms
        The sampled currents (A), voltages (V) and centre field (T) against time (s).
    """
    frames = []
    n0, u0, v0 = heading_frame(np.asarray(headings[0], dtype=float))
    frames.append((n0, u0, v0))
    turns = [(np.zeros(3), 0.0)]
    for h in headings[1:]:
        n_prev, u_prev, v_prev = frames[-1]
        n_new = heading_frame(np.asarray(h, dtype=float))[0]
        cross = np.cross(n_prev, n_new)
        angle = float(np.arctan2(np.linalg.norm(cross), n_prev @ n_new))
        axis = cross / np.linalg.norm(cross) if np.linalg.norm(cross) > 1e-12 else u_prev
        one = np.array([angle])
        frames.append(tuple(_rotate(x[None, :], axis, one)[0] for x in (n_prev, u_prev, v_prev)))
        turns.append((axis, angle))
    count = len(frames)
    dt = min(1.0 / (frequency_hz * samples_per_period), ramp_s / 200.0)
    n = int(np.ceil(count * dwell_s / dt)) + 1
    t = np.linspace(0.0, count * dwell_s, n)
    seg = np.minimum((t // dwell_s).astype(int), count - 1)
    local = t - seg * dwell_s
    omega = 2.0 * np.pi * frequency_hz
    cos, sin = np.cos(omega * t)[:, None], np.sin(omega * t)[:, None]
    field = np.empty((n, 3))
    dfield = np.empty((n, 3))
    for i in range(count):
        sel = seg == i
        n_prev, u_prev, v_prev = frames[i - 1] if i > 0 else frames[0]
        axis, angle = turns[i]
        s, ds = _smooth_step(local[sel] / ramp_s)
        u = _rotate(np.broadcast_to(u_prev, (sel.sum(), 3)), axis, angle * s)
        v = _rotate(np.broadcast_to(v_prev, (sel.sum(), 3)), axis, angle * s)
        if i == 0:
            u, v = np.broadcast_to(u0, u.shape), np.broadcast_to(v0, v.shape)
            ds = np.zeros_like(ds)
        rate = (angle * ds / ramp_s)[:, None] * axis[None, :]  # Ω, rad/s
        c, sn = cos[sel], sin[sel]
        b = u * c + v * sn
        field[sel] = amplitude_T * b
        dfield[sel] = amplitude_T * (np.cross(rate, b) + omega * (v * c - u * sn))
    g_inv = np.linalg.inv(field_matrix_T_per_A)
    offset = np.zeros(3) if background_T is None else np.asarray(background_T, dtype=float)
    current = (field - offset) @ g_inv.T
    dcurrent = dfield @ g_inv.T
    r, ind = np.asarray(resistance_ohm, float), np.asarray(inductance_H, float)
    return Waveforms(
        time_s=t,
        heading_index=seg,
        current_A=current,
        voltage_V=current * r + dcurrent * ind,
        field_T=field,
        headings=np.array([f[0] for f in frames]),
        resistance_ohm=r,
        inductance_H=ind,
        amplitude_T=float(amplitude_T),
        frequency_hz=float(frequency_hz),
        dwell_s=float(dwell_s),
        ramp_s=float(ramp_s),
    )


@dataclass(frozen=True)
class LimitSample:
    """The sample where one quantity comes closest to (or goes furthest past) its limit.

    Attributes
    ----------
    quantity : str
        ``"current"`` or ``"voltage"``.
    axis : str
        ``"x"``, ``"y"`` or ``"z"``.
    time_s : float
        Time of the sample, s.
    heading_index : int
        Index of the heading it belongs to.
    value : float
        The sample's current (A) or voltage (V), as ``quantity`` says.
    allowed : float
        The limit, in the unit of ``value`` (A or V).
    """

    quantity: str  # "current" or "voltage"
    axis: str
    time_s: float
    heading_index: int
    value: float
    allowed: float

    @property
    def utilisation(self) -> float:
        """|value| / allowed, dimensionless (a ratio)."""
        return abs(self.value) / self.allowed


@dataclass(frozen=True)
class WaveformCheck:
    """Per heading, the sample that binds most; ``exceeded``: first violation per quantity-axis.

    Attributes
    ----------
    binding : tuple of LimitSample
        Per heading, the sample closest to (or furthest past) its limit.
    exceeded : tuple of LimitSample
        The first violation of each quantity and axis, in time order (empty: none).
    """

    binding: tuple[LimitSample, ...]
    exceeded: tuple[LimitSample, ...]

    @property
    def ok(self) -> bool:
        """No sample exceeds a limit."""
        return not self.exceeded


def check_waveforms(w: Waveforms, current_limit_A: Any, voltage_limit_V: Any) -> WaveformCheck:
    """Check every sample's |I_k| and |V_k| against the limits (switching transients included).

    Parameters
    ----------
    w : Waveforms
        The sampled waveforms.
    current_limit_A : float or sequence of 3 floats
        Allowed |I| of each pair (one for all, or each pair's own amplifier channel), A.
    voltage_limit_V : float or sequence of 3 floats
        Allowed |V| of each pair (one for all, or each pair's own), V.

    Returns
    -------
    WaveformCheck
        Binding samples and violations.
    """
    binding: list[LimitSample] = []
    exceeded: list[LimitSample] = []
    series = tuple(
        (name, data, np.broadcast_to(np.asarray(lim, dtype=float), (3,)))
        for name, data, lim in (
            ("current", w.current_A, current_limit_A),
            ("voltage", w.voltage_V, voltage_limit_V),
        )
    )
    for i in range(len(w.headings)):
        best: LimitSample | None = None
        for name, data, lim in series:
            sel = np.nonzero(w.heading_index == i)[0]
            util = np.abs(data[sel]) / lim
            flat = np.unravel_index(int(np.argmax(util)), util.shape)
            j, k = int(flat[0]), int(flat[1])
            cand = LimitSample(
                name, "xyz"[k], float(w.time_s[sel[j]]), i, float(data[sel[j], k]), float(lim[k])
            )
            if best is None or cand.utilisation > best.utilisation:
                best = cand
        if best is not None:
            binding.append(best)
    for name, data, lim in series:
        for k in range(3):
            over = np.nonzero(np.abs(data[:, k]) > lim[k])[0]
            if over.size:
                j = int(over[0])
                exceeded.append(
                    LimitSample(
                        name,
                        "xyz"[k],
                        float(w.time_s[j]),
                        int(w.heading_index[j]),
                        float(data[j, k]),
                        float(lim[k]),
                    )
                )
    exceeded.sort(key=lambda s: s.time_s)
    return WaveformCheck(tuple(binding), tuple(exceeded))
