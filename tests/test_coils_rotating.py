"""Rotating-field allocation at the centre and off it, and the field ellipse elsewhere."""

from __future__ import annotations

import numpy as np
import pytest

import coils
from spiralcap.core.errors import InputError

HEADINGS = [[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1], [0.3, -0.8, 0.2], [-1, 2, 0.5]]
B0_T = 8e-3


@pytest.fixture(scope="module")
def system() -> coils.ThreeAxisHelmholtz:
    return coils.ThreeAxisHelmholtz(
        coils.HelmholtzPair(0.4, 400, "x"),
        coils.HelmholtzPair(0.35, 300, "y"),
        coils.HelmholtzPair(0.3, 320, "z"),
    )


def _fields_over_a_turn(system, currents):
    return np.array([system.field(np.zeros((1, 3)), c)[0] for c in currents])


def _check_rotating(fields: np.ndarray, heading, label: str) -> None:
    n = np.asarray(heading, float) / np.linalg.norm(heading)
    mags = np.linalg.norm(fields, axis=1)
    assert np.max(np.abs(mags / B0_T - 1)) < 1e-12, f"{label}: |B| = B0 at all t, rel 1e-12"
    assert np.max(np.abs(fields @ n)) < 1e-12 * B0_T, f"{label}: B . n = 0, < 1e-12 B0"
    turn = np.cross(fields[:-1], fields[1:]) @ n
    assert np.all(turn > 0), f"{label}: B turns right-handedly about n (B x dB/dt . n > 0)"


@pytest.mark.parametrize("heading", HEADINGS)
def test_centre_allocation_makes_the_rotating_field(system, heading) -> None:
    f_hz = 2.0
    t = np.linspace(0, 1 / f_hz, 73)
    currents = system.rotating_currents(heading, B0_T, f_hz, t)
    assert currents.shape == (73, 3)
    _check_rotating(_fields_over_a_turn(system, currents), heading, "centre")
    amps, _ = system.rotating_allocation(heading, B0_T)
    n = np.asarray(heading, float) / np.linalg.norm(heading)
    want = B0_T * np.sqrt(1 - n**2) / system.centre_gains_T_per_A
    assert np.allclose(amps, want, rtol=1e-12, atol=1e-18), (
        "A_k = B0 sqrt(1 - n_k^2) / g_k (docs/optimisation.md, Limits), rel 1e-12"
    )
    assert np.allclose(
        system.rotating_current_per_tesla_A_per_T(heading) * B0_T, amps, rtol=1e-14, atol=0
    )


@pytest.mark.parametrize("heading", HEADINGS[3:])
def test_off_centre_allocation_reproduces_the_field_there(system, heading) -> None:
    point = np.array([0.06, -0.04, 0.09])
    amps, phases = system.rotating_allocation_at(point, heading, B0_T)
    t = np.linspace(0, 1, 61)
    currents = amps * np.cos(2 * np.pi * t[:, None] + phases)
    fields = np.array([system.field(point[None], c)[0] for c in currents])
    _check_rotating(fields, heading, "off-centre")
    centre_amps, _ = system.rotating_allocation(heading, B0_T)
    assert not np.allclose(amps, centre_amps, rtol=1e-4), "the off-centre solve is not trivial"


def test_semi_axes(system) -> None:
    heading = [0.2, 0.5, -0.8]
    minor, major = system.rotating_field_semi_axes_T(np.zeros((1, 3)), heading, B0_T)
    assert minor[0] == pytest.approx(B0_T, rel=1e-12) and major[0] == pytest.approx(
        B0_T, rel=1e-12
    ), "centre: a circle of radius B0, rel 1e-12"
    rng = np.random.default_rng(5)
    pts = rng.uniform(-0.12, 0.12, (20, 3))
    minor, major = system.rotating_field_semi_axes_T(pts, heading, B0_T)
    n = np.asarray(heading) / np.linalg.norm(heading)
    amps, phases = system.rotating_allocation(heading, B0_T)
    wt = np.linspace(0, 2 * np.pi, 200001)
    for p, lo, hi in zip(pts, minor, major, strict=True):
        b = system.field_matrix(p[None])[0] @ (amps[:, None] * np.cos(wt + phases[:, None]))
        b_perp = b - np.outer(n, n @ b)
        # P' and Q' are the projected fields at wt = 0 and wt = pi/2 (sample 50000).
        svals = np.linalg.svd(b_perp[:, [0, 50000]], compute_uv=False)
        mags = np.linalg.norm(b_perp, axis=0)
        assert lo == pytest.approx(svals[1], rel=1e-10) and hi == pytest.approx(
            svals[0], rel=1e-10
        ), "singular values of [P', Q'] (SVD), rel 1e-10"
        assert lo == pytest.approx(mags.min(), rel=1e-9) and hi == pytest.approx(
            mags.max(), rel=1e-9
        ), "min/max of |B_perp(t)| sampled at 2e5 phases, rel 1e-9"
        assert lo <= hi


def test_bad_heading() -> None:
    with pytest.raises(InputError) as err:
        coils.heading_frame([0, 0, 0])
    assert err.value.key == "heading"
