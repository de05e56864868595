"""Continuation drivers: nested meshes (solve coarse, interpolate, solve fine).

A free-boundary problem solved by an active-set Newton from a cold start moves
its active set by about one node per step, so the step count grows with the
mesh (docs/design.md, solver strategy).  Starting each level from the interpolated
solution of the level below puts the free boundary within a cell or two of
its place, and the Newton steps per level stay bounded whatever the size.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from dolfinx_seal import compat
from dolfinx_seal.errors import SolverError
from dolfinx_seal.mpi import get_logger
from dolfinx_seal.solvers.snes import NonlinearSolver


@dataclass
class LevelReport:
    """What one level of a nested solve took.

    Attributes:
        level: Level index (0 = coarsest).
        size: The size parameter of the level (e.g. number of cells).
        dofs: Global number of unknowns.
        newton_iterations: Newton steps on this level (all passes).
        wall_time_s: Wall time of the solve on this level [s] (set-up excluded).
        setup_time_s: Wall time of building the level and transferring the guess [s].
        reason: Final SNES converged reason name.
    """

    level: int
    size: int
    dofs: int
    newton_iterations: int
    wall_time_s: float
    setup_time_s: float
    reason: str


def transfer(u_from: Any, u_to: Any, padding: float = 1e-8) -> None:
    """Interpolate ``u_from`` onto ``u_to`` (another mesh of the same domain).

    Raises:
        SolverError: the interpolated field is not finite (a point fell outside
            the coarse mesh and the padding is too small for the curved boundary).
    """
    compat.interpolate_nonmatching(u_to, u_from, padding=padding)
    if not np.all(np.isfinite(u_to.x.array)):
        raise SolverError(
            "interpolation between levels produced non-finite values", where="transfer"
        )


def nested_solve(
    build: Callable[[int], tuple[NonlinearSolver, Any]],
    sizes: Sequence[int],
    solve: Callable[[NonlinearSolver, int], Any] | None = None,
    padding: float = 1e-8,
) -> tuple[NonlinearSolver, Any, list[LevelReport]]:
    """Solve on a sequence of meshes, each level started from the previous one.

    Args:
        build: ``build(size) -> (solver, u)`` makes the problem of one level.
        sizes: Level sizes, coarsest first.
        solve: ``solve(solver, level)`` (default ``solver.solve()``); use it to pick
            e.g. the penalty warm start on the coarsest level only.
        padding: Interpolation padding (mesh units), see :func:`transfer`.

    Returns:
        The finest solver, its unknown, and one :class:`LevelReport` per level.
    """
    log = get_logger()
    reports: list[LevelReport] = []
    prev = prev_solver = None
    solver = u = None
    for level, n in enumerate(sizes):
        t0 = time.perf_counter()
        solver, u = build(n)
        if prev is not None:
            transfer(prev, u, padding)
        t1 = time.perf_counter()
        n0 = solver.total_newton_iterations
        if solve is None:
            solver.solve(where=f"nested level {level} (size {n})")
        else:
            solve(solver, level)
        t2 = time.perf_counter()
        V = u.function_space
        dofs = V.dofmap.index_map.size_global * V.dofmap.index_map_bs
        rep = LevelReport(
            level=level,
            size=int(n),
            dofs=int(dofs),
            newton_iterations=solver.total_newton_iterations - n0,
            wall_time_s=t2 - t1,
            setup_time_s=t1 - t0,
            reason=solver.history.reason_name,
        )
        log.info(
            "nested level %d: size %d, %d Newton steps, %.3f s",
            level,
            n,
            rep.newton_iterations,
            rep.wall_time_s,
        )
        reports.append(rep)
        if prev_solver is not None:
            prev_solver.destroy()  # the coarser level's PETSc objects are no longer needed
        prev, prev_solver = u, solver
    return solver, u, reports
