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

The force equation may go with the body instead (``position = "solid"``: the
film at a fixed counter, the body and the counter position together), as on the
lip sector, whose film solves hold the shaft; a periodic problem's body solve
keeps its constraints (:class:`~dolfinx_seal.solvers.assembly.ProjectedMPCAssembly`),
and a scene may give its own film solve (``film_step``: the sector's film with
its fallbacks).
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from mpi4py import MPI

from dolfinx_seal.errors import SolverError
from dolfinx_seal.mpi import get_logger
from dolfinx_seal.params import check_choice, check_int_range, check_positive, check_range
from dolfinx_seal.solid.step_limits import displacement_limiter
from dolfinx_seal.solvers import NonlinearSolver
from dolfinx_seal.solvers.assembly import ProjectedMPCAssembly

#: The sub-solves' tolerances: to their round-off floor (the step criterion), not
#: to the coupled solver's.  Those are relative to the forcing scale ``|F(0)|``
#: (:meth:`~dolfinx_seal.solvers.NonlinearSolver.residual_scale`), which for the
#: body alone is the rubber undeformed into the counter, decades above the
#: coupled residual: on the cylinder (20 um, 1e-3 m/s, relaxation 0.1) the
#: elasticity solve then stopped at a residual of 1.3e-3 (the coupled solver's
#: converged one 1e-11) and the loop's fixed point lay 5e-6 off the monolithic
#: point in mu, 3.3e-5 in h_min; solved to round-off, 2.5e-9 and 5.5e-9.
SUBSOLVE_TOLERANCES = {"rtol": 1e-20, "atol": 1e-300}
#: iterations between the loop's progress lines (the logger's ``info``)
PROGRESS_EVERY = 10


@dataclass(frozen=True)
class PartitionedOptions:
    """Partitioned-scheme options.

    Attributes:
        relaxation: Under-relaxation factor omega of the fluid pressure (S0: 0.01-0.1).
        tol: Relative change of the fluid pressure (max norm) that ends the loop.
        max_iterations: Largest number of coupling iterations.
        max_time_s: Wall-time budget [s] (the loop stops unconverged after it).
        stall_iterations: The loop stops unconverged when the change has not halved
            in this many iterations: not fallen below half the last change that did
            (the first change counts as halved; 0: never stops so).
    """

    relaxation: float = 0.1
    tol: float = 1e-6
    max_iterations: int = 5000
    max_time_s: float = 1e30
    stall_iterations: int = 0

    def __post_init__(self) -> None:
        check_range("relaxation", self.relaxation, 0.0, 1.0, lo_open=True)
        check_positive("tol", self.tol)
        check_int_range("max_iterations", self.max_iterations, 1)
        check_positive("max_time_s", self.max_time_s, "s")
        check_int_range("stall_iterations", self.stall_iterations, 0)


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
    """Alternating elasticity / film solves on a coupled :class:`SolidContactProblem`.

    Args:
        prob: The coupled problem (a film and a deformable bulk).
        position: Under force control, the sub-problem that carries the counter
            position and its force equation: ``"film"`` (S1 appendix D) or
            ``"solid"`` (the body and the counter together, the film at a fixed
            counter).
        film_step: The film solve on the frozen deformation, ``film_step(where)``
            returning its Newton steps (default: a solver of the film's rows, with
            the force equation when ``position = "film"``).
        solid_options: Overrides of the body solve's SNES options (default: the
            problem's, with ``newtonls`` and :data:`SUBSOLVE_TOLERANCES`).
    """

    def __init__(
        self,
        prob: Any,
        position: str = "film",
        film_step: Callable[[str], int] | None = None,
        solid_options: dict[str, Any] | None = None,
    ) -> None:
        if prob.film is None or not prob.bulk:
            raise SolverError("the partitioned scheme needs a film and a deformable bulk",
                              where=prob.name)  # fmt: skip
        check_choice("position", position, ("film", "solid"))
        self.prob = prob
        film = prob.film
        film_fns = [b[1] for b in film.blocks]
        force = prob.control == "force"
        ids = [i for i, b in enumerate(prob.blocks)
               if b[1] is prob.w or (force and position == "solid" and b[1] is prob.position)]  # fmt: skip
        solid_blocks = [prob.blocks[i] for i in ids]
        pos_block = [
            b for b in prob.blocks if force and position == "film" and b[1] is prob.position
        ]
        opts = prob.solver.options
        s_opts = dataclasses.replace(
            opts, snes_type="newtonls", **{**SUBSOLVE_TOLERANCES, **(solid_options or {})}
        )
        limiter = None
        lim = prob.limits
        if lim.max_step or lim.max_gap_step:  # the problem's step limits, this layout
            limiter = displacement_limiter(
                prob, lim.max_step, lim.max_gap_step, blocks=solid_blocks
            )
        cons = prob.constraints
        assembly = None
        if cons is not None:  # the periodic constraints of the body's blocks
            picked = [cons[i] for i in ids]
            assembly = ProjectedMPCAssembly(picked[0] if len(picked) == 1 else picked)
        F, u = [b[0] for b in solid_blocks], [b[1] for b in solid_blocks]
        self.solid = NonlinearSolver(
            F[0] if len(F) == 1 else F, u[0] if len(u) == 1 else u, prob._dirichlet_bcs,
            options=s_opts, name=f"{prob.name} elasticity", step_limiter=limiter,
            assembly=assembly,
        )  # fmt: skip
        self.film = None
        if film_step is None:
            f_opts = dataclasses.replace(opts, **SUBSOLVE_TOLERANCES)
            self.film = film.make_solver(f_opts, pos_block, name=f"{prob.name} film")
            film_step = self._own_film_step
        self.film_step = film_step
        self.film_fns = film_fns

    def _own_film_step(self, where: str) -> int:
        return self.film.solve(where=where).newton_iterations

    def solve(
        self, options: PartitionedOptions | None = None, where: str = ""
    ) -> PartitionedReport:
        """Iterate to the fixed point from the current state (``where`` prefixes the
        sub-solves' failure messages)."""
        o = options or PartitionedOptions()
        comm = self.prob.mesh.comm
        t0 = time.perf_counter()
        rep = PartitionedReport(False, 0, 0, 0, 0.0)
        P = self.film_fns[0]
        best, best_at = math.inf, 0
        for k in range(1, o.max_iterations + 1):
            old = [f.x.array.copy() for f in self.film_fns]
            where_k = (
                f"{where}: partitioned iteration {k}" if where else f"partitioned iteration {k}"
            )
            rep.newton_film += self.film_step(f"{where_k}: film")
            for f, a in zip(self.film_fns, old, strict=True):
                f.x.array[:] = a + o.relaxation * (f.x.array - a)
            rep.newton_solid += self.solid.solve(where=f"{where_k}: elasticity").newton_iterations
            n_own = P.function_space.dofmap.index_map.size_local
            d = float(np.abs(P.x.array[:n_own] - old[0][:n_own]).max(initial=0.0))
            dmax = comm.allreduce(d, op=MPI.MAX)
            pmax = comm.allreduce(float(np.abs(P.x.array[:n_own]).max(initial=0.0)), op=MPI.MAX)
            change = dmax / max(pmax, 1e-300) / o.relaxation  # the unrelaxed change
            rep.changes.append(change)
            rep.iterations = k
            if k % PROGRESS_EVERY == 0:  # a loop can run for minutes: show where it is
                get_logger().info("%s: relative pressure change %.2e", where_k, change)
            if change < o.tol:
                rep.converged = True
                break
            if time.perf_counter() - t0 > o.max_time_s:
                break
            if change < 0.5 * best:
                best, best_at = change, k
            if o.stall_iterations and k - best_at >= o.stall_iterations:
                break
        rep.wall_time_s = time.perf_counter() - t0
        return rep

    def destroy(self) -> None:
        self.solid.destroy()
        if self.film is not None:
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
