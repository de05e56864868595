"""Scene ``ball``: a rubber ball sliding on a rigid flat (S1 section 3), lubricated or dry.

3D half ball (symmetry plane ``y = 0``, which contains the sliding direction x)
or the full ball; the S1 figure-18 system by default (R = 1 cm, F = 1.3 N,
E* = 1.6 MPa, nu = 0.5, h_rms = 1 um, D_f = 2.2, eta = 0.1 Pa s).  Persson
asperity contact as a nonlinear traction on the deformed surface, force
control (the flat's position is a global unknown), mixed u-p neo-Hookean bulk.

With ``lubricated = true`` (default) the 2D Reynolds film on the deformed
contact cap (radius ``film_extent`` Hertz radii; zero flux across the
symmetry plane) joins the Newton system (:mod:`dolfinx_seal.film.surface`),
as in the cylinder scene; ``dolfinx-seal sweep ball --over film.speed`` runs
a Stribeck sweep with speed continuation.  Reports mu and its parts, the load
split, h_min, h_central (at the contact centre), x_cavitation (on y = 0),
the cavitated area fraction, max pressures, load and mass balance,
``film_map.csv`` / ``film_map.png`` (pressure, asperity pressure, gap,
cavitation) and ``fields.xdmf``.

Dry (``lubricated = false``, no film unknowns): the total normal load (twice
the half model's), the contact radius from the second moment of the pressure
(``a = (5 <r^2> / 2)^(1/2)``, exact for a Hertz distribution), peak pressure,
the Hertz references, and the pressure along the x axis (``pressure.csv``,
``pressure.png``).

A configuration of :class:`~dolfinx_seal.scenes.lubricated.LubricatedScene`
(run, dry run, sweep, results): this module holds the parameters and the hooks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from dolfinx_seal.contact.hertz import hertz_point
from dolfinx_seal.coupled.continuation import SpeedStepping, speed_sweep, start_coupled
from dolfinx_seal.coupled.results import write_film_map
from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.film.surface import FilmParams
from dolfinx_seal.meshing import TaggedMesh, create_mesh
from dolfinx_seal.params import (
    check_choice,
    check_int_range,
    check_positive,
    check_range,
    check_types,
)
from dolfinx_seal.roughness.psd import RoughnessParams
from dolfinx_seal.scenes.common import ContactLawParams, MaterialParams
from dolfinx_seal.scenes.lubricated import (
    Control,
    LubricatedScene,
    Scales,
    film_snes,
    write_dry_profile,
)
from dolfinx_seal.solid.body import Body, Dirichlet
from dolfinx_seal.solid.counter_surface import Flat
from dolfinx_seal.solid.kinematics import Solid3D
from dolfinx_seal.solid.problem import SolidContactProblem
from dolfinx_seal.solid.step_limits import StepLimits
from dolfinx_seal.solvers import SNESOptions
from dolfinx_seal.verification.ehl import IsoviscousElasticFilm

#: Default elements per Hertz radius at the contact (:attr:`BallParameters.contact_elements`).
CONTACT_ELEMENTS = 20.0
#: Default of :attr:`BallParameters.rim_refinement`.  Measured (5 December, the
#: S1 ball, 2 ranks, 0.3 and 0.1 m/s): h_min of a/20 rose from 7.072 / 3.260 um
#: (no rim) to 7.150 / 3.398 (rim a/40), 7.178 / 3.435 (a/60, this default) and,
#: with a/30 at the contact and the rim at a/90, 7.187 / 3.457 um; the limit,
#: extrapolated at orders 1 to 2, is 3.475-3.50 um at 0.1 m/s, so the default's
#: h_min is 1.2-1.9 % low there, against 6.2-6.9 % without the rim.  mu, h_central
#: and the contact radius move by at most 0.5 %.  Unknowns 89,748 -> 195,069.
RIM_REFINEMENT = 3.0
START_FILM = 4.0  # central film of the start point, in h_rms
#: Default of :attr:`BallParameters.max_start_moes`.
MAX_START_MOES = 500.0
GAP_CLOSURE = 0.5  # a Newton step closes no film gap by more than this fraction of itself


#: Newton steps allowed to one continuation step of the ball's speed walk
#: (``stepping.max_newton``): a step that needs more is halved.  Measured on the
#: 30-speed sweep of ``bench/perf.py`` (2 ranks): the same 118 accepted Newton
#: steps, residual evaluations 569 -> 331, Jacobians 149 -> 138, 542 s -> 469 s,
#: mu, h_central and h_min within 6.4e-8 of the uncapped walk
#: (docs/performance.md).  The start is not capped.
BALL_MAX_NEWTON = 12

#: consecutive Newton steps that each lower the residual by less than 1 % before a
#: continuation step of the ball's speed walk is given up (``stepping.stall_steps``).
#: Measured on the same sweep (2 ranks, 4 December): the last step (0.0117 -> 0.01
#: m/s, the onset of asperity contact) had two attempts stuck at a residual plateau
#: for 5 and 6 steps, which now stop after 3 and 9 Newton steps; the same 118
#: accepted Newton steps, Jacobians 139 -> 130, residuals 343 -> 193, that point
#: 88 s -> 56 s, the sweep 340 s -> 298 s; mu, h_central, h_min within 4.4e-13.
BALL_STALL_STEPS = 2

#: GMRES iterations a linear solve of the ball's coupled Newton (the reduced-space
#: VI, ``p >= 0``) may take before its kept LU is made afresh
#: (``SNESOptions.factor_reuse_its``, through the full pattern; JFO's semismooth
#: Newton keeps a factorisation per step, where it was measured to be no lever).
#: Measured on the 30-speed sweep of ``bench/perf.py`` (2 ranks, 7 December, this
#: machine idle): 112 -> 41 numeric factorisations, 112 -> 115 Newton steps, a
#: continuation point 12.1 -> 9.6 s, the sweep 495 -> 403 s; mu, h_central, h_min
#: within 1.7e-11 of a factorisation every step.  With 20: 20 factorisations and
#: 8.9 s a point, but 122 Newton steps (the last point in 3 continuation steps, 93 s)
#: and 468 s (docs/performance.md).
BALL_FACTOR_REUSE = 8

#: The mesh partition's cost of a cell on the contact cap, in cells, beyond its
#: own (:func:`~dolfinx_seal.meshing.surface_weighted_partition`): the contact
#: surface's integrals (asperity law, film, tractions), assembled apart, took
#: 0.47 s on 3,065 facets at one rank, and the whole Jacobian 0.844 s, so the bulk
#: about 0.37 s on 12,348 cells (the demo mesh, 7 December): about 150 against 30
#: us.  DOLFINx's graph partitioner, which balances cells, left 2,527 of the
#: 3,065 facets on one of 2 ranks.
CONTACT_COST = 5.0


@dataclass(frozen=True)
class BallParameters:
    """Ball on a flat (SI units).

    Attributes:
        radius: Ball radius R [m].
        load: Total normal load F [N] (the half model carries F/2).
        material: Rubber bulk (S1 fig 18: E* = 1.6 MPa, i.e. E = 1.2 MPa at nu = 0.5).
        roughness: Roughness (S1: h_rms 1 um, D_f 2.2).
        contact: Asperity contact law.
        shape: ``half`` (symmetry plane y = 0) or ``full``.
        contact_elements: Elements per Hertz radius at the contact [-]: the contact
            element size is ``a_Hertz / contact_elements`` unless ``h_contact`` is
            given, so a changed load, radius or modulus keeps the film resolved
            (bench/mesh_defaults.py, levels 15 to 30 at 0.3 and 0.1 m/s: mu,
            h_central and the contact radius of the default within 0.4 % of a/30;
            h_min is not resolved to 2 %: -1.1 % and -3.7 % at 0.3 and 0.1 m/s,
            and a/30 still moves 1.7 % from a/25, all without a rim zone; with
            the default rim every output at both speeds is within 0.64 % of
            a/30, h_min 1.2-1.9 % from its extrapolated limit).
        h_contact: Element size at the contact [m] (at most a_Hertz / 4); None
            (default): ``a_Hertz / contact_elements``.
        rim_refinement: Element size at the contact over the element size on the
            rim band ``0.8 a_Hertz <= r <= 1.1 a_Hertz`` [-] (1 to 4; 1: no rim
            zone).  The side lobes of the exit constriction, where h_min sits, lie
            there (r = 0.96-0.97 a_Hertz at 0.3 and 0.1 m/s), and h_min follows the
            element size there (a/10 with an a/20 rim gives a uniform a/20's
            h_min to 0.3 %).  The default (:data:`RIM_REFINEMENT`) puts h_min
            within 2 % of its extrapolated limit at 0.3 and 0.1 m/s, for 2.2x the
            unknowns of no rim (docs/scenes/ball.md, "h_min and the rim").  The
            dry ball has no rim zone (no film, no h_min).
        mesh_order: Geometry order of the mesh: 2 puts the mid-edge nodes on the
            sphere; 1 leaves flat facets whose chord sag ``h^2 / (8 R)`` (0.1 um at
            a/20) is a few per cent of a film of microns.
        mesh_growth: Element size increase per unit depth below the contact surface
            [-] (0 < growth <= 2): 1 keeps the fine film zone a thin layer, so the
            film can be resolved (a/25 at about 1e5 unknowns); the dry-ball studies of
            the README used 0.2.
        degree: Displacement degree.
        lubricated: Solve the film (false: dry contact, no film unknowns).
        film: The lubricant film (speed, viscosity, cavitation model, ...);
            ``film.upstream`` / ``downstream`` are not used (line contacts only).
        film_extent: Radius of the lubricated cap in Hertz radii [-] (S1 uses
            the window [-1.5 a, 1.5 a]^2 for fig 18-29 and [-4 a, 1.5 a] x [-3 a, 3 a]
            for its appendix D); at most 0.9 R / a_Hertz, the mesh's contact cap
            (2.29 at ten times the default load).
        sweep_order: Order of a speed sweep: ``down`` (default: the sweep starts in
            full film, where the hydrodynamic start is robust), ``up``, ``up-down``
            or ``given``.
        stepping: Speed continuation options of sweeps (``film_presolve`` off: the
            ball's figures were measured without it; ``max_newton`` 12 and
            ``stall_steps`` 2: see :data:`BALL_MAX_NEWTON`, :data:`BALL_STALL_STEPS`).
        max_start_moes: Largest Moes load ``M = W U^(-3/4)`` of the first coupled
            solve [-] (10 to 1e5): where ``film.speed`` (or the rough start speed)
            has a larger ``M``, the start is made at the speed where ``M`` is this
            cap, in full film, and walks down to ``film.speed`` (:func:`start_speed`).
            The S1 ball's starts converged at M = 517 and 661 and failed at M = 757
            and 2907 (docs/scenes/ball.md).
    """

    radius: float = 0.01
    load: float = 1.3
    material: MaterialParams = field(default_factory=lambda: MaterialParams(E=1.2e6))
    roughness: RoughnessParams = field(default_factory=RoughnessParams)
    contact: ContactLawParams = field(default_factory=ContactLawParams)
    shape: str = "half"
    contact_elements: float = CONTACT_ELEMENTS
    h_contact: float | None = None
    rim_refinement: float = RIM_REFINEMENT
    mesh_order: int = 2
    mesh_growth: float = 1.0
    degree: int = 2
    lubricated: bool = True
    film: FilmParams = field(default_factory=lambda: FilmParams(speed=0.01))
    film_extent: float = 3.0
    sweep_order: str = "down"
    stepping: SpeedStepping = field(
        default_factory=lambda: SpeedStepping(
            film_presolve=False, max_newton=BALL_MAX_NEWTON, stall_steps=BALL_STALL_STEPS
        )
    )
    max_start_moes: float = MAX_START_MOES

    def __post_init__(self) -> None:
        check_types(self)
        check_positive("radius", self.radius, "m")
        check_positive("load", self.load, "N")
        check_choice("shape", self.shape, ("half", "full"))
        check_int_range("degree", self.degree, 1, 3)
        a, _ = hertz_point(self.load, self.radius, self.material.E_star)
        check_range("contact_elements", self.contact_elements, 4.0, 200.0)
        # on the resolved size: an explicit h_contact, or a / contact_elements (<= a / 4)
        check_range(
            "h_contact", self.element_size, 0.0, a / 4.0, lo_open=True, unit="m (<= a_Hertz/4)"
        )
        check_range("rim_refinement", self.rim_refinement, 1.0, 4.0)
        check_int_range("mesh_order", self.mesh_order, 1, 2)
        check_range("mesh_growth", self.mesh_growth, 0.0, 2.0, lo_open=True)
        check_choice("sweep_order", self.sweep_order, ("up", "down", "up-down", "given"))
        check_range("max_start_moes", self.max_start_moes, 10.0, 1e5)
        if not self.lubricated and self.contact.model == "none":
            raise ParameterError("contact.model = 'none' needs lubricated = true")
        if self.lubricated and self.film.speed == 0.0:
            raise ParameterError(
                "film.speed = 0 m/s: the lubricated ball needs film.speed > 0 (it starts from "
                "a full film and walks down in speed; at zero speed the film carries nothing, "
                "so run the dry contact, lubricated = false)"
            )
        if a > 0.4 * self.radius:
            f_max = self.load * (0.4 * self.radius / a) ** 3  # a ~ F^(1/3)
            raise ParameterError(
                f"load = {self.load!r} N gives a Hertz radius {a:.3g} m > 0.4 R: outside the "
                f"small-contact regime of this scene; allowed range (0, {f_max:.4g}] N at "
                f"radius = {self.radius!r} m and material.E* = {self.material.E_star:.4g} Pa",
                "load",
            )
        # the film cap must fit the mesh's contact cap, at most 0.9 R across (the default
        # 3 Hertz radii does not at ten times the S1 load: a = 0.39 R)
        hi = min(4.5, 0.9 * self.radius / a)
        check_range("film_extent", self.film_extent, 1.5, hi,
                    unit=f"Hertz radii (at most 0.9 R / a_Hertz = {0.9 * self.radius / a:.4g})")  # fmt: skip

    @property
    def element_size(self) -> float:
        """The element size at the contact [m]: ``h_contact``, or the Hertz radius
        over ``contact_elements``."""
        if self.h_contact is not None:
            return self.h_contact
        return hertz_point(self.load, self.radius, self.material.E_star)[0] / self.contact_elements


def scales(p: BallParameters) -> Scales:
    """Hertz point contact: radius, peak pressure, nominal area ``pi a^2``; the half
    model carries half the load."""
    a, p_h = hertz_point(p.load, p.radius, p.material.E_star)
    f = 2.0 if p.shape == "half" else 1.0
    report = {"hertz_contact_radius": a, "hertz_peak_pressure": p_h, "symmetry_factor": f}
    if p.lubricated:
        report["nominal_area"] = math.pi * a**2
    return Scales(length=a, pressure=p_h, nominal_area=math.pi * a**2, approach=a**2 / p.radius,
                  line=False, symmetry_factor=f, report=report)  # fmt: skip


def mesh(p: BallParameters, s: Scales, comm: Any) -> TaggedMesh:
    """The ball mesh; lubricated: the contact cap (radius ``film_extent a``) is the film.
    Every size follows the contact: the cap's elements grow to ``a / 6`` (at least
    twice the contact element), the far field to ``R / 10``."""
    extra: dict[str, Any] = {}
    if p.lubricated:
        extra = dict(cap_extent=p.film_extent, fine_extent=min(1.5, p.film_extent - 0.1))
    h = p.element_size
    if p.lubricated and p.rim_refinement > 1.0:  # where h_min sits
        extra["h_rim"] = h / p.rim_refinement
    h_far = max(2 * h, p.radius / 10)
    return create_mesh(
        "ball", comm=comm, radius=p.radius, shape=p.shape, contact_radius=s.length,
        h_contact=h, h_cap=min(max(2 * h, s.length / 6), h_far), h_far=h_far,
        growth=p.mesh_growth, order=p.mesh_order, balance={"contact": CONTACT_COST}, **extra,
    )  # fmt: skip


def problem(p: BallParameters, tm: TaggedMesh, s: Scales, law: Any, film: Any,
            control: Control) -> SolidContactProblem:  # fmt: skip
    """3D on a flat, loaded on the top face (and ``u_y = 0`` on the symmetry plane).
    Newton steps: half an element; no film gap closed by more than ``GAP_CLOSURE``
    of itself or three decay lengths of the contact law."""
    bcs = [Dirichlet(tm.tag("load"))]
    if p.shape == "half":
        bcs.append(Dirichlet(tm.tag("symmetry"), component=1))
    # backtracking: with full (limited) steps, 0.03 -> 0.018 m/s (a/15) wandered and
    # jumped to a residual 4x the start at step 10; with "bt" it reached 0.01 m/s.
    # (JFO: full steps, film_snes)
    lub = film is not None
    if not lub:
        snes = SNESOptions(max_it=60, dtol=1e12)
    elif p.film.cavitation == "jfo":
        snes = film_snes(p.film, line_search="bt")
    else:
        snes = film_snes(p.film, line_search="bt", factor_reuse_its=BALL_FACTOR_REUSE)
    limits = StepLimits(
        max_step=0.5 * p.element_size,
        max_gap_step=3.0 * law.h_rms / law.alpha if law is not None else None,  # decay lengths
        max_gap_closure=GAP_CLOSURE if lub else None,
    )  # fmt: skip
    return SolidContactProblem(
        tm.mesh, tm.facet_tags, Body(Solid3D(), p.material.build(), bcs, degree=p.degree),
        Flat(axis=2), control, tm.tag("contact"), law=law, film=film, limits=limits, snes=snes,
        name="ball",
    )  # fmt: skip


def film_estimate(p: BallParameters) -> IsoviscousElasticFilm:
    """The Hamrock-Dowson film and Moes number of this ball (smooth, isoviscous)."""
    return IsoviscousElasticFilm(p.radius, p.material.E_star, p.film.viscosity, p.load)


def moes_load(p: BallParameters, speed: float) -> float:
    """Moes' dimensionless load ``M = W U^(-3/4)`` [-] of the ball at the sliding
    speed ``speed`` [m/s] (the flat slides, the ball is at rest: ``u_m = |speed| / 2``)."""
    return film_estimate(p).moes_load(0.5 * abs(speed))


def start_speed(p: BallParameters) -> float:
    """Speed U [m/s] of the first coupled solve, never below ``film.speed``.

    Rough: a hydrodynamic one, where the Hamrock-Dowson central film
    (:mod:`dolfinx_seal.verification.ehl`, u_m = U/2) is ``START_FILM`` h_rms, so
    that the asperities carry little and the Persson law is in its soft tail.
    Smooth (``contact.model = "none"``): ``film.speed``.  Either way at least the
    speed where Moes' ``M`` is ``max_start_moes``: a start in full film, walked down
    to ``film.speed``.  A thin film over the Hertz-deformed shape at high ``M``
    (h_rms 0.1 um at 0.01 m/s, M = 2907: a central film of 14 h_rms) is beyond the
    coupled Newton's reach from the Hertz guess (``DIVERGED_LINE_SEARCH after 2
    Newton steps``), where the start at M = 517 converged and walked down."""
    f = p.film
    hd = film_estimate(p)
    v = f.speed
    if p.contact.model != "none":
        v = max(v, 2.0 * hd.mean_speed_for_central(START_FILM * p.roughness.h_rms))
    return max(v, 2.0 * hd.mean_speed_for_moes(p.max_start_moes))


def film_gap(p: BallParameters) -> float:
    """The gap scale of the film rows and unknowns [m]: ``h_rms``, or a
    :data:`START_FILM`-th of the Hamrock-Dowson central film at :func:`start_speed`
    where that is larger.  For the rough default (``film.speed`` 0.01 m/s) the two
    agree (it starts where the central film is ``START_FILM`` h_rms); a smooth ball at 1 m/s runs
    on a 22 um film, and with its rows scaled at h_rms = 1 um the coupled start
    stalled at a scaled residual of 2.5e-2 (``DIVERGED_LINE_SEARCH``): with the
    film's own scale (a fourth or all of it) it converged in 36 / 31 Newton steps
    to the same state (1e-13)."""
    hd = film_estimate(p)
    return max(p.roughness.h_rms, hd.h_central(0.5 * start_speed(p)) / START_FILM)


def start(prob: SolidContactProblem, p: BallParameters, s: Scales) -> dict[str, Any]:
    """First converged state at ``film.speed``.

    The ball is deformed under the Hertz pressure, the flat placed at the
    Hamrock-Dowson central film of :func:`start_speed`, the fluid pressure set
    to the Hertz pressure and then solved with the flat's position on that frozen
    shape (:func:`~dolfinx_seal.coupled.continuation.film_presolve`), and the
    coupled Newton solved there; then speed continuation (down) to ``film.speed``
    (:func:`~dolfinx_seal.coupled.continuation.start_coupled`).  The
    boundary-lubrication start of the cylinder fails here: at the ball's
    p/E* ~ 0.1 the Persson law sits at separations of ~0.05 h_rms, where the
    gap errors of the Hertz-deformed shape are decades of pressure.
    """
    f = p.film
    v0 = start_speed(p)
    hd = film_estimate(p)
    prob.film.set_speed(v0)
    info = start_coupled(
        prob, v0, v0, p.stepping, "ball", pressure_guess=s.hertz_pressure(prob.X),
        peak_gap=hd.h_central(0.5 * v0), film_guess=True,
    )  # fmt: skip
    if f.speed < v0:
        recs = speed_sweep(prob, [f.speed], lambda *_: None, dict, p.stepping)
        if not recs[-1].converged:
            raise SolverError(
                f"the start at {v0:.3g} m/s (Moes M = {moes_load(p, v0):.3g}) did not come "
                f"down to film.speed = {f.speed:g} m/s (M = {moes_load(p, f.speed):.3g}): "
                f"{recs[-1].error}",
                where="ball start", partial={"speed": float(prob.film.speed.value)},
            )  # fmt: skip
        info["newton_iterations"] += recs[-1].newton_iterations
        info["strategy"] = (f"start at {v0:.3g} m/s (Moes M = {moes_load(p, v0):.3g}), speed "
                            f"continuation ({recs[-1].steps} steps)")  # fmt: skip
    return info


def write_point(out: Path, prob: SolidContactProblem, p: BallParameters) -> None:
    """``film_map.csv`` / ``film_map.png`` over the contact (at most 2 a across)."""
    f = p.film
    rough = f"h_rms = {p.roughness.h_rms * 1e6:g} um" if p.contact.model != "none" else "smooth"
    title = f"ball F = {p.load:g} N, U = {f.speed:.3g} m/s, {rough}, {f.cavitation}"
    write_film_map(out, prob, title, extent=min(p.film_extent, 2.0) * scales(p).length)


def write_dry(out: Path, prob: SolidContactProblem, p: BallParameters,
              s: Scales) -> dict[str, Any]:  # fmt: skip
    """``pressure.csv`` / ``pressure.png`` along the x axis (y = 0) against Hertz."""
    Xs, pc = prob.surface_values(prob.p_cont, average=True)
    on_axis = np.abs(Xs[:, 1]) < 1e-9 * p.radius
    x, pa = Xs[on_axis, 0], pc[on_axis]
    order = np.argsort(x)
    x, pa = x[order], pa[order]
    write_dry_profile(out, s, f"dry ball, F = {p.load:g} N, law: {prob.law.name} (y = 0)", x, pa)
    return {}


BALL = LubricatedScene(
    name="ball",
    summary="rubber ball on a flat (S1 sec 3): 3D soft EHL film + Persson contact, or dry",
    parameters=BallParameters,
    scales=scales, mesh=mesh, problem=problem, start=start, write_point=write_point,
    write_dry=write_dry, film_gap=film_gap, first_speed=start_speed,
)  # fmt: skip
SCENE = BALL.scene
run, run_lubricated, run_dry, sweep = BALL.run, BALL.run_lubricated, BALL.run_dry, BALL.sweep
build_lubricated, start_lubricated, build_dry = (
    BALL.build_lubricated, BALL.start_lubricated, BALL.build_dry
)  # fmt: skip

__all__ = ["BALL", "SCENE", "BallParameters", "build_dry", "build_lubricated", "film_estimate",
           "moes_load", "run", "start_lubricated", "start_speed", "sweep"]  # fmt: skip
