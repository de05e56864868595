"""Kuzmin's discrete upwinding (:mod:`dolfinx_seal.film.upwinding`) on a Galerkin
convection matrix: the corrected matrix has no positive off-diagonal entry, the
correction is symmetric with zero row and column sums (it moves mass between
nodes and creates none), and it leaves alone the entries that were already
upwind.  At 1, 2 and 3 ranks (the transpose crosses ranks)."""

from __future__ import annotations

import dolfinx
import dolfinx.fem.petsc
import numpy as np
import pytest
import scipy.sparse as sp
import ufl
from mpi4py import MPI

from dolfinx_seal.film.upwinding import upwinding_diffusion


def _gathered(M) -> sp.csr_matrix:
    """The whole matrix on every rank (small test sizes)."""
    ai, aj, av = M.getValuesCSR()
    r0, _ = M.getOwnershipRange()
    rows = np.repeat(np.arange(r0, r0 + ai.size - 1), np.diff(ai))
    comm = MPI.COMM_WORLD
    R = np.concatenate(comm.allgather(rows))
    C = np.concatenate(comm.allgather(aj))
    V = np.concatenate(comm.allgather(av))
    n = M.getSize()[0]
    return sp.csr_matrix((V, (R, C)), shape=(n, n))


@pytest.fixture(scope="module")
def convection():
    """The Galerkin convection matrix ``int (b . grad u) v`` of P1 on an
    unstructured-looking (crossed diagonal) mesh, a rotating field ``b``: it has
    positive off-diagonal entries (a central scheme)."""
    mesh = dolfinx.mesh.create_unit_square(
        MPI.COMM_WORLD,
        9,
        7,
        dolfinx.mesh.CellType.triangle,
        diagonal=dolfinx.mesh.DiagonalType.crossed,
    )
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    x = ufl.SpatialCoordinate(mesh)
    b = ufl.as_vector((1.0 + x[1], 0.3 - x[0]))
    A = dolfinx.fem.petsc.assemble_matrix(dolfinx.fem.form(ufl.dot(b, ufl.grad(u)) * v * ufl.dx))
    A.assemble()
    yield A
    A.destroy()


def test_corrected_transport_is_upwind_and_conservative(convection):
    minus_D = upwinding_diffusion(convection)
    C = _gathered(convection)
    M = _gathered(minus_D)
    minus_D.destroy()
    off = sp.triu(C, 1) + sp.tril(C, -1)
    scale = abs(C).max()
    assert off.max() > 0.05 * scale  # the matrix tested is not upwind already
    L = (C + M).tocoo()
    offL = L.row != L.col
    assert L.data[offL].max() <= 1e-14 * scale
    # symmetric, zero row and column sums: no mass created or lost
    assert abs(M - M.T).max() <= 1e-15 * scale
    assert np.abs(np.asarray(M.sum(axis=1))).max() <= 1e-14 * scale
    assert np.abs(np.asarray(M.sum(axis=0))).max() <= 1e-14 * scale
    # least diffusion: D_ij = max(0, C_ij, C_ji) off the diagonal, exactly
    Cd = C.toarray()
    D = -M.toarray()
    expect = np.maximum(0.0, np.maximum(Cd, Cd.T))
    np.fill_diagonal(expect, 0.0)
    np.fill_diagonal(D, 0.0)
    assert np.abs(D - expect).max() <= 1e-15 * scale
