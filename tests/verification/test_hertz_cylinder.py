"""Dry cylinder on a flat against Hertz line contact (S1 figure-4 system).

R = 1 cm, F/L = 100 N/m, E = 10 MPa, nu = 0.5: a_H = 0.309 mm, p_H = 0.206 MPa.
The nearly smooth contact law ``E* exp(-g / l)`` with ``l = 1e-3 a^2/R``
broadens the edges by about (l R / a^2)^(2/3) ~ 1 % of a locally, which
moves the second-moment half-width by ~0.2 %; the finite body (a/R = 0.03)
changes the pressure by O((a/R)^2) ~ 1e-3.  Tolerances below are those
modelling errors plus the discretisation error, whose order is measured.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from mpi4py import MPI

from dolfinx_seal.contact.hertz import hertz_line
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.scenes import make_parameters, run_scene
from dolfinx_seal.scenes.common import MaterialParams

A_H, P_H = hertz_line(100.0, 0.01, 10e6 / 0.75)


def _run(tmp, **values):
    p = make_parameters(
        "cylinder", values={"contact": {"model": "stiff"}, "lubricated": False, **values}
    )
    return run_scene("cylinder", p, tmp)


@pytest.fixture(scope="module")
def refinement(tmp_path_factory):
    out = tmp_path_factory.mktemp("cyl") if MPI.COMM_WORLD.rank == 0 else None
    out = MPI.COMM_WORLD.bcast(str(out))
    return {h: _run(f"{out}/h{h}", h_contact=h) for h in (20e-6, 10e-6, 5e-6)}


def test_hertz_half_width_and_peak(refinement):
    fine = refinement[5e-6]
    assert fine["converged"] and fine["load_balance_error"] < 1e-8
    # measured: +0.16 % and -0.06 %; modelling errors (edge broadening, finite body) ~0.2 %
    assert fine["contact_half_width"] == pytest.approx(A_H, rel=3e-3)
    assert fine["max_contact_pressure"] == pytest.approx(P_H, rel=3e-3)


def test_peak_pressure_converges_with_an_observed_order(refinement):
    """Self-convergence from successive differences (Richardson): the discretisation
    error of the (lumped-projected) peak pressure decays at about second order."""
    p = [refinement[h]["max_contact_pressure"] for h in (20e-6, 10e-6, 5e-6)]
    order = math.log2(abs(p[0] - p[1]) / abs(p[1] - p[2]))
    assert order > 1.5, (p, order)  # measured 2.2
    a = [refinement[h]["contact_half_width"] for h in (20e-6, 10e-6, 5e-6)]
    assert abs(a[2] - a[1]) < abs(a[1] - a[0]) + 1e-3 * A_H


def test_newton_converges_quadratically_with_warm_start(refinement):
    # Hertz warm start + one force-controlled Newton solve: a handful of steps
    for r in refinement.values():
        assert r["newton_iterations"] <= 12 and r["strategy"] == "warm start"  # measured 7-8


def test_coarse_mesh_recovers_by_load_stepping(mpi_tmp_path):
    """At 40 um the coupled solve after the warm start fails in the linear solver; the
    solver must recover (rebuilt factorisation) and converge by adaptive load stepping."""
    r = _run(mpi_tmp_path / "coarse", h_contact=40e-6)
    assert r["converged"] and r["strategy"].startswith("load stepping")
    assert r["load_balance_error"] < 1e-8
    assert r["contact_half_width"] == pytest.approx(A_H, rel=5e-3)  # measured +0.19 %
    assert r["max_contact_pressure"] == pytest.approx(P_H, rel=1e-2)  # measured -0.37 %


def test_linear_and_neo_hookean_agree_at_small_strain(mpi_tmp_path):
    lin = _run(mpi_tmp_path / "lin", h_contact=10e-6, material={"model": "linear"})
    nh = _run(mpi_tmp_path / "nh", h_contact=10e-6)
    # strains are ~ p/E ~ 2 %: the models may differ by a fraction of that
    assert lin["max_contact_pressure"] == pytest.approx(nh["max_contact_pressure"], rel=2e-3)
    assert lin["contact_half_width"] == pytest.approx(nh["contact_half_width"], rel=2e-3)


def test_nearly_incompressible_both_formulations(mpi_tmp_path):
    """nu = 0.4999: the mixed u-p form and the displacement-only (penalty, P2) form both
    converge and match Hertz (P2 displacements do not lock in this measure; the
    nodal contact pressure of the penalty form oscillates, its projection does not)."""
    a, p = hertz_line(100.0, 0.01, 10e6 / (1 - 0.4999**2))
    for form in ("mixed", "compressible"):
        r = _run(mpi_tmp_path / form, h_contact=10e-6, material={"nu": 0.4999, "formulation": form})
        assert r["contact_half_width"] == pytest.approx(a, rel=3e-3), form
        assert r["max_contact_pressure"] == pytest.approx(p, rel=3e-3), form
        assert r["load_balance_error"] < 1e-8


def test_stiff_rubber_1_gpa(mpi_tmp_path):
    # E = 1 GPa (S1 figure 15): a_H = 31 um, elements scaled with it
    stiff = _run(mpi_tmp_path / "gpa", h_contact=1e-6, material={"E": 1e9})
    a, p = hertz_line(100.0, 0.01, 1e9 / 0.75)
    assert stiff["contact_half_width"] == pytest.approx(a, rel=1e-2)
    assert stiff["max_contact_pressure"] == pytest.approx(p, rel=3e-2)


def test_rough_contact_is_hertz_like_with_broadened_edges(mpi_tmp_path):
    """S1 figure 4: h_rms = 1 um, D_f = 2.2, full Persson law."""
    p = make_parameters("cylinder", values={"lubricated": False})
    r = run_scene("cylinder", p, mpi_tmp_path / "rough")
    assert r["load_balance_error"] < 1e-8
    assert r["contact_half_width"] > A_H * 1.02  # broadened
    assert 0.85 * P_H < r["max_contact_pressure"] < P_H  # flattened peak, still Hertz-like
    # Persson's law at the Hertz mean pressure gives A/A0 = 0.064 (numpy law):
    # the real contact area per unit length is a few % of 2 a_H
    assert 0.02 < r["real_contact_area"] / (2 * A_H) < 0.12


@pytest.mark.parametrize(
    "material, match",
    [
        ({"E": -1.0}, "E = -1.0"),
        ({"nu": 0.7}, "nu = 0.7"),
        ({"nu": -1.0}, "nu = -1.0"),
        ({"nu": 0.5, "formulation": "compressible"}, "needs material.formulation = 'mixed'"),
    ],
)
def test_bad_material_stops_before_assembly(material, match):
    with pytest.raises(ParameterError, match=match):
        make_parameters("cylinder", values={"material": material})


def test_zero_load_is_rejected():
    with pytest.raises(ParameterError, match="load = 0"):
        make_parameters("cylinder", values={"load": 0.0})
    with pytest.raises(ParameterError, match="nu"):
        MaterialParams(nu=0.5, formulation="compressible")
    assert np.isfinite(A_H)


def test_load_stepping_stops_when_its_caller_says_so():
    """``ramp(stop=...)``: a spent time budget (here: after two load steps) ends the
    stepping before its next step with a :class:`SolverError` that says so, the
    state kept at the last converged load fraction (a converged dry state)."""
    from dolfinx_seal.errors import SolverError
    from dolfinx_seal.scenes.cylinder import CYLINDER

    p = make_parameters("cylinder", values={"contact": {"model": "stiff"}, "lubricated": False,
                                            "h_contact": 20e-6})  # fmt: skip
    prob, _ = CYLINDER.build_dry(p)
    asked: list[int] = []

    def stop() -> str:
        asked.append(len(prob.steps))
        return "the time budget of 1 s was spent" if len(prob.steps) >= 2 else ""

    with pytest.raises(SolverError, match="load stepping stopped: the time budget") as info:
        prob.ramp(stop=stop)
    t = info.value.partial["fraction"]
    # asked before every attempt, failed ones included (the first steps are cut)
    assert len(prob.steps) == 2 and asked[-2:] == [1, 2] and asked == sorted(asked)
    assert 0.0 < t < 1.0
    assert prob.steps[-1].fraction == t and float(prob.load.value) == pytest.approx(t * prob.target)
    assert "at load fraction" in info.value.where
    # the state left is the converged one at t: one more solve there takes no step
    assert prob.solver.solve(where="check").newton_iterations == 0
