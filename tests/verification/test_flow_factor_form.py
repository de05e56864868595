"""The UFL pressure flow factors of the film equal their numpy definitions."""

from __future__ import annotations

import dolfinx
import numpy as np
import pytest
import ufl
from mpi4py import MPI

from dolfinx_seal.compat import interpolation_points
from dolfinx_seal.contact import BruggemanFlowFactor, PatirCheng
from dolfinx_seal.film.surface import pressure_flow_factor
from dolfinx_seal.roughness import SelfAffinePSD

H_RMS = 1e-6


@pytest.mark.parametrize("model", ["patir-cheng", "persson"])
def test_ufl_flow_factor_matches_numpy(model):
    """Interpolate phi_p(g) with g = x on [0.01, 40] h_rms (a 1D mesh, every rank its
    own): the UFL expression must reproduce the numpy function at every node to
    round-off, including below the first and beyond the last table node."""
    mesh = dolfinx.mesh.create_interval(MPI.COMM_SELF, 400, [0.01 * H_RMS, 40 * H_RMS])
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1))
    x = ufl.SpatialCoordinate(mesh)[0]
    if model == "persson":
        emt = BruggemanFlowFactor(SelfAffinePSD(1e4, 7.8e9, 0.8, h_rms=H_RMS), 10e6 / 0.75)
        table = emt.hermite_table()
        ref = table
    else:
        table, ref = None, PatirCheng(H_RMS).pressure_factor
    f = dolfinx.fem.Function(V)
    expr = pressure_flow_factor(model, x, H_RMS, table)
    f.interpolate(dolfinx.fem.Expression(expr, interpolation_points(V.element)))
    u = V.tabulate_dof_coordinates()[:, 0]
    np.testing.assert_allclose(f.x.array, ref(u), rtol=1e-12, atol=1e-15)
