# %% [markdown]
# # S0's two-scale lip seal: a rough periodic sector at rest and on a turning shaft
#
# The seal of the main demo is installed in axisymmetry, then one roughness
# period of its tip is cut out and solved in 3D: the long wavelengths of the
# roughness (from $\lambda_0 = 2\pi/q_0$ down to $\lambda_{th} = 2\pi/q_{th}$)
# are a seeded random-phase surface resolved on the mesh, the shorter ones are
# homogenised (Persson's asperity pressure, real area and pressure flow
# factor), and a 2D Reynolds film on the deformed band carries the oil from the
# oil side to the air side (seed S0, sections 2-3),
#
# $$ \nabla_s\cdot\Big(-\phi_p \frac{u^3}{12\eta}\nabla_s p + \frac{U}{2}\, u\,\theta\Big) = 0,
#    \qquad p \ge 0,\quad 0 \le \theta \le 1,\quad p\,(1-\theta) = 0 , $$
#
# the mass-conserving (JFO) film on a turning shaft, where $\theta < 1$ marks
# the cavitated zones.  The demo writes, into `--out`:
#
# * `static/`: the sector at rest (scene `lip-static`): `maps.png` (separation,
#   asperity and fluid pressure, A/A0, flux lines, area change: S0 figs 4-10),
#   `band.csv`, `fields.xdmf`, and a summary row in `static.csv`;
# * `dynamic/`: the frozen lip on a turning shaft under the sealed pressure
#   (scene `lip-dynamic`), pressurised at the slowest speed and walked up:
#   `speed_*/maps.png` (the film fraction panel is S0 fig 11), `sweep.csv`;
# * `cavitation.png`: cavitated area and its place, torque and the net oil
#   flow against the shaft speed.
#
# Run: `make demo-sector`, or `scripts/dx mpirun -n 2 python3 demos/lip_sector.py [--out DIR]`
# (6.4 minutes on two ranks on the coarsest band, measured on a 2-core machine).

# %%
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from dolfinx_seal.mpi import COMM_WORLD, bcast_path, print0
from dolfinx_seal.output import SweepWriter
from dolfinx_seal.scenes import lip_sector, make_parameters

SPEEDS = [1e-4, 1e-3, 1e-2, 0.1, 1.0]  # shaft surface speed [m/s]

# %% [markdown]
# ## The seal's parameters
# The defaults of scenes `lip-static` and `lip-dynamic` are the main demo's
# seal on a ground shaft (h_rms 0.5 um, q_th = 2 q0) with 0.05 MPa of oil.  The
# demo uses the coarsest band the scenes accept, two elements per
# $\lambda_{th}$ (5.2 um); `--set KEY=VALUE` changes any parameter of both
# scenes (e.g. `--set sector.elements_per_wavelength=4` for the default band).


# %%
def parameters(scene: str, overrides: list[str], *fixed: str) -> Any:
    """The scene's defaults on the coarse band, then ``overrides`` (``KEY=VALUE``
    strings, as ``--set`` takes them), then the demo's ``fixed`` settings."""
    coarse = {"sector": {"elements_per_wavelength": 2.0}}
    return make_parameters(scene, values=coarse, overrides=[*overrides, *fixed])


# %% [markdown]
# ## At rest: leakage through the constrictions
# Without sliding the film needs no cavitation condition: the pressure falls
# from the oil to the air side, step-like at the narrowest constrictions
# between the resolved asperities (S0 fig 5b).  The leakage is the net axial
# flux times the number of sectors around the shaft.


# %%
KEYS = ("leakage_rate", "friction_torque", "radial_load", "contact_area_fraction",
        "fluid_load_fraction", "h_min", "max_fluid_pressure", "nodal_mass_balance_error")  # fmt: skip


def static(out: Path, overrides: list[str]) -> dict[str, Any]:
    """The sector at rest; its results (and ``static.csv``, the maps)."""
    p = parameters("lip-static", overrides)
    t0 = time.perf_counter()
    r = lip_sector.run(p, out / "static")
    row = {"dofs": r["dofs"], **{k: r[k] for k in KEYS}, "wall_time_s": time.perf_counter() - t0}
    SweepWriter(out, "static.csv").append(row)
    print0(f"  at rest: leakage {r['leakage_ml_per_h']:.3g} ml/h, contact area fraction "
           f"{r['contact_area_fraction']:.3f}, torque {r['friction_torque']:.4g} N m, "
           f"{r['dofs']} unknowns, {row['wall_time_s']:.0f} s")  # fmt: skip
    return row


# %% [markdown]
# ## Turning: cavitation against speed (S0 fig 11)
# The shaft drags the oil along the circumference over the resolved asperities;
# behind each constriction, where the gap opens along the sliding, the film
# cannot hold a pressure below the cavitation pressure and breaks up
# ($\theta < 1$).  The pressure drop is brought in at the slowest speed, where
# the film is unique, and the sweep walks up in log10 of the speed, each speed
# from the last (a step that fails is halved).  The lip is frozen in its dry state: at high speed read
# `fluid_load_fraction`, the share of the radial load the film carries, before
# trusting a point.


# %%
def dynamic(out: Path, overrides: list[str], speeds: list[float]) -> list[dict[str, Any]]:
    """The speed sweep of ``lip-dynamic``; rows in ascending speed."""
    p = parameters("lip-dynamic", overrides, f"film.speed={min(speeds)!r}")
    writer = SweepWriter(out / "dynamic", "sweep.csv")
    keys = ("speed", "cavitation_fraction", "cavitation_axial_offset",
            "cavitation_divergent_fraction", "counter_gradient_fraction", *KEYS,
            "newton_iterations")  # fmt: skip
    done: list[float] = []

    def on_point(v: float, r: dict[str, Any]) -> bool:
        writer.append({k: r.get(k, np.nan) for k in keys})
        done.append(v)
        print0(f"  [{len(done)}/{len(speeds)}] {v:.3g} m/s: cavitated {r.get('cavitation_fraction', 0):.3f} "
               f"of the band, torque {r['friction_torque']:.4g} N m, net flow "
               f"{r['leakage_rate']:.3g} m^3/s, {r['newton_iterations']} Newton steps")  # fmt: skip
        return True  # every speed's maps (speed_<U>/maps.png)

    return lip_sector.sweep(p, out / "dynamic", "film.speed", speeds, on_point)


def plot(out: Path, rows: list[dict[str, Any]]) -> None:
    """``cavitation.png`` (rank 0)."""
    if COMM_WORLD.rank != 0 or not rows:
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    v = np.array([r["speed"] for r in rows])
    fig, ax = plt.subplots(1, 3, figsize=(12.0, 3.6))
    ax[0].semilogx(v, [r["cavitation_fraction"] for r in rows], "ko-", label="cavitated area")
    ax[0].semilogx(v, [r.get("cavitation_divergent_fraction", np.nan) for r in rows], "b^--",
                   label="of it where the gap opens")  # fmt: skip
    ax[0].set_ylabel("fraction of the band [-]")
    ax[0].legend(frameon=False)
    ax[1].semilogx(v, [r["friction_torque"] for r in rows], "ko-")
    ax[1].set_ylabel("friction torque [N m]")
    ax[2].semilogx(v, [r["leakage_rate"] for r in rows], "ko-")
    ax[2].axhline(0.0, color="0.6", lw=0.8)
    ax[2].set_ylabel("net flow oil -> air [m^3/s]")
    for a in ax:
        a.set_xlabel("shaft surface speed [m/s]")
    fig.tight_layout()
    fig.savefig(out / "cavitation.png", dpi=120)
    plt.close(fig)


# %% [markdown]
# ## Putting it together


# %%
def run(out: Path, overrides: list[str], speeds: list[float] = SPEEDS) -> dict[str, Any]:
    """The sector at rest, then the speed sweep; the rows."""
    t0 = time.perf_counter()
    print0(f"lip sector demo ({COMM_WORLD.size} rank(s)): installing the seal, cutting the "
           "sector, bringing in the roughness, at rest ...")  # fmt: skip
    rest = static(out, overrides)
    print0(f"  turning: {len(speeds)} speeds, pressurised at {min(speeds):g} m/s, walked up ...")
    rows = dynamic(out, overrides, speeds)
    plot(out, rows)
    print0(f"done in {time.perf_counter() - t0:.0f} s; wrote {out}/")
    return {"static": rest, "dynamic": rows}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="S0's two-scale lip seal on a periodic sector")
    ap.add_argument("--out", default="results/lip-sector-demo")
    ap.add_argument("--speeds", type=float, nargs="+", default=SPEEDS, help="[m/s]")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    a = ap.parse_args(argv)
    out = bcast_path(Path(a.out))
    if COMM_WORLD.rank == 0:
        out.mkdir(parents=True, exist_ok=True)
    COMM_WORLD.barrier()
    run(out, a.set, a.speeds)
    return 0


if __name__ == "__main__":
    sys.exit(main())
