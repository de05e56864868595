# %% [markdown]
# # Demo: a rigid cylinder on a plane, Reynolds film with the Reynolds cavitation condition
#
# The 1D free-boundary problem of `dolfinx_seal.film.rigid_cylinder`: in the
# dimensionless variables $X = x / \sqrt{2 R h_0}$ (gap $H = 1 + X^2$) and
# $P = p\, h_0 \sqrt{2 R h_0} / (24 \eta R U_m)$ the film pressure solves
#
# $$ \frac{d}{dX}\Big( H^3 \frac{dP}{dX} \Big) = \frac{dH}{dX}, \qquad
#    P(-X_\mathrm{in}) = P(X_\mathrm{out}) = 0, $$
#
# with the Reynolds (Swift-Stieber) condition downstream: $P \ge 0$ everywhere,
# the equation holds where $P > 0$, and $P = dP/dX = 0$ at the free boundary
# $X_c$ where the film cavitates.  It is a variational inequality (lower bound
# $P \ge 0$), solved with three strategies and compared with the independent
# Martin reference of `dolfinx_seal.verification.martin` (the cavitation point
# $X_c$ and the load $W = \int P\, dX$):
#
# * `cold` -- `vinewtonrsls` from $P = 0$: the active set moves about one
#   node per Newton step, so the step count grows with the mesh;
# * `penalty` -- penalty continuation ($\kappa$ from 1 to $10^8$) then the exact VI;
# * `nested` -- coarse-to-fine levels (doubling), each level started from the
#   interpolated solution of the one below: 1-2 steps per level.
#
# Writes into `--out`: `solver_table.csv` (Newton steps and wall time per
# size and strategy), `pressure.png` (FEM against the reference) and
# `results.json`.
#
# Run: `scripts/dx python3 demos/reynolds_1d.py --out results/demo` (as a
# script, or cell by cell in Jupyter through Jupytext's percent format).

# %%
from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

import numpy as np
from mpi4py import MPI

from dolfinx_seal.errors import SolverError
from dolfinx_seal.film.rigid_cylinder import RigidCylinderFilm, RigidCylinderParameters
from dolfinx_seal.mpi import bcast_path, print0
from dolfinx_seal.output import SweepWriter, write_results
from dolfinx_seal.solvers import SNESOptions
from dolfinx_seal.solvers.continuation import nested_solve
from dolfinx_seal.verification.martin import martin_solution

STRATEGIES = ("cold", "penalty", "nested")
DESCRIPTION = "Rigid cylinder on a plane: Reynolds film with the Reynolds cavitation condition"

# %% [markdown]
# ## The nested levels
# The mesh sizes of the nested strategy halve down to about 500 cells.


# %%


def nested_sizes(cells: int, coarsest: int = 500) -> list[int]:
    """Levels ``cells / 2^k`` down to about ``coarsest`` cells, coarsest first."""
    sizes = [cells]
    while sizes[-1] // 2 >= coarsest:
        sizes.append(sizes[-1] // 2)
    return sizes[::-1]


# %% [markdown]
# ## One solve
# Each strategy builds the same `RigidCylinderFilm`; a strategy that does not
# converge within `max_it` steps is a row with `converged = False`, not an error.


# %%
def solve(
    cells: int,
    strategy: str = "nested",
    x_in: float = 10.0,
    x_out: float = 2.0,
    max_it: int = 200,
    comm: MPI.Comm = MPI.COMM_WORLD,
) -> tuple[dict[str, Any], RigidCylinderFilm | None]:
    """Solve the problem with ``cells`` cells by ``strategy``; return figures and the problem.

    A strategy that does not converge within ``max_it`` steps is reported with
    ``converged = False`` (and its step count), not raised.
    """
    opts = SNESOptions(max_it=max_it)

    def make(n: int) -> RigidCylinderFilm:
        return RigidCylinderFilm(
            RigidCylinderParameters(x_in=x_in, x_out=x_out, cells=n, snes=opts), comm
        )

    t0 = time.perf_counter()
    prob: RigidCylinderFilm | None = None
    row: dict[str, Any] = {"cells": cells, "strategy": strategy}
    try:
        if strategy == "cold":
            prob = make(cells)
            prob.solver.solve()
            its = prob.solver.total_newton_iterations
        elif strategy == "penalty":
            prob = make(cells)
            prob.solver.solve_penalty()
            its = prob.solver.total_newton_iterations
        elif strategy == "nested":
            holder: dict[str, RigidCylinderFilm] = {}

            def build(n: int):
                holder["p"] = make(n)
                return holder["p"].solver, holder["p"].p

            _, _, reps = nested_solve(build, nested_sizes(cells))
            prob = holder["p"]
            its = reps[-1].newton_iterations
            row["newton_iterations_all_levels"] = sum(r.newton_iterations for r in reps)
            row["levels"] = len(reps)
        else:
            raise ValueError(f"strategy must be one of {STRATEGIES}, got {strategy!r}")
        row.update(converged=True, newton_iterations=its)
    except SolverError as e:
        row.update(converged=False, newton_iterations=e.history.newton_iterations, error=e.what)
        prob = None
    row["wall_time_s"] = time.perf_counter() - t0
    if prob is not None:
        row.update(prob.quantities())
    return row, prob


# %% [markdown]
# ## The pressure against the reference
# Rank 0 gathers the nodal pressure and draws it with Martin's profile; the
# dotted line is the reference cavitation point $X_c$.


# %%
def plot(prob: RigidCylinderFilm, x_in: float, path: Path) -> None:
    """Pressure profile against the reference (rank 0 draws; data gathered)."""
    comm = prob.mesh.comm
    n = prob.V.dofmap.index_map.size_local
    x = prob.V.tabulate_dof_coordinates()[:n, 0]
    p = prob.p.x.array[:n]
    xs = comm.gather(x, root=0)
    ps = comm.gather(p, root=0)
    if comm.rank != 0:
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from dolfinx_seal.verification.martin import pressure

    x = np.concatenate(xs)
    p = np.concatenate(ps)
    order = np.argsort(x)
    ref = martin_solution(x_in)
    xr = np.linspace(-3.0, ref.x_cavitation, 400)
    fig, ax = plt.subplots(figsize=(6.4, 3.6))
    ax.plot(x[order], p[order], "-", lw=2, label=f"FEM, {len(x) - 1} cells (VI, P >= 0)")
    ax.plot(
        xr, [pressure(t, x_in, ref.x_cavitation) for t in xr], "k--", lw=1, label="Martin reference"
    )
    ax.axvline(ref.x_cavitation, color="grey", lw=0.8, ls=":")
    ax.set_xlim(-3.0, 1.5)
    ax.set_xlabel(r"$X = x / \sqrt{2 R h_0}$")
    ax.set_ylabel(r"$P = p\, h_0 \sqrt{2 R h_0} / (24 \eta R U_m)$")
    ax.set_title("Rigid cylinder on a plane: Reynolds cavitation condition")
    ax.legend(frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


# %% [markdown]
# ## The solver table
# Every size with every strategy (the cold start only up to `--cold-max-cells`,
# it needs about 0.04 Newton steps per cell): the errors in $X_c$ and $W$ and
# the film's mass balance.


# %%
def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=DESCRIPTION)
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 100000])
    parser.add_argument("--strategies", nargs="+", default=list(STRATEGIES), choices=STRATEGIES)
    parser.add_argument("--x-in", type=float, default=10.0, help="inlet distance upstream")
    parser.add_argument("--max-it", type=int, default=200, help="Newton step limit per solve")
    parser.add_argument("--cold-max-cells", type=int, default=20000,
                        help="skip the cold start above this size (it needs ~0.04 steps per cell)")  # fmt: skip
    parser.add_argument("--out", default="results/demo")
    args = parser.parse_args(argv)
    out = bcast_path(args.out)
    ref = martin_solution(args.x_in)
    print0(
        f"reference (inlet at X = -{args.x_in:g}): X_c = {ref.x_cavitation:.8f}, load W = {ref.load:.8f}"
    )
    print0(
        f"{'cells':>8} {'strategy':>8} {'Newton':>6} {'time/s':>8} {'X_c err':>9} {'W err':>9} {'mass bal':>9}"
    )
    table = SweepWriter(out, "solver_table.csv")
    last = None
    for n in args.sizes:
        for s in args.strategies:
            if s == "cold" and n > args.cold_max_cells:
                continue
            row, prob = solve(n, s, x_in=args.x_in, max_it=args.max_it)
            if prob is not None:
                row["x_cavitation_error"] = abs(row["x_cavitation"] - ref.x_cavitation)
                row["load_error"] = abs(row["load"] - ref.load) / ref.load
                last = (row, prob)
                print0(f"{n:8d} {s:>8} {row['newton_iterations']:6d} {row['wall_time_s']:8.2f} "
                       f"{row['x_cavitation_error']:9.2e} {row['load_error']:9.2e} {row['mass_balance_error']:9.1e}")  # fmt: skip
            else:
                print0(
                    f"{n:8d} {s:>8} {row['newton_iterations']:6d} {row['wall_time_s']:8.2f}  not converged: {row['error']}"
                )
            table.append({k: row.get(k, "") for k in (
                "cells", "strategy", "converged", "newton_iterations",
                "newton_iterations_all_levels", "wall_time_s",
                "x_cavitation", "load", "x_cavitation_error", "load_error", "mass_balance_error")})  # fmt: skip
    if last is None:
        return 1
    row, prob = last
    plot(prob, args.x_in, out / "pressure.png")
    write_results(out, {
        "scene": "demo-reynolds-1d",
        "parameters": {"x_in": args.x_in, "sizes": args.sizes, "strategies": args.strategies},
        "x_cavitation": row["x_cavitation"], "load_dimensionless": row["load"],
        "reference_x_cavitation": ref.x_cavitation, "reference_load": ref.load,
        "mass_balance_error": row["mass_balance_error"], "newton_iterations": row["newton_iterations"],
        "ranks": MPI.COMM_WORLD.size, "converged": True,
    })  # fmt: skip
    print0(f"wrote {out}/solver_table.csv, {out}/pressure.png, {out}/results.json")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
