"""Contact-law objects: Persson (full, asymptotic, closed form), GW, GT, BGT."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import erf, erfc, gamma

from dolfinx_seal.contact import (
    BushGibsonThomas,
    ClosedFormPersson,
    GreenwoodTripp,
    GreenwoodWilliamson,
    PerssonExponentialLaw,
    PerssonLaw,
    elastoplastic_fractions,
    gw_function,
    gw_function_derivative,
)
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.roughness import SelfAffinePSD

E_STAR = 10e6 / 0.75


@pytest.fixture(scope="module")
def law() -> PerssonLaw:
    return PerssonLaw(SelfAffinePSD(1e4, 7.8e9, 0.8, h_rms=1e-6), E_STAR)


def fd(f, u, rel=1e-6):
    """Central finite difference (relative step; error ~ rel^2 f''' u^2 / 6)."""
    return (f(u * (1 + rel)) - f(u * (1 - rel))) / (2 * rel * u)


# ------------------------------------------------------------------ Persson
def test_persson_monotone_positive_and_derivative(law):
    u = np.geomspace(1e-250, 1e-3, 400)  # far beyond both ends of the table
    p = law.pressure(u)
    d = law.dpressure_du(u)
    assert np.all(np.isfinite(p)) and np.all(p > 0)
    assert np.all(np.diff(p) <= 0) and np.all(d <= 0)
    assert np.all(np.diff(p[u < 3e-4]) < 0)  # strictly, until ln p meets its floor
    # table region: small step (PCHIP knots); far below it p ~ ln(c/u)^(1/2) varies so
    # slowly that a larger step is needed to beat rounding (truncation ~ step^2)
    tab = (u >= law.u_table[0]) & (u < 3e-4)
    np.testing.assert_allclose(d[tab], fd(law.pressure, u[tab], 1e-7), rtol=1e-6)
    tiny = u < law.u_table[0]
    np.testing.assert_allclose(d[tiny], fd(law.pressure, u[tiny], 1e-3), rtol=1e-6)


def test_persson_diverges_at_zero_and_inverse(law):
    u = np.array([1e-300, 1e-200, 1e-100, 1e-50, 1e-20])
    p = law.pressure(u)
    assert np.all(np.diff(p) < 0)  # grows without bound as u -> 0 ...
    # ... as (ln(c/u))^(1/2): p^2 is linear in ln u on the small-u continuation
    lp2 = p**2
    slope = np.diff(lp2) / np.diff(np.log(u))
    np.testing.assert_allclose(slope, slope[0], rtol=1e-9)
    pp = np.geomspace(1e-12, 3.0, 50) * E_STAR
    np.testing.assert_allclose(law.pressure(law.separation(pp)), pp, rtol=1e-10)


def test_persson_rejects_bad_u(law):
    for bad in (0.0, -1e-6, np.nan, np.inf):
        with pytest.raises(ParameterError, match="u"):
            law.pressure(np.array([1e-6, bad]))


def test_exponential_law_closed_form_and_cap(law):
    ex = law.exponential()
    u = np.linspace(-2e-6, 8e-6, 11)
    np.testing.assert_allclose(
        ex.pressure(u), ex.beta * E_STAR * np.exp(-ex.alpha * u / 1e-6), rtol=1e-14
    )
    np.testing.assert_allclose(ex.dpressure_du(u), -ex.alpha / 1e-6 * ex.pressure(u), rtol=1e-14)
    up = u[u >= 0]  # the inverse is the mean separation, u >= 0 (p <= beta E*)
    np.testing.assert_allclose(ex.separation(ex.pressure(up)), up, atol=1e-20)
    with pytest.raises(ParameterError, match="beta E"):
        ex.separation(ex.pressure(u[u < 0]))
    assert np.isfinite(ex.pressure(np.array([-1.0]))).all()  # exponent capped, no overflow
    with pytest.raises(ParameterError, match="alpha"):
        PerssonExponentialLaw(-1.0, 0.1, E_STAR, 1e-6)


def test_closed_form_error_bound_and_monotone(law):
    cf = law.closed_form()
    assert cf.max_rel_error < 0.035
    # checked independently on a finer grid than the fit's
    u = np.geomspace(0.05, 12.0, 3001) * law.h_rms
    rel = np.abs(cf.pressure(u) / law.pressure(u) - 1)
    assert rel.max() <= cf.max_rel_error * 1.05
    uu = np.geomspace(1e-4, 50.0, 2000) * law.h_rms
    assert np.all(cf.dpressure_du(uu) < 0)
    np.testing.assert_allclose(cf.dpressure_du(uu), fd(cf.pressure, uu), rtol=1e-6)
    # any exp/ln (here the math module's) builds the same expression (UFL-friendly)
    one = cf.formula(2e-7, exp=math.exp, ln=math.log)
    assert one == pytest.approx(float(cf.pressure(np.array([2e-7]))[0]), rel=1e-14)


def test_closed_form_carries_the_contact_area_of_its_full_law(law):
    # the closed form (the law in the FEM forms) has the erf area of the full law
    cf = law.closed_form()
    assert cf.rms_slope == law.rms_slope
    p = np.array([0.0, 1e3, 1e5, 1e7])
    np.testing.assert_allclose(cf.area_fraction(p), law.area_fraction(p), rtol=1e-15)
    bare = ClosedFormPersson(cf.alpha, cf.beta, cf.m, cf.c, cf.a, cf.b, cf.e_star, cf.h_rms)
    with pytest.raises(ParameterError, match="contact-area relation"):
        bare.area_fraction(p)


def test_area_fraction_small_load_slope(law):
    # erf law: A/A0 -> sqrt(8/pi) p / (E* slope) as p -> 0 (Persson's kappa)
    p = np.array([1e-9, 1e-7]) * E_STAR * law.rms_slope
    kappa = law.area_fraction(p) * E_STAR * law.rms_slope / p
    np.testing.assert_allclose(kappa, math.sqrt(8 / math.pi), rtol=1e-12)
    a = np.array([0.0, 0.01, 0.3, 0.9, 0.999])
    np.testing.assert_allclose(law.area_fraction(law.pressure_from_area(a)), a, atol=1e-14)
    with pytest.raises(ParameterError, match="< 1"):
        law.pressure_from_area(np.array([1.0]))
    with pytest.raises(ParameterError, match="p"):
        law.area_fraction(np.array([-1.0]))


def test_elastoplastic_fractions():
    g = np.geomspace(1e-4, 1e6, 41)
    for r in (0.01, 0.2, 0.7):
        el, pl, non = elastoplastic_fractions(g, r)
        np.testing.assert_allclose(el + pl + non, 1.0, atol=1e-14)  # S3 eq C3
        assert np.all((el >= 0) & (pl >= 0) & (non >= 0))
    # sigma_Y -> inf: P_el = erf(1 / (2 sqrt g)) (S3 eq 31 / appendix B)
    el, pl, _ = elastoplastic_fractions(g, 1e-7)
    np.testing.assert_allclose(el, erf(0.5 / np.sqrt(g)), atol=1e-6)
    # g -> inf: P_pl -> sigma_0 / sigma_Y (S3 after eq C8)
    _, pl, _ = elastoplastic_fractions(np.array([1e8]), 0.3)
    assert pl[0] == pytest.approx(0.3, rel=1e-12)
    # the Fourier series (C9-C10) and the image series are independent solutions
    for r in (0.05, 0.5, 0.9):
        gg = np.geomspace(1e-3, 1.0, 7) / (math.pi * r) ** 2
        a, b = elastoplastic_fractions(gg, r, "fourier"), elastoplastic_fractions(gg, r, "images")
        for x, y in zip(a, b, strict=True):
            np.testing.assert_allclose(x, y, atol=1e-13)
    with pytest.raises(ParameterError, match="sigma_0/sigma_Y"):
        elastoplastic_fractions(g, 1.5)


def test_yield_stress_area(law):
    es = E_STAR * law.rms_slope
    # (pi sigma_0/sigma_Y)^2 G/sigma_0^2 = pi^2 (E* slope)^2 / (8 sigma_Y^2) does not depend
    # on the load: sigma_Y >> E* slope is the elastic limit, sigma_Y << E* slope the plastic
    # one, where A = F / sigma_Y (every junction at incipient yield, S3 after eq C8)
    hard = PerssonLaw(law.theory.psd, E_STAR, yield_stress=1e3 * es)
    p = np.array([1e-6, 1e-4, 1e-2]) * es
    np.testing.assert_allclose(hard.area_fraction(p), law.area_fraction(p), rtol=1e-5)
    soft = PerssonLaw(law.theory.psd, E_STAR, yield_stress=1e-3 * es)
    p = np.array([1e-8, 1e-7, 1e-6]) * es
    np.testing.assert_allclose(soft.area_fraction(p), p / soft.yield_stress, rtol=1e-3)
    assert soft.area_fraction(np.array([2e-3 * es]))[0] == 1.0  # p above yield


# ---------------------------------------------------------- GW, GT, BGT
def fn_quad(n: float, lam: float) -> float:
    """F_n by direct quadrature of S2 eq 29 (independent of the parabolic-cylinder form)."""
    f = lambda s: (s - lam) ** n * math.exp(-s * s / 2) / math.sqrt(2 * math.pi)  # noqa: E731
    return quad(f, lam, max(lam, 0.0) + 40.0, epsabs=0, epsrel=1e-12, limit=200)[0]


@pytest.mark.parametrize("n", [0.0, 0.5, 1.0, 1.5, 2.0, 2.5])
def test_gw_function(n):
    lam = np.array([-35.0, -5.0, -1.0, 0.0, 0.7, 2.0, 4.5])
    ref = np.array([fn_quad(n, x) for x in lam])
    np.testing.assert_allclose(gw_function(n, lam), ref, rtol=1e-10)
    # closed form at lambda = 0: 2^((n-1)/2) Gamma((n+1)/2) / sqrt(2 pi)
    f0 = 2 ** ((n - 1) / 2) * gamma((n + 1) / 2) / math.sqrt(2 * math.pi)
    assert gw_function(n, np.array(0.0)) == pytest.approx(f0, rel=1e-13)
    x = np.array([-2.0, 0.3, 1.7])
    d = (gw_function(n, x + 1e-6) - gw_function(n, x - 1e-6)) / 2e-6
    np.testing.assert_allclose(gw_function_derivative(n, x), d, rtol=1e-7)
    assert gw_function(n, np.array([40.0]))[0] == 0.0 or np.isfinite(
        gw_function(n, np.array([40.0]))
    )


def test_greenwood_williamson_laws():
    eta, r, s = 5e10, 20e-6, 0.5e-6
    u = np.array([-0.5, 0.0, 0.6, 1.5, 3.0]) * s
    gauss = GreenwoodWilliamson(eta, r, s, E_STAR)
    expo = GreenwoodWilliamson(eta, r, s, E_STAR, "exponential")
    for x in u:  # S2 eqs 20-21 by quadrature over summit heights
        load = quad(lambda z, x=x: (z - x) ** 1.5 * math.exp(-z * z / (2 * s * s)) / (s * math.sqrt(2 * math.pi)),
                    x, x + 40 * s, epsabs=0, epsrel=1e-12)[0]  # fmt: skip
        assert gauss.pressure(x) == pytest.approx(
            4 / 3 * eta * E_STAR * math.sqrt(r) * load, rel=1e-9
        )
        # exponential summits (phi* = exp(-s) for s > 0): eq 20 with that density, u >= 0
        if x >= 0:
            load_e = quad(lambda z, x=x: (z - x) ** 1.5 * math.exp(-z / s) / s, x, x + 80 * s,
                          epsabs=0, epsrel=1e-12)[0]  # fmt: skip
            assert expo.pressure(x) == pytest.approx(
                4 / 3 * eta * E_STAR * math.sqrt(r) * load_e, rel=1e-9
            )
    for m in (gauss, expo):
        np.testing.assert_allclose(
            m.dpressure_du(u), (m.pressure(u + 1e-12) - m.pressure(u - 1e-12)) / 2e-12, rtol=1e-5
        )
        np.testing.assert_allclose(m.separation(m.pressure(u)), u, atol=1e-15)
    # exponential: A/A0 proportional to p (S2 eqs 24-25), ratio sqrt(pi) (R/sigma)^(1/2) / E*
    p = expo.pressure(u[u >= expo.u_full])
    np.testing.assert_allclose(
        expo.area_fraction(p) / p, math.sqrt(math.pi * r / s) / E_STAR, rtol=1e-12
    )
    with pytest.raises(ParameterError, match="p_full"):
        expo.area_fraction(expo.pressure(np.array([0.0])))
    with pytest.raises(ParameterError, match="distribution"):
        GreenwoodWilliamson(eta, r, s, E_STAR, "weibull")
    with pytest.raises(ParameterError, match="summit_radius"):
        GreenwoodWilliamson(eta, -r, s, E_STAR)


def test_greenwood_tripp():
    eta, beta, s = 5e10, 20e-6, 0.5e-6
    gt = GreenwoodTripp(eta, beta, s, E_STAR)
    k = 16 * math.sqrt(2) / 15 * math.pi * (eta * beta * s) ** 2 * E_STAR * math.sqrt(s / beta)
    lam = np.array([0.0, 1.0, 2.5])
    ref = np.array([fn_quad(2.5, x) for x in lam]) * k
    np.testing.assert_allclose(gt.pressure(lam * s), ref, rtol=1e-10)
    u = lam * s
    np.testing.assert_allclose(
        gt.dpressure_du(u), (gt.pressure(u + 1e-12) - gt.pressure(u - 1e-12)) / 2e-12, rtol=1e-5
    )
    np.testing.assert_allclose(gt.separation(gt.pressure(u)), u, atol=1e-15)
    a = gt.area_fraction(gt.pressure(u[1:]))
    np.testing.assert_allclose(
        a,
        math.pi**2 * (eta * beta * s) ** 2 * np.array([fn_quad(2.0, x) for x in lam[1:]]),
        rtol=1e-9,
    )
    with pytest.raises(ParameterError, match="p_full"):
        gt.area_fraction(gt.pressure(u[:1]))


@pytest.mark.parametrize("t", [3.0, 5.0, 8.0])
def test_bush_gibson_thomas_asymptotics(t):
    """The BGT law against the summit integrals it is derived from (see its docstring)."""
    s, m2 = 1e-6, 0.01
    bgt = BushGibsonThomas(s, m2, E_STAR)
    # area: exact integral of pi R delta over Nayak's high-level summit density
    a_int = (
        math.pi
        * (2 * math.pi) ** -1.5
        * quad(lambda z: z * (z - t) * math.exp(-z * z / 2), t, np.inf, epsabs=0, epsrel=1e-12)[0]
    )
    assert bgt.area_fraction_at(t * s) == pytest.approx(a_int, rel=1e-10)
    assert a_int == pytest.approx(0.25 * erfc(t / math.sqrt(2)), rel=1e-10)
    # load: the Hertz integral tends to the law with a relative correction O(t^-2)
    j = quad(lambda z: z**1.5 * (z - t) ** 1.5 * math.exp(-z * z / 2), t, np.inf, epsabs=0,
             epsrel=1e-12)[0]  # fmt: skip
    p_int = 4 / 3 * (2 * math.pi) ** -1.5 * j * E_STAR * math.sqrt(m2)
    assert abs(p_int / bgt.pressure(t * s) - 1) < 0.4 / t**2
    # linear area-load law with the BGT constant kappa = sqrt(2 pi)
    p = bgt.pressure(t * s)
    assert bgt.area_fraction(p) == pytest.approx(
        math.sqrt(2 * math.pi) * p / (E_STAR * math.sqrt(2 * m2)), rel=1e-12
    )
    assert bgt.separation(p) == pytest.approx(t * s, rel=1e-10, abs=0)
