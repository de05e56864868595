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
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import ufl

from dolfinx_seal.contact.hertz import hertz_line, separation_of
from dolfinx_seal.coupled.continuation import SpeedStepping, boundary_start_speed, start_coupled
from dolfinx_seal.coupled.results import lubricated_results, write_fields, write_film_profile
from dolfinx_seal.coupled.sweep import SweepHooks, lubricated_sweep, plot_sweep
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.film.surface import FilmParams, FilmScales, SurfaceFilm
from dolfinx_seal.meshing import create_mesh
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.params import (
    check_choice,
    check_int_range,
    check_positive,
    check_range,
    check_types,
)
from dolfinx_seal.roughness.psd import RoughnessParams
from dolfinx_seal.scenes import Scene
from dolfinx_seal.scenes.common import (
    ContactLawParams,
    MaterialParams,
    solve_dry,
    write_profile,
)
from dolfinx_seal.solid.body import Body, Dirichlet, ForceControl, PositionControl
from dolfinx_seal.solid.counter_surface import Flat
from dolfinx_seal.solid.kinematics import PlaneStrain
from dolfinx_seal.solid.problem import SolidContactProblem
from dolfinx_seal.solid.step_limits import StepLimits
from dolfinx_seal.solvers import SNESOptions
from dolfinx_seal.surface import tractions
from dolfinx_seal.surface.asperity import area_fraction


@dataclass(frozen=True)
class CylinderParameters:
    """Cylinder on a flat (SI units).

    Attributes:
        radius: Cylinder radius R [m].
        load: Normal load per unit length F/L [N/m].
        material: Rubber bulk.
        roughness: Roughness of the combined surfaces (S1: h_rms 1 um, D_f 2.2).
        contact: Asperity contact law (``none``: no asperity contact, lubricated only).
        h_contact: Element size at the contact [m] (at most a_Hertz / 4).
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
    h_contact: float = 10e-6
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
        check_range(
            "h_contact", self.h_contact, 0.0, a / 4.0, lo_open=True, unit="m (<= a_Hertz/4)"
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


def run(params: CylinderParameters, out: Path) -> dict[str, Any]:
    """Solve one point (lubricated or dry); write the profiles; return the results."""
    if params.lubricated:
        return run_lubricated(params, out)
    return run_dry(params, out)


def _mesh(params: CylinderParameters, a_h: float, comm: Any = None) -> Any:
    """The cylinder mesh; lubricated: the contact arc is the lubricated zone."""
    extra = {}
    if params.lubricated:
        extra = dict(
            contact_upstream=params.film.upstream, contact_downstream=params.film.downstream
        )
    return create_mesh(
        "cylinder", comm=comm or COMM_WORLD, radius=params.radius, contact_half_width=a_h,
        h_contact=params.h_contact, h_arc=max(4 * params.h_contact, min(60e-6, a_h)), **extra,
    )  # fmt: skip


def build_lubricated(
    params: CylinderParameters,
    comm: Any = None,
    position: float | None = None,
    position0: float | None = None,
) -> tuple[SolidContactProblem, dict[str, Any]]:
    """The coupled problem (film on) and scalars describing it.

    Args:
        params: Scene parameters.
        comm: Communicator (default COMM_WORLD).
        position: None: force control (the flat's position is an unknown);
            otherwise the flat's final position [m] (position control).
        position0: Start of the position ramp (position control; default ``position``).
    """
    e_star = params.material.E_star
    a_h, p_h = hertz_line(params.load, params.radius, e_star)
    law, law_info = params.contact.build(params.roughness, e_star, approach=a_h**2 / params.radius)
    h_rms = params.roughness.h_rms
    rms_slope = getattr(law, "rms_slope", math.nan) if law is not None else math.nan
    tm = _mesh(params, a_h, comm)
    film = SurfaceFilm(
        params.film, FilmScales(pressure=p_h, length=a_h, gap=h_rms, element=params.h_contact),
        h_rms=h_rms, rms_slope=rms_slope, e_star=e_star,
        psd=params.roughness.build() if params.film.flow_factor == "persson" else None,
    )  # fmt: skip
    snes = SNESOptions(
        max_it=60, dtol=1e12, rtol=1e-11,
        snes_type="vinewtonssls" if params.film.cavitation == "jfo" else "vinewtonrsls",
    )  # fmt: skip
    body = Body(PlaneStrain(), params.material.build() if params.bulk else None,
                [Dirichlet(tm.tag("load"))], degree=params.degree)  # fmt: skip
    if position is None:
        control: ForceControl | PositionControl = ForceControl(params.load)
    else:
        control = PositionControl(position, position if position0 is None else position0)
    limits = StepLimits(
        max_step=max(0.5 * params.h_contact, a_h / 60.0) if params.bulk else None,
        max_normal_step=0.5 * params.h_contact,
    )  # fmt: skip
    prob = SolidContactProblem(tm.mesh, tm.facet_tags, body, Flat(axis=1), control,
                               tm.tag("contact"), law=law, film=film, limits=limits, snes=snes,
                               name="cylinder")  # fmt: skip
    info = {
        "hertz_half_width": a_h,
        "hertz_peak_pressure": p_h,
        "contact_law": law.name if law is not None else "none",
        **law_info,
    }
    return prob, info


def start_speed(params: CylinderParameters) -> float:
    """A speed of boundary lubrication [m/s] where the coupled Newton starts
    (:func:`~dolfinx_seal.coupled.continuation.boundary_start_speed`, p_mean = pi/4 p_H)."""
    a_h, p_h = hertz_line(params.load, params.radius, params.material.E_star)
    return boundary_start_speed(
        params.roughness.h_rms, params.film.viscosity, a_h, math.pi / 4.0 * p_h
    )


def start_lubricated(prob: SolidContactProblem, params: CylinderParameters) -> dict[str, Any]:
    """Bring the coupled problem to its first converged state at ``film.speed``.

    Deformable: :func:`~dolfinx_seal.coupled.continuation.start_coupled` from
    the Hertz-deformed shape at :func:`start_speed`.  Rigid: the film at the
    Martin film thickness of the load first, then the coupled solve.
    """
    a_h, p_h = hertz_line(params.load, params.radius, params.material.E_star)
    target = params.film.speed
    pre_its = 0
    if prob.bulk:
        X = prob.X
        guess = p_h * ufl.sqrt(ufl.max_value(1.0 - (X[0] / a_h) ** 2, 0.0))
        peak_gap = separation_of(prob.law, p_h) if prob.law is not None else params.roughness.h_rms
        kw: dict[str, Any] = dict(pressure_guess=guess, peak_gap=peak_gap)
        v_start = start_speed(params)
    else:  # rigid: the film at the Martin film thickness first, then the coupled solve
        if prob.control == "force":
            h0 = 4.9 * params.film.viscosity * 0.5 * max(target, 1e-12) * params.radius
            prob.position.x.array[:] = -max(h0 / params.load, params.roughness.h_rms)
        else:
            prob.set_fraction(1.0)
        pre = prob.film.make_solver(prob.solver.options, name="cylinder film start")
        pre_its = pre.solve(where="cylinder: film at the guessed film thickness").newton_iterations
        pre.destroy()
        kw, v_start = {}, target
    info = start_coupled(prob, target, v_start, params.stepping, "cylinder", **kw)
    info["newton_iterations"] += pre_its
    return info


def run_lubricated(params: CylinderParameters, out: Path) -> dict[str, Any]:
    """One lubricated point at ``film.speed``."""
    t0 = time.perf_counter()
    prob, info = build_lubricated(params)
    if params.solver == "partitioned":
        from dolfinx_seal.coupled.partitioned import partitioned_start

        a_h, p_h = hertz_line(params.load, params.radius, params.material.E_star)
        guess = p_h * ufl.sqrt(ufl.max_value(1.0 - (prob.X[0] / a_h) ** 2, 0.0))
        peak_gap = separation_of(prob.law, p_h) if prob.law is not None else params.roughness.h_rms
        speeds = [min(params.film.speed, start_speed(params))]
        while speeds[-1] < params.film.speed * (1 - 1e-12):  # half a decade per step
            speeds.append(min(params.film.speed, speeds[-1] * 10**0.5))
        solve_info = partitioned_start(prob, guess, peak_gap, speeds, params.relaxation)
    else:
        solve_info = start_lubricated(prob, params)
    a_h = info["hertz_half_width"]
    res = lubricated_results(prob, nominal_area=2.0 * a_h)
    res.update(info)
    res.update(solve_info)
    res.update(dofs=prob.dofs, dof_counts=prob.dof_counts(), ranks=COMM_WORLD.size,
               wall_time_s=time.perf_counter() - t0, converged=True)  # fmt: skip
    write_film_profile(out, prob, _title(params))
    write_fields(out, prob)
    return res


def _title(params: CylinderParameters) -> str:
    f = params.film
    return (f"cylinder F/L = {params.load:g} N/m, U = {f.speed:.3g} m/s, "
            f"h_rms = {params.roughness.h_rms * 1e6:g} um, {f.cavitation}")  # fmt: skip


def _write_point(out: Path, prob: SolidContactProblem, params: CylinderParameters) -> None:
    write_film_profile(out, prob, _title(params))


def sweep(
    params: CylinderParameters, out: Path, name: str, values: list[float], on_point: Any
) -> list[dict[str, Any]]:
    """Stribeck sweep over ``film.speed`` with continuation
    (:func:`~dolfinx_seal.coupled.sweep.lubricated_sweep`)."""

    def build(p: CylinderParameters) -> tuple[SolidContactProblem, dict[str, Any]]:
        prob, info = build_lubricated(p)
        info["nominal_area"] = 2.0 * info["hertz_half_width"]
        return prob, info

    hooks = SweepHooks(build=build, start=start_lubricated, write_point=_write_point)
    return lubricated_sweep(params, out, name, values, on_point, hooks)


def run_dry(params: CylinderParameters, out: Path) -> dict[str, Any]:
    """Solve the dry cylinder; write the pressure profile; return the results."""
    t0 = time.perf_counter()
    mat = params.material.build()
    e_star = params.material.E_star
    a_h, p_h = hertz_line(params.load, params.radius, e_star)
    law, law_info = params.contact.build(params.roughness, e_star, approach=a_h**2 / params.radius)
    tm = _mesh(params, a_h)
    body = Body(PlaneStrain(), mat, [Dirichlet(tm.tag("load"))], degree=params.degree)
    prob = SolidContactProblem(
        tm.mesh, tm.facet_tags, body, Flat(axis=1), ForceControl(params.load), tm.tag("contact"),
        law=law, limits=StepLimits(max_step=0.5 * params.h_contact),
        snes=SNESOptions(max_it=40, dtol=1e12), name="cylinder",
    )  # fmt: skip
    X = prob.X
    guess = p_h * ufl.sqrt(ufl.max_value(1.0 - (X[0] / a_h) ** 2, 0.0))
    info = solve_dry(prob, guess, p_h)
    res = dry_results(prob, params.load, line=True)
    res.update(info)
    res.update(
        hertz_half_width=a_h, hertz_peak_pressure=p_h, dofs=prob.dofs, ranks=COMM_WORLD.size,
        wall_time_s=time.perf_counter() - t0, converged=True, contact_law=law.name, **law_info,
    )  # fmt: skip
    if math.isfinite(getattr(law, "rms_slope", math.nan)):
        A = area_fraction(prob.p_cont, e_star, law.rms_slope)
        res["real_contact_area"] = prob.integrate(
            A * tractions.area_ratio(prob.F, prob.N3), prob.ds_c
        )
    Xs, p = prob.surface_values(prob.p_cont, average=True)
    _, gap = prob.surface_values(prob.gap, average=True)
    x = Xs[:, 0]
    hz = p_h * (1.0 - (x / a_h) ** 2).clip(min=0.0) ** 0.5
    write_profile(
        out, "pressure", {"x_m": x, "p_contact_Pa": p, "gap_m": gap, "p_hertz_Pa": hz},
        title=f"dry cylinder, F/L = {params.load:g} N/m, law: {law.name}",
        xlabel="x [mm]", ylabel="contact pressure [MPa]",
        curves={"FEM": (x * 1e3, p / 1e6), "Hertz": (x * 1e3, hz / 1e6)},
    )  # fmt: skip
    return res


def dry_results(
    prob: SolidContactProblem, target: float, line: bool, symmetry_factor: float = 1.0
) -> dict[str, Any]:
    """Load, moment-based contact size, peak pressure and load balance of a dry solve.

    ``symmetry_factor`` multiplies integrals over a symmetric half model.
    """
    fn = -prob.p_cont * ufl.dot(tractions.nanson_normal(prob.F, prob.N3), prob.e_n) * prob.weight
    M0 = prob.integrate(fn, prob.ds_c)
    x = prob.x
    if line:
        r2 = x[0] ** 2
    else:
        r2 = x[0] ** 2 + x[1] ** 2
    M2 = prob.integrate(fn * r2, prob.ds_c)
    _, p = prob.surface_values(prob.p_cont, average=True)
    load = symmetry_factor * M0
    out = {
        "normal_load": load,
        "load_contact": load,
        "max_contact_pressure": float(p.max()),
        "load_balance_error": abs(M0 - target) / target,
        "counter_position": prob.counter_position(),
    }
    if line:
        out["contact_half_width"] = 2.0 * math.sqrt(M2 / M0)  # Hertz: <x^2> = a^2/4
    else:
        out["contact_radius"] = math.sqrt(2.5 * M2 / M0)  # Hertz: <r^2> = 2 a^2 / 5
    return out


SCENE = Scene(
    name="cylinder",
    summary="rubber cylinder on a flat (S1 sec 2): soft EHL film + Persson contact, or dry",
    parameters=CylinderParameters,
    run=run,
    sweep=lambda *a: sweep(*a),
    plot_sweep=lambda *a: plot_sweep(*a),
)

__all__ = ["SCENE", "CylinderParameters", "build_lubricated", "dry_results", "run", "sweep"]
