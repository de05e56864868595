"""Study: Stribeck curves of the lubricated ball for several roughness amplitudes
(S1 figure 25: "when the surface roughness decreases, the minimum ... is shifted to
lower velocities"; S1 prints no numbers).

The S1 figure-18 system (R = 1 cm, F = 1.3 N, E* = 1.6 MPa, eta = 0.1 Pa s,
D_f = 2.2) with h_rms from ``--h-rms``; each curve is one sweep walking down in
speed (:mod:`demos.ball_stribeck` settings) on a contact mesh of
a_Hertz / ``--elements-per-radius``.  The minimum of each curve is located by the
smallest computed mu and refined by a parabola in (log eta v, log mu) through it
and its two neighbours.  Writes ``<out>/hrms_<h>um/sweep.csv`` per curve,
``<out>/stribeck_minima.csv`` and ``<out>/stribeck_roughness.png``.  With
``--plot-only`` it reads existing sweeps instead of computing them.

Run:  scripts/dx python3 bench/ball_stribeck_roughness.py [--h-rms 1e-6 1.6e-6 3.6e-6]
          [--speeds 1 0.56 0.3 0.18 0.1 0.056 0.03 0.018 0.01]
          [--elements-per-radius 20] [--out bench/results/stribeck_roughness] [--plot-only]
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from demos.ball_stribeck import run
from dolfinx_seal.coupled.sweep import stribeck_minimum
from dolfinx_seal.mpi import COMM_WORLD, bcast_path, print0
from dolfinx_seal.output import SweepWriter, column, read_csv

SPEEDS = [1.0, 0.56, 0.3, 0.18, 0.1, 0.056, 0.03, 0.018, 0.01]  # m/s, quarter decades


def _label(h_rms: float) -> str:
    return f"hrms_{h_rms * 1e6:g}um"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--h-rms", type=float, nargs="+", default=[1e-6, 1.6e-6, 3.6e-6])
    parser.add_argument("--speeds", type=float, nargs="+", default=SPEEDS, help="[m/s]")
    parser.add_argument("--elements-per-radius", type=float, default=20.0)
    parser.add_argument("--out", default="bench/results/stribeck_roughness")
    parser.add_argument("--plot-only", action="store_true")
    args = parser.parse_args(argv)
    out = bcast_path(args.out)
    curves = {}
    for h in args.h_rms:
        d = out / _label(h)
        if not args.plot_only:
            run(d, args.speeds, args.elements_per_radius, roughness={"h_rms": h})
        rows = read_csv(d / "sweep.csv") if COMM_WORLD.rank == 0 else []
        curves[h] = tuple(np.array(column(rows, k)) for k in ("eta_v", "mu", "fluid_load_fraction"))
    if COMM_WORLD.rank != 0:
        return
    w = SweepWriter(out, "stribeck_minima.csv")
    print0("| h_rms [um] | speeds | eta v at min [Pa m] | mu min | bracketed |")
    print0("|---:|---:|---:|---:|---|")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    for h, (ev, mu, fl) in curves.items():
        ev_min, mu_min, bracketed = stribeck_minimum(ev, mu)
        w.append({"h_rms_m": h, "points": len(ev), "eta_v_min_Pa_m": ev_min, "mu_min": mu_min,
                  "bracketed": bracketed})  # fmt: skip
        print0(f"| {h * 1e6:g} | {len(ev)} | {ev_min:.3g} | {mu_min:.4f} | {bracketed} |")
        o = np.argsort(ev)
        (line,) = ax1.loglog(ev[o], mu[o], "o-", ms=3, label=f"h_rms {h * 1e6:g} um")
        ax1.plot([ev_min], [mu_min], "x", color=line.get_color(), ms=9)
        ax2.semilogx(ev[o], fl[o], "o-", ms=3, color=line.get_color())
    ax1.set_xlabel("eta v [Pa m]")
    ax1.set_ylabel("friction coefficient")
    ax1.legend(frameon=False, fontsize=8)
    ax1.set_title("x: minimum (parabola in log-log)", fontsize=9)
    ax2.set_xlabel("eta v [Pa m]")
    ax2.set_ylabel("fluid load fraction")
    fig.suptitle("ball, S1 fig-18 system: Stribeck curves against roughness (cf. S1 fig 25)")
    fig.tight_layout()
    fig.savefig(out / "stribeck_roughness.png", dpi=120)
    plt.close(fig)
    if any(math.isnan(float(v)) for v in np.concatenate([c[1] for c in curves.values()])):
        raise SystemExit("a Stribeck curve holds NaN")


if __name__ == "__main__":
    main()
