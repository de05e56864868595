"""The strain energy's default quadrature (``solid.body.energy_quadrature``).

The default must integrate the linearised stiffness of affine cells exactly: the
stiffness matrix of the P2 (and P3) elasticity form assembled with the default
rule equals the one with a rule of degree 8 (exact for its degree-2 or degree-4
integrand) to round-off, on a distorted affine mesh; in 2D with the
axisymmetric weight ``r`` too.  On tetrahedra the rule must have positive
weights (basix's default degree-3 rule has a negative one), and FFCx must use
the rule the metadata names: the mass matrix of P2, whose degree-4 integrand the
default degree-3 rule does not integrate exactly, differs between the two rules."""

from __future__ import annotations

import basix
import dolfinx
import numpy as np
import pytest
import ufl
from dolfinx.fem.petsc import assemble_matrix
from mpi4py import MPI

from dolfinx_seal.solid.body import energy_quadrature


def _mesh(dim):
    comm = MPI.COMM_WORLD
    if dim == 2:
        mesh = dolfinx.mesh.create_unit_square(comm, 5, 4, dolfinx.mesh.CellType.triangle)
    else:
        mesh = dolfinx.mesh.create_unit_cube(comm, 3, 2, 3)
    x = mesh.geometry.x
    x[:, 0] = 0.2 + x[:, 0] + 0.3 * x[:, 1]  # sheared, and r > 0 for the axisymmetric weight
    x[:, 1] = x[:, 1] * (1.0 + 0.5 * x[:, 0])  # cells of different shapes (still affine)
    return mesh


def _norm(mesh, form):
    A = assemble_matrix(dolfinx.fem.form(form))
    A.assemble()
    n = A.norm()
    return A, n


def _stiffness(mesh, degree, metadata, weight):
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", degree, (mesh.geometry.dim,)))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    eps = ufl.sym(ufl.grad(u))
    sigma = 2.0 * eps + 3.0 * ufl.tr(eps) * ufl.Identity(mesh.geometry.dim)
    dx = ufl.Measure("dx", domain=mesh, metadata=metadata)
    return ufl.inner(sigma, ufl.sym(ufl.grad(v))) * weight * dx


@pytest.mark.parametrize(
    "dim,degree,axisymmetric",
    [(2, 2, False), (2, 2, True), (2, 3, True), (3, 2, False), (3, 3, False)],
)
def test_the_default_rule_integrates_the_linearised_stiffness_exactly(dim, degree, axisymmetric):
    mesh = _mesh(dim)
    weight = ufl.SpatialCoordinate(mesh)[0] if axisymmetric else 1.0
    cell = mesh.basix_cell().name
    A, _ = _norm(mesh, _stiffness(mesh, degree, energy_quadrature(degree, cell), weight))
    B, nB = _norm(mesh, _stiffness(mesh, degree, {"quadrature_degree": 8}, weight))
    A.axpy(-1.0, B)
    assert A.norm() <= 1e-12 * nB


def test_the_tetrahedral_rule_has_positive_weights_and_is_the_one_used():
    md = energy_quadrature(2, "tetrahedron")
    rule = basix.quadrature.string_to_type(md["quadrature_rule"])
    _, w = basix.make_quadrature(basix.CellType.tetrahedron, md["quadrature_degree"], rule=rule)
    assert w.min() > 0.0
    _, w_default = basix.make_quadrature(basix.CellType.tetrahedron, md["quadrature_degree"])
    assert w_default.min() < 0.0  # why the default rule is not used
    mesh = _mesh(3)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 2))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)

    def mass(metadata):
        return _norm(mesh, u * v * ufl.Measure("dx", domain=mesh, metadata=metadata))

    A, nA = mass(md)
    B, _ = mass({"quadrature_degree": md["quadrature_degree"]})
    A.axpy(-1.0, B)
    assert A.norm() > 1e-6 * nA  # two different rules: FFCx honoured the name


def test_a_given_degree_takes_the_default_rule():
    assert energy_quadrature(2, "tetrahedron", 4) == {"quadrature_degree": 4}
    assert energy_quadrature(2, "triangle") == {"quadrature_degree": 4}
    assert np.isclose(energy_quadrature(1, "tetrahedron")["quadrature_degree"], 1)
