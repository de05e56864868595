"""Benchmark: the JFO film's transport schemes on a rigid rough band, error against
run time (the lip sector's film alone, :mod:`dolfinx_seal.film.rigid_band`).

For each speed, the finite-volume reference
(:func:`~dolfinx_seal.verification.rough_band.fv_jfo_band`, 512 x 640 cells, and
256 x 320 for its own grid error) and the surface-film code on irregular bands of
16, 32, 64 and 128 elements per period with each scheme:

* ``film``: streamline diffusion of the film ``g theta`` (``film.upwind = film``,
  the lip sector's default);
* ``film+du``: the same with ``film.discrete_upwinding``;
* ``none+du``: ``film.upwind = none`` with ``film.discrete_upwinding``;
* ``film+du+release``: ``film+du``, then ``film.release_upwinding``: the
  weight of the discrete upwinding walked to 0, ending on ``film``'s film.

Per row: elements per period, scheme, film unknowns, Newton steps, the path that
solved it, wall time, leakage, load and cavitated fraction with their errors
against the reference, smallest film fraction and pressure.  Writes
``bench/results/rough_band_np<ranks>.csv`` (appended row by row) and prints a
Markdown table on rank 0.

Run::

    scripts/dx python3 bench/rough_band.py
    scripts/dx mpirun -n 2 python3 bench/rough_band.py --speeds 0.1 --per-period 32 64
"""

from __future__ import annotations

import argparse
import csv
import time
from pathlib import Path

from mpi4py import MPI

from dolfinx_seal.errors import SolverError
from dolfinx_seal.film.rigid_band import RigidBandFilm
from dolfinx_seal.verification.rough_band import fv_jfo_band, rough_band_case

SCHEMES = {
    "film": {"upwind": "film", "discrete_upwinding": False},
    "film+du": {"upwind": "film", "discrete_upwinding": True},
    "none+du": {"upwind": "none", "discrete_upwinding": True},
    "film+du+release": {"upwind": "film", "discrete_upwinding": True, "release_upwinding": True},
}
FIELDS = ["speed", "per_period", "scheme", "unknowns", "newton", "path", "time_s", "leakage",
          "leakage_error", "load", "load_error", "cavitation_fraction", "cavitation_error",
          "theta_min", "p_min", "note"]  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--speeds", type=float, nargs="+", default=[0.01, 0.1, 1.0])
    ap.add_argument("--per-period", type=int, nargs="+", default=[16, 32, 64, 128])
    ap.add_argument("--schemes", nargs="+", default=list(SCHEMES), choices=list(SCHEMES))
    ap.add_argument("--out", default="bench/results")
    args = ap.parse_args()
    comm = MPI.COMM_WORLD
    out = Path(args.out) / f"rough_band_np{comm.size}.csv"
    rows = []
    if comm.rank == 0:
        out.parent.mkdir(parents=True, exist_ok=True)
        with out.open("w", newline="") as f:
            csv.DictWriter(f, FIELDS).writeheader()
    for speed in args.speeds:
        gap, op = rough_band_case(speed)
        t0 = time.perf_counter()
        ref = fv_jfo_band(gap, op, 512, 640)
        t_ref = time.perf_counter() - t0
        half = fv_jfo_band(gap, op, 256, 320)
        if comm.rank == 0:
            print(f"speed {speed:g} m/s: FV 512 x 640 in {t_ref:.1f} s, leakage "
                  f"{ref.leakage:.6e} (256 x 320: {half.leakage:.6e}), load {ref.load:.6e}, "
                  f"cavitated {ref.cavitation_fraction:.4f}", flush=True)  # fmt: skip
        for n in args.per_period:
            for name in args.schemes:
                row = {"speed": speed, "per_period": n, "scheme": name, "note": ""}
                t0 = time.perf_counter()
                try:
                    band = RigidBandFilm(gap, op, gap.length / n, **SCHEMES[name])
                    row["unknowns"] = band.solver.x.getSize()
                    row["newton"] = band.solve()
                    row["path"] = band.path
                    q = band.quantities()
                    row.update({k: q[k] for k in ("leakage", "load", "cavitation_fraction",
                                                  "theta_min", "p_min")})  # fmt: skip
                    row["leakage_error"] = q["leakage"] / ref.leakage - 1.0
                    row["load_error"] = q["load"] / ref.load - 1.0
                    row["cavitation_error"] = q["cavitation_fraction"] - ref.cavitation_fraction
                except SolverError as e:
                    row["note"] = f"failed: {e.what}"
                row["time_s"] = time.perf_counter() - t0
                rows.append(row)
                if comm.rank == 0:
                    with out.open("a", newline="") as f:
                        csv.DictWriter(f, FIELDS).writerow(row)
                    done = row["note"] or f"leakage error {100 * row['leakage_error']:+.2f} %"
                    print(f"  {n} per period, {name}: {done}, {row['time_s']:.1f} s", flush=True)
    if comm.rank == 0:
        print("| speed | el/period | scheme | Newton | time [s] | leakage error | "
              "load error | cavitated (error) |")  # fmt: skip
        print("|---:|---:|---|---:|---:|---:|---:|---:|")
        for r in rows:
            if r["note"]:
                print(f"| {r['speed']:g} | {r['per_period']} | {r['scheme']} | | "
                      f"{r['time_s']:.1f} | {r['note']} | | |")  # fmt: skip
                continue
            print(f"| {r['speed']:g} | {r['per_period']} | {r['scheme']} | {r['newton']} | "
                  f"{r['time_s']:.1f} | {100 * r['leakage_error']:+.2f} % | "
                  f"{100 * r['load_error']:+.1f} % | {r['cavitation_fraction']:.3f} "
                  f"({r['cavitation_error']:+.3f}) |")  # fmt: skip
        print(f"written {out}")


if __name__ == "__main__":
    main()
