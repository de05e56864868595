"""Benchmark: the smooth FEM ball against the independent point-contact soft-EHL
reference (:mod:`dolfinx_seal.verification.point_ehl`) over two decades of speed.

The system: the S1 figure-18 ball (R = 1 cm, E = 1.2 MPa, nu = 0.5, so E* =
E / (1 - nu^2) = 1.6 MPa in both: the FEM bulk is the incompressible mixed
neo-Hookean, the reference an incompressible half-space), eta = 0.1 Pa s, Reynolds
condition, no asperity contact (``contact.model = none``), at a tenth of its load
(``--load``, 0.13 N: a_H = 0.85 mm = 0.085 R, so the finite ball and its finite
strain stay close to the half-space), lubricated disc of ``--extent`` Hertz radii
in both (``film_extent``).

Runs the reference on every ``--cells`` grid (cells per Hertz radius; it converges
at second order, so the two finest give a Richardson value) and one FEM speed sweep
(walking down, :func:`~dolfinx_seal.scenes.sweep_scene`) per ``--levels`` mesh
(``contact_elements``), and compares mu, h_central, h_min and the contact radius of
each FEM level with the reference's Richardson value.  Writes into ``--out``
(default ``bench/results/ball_point_ehl``): ``reference.csv`` and ``fem.csv`` (one
row per level and speed, appended to what earlier runs left there; the last row of
a level and speed counts) and ``summary.md``.

Run:  scripts/dx python3 bench/ball_point_ehl_reference.py [--speeds 1 0.3 0.1 0.03 0.01]
          [--levels 15 20] [--cells 15 20 30] [--load 0.13] [--extent 2]
          [--report-only] [--skip-fem] [--skip-reference] [--out DIR]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from dolfinx_seal.mpi import COMM_WORLD, bcast_path, print0
from dolfinx_seal.output import SweepWriter, read_csv
from dolfinx_seal.params import set_parameter
from dolfinx_seal.scenes import make_parameters, sweep_scene
from dolfinx_seal.verification.point_ehl import for_ball, speed_continuation

SPEEDS = [1.0, 0.3, 0.1, 0.03, 0.01]  # m/s: two decades
KEYS = ("mu", "h_central", "h_min", "contact_radius")


def parameters(load: float, extent: float, speed: float = 1.0) -> object:
    """The smooth ball of the comparison (everything else at the scene's defaults)."""
    return make_parameters("ball", overrides=[
        "contact.model=none", f"load={load!r}", f"film_extent={extent!r}",
        f"film.speed={speed!r}", "sweep_order=down"])  # fmt: skip


def moes_m(p: object, speed: float) -> float:
    """Moes' ``M = W U^(-3/4)`` of the point contact at sliding speed ``speed``, with
    ``E' = 2 E*``, ``W = F / (E' R^2)`` and ``U = eta u_m / (E' R)``, u_m = speed / 2."""
    e1 = 2.0 * p.material.E_star
    w = p.load / (e1 * p.radius**2)
    return w * (p.film.viscosity * 0.5 * speed / (e1 * p.radius)) ** -0.75


def run_reference(p: object, cells: list[int], speeds: list[float], out: Path) -> None:
    """One walk down in speed per grid; rows to ``reference.csv``."""
    writer = SweepWriter(out, "reference.csv", resume=True)
    for n in cells:
        t0 = time.perf_counter()
        model = for_ball(p, cells_per_radius=n)
        for r in speed_continuation(model, speeds):
            writer.append({"cells_per_radius": n, "cells": model.n, "speed": r.speed,
                           **{k: float(getattr(r, k)) for k in KEYS},
                           "newton_iterations": r.newton_iterations,
                           "mass_balance_error": r.mass_balance_error})  # fmt: skip
        print0(f"reference {n} cells per radius ({model.n} cells): "
               f"{time.perf_counter() - t0:.0f} s")  # fmt: skip


def run_fem(p: object, levels: list[float], speeds: list[float], out: Path) -> None:
    """One FEM sweep per mesh level; rows to ``fem.csv``."""
    writer = SweepWriter(out, "fem.csv", resume=True)
    for n in levels:
        q = set_parameter(p, "contact_elements", float(n))
        t0 = time.perf_counter()
        rows = sweep_scene("ball", q, out / f"fem_n{n:g}", "film.speed", speeds, force=True)
        for r in rows:
            writer.append({"contact_elements": float(n), "speed": float(r["speed"]),
                           **{k: float(r[k]) for k in KEYS}, "dofs": int(r["dofs"]),
                           "newton_iterations": int(r["newton_iterations"]),
                           "wall_time_s": float(r["wall_time_s"]),
                           "load_balance_error": float(r["load_balance_error"]),
                           "mass_balance_error": float(r["mass_balance_error"])})  # fmt: skip
        print0(f"FEM a/{n:g}: {len(rows)} of {len(speeds)} speeds, "
               f"{time.perf_counter() - t0:.0f} s")  # fmt: skip


def report(out: Path, p: object) -> str:
    """``summary.md``: each FEM level against the reference's Richardson value of its
    two finest grids (and the change of the reference between them)."""
    COMM_WORLD.barrier()
    ref = read_csv(out / "reference.csv")
    fem = read_csv(out / "fem.csv") if (out / "fem.csv").exists() else []
    grids = sorted({int(float(r["cells_per_radius"])) for r in ref})
    levels = sorted({float(r["contact_elements"]) for r in fem})
    speeds = sorted({float(r["speed"]) for r in ref}, reverse=True)
    rv = {(int(float(r["cells_per_radius"])), float(r["speed"])): r for r in ref}
    fv = {(float(r["contact_elements"]), float(r["speed"])): r for r in fem}
    c, f = grids[-2], grids[-1]
    ratio = f / c
    lines = ["# Smooth FEM ball against the point-contact soft-EHL reference", "",
             f"Reference: Richardson value of {c} and {f} cells per Hertz radius (second "
             "order) and its move from the finest grid.  FEM: each level (elements per "
             "Hertz radius) and, in brackets, its relative difference to the reference; "
             "the FEM's own Richardson value of its two finest levels assumes second "
             "order (unstructured meshes: an estimate of the FEM's mesh error, not a "
             "result).", "",
             "| speed [m/s] | Moes M | quantity | reference | ref. Richardson - finest | "
             + " | ".join(f"FEM a/{n:g}" for n in levels)
             + (f" | FEM Richardson a/{levels[-2]:g}, a/{levels[-1]:g} |" if len(levels) > 1 else " |"),
             "|---:|---:|---|---:|---:|" + "---:|" * (len(levels) + (len(levels) > 1))]  # fmt: skip
    for v in speeds:
        if (c, v) not in rv or (f, v) not in rv:
            continue
        for k in KEYS:
            rc, rf = float(rv[(c, v)][k]), float(rv[(f, v)][k])
            ext = rf + (rf - rc) / (ratio**2 - 1.0)
            cells = []
            for n in levels:
                r = fv.get((n, v))
                cells.append("not converged" if r is None else
                             f"{float(r[k]):.5g} ({float(r[k]) / ext - 1.0:+.2%})")  # fmt: skip
            if len(levels) > 1:
                r1, r2 = fv.get((levels[-2], v)), fv.get((levels[-1], v))
                if r1 is None or r2 is None:
                    cells.append("")
                else:
                    a1, a2 = float(r1[k]), float(r2[k])
                    fx = a2 + (a2 - a1) / ((levels[-1] / levels[-2]) ** 2 - 1.0)
                    cells.append(f"{fx:.5g} ({fx / ext - 1.0:+.2%})")
            lines.append(f"| {v:g} | {moes_m(p, v):.3g} | {k} | {ext:.5g} | {ext / rf - 1.0:+.2%} | "
                         + " | ".join(cells) + " |")  # fmt: skip
    text = "\n".join(lines) + "\n"
    if COMM_WORLD.rank == 0:
        (out / "summary.md").write_text(text)
    print0(text)
    return text


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds", type=float, nargs="+", default=SPEEDS, help="[m/s]")
    parser.add_argument("--levels", type=float, nargs="+", default=[15.0, 20.0],
                        help="FEM elements per Hertz radius")  # fmt: skip
    parser.add_argument("--cells", type=int, nargs="+", default=[15, 20, 30],
                        help="reference cells per Hertz radius")  # fmt: skip
    parser.add_argument("--load", type=float, default=0.13, help="[N]")
    parser.add_argument("--extent", type=float, default=2.0, help="lubricated disc [a_H]")
    parser.add_argument("--skip-reference", action="store_true")
    parser.add_argument("--skip-fem", action="store_true")
    parser.add_argument("--report-only", action="store_true")
    parser.add_argument("--out", default="bench/results/ball_point_ehl")
    args = parser.parse_args(argv)
    out = bcast_path(args.out)
    p = parameters(args.load, args.extent, max(args.speeds))
    if not args.report_only:
        if not args.skip_reference and COMM_WORLD.rank == 0:
            run_reference(p, sorted(args.cells), args.speeds, out)
        if not args.skip_fem:
            run_fem(p, sorted(args.levels), args.speeds, out)
    if not (out / "reference.csv").exists():  # --skip-reference without an earlier run
        print0(f"no report: {out / 'reference.csv'} is missing (run without --skip-reference "
               f"once); the FEM rows are in {out / 'fem.csv'}")  # fmt: skip
        return 1
    report(out, p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
