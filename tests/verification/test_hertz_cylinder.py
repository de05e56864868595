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

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.scenes import make_parameters, run_scene
from dolfinx_seal.scenes.common import MaterialParams, hertz_line

A_H, P_H = hertz_line(100.0, 0.01, 10e6 / 0.75)


def _run(tmp, **values):
    p = make_parameters("cylinder", values={"contact": {"model": "stiff"}, **values})
    return run_scene("cylinder", p, tmp)


@pytest.fixture(scope="module")
def refinement(tmp_path_factory):
    out = tmp_path_factory.mktemp("cyl") if MPI.COMM_WORLD.rank == 0 else None
    out = MPI.COMM_WORLD.bcast(str(out))
    return {h: _run(f"{out}/h{h}", h_contact=h) for h in (20e-6, 10e-6, 5e-6)}


def test_hertz_half_width_and_peak(refinement):
    fine = refinement[5e-6]
    assert fine["converged"] and fine["load_balance_error"] < 1e-8
    assert fine["contact_half_width"] == pytest.approx(A_H, rel=5e-3)
    assert fine["max_contact_pressure"] == pytest.approx(P_H, rel=1.5e-2)


def test_peak_pressure_converges_with_an_observed_order(refinement):
    e = [abs(refinement[h]["max_contact_pressure"] / P_H - 1.0) for h in (20e-6, 10e-6, 5e-6)]
    # measured here: 3.7 %, 1.7 %, 0.6 % (order 1.1 then 1.4): the peak of a
    # square-root profile sampled at P2 nodes converges at about first order
    assert e[0] > e[1] > e[2]
    order = math.log2(e[0] / e[2]) / 2.0
    assert order > 0.9, e


def test_newton_converges_quadratically_with_warm_start(refinement):
    # Hertz warm start + one force-controlled Newton solve: a handful of steps
    for r in refinement.values():
        assert r["newton_iterations"] <= 12 and r["strategy"] == "warm start"


def test_linear_and_neo_hookean_agree_at_small_strain(mpi_tmp_path):
    lin = _run(mpi_tmp_path / "lin", h_contact=10e-6, material={"model": "linear"})
    nh = _run(mpi_tmp_path / "nh", h_contact=10e-6)
    # strains are ~ p/E ~ 2 %: the models may differ by a fraction of that
    assert lin["max_contact_pressure"] == pytest.approx(nh["max_contact_pressure"], rel=2e-3)
    assert lin["contact_half_width"] == pytest.approx(nh["contact_half_width"], rel=2e-3)


def test_nearly_incompressible_mixed_does_not_lock_penalty_does(mpi_tmp_path):
    """nu = 0.4999: the mixed u-p form matches Hertz as at nu = 0.5; the displacement-only
    (penalty) P2 form converges too but locks: its peak pressure is visibly worse."""
    a, p = hertz_line(100.0, 0.01, 10e6 / (1 - 0.4999**2))
    mixed = _run(mpi_tmp_path / "mix", h_contact=10e-6, material={"nu": 0.4999})
    pen = _run(mpi_tmp_path / "pen", h_contact=10e-6,
               material={"nu": 0.4999, "formulation": "compressible"})  # fmt: skip
    e_mixed = abs(mixed["max_contact_pressure"] / p - 1)
    e_pen = abs(pen["max_contact_pressure"] / p - 1)
    assert mixed["contact_half_width"] == pytest.approx(a, rel=5e-3)
    assert e_mixed < 0.02  # as nu = 0.5 on this mesh (1.7 %)
    assert e_pen > 2 * e_mixed  # measured: 5.6 % vs 1.7 % (volumetric locking)
    assert pen["contact_half_width"] == pytest.approx(a, rel=1e-2)


def test_stiff_rubber_1_gpa(mpi_tmp_path):
    # E = 1 GPa (S1 figure 15): a_H = 31 um, elements scaled with it
    stiff = _run(mpi_tmp_path / "gpa", h_contact=1e-6, material={"E": 1e9})
    a, p = hertz_line(100.0, 0.01, 1e9 / 0.75)
    assert stiff["contact_half_width"] == pytest.approx(a, rel=1e-2)
    assert stiff["max_contact_pressure"] == pytest.approx(p, rel=3e-2)


def test_rough_contact_is_hertz_like_with_broadened_edges(mpi_tmp_path):
    """S1 figure 4: h_rms = 1 um, D_f = 2.2, full Persson law."""
    r = run_scene("cylinder", make_parameters("cylinder"), mpi_tmp_path / "rough")
    assert r["load_balance_error"] < 1e-8
    assert r["contact_half_width"] > A_H * 1.02  # broadened
    assert 0.85 * P_H < r["max_contact_pressure"] < P_H  # flattened peak, still Hertz-like
    # Persson's law at the Hertz mean pressure gives A/A0 = 0.064 (numpy law):
    # the real contact area per unit length is a few % of 2 a_H
    assert 0.02 < r["real_contact_area"] / (2 * A_H) < 0.12


def test_same_answer_serial_and_parallel(mpi_tmp_path):
    from dolfinx_seal.scenes.cylinder import CylinderParameters  # noqa: F401

    par = _run(mpi_tmp_path / "par", h_contact=20e-6)
    if MPI.COMM_WORLD.size == 1:
        pytest.skip("compare with a serial run only when running in parallel")
    # a serial solve of the same problem on each rank
    import dolfinx_seal.scenes.cylinder as cyl
    from dolfinx_seal import mpi as _mpi

    saved = _mpi.COMM_WORLD
    try:
        cyl.COMM_WORLD = MPI.COMM_SELF
        ser = cyl.run(make_parameters("cylinder", values={"contact": {"model": "stiff"}, "h_contact": 20e-6}),
                      mpi_tmp_path / f"ser{MPI.COMM_WORLD.rank}")  # fmt: skip
    finally:
        cyl.COMM_WORLD = saved
    for k in ("max_contact_pressure", "contact_half_width", "normal_load"):
        assert par[k] == pytest.approx(ser[k], rel=1e-8), k


@pytest.mark.parametrize(
    "material, match",
    [
        ({"E": -1.0}, "E = -1.0"),
        ({"nu": 0.7}, "nu = 0.7"),
        ({"nu": -1.0}, "nu = -1.0"),
        ({"nu": 0.5, "formulation": "compressible"}, "needs formulation = 'mixed'"),
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
