"""Contact laws stay in their domain (issue 21, point 7).

Every law of :mod:`dolfinx_seal.contact` is swept over nominal pressures from
1e-8 to 10 E* (200 log-spaced points, plus edge values) and over separations
from 0 (and negative values, for the laws defined for every real ``u``) to
1e300 m.  The law must return finite values in the physical range -- ``p >= 0``
with ``dp/du <= 0``, ``0 <= A/A0 <= 1``, flow factors in ``[0, 1]``,
separations ``>= 0`` (or, for the signed summit-plane coordinate of GW, GT and
BGT, any real ``u``) with ``p(u(p)) = p`` -- exactly where its documented
domain says so, and raise ParameterError naming the law, the quantity and the
allowed range everywhere else.  Each in-domain set is evaluated in one
vectorised call (it must not raise), each out-of-domain point on its own (it
must raise).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pytest

from dolfinx_seal.contact import (
    BruggemanFlowFactor,
    BushGibsonThomas,
    GreenwoodTripp,
    GreenwoodWilliamson,
    PatirCheng,
    PerssonExponentialLaw,
    PerssonLaw,
    gw_function,
    load_fraction,
)
from dolfinx_seal.contact.flow_factors import LogHermiteTable
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.roughness import SelfAffinePSD

E_STAR = 10e6 / 0.75  # [Pa]
H_RMS = 1e-6  # [m]

#: Nominal pressures [Pa]: the sweep 1e-8 ... 10 E*, then edge values (0, negative,
#: denormal, huge).
P_SWEEP = np.geomspace(1e-8, 10.0, 200) * E_STAR
P_EDGE = np.array([0.0, -1.0, -1e9, 5e-324, 1e-300, 1e-30, 1e30, 1e300])
P_ALL = np.concatenate((P_SWEEP, P_EDGE))
#: Separations [m]: 0, denormals, 1e-300 ... 1e300 (every 5 decades), a dense physical
#: range 1e-3 ... 1e3 h_rms, and their negatives.
U_POS = np.unique(
    np.concatenate(
        ([5e-324, 1e-310], np.geomspace(1e-300, 1e300, 121), np.geomspace(1e-3, 1e3, 61) * H_RMS)
    )
)
U_ALL = np.concatenate((-U_POS[::-1], [0.0], U_POS))
NON_FINITE = (np.nan, np.inf, -np.inf)


def expect_domain_error(call: Callable[[], object], law: str, quantity: str) -> None:
    """``call()`` raises ParameterError naming ``law``, ``quantity`` and a range."""
    with pytest.raises(ParameterError) as err:
        call()
    msg = str(err.value)
    assert law in msg, msg
    assert f"{quantity} = " in msg, msg
    assert "allowed range" in msg, msg


def sweep(
    f: Callable[[np.ndarray], np.ndarray],
    x: np.ndarray,
    inside: np.ndarray,
    valid: Callable[[np.ndarray, np.ndarray], np.ndarray],
    law: str,
    quantity: str,
    label: str = "",
) -> np.ndarray:
    """Check ``f`` on ``x``: valid values on ``inside`` (one call), a domain error at each
    other point, a "must be finite" error for NaN/inf.  Returns the inside values."""
    assert np.any(inside), "the sweep must reach into the domain"
    xin = x[inside]
    v = np.asarray(f(xin), dtype=float)
    assert v.shape == xin.shape
    assert np.all(np.isfinite(v)), (label or law, quantity, xin[~np.isfinite(v)])
    ok = valid(v, xin)
    assert np.all(ok), (label or law, quantity, xin[~ok][:5], v[~ok][:5])
    for i in (0, xin.size // 2, xin.size - 1):  # scalars in, scalars out, same values
        for xs in (float(xin[i]), np.array(xin[i])):
            vs = f(xs)
            assert np.shape(vs) == (), (label or law, quantity, xs)
            assert float(vs) == pytest.approx(v[i], rel=1e-12, abs=1e-300), (label or law, xs)
    for xo in x[~inside]:
        expect_domain_error(lambda xo=xo: f(np.array([xo])), law, quantity)
    for bad in NON_FINITE:
        with pytest.raises(ParameterError, match="finite"):
            f(np.array([1.0, bad]))
    return v


# ------------------------------------------------------------------ laws
def _psd(hurst: float) -> SelfAffinePSD:
    return SelfAffinePSD(1e4, 7.8e9, hurst, h_rms=H_RMS)


@pytest.fixture(scope="module")
def persson() -> dict[float, PerssonLaw]:
    return {h: PerssonLaw(_psd(h), E_STAR) for h in (0.6, 0.8)}


@dataclass
class Case:
    """A contact law and its documented domains (predicates on the inputs)."""

    law: object
    pressure_domain: Callable[[np.ndarray], np.ndarray] | None = None
    separation_domain: Callable[[np.ndarray], np.ndarray] | None = None
    signed: bool = False  # separation is a signed coordinate (GW, GT, BGT)
    area_domain: Callable[[np.ndarray], np.ndarray] | None = None
    area_at_domain: Callable[[np.ndarray], np.ndarray] | None = None


def _positive(x: np.ndarray) -> np.ndarray:
    return x > 0


def _real(x: np.ndarray) -> np.ndarray:
    return np.ones(x.shape, dtype=bool)


def _nonnegative(x: np.ndarray) -> np.ndarray:
    return x >= 0


#: The laws by family (one test item each: the per-test clean-up of tests/conftest.py
#: costs ~0.1 s); a failure names the variant in its message.
FAMILIES = {
    "persson": ("persson-H0.6", "persson-H0.8", "persson-yield"),
    "exponential": ("exponential-H0.6", "exponential-H0.8", "exponential-stiff"),
    "closed-form": ("closed-form-H0.8",),
    "gw": ("gw-gaussian-dense", "gw-exponential-dense", "gw-gaussian-sparse",
           "gw-exponential-sparse"),
    "gt": ("gt-dense", "gt-sparse"),
    "bgt": ("bgt",),
}  # fmt: skip


def build_case(key: str, persson: dict[float, PerssonLaw]) -> Case:
    if key.startswith("persson-H"):
        law = persson[float(key[-3:])]
        return Case(law, _positive, lambda p: (p > 0) & (p <= law.p_max), False, _nonnegative)
    if key == "persson-yield":
        base = persson[0.8]
        law = PerssonLaw(base.theory.psd, E_STAR, yield_stress=1e-2 * E_STAR)
        return Case(law, _positive, lambda p: (p > 0) & (p <= law.p_max), False, _nonnegative)
    if key.startswith("exponential-H"):
        law = persson[float(key[-3:])].exponential()
        top = law.beta * law.e_star
        return Case(law, _real, lambda p: (p > 0) & (p <= top), False, _nonnegative)
    if key == "exponential-stiff":  # the scenes' "stiff" law, no contact area
        law = PerssonExponentialLaw(1.0, 1.0, E_STAR, 1e-9)
        return Case(law, _real, lambda p: (p > 0) & (p <= E_STAR))
    if key == "closed-form-H0.8":
        law = persson[0.8].closed_form()
        return Case(law, _positive, None, False, _nonnegative)
    if key.startswith(("gw-", "gt-")):
        # dense: eta R sigma = 0.5 (A/A0 > 1 already near u = 0); sparse: 0.05
        eta = 5e10 if key.endswith("dense") else 5e9
        if key.startswith("gt-"):
            law = GreenwoodTripp(eta, 20e-6, 0.5e-6, E_STAR)
        else:
            dist = "gaussian" if "gaussian" in key else "exponential"
            law = GreenwoodWilliamson(eta, 20e-6, 0.5e-6, E_STAR, dist)
        return Case(
            law, _real, lambda p: (p > 0) & (p <= law.p_max), True,
            lambda p: (p >= 0) & (p <= law.p_full), lambda u: u >= law.u_full,
        )  # fmt: skip
    assert key == "bgt"
    law = BushGibsonThomas.from_psd(_psd(0.8), E_STAR)
    top = E_STAR * math.sqrt(law.m2 / math.pi) / 2
    return Case(
        law, _real, lambda p: (p > 0) & (p < top), True, lambda p: (p >= 0) & (p <= top), _real
    )


@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_law_stays_in_its_domain(family, persson):
    for key in FAMILIES[family]:
        check_case(key, build_case(key, persson))


def check_case(key: str, case: Case) -> None:
    law = case.law
    name = law.name

    def pressure_ok(v, u):
        d = np.asarray(law.dpressure_du(u), dtype=float)
        return (v >= 0) & np.isfinite(d) & (d <= 0)

    if case.pressure_domain is not None:
        sweep(law.pressure, U_ALL, case.pressure_domain(U_ALL), pressure_ok, name, "u", key)
    if case.separation_domain is not None:

        def sep_ok(u, p):
            ok = np.ones(u.shape, dtype=bool) if case.signed else u >= 0
            # on the sweep the separation is the inverse of the pressure
            s = (p >= P_SWEEP[0]) & (p <= P_SWEEP[-1])
            back = np.asarray(law.pressure(u[s]), dtype=float)
            ok[s] &= np.abs(back / p[s] - 1) < 1e-8
            return ok

        inside = case.separation_domain(P_ALL)
        u = sweep(law.separation, P_ALL, inside, sep_ok, name, "p", key)
        if not case.signed:
            # high pressure -- small separation
            assert np.all(np.diff(u[: np.count_nonzero(inside[: P_SWEEP.size])]) <= 0), key
    if case.area_domain is not None:
        inside = case.area_domain(P_ALL)
        a = sweep(
            law.area_fraction, P_ALL, inside, lambda a, p: (a >= 0) & (a <= 1), name, "p", key
        )
        order = np.argsort(P_ALL[inside])
        assert np.all(np.diff(a[order]) >= 0), key  # more load, more contact
    if case.area_at_domain is not None:
        sweep(
            law.area_fraction_at, U_ALL, case.area_at_domain(U_ALL),
            lambda a, u: (a >= 0) & (a <= 1), name, "u", key,
        )  # fmt: skip


# ------------------------------------------ the case of the issue (H = 0.6)
def test_exponential_separation_never_negative(persson):
    """S1 spectrum with H = 0.6: ``p/E* = 0.32`` is far above ``beta E*`` (beta = 0.026),
    where the inverted asymptote ``(h_rms/alpha) ln(beta E*/p)`` is -1.17 h_rms."""
    ex = PerssonExponentialLaw.from_psd(_psd(0.6), E_STAR, 0.4)
    assert ex.beta == pytest.approx(0.0261, abs=5e-4)
    p = 0.32 * E_STAR
    assert H_RMS / ex.alpha * math.log(ex.beta * E_STAR / p) < -1.0 * H_RMS  # the old value
    with pytest.raises(ParameterError) as err:
        ex.separation(np.array([p]))
    msg = str(err.value)
    for part in ("persson-exponential", "p = 4.26667e+06 Pa", "p/E* = 0.32", "beta E* = "):
        assert part in msg, msg
    with pytest.raises(ParameterError, match="beta E"):
        ex.separation(np.array([1e3, p]))  # one bad entry rejects the call
    # the bound itself is the contact state u = 0, just below it u > 0
    top = ex.beta * E_STAR
    assert ex.separation(np.array([top]))[0] == 0.0
    assert ex.separation(np.array([top * (1 - 1e-9)]))[0] > 0.0
    with pytest.raises(ParameterError, match="beta E"):
        ex.separation(np.array([np.nextafter(top, np.inf)]))
    # the full relation is defined there: a small positive separation
    u_full = float(persson[0.6].separation(np.array([p]))[0])
    assert 0.0 < u_full < 0.1 * H_RMS


def test_inverses_at_the_edges_of_their_domains(persson):
    law = persson[0.8]
    tiny = np.finfo(float).tiny
    assert law.p_max == pytest.approx(float(law.pressure(np.array([tiny]))[0]), rel=1e-15)
    assert law.p_max > E_STAR  # 3.6 E* here, 39 E* for H = 0.6
    u = float(law.separation(np.array([law.p_max]))[0])
    assert 0.0 < u and u == pytest.approx(tiny, rel=1e-6)
    expect_domain_error(lambda: law.separation(np.array([law.p_max * 1.001])), "persson", "p")
    # denormal pressures: finite, very large separations (not inf)
    ex = law.exponential()
    for f in (law.separation, ex.separation):
        v = f(np.array([5e-324]))
        assert np.isfinite(v).all() and v[0] > 100 * H_RMS
    # GW / GT: A/A0 = 1 exactly at p_full, u_full
    for law2 in (
        GreenwoodWilliamson(5e10, 20e-6, 0.5e-6, E_STAR),
        GreenwoodWilliamson(5e10, 20e-6, 0.5e-6, E_STAR, "exponential"),
        GreenwoodTripp(5e10, 20e-6, 0.5e-6, E_STAR),
    ):
        assert law2.area_fraction_at(np.array([law2.u_full]))[0] == pytest.approx(1.0, rel=1e-12)
        assert law2.area_fraction(np.array([law2.p_full]))[0] == pytest.approx(1.0, rel=1e-9)
        expect_domain_error(
            lambda law2=law2: law2.area_fraction(np.array([law2.p_full * (1 + 1e-6)])),
            law2.name, "p",
        )  # fmt: skip
        expect_domain_error(
            lambda law2=law2: law2.area_fraction_at(np.array([law2.u_full - 1e-3 * law2.sigma])),
            law2.name, "u",
        )  # fmt: skip
    bgt = BushGibsonThomas(1e-6, 0.01, E_STAR)
    assert bgt.area_fraction(np.array([bgt.p_max]))[0] == pytest.approx(0.5, rel=1e-15)
    assert np.isfinite(bgt.separation(np.array([5e-324]))).all()
    expect_domain_error(lambda: bgt.separation(np.array([bgt.p_max])), bgt.name, "p")
    # the closed form: no inverse, finite for denormal u, validated parameters
    cf = persson[0.8].closed_form()
    with pytest.raises(ParameterError, match="no inverse"):
        cf.separation(np.array([1e3]))
    p = cf.pressure(np.array([5e-324, 1e-300]))
    assert np.all(np.isfinite(p)) and np.all(p > 0)
    with pytest.raises(ParameterError, match=r"c = -0\.1 is outside the allowed range"):
        type(cf)(cf.alpha, cf.beta, cf.m, -0.1, cf.a, cf.b, cf.e_star, cf.h_rms)


# --------------------------------------------------- S2 load fractions X(lambda)
def test_load_fractions_stay_in_their_domain():
    lam = np.concatenate((-U_POS[::-1] / H_RMS, [0.0], U_POS / H_RMS))
    for name, law in sorted(load_fraction.LAWS.items()):
        x = sweep(law, lam, lam >= 0, lambda x, _: (x >= 0) & (x <= 1), name, "lambda")
        assert x[0] == pytest.approx(1.0, rel=1e-15), name  # lambda = 0: all on the asperities
        assert np.all(np.diff(x) <= 0), name
    # F_n: pbdv returns NaN for very large arguments; F_n is below the smallest double there
    for n in (0.0, 1.0, 1.5, 2.5):
        v = gw_function(n, np.array([40.0, 41.0, 1e3, 1e10, 1e300]))
        assert np.all(v == 0.0)


# ------------------------------------------------------------- flow factors
@pytest.fixture(scope="module")
def emt() -> BruggemanFlowFactor:
    return BruggemanFlowFactor(_psd(0.8), E_STAR)


def test_flow_factors_stay_in_their_domain(emt):
    def unit(v, _):
        return (v >= 0) & (v <= 1)

    def nonneg(v, _):
        return v >= 0

    pc = PatirCheng(H_RMS)
    tab = emt.hermite_table()
    for f, valid in (
        (pc.pressure_factor, unit),
        (pc.shear_factor, nonneg),
        (pc.dpressure_factor_du, nonneg),
        (pc.dshear_factor_du, lambda v, _: np.ones(v.shape, bool)),
        (emt.pressure_factor, unit),
        (emt.dpressure_factor_du, nonneg),
        (emt.shear_factor, lambda v, _: v == 0),
        (tab, unit),
    ):
        name = getattr(f, "__self__", f).name
        sweep(f, U_ALL, U_ALL > 0, valid, name, "u")


def test_log_hermite_table_rejects_a_table_outside_0_1():
    s = np.array([0.0, 1.0])
    # end slope -2 makes the cubic overshoot to 1.16 inside the segment
    with pytest.raises(ParameterError, match=r"phi = 1\.16.*allowed range \[0, 1\]"):
        LogHermiteTable(s, [0.5, 0.95], [0.0, -2.0], H_RMS)
    # a negative first slope: phi_0 (H/H_0)^k would grow without bound as u -> 0
    with pytest.raises(ParameterError, match=r"dphi/ds = -0\.1"):
        LogHermiteTable(s, [0.5, 0.6], [-0.1, 0.1], H_RMS)
    ok = LogHermiteTable(s, [0.5, 0.95], [0.1, 0.2], H_RMS)
    assert 0.0 < ok(np.array([1e-300]))[0] <= 0.5


# -------------------------------------------------------------- Persson theory
def test_persson_theory_area_and_separation(persson):
    th = persson[0.6].theory
    a = sweep(th.area_fraction, P_ALL, P_ALL >= 0, lambda a, _: (a >= 0) & (a <= 1),
              "persson-theory", "p")  # fmt: skip
    assert a[0] > 0 and np.all(np.diff(a[: P_SWEEP.size]) > 0)
    u = sweep(th.mean_separation, P_ALL, P_ALL > 0, lambda u, _: u >= 0,
              "persson-theory", "pressure")  # fmt: skip
    assert np.all(np.diff(u[: P_SWEEP.size]) < 0)
