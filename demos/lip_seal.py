# %% [markdown]
# # The main demo: a radial lip seal on its shaft, with oil under it
#
# An 80 x 100 x 10 mm radial shaft seal (ISO 6194-1 / DIN 3760 type A size) of
# NBR (Mooney-Rivlin, E = 8 MPa, incompressible) is pushed onto an 80 mm shaft
# (0.3 mm radial interference) with its garter spring (170 N/m), then lubricated:
# a 1D Reynolds film along the deformed contact band joins the Newton system of
# the rubber,
#
# $$ \frac{d}{ds}\Big( 2\pi r\, \phi_p(u) \frac{u^3}{12\eta} \frac{dp}{ds} \Big) = 0,
#    \qquad p = p_\mathrm{oil} \text{ (oil end)}, \quad p = p_\mathrm{air} \text{ (air end)}, $$
#
# with the combined lip and shaft roughness homogenised (h_rms 0.5 um): the
# Persson asperity pressure $p_\mathrm{cont}(u)$ and real area $A/A_0$, and the
# Persson/Bruggeman pressure flow factor $\phi_p(u)$.  The fluid pressure acts
# on the lip.  A turning shaft slides along the hoop direction: it shears the
# film (Couette $\eta U/u$) and the asperities ($\sigma_1 A/A_0$) but carries no
# oil axially, so the friction torque is
#
# $$ T = R_s \int_\mathrm{band} \Big( \frac{\eta U}{u} + \sigma_1 \frac{A}{A_0} \Big) 2\pi r\, ds . $$
#
# The demo writes, into `--out`:
#
# * `section.png`, `fields.xdmf` -- the installed section coloured by the
#   largest principal strain (ParaView: displacement, strain, contact and
#   fluid pressure, separation);
# * `leakage.csv`, `leakage.png` -- the leakage line: leakage against the
#   sealed oil pressure, with the fluid pressure acting on the lip and without
#   (the frozen lip, exactly linear);
# * `torque.csv`, `torque.png` -- friction torque against shaft speed with its
#   Couette and asperity parts, and the power loss;
# * `film.csv`, `film.png` -- the film along the band at the default pressure.
#
# Run: `scripts/dx mpirun -n 2 python3 demos/lip_seal.py [--out results/demo]`

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
from dolfinx_seal.scenes import lip, make_parameters, set_parameter
from dolfinx_seal.scenes.lip_install import principal_strain, write_section

PRESSURES = [0.0, 0.025, 0.05, 0.1, 0.2]  # sealed oil pressure [MPa]
SPEEDS = [1e-3, 3e-3, 0.01, 0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0]  # shaft surface speed [m/s]

# %% [markdown]
# ## The seal's parameters
# The defaults of scene `lip` are the seal above; the demo coarsens the contact
# band to 10 um elements (the default is 5 um: see the mesh study in
# `docs/scenes/lip.md`) so that it runs in a few minutes on two cores.


# %%
def parameters(h_contact: float = 10e-6, **values: Any) -> Any:
    """The default seal of scene ``lip`` with contact elements of ``h_contact`` [m]."""
    return make_parameters("lip", values={"lip": {"h_contact": h_contact}, **values})


# %% [markdown]
# ## The leakage line
# One installation; then the sealed pressure is moved from point to point, each
# a Newton solve of lip and film together from the previous point.  The frozen
# line solves the film alone on the lip as installed (no fluid pressure on the
# rubber): there the film equation is linear and so is the leakage.


# %%
def leakage_line(lub: Any, p: Any, pressures: list[float], out: Path) -> list[dict[str, Any]]:
    """Leakage at each oil pressure [MPa], coupled and frozen; rows of ``leakage.csv``."""
    writer = SweepWriter(out, "leakage.csv")
    frozen = lub.problem.film.make_solver(lub.problem.solver.options, name="lip film")
    rows = []
    state = lub.problem.state()
    for i, mpa in enumerate(sorted(pressures)):
        t0 = time.perf_counter()
        pv = set_parameter(p, "oil_pressure", mpa * 1e6)
        info = lip.move_oil_pressure(lub, pv)
        r = lip.results(lub, pv)
        coupled_state = lub.problem.state()
        lub.problem.restore(state)  # the lip as installed, film alone
        lip.apply_pressures(lub, pv, 1.0)
        frozen.solve(where=f"frozen lip at {mpa:g} MPa")
        q_frozen = lip.results(lub, pv)["leakage_rate"]
        lub.problem.restore(coupled_state)
        row = {
            "oil_pressure": pv.oil_pressure,
            "leakage_rate": r["leakage_rate"],
            "leakage_ml_per_h": r["leakage_ml_per_h"],
            "leakage_rate_frozen_lip": q_frozen,
            "radial_load": r["radial_load"],
            "load_fluid": r["load_fluid"],
            "max_contact_pressure": r["max_contact_pressure"],
            "h_min": r["h_min"],
            "mass_balance_error": r["mass_balance_error"],
            "newton_iterations": info["newton_iterations"],
            "wall_time_s": time.perf_counter() - t0,
        }
        writer.append(row)
        rows.append(row)
        print0(f"  [{i + 1}/{len(pressures)}] oil {mpa:g} MPa: leakage {row['leakage_ml_per_h'] + 0.0:.3g}"
               f" ml/h (frozen lip {q_frozen * lip.ML_PER_H + 0.0:.3g}), {info['newton_iterations']}"
               f" Newton steps, {row['wall_time_s']:.1f} s")  # fmt: skip
    frozen.destroy()
    return rows


# %% [markdown]
# ## The torque curve
# The turning shaft does not change the axisymmetric solution (no axial
# transport), only the hoop shear: the torque at every speed comes from the one
# converged state.


# %%
def torque_curve(lub: Any, p: Any, speeds: list[float], out: Path) -> list[dict[str, Any]]:
    """Friction torque and its parts at each shaft speed; rows of ``torque.csv``."""
    writer = SweepWriter(out, "torque.csv")
    rows = []
    for v in speeds:
        r = lip.results(lub, set_parameter(p, "film.speed", v))
        row = {k: r[k] for k in ("speed", "friction_torque", "friction_torque_couette",
                                 "friction_torque_asperity", "power_loss", "mu")}  # fmt: skip
        writer.append(row)
        rows.append(row)
    return rows


def plot(out: Path, leak: list[dict[str, Any]], torque: list[dict[str, Any]]) -> None:
    """``leakage.png`` and ``torque.png`` (rank 0)."""
    if COMM_WORLD.rank != 0:
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    x = np.array([r["oil_pressure"] for r in leak]) / 1e6
    ax.plot(
        x, [r["leakage_rate"] * lip.ML_PER_H for r in leak], "ko-", label="lip and film coupled"
    )
    ax.plot(x, [r["leakage_rate_frozen_lip"] * lip.ML_PER_H for r in leak], "b^--",
            label="frozen lip (film only)")  # fmt: skip
    ax.set_xlabel("sealed oil pressure [MPa]")
    ax.set_ylabel("leakage [ml/h]")
    ax.legend(frameon=False)
    ax.set_title("static leakage of the default seal")
    fig.tight_layout()
    fig.savefig(out / "leakage.png", dpi=120)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    v = np.array([r["speed"] for r in torque])
    ax.loglog(v, [r["friction_torque"] for r in torque], "ko-", label="total")
    ax.loglog(v, [r["friction_torque_couette"] for r in torque], "b^--", label="Couette")
    ax.loglog(v, [r["friction_torque_asperity"] for r in torque], "rs--", label="asperities")
    ax.set_xlabel("shaft surface speed [m/s]")
    ax.set_ylabel("friction torque [N m]")
    ax.legend(frameon=False)
    fig.tight_layout()
    fig.savefig(out / "torque.png", dpi=120)
    plt.close(fig)


# %% [markdown]
# ## Putting it together


# %%
def run(out: Path, h_contact: float = 10e-6, pressures: list[float] = PRESSURES,
        speeds: list[float] = SPEEDS) -> dict[str, Any]:  # fmt: skip
    """Install, lubricate, write the section, the leakage line and the torque curve."""
    t0 = time.perf_counter()
    p = parameters(h_contact)
    print0(f"lip seal demo: installing the seal ({p.lip.h_contact * 1e6:g} um contact elements,"
           f" {COMM_WORLD.size} rank(s)) ...")  # fmt: skip
    lub = lip.build(p)
    inst = lub.install
    print0(f"  installed in {inst.solve_time_s:.0f} s ({len(inst.problem.steps)} load steps); "
           "lubricating ...")  # fmt: skip
    leak = leakage_line(lub, p, pressures, out)
    lip.move_oil_pressure(lub, p)  # back to the default pressure
    torque = torque_curve(lub, p, speeds, out)
    res = lip.results(lub, p)
    lip.write_film(out, lub, p)
    write_section(out, lub.problem, f"installed lip: {res['radial_load']:.0f} N/m, band "
                  f"{res['contact_width'] * 1e3:.3f} mm, oil {p.oil_pressure / 1e6:g} MPa")  # fmt: skip
    from dolfinx_seal.coupled.results import write_fields

    prob = lub.problem
    write_fields(out, prob, extra={"max_principal_strain": principal_strain(prob),
                                   "contact_pressure": prob.p_cont, "separation": prob.gap})  # fmt: skip
    plot(out, leak, torque)
    print0(f"  radial load {res['radial_load']:.1f} N/m, band {res['contact_width'] * 1e3:.3f} mm,"
           f" peak contact pressure {res['max_contact_pressure'] / 1e6:.2f} MPa")  # fmt: skip
    for r in torque:
        print0(f"  shaft {r['speed']:8.3g} m/s: torque {r['friction_torque']:.4g} N m "
               f"(Couette {r['friction_torque_couette']:.3g}, asperities "
               f"{r['friction_torque_asperity']:.3g}), power {r['power_loss']:.3g} W")  # fmt: skip
    print0(f"done in {time.perf_counter() - t0:.0f} s; wrote {out}/")
    return {"leakage": leak, "torque": torque, "results": res}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    ap.add_argument("--out", default="results/demo")
    ap.add_argument("--h-contact", type=float, default=10e-6, help="contact element size [m]")
    ap.add_argument("--pressures", type=float, nargs="+", default=PRESSURES, help="[MPa]")
    ap.add_argument("--speeds", type=float, nargs="+", default=SPEEDS, help="[m/s]")
    a = ap.parse_args(argv)
    out = bcast_path(Path(a.out))
    if COMM_WORLD.rank == 0:
        out.mkdir(parents=True, exist_ok=True)
    COMM_WORLD.barrier()
    run(out, a.h_contact, a.pressures, a.speeds)
    return 0


if __name__ == "__main__":
    sys.exit(main())
