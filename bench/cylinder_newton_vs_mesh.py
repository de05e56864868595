"""Benchmark: Newton steps per Stribeck point against the mesh, lubricated cylinder.

The same speed sweep (continuation, ``dolfinx-seal sweep cylinder``) on three
contact element sizes; for each mesh the min / median / max Newton steps per
continuation step (the first point, which includes the start from the dry
state, is reported separately), the film-only Newton steps on the predicted
shape that precede each coupled step (``stepping.film_presolve``), the wall
time per point and the unknowns.

Writes ``cylinder_newton_vs_mesh.csv`` and prints a markdown table.

Run:  scripts/dx python3 bench/cylinder_newton_vs_mesh.py [--out bench/results]
"""

from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from dolfinx_seal.mpi import COMM_WORLD, bcast_path, print0
from dolfinx_seal.output import SweepWriter
from dolfinx_seal.scenes import make_parameters, parse_values, sweep_scene


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--h-contact", type=float, nargs="+", default=[20e-6, 10e-6, 5e-6])
    parser.add_argument("--speeds", default="1e-6:1:13:log")
    parser.add_argument("--out", default="bench/results")
    args = parser.parse_args(argv)
    out = bcast_path(args.out)
    speeds = parse_values(args.speeds)
    w = SweepWriter(out, "cylinder_newton_vs_mesh.csv")
    print0(
        f"ranks: {COMM_WORLD.size}; speeds {speeds[0]:g}..{speeds[-1]:g} m/s, {len(speeds)} points"
    )
    print0("| contact element | unknowns | first point Newton (+ film) | Newton per step min / median / max "
           "| film presolve per step min / median / max | wall time per point [s] "
           "| mu at 1e-2 m/s |")  # fmt: skip
    print0("|---:|---:|---:|---|---|---:|---:|")
    for h in args.h_contact:
        p = make_parameters("cylinder", values={"h_contact": h})
        rows = sweep_scene("cylinder", p, out / f"sweep_h{h:.1e}", "film.speed", speeds)
        per = [
            float(r["newton_iterations"]) / max(float(r["continuation_steps"]), 1.0)
            for r in rows[1:]
        ]
        pre = [
            float(r.get("film_presolve_iterations") or 0) / max(float(r["continuation_steps"]), 1.0)
            for r in rows[1:]
        ]
        t = statistics.median(float(r["wall_time_s"]) for r in rows)
        mu = {round(float(r["speed"]), 12): float(r["mu"]) for r in rows}
        row = {
            "h_contact": h, "dofs": int(rows[0]["dofs"]), "points": len(rows),
            "first_newton": int(rows[0]["newton_iterations"]),
            "first_film": int(rows[0].get("film_presolve_iterations") or 0), "newton_min": min(per),
            "newton_median": statistics.median(per), "newton_max": max(per),
            "presolve_min": min(pre), "presolve_median": statistics.median(pre),
            "presolve_max": max(pre), "median_point_time_s": t, "mu_1e-2": mu.get(0.01, float("nan")),
        }  # fmt: skip
        w.append(row)
        print0(f"| {h * 1e6:g} um | {row['dofs']} | {row['first_newton']} (+{row['first_film']}) | {min(per):.1f} / "
               f"{statistics.median(per):.1f} / {max(per):.1f} | {min(pre):.1f} / "
               f"{statistics.median(pre):.1f} / {max(pre):.1f} | {t:.2f} | {row['mu_1e-2']:.5f} |")  # fmt: skip


if __name__ == "__main__":
    main()
