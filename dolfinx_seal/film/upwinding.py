"""Discrete upwinding of the film's Couette transport (``film.discrete_upwinding``).

The JFO film's transport rows (the Couette flux ``U_m g theta`` against the test
function, one-point quadrature plus streamline diffusion, :class:`SurfaceFilm`)
are not a monotone scheme on an unstructured band: their Jacobian in the film
fraction, ``C = dR_P / dtheta``, has positive off-diagonal entries.  Measured on
the frozen default lip sector band (two-scale, 2.6 um elements, 1,047 free film
nodes at 1 mm/s): 2,384 of its 6,248 off-diagonal entries are positive, up to
0.41 of their row's diagonal.  In a cavitated zone the film is then not an
M-matrix system: Newton's iterates put ``theta`` below 0 (to -6 at 3 mm/s when
left unbounded), the bound ``theta >= 0`` clips them, and the active set
wanders (250-680 of about 3,900 rows changing every step, docs/scenes/lip-sector.md).

Kuzmin's discrete upwinding (D. Kuzmin, "Algebraic flux correction I", in Flux-
Corrected Transport, Springer 2012, section 3; Kuzmin and Turek, J. Comput.
Phys. 175, 2002) adds the least symmetric artificial diffusion that removes the
positive off-diagonal entries:

    D_ij = max(0, C_ij, C_ji)  (i != j),    D_ii = -sum_{j != i} D_ij,

and the transport rows become ``C - D``: off-diagonal entries <= 0, the same
column sums.  ``D`` is symmetric with zero row sums, so

* a uniform film fraction feels nothing (``D 1 = 0``): a full film's Reynolds
  equation is unchanged;
* the correction moves oil between nodes and creates none (``1^T D = 0``):
  the global mass balance and the edge flows are the scheme's own.

The correction is numerical diffusion of ``g theta`` along the mesh edges where
the scheme was not upwind.  Measured on the lip sector: torque and load change
by less than 0.5 %, the leakage at 1 mm/s by a factor of 1.8-1.9.  That is
a bias: the diffusion acts along every edge, so across the sliding too, and a
seal's leakage is a small residual of the circumferential Couette flux.  On a
rigid rough band against a finite-volume reference
(:mod:`dolfinx_seal.verification.rough_band`) the leakage with it is 16-29 %
low at 0.1 m/s and of the wrong sign at 1 m/s, where streamline diffusion
alone is within 1.2 % and 17 % (docs/verification.md).  It is built from the assembled Jacobian (Dirichlet
and periodic-slave rows and columns are zero there, so ``D`` does not touch
them).  On a frozen lip it is constant for a given speed and zone; on a coupled
lip it depends on the displacement, and the lip sector keeps it lagged: built
on the state a Newton solve starts from, rebuilt on the converged state and
solved again until a solve starts converged (``lip_sector._settle_upwinding``).

:func:`release_discrete_upwinding` (``film.release_upwinding``) makes the term a
path rather than the scheme: from the monotone film it walks the term's weight
to 0, each weight solved from the last film, and ends on the film of the
scheme without it, whose leakage is the accurate one, or stops at the smallest
weight that converges (reported as ``discrete_upwinding_weight``).  On the rough band at
1 m/s, on a lattice where that scheme's own semismooth Newton fails from a full
film and pseudo-time takes 212-237 steps, the walk takes 48-51.  On the frozen
default lip band, capping each of its solves at 30 Newton steps (``max_newton``,
against the film solver's 150) gave the same films 3-6 times faster.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import scipy.sparse as sp
from petsc4py import PETSc

from dolfinx_seal.errors import SolverError
from dolfinx_seal.mpi import get_logger
from dolfinx_seal.solvers.adaptive import restore_arrays
from dolfinx_seal.solvers.assembly import owned_block_offsets


def _local_csr(M: PETSc.Mat) -> sp.csr_matrix:
    """The owned rows of ``M`` with global column indices, as SciPy CSR."""
    ai, aj, av = M.getValuesCSR()
    (m, _), (_, N) = M.getSizes()
    return sp.csr_matrix((av, aj, ai), shape=(m, N))


def upwinding_diffusion(C: PETSc.Mat) -> PETSc.Mat:
    """``-D`` (Kuzmin's discrete upwinding) of the square transport matrix ``C``,
    with ``C``'s parallel layout: added to ``C`` it leaves no positive off-diagonal
    entry and the column sums unchanged."""
    r0, r1 = C.getOwnershipRange()
    Cl = _local_csr(C).tocoo()
    rows = Cl.row + r0
    keep = (Cl.col != rows) & (Cl.data > 0.0)
    positive = PETSc.Mat().createAIJ(C.getSizes(), comm=C.comm)
    pos = sp.csr_matrix(
        (Cl.data[keep], (Cl.row[keep], Cl.col[keep])), shape=(r1 - r0, C.getSize()[1])
    )
    pos.sort_indices()
    positive.setPreallocationCSR(
        (pos.indptr.astype(PETSc.IntType), pos.indices.astype(PETSc.IntType), pos.data)
    )
    positive.assemble()
    transposed = positive.transpose(PETSc.Mat())
    D = _local_csr(positive).maximum(_local_csr(transposed)).tocsr()
    positive.destroy()
    transposed.destroy()
    row_sums = np.asarray(D.sum(axis=1)).ravel()
    minus_D = (sp.diags(row_sums, offsets=r0, shape=D.shape) - D).tocsr()
    minus_D.sum_duplicates()
    minus_D.sort_indices()
    out = PETSc.Mat().createAIJ(C.getSizes(), comm=C.comm)
    out.setPreallocationCSR(
        (minus_D.indptr.astype(PETSc.IntType), minus_D.indices.astype(PETSc.IntType), minus_D.data)
    )
    out.assemble()
    return out


def attach_discrete_upwinding(
    solver: Any, pressure: int = 0, fraction: int = 1, weight: float = 1.0
) -> None:
    """Set the discrete upwinding term of a solver whose unknowns include a JFO
    film's pressure (block ``pressure``) and film fraction (block ``fraction``):
    the film-only solver of :meth:`SurfaceFilm.make_solver` (``[P, theta]``) or a
    coupled one (``[w, P, theta, ...]``).  The term, its
    :attr:`~dolfinx_seal.solvers.NonlinearSolver.linear_term`, is ``-D`` in the
    pressure rows and film-fraction columns, nothing else (the previous term is
    destroyed first), times ``weight`` (0: no term).

    Assembles the solver's Jacobian at its current unknowns; call it again when the
    speed, the film zone (its Dirichlet conditions) or the lip change.
    """
    _drop(solver)
    if weight == 0.0:
        return
    solver.linear_term = _transport_correction(solver, pressure, fraction)
    if weight != 1.0:
        solver.linear_term.scale(weight)


def _block_offsets(solver: Any) -> np.ndarray:
    """This rank's offsets of the solver's blocks in its owned rows (block layout)."""
    off = owned_block_offsets(solver.u if isinstance(solver.u, list | tuple) else [solver.u])
    start, end = solver.A.getOwnershipRange()
    if off[-1] != end - start:
        raise SolverError(
            f"{solver.name}: the blocks own {off[-1]} rows on this rank, its matrix "
            f"{end - start}: not the block layout film.discrete_upwinding reads"
        )
    return off


def transport_block(solver: Any, pressure: int = 0, fraction: int = 1) -> PETSc.Mat:
    """The solver's Jacobian block ``dR_P/dtheta`` (the rows of block ``pressure``,
    the columns of block ``fraction``; the weighted rows the solver solves) at its
    current unknowns, without its :attr:`linear_term`."""
    A = solver.jacobian(with_linear_term=False)
    comm = A.getComm().tompi4py()
    start = A.getOwnershipRange()[0]
    off = _block_offsets(solver)
    rows = np.arange(start + off[pressure], start + off[pressure + 1], dtype=PETSc.IntType)
    cols = np.arange(start + off[fraction], start + off[fraction + 1], dtype=PETSc.IntType)
    if rows.size != cols.size:
        raise SolverError(
            f"{solver.name}: the film pressure and fraction blocks own {rows.size} and "
            f"{cols.size} rows on this rank; film.discrete_upwinding needs them equal"
        )
    isP = PETSc.IS().createGeneral(rows, comm=comm)
    isT = PETSc.IS().createGeneral(cols, comm=comm)
    C = A.createSubMatrix(isP, isT)
    isP.destroy()
    isT.destroy()
    return C


def _transport_correction(solver: Any, pressure: int, fraction: int) -> PETSc.Mat:
    A = solver.A
    comm = A.getComm().tompi4py()
    start, end = A.getOwnershipRange()
    C = transport_block(solver, pressure, fraction)
    minus_D = upwinding_diffusion(C)
    C.destroy()
    off = _block_offsets(solver)
    # columns: theta's numbering in the submatrix -> the solver's global rows
    sub_starts = np.array(comm.allgather(minus_D.getOwnershipRange()[0]), dtype=np.int64)
    theta_starts = np.array(comm.allgather(start + off[fraction]), dtype=np.int64)
    Dl = _local_csr(minus_D).tocoo()
    minus_D.destroy()
    owner = np.searchsorted(sub_starts, Dl.col, side="right") - 1
    cols = theta_starts[owner] + (Dl.col - sub_starts[owner])
    full = sp.csr_matrix(
        (Dl.data, (Dl.row + off[pressure], cols)), shape=(end - start, A.getSize()[0])
    )
    full.sort_indices()
    M = PETSc.Mat().createAIJ(A.getSizes(), comm=comm)
    M.setPreallocationCSR(
        (full.indptr.astype(PETSc.IntType), full.indices.astype(PETSc.IntType), full.data)
    )
    M.assemble()
    return M


def release_discrete_upwinding(
    solver: Any,
    unknowns: Any,
    where: str,
    min_step: float = 1.0 / 256.0,
    fallback: Callable[[str], int] | None = None,
    max_newton: int = 0,
) -> tuple[int, float]:
    """Walk the weight of the solver's discrete upwinding term from 1 towards 0,
    each weight solved from the last film: the film of the scheme without the
    term, reached from the monotone scheme's, or as close to it as converges.

    The weight halves from 1 (0.5, 0.25, ... while at least ``min_step``), then
    goes to 0; a failed step is retried at the midpoint of the last weight solved
    and its target, from that weight's film (``unknowns``, the functions to
    restore); ``fallback(where)``, if given, is tried first on a failed step
    (e.g. pseudo-time steps of the film at that weight), from the same film, and
    returns its Newton steps or raises :class:`SolverError`.  ``max_newton`` (0:
    the solver's own limit) caps the Newton steps of each solve of an attempt, the
    fallback's included, so that a weight step that does not converge fails sooner.
    When a step would be shorter than ``min_step`` the walk stops
    there: the term stays at the last weight solved and the film at its
    solution (logged).  Returns ``(newton_steps, weight)``: ``weight`` 0 when
    released, else the weight kept (the term is then that weight times the
    original).
    """
    base = solver.linear_term
    if base is None:
        raise SolverError("no discrete upwinding term to release", where)
    targets, w = [], 0.5
    while w >= min_step:
        targets.append(w)
        w *= 0.5
    targets.append(0.0)
    good, its = 1.0, 0
    saved = [u.x.array.copy() for u in unknowns]
    solver.linear_term = None  # base is kept apart; each weight gets its own copy
    while targets:
        w = targets[0]
        solver.linear_term = _scaled(base, w)
        at = f"{where}: discrete upwinding at {w:.4g}"
        attempts = [lambda where: solver.solve(where=where).newton_iterations]
        if fallback is not None:
            attempts.append(fallback)
        failure = None
        for attempt in attempts:  # each from the last film solved
            try:
                with solver.newton_limit(max_newton):
                    its += attempt(at)
                failure = None
                break
            except SolverError as e:
                its += e.history.newton_iterations if e.history else 0
                restore_arrays(unknowns, saved)
                failure = e
        if failure is not None:
            _drop(solver)
            mid = 0.5 * (good + w)
            if good - mid < min_step:
                get_logger().warning(
                    "%s: film.release_upwinding stopped at weight %.4g of the discrete "
                    "upwinding (the step to %.4g failed: %s)",
                    where,
                    good,
                    w,
                    failure.what,
                )
                solver.linear_term = _scaled(base, good)
                break
            targets.insert(0, mid)
            continue
        targets.pop(0)
        good = w
        saved = [u.x.array.copy() for u in unknowns]
        _drop(solver)
    base.destroy()
    return its, good


def _scaled(M: PETSc.Mat, w: float) -> PETSc.Mat | None:
    if w == 0.0:
        return None
    out = M.copy()
    out.scale(w)
    return out


def _drop(solver: Any) -> None:
    if solver.linear_term is not None:
        solver.linear_term.destroy()
        solver.linear_term = None


__all__ = [
    "attach_discrete_upwinding",
    "release_discrete_upwinding",
    "transport_block",
    "upwinding_diffusion",
]
