"""Scene ``flat``: flat-on-flat sliding in a fluid, viscous hydroplaning (S1 section 4).

A rubber block with a flat surface slides on a rigid rough flat in a
Newtonian fluid; the mean-field theory of S1 eqs 31-35 (with Persson's
``A(zeta)``, ``u(zeta)`` and ``u1(zeta)`` at the fluid-reduced asperity load,
see :mod:`dolfinx_seal.contact.hydroplaning`) gives the load split and the
friction ``mu = (sigma_cont + sigma_fluid) / p0``.  No finite elements.

Defaults are the S1 figure 32 system (E = 10 MPa, rms roughness 1 um, D_f =
2.2, eta = 0.1 Pa s, sigma_1 = 1 MPa, real contact where u < 1 nm).  S1 does
not state the nominal pressure, the cut-offs or the system size for figures
32-35; we take ``q0 = 1e4``, ``q1 = 7.8e9`` 1/m and ``nu = 0.5`` of its figure
4 (same rubber and substrate), ``p0 = 0.1618`` MPa (the mean Hertz pressure of
that figure) and ``L = 2 pi / q0``.

Parameter names are those of the FEM scenes (``film.speed``,
``film.viscosity``, ``film.asperity_shear``, ``material.E``, ``material.nu``,
``contact.gamma``, ``roughness.*``); the old names (``velocity``, ``eta``,
``sigma1``, ``youngs_modulus``, ``nu``, ``gamma``, ``pressure``, ``kappa``,
``u_contact``) are refused with the new one (:attr:`FlatParams.RENAMED`).

``run`` writes ``results.json``, ``profile.csv`` (``zeta, A/A0, p_cont,
p_fluid``) and ``flat.png``; a sweep over ``film.speed`` (or
``film.viscosity``) reuses one tabulation of the contact mechanics and draws S1
figures 32-33.  Scene-specific results: ``speed`` and ``eta_v`` (as in the
lubricated FEM scenes), ``sigma_contact`` and ``sigma_fluid`` (the two shear
stresses of S1 eq 35 [Pa]), ``p_contact`` and ``p_fluid`` (the load split at
``zeta1`` [Pa]), ``alpha``, ``beta`` (the asymptote of the Persson law),
``zeta1`` and ``hydroplaning``.

Example::

    dolfinx-seal run flat --set film.speed=3e-5
    dolfinx-seal sweep flat --over film.speed --values 1e-7:1e-1:61:log
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from dolfinx_seal.contact.hydroplaning import FlatOnFlat, HydroplaningResult
from dolfinx_seal.mpi import world
from dolfinx_seal.params import (
    check_int_range,
    check_nonnegative,
    check_positive,
    check_range,
)
from dolfinx_seal.roughness.psd import RoughnessParams
from dolfinx_seal.scenes import PointCallback, Scene, set_parameter

# Why the groups below are not the FEM scenes' dataclasses (scenes.common.MaterialParams,
# ContactLawParams, film.surface.FilmParams): those modules import UFL/DOLFINx, which
# this pure-numpy scene must not, and most of their fields (material model and
# formulation, contact-law model, cavitation, flow factor, lubricated zone, boundary
# pressures) have no meaning in the mean-field theory.  The fields kept have the same
# names, units and meaning.


@dataclass(frozen=True)
class ElasticParams:
    """The rubber block, linear elastic (the ``E``, ``nu`` of the FEM scenes' ``material``).

    Not :class:`~dolfinx_seal.scenes.common.MaterialParams`: its module imports UFL
    (this scene imports no DOLFINx) and its hyperelastic ``model``, ``formulation``
    and ``c01_ratio`` mean nothing to the mean-field theory, which needs ``E*`` only.

    Attributes:
        E: Young's modulus [Pa].
        nu: Poisson ratio, in (-1, 0.5] (``E* = E / (1 - nu^2)``).
    """

    E: float = 10.0e6
    nu: float = 0.5

    def __post_init__(self) -> None:
        check_positive("material.E", self.E, "Pa")
        check_range("material.nu", self.nu, -1.0, 0.5, lo_open=True)

    @property
    def E_star(self) -> float:
        """``E / (1 - nu^2)`` [Pa]."""
        return self.E / (1.0 - self.nu**2)


@dataclass(frozen=True)
class MeanFieldFilmParams:
    """The fluid of the mean-field theory (names as in the FEM scenes' ``film``).

    Not :class:`~dolfinx_seal.film.surface.FilmParams`, whose module imports
    DOLFINx and whose cavitation, flow factor, zone and boundary fields describe a
    Reynolds film this theory does not solve; ``kappa`` is this theory's own.

    Attributes:
        speed: Sliding speed v of the substrate under the rubber [m/s], >= 0 (the
            theory depends on ``viscosity * speed`` only).
        viscosity: Dynamic viscosity eta [Pa s].
        asperity_shear: Frictional shear stress sigma_1 of the real contact
            area [Pa] (S1 eq 35: sigma_1 A(zeta_1)/A0).
        kappa: Tilted-junction factor of the hydrodynamic pressure (S1 eq 32) [-].
    """

    speed: float = 1.0e-5
    viscosity: float = 0.1
    asperity_shear: float = 1.0e6
    kappa: float = 0.2

    def __post_init__(self) -> None:
        check_nonnegative("film.speed", self.speed, "m/s")
        check_positive("film.viscosity", self.viscosity, "Pa s")
        check_nonnegative("film.asperity_shear", self.asperity_shear, "Pa")
        check_positive("film.kappa", self.kappa)


@dataclass(frozen=True)
class MeanFieldContactParams:
    """Persson's contact mechanics of the mean-field theory (names as in ``contact``).

    Not :class:`~dolfinx_seal.scenes.common.ContactLawParams` (a UFL-importing
    module, and a choice of law ``p_cont(u)`` where this theory uses Persson's
    full ``A(zeta)``, ``u1(zeta)``); ``u_contact`` is this theory's own.

    Attributes:
        gamma: Yang-Persson factor (S1: 0.4).
        u_contact: Separation below which the surfaces count as in contact [m]
            (S1: 1 nm).
    """

    gamma: float = 0.4
    u_contact: float = 1.0e-9

    def __post_init__(self) -> None:
        check_range("contact.gamma", self.gamma, 0.0, 1.0, lo_open=True)
        check_positive("contact.u_contact", self.u_contact, "m")


@dataclass(frozen=True)
class FlatParams:
    """Parameters of the ``flat`` scene (SI units; defaults: S1 figure 32).

    Attributes:
        nominal_pressure: Nominal pressure ``p0`` [Pa].
        material: The rubber (nested table ``[parameters.material]``).
        roughness: Substrate roughness (nested table ``[parameters.roughness]``).
        contact: Contact mechanics (nested table ``[parameters.contact]``).
        film: Speed, fluid and shear stresses (nested table ``[parameters.film]``).
        system_size: ``L`` of ``lambda = L/zeta`` [m]; 0 means ``2 pi / q_L``.
        points_per_decade: Magnification resolution.
        n_pressures: Size of the contact-mechanics table.
    """

    #: Old names -> new names (and units), refused by :func:`dolfinx_seal.params.refuse_renamed`.
    RENAMED: ClassVar[dict[str, tuple[str, str]]] = {
        "velocity": ("film.speed", "m/s"),
        "eta": ("film.viscosity", "Pa s"),
        "sigma1": ("film.asperity_shear", "Pa"),
        "kappa": ("film.kappa", "-"),
        "pressure": ("nominal_pressure", "Pa"),
        "youngs_modulus": ("material.E", "Pa"),
        "nu": ("material.nu", "-"),
        "gamma": ("contact.gamma", "-"),
        "u_contact": ("contact.u_contact", "m"),
    }

    nominal_pressure: float = 0.1618e6
    material: ElasticParams = field(default_factory=ElasticParams)
    roughness: RoughnessParams = field(default_factory=RoughnessParams)
    contact: MeanFieldContactParams = field(default_factory=MeanFieldContactParams)
    film: MeanFieldFilmParams = field(default_factory=MeanFieldFilmParams)
    system_size: float = 0.0
    points_per_decade: int = 30
    n_pressures: int = 48

    def __post_init__(self) -> None:
        check_positive("nominal_pressure", self.nominal_pressure, "Pa")
        check_nonnegative("system_size", self.system_size, "m")
        check_int_range("points_per_decade", self.points_per_decade, 5)
        check_int_range("n_pressures", self.n_pressures, 8)

    @property
    def eta_v(self) -> float:
        """``film.viscosity * film.speed`` [Pa m], the one speed group of the theory."""
        return self.film.viscosity * self.film.speed

    def model(self) -> FlatOnFlat:
        """The tabulated :class:`FlatOnFlat` model (independent of ``film.speed`` and
        ``film.viscosity``)."""
        c = self.contact
        return FlatOnFlat(
            self.roughness.build(), self.material.E_star, self.nominal_pressure,
            self.film.asperity_shear, self.film.kappa, c.gamma, c.u_contact,
            self.system_size or None, self.points_per_decade, self.n_pressures,
        )  # fmt: skip


#: Sweeps over these share one tabulated model (the theory depends on them only through eta v).
SPEED_GROUP = ("film.speed", "film.viscosity")


def _results(res: HydroplaningResult, params: FlatParams, model: FlatOnFlat) -> dict[str, Any]:
    alpha, beta = model.theory.asymptote()
    out: dict[str, Any] = {
        "mu": res.mu,
        "speed": params.film.speed,
        "eta_v": res.eta_v,
        "sigma_contact": res.sigma_contact,
        "sigma_fluid": res.sigma_fluid,
        "p_contact": res.p_contact1,
        "p_fluid": res.p_fluid1,
        "fluid_load_fraction": res.p_fluid1 / params.nominal_pressure,
        "contact_area_fraction": res.area1,
        "hydroplaning": res.hydroplaning,
        "alpha": alpha,
        "beta": beta,
        "zeta1": res.zeta1,
        "converged": True,
    }
    return out


def run(params: FlatParams, out_dir: Path) -> dict[str, Any]:
    """Solve one point; write ``profile.csv`` and ``flat.png``."""
    model = params.model()
    res = model.solve(params.eta_v)
    if world().rank == 0:
        out_dir.mkdir(parents=True, exist_ok=True)
        np.savetxt(
            out_dir / "profile.csv",
            np.column_stack((res.zeta, res.area, res.p_contact, res.p_fluid)),
            delimiter=",", header="zeta,area_fraction,p_contact_Pa,p_fluid_Pa", comments="",
        )  # fmt: skip
        _plot_profile(out_dir / "flat.png", res)
    return _results(res, params, model)


def sweep(
    params: FlatParams,
    out_dir: Path,
    name: str,
    values: list[float],
    on_point: PointCallback,
) -> list[dict[str, Any]]:
    """Sweep; over ``film.speed`` or ``film.viscosity`` one tabulated model serves every point."""
    rows: list[dict[str, Any]] = []
    model = params.model() if name in SPEED_GROUP else None
    for v in values:
        p = set_parameter(params, name, v)
        m = model if model is not None else p.model()
        r = _results(m.solve(p.eta_v), p, m)
        on_point(v, r)
        rows.append(r)
    return rows


def _plot_profile(path: Path, res: HydroplaningResult) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    lz = np.log10(res.zeta)
    ax1.plot(lz, res.p_contact / 1e6, label="p_cont")
    ax1.plot(lz, res.p_fluid / 1e6, label="p_fluid")
    ax1.set_xlabel("log10 magnification zeta")
    ax1.set_ylabel("nominal pressure [MPa]")
    ax1.legend()
    ax1.set_title(f"eta v = {res.eta_v:.3g} Pa m (S1 fig 34)")
    ax2.plot(lz, np.log10(np.maximum(res.area, 1e-12)))
    ax2.set_xlabel("log10 magnification zeta")
    ax2.set_ylabel("log10 A(zeta)/A0")
    ax2.set_title("contact area (S1 fig 35)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_sweep(rows: list[dict[str, Any]], out_dir: Path, name: str) -> None:
    """``mu`` and the shear stresses against ``log10(eta v)`` (S1 figures 32-33)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ev = np.array([float(r["eta_v"]) for r in rows])
    x = (
        np.log10(np.maximum(ev, 1e-300))
        if np.all(ev > 0)
        else np.array([float(r[name]) for r in rows])
    )
    xl = "log10(eta v) [Pa m]" if np.all(ev > 0) else name
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    ax1.plot(x, [float(r["mu"]) for r in rows], "o-", ms=3)
    ax1.set_xlabel(xl)
    ax1.set_ylabel("friction coefficient mu")
    ax1.set_title("flat on flat (S1 fig 32)")
    ax2.plot(x, [float(r["sigma_contact"]) / 1e6 for r in rows], "o-", ms=3, label="sigma_cont")
    ax2.plot(x, [float(r["sigma_fluid"]) / 1e6 for r in rows], "s-", ms=3, label="sigma_fluid")
    ax2.set_xlabel(xl)
    ax2.set_ylabel("shear stress [MPa]")
    ax2.set_yscale("symlog", linthresh=1e-4)
    ax2.legend()
    ax2.set_title("S1 fig 33")
    fig.tight_layout()
    fig.savefig(Path(out_dir) / "sweep.png", dpi=110)
    plt.close(fig)


SCENE = Scene(
    name="flat",
    summary="flat-on-flat soft contact in a fluid: mu(eta v), viscous hydroplaning (S1 sec 4; no FEM)",
    parameters=FlatParams,
    run=run,
    sweep=sweep,
    plot_sweep=plot_sweep,
)
