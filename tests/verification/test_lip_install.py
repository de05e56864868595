"""Lip installation: converges from the undeformed lip to full interference; the
radial load integrated from the written pressure profile equals the force integral."""

from __future__ import annotations

import math

import numpy as np
import pytest
from mpi4py import MPI

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.mpi import using_comm
from dolfinx_seal.scenes import make_parameters, run_scene


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    out = tmp_path_factory.mktemp("lip") if MPI.COMM_WORLD.rank == 0 else None
    out = MPI.COMM_WORLD.bcast(str(out))
    p = make_parameters("lip-install", values={"lip": {"h_contact": 10e-6}})
    return run_scene("lip-install", p, out), out, p


def test_installs_with_adaptive_steps(installed):
    res, _, _ = installed
    assert res["converged"] and res["load_steps"] >= 5
    # the default 80 mm seal with its spring lands in the handbook bands of radial
    # shaft seals (Muller & Nau): radial force 0.1-0.2 N/mm of circumference and a
    # sealing band 0.1-0.3 mm wide (measured: 142.8 N/m, 0.120 mm on 10 um)
    assert 100.0 < res["radial_load"] < 200.0
    assert 0.1e-3 < res["contact_width"] < 0.3e-3
    # oil-side angle 45 deg, air-side 15 deg: the peak lies on the oil side of the
    # band's centre (by 24 um of 120 um)
    assert res["z_peak_pressure"] < res["z_contact_centre"] - 0.1 * res["contact_width"]


@pytest.mark.slow
def test_radial_load_and_width_converge(mpi_tmp_path):
    from dolfinx_seal.studies import convergence_study

    p = make_parameters("lip-install")
    rows = convergence_study(
        "lip-install", p, mpi_tmp_path, "lip.h_contact", [20e-6, 10e-6, 5e-6],
        ["radial_load", "contact_width"], reference="finest",
    )  # fmt: skip
    assert rows[1]["radial_load_error"] < rows[0]["radial_load_error"] < 5e-3
    assert rows[1]["contact_width_error"] < rows[0]["contact_width_error"] < 2e-2


@pytest.mark.slow
def test_linear_lip_has_the_larger_contact(mpi_tmp_path):
    """S0 figure 8: the linear elastic lip has a (slightly) larger contact area than Mooney-Rivlin."""
    lin = run_scene(
        "lip-install",
        make_parameters(
            "lip-install", values={"lip": {"h_contact": 10e-6}, "material": {"model": "linear"}}
        ),
        mpi_tmp_path / "lin",
    )
    mr = run_scene(
        "lip-install",
        make_parameters("lip-install", values={"lip": {"h_contact": 10e-6}}),
        mpi_tmp_path / "mr",
    )
    assert lin["contact_width"] > mr["contact_width"]


def test_radial_load_from_profile_matches_force_integral(installed):
    res, out, p = installed
    if MPI.COMM_WORLD.rank == 0:
        data = np.loadtxt(f"{out}/pressure.csv", delimiter=",", skiprows=1)
        z, r, pc = data[:, 0], data[:, 1], data[:, 2]
        # trapezoid of p * r along the deformed surface (the normal is nearly radial
        # where p is large) over R_shaft: an independent quadrature of the same load
        ds = np.hypot(np.diff(z), np.diff(r))
        f = np.sum(0.5 * (pc[1:] * r[1:] + pc[:-1] * r[:-1]) * ds) / p.lip.shaft_radius
        assert f == pytest.approx(res["radial_load"], rel=3e-2)
    assert math.isfinite(res["max_principal_strain"])


def test_radial_balance_and_band(installed):
    """Statics of the section for a uniform radial virtual displacement: contact
    force - spring force + case reaction = hoop force.  What is left is the
    quadrature of the contact force (its own form against the residual's)."""
    res, _, _ = installed
    assert abs(res["radial_balance_error"]) < 1e-3
    # the spring (2 pi T = 45.1 N) pushes the head down: the case pulls the lip
    # back (+11.1 N) and the hoop force is small (1.9 N against 35.9 N of contact)
    assert res["spring_force"] > res["normal_load"] > 0.0
    assert res["case_radial_reaction"] > 0.0
    # the lip outside the contact band stays off the shaft
    assert res["min_gap_outside_band"] > 0.0


def test_interference_larger_than_the_lip_is_rejected():
    with pytest.raises(ParameterError, match="interference"):
        make_parameters("lip-install", values={"lip": {"interference": 5e-3}})


def test_same_answer_serial_and_parallel(mpi_tmp_path):
    """Under mpirun: the distributed lip equals a serial copy solved on each rank
    (the package's communicator made COMM_SELF by ``using_comm``)."""
    if MPI.COMM_WORLD.size == 1:
        pytest.skip("compares a parallel run with a serial one")
    import dolfinx_seal.scenes.lip_install as lip

    p = make_parameters("lip-install", values={"lip": {"h_contact": 20e-6}})
    par = lip.run(p, mpi_tmp_path / "par")
    with using_comm(MPI.COMM_SELF):
        ser = lip.run(p, mpi_tmp_path / f"ser{MPI.COMM_WORLD.rank}")
    for k in ("radial_load", "contact_width"):
        assert par[k] == pytest.approx(ser[k], rel=1e-6), k


@pytest.mark.slow
def test_a_smooth_lip_installs_through_the_roughness_walk(installed, mpi_tmp_path):
    """h_rms 0.05 um: growing the shaft under the smooth law stalled; installed at 0.5
    um and walked down (roughness homotopy) it converges, with the rough lip's
    radial load to 1e-3: the separation under the band changes by about 50 nm
    (from about 0.1 h_rms of 0.5 um to almost nothing), 2e-4 of the 0.3 mm
    interference (measured 142.93 against 142.8 N/m on 10 um)."""
    from dolfinx_seal.scenes.lip_install import INSTALL_H_RMS

    rough, _, _ = installed
    p = make_parameters(
        "lip-install", values={"lip": {"h_contact": 10e-6}, "roughness": {"h_rms": 0.05e-6}}
    )
    smooth = run_scene("lip-install", p, mpi_tmp_path / "smooth")
    assert smooth["install_roughness_scale"] == pytest.approx(INSTALL_H_RMS / 0.05e-6)
    assert smooth["roughness_walk_newton_iterations"] > 0
    assert smooth["radial_load"] == pytest.approx(rough["radial_load"], rel=1e-3)
    assert smooth["contact_width"] == pytest.approx(rough["contact_width"], rel=2e-2)
