"""Benchmark: the FEM cylinder Stribeck curves against the independent half-space solver.

The S1 figure-12 and figure-14 systems (E = 10 MPa with sigma_1 = 1 MPa, E = 100 MPa
with sigma_1 = 10 MPa; h_rms 1 um), each with the Reynolds condition and with full
Sommerfeld (no cavitation): the FEM sweep (``dolfinx-seal sweep cylinder``, 30
elements per Hertz half-width) and the line-contact reference
(:mod:`dolfinx_seal.verification.line_ehl`: finite volumes and half-space influence
coefficients, the same Persson law) at the same speeds.  This checks the FEM's
Stribeck curves point by point and settles whether full Sommerfeld changes mu (S1:
"nearly the same" at E = 10 MPa) with a second, independent discretisation.

Writes ``cylinder_half_space_reference.csv`` and ``.png`` (mu against eta v, FEM
lines, reference markers) and prints a markdown table.

Run:  scripts/dx python3 bench/cylinder_half_space_reference.py [--out bench/results]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from dolfinx_seal.contact.hertz import hertz_line
from dolfinx_seal.coupled.sweep import stribeck_minimum
from dolfinx_seal.mpi import COMM_WORLD, bcast_path, print0
from dolfinx_seal.output import SweepWriter
from dolfinx_seal.scenes import make_parameters, parse_values, sweep_scene
from dolfinx_seal.verification.line_ehl import for_cylinder, speed_continuation

#: (label, Young's modulus [Pa], asperity shear sigma_1 [Pa]) as in S1 figures 12 and 14
SYSTEMS = {"E10MPa": (10e6, 1e6), "E100MPa": (100e6, 10e6)}
QUANTITIES = ("mu", "mu_couette", "mu_poiseuille", "mu_asperity", "h_min", "fluid_load_fraction")


def scene(E: float, sigma1: float, cavitation: str, elements: float) -> Any:
    """Cylinder parameters with ``elements`` contact elements per Hertz half-width."""
    values: dict[str, Any] = {
        "material": {"E": E},
        "film": {"asperity_shear": sigma1, "cavitation": cavitation},
    }
    p = make_parameters("cylinder", values={**values, "h_contact": 1e-9})
    a_h, _ = hertz_line(p.load, p.radius, p.material.E_star)
    return make_parameters("cylinder", values={**values, "h_contact": a_h / elements})


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--speeds", default="1e-5:1:11:log")
    parser.add_argument("--systems", nargs="+", default=list(SYSTEMS), choices=list(SYSTEMS))
    parser.add_argument("--cells", type=int, default=800, help="reference cells")
    parser.add_argument("--elements", type=float, default=30.0,
                        help="FEM contact elements per Hertz half-width")  # fmt: skip
    parser.add_argument("--out", default="bench/results")
    args = parser.parse_args(argv)
    out = bcast_path(args.out)
    speeds = parse_values(args.speeds)
    w = SweepWriter(out, "cylinder_half_space_reference.csv")
    curves: dict[tuple[str, str], tuple[list[dict[str, Any]], list[Any]]] = {}
    print0("| system | cavitation | points | FEM mu_min (eta v) | reference mu_min (eta v) "
           "| max rel. diff. mu | max rel. diff. h_min | FEM / reference time [s] |")  # fmt: skip
    print0("|---|---|---:|---|---|---:|---:|---|")
    for name in args.systems:
        E, sigma1 = SYSTEMS[name]
        for cav in ("reynolds", "none"):
            p = scene(E, sigma1, cav, args.elements)
            t0 = time.perf_counter()
            rows = sweep_scene("cylinder", p, out / f"half_space_{name}_{cav}", "film.speed",
                               speeds)  # fmt: skip
            t_fem = time.perf_counter() - t0
            t0 = time.perf_counter()
            refs = speed_continuation(for_cylinder(p, args.cells), speeds)
            t_ref = time.perf_counter() - t0
            by_speed = {round(float(r["speed"]), 12): r for r in rows}
            pairs = [
                (by_speed[round(s.speed, 12)], s) for s in refs if round(s.speed, 12) in by_speed
            ]
            diff = {q: 0.0 for q in ("mu", "h_min")}
            for fem, ref in pairs:
                row: dict[str, Any] = {"system": name, "cavitation": cav, "speed": ref.speed,
                                       "eta_v": float(fem["eta_v"])}  # fmt: skip
                for q in QUANTITIES:
                    row[f"{q}_fem"] = float(fem[q])
                    row[f"{q}_ref"] = float(getattr(ref, q))
                for q in diff:
                    diff[q] = max(diff[q], abs(row[f"{q}_fem"] / row[f"{q}_ref"] - 1.0))
                w.append(row)
            curves[(name, cav)] = (rows, refs)
            if len(pairs) < 3:  # the FEM sweep stopped early (see its sweep_failures.csv)
                print0(f"| {name} | {cav} | {len(pairs)} | FEM sweep incomplete | | | | |")
                continue
            ev = [float(f["eta_v"]) for f, _ in pairs]
            mf = stribeck_minimum(ev, [float(f["mu"]) for f, _ in pairs])
            mr = stribeck_minimum(ev, [r.mu for _, r in pairs])
            print0(f"| {name} | {cav} | {len(pairs)} | {mf[1]:.4f} ({mf[0]:.2e}) | "
                   f"{mr[1]:.4f} ({mr[0]:.2e}) | {diff['mu']:.1e} | {diff['h_min']:.1e} | "
                   f"{t_fem:.0f} / {t_ref:.0f} |")  # fmt: skip
    if COMM_WORLD.rank == 0:
        _plot(out / "cylinder_half_space_reference.png", curves, p.film.viscosity)


def _plot(path: Path, curves: dict[tuple[str, str], Any], viscosity: float) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    colours = {"E10MPa": "tab:blue", "E100MPa": "tab:red"}
    for (name, cav), (rows, refs) in curves.items():
        style = "-" if cav == "reynolds" else "--"
        label = f"{name.replace('MPa', ' MPa').replace('E', 'E = ')}, {cav}"
        ax.loglog([float(r["eta_v"]) for r in rows], [float(r["mu"]) for r in rows], style,
                  color=colours[name], label=f"FEM, {label}")  # fmt: skip
        ax.loglog([viscosity * r.speed for r in refs], [r.mu for r in refs], "o" if
                  cav == "reynolds" else "s", mfc="none", color=colours[name])  # fmt: skip
    ax.plot([], [], "ko", mfc="none", label="half-space reference (markers)")
    ax.set_xlabel("eta v [Pa m]")
    ax.set_ylabel("mu")
    ax.set_title("cylinder: FEM against the half-space line-contact solver")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
