"""Magnet moment, magnetic torque (checked against magpylib.getFT), propulsion relations."""

from __future__ import annotations

import math

import magpylib as magpy
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import capsule
from spiralcap.core.constants import MU0_T_m_per_A
from spiralcap.core.errors import InputError


def test_moment_is_remanence_times_volume_over_mu0() -> None:
    m = capsule.Magnet(6e-3, 10e-3, 1.345)
    volume = math.pi * 3e-3**2 * 10e-3
    assert m.volume_m3 == pytest.approx(volume, rel=1e-15), "pi r^2 l by hand, rel 1e-15"
    assert m.moment_Am2 == pytest.approx(1.345 * volume / MU0_T_m_per_A, rel=1e-15), (
        "m = B_r V / mu0 (docs/optimisation.md, Margin), rel 1e-15"
    )
    ref = magpy.magnet.Cylinder(polarization=(1.345, 0, 0), dimension=(6e-3, 10e-3))
    assert m.moment_Am2 == pytest.approx(np.linalg.norm(ref.dipole_moment), rel=1e-8), (
        "magpylib Cylinder.dipole_moment (its own mu0 = 4 pi 1e-7), rel 1e-8"
    )
    ring = capsule.Magnet(6e-3, 10e-3, 1.345, inner_diameter_m=2e-3)
    ref_ring = magpy.magnet.CylinderSegment(
        polarization=(1.345, 0, 0), dimension=(1e-3, 3e-3, 10e-3, 0, 360)
    )
    assert ring.shape == "ring" and m.shape == "cylinder"
    assert ring.moment_Am2 == pytest.approx(np.linalg.norm(ref_ring.dipole_moment), rel=1e-8), (
        "magpylib CylinderSegment.dipole_moment for a 6/2 x 10 mm ring, rel 1e-8"
    )


def test_grades() -> None:
    assert list(capsule.GRADE_REMANENCE_T) == ["N35", "N42", "N45", "N48", "N52"]
    values = list(capsule.GRADE_REMANENCE_T.values())
    assert values == sorted(values), "higher grade, higher B_r (grade tables), exact"
    for g, (lo, hi) in capsule.GRADE_REMANENCE_RANGE_T.items():
        assert lo <= capsule.remanence_for_grade(g) <= hi, f"{g} nominal inside its band"
        # (BH)max ~ B_r^2 / (4 mu0) for an ideal magnet: the grade number in MGOe is about it.
        bh_mgoe = capsule.remanence_for_grade(g) ** 2 / (4 * MU0_T_m_per_A) / 7957.747
        assert bh_mgoe == pytest.approx(float(g[1:]), rel=0.08), (
            f"{g}: B_r^2/(4 mu0) vs grade number in MGOe (ideal-magnet bound), rel 8 %"
        )
    assert capsule.remanence_for_grade("n52") == capsule.GRADE_REMANENCE_T["N52"]
    with pytest.raises(InputError):
        capsule.remanence_for_grade("N99")


@pytest.mark.parametrize(
    "kwargs",
    [
        {"diameter_m": 0.0, "length_m": 1e-2, "remanence_T": 1.3},
        {"diameter_m": 6e-3, "length_m": -1e-2, "remanence_T": 1.3},
        {"diameter_m": 6e-3, "length_m": 1e-2, "remanence_T": 0.0},
        {"diameter_m": 6e-3, "length_m": 1e-2, "remanence_T": 1.3, "inner_diameter_m": 6e-3},
    ],
)
def test_magnet_rejects_bad_sizes(kwargs: dict) -> None:
    with pytest.raises(InputError):
        capsule.Magnet(**kwargs)


def _helmholtz_x(radius_m: float = 0.3, current_A: float = 3000.0) -> list:
    """A Helmholtz pair with its axis along x: uniform field at the centre (magpylib Circle)."""
    rot = Rotation.from_rotvec([0.0, math.pi / 2, 0.0])  # loop normal z -> x
    return [
        magpy.current.Circle(
            diameter=2 * radius_m, current=current_A, position=(x, 0.0, 0.0), orientation=rot
        )
        for x in (-radius_m / 2, radius_m / 2)
    ]


#: Cases for the getFT comparison. Measured with magpylib 6.1 (meshing 200/400):
#: |m x B - getFT| / |getFT| = 6e-10 to 2e-8 at the centre, 1.4e-6 (cylinder) and 4.8e-6
#: (ring) 5 cm off-centre, where the field varies across the magnet; |B| ~ 9.0 mT.
GETFT_CASES = [
    # (magnet, position (m), moment direction)
    ("cylinder", (0.0, 0.0, 0.0), (0.0, 1.0, 0.0)),
    ("cylinder", (0.0, 0.0, 0.0), (0.0, 0.6, 0.8)),
    ("ring", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
    ("cylinder", (0.03, 0.04, 0.0), (0.0, 1.0, 0.0)),  # 5 cm off-centre (workspace radius)
    ("ring", (0.0, 0.03, 0.04), (0.0, 0.6, -0.8)),
]


@pytest.mark.parametrize(("shape", "position", "direction"), GETFT_CASES)
def test_dipole_torque_matches_magpylib_getft(
    shape: str, position: tuple, direction: tuple
) -> None:
    coils = _helmholtz_x()
    br = capsule.remanence_for_grade("N45")
    u = np.asarray(direction) / np.linalg.norm(direction)
    if shape == "cylinder":
        mag = capsule.Magnet(6e-3, 10e-3, br)
        target = magpy.magnet.Cylinder(
            polarization=br * u, dimension=(6e-3, 10e-3), position=position
        )
        meshing = 200
    else:
        mag = capsule.Magnet(8e-3, 10e-3, br, inner_diameter_m=3e-3)
        target = magpy.magnet.CylinderSegment(
            polarization=br * u, position=position, dimension=(1.5e-3, 4e-3, 10e-3, 0.0, 360.0)
        )
        meshing = 400
    field = magpy.getB(coils, position, sumup=True)
    ours = capsule.magnetic_torque_Nm(mag.moment_Am2 * u, field)
    _, torque = magpy.getFT(coils, target, meshing=meshing)
    theirs = np.sum(torque, axis=0)  # sum over the two coils; pivot = magnet centroid
    rel = np.linalg.norm(ours - theirs) / np.linalg.norm(theirs)
    assert rel < 1e-4, (
        f"m x B vs magpylib.getFT (meshed {shape}, two-loop Helmholtz source) at "
        f"{position}: relative difference {rel:.2e} (measured <= 2e-8 at the "
        "centre, <= 5e-6 at 5 cm); tolerance 1e-4, requirement 1 %"
    )


def test_torque_perpendicular_to_moment_and_field() -> None:
    rng = np.random.default_rng(3)
    m, b = rng.normal(size=(50, 3)), rng.normal(size=(50, 3)) * 1e-2
    t = capsule.magnetic_torque_Nm(m, b)
    scale = np.linalg.norm(m, axis=1) * np.linalg.norm(b, axis=1)
    assert np.max(np.abs(np.sum(t * m, axis=1)) / (scale * np.linalg.norm(m, axis=1))) < 1e-14, (
        "tau . m = 0 (property of the cross product), rel 1e-14"
    )
    assert np.max(np.abs(np.sum(t * b, axis=1)) / (scale * np.linalg.norm(b, axis=1))) < 1e-14, (
        "tau . B = 0 (property of the cross product), rel 1e-14"
    )
    # |tau| = m B sin(angle) (Jackson eq. 5.1)
    cosang = np.sum(m * b, axis=1) / scale
    np.testing.assert_allclose(
        np.linalg.norm(t, axis=1),
        scale * np.sqrt(1 - cosang**2),
        rtol=1e-10,
        err_msg="|m x B| = m B sin(angle), rtol 1e-10",
    )


def test_synchronous_torque_and_lag() -> None:
    m, b0 = 0.3, 10e-3
    assert capsule.max_synchronous_torque_Nm(m, b0) == pytest.approx(3e-3, rel=1e-15), (
        "m B0 by hand = 3 mN m (docs/optimisation.md, Margin), rel 1e-15"
    )
    loads = np.linspace(-2.9e-3, 2.9e-3, 11)
    lag = capsule.lag_angle_rad(loads, m, b0)
    np.testing.assert_allclose(
        capsule.synchronous_torque_Nm(m, b0, lag),
        loads,
        rtol=1e-12,
        err_msg="m B0 sin(asin(T/(m B0))) = T round trip, rtol 1e-12",
    )
    beyond = capsule.lag_angle_rad(np.array([3.1e-3, -4e-3]), m, b0)  # no warning (errors on)
    assert np.all(np.isnan(beyond)), "step-out: no synchronous lag, documented NaN"


def test_forward_speed_and_thrust_torque() -> None:
    lead = capsule.lead_m(math.radians(10.0), 12e-3)
    assert capsule.forward_speed_m_s(2.0, lead, 0.5) == pytest.approx(
        0.5 * 2.0 * lead, rel=1e-15
    ), "eta f lead (docs/optimisation.md, Margin), rel 1e-15"
    f_load, mu = 0.05, 0.28
    for deg in (5.0, 10.0, 20.0, 40.0):
        a = math.radians(deg)
        l_ = capsule.lead_m(a, 12e-3)
        shigley = f_load * 6e-3 * (l_ + math.pi * mu * 12e-3) / (math.pi * 12e-3 - mu * l_)
        assert capsule.thrust_torque_Nm(f_load, 12e-3, a, mu) == pytest.approx(
            shigley, rel=1e-12
        ), f"Shigley 9th ed. eq. (8-1) raising torque, square thread, at {deg} deg, rel 1e-12"
    # Frictionless screw: torque x 2 pi = F x lead (work balance per revolution)
    a = math.radians(10.0)
    work = capsule.thrust_torque_Nm(f_load, 12e-3, a, 0.0) * 2 * math.pi
    assert work == pytest.approx(f_load * capsule.lead_m(a, 12e-3), rel=1e-12), (
        "virtual work of an ideal screw: 2 pi T = F lead, rel 1e-12"
    )
