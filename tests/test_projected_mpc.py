"""The projected constraint assembly (``P^T A P + D`` by PETSc's PtAP) against
dolfinx_mpc's own (cell-by-cell condensation): the same Jacobian, the same Newton
solutions, at any number of ranks.

The problems are those of ``tests/verification/test_periodic_vi.py``: a periodic
obstacle VI (scalar Q1), the same with a scifem real unknown (blocked), and a
sector of an annulus with the rotational constraint (vector Q2 and the mixed
Q2/Q1 u-p form).  Their solutions equal the unconstrained references there; here
the two assemblies must agree with each other.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
from petsc4py import PETSc

from dolfinx_seal.solvers import MPCAssembly, NonlinearSolver, ProjectedMPCAssembly

pytest.importorskip("dolfinx_mpc")

_spec = importlib.util.spec_from_file_location(
    "_periodic_vi", Path(__file__).parent / "verification" / "test_periodic_vi.py"
)
T = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(T)


def _jacobian_pair(make_solver):
    """The Jacobian of the same solver state with both assemblies."""
    out = []
    for cls in (MPCAssembly, ProjectedMPCAssembly):
        solver: NonlinearSolver = make_solver(cls)
        x = solver.x
        solver._from_functions(x)
        rng = np.random.default_rng(3)
        arr = x.getArray(readonly=False)
        arr[:] = rng.uniform(-0.5, 0.5, arr.size)
        del arr
        solver._to_functions(x)
        solver.assembly.jacobian(solver.A)
        out.append(solver)
    return out


def _matvec_difference(A, B):
    """max over random vectors of |A v - B v| / |A v|."""
    v = A.createVecRight()
    worst = 0.0
    for seed in range(3):
        arr = v.getArray(readonly=False)
        arr[:] = np.random.default_rng(seed + 10 * v.comm.rank).normal(size=arr.size)
        del arr
        a, b = A.createVecLeft(), B.createVecLeft()
        A.mult(v, a)
        B.mult(v, b)
        b.axpy(-1.0, a)
        worst = max(worst, b.norm() / a.norm())
        a.destroy()
        b.destroy()
    v.destroy()
    return worst


def _periodic_strip(length, n):
    """The strip of test_periodic_vi, ``length`` long, periodic along x: V, its
    Dirichlet condition, the finalised constraint and an unknown on its space."""
    import dolfinx
    from mpi4py import MPI

    V, bc = T._strip(MPI.COMM_WORLD, 0.0, length, n, 1)
    mpc = T.dolfinx_mpc.MultiPointConstraint(V)
    mpc.create_periodic_constraint_geometrical(
        V,
        lambda x: np.isclose(x[0], length),
        lambda x: np.vstack((x[0] - length, x[1], x[2])),
        [bc],
    )
    mpc.finalize()
    return V, bc, mpc, dolfinx.fem.Function(mpc.function_space)


def _obstacle(cls):
    V, bc, mpc, u = _periodic_strip(1.0, 8)
    return T._obstacle(V, bc, u, assembly=cls(mpc))


def _sector(mixed):
    from mpi4py import MPI

    def make(cls):
        T.MPCAssembly = cls  # the helper builds its assembly with this name
        try:
            solver, _ = T._elasticity(
                T._annulus(MPI.COMM_WORLD, 2, 2, 1),
                T._sector_assembly(T._rotation(T.ALPHA), mixed),
                mixed=mixed,
            )
        finally:
            T.MPCAssembly = MPCAssembly
        return solver

    return make


@pytest.mark.parametrize(
    "make", [_obstacle, _sector(False), _sector(True)], ids=["obstacle", "sector", "sector_u_p"]
)
def test_projected_jacobian_equals_dolfinx_mpc(make):
    """Same matrix to round-off: the projected one leaves out master weights below
    1e-10 of the largest (the point search's round-off, ~1e-13), so the two differ
    by that round-off times the matrix entries; measured below 1e-14 here."""
    s1, s2 = _jacobian_pair(make)
    assert s1.A.getSize() == s2.A.getSize()
    assert _matvec_difference(s1.A, s2.A) < 1e-12
    for s in (s1, s2):
        s.destroy()


def test_projected_solutions_equal_dolfinx_mpc():
    """The Newton solution of the periodic obstacle VI and of the rotational mixed
    sector: equal to round-off with either assembly (measured 0 and 2e-16 of max|u|)."""
    for make in (_obstacle, _sector(True)):
        sols = []
        for cls in (MPCAssembly, ProjectedMPCAssembly):
            s = make(cls)
            h = s.solve()
            assert h.reason > 0
            u = s.u[0] if isinstance(s.u, list) else s.u
            n = u.function_space.dofmap.index_map.size_local * u.function_space.dofmap.index_map_bs
            sols.append(u.x.array[:n].copy())
            s.destroy()
        scale = np.abs(sols[0]).max()
        comm = PETSc.COMM_WORLD.tompi4py()
        diff = comm.allreduce(float(np.abs(sols[0] - sols[1]).max(initial=0.0)), op=_max())
        assert diff <= 1e-12 * comm.allreduce(float(scale), op=_max())


def _max():
    from mpi4py import MPI

    return MPI.MAX


def test_projected_blocked_with_real_unknown():
    """A constrained field and an unconstrained real unknown (blocked): the projected
    assembly gives the force-controlled periodic obstacle of test_periodic_vi."""

    lam = []
    for cls in (MPCAssembly, ProjectedMPCAssembly):
        V, bc, mpc, u = _periodic_strip(1.0, 8)
        solver, lp = T._blocked(V, bc, u, 1.0, assembly=cls([mpc, None]))
        h = solver.solve()
        assert h.reason > 0
        lam.append(T._real_value(lp))
        solver.destroy()
    assert lam[1] == pytest.approx(lam[0], rel=1e-12)


def test_projected_pins_masters_on_other_ranks():
    """Every dof pinned (the film's dry pin): no slave is pinned without its master.

    The conditions index the form's space; a master owned by another rank that is
    not already one of its ghosts is appended to the constraint's index map only
    (a strip four times longer than wide, cut across its length at two ranks, so the
    periodic faces' masters sit on another rank).  Before the flags were scattered
    through the constraint's map such a master counted as free and ``set_bcs``
    refused the pin (the intermittent 2-rank failure of the lip sector)."""
    import dolfinx

    V, bc, mpc, u = _periodic_strip(4.0, 4)
    solver = T._obstacle(V, bc, u, assembly=ProjectedMPCAssembly(mpc))
    comm = V.mesh.comm
    im_v, im_c = V.dofmap.index_map, mpc.function_space.dofmap.index_map
    appended = comm.allreduce(im_c.num_ghosts - im_v.num_ghosts)
    if comm.size > 1:
        assert appended > 0  # the case under test is present at this partition
    every = np.arange(im_v.size_local + im_v.num_ghosts, dtype=np.int32)
    pin = dolfinx.fem.dirichletbc(dolfinx.fem.Function(V), every)
    solver.set_bcs([pin])
    flags = solver.assembly._pinned_local(0)
    assert flags.size == im_c.size_local + im_c.num_ghosts
    assert comm.allreduce(int((~flags).sum())) == 0
    solver.destroy()
