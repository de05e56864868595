"""Benchmark: the dry ball (smooth law) on self-similar meshes, with observed orders.

The scene's study refines only the contact zone (``h_contact``); here every mesh
size is scaled with it (contact cap ``2 h``, far field ``min(6 h, R/3)``), so the
levels are similar and the discretisation error of global quantities falls
regularly.  For each level: unknowns, Newton steps, wall time, the rigid approach
of the flat (with the observed order of its successive changes), the contact
radius and the peak pressure against Hertz.

Writes ``ball_similar_meshes.csv`` and prints a markdown table.

Run:  scripts/dx python3 bench/ball_similar_meshes.py [--h 0.45e-3 0.32e-3 ...] [--out bench/results]
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import dolfinx_seal.scenes.ball as ball_scene
from dolfinx_seal.meshing import create_mesh
from dolfinx_seal.mpi import bcast_path, print0
from dolfinx_seal.output import SweepWriter
from dolfinx_seal.scenes import make_parameters


def similar_mesh(kind: str, **kw: object) -> object:
    """The scene's mesh with every size scaled with ``h_contact``."""
    h = float(kw["h_contact"])  # type: ignore[arg-type]
    kw["h_cap"] = 2.0 * h
    kw["h_far"] = min(6.0 * h, float(kw["radius"]) / 3.0)  # type: ignore[arg-type]
    return create_mesh(kind, **kw)  # type: ignore[arg-type]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--h", type=float, nargs="+",
                        default=[0.45e-3, 0.32e-3, 0.225e-3, 0.16e-3, 0.113e-3])  # fmt: skip
    parser.add_argument("--out", default="bench/results")
    args = parser.parse_args(argv)
    out = bcast_path(args.out)
    ball_scene.create_mesh = similar_mesh  # the scene builds its mesh through this name
    w = SweepWriter(out, "ball_similar_meshes.csv")
    print0("| h [mm] | unknowns | Newton | wall [s] | approach [um] | change [um] | order "
           "| radius vs Hertz | peak vs Hertz |")  # fmt: skip
    print0("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    prev: list[tuple[float, float]] = []
    for h in args.h:
        p = make_parameters(
            "ball",
            values={
                "lubricated": False,
                "contact": {"model": "stiff"},
                "h_contact": h,
                "mesh_growth": 0.2,
            },
        )
        r = ball_scene.run(p, out / f"ball_similar_{h:.3e}")
        d = r["counter_position"]
        change = abs(prev[-1][1] - d) if prev else math.nan
        order = math.nan
        if len(prev) >= 2:
            c0 = abs(prev[-2][1] - prev[-1][1])
            order = math.log(c0 / change) / math.log(prev[-1][0] / h)
        prev.append((h, d))
        ra = r["contact_radius"] / r["hertz_contact_radius"] - 1.0
        pk = r["max_contact_pressure"] / r["hertz_peak_pressure"] - 1.0
        row = {"h_contact": h, "dofs": r["dofs"], "newton_iterations": r["newton_iterations"],
               "wall_time_s": r["wall_time_s"], "approach": d, "change": change, "order": order,
               "radius_error": ra, "peak_error": pk}  # fmt: skip
        w.append(row)
        print0(f"| {h * 1e3:.3f} | {r['dofs']} | {r['newton_iterations']} | "
               f"{r['wall_time_s']:.0f} | {d * 1e6:.3f} | {change * 1e6:.3f} | {order:.1f} | "
               f"{ra * 100:+.2f} % | {pk * 100:+.2f} % |")  # fmt: skip


if __name__ == "__main__":
    main()
