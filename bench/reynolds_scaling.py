"""Benchmark: Newton steps and wall time of the 1D Reynolds-condition VI against size.

Sizes 10^3 .. 10^6 cells, strategies cold / penalty / nested (see
demos/reynolds_1d.py).  A cold start needs about one step per moved node, so it
is capped at ``--max-it`` steps and reported as not converged beyond that.

Run:  scripts/dx python3 bench/reynolds_scaling.py [--sizes ...] [--out bench/results]
Writes ``reynolds_scaling.csv`` and prints a markdown table.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from mpi4py import MPI

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from demos.reynolds_1d import solve
from dolfinx_seal.mpi import bcast_path, print0
from dolfinx_seal.output import SweepWriter
from dolfinx_seal.verification.martin import martin_solution


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000, 100000, 1000000])
    parser.add_argument("--strategies", nargs="+", default=["cold", "penalty", "nested"])
    parser.add_argument("--max-it", type=int, default=200)
    parser.add_argument("--out", default="bench/results")
    args = parser.parse_args(argv)
    out = bcast_path(args.out)
    ref = martin_solution(10.0)
    w = SweepWriter(out, "reynolds_scaling.csv")
    print0(f"ranks: {MPI.COMM_WORLD.size}")
    print0(
        "| cells | strategy | Newton steps (finest) | all levels | wall time [s] | X_c error | W rel. error | converged |"
    )
    print0("|---:|---|---:|---:|---:|---:|---:|---|")
    for n in args.sizes:
        for s in args.strategies:
            row, prob = solve(n, s, max_it=args.max_it)
            ok = row["converged"]
            exc = abs(row["x_cavitation"] - ref.x_cavitation) if ok else float("nan")
            ew = abs(row["load"] - ref.load) / ref.load if ok else float("nan")
            print0(f"| {n} | {s} | {row['newton_iterations']} | {row.get('newton_iterations_all_levels', row['newton_iterations'])} "
                   f"| {row['wall_time_s']:.2f} | {exc:.2e} | {ew:.2e} | {'yes' if ok else 'no (max_it)'} |")  # fmt: skip
            w.append({"cells": n, "strategy": s, "ranks": MPI.COMM_WORLD.size,
                      "newton_iterations": row["newton_iterations"],
                      "newton_iterations_all_levels": row.get("newton_iterations_all_levels", row["newton_iterations"]),
                      "wall_time_s": row["wall_time_s"], "converged": ok,
                      "x_cavitation_error": exc if ok else "", "load_error": ew if ok else ""})  # fmt: skip
            if prob is not None:
                prob.solver.destroy()


if __name__ == "__main__":
    main()
