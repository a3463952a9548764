"""Every backend-generic capsule function gives the same numbers on numpy and on CasADi."""

from __future__ import annotations

from collections.abc import Callable

import casadi as ca
import numpy as np
import pytest

import capsule

RNG = np.random.default_rng(11)
N = 64
ALPHA = np.radians(RNG.uniform(2.0, 60.0, N))

#: name -> (function, sample arguments as numpy arrays of length N)
CASES: dict[str, tuple[Callable, tuple[np.ndarray, ...]]] = {
    "helix_diameter_m": (
        capsule.helix_diameter_m,
        (RNG.uniform(8e-3, 13e-3, N), RNG.uniform(0.2e-3, 2e-3, N)),
    ),
    "lead_m": (capsule.lead_m, (ALPHA, RNG.uniform(9e-3, 14e-3, N))),
    "spiral_turns": (
        capsule.spiral_turns,
        (ALPHA, RNG.uniform(9e-3, 14e-3, N), RNG.uniform(5e-3, 20e-3, N)),
    ),
    "footprint_width_m": (capsule.footprint_width_m, (ALPHA, RNG.uniform(0.2e-3, 2e-3, N))),
    "max_helical_angle_for_turns_rad": (
        capsule.max_helical_angle_for_turns_rad,
        (RNG.uniform(9e-3, 14e-3, N), RNG.uniform(5e-3, 20e-3, N), RNG.uniform(0.0, 4.0, N)),
    ),
    "min_helical_angle_for_clearance_rad": (
        capsule.min_helical_angle_for_clearance_rad,
        (
            RNG.uniform(9e-3, 14e-3, N),
            RNG.uniform(0.2e-3, 2e-3, N),
            RNG.integers(1, 4, N).astype(float),
        ),
    ),
    "max_synchronous_torque_Nm": (
        capsule.max_synchronous_torque_Nm,
        (RNG.uniform(0.05, 1.0, N), RNG.uniform(1e-3, 20e-3, N)),
    ),
    "synchronous_torque_Nm": (
        capsule.synchronous_torque_Nm,
        (RNG.uniform(0.05, 1.0, N), RNG.uniform(1e-3, 20e-3, N), RNG.uniform(-1.5, 1.5, N)),
    ),
    "lag_angle_rad": (
        capsule.lag_angle_rad,
        (RNG.uniform(-1e-3, 1e-3, N), RNG.uniform(0.3, 1.0, N), RNG.uniform(5e-3, 20e-3, N)),
    ),
    "forward_speed_m_s": (
        capsule.forward_speed_m_s,
        (RNG.uniform(0.1, 5.0, N), RNG.uniform(1e-3, 30e-3, N), RNG.uniform(0.0, 1.0, N)),
    ),
    "thrust_torque_Nm": (
        capsule.thrust_torque_Nm,
        (RNG.uniform(0.0, 0.1, N), RNG.uniform(9e-3, 14e-3, N), ALPHA, RNG.uniform(0.05, 0.6, N)),
    ),
}


@pytest.mark.parametrize("name", sorted(CASES))
@pytest.mark.parametrize("symbol", [ca.SX, ca.MX])
def test_numpy_and_casadi_agree(name: str, symbol: type) -> None:
    fn, args = CASES[name]
    expected = np.asarray(fn(*args), dtype=float)
    syms = [symbol.sym(f"x{i}") for i in range(len(args))]
    expr = fn(*syms)
    assert isinstance(expr, (ca.SX, ca.MX)), f"{name} must stay symbolic on {symbol.__name__}"
    f = ca.Function(name, syms, [expr])
    got = np.array([float(f(*(a[k] for a in args))) for k in range(N)])
    np.testing.assert_allclose(
        got,
        expected,
        rtol=1e-12,
        atol=0.0,
        err_msg=f"{name}: CasADi {symbol.__name__} vs numpy (CONTRIBUTING: 1e-12), rtol 1e-12",
    )


def test_casadi_gradient_of_lead_matches_analytic() -> None:
    a, dh = ca.SX.sym("a"), ca.SX.sym("dh")
    grad = ca.Function("g", [a, dh], [ca.gradient(capsule.lead_m(a, dh), a)])
    alpha, d_h = np.radians(12.0), 12e-3
    assert float(grad(alpha, d_h)) == pytest.approx(np.pi * d_h / np.cos(alpha) ** 2, rel=1e-12), (
        "d/dalpha pi D_h tan(alpha) = pi D_h sec^2(alpha) (calculus), rel 1e-12"
    )
