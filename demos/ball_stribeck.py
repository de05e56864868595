# %% [markdown]
# # A Stribeck sweep of the lubricated rubber ball (S1 section 3)
#
# The S1 figure-18 system: a rubber ball ($R$ = 1 cm, $F$ = 1.3 N,
# $E^*$ = 1.6 MPa) on a rigid flat in oil ($\eta$ = 0.1 Pa s), with a rough
# surface ($h_\mathrm{rms}$ = 1 um, fractal dimension 2.2).  A half ball (symmetry
# plane $y = 0$), neo-Hookean; on the deformed contact cap a 2D Reynolds film
#
# $$ \nabla \cdot \Big( \frac{g^3}{12 \eta} \nabla p \Big) = \frac{U}{2} \frac{\partial g}{\partial x}, \qquad p \ge 0 \ \text{(Reynolds cavitation condition)}, $$
#
# shares one Newton system with the rubber, whose surface carries the fluid
# pressure $p$ and the Persson asperity pressure $p_\mathrm{cont}(g)$; the
# ball's height is the unknown that balances the load,
# $\int (p + p_\mathrm{cont})\, dA = F$.  The friction coefficient
#
# $$ \mu = \frac{1}{F} \int \Big( \sigma_1 \frac{A}{A_0} + \frac{\eta U}{g} + \frac{g}{2} \frac{\partial p}{\partial x} \Big) dA $$
#
# splits into its asperity, Couette and Poiseuille parts (S1 eq 29).  The sweep
# starts in full film (hydrodynamic start from the Hamrock-Dowson film) and
# walks down in speed with continuation.
#
# Writes into `--out`:
#
# * `sweep.csv` -- one row per converged speed (mu and its parts, load split,
#   h_min, h_central, cavitated area, load and mass balance, Newton steps, times);
# * `sweep.png` -- mu against eta v with the load split and the film thickness;
# * `speed_<U>/film_map.png` (and `.csv`) -- fluid pressure, asperity
#   pressure, gap and cavitation at each speed;
# * `hamrock_dowson.csv` -- h_central and h_min against the Hamrock-Dowson
#   isoviscous-elastic regressions at the full-film speeds.
#
# Run: `scripts/dx python3 demos/ball_stribeck.py [--out results/demo] [--speeds ...]`

# %%
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from dolfinx_seal.contact.hertz import hertz_point
from dolfinx_seal.mpi import COMM_WORLD, bcast_path, print0
from dolfinx_seal.output import Progress, SweepWriter
from dolfinx_seal.scenes import make_parameters, sweep_scene
from dolfinx_seal.verification.ehl import IsoviscousElasticFilm

SPEEDS = [0.3, 0.1, 0.03]  # [m/s], walked downwards (full film to the onset of asperity contact)
ELEMENTS_PER_RADIUS = 15.0  # contact element size a_Hertz / 15
DESCRIPTION = "A Stribeck sweep of the lubricated rubber ball (S1 section 3)"

# %% [markdown]
# ## The parameters
# The defaults of scene `ball` are the S1 system; the mesh is set by the
# Hertz contact radius $a = (3 F R / 4 E^*)^{1/3}$: contact elements of
# $a$ / `elements_per_radius`.


# %%


def parameters(elements_per_radius: float = ELEMENTS_PER_RADIUS, **values: Any) -> Any:
    """Ball parameters with the contact element size ``a_Hertz / elements_per_radius``
    and no rim zone (``rim_refinement`` 1, unless given): the demo follows mu, which
    the rim moves by 0.3 %, at half the unknowns (the rim resolves h_min)."""
    values = {"rim_refinement": 1.0, **values}
    p = make_parameters("ball", values={**values, "h_contact": 1e-4})  # for a_Hertz only
    a_h, _ = hertz_point(p.load, p.radius, p.material.E_star)
    return make_parameters("ball", values={**values, "h_contact": a_h / elements_per_radius})


# %% [markdown]
# ## The Hamrock-Dowson check
# In full film (fluid load fraction > 99 %) the central and minimum film
# thickness follow the isoviscous-elastic regressions of Hamrock and Dowson,
# with the mean surface speed $u_m = U/2$ (`dolfinx_seal.verification.ehl`).


# %%
def hamrock_dowson_rows(p: Any, rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """h_central and h_min of the full-film points (fluid load > 99 %) against the
    Hamrock-Dowson regressions (u_m = U / 2)."""
    hd = IsoviscousElasticFilm(p.radius, p.material.E_star, p.film.viscosity, p.load)
    return [
        hd.compare(float(r["speed"]), float(r["h_central"]), float(r["h_min"]))
        for r in rows
        if float(r["fluid_load_fraction"]) >= 0.99
    ]


# %% [markdown]
# ## The sweep
# `sweep_scene` walks the speeds with continuation (secant predictor, step
# halved on failure); the progress of each point is shown on rank 0.


# %%
def run(
    out: Path,
    speeds: list[float] | None = None,
    elements_per_radius: float = ELEMENTS_PER_RADIUS,
    **values: Any,
) -> list[dict[str, Any]]:
    """Run the sweep; returns the converged rows (also in ``out/sweep.csv``)."""
    p = parameters(elements_per_radius, **values)
    speeds = list(speeds or SPEEDS)
    with Progress(len(speeds), "film.speed", "m/s") as progress:
        rows = sweep_scene("ball", p, out, "film.speed", speeds, progress=progress)
    writer = SweepWriter(out, "hamrock_dowson.csv")
    for r in hamrock_dowson_rows(p, rows):
        writer.append(r)
    return rows


# %% [markdown]
# ## From the command line
# The table: speed, mu, fluid load fraction, central and minimum film thickness.


# %%
def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=DESCRIPTION)
    parser.add_argument("--out", default="results/demo")
    parser.add_argument("--speeds", type=float, nargs="+", default=SPEEDS, help="[m/s]")
    parser.add_argument("--elements-per-radius", type=float, default=ELEMENTS_PER_RADIUS)
    parser.add_argument("--h-rms", type=float, default=1e-6, help="roughness [m]")
    args = parser.parse_args(argv)
    out = bcast_path(args.out)
    t0 = time.perf_counter()
    rows = run(out, args.speeds, args.elements_per_radius, roughness={"h_rms": args.h_rms})
    print0(f"\n{len(rows)} of {len(args.speeds)} speeds converged in "
           f"{time.perf_counter() - t0:.0f} s on {COMM_WORLD.size} rank(s)")  # fmt: skip
    print0(f"{'U [m/s]':>9} {'mu':>8} {'fluid':>6} {'h_c [um]':>9} {'h_min [um]':>10}")
    for r in rows:
        print0(f"{float(r['speed']):9.3g} {float(r['mu']):8.4f} "
               f"{float(r['fluid_load_fraction']):6.3f} {float(r['h_central']) * 1e6:9.3f} "
               f"{float(r['h_min']) * 1e6:10.3f}")  # fmt: skip
    print0(f"\nwritten: {out / 'sweep.csv'}, {out / 'sweep.png'}, {out}/speed_*/film_map.png")
    return 0 if rows else 1


if __name__ == "__main__":
    sys.exit(main())
