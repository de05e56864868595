"""The independent soft-EHL line-contact reference (verification/line_ehl.py), numpy only.

Checked against: Hertz line contact (dry), the rigid-cylinder Martin solution
(Reynolds condition) and the analytic full-Sommerfeld pressure of a rigid
cylinder, discrete mass conservation, finite differences of the Jacobian, and
the parameter validation.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from dolfinx_seal.contact.persson import PerssonExponentialLaw
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.verification.line_ehl import LineEHL, LineEHLParameters, speed_continuation
from dolfinx_seal.verification.martin import martin_solution
from dolfinx_seal.verification.martin import pressure as martin_pressure

# Rigid-cylinder set-up: R, eta, sliding speed U (mean velocity U/2), and the gap
# at x = 0; lengths in units of b = (2 R h0)^(1/2), so the Martin inlet is at X = -10.
R, ETA, U, H0 = 0.01, 0.1, 0.01, 1e-6
B = math.sqrt(2.0 * R * H0)
P_REF = 24.0 * ETA * R * (U / 2) / (H0 * B)  # martin.py: p = P_REF * P(X)
RIGID = 1e20  # E* [Pa]: elastic deflection ~ 1e-14 of the gap (1e15 gave 1e-9)


def s1_law(e_star: float) -> PerssonExponentialLaw:
    """S1's asymptotic Persson law for h_rms = 1 um, D_f = 2.2 (alpha, beta and the rms
    slope of the project's spectrum, rounded)."""
    return PerssonExponentialLaw(2.35, 0.0201, e_star, 1e-6, rms_slope=0.30)


# ---------------------------------------------------------------------------- Hertz
def test_dry_hertz_line_contact():
    """No sliding (no film) and a nearly rigid-plastic 'stiff' law, p = E* exp(-u/l) with
    l = 1e-4 a_H^2/R: the pressure must be Hertz's.

    Tolerance 1e-3 on the half-width (2 <x^2>^(1/2), = a_H for the ellipse) and on the
    peak.  Measured errors at N = 200 / 400 / 800: peak 6.9e-4 / 3.0e-4 / 1.4e-4 (grid
    error of the piecewise-constant pressure, first order in dx = 0.04 a_H at N = 400);
    half-width 4.0e-4 / 1.9e-4 / 1.8e-4, the floor being the law, which rounds the
    edges over (l R / a^2)^(2/3) a = 0.2 % of a (with l = 1e-3 a^2/R it was 1.8e-3).
    """
    pr = LineEHLParameters(n_cells=400, asperity_shear=0.0)
    a_h, p_h = pr.hertz_half_width, pr.hertz_peak_pressure
    law = PerssonExponentialLaw(1.0, 1.0, pr.e_star, 1e-4 * a_h**2 / pr.radius)
    model = LineEHL(pr, law)
    res = model.solve(0.0)
    p, x, dx = res.p_cont, res.x, model.dx
    m0 = float(np.sum(p) * dx)
    half_width = 2.0 * math.sqrt(float(np.sum(p * x * x) * dx) / m0)
    assert res.load_fluid == 0.0
    assert m0 == pytest.approx(pr.load, rel=1e-10)  # force control, to the tolerance
    assert abs(float(np.sum(p * x) * dx) / m0) < 1e-6 * a_h  # symmetric
    assert half_width == pytest.approx(a_h, rel=1e-3)
    assert p.max() == pytest.approx(p_h, rel=1e-3)


# ---------------------------------------------------------------------- rigid limit
def test_rigid_cylinder_reynolds_matches_martin():
    """E* = 1e15 and no asperity contact: the film alone carries the Martin load of a
    rigid cylinder with the Reynolds condition.  Prescribe the load of the gap H0
    (inlet at X = -10, martin_solution(10)) and find H0 back.

    Tolerances: the scheme is second order (measured |u0/H0 - 1| = 4.9e-3, 1.2e-3,
    2.6e-4 at N = 200, 400, 800), so 3e-3 at N = 400; the peak pressure and the
    flux converge alike (1.6e-4 and 8e-4 at N = 400): 2e-3.  The free boundary is
    captured to O(dx): within two cells.
    """
    ref = martin_solution(10.0)
    load = P_REF * B * ref.load
    pr = LineEHLParameters(
        radius=R, load=load, e_star=RIGID, viscosity=ETA, n_cells=400, length_scale=B
    )
    model = LineEHL(pr, None)
    res = model.solve(U)
    assert res.u0 == pytest.approx(H0, rel=3e-3)
    assert res.h_central == pytest.approx(H0, rel=3e-3)
    assert res.min_fluid_pressure >= 0.0
    assert res.max_fluid_pressure == pytest.approx(P_REF * ref.p_max, rel=2e-3)
    assert res.flux == pytest.approx(0.5 * U * H0 * ref.flux, rel=2e-3, abs=0)
    assert abs(res.x_cavitation - B * ref.x_cavitation) <= 2.0 * model.dx
    assert res.mass_balance_error < 1e-9


@pytest.mark.parametrize("upstream, downstream", [(8.0, 8.0), (10.0, 6.0)])
def test_rigid_cylinder_full_sommerfeld(upstream, downstream):
    """Full Sommerfeld, rigid cylinder at a fixed gap H0: the pressure is the analytic
    P(X) = int_{-X_in}^X (H - H_q)/H^3 with H = 1 + X^2 and the flux H_q set by
    P(X_out) = 0 (martin.pressure with 1 + x_c^2 = H_q).  A symmetric domain carries
    no load (the antisymmetry of p behind S1's remark that a rigid cylinder with no
    cavitation cannot carry load), so the force-controlled problem has no solution:
    it must raise, not return NaN.

    Tolerances: max pressure error 2.5e-3 of the peak (second order, measured 1.1e-3
    at N = 400, 4.5e-3 at N = 200); the discrete solution on a symmetric grid is exactly
    antisymmetric, so its load vanishes to the solver tolerance (1e-12 here).
    """
    pr = LineEHLParameters(
        radius=R, load=10.0, e_star=RIGID, viscosity=ETA, cavitation="none", n_cells=400,
        length_scale=B, upstream=upstream, downstream=downstream, fixed_approach=H0, tol=1e-12,
    )  # fmt: skip
    model = LineEHL(pr, None)
    res = model.solve(U)

    def h(s: float) -> float:
        return 1.0 + s * s

    x_in, x_out = upstream, downstream
    i2 = quad(lambda s: h(s) ** -2, -x_in, x_out, epsabs=0, epsrel=1e-13)[0]
    i3 = quad(lambda s: h(s) ** -3, -x_in, x_out, epsabs=0, epsrel=1e-13)[0]
    x_c = math.sqrt(i2 / i3 - 1.0)
    exact = P_REF * np.array([martin_pressure(xx / B, x_in, x_c) for xx in res.x])
    peak = float(np.max(np.abs(exact)))
    assert float(np.max(np.abs(res.p_fluid - exact))) < 2.5e-3 * peak
    assert res.min_fluid_pressure < -0.5 * peak  # sub-ambient pressures are kept
    if upstream == downstream:
        assert abs(res.normal_load) < 1e-10 * peak * (x_in + x_out) * B
        forced = LineEHLParameters(
            radius=R, load=10.0, e_star=RIGID, viscosity=ETA, cavitation="none", n_cells=100,
            length_scale=B, upstream=upstream, downstream=downstream, max_iter=20,
        )  # fmt: skip
        with pytest.raises(RuntimeError, match="speed"):
            LineEHL(forced, None).solve(U)


# ------------------------------------------------------------------ conservation
@pytest.mark.parametrize("cavitation", ["reynolds", "none"])
def test_mass_conservation_and_load_balance(cavitation):
    """S1 cylinder (E = 10 MPa) at 0.0316 m/s, N = 200: the face fluxes of the full film
    are equal.  The scaled film row is r_i / (D_i p_s) with D_i = dr_i/dp_i, so at the
    tolerance each cell balances to tol * D_i p_s; summed over the film that bounds
    |q - q_mean| by tol * sum(D_i) p_s (a loose bound: the quadratic Newton ends far
    below it, ~1e-12 relative).  The load balances to tol * F.
    """
    pr = LineEHLParameters(e_star=10e6 / 0.75, n_cells=200, cavitation=cavitation)
    model = LineEHL(pr, s1_law(pr.e_star))
    (res,) = speed_continuation(model, [0.0316])
    bound = pr.tol * float(np.sum(model.film_diagonal(res.h))) * model.p_scale / abs(res.flux)
    assert res.mass_balance_error <= min(bound, 1e-8)
    assert res.normal_load == pytest.approx(pr.load, rel=pr.tol)
    assert res.residual_norm <= pr.tol
    assert res.fluid_load_fraction > 0.9  # mostly hydrodynamic at this speed
    assert res.mu == pytest.approx(res.mu_asperity + res.mu_couette + res.mu_poiseuille)
    if cavitation == "reynolds":
        assert res.min_fluid_pressure >= 0.0  # cavitated cells are reported as exactly 0
        assert res.cavitation_fraction > 0.1
        # the film ruptures with p = dp/dx = 0, so q = U h(x_c) / 2: the gap 2 q / U lies
        # between those of the last full-film and the first cavitated cell
        i = int(np.searchsorted(res.x, res.x_cavitation))  # first cavitated cell
        assert res.h[i - 1] <= 2.0 * res.flux / 0.0316 <= res.h[i]
    else:
        assert res.min_fluid_pressure < 0.0


def test_continuation_is_path_independent():
    """The same speed reached upwards and downwards gives the same solution (unique
    solution, converged to tolerance): h_min and mu agree to 1e-7 relative."""
    pr = LineEHLParameters(e_star=10e6 / 0.75, n_cells=100)
    model = LineEHL(pr, s1_law(pr.e_star))
    down = speed_continuation(model, [0.1, 0.01])
    up = speed_continuation(model, [0.01, 0.1])
    for a, b in zip(down, up[::-1], strict=True):
        assert a.speed == b.speed
        assert a.h_min == pytest.approx(b.h_min, rel=1e-7, abs=0)
        assert a.mu == pytest.approx(b.mu, rel=1e-7)


# ---------------------------------------------------------------------- Jacobian
@pytest.mark.parametrize("cavitation", ["reynolds", "none"])
@pytest.mark.parametrize("with_law", [True, False])
def test_jacobian_matches_finite_differences(cavitation, with_law):
    """Analytic dense Jacobian vs central differences at a perturbed (non-solution) state.

    Step 1e-7 in the scaled unknowns: truncation ~1e-14, rounding ~1e-16/1e-7 of
    the row size, so 1e-6 relative to the largest entry of each row.  Rows of the
    Reynolds condition whose two min() arguments are within 1e-5 are skipped (the
    difference would straddle the kink).
    """
    pr = LineEHLParameters(n_cells=30, cavitation=cavitation, asperity_shear=0.0)
    model = LineEHL(pr, s1_law(pr.e_star) if with_law else None)
    speed = 0.01
    p, h, u0 = model.hertz_guess(speed)
    rng = np.random.default_rng(1)
    p = p + 0.1 * model.p_scale * rng.standard_normal(p.size)
    h = h * (1.0 + 0.1 * rng.random(h.size))
    scales = model.scales(h)
    z = model.pack(p, h, u0, scales.gap)
    _, jac = model.system(z, speed, scales)
    assert jac is not None
    fd = np.empty_like(jac)
    eps = 1e-7
    for k in range(z.size):
        e = np.zeros_like(z)
        e[k] = eps * max(1.0, abs(z[k]))
        plus = model.system(z + e, speed, scales, jacobian=False)[0]
        minus = model.system(z - e, speed, scales, jacobian=False)[0]
        fd[:, k] = (plus - minus) / (2.0 * e[k])
    rows = np.ones(z.size, dtype=bool)
    if cavitation == "reynolds":
        rs = np.diff(model._faces(p, h, speed).q) / scales.film  # the film row's r / (D p_s)
        rows[: model.n] = np.abs(rs - p / model.p_scale) > 1e-5
    err = np.abs(jac - fd)[rows] / np.abs(jac[rows]).max(axis=1, keepdims=True)
    assert err.max() < 1e-6


# ---------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "field, value",
    [
        ("radius", -0.01),
        ("load", 0.0),
        ("e_star", float("nan")),
        ("viscosity", 0.0),
        ("asperity_shear", -1.0),
        ("cavitation", "jfo"),
        ("couette", "downwind"),
        ("n_cells", 8),
        ("n_cells", 100.5),
        ("upstream", 0.5),
        ("downstream", 200.0),
        ("length_scale", -1e-4),
        ("fixed_approach", 0.0),
        ("tol", 0.1),
        ("max_iter", 0),
    ],
)
def test_bad_parameters_raise_parameter_error(field, value):
    with pytest.raises(ParameterError, match=field):
        LineEHLParameters(**{field: value})


def test_bad_speeds_raise_parameter_error():
    pr = LineEHLParameters(n_cells=50)
    model = LineEHL(pr, s1_law(pr.e_star))
    with pytest.raises(ParameterError, match="speed"):
        model.solve(-1.0)
    with pytest.raises(ParameterError, match="speeds"):
        speed_continuation(model, [0.01, -0.1])
    with pytest.raises(ParameterError, match="speed = 0"):
        LineEHL(pr, None).solve(0.0)


def test_failed_solve_raises_runtime_error():
    """Too few Newton iterations: a RuntimeError naming the speed, never NaNs."""
    pr = LineEHLParameters(n_cells=50, max_iter=1)
    model = LineEHL(pr, s1_law(pr.e_star))
    with pytest.raises(RuntimeError, match=r"speed 0\.1 m/s.*1 iterations"):
        model.solve(0.1)
