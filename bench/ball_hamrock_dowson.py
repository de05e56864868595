"""Benchmark: the smooth lubricated ball against the Hamrock-Dowson isoviscous-elastic
film regressions, over a grid of speeds and loads (issue 7: at least 3 x 3).

Smooth ball (no asperity contact), S1 figure-18 system otherwise (R = 1 cm,
E* = 1.6 MPa, eta = 0.1 Pa s, Reynolds cavitation condition, half ball), contact
element size ``a_Hertz(F) / elements_per_radius``.  Each load runs one sweep down
in speed (continuation).  Writes ``ball_hamrock_dowson.csv`` (speed, load, the
dimensionless U and W, h_central and h_min with their regression values and
errors, Newton steps, wall time) and prints a markdown table.

Run:  scripts/dx python3 bench/ball_hamrock_dowson.py [--loads 0.5 1.3 3] \
          [--speeds 0.3 0.1 0.03] [--elements-per-radius 20] [--out bench/results]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from dolfinx_seal.contact.hertz import hertz_point
from dolfinx_seal.mpi import bcast_path, print0
from dolfinx_seal.output import SweepWriter
from dolfinx_seal.scenes import make_parameters, sweep_scene
from dolfinx_seal.verification.ehl import IsoviscousElasticFilm


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--loads", type=float, nargs="+", default=[0.5, 1.3, 3.0], help="[N]")
    parser.add_argument("--speeds", type=float, nargs="+", default=[0.3, 0.1, 0.03], help="[m/s]")
    parser.add_argument("--elements-per-radius", type=float, default=20.0)
    parser.add_argument("--out", default="bench/results")
    args = parser.parse_args(argv)
    out = bcast_path(args.out)
    w = SweepWriter(out, "ball_hamrock_dowson.csv")
    print0("| F [N] | U [m/s] | U_HD | W_HD | h_c [um] | HD h_c | error | h_min [um] | HD h_min "
           "| error | Newton | wall [s] |")  # fmt: skip
    print0("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for load in args.loads:
        base = make_parameters("ball", values={"load": load, "h_contact": 1e-4})
        e_star = base.material.E_star
        a_h, _ = hertz_point(load, base.radius, e_star)
        p = make_parameters(
            "ball",
            values={
                "load": load,
                "h_contact": a_h / args.elements_per_radius,
                "contact": {"model": "none"},
            },
        )
        hd = IsoviscousElasticFilm(p.radius, e_star, p.film.viscosity, load)
        rows = sweep_scene("ball", p, out / f"hd_load_{load:g}N", "film.speed", args.speeds)
        for r in rows:
            v = float(r["speed"])
            cmp = hd.compare(v, float(r["h_central"]), float(r["h_min"]))
            hc, hm = cmp["hd_h_central"], cmp["hd_h_min"]
            row = {
                "load_N": load,
                "U_hd": hd.speed_parameter(0.5 * v),
                "W_hd": hd.load_parameter,
                **cmp,
                "mu": float(r["mu"]),
                "dofs": int(r["dofs"]),
                "newton_iterations": int(r["newton_iterations"]),
                "wall_time_s": float(r["wall_time_s"]),
                "load_balance_error": float(r["load_balance_error"]),
                "mass_balance_error": float(r["mass_balance_error"]),
            }
            w.append(row)
            print0(
                f"| {load:g} | {v:g} | {row['U_hd']:.3g} | {row['W_hd']:.3g} "
                f"| {row['h_central'] * 1e6:.3f} | {hc * 1e6:.3f} | {row['h_central_error']:+.1%} "
                f"| {row['h_min'] * 1e6:.3f} | {hm * 1e6:.3f} | {row['h_min_error']:+.1%} "
                f"| {row['newton_iterations']} | {row['wall_time_s']:.0f} |"
            )


if __name__ == "__main__":
    main()
