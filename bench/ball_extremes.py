"""Benchmark: the lubricated ball on the extreme cases of docs/design.md, robustness contract that
apply to it (issue 7): E from 1 MPa to 1 GPa, speeds over 8 decades (10 m/s down to
1e-7 m/s), h_rms from 0.1 to 10 um, zero speed.

Each case is one Stribeck sweep walking down in speed (the S1 figure-18 ball
otherwise: R = 1 cm, F = 1.3 N, eta = 0.1 Pa s, D_f 2.2, Reynolds condition), on a
contact mesh of a_Hertz / ``elements_per_radius``, with
``stepping.max_failures = 1`` (the sweep stops at the first speed it cannot reach
and records the rest as not attempted) and ``stepping.min_decades`` coarsened to
0.06 (four halvings of a half-decade step before a target is given up).  What is
checked per case: which speeds converged, where and with which error it stopped,
that every converged point is in ``sweep.csv`` and none holds a NaN, and the load
and mass balance.  Writes ``ball_extremes.csv`` and prints a markdown table.

Run:  scripts/dx python3 bench/ball_extremes.py [--cases E1MPa E1GPa ...]
          [--elements-per-radius 12] [--out bench/results]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from dolfinx_seal.contact.hertz import hertz_point
from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.mpi import bcast_path, print0
from dolfinx_seal.output import SweepWriter, read_csv
from dolfinx_seal.scenes import make_parameters, run_scene, sweep_scene

SPEEDS = [10.0, 1.0, 0.1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7]  # m/s, 8 decades

#: case name -> parameter overrides (E in Pa, h_rms in m); film.speed 0 is its own case
CASES: dict[str, dict[str, Any]] = {
    "E1MPa": {"material": {"E": 1.0e6}},
    "E10MPa": {"material": {"E": 10.0e6}},
    "E100MPa": {"material": {"E": 100.0e6}},
    "E1GPa": {"material": {"E": 1.0e9}},
    "hrms0.1um": {"roughness": {"h_rms": 0.1e-6}},
    "hrms10um": {"roughness": {"h_rms": 10e-6}},
    "speed0": {"film": {"speed": 0.0}},
}


def _parameters(overrides: dict[str, Any], elements_per_radius: float) -> Any:
    base = make_parameters("ball", values={"h_contact": 1e-5, **overrides})
    a_h, _ = hertz_point(base.load, base.radius, base.material.E_star)
    values = {
        **overrides,
        "h_contact": a_h / elements_per_radius,
        "stepping": {"max_failures": 1, "min_decades": 0.06},
    }
    return make_parameters("ball", values=values)


COLUMNS = ("case", "E_star_Pa", "h_rms_m", "outcome", "converged_speeds", "n_converged",
           "lowest_speed", "first_failure", "error", "nan_in_results", "max_load_balance_error",
           "max_mass_balance_error", "mu", "fluid_load_fraction", "wall_time_s")  # fmt: skip


def run_case(name: str, elements_per_radius: float, out: Path) -> dict[str, Any]:
    """One case: its sweep (or the error that refused it) summarised in one row."""
    row: dict[str, Any] = dict.fromkeys(COLUMNS, "")
    row["case"] = name
    t0 = time.perf_counter()
    try:
        params = _parameters(CASES[name], elements_per_radius)
    except ParameterError as e:
        row.update(outcome="refused: parameter error", error=str(e), wall_time_s=0.0)
        return row
    row.update(E_star_Pa=params.material.E_star, h_rms_m=params.roughness.h_rms)
    case_out = out / f"extreme_{name}"
    raised = ""
    try:
        if params.film.speed == 0.0:  # one point at zero speed
            run_scene("ball", params, case_out)
        else:
            sweep_scene("ball", params, case_out, "film.speed", SPEEDS)
    except (ParameterError, SolverError) as e:  # refused or failed before the sweep
        raised = f"{type(e).__name__}: {e}"
    row["wall_time_s"] = time.perf_counter() - t0
    points = read_csv(case_out / "sweep.csv") if (case_out / "sweep.csv").exists() else []
    failures = (
        read_csv(case_out / "sweep_failures.csv")
        if (case_out / "sweep_failures.csv").exists()
        else []
    )
    if not raised and (case_out / "results.json").exists():
        failed = json.loads((case_out / "results.json").read_text()).get("failed_points", [])
        raised = "; ".join(f["error"] for f in failed)
    done = [float(p["film.speed"]) for p in points]
    numbers = [float(v) for p in points for v in p.values() if _is_number(v)]
    row.update(
        converged_speeds=" ".join(f"{v:g}" for v in done),
        n_converged=len(done),
        lowest_speed=min(done) if done else math.nan,
        first_failure=float(failures[0]["speed"]) if failures else math.nan,
        error=failures[0]["error"] if failures else raised,
        nan_in_results=any(math.isnan(v) for v in numbers),
        max_load_balance_error=max((float(p["load_balance_error"]) for p in points), default=0),
        max_mass_balance_error=max((float(p["mass_balance_error"]) for p in points), default=0),
        mu=" ".join(f"{float(p['mu']):.3g}" for p in points),
        fluid_load_fraction=" ".join(f"{float(p['fluid_load_fraction']):.3f}" for p in points),
    )
    if not done:
        row["outcome"] = "refused or stopped before the first point, with an error"
    elif failures:
        row["outcome"] = f"{len(done)} of {len(SPEEDS)} speeds, then stopped with an error"
    else:
        row["outcome"] = f"all {len(done)} speeds converged"
    return row


def _is_number(v: str) -> bool:
    try:
        float(v)
    except ValueError:
        return False
    return True


def _g(v: Any, scale: float) -> str:
    return f"{float(v) * scale:.3g}" if v != "" else ""


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--elements-per-radius", type=float, default=12.0)
    parser.add_argument("--out", default="bench/results")
    args = parser.parse_args(argv)
    out = bcast_path(args.out)
    w = SweepWriter(out, "ball_extremes.csv")
    print0("| case | E* [MPa] | h_rms [um] | outcome | converged speeds [m/s] | mu | "
           "fluid load | stopped at [m/s] | error | wall [s] |")  # fmt: skip
    print0("|---|---:|---:|---|---|---|---|---:|---|---:|")
    for name in args.cases:
        row = run_case(name, args.elements_per_radius, out)
        w.append(row)
        print0(
            f"| {name} | {_g(row['E_star_Pa'], 1e-6)} | {_g(row['h_rms_m'], 1e6)} "
            f"| {row['outcome']} | {row['converged_speeds']} | {row['mu']} "
            f"| {row['fluid_load_fraction']} | {_g(row['first_failure'], 1.0)} "
            f"| {str(row['error'])[:200]} | {float(row['wall_time_s'] or 0.0):.0f} |"
        )


if __name__ == "__main__":
    main()
