"""Benchmark: error against run time of the lubricated lip over contact meshes.

The default seal (scene ``lip``, rotary, oil 0.05 MPa) on contact elements of
20 / 10 / 5 / 2.5 um: leakage, friction torque (at the default speed), h_min,
radial load and band width, the wall time of each level (installation,
lubrication), observed orders against the finest level and Richardson's
extrapolation of the three finest.  Also the frozen-lip leakage against the
resistance integral of the FEM's own separation field
(:func:`~dolfinx_seal.verification.seal_leakage.static_leakage`).

Writes ``bench/results/lip_mesh.csv`` and ``lip_mesh.png``.

Run:  scripts/dx python3 bench/lip_mesh.py [--sizes 20e-6 10e-6 5e-6 2.5e-6] [--h-rms 0.5e-6]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from dolfinx_seal.contact.flow_factors import BruggemanFlowFactor
from dolfinx_seal.mpi import COMM_WORLD, print0
from dolfinx_seal.output import SweepWriter
from dolfinx_seal.scenes import lip, make_parameters
from dolfinx_seal.verification.seal_leakage import static_leakage

KEYS = ("leakage_rate", "friction_torque", "h_min", "radial_load", "contact_width")


def level(h: float, h_rms: float) -> dict[str, float]:
    """One mesh level: the coupled point and the frozen film against the reference."""
    p = make_parameters("lip", values={"lip": {"h_contact": h}, "roughness": {"h_rms": h_rms}})
    t0 = time.perf_counter()
    lub = lip.build(p)
    t_install = time.perf_counter() - t0
    # the frozen film on the installed lip first (the reference sees the same gap)
    film = lub.problem.film
    frozen = film.make_solver(lub.problem.solver.options, name="lip film")
    lip.set_sealed_pressures(lub, p.oil_pressure, p.air_pressure)
    frozen.solve(where="frozen lip")
    q_frozen = lip.results(lub, p)["leakage_rate"]
    band = lip.band_nodes(lub)
    ff = BruggemanFlowFactor(p.roughness.build(), p.material.E_star)
    q_ref = static_leakage(band["r"], band["z"], band["u"], p.oil_pressure, p.film.viscosity,
                           ff.pressure_factor)  # fmt: skip
    frozen.destroy()
    lip.set_sealed_pressures(lub, 0.0, 0.0)
    lub.problem.solver.solve(where="back to zero pressure")
    t1 = time.perf_counter()
    info = lip.move_oil_pressure(lub, p)
    res = lip.results(lub, p)
    row = {"h_contact": h, "dofs": res["dofs"], "install_time_s": t_install,
           "lubricate_time_s": time.perf_counter() - t1,
           "wall_time_s": time.perf_counter() - t0,
           "newton_iterations": info["newton_iterations"],
           "mass_balance_error": res["mass_balance_error"],
           "frozen_leakage": q_frozen, "frozen_reference": q_ref,
           # an exact reference of 0: the band percolates (the Bruggeman factor
           # vanishes where A/A0 passes 1/2; the film's table keeps a small tail)
           "frozen_error": q_frozen / q_ref - 1.0 if q_ref > 0 else math.inf}  # fmt: skip
    row.update({k: res[k] for k in KEYS})
    return row


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="lip seal: error against run time")
    ap.add_argument("--sizes", type=float, nargs="+", default=[20e-6, 10e-6, 5e-6, 2.5e-6])
    ap.add_argument("--h-rms", type=float, default=0.5e-6)
    ap.add_argument("--out", default="bench/results")
    a = ap.parse_args(argv)
    out = Path(a.out)
    tag = "" if a.h_rms == 0.5e-6 else f"_hrms{a.h_rms:g}"
    writer = SweepWriter(out, f"lip_mesh{tag}.csv")
    rows = []
    for h in sorted(a.sizes, reverse=True):
        r = level(h, a.h_rms)
        rows.append(r)
        print0(f"h {h * 1e6:g} um: " + ", ".join(f"{k} {r[k]:.6g}" for k in KEYS)
               + f", frozen/ref - 1 = {r['frozen_error']:+.3g}, {r['wall_time_s']:.0f} s")  # fmt: skip
    fine = rows[-1]
    for r in rows:
        for k in KEYS:
            r[f"{k}_error"] = abs(r[k] / fine[k] - 1.0) if r is not fine else 0.0
        writer.append(r)
    if len(rows) >= 3:  # observed orders and Richardson from the three finest
        for k in KEYS:
            f3, f2, f1 = (rows[i][k] for i in (-3, -2, -1))
            if (f2 - f1) != 0 and (f3 - f2) / (f2 - f1) > 0:
                order = math.log((f3 - f2) / (f2 - f1)) / math.log(2.0)
                extra = f1 + (f1 - f2) / (2**order - 1)
                print0(f"{k}: observed order {order:.2f}, extrapolated {extra:.6g}, "
                       f"finest off by {f1 / extra - 1:+.2e}")  # fmt: skip
            else:
                print0(f"{k}: not monotone over the three finest levels")
    if COMM_WORLD.rank == 0:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6.4, 4.2))
        t = np.array([r["wall_time_s"] for r in rows[:-1]])
        for k, st in zip(KEYS, ("ko-", "bs-", "g^-", "rv-", "mD-"), strict=True):
            e = np.array([r[f"{k}_error"] for r in rows[:-1]])
            ax.loglog(t, np.maximum(e, 1e-12), st, label=k)
        ax.set_xlabel("wall time per level [s]")
        ax.set_ylabel(f"error against {fine['h_contact'] * 1e6:g} um")
        ax.legend(frameon=False, fontsize=8)
        fig.tight_layout()
        fig.savefig(out / f"lip_mesh{tag}.png", dpi=120)
        plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
