"""Stray field and exposure of the operating point (``spiralcap coils``, the report).

The stray field: along each axis, the distance from the coil centre beyond which the largest
|B| over a turn, over every heading, at the operating field falls below 0.5 mT -- the level
ICNIRP 2009 (Health Physics 96(4), static magnetic fields) gives for people with implanted
medical devices such as pacemakers (:func:`coils.stray.fade_distance_m`, the allocation of each
heading at the operating field). The exposure: the rotation frequencies at which the operating
field B0 reaches ICNIRP 2010's occupational and public reference levels
(:func:`optimize.physics.exposure_level_T`, the same tables the limit row uses).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = [
    "IMPLANT_LEVEL_T",
    "PeakFieldPlane",
    "StrayField",
    "exposure_crossing_hz",
    "peak_field_plane",
    "stray_field",
]

#: ICNIRP 2009 (static magnetic fields): keep people with implanted devices below 0.5 mT, T.
IMPLANT_LEVEL_T = 0.5e-3
#: How far out the stray-field search goes, in multiples of the largest half-extent of a pack (the
#: field of air coils falls as a dipole's beyond the windings).
REACH_RADII = 6.0
_AXES = ("x", "y", "z")


@dataclass(frozen=True)
class StrayField:
    """Where the operating point's field fades below :data:`IMPLANT_LEVEL_T`, and exposure.

    Attributes
    ----------
    level_T : float
        The level, T.
    field_amplitude_T : float
        The operating field at the centre, T.
    fade_distance_m : dict of str to float
        Per axis, the larger of the two directions' fade distances, m (``inf``: beyond
        ``reach_m``).
    reach_m : float
        How far out the search went, m.
    exposure_crossing_hz : dict of str to float
        ICNIRP 2010 level (``occupational``, ``public``) -> the rotation frequency above which
        B0 exceeds it, Hz (0: at every frequency; ``inf``: at none).
    """

    level_T: float
    field_amplitude_T: float
    fade_distance_m: dict[str, float]
    reach_m: float
    exposure_crossing_hz: dict[str, float]


def exposure_crossing_hz(field_T: float, kind: str) -> float:
    """The rotation frequency above which ``field_T`` exceeds ICNIRP 2010's ``kind`` level, Hz.

    The level is a / f² below 8 Hz (held at its 1 Hz value below 1 Hz), b / f up to 25 Hz and c
    above (:data:`optimize.physics.ICNIRP2010_LEVELS_T`): it falls with f, so the
    field exceeds it above one frequency.

    Parameters
    ----------
    field_T : float
        Rotating-field amplitude (the rms of a circular rotating field), T.
    kind : str
        ``"occupational"`` or ``"public"``.

    Returns
    -------
    float
        The crossing, Hz: 0 when the field exceeds the level at every frequency, ``inf`` when
        at none.
    """
    from optimize.physics import ICNIRP2010_LEVELS_T

    a, b, c = ICNIRP2010_LEVELS_T[kind]
    if field_T > a:
        return 0.0
    if field_T >= a / 64.0:  # the a / f² branch, 1-8 Hz
        return math.sqrt(a / field_T)
    if field_T >= c:  # the b / f branch, 8-25 Hz
        return b / field_T
    return math.inf


def stray_field(model: Any, field_T: float) -> StrayField:
    """The stray field and exposure of ``model`` driven at ``field_T`` (T) at the centre.

    Parameters
    ----------
    model : optimize.DesignModel
        The design (its coils, calibrated if it carries a calibration, and headings).
    field_T : float
        Operating field amplitude at the centre, T.

    Returns
    -------
    StrayField
        Fade distances along the axes and the ICNIRP 2010 crossing frequencies.
    """
    from coils.stray import allocation_vectors, fade_distance_m

    coils = model.coils
    allocations = [
        allocation_vectors(*coils.rotating_allocation(h, float(field_T))) for h in model.headings
    ]
    # the search reaches past every pack: its half-extent, not a frame's half shortest side
    reach = REACH_RADII * max(max(p.extents_m) for p in coils.pairs)
    fade = {}
    for k, ax in enumerate(_AXES):
        e = np.eye(3)[k]
        fade[ax] = max(
            fade_distance_m(coils.field_matrix, allocations, s * e, IMPLANT_LEVEL_T, reach)
            for s in (1.0, -1.0)
        )
    return StrayField(
        level_T=IMPLANT_LEVEL_T,
        field_amplitude_T=float(field_T),
        fade_distance_m=fade,
        reach_m=reach,
        exposure_crossing_hz={
            kind: exposure_crossing_hz(float(field_T), kind) for kind in ("occupational", "public")
        },
    )


def stray_payload(s: StrayField) -> dict[str, Any]:
    """The JSON block (``stray_field`` of ``spiralcap coils --json``): no inf (one type per
    field), a flag in its place.

    Parameters
    ----------
    s : StrayField
        The stray field.

    Returns
    -------
    dict
        ``level_T``, ``field_amplitude_T``, ``search_reach_m``, ``fade_distance_m`` per axis
        (``<axis>_beyond_reach: true`` in place of inf), ``exposure_crossing_hz`` per level
        (``<level>_never: true`` in place of inf).
    """
    fade: dict[str, Any] = {}
    for ax, d in s.fade_distance_m.items():
        fade.update({ax: d} if math.isfinite(d) else {f"{ax}_beyond_reach": True})
    crossing: dict[str, Any] = {}
    for kind, f in s.exposure_crossing_hz.items():
        crossing.update({kind: f} if math.isfinite(f) else {f"{kind}_never": True})
    return {
        "level_T": s.level_T,
        "standard": "ICNIRP 2009 static fields: 0.5 mT for people with implanted devices",
        "field_amplitude_T": s.field_amplitude_T,
        "search_reach_m": s.reach_m,
        "fade_distance_m": fade,
        "exposure_crossing_hz": crossing,
    }


def stray_words(s: StrayField) -> list[str]:
    """Two lines for ``spiralcap coils``: the fade distances and the exposure crossings.

    Parameters
    ----------
    s : StrayField
        The stray field.

    Returns
    -------
    list of str
        The lines (text).
    """

    def dist(d: float) -> str:
        return f"{d * 1e3:.0f} mm" if math.isfinite(d) else f"beyond {s.reach_m * 1e3:.0f} mm"

    def freq(kind: str) -> str:
        f = s.exposure_crossing_hz[kind]
        if f == 0.0:
            return f"{kind}: above the level at every frequency"
        return f"{kind}: never" if not math.isfinite(f) else f"{kind} above {f:.3g} Hz"

    fades = ", ".join(f"{ax} {dist(d)}" for ax, d in s.fade_distance_m.items())
    return [
        f"stray field: the largest |B| over a turn (every heading, {s.field_amplitude_T * 1e3:.4g}"
        f" mT at the centre) falls below {s.level_T * 1e3:g} mT (ICNIRP 2009, implanted "
        f"devices) beyond {fades} from the centre",
        f"exposure: {s.field_amplitude_T * 1e3:.4g} mT exceeds ICNIRP 2010's reference level "
        f"at rotation frequencies ({freq('occupational')}; {freq('public')})",
    ]


@dataclass(frozen=True)
class PeakFieldPlane:
    """The largest |B| over a turn and every heading on a plane through the centre.

    Attributes
    ----------
    plane : str
        ``"xz"`` or ``"xy"``: the two coordinates of the grid.
    u_m, v_m : ndarray, shape (n,)
        Grid coordinates along the plane's two axes, m.
    peak_T : ndarray, shape (n, n)
        Peak |B| at (v, u) (rows v), T.
    """

    plane: str
    u_m: np.ndarray
    v_m: np.ndarray
    peak_T: np.ndarray


def peak_field_plane(
    model: Any, field_T: float, plane: str, half_width_m: float, points: int = 81
) -> PeakFieldPlane:
    """:class:`PeakFieldPlane` of ``model`` at ``field_T`` on ``plane`` out to ``half_width_m``.

    Parameters
    ----------
    model : optimize.DesignModel
        The design.
    field_T : float
        Operating field at the centre, T.
    plane : str
        ``"xz"`` (y = 0) or ``"xy"`` (z = 0).
    half_width_m : float
        Half the side of the square sampled, m.
    points : int
        Grid points along each side, count.

    Returns
    -------
    PeakFieldPlane
        The grid and the peak field on it, m and T.
    """
    from coils.stray import allocation_vectors, peak_field_T

    coils = model.coils
    allocations = [
        allocation_vectors(*coils.rotating_allocation(h, float(field_T))) for h in model.headings
    ]
    axis = np.linspace(-half_width_m, half_width_m, points)
    uu, vv = np.meshgrid(axis, axis)
    k = {"xz": 2, "xy": 1}[plane]
    pts = np.zeros((uu.size, 3))
    pts[:, 0], pts[:, k] = uu.ravel(), vv.ravel()
    peak = peak_field_T(coils.field_matrix(pts), allocations).reshape(uu.shape)
    return PeakFieldPlane(plane, axis, axis, peak)
