"""The compat module's workarounds, and the upstream behaviour each one answers.

* FFCx 0.9 can integrate a group of integrals of one type on one subdomain
  wholly one-point when one of them is degree 1 and another is not.  The test
  pins that behaviour (it fails once FFCx integrates such a form right: then the
  guard can be relaxed) and checks that the guard refuses the pattern and lets
  the others through.
* scifem builds its real space's index map on ``MPI_COMM_WORLD``;
  :func:`~dolfinx_seal.compat.real_functionspace` builds it on the mesh's
  communicator (a sweep chain's sub-communicator).
"""

from __future__ import annotations

import dolfinx
import numpy as np
import pytest
import ufl
from dolfinx.fem.petsc import assemble_vector, create_vector_block
from mpi4py import MPI
from petsc4py import PETSc

from dolfinx_seal.compat import check_quadrature_rules, real_functionspace
from dolfinx_seal.solvers import NonlinearSolver


@pytest.fixture(scope="module")
def square():
    m = dolfinx.mesh.create_unit_square(MPI.COMM_WORLD, 4, 4)
    V = dolfinx.fem.functionspace(m, ("Lagrange", 1))
    u = dolfinx.fem.Function(V)
    u.interpolate(lambda x: 1 + x[0] ** 2 + x[1])
    return m, u, ufl.TestFunction(V)


def _assemble(form):
    b = assemble_vector(dolfinx.fem.form(form))
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    out = b.array.copy()  # owned entries
    b.destroy()
    return out


def _rel(a, b):
    num = MPI.COMM_WORLD.allreduce(float(np.sum((a - b) ** 2)))
    den = MPI.COMM_WORLD.allreduce(float(np.sum(b**2)))
    return float(np.sqrt(num / den))


@pytest.mark.parametrize("measure", ["dx", "ds"])
def test_ffcx_integrates_a_group_with_a_one_point_integral_wholly_one_point(square, measure):
    m, u, v = square
    M = getattr(ufl, measure)
    a, b = ufl.exp(u) * v, u**3 * v

    def dm(degree):
        return M(domain=m, metadata={"quadrature_degree": degree})

    whole = _assemble(a * dm(8) + b * dm(1))
    apart = _assemble(a * dm(8)) + _assemble(b * dm(1))
    one_point = _assemble(a * dm(1)) + _assemble(b * dm(1))
    assert _rel(whole, apart) > 1e-3  # a term integrated with the wrong rule ...
    assert _rel(whole, one_point) < 1e-13  # ... the one-point rule
    assert _rel(_assemble(b * dm(1) + a * dm(8)), one_point) < 1e-13  # in either order
    # two degrees above 1 are integrated as written
    assert (
        _rel(_assemble(a * dm(8) + b * dm(2)), _assemble(a * dm(8)) + _assemble(b * dm(2))) < 1e-13
    )


def test_the_guard_refuses_a_one_point_integral_beside_another_rule(square):
    m, u, v = square
    ds1 = ufl.ds(domain=m, metadata={"quadrature_degree": 1})
    ds8 = ufl.ds(domain=m, metadata={"quadrature_degree": 8})
    with pytest.raises(ValueError, match=r"film row: the exterior_facet integrals .* one-point"):
        check_quadrature_rules(u * v * ds8 + u**2 * v * ds1, "film row")
    with pytest.raises(ValueError, match="one-point"):  # in either order
        check_quadrature_rules(u**2 * v * ds1 + u * v * ds8)
    with pytest.raises(ValueError, match="residual"):  # every solver checks its forms
        NonlinearSolver(u * v * ds8 + u**2 * v * ds1 - v * ufl.dx, u)
    check_quadrature_rules(u * v * ds1 + u**2 * v * ds1 + u * v * ufl.dx)  # one rule each
    check_quadrature_rules(u * v * ds8 + u**2 * v.dx(0) * ds(m, 3))


def ds(m, degree):
    return ufl.ds(domain=m, metadata={"quadrature_degree": degree})


def test_the_real_space_lives_on_the_mesh_communicator():
    world = MPI.COMM_WORLD
    sub = world.Split(world.rank, key=world.rank)  # one rank each
    m = dolfinx.mesh.create_unit_interval(sub, 4)
    R = real_functionspace(m)
    imap = R.dofmap.index_map
    assert imap.size_global == 1 and imap.comm.size == 1
    V = dolfinx.fem.functionspace(m, ("Lagrange", 1))
    forms = [
        dolfinx.fem.form(ufl.TestFunction(V) * ufl.dx),
        dolfinx.fem.form(ufl.TestFunction(R) * ufl.dx),
    ]
    assert create_vector_block(forms).getSize() == 6  # scifem's space failed here (MPI_ERR_ARG)
    # on COMM_WORLD: one global dof, owned by rank 0, integrating like a constant
    mw = dolfinx.mesh.create_unit_square(world, 3, 3)
    Rw = real_functionspace(mw)
    assert Rw.dofmap.index_map.size_global == 1
    assert Rw.dofmap.index_map.size_local == (1 if world.rank == 0 else 0)
    c = dolfinx.fem.Function(Rw)
    c.x.array[:] = 2.5
    total = world.allreduce(dolfinx.fem.assemble_scalar(dolfinx.fem.form(c * ufl.dx(domain=mw))))
    assert total == pytest.approx(2.5, rel=1e-14)
