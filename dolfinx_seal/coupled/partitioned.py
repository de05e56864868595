"""The seeds' partitioned scheme: the baseline the monolithic Newton is measured against.

S0 (end of section 2) and S1 (appendix D) alternate the two physics with
heavy under-relaxation of the fluid pressure:

1. the film (Reynolds / JFO, with its bounds) on the frozen deformation,
   together with the counter position from the force equation (S1 appendix
   D: "the load conservation is applied ... updating the central separation");
2. ``P <- P + omega (P_film - P)`` (and the film fraction likewise; S1:
   omega = 1e-1 to 1e-3, S0: 0.01 to 0.1);
3. elasticity (asperity law, fluid pressure and shear frozen, counter fixed).

until the relative change of the fluid pressure falls below ``tol``.  The two
sub-problems reuse the residual forms of the coupled problem (the Jacobian of
each is ``ufl.derivative`` of its own rows), so the converged fixed point is
the monolithic solution.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from mpi4py import MPI

from dolfinx_seal.errors import SolverError
from dolfinx_seal.params import check_int_range, check_positive, check_range
from dolfinx_seal.solid.step_limits import displacement_limiter
from dolfinx_seal.solvers import NonlinearSolver


@dataclass(frozen=True)
class PartitionedOptions:
    """Partitioned-scheme options.

    Attributes:
        relaxation: Under-relaxation factor omega of the fluid pressure (S0: 0.01-0.1).
        tol: Relative change of the fluid pressure (max norm) that ends the loop.
        max_iterations: Largest number of coupling iterations.
        max_time_s: Wall-time budget [s] (the loop stops unconverged after it).
    """

    relaxation: float = 0.1
    tol: float = 1e-6
    max_iterations: int = 5000
    max_time_s: float = 1e30

    def __post_init__(self) -> None:
        check_range("relaxation", self.relaxation, 0.0, 1.0, lo_open=True)
        check_positive("tol", self.tol)
        check_int_range("max_iterations", self.max_iterations, 1)
        check_positive("max_time_s", self.max_time_s, "s")


@dataclass
class PartitionedReport:
    """What the loop did."""

    converged: bool
    iterations: int
    newton_solid: int
    newton_film: int
    wall_time_s: float
    changes: list[float] = field(default_factory=list)


class PartitionedSolver:
    """Alternating elasticity / film solves on a coupled :class:`SolidContactProblem`."""

    def __init__(self, prob: Any) -> None:
        if prob.film is None or not prob.bulk:
            raise SolverError("the partitioned scheme needs a film and a deformable bulk",
                              where=prob.name)  # fmt: skip
        self.prob = prob
        film = prob.film
        film_fns = [b[1] for b in film.blocks]
        w_block = [b for b in prob.blocks if b[1] is prob.w]
        pos_block = [b for b in prob.blocks if prob.control == "force" and b[1] is prob.position]
        opts = prob.solver.options
        s_opts = dataclasses.replace(opts, snes_type="newtonls")
        limiter = None
        lim = prob.limits
        if lim.max_step or lim.max_gap_step:  # the problem's step limits, this layout
            limiter = displacement_limiter(prob, lim.max_step, lim.max_gap_step, blocks=w_block)
        self.solid = NonlinearSolver(
            w_block[0][0], prob.w, prob._dirichlet_bcs, options=s_opts,
            name=f"{prob.name} elasticity", step_limiter=limiter,
        )  # fmt: skip
        self.film = film.make_solver(opts, pos_block, name=f"{prob.name} film")
        self.film_fns = film_fns

    def solve(self, options: PartitionedOptions | None = None) -> PartitionedReport:
        """Iterate to the fixed point from the current state."""
        o = options or PartitionedOptions()
        comm = self.prob.mesh.comm
        t0 = time.perf_counter()
        rep = PartitionedReport(False, 0, 0, 0, 0.0)
        P = self.film_fns[0]
        for k in range(1, o.max_iterations + 1):
            old = [f.x.array.copy() for f in self.film_fns]
            where = f"partitioned iteration {k}"
            rep.newton_film += self.film.solve(where=f"{where}: film").newton_iterations
            for f, a in zip(self.film_fns, old, strict=True):
                f.x.array[:] = a + o.relaxation * (f.x.array - a)
            rep.newton_solid += self.solid.solve(where=f"{where}: elasticity").newton_iterations
            n_own = P.function_space.dofmap.index_map.size_local
            d = float(np.abs(P.x.array[:n_own] - old[0][:n_own]).max(initial=0.0))
            dmax = comm.allreduce(d, op=MPI.MAX)
            pmax = comm.allreduce(float(np.abs(P.x.array[:n_own]).max(initial=0.0)), op=MPI.MAX)
            change = dmax / max(pmax, 1e-300) / o.relaxation  # the unrelaxed change
            rep.changes.append(change)
            rep.iterations = k
            if change < o.tol:
                rep.converged = True
                break
            if time.perf_counter() - t0 > o.max_time_s:
                break
        rep.wall_time_s = time.perf_counter() - t0
        return rep

    def destroy(self) -> None:
        self.solid.destroy()
        self.film.destroy()


def partitioned_start(
    prob: Any, pressure_guess: Any, peak_gap: float, speeds: list[float], relaxation: float
) -> dict[str, Any]:
    """First point of a scene with ``solver = "partitioned"``.

    Warm start (the deformation under ``pressure_guess`` [Pa, UFL], with the gap
    ``peak_gap`` [m] at its peak), then the partitioned loop at each of ``speeds``
    [m/s] in turn (the scene's start speed up to its target: the same path as the
    monolithic start, each step solved by the partitioned scheme).

    Raises:
        SolverError: a loop did not converge; ``partial`` holds the last speed reached.
    """
    t0 = time.perf_counter()
    its = prob.warm_start(pressure_guess, peak_gap)
    prob.set_fraction(1.0)
    ps = PartitionedSolver(prob)
    iterations = 0
    last = None
    try:
        for s in speeds:
            prob.film.set_speed(s)
            try:
                rep = ps.solve(PartitionedOptions(relaxation=relaxation))
            except SolverError as e:
                raise SolverError(
                    f"partitioned scheme (relaxation {relaxation:g}) failed at "
                    f"{s:.3g} m/s: {e.what}", where=prob.name, partial={"speed": last},
                ) from e  # fmt: skip
            its += rep.newton_solid + rep.newton_film
            iterations += rep.iterations
            if not rep.converged:
                raise SolverError(
                    f"partitioned scheme (relaxation {relaxation:g}) not converged at "
                    f"{s:.3g} m/s after {rep.iterations} iterations (last relative pressure "
                    f"change {rep.changes[-1]:.2e})", where=prob.name, partial={"speed": last},
                )  # fmt: skip
            last = s
    finally:
        ps.destroy()
    return {
        "newton_iterations": its,
        "coupling_iterations": iterations,
        "solve_time_s": time.perf_counter() - t0,
        "strategy": f"partitioned (relaxation {relaxation:g}), {len(speeds)} speeds",
    }


__all__ = ["PartitionedOptions", "PartitionedReport", "PartitionedSolver", "partitioned_start"]
