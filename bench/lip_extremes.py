"""Benchmark: the lubricated lip on stiff and extreme cases (docs/design.md,
robustness contract), one parameter changed from the default seal at a time.

E 2 and 50 MPa, nu = 0.4999 in the displacement (compressible) form, oil
pressure 0.5 MPa, h_rms 0.1 and 10 um, rod speeds 1e-4 and +-30 m/s, zero
speed (rotary and reciprocating).  Each case converges or stops with its
error; the table records which, and the headline results.

Writes ``bench/results/lip_extremes.csv`` and ``lip_extremes.md``.

Run:  scripts/dx python3 bench/lip_extremes.py [--h-contact 10e-6]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.mpi import COMM_WORLD, print0
from dolfinx_seal.output import SweepWriter
from dolfinx_seal.scenes import make_parameters, run_scene

CASES = {
    "default (rotary, 5 m/s, oil 0.05 MPa)": {},
    "E = 2 MPa": {"material": {"E": 2e6}},
    "E = 50 MPa": {"material": {"E": 50e6}},
    "nu = 0.4999, displacement form": {"material": {"nu": 0.4999, "formulation": "compressible"}},
    "oil pressure 0.5 MPa": {"oil_pressure": 0.5e6},
    "h_rms 0.1 um": {"roughness": {"h_rms": 0.1e-6}},
    "h_rms 10 um": {"roughness": {"h_rms": 10e-6}},
    "rotary, zero speed": {"film": {"speed": 0.0}},
    "rotary, 30 m/s": {"film": {"speed": 30.0}},
    "rod, zero speed": {"motion": "reciprocating", "film": {"speed": 0.0}},
    "rod, 1e-4 m/s out": {"motion": "reciprocating", "film": {"speed": 1e-4}},
    "rod, 30 m/s out": {"motion": "reciprocating", "film": {"speed": 30.0}},
    "rod, 30 m/s in": {"motion": "reciprocating", "film": {"speed": -30.0}},
}
KEYS = ("radial_load", "contact_width", "leakage_rate", "h_min", "fluid_load_fraction",
        "mass_balance_error", "newton_iterations")  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="lip seal: stiff and extreme cases")
    ap.add_argument("--h-contact", type=float, default=10e-6)
    ap.add_argument("--out", default="bench/results")
    a = ap.parse_args(argv)
    out = Path(a.out)
    writer = SweepWriter(out, "lip_extremes.csv")
    lines = ["| case | outcome | radial load [N/m] | band [mm] | leakage [m^3/s] | h_min [nm] "
             "| fluid load | mass balance | Newton | time [s] |", "|---" * 10 + "|"]  # fmt: skip
    for name, values in CASES.items():
        t0 = time.perf_counter()
        row: dict = {"case": name}
        try:
            p = make_parameters("lip", values={**values, "lip": {"h_contact": a.h_contact}})
            res = run_scene("lip", p, out / "lip_extremes" / name.replace(" ", "_"), force=True)
            row.update(outcome="converged", **{k: res[k] for k in KEYS})
        except (SolverError, ParameterError) as e:
            row.update(outcome=f"stopped: {e}"[:300], **{k: math.nan for k in KEYS})
        row["wall_time_s"] = time.perf_counter() - t0
        writer.append(row)
        f = {k: row[k] for k in KEYS}
        ok = row["outcome"] == "converged"
        lines.append(
            f"| {name} | {row['outcome'] if not ok else 'converged'} | "
            + (f"{f['radial_load']:.1f} | {f['contact_width'] * 1e3:.3f} | {f['leakage_rate']:.3g} | "
               f"{f['h_min'] * 1e9:.1f} | {f['fluid_load_fraction']:.3f} | "
               f"{f['mass_balance_error']:.1e} | {f['newton_iterations']} |" if ok else "| | | | | | |")
            + f" {row['wall_time_s']:.0f} |"
        )  # fmt: skip
        print0(lines[-1])
    if COMM_WORLD.rank == 0:
        (out / "lip_extremes.md").write_text("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
