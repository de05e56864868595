"""Benchmark: monolithic Newton against the seeds' partitioned scheme, lubricated cylinder.

One run, one mesh (the S1 figure-4 cylinder, ``--h-contact``), three speeds
(boundary, mixed, hydrodynamic lubrication).  At each speed both schemes start
from the same state: the secant predictor (in log speed) from the converged
solutions one and half a decade lower (``--tangent``: the tangent predictor from
the point half a decade lower, a sweep's default, its time counted;
``--no-predictor``: the solution half a decade lower).  Measured: wall time and
iterations of

* the monolithic SNES VI (``vinewtonrsls`` and ``vinewtonssls``), preceded, as in
  a sweep, by the film-only solve on the predicted shape (``stepping.film_presolve``;
  its time is counted, its steps are reported apart; ``--no-film-presolve``: without);
* the partitioned scheme (:mod:`dolfinx_seal.coupled.partitioned`) at the
  seeds' relaxation factors (0.01, 0.03, 0.1) and at larger ones, stopped at a
  relative fluid-pressure change of ``--tol`` or after ``--budget`` seconds;
* one linear-elastic solve on the same mixed u-p space (assembly + MUMPS LU +
  solve) under the Hertz pressure: the unit cost of a coupled point.

Writes ``coupled_vs_partitioned.csv`` and prints a markdown table.

Run:  scripts/dx python3 bench/coupled_vs_partitioned.py [--out bench/results]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import ufl

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from solver_levers import solver_field

from dolfinx_seal.contact.hertz import hertz_line
from dolfinx_seal.coupled.continuation import (
    FilmPresolver,
    path_tangent,
    secant_predictor,
    tangent_predictor,
)
from dolfinx_seal.coupled.partitioned import PartitionedOptions, PartitionedSolver
from dolfinx_seal.coupled.results import lubricated_results
from dolfinx_seal.errors import SolverError
from dolfinx_seal.mpi import bcast_path, print0
from dolfinx_seal.output import SweepWriter
from dolfinx_seal.scenes import make_parameters
from dolfinx_seal.scenes.cylinder import build_lubricated, start_lubricated
from dolfinx_seal.solid.materials import LinearElastic
from dolfinx_seal.solvers import NonlinearSolver, SNESOptions, solver_session


def linear_elastic_solve_time(prob, params) -> float:
    """Wall time of one linear-elastic solve on the problem's displacement space."""
    mat = LinearElastic(params.material.E, params.material.nu, formulation="mixed")
    a_h, p_h = hertz_line(params.load, params.radius, params.material.E_star)
    X = prob.X
    w = prob.w.copy()
    w.x.array[:] = 0.0
    vw = ufl.TestFunction(prob.W)
    u, p_mix = ufl.split(w)
    v, _ = ufl.split(vw)
    energy = mat.small_strain_energy(prob.kin.eps(u), p_mix)
    R = ufl.derivative(energy * prob.dx, w, vw)
    pr = p_h * ufl.sqrt(ufl.max_value(1.0 - (X[0] / a_h) ** 2, 0.0))
    R += pr * ufl.dot(prob.N3, prob.kin.vector3(v)) * prob.ds_c
    s = NonlinearSolver(R, w, prob._dirichlet_bcs, options=SNESOptions(), name="linear elastic")
    t0 = time.perf_counter()
    s.solve()
    t = time.perf_counter() - t0
    s.destroy()
    return t


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds", type=float, nargs="+", default=[1e-5, 1e-3, 1e-1])
    parser.add_argument("--relaxations", type=float, nargs="+",
                        default=[0.01, 0.03, 0.1, 0.3, 0.5, 1.0])  # fmt: skip
    parser.add_argument("--h-contact", type=float, default=10e-6)
    parser.add_argument("--tol", type=float, default=1e-6)
    parser.add_argument("--budget", type=float, default=300.0, help="seconds per partitioned run")
    parser.add_argument("--out", default="bench/results")
    parser.add_argument("--no-predictor", dest="predictor", action="store_false",
                        help="start both schemes from the lower point, not the secant predictor")  # fmt: skip
    parser.add_argument("--tangent", action="store_true",
                        help="the tangent predictor (stepping.tangent) instead of the secant; "
                             "its time is counted in the monolithic point's")  # fmt: skip
    parser.add_argument("--no-film-presolve", dest="film_presolve", action="store_false",
                        help="monolithic Newton without the film-only solve before it")  # fmt: skip
    parser.add_argument("--solver", action="append", default=[], metavar="FIELD=VALUE",
                        help="SNESOptions fields for every solver (e.g. "
                             "vi_linear_solve=submatrix)")  # fmt: skip
    args = parser.parse_args(argv)
    with solver_session(**dict(solver_field(f) for f in args.solver)):
        run(args)


def run(args: argparse.Namespace) -> None:
    """The benchmark of :func:`main` (inside its solver session)."""
    out = bcast_path(args.out)
    w = SweepWriter(out, "coupled_vs_partitioned.csv")
    p0 = make_parameters("cylinder", values={"h_contact": args.h_contact,
                                             "film": {"speed": args.speeds[0] / 10**0.5}})  # fmt: skip
    prob, _ = build_lubricated(p0)
    start_lubricated(prob, p0)
    t_lin = linear_elastic_solve_time(prob, p0)
    print0(f"dofs {prob.dof_counts()}; one linear-elastic solve: {t_lin:.3f} s")
    presolver = FilmPresolver(prob) if args.film_presolve else None
    print0("| speed [m/s] | scheme | relaxation | iterations | Newton steps | wall time [s] | "
           "x linear solve | x monolithic | mu rel. diff | converged |")  # fmt: skip
    print0("|---|---|---|---|---|---|---|---|---|---|")
    for v in args.speeds:
        # the two converged points a sweep would hold: 1 and 1/2 decade below
        history = []
        for lower in (10.0, 10**0.5):
            prob.film.set_speed(v / lower)
            prob.solver.solve(where="bench start")
            history.append((math.log10(v / lower), prob.state()))
        prob.film.set_speed(v)
        t_pred = 0.0
        if args.predictor and args.tangent:  # stepping.tangent: counted in the point's time
            t0 = time.perf_counter()
            tangent = path_tangent(prob, v / 10**0.5)
            tangent_predictor(prob, tangent, v)
            tangent[1].destroy()
            t_pred = time.perf_counter() - t0
        elif args.predictor:  # the sweep's secant predictor (continuation.speed_sweep)
            secant_predictor(prob, history, v)
        start = prob.state()
        rows = []
        mono = {}
        for snes_type in ("vinewtonrsls", "vinewtonssls"):
            prob.restore(start)
            if prob.solver.options.snes_type != snes_type:  # a new SNES analyses afresh
                prob.solver.set_snes_type(snes_type)
            prob.film.set_speed(v)
            t0 = time.perf_counter()
            film_its = presolver.solve(f"bench {snes_type}") if presolver else 0
            try:
                its = prob.solver.solve(where=f"bench {snes_type}").newton_iterations
                ok = True
            except SolverError:
                its, ok = -1, False
            t = time.perf_counter() - t0 + t_pred
            mono[snes_type] = (t, lubricated_results(prob)["mu"] if ok else float("nan"))
            rows.append(dict(speed=v, scheme=f"monolithic {snes_type}", relaxation=float("nan"),
                             iterations=1, newton=its, film_newton=film_its, time=t,
                             converged=ok))  # fmt: skip
        prob.solver.set_snes_type("vinewtonrsls")
        t_ref, mu_ref = mono["vinewtonrsls"]
        for om in args.relaxations:
            prob.restore(start)
            prob.film.set_speed(v)
            ps = PartitionedSolver(prob)
            t0 = time.perf_counter()
            try:
                rep = ps.solve(
                    PartitionedOptions(relaxation=om, tol=args.tol, max_time_s=args.budget)
                )
                ok, iters, newton = (
                    rep.converged,
                    rep.iterations,
                    rep.newton_solid + rep.newton_film,
                )
            except SolverError:
                ok, iters, newton = False, -1, -1
            t = time.perf_counter() - t0
            ps.destroy()
            mu = lubricated_results(prob)["mu"] if ok else float("nan")
            rows.append(dict(speed=v, scheme="partitioned", relaxation=om, iterations=iters,
                             newton=newton, time=t, converged=ok, mu=mu))  # fmt: skip
        for r in rows:
            r["x_linear"] = r["time"] / t_lin
            r["x_monolithic"] = r["time"] / t_ref
            r["mu_rel_diff"] = abs(r.get("mu", mu_ref) / mu_ref - 1.0)
            r["linear_solve_s"] = t_lin
            w.append({k: r.get(k, float("nan")) for k in (
                "speed", "scheme", "relaxation", "iterations", "newton", "film_newton", "time",
                "x_linear",
                "x_monolithic", "mu_rel_diff", "converged", "linear_solve_s")})  # fmt: skip
            film = f" (+{r['film_newton']} film)" if "film_newton" in r else ""
            print0(f"| {v:.0e} | {r['scheme']} | {r['relaxation']:.2g} | {r['iterations']} | "
                   f"{r['newton']}{film} | {r['time']:.2f} | {r['x_linear']:.1f} | {r['x_monolithic']:.1f} | "
                   f"{r['mu_rel_diff']:.1e} | {r['converged']} |")  # fmt: skip
        prob.restore(start)
        prob.film.set_speed(v)
        prob.solver.solve(where="bench continue")
    if presolver is not None:
        presolver.destroy()


if __name__ == "__main__":
    main()
