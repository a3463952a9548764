"""The numpy/CasADi backend: both paths agree, and the AGM elliptic integrals are exact."""

import math

import casadi as ca
import numpy as np
import pytest
from scipy import special

from spiralcap.core import backend as bk


@pytest.mark.parametrize("m", [0.0, 1e-10, 0.1, 0.5, 0.9, 0.999, 0.99999, 1 - 1e-8])
def test_agm_matches_scipy(m):
    x = ca.SX.sym("m")
    k, e = ca.Function("ke", [x], [bk.ellipk(x), bk.ellipe(x)])(m)
    assert abs(float(k) - special.ellipk(m)) < 1e-13 * special.ellipk(m), (
        "AGM K(m) vs scipy.special.ellipk: tolerance 1e-13 relative"
    )
    assert abs(float(e) - special.ellipe(m)) < 1e-13, (
        "AGM E(m) vs scipy.special.ellipe: tolerance 1e-13"
    )


def test_agm_derivative_matches_legendre_relation():
    # dK/dm = (E - (1-m) K) / (2 m (1-m)): DLMF 19.4.1; CasADi's exact derivative of the AGM.
    x = ca.SX.sym("m")
    dk = ca.Function("dk", [x], [ca.jacobian(bk.ellipk(x), x)])
    for m in (0.2, 0.7, 0.95):
        ref = (special.ellipe(m) - (1 - m) * special.ellipk(m)) / (2 * m * (1 - m))
        assert abs(float(dk(m)) - ref) < 1e-11 * abs(ref), (
            "d K/dm from AGM vs DLMF 19.4.1: tolerance 1e-11 relative"
        )


@pytest.mark.parametrize(
    "name", ["sin", "cos", "tan", "arctan", "exp", "sqrt", "log", "abs", "square", "softplus"]
)
def test_unary_paths_agree(name):
    fn = getattr(bk, name)
    xs = np.array([0.1, 0.7, 1.3, 2.9])
    x = ca.SX.sym("x")
    f = ca.Function("f", [x], [fn(x)])
    got = np.array([float(f(v)) for v in xs])
    assert np.allclose(got, fn(xs), rtol=1e-14, atol=0), (
        f"backend.{name}: numpy and CasADi paths agree to 1e-14"
    )


def test_where_and_minmax_on_both_paths():
    x = ca.SX.sym("x")
    f = ca.Function("f", [x], [bk.where(x < 1, x * x, 2 * x), bk.fmax(x, 1.0), bk.fmin(x, 1.0)])
    for v in (0.5, 1.5):
        w, hi, lo = (float(o) for o in f(v))
        assert w == float(np.where(v < 1, v * v, 2 * v)), "where: CasADi if_else == numpy.where"
        assert (hi, lo) == (max(v, 1.0), min(v, 1.0)), "fmax/fmin on the CasADi path"


def test_is_casadi_does_not_trip_on_numpy():
    assert not bk.is_casadi(1.0, np.ones(3)), "numpy values take the numpy path"
    assert bk.is_casadi(1.0, ca.SX.sym("x")), "any CasADi argument takes the CasADi path"


def test_sqrt_guarded_has_finite_derivative_at_zero():
    x = ca.SX.sym("x")
    f = ca.Function("f", [x], [bk.sqrt_guarded(x), ca.jacobian(bk.sqrt_guarded(x), x)])
    val0, d0 = (float(v) for v in f(0.0))
    assert val0 == 0.0 and math.isfinite(d0), "guarded sqrt: value 0 and finite slope at 0"
    val, d = (float(v) for v in f(4.0))
    assert (val, d) == (2.0, 0.25), "away from 0 it is the plain square root and its slope"
    assert bk.sqrt_guarded(np.array([0.0, 4.0])).tolist() == [0.0, 2.0], "numpy path"


def test_ellipke_near_m_1_through_the_complement() -> None:
    """Next to m = 1 the field passes 1 - m exactly: K from it follows the logarithmic
    expansion K = ln(4/sqrt(x)) + (x/4)(ln(4/sqrt(x)) - 1) + O(x²) (Abramowitz & Stegun 17.3.26)
    to 1e-15, where 1 - m formed by subtraction would have lost every digit of x."""
    x = np.geomspace(1e-300, 1e-9, 200)
    K, E = bk.ellipke(1.0 - x, complement=x)
    lead = np.log(4.0 / np.sqrt(x))
    assert np.allclose(K, lead + 0.25 * x * (lead - 1.0), rtol=1e-15, atol=0), "A&S 17.3.26"
    assert np.allclose(E, 1.0, rtol=1e-8, atol=0), "E(1) = 1 (A&S 17.3.12)"
    m = np.linspace(0.0, 0.99, 1000)
    K2, E2 = bk.ellipke(m, complement=1.0 - m)
    assert np.allclose(K2, special.ellipk(m), rtol=1e-15) and np.array_equal(E2, special.ellipe(m))
    Ke, Ee = bk.ellipke(np.array([1.0, -0.5]))
    assert Ke[0] == np.inf and Ee[0] == 1.0, "K(1) = inf, E(1) = 1 (A&S 17.3.11-12 limits)"
    assert Ke[1] == pytest.approx(special.ellipk(-0.5), rel=1e-15), "m < 0 as scipy"


def test_ellipke_numpy_path_matches_casadi_agm() -> None:
    m = np.linspace(0.0, 0.999, 1000)
    sym = ca.SX.sym("m")
    agm = ca.Function("ke", [sym], list(bk.ellipke(sym)))
    k_ca, e_ca = (np.array(v).ravel() for v in agm.map(m.size)(m))
    k_np, e_np = bk.ellipke(m)
    assert np.allclose(k_np, k_ca, rtol=1e-13, atol=0) and np.allclose(
        e_np, e_ca, rtol=1e-13, atol=0
    ), "one-pass numpy K, E vs the CasADi AGM (Abramowitz & Stegun 17.6), rel 1e-13"
