"""Cavitation models of the surface film against independent 1D references.

The references (:mod:`dolfinx_seal.verification.slider`: closed-form flux
functions + Brent, checked against a 1e5-cell finite-volume LCP) share no code
with the FEM film.  Cases: the pocketed pad of Almqvist et al. (J. Tribol.
2014) with a reformation front inside the pocket, and a converging textured
slider with a supply pressure.
"""

from __future__ import annotations

import pytest

from dolfinx_seal.film.rigid_slider import RigidSliderFilm
from dolfinx_seal.verification import slider as ref

CASES = {"almqvist-pocket": ref.pocket_slider_benchmark, "textured": ref.textured_slider_case}


@pytest.fixture(scope="module", params=list(CASES))
def case(request):
    gap, op = CASES[request.param]()
    return (
        request.param,
        gap,
        op,
        ref.jfo_solution(gap, op),
        ref.reynolds_condition_solution(gap, op),
    )


def test_jfo_conserves_mass_across_the_reformation_front(case):
    _, gap, op, jfo, _ = case
    cells = 1000
    s = RigidSliderFilm(gap, op, cells, "jfo")
    s.solve()
    q = s.quantities()
    dx = gap.length / cells
    # discrete conservation: the cell fluxes of the scheme are one number
    # (to the solver tolerance), also across rupture and reformation
    assert q["flux_spread"] < 1e-9
    assert q["mass_balance_error"] < 1e-9
    # the flux is set by the inlet land (independent of the mesh here)
    assert q["flux_mean"] == pytest.approx(jfo.flux, rel=1e-6, abs=0)
    # starved pocket: theta = Q / (U_m h) between the fronts (upwind: theta_i
    # carries the cell (x_i, x_i+1), an O(dx h') shift, 1e-5 here)
    v = s.film.film_values()
    x, th = v["X"][:, 0], v["theta"]
    inside = (x > jfo.x_rupture + 2 * dx) & (x < jfo.x_reformation - 2 * dx)
    assert inside.sum() > 10
    assert abs(th[inside] - jfo.theta(x[inside])).max() < 1e-4
    # free boundaries within two cells, load to 1e-4 (measured 7e-6 at 1000 cells)
    assert abs(q["x_rupture"] - jfo.x_rupture) <= 2 * dx
    assert abs(q["x_reformation"] - jfo.x_reformation) <= 2 * dx
    assert q["load"] == pytest.approx(jfo.load, rel=1e-4)
    assert q["p_max"] == pytest.approx(jfo.p_max, rel=1e-4)


def test_reynolds_condition_loses_mass_and_overestimates_the_load(case):
    """The Reynolds condition re-forms the film at the pocket edge without the mass
    to fill it (a flux jump), and predicts a much larger load than JFO."""
    _, gap, op, jfo, rey = case
    s = RigidSliderFilm(gap, op, 1000, "reynolds")
    s.solve()
    q = s.quantities()
    assert q["load"] == pytest.approx(rey.load, rel=1e-4)
    assert q["p_max"] == pytest.approx(rey.p_max, rel=1e-4)
    jump = abs(rey.fluxes[-1] / rey.fluxes[0] - 1.0)
    assert q["flux_spread"] == pytest.approx(jump, rel=0.05, abs=0)  # the flux is not conserved
    assert rey.load > 3.0 * jfo.load
    assert q["load"] > 3.0 * _jfo_load(gap, op)


def _jfo_load(gap, op) -> float:
    s = RigidSliderFilm(gap, op, 500, "jfo")
    s.solve()
    return s.quantities()["load"]


def test_full_sommerfeld_has_negative_pressure_and_no_bounds():
    gap, op = ref.pocket_slider_benchmark()
    s = RigidSliderFilm(gap, op, 200, "none")
    assert not s.solver.has_bounds and not s.film.has_theta
    s.solve()
    v = s.film.film_values()
    assert v["p"].min() < 0.0


def test_bad_mesh_for_the_gap_is_rejected():
    gap, op = ref.pocket_slider_benchmark()
    from dolfinx_seal.errors import ParameterError

    with pytest.raises(ParameterError, match="cells = 7"):
        RigidSliderFilm(gap, op, 7, "jfo")


def test_pseudo_time_reaches_the_steady_jfo_film(case):
    """Pseudo-transient continuation (the film's storage term, implicit Euler in a
    growing pseudo-time step, then the steady solve) from a full film at rest
    reaches the steady film of the direct solve (the same semismooth Newton from
    the same full film, converged on its step): the same discrete equations, so
    the same solution to round-off, and the reference's free boundaries and load
    as the direct solve."""
    import numpy as np

    from dolfinx_seal.film.pseudo_time import pseudo_transient_solve
    from dolfinx_seal.solvers import SNESOptions

    _, gap, op, jfo, _ = case
    cells = 1000
    opts = SNESOptions(max_it=60, snes_type="semismooth", rtol=1e-20, atol=1e-300, dtol=1e300)
    direct = RigidSliderFilm(gap, op, cells, "jfo", snes=opts)
    direct.solve()
    p0 = direct.film.film_values()["p"]
    s = RigidSliderFilm(gap, op, cells, "jfo", snes=opts)
    s.film.P.x.array[:] = 0.0
    s.film.theta_fn.x.array[:] = 1.0
    pseudo_transient_solve(s.film, s.solver, "slider")
    assert float(s.film.inv_dt.value) == 0.0  # left steady
    v = s.film.film_values()
    assert np.abs(v["p"] - p0).max() <= 1e-11 * np.abs(p0).max()  # measured 4e-14, 4e-16
    q = s.quantities()
    dx = gap.length / cells
    assert abs(q["x_rupture"] - jfo.x_rupture) <= 2 * dx
    assert abs(q["x_reformation"] - jfo.x_reformation) <= 2 * dx
    assert q["load"] == pytest.approx(jfo.load, rel=1e-4)
    assert q["mass_balance_error"] < 1e-9


def test_pseudo_time_needs_the_jfo_film():
    from dolfinx_seal.errors import ParameterError
    from dolfinx_seal.film.pseudo_time import PseudoTimeOptions, pseudo_transient_solve

    gap, op = ref.pocket_slider_benchmark()
    s = RigidSliderFilm(gap, op, 200, "reynolds")
    with pytest.raises(ParameterError, match=r"film\.cavitation"):
        pseudo_transient_solve(s.film, s.solver, "slider")
    with pytest.raises(ParameterError, match="last"):
        PseudoTimeOptions(first=10.0, last=1.0)
