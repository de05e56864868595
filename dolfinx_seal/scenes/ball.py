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
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import ufl

from dolfinx_seal.contact.hertz import hertz_point
from dolfinx_seal.coupled.continuation import SpeedStepping, speed_sweep, start_coupled
from dolfinx_seal.coupled.results import lubricated_results, write_fields, write_film_map
from dolfinx_seal.coupled.sweep import SweepHooks, lubricated_sweep, plot_sweep
from dolfinx_seal.errors import ParameterError, SolverError
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
from dolfinx_seal.scenes.cylinder import dry_results
from dolfinx_seal.solid.body import Body, Dirichlet, ForceControl, PositionControl
from dolfinx_seal.solid.counter_surface import Flat
from dolfinx_seal.solid.kinematics import Solid3D
from dolfinx_seal.solid.problem import SolidContactProblem
from dolfinx_seal.solid.step_limits import StepLimits
from dolfinx_seal.solvers import SNESOptions
from dolfinx_seal.verification.ehl import IsoviscousElasticFilm


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
        h_contact: Element size at the contact [m] (at most a_Hertz / 4).
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
            for its appendix D).
        sweep_order: Order of a speed sweep: ``down`` (default: the sweep starts in
            full film, where the hydrodynamic start is robust), ``up``, ``up-down``
            or ``given``.
        stepping: Speed continuation options of sweeps (``film_presolve`` off: the
            ball's figures were measured without it).
    """

    radius: float = 0.01
    load: float = 1.3
    material: MaterialParams = field(default_factory=lambda: MaterialParams(E=1.2e6))
    roughness: RoughnessParams = field(default_factory=RoughnessParams)
    contact: ContactLawParams = field(default_factory=ContactLawParams)
    shape: str = "half"
    h_contact: float = 0.25e-3
    mesh_growth: float = 1.0
    degree: int = 2
    lubricated: bool = True
    film: FilmParams = field(default_factory=lambda: FilmParams(speed=0.01))
    film_extent: float = 3.0
    sweep_order: str = "down"
    stepping: SpeedStepping = field(default_factory=lambda: SpeedStepping(film_presolve=False))

    def __post_init__(self) -> None:
        check_types(self)
        check_positive("radius", self.radius, "m")
        check_positive("load", self.load, "N")
        check_choice("shape", self.shape, ("half", "full"))
        check_int_range("degree", self.degree, 1, 3)
        a, _ = hertz_point(self.load, self.radius, self.material.E_star)
        check_range(
            "h_contact", self.h_contact, 0.0, a / 4.0, lo_open=True, unit="m (<= a_Hertz/4)"
        )
        check_range("mesh_growth", self.mesh_growth, 0.0, 2.0, lo_open=True)
        check_range("film_extent", self.film_extent, 1.5, 4.5)
        check_choice("sweep_order", self.sweep_order, ("up", "down", "up-down", "given"))
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


def run(params: BallParameters, out: Path) -> dict[str, Any]:
    """Solve one point (lubricated or dry); write the maps/profiles; return the results."""
    if params.lubricated:
        return run_lubricated(params, out)
    return run_dry(params, out)


def _mesh(params: BallParameters, a_h: float, comm: Any = None) -> Any:
    """The ball mesh; lubricated: the contact cap (radius ``film_extent a``) is the film."""
    extra: dict[str, Any] = {}
    if params.lubricated:
        extra = dict(cap_extent=params.film_extent, fine_extent=min(1.5, params.film_extent - 0.1))
    return create_mesh(
        "ball", comm=comm or COMM_WORLD, radius=params.radius, shape=params.shape,
        contact_radius=a_h, h_contact=params.h_contact,
        h_cap=max(2 * params.h_contact, min(0.3e-3, a_h / 2)), growth=params.mesh_growth,
        **extra,
    )  # fmt: skip


def _bcs(params: BallParameters, tm: Any) -> list[Dirichlet]:
    bcs = [Dirichlet(tm.tag("load"))]
    if params.shape == "half":
        bcs.append(Dirichlet(tm.tag("symmetry"), component=1))
    return bcs


def build_lubricated(
    params: BallParameters, comm: Any = None, position: float | None = None
) -> tuple[SolidContactProblem, dict[str, Any]]:
    """The coupled problem (film on the contact cap) and scalars describing it.

    Args:
        params: Scene parameters.
        comm: Communicator (default COMM_WORLD).
        position: None: force control (the flat's position is an unknown);
            otherwise the flat's position [m] (position control, e.g. to check a
            parallel solution on one rank).
    """
    e_star = params.material.E_star
    a_h, p_h = hertz_point(params.load, params.radius, e_star)
    law, law_info = params.contact.build(params.roughness, e_star, approach=a_h**2 / params.radius)
    h_rms = params.roughness.h_rms
    tm = _mesh(params, a_h, comm)
    half = params.shape == "half"
    film = SurfaceFilm(
        params.film, FilmScales(pressure=p_h, length=a_h, gap=h_rms, element=params.h_contact),
        h_rms=h_rms, rms_slope=getattr(law, "rms_slope", math.nan) if law is not None else math.nan,
        e_star=e_star, no_flux_tags=(tm.tag("symmetry"),) if half else (),
    )  # fmt: skip
    # backtracking: with full (limited) steps, 0.03 -> 0.018 m/s (a/15) wandered and
    # jumped to a residual 4x the start at step 10; with "bt" it reached 0.01 m/s
    snes = SNESOptions(
        max_it=60, dtol=1e12, rtol=1e-11, line_search="bt",
        snes_type="vinewtonssls" if params.film.cavitation == "jfo" else "vinewtonrsls",
    )  # fmt: skip
    factor = 2.0 if half else 1.0
    body = Body(Solid3D(), params.material.build(), _bcs(params, tm), degree=params.degree)
    control = (ForceControl(params.load / factor) if position is None
               else PositionControl(position, position0=position))  # fmt: skip
    limits = StepLimits(
        max_step=0.5 * params.h_contact, max_gap_closure=GAP_CLOSURE,
        max_gap_step=3.0 * _decay_length(law) if law is not None else None,
    )  # fmt: skip
    prob = SolidContactProblem(tm.mesh, tm.facet_tags, body, Flat(axis=2), control,
                               tm.tag("contact"), law=law, film=film, limits=limits, snes=snes,
                               name="ball")  # fmt: skip
    info = {
        "hertz_contact_radius": a_h,
        "hertz_peak_pressure": p_h,
        "nominal_area": math.pi * a_h**2,
        "symmetry_factor": factor,
        "contact_law": law.name if law is not None else "none",
        **law_info,
    }
    return prob, info


def start_speed(params: BallParameters) -> float:
    """Speed U [m/s] of the first coupled solve: a hydrodynamic one, where the
    Hamrock-Dowson central film (:mod:`dolfinx_seal.verification.ehl`, u_m = U/2) is
    ``START_FILM`` h_rms, so that the asperities carry little and the Persson law
    is in its soft tail; never below ``film.speed``.  Without asperity contact:
    ``film.speed``."""
    f = params.film
    if params.contact.model == "none":
        return f.speed
    hd = IsoviscousElasticFilm(params.radius, params.material.E_star, f.viscosity, params.load)
    return max(f.speed, 2.0 * hd.mean_speed_for_central(START_FILM * params.roughness.h_rms))


START_FILM = 4.0  # central film of the start point, in h_rms
GAP_CLOSURE = 0.5  # a Newton step closes no film gap by more than this fraction of itself


def start_lubricated(prob: SolidContactProblem, params: BallParameters) -> dict[str, Any]:
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
    f = params.film
    e_star = params.material.E_star
    a_h, p_h = hertz_point(params.load, params.radius, e_star)
    v0 = start_speed(params)
    hd = IsoviscousElasticFilm(params.radius, e_star, f.viscosity, params.load)
    X = prob.X
    guess = p_h * ufl.sqrt(ufl.max_value(1.0 - (X[0] ** 2 + X[1] ** 2) / a_h**2, 0.0))
    prob.film.set_speed(v0)
    info = start_coupled(
        prob, v0, v0, params.stepping, "ball", pressure_guess=guess,
        peak_gap=hd.h_central(0.5 * v0), film_guess=True,
    )  # fmt: skip
    if f.speed < v0:
        recs = speed_sweep(prob, [f.speed], lambda *_: None, dict, params.stepping)
        if not recs[-1].converged:
            raise SolverError(
                f"coupled solve did not reach film.speed = {f.speed:g} m/s: {recs[-1].error}",
                where="ball start", partial={"speed": float(prob.film.speed.value)},
            )  # fmt: skip
        info["newton_iterations"] += recs[-1].newton_iterations
        info["strategy"] = f"start at {v0:.3g} m/s, speed continuation ({recs[-1].steps} steps)"
    return info


def _title(params: BallParameters) -> str:
    f = params.film
    rough = (f"h_rms = {params.roughness.h_rms * 1e6:g} um" if params.contact.model != "none"
             else "smooth")  # fmt: skip
    return f"ball F = {params.load:g} N, U = {f.speed:.3g} m/s, {rough}, {f.cavitation}"


def _write_point(out: Path, prob: SolidContactProblem, params: BallParameters) -> None:
    a_h, _ = hertz_point(params.load, params.radius, params.material.E_star)
    write_film_map(out, prob, _title(params), extent=min(params.film_extent, 2.0) * a_h)


def run_lubricated(params: BallParameters, out: Path) -> dict[str, Any]:
    """One lubricated point at ``film.speed``."""
    t0 = time.perf_counter()
    prob, info = build_lubricated(params)
    solve_info = start_lubricated(prob, params)
    res = lubricated_results(
        prob, symmetry_factor=info["symmetry_factor"], nominal_area=info["nominal_area"]
    )
    res.update(info)
    res.update(solve_info)
    res.update(dofs=prob.dofs, dof_counts=prob.dof_counts(), ranks=COMM_WORLD.size,
               wall_time_s=time.perf_counter() - t0, converged=True)  # fmt: skip
    _write_point(out, prob, params)
    write_fields(out, prob)
    return res


def sweep(
    params: BallParameters, out: Path, name: str, values: list[float], on_point: Any
) -> list[dict[str, Any]]:
    """Stribeck sweep over ``film.speed`` with continuation
    (:func:`~dolfinx_seal.coupled.sweep.lubricated_sweep`)."""
    half = params.shape == "half"
    hooks = SweepHooks(
        build=build_lubricated, start=start_lubricated, write_point=_write_point,
        symmetry_factor=2.0 if half else 1.0,
    )  # fmt: skip
    return lubricated_sweep(params, out, name, values, on_point, hooks)


def build_dry(
    params: BallParameters, comm: Any = None
) -> tuple[SolidContactProblem, dict[str, Any]]:
    """The dry problem (no film unknowns, force control) and scalars describing it."""
    e_star = params.material.E_star
    a_h, p_h = hertz_point(params.load, params.radius, e_star)
    law, law_info = params.contact.build(params.roughness, e_star, approach=a_h**2 / params.radius)
    tm = _mesh(params, a_h, comm)
    factor = 2.0 if params.shape == "half" else 1.0
    body = Body(Solid3D(), params.material.build(), _bcs(params, tm), degree=params.degree)
    limits = StepLimits(max_step=0.5 * params.h_contact, max_gap_step=3.0 * _decay_length(law))
    prob = SolidContactProblem(
        tm.mesh, tm.facet_tags, body, Flat(axis=2), ForceControl(params.load / factor),
        tm.tag("contact"), law=law, limits=limits, snes=SNESOptions(max_it=60, dtol=1e12),
        name="ball",
    )  # fmt: skip
    info = {"hertz_contact_radius": a_h, "hertz_peak_pressure": p_h, "symmetry_factor": factor,
            "contact_law": law.name, **law_info}  # fmt: skip
    return prob, info


def run_dry(params: BallParameters, out: Path) -> dict[str, Any]:
    """Solve the dry ball; write the pressure profile along x; return the results."""
    t0 = time.perf_counter()
    prob, info = build_dry(params)
    a_h, p_h = info["hertz_contact_radius"], info["hertz_peak_pressure"]
    factor = info["symmetry_factor"]
    X = prob.X
    guess = p_h * ufl.sqrt(ufl.max_value(1.0 - (X[0] ** 2 + X[1] ** 2) / a_h**2, 0.0))
    solve_info = solve_dry(prob, guess, p_h)
    res = dry_results(prob, params.load / factor, line=False, symmetry_factor=factor)
    res.update(solve_info)
    res.update(info)
    res.update(dofs=prob.dofs, ranks=COMM_WORLD.size, wall_time_s=time.perf_counter() - t0,
               converged=True)  # fmt: skip
    Xs, p = prob.surface_values(prob.p_cont, average=True)
    on_axis = np.abs(Xs[:, 1]) < 1e-9 * params.radius
    x, pa = Xs[on_axis, 0], p[on_axis]
    order = np.argsort(x)
    x, pa = x[order], pa[order]
    hz = p_h * (1.0 - (x / a_h) ** 2).clip(min=0.0) ** 0.5
    write_profile(
        out, "pressure", {"x_m": x, "p_contact_Pa": pa, "p_hertz_Pa": hz},
        title=f"dry ball, F = {params.load:g} N, law: {info['contact_law']} (y = 0)",
        xlabel="x [mm]", ylabel="contact pressure [MPa]",
        curves={"FEM": (x * 1e3, pa / 1e6), "Hertz": (x * 1e3, hz / 1e6)},
    )  # fmt: skip
    return res


def _decay_length(law: Any) -> float:
    """Gap over which the contact pressure changes by a factor e (at large gaps) [m]."""
    return law.h_rms / law.alpha


SCENE = Scene(
    name="ball",
    summary="rubber ball on a flat (S1 sec 3): 3D soft EHL film + Persson contact, or dry",
    parameters=BallParameters,
    run=run,
    sweep=lambda *a: sweep(*a),
    plot_sweep=lambda *a: plot_sweep(*a),
)
