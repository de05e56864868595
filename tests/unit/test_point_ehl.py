"""The point-contact soft-EHL reference (numpy only): its elasticity against Hertz,
its Jacobian against finite differences, its balances, and its convergence."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.verification.point_ehl import (
    PointEHL,
    PointEHLParameters,
    richardson,
    speed_continuation,
)


def test_influence_coefficients_give_the_hertz_displacement():
    """A Hertz pressure on the grid (mirror cells included) deflects the half-space by
    ``pi p_H (2 a^2 - r^2) / (4 a E*)`` inside the contact (Johnson eq 3.41): measured
    0.14 % (10 cells per radius) and 0.07 % (15) of the central deflection, the error of
    sampling the pressure's square-root edge on square cells."""
    m = PointEHL(PointEHLParameters(cells_per_radius=10, sphere=False))
    a, p0, e_star = m.a, m.p_scale, m.params.e_star
    r2 = m.x**2 + m.y**2
    hertz = p0 * np.sqrt(np.clip(1.0 - r2 / a**2, 0.0, None))
    w = m.kernel @ hertz
    exact = math.pi * p0 * (2 * a * a - r2) / (4 * a * e_star)
    inside = r2 < (0.9 * a) ** 2
    assert np.abs(w - exact)[inside].max() < 3e-3 * exact.max()
    assert 2 * m.area * hertz.sum() == pytest.approx(m.params.load, rel=5e-3)


@pytest.mark.parametrize("cavitation", ["none", "reynolds"])
def test_jacobian_matches_finite_differences(cavitation):
    m = PointEHL(PointEHLParameters(cells_per_radius=4, extent=2.0, cavitation=cavitation))
    p, u0 = m.hertz_guess(1.0)
    h = m.gap(p, u0)
    film = m._film_diagonal(h, 1.0) * m.p_scale
    z = np.concatenate([p / m.p_scale, [u0 / h.min()]])
    _res, jac, _ = m._system(z, 1.0, film, float(h.min()))
    # the rows whose min(p, r) picks the other branch within the step are kinks
    smooth = np.ones(m.n + 1, dtype=bool)
    if cavitation == "reynolds":
        r, _, _ = m._fluxes(p, h, 1.0)
        smooth[: m.n] = np.abs(r / film - p / m.p_scale) > 1e-4
    fd = np.zeros_like(jac)
    for k in range(z.size):
        e = np.zeros_like(z)
        e[k] = 1e-7
        up, _, _ = m._system(z + e, 1.0, film, float(h.min()), jacobian=False)
        down, _, _ = m._system(z - e, 1.0, film, float(h.min()), jacobian=False)
        fd[:, k] = (up - down) / 2e-7
    assert np.abs(fd - jac)[smooth].max() < 1e-6 * np.abs(jac).max()


def test_converged_point_balances_load_and_mass():
    m = PointEHL(PointEHLParameters(cells_per_radius=8, extent=2.0, load=0.13))
    r = m.solve(1.0)
    assert r.normal_load == pytest.approx(0.13, rel=1e-9)
    assert r.mass_balance_error < 1e-6
    assert r.p.min() >= 0.0 and 0.0 < r.cavitation_fraction < 1.0
    assert 0.0 < r.h_min < r.h_central and r.x_cavitation > 0.0
    parts = r.mu_couette + r.mu_poiseuille
    assert parts == pytest.approx(r.mu, rel=1e-12)


def test_richardson_is_second_order_and_continuation_walks_down():
    """Two grids and their Richardson value on the S1 ball at a tenth of its load,
    walking down 1 -> 0.3 m/s: the finer grid moves h_central towards the
    extrapolated value, which lies beyond it (monotone convergence)."""
    out = {}
    for n in (6, 9):
        m = PointEHL(PointEHLParameters(cells_per_radius=n, extent=2.0, load=0.13))
        out[n] = speed_continuation(m, [1.0, 0.3])
    for k in range(2):
        ext = richardson(out[6][k], out[9][k], ratio=1.5)
        c, f = out[6][k].h_central, out[9][k].h_central
        assert abs(ext["h_central"] - f) < abs(f - c)
        assert out[9][k].speed == [1.0, 0.3][k]


def test_bad_parameters_are_refused():
    with pytest.raises(ParameterError, match="cavitation"):
        PointEHLParameters(cavitation="jfo")
    with pytest.raises(ParameterError, match="extent"):
        PointEHLParameters(extent=6.0, load=1e3)
