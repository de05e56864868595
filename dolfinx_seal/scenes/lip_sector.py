r"""Scenes ``lip-static`` and ``lip-dynamic``: S0's two-scale lip seal on a periodic 3D
sector, at zero speed, and on a shaft sliding along the circumference (JFO film,
coupled to the lip or on the frozen lip: :class:`LipDynamicParameters`,
:func:`solve_sliding`).

The radial lip seal of :mod:`~dolfinx_seal.scenes.lip_install` (the same
parameters and defaults) is first installed on its shaft in axisymmetry (the
same solve, :func:`~dolfinx_seal.scenes.lip_install.install`).  Then a sector
of its tip, one (or more) periods ``lambda_0`` of the roughness along the
circumference (:mod:`geometry.lip_sector`: the tip below the radial cut
``r = r_tip + sector.height`` revolved through ``lambda_0 / R_shaft``), solves
its own finite-strain equilibrium against the shaft (:class:`~dolfinx_seal.solid.counter_surface.Shaft3D`):

* the installed axisymmetric displacement, revolved, is imposed on the cut and
  is the first iterate (:class:`~dolfinx_seal.solid.revolve.RevolvedState`);
* the displacement (and the mixed pressure) are periodic with the rotation of
  the vector field between the two cut faces, the film pressure (and film
  fraction) periodic along the circumference (dolfinx_mpc constraints through
  the solver's assembly seam, :class:`~dolfinx_seal.solvers.periodic.RotationalPeriodicity`);
* **two-scale roughness** (S0 eqs 15-21): the spectrum is split at
  ``roughness.q_th``.  The wavelengths from ``lambda_0 = 2 pi / q_min`` down to
  ``lambda_th = 2 pi / q_th`` are a seeded periodic random-phase surface
  ``h_r(x_1, x_2)`` (:class:`~dolfinx_seal.roughness.surface.TwoScaleSplit`,
  ``x_1 = R_shaft phi`` along the circumference, ``x_2 = z``) on the lip
  surface, in the gap as S0 eq 1 has it: ``u = (r - R_shaft) + h_r(X)``
  (:class:`~dolfinx_seal.solid.counter_surface.WithSurfaceHeight`), ramped in
  from 0 by adaptive steps; the rest, ``C_sto(q) = C(q)`` for ``q > q_th``,
  enters through the Persson laws (``p_cont(u)``, ``A/A0``) and the
  Persson/Bruggeman pressure flow factor.  ``q_th = q_min``: nothing
  deterministic, the axisymmetric ``lip`` scene's physics on a 3D mesh;
* **film** (S0 eqs 8-9, 12-13, A.1-A.3): 2D Reynolds on the deformed contact
  band (:class:`~dolfinx_seal.film.surface.SurfaceFilm`, the current surface
  and its tangential gradient by Nanson's formula), ``oil_pressure`` on the
  oil-side end of the band and ``air_pressure`` on the air-side end, periodic
  circumferentially, in one Newton with the bulk.  At zero speed the film has
  no transport and the pressure lies between the sealed pressures (maximum
  principle), so no cavitation condition is assembled.

Outputs (SI, totals over the whole circumference: a sector value times
``2 pi / angle``): ``leakage_rate`` (flow out of the air-side end, positive from
oil to air), ``radial_load`` (per unit circumference), the load split,
``friction_torque`` (the asperity shear ``sigma_1 A/A0`` and the Poiseuille
shear on the shaft, times ``R_shaft``: the breakaway torque of the static
seal), contact area fraction, min/mean separation, max pressures, mass balance;
maps on the unrolled band (``maps.png``, ``band.csv``; :mod:`~dolfinx_seal.scenes.lip_sector_maps`)
and ``fields.xdmf``.

S0's roughness (q0 = 2 pi / 200 um, D_f 2.4, h_rms 10 um, q1 = 1000 q0) has an
rms slope of about 6, far from the small slopes that Reynolds roughness (and
the gap-offset roughness here) assumes: its scene file says so.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import dolfinx
import numpy as np
import ufl
from mpi4py import MPI

from dolfinx_seal.coupled.continuation import path_tangent, tangent_predictor
from dolfinx_seal.coupled.partitioned import PartitionedOptions, PartitionedSolver
from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.film.pseudo_time import pseudo_transient_solve
from dolfinx_seal.film.surface import FilmParams, FilmScales, SurfaceFilm
from dolfinx_seal.film.upwinding import attach_discrete_upwinding, release_discrete_upwinding
from dolfinx_seal.meshing import TaggedMesh, create_mesh
from dolfinx_seal.mpi import get_logger, world
from dolfinx_seal.params import (
    check_bool,
    check_choice,
    check_int_range,
    check_nonnegative,
    check_positive,
    check_range,
    set_parameter,
)
from dolfinx_seal.roughness.psd import PowerSpectrum, RoughnessParams
from dolfinx_seal.roughness.surface import FourierSurface, TwoScaleSplit
from dolfinx_seal.scenes import Scene
from dolfinx_seal.scenes.lip_install import (
    SEAL_GEOMETRY,
    SEAL_ROUGHNESS,
    LipInstallParameters,
    install,
    moment_width,
)
from dolfinx_seal.solid.body import Body, Dirichlet, ForceControl, PositionControl
from dolfinx_seal.solid.counter_surface import Shaft3D, WithSurfaceHeight
from dolfinx_seal.solid.kinematics import Solid3D
from dolfinx_seal.solid.problem import SolidContactProblem, SteppingOptions
from dolfinx_seal.solid.revolve import RevolvedState, serial_copy
from dolfinx_seal.solid.step_limits import StepLimits, SurfaceGapLimiter
from dolfinx_seal.solvers import RotationalPeriodicity, SNESOptions
from dolfinx_seal.solvers.adaptive import AdaptiveWalk, StepControl, TimeBudget
from dolfinx_seal.surface.asperity import LawHomotopy, area_fraction
from geometry.lip import LipGeometry, LipSealParams
from geometry.lip_sector import LipSectorParams

ML_PER_H = 1e6 * 3600.0  # m^3/s -> ml/h
#: default split: wavelengths down to half the longest are resolved (q_th = 2 q0)
SECTOR_Q_TH = 2.0 * SEAL_ROUGHNESS["q0"]


# ---------------------------------------------------------------- parameters
@dataclass(frozen=True)
class SectorRoughnessParams(RoughnessParams):
    """Roughness of the lip and shaft with the two-scale split (S0 eqs 15-21; SI units).

    Attributes:
        q_th: Threshold wavevector q_th [1/m]: wavelengths from 2 pi / q_min (the
            longest of the spectrum, lambda_0) down to 2 pi / q_th are resolved
            on the mesh as a random-phase surface; shorter ones are homogenised.
            q_th = q_min (q0 without a roll-off): nothing deterministic.
        seed: Seed of the random phases (the same seed, the same surface).
        amplitude: ``fixed`` (|a_k| = <|a_k|^2>^(1/2), S0 eq 21) or ``gaussian``.
    """

    q_th: float = SECTOR_Q_TH
    seed: int = 1
    amplitude: str = "fixed"

    def __post_init__(self) -> None:
        super().__post_init__()
        psd = self.build()
        check_range("roughness.q_th", self.q_th, psd.q_min, psd.q_max, hi_open=True,
                    unit="1/m (q_min <= q_th < q1)")  # fmt: skip
        check_int_range("roughness.seed", self.seed, 0)
        check_choice("roughness.amplitude", self.amplitude, ("fixed", "gaussian"))


@dataclass(frozen=True)
class SectorParams:
    """The periodic sector and its mesh (SI units).

    Attributes:
        elements_per_wavelength: Elements per shortest deterministic wavelength
            lambda_th = 2 pi / roughness.q_th on the contact band [-] (the band
            element is lambda_th / elements_per_wavelength).
        periods: Roughness periods lambda_0 along the circumference of the sector [-].
        height: Radial extent of the sector above the lip tip [m]; the installed
            state is imposed on the cut there.
        band_oil: Axial extent of the sector's contact band on the oil side of the
            tip [m] (it must hold the lubricated zone).
        band_air: Axial extent on the air side [m].
        h_far: Largest element size [m].
        growth: Element size increase per unit distance from the band [-].
    """

    elements_per_wavelength: float = 4.0
    periods: int = 1
    height: float = 0.4e-3
    band_oil: float = 0.15e-3
    band_air: float = 0.25e-3
    h_far: float = 60e-6
    growth: float = 0.3

    def __post_init__(self) -> None:
        check_range("sector.elements_per_wavelength", self.elements_per_wavelength, 2.0, 100.0)
        check_int_range("sector.periods", self.periods, 1, 100)
        check_positive("sector.height", self.height, "m")
        check_positive("sector.band_oil", self.band_oil, "m")
        check_positive("sector.band_air", self.band_air, "m")
        check_positive("sector.h_far", self.h_far, "m")
        check_range("sector.growth", self.growth, 0.0, 2.0, lo_open=True)


@dataclass(frozen=True)
class LipStaticParameters(LipInstallParameters):
    """The lip seal on a periodic sector at zero speed (SI units); the installation
    fields (``material``, ``contact``, ``spring_load``, ``degree``) as in
    ``lip-install``.

    Attributes:
        lip: The lip section and its axisymmetric mesh, as in ``lip-install`` but with
            curved (``order = 2``) elements, the only order allowed here: the sector's
            nodes lie on the true surface of revolution, and on straight facets of
            the section (order 1) they would sit outside it by the chord sag
            ``h^2 / (8 tip_radius)``, 0.5 um on a 20 um band, which is several decay
            lengths of the contact law (the first iterate then overlaps the shaft).
        roughness: The lip and shaft roughness (``lip-install``'s) and its split
            ``q_th`` (:class:`SectorRoughnessParams`).
        sector: The sector and its mesh (:class:`SectorParams`).
        film: The oil film: ``viscosity`` [Pa s]; ``flow_factor`` (``persson`` or
            ``patir-cheng``, of the homogenised part); ``asperity_shear`` sigma_1
            [Pa]; ``speed`` the shaft surface speed [m/s] (0 here).
        oil_pressure: Sealed (gauge) oil pressure on the oil side [Pa].
        air_pressure: Pressure on the air side [Pa].
        feedback: The fluid pressure acts on the lip (false: the lip is frozen in its
            dry equilibrium and only the film is solved on it).
        zone_gap: The lubricated zone ends where the gap exceeds this many
            roughness.h_rms [-] (beyond, the film is pinned at the sealed pressure
            of its side, as in the ``lip`` scene).
    """

    lip: LipSealParams = field(default_factory=lambda: LipSealParams(**SEAL_GEOMETRY, order=2))
    roughness: SectorRoughnessParams = field(
        default_factory=lambda: SectorRoughnessParams(**SEAL_ROUGHNESS)
    )
    sector: SectorParams = field(default_factory=SectorParams)
    film: FilmParams = field(
        default_factory=lambda: FilmParams(
            speed=0.0, viscosity=0.01, cavitation="none", flow_factor="persson",
            asperity_shear=1.0e6,
        )
    )  # fmt: skip
    oil_pressure: float = 0.05e6
    air_pressure: float = 0.0
    feedback: bool = True
    zone_gap: float = 20.0

    #: the scene's name (errors and results)
    scene_name = "lip-static"

    def __post_init__(self) -> None:
        super().__post_init__()
        check_range("oil_pressure", self.oil_pressure, 0.0, 5e6, unit="Pa")
        check_range("air_pressure", self.air_pressure, 0.0, 5e6, unit="Pa")
        check_bool("feedback", self.feedback)
        # curved section elements: see the ``lip`` attribute
        check_int_range("lip.order", self.lip.order, 2, 2)
        check_range("zone_gap", self.zone_gap, 2.0, 1e4, unit="h_rms")
        self._check_speed()
        if self.contact.model in ("none", "stiff"):
            raise ParameterError(
                f"contact.model = {self.contact.model!r}: the sector homogenises the "
                "roughness above q_th with a rough law ('persson' or 'exponential')",
                "contact.model",
            )
        for name, own in (("inlet_pressure", "oil_pressure"), ("outlet_pressure", "air_pressure")):
            if getattr(self.film, name) != 0.0:
                raise ParameterError(
                    f"film.{name} = {getattr(self.film, name)!r} Pa: the film edges hold the "
                    f"sealed pressures; set {own} [Pa] instead", f"film.{name}",
                )  # fmt: skip
        self.mesh_params()  # the sector must fit the lip: names the parameter at fault

    def _check_speed(self) -> None:
        """Zero speed (a sliding shaft is the scene ``lip-dynamic``)."""
        check_range("film.speed", self.film.speed, 0.0, 0.0, unit="m/s (lip-dynamic slides)")
        if self.film.discrete_upwinding:
            raise ParameterError(
                "film.discrete_upwinding = True at rest: there is no Couette transport "
                "to upwind (the sliding scene is lip-dynamic); set it to false",
                "film.discrete_upwinding",
            )

    # ------------------------------------------------------------ derived
    @property
    def wavelength(self) -> float:
        """lambda_0 = 2 pi / q_min, the longest roughness wavelength [m] (the period)."""
        return 2.0 * math.pi / self.roughness.build().q_min

    @property
    def threshold_wavelength(self) -> float:
        """lambda_th = 2 pi / q_th [m]."""
        return 2.0 * math.pi / self.roughness.q_th

    @property
    def h_band(self) -> float:
        """Element size on the contact band [m]."""
        return self.threshold_wavelength / self.sector.elements_per_wavelength

    def mesh_params(self) -> LipSectorParams:
        """The sector geometry and mesh (:class:`geometry.lip_sector.LipSectorParams`).

        Raises:
            ParameterError: naming the scene parameter at fault (the band element
                ``lambda_th / sector.elements_per_wavelength`` at most half the tip
                radius, the sector angle at most 0.5 rad, ``sector.height`` and
                ``sector.h_far`` within the lip tip).
        """
        s, lp = self.sector, self.lip
        lam0, h = self.wavelength, self.h_band
        check_range("sector.elements_per_wavelength", s.elements_per_wavelength,
                    self.threshold_wavelength / (0.5 * lp.tip_radius), 100.0,
                    unit=f"(the band element lambda_th / elements_per_wavelength = {h:.3g} m "
                    f"must be at most lip.tip_radius / 2 = {0.5 * lp.tip_radius:.3g} m)")  # fmt: skip
        check_range("sector.periods", s.periods * lam0 / lp.shaft_radius, 0.0, 0.5,
                    lo_open=True, unit="rad (sector angle periods * lambda_0 / lip.shaft_radius)")  # fmt: skip
        lip = dataclasses.replace(lp, band_oil=s.band_oil, band_air=s.band_air)
        try:
            g = LipGeometry(lip)
        except ParameterError as e:
            raise ParameterError(
                f"sector.band_oil / sector.band_air: {e}", "sector.band_oil"
            ) from None
        lo = g.r_band - g.r0 + 2 * h
        hi = min(g.O1[0], g.A1[0], g.Gb[0]) - g.r0
        check_range("sector.height", s.height, lo, hi, lo_open=True, hi_open=True,
                    unit="m (above the band, below the lip head)")  # fmt: skip
        check_range("sector.h_far", s.h_far, h, 0.5 * s.height,
                    unit="m (between the band element and sector.height / 2)")  # fmt: skip
        q_ratio = self.roughness.q_th * lam0 / (2.0 * math.pi)
        return LipSectorParams(
            lip=lip, roughness_wavelength=lam0, q_ratio=max(q_ratio, 1.0),
            elements_per_wavelength=s.elements_per_wavelength, periods=s.periods,
            sector_height=s.height, h_far=s.h_far, growth=s.growth,
        )  # fmt: skip


@dataclass(frozen=True)
class SectorStepping:
    """The speed walk of the sliding sector's sweeps (``lip-dynamic``).

    Attributes:
        time_budget: Wall time of one sweep's speed walk, after its first speed
            [s] (0: none), as the lubricated scenes' ``stepping.time_budget``: once
            spent, the walk stops before its next continuation step, the speed
            under way is recorded as failed ("stopped at ... m/s: the time budget
            ... was spent") and the speeds not yet walked to as not attempted.
    """

    time_budget: float = 0.0

    def __post_init__(self) -> None:
        check_nonnegative("time_budget", self.time_budget, unit="s")


@dataclass(frozen=True)
class LipDynamicParameters(LipStaticParameters):
    """The lip seal sector on a turning shaft (SI units); the fields of ``lip-static``.

    Attributes:
        film: The oil film: ``speed`` the shaft surface speed along the
            circumference [m/s] (> 0: the shaft turns counter-clockwise about +z, the
            surface slides along +x1 on the maps); ``cavitation`` ``jfo``
            (mass-conserving, S0 eqs 10-11, the only choice); ``viscosity``,
            ``flow_factor``, ``asperity_shear`` as in ``lip-static``.
        feedback: True: the film pressure deforms the lip (the coupled sliding
            sector: each speed the coupled semismooth Newton with projected steps,
            full and then backtracking, from a frozen-film predictor on the current
            lip (or first from the path's tangent, ``tangent``), pseudo-time steps
            of the coupled film if that fails too, :func:`solve_sliding`).  False: the lip is
            frozen in its dry two-scale state and only the film is solved on it
            (valid while the film carries a small part of the load: see
            ``fluid_load_fraction`` and docs/scenes/lip-sector.md).
        lift: With ``feedback``: true, the lip floats on the shaft at the radial
            load it carries at rest (the film lifts it as a whole: the shaft radius
            becomes an unknown with the load equation; the sector is pressurised at
            :data:`LIFT_START_SPEED` with the shaft at its radius, then released);
            false, the cut holds the installed displacement and the lip lifts only
            by compressing its tip, which raises the radial load.
        tangent: With ``feedback``: true, each speed step of the walk starts the
            coupled Newton from the first-order prediction along the solution
            path's tangent ``dx/d ln U`` at the last converged speed, the lip and
            the film moving together (the frozen-film predictor only if that
            fails); false, from the frozen-film predictor alone.  Opt-in: on the
            lifting default band it walks further and in fewer Newton steps, but
            on the coarse band its decade step to 0.1 m/s converged to another
            point of the discrete problem (0.5 % in torque, 11 % in fluid load)
            than walks in quarter-decade steps reach with either predictor, and
            there it was not faster (docs/scenes/lip-sector.md).
        stepping: The sweeps' speed walk: its ``time_budget`` [s]
            (:class:`SectorStepping`).
    """

    film: FilmParams = field(
        default_factory=lambda: FilmParams(
            speed=0.1, viscosity=0.01, cavitation="jfo", flow_factor="persson",
            asperity_shear=1.0e6,
        )
    )  # fmt: skip
    feedback: bool = False
    lift: bool = False
    tangent: bool = False
    stepping: SectorStepping = field(default_factory=SectorStepping)

    scene_name = "lip-dynamic"

    def _check_speed(self) -> None:
        """A turning shaft (zero speed is the scene ``lip-static``), JFO."""
        check_bool("lift", self.lift)
        check_bool("tangent", self.tangent)
        check_range("film.speed", self.film.speed, 0.0, 100.0, lo_open=True,
                    unit="m/s (the turning shaft; a shaft at rest is the scene lip-static)")  # fmt: skip
        check_choice("film.cavitation", self.film.cavitation, ("jfo",))


# ---------------------------------------------------------------- two scales
@dataclass
class TwoScale:
    """The roughness split at q_th (S0 eqs 15-21).

    Attributes:
        psd: The whole spectrum C(q).
        stochastic: C_sto(q) = C(q) for q > q_th, homogenised (Persson laws, flow factor).
        surface: The deterministic surface h_r (None when q_th = q_min).
        period: lambda_0 [m], the period of ``surface`` along both axes.
        q_th: Threshold [1/m].
    """

    psd: PowerSpectrum
    stochastic: PowerSpectrum
    surface: FourierSurface | None
    period: float
    q_th: float

    def info(self) -> dict[str, float]:
        """Scalars: rms height and slope of the whole spectrum, of the homogenised
        part, and of the deterministic surface (lattice and realisation)."""
        out = {
            "h_rms": self.psd.h_rms(),
            "rms_slope": self.psd.rms_slope(),
            "h_rms_homogenised": self.stochastic.h_rms(),
            "rms_slope_homogenised": self.stochastic.rms_slope(),
            "roughness_wavelength": self.period,
            "threshold_wavelength": 2.0 * math.pi / self.q_th,
            "deterministic_modes": 0,
        }
        if self.surface is not None:
            out.update(
                deterministic_modes=int(self.surface.kx.size),
                h_rms_deterministic=self.surface.h_rms(),
                rms_slope_deterministic=self.surface.rms_slope(),
            )
        return out


def two_scale(r: SectorRoughnessParams) -> TwoScale:
    """Split the spectrum of ``r`` at ``r.q_th`` and synthesise the deterministic part
    (period lambda_0 = 2 pi / q_min)."""
    psd = r.build()
    period = 2.0 * math.pi / psd.q_min
    if r.q_th <= psd.q_min * (1.0 + 1e-12):
        return TwoScale(psd, psd, None, period, r.q_th)
    split = TwoScaleSplit(psd, r.q_th, period=period)
    surface = split.deterministic_surface(r.seed, r.amplitude)
    return TwoScale(psd, split.stochastic_psd, surface, period, r.q_th)


def height_field(surface: FourierSurface, X: Any, shaft_radius: float) -> Any:
    """``h_r(x_1, x_2)`` [m] as UFL of the reference coordinates ``X``: ``x_1 = R_shaft
    atan2(Y, X)`` along the circumference (period lambda_0 over the sector), ``x_2 = Z``;
    the real form of S0 eq 17, exact at every quadrature point."""
    x1 = shaft_radius * ufl.atan2(X[1], X[0])
    x2 = X[2]
    terms = [
        2.0 * float(a) * ufl.cos(float(qx) * x1 + float(qy) * x2 + float(ph))
        for a, qx, qy, ph in zip(
            surface.amplitude, surface.qx, surface.qy, surface.phase, strict=True
        )
    ]
    return sum(terms[1:], terms[0])


# ---------------------------------------------------------------- building
class SectorProblem(SolidContactProblem):
    """The sector's contact problem; its load fraction ramps what :attr:`ramp_hook` is
    given (the roughness height, then the sealed pressures) with the shaft held at
    its radius."""

    ramp_hook: Any = None

    def set_fraction(self, t: float) -> None:
        if self.ramp_hook is None:
            super().set_fraction(t)
        else:
            self.ramp_hook(t)


@dataclass
class SectorLip:
    """The installed lip sector with its film (what :func:`build` returns).

    Attributes:
        problem: The coupled sector problem (shaft at its radius).
        mesh: The tagged sector mesh.
        roughness: The two-scale split.
        height_scale: Constant multiplying ``h_r`` (ramped from 0 to 1).
        installed: Scalars of the axisymmetric installation (``axisymmetric_*``).
        angle: Sector angle [rad].
        film_only: The frozen-lip film solver (``feedback = false``), else None.
        film_polish: The film solver that finishes a coupled point
            (``feedback = true``, :func:`polish_film`), else None.
        upwinding_weight: The weight of ``film.discrete_upwinding``'s term in the
            last film solved: with the option 1 (with ``film.release_upwinding``
            0, or the smallest weight that converged); without it 0, or the weight
            a rescued film kept (:func:`_rescue_film`).
        tangent: The coupled sliding sector's speed steps start from the path's
            tangent (``lip-dynamic``'s ``tangent``, :func:`solve_sliding`).
        sliding_point: ``(speed [m/s], state)`` of the last converged coupled
            sliding point (the start of the next step's tangent), else None.
        steps: Newton steps and time of each stage.
        gap_limiter: The Newton step limit on the contact gaps; while the
            roughness comes in it crosses zero by at most :data:`CREST_CROSSING`
            ``h_rms`` a step.
        narrow_limits: The step limits without the tip's twist
            (:func:`sector_step_limits`), taken where the wide ones fail
            (:func:`_first_equilibrium`).
    """

    problem: SectorProblem
    mesh: TaggedMesh
    roughness: TwoScale
    height_scale: Any
    installed: dict[str, float]
    angle: float
    film_only: Any = None
    film_polish: Any = None
    upwinding_weight: float = 1.0
    tangent: bool = False
    sliding_point: tuple[float, list[Any]] | None = None
    steps: dict[str, Any] = field(default_factory=dict)
    gap_limiter: SurfaceGapLimiter | None = None
    narrow_limits: StepLimits | None = None

    @property
    def per_revolution(self) -> float:
        """Sectors in the whole circumference, ``2 pi / angle``."""
        return 2.0 * math.pi / self.angle

    def destroy(self) -> None:
        """Free the PETSc objects (collective)."""
        self.problem.destroy()
        for solver in (self.film_only, self.film_polish):
            if solver is not None:
                solver.destroy()


def film_parameters(params: LipStaticParameters) -> FilmParams:
    """The film as solved: edges at the sealed pressures; without transport no
    cavitation condition (the pressure lies between the sealed pressures)."""
    f = params.film
    cav = f.cavitation if f.speed != 0.0 else "none"
    return dataclasses.replace(
        f, cavitation=cav, inlet_pressure=params.oil_pressure, outlet_pressure=params.air_pressure
    )


def snes_type(fp: FilmParams) -> str:
    """The Newton type of a film's cavitation model."""
    return {"jfo": "vinewtonssls", "reynolds": "vinewtonrsls"}.get(fp.cavitation, "newtonls")


def _installed(params: LipStaticParameters) -> tuple[RevolvedState, dict[str, float], Any]:
    """Install the lip in axisymmetry; return its revolved state, its scalars and law."""
    t0 = time.perf_counter()
    inst = install(params)
    dry = inst.problem
    _, p_pc = dry.surface_values(dry.p_cont, average=True)
    width, _ = moment_width(dry)
    R_s = params.lip.shaft_radius
    info = {
        "axisymmetric_radial_load": dry.contact_force() / (2.0 * math.pi * R_s),
        "axisymmetric_contact_width": width,
        "axisymmetric_max_contact_pressure": float(p_pc.max()),
        "install_steps": len(dry.steps),
        "install_newton_iterations": int(sum(s.newton_iterations for s in dry.steps)),
    }
    # the chord sag of the section's straight boundary facets on the tip arc, with margin
    sag = 4.0 * params.lip.h_contact**2 / params.lip.tip_radius + 1e-9
    revolved = RevolvedState(serial_copy("lip", params.lip), dry.W, dry.w, max_outside=sag)
    info["install_time_s"] = time.perf_counter() - t0
    dry.destroy()
    return revolved, info, inst


def build(params: LipStaticParameters) -> SectorLip:
    """Install the lip (axisymmetric), cut the sector, and build its coupled problem at
    the installed state with the deterministic roughness off and the sealed
    pressures at zero (:func:`solve_dry` and :func:`solve_pressures` go on)."""
    revolved, installed, inst = _installed(params)
    lp, fp = params.lip, film_parameters(params)
    mp = params.mesh_params()
    tm = create_mesh("lip-sector", mp, comm=world())
    rough = two_scale(params.roughness)
    law, law_info = params.contact.build(params.roughness, params.material.E_star,
                                         approach=lp.interference, psd=rough.stochastic)  # fmt: skip
    installed.update({f"law_{k}": v for k, v in law_info.items()})
    h_rms = rough.stochastic.h_rms()
    h = mp.h_band
    # the homotopy weight: deterministic height scale and law blend (0: the installed
    # lip's law of the whole spectrum, no resolved roughness; 1: the two scales)
    scale = dolfinx.fem.Constant(tm.mesh, 1.0)
    counter: Any = Shaft3D()
    if rough.surface is not None:
        scale.value = 0.0
        X = ufl.SpatialCoordinate(tm.mesh)
        counter = WithSurfaceHeight(
            counter, scale * height_field(rough.surface, X, lp.shaft_radius)
        )
        whole, _ = params.contact.build(params.roughness, params.material.E_star,
                                        approach=lp.interference)  # fmt: skip
        law = LawHomotopy(whole, law, scale)
    film = SurfaceFilm(
        fp,
        FilmScales(pressure=installed["axisymmetric_max_contact_pressure"],
                   length=0.5 * installed["axisymmetric_contact_width"], gap=h_rms, element=h),
        h_rms=h_rms, rms_slope=getattr(law, "rms_slope", math.nan), e_star=params.material.E_star,
        no_flux_tags=(tm.tag("periodic_left"), tm.tag("periodic_right")),
        psd=rough.stochastic if fp.flow_factor == "persson" else None,
        allow_discrete_upwinding=True,
    )  # fmt: skip
    body = Body(Solid3D(), params.material.build(),
                [Dirichlet(tm.tag("cut"), value=revolved.displacement)], degree=params.degree)  # fmt: skip
    periodic = RotationalPeriodicity(mp.angle, tolerance=1e-3 * h)
    control: Any = PositionControl(lp.shaft_radius, lp.shaft_radius)
    if lifts(params):  # held at the radius until released (pressurise_sliding)
        load = installed["axisymmetric_radial_load"] * lp.shaft_radius * mp.angle  # N
        control = ForceControl(load, lp.shaft_radius, held=True)
    prob = SectorProblem(
        tm.mesh, tm.facet_tags, body, counter, control, tm.tag("contact"), law=law,
        film=film,
        limits=sector_step_limits(mp),
        # rtol 1e-13 as the lip's: the band's film rows converge with the solid's only there
        snes=SNESOptions(max_it=60, rtol=1e-13, snes_type=snes_type(fp)), periodic=periodic,
        name=params.scene_name,
    )  # fmt: skip
    _set_installed(prob, revolved)
    # no Newton step closes a contact gap by more than half of itself (the contact law
    # diverges as u -> 0: an overshoot into u < 0 is decades of pressure); the gap
    # and the radial normal from the problem itself, roughness included
    closing = SurfaceGapLimiter(prob, GAP_CLOSURE, law.h_rms / law.alpha)
    _with_gap_limit(prob, prob.solver.step_limiter, closing)
    film.set_edge_pressures(0.0, 0.0)
    if film.has_couette:  # a sliding shaft: pressurised at a slow speed, then walked up
        film.set_speed(start_speed(params.film.speed, lifts(params)))
    out = SectorLip(
        prob,
        tm,
        rough,
        scale,
        installed,
        mp.angle,
        upwinding_weight=1.0 if fp.discrete_upwinding else 0.0,
        tangent=bool(getattr(params, "tangent", False)),
        gap_limiter=closing,
        narrow_limits=sector_step_limits(mp, twist=False),
    )
    film_solver = film.make_solver(
        dataclasses.replace(
            prob.solver.options,
            snes_type="semismooth" if film.has_theta else snes_type(fp),
            **FILM_ONLY_TOLERANCES,
        ),
        name=f"{params.scene_name} film",
    )
    if params.feedback:
        out.film_polish = film_solver
    else:
        out.film_only = film_solver
    del inst
    return out


def sector_step_limits(mp: LipSectorParams, twist: bool = True) -> StepLimits:
    """The sector's Newton step limits [m]: the radial component (``x``, radial in the
    sector's middle plane, ``Shaft3D.normal_axis``) by half a band element (the
    motion the contact law drives, and what can invert the band's thin
    elements); with ``twist``, any component by half the largest element
    (``sector.h_far``), else by half a band element as well.

    The asperity shear twists the lip tip along the circumference as a whole, a
    motion the axisymmetric installation does not have, so the sector's first
    solve must make it.  Measured (7 December, default sector, two ranks): the
    first Newton direction moved the tip 11.5 um along the circumference; with
    every component held to half a band element (1.3 um) the first solve took 10
    Newton steps, the residual falling by equal amounts (2.34e-5, 2.07e-5, ...,
    1.92e-6) until the step was whole; with half the largest element it took 4.
    The gaps keep their own limit (:class:`SurfaceGapLimiter`).  Where the wide
    steps fail, the dry stage starts again with the narrow ones
    (:func:`_first_equilibrium`)."""
    # h_far >= h_band (LipSectorParams checks it)
    band = 0.5 * mp.h_band
    return StepLimits(max_step=0.5 * mp.h_far if twist else band, max_normal_step=band)


def _with_gap_limit(prob: SolidContactProblem, own: Any, closing: SurfaceGapLimiter) -> None:
    """The sector solver's step limit: the displacement limit ``own`` (or None) and
    the gap limit ``closing``, whichever cuts more."""
    prob.solver.step_limiter = lambda x, dx: min(own(x, dx) if own else 1.0, closing(x, dx))


def _use_step_limits(lub: SectorLip, limits: StepLimits) -> None:
    """Give the sector's solver ``limits``, with its gap limit."""
    prob = lub.problem
    prob.limits = limits
    assert lub.gap_limiter is not None
    _with_gap_limit(prob, prob.step_limiter(), lub.gap_limiter)


def _set_installed(prob: SolidContactProblem, revolved: RevolvedState) -> None:
    """The revolved installed state as the first iterate (displacement, mixed pressure)."""
    if prob.mixed:
        prob.w.sub(0).interpolate(revolved.displacement)
        prob.w.sub(1).interpolate(revolved.pressure)
    else:
        prob.w.interpolate(revolved.displacement)
    prob.w.x.scatter_forward()


# ---------------------------------------------------------------- solving
#: adaptive steps of the roughness height and of the sealed pressures.  On the default
#: sector at two ranks (5 December): a first step of 1/64, growth only after at most 3
#: Newton steps and increments of at most 1/16 bring the roughness in with no failed
#: step (the accepted steps take 0 to 5 Newton steps), 37 Newton steps in all, the dry
#: stage in 68-71 s.  A first step of 1/32 failed at 0.0625 (a NaN, 14 Newton steps
#: lost); growth after up to 12 Newton steps failed three steps (18 lost, 123-132 s);
#: steps of 1/8 above t = 0.5 failed five times (52 lost; from the secant).  The
#: results are the same to 1e-10 (leakage, torque, radial load).  A step is cut
#: after 15 Newton steps, not fewer: where resolved asperities come into contact a
#: Newton step closes a gap by at most half (GAP_CLOSURE), so a step needs several
#: whatever its size (with a cut after 8, the band of 6 elements per lambda_th
#: failed steps of 0.002 at t = 0.045).
#: Each step starts from the tangent of the path (``tangent``; the Jacobian at the
#: last converged state, refactorised): on the default sector at two ranks (7
#: December, back to back) 8 dry Newton steps instead of 34 with the secant, the
#: dry stage 85 s instead of 116 s, the point 118 s instead of 147 s, the same
#: leakage, torque and h_min to the printed digits; most steps then start
#: converged, each costing one Jacobian and one factorisation.  So from the
#: tangent the cap is 1/8 (7 December, night): 11 steps and 10 Newton steps, the
#: point 106.6 s against 116.4 s with 1/16 (two ranks, back to back), and the 13 cases
#: of the lip-static stability table give the same results to 4e-9 (the fine
#: shaft and E 2 MPa, where crests cross zero, 3-4 Newton steps more).
ROUGHNESS_STEPS = SteppingOptions(first=1.0 / 64, grow=2.0, easy=3, max_steps=80, predictor=True,
                                  tangent=True, max_increment=1.0 / 8, max_newton=15)  # fmt: skip
#: Newton tolerance of the intermediate roughness steps (the last is solved to the
#: solver's own, 1e-13: the film rows need it, the dry path does not)
PATH_RTOL = 1e-9
#: a Newton step closes a contact gap by at most this fraction of itself
GAP_CLOSURE = 0.5
#: While the roughness comes in, no Newton step takes a positive contact gap more
#: than ``CREST_CROSSING h_rms`` below zero, nor closes one at or below zero by more
#: (``SurfaceGapLimiter.crossing``); the other
#: stages let a small gap close by up to the floor ``h_rms / alpha`` (24 nm at
#: h_rms 0.1 um), which a resolved crest near zero separation crosses into the
#: homogenised law's continuation, whose pressure rises by decades per nm.
#: Measured (6 December, coarse band, one rank, h_rms 0.1 um, where the installed
#: band is near full contact, 0.33 nm = 0.0025 h_rms under the peak): the first
#: roughness step (1/64) put crests 4.8 nm into the shaft (3.3 GPa), the first
#: Newton step drove them to -23 nm, and after three steps the bulk residual was
#: NaN (the rubber under them crushed); the homotopy stalled at 0.74.  With a
#: crossing of 0.01 h_rms it comes in whole (143 Newton steps in 26 roughness
#: steps); with 0.001 h_rms too (112 in 22), but the default band then needed 48
#: Newton steps instead of 37; with 0.01 it needs the same 37, to the same state.
CREST_CROSSING = 1e-2

PRESSURE_STEPS = SteppingOptions(first=1.0, grow=2.0, easy=8, max_steps=60)


def solve_dry(lub: SectorLip, params: LipStaticParameters) -> dict[str, Any]:
    """The sector's own equilibrium at zero sealed pressures: one Newton from the
    installed state (the law of the whole spectrum, no resolved roughness), then
    the two scales brought in together by one weight ``t`` (0 -> 1, adaptive steps;
    a failed step is cut and retried from the last converged state): the height
    ``t h_r`` and the law ``(1 - t) p_whole + t p_sto``; then the lubricated zone is
    restricted to ``zone_gap`` h_rms.

    Raises:
        SolverError: with ``partial`` holding the height fraction reached.
    """
    prob = lub.problem
    t0 = time.perf_counter()
    # dry: the film's unknowns pinned (zero pressure, full film) until the zone is cut,
    # and a plain Newton, as at rest (no bound can be active; on the default sector the
    # roughness homotopy failed the same steps with either type, DIVERGED_FNORM_NAN
    # towards 0.094 and 0.14, and accepted 0.031, 0.047, 0.078, 0.109)
    prob.film.pin([prob.solver])
    with prob.solver.switched(snes_type="newtonls"):
        _dry_stages(lub, params)
    lub.height_scale.value = 1.0
    h_rms = params.roughness.h_rms
    free = prob.film.restrict_to_gap(params.zone_gap * h_rms, [prob.solver])
    for solver in (lub.film_only, lub.film_polish):
        if solver is not None:
            prob.film.restrict_to_gap(params.zone_gap * h_rms, [solver])
    info = {**lub.steps, "film_nodes": free, "dry_time_s": time.perf_counter() - t0}
    lub.steps.update(info)
    return info


def _dry_stages(lub: SectorLip, params: LipStaticParameters) -> None:
    """The dry solves of :func:`solve_dry`; Newton steps and homotopy steps into ``lub.steps``."""
    prob = lub.problem
    its = _first_equilibrium(lub)
    steps = 0
    if lub.roughness.surface is not None:
        prob.ramp_hook = lambda t: setattr(lub.height_scale, "value", t)
        rtol = max(PATH_RTOL, prob.solver.options.rtol)
        crossing = CREST_CROSSING * prob.law.h_rms
        try:
            n0 = len(prob.steps)
            with prob.solver.switched(rtol=rtol), lub.gap_limiter.crossing_set(crossing):
                prob.ramp(ROUGHNESS_STEPS)
            rec = prob.steps[n0:]
            its += int(sum(s.newton_iterations for s in rec))
            steps = len(rec)
        except SolverError as e:
            raise SolverError(
                f"the deterministic roughness could not be brought in: {e.what}",
                where=f"{prob.name}, roughness height fraction {lub.height_scale.value:.4g}",
                history=e.history,
                partial=e.partial,
            ) from e
        finally:
            prob.ramp_hook = None
        lub.height_scale.value = 1.0
        its += prob.solver.solve(where=f"{prob.name}: two-scale dry state").newton_iterations
    lub.steps.update(dry_newton_iterations=its, roughness_steps=steps)


def _first_equilibrium(lub: SectorLip) -> int:
    """The sector's equilibrium at the installed state; its Newton steps.

    With the wide step limits first (the tip twists by up to half the largest
    element a step, :func:`sector_step_limits`); if that solve fails, again from
    the installed state with every component held to half a band element, which
    the rest of the dry stage keeps.  Measured (7 December, the stability table on
    the coarse band, one rank): the wide steps crushed the rubber (a NaN residual)
    on a very soft elastomer (E 2 MPa, after 23 Newton steps) and on a fine shaft
    (h_rms 0.1 um, after 5); both cases had converged with the narrow steps.
    """
    prob = lub.problem
    where = f"{prob.name}: sector equilibrium at the installed state"
    start = prob.state()
    try:
        return prob.solver.solve(where=where).newton_iterations
    except SolverError as e:
        get_logger().warning("%s: %s; again with every component of a step held to half a "
                             "band element", prob.name, e.what)  # fmt: skip
        lost = e.history.newton_iterations
    prob.restore(start)
    assert lub.narrow_limits is not None
    _use_step_limits(lub, lub.narrow_limits)
    hist = prob.solver.solve(where=f"{where} (narrow steps, after the wide ones failed)")
    return lost + hist.newton_iterations


def set_sealed_pressures(lub: SectorLip, oil: float, air: float) -> None:
    """The sealed oil and air pressures [Pa] on the film's edges (a coupled sliding
    point solved at other pressures is no start for a tangent in the speed)."""
    lub.problem.film.set_edge_pressures(oil, air)
    lub.sliding_point = None


#: the frozen film converges on its Newton step (``stol``, with the round-off check of
#: the residual), not on ``rtol |F(0)|``: its rows are scaled by the zone's gap
#: estimate, and the flow through the constriction is ~1e-7 of that scale (at
#: ``rtol`` 1e-13 the q_th = q0 sector stopped after one step with a mass balance of
#: 4.8e-7; one step more gives 1e-10)
#: The JFO film's semismooth Newton is an active-set method: its residual is no merit
#: function (a node switched on or off overshoots, e.g. ``theta > 1`` before it is
#: pressurised again), so growth of the residual is no sign of divergence.  Measured
#: on the coarse two-scale sector: |F| 2.9e-5 -> 1.4e-5 -> 0.79 at the first switch
#: with equal sealed pressures (DIVERGED_DTOL at the default dtol 1e4), up to 227 on
#: the way with 0.05 MPa, both before the active set settled; convergence is still
#: judged on the step and the complementarity check.
#: The active set moves a few nodes per step: from the pinned film at equal sealed
#: pressures the coarse two-scale sector (485 band nodes) took 55 steps; the default
#: band (2.6 um, about 4x the nodes) ran out of 60 at two ranks, hence 150.
FILM_ONLY_TOLERANCES = {"rtol": 1e-20, "atol": 1e-300, "dtol": 1e300, "max_it": 150}


#: Newton steps of each solve in the release of the frozen film's discrete upwinding
#: (a weight step, and each of its pseudo-time steps), against FILM_ONLY_TOLERANCES'
#: 150 for a film solved from afar
RELEASE_MAX_NEWTON = 30


def solve_film(lub: SectorLip, where: str, solver: Any = None, release: bool = True) -> int:
    """Solve the film on the frozen lip with ``solver`` (default ``lub.film_only``,
    ``feedback = false``; the coupled sliding sector's predictor passes
    ``lub.film_polish`` and ``release = false``); returns the Newton steps.
    With ``film.release_upwinding`` (and ``release``) the discrete upwinding is
    then walked down (:func:`_release`), its final weight kept in
    ``lub.upwinding_weight``.

    Without JFO one Newton solve.  With JFO the fixed-pattern semismooth Newton
    (``semismooth``: identity rows at the bounds the natural residual
    ``x - clip(x - F)`` finds active, a node exactly on its bound counted active)
    from the last state; if that fails, by pseudo-time steps from the last state
    (:func:`~dolfinx_seal.film.pseudo_time.pseudo_transient_solve`: the active set
    moves a little per step instead of cycling); if that fails too, once more from
    a full film (``theta = 1``
    everywhere, the pressure of the last state), where the first step is the
    full-film Reynolds solution and the next ones cavitate the nodes whose pressure
    it left negative.  Measured on the coarse two-scale sector (q_th = 2 q0, 5.2 um
    band elements) at 1 mm/s: 26 steps, cavitation fraction 0.55, nodal mass
    balance 3.7e-9.  Fischer-Burmeister (``vinewtonssls``) crept there and its
    state (``theta`` a round-off below 1 at pressurised nodes) made the
    semismooth Newton's first active set cavitate them all (DIVERGED_DTOL).

    With the default scheme (no ``film.discrete_upwinding``) and ``release``, a
    film that none of these reaches is rescued (:func:`_rescue_film`): the
    monotone film from the last state, then its discrete upwinding released, so
    that the film reported is still the default scheme's, or, where the release
    stops, the blend ``lub.upwinding_weight`` says (logged as a warning).
    """
    solver = solver if solver is not None else lub.film_only
    if not lub.problem.film.has_theta:
        return solver.solve(where=where).newton_iterations
    film = lub.problem.film
    if film.params.discrete_upwinding:
        its = _solve_jfo_film(lub, where, solver)
        if release and film.params.release_upwinding:
            n, lub.upwinding_weight = _release(lub, solver, where)
            its += n
        return its
    attach_discrete_upwinding(solver, weight=0.0)  # a former rescue's term, if any
    last = _sliding_film_state(film)
    try:
        its = _solve_jfo_film(lub, where, solver)
    except SolverError as e:
        if not release:
            raise
        return e.history.newton_iterations + _rescue_film(lub, where, solver, last, e)
    if release:
        lub.upwinding_weight = 0.0
    return its


def _release(lub: SectorLip, solver: Any, where: str) -> tuple[int, float]:
    """The frozen film's discrete upwinding walked from its weight 1 to 0
    (:func:`~dolfinx_seal.film.upwinding.release_discrete_upwinding`, a failed
    weight step tried again by pseudo-time steps, every solve capped at
    :data:`RELEASE_MAX_NEWTON` Newton steps); ``(Newton steps, weight kept)``."""
    film = lub.problem.film
    return release_discrete_upwinding(
        solver, [film.P, film.theta_fn], where,
        fallback=lambda at: pseudo_transient_solve(film, solver, at),
        max_newton=RELEASE_MAX_NEWTON,
    )  # fmt: skip


def _rescue_film(lub: SectorLip, where: str, solver: Any, last: Any, failure: SolverError) -> int:
    """The default scheme's film where its own solves failed: from the last film
    (``last``), the film with ``film.discrete_upwinding``'s term (the monotone
    scheme, whose Newton converges in a few steps where the default scheme's
    cycles), then the term released (:func:`_release`).  Returns the Newton steps;
    ``lub.upwinding_weight`` is the weight kept (0: the default scheme's film),
    and a weight above 0 stays on the solver until the next film solve.

    Measured on the frozen default band (2.6 um, default floor, two ranks):
    ``lip-dynamic`` at its default 0.1 m/s walked from 1 mm/s in 6 steps, three of
    them failed (1 cm/s, 3.2 and 1.8 mm/s, about 80 s each), 689 s in all; with
    the rescue at 1 cm/s, 2 steps and 299 s, the same film (torque to 1e-10); the
    six speeds of ``bench/lip_sector.py dynamic`` all converged, weight 0
    (docs/scenes/lip-sector.md).

    Raises:
        SolverError: the monotone film did not converge either (both failures named).
    """
    film = lub.problem.film
    _set_sliding_film_state(film, last)
    get_logger().warning("%s: the film did not converge (%s); solved with the discrete "
                         "upwinding, then released", where, failure.what)  # fmt: skip
    attach_discrete_upwinding(solver)
    try:
        its = solver.solve(where=f"{where}: with discrete upwinding").newton_iterations
    except SolverError as e:
        attach_discrete_upwinding(solver, weight=0.0)
        _set_sliding_film_state(film, last)
        raise SolverError(f"{failure.what}; with discrete upwinding: {e.what}", where,
                          e.history) from e  # fmt: skip
    n, lub.upwinding_weight = _release(lub, solver, f"{where} (rescue)")
    if lub.upwinding_weight > 0.0:
        get_logger().warning("%s: the film reported keeps weight %.4g of the discrete "
                             "upwinding (discrete_upwinding_weight)", where,
                             lub.upwinding_weight)  # fmt: skip
    return its + n


def _solve_jfo_film(lub: SectorLip, where: str, solver: Any) -> int:
    film = lub.problem.film
    if film.params.discrete_upwinding:  # for this speed and zone
        attach_discrete_upwinding(solver)
    P0, T0 = _sliding_film_state(film)
    its = 0
    try:
        return solver.solve(where=f"{where}: semismooth").newton_iterations
    except SolverError as e:
        its += e.history.newton_iterations
        get_logger().info("%s: semismooth from the last state failed (%s); pseudo-time steps",
                          where, e.what)  # fmt: skip
    film.P.x.array[:], film.theta_fn.x.array[:] = P0, T0
    try:
        return its + pseudo_transient_solve(film, solver, where)
    except SolverError as e:
        its += e.history.newton_iterations
        get_logger().info("%s: pseudo-time stepping failed (%s); from a full film", where, e.what)
    film.P.x.array[:] = P0
    film.theta_fn.x.array[:] = 1.0
    hist = solver.solve(where=f"{where}: semismooth from a full film")
    return its + hist.newton_iterations


def solve_pressures(lub: SectorLip, params: LipStaticParameters) -> dict[str, Any]:
    """Move the sealed pressures from their current values to those of ``params``:
    one film solve on the frozen lip (``feedback = false``), else the coupled
    problem with adaptive steps from the last converged state."""
    prob = lub.problem
    t0 = time.perf_counter()
    (oil0, air0) = prob.film._edge_values
    target = (params.oil_pressure, params.air_pressure)
    where = f"{prob.name} at oil pressure {target[0]:g} Pa"
    if lub.film_only is not None:
        set_sealed_pressures(lub, *target)
        its = solve_film(lub, where=f"{where} (frozen lip)")
        return {"newton_iterations": its, "pressure_steps": 1,
                "solve_time_s": time.perf_counter() - t0}  # fmt: skip
    prob.ramp_hook = lambda t: set_sealed_pressures(
        lub, oil0 + t * (target[0] - oil0), air0 + t * (target[1] - air0)
    )
    try:
        n0 = len(prob.steps)
        prob.ramp(PRESSURE_STEPS)
        steps = prob.steps[n0:]
    finally:
        prob.ramp_hook = None
    polish = polish_film(lub, where)
    return {
        "newton_iterations": int(sum(s.newton_iterations for s in steps)) + polish,
        "pressure_steps": len(steps),
        "solve_time_s": time.perf_counter() - t0,
    }


def polish_film(lub: SectorLip, where: str) -> int:
    """Finish a converged coupled point with the film alone on its geometry; returns
    the film's Newton steps.

    The coupled Newton stops at the round-off of the whole residual, set by the
    solid's rows; the film rows' flow through the constrictions lies below it (the
    rows are scaled with the zone's gap estimate, the flow through the narrowest
    gaps is ~1e-7 of that scale).  Measured on the default sector's coarse band at
    0.05 MPa: after the coupled solve the oil-side inflow and the leakage differed
    by 2.2e-3 (node by node 2.8e-3), and a further coupled solve on the step
    criterion could not move (residual 9e-14, 60 steps).  The film-only solve
    (:data:`FILM_ONLY_TOLERANCES`) took 2 steps, 0.06 s: the pressure moved by
    1.8e-8 of its maximum, the mass balance went to 2.7e-10 (node by node 5e-9),
    the radial load changed by 1.4e-10, and the coupled solver accepted the result
    at its first residual (6.7e-11).
    """
    if lub.film_polish is None:
        return 0
    fp = lub.problem.film.params
    if fp.discrete_upwinding:  # this lip's, at the coupled point's weight
        weight = lub.upwinding_weight if fp.release_upwinding else 1.0
        attach_discrete_upwinding(lub.film_polish, weight=weight)
    return lub.film_polish.solve(where=f"{where}: film on the converged lip").newton_iterations


#: Passes of the coupled sliding Newton with the discrete upwinding rebuilt at its
#: last state (:func:`_settle_upwinding`): the term depends on the lip.
UPWINDING_PASSES = 8


def _film_blocks(prob: Any) -> tuple[int, int]:
    """The blocks of the film pressure and fraction among the problem's unknowns."""
    film = prob.film
    ids = [i for i, b in enumerate(prob.blocks) if b[1] is film.P or b[1] is film.theta_fn]
    return ids[0], ids[1]


def _settle_upwinding(lub: SectorLip, where: str) -> int:
    """The coupled sliding point with ``film.discrete_upwinding``: the term was built
    on the state the Newton started from, so rebuild it on the converged state and
    solve again until a solve starts converged (at most :data:`UPWINDING_PASSES`);
    returns the Newton steps."""
    prob = lub.problem
    its = 0
    for k in range(UPWINDING_PASSES):
        attach_discrete_upwinding(prob.solver, *_film_blocks(prob))
        n = prob.solver.solve(where=f"{where}: coupled, upwinding pass {k + 1}").newton_iterations
        its += n
        if n == 0:
            return its
    raise SolverError(
        f"the coupled film with film.discrete_upwinding did not settle in "
        f"{UPWINDING_PASSES} passes (the term rebuilt on each converged lip)",
        where,
        history=prob.solver.history,
    )


# ---------------------------------------------------------------- results
def _flows(lub: SectorLip) -> tuple[float, float]:
    """Outflows [m^3/s] through the oil and the air end, whole circumference."""
    q_oil, q_air = lub.problem.film.edge_flows()
    return q_oil * lub.per_revolution, q_air * lub.per_revolution


def nodal_mass_imbalance(lub: SectorLip) -> float:
    """Largest net flow [m^3/s] into one film node of the sector: its mass imbalance.

    The Reynolds rows (unweighted, SI) assembled with the periodic constraint,
    ``K^T R``: a seam node's balance is its master's and its slave's rows together.
    Max over the free, non-slave film nodes.  With
    ``film.discrete_upwinding`` the rows include its term (the film-only solver's
    :attr:`~dolfinx_seal.solvers.NonlinearSolver.linear_term`, pressure rows
    first in its layout; on the coupled lip the polish's, built on the last lip).
    """
    import dolfinx_mpc
    from petsc4py import PETSc

    film = lub.problem.film
    mpc = film.constraints[0]
    b = dolfinx_mpc.assemble_vector(film._flux_form(), mpc)
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    r = b.getArray(readonly=True).copy()
    n = film.S.dofmap.index_map.size_local
    solver = lub.film_only if lub.film_only is not None else lub.film_polish
    if solver is not None and solver.linear_term is not None:
        solver._from_functions(solver.x)
        extra = solver.linear_term.createVecLeft()
        solver.linear_term.mult(solver.x, extra)
        r[:n] += extra.getArray(readonly=True)[:n]
        extra.destroy()
    r /= float(film.row_weight.value)
    slaves = np.asarray(mpc.slaves)
    free = np.setdiff1d(film.film_dofs_local, slaves[slaves < n])
    comm = lub.mesh.comm
    worst = comm.allreduce(float(np.abs(r[free]).max(initial=0.0)), op=MPI.MAX)
    b.destroy()
    return worst


def _by_z(lub: SectorLip, expr: Any) -> tuple[np.ndarray, np.ndarray]:
    """Reference coordinates and lumped P1 values of ``expr`` on the contact band."""
    return lub.problem.surface_values(expr, average=True)


def contact_width(lub: SectorLip) -> tuple[float, float]:
    """Width [m] and centre z [m] of the uniform band with the same asperity force,
    centre and second moment along the axis (as ``lip-install``'s, on the sector)."""
    prob = lub.problem
    fn = prob.asperity_force_integrand()
    z = prob.x[2]
    m0 = prob.integrate(fn, prob.ds_c)
    m1 = prob.integrate(fn * z, prob.ds_c) / m0
    centre = prob.compiled.constant(prob.mesh, "band centre", m1)  # not a literal: one kernel
    var = prob.integrate(fn * (z - centre) ** 2, prob.ds_c) / m0
    return math.sqrt(12.0 * var), m1


def results(lub: SectorLip, params: LipStaticParameters) -> dict[str, Any]:
    """Scalars of a solved point (SI; totals over the circumference)."""
    prob, film = lub.problem, lub.problem.film
    n = lub.per_revolution
    R_s = params.lip.shaft_radius
    ds = prob.ds_c
    load_fluid = prob.integrate(film.normal_force_integrand(), ds) * n
    load_contact = prob.integrate(prob.asperity_force_integrand(), ds) * n
    normal = load_fluid + load_contact
    q_oil, q_air = _flows(lub)
    flow = max(abs(q_oil), abs(q_air))
    nodal = nodal_mass_imbalance(lub)
    vals = film.film_values()
    gap, p = vals["gap"], vals["p"]
    _, pc = _by_z(lub, prob.p_cont)
    width, z_c = contact_width(lub)
    A = area_fraction(prob.p_cont, film.e_star, film.rms_slope)
    real = prob.integrate(A * film.da, ds) * n
    nominal = 2.0 * math.pi * R_s * width
    band_area = prob.integrate(film.da, ds) * n
    floored = film.floored()
    floored_load = prob.integrate(floored * film.normal_force_integrand(), ds) * n
    parts = {k: prob.integrate(v, ds) * n for k, v in film.friction_parts().items()}
    torque = R_s * sum(parts.values())
    out: dict[str, Any] = {
        "speed": float(params.film.speed),
        "oil_pressure": params.oil_pressure,
        "air_pressure": params.air_pressure,
        "leakage_rate": q_air,
        "leakage_ml_per_h": q_air * ML_PER_H,
        "oil_side_inflow": -q_oil,
        "mass_balance_error": abs(q_oil + q_air) / flow if flow > 0 else 0.0,
        "nodal_mass_balance_error": nodal / (flow / n) if flow > 0 else 0.0,
        "mass_imbalance": abs(q_oil + q_air),
        "nodal_mass_imbalance": nodal,
        "radial_load": normal / (2.0 * math.pi * R_s),
        "normal_load": normal,
        "load_fluid": load_fluid,
        "load_contact": load_contact,
        "fluid_load_fraction": load_fluid / normal,
        "contact_width": width,
        "z_contact_centre": z_c,
        "h_min": float(gap.min()),
        "mean_separation": prob.integrate(film.g * film.da, ds) * n / band_area,
        "max_fluid_pressure": float(p.max()),
        "floored_area_fraction": prob.integrate(floored * film.da, ds) * n / band_area,
        "floored_fluid_load_fraction": floored_load / load_fluid if load_fluid else 0.0,
        "max_contact_pressure": float(pc.max()),
        "real_contact_area": real,
        "contact_area_fraction": real / nominal,
        "friction_torque": torque,
        **{f"friction_torque_{k}": R_s * v for k, v in parts.items()},
        "mu": sum(parts.values()) / normal,
        "sector_angle": lub.angle,
        "dofs": prob.dofs,
        "dof_counts": prob.dof_counts(),
        "periodic_slaves": _slaves(prob),
        "ranks": world().size,
        **lub.roughness.info(),
        **lub.installed,
    }
    if film.has_theta:
        cav = _cavitated_area(lub)
        out["cavitation_fraction"] = cav / band_area
        out["suction_load_fraction"] = suction_load_fraction(lub)
        out.update(_cavitation_place(lub, z_c))
    if film.has_couette:
        out.update(_sliding_results(lub, params, band_area))
    if film.has_theta and film.has_couette:  # lip-dynamic (lip-static refuses the term)
        out["discrete_upwinding_weight"] = lub.upwinding_weight
    out.update(factor_memory(lub))
    if prob.control == "force":  # lift = true: how far the film lifts the lip [m]
        out["lip_lift"] = R_s - prob.counter_position()
    return out


def suction_load_fraction(lub: SectorLip) -> float:
    """The film's pull on the lip from pressures below the cavitation pressure 0, over
    its push from those above (both normal to the shaft).

    The JFO conditions allow ``p < 0`` only where the film is fully starved
    (``theta = 0``), and the default transport scheme, which is not monotone,
    produces such nodes (docs/stability.md, the fine shaft: 42 % at 1e-4 m/s, more
    than the push from 1 cm/s); a monotone scheme (``film.discrete_upwinding``)
    does not.  ``inf`` when the film only pulls.
    """
    prob, film = lub.problem, lub.problem.film
    push = prob.integrate(film.normal_force_integrand("push"), prob.ds_c)
    pull = -prob.integrate(film.normal_force_integrand("suction"), prob.ds_c)
    if push > 0.0:
        return max(pull, 0.0) / push
    return math.inf if pull > 0.0 else 0.0


def factor_memory(lub: SectorLip) -> dict[str, float]:
    """MUMPS memory of the factorisations of the sector's solvers (the coupled
    problem's and the film solver's) [MB]: ``factor_memory_mb``, what they hold
    now (:meth:`~dolfinx_seal.solvers.NonlinearSolver.factor_memory_mb`), and
    ``factor_memory_peak_mb``, the sum of each solver's largest at the end of a
    solve (the dry stage's for a frozen lip, whose problem solver is freed once
    the film alone is solved), both summed over the ranks;
    ``factor_memory_peak_rank_mb``, the same sum of each solver's largest rank
    (at least the largest rank's share).  Empty before any factorisation."""
    solvers = [s for s in (lub.problem.solver, lub.film_only, lub.film_polish) if s is not None]
    held = [m for m in (s.factor_memory_mb() for s in solvers) if m is not None]
    peak = [s.peak_factor_memory_mb for s in solvers]
    if not held and not any(m[1] for m in peak):
        return {}
    return {
        "factor_memory_mb": sum(m[1] for m in held),
        "factor_memory_peak_mb": sum(m[1] for m in peak),
        "factor_memory_peak_rank_mb": sum(m[0] for m in peak),
    }


def dimensionless_speed(params: LipStaticParameters, speed: float) -> float:
    """S0's reduced sliding speed ``U~ = 6 eta U lambda_0 / (2 G h_rms^2)`` (S0 eq 14;
    G = E / (2 (1 + nu)) the shear modulus, h_rms of the whole spectrum)."""
    m = params.material
    G = m.E / (2.0 * (1.0 + m.nu))
    return (
        6.0
        * params.film.viscosity
        * speed
        * params.wavelength
        / (2.0 * G * params.roughness.h_rms**2)
    )


#: a counter-gradient axial flux counts where it exceeds this fraction of the band's
#: mean |q_z| (:func:`_sliding_results`)
COUNTER_FLUX_FLOOR = 1e-6


def _sliding_results(
    lub: SectorLip, params: LipStaticParameters, band_area: float
) -> dict[str, Any]:
    """``dimensionless_speed``, ``pumping_rate`` (at equal sealed pressures: the flow
    from the air side to the oil side, positive for a seal that pumps back) and
    ``counter_gradient_fraction`` (with a pressure drop: the band area whose axial
    flux runs from the air side to the oil side, against the drop, S0 fig 12; a
    flux below :data:`COUNTER_FLUX_FLOOR` of the mean |q_z| counts as none)."""
    from dolfinx_seal.scenes.lip_sector_maps import band_quantities

    prob = lub.problem
    speed = float(prob.film.speed.value)
    out: dict[str, Any] = {"dimensionless_speed": dimensionless_speed(params, speed)}
    _, q_air = _flows(lub)
    if params.oil_pressure == params.air_pressure:
        out["pumping_rate"] = -q_air
    else:
        qz = band_quantities(lub)["flux_axial"]
        sign = 1.0 if params.oil_pressure > params.air_pressure else -1.0
        # where the film is cavitated (p = 0) and the shaft slides along the
        # circumference the axial flux is zero but for round-off, whose sign is
        # noise (counted, it moved the fraction by 2 % between 1 and 2 ranks): only
        # a counter flux above 1e-6 of the band's mean |q_z| counts
        mean_abs = prob.integrate(abs(qz) * prob.film.da, prob.ds_c) * lub.per_revolution
        floor = COUNTER_FLUX_FLOOR * mean_abs / band_area
        against = ufl.conditional(ufl.lt(sign * qz, -floor), 1.0, 0.0)
        area = prob.integrate(against * prob.film.da, prob.ds_c) * lub.per_revolution
        out["counter_gradient_fraction"] = area / band_area
    return out


def _slaves(prob: SolidContactProblem) -> int:
    """Global number of slave dofs of the periodic constraints."""
    comm = prob.mesh.comm
    total = 0
    for c in prob.constraints or []:
        if c is None:
            continue
        n = c.function_space.dofmap.index_map.size_local * c.function_space.dofmap.index_map_bs
        s = np.asarray(c.slaves)
        total += comm.allreduce(int(np.sum(s < n)), op=MPI.SUM)
    return total


def _cavitated_area(lub: SectorLip) -> float:
    film = lub.problem.film
    cav = ufl.conditional(ufl.lt(film.theta_fn, 1.0 - 1e-8), 1.0, 0.0)
    return lub.problem.integrate(cav * film.da, lub.problem.ds_c) * lub.per_revolution


def _cavitation_place(lub: SectorLip, z_centre: float) -> dict[str, float]:
    """Where the film is cavitated (S0 fig 11), over the cavitated area (nothing
    without cavitation):

    * ``cavitation_axial_offset`` [m]: its axial centroid (current ``z``) from the
      contact's centre ``z_centre``, positive towards the air side (``z > 0``): S0's
      zones start on the low-pressure side and grow towards the high-pressure side;
    * ``cavitation_divergent_fraction`` [-]: the part of it where the gap opens along
      the sliding (``U dg/dx_1 > 0``, the trailing side of an asperity), where a
      film the shaft drags along loses pressure.
    """
    prob, film = lub.problem, lub.problem.film
    cav = ufl.conditional(ufl.lt(film.theta_fn, 1.0 - 1e-8), 1.0, 0.0) * film.da
    area = prob.integrate(cav, prob.ds_c)
    if area <= 0.0:
        return {}
    e_theta = prob.counter.sliding_direction(prob.x)
    opening = float(np.sign(film.speed.value)) * ufl.dot(film.surface_grad(film.g), e_theta)
    divergent = ufl.conditional(ufl.gt(opening, 0.0), 1.0, 0.0)
    z = prob.integrate(cav * prob.x[2], prob.ds_c) / area
    return {
        "cavitation_axial_offset": z - z_centre,
        "cavitation_divergent_fraction": prob.integrate(cav * divergent, prob.ds_c) / area,
    }


# ---------------------------------------------------------------- run, sweep
def solve_point(lub: SectorLip, params: LipStaticParameters) -> dict[str, Any]:
    """Dry equilibrium with the roughness, then the sealed pressures, then (sliding)
    the shaft speed (:func:`pressurise_sliding`); the results."""
    t0 = time.perf_counter()
    dry = solve_dry(lub, params)
    if lub.problem.film.has_couette:
        sp = pressurise_sliding(lub, params, params.film.speed)
        pr = {"pressure_steps": sp["pressure_steps"], "newton_iterations": 0}
    else:
        pr = solve_pressures(lub, params)
        sp = solve_speed(lub, params)
    res = results(lub, params)
    res.update(dry)
    res.update(pressure_steps=pr["pressure_steps"], speed_steps=sp["continuation_steps"],
               newton_iterations=(dry["dry_newton_iterations"] + pr["newton_iterations"]
                                  + sp["newton_iterations"]),
               solve_time_s=time.perf_counter() - t0, converged=True)  # fmt: skip
    return res


#: m/s: the sliding sector is pressurised at this shaft speed (or slower), where
#: the Couette flux is a small part of the static film's
START_SPEED = 1e-3
#: m/s: the lifting sector (``lift``) is pressurised at this speed (or slower) with
#: the shaft at its radius and released there: on the default band the film then
#: carries what it carries at rest (fluid load fraction 0.054 against 0.050 at
#: 1e-6 m/s, radial load 151.0 N/m as at rest), where at 1e-4 m/s the held lip
#: already carried 13 % more radial load (171 N/m) through its compressed tip
LIFT_START_SPEED = 1e-5

#: the walk in log10 of the shaft speed from the start speed to a target and between
#: the points of a speed sweep [decades]: a target within a decade is tried in one
#: step, a failed step is halved, given up below 1/32 decade.  Measured on the coarse
#: two-scale sector at 0.05 MPa from 1 mm/s: 1e-2, 0.1, 1 m/s each reached in one
#: step (102, 180 and 4 Newton steps, pseudo-time where the semismooth Newton cycled)
SPEED_WALK = StepControl(first=1.0, grow=2.0, easy=None, cut=0.5, min_step=1.0 / 32.0,
                         max_step=1.0)  # fmt: skip


def lifts(params: Any) -> bool:
    """Whether the film may lift the lip as a whole (``lip-dynamic`` with ``feedback``
    and ``lift``): the shaft radius is then an unknown with the load equation."""
    return bool(getattr(params, "lift", False) and params.feedback)


def start_speed(speed: float, lift: bool = False) -> float:
    """The shaft speed [m/s] a sliding sector is pressurised at before it walks to
    ``speed``: :data:`START_SPEED`, or :data:`LIFT_START_SPEED` for a lip that
    lifts (it is released at the radial load it carries there)."""
    return min(speed, LIFT_START_SPEED if lift else START_SPEED)


#: The coupled sliding Newton (``feedback = true``): the fixed-pattern semismooth
#: Newton, each step projected onto the bounds (``project_step``), no divergence test,
#: at most 25 steps; with full steps first, then with a backtracking line search
#: (:data:`COUPLED_LINE_SEARCHES`).  Measured on the default band (2.6 um, two ranks)
#: at 8e-5 m/s from the converged 4e-5 m/s point: the Jacobian agrees with central
#: differences of the residual (errors falling as eps^2) and the Newton step is
#: solved to 1e-14, yet unprojected the full step (``basic``) 2-cycles between 5.3e-6
#: and 3.1e-2 and ``bt`` stalls at 1.7e-6: one film node at a resolved asperity
#: (theta = 0.99999, p = 0) is stepped to theta = 1.032, and the natural residual
#: ``theta - 1`` of that overshoot is 2e4 times the rest.  Projected, ``basic`` stops
#: at 2.9e-7 in 25 steps and ``bt`` converges in 5 (7.0e-6 -> 9.5e-11).  On the
#: coarse band ``bt`` alone failed at 1 m/s, where the full steps' pseudo-time
#: fallback converges (with ``bt`` its first pseudo-time step failed), hence full
#: steps first.  A solve that converges with neither goes to the pseudo-time
#: fallback (with a cap of 150, then 40 steps, a failed solve cost 65 s, then 20 s,
#: on the coarse band).  No divergence test: the first step from the frozen film's
#: state may raise the residual (8.8e-6 -> 0.11 on the coarse band at 1e-4 m/s).
COUPLED_SLIDING_OPTIONS = {"dtol": 1e300, "max_it": 25, "project_step": True}
#: the coupled Newton's line searches, tried in turn from the film predictor's state
#: before the pseudo-time fallback (which takes full steps)
COUPLED_LINE_SEARCHES = ("basic", "bt")

#: Newton steps per line search of the coupled Newton from the path's tangent
#: (``tangent``), against :data:`COUPLED_SLIDING_OPTIONS`'s 25 from the film
#: predictor.  The converged tangent steps measured took at most 12 per line
#: search (the lifting default band and the coarse band); with 15, the lifting
#: default band's 8 mm/s point (floor 0.1, ``film.discrete_upwinding``, two
#: ranks) took 380 s against 458 s, the same point (torque to 1e-10).
TANGENT_NEWTON_STEPS = 15


def solve_sliding(lub: SectorLip, where: str) -> int:
    """The sliding film at the current shaft speed and sealed pressures, from the
    last converged state; returns the Newton steps.

    Frozen lip (``feedback = false``): :func:`solve_film`.  Coupled (``feedback =
    true``): with ``tangent`` and the last converged coupled point known (the
    walk's last accepted state, at another speed), the coupled semismooth Newton
    from the path's tangent there (:func:`_coupled_from_tangent`); if that fails,
    or without it, from the film predictor (:func:`_coupled_from_film`).  With
    ``film.discrete_upwinding`` the term is then rebuilt on the converged lip
    until a solve starts converged (:func:`_settle_upwinding`) and, with
    ``film.release_upwinding``, released; then :func:`polish_film`.  Where the
    film predictor's chain fails too, S0's partitioned scheme from the last
    converged point (:func:`_coupled_partitioned`).
    """
    if lub.film_only is not None:
        return solve_film(lub, where=f"{where} (frozen lip)")
    prob = lub.problem
    speed = float(prob.film.speed.value)
    solver = prob.solver
    upwinding = prob.film.params.discrete_upwinding
    last = lub.sliding_point  # kept when this step fails: the walk restores that state
    start = prob.state()
    its = 0
    with solver.switched(snes_type="semismooth", **COUPLED_SLIDING_OPTIONS):
        converged = False
        if lub.tangent and last is not None and last[0] != speed and _is_state(prob, last[1]):
            n, converged = _coupled_from_tangent(lub, where, last[0])
            its += n
            if not converged:
                get_logger().info("%s: the coupled Newton from the tangent at %g m/s failed; "
                                  "from the film on the current lip", where, last[0])  # fmt: skip
                prob.restore(last[1])
        if not converged:
            try:
                its += _coupled_from_film(lub, where)
            except SolverError as e:
                get_logger().info("%s: the film predictor's chain failed (%s); S0's "
                                  "partitioned scheme", where, e.what)  # fmt: skip
                n, converged, why = _coupled_partitioned(lub, where, start)
                its += n
                if not converged:
                    raise SolverError(f"{e.what}; the partitioned scheme: {why}", where,
                                      e.history) from e  # fmt: skip
        if upwinding:
            its += _settle_upwinding(lub, where)
            if prob.film.params.release_upwinding:
                n, lub.upwinding_weight = release_discrete_upwinding(
                    solver, [b[1] for b in prob.blocks], f"{where}: coupled"
                )
                its += n
    its += polish_film(lub, where)
    lub.sliding_point = (speed, prob.state()) if lub.tangent else None
    return its


#: S0's partitioned scheme as the coupled sliding solve's last resort
#: (:func:`_coupled_partitioned`): the film pressure and fraction moved by 0.2 of
#: their change per iteration, until the unrelaxed change of the pressure falls below
#: 1e-5 of its maximum; stopped after 200 iterations, or after 40 in which the
#: change did not halve.  Measured on the lifting default band (floor 0.1,
#: ``film.discrete_upwinding``, ``tangent``, two ranks) from 3 mm/s, where the
#: coupled Newton and its pseudo-time fall into NaNs at 1 cm/s: 87 iterations,
#: 216 s, then the coupled Newton.  Past 1 cm/s (steps of 1/2 to 1/16 of a decade)
#: it stopped after 41 iterations, the change still 2.1 to 0.16, not halved in 40
#: (docs/scenes/lip-sector.md).
PARTITIONED_FALLBACK = PartitionedOptions(relaxation=0.2, tol=1e-5, max_iterations=200,
                                          stall_iterations=40)  # fmt: skip
#: the lip's solves in the partitioned scheme (the film frozen): plain Newton to 1e-9
#: relative; the coupled Newton that follows takes the point to its own tolerance
PARTITIONED_LIP_OPTIONS = {"rtol": 1e-9, "max_it": 40}


def _coupled_partitioned(lub: SectorLip, where: str, start: list[Any]) -> tuple[int, bool, str]:
    """The coupled sliding point by S0's partitioned scheme from the problem's state
    ``start`` (the last converged point; :data:`PARTITIONED_FALLBACK`), then the
    coupled Newton from its fixed point (:func:`_coupled_newton`);
    ``(Newton steps, converged, why not)``, ``start`` restored when it fails.

    Each iteration: the film alone on the frozen lip (:func:`solve_film` with
    ``lub.film_polish`` and its fallbacks, the shaft held), the film pressure and
    fraction under-relaxed, then the lip alone with the film frozen: displacement
    and, for a lifting lip, the shaft radius with the load equation, in the
    periodic constraints
    (:class:`~dolfinx_seal.coupled.partitioned.PartitionedSolver`, ``position =
    "solid"``).  The converged fixed point is the coupled point; the coupled
    Newton takes it to the coupled solver's tolerance.
    """
    prob = lub.problem
    prob.restore(start)
    ps = PartitionedSolver(
        prob, position="solid", solid_options=PARTITIONED_LIP_OPTIONS,
        film_step=lambda at: solve_film(lub, at, solver=lub.film_polish, release=False),
    )  # fmt: skip
    try:
        rep = ps.solve(PARTITIONED_FALLBACK, where=where)
    except SolverError as e:
        prob.restore(start)
        return 0, False, e.what
    finally:
        ps.destroy()
    its = rep.newton_film + rep.newton_solid
    o = PARTITIONED_FALLBACK
    get_logger().info("%s: partitioned scheme %s after %d iterations (%.1f s), change %.2e",
                      where, "converged" if rep.converged else "stopped", rep.iterations,
                      rep.wall_time_s, rep.changes[-1])  # fmt: skip
    if not rep.converged:
        prob.restore(start)
        return its, False, (f"not converged after {rep.iterations} iterations (relaxation "
                            f"{o.relaxation:g}; last relative pressure change "
                            f"{rep.changes[-1]:.2e}, tolerance {o.tol:g})")  # fmt: skip
    if prob.film.params.discrete_upwinding:  # the term of the partitioned point's lip
        attach_discrete_upwinding(prob.solver, *_film_blocks(prob))
    n, converged = _coupled_newton(lub, f"{where}: from the partitioned point", prob.state())
    if not converged:
        prob.restore(start)
        return its + n, False, "the coupled Newton from its fixed point failed"
    return its + n, True, ""


def _is_state(prob: Any, state: list[Any]) -> bool:
    """Whether the problem's unknowns are ``state`` (a :meth:`state` copy), on every rank."""
    same = all(np.array_equal(a, b) for a, b in zip(prob.state(), state, strict=True))
    return bool(prob.mesh.comm.allreduce(same, op=MPI.LAND))


def _coupled_newton(
    lub: SectorLip, where: str, start: list[Any], max_it: int | None = None
) -> tuple[int, bool]:
    """The coupled semismooth Newton from the problem's state ``start``, with each of
    :data:`COUPLED_LINE_SEARCHES` in turn (``start`` restored after a failure), at
    most ``max_it`` steps each (None: :data:`COUPLED_SLIDING_OPTIONS`'s);
    ``(Newton steps, converged)``."""
    prob, solver = lub.problem, lub.problem.solver
    its = 0
    cap = {} if max_it is None else {"max_it": max_it}
    for line_search in COUPLED_LINE_SEARCHES:
        try:
            with solver.switched(line_search=line_search, **cap):
                hist = solver.solve(where=f"{where}: coupled ({line_search})")
            return its + hist.newton_iterations, True
        except SolverError as e:
            its += e.history.newton_iterations if e.history else 0
            get_logger().info("%s: coupled Newton (%s line search) failed (%s)", where,
                              line_search, e.what)  # fmt: skip
            prob.restore(start)
    return its, False


def _coupled_from_tangent(lub: SectorLip, where: str, last_speed: float) -> tuple[int, bool]:
    """The coupled point at the current speed by the coupled Newton
    (:func:`_coupled_newton`) from the first-order prediction along the path's
    tangent ``dx/d ln U`` at the converged point at ``last_speed`` [m/s] (the current
    state: :func:`~dolfinx_seal.coupled.continuation.path_tangent`, with the
    semismooth active set and the discrete upwinding's term of that lip);
    ``(Newton steps, converged)``.

    The lip and the film move together, as the path does.  The film predictor
    (:func:`_coupled_from_film`) solves the film alone at the new speed on the old
    lip, where it builds pressures the lip then yields to; on the lifting default
    band (2.6 um, floor 0.1 with ``film.discrete_upwinding``, two ranks) that walk
    from 3 mm/s crept to 8.6 mm/s and was still failing its steps towards 1 cm/s
    after 29 minutes; from the tangent it reached 8.6 mm/s 8 minutes after 3 mm/s
    (docs/scenes/lip-sector.md).  The Newton is capped at
    :data:`TANGENT_NEWTON_STEPS` per line search: a tangent that does not bring
    Newton to the point in that many steps hands over to the film predictor sooner.
    """
    prob = lub.problem
    if prob.film.params.discrete_upwinding:  # the term of the converged lip
        attach_discrete_upwinding(prob.solver, *_film_blocks(prob))
    speed = float(prob.film.speed.value)
    tangent = path_tangent(prob, last_speed)
    try:
        tangent_predictor(prob, tangent, speed)
    finally:
        tangent[1].destroy()
    return _coupled_newton(lub, f"{where}: from the tangent", prob.state(),
                           max_it=TANGENT_NEWTON_STEPS)  # fmt: skip


def _coupled_from_film(lub: SectorLip, where: str) -> int:
    """The coupled point at the current speed from the film predictor; returns the
    Newton steps.

    1. The film alone on the current lip at the new speed (:func:`solve_film` with
       ``lub.film_polish``: the film's own fallback chain finds the cavitated zones);
    2. the coupled semismooth Newton from that state (:func:`_coupled_newton`: each
       step projected onto the bounds, with full steps, then with a backtracking
       line search, :data:`COUPLED_SLIDING_OPTIONS`);
    3. if both fail, pseudo-time steps of the coupled film from the predicted state
       (every unknown restored on a failed step).

    Measured on the coarse two-scale sector (5.2 um band, 0.05 MPa, two ranks): from
    1e-4 m/s straight to 1e-3 m/s without the film predictor the coupled Newton ran
    32 steps into a NaN; with it, 184 film steps (its pseudo-time fallback) and 3
    coupled steps; 1e-2 m/s: 62 and 4.
    """
    prob = lub.problem
    its = solve_film(lub, where=f"{where}: film on the current lip", solver=lub.film_polish,
                     release=False)  # fmt: skip
    if prob.film.params.discrete_upwinding:
        attach_discrete_upwinding(prob.solver, *_film_blocks(prob))
    n, converged = _coupled_newton(lub, f"{where}: from the film on the current lip",
                                   prob.state())  # fmt: skip
    its += n
    if converged:
        return its
    get_logger().info("%s: pseudo-time steps of the coupled film", where)
    return its + pseudo_transient_solve(prob.film, prob.solver, f"{where}: coupled",
                                        unknowns=[b[1] for b in prob.blocks])  # fmt: skip


def _sliding_film_state(film: Any) -> tuple[np.ndarray, np.ndarray]:
    """A copy of the JFO film's unknowns (pressure, film fraction)."""
    return film.P.x.array.copy(), film.theta_fn.x.array.copy()


def _set_sliding_film_state(film: Any, state: tuple[np.ndarray, np.ndarray]) -> None:
    film.P.x.array[:], film.theta_fn.x.array[:] = state


def _sliding_state(lub: SectorLip) -> Any:
    """What a speed step changes: the film (frozen lip) or every unknown (coupled)."""
    if lub.film_only is None:
        return lub.problem.state()
    return _sliding_film_state(lub.problem.film)


def _set_sliding_state(lub: SectorLip, state: Any) -> None:
    if lub.film_only is None:
        lub.problem.restore(state)
        return
    _set_sliding_film_state(lub.problem.film, state)


def speed_walker(lub: SectorLip, on_accept: Any = None) -> AdaptiveWalk:
    """The sliding film's walk in log10 of the shaft speed (:data:`SPEED_WALK`; each
    step a :func:`solve_sliding` from the last converged state)."""
    film = lub.problem.film
    return AdaptiveWalk(
        SPEED_WALK, film.set_speed,
        lambda v: solve_sliding(lub, where=f"{lub.problem.name} at {v:g} m/s"),
        lambda: _sliding_state(lub), lambda s: _set_sliding_state(lub, s),
        coordinate=AdaptiveWalk.log_speed(1.0), on_accept=on_accept,
        name=f"{lub.problem.name}: speed walk",
    )  # fmt: skip


def pressurise_sliding(lub: SectorLip, params: LipStaticParameters, speed: float) -> dict[str, Any]:
    """The sliding film (``lip-dynamic``, frozen or coupled: :func:`solve_sliding`) at
    the sealed pressures of ``params`` and the shaft speed ``speed`` [m/s], from the
    dry state: the film at the sealed pressures at :func:`start_speed`, then walked
    up to ``speed`` (:func:`speed_walker`).

    Why this order (measured on the two-scale sector, 0.05 MPa):

    * At :data:`START_SPEED` with the pressure difference the film is well posed:
      the pressurised zone reaches every streamline, and the film is the same
      whichever way it is reached (1.7120e-13 m^3/s directly and walked down from
      1 m/s).  Set at once on a fast shaft, the cavitated zones must move across
      the band in one solve and the active set cycles (the step 1 mm/s -> 1.5 mm/s
      failed before the pseudo-time fallback; 1 -> 10 -> 100 mm/s -> 1 m/s now
      converge).
    * With equal sealed pressures first, a periodic band's streamlines that never
      meet a pressurised zone may carry any amount of oil (``g theta`` constant
      along them): the film is not unique and its Newton matrix is singular there.
      That start converged on the coarse band (5.2 um) but not on the default band
      (2.6 um, two ranks: 150 semismooth steps, pseudo-time stalled at 1e3 t_e,
      and from a full film), so it is not used.

    Raises:
        SolverError: naming the speed reached (``partial``).
    """
    film = lub.problem.film
    t0 = time.perf_counter()
    name = lub.problem.name
    v0 = start_speed(speed, lifts(params))
    set_sealed_pressures(lub, params.oil_pressure, params.air_pressure)
    film.set_speed(v0)
    its = solve_sliding(lub, where=f"{name} at {v0:g} m/s")
    if lifts(params):
        load = lub.problem.release_position()
        get_logger().info("%s: the lip released at %g m/s, radial load %.6g N/m", name, v0,
                          load / (lub.problem.position0 * lub.angle))  # fmt: skip
    walk = solve_speed(lub, set_parameter(params, "film.speed", speed))
    its += walk["newton_iterations"]
    return {"newton_iterations": its, "pressure_steps": 1,
            "continuation_steps": walk["continuation_steps"],
            "speed_time_s": time.perf_counter() - t0}  # fmt: skip


def solve_speed(lub: SectorLip, params: LipStaticParameters) -> dict[str, Any]:
    """The sliding film walked from the last solved state to ``film.speed``
    (:func:`speed_walker`); nothing at zero speed or at the speed already solved.

    Raises:
        SolverError: naming the speed reached (``partial``).
    """
    film = lub.problem.film
    target = params.film.speed
    v0 = float(film.speed.value)
    if not film.has_couette or v0 == target:
        return {"newton_iterations": 0, "continuation_steps": 0}
    t0 = time.perf_counter()
    res = speed_walker(lub).walk(v0, target)
    if not res.converged:
        lip = "frozen lip" if lub.film_only is not None else "coupled"
        raise SolverError(
            f"the speed walk from {v0:g} m/s: {res.error}",
            where=f"{lub.problem.name} on the way to {target:g} m/s ({lip})",
            history=res.last_error.history if res.last_error else None,
            partial={"speed": res.reached},
        )  # fmt: skip
    return {"newton_iterations": res.newton_iterations, "continuation_steps": res.steps,
            "speed_time_s": time.perf_counter() - t0}  # fmt: skip


def run(params: LipStaticParameters, out: Path) -> dict[str, Any]:
    """Install, cut the sector, bring in the roughness, pressurise; write the maps
    and ``fields.xdmf``."""
    from dolfinx_seal.scenes.lip_sector_maps import write_maps

    t0 = time.perf_counter()
    lub = build(params)
    try:
        res = solve_point(lub, params)
        res["wall_time_s"] = time.perf_counter() - t0
        write_maps(out, lub, params)
    finally:
        lub.destroy()
    return res


SWEEPABLE = ("oil_pressure", "film.speed")


def sweep(
    params: LipStaticParameters, out: Path, name: str, values: list[float], on_point: Any
) -> list[dict[str, Any]]:
    """Over ``oil_pressure``: one sector, each point from the last (ascending); over
    ``film.speed`` (``lip-dynamic``): one sector pressurised at the slowest speed,
    then walked up through the others (:func:`_speed_sweep`; each target
    converged or recorded in ``sweep_failures.csv``); over any other parameter:
    each point built and solved afresh (a failed one is recorded and the sweep
    goes on)."""
    from dolfinx_seal.scenes.lip_sector_maps import write_maps

    rows: list[dict[str, Any]] = []
    if name == "film.speed":
        return _speed_sweep(params, out, values, on_point)
    if name not in SWEEPABLE:
        for v in values:
            pv = set_parameter(params, name, v)
            t0 = time.perf_counter()
            try:
                r = run(pv, out / f"{name}_{v:.4g}")
            except SolverError as e:
                get_logger().error("%s: %s = %g failed: %s", params.scene_name, name, v, e)
                continue
            r["wall_time_s"] = time.perf_counter() - t0
            rows.append(r)
            on_point(v, r)
        return rows
    lub = build(params)
    try:
        t0 = time.perf_counter()
        dry = solve_dry(lub, set_parameter(params, "oil_pressure", 0.0))
        for v in sorted(float(x) for x in values):
            pv = set_parameter(params, name, v)
            t1 = time.perf_counter()
            info = solve_pressures(lub, pv)
            r = results(lub, pv)
            r.update(info, **(dry if not rows else {}), converged=True,
                     wall_time_s=time.perf_counter() - (t0 if not rows else t1))  # fmt: skip
            rows.append(r)
            if on_point(v, r):
                write_maps(out / f"oil_pressure_{v:.3e}", lub, pv, fields=False)
    finally:
        lub.destroy()
    return rows


def _speed_sweep(
    params: LipStaticParameters, out: Path, values: list[float], on_point: Any
) -> list[dict[str, Any]]:
    """The speed sweep of ``lip-dynamic`` (:func:`sweep`): the film pressurised at the
    slowest speed (:func:`pressurise_sliding`), then walked up through the others in
    log10 of the speed (:func:`speed_walker`, each step from the last converged
    film).  A speed the walk does not reach is recorded in ``sweep_failures.csv``
    and the walk goes on to the next one from the last converged film; once
    ``stepping.time_budget`` is spent, the speed under way and the rest are
    recorded there too (stopped, not attempted)."""
    from dolfinx_seal.output import write_sweep_failures
    from dolfinx_seal.scenes.lip_sector_maps import write_maps

    speeds = sorted({float(v) for v in values})
    first_p = set_parameter(params, "film.speed", speeds[0])  # refuses a speed <= 0
    for v in speeds[1:]:
        set_parameter(params, "film.speed", v)
    rows: list[dict[str, Any]] = []
    failed: list[dict[str, Any]] = []
    lub = build(first_p)
    try:
        t0 = time.perf_counter()
        dry = solve_dry(lub, first_p)
        try:
            pr = pressurise_sliding(lub, first_p, speeds[0])
        except SolverError as e:
            failed += [{"speed": v, "error": f"not pressurised: {e.what}"} for v in speeds]
            write_sweep_failures(out, failed)
            raise
        first = {**dry, "pressure_steps": pr["pressure_steps"],
                 "newton_iterations": dry["dry_newton_iterations"] + pr["newton_iterations"],
                 "continuation_steps": pr["continuation_steps"]}  # fmt: skip
        counted = {"its": 0, "steps": 0}

        def accepted(_v: float, its: int) -> None:
            counted["its"] += its
            counted["steps"] += 1

        walk = speed_walker(lub, on_accept=accepted)
        film = lub.problem.film
        budget = params.stepping.time_budget
        spent = TimeBudget(budget, lub.mesh.comm if budget else None).spent
        for i, v in enumerate(speeds):
            t1 = time.perf_counter()
            if rows or failed:
                if why := spent():
                    failed += [{"speed": u, "error": f"not attempted: {why}"} for u in speeds[i:]]
                    get_logger().error("%s: sweep stopped at %g m/s: %s", params.scene_name,
                                       float(film.speed.value), why)  # fmt: skip
                    break
                counted.update(its=0, steps=0)
                res = walk.walk(float(film.speed.value), v, stop=spent)
                if not res.converged:
                    error = res.error
                    if res.stopped:
                        error = f"stopped at {float(film.speed.value):.4g} m/s: {res.error}"
                    failed.append({"speed": v, "error": error})
                    get_logger().error("%s: %g m/s not reached: %s", params.scene_name, v,
                                       error)  # fmt: skip
                    continue
                info = {"newton_iterations": counted["its"],
                        "continuation_steps": counted["steps"]}  # fmt: skip
            else:
                info = first
            pv = set_parameter(params, "film.speed", v)
            r = results(lub, pv)
            r.update(info, converged=True,
                     wall_time_s=time.perf_counter() - (t0 if info is first else t1))  # fmt: skip
            rows.append(r)
            if on_point(v, r):
                write_maps(out / f"speed_{v:.3e}", lub, pv, fields=False)
    finally:
        lub.destroy()
    write_sweep_failures(out, failed)
    return rows


def plot_sweep(rows: list[dict[str, Any]], out_dir: Path, name: str) -> None:
    """``sweep.png``: leakage (and the fluid load) against the swept parameter."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x = np.array([r.get(name, r.get("speed")) for r in rows], dtype=float)
    if name == "film.speed":
        fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.0))
        for key, style in (("friction_torque", "ko-"), ("friction_torque_couette", "b^--"),
                           ("friction_torque_asperity", "rs--")):  # fmt: skip
            ax.loglog(x, [abs(r.get(key, np.nan)) for r in rows], style, ms=4, label=key)
        ax.set_xlabel("shaft surface speed [m/s]")
        ax.set_ylabel("friction torque [N m]")
        ax.legend(frameon=False, fontsize=8)
        key = "pumping_rate" if "pumping_rate" in rows[0] else "leakage_rate"
        ax2.semilogx(x, [r[key] for r in rows], "ko-", ms=4)
        ax2.set_xlabel("shaft surface speed [m/s]")
        ax2.set_ylabel(f"{key} [m^3/s]")
    else:
        fig, ax = plt.subplots(figsize=(6.4, 4.0))
        ax.plot(x, [r["leakage_rate"] for r in rows], "ko-", ms=4)
        ax.set_xlabel(name)
        ax.set_ylabel("leakage rate [m^3/s]")
    fig.tight_layout()
    fig.savefig(Path(out_dir) / "sweep.png", dpi=120)
    plt.close(fig)


SCENE = Scene(
    name="lip-static",
    summary="lip seal on a periodic 3D sector with deterministic roughness (S0), zero speed",
    parameters=LipStaticParameters,
    run=run,
    sweep=lambda *a: sweep(*a),
    plot_sweep=lambda *a: plot_sweep(*a),
)
DYNAMIC_SCENE = Scene(
    name="lip-dynamic",
    summary="lip seal sector on a turning shaft (S0): JFO film, friction torque, pumping",
    parameters=LipDynamicParameters,
    run=run,
    sweep=lambda *a: sweep(*a),
    plot_sweep=lambda *a: plot_sweep(*a),
)

__all__ = [
    "DYNAMIC_SCENE",
    "SCENE",
    "LipDynamicParameters",
    "LipStaticParameters",
    "SectorLip",
    "SectorParams",
    "SectorRoughnessParams",
    "build",
    "results",
    "run",
    "solve_dry",
    "solve_pressures",
    "sweep",
    "two_scale",
]
