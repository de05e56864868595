"""Benchmark (issue 18): the 30-speed ball Stribeck sweep, one chain or several.

The demo system (S1 figure 18: R = 1 cm, F = 1.3 N, E* = 1.6 MPa, eta = 0.1 Pa s,
h_rms = 1 um) on the demo mesh (contact elements a_Hertz / 15; ``--per-a``), ``--points``
speeds of the 30 from 1 to 0.01 m/s (equal ratios), run as ``--chains K`` chains
on the ranks of the ``mpirun`` (K = 1: one chain on every rank).  Recorded in
one row of ``<out>/perf.csv``:

* the wall time of the sweep, and per point: Newton steps and solve time;
* the unit of cost: one linear-elastic solve of the same mesh and space
  (assembly of the elasticity matrix and load, MUMPS factorisation, solve; the
  fastest of three), measured on one chain's ranks; a continuation point's cost
  in these units;
* the per-step profile from PETSc's event log (rank 0 of the world, its chain's
  solves): Jacobian assembly, analysis, numeric factorisation, triangular solves,
  Krylov iterations per linear solve;
* the peak resident memory of the ranks (summed, and the largest), the whole
  process: mesh, forms, the factorisations;
* ``--point-files K`` as the CLI's sweep: the film maps (about 1 s each on rank 0)
  of every K-th speed only;
* with ``--reference`` (a ``sweep.csv`` of the same sweep, e.g. an earlier
  solver's), the largest relative difference of mu, h_central and h_min at the
  shared speeds.

Run (``make bench-perf`` runs the solver before issue 18 first, ``--label before``
with the options of its ``PERF_BEFORE``, then these three layouts with
``--reference`` to its ``sweep.csv``, on 2 cores)::

    scripts/dx python3 bench/perf.py --chains 1
    scripts/dx mpirun -n 2 python3 bench/perf.py --chains 1
    scripts/dx mpirun -n 2 python3 bench/perf.py --chains 2

``--set lubricated=false`` runs the dry ball at its load instead (one point; with
``--set contact.model=stiff`` the smooth Hertz contact, which starts in a few
Newton steps).

The 2-rank speed-up of one point at a/20 (``make bench-point``): the first speed
alone, ``--points 1 --per-a 20``, on one rank and on two.  ``--solver
FIELD=VALUE`` sets :class:`~dolfinx_seal.solvers.SNESOptions` fields for every
solver (e.g. ``vi_linear_solve=submatrix``, PETSc's own reduced-space solve);
``--petsc KEY=VALUE`` gives PETSc options to every solver (e.g. MUMPS's block
low-rank factorisation, ``mat_mumps_icntl_35=2 --petsc mat_mumps_cntl_7=1e-8``).
"""

from __future__ import annotations

import argparse
import logging
import resource
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from solver_levers import EVENTS, _events, add_solver_arguments, solver_options

from demos.ball_stribeck import parameters
from dolfinx_seal.mpi import COMM_WORLD, bcast_path, print0, setup_logging, using_comm
from dolfinx_seal.output import SweepWriter, parse_cell, read_csv
from dolfinx_seal.scenes import make_parameters, run_scene, sweep_chains, sweep_scene


def linear_elastic_solve_time(p: Any, comm: Any, repeats: int = 3) -> tuple[float, int]:
    """Fastest of ``repeats`` linear-elastic solves on the ball's mesh and displacement
    space (P``p.degree`` vectors; fixed top, unit pressure on the contact face) with
    MUMPS: assembly + factorisation + solve [s], and the unknowns."""
    import dolfinx
    import ufl
    from dolfinx.fem.petsc import assemble_matrix, assemble_vector, set_bc

    from dolfinx_seal.scenes.ball import BALL

    s = BALL.scales(p)
    tm = BALL.mesh(p, s, comm)
    mesh = tm.mesh
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", p.degree, (mesh.geometry.dim,)))
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    E, nu = 2.0e6, 0.45
    mu_, lam = E / (2 * (1 + nu)), E * nu / ((1 + nu) * (1 - 2 * nu))

    def eps(w: Any) -> Any:
        return ufl.sym(ufl.grad(w))

    a = dolfinx.fem.form(
        (2 * mu_ * ufl.inner(eps(u), eps(v)) + lam * ufl.div(u) * ufl.div(v)) * ufl.dx
    )
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tm.facet_tags)
    n = ufl.FacetNormal(mesh)
    L = dolfinx.fem.form(-1e3 * ufl.dot(n, v) * ds(tm.tag("contact")))
    fdim = mesh.topology.dim - 1
    top = dolfinx.fem.locate_dofs_topological(V, fdim, tm.facet_tags.find(tm.tag("load")))
    zero = dolfinx.fem.Function(V)
    bc = dolfinx.fem.dirichletbc(zero, top)
    best = np.inf
    for _ in range(repeats):
        comm.barrier()
        t0 = time.perf_counter()
        A = assemble_matrix(a, bcs=[bc])
        A.assemble()
        b = assemble_vector(L)
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        set_bc(b, [bc])
        ksp = PETSc.KSP().create(comm)
        ksp.setOperators(A)
        ksp.setType("preonly")
        ksp.getPC().setType("lu")
        ksp.getPC().setFactorSolverType("mumps")
        x = b.duplicate()
        ksp.solve(b, x)
        comm.barrier()
        best = min(best, time.perf_counter() - t0)
        for obj in (ksp, A, b, x):
            obj.destroy()
    return best, V.dofmap.index_map.size_global * V.dofmap.index_map_bs


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=30, help="speeds of the 30 (from 1 m/s)")
    parser.add_argument("--chains", type=int, default=1)
    parser.add_argument("--per-a", type=float, default=15.0,
                        help="contact elements per Hertz radius (the demo mesh: 15)")  # fmt: skip
    parser.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                        help="parameter overrides (e.g. stepping.tangent=true)")  # fmt: skip
    add_solver_arguments(parser)
    parser.add_argument("--point-files", type=int, default=1, metavar="K",
                        help="film maps of the first speed, every K-th after it and the "
                        "last (the CLI's sweep --point-files; 0: none, 1: every speed)")  # fmt: skip
    parser.add_argument("--label", default="", help="name of the row (default: the layout)")
    parser.add_argument("--reference", help="sweep.csv to compare mu, h_central, h_min with")
    parser.add_argument("--out", default="bench/results/perf")
    parser.add_argument("-v", "--verbose", action="store_true",
                        help="log every Newton step and continuation step (stderr, rank 0)")  # fmt: skip
    args = parser.parse_args(argv)
    options = solver_options(parser, args)
    if args.verbose:
        setup_logging(logging.DEBUG)
    PETSc.Log.begin()
    out = bcast_path(args.out)
    ranks = COMM_WORLD.size
    label = args.label or f"{ranks} rank(s), {args.chains} chain(s)"
    speeds = [float(v) for v in np.logspace(0.0, -2.0, 30)[: args.points]]
    p = parameters(args.per_a, roughness={"h_rms": 1e-6})
    if args.set:
        p = make_parameters("ball", overrides=args.set,
                            values={"h_contact": p.h_contact, "rim_refinement": p.rim_refinement,
                                    "roughness": {"h_rms": 1e-6}})  # fmt: skip
    # the unit of cost on one chain's ranks
    color = COMM_WORLD.rank * args.chains // ranks
    sub = COMM_WORLD.Split(color, key=COMM_WORLD.rank)
    with using_comm(sub):
        t_le, n_le = linear_elastic_solve_time(p, sub)
    t_le = COMM_WORLD.bcast(t_le, root=0)
    folder = out / label.replace(" ", "_").replace(",", "").replace("(", "").replace(")", "")
    before = _events()
    t0 = time.perf_counter()
    dry = not p.lubricated
    if dry and (args.chains != 1 or args.points != 1):
        parser.error("lubricated=false: one dry point (--points 1 --chains 1)")
    with options:
        if dry:  # the dry ball at its load (no film, no speed)
            res = run_scene("ball", p, folder, force=True)
        elif args.chains == 1:
            sweep_scene("ball", p, folder, "film.speed", speeds, force=True,
                        point_files=args.point_files)  # fmt: skip
        else:
            sweep_chains("ball", p, folder, "film.speed", speeds, args.chains, force=True,
                         point_files=args.point_files)  # fmt: skip
    wall = time.perf_counter() - t0
    after = _events()
    if dry:
        rows = [{k: res[k] for k in ("dofs", "newton_iterations", "wall_time_s")}]
    else:
        done = folder / "sweep.csv"  # absent when the first point failed
        rows = [{k: parse_cell(v) for k, v in r.items()} for r in read_csv(done)] \
            if COMM_WORLD.rank == 0 and done.exists() else []  # fmt: skip
        rows = COMM_WORLD.bcast(rows, root=0)
    steps = [int(r["newton_iterations"]) for r in rows]
    times = [float(r["wall_time_s"]) for r in rows]
    later = [t for t, r in zip(times, rows, strict=True) if (r.get("continuation_steps") or 0) > 0]
    jac = max(after["jacobian"][0] - before["jacobian"][0], 1)
    row: dict[str, Any] = {
        "layout": label,
        "ranks": ranks,
        "chains": args.chains,
        "options": " ".join([*args.set, *args.solver, *args.petsc]) or "(defaults)",
        "point_files": args.point_files,
        "points": len(rows),
        "points_asked": len(speeds),
        "dofs": int(rows[0]["dofs"]) if rows else 0,
        "elements_per_a": args.per_a,
        "wall_s": wall,
        "newton_steps": ";".join(str(s) for s in steps),
        "newton_total": sum(steps),
        "le_solve_s": t_le,
        "le_unknowns": n_le,
        "continuation_point_s": float(np.median(later)) if later else float("nan"),
        "continuation_point_le_solves": float(np.median(later)) / t_le if later else float("nan"),
        "newton_step_s": (after["jacobian"][1] - before["jacobian"][1]) / jac,
    }
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # this rank's peak [MB]
    row["peak_rss_mb_sum"] = COMM_WORLD.allreduce(rss)
    row["peak_rss_mb_max"] = COMM_WORLD.allreduce(rss, op=MPI.MAX)
    for key in EVENTS:
        n = max(after[key][0] - before[key][0], 1)
        row[f"{key}_count"] = after[key][0] - before[key][0]
        row[f"{key}_s_each"] = (after[key][1] - before[key][1]) / n
    if args.reference:
        ref = {round(float(r["speed"]), 12): r for r in read_csv(args.reference)}
        diff = 0.0
        for r in rows:
            q = ref.get(round(float(r["speed"]), 12))
            if q is None:
                continue
            for key in ("mu", "h_central", "h_min"):
                diff = max(diff, abs(float(r[key]) / float(q[key]) - 1.0))
        row["max_rel_diff_vs_reference"] = diff
    SweepWriter(out, "perf.csv", resume=True).append(row)
    print0(f"| {label} | {row['points']}/{len(speeds)} | {wall:.0f} s | {sum(steps)} | "
           f"{row['continuation_point_s']:.1f} s = {row['continuation_point_le_solves']:.1f} LE | "
           f"LE {t_le:.2f} s | diff {row.get('max_rel_diff_vs_reference', float('nan')):.1e} |")  # fmt: skip
    print0(f"written: {out / 'perf.csv'}")


if __name__ == "__main__":
    main()
