"""Lip installation: converges from the undeformed lip to full interference; the
radial load integrated from the written pressure profile equals the force integral."""

from __future__ import annotations

import math

import numpy as np
import pytest
from mpi4py import MPI

from dolfinx_seal.errors import ParameterError
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
    # a rubber-only lip (no spring) of an 80 mm seal: a few tens of N per metre of
    # circumference (ring + cantilever estimate of this geometry: ~15-20 N/m)
    assert 5.0 < res["radial_load"] < 60.0
    assert 0.0 < res["contact_width"] < 0.9e-3  # inside the contact band


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


def test_interference_larger_than_the_lip_is_rejected():
    with pytest.raises(ParameterError, match="interference"):
        make_parameters("lip-install", values={"lip": {"interference": 5e-3}})
