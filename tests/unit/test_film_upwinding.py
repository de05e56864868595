"""Kuzmin's discrete upwinding (:mod:`dolfinx_seal.film.upwinding`) on a Galerkin
convection matrix: the corrected matrix has no positive off-diagonal entry, the
correction is symmetric with zero row and column sums (it moves mass between
nodes and creates none), and it leaves alone the entries that were already
upwind.  At 1, 2 and 3 ranks (the transpose crosses ranks)."""

from __future__ import annotations

import contextlib

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


class _WeightSolver:
    """A stand-in for a film solver whose Newton converges only while the discrete
    upwinding's weight (its 1 x 1 term's entry) is at least ``lowest``; a failed
    solve scribbles on the unknown, a converged one writes the weight into it."""

    def __init__(self, lowest: float, unknown) -> None:
        from petsc4py import PETSc

        self.lowest, self.unknown, self.tried = lowest, unknown, []
        self.limit, self.limits = 0, []  # newton_limit's cap (0: none), at each solve
        M = PETSc.Mat().createAIJ([1, 1], nnz=1, comm=MPI.COMM_SELF)
        M.setValue(0, 0, 1.0)
        M.assemble()
        self.linear_term = M

    @contextlib.contextmanager
    def newton_limit(self, max_newton: int, stall_steps: int = 0):
        before, self.limit = self.limit, max_newton
        try:
            yield
        finally:
            self.limit = before

    def solve(self, where: str):
        from types import SimpleNamespace

        from dolfinx_seal.errors import SolveHistory, SolverError

        w = 0.0 if self.linear_term is None else self.linear_term.getValue(0, 0)
        self.tried.append(w)
        self.limits.append(self.limit)
        if w < self.lowest:
            self.unknown.x.array[:] = np.nan
            raise SolverError("stand-in divergence", where,
                              history=SolveHistory(residual_norms=[1.0] * 4))  # fmt: skip
        self.unknown.x.array[:] = w
        return SimpleNamespace(newton_iterations=2)


def _unknown():
    from types import SimpleNamespace

    return SimpleNamespace(x=SimpleNamespace(array=np.zeros(4)))


@pytest.mark.parametrize("lowest", [0.0, 0.3, 0.01, 0.6])
def test_release_walks_the_weight_down_as_far_as_it_converges(lowest):
    """``release_discrete_upwinding``: the weight halves from 1, a failed step is
    retried at the midpoint from the last film, and the walk stops when a step
    would be shorter than 1/256: it keeps the last weight solved (its term and its
    film), within 2/256 above the lowest weight that converges.  With every weight
    converging it ends at 0 with no term left."""
    from dolfinx_seal.film.upwinding import release_discrete_upwinding

    u = _unknown()
    solver = _WeightSolver(lowest, u)
    its, got = release_discrete_upwinding(solver, [u], "stand-in")
    if lowest == 0.0:
        assert got == 0.0 and solver.linear_term is None
    else:
        assert lowest <= got < lowest + 2.0 / 256
        assert solver.linear_term.getValue(0, 0) == pytest.approx(got, rel=1e-15)
    assert np.all(u.x.array == got)  # the film of the weight kept, not a failed one's
    solved = [w for w in solver.tried if w >= lowest]
    failed = [w for w in solver.tried if w < lowest]
    assert its == 2 * len(solved) + 3 * len(failed)
    assert solved == sorted(solved, reverse=True)  # the weight only goes down


@pytest.mark.parametrize("rescues", [False, True])
def test_release_tries_the_fallback_on_a_failed_step(rescues):
    """A ``fallback`` (e.g. pseudo-time steps) is tried from the last film on each
    failed weight step: when it converges the walk goes on from its film and
    reaches 0; when it fails too, the walk bisects as without it."""
    from dolfinx_seal.errors import SolveHistory, SolverError
    from dolfinx_seal.film.upwinding import release_discrete_upwinding

    u = _unknown()
    solver = _WeightSolver(0.3, u)
    calls = []

    def fallback(where: str) -> int:
        w = 0.0 if solver.linear_term is None else solver.linear_term.getValue(0, 0)
        calls.append(w)
        assert np.all(u.x.array > w)  # from the last film solved, above w, not the failed one
        if not rescues:
            raise SolverError("stand-in", where, history=SolveHistory(residual_norms=[1.0] * 6))
        u.x.array[:] = w
        return 7

    _, got = release_discrete_upwinding(solver, [u], "stand-in", fallback=fallback)
    if rescues:
        assert got == 0.0 and solver.linear_term is None and np.all(u.x.array == 0.0)
        assert calls == [w for w in solver.tried if w < 0.3]
    else:
        assert 0.3 <= got < 0.3 + 2.0 / 256
        assert len(calls) == len([w for w in solver.tried if w < 0.3])


def test_release_caps_the_newton_steps_of_every_attempt():
    """``max_newton`` holds for every solve of the walk, the fallback's included, and
    is lifted when the walk ends; without it the solver keeps its own limit."""
    from dolfinx_seal.film.upwinding import release_discrete_upwinding

    for cap in (0, 7):
        u = _unknown()
        solver = _WeightSolver(0.3, u)
        seen = []

        def fallback(where: str, solver=solver, seen=seen) -> int:
            seen.append(solver.limit)
            return solver.solve(where).newton_iterations

        release_discrete_upwinding(solver, [u], "stand-in", fallback=fallback, max_newton=cap)
        assert solver.limits and set(solver.limits) == {cap} and set(seen) == {cap}
        assert solver.limit == 0
