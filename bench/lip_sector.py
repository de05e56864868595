"""Benchmark: the periodic lip sector (scenes ``lip-static`` and ``lip-dynamic``).

* ``static``: one static point of the default sector (or with ``--set`` overrides):
  unknowns, periodic slaves, Newton steps of each stage (sector equilibrium and
  roughness homotopy, sealed pressures), wall time of each stage, MUMPS memory
  (INFOG(21): largest on one rank, INFOG(22): total, MB) and the results.
* ``dynamic``: a speed sweep of ``lip-dynamic`` (six speeds by default) from one
  sector pressurised at the slowest speed and walked up (``lip_sector.sweep``;
  ``--set feedback=true`` for the coupled sector, the lip deformed by the film):
  per point, in
  the order solved, the Newton steps,
  continuation steps, time, friction torque and its parts, leakage or pumping
  rate, cavitation fraction and place, counter-gradient fraction, mass balance,
  MUMPS memory (``factor_memory_mb``: the factorisations the solvers hold;
  ``factor_memory_peak_mb``: each solver's largest, summed; all ranks;
  ``factor_memory_peak_rank_mb``: the same of the largest rank);
  targets not reached are in ``sweep_failures.csv``.
* ``--solver FIELD=VALUE`` sets :class:`~dolfinx_seal.solvers.SNESOptions` fields of
  every solver (e.g. ``factor_reuse_its=8``: a kept factorisation preconditioning
  GMRES), ``--petsc KEY=VALUE`` PETSc options of every solver; the row gives the
  count and time of each PETSc event (Jacobian, residual, analysis, factorisation,
  triangular solves, Krylov) on rank 0.
* ``levels``: the static point on several band resolutions (``--epw``, elements
  per lambda_th): leakage, torque and radial load against run time, with
  observed orders against the finest level; with ``--scene lip-dynamic`` the
  sliding point at ``film.speed`` (fluid load fraction, peak film pressure,
  cavitation fraction and the discrete upwinding's weight as well).

Writes ``bench/results/lip_sector_<mode>_np<ranks>.csv`` (one row per point,
appended as each finishes) and prints a Markdown table on rank 0.

Run::

    scripts/dx python3 bench/lip_sector.py static
    scripts/dx mpirun -n 2 python3 bench/lip_sector.py static
    scripts/dx python3 bench/lip_sector.py dynamic --speeds 1e-3 3e-3 1e-2 3e-2 1e-1 3e-1
    scripts/dx python3 bench/lip_sector.py levels --epw 2 3 4 --set roughness.q_th=3e5
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path
from typing import Any

from petsc4py import PETSc

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))
from solver_levers import EVENTS, _events, add_solver_arguments, solver_options

from dolfinx_seal.mpi import COMM_WORLD, print0, setup_logging
from dolfinx_seal.output import SweepWriter
from dolfinx_seal.params import parse_overrides
from dolfinx_seal.scenes import lip_sector, make_parameters

KEYS = ("leakage_rate", "friction_torque", "radial_load", "contact_area_fraction", "h_min",
        "max_contact_pressure", "mass_balance_error", "nodal_mass_balance_error")  # fmt: skip
#: and of a sliding point (``--scene lip-dynamic``)
SLIDING_KEYS = ("fluid_load_fraction", "max_fluid_pressure", "cavitation_fraction",
                "discrete_upwinding_weight")  # fmt: skip


def mumps_memory(solver: Any, prefix: str = "mumps") -> dict[str, float]:
    """MUMPS INFOG(21) (largest on one rank) and INFOG(22) (total) [MB] of the last
    factorisation of ``solver`` (:meth:`~dolfinx_seal.solvers.NonlinearSolver.factor_memory_mb`)."""
    held = solver.factor_memory_mb()
    return {} if held is None else {f"{prefix}_mb_max": held[0], f"{prefix}_mb_total": held[1]}


def static_point(scene: str, values: dict[str, Any]) -> dict[str, Any]:
    """One point: build (install + sector), dry (+ roughness), pressures (+ speed)."""
    p = make_parameters(scene, values=values)
    before = _events()
    t0 = time.perf_counter()
    lub = lip_sector.build(p)
    t_build = time.perf_counter() - t0
    try:
        dry = lip_sector.solve_dry(lub, p)
        mem = mumps_memory(lub.problem.solver)
        if lub.problem.film.has_couette:  # sliding: lip_sector.solve_point's path
            pr = lip_sector.pressurise_sliding(lub, p, p.film.speed)
            pr["solve_time_s"] = pr["speed_time_s"]
            sp = {"newton_iterations": 0}
        else:
            pr = lip_sector.solve_pressures(lub, p)
            sp = lip_sector.solve_speed(lub, p)
        if lub.film_only is not None:
            mem.update(mumps_memory(lub.film_only, "film_mumps"))
        res = lip_sector.results(lub, p)
        row = {
            "ranks": COMM_WORLD.size, "dofs": res["dofs"], "periodic_slaves": res["periodic_slaves"],
            "band_element": p.h_band, "elements_per_wavelength": p.sector.elements_per_wavelength,
            "q_th": p.roughness.q_th, "deterministic_modes": res["deterministic_modes"],
            "install_time_s": res["install_time_s"], "build_time_s": t_build,
            "dry_newton": dry["dry_newton_iterations"], "roughness_steps": dry["roughness_steps"],
            "dry_time_s": dry["dry_time_s"], "pressure_newton": pr["newton_iterations"],
            "pressure_time_s": pr["solve_time_s"], "speed_newton": sp["newton_iterations"],
            "wall_time_s": time.perf_counter() - t0, **mem,
        }  # fmt: skip
        row.update({k: res[k] for k in KEYS})
        row.update({k: res[k] for k in SLIDING_KEYS if k in res})
        after = _events()
        for key in EVENTS:
            row[f"{key}_count"] = after[key][0] - before[key][0]
            row[f"{key}_s"] = after[key][1] - before[key][1]
    finally:
        lub.destroy()
    return row


def dynamic(values: dict[str, Any], speeds: list[float], out: Path) -> list[dict[str, Any]]:
    """The speed sweep of ``lip-dynamic``; rows as the points finish."""
    p = make_parameters("lip-dynamic", values=values)
    writer = SweepWriter(out, f"lip_sector_dynamic_np{COMM_WORLD.size}.csv")
    rows: list[dict[str, Any]] = []
    t_last = [time.perf_counter()]

    def on_point(v: float, r: dict[str, Any]) -> bool:
        now = time.perf_counter()
        row = {"speed": v, "feedback": p.feedback,
               "dimensionless_speed": r.get("dimensionless_speed"),
               "newton_iterations": r.get("newton_iterations"),
               "continuation_steps": r.get("continuation_steps"), "point_time_s": now - t_last[0],
               "dofs": r["dofs"], "friction_torque": r["friction_torque"],
               "friction_torque_couette": r.get("friction_torque_couette", 0.0),
               "friction_torque_asperity": r["friction_torque_asperity"],
               "friction_torque_poiseuille": r["friction_torque_poiseuille"],
               "leakage_rate": r["leakage_rate"], "pumping_rate": r.get("pumping_rate", math.nan),
               "cavitation_fraction": r.get("cavitation_fraction", math.nan),
               "cavitation_axial_offset": r.get("cavitation_axial_offset", math.nan),
               "cavitation_divergent_fraction": r.get("cavitation_divergent_fraction", math.nan),
               "counter_gradient_fraction": r.get("counter_gradient_fraction", math.nan),
               "max_fluid_pressure": r["max_fluid_pressure"],
               "fluid_load_fraction": r["fluid_load_fraction"], "h_min": r["h_min"],
               "radial_load": r["radial_load"],
               "mass_balance_error": r["mass_balance_error"],
               "nodal_mass_balance_error": r["nodal_mass_balance_error"],
               "discrete_upwinding_weight": r.get("discrete_upwinding_weight", math.nan),
               "factor_memory_mb": r.get("factor_memory_mb", math.nan),
               "factor_memory_peak_mb": r.get("factor_memory_peak_mb", math.nan),
               "factor_memory_peak_rank_mb": r.get("factor_memory_peak_rank_mb", math.nan)}  # fmt: skip
        t_last[0] = now
        rows.append(row)
        writer.append(row)
        print0(f"  speed {v:.3g} m/s: {row['newton_iterations']} Newton, "
               f"{row['point_time_s']:.1f} s, torque {row['friction_torque']:.4g} N m")  # fmt: skip
        return True  # every point's maps

    lip_sector.sweep(p, out / "lip_sector_dynamic", "film.speed", speeds, on_point)
    return rows


def table(rows: list[dict[str, Any]]) -> str:
    if not rows:
        return "(no rows)"
    keys = list(rows[0])
    lines = ["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
    for r in rows:
        lines.append("| " + " | ".join(f"{r.get(k, ''):.4g}" if isinstance(r.get(k), float)
                                       else str(r.get(k, "")) for k in keys) + " |")  # fmt: skip
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="periodic lip sector benchmarks")
    ap.add_argument("mode", choices=("static", "dynamic", "levels"))
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--speeds", type=float, nargs="+", default=[1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.3])
    ap.add_argument("--epw", type=float, nargs="+", default=[2.0, 3.0, 4.0])
    ap.add_argument("--scene", default="lip-static")
    ap.add_argument("--out", default="bench/results")
    add_solver_arguments(ap)
    a = ap.parse_args(argv)
    options = solver_options(ap, a)
    PETSc.Log.begin()
    with options:
        return _run(a)


def _run(a: argparse.Namespace) -> int:
    setup_logging("INFO")  # the stages and every fallback, on stderr
    out = Path(a.out)
    values = parse_overrides(a.set)
    if a.mode == "dynamic":
        rows = dynamic(values, a.speeds, out)
    elif a.mode == "static":
        rows = [static_point(a.scene, values)]
        SweepWriter(out, f"lip_sector_static_np{COMM_WORLD.size}.csv").append(rows[0])
    else:
        rows = []
        writer = SweepWriter(out, f"lip_sector_levels_np{COMM_WORLD.size}.csv")
        for e in a.epw:
            v = parse_overrides([*a.set, f"sector.elements_per_wavelength={e}"])
            rows.append(static_point(a.scene, v))
            writer.append(rows[-1])
            print0(f"  epw {e:g}: {rows[-1]['dofs']} unknowns, {rows[-1]['wall_time_s']:.0f} s")
        fine = rows[-1]
        for r in rows:
            for k in ("leakage_rate", "friction_torque", "radial_load"):
                r[f"{k}_vs_finest"] = r[k] / fine[k] - 1.0
    print0(table(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
