"""Benchmark: a smooth rod in full film under the default lip, against inverse hydrodynamics.

The default lip seal (scene ``lip``) on a reciprocating rod smoother than the
installation roughness (default h_rms 0.02 um: a lapped rod under a smooth lip),
with a hydraulic oil (ISO VG 46 at 40 C: 0.04 Pa s) and no sealed pressure, swept
over both stroke directions (``dolfinx-seal sweep lip --over film.speed``, each
chain starting at its fastest speed).  Each converged point is compared with the
inverse hydrodynamic (IHL) solution of the dry installed contact pressure of the
same mesh (:func:`~dolfinx_seal.verification.seal_leakage.ihl_solution`, Blok;
Muller & Nau): the film the rod carries (``q / U = h*/2``) and the full-film
friction.  IHL holds where the film does not change the pressure under the lip;
the FEM shows where that stops (the lip lifts and tilts at high speed).

Writes ``bench/results/lip_rod.csv``, ``lip_rod.md`` and ``lip_rod.png``.

Run:  scripts/dx python3 bench/lip_rod.py [--sizes 10e-6 5e-6] [--speeds 0.03 0.3 3 30]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from dolfinx_seal.mpi import COMM_WORLD, print0
from dolfinx_seal.output import SweepWriter, read_csv, write_text_atomic
from dolfinx_seal.scenes import lip_install, make_parameters, sweep_scene
from dolfinx_seal.verification.seal_leakage import ihl_solution

SPEEDS = (0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0)


def parameters(h_contact: float, h_rms: float, viscosity: float):
    return make_parameters("lip", values={
        "lip": {"h_contact": h_contact}, "roughness": {"h_rms": h_rms},
        "film": {"viscosity": viscosity}, "motion": "reciprocating", "oil_pressure": 0.0,
    })  # fmt: skip


def dry_profile(p) -> tuple[np.ndarray, np.ndarray]:
    """The installed contact pressure [Pa] against the current axial position [m]."""
    inst = lip_install.install(p)
    prob = inst.problem
    _, pc = prob.surface_values(prob.p_cont, average=True)
    _, z = prob.surface_values(prob.x[1], average=True)
    prob.destroy()
    order = np.argsort(z)
    return z[order], pc[order]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="smooth rod under the lip against IHL")
    ap.add_argument("--sizes", type=float, nargs="+", default=[10e-6, 5e-6])
    ap.add_argument("--speeds", type=float, nargs="+", default=list(SPEEDS))
    ap.add_argument("--h-rms", type=float, default=0.02e-6)
    ap.add_argument("--viscosity", type=float, default=0.04)
    ap.add_argument("--out", default="bench/results")
    a = ap.parse_args(argv)
    out = Path(a.out)
    writer = SweepWriter(out, "lip_rod.csv")
    rows = []
    speeds = sorted({s * sign for s in a.speeds for sign in (1.0, -1.0)})
    for h in a.sizes:
        p = parameters(h, a.h_rms, a.viscosity)
        z, pc = dry_profile(p)
        t0 = time.perf_counter()
        folder = out / f"lip_rod_{h:g}"
        try:
            sweep_scene("lip", p, folder, "film.speed", speeds, force=True)
        except Exception as e:  # the finished points are in the sweep's folder
            print0(f"h_contact {h:g}: sweep incomplete: {e}")
        wall = time.perf_counter() - t0
        for r in read_csv(folder / "sweep.csv"):
            u = float(r["speed"])
            ihl = ihl_solution(z, pc, a.viscosity, u, p.lip.shaft_radius)
            t = float(r["transport_film_thickness"])
            f = float(r["friction_force"])
            row = {"h_contact": h, "speed": u, "transport_film": t,
                   "ihl_transport_film": ihl["transport_film_thickness"],
                   "film_ratio": t / ihl["transport_film_thickness"],
                   "friction_force": f, "ihl_friction_force": ihl["friction_force"],
                   "friction_ratio": f / ihl["friction_force"],
                   "h_min": float(r["h_min"]), "fluid_load_fraction": float(r["fluid_load_fraction"]),
                   "radial_load": float(r["radial_load"]),
                   "mass_balance_error": float(r["mass_balance_error"]),
                   "newton_iterations": int(float(r["newton_iterations"])),
                   "sweep_wall_time_s": wall}  # fmt: skip
            writer.append(row)
            rows.append(row)
            print0(f"h {h:g} U {u:+g}: film {t:.4g} m (IHL {row['ihl_transport_film']:.4g}, "
                   f"ratio {row['film_ratio']:.3f}), friction {f:.4g} N (IHL ratio "
                   f"{row['friction_ratio']:.3f}), fluid load {row['fluid_load_fraction']:.4f}")  # fmt: skip
    if COMM_WORLD.rank == 0 and rows:
        _report(out, rows, a)
    return 0


def _report(out: Path, rows: list[dict], a: argparse.Namespace) -> None:
    lines = [
        f"# Smooth rod under the default lip (h_rms {a.h_rms:g} m, eta {a.viscosity:g} Pa s)",
        "",
        "| h_contact [um] | U [m/s] | film carried [nm] | IHL [nm] | ratio | friction [N] | "
        "IHL friction [N] | ratio | h_min [nm] | fluid load | radial load [N/m] |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(
            f"| {r['h_contact'] * 1e6:g} | {r['speed']:+g} | {r['transport_film'] * 1e9:.1f} | "
            f"{r['ihl_transport_film'] * 1e9:.1f} | {r['film_ratio']:.3f} | "
            f"{r['friction_force']:.3f} | {r['ihl_friction_force']:.3f} | "
            f"{r['friction_ratio']:.3f} | {r['h_min'] * 1e9:.1f} | "
            f"{r['fluid_load_fraction']:.4f} | {r['radial_load']:.1f} |"
        )
    write_text_atomic(out / "lip_rod.md", "\n".join(lines) + "\n")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    for h in sorted({r["h_contact"] for r in rows}):
        for sign, mk, name in ((1.0, "o", "out-stroke"), (-1.0, "s", "in-stroke")):
            rr = sorted((r for r in rows if r["h_contact"] == h and r["speed"] * sign > 0),
                        key=lambda r: abs(r["speed"]))  # fmt: skip
            if not rr:
                continue
            u = [abs(r["speed"]) for r in rr]
            ax1.loglog(u, [r["transport_film"] * 1e9 for r in rr], mk + "-", ms=4,
                       label=f"FEM {name}, {h * 1e6:g} um")  # fmt: skip
            ax2.loglog(u, [r["friction_force"] for r in rr], mk + "-", ms=4,
                       label=f"FEM {name}, {h * 1e6:g} um")  # fmt: skip
    for sign, ls, name in ((1.0, "k--", "IHL out"), (-1.0, "k:", "IHL in")):
        rr = sorted((r for r in rows if r["speed"] * sign > 0 and r["h_contact"] == rows[0]["h_contact"]),
                    key=lambda r: abs(r["speed"]))  # fmt: skip
        if rr:
            u = [abs(r["speed"]) for r in rr]
            ax1.loglog(u, [r["ihl_transport_film"] * 1e9 for r in rr], ls, label=name)
            ax2.loglog(u, [r["ihl_friction_force"] for r in rr], ls, label=name)
    ax1.set_xlabel("|rod speed| [m/s]")
    ax1.set_ylabel("oil film carried q/U [nm]")
    ax2.set_xlabel("|rod speed| [m/s]")
    ax2.set_ylabel("friction force [N]")
    ax1.legend(frameon=False, fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "lip_rod.png", dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    raise SystemExit(main())
