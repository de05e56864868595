# %% [markdown]
# # Demo: the 2D obstacle problem as a variational inequality (exact solution known)
#
# Find $u \ge \psi$ on $\Omega = [-2, 2]^2$ with $u = g$ on the boundary such that
#
# $$ u \ge \psi, \qquad -\Delta u \ge 0, \qquad (u - \psi)\, \Delta u = 0 \quad \text{in } \Omega, $$
#
# the obstacle being the hemisphere $\psi(r) = \sqrt{1 - r^2}$ for $r \le 1$
# and $-1$ beyond.  The exact solution is radial: the hemisphere on the contact
# disc $r \le r^*$ and the harmonic, $C^1$-matched branch
# $-(r^*)^2 \ln(r/2) / \sqrt{1 - (r^*)^2}$ outside, with $r^* = 0.697965\ldots$
# (`dolfinx_seal.verification.obstacle`).  The weak form is a bound-constrained
# Newton (`vinewtonrsls` of `dolfinx_seal.solvers.NonlinearSolver`, lower bound
# the nodal obstacle), solved cold or on nested meshes.
#
# Run: `scripts/dx python3 demos/obstacle.py --cells 64`

# %%
from __future__ import annotations

import argparse
import time
from typing import Any

import dolfinx
import numpy as np
import ufl
from mpi4py import MPI

from dolfinx_seal.mpi import print0
from dolfinx_seal.solvers import NonlinearSolver, SNESOptions
from dolfinx_seal.solvers.continuation import nested_solve
from dolfinx_seal.verification import obstacle as ref

DESCRIPTION = "The 2D obstacle problem as a variational inequality (exact solution known)"

# %% [markdown]
# ## The discrete problem
# P1 elements; the residual $\int \nabla u \cdot \nabla v\, dx$, the exact
# solution as Dirichlet data, the obstacle interpolated at the nodes as the
# lower bound of the VI.


# %%


def build(
    cells: int, comm: MPI.Comm = MPI.COMM_WORLD
) -> tuple[NonlinearSolver, dolfinx.fem.Function]:
    """The P1 obstacle VI on a ``cells x cells`` mesh of [-2, 2]^2."""
    mesh = dolfinx.mesh.create_rectangle(comm, [[-2.0, -2.0], [2.0, 2.0]], [cells, cells])
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1))
    u = dolfinx.fem.Function(V, name="u")
    v = ufl.TestFunction(V)
    residual = ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx
    g = dolfinx.fem.Function(V)
    g.interpolate(ref.exact)
    mesh.topology.create_connectivity(1, 2)
    facets = dolfinx.mesh.exterior_facet_indices(mesh.topology)
    bc = dolfinx.fem.dirichletbc(g, dolfinx.fem.locate_dofs_topological(V, 1, facets))
    lower = dolfinx.fem.Function(V)
    lower.interpolate(ref.obstacle)
    solver = NonlinearSolver(
        residual, u, [bc], lower=lower, options=SNESOptions(max_it=200), name="obstacle"
    )
    return solver, u


# %% [markdown]
# ## Errors against the exact solution
# The largest nodal error, the $L^2$ error, and the contact radius read off
# the active set (nodes where $u = \psi$) against $r^*$.


# %%
def errors(u: dolfinx.fem.Function) -> dict[str, float]:
    """Max nodal error and L2 error against the exact solution; contact radius from the active set."""
    comm = u.function_space.mesh.comm
    V = u.function_space
    n = V.dofmap.index_map.size_local
    x = V.tabulate_dof_coordinates()[:n].T
    err = np.abs(u.x.array[:n] - ref.exact(x))
    max_err = comm.allreduce(float(err.max(initial=0.0)), op=MPI.MAX)
    ue = dolfinx.fem.Function(V)
    ue.interpolate(ref.exact)
    l2 = np.sqrt(
        comm.allreduce(
            dolfinx.fem.assemble_scalar(dolfinx.fem.form((u - ue) ** 2 * ufl.dx)), op=MPI.SUM
        )
    )
    # contact area = nodes where u sits on the obstacle, as an equivalent radius
    r = np.sqrt(x[0] ** 2 + x[1] ** 2)
    on = (np.abs(u.x.array[:n] - ref.obstacle(x)) < 1e-9) & (r < 1.0)
    r_contact = comm.allreduce(float(r[on].max(initial=0.0)), op=MPI.MAX)
    return {"max_error": max_err, "l2_error": float(l2), "contact_radius": r_contact}


# %% [markdown]
# ## Cold and nested solves
# Cold: one VI solve from $u = 0$.  Nested: levels of `cells/8`, `/4`, `/2` and
# `cells`, each started from the interpolated solution of the one below.


# %%
def run(
    cells: int = 64, strategy: str = "nested", comm: MPI.Comm = MPI.COMM_WORLD
) -> dict[str, Any]:
    """Solve once; ``strategy`` is ``"cold"`` or ``"nested"`` (levels cells/8, /4, /2, cells)."""
    t0 = time.perf_counter()
    if strategy == "cold":
        solver, u = build(cells, comm)
        solver.solve()
        its = solver.history.newton_iterations
    else:
        sizes = [max(cells // 2**k, 4) for k in (3, 2, 1, 0)]
        solver, u, reps = nested_solve(lambda n: build(n, comm), sizes)
        its = reps[-1].newton_iterations
    out = {"cells": cells, "strategy": strategy, "newton_iterations_finest": its,
           "wall_time_s": time.perf_counter() - t0, **errors(u),
           "complementarity": solver.history.complementarity}  # fmt: skip
    solver.destroy()
    return out


# %% [markdown]
# ## The table
# One line per mesh and strategy: Newton steps on the finest level, time and errors.


# %%
def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=DESCRIPTION)
    parser.add_argument("--cells", type=int, nargs="+", default=[16, 32, 64, 128])
    args = parser.parse_args(argv)
    print0(f"exact contact radius r* = {ref.free_boundary_radius():.6f}")
    print0(
        f"{'cells':>6} {'strategy':>8} {'Newton':>6} {'time/s':>7} {'max err':>10} {'L2 err':>10} {'r_c':>7}"
    )
    for n in args.cells:
        for s in ("cold", "nested"):
            r = run(n, s)
            print0(f"{n:6d} {s:>8} {r['newton_iterations_finest']:6d} {r['wall_time_s']:7.2f} "
                   f"{r['max_error']:10.3e} {r['l2_error']:10.3e} {r['contact_radius']:7.4f}")  # fmt: skip


if __name__ == "__main__":
    main()
