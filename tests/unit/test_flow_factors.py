"""Flow factors: Patir-Cheng fits and the Persson-Bruggeman effective medium."""

from __future__ import annotations

import numpy as np
import pytest

from dolfinx_seal.contact import BruggemanFlowFactor, PatirCheng
from dolfinx_seal.contact.flow_factors import bruggeman_conductivity
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.roughness import SelfAffinePSD

GH = np.polynomial.hermite_e.hermegauss(40)


def gauss_classes(mean: float, sd: float) -> tuple[np.ndarray, np.ndarray]:
    z, w = GH
    return np.abs(mean + sd * z)[None, :], w / w.sum()


def test_bruggeman_exact_limits():
    # one class of equal separations: s = u0^3 exactly
    s = bruggeman_conductivity(0.0, [1.0], np.full((1, 3), 2e-6), np.ones(3) / 3)
    assert s == pytest.approx(8e-18, rel=1e-11, abs=0)
    # 2D two-phase mixture with a fraction f of insulator: s = (1 - 2 f) sigma_1
    for f in (0.1, 0.3, 0.45):
        s = bruggeman_conductivity(f, [1.0 - f], np.full((1, 1), 1e-6), np.ones(1))
        assert s == pytest.approx((1 - 2 * f) * 1e-18, rel=1e-10, abs=0)
    # percolation threshold of 2D EMT: no flow once half the area is in contact
    assert bruggeman_conductivity(0.5, [0.5], np.full((1, 1), 1e-6), np.ones(1)) == 0.0


def test_bruggeman_tripp_limit():
    """Gaussian gaps, sd/mean = r small: s/u^3 = 1 - (3/2) r^2 + O(r^4) (Tripp 1983).

    The remainder must shrink as r^4: halving r divides it by ~16.
    """
    err = []
    for r in (0.025, 0.05, 0.1):
        u, w = gauss_classes(1e-6, r * 1e-6)
        err.append(abs(bruggeman_conductivity(0.0, [1.0], u, w) / 1e-18 - (1 - 1.5 * r**2)))
    assert err[2] < 1e-3
    for a, b in zip(err[1:], err[:-1], strict=True):
        assert 13.0 < a / b < 19.0


def test_patir_cheng():
    pc = PatirCheng(1e-6)
    h = np.array([0.5, 1.0, 3.0, 6.0])
    np.testing.assert_allclose(
        pc.pressure_factor(h * 1e-6), 1 - 0.9 * np.exp(-0.56 * h), rtol=1e-15
    )
    assert pc.pressure_factor(np.array([1e-4]))[0] == pytest.approx(1.0, abs=1e-20)
    # the two shear-factor fits of Patir & Cheng (1979) meet at H = 5 to 0.1 %
    lo, hi = pc.shear_factor(np.array([5e-6 * (1 - 1e-12), 5e-6 * (1 + 1e-12)]))
    assert lo == pytest.approx(hi, rel=1e-3)
    u = np.array([0.7, 2.0, 4.0, 7.0]) * 1e-6
    for f, df in (
        (pc.pressure_factor, pc.dpressure_factor_du),
        (pc.shear_factor, pc.dshear_factor_du),
    ):
        np.testing.assert_allclose(
            df(u), (f(u * (1 + 1e-7)) - f(u * (1 - 1e-7))) / (2e-7 * u), rtol=1e-6
        )
    with pytest.raises(ParameterError, match="u"):
        pc.pressure_factor(np.array([0.0]))
    with pytest.raises(ParameterError, match="sigma"):
        PatirCheng(0.0)


@pytest.fixture(scope="module")
def emt() -> BruggemanFlowFactor:
    return BruggemanFlowFactor(SelfAffinePSD(1e4, 7.8e9, 0.8, h_rms=1e-6), 10e6 / 0.75)


def test_persson_bruggeman_factor(emt):
    u = np.geomspace(emt.percolation_separation * 1.01, 50e-6, 300)
    phi = emt.pressure_factor(u)
    assert np.all(np.diff(phi) > 0) and np.all((phi > 0) & (phi < 1))
    assert emt.pressure_factor(np.array([0.5 * emt.percolation_separation]))[0] == 0.0
    # far from contact the flow sees nearly smooth walls: 1 - c (h/u)^2 with
    # 0 < c <= 3/2, the Tripp value for the full height distribution (Persson's P(u)
    # mixes folded Gaussians of width h_rms(zeta) <= h_rms)
    assert 0.0 < emt._c_tail <= 1.5
    assert emt.pressure_factor(np.array([50e-6]))[0] == pytest.approx(
        1 - emt._c_tail / 2500, rel=1e-12
    )
    uu = np.array([0.1, 1.0, 3.0, 20.0]) * 1e-6
    d = (emt.pressure_factor(uu * (1 + 1e-6)) - emt.pressure_factor(uu * (1 - 1e-6))) / (2e-6 * uu)
    np.testing.assert_allclose(emt.dpressure_factor_du(uu), d, rtol=1e-5)
    assert np.all(emt.shear_factor(uu) == 0.0)


def test_log_hermite_table_of_the_bruggeman_factor(emt):
    """The C1 form the FEM film evaluates: within 1e-3 of the Bruggeman interpolant
    on [0.05, 12] h_rms with 25 nodes (measured 8.7e-4; 13 nodes give 5.2e-3, 49 give
    1.3e-4, i.e. the h^3 of cubic Hermite), equal to it at the nodes, C1 at the nodes,
    and Tripp's 1 - c/H^2 tail beyond."""
    tab = emt.hermite_table(n=25)
    u = np.geomspace(0.05, 12.0, 3001) * emt.h_rms
    assert np.abs(tab(u) - emt.pressure_factor(u)).max() < 1e-3
    nodes = np.exp(tab.s) * emt.h_rms
    np.testing.assert_allclose(tab(nodes), emt.pressure_factor(nodes), rtol=1e-12)
    for un in nodes[1:-1]:  # continuous slope across each node
        lo, hi = tab(np.array([un * (1 - 1e-7), un])), tab(np.array([un, un * (1 + 1e-7)]))
        np.testing.assert_allclose(np.diff(lo), np.diff(hi), rtol=1e-4, atol=1e-13)
    far = np.array([30.0, 100.0]) * emt.h_rms
    np.testing.assert_allclose(tab(far), 1 - tab.c_tail * (emt.h_rms / far) ** 2, rtol=1e-14)
    assert 0.0 < tab(np.array([0.01 * emt.h_rms]))[0] < tab(np.array([0.05 * emt.h_rms]))[0]
    for kw, name in (({"h_min": 0.0}, "h_min"), ({"h_max": 1.0}, "h_max"), ({"n": 2}, "n")):
        with pytest.raises(ParameterError, match=name):
            emt.hermite_table(**kw)


def test_log_hermite_table_of_a_film_that_stops_percolating_above_h_min():
    """The homogenised part of the default lip sector split at q_th = 4 q0 (q 1.2e6 to
    1e8 1/m, H 0.8, h_rms 0.165 um, rubber E* 10.7 MPa) stops percolating at 0.056 h_rms,
    above the table's 0.05 h_rms, where phi_p = 0 and no table can start (before:
    refused, "nodes must increase and 0 < phi < 1 at the ends").  The table then starts
    at the first tabulated separation above percolation and is the interpolant there
    (nodes to 1e-12, between them within 1e-3 as the other table), and below it
    decays towards contact without leaving [0, 1]."""
    emt = BruggemanFlowFactor(SelfAffinePSD(1.2e6, 1e8, 0.8, h_rms=1.65e-7), 8e6 / 0.75)
    u_perc = emt.percolation_separation
    assert u_perc > 0.05 * emt.h_rms
    tab = emt.hermite_table(n=25)
    first = np.exp(tab.s[0]) * emt.h_rms
    assert first == pytest.approx(emt.u_table[1], rel=1e-12)
    nodes = np.exp(tab.s) * emt.h_rms
    np.testing.assert_allclose(tab(nodes), emt.pressure_factor(nodes), rtol=1e-12)
    u = np.geomspace(first, 12.0 * emt.h_rms, 3001)
    assert np.abs(tab(u) - emt.pressure_factor(u)).max() < 1e-3
    below = tab(np.geomspace(1e-3 * emt.h_rms, first, 200))
    assert np.all((below >= 0.0) & (below <= tab(np.array([first]))[0]))
    assert np.all(np.diff(below) >= 0.0)
