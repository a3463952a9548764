"""Winding geometry, resistance, inductances, thermal conductance, electrical functions."""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest
from scipy import integrate

import coils
from coils.filaments import gauss_legendre_pack
from spiralcap.core.constants import (
    COPPER_RESISTIVITY_20C_ohm_m,
    COPPER_TEMPERATURE_COEFFICIENT_per_K,
    MU0_T_m_per_A,
)
from spiralcap.core.errors import InputError


def neumann_mutual_H(a: float, b: float, d: float) -> float:
    """Neumann's double integral for coaxial circles, reduced by symmetry to one quadrature
    over [0, pi] (the integrand is even about pi)."""

    def integrand(phi: float) -> float:
        return math.cos(phi) / math.sqrt(a * a + b * b + d * d - 2 * a * b * math.cos(phi))

    value, _ = integrate.quad(integrand, 0.0, math.pi, epsabs=0, epsrel=1e-12, limit=200)
    return MU0_T_m_per_A * a * b * value


def volume_self_inductance_H(radius: float, side: float, turns: int, n: int) -> float:
    """N^2 x mean of Maxwell's M over n x n sub-squares; self terms mu0 r (ln(8r/g) - 2),
    g = 0.447049 h (Maxwell's GMD of a square). Converges as 1/n^2 to the volume integral."""
    h = side / n
    x = (np.arange(n) + 0.5) * h - side / 2
    r, z = (v.ravel() for v in np.meshgrid(radius + x, x, indexing="ij"))
    same = np.eye(r.size, dtype=bool)
    a, b = r[:, None], np.where(same, 2 * r[:, None], r[None, :])
    mutual = coils.coaxial_mutual_inductance_H(a, b, z[:, None] - z[None, :])
    own = MU0_T_m_per_A * r * (np.log(8 * r / (0.447049 * h)) - 2)
    return turns**2 * (np.where(same, 0.0, mutual).sum() + own.sum()) / r.size**2


def test_maxwell_mutual_matches_neumann_integral() -> None:
    for a, b, d in ((0.3, 0.3, 0.3), (0.2, 0.35, 0.1), (0.4, 0.38, 0.02), (0.1, 0.5, 1.0)):
        assert coils.coaxial_mutual_inductance_H(a, b, d) == pytest.approx(
            neumann_mutual_H(a, b, d), rel=1e-10
        ), "Neumann integral (quad), rel 1e-10"


@pytest.mark.parametrize(("radius", "turns", "wire_mm"), [(0.4, 400, 2.5), (0.1, 60, 3.0)])
def test_self_inductance_stefan_vs_volume_integral(
    radius: float, turns: int, wire_mm: float
) -> None:
    pair = coils.HelmholtzPair(radius, turns, wire_diameter_m=wire_mm * 1e-3)
    side = pair.winding_pack_side_m
    coarse, fine = (volume_self_inductance_H(radius, side, turns, n) for n in (16, 32))
    reference = (4 * fine - coarse) / 3  # Richardson on the 1/n^2 error
    assert pair.self_inductance_H == pytest.approx(reference, rel=2e-5), (
        f"filament-sum volume integral (Richardson 16/32), rel 2e-5 at c/R = {side / radius:.2f}"
    )


def test_self_inductance_near_wheeler() -> None:
    pair = coils.HelmholtzPair(0.4, 400, wire_diameter_m=2.5e-3)
    a, c = pair.radius_m / 0.0254, pair.winding_pack_side_m / 0.0254
    wheeler = 0.8e-6 * a * a * pair.turns**2 / (6 * a + 9 * c + 10 * c)
    assert pair.self_inductance_H == pytest.approx(wheeler, rel=0.02), (
        "Wheeler 1928 multilayer formula (inches, uH; ~1 % claimed), rel 2 %"
    )


def test_pair_mutual_and_series_inductance() -> None:
    pair = coils.HelmholtzPair(0.35, 350, "y", wire_diameter_m=2.5e-3)
    dr, dz, w = gauss_legendre_pack(pair.winding_pack_side_m, (8, 8))
    dense = pair.turns**2 * np.sum(
        w[:, None]
        * w[None, :]
        * coils.coaxial_mutual_inductance_H(
            pair.radius_m + dr[:, None],
            pair.radius_m + dr[None, :],
            pair.separation_m + dz[:, None] - dz[None, :],
        )
    )
    assert pair.mutual_inductance_H == pytest.approx(dense, rel=1e-9), (
        "4x4 Gauss-Legendre pack average converged vs 8x8, rel 1e-9"
    )
    filament = pair.turns**2 * neumann_mutual_H(pair.radius_m, pair.radius_m, pair.separation_m)
    assert pair.mutual_inductance_H == pytest.approx(
        filament, rel=(pair.winding_pack_side_m / pair.separation_m) ** 2
    ), "pack average vs N^2 x Neumann filament value, within (c/s)^2"
    assert pair.series_inductance_H == pytest.approx(
        2 * pair.self_inductance_H + 2 * pair.mutual_inductance_H, rel=1e-15
    ), "2L + 2M"


def test_geometry_resistance_and_conductance_by_hand() -> None:
    pair = coils.HelmholtzPair(0.3, 300, wire_diameter_m=2.0e-3, packing_factor=0.6)
    side = math.sqrt(300 * math.pi * 1e-6 / 0.6)
    assert pair.winding_pack_side_m == pytest.approx(side, rel=1e-15), "sqrt(N pi d^2/4 / pf)"
    length = 2 * 300 * 2 * math.pi * 0.3
    assert pair.wire_length_m == pytest.approx(length, rel=1e-15), "2 N 2 pi R"
    rho_60 = COPPER_RESISTIVITY_20C_ohm_m * (1 + COPPER_TEMPERATURE_COEFFICIENT_per_K * 40)
    assert pair.resistance_ohm(60.0) == pytest.approx(
        rho_60 * length / (math.pi * 1e-6), rel=1e-14
    ), "IEC 60028 rho(T) l / A"
    assert pair.thermal_conductance_W_per_K(12.0) == pytest.approx(
        12.0 * 2 * 4 * side * 2 * math.pi * 0.3, rel=1e-14
    ), "h x 2 coils x 4c x 2 pi R"


def test_electrical_functions_numpy_and_casadi() -> None:
    r, ind, f, i = 4.0, 0.2, 3.0, 12.0
    z = math.hypot(r, 2 * math.pi * f * ind)
    assert coils.impedance_ohm(r, ind, f) == pytest.approx(z, rel=1e-15), "|R + j w L|"
    assert coils.voltage_amplitude_V(r, ind, f, i) == pytest.approx(z * i, rel=1e-15), (
        "voltage amplitude = |Z| I (Ohm's law), 1e-15"
    )
    assert coils.copper_loss_W(r, i) == pytest.approx(r * i * i / 2, rel=1e-15), "R I^2 / 2"
    assert coils.temperature_rise_K(100.0, 4.0) == 25.0, "P / G"
    fs, cs = ca.SX.sym("f"), ca.SX.sym("i")
    fn = ca.Function(
        "e",
        [fs, cs],
        [
            coils.impedance_ohm(r, ind, fs),
            coils.voltage_amplitude_V(r, ind, fs, cs),
            coils.copper_loss_W(r, cs),
            coils.temperature_rise_K(coils.copper_loss_W(r, cs), 4.0),
        ],
    )
    got = [float(v) for v in fn(f, i)]
    want = [z, z * i, r * i * i / 2, r * i * i / 8]
    assert np.allclose(got, want, rtol=1e-12, atol=0), "CasADi vs numpy, rel 1e-12"
    arr = coils.voltage_amplitude_V(r, ind, np.array([1.0, 2.0]), np.array([3.0, 4.0]))
    assert arr.shape == (2,), "broadcasts over numpy arrays"


@pytest.mark.parametrize(
    ("kwargs", "key"),
    [
        ({"radius_m": float("nan")}, "radius_m"),
        ({"radius_m": -1.0}, "radius_m"),
        ({"turns": 0}, "turns"),
        ({"turns": 2.5}, "turns"),
        ({"turns": True}, "turns"),
        ({"axis": "w"}, "axis"),
        ({"separation_m": 0.0}, "separation_m"),
        ({"wire_diameter_m": 0.0}, "wire_diameter_m"),
        ({"packing_factor": 0.95}, "packing_factor"),
        ({"wire_diameter_m": 0.03}, "wire_diameter_m"),
        ({"separation_m": 0.04}, "separation_m"),
        ({"filaments": (0, 2)}, "filaments"),
        ({"filaments": 3}, "filaments"),
    ],
)
def test_pair_rejects_bad_parameters(kwargs: dict, key: str) -> None:
    args = {"radius_m": 0.3, "turns": 300, **kwargs}
    with pytest.raises(InputError) as err:
        coils.HelmholtzPair(**args)
    assert err.value.key == key, str(err.value)


def test_system_rejects_pair_on_wrong_axis() -> None:
    x, y = coils.HelmholtzPair(0.4, 400, "x"), coils.HelmholtzPair(0.35, 350, "y")
    with pytest.raises(InputError) as err:
        coils.ThreeAxisHelmholtz(x=x, y=x, z=y)
    assert err.value.key == "y", str(err.value)


def _rect_gmd(p: float, q: float) -> float:
    """Maxwell's geometric mean distance of a p x q rectangle from itself (Rosa & Grover 1912)."""
    x = p / q
    return math.exp(
        math.log(math.hypot(p, q))
        - x * x / 12 * math.log(1 + 1 / x**2)
        - 1 / (12 * x * x) * math.log(1 + x * x)
        + 2 / 3 * (x * math.atan(1 / x) + math.atan(x) / x)
        - 25 / 12
    )


def volume_self_inductance_rect_H(
    radius: float, width: float, depth: float, turns: int, n: int
) -> float:
    """As volume_self_inductance_H on an axial-width x radial-depth rectangle of n x n cells."""
    xr = (np.arange(n) + 0.5) * depth / n - depth / 2
    xz = (np.arange(n) + 0.5) * width / n - width / 2
    r, z = (v.ravel() for v in np.meshgrid(radius + xr, xz, indexing="ij"))
    same = np.eye(r.size, dtype=bool)
    a, b = r[:, None], np.where(same, 2 * r[:, None], r[None, :])
    mutual = coils.coaxial_mutual_inductance_H(a, b, z[:, None] - z[None, :])
    own = MU0_T_m_per_A * r * (np.log(8 * r / _rect_gmd(width / n, depth / n)) - 2)
    return turns**2 * (np.where(same, 0.0, mutual).sum() + own.sum()) / r.size**2


@pytest.mark.parametrize("aspect", [0.3, 0.5, 2.0, 3.5])
def test_self_inductance_of_a_rectangular_pack_vs_volume_integral(aspect: float) -> None:
    pair = coils.HelmholtzPair(0.3, 400, wire_diameter_m=2.5e-3, pack_aspect=aspect)
    w, d = pair.winding_pack_width_m, pair.winding_pack_depth_m
    assert w / d == pytest.approx(aspect, rel=1e-14), "aspect = axial width / radial depth"
    assert w * d == pytest.approx(pair.winding_pack_area_m2, rel=1e-14), "area kept"
    coarse, fine = (volume_self_inductance_rect_H(0.3, w, d, 400, n) for n in (16, 32))
    reference = (4 * fine - coarse) / 3
    assert pair.self_inductance_H == pytest.approx(reference, rel=5e-5), (
        f"filament-sum volume integral (Richardson 16/32), rel 5e-5 at aspect {aspect}"
    )


def test_square_aspect_is_the_square_pack() -> None:
    square = coils.HelmholtzPair(0.35, 300, wire_diameter_m=2.0e-3)
    also = coils.HelmholtzPair(0.35, 300, wire_diameter_m=2.0e-3, pack_aspect=1.0)
    side = square.winding_pack_side_m
    assert also.winding_pack_width_m == pytest.approx(side, rel=1e-15), "w = c at aspect 1"
    assert also.winding_pack_depth_m == pytest.approx(side, rel=1e-15), "h = c at aspect 1"
    a, c = 0.35, side
    stefan = (
        MU0_T_m_per_A
        * a
        * 300**2
        * (
            (1 + 4 * c * c / (96 * a * a)) * math.log(8 * a / (math.sqrt(2) * c))
            - 0.848340
            + c * c / (16 * a * a) * 0.8162
        )
    )
    assert also.self_inductance_H == pytest.approx(stefan, rel=1e-14), (
        "Stefan's square-section formula, y1 = 0.84834, y2 = 0.8162 (Rosa & Grover Table 23)"
    )
    with pytest.raises(InputError, match="pack_aspect"):
        coils.HelmholtzPair(0.35, 300, pack_aspect=5.0)


def test_stefan_bracket_numpy_and_casadi_agree() -> None:
    from coils.pair import stefan_bracket

    a, w, d = ca.SX.sym("a"), ca.SX.sym("w"), ca.SX.sym("d")
    fn = ca.Function("L", [a, w, d], [stefan_bracket(a, w, d)])
    for args in ((0.3, 0.05, 0.02), (0.4, 0.03, 0.06), (0.35, 0.04, 0.04)):
        assert float(fn(*args)) == pytest.approx(float(stefan_bracket(*args)), rel=1e-12), (
            "numpy vs CasADi, 1e-12"
        )


def test_clearance_row_is_exact_at_the_frozen_hardware() -> None:
    """The sizing row's value (torus bound + frozen correction) at the hardware the factors
    were frozen at equals the exact clearance of coils.clearance (docs/coils-buildable.md)."""
    from coils.clearance import pack_clearance_m, torus_clearance_bound_m
    from optimize import hardware as hw
    from spiralcap.assemble import build_model
    from spiralcap.design import load_design

    model = build_model(load_design(None))
    frozen = hw.frozen_factors(model)
    pairs = model.coils.pairs
    for n, (i, j) in enumerate(hw.PAIRS_OF_PAIRS):
        row = torus_clearance_bound_m(frozen.gap0_m[n], pairs[i], pairs[j])
        row += frozen.clearance_delta_m[n]
        assert row == pytest.approx(pack_clearance_m(pairs[i], pairs[j]), abs=1e-12)
        assert frozen.clearance_delta_m[n] >= 0.0, "the bound is conservative"
