"""Study: the lubricated ball walking down into boundary lubrication (S1 figures 23-24):
the fluid load fraction falls and the total pressure (fluid + asperity) tends to
the dry, roughness-broadened Hertz pressure.

The S1 figure-18 system (R = 1 cm, F = 1.3 N, E* = 1.6 MPa, eta = 0.1 Pa s,
D_f = 2.2) with h_rms ``--h-rms`` (default 3.6 um: the roughness whose sweep reaches
lowest; with 1 um the continuation stalls between 5.6 and 3.2 mm/s), one sweep walking
down in speed (:mod:`demos.ball_stribeck`) with ``stepping.max_failures = 1``, and
the dry ball (``lubricated = false``) with the same roughness and contact elements as
the limit.  For every converged speed it compares, on the contact plane, the total
pressure with the dry pressure and with Hertz (rms difference over r < 1.5 a_H, in
units of p_H, and the peaks).  Writes ``<out>/sweep/`` (the sweep), ``<out>/dry/``,
``<out>/low_speed.csv`` and ``<out>/low_speed.png`` (centre-line total and fluid
pressure at each speed with the dry and Hertz ones).  ``--plot-only`` reads existing
runs.

Run:  scripts/dx python3 bench/ball_low_speed.py [--h-rms 3.6e-6]
          [--speeds 0.1 0.03 0.01 0.003 0.001 3e-4 1e-4] [--elements-per-radius 15]
          [--out bench/results/low_speed] [--plot-only]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from demos.ball_stribeck import parameters, run
from dolfinx_seal.contact.hertz import hertz_point
from dolfinx_seal.mpi import COMM_WORLD, bcast_path, print0
from dolfinx_seal.output import SweepWriter, read_csv
from dolfinx_seal.scenes import run_scene

SPEEDS = [0.1, 0.03, 0.01, 3e-3, 1e-3, 3e-4, 1e-4]  # m/s


def _map(path: Path) -> dict[str, np.ndarray]:
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    keys = path.read_text().splitlines()[0].split(",")
    return {k: data[:, i] for i, k in enumerate(keys)}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--h-rms", type=float, default=3.6e-6, help="[m]")
    parser.add_argument("--speeds", type=float, nargs="+", default=SPEEDS, help="[m/s]")
    parser.add_argument("--elements-per-radius", type=float, default=15.0)
    parser.add_argument("--out", default="bench/results/low_speed")
    parser.add_argument("--plot-only", action="store_true")
    args = parser.parse_args(argv)
    out = bcast_path(args.out)
    rough = {"roughness": {"h_rms": args.h_rms}}
    if not args.plot_only:
        run(out / "sweep", args.speeds, args.elements_per_radius,
            stepping={"max_failures": 1}, **rough)  # fmt: skip
        dry = parameters(args.elements_per_radius, lubricated=False, **rough)
        run_scene("ball", dry, out / "dry")
    if COMM_WORLD.rank != 0:
        return
    p = parameters(args.elements_per_radius, **rough)
    a_h, p_h = hertz_point(p.load, p.radius, p.material.E_star)
    dry = np.loadtxt(out / "dry" / "pressure.csv", delimiter=",", skiprows=1)
    x_dry, p_dry = dry[:, 0], dry[:, 1]
    rows = read_csv(out / "sweep" / "sweep.csv")
    w = SweepWriter(out, "low_speed.csv")
    print0("| U [m/s] | eta v [Pa m] | fluid load | mu | rms(p - p_dry)/p_H | rms(p - Hertz)/p_H "
           "| max p / p_H | max p_fluid / p_H |")  # fmt: skip
    print0("|---:|---:|---:|---:|---:|---:|---:|---:|")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
    colours = plt.cm.viridis(np.linspace(0.0, 0.92, max(len(rows), 1)))
    for r, colour in zip(rows, colours, strict=True):
        v = float(r["speed"])
        m = _map(out / "sweep" / f"speed_{v:.3e}" / "film_map.csv")
        X, Y = m["X_m"], m["Y_m"]
        total = m["p_fluid_Pa"] + m["p_contact_Pa"]
        rad = np.hypot(X, Y)
        hertz = p_h * np.sqrt(np.clip(1.0 - (rad / a_h) ** 2, 0.0, None))
        # the dry pressure is axisymmetric to plotting accuracy: take it along |x| = r
        dry_here = np.interp(rad, np.abs(x_dry[np.argsort(np.abs(x_dry))]),
                             p_dry[np.argsort(np.abs(x_dry))], right=0.0)  # fmt: skip
        near = rad < 1.5 * a_h
        row = {
            "speed": v,
            "eta_v": float(r["eta_v"]),
            "fluid_load_fraction": float(r["fluid_load_fraction"]),
            "mu": float(r["mu"]),
            "rms_vs_dry": float(np.sqrt(np.mean((total - dry_here)[near] ** 2)) / p_h),
            "rms_vs_hertz": float(np.sqrt(np.mean((total - hertz)[near] ** 2)) / p_h),
            "max_total_over_pH": float(total.max() / p_h),
            "max_fluid_over_pH": float(m["p_fluid_Pa"].max() / p_h),
        }
        w.append(row)
        print0(f"| {v:g} | {row['eta_v']:.2g} | {row['fluid_load_fraction']:.3f} "
               f"| {row['mu']:.3f} | {row['rms_vs_dry']:.3f} | {row['rms_vs_hertz']:.3f} "
               f"| {row['max_total_over_pH']:.3f} | {row['max_fluid_over_pH']:.3f} |")  # fmt: skip
        axis = np.abs(Y) < 1e-9 * a_h
        o = np.argsort(X[axis])
        ax1.plot(X[axis][o] / a_h, total[axis][o] / p_h, lw=1.2, color=colour, label=f"{v:g} m/s")
        ax2.plot(X[axis][o] / a_h, m["p_fluid_Pa"][axis][o] / p_h, lw=1.2, color=colour)
    xs = np.linspace(-1.5, 1.5, 301)
    for ax in (ax1, ax2):
        ax.plot(xs, np.sqrt(np.clip(1 - xs**2, 0, None)), "k--", lw=1, label="Hertz")
        ax.plot(x_dry / a_h, p_dry / p_h, "k:", lw=1.5, label="dry, same roughness")
        ax.set_xlabel("x / a_H (y = 0, sliding along x)")
        ax.set_xlim(-1.5, 1.5)
    ax1.set_ylabel("total pressure / p_H")
    ax2.set_ylabel("fluid pressure / p_H")
    ax1.legend(frameon=False, fontsize=7)
    fig.suptitle(f"ball, h_rms = {args.h_rms * 1e6:g} um: towards boundary lubrication "
                 "(cf. S1 figs 23-24)")  # fmt: skip
    fig.tight_layout()
    fig.savefig(out / "low_speed.png", dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main()
