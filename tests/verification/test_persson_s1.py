"""Persson's p(u) on the S1 figure-4 surface and the S1 section 4 flat-on-flat model.

S1 figure 4: E = 10 MPa, nu = 0.5, h_rms = 1 um, D_f = 2.2 (H = 0.8),
q0 = 1e4 1/m, q1 = 7.8e9 1/m.  S1 prints no alpha, beta for it (they are "determined
by C(q)"), so the checks are against an independent quadrature, the analytic
asymptote and the limits; the values are printed for the report.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import erf

from dolfinx_seal.contact import PerssonLaw
from dolfinx_seal.mpi import print0
from dolfinx_seal.roughness import SelfAffinePSD
from dolfinx_seal.scenes.flat import FlatParams

Q0, Q1, H, HRMS = 1e4, 7.8e9, 0.8, 1e-6
E_STAR = 10e6 / (1 - 0.5**2)
GAMMA = 0.4


@pytest.fixture(scope="module")
def psd() -> SelfAffinePSD:
    return SelfAffinePSD(Q0, Q1, H, h_rms=HRMS)


@pytest.fixture(scope="module")
def law(psd) -> PerssonLaw:
    return PerssonLaw(psd, E_STAR, GAMMA)


def u_reference(psd: SelfAffinePSD, p: float) -> float:
    """Yang-Persson u(p) by adaptive quadrature with closed-form w(q) (independent code)."""
    c0 = psd.c0

    def kernel(x0: float) -> float:
        f = lambda x: (GAMMA + 3 * (1 - GAMMA) * erf(x) ** 2) * math.exp(-x * x) / x  # noqa: E731
        return quad(f, x0, np.inf, epsabs=0, epsrel=1e-12, limit=400)[0]

    def g(q: float) -> float:
        w3 = c0 * Q0 ** (2 * H + 2) * (q ** (2 - 2 * H) - Q0 ** (2 - 2 * H)) / (2 - 2 * H)
        w = 1 / math.sqrt(math.pi * w3)
        return q * q * c0 * (q / Q0) ** (-2 * H - 2) * w * kernel(w * p / E_STAR)

    # q = q0 + s^2 removes the (q - q0)^(-1/2) singularity on the first interval
    a = quad(lambda s: 2 * s * g(Q0 + s * s), 0, math.sqrt(Q0), epsabs=0, epsrel=1e-10, limit=400)[
        0
    ]
    b = quad(lambda lq: math.exp(lq) * g(math.exp(lq)), math.log(2 * Q0), math.log(Q1),
             epsabs=0, epsrel=1e-10, limit=400)[0]  # fmt: skip
    return math.sqrt(math.pi) * (a + b)


@pytest.mark.parametrize("p", [1e2, 1.618e5, 2.06e6])
def test_separation_against_independent_quadrature(psd, law, p):
    ref = u_reference(psd, p)
    assert float(law.theory.mean_separation(np.array([p]))[0]) == pytest.approx(
        ref, rel=1e-7, abs=0
    )
    # the tabulated law (PCHIP of ln p vs ln u) reproduces it to 1e-4 in p
    assert float(law.pressure(np.array([ref]))[0]) == pytest.approx(p, rel=1e-4)


def test_asymptote_and_fit(law):
    print0(
        f"\nS1 fig-4 surface: alpha = {law.alpha:.5f}, beta = {law.beta:.5f} (analytic); "
        f"fit 1e-10 <= p/E* <= 1e-6: alpha = {law.alpha_fit:.5f}, beta = {law.beta_fit:.5f}"
    )
    # the least-squares fit of the tabulated relation meets the analytic asymptote
    assert law.alpha_fit == pytest.approx(law.alpha, rel=1e-3)
    assert law.beta_fit == pytest.approx(law.beta, rel=1e-2)
    # large u: the full relation is the exponential beta E* exp(-alpha u/h_rms) ...
    u = np.linspace(5.0, 10.0, 11) * HRMS
    np.testing.assert_allclose(law.pressure(u), law.exponential().pressure(u), rtol=1e-3)
    # ... and the deviation shrinks with u (the correction is O(p/E*)) down to the
    # interpolation error of the table (~1e-7)
    dev = np.abs(law.pressure(u) / law.exponential().pressure(u) - 1)
    assert dev[0] < 1e-4 and np.all(dev[u >= 8 * HRMS] < 1e-6)
    # small u: it diverges where the exponential stays finite
    tiny = np.array([1e-30, 1e-60])
    assert np.all(law.pressure(tiny) > law.exponential().pressure(tiny))
    assert law.pressure(tiny)[1] > law.pressure(tiny)[0]


def test_hertz_pressures_of_figure4(law):
    """Mean separations at the figure-4 Hertz mean and maximum pressures (reported)."""
    for p in (0.1618e6, 0.2060e6):
        u = float(law.separation(np.array([p]))[0])
        print0(f"S1 fig-4: p = {p / 1e6:.4f} MPa -> u = {u * 1e9:.1f} nm, A/A0 = "
               f"{float(law.area_fraction(np.array([p]))[0]):.4f}")  # fmt: skip
        # consistency of the law and its inverse; erf area law vs its small-load slope
        assert float(law.pressure(np.array([u]))[0]) == pytest.approx(p, rel=1e-10)
        a = float(law.area_fraction(np.array([p]))[0])
        chi = math.sqrt(8 / math.pi) / law.rms_slope  # S1 eq 14: A/A0 = chi p/E* for A << A0
        assert a == pytest.approx(erf(chi * math.sqrt(math.pi) / 2 * p / E_STAR), rel=1e-12)


# ------------------------------------------------------ S1 section 4: flat
@pytest.fixture(scope="module")
def flat():
    params = FlatParams()
    return params, params.model()


def drop_speed(model, eta: float) -> float:
    """Smallest speed at which the real contact vanishes (bisection in ln v)."""
    lo, hi = math.log(1e-6), math.log(1e-2)
    assert not model.solve(eta * math.exp(lo)).hydroplaning
    assert model.solve(eta * math.exp(hi)).hydroplaning
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        if model.solve(eta * math.exp(mid)).hydroplaning:
            hi = mid
        else:
            lo = mid
    return math.exp(hi)


def test_flat_viscous_hydroplaning_drop(flat):
    params, model = flat
    v_drop = drop_speed(model, params.film.viscosity)
    mu = lambda v: model.solve(params.film.viscosity * v).mu  # noqa: E731
    print0(f"\nS1 fig-32 system: friction drop (onset of viscous hydroplaning) at v = "
           f"{v_drop * 1e6:.1f} um/s; mu = {mu(1e-7):.3f} at 0.1 um/s, {mu(0.5 * v_drop):.3f} at "
           f"v_drop/2, {mu(2 * v_drop):.4f} at 2 v_drop (S1: abrupt drop at v ~ 50 um/s)")  # fmt: skip
    # S1 reads the drop off its figure 32 at ~50 um/s but does not state p0, q0, q1 or L;
    # with those taken from its figure 4 (see scenes/flat.py) we find ~113 um/s, and
    # p0 in 0.1-0.3 MPa moves it over 90-125 um/s: a factor 3 around 50 um/s is what
    # the comparison supports.
    assert 50e-6 / 3 < v_drop < 50e-6 * 3
    # abrupt: the contact shear stress vanishes at the drop (S1 fig 33) and mu falls by
    # more than 50x within a factor 4 in speed, while it changes by < 10 % over the
    # decade below v_drop / 10
    below, above = (
        model.solve(params.film.viscosity * v_drop * 0.999),
        model.solve(params.film.viscosity * v_drop * 1.001),
    )
    assert below.sigma_contact > 0 and above.sigma_contact == 0.0
    assert mu(0.5 * v_drop) > 50 * mu(2 * v_drop)
    assert abs(mu(v_drop / 100) / mu(v_drop / 10) - 1) < 0.1
    # load balance at every magnification (S1 eq 31)
    r = model.solve(params.film.viscosity * 1e-5)
    np.testing.assert_allclose(r.p_contact + r.p_fluid, params.nominal_pressure, rtol=1e-12)
    assert np.all(np.diff(r.area) <= 1e-15)


def test_flat_drop_converged_in_magnification(flat):
    params, model = flat
    v30 = drop_speed(model, params.film.viscosity)
    fine = FlatParams(points_per_decade=60).model()
    assert drop_speed(fine, params.film.viscosity) == pytest.approx(v30, rel=0.03)


def test_flat_dry_limit(flat, law):
    """v -> 0: no fluid load, A(zeta1) from the erf law at p0, zeta1 where u1 = 1 nm."""
    params, model = flat
    r = model.solve(0.0)
    assert r.p_fluid1 == 0.0 and r.sigma_fluid == 0.0
    a = float(
        model.theory.area_fraction(np.array([params.nominal_pressure]), np.array([r.zeta1]))[0]
    )
    assert r.area1 == pytest.approx(a, rel=2e-3)  # a(zeta) interpolated between nodes
    assert r.mu == pytest.approx(
        params.film.asperity_shear * r.area1 / params.nominal_pressure, rel=1e-12
    )
