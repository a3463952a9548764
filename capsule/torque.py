"""Magnetic torque on the capsule's magnet, treated as a point dipole in a uniform field.

``tau = m x B``. In a field of amplitude ``B0`` rotating about the capsule axis the magnet
follows with a lag angle ``delta`` behind the field, and the torque it delivers is
``m B0 sin(delta)``; the most it can deliver is ``m B0`` at ``delta = 90°``. A load above that
makes the capsule step out of synchrony (it stalls and jitters instead of turning).
docs/optimisation.md, Margin; any electromagnetism text, e.g. Jackson, *Classical Electrodynamics*,
3rd ed., eq. (5.1) for the torque on a dipole.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from spiralcap.core import backend as bk
from spiralcap.core.checks import finite, guard, nonnegative, positive


@guard(moment_Am2_vec=finite(), field_T_vec=finite())
def magnetic_torque_Nm(moment_Am2_vec: Any, field_T_vec: Any) -> np.ndarray:
    """Torque on a point dipole in a uniform field, ``m x B`` (numpy only).

    Parameters
    ----------
    moment_Am2_vec : array-like, shape (..., 3)
        Dipole moment vector(s), A·m^2.
    field_T_vec : array-like, shape (..., 3)
        Flux density at the dipole, T. Broadcasts against ``moment_Am2_vec``.

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        Torque about the dipole's centre, N·m. Perpendicular to both arguments.

    Notes
    -----
    Exact for a uniform field; for a finite magnet in a non-uniform field the field is taken at
    the magnet's centre (the capsule's magnet is millimetres across, the coils tens of
    centimetres, so the error is of order (magnet size / coil radius)^2).

    Examples
    --------
    A 0.1 A m² moment along x in a 10 mT field along y: τ = m × B, 1 mN m about z:

    >>> import numpy as np
    >>> from capsule import magnetic_torque_Nm
    >>> print(magnetic_torque_Nm(np.array([0.1, 0.0, 0.0]), np.array([0.0, 0.01, 0.0])) * 1e3)
    [0. 0. 1.]
    """
    return np.cross(np.asarray(moment_Am2_vec, dtype=float), np.asarray(field_T_vec, dtype=float))


@guard(moment_Am2=nonnegative(), field_amplitude_T=nonnegative())
def max_synchronous_torque_Nm(moment_Am2: Any, field_amplitude_T: Any) -> Any:
    """Largest torque a rotating field can deliver before step-out, ``m B0``.

    Parameters
    ----------
    moment_Am2 : float, array or CasADi
        Magnitude of the magnet's moment, A·m^2 (moment perpendicular to the rotation axis).
    field_amplitude_T : float, array or CasADi
        Amplitude ``B0`` of the field component rotating in the plane of the moment, T.

    Returns
    -------
    float, array or CasADi
        Torque, N·m.

    Examples
    --------
    >>> from capsule import max_synchronous_torque_Nm
    >>> print(f"{max_synchronous_torque_Nm(0.1, 0.01) * 1e3:.3f} mN m")  # m B0
    1.000 mN m
    """
    return moment_Am2 * field_amplitude_T


@guard(moment_Am2=nonnegative(), field_amplitude_T=nonnegative(), lag_angle_rad=finite())
def synchronous_torque_Nm(moment_Am2: Any, field_amplitude_T: Any, lag_angle_rad: Any) -> Any:
    """Torque delivered at lag angle ``delta`` behind the rotating field, ``m B0 sin(delta)``.

    Parameters
    ----------
    moment_Am2 : float, array or CasADi
        Magnitude of the moment, A·m^2.
    field_amplitude_T : float, array or CasADi
        Rotating-field amplitude, T.
    lag_angle_rad : float, array or CasADi
        Angle between the field and the moment, rad.

    Returns
    -------
    float, array or CasADi
        Torque about the rotation axis, N·m.

    Examples
    --------
    Lagging the field by 30° the magnet gives half its largest torque, m B0 sin 30°:

    >>> import math
    >>> from capsule import synchronous_torque_Nm
    >>> print(f"{synchronous_torque_Nm(0.1, 0.01, math.radians(30.0)) * 1e3:.3f} mN m")
    0.500 mN m
    """
    return moment_Am2 * field_amplitude_T * bk.sin(lag_angle_rad)


@guard(load_torque_Nm=finite(), moment_Am2=positive(), field_amplitude_T=positive())
def lag_angle_rad(load_torque_Nm: Any, moment_Am2: Any, field_amplitude_T: Any) -> Any:
    """Steady lag of the magnet behind the rotating field at a given load, ``asin(T / (m B0))``.

    Parameters
    ----------
    load_torque_Nm : float, array or CasADi
        Resisting torque about the rotation axis that the field must balance, N·m.
    moment_Am2 : float, array or CasADi
        Magnitude of the moment, A·m^2 (> 0).
    field_amplitude_T : float, array or CasADi
        Rotating-field amplitude, T (> 0).

    Returns
    -------
    float, array or CasADi
        Lag angle, rad, in [-pi/2, pi/2] (the stable branch). Where ``|load| > m B0`` there is no
        synchronous solution (step-out) and the result is NaN: silently on the numpy path, and on
        the CasADi path when the expression is evaluated. Optimisers should constrain
        ``m B0 - load`` instead of calling this near step-out.

    Examples
    --------
    The inverse of :func:`synchronous_torque_Nm`: half the largest torque needs a 30° lag:

    >>> import math
    >>> from capsule import lag_angle_rad
    >>> print(f"{math.degrees(lag_angle_rad(0.0005, 0.1, 0.01)):.6f} deg")
    30.000000 deg
    """
    ratio = load_torque_Nm / (moment_Am2 * field_amplitude_T)
    with np.errstate(invalid="ignore"):
        return bk.arcsin(ratio)
