"""Benchmark (issue 18): what the linear-solver levers do to a ball Stribeck sweep.

The demo system (S1 figure 18: R = 1 cm, F = 1.3 N, E* = 1.6 MPa, eta = 0.1 Pa s,
h_rms = 1 um), the demo mesh (contact elements a_Hertz / 15), the first
``--points`` speeds of the 30-speed sweep from 1 to 0.01 m/s (equal ratios), run
once per lever.  A lever is a set of PETSc options given to every solver of the
scene (:func:`dolfinx_seal.solvers.extra_petsc_options`): the MUMPS ordering,
block low-rank factorisation, ...; or of the wrapper's own solver fields
(:func:`dolfinx_seal.solvers.solver_session`): the fixed-pattern semismooth VI,
the kept factorisation.  For each lever the run records the numbers of analyses,
numeric factorisations and triangular solves (load-independent counts) and, from PETSc's
own event log (this rank's times), the time per Newton step of the Jacobian
assembly, the symbolic (analysis) and numeric factorisations and the triangular
solves, the Newton steps of each point, the wall time, and the largest relative
difference of mu, h_central and h_min from the first lever (the baseline) at the
same speeds.

Writes ``<out>/solver_levers.csv`` (one row per lever) and prints a markdown
table.  About 2 minutes per lever and 2 points on one core.

Run:  scripts/dx python3 bench/solver_levers.py [--points 2] [--levers default metis ...]
          [--out bench/results/solver_levers]
"""

from __future__ import annotations

import argparse
import contextlib
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
from petsc4py import PETSc

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from demos.ball_stribeck import parameters
from dolfinx_seal.mpi import COMM_WORLD, bcast_path, print0
from dolfinx_seal.output import SweepWriter
from dolfinx_seal.scenes import sweep_scene
from dolfinx_seal.solvers import extra_petsc_options, solver_session

#: the levers: name -> PETSc options (without prefix) for every solver of the scene
LEVERS: dict[str, dict[str, Any]] = {
    "default": {},  # MUMPS with its automatic ordering choice (ICNTL(7) = 7)
    # PETSc's own reduced-space solve: a new submatrix (and analysis) every step
    "submatrix": {},
    "metis": {"mat_mumps_icntl_7": 5},
    "scotch": {"mat_mumps_icntl_7": 3},
    "pord": {"mat_mumps_icntl_7": 4},
    "amd": {"mat_mumps_icntl_7": 0},
    # block low-rank factorisation, compression threshold 1e-8 (a direct solve to
    # about that accuracy: Newton then converges linearly at that rate at worst)
    "blr": {"mat_mumps_icntl_35": 1, "mat_mumps_cntl_7": 1e-8},
    "semismooth": {},
    "semismooth-reuse": {},
}

#: the levers' :class:`~dolfinx_seal.solvers.SNESOptions` fields for every solver
#: of the scene (:func:`dolfinx_seal.solvers.solver_session`): PETSc's own
#: reduced-space solve (a submatrix and its analysis every step); the wrapper's
#: fixed-pattern semismooth VI (one analysis for the whole sweep), then with the
#: factorisation kept as GMRES's right preconditioner across Newton steps and
#: points, rebuilt after a linear solve of more than 10 iterations
SNES_FIELDS: dict[str, dict[str, Any]] = {
    "submatrix": {"vi_linear_solve": "submatrix"},
    "semismooth": {"snes_type": "semismooth"},
    "semismooth-reuse": {"snes_type": "semismooth", "factor_reuse_its": 10},
}

#: PETSc's log events of each count; vinewtonrsls's reduced copy J_II, made every
#: Newton step (the outer Krylov operator, with either ``vi_linear_solve``), is
#: logged as ``MatCreateSubMats`` on one rank and ``MatCreateSubMat`` on several
EVENTS: dict[str, tuple[str, ...]] = {
    "jacobian": ("SNESJacobianEval",),
    "residual": ("SNESFunctionEval",),
    "submatrix": ("MatCreateSubMats", "MatCreateSubMat"),
    "analysis": ("MatLUFactorSym",),
    "factorisation": ("MatLUFactorNum",),
    "solve": ("MatSolve",),
    "krylov": ("KSPSolve",),
}


def _events() -> dict[str, tuple[int, float]]:
    """Count and time [s] of each of :data:`EVENTS` on this rank so far (its events summed)."""
    out = {}
    for key, names in EVENTS.items():
        infos = [PETSc.Log.Event(name).getPerfInfo() for name in names]
        out[key] = (sum(int(i["count"]) for i in infos), sum(float(i["time"]) for i in infos))
    return out


def solver_field(text: str) -> tuple[str, Any]:
    """``FIELD=VALUE`` of a bench's ``--solver`` option: the value as an int or float where it is one."""
    key, _, value = text.partition("=")
    for kind in (int, float):
        try:
            return key, kind(value)
        except ValueError:
            pass
    return key, value


def add_solver_arguments(parser: argparse.ArgumentParser) -> None:
    """A bench's ``--solver FIELD=VALUE`` (:class:`~dolfinx_seal.solvers.SNESOptions`
    fields of every solver) and ``--petsc KEY=VALUE`` (PETSc options, no prefix)."""
    parser.add_argument("--solver", action="append", default=[], metavar="FIELD=VALUE",
                        help="SNESOptions fields for every solver (e.g. "
                             "vi_linear_solve=submatrix, factor_reuse_its=8)")  # fmt: skip
    parser.add_argument("--petsc", action="append", default=[], metavar="KEY=VALUE",
                        help="PETSc options (no prefix) for every solver, e.g. "
                             "mat_mumps_icntl_35=2 (block low-rank)")  # fmt: skip


def solver_options(parser: argparse.ArgumentParser, args: argparse.Namespace) -> Any:
    """The context of :func:`add_solver_arguments`' options (every solver built inside
    it takes them); a ``--petsc`` entry without ``=`` is refused before anything runs."""
    if any("=" not in kv for kv in args.petsc):
        parser.error(f"--petsc takes KEY=VALUE, got {args.petsc}")
    fields = dict(solver_field(f) for f in args.solver)
    petsc = dict(kv.split("=", 1) for kv in args.petsc)

    @contextlib.contextmanager
    def options() -> Any:
        with solver_session(**fields), extra_petsc_options(petsc):
            yield

    return options()


def run_lever(name: str, options: dict[str, Any], speeds: list[float], out: Path) -> dict:
    """One sweep with ``options``; returns its row (times per step from this rank)."""
    p = parameters(15.0, roughness={"h_rms": 1e-6})
    before = _events()
    t0 = time.perf_counter()
    with extra_petsc_options(options), solver_session(**SNES_FIELDS.get(name, {})):
        rows = sweep_scene("ball", p, out / name, "film.speed", speeds, force=True)
    wall = time.perf_counter() - t0
    after = _events()
    steps = after["jacobian"][0] - before["jacobian"][0]
    row: dict[str, Any] = {
        "lever": name,
        "options": " ".join(f"-{k} {v}" for k, v in options.items())
        + " ".join(f"{k}={v}" for k, v in SNES_FIELDS.get(name, {}).items())
        or "(none)",
        "ranks": COMM_WORLD.size,
        "points": len(rows),
        "dofs": int(rows[0]["dofs"]) if rows else 0,
        "newton_steps": ";".join(str(r["newton_iterations"]) for r in rows),
        "jacobians": steps,
        "factorisations": after["factorisation"][0] - before["factorisation"][0],
        "analyses": after["analysis"][0] - before["analysis"][0],
        "triangular_solves": after["solve"][0] - before["solve"][0],
        "linear_solves": after["krylov"][0] - before["krylov"][0],
        "wall_s": wall,
        "first_point_s": float(rows[0]["wall_time_s"]) if rows else float("nan"),
        "later_points_s": float(np.mean([float(r["wall_time_s"]) for r in rows[1:]]))
        if len(rows) > 1
        else float("nan"),
    }
    for key in EVENTS:
        n = max(after[key][0] - before[key][0], 1)
        row[f"{key}_s_each"] = (after[key][1] - before[key][1]) / n
    row["_rows"] = rows
    return row


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=2, help="speeds of the 30 (from 1 m/s)")
    parser.add_argument("--levers", nargs="+", default=list(LEVERS), choices=list(LEVERS))
    parser.add_argument("--out", default="bench/results/solver_levers")
    args = parser.parse_args(argv)
    PETSc.Log.begin()  # before any solve: the events are counted from here
    out = bcast_path(args.out)
    speeds = [float(v) for v in np.logspace(0.0, -2.0, 30)[: args.points]]
    results = [run_lever(name, LEVERS[name], speeds, out) for name in args.levers]
    base = {float(r["speed"]): r for r in results[0].pop("_rows")}
    writer = SweepWriter(out, "solver_levers.csv")
    for res in [*results[1:], results[0]]:
        rows = res.pop("_rows", None)
        diff = 0.0
        for r in rows or []:
            b = base.get(float(r["speed"]))
            if b is None:
                continue
            for key in ("mu", "h_central", "h_min"):
                diff = max(diff, abs(float(r[key]) / float(b[key]) - 1.0))
        res["max_rel_diff_vs_first"] = diff
    for res in results:
        writer.append(res)
    print0("| lever | points | Newton steps | analyses | factorisations | triangular solves | "
           "jac [s] | analysis [s] | factor [s] | solve [s] | point 1 [s] | later [s] | rel diff |")  # fmt: skip
    print0("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in results:
        print0(f"| {r['lever']} | {r['points']} | {r['newton_steps']} | {r['analyses']} | "
               f"{r['factorisations']} | {r['triangular_solves']} | "
               f"{r['jacobian_s_each']:.2f} | {r['analysis_s_each']:.2f} | "
               f"{r['factorisation_s_each']:.2f} | {r['solve_s_each']:.3f} | "
               f"{r['first_point_s']:.1f} | {r['later_points_s']:.1f} | "
               f"{r['max_rel_diff_vs_first']:.1e} |")  # fmt: skip
    print0(f"written: {out / 'solver_levers.csv'}")


if __name__ == "__main__":
    main()
