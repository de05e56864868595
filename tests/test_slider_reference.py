"""The 1D slider reference (dolfinx_seal.verification.slider) checked on its own:
closed forms, flux conservation, JFO vs Reynolds condition, and two independent
methods (semi-analytic zones vs a fine finite-volume LCP) against each other."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.verification.martin import martin_solution
from dolfinx_seal.verification.slider import (
    SliderOperating,
    fv_jfo_lcp,
    fv_reynolds_lcp,
    jfo_solution,
    linear_gap,
    parabolic_gap,
    pocket_slider_benchmark,
    reynolds_condition_solution,
    textured_gap,
    textured_slider_case,
)

# cylinder-on-plane gap: R = 10 mm, h_min = 2 um, inlet 5 ell upstream, L = 10 ell
R, H_MIN, X_IN = 0.01, 2e-6, 5.0
ELL = math.sqrt(2.0 * R * H_MIN)


def _parabola():
    return parabolic_gap(10.0 * ELL, H_MIN, R, X_IN * ELL)


def _zone_flux(gap, op, x0, x1, p0, p1):
    """Flux of a full film from p(x0) = p0 to p(x1) = p1, by plain quad (breakpoints
    passed as points): Q = (12 eta U_m int h^-2 - (p1 - p0)) / (12 eta int h^-3)."""
    pts = [b for b in gap.breakpoints if x0 < b < x1] or None
    i2 = quad(lambda x: gap(x) ** -2, x0, x1, points=pts, epsabs=0, epsrel=1e-13, limit=200)[0]
    i3 = quad(lambda x: gap(x) ** -3, x0, x1, points=pts, epsabs=0, epsrel=1e-13, limit=200)[0]
    k = 12.0 * op.viscosity
    return (k * op.speed * i2 - (p1 - p0)) / (k * i3)


# ------------------------------------------------------- (a) no cavitation
def test_linear_slider_against_closed_form():
    """Plane converging slider, p_in = p_out = 0: Q = 2 U_m h_i h_o / (h_i + h_o),
    p = 12 eta U_m L (h_i - h)(h - h_o) / ((h_i^2 - h_o^2) h^2),
    W = 12 eta U_m L^2 / (h_o^2 (K - 1)^2) [ln K - 2 (K - 1)/(K + 1)], K = h_i / h_o."""
    L, hi, ho = 4e-3, 4e-6, 2e-6
    op = SliderOperating(speed=0.5, viscosity=0.1)
    gap = linear_gap(L, hi, ho)
    K = hi / ho
    q = 2.0 * op.speed * hi * ho / (hi + ho)
    w = 12 * op.viscosity * op.speed * L**2 / (ho**2 * (K - 1) ** 2)
    w *= math.log(K) - 2 * (K - 1) / (K + 1)
    x = np.linspace(0.0, L, 101)
    h = gap(x)
    p = 12 * op.viscosity * op.speed * L * (hi - h) * (h - ho) / ((hi**2 - ho**2) * h**2)
    for sol in (jfo_solution(gap, op), reynolds_condition_solution(gap, op)):
        assert sol.x_rupture is None and sol.x_reformation is None
        assert sol.flux == pytest.approx(q, rel=1e-12, abs=0)
        assert sol.load == pytest.approx(w, rel=1e-10)
        np.testing.assert_allclose(sol.pressure(x), p, rtol=0, atol=1e-11 * p.max())
        np.testing.assert_array_equal(sol.theta(x), 1.0)
        # the peak is where U_m h = Q, i.e. h = 2 h_i h_o / (h_i + h_o)
        assert float(gap(sol.x_p_max)) == pytest.approx(2 * hi * ho / (hi + ho), rel=1e-9, abs=0)
        assert sol.p_max == pytest.approx(p.max(), rel=1e-4)


# -------------------------------------------------- (b) flux conservation
def test_benchmark_jfo_against_hand_solution_and_flux_conservation():
    """Pocketed pad (Almqvist et al. 2014), JFO.  Piecewise-constant gap, so by hand:
    inlet land from p_in to 0 at the pocket edge a gives Q = U_m h0 + h0^3 p_in/(12 eta a);
    the starved pocket (theta = Q/(U_m h1)) re-forms at x_r where the film from
    p(x_r) = 0 through the rest of the pocket and the outlet land ends at p_out."""
    gap, op = pocket_slider_benchmark()
    a, b, L, h0, h1 = 2e-3, 3e-3, 20e-3, 1e-6, 10e-6
    c, k, um = L - a - b, 12 * op.viscosity, op.speed
    q = um * h0 + h0**3 * op.p_inlet / (k * a)
    g_pocket = k * (um * h1 - q) / h1**3  # p' in the re-formed pocket (> 0)
    g_land = k * (um * h0 - q) / h0**3  # p' on the outlet land (< 0)
    xr = a + b - (op.p_outlet - g_land * c) / g_pocket
    p5 = g_pocket * (a + b - xr)
    load = op.p_inlet * a / 2 + p5 * (a + b - xr) / 2 + (p5 + op.p_outlet) * c / 2

    sol = jfo_solution(gap, op)
    assert sol.flux == pytest.approx(q, rel=1e-13, abs=0)
    assert sol.x_rupture == pytest.approx(a, abs=1e-15)
    assert sol.x_reformation == pytest.approx(xr, rel=1e-12)
    assert a < sol.x_reformation < a + b  # reformation inside the pocket
    assert sol.load == pytest.approx(load, rel=1e-11)
    assert sol.p_max == pytest.approx(p5, rel=1e-11)

    # one flux: the upstream and downstream full-film zones, each from its own
    # boundary values by plain quadrature, carry the same Q
    q_up = _zone_flux(gap, op, 0.0, sol.x_rupture, op.p_inlet, 0.0)
    q_down = _zone_flux(gap, op, sol.x_reformation, L, 0.0, op.p_outlet)
    assert sol.fluxes[0] == sol.fluxes[1]
    assert q_up == pytest.approx(sol.flux, rel=1e-12, abs=0)
    assert q_down == pytest.approx(sol.flux, rel=1e-12, abs=0)

    # cavity: p = 0 and U_m h theta = Q; theta just past the rupture is Q / (U_m h1)
    xcav = np.linspace(sol.x_rupture, sol.x_reformation, 50)[1:-1]
    np.testing.assert_array_equal(sol.pressure(xcav), 0.0)
    np.testing.assert_allclose(um * gap(xcav) * sol.theta(xcav), q, rtol=1e-14)
    assert float(sol.theta(a + 1e-9)) == pytest.approx(q / (um * h1), rel=1e-14)
    assert float(sol.theta(a + 1e-9)) < 0.11  # a starved pocket
    # reformation front: theta jumps to 1 and the mass flux is continuous,
    # U_m h1 theta^- = U_m h1 - h1^3/(12 eta) p'^+ (p' by a one-sided difference)
    d = 1e-7
    theta_m = float(sol.theta(xr - d))
    dp = (float(sol.pressure(xr + d)) - float(sol.pressure(xr))) / d
    assert float(sol.theta(xr + d)) == 1.0
    assert um * h1 * theta_m == pytest.approx(um * h1 - h1**3 / k * dp, rel=1e-9)
    # boundary values and p >= 0
    _, p, _ = sol.sample(4001)
    assert p[0] == pytest.approx(op.p_inlet) and p[-1] == pytest.approx(op.p_outlet)
    assert np.all(p >= 0.0)


def test_smooth_reformation_conserves_mass():
    """Parabolic gap with an outlet pressure: rupture at a smooth point (p = p' = 0,
    U_m h = Q), reformation in the divergent part, one flux, continuous mass flux."""
    gap = _parabola()
    op = SliderOperating(speed=0.5, viscosity=0.1, p_inlet=0.0, p_outlet=0.05e6)
    sol = jfo_solution(gap, op)
    xc, xr, q = sol.x_rupture, sol.x_reformation, sol.flux
    assert X_IN * ELL < xc < xr < gap.length
    assert op.speed * float(gap(xc)) == pytest.approx(q, rel=1e-10, abs=0)
    assert float(sol.dpdx(xc - 1e-12)) == pytest.approx(0.0, abs=1e-6 * sol.p_max / ELL)
    assert _zone_flux(gap, op, 0.0, xc, 0.0, 0.0) == pytest.approx(q, rel=1e-10, abs=0)
    assert _zone_flux(gap, op, xr, gap.length, 0.0, op.p_outlet) == pytest.approx(
        q, rel=1e-10, abs=0
    )
    # theta continuous at rupture (= 1), < 1 before the reformation front
    d = 1e-14  # [m]; |h'| d / h ~ 4e-11 here
    assert float(sol.theta(xc + d)) == pytest.approx(1.0, rel=1e-9)
    assert float(sol.theta(xr - d)) < 0.9
    hr = float(gap(xr))
    dp = float(sol.dpdx(xr + d))
    flux_plus = op.speed * hr - hr**3 / (12 * op.viscosity) * dp
    assert flux_plus == pytest.approx(op.speed * hr * float(sol.theta(xr - d)), rel=1e-9, abs=0)


# ------------------------------------------------- (c) JFO vs Reynolds
def test_parabola_to_outlet_jfo_equals_reynolds_equals_martin():
    """Cavitation to the outlet, no reformation: both models coincide, and match the
    independent Martin reference (closed-form antiderivatives) rescaled to SI."""
    gap = _parabola()
    op = SliderOperating(speed=0.5, viscosity=0.1)
    jfo = jfo_solution(gap, op)
    rey = reynolds_condition_solution(gap, op)
    assert jfo.x_reformation is None and rey.x_reformation is None
    assert jfo.x_rupture == pytest.approx(rey.x_rupture, rel=1e-14)
    assert jfo.flux == pytest.approx(rey.flux, rel=1e-14, abs=0)
    assert jfo.load == pytest.approx(rey.load, rel=1e-14)
    x = np.linspace(0.0, gap.length, 501)
    np.testing.assert_allclose(jfo.pressure(x), rey.pressure(x), rtol=0, atol=1e-12 * jfo.p_max)
    np.testing.assert_allclose(jfo.theta(x), rey.theta(x), rtol=1e-14)

    m = martin_solution(X_IN)
    p_ref = 12.0 * op.viscosity * op.speed * ELL / H_MIN**2
    assert jfo.x_rupture == pytest.approx(X_IN * ELL + m.x_cavitation * ELL, rel=1e-10)
    assert jfo.flux == pytest.approx(op.speed * H_MIN * m.flux, rel=1e-10, abs=0)
    assert jfo.load == pytest.approx(p_ref * ELL * m.load, rel=1e-9)
    assert jfo.p_max == pytest.approx(p_ref * m.p_max, rel=1e-10)


@pytest.mark.parametrize("case", ["benchmark", "own"])
def test_pocket_jfo_and_reynolds_differ(case):
    """With a reformation front the models differ: JFO starves the pocket (cavity from
    the divergent edge to x_r inside the pocket, one flux), the Reynolds condition
    re-pressurises the whole pocket (p = 0 only at the edge, the flux jumps up)."""
    gap, op = pocket_slider_benchmark() if case == "benchmark" else textured_slider_case()
    a, e = gap.breakpoints
    jfo = jfo_solution(gap, op)
    rey = reynolds_condition_solution(gap, op)
    assert jfo.x_rupture == rey.x_rupture == a
    assert jfo.flux == pytest.approx(rey.flux, rel=1e-14, abs=0)  # same inlet zone
    assert a < jfo.x_reformation < e
    assert rey.x_reformation == a  # zero-length cavity
    assert rey.fluxes[1] > rey.fluxes[0]  # Reynolds creates mass at the edge
    assert jfo.load < 0.3 * rey.load and jfo.p_max < 0.35 * rey.p_max
    xp = np.linspace(a, e, 41)[1:-1]
    assert np.all(rey.pressure(xp) > 0.0)
    assert np.any(jfo.pressure(xp) == 0.0)
    if case == "benchmark":
        # Reynolds by hand: pocket pressure rises linearly from 0 to p_m at x = e,
        # flux continuity into the outlet land fixes p_m
        h0, h1, c = 1e-6, 10e-6, gap.length - e
        k0, k1 = h0**3 / (12 * op.viscosity), h1**3 / (12 * op.viscosity)
        p_m = (op.speed * (h1 - h0) + k0 * op.p_outlet / c) / (k1 / (e - a) + k0 / c)
        load = op.p_inlet * a / 2 + p_m * (e - a) / 2 + (p_m + op.p_outlet) * c / 2
        assert rey.p_max == pytest.approx(p_m, rel=1e-11)
        assert rey.load == pytest.approx(load, rel=1e-11)
        assert rey.fluxes[1] == pytest.approx(op.speed * h1 - k1 * p_m / (e - a), rel=1e-11, abs=0)


# ------------------------------------------- (d) two independent methods
CASES = {
    "linear": lambda: (linear_gap(4e-3, 4e-6, 2e-6), SliderOperating(0.5, 0.1)),
    "parabola_to_outlet": lambda: (_parabola(), SliderOperating(0.5, 0.1)),
    "parabola_reforming": lambda: (_parabola(), SliderOperating(0.5, 0.1, 0.0, 0.05e6)),
    "benchmark": pocket_slider_benchmark,
    "own": textured_slider_case,
}


@pytest.mark.parametrize("model", ["jfo", "reynolds"])
@pytest.mark.parametrize("case", list(CASES))
def test_semi_analytic_against_fine_finite_volume_lcp(case, model):
    """Semi-analytic zones vs a 1e5-cell finite-volume LCP (cell-midpoint gap, no
    quadrature or free-boundary logic shared): loads and pressures to 1e-7 relative,
    free boundaries to one cell, fluxes of the film zones to 1e-8."""
    gap, op = CASES[case]()
    n = 100_000
    dx = gap.length / n
    sol = (jfo_solution if model == "jfo" else reynolds_condition_solution)(gap, op)
    fv = (fv_jfo_lcp if model == "jfo" else fv_reynolds_lcp)(gap, op, n)
    assert fv.load == pytest.approx(sol.load, rel=1e-7)
    np.testing.assert_allclose(fv.p, sol.pressure(fv.x), rtol=0, atol=1e-7 * sol.p_max)
    for a_, b_ in ((sol.x_rupture, fv.x_rupture), (sol.x_reformation, fv.x_reformation)):
        assert (a_ is None) == (b_ is None)
        if a_ is not None:
            assert abs(a_ - b_) <= 1.01 * dx
    # fluxes: cells in the film zones carry the zone fluxes
    xm = 0.5 * (fv.x[:-1] + fv.x[1:])
    for z in sol.zones:
        inside = (xm > z.x_start + 2 * dx) & (xm < z.x_end - 2 * dx)
        np.testing.assert_allclose(fv.flux[inside], z.flux, rtol=1e-8)
    if model == "jfo":
        # one flux everywhere; theta away from the fronts.  The upwind theta of node
        # i is the film fraction carried by cell i, so it is compared at the midpoint
        # of that cell (at the node itself it is only O(dx) accurate in a smooth gap)
        np.testing.assert_allclose(fv.flux, sol.flux, rtol=1e-8)
        fronts = [v for v in (sol.x_rupture, sol.x_reformation) if v is not None]
        away = np.all([np.abs(fv.x[:-1] - f) > 2 * dx for f in fronts], axis=0)
        np.testing.assert_allclose(fv.theta[:-1][away], sol.theta(xm[away]), rtol=1e-8)


# ------------------------------------------------------------ validation
def test_parameter_validation():
    with pytest.raises(ParameterError, match="speed"):
        SliderOperating(speed=0.0)
    with pytest.raises(ParameterError, match="p_inlet"):
        SliderOperating(p_inlet=-1.0)
    with pytest.raises(ParameterError, match="x_min"):
        parabolic_gap(1e-3, 1e-6, 1e-2, 2e-3)
    with pytest.raises(ParameterError, match="pockets"):
        textured_gap(5e-3, 1e-6, 1e-6, [(1e-3, 2e-3), (1.5e-3, 3e-3)], 1e-6)
    with pytest.raises(ParameterError, match="h_outlet"):
        linear_gap(1e-3, 1e-6, -1e-6)


def test_two_cavities_are_refused_not_guessed():
    """Two pockets in a parallel slider: JFO needs two cavities -> SolverError (the FV
    LCP shows two starved pockets)."""
    gap = textured_gap(5e-3, 5e-6, 5e-6, [(1e-3, 1.8e-3), (3e-3, 3.8e-3)], 5e-6)
    op = SliderOperating(0.5, 0.1, 0.2e6, 0.0)
    with pytest.raises(SolverError):
        jfo_solution(gap, op)
    fv = fv_jfo_lcp(gap, op, 20_000)
    starts = np.nonzero(np.diff((fv.theta < 1.0).astype(int)) == 1)[0]
    assert starts.size == 2
