# %% [markdown]
# # Stribeck curves of the soft lubricated cylinder (S1 figures 8-10, 12, 14-15)
#
# A rubber cylinder ($R$ = 1 cm, 100 N/m, plane strain) slides on a rigid flat
# in oil.  The 1D Reynolds film on the deformed contact line,
#
# $$ \frac{d}{dx}\Big( \frac{g^3}{12 \eta} \frac{dp}{dx} \Big) = \frac{U}{2} \frac{dg}{dx}, $$
#
# and the Persson asperity pressure $p_\mathrm{cont}(g)$ share one Newton
# system with the rubber; the friction coefficient $\mu(\eta v)$ goes from
# boundary lubrication (asperities carry the load, $\mu \approx \sigma_1 A / F$)
# through a minimum to the hydrodynamic branch ($\mu$ grows with the film's
# viscous shear).  `dolfinx-seal sweep cylinder` is run over speed for
#
# * h_rms = 1, 3, 6 um at E = 10 MPa (S1 figures 8-10: the minimum moves with h_rms);
# * h_rms = 1 um with the Persson/Bruggeman pressure flow factor (not in S1, which
#   has none);
# * E = 10 MPa, 100 MPa, 1 GPa with the Reynolds condition and without
#   cavitation (full Sommerfeld) (S1 figures 12, 14-15), with S1's asperity
#   shear stress sigma_1 = 1, 10, 100 MPa (E / 10);
#
# and writes `stribeck.png` (all curves), `minima.csv` (speed and mu at
# each curve's minimum) and one folder per curve (`sweep.csv`, `sweep.png`).
# The element size at the contact is the Hertz half-width $a$ over
# `elements_per_half_width`.
#
# Run: `scripts/dx python3 demos/cylinder_stribeck.py [--out results/stribeck] [--quick]`

# %%
from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from dolfinx_seal.contact.hertz import hertz_line
from dolfinx_seal.mpi import COMM_WORLD, bcast_path, print0
from dolfinx_seal.output import Progress
from dolfinx_seal.scenes import make_parameters, sweep_scene

DESCRIPTION = "Stribeck curves of the soft lubricated cylinder (S1 figures 8-10, 12, 14-15)"

# %% [markdown]
# ## The curves
# Each curve is a set of parameter values over the scene's defaults.

# %%
CURVES = {
    "h1um": {"roughness": {"h_rms": 1e-6}},
    "h3um": {"roughness": {"h_rms": 3e-6}},
    "h6um": {"roughness": {"h_rms": 6e-6}},
    "h1um-nocav": {"roughness": {"h_rms": 1e-6}, "film": {"cavitation": "none"}},
    # not in S1: the Persson/Bruggeman pressure flow factor of the same roughness
    "h1um-flowfactor": {"roughness": {"h_rms": 1e-6}, "film": {"flow_factor": "persson"}},
    # S1 figures 14-15: sigma_1 = 10 MPa at E = 100 MPa, 100 MPa at E = 1 GPa
    "E100MPa": {"material": {"E": 100e6}, "film": {"asperity_shear": 10e6}},
    "E100MPa-nocav": {
        "material": {"E": 100e6},
        "film": {"asperity_shear": 10e6, "cavitation": "none"},
    },
    "E1GPa": {"material": {"E": 1e9}, "film": {"asperity_shear": 100e6}},
    "E1GPa-nocav": {
        "material": {"E": 1e9},
        "film": {"asperity_shear": 100e6, "cavitation": "none"},
    },
}


# %% [markdown]
# ## The mesh of a curve
# The Hertz half-width of the line contact, $a = \sqrt{4 F' R / (\pi E^*)}$,
# sets the contact element size.


# %%
def curve_parameters(values: dict[str, Any], elements_per_half_width: float) -> Any:
    """Scene parameters of one curve, with the contact element size set from a_Hertz."""
    p = make_parameters("cylinder", values={**values, "h_contact": 1e-9})  # for a_Hertz only
    a_h, _ = hertz_line(p.load, p.radius, p.material.E_star)
    return make_parameters(
        "cylinder", values={**values, "h_contact": a_h / elements_per_half_width}
    )


# %% [markdown]
# ## The sweeps and their minima
# One continuation sweep per curve; the minimum of $\mu$ with its speed, the
# fluid share of the load there, and the worst load and mass balance.


# %%
def run(
    out: Path, curves: list[str], speeds: list[float], elements_per_half_width: float = 30.0
) -> list[dict[str, Any]]:
    """Run the curves; returns one summary row per curve (minimum of mu)."""
    summary = []
    all_rows = {}
    for name in curves:
        p = curve_parameters(CURVES[name], elements_per_half_width)
        with Progress(len(speeds), "film.speed", "m/s") as progress:
            rows = sweep_scene("cylinder", p, out / name, "film.speed", speeds, progress=progress)
        all_rows[name] = rows
        if not rows:
            continue
        mu = np.array([float(r["mu"]) for r in rows])
        i = int(np.argmin(mu))
        summary.append({
            "curve": name, "points": len(rows), "speed_at_min": float(rows[i]["speed"]),
            "eta_v_at_min": float(rows[i]["eta_v"]), "mu_min": float(mu[i]),
            "fluid_fraction_at_min": float(rows[i]["fluid_load_fraction"]),
            "newton_per_step_max": max(
                float(r["newton_iterations"]) / max(float(r["continuation_steps"]), 1.0)
                for r in rows[1:]) if len(rows) > 1 else float("nan"),
            "max_load_balance_error": max(float(r["load_balance_error"]) for r in rows),
            "max_mass_balance_error": max(float(r["mass_balance_error"]) for r in rows),
        })  # fmt: skip
    if COMM_WORLD.rank == 0 and summary:
        keys = list(summary[0])
        with (out / "minima.csv").open("w") as fh:
            fh.write(",".join(keys) + "\n")
            for s in summary:
                fh.write(",".join(str(s[k]) for k in keys) + "\n")
        _plot(out, all_rows)
    return summary


# %% [markdown]
# ## The figure
# mu and the fluid load fraction against $\eta v$ for every curve (dashed:
# without cavitation).


# %%
def _plot(out: Path, all_rows: dict[str, list[dict[str, Any]]]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for name, rows in all_rows.items():
        if not rows:
            continue
        ev = [float(r["eta_v"]) for r in rows]
        style = "--" if "nocav" in name else "-"
        ax1.loglog(ev, [float(r["mu"]) for r in rows], style, marker="o", ms=3, label=name)
        ax2.semilogx(ev, [float(r["fluid_load_fraction"]) for r in rows], style, marker="o", ms=3,
                     label=name)  # fmt: skip
    ax1.set_xlabel("eta v [Pa m]")
    ax1.set_ylabel("friction coefficient mu")
    ax1.set_title("cylinder Stribeck curves (S1 figs 8-15)")
    ax1.legend(frameon=False, fontsize=7)
    ax2.set_xlabel("eta v [Pa m]")
    ax2.set_ylabel("fluid load fraction")
    fig.tight_layout()
    fig.savefig(out / "stribeck.png", dpi=120)
    plt.close(fig)


# %% [markdown]
# ## From the command line
# `--quick`: 3 speeds, 2 curves, coarse; `--plot-only` redraws the figure from
# the `sweep.csv` files already in `--out`.


# %%
def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=DESCRIPTION)
    parser.add_argument("--out", default="results/stribeck")
    parser.add_argument("--curves", nargs="+", default=list(CURVES), choices=list(CURVES))
    parser.add_argument("--speeds", default="1e-6:10:15:log")
    parser.add_argument(
        "--elements", type=float, default=30.0, help="elements per Hertz half-width"
    )
    parser.add_argument("--quick", action="store_true", help="3 speeds, 2 curves, coarse")
    parser.add_argument("--plot-only", action="store_true",
                        help="redraw stribeck.png from the sweep.csv files in --out")  # fmt: skip
    args = parser.parse_args(argv)
    from dolfinx_seal.scenes import parse_values

    if args.plot_only:
        from dolfinx_seal.output import read_csv

        out = Path(args.out)
        rows = {
            c: read_csv(out / c / "sweep.csv")
            for c in args.curves
            if (out / c / "sweep.csv").exists()
        }
        if COMM_WORLD.rank == 0:
            _plot(out, rows)
        return

    speeds = parse_values(args.speeds)
    curves = args.curves
    if args.quick:
        speeds, curves, args.elements = [1e-4, 3e-2, 1.0], ["h1um", "h3um"], 15.0
    out = bcast_path(args.out)
    summary = run(out, curves, speeds, args.elements)
    print0(
        "| curve | points | speed at min [m/s] | eta v at min [Pa m] | mu_min | fluid fraction | max Newton/step |"
    )
    print0("|---|---|---|---|---|---|---|")
    for s in summary:
        print0(f"| {s['curve']} | {s['points']} | {s['speed_at_min']:.3g} | {s['eta_v_at_min']:.3g} | "
               f"{s['mu_min']:.4f} | {s['fluid_fraction_at_min']:.3f} | {s['newton_per_step_max']:.1f} |")  # fmt: skip
    print0(f"wrote {out}/stribeck.png and {out}/minima.csv")


if __name__ == "__main__":
    main()
