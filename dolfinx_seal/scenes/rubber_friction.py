"""Scene ``rubber-friction``: Persson's viscoelastic rubber friction (S3), no FEM.

Rubber slides at ``velocity`` on a hard self-affine surface (S3 eq 35 with the
S3 normalisation ``q0 h0``, cut off at ``q1 = zeta_max q0``) or a measured PSD
table; the friction coefficient is S3 eq 30 with the contact function ``P(q)``
of eq 31 (or the interpolation eq 34) and a modulus model: the S3 eq 38
standard linear solid, a Prony series or a tabulated master curve with a
WLF/Arrhenius shift.  Isothermal: no flash temperature.

``run`` computes ``mu`` at ``velocity`` and the whole curve ``mu(v)`` on
``[v_min, v_max]`` (its peak ``mu_peak`` at ``v_peak``), writes
``results.json``, ``mu_curve.csv``, ``contact_function.csv`` and
``rubber_friction.png``.  A sweep over ``velocity`` is vectorised.

Example (defaults = S3 figure 11, ``zeta_max = 100``)::

    dolfinx-seal run rubber-friction --set velocity=1 --set zeta_max=1000
    dolfinx-seal sweep rubber-friction --over velocity --values 1e-8:1e4:200:log
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.friction.modulus import (
    MasterCurve,
    Modulus,
    PronySeries,
    StandardLinearSolid,
)
from dolfinx_seal.friction.rubber import RubberFriction
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.params import (
    check_choice,
    check_int_range,
    check_positive,
    check_range,
)
from dolfinx_seal.roughness.psd import PowerSpectrum, SelfAffinePSD, read_psd_table
from dolfinx_seal.scenes import PointCallback, Scene, set_parameter


@dataclass(frozen=True)
class ModulusParams:
    """Rubber modulus ``E(omega)`` (SI).

    Attributes:
        kind: ``"sls"`` (S3 eq 38), ``"prony"`` or ``"master"`` (tabulated, shifted).
        e1, a, tau: SLS glassy modulus [Pa], ``E(inf)/E(0) - 1``, relaxation time [s].
        e_inf, prony_moduli, prony_times: Prony series [Pa], [Pa], [s].
        file: Master-curve table ``omega [rad/s], E' [Pa], E'' [Pa]``.
        t_ref, temperature: Reference and evaluation temperature [K].
        shift: ``"wlf"`` or ``"arrhenius"``; ``c1``, ``c2`` [K] (WLF) and
            ``activation_energy`` [J/mol] (Arrhenius).
    """

    kind: str = "sls"
    e1: float = 1.0e9
    a: float = 1000.0
    tau: float = 1.0e-3
    e_inf: float = 1.0e6
    prony_moduli: tuple[float, ...] = (1.0e8, 1.0e8, 1.0e8)
    prony_times: tuple[float, ...] = (1.0e-6, 1.0e-4, 1.0e-2)
    file: str = ""
    t_ref: float = 293.15
    temperature: float = 293.15
    shift: str = "wlf"
    c1: float = 17.44
    c2: float = 51.6
    activation_energy: float = 1.0e5

    def __post_init__(self) -> None:
        check_choice("modulus.kind", self.kind, ("sls", "prony", "master"))
        check_positive("modulus.e1", self.e1, "Pa")
        check_positive("modulus.a", self.a)
        check_positive("modulus.tau", self.tau, "s")
        check_positive("modulus.e_inf", self.e_inf, "Pa")
        check_positive("modulus.t_ref", self.t_ref, "K")
        check_positive("modulus.temperature", self.temperature, "K")
        check_choice("modulus.shift", self.shift, ("wlf", "arrhenius"))
        if self.kind == "master" and not self.file:
            raise ParameterError(
                "modulus.kind = 'master' needs modulus.file (omega, E', E'' table)"
            )

    def build(self) -> Modulus:
        """The modulus object."""
        if self.kind == "sls":
            return StandardLinearSolid(self.e1, self.a, self.tau)
        if self.kind == "prony":
            return PronySeries(self.e_inf, self.prony_moduli, self.prony_times)
        return MasterCurve.from_file(
            self.file, t_ref=self.t_ref, temperature=self.temperature, shift=self.shift,
            c1=self.c1, c2=self.c2, activation_energy=self.activation_energy,
        )  # fmt: skip


@dataclass(frozen=True)
class RubberFrictionParams:
    """Parameters of the ``rubber-friction`` scene (defaults: S3 figure 11, SI units).

    Attributes:
        velocity: Sliding speed [m/s].
        hurst: Hurst exponent ``H`` of the substrate (S3: 0.85).
        q0: Lower cut-off wavevector [1/m] (S3: 2000).
        q0h0: S3's ``q0 h0`` with ``<h^2> = h0^2/2`` (S3: 1).
        zeta_max: ``q1 / q0`` (S3 figure 11: 10, 100, 1000).
        psd_file: Optional measured ``(q, C)`` table replacing the self-affine model.
        sigma0: Nominal pressure [Pa] (mu is independent of it while ``sigma0 << E(0)``).
        nu: Poisson ratio of the rubber.
        contact: ``"exact"`` (S3 eq 31) or ``"interpolated"`` (eq 34).
        modulus: Rubber modulus (nested table ``[parameters.modulus]``).
        v_min, v_max, n_curve: Speed range [m/s] and points of the ``mu(v)`` curve.
        points_per_decade: ``q`` resolution of the integrals.
    """

    velocity: float = 1.0
    hurst: float = 0.85
    q0: float = 2000.0
    q0h0: float = 1.0
    zeta_max: float = 100.0
    psd_file: str = ""
    sigma0: float = 1.0e5
    nu: float = 0.5
    contact: str = "exact"
    modulus: ModulusParams = field(default_factory=ModulusParams)
    v_min: float = 1.0e-8
    v_max: float = 1.0e4
    n_curve: int = 121
    points_per_decade: int = 40

    def __post_init__(self) -> None:
        check_positive("velocity", self.velocity, "m/s")
        check_range("hurst", self.hurst, 0.0, 1.0, lo_open=True, hi_open=True)
        check_positive("q0", self.q0, "1/m")
        check_positive("q0h0", self.q0h0)
        check_range("zeta_max", self.zeta_max, 1.0, math.inf, lo_open=True)
        check_positive("sigma0", self.sigma0, "Pa")
        check_range("nu", self.nu, 0.0, 0.5)
        check_choice("contact", self.contact, ("exact", "interpolated"))
        check_positive("v_min", self.v_min, "m/s")
        check_range("v_max", self.v_max, self.v_min, math.inf, lo_open=True, unit="m/s (> v_min)")
        check_int_range("n_curve", self.n_curve, 5)
        check_int_range("points_per_decade", self.points_per_decade, 4)

    def spectrum(self) -> PowerSpectrum:
        """The substrate spectrum."""
        if self.psd_file:
            return read_psd_table(self.psd_file)
        return SelfAffinePSD.from_q0h0(self.q0, self.q0 * self.zeta_max, self.hurst, self.q0h0)

    def model(self) -> RubberFriction:
        """The :class:`RubberFriction` model of these parameters."""
        return RubberFriction(
            self.spectrum(), self.modulus.build(), self.sigma0, self.nu, self.contact,
            self.points_per_decade,
        )  # fmt: skip


def _point(model: RubberFriction, v: float, mu: float) -> dict[str, Any]:
    zeta, p = model.contact_function(v)
    return {
        "mu": mu,
        "velocity": v,
        "contact_area_fraction": float(p[-1]),
        "zeta_max_effective": float(zeta[-1]),
        "converged": True,
    }


def run(params: RubberFrictionParams, out_dir: Path) -> dict[str, Any]:
    """``mu`` at ``params.velocity``, the curve ``mu(v)`` and its peak; files into ``out_dir``."""
    model = params.model()
    mu = float(model.mu(np.array([params.velocity]))[0])
    res = _point(model, params.velocity, mu)
    v = np.geomspace(params.v_min, params.v_max, params.n_curve)
    curve = model.mu(v)
    v_peak, mu_peak = model.peak(params.v_min, params.v_max, params.n_curve)
    res.update(mu_peak=mu_peak, v_peak=v_peak)
    zeta, p = model.contact_function(params.velocity)
    if COMM_WORLD.rank == 0:
        out_dir.mkdir(parents=True, exist_ok=True)
        np.savetxt(out_dir / "mu_curve.csv", np.column_stack((v, curve)), delimiter=",",
                   header="velocity_m_s,mu", comments="")  # fmt: skip
        np.savetxt(out_dir / "contact_function.csv", np.column_stack((zeta, p)), delimiter=",",
                   header="zeta,P", comments="")  # fmt: skip
        _plot_run(out_dir / "rubber_friction.png", v, curve, params.velocity, mu, zeta, p)
    return res


def sweep(
    params: RubberFrictionParams,
    out_dir: Path,
    name: str,
    values: list[float],
    on_point: PointCallback,
) -> list[dict[str, Any]]:
    """Sweep; over ``velocity`` all points are computed at once (vectorised)."""
    rows: list[dict[str, Any]] = []
    if name == "velocity":
        for v in values:
            check_positive("velocity", v, "m/s")
        model = params.model()
        mus = model.mu(np.asarray(values, dtype=float))
        for v, m in zip(values, mus, strict=True):
            r = _point(model, float(v), float(m))
            on_point(v, r)
            rows.append(r)
        return rows
    for v in values:
        p = set_parameter(params, name, v)
        model = p.model()
        r = _point(model, p.velocity, float(model.mu(np.array([p.velocity]))[0]))
        vp, mp = model.peak(p.v_min, p.v_max, p.n_curve)
        r.update(mu_peak=mp, v_peak=vp)
        on_point(v, r)
        rows.append(r)
    return rows


def _plot_run(path: Path, v: Any, mu: Any, v0: float, mu0: float, zeta: Any, p: Any) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    ax1.semilogx(v, mu, "-")
    ax1.plot([v0], [mu0], "o")
    ax1.set_xlabel("sliding speed v [m/s]")
    ax1.set_ylabel("friction coefficient mu")
    ax1.set_title("Persson viscoelastic friction (S3 eq 30)")
    ax2.loglog(zeta, p)
    ax2.set_xlabel("magnification zeta = q/q0")
    ax2.set_ylabel("P(zeta) = A(zeta)/A0")
    ax2.set_title(f"contact function at v = {v0:.3g} m/s")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_sweep(rows: list[dict[str, Any]], out_dir: Path, name: str) -> None:
    """``mu`` (and the contact fraction) against the swept parameter."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x = [float(r[name]) for r in rows]
    fig, ax = plt.subplots(figsize=(6, 4))
    logx = name == "velocity" or (min(x) > 0 and max(x) / min(x) > 100)
    (ax.semilogx if logx else ax.plot)(x, [float(r["mu"]) for r in rows], "o-", ms=3)
    ax.set_xlabel(name)
    ax.set_ylabel("friction coefficient mu")
    ax.set_title("rubber-friction sweep")
    fig.tight_layout()
    fig.savefig(Path(out_dir) / "sweep.png", dpi=110)
    plt.close(fig)


SCENE = Scene(
    name="rubber-friction",
    summary="Persson viscoelastic rubber friction mu(v), P(q) on a rough surface (S3; no FEM)",
    parameters=RubberFrictionParams,
    run=run,
    sweep=sweep,
    plot_sweep=plot_sweep,
)
