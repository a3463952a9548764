"""Winding thermal model (coils.thermal): hot spot, self-consistent resistance, run time."""

import math

import casadi as ca
import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spl

from coils import thermal as th
from optimize import evaluate, prepare
from spiralcap.analysis.coils import operating_thermal
from spiralcap.assemble import build_model
from spiralcap.core.constants import COPPER_TEMPERATURE_COEFFICIENT_per_K as ALPHA
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


@pytest.mark.parametrize("biot", [0.3, 1.7, 8.0])
def test_robin_statics_against_finite_volumes(biot):
    """The Robin section (faces cooled by h) the model solves: its exact series against finite
    volumes of the same problem on the unit square (k = 1, q = 1, h a / k = biot)."""
    from coils.conduction import robin_statics

    t = _square_poisson(80, biot)
    st = robin_statics(1.0, 1.0, biot, 1.0)
    assert float(st.centre) == pytest.approx(_centre(t), rel=2e-3), (
        f"Robin centre rise, series vs 80x80 finite volumes at Bi = {biot} (0.2 %)"
    )
    assert float(st.mean) == pytest.approx(t.mean(), rel=2e-3), "Robin mean rise (0.2 %)"
    assert float(st.surface_mean) == pytest.approx(1.0 / (4.0 * biot), rel=1e-12), (
        "mean face rise q A_section / (h P) = 1/(4 Bi) (energy balance)"
    )


def test_built_in_hot_spot_is_the_robin_centre():
    """Steady state of the built-in x pack: hot spot above the mean face = the Robin solution
    (finite volumes) at the model's own h_eff."""
    m = prepare(build_model(load_design(None, ["coils.heat_transfer_coefficient_W_m2K=10"])))
    ev = evaluate(m)
    pack, r20 = m.constants.packs[0], float(m.constants.resistance_20C_ohm[0])
    op = th.steady_state(pack, r20, ev.current_amplitudes_A[0], 25.0)
    rise = float(op.hot_spot_C - op.surface_C)
    q = float(op.power_W) / pack.volume_m3
    c = pack.pack_width_m
    biot = float(op.effective_h_W_m2K) * c / pack.conductivity_W_mK
    t = _square_poisson(60, biot)
    robin = (_centre(t) - 1.0 / (4.0 * biot)) * q * c * c / pack.conductivity_W_mK
    assert rise == pytest.approx(robin, rel=5e-3), (
        f"hot spot above the mean face vs 60x60 finite volumes of the Robin problem at "
        f"Bi = {biot:.2f} (0.5 %)"
    )
    iso = th.KAPPA_CENTRE * q * c * c / pack.conductivity_W_mK
    assert rise > iso, "the Robin rise exceeds the isothermal-face one (issue 10's 0.0737)"


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


@pytest.mark.parametrize("convection", ["fixed", "natural", "forced"])
def test_numpy_and_casadi_agree(convection):
    from coils.thermal_system import mean_rise_at_K, pair_temperatures

    packs = tuple(
        th.WindingPack(
            0.05,
            0.04,
            r,
            0.7,
            0.5,
            10.0,
            0.9,
            air_speed_m_s=2.0,
            vertical_axis=k == 2,
            convection=convection,
        )
        for k, r in enumerate((0.4, 0.35, 0.3))
    )
    pack = packs[2]
    vf = [[0.7, 0.05, 0.15, 0.1], [0.65, 0.15, 0.05, 0.15], [0.6, 0.12, 0.18, 0.1]]
    x = ca.SX.sym("x")
    env = th.Surroundings(35.0, 0.9)
    for fn in (
        lambda i: th.steady_state(pack, 7.0, i, 25.0).hot_spot_C,
        lambda i: th.steady_state(pack, 7.0, i, 25.0, env).surface_max_C,
        lambda i: th.transient(pack, 7.0, i, 25.0, 1200.0, 60.0, env).hot_spot_C,
        lambda i: th.surface_estimate_C(pack, 7.0, i, 25.0, env, 3600.0),
        lambda i: (
            pair_temperatures(packs, (7.0, 6.0, 5.0), (i, 0.8 * i, i), 25.0, vf)[0].hot_spot_C
        ),
        lambda i: (
            pair_temperatures(packs, (7.0, 6.0, 5.0), (i, i, i), 25.0, vf, 2400.0)[2].surface_max_C
        ),
        lambda i: mean_rise_at_K(
            pair_temperatures(packs, (7.0, 6.0, 5.0), (13.0, 13.0, 13.0), 25.0, vf)[1], 6.0, i, 25.0
        ),
    ):
        f = ca.Function("f", [x], [fn(x)])
        for i in (0.0, 5.0, 13.0):
            assert float(f(i)) == pytest.approx(float(fn(i)), rel=1e-12, abs=1e-12), (
                "numpy and CasADi, 1e-12"
            )


def test_runaway_is_reported():
    pack = th.WindingPack(0.05, 0.05, 0.4, 0.7, 0.5, 0.01, 0.0)
    st = th.steady_state(pack, 7.0, 200.0, 25.0)  # a fixed h: no convection growth
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
    assert poor.field_limited_by == "hot_spot_y"


def _fv_transient(pack, r20, current, minutes, n=24, steps=600):
    """Independent 2-D finite volumes of the pack section heating from ambient (θ = 0): cell
    centred, Robin faces with h (the conductance of half a cell in series), implicit Euler,
    the loss R(T_mean) I²/2 spread uniformly (its resistance at the current mean). Returns the
    hottest cell's rise, K."""
    w, d, k = pack.pack_width_m, pack.pack_depth_m, pack.conductivity_W_mK
    h = pack.heat_transfer_coefficient_W_m2K
    rc = pack.heat_capacity_J_per_K / pack.volume_m3
    nx, ny = n, max(4, round(n * d / w))
    dx, dy = w / nx, d / ny

    def lap(m, step):
        main = np.full(m, 2.0)
        main[[0, -1]] = 1.0
        return sp.diags([-np.ones(m - 1), main, -np.ones(m - 1)], [-1, 0, 1]) / step**2

    a = k * (sp.kron(sp.identity(ny), lap(nx, dx)) + sp.kron(lap(ny, dy), sp.identity(nx)))
    gx, gy = 1.0 / (dx / (2 * k) + 1 / h), 1.0 / (dy / (2 * k) + 1 / h)
    face = np.zeros((ny, nx))
    face[:, [0, -1]] += gx / dx
    face[[0, -1], :] += gy / dy
    dt = minutes * 60.0 / steps
    lu = spl.splu((sp.identity(nx * ny) * rc / dt + a + sp.diags(face.ravel())).tocsc())
    theta = np.zeros(nx * ny)
    for _ in range(steps):
        mean_c = 25.0 + theta.mean()
        q = r20 * (1 + ALPHA * (mean_c - 20.0)) * current**2 / 2 / pack.volume_m3
        theta = lu.solve(theta * rc / dt + q)
    return float(theta.max())


@pytest.mark.parametrize("minutes", [20, 120])
def test_session_hot_spot_against_finite_volumes(minutes):
    """Issue 19: with h = 10 and emissivity 0, the x pair's hot spot at the end of a session
    within 3 K of an independent 2-D finite-volume transient of the pack at the same current."""
    sets = [
        "coils.heat_transfer_coefficient_W_m2K=10",
        "coils.surface_emissivity=0",
        f"operation.session_min={minutes}",
    ]
    model = prepare(build_model(load_design(None, sets)))
    ev = evaluate(model)
    c = model.constants
    current = ev.current_amplitudes_A[0]
    ops, _ = operating_thermal(model, ev.field_amplitude_T)
    hot = ops[0].session_hot_spot_temperature_C
    fv = 25.0 + _fv_transient(c.packs[0], float(c.resistance_20C_ohm[0]), current, minutes)
    assert hot == pytest.approx(fv, abs=3.0), (
        f"{minutes} min session: modal hot spot vs 2-D finite volumes (issue 19: 3 K)"
    )
    assert hot == pytest.approx(fv, abs=1.0), "and in fact within 1 K"


def test_long_session_reaches_steady_state():
    """Issue 19: a 10-hour session allows the steady field within 0.5 %."""
    steady = evaluate(prepare(build_model(load_design(None))))
    long = evaluate(prepare(build_model(load_design(None, ["operation.session_min=600"]))))
    assert long.field_amplitude_T == pytest.approx(steady.field_amplitude_T, rel=5e-3), (
        "10 h session vs steady state: field within 0.5 %"
    )


def test_session_allows_more_and_the_curve_starts_at_ambient():
    sets = ["limits.voltage_V=1000", "limits.current_A=100", "limits.power_W=1e5"]
    steady = evaluate(prepare(build_model(load_design(None, sets))))
    design = load_design(None, [*sets, "operation.session_min=20"])
    run = evaluate(prepare(build_model(design)))
    assert run.field_amplitude_T > steady.field_amplitude_T, (
        "issue 10: a 20 min session allows a higher field than steady state"
    )
    assert run.field_limited_by.startswith("hot_spot_")
    model = prepare(build_model(design))
    ops, curves = operating_thermal(model, run.field_amplitude_T)
    for op, curve in zip(ops, curves):
        assert curve.hot_spot_C[0] == pytest.approx(25.0, abs=1e-9), "heating starts at ambient"
        assert curve.mean_C[0] == pytest.approx(25.0, abs=1e-9)
        assert np.all(np.diff(curve.hot_spot_C) > 0), "the hot spot rises monotonically"
        i = int(np.argmin(np.abs(curve.time_s - 1200.0)))
        assert curve.time_s[i] == pytest.approx(1200.0, abs=1e-6)
        assert curve.hot_spot_C[i] == pytest.approx(op.session_hot_spot_temperature_C, abs=0.5), (
            "the curve passes through the session's end state (linearised at that point: 0.5 K)"
        )


def test_optimiser_and_evaluate_agree_on_the_session_hot_spot():
    from optimize import optimize_design

    sets = [
        "limits.voltage_V=1000",
        "limits.current_A=100",
        "limits.power_W=1e5",
        "operation.session_min=20",
        "optimize.starts=1",  # one IPOPT start: the hot-spot row binds whichever start wins
    ]
    m = prepare(build_model(load_design(None, sets)))
    res = optimize_design(m)
    assert res.status == "optimal"
    ev = evaluate(m, res.helical_angle_rad, res.frequency_hz)
    assert ev.field_limited_by.startswith("hot_spot_")
    assert res.field_amplitude_T == pytest.approx(ev.field_amplitude_T, rel=1e-6), (
        "IPOPT on the CasADi hot-spot term reaches the field the numpy bisection allows (1e-6)"
    )
    assert ev.field_limited_by in {b.name for b in res.binding_limits}, "the optimiser's row"
    assert res.margin_Nm == pytest.approx(ev.margin_Nm, rel=1e-6)


@pytest.mark.parametrize("session", [None, "operation.session_min=20"])
def test_limit_terms_numpy_and_casadi_agree(session):
    from optimize import physics as ph

    sets = ["limits.surface_temperature_C=60", *([session] if session else [])]
    m = prepare(build_model(load_design(None, sets)))
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


def test_heat_capacity_and_copper_mass_use_one_copper_density() -> None:
    """Issue 26 (c): the pack's copper heat capacity is the copper mass of the bill of
    materials times copper's specific heat. The copper volume of a pack is pf · V = 2N·2πR·πd²/4
    (the wire's volume), so C = m_Cu c_Cu + (V - m_Cu/ρ) ρc_epoxy with ρ the IEC 60028 density
    (8890 kg/m³), c_Cu = 385 J/(kg·K) (CRC Handbook, 97th ed.), epoxy 1200 x 1100 J/(m³·K)
    (the documented impregnation); exact to 1e-12."""
    from spiralcap.analysis.coils import analyse_coils, coils_payload

    design = load_design(None)
    model = prepare(build_model(design))
    out = coils_payload(analyse_coils(design, model))
    rho_iec, c_crc, epoxy = 8890.0, 385.0, 1200.0 * 1100.0
    for k, ax in enumerate("xyz"):
        mass = out["axes"][ax]["copper_mass_kg"]
        pack = model.constants.packs[k]
        expected = mass * c_crc + (float(pack.volume_m3) - mass / rho_iec) * epoxy
        assert out["axes"][ax]["heat_capacity_J_per_K"] == pytest.approx(expected, rel=1e-12), (
            f"{ax}: heat capacity from the reported copper mass (IEC 60028 8890 kg/m³, CRC "
            "385 J/(kg·K)), 1e-12"
        )
        assert mass == pytest.approx(rho_iec * pack.volume_m3 * pack.packing_factor, rel=1e-12), (
            f"{ax}: copper mass is 8890 kg/m³ (IEC 60028) x the pack's copper volume, 1e-12"
        )
