"""Scene ``rubber-friction``: Persson's viscoelastic rubber friction (S3), no FEM.

Rubber slides at ``speed`` on a hard rough surface -- the self-affine
``roughness`` of the other scenes (a measured PSD or height map as there) --
and the friction coefficient is S3 eq 30 with the contact function ``P(q)`` of
eq 31 (or the interpolation eq 34: ``contact.model``) and a modulus model
``material.model``: the S3 eq 38 standard linear solid, a Prony series or a
tabulated master curve with a WLF/Arrhenius shift.  Isothermal: no flash
temperature.

S3 states the roughness as ``q0 h0`` (``C0 = (h0/q0)^2 H / (2 pi)``, with
``<h^2> = h0^2/2`` for ``q1 -> inf``) and the cut-off as ``zeta_max = q1/q0``;
here, as in every scene, ``roughness.h_rms`` is the rms height between ``q0``
and ``q1`` and ``roughness.q1`` the cut-off [1/m]: :func:`s3_h_rms` converts
(the defaults are S3 figure 11 at ``zeta_max = 100``, ``q0 h0 = 1``; the scene
file ``rubber-friction.toml`` is ``zeta_max = 1000``).  Changing ``q1`` at fixed
``h_rms`` changes ``C0``; S3's figure 11 keeps ``C0`` (give :func:`s3_h_rms` of
the new ``q1``).  The old names (``velocity``, ``hurst``, ``q0``, ``q0h0``,
``zeta_max``, ``psd_file``, ``sigma0``, ``nu``, ``contact``, ``modulus.*``,
``v_min``, ``v_max``) are refused with the new one
(:attr:`RubberFrictionParams.RENAMED`).

``run`` computes ``mu`` at ``speed`` and the whole curve ``mu(v)`` on
``[speed_min, speed_max]`` (its peak ``mu_peak`` at ``speed_peak``), writes
``results.json``, ``mu_curve.csv``, ``contact_function.csv`` and
``rubber_friction.png``.  A sweep over ``speed`` is vectorised.  Scene-specific
results: ``speed`` [m/s], ``mu_peak``, ``speed_peak`` [m/s] and
``zeta_max_effective`` (the magnification ``q/q0`` where ``P(q)`` ends).

Example (S3 figure 11 at ``zeta_max = 1000``, then a speed sweep at the defaults)::

    dolfinx-seal run rubber-friction --scene-file dolfinx_seal/scenes/rubber-friction.toml
    dolfinx-seal sweep rubber-friction --over speed --values 1e-8:1e4:200:log
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.friction.modulus import (
    MasterCurve,
    Modulus,
    PronySeries,
    StandardLinearSolid,
)
from dolfinx_seal.friction.rubber import RubberFriction
from dolfinx_seal.mpi import world
from dolfinx_seal.params import (
    check_choice,
    check_int_range,
    check_positive,
    check_range,
)
from dolfinx_seal.roughness.psd import RoughnessParams, SelfAffinePSD
from dolfinx_seal.scenes import PointCallback, Scene, set_parameter


def s3_h_rms(q0: float, q1: float, hurst: float, q0h0: float = 1.0) -> float:
    """``roughness.h_rms`` [m] of S3's self-affine surface of ``q0 h0`` cut off at ``q1``.

    S3 fixes ``C0 = (h0/q0)^2 H / (2 pi)`` with ``h0 = q0h0 / q0`` [m]; between
    ``q0`` and ``q1`` [1/m] its rms height is ``h0 ((1 - (q1/q0)^(-2H)) / 2)^(1/2)``.
    """
    return SelfAffinePSD.from_q0h0(q0, q1, hurst, q0h0).h_rms()


#: S3 figure 11: H = 0.85, q0 = 2000 1/m, q0 h0 = 1, zeta_max = q1/q0 = 100.
S3_ROUGHNESS = {"hurst": 0.85, "q0": 2000.0, "q1": 2.0e5, "h_rms": s3_h_rms(2000.0, 2.0e5, 0.85)}


@dataclass(frozen=True)
class ViscoelasticParams:
    """The rubber: modulus ``E(omega)`` and Poisson ratio (SI).

    The viscoelastic counterpart of the FEM scenes' ``material`` (same group name,
    ``model`` and ``nu``); not :class:`~dolfinx_seal.scenes.common.MaterialParams`,
    whose models are hyperelastic (and whose module imports UFL, which this
    pure-numpy scene must not).

    Attributes:
        model: ``"sls"`` (S3 eq 38), ``"prony"`` or ``"master"`` (tabulated, shifted).
        nu: Poisson ratio of the rubber, in [0, 0.5].
        e1, a, tau: SLS glassy modulus [Pa], ``E(inf)/E(0) - 1``, relaxation time [s].
        e_inf, prony_moduli, prony_times: Prony series [Pa], [Pa], [s].
        file: Master-curve table ``omega [rad/s], E' [Pa], E'' [Pa]``.
        t_ref, temperature: Reference and evaluation temperature [K].
        shift: ``"wlf"`` or ``"arrhenius"``: the shift of the master curve.
        c1, c2: WLF constants [-], [K].
        activation_energy: Arrhenius activation energy [J/mol].
    """

    model: str = "sls"
    nu: float = 0.5
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
        check_choice("material.model", self.model, ("sls", "prony", "master"))
        check_range("material.nu", self.nu, 0.0, 0.5)
        check_positive("material.e1", self.e1, "Pa")
        check_positive("material.a", self.a)
        check_positive("material.tau", self.tau, "s")
        check_positive("material.e_inf", self.e_inf, "Pa")
        check_positive("material.t_ref", self.t_ref, "K")
        check_positive("material.temperature", self.temperature, "K")
        check_choice("material.shift", self.shift, ("wlf", "arrhenius"))
        check_positive("material.c1", self.c1)
        check_positive("material.c2", self.c2, "K")
        check_positive("material.activation_energy", self.activation_energy, "J/mol")
        if not isinstance(self.file, str):
            raise ParameterError(
                f"material.file must be a string, got {self.file!r}", "material.file"
            )
        moduli, times = tuple(self.prony_moduli), tuple(self.prony_times)
        for i, v in enumerate(moduli):
            check_positive(f"material.prony_moduli[{i}]", v, "Pa")
        for i, v in enumerate(times):
            check_positive(f"material.prony_times[{i}]", v, "s")
        if len(moduli) != len(times) or not moduli:
            raise ParameterError(
                f"material.prony_moduli ({len(moduli)} values) and material.prony_times "
                f"({len(times)} values) must be non-empty and of the same length",
                "material.prony_moduli",
            )
        if self.model == "master" and not self.file:
            raise ParameterError(
                "material.model = 'master' needs material.file (omega, E', E'' table)"
            )

    def build(self) -> Modulus:
        """The modulus object."""
        if self.model == "sls":
            return StandardLinearSolid(self.e1, self.a, self.tau)
        if self.model == "prony":
            return PronySeries(self.e_inf, self.prony_moduli, self.prony_times)
        return MasterCurve.from_file(
            self.file, t_ref=self.t_ref, temperature=self.temperature, shift=self.shift,
            c1=self.c1, c2=self.c2, activation_energy=self.activation_energy,
        )  # fmt: skip


@dataclass(frozen=True)
class ContactFunctionParams:
    """The contact function ``P(q)`` (the ``contact`` group of the other scenes).

    Attributes:
        model: ``"exact"`` (S3 eq 31) or ``"interpolated"`` (eq 34).
    """

    model: str = "exact"

    def __post_init__(self) -> None:
        check_choice("contact.model", self.model, ("exact", "interpolated"))


@dataclass(frozen=True)
class RubberFrictionParams:
    """Parameters of the ``rubber-friction`` scene (defaults: S3 figure 11, SI units).

    Attributes:
        speed: Sliding speed [m/s].
        nominal_pressure: Nominal pressure [Pa] (mu is independent of it while it is
            far below ``E(0)``).
        material: The rubber (nested table ``[parameters.material]``).
        roughness: The hard substrate (nested table ``[parameters.roughness]``;
            default S3 figure 11: ``H = 0.85``, ``q0 = 2000`` 1/m, ``q1 = 100 q0``,
            ``h_rms`` of ``q0 h0 = 1``, :func:`s3_h_rms`).
        contact: The contact function (nested table ``[parameters.contact]``).
        speed_min, speed_max, n_curve: Speed range [m/s] and points of the ``mu(v)`` curve.
        points_per_decade: ``q`` resolution of the integrals.
    """

    #: Old names -> new names (and units), refused by :func:`dolfinx_seal.params.refuse_renamed`.
    RENAMED: ClassVar[dict[str, str | tuple[str, str]]] = {
        "velocity": ("speed", "m/s"),
        "sigma0": ("nominal_pressure", "Pa"),
        "hurst": ("roughness.hurst", "-"),
        "q0": ("roughness.q0", "1/m"),
        "zeta_max": ("roughness.q1", "1/m; q1 = zeta_max * q0"),
        "q0h0": (
            "roughness.h_rms",
            "m; the rms of S3's surface, h_rms = (q0h0/q0) ((1 - (q1/q0)^(-2 H))/2)^(1/2)",
        ),
        "psd_file": ("roughness.psd_file", "path"),
        "nu": ("material.nu", "-"),
        "modulus": "material",
        "modulus.kind": ("material.model", "sls, prony or master"),
        "contact": ("contact.model", "exact or interpolated"),
        "v_min": ("speed_min", "m/s"),
        "v_max": ("speed_max", "m/s"),
    }

    speed: float = 1.0
    nominal_pressure: float = 1.0e5
    material: ViscoelasticParams = field(default_factory=ViscoelasticParams)
    roughness: RoughnessParams = field(default_factory=lambda: RoughnessParams(**S3_ROUGHNESS))
    contact: ContactFunctionParams = field(default_factory=ContactFunctionParams)
    speed_min: float = 1.0e-8
    speed_max: float = 1.0e4
    n_curve: int = 121
    points_per_decade: int = 40

    def __post_init__(self) -> None:
        check_positive("speed", self.speed, "m/s")
        check_positive("nominal_pressure", self.nominal_pressure, "Pa")
        check_positive("speed_min", self.speed_min, "m/s")
        check_range(
            "speed_max", self.speed_max, self.speed_min, math.inf, lo_open=True,
            unit="m/s (> speed_min)",
        )  # fmt: skip
        check_int_range("n_curve", self.n_curve, 5)
        check_int_range("points_per_decade", self.points_per_decade, 4)

    def model(self) -> RubberFriction:
        """The :class:`RubberFriction` model of these parameters."""
        return RubberFriction(
            self.roughness.build(), self.material.build(), self.nominal_pressure,
            self.material.nu, self.contact.model, self.points_per_decade,
        )  # fmt: skip


def _point(model: RubberFriction, v: float, mu: float) -> dict[str, Any]:
    zeta, p = model.contact_function(v)
    return {
        "mu": mu,
        "speed": v,
        "contact_area_fraction": float(p[-1]),
        "zeta_max_effective": float(zeta[-1]),
        "converged": True,
    }


def run(params: RubberFrictionParams, out_dir: Path) -> dict[str, Any]:
    """``mu`` at ``params.speed``, the curve ``mu(v)`` and its peak; files into ``out_dir``."""
    model = params.model()
    mu = float(model.mu(np.array([params.speed]))[0])
    res = _point(model, params.speed, mu)
    v = np.geomspace(params.speed_min, params.speed_max, params.n_curve)
    curve = model.mu(v)
    v_peak, mu_peak = model.peak(params.speed_min, params.speed_max, params.n_curve)
    res.update(mu_peak=mu_peak, speed_peak=v_peak)
    zeta, p = model.contact_function(params.speed)
    if world().rank == 0:
        out_dir.mkdir(parents=True, exist_ok=True)
        np.savetxt(out_dir / "mu_curve.csv", np.column_stack((v, curve)), delimiter=",",
                   header="speed_m_s,mu", comments="")  # fmt: skip
        np.savetxt(out_dir / "contact_function.csv", np.column_stack((zeta, p)), delimiter=",",
                   header="zeta,P", comments="")  # fmt: skip
        _plot_run(out_dir / "rubber_friction.png", v, curve, params.speed, mu, zeta, p)
    return res


def sweep(
    params: RubberFrictionParams,
    out_dir: Path,
    name: str,
    values: list[float],
    on_point: PointCallback,
) -> list[dict[str, Any]]:
    """Sweep; over ``speed`` all points are computed at once (vectorised)."""
    rows: list[dict[str, Any]] = []
    if name == "speed":
        for v in values:
            check_positive("speed", v, "m/s")
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
        r = _point(model, p.speed, float(model.mu(np.array([p.speed]))[0]))
        vp, mp = model.peak(p.speed_min, p.speed_max, p.n_curve)
        r.update(mu_peak=mp, speed_peak=vp)
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
    logx = name == "speed" or (min(x) > 0 and max(x) / min(x) > 100)
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
