"""Scene ``cylinder``: a rubber cylinder on a rigid flat (S1 section 2), lubricated or dry.

2D plane strain, the S1 figure-4 system by default (R = 1 cm, F/L = 100 N/m,
E = 10 MPa, nu = 0.5, h_rms = 1 um, D_f = 2.2, eta = 0.1 Pa s), Persson
asperity contact as a nonlinear traction on the deformed surface, force
control (the flat's position is a global unknown), neo-Hookean mixed u-p bulk.

With ``lubricated = true`` (default) the 1D Reynolds film on the deformed
contact line (:mod:`dolfinx_seal.film.surface`) joins the Newton system: one
SNES (VI) on displacement, mixed pressure, fluid pressure (and film fraction
for JFO) and the flat's position (``solver = "monolithic"``), or the seeds'
partitioned scheme (``solver = "partitioned"``, :mod:`dolfinx_seal.coupled.partitioned`).
``bulk = false`` makes the cylinder rigid (no displacement unknowns; the
Martin limit).  Only the enabled terms are assembled: a dry run
(``lubricated = false``) has no film unknowns, zero speed no Couette term.

Reports (lubricated): mu and its Couette / Poiseuille / asperity parts, the
load split, h_min, h_central, x_cavitation, max pressures, load and mass
balance, ``film.csv`` / ``film.png`` profiles.  Dry: normal load, contact
half-width (second moment of the pressure, ``a = 2 <x^2>^(1/2)``), peak
pressure, Hertz references, ``pressure.csv`` / ``pressure.png``.

A configuration of :class:`~dolfinx_seal.scenes.lubricated.LubricatedScene`
(run, dry run, sweep, results): this module holds the parameters and the hooks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from dolfinx_seal.contact.hertz import hertz_line
from dolfinx_seal.coupled.continuation import (
    SpeedStepping,
    boundary_start_speed,
    speed_sweep,
    start_coupled,
)
from dolfinx_seal.coupled.results import write_film_profile
from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.film.surface import FilmParams
from dolfinx_seal.meshing import TaggedMesh, create_mesh
from dolfinx_seal.mpi import get_logger
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
from dolfinx_seal.solid.kinematics import PlaneStrain
from dolfinx_seal.solid.problem import SolidContactProblem
from dolfinx_seal.solid.step_limits import StepLimits
from dolfinx_seal.solvers import SNESOptions
from dolfinx_seal.surface import tractions
from dolfinx_seal.surface.asperity import area_fraction

#: A Newton step closes no film gap by more than this fraction of itself (rough,
#: deformable and lubricated; :class:`~dolfinx_seal.solid.step_limits.StepLimits`).
GAP_CLOSURE = 0.5
#: The full-film start (:func:`full_film_start`) puts the flat this many ``h_rms``
#: below the Hertz-deformed cylinder, at the speed where S1's film estimate is that thick.
START_FILM = 4.0

#: Default elements per Hertz half-width at the contact
#: (:attr:`CylinderParameters.contact_elements`; 10.3 um for the S1 cylinder).
CONTACT_ELEMENTS = 30.0


@dataclass(frozen=True)
class CylinderParameters:
    """Cylinder on a flat (SI units).

    Attributes:
        radius: Cylinder radius R [m].
        load: Normal load per unit length F/L [N/m].
        material: Rubber bulk.
        roughness: Roughness of the combined surfaces (S1: h_rms 1 um, D_f 2.2).
        contact: Asperity contact law (``none``: no asperity contact, lubricated only).
        contact_elements: Elements per Hertz half-width at the contact [-]: the
            contact element size is ``a_Hertz / contact_elements`` unless ``h_contact``
            is given, so a changed load, radius or modulus keeps the contact resolved
            (bench/mesh_defaults.py: the default lands within 2 % of the finest level
            for mu, h_central, h_min and the contact half-width).
        h_contact: Element size at the contact [m] (at most a_Hertz / 4); None
            (default): ``a_Hertz / contact_elements``.
        degree: Displacement degree (2; the mixed pressure is one lower).
        lubricated: Solve the film (false: dry contact, no film unknowns).
        bulk: Deformable cylinder (false: rigid, no displacement unknowns).
        film: The lubricant film (speed, viscosity, cavitation model, ...).
        solver: ``monolithic`` (one Newton on all unknowns) or ``partitioned``
            (the seeds' alternating scheme, the baseline).
        relaxation: Under-relaxation factor of the partitioned scheme (S0: 0.01-0.1).
        sweep_order: Order of a speed sweep: ``up``, ``down``, ``up-down`` or ``given``.
        stepping: Speed continuation options of sweeps.
    """

    radius: float = 0.01
    load: float = 100.0
    material: MaterialParams = field(default_factory=MaterialParams)
    roughness: RoughnessParams = field(default_factory=RoughnessParams)
    contact: ContactLawParams = field(default_factory=ContactLawParams)
    contact_elements: float = CONTACT_ELEMENTS
    h_contact: float | None = None
    degree: int = 2
    lubricated: bool = True
    bulk: bool = True
    film: FilmParams = field(default_factory=lambda: FilmParams(speed=0.01))
    solver: str = "monolithic"
    relaxation: float = 0.1
    sweep_order: str = "up"
    stepping: SpeedStepping = field(default_factory=SpeedStepping)

    def __post_init__(self) -> None:
        check_types(self)
        check_positive("radius", self.radius, "m")
        check_positive("load", self.load, "N/m")
        check_int_range("degree", self.degree, 1, 3)
        check_choice("solver", self.solver, ("monolithic", "partitioned"))
        check_range("relaxation", self.relaxation, 0.0, 1.0, lo_open=True)
        check_choice("sweep_order", self.sweep_order, ("up", "down", "up-down", "given"))
        a, _ = hertz_line(self.load, self.radius, self.material.E_star)
        check_range("contact_elements", self.contact_elements, 4.0, 1000.0)
        # on the resolved size: an explicit h_contact, or a / contact_elements (<= a / 4)
        check_range(
            "h_contact", self.element_size, 0.0, a / 4.0, lo_open=True, unit="m (<= a_Hertz/4)"
        )
        if a > 0.3 * self.radius:
            f_max = self.load * (0.3 * self.radius / a) ** 2  # a ~ F^(1/2)
            raise ParameterError(
                f"load = {self.load!r} N/m gives a Hertz half-width {a:.3g} m > 0.3 R: "
                f"outside the small-contact regime of this scene; allowed range (0, {f_max:.4g}] "
                f"N/m at radius = {self.radius!r} m and material.E* = {self.material.E_star:.4g} Pa",
                "load",
            )
        if not self.lubricated and not self.bulk:
            raise ParameterError(
                "bulk = false needs lubricated = true (a rigid dry cylinder is not a scene)"
            )
        if not self.lubricated and self.contact.model == "none":
            raise ParameterError("contact.model = 'none' needs lubricated = true")
        if self.lubricated and self.film.speed == 0.0 and self.contact.model == "none":
            raise ParameterError(
                "film.speed = 0 with contact.model = 'none': nothing would carry the load"
            )

    @property
    def element_size(self) -> float:
        """The element size at the contact [m]: ``h_contact``, or the Hertz half-width
        over ``contact_elements``."""
        if self.h_contact is not None:
            return self.h_contact
        return hertz_line(self.load, self.radius, self.material.E_star)[0] / self.contact_elements


def scales(p: CylinderParameters) -> Scales:
    """Hertz line contact: half-width, peak pressure, nominal length ``2 a``."""
    a, p_h = hertz_line(p.load, p.radius, p.material.E_star)
    return Scales(length=a, pressure=p_h, nominal_area=2.0 * a, approach=a**2 / p.radius,
                  line=True, report={"hertz_half_width": a, "hertz_peak_pressure": p_h})  # fmt: skip


def mesh(p: CylinderParameters, s: Scales, comm: Any) -> TaggedMesh:
    """The cylinder mesh; lubricated: the contact arc is the lubricated zone."""
    extra = {}
    if p.lubricated:
        extra = dict(contact_upstream=p.film.upstream, contact_downstream=p.film.downstream)
    return create_mesh(
        "cylinder", comm=comm, radius=p.radius, contact_half_width=s.length,
        h_contact=p.element_size, h_arc=max(4 * p.element_size, min(60e-6, s.length)), **extra,
    )  # fmt: skip


def problem(p: CylinderParameters, tm: TaggedMesh, s: Scales, law: Any, film: Any,
            control: Control) -> SolidContactProblem:  # fmt: skip
    """Plane strain on a flat, loaded on the top face; a rigid cylinder has no bulk.
    Newton steps are held to half an element normal to the flat (and, deformable,
    to the larger of half an element and a/60 in any direction); lubricated, rough
    and deformable, no film gap closes by more than :data:`GAP_CLOSURE` of itself
    (or opens by more than the factor ``1 / (1 - GAP_CLOSURE)``) unless by at most
    three decay lengths ``h_rms / alpha`` of the contact law, as on the ball.  From a
    full-film start a normal step of half an element (5 um) closed the 4 um film
    of the E = 1 MPa cylinder to -1.3 um in one step (residual 4.3 -> 8.7e4, then
    NaN); with the rule its start converges in 46 Newton steps."""
    h = p.element_size
    gap_step = closure = None
    if film is None:
        snes, max_step, max_normal = SNESOptions(max_it=40, dtol=1e12), 0.5 * h, None
    else:
        snes, max_normal = film_snes(p.film), 0.5 * h
        max_step = max(0.5 * h, s.length / 60.0) if p.bulk else None
        if p.bulk:  # the film gap rule of the ball (smooth: closure alone)
            closure = GAP_CLOSURE
            gap_step = 3.0 * law.h_rms / law.alpha if law is not None else None
    body = Body(PlaneStrain(), p.material.build() if p.bulk else None,
                [Dirichlet(tm.tag("load"))], degree=p.degree)  # fmt: skip
    limits = StepLimits(max_step=max_step, max_normal_step=max_normal, max_gap_step=gap_step,
                        max_gap_closure=closure)  # fmt: skip
    return SolidContactProblem(
        tm.mesh, tm.facet_tags, body, Flat(axis=1), control, tm.tag("contact"), law=law,
        film=film, limits=limits, snes=snes, name="cylinder",
    )  # fmt: skip


#: Moes' dimensionless load ``M = W U^(-1/2)`` at which a smooth cylinder starts
#: (:func:`moes_load`).  Below about 1 the contact is in the rigid-isoviscous
#: regime: the elastic deflection is small against the film, and the undeformed
#: cylinder at the Martin film thickness is within Newton's reach.
START_MOES = 1.0


def moes_load(p: CylinderParameters, speed: float) -> float:
    """Moes' dimensionless load of the line contact, ``M = W U^(-1/2)`` with
    ``W = F / (E' R)``, ``U = eta u_m / (E' R)``, ``E' = 2 E*`` and the mean
    surface speed ``u_m = |speed| / 2`` (the flat slides, the cylinder is at rest)."""
    e_r = 2.0 * p.material.E_star * p.radius
    u = p.film.viscosity * 0.5 * abs(speed) / e_r
    return (p.load / e_r) / math.sqrt(u)


def moes_speed(p: CylinderParameters, moes: float) -> float:
    """The sliding speed [m/s] at which Moes' load :func:`moes_load` is ``moes``."""
    e_r = 2.0 * p.material.E_star * p.radius
    u_mean = (p.load / e_r / moes) ** 2  # M = W U^(-1/2)
    return 2.0 * u_mean * e_r / p.film.viscosity


def start_speed(p: CylinderParameters) -> float:
    """Where the coupled Newton starts [m/s].

    Rough (a contact law): a speed of boundary lubrication, from the dry Hertz
    shape (:func:`~dolfinx_seal.coupled.continuation.boundary_start_speed`,
    p_mean = pi/4 p_H), where the asperities carry nearly all the load.
    Smooth (``contact.model = "none"``): nothing carries the load at low speed,
    so the walk starts in full film instead, at the speed where Moes' ``M`` is
    :data:`START_MOES` (never below ``film.speed``), and comes down.
    """
    if p.contact.model == "none":
        return max(abs(p.film.speed), moes_speed(p, START_MOES))
    s = scales(p)
    return boundary_start_speed(
        p.roughness.h_rms, p.film.viscosity, s.length, math.pi / 4.0 * s.pressure
    )


def first_speed(p: CylinderParameters) -> float:
    """The signed speed [m/s] of :func:`start`'s first coupled solve: rough and
    deformable, the lower of ``|film.speed|`` and the boundary-lubrication
    :func:`start_speed`; smooth, :func:`start_speed` (at least ``|film.speed|``);
    rigid, ``film.speed`` itself."""
    v = p.film.speed
    if not p.bulk:
        return v
    if p.contact.model == "none":
        return math.copysign(start_speed(p), v)
    return math.copysign(min(abs(v), start_speed(p)), v)


def _martin_start(prob: SolidContactProblem, p: CylinderParameters, speed: float) -> int:
    """The film at ``speed`` on the present shape, with the flat at the Martin film
    thickness of a rigid cylinder ``4.9 eta (U/2) R / F`` (at least ``h_rms``; force
    control); returns the film solver's Newton steps."""
    prob.film.set_speed(speed)
    if prob.control == "force":
        h0 = 4.9 * p.film.viscosity * 0.5 * max(speed, 1e-12) * p.radius / p.load
        prob.position.x.array[:] = -max(h0, p.roughness.h_rms)
    else:
        prob.set_fraction(1.0)
    pre = prob.film.make_solver(prob.solver.options, name="cylinder film start")
    try:
        return pre.solve(where="cylinder: film at the Martin film thickness").newton_iterations
    finally:
        pre.destroy()


def _martin_coupled(prob: SolidContactProblem, p: CylinderParameters, speed: float,
                    where: str) -> dict[str, Any]:  # fmt: skip
    """The coupled problem at ``speed`` from the present shape with the film at the
    Martin film thickness (:func:`_martin_start`); the start's solver figures."""
    pre_its = _martin_start(prob, p, speed)
    info = start_coupled(prob, speed, speed, p.stepping, where)
    info["newton_iterations"] += pre_its
    return info


def start(prob: SolidContactProblem, p: CylinderParameters, s: Scales) -> dict[str, Any]:
    """Bring the coupled problem to its first converged state at ``film.speed``.

    Rough and deformable: :func:`~dolfinx_seal.coupled.continuation.start_coupled`
    from the Hertz-deformed shape at :func:`start_speed` (boundary lubrication),
    up to ``film.speed``.  Smooth (or rigid): the undeformed cylinder with the film
    at the Martin film thickness at :func:`start_speed` (rigid-isoviscous for a
    smooth deformable cylinder, ``film.speed`` for a rigid one), the coupled
    solve there, and speed continuation down to ``film.speed``.
    """
    target = p.film.speed
    if prob.bulk and prob.law is not None:
        return start_coupled(
            prob, target, start_speed(p), p.stepping, "cylinder",
            pressure_guess=s.hertz_pressure(prob.X), peak_gap=s.peak_gap(prob.law, p.roughness.h_rms),
        )  # fmt: skip
    v0 = math.copysign(start_speed(p), target) if prob.bulk else target
    info = _martin_coupled(prob, p, v0, "cylinder")
    if v0 != target:
        recs = speed_sweep(prob, [target], lambda *_: None, dict, p.stepping)
        if not recs[-1].converged:
            raise SolverError(
                f"smooth cylinder: the full-film start at {v0:.3g} m/s (Moes M = "
                f"{moes_load(p, v0):.3g}) did not come down to film.speed = {target:g} m/s "
                f"(Moes M = {moes_load(p, target):.3g}): {recs[-1].error}",
                where="cylinder start", partial={"speed": float(prob.film.speed.value)},
            )  # fmt: skip
        info["newton_iterations"] += recs[-1].newton_iterations
        info["strategy"] = (f"full-film start at {v0:.3g} m/s (M = {START_MOES:g}), speed "
                            f"continuation down ({recs[-1].steps} steps)")  # fmt: skip
    return info


def film_start_speed(p: CylinderParameters) -> float:
    """The speed [m/s] of :func:`full_film_start`: S1's film estimate (after its
    fig 15) ``u = (0.2 eta v a / p_mean)^(1/2)`` set to :data:`START_FILM` ``h_rms``
    (``p_mean = pi/4 p_H``), i.e. ``(30 START_FILM)^2`` times the boundary start speed
    (0.42 m/s for the default system)."""
    s = scales(p)
    h0 = START_FILM * p.roughness.h_rms
    return h0**2 * (math.pi / 4.0 * s.pressure) / (0.2 * p.film.viscosity * s.length)


def full_film_start(prob: SolidContactProblem, p: CylinderParameters, s: Scales) -> dict[str, Any]:
    """A rough cylinder's start in full film, walked to ``film.speed`` (the fallback
    chain's other regime, :meth:`~dolfinx_seal.scenes.lubricated.LubricatedScene.first_state`).

    The boundary-lubrication start (:func:`start`) begins where the asperities carry
    the Hertz pressure.  Where that pressure puts the contact law near complete
    contact (E = 1 MPa: separation 0.002 h_rms at p_H, local decay length 3 nm;
    h_rms = 0.1 um: 2e-5 h_rms) its first Newton step diverged (NaN: inverted
    elements after a step closing the 2 nm gap to -0.57 um).  Here:

    1. the cylinder is deformed under the Hertz pressure with the flat
       :data:`START_FILM` ``h_rms`` below it, at :func:`film_start_speed`, where the
       asperities carry little; the film and the flat's position are solved on
       that frozen shape, then the coupled problem;
    2. if that fails and the rigid-isoviscous regime lies faster, the smooth
       cylinder's start instead: the undeformed cylinder at the Martin film
       thickness at Moes M = :data:`START_MOES` (:func:`moes_speed`), where the film
       is far thicker than the roughness.  A fine finish needs it: with h_rms =
       0.1 um the film of 4 h_rms sits at Moes M 13 (4.2 mm/s), in the
       elastohydrodynamic regime, and the coupled solve from the Hertz shape
       diverged (NaN after 12 Newton steps);

    then speed continuation to ``film.speed`` (down or up).  Only for a rough,
    deformable cylinder with a sliding speed."""
    target = p.film.speed
    if not (prob.bulk and prob.law is not None) or target == 0.0:
        raise ParameterError("the full-film start needs a rough, deformable, sliding cylinder")
    initial = prob.state()
    v0 = math.copysign(film_start_speed(p), target)
    prob.film.set_speed(v0)
    try:
        info = start_coupled(
            prob, v0, v0, p.stepping, "cylinder full-film start",
            pressure_guess=s.hertz_pressure(prob.X), peak_gap=START_FILM * p.roughness.h_rms,
            film_guess=True,
        )  # fmt: skip
        how = f"full-film start at {v0:.3g} m/s (film {START_FILM:g} h_rms)"
    except SolverError as e:
        v1 = moes_speed(p, START_MOES)
        if v1 <= abs(v0):
            raise
        get_logger().info("cylinder full-film start at %.3g m/s failed (%s); the rigid-"
                          "isoviscous start at %.3g m/s (M = %g)", v0, e.what, v1, START_MOES)  # fmt: skip
        prob.restore(initial)
        prob.set_fraction(1.0)
        v0 = math.copysign(v1, target)
        info = _martin_coupled(prob, p, v0, "cylinder rigid-isoviscous start")
        info["newton_iterations"] += e.history.newton_iterations
        how = (f"rigid-isoviscous start at {v0:.3g} m/s (Moes M = {START_MOES:g}; the film "
               f"start at {film_start_speed(p):.3g} m/s failed)")  # fmt: skip
    if v0 != target:
        recs = speed_sweep(prob, [target], lambda *_: None, dict, p.stepping)
        if not recs[-1].converged:
            raise SolverError(
                f"the {how} did not reach film.speed = {target:g} m/s: {recs[-1].error}",
                where="cylinder full-film start", partial={"speed": float(prob.film.speed.value)},
            )  # fmt: skip
        info["newton_iterations"] += recs[-1].newton_iterations
    info["strategy"] = f"{how}, speed continuation to {target:.3g} m/s"
    return info


def write_point(out: Path, prob: SolidContactProblem, p: CylinderParameters) -> None:
    """``film.csv`` / ``film.png`` along the contact line."""
    f = p.film
    title = (f"cylinder F/L = {p.load:g} N/m, U = {f.speed:.3g} m/s, "
             f"h_rms = {p.roughness.h_rms * 1e6:g} um, {f.cavitation}")  # fmt: skip
    write_film_profile(out, prob, title)


def write_dry(out: Path, prob: SolidContactProblem, p: CylinderParameters,
              s: Scales) -> dict[str, Any]:  # fmt: skip
    """``pressure.csv`` / ``pressure.png`` against Hertz; the real contact area
    (Persson's ``A/A0`` on the deformed line) for a rough law."""
    law = prob.law
    extra = {}
    if math.isfinite(getattr(law, "rms_slope", math.nan)):
        A = area_fraction(prob.p_cont, p.material.E_star, law.rms_slope)
        extra["real_contact_area"] = prob.integrate(
            A * tractions.area_ratio(prob.F, prob.N3), prob.ds_c
        )
    Xs, pc = prob.surface_values(prob.p_cont, average=True)
    _, gap = prob.surface_values(prob.gap, average=True)
    title = f"dry cylinder, F/L = {p.load:g} N/m, law: {law.name}"
    write_dry_profile(out, s, title, Xs[:, 0], pc, gap_m=gap)
    return extra


CYLINDER = LubricatedScene(
    name="cylinder",
    summary="rubber cylinder on a flat (S1 sec 2): soft EHL film + Persson contact, or dry",
    parameters=CylinderParameters,
    scales=scales, mesh=mesh, problem=problem, start=start, write_point=write_point,
    write_dry=write_dry, start_speed=start_speed, first_speed=first_speed,
    other_start=full_film_start,
)  # fmt: skip
SCENE = CYLINDER.scene
run, run_lubricated, run_dry, sweep = (
    CYLINDER.run,
    CYLINDER.run_lubricated,
    CYLINDER.run_dry,
    CYLINDER.sweep,
)
build_lubricated, start_lubricated = CYLINDER.build_lubricated, CYLINDER.start_lubricated

__all__ = ["CYLINDER", "SCENE", "CylinderParameters", "build_lubricated", "run", "start_lubricated",
           "sweep"]  # fmt: skip
