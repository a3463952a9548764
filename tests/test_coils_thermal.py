"""Winding thermal model (coils.thermal): hot spot, self-consistent resistance, run time."""

import math

import casadi as ca
import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from scipy.integrate import solve_ivp

from coils import thermal as th
from optimize import evaluate, prepare
from spiralcap.analysis.coils import operating_thermal
from spiralcap.assemble import build_model
from spiralcap.constants import COPPER_TEMPERATURE_COEFFICIENT_per_K as ALPHA
from spiralcap.design import load_design


def _square_poisson(n: int, biot: float | None = None) -> np.ndarray:
    """Cell-centred finite volumes for -∇²T = 1 on the unit square (k = 1, q''' = 1).

    Faces: T = 0 (``biot`` None) or -dT/dn = biot T (h a / k = biot)."""
    face = 2.0 if biot is None else 1.0 / (0.5 + n / biot)
    main = np.full((n, n), 4.0)
    main[0, :] += face - 1.0
    main[-1, :] += face - 1.0
    main[:, 0] += face - 1.0
    main[:, -1] += face - 1.0
    one = sp.identity(n)
    lap1 = sp.diags([-np.ones(n - 1), -np.ones(n - 1)], [-1, 1])
    a = sp.kron(one, lap1) + sp.kron(lap1, one) + sp.diags(main.ravel())
    return spl.spsolve(a.tocsc(), np.full(n * n, 1.0 / n**2)).reshape(n, n)


def _centre(t: np.ndarray) -> float:
    m = t.shape[0] // 2
    return float(t[m - 1 : m + 1, m - 1 : m + 1].mean())


def test_square_pack_coefficients_against_finite_differences():
    t = _square_poisson(80)
    assert th.KAPPA_CENTRE == pytest.approx(0.0737, abs=5e-5), "Carslaw & Jaeger: 0.0737"
    assert _centre(t) == pytest.approx(th.KAPPA_CENTRE, rel=2e-3), (
        "centre rise of the square, isothermal faces: series vs 80x80 finite volumes (0.2 %)"
    )
    assert t.mean() == pytest.approx(th.KAPPA_MEAN, rel=2e-3), (
        "mean rise (Saint-Venant torsion J = 0.1406 a^4): series vs finite volumes (0.2 %)"
    )


def test_built_in_hot_spot_within_10_percent_of_the_robin_problem():
    """The model puts the faces at one (mean) temperature; the real faces are cooled by h_eff
    (Robin). Finite volumes of the Robin problem at the built-in x pack's Biot number: the
    centre-minus-mean-face rise is within 10 % of the model's."""
    m = prepare(build_model(load_design(None)))
    ev = evaluate(m)
    pack, r20 = m.constants.packs[0], float(m.constants.resistance_20C_ohm[0])
    op = th.steady_state(pack, r20, ev.current_amplitudes_A[0], 25.0)
    rise = float(op.hot_spot_C - op.surface_C)
    q = float(op.power_W) / pack.volume_m3
    by_hand = 0.0737 * q * pack.pack_width_m**2 / 0.5
    assert rise == pytest.approx(by_hand, rel=1e-3), (
        "issue 10: hot-spot rise = 0.0737 q''' a²/k for the built-in x pack, k = 0.5 (1e-3)"
    )
    h_eff = pack.heat_transfer_coefficient_W_m2K + th.radiation_coefficient_W_m2K(
        float(op.surface_C), 25.0, pack.emissivity
    )
    biot = float(h_eff * pack.pack_width_m / pack.conductivity_W_mK)
    t = _square_poisson(60, biot)
    robin = _centre(t) - 1.0 / (4.0 * biot)  # mean face temperature from the energy balance
    assert rise / (robin * q * pack.pack_width_m**2 / 0.5) == pytest.approx(1.0, abs=0.10), (
        f"hot-spot rise within 10 % of the finite-volume Robin solution at Bi = {biot:.2f}"
    )


def test_steady_state_is_self_consistent():
    pack = th.WindingPack(0.05, 0.05, 0.4, 0.7, 0.5, 10.0, 0.9)
    st = th.steady_state(pack, 7.0, 13.0, 25.0)
    assert float(st.resistance_ohm) == pytest.approx(
        7.0 * (1 + ALPHA * (float(st.mean_C) - 20.0)), rel=1e-12
    ), "R at the mean winding temperature (IEC 60028), 1e-12"
    assert float(st.power_W) == pytest.approx(0.5 * float(st.resistance_ohm) * 13.0**2, rel=1e-12)
    sigma = 5.670374419e-8
    ts, ta = float(st.surface_C) + 273.15, 298.15
    shed = pack.surface_area_m2 * (10.0 * (ts - ta) + 0.9 * sigma * (ts**4 - ta**4))
    assert shed == pytest.approx(float(st.power_W), rel=1e-10), (
        "surface balance: convection + grey-body radiation (Stefan-Boltzmann) = loss, 1e-10"
    )


def test_numpy_and_casadi_agree():
    pack = th.WindingPack(0.05, 0.05, 0.4, 0.7, 0.5, 10.0, 0.9)
    x = ca.SX.sym("x")
    for fn in (
        lambda i: th.steady_state(pack, 7.0, i, 25.0).hot_spot_C,
        lambda i: th.transient(pack, 7.0, i, 25.0, 1200.0, 60.0).hot_spot_C,
        lambda i: th.limit_state(pack, 60.0 + i, 25.0).power_W,
    ):
        f = ca.Function("f", [x], [fn(x)])
        for i in (0.0, 5.0, 13.0):
            assert float(f(i)) == pytest.approx(float(fn(i)), rel=1e-12, abs=1e-12)


def test_runaway_is_reported():
    pack = th.WindingPack(0.05, 0.05, 0.4, 0.7, 0.5, 0.01, 0.0)
    st = th.steady_state(pack, 7.0, 200.0, 25.0)
    assert float(st.runaway) == 1.0 and float(st.hot_spot_C) > 1000.0, (
        "no steady state: flagged, with a finite bound far above any limit"
    )


def test_poor_winding_conductivity_lowers_the_field():
    poor = evaluate(
        prepare(build_model(load_design(None, ["coils.winding_conductivity_W_mK=0.5"])))
    )
    good = evaluate(prepare(build_model(load_design(None, ["coils.winding_conductivity_W_mK=50"]))))
    assert poor.field_amplitude_T < good.field_amplitude_T, (
        "issue 10: k = 0.5 W/(m·K) allows a lower field than k = 50"
    )
    assert poor.field_limited_by == "hot_spot_x"


def test_session_allows_more_and_follows_the_lumped_exponential():
    sets = ["limits.voltage_V=1000", "limits.current_A=100", "limits.power_W=1e5"]
    steady = evaluate(prepare(build_model(load_design(None, sets))))
    design = load_design(None, [*sets, "operation.session_min=20"])
    run = evaluate(prepare(build_model(design)))
    assert run.field_amplitude_T > steady.field_amplitude_T, (
        "issue 10: a 20 min session allows a higher field than steady state"
    )
    assert run.field_limited_by == "hot_spot_x"
    model = prepare(build_model(design))
    ops, curves = operating_thermal(model, run.field_amplitude_T)
    t = 1200.0
    for op, curve in zip(ops, curves):
        expected = 25.0 + (curve.final_mean_C - 25.0) * (1.0 - math.exp(-t / op.time_constant_s))
        assert op.session_mean_temperature_C == pytest.approx(expected, rel=0.01), (
            "issue 10: end-of-session temperature follows the lumped exponential with the "
            "reported time constant (1 %)"
        )
    # independent: integrate C dθ/dt = R(T) I²/2 - θ/(r_m + 1/G) with the pack's numbers
    op, c = ops[0], model.constants
    pack, r20 = c.packs[0], float(c.resistance_20C_ohm[0])
    steady_surface = float(th.steady_state(pack, r20, op.current_A, 25.0).surface_C)
    g = pack.surface_area_m2 * (
        10.0 + th.radiation_coefficient_W_m2K(steady_surface, 25.0, pack.emissivity)
    )
    r_th = 0.03514 * pack.pack_width_m**2 / (0.5 * pack.volume_m3) + 1.0 / g
    cap = pack.volume_m3 * (0.7 * 8960 * 385 + 0.3 * 1200 * 1100)

    def rhs(_t, y):
        return [(r20 * (1 + ALPHA * (5.0 + y[0])) * op.current_A**2 / 2 - y[0] / r_th) / cap]

    sol = solve_ivp(rhs, (0.0, t), [0.0], rtol=1e-10, atol=1e-10)
    assert 25.0 + sol.y[0, -1] == pytest.approx(op.session_mean_temperature_C, rel=1e-3), (
        "lumped ODE (scipy solve_ivp) from the pack geometry by hand, 1e-3"
    )


def test_optimiser_and_evaluate_agree_on_the_session_hot_spot():
    from optimize import optimize_design

    sets = [
        "limits.voltage_V=1000",
        "limits.current_A=100",
        "limits.power_W=1e5",
        "operation.session_min=20",
    ]
    m = prepare(build_model(load_design(None, sets)))
    res = optimize_design(m)
    assert res.status == "optimal"
    ev = evaluate(m, res.helical_angle_rad, res.frequency_hz)
    assert ev.field_limited_by == "hot_spot_x"
    assert res.field_amplitude_T == pytest.approx(ev.field_amplitude_T, rel=1e-6), (
        "IPOPT on the CasADi hot-spot term reaches the field the numpy bisection allows (1e-6)"
    )
    assert "hot_spot_x" in {b.name for b in res.binding_limits}, "the optimiser's binding row"
    assert res.margin_Nm == pytest.approx(ev.margin_Nm, rel=1e-6)


@pytest.mark.parametrize("session", [None, "operation.session_min=20"])
def test_limit_terms_numpy_and_casadi_agree(session):
    from optimize import physics as ph

    m = prepare(build_model(load_design(None, [session] if session else [])))
    b, f = ca.SX.sym("b"), ca.SX.sym("f")
    terms = ph.limit_terms(f, b, m.constants, m.limits, 25.0)
    fn = ca.Function("g", [b, f], [ca.vertcat(*[t.value for t in terms])])
    for field, freq in ((0.004, 0.7), (0.0119, 2.0), (0.03, 4.5)):
        expected = [
            float(t.value) for t in ph.limit_terms(freq, field, m.constants, m.limits, 25.0)
        ]
        got = np.array(fn(field, freq)).ravel()
        assert np.allclose(got, expected, rtol=1e-12, atol=0), "numpy and CasADi limits, 1e-12"


def _rect_poisson(nx: int, ny: int, lx: float, ly: float) -> np.ndarray:
    """Cell-centred finite volumes for -∇²T = 1 on an lx x ly rectangle, T = 0 on the faces."""
    hx, hy = lx / nx, ly / ny

    def lap(n: int, h: float) -> sp.spmatrix:
        main = np.full(n, 2.0)
        main[[0, -1]] = 3.0  # the wall half a cell away
        return sp.diags([-np.ones(n - 1), main, -np.ones(n - 1)], [-1, 0, 1]) / (h * h)

    a = sp.kron(lap(nx, hx), sp.identity(ny)) + sp.kron(sp.identity(nx), lap(ny, hy))
    return spl.spsolve(a.tocsc(), np.ones(nx * ny)).reshape(nx, ny)


@pytest.mark.parametrize("aspect", [0.25, 0.5, 2.0, 3.0])
def test_rectangle_pack_coefficients_against_finite_volumes(aspect: float) -> None:
    w, d = math.sqrt(aspect), 1.0 / math.sqrt(aspect)
    centre, mean = th.rectangle_pack_coefficients(w, d)
    t = _rect_poisson(int(60 * w) * 2, int(60 * d) * 2, w, d)
    mx, my = t.shape[0] // 2, t.shape[1] // 2
    assert float(t[mx - 1 : mx + 1, my - 1 : my + 1].mean()) / (w * d) == pytest.approx(
        float(centre), rel=3e-3
    ), f"centre rise of a {w:.2f} x {d:.2f} rectangle: series vs finite volumes (0.3 %)"
    assert t.mean() / (w * d) == pytest.approx(float(mean), rel=3e-3), (
        "mean rise: series vs finite volumes (0.3 %)"
    )
    swapped = th.rectangle_pack_coefficients(d, w)
    assert float(swapped[0]) == pytest.approx(float(centre), rel=1e-14), "symmetric in w, d"


def test_rectangle_pack_reduces_to_the_square_at_aspect_one() -> None:
    centre, mean = th.rectangle_pack_coefficients(0.03, 0.03)
    assert float(centre) == pytest.approx(th.KAPPA_CENTRE, rel=1e-14), "square series, centre"
    # the square's 60-term mean series is truncated at ~1e-9; the rectangle sums the tail exactly
    assert float(mean) == pytest.approx(th.square_pack_coefficients(150)[1], rel=1e-12), (
        "square series (150 terms), mean"
    )
    assert float(mean) == pytest.approx(th.KAPPA_MEAN, rel=2e-9), "KAPPA_MEAN (60 terms)"
    square = th.WindingPack(0.04, 0.04, 0.3, 0.7, 0.5, 10.0, 0.9)
    assert square.surface_area_m2 == pytest.approx(2 * 4 * 0.04 * 2 * math.pi * 0.3, rel=1e-15)
    assert square.centre_resistance_K_per_W == pytest.approx(
        th.KAPPA_CENTRE * 0.04**2 / (0.5 * square.volume_m3), rel=1e-14
    ), "square pack: KAPPA_CENTRE c²/(k V)"
    flat = th.WindingPack(0.08, 0.02, 0.3, 0.7, 0.5, 10.0, 0.9)
    assert flat.volume_m3 == pytest.approx(square.volume_m3, rel=1e-15), "same area w d"
    assert flat.surface_area_m2 == pytest.approx(2 * 2 * (0.08 + 0.02) * 2 * math.pi * 0.3)
    assert flat.centre_resistance_K_per_W < square.centre_resistance_K_per_W, (
        "a flat pack of the same area conducts its heat out over a shorter path"
    )


def test_rectangle_pack_numpy_and_casadi_agree() -> None:
    w, d = ca.SX.sym("w"), ca.SX.sym("d")
    fn = ca.Function("k", [w, d], list(th.rectangle_pack_coefficients(w, d)))
    for ww, dd in ((0.05, 0.02), (0.02, 0.05), (0.03, 0.03)):
        ref = th.rectangle_pack_coefficients(ww, dd)
        out = fn(ww, dd)
        assert float(out[0]) == pytest.approx(float(ref[0]), rel=1e-12), "numpy vs CasADi"
        assert float(out[1]) == pytest.approx(float(ref[1]), rel=1e-12), "numpy vs CasADi"
