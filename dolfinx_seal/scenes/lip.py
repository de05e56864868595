r"""Scene ``lip``: the lubricated radial lip seal in axisymmetry (rotary or reciprocating).

The lip of :mod:`dolfinx_seal.scenes.lip_install` is first installed dry on
its shaft (the same solve, :func:`~dolfinx_seal.scenes.lip_install.install`);
then a 1D Reynolds film on the deformed contact band (axial coordinate of the
current surface of revolution, :mod:`dolfinx_seal.film.surface`) joins the
Newton system with the bulk.  All roughness is homogenised (Persson laws for
the asperity pressure ``p_cont(u)`` and the real area ``A/A0``; the
Persson/Bruggeman or Patir-Cheng pressure flow factor ``phi_p(u)``).

Film, per unit circumference of the current surface (``s`` the arc length
along the section, from the oil side to the air side)::

    d/ds( phi_p u^3 / (12 eta) dp/ds ) = d/ds( U_z u theta / 2 )

with ``p = oil_pressure`` on the oil-side end of the contact band and
``p = air_pressure`` on the air-side end; the film pressure acts on the lip
(it relieves the asperity contact).  With ``face_pressure = true`` the sealed
pressures also act on the free faces of the lip (``oil_side`` and the spring
groove: ``oil_pressure``; ``air_side``: ``air_pressure``).  On this section,
whose housing is not backed by a metal flange, that is a net axial force of
``oil_pressure`` times the annulus from the shaft to the case (about 70 N at
0.25 bar on the 80 mm seal) on a flex section of 1 mm: the lip swings axially
by millimetres, so it is off by default and stepped finely when on.

* ``motion = "rotary"``: the shaft turns at the surface speed ``film.speed``.
  The sliding is along the hoop direction, which no axisymmetric gradient
  has: no Couette flux (isotropic roughness; the axial film is set by the
  contact and the pressure flow), so the solution does not depend on the
  speed, and only the friction does: the hoop shear ``eta U / u`` (Couette)
  plus ``sigma_1 A/A0`` (asperities) gives ``friction_torque = R_s int tau
  da`` [N m] and ``power_loss = friction_torque * U / R_s`` [W].
* ``motion = "reciprocating"``: the rod slides axially with the signed
  ``film.speed`` (positive: towards the air side, the out-stroke).  The
  axial Couette flux is on, cavitation by JFO (mass-conserving) or the
  Reynolds condition; ``friction_force`` [N] is the axial drag on the rod.
  A flooded air-side inlet is assumed on the in-stroke (the rod returns
  through an oil-wetted air side).

``leakage_rate`` [m^3/s, positive from oil to air] is the flow out of the
air-side end of the band; the flow into the oil-side end is computed too and
their difference is ``mass_imbalance`` [m^3/s], and over the flow
``mass_balance_error``.  Only what a point
needs is assembled: zero speed and rotary motion have no Couette flux; where
the film has no transport and both sealed pressures are >= 0 the pressure
cannot fall below zero (maximum principle), so no cavitation bounds either.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from dolfinx_seal.coupled.continuation import SpeedStepping, speed_sweep
from dolfinx_seal.coupled.results import complementarity_of, write_fields
from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.film.surface import CONTINUUM_FILM, FilmParams, FilmScales, SurfaceFilm
from dolfinx_seal.mpi import get_logger, world
from dolfinx_seal.output import write_sweep_failures
from dolfinx_seal.params import check_choice, check_positive, check_range
from dolfinx_seal.scenes import Scene
from dolfinx_seal.scenes.lip_install import (
    LipInstallParameters,
    build_problem,
    install,
    moment_width,
    radial_balance,
)
from dolfinx_seal.solid.counter_surface import Shaft
from dolfinx_seal.solid.problem import SolidContactProblem, SteppingOptions
from dolfinx_seal.solvers import SNESOptions, with_snes_type
from dolfinx_seal.surface import tractions
from dolfinx_seal.surface.asperity import area_fraction

MOTIONS = ("rotary", "reciprocating")
ML_PER_H = 1e6 * 3600.0  # m^3/s -> ml/h


@dataclass(frozen=True)
class LipParameters(LipInstallParameters):
    """The lubricated lip seal (SI units); the installation fields as in ``lip-install``.

    Attributes:
        film: The oil film: ``speed`` is the shaft surface speed (rotary) or the
            signed rod speed (reciprocating, positive towards the air side) [m/s];
            ``viscosity`` [Pa s]; ``cavitation`` (reciprocating; a film without
            transport needs none); ``flow_factor`` (``persson`` or ``patir-cheng``
            for the homogenised roughness); ``asperity_shear`` sigma_1 [Pa].
        motion: ``rotary`` (a turning shaft) or ``reciprocating`` (a stroking rod).
        oil_pressure: Sealed (gauge) oil pressure on the oil side [Pa].
        air_pressure: Pressure on the air side [Pa].
        face_pressure: The sealed pressures also act on the free faces of the lip
            (see the module docstring).
        feedback: The fluid pressure acts on the lip (false: the installed lip is
            frozen and only the film is solved on it, e.g. for the exactly linear
            leakage of a rigid contact).
        stroke_length: Stroke L of a reciprocating rod [m] (per-cycle transport).
        zone_gap: The lubricated zone ends where the installed gap exceeds this
            many film scales [-]: h_rms, or for a stroking rod the thicker film
            inverse hydrodynamics predicts (:func:`film_scale`).  Beyond, the film
            is pinned at the sealed pressure of its side: its conductance ~ g^3
            makes the pressure drop there negligible, and its rows would leave the
            narrow ones at round-off.
        stepping: Speed continuation options (reciprocating sweeps).
    """

    film: FilmParams = field(
        default_factory=lambda: FilmParams(
            speed=5.0,
            viscosity=0.01,
            cavitation="jfo",
            flow_factor="persson",
            asperity_shear=1.0e6,
            # a seal is deformed hundreds of times its film: the inverse-hydrodynamic
            # limit, where a central film gap wiggles node to node (FilmParams.upwind)
            upwind="film",
        )
    )
    motion: str = "rotary"
    oil_pressure: float = 0.05e6
    air_pressure: float = 0.0
    face_pressure: bool = False
    feedback: bool = True
    stroke_length: float = 0.1
    zone_gap: float = 20.0
    stepping: SpeedStepping = field(default_factory=lambda: SpeedStepping(film_presolve=False))

    def __post_init__(self) -> None:
        super().__post_init__()
        check_choice("motion", self.motion, MOTIONS)
        check_range("oil_pressure", self.oil_pressure, 0.0, 5e6, unit="Pa")
        check_range("air_pressure", self.air_pressure, 0.0, 5e6, unit="Pa")
        check_positive("stroke_length", self.stroke_length, "m")
        check_range("zone_gap", self.zone_gap, 2.0, 1e4, unit="film scales")
        if self.motion == "rotary" and self.film.speed < 0.0:
            raise ParameterError(
                f"film.speed = {self.film.speed!r} m/s: a rotary shaft speed is >= 0 "
                "(the turning direction does not change an axisymmetric seal)"
            )
        if self.contact.model == "none":
            raise ParameterError(
                "contact.model = 'none': the installed lip needs an asperity contact law"
            )
        for name, own in (("inlet_pressure", "oil_pressure"), ("outlet_pressure", "air_pressure")):
            if getattr(self.film, name) != 0.0:  # one name for one quantity
                raise ParameterError(
                    f"film.{name} = {getattr(self.film, name)!r} Pa: the lip's film edges hold "
                    f"the sealed pressures; set {own} [Pa] instead"
                )
        if self.film.flow_factor == "persson" and self.contact.model == "stiff":
            raise ParameterError(
                "film.flow_factor = 'persson' needs a rough contact law (contact.model = "
                "'persson' or 'exponential'), not 'stiff'"
            )


# ---------------------------------------------------------------- building
@dataclass
class LubricatedLip:
    """The installed lip with its film (what :func:`build` returns).

    Attributes:
        problem: The coupled problem (position control at the nominal shaft radius).
        install: The dry installation it started from (its figures and mesh).
        face_pressures: Constants of the sealed oil and air pressures on the free
            faces [Pa] (``face_pressure = true``), else None.
        film_only: The frozen-geometry film solver (``feedback = false``), else None.
        rough_start: Roughness scale the coupled problem starts at (a stroking rod
            smoother than :data:`~dolfinx_seal.scenes.lip_install.INSTALL_H_RMS`:
            pressurised and brought to speed at the installation's rough scale,
            where the film forms from a mixed start, then walked to its own
            roughness; 1: no walk).
    """

    problem: SolidContactProblem
    install: Any
    face_pressures: tuple[Any, Any] | None = None
    film_only: Any = None
    rough_start: float = 1.0
    z_installed: float = math.nan

    def destroy(self) -> None:
        """Free the PETSc objects of the coupled and the film-only solvers (collective)."""
        self.problem.destroy()
        if self.film_only is not None:
            self.film_only.destroy()

    @property
    def sealed_pressures(self) -> tuple[float, float]:
        """The oil and air pressures [Pa] the film's edges hold now."""
        return self.problem.film._edge_values


def film_parameters(params: LipParameters) -> FilmParams:
    """The film as solved: edge pressures from the sealed pressures, and no
    cavitation bounds where the film has no transport and the sealed pressures
    are >= 0 (the pressure then lies between them: maximum principle)."""
    f = params.film
    transport = params.motion == "reciprocating" and f.speed != 0.0
    cav = f.cavitation if transport else "none"
    return dataclasses.replace(
        f, cavitation=cav, inlet_pressure=params.oil_pressure, outlet_pressure=params.air_pressure
    )


def sealed_face_work(
    prob: SolidContactProblem, tm: Any, oil: Any, air: Any
) -> Any:  # a residual term
    """Virtual work of the sealed pressures ``oil``, ``air`` [Pa] (Constants) on the
    free faces of the lip: ``oil_side`` and the spring groove, ``air_side``
    (follower loads on the current surface)."""
    w = 0
    for tag, p in (("oil_side", oil), ("spring_groove", oil), ("air_side", air)):
        w += tractions.pressure_work(p, prob.F, prob.N3, prob.v3, prob.weight,
                                     prob.ds(tm.tag(tag)))  # fmt: skip
    return -w


def film_scale(params: LipParameters, z: np.ndarray, p: np.ndarray, speed: float) -> float:
    """The gap scale [m] of the lip's film: the rms roughness, or, for a rod stroking
    at ``|speed|``, the thicker of it and the film inverse hydrodynamics predicts
    from the dry contact pressure ``p(z)`` (Blok's ``h* = sqrt(8 eta U / (9 w))``,
    the larger of the two stroke directions).  It sets where the lubricated zone
    ends (``zone_gap`` times it: the zone must reach well beyond the film a
    smooth rod carries, micrometres where its h_rms is tens of nanometres) and
    the scale of the film's rows."""
    from dolfinx_seal.verification.seal_leakage import ihl_film

    h = params.roughness.build().h_rms()
    if params.motion != "reciprocating" or speed == 0.0:
        return h
    return max(h, *(ihl_film(z, p, params.film.viscosity, s * abs(speed)) for s in (1.0, -1.0)))


def build(params: LipParameters, speed_scale: float | None = None) -> LubricatedLip:
    """Install the lip dry, then build the coupled problem with the film on the
    same mesh and start it from the installed state (sealed pressures at zero).
    ``speed_scale`` [m/s]: the largest rod speed the problem will be solved at
    (default ``|film.speed|``; it sets the film's scale, :func:`film_scale`)."""
    import dolfinx

    inst = install(params)
    dry, tm = inst.problem, inst.mesh
    lp = params.lip
    fp = film_parameters(params)
    _, p_pc = dry.surface_values(dry.p_cont, average=True)
    _, z_pc = dry.surface_values(dry.x[1], average=True)
    order = np.argsort(z_pc)
    width, z_installed = moment_width(dry)
    law = dry.law
    speed = abs(params.film.speed) if speed_scale is None else abs(speed_scale)
    gap_scale = film_scale(params, z_pc[order], p_pc[order], speed)
    scales = FilmScales(
        pressure=float(p_pc.max()), length=0.5 * width, gap=gap_scale, element=lp.h_contact
    )
    film = SurfaceFilm(
        fp, scales, h_rms=params.roughness.h_rms, rms_slope=getattr(law, "rms_slope", math.nan),
        e_star=params.material.E_star,
        psd=params.roughness.build() if fp.flow_factor == "persson" else None,
    )  # fmt: skip
    # a rod at rest shears nothing axially: only a moving rod is an axial counter-surface
    axial = params.motion == "reciprocating" and params.film.speed != 0.0
    counter = Shaft("axial" if axial else "rotary")
    faces = None
    terms = []
    if params.face_pressure and params.feedback:
        faces = (dolfinx.fem.Constant(tm.mesh, 0.0), dolfinx.fem.Constant(tm.mesh, 0.0))
        terms = [lambda prob: sealed_face_work(prob, tm, *faces)]
    snes_type = {"jfo": "vinewtonssls", "reynolds": "vinewtonrsls"}.get(fp.cavitation, "newtonls")
    prob = build_problem(
        params, tm, law, inst.spring, position0=lp.shaft_radius, film=film, counter=counter,
        extra_terms=terms,
        # rtol 1e-13: the solid's rows set the residual norm; the film's rows at the
        # constriction carry a flow 1e-7 of the wide gap's and converge with them only
        # at this depth (mass balance 1e-4 at 1e-10, 3e-10 at 1e-13; quadratic steps)
        snes=SNESOptions(max_it=60, rtol=1e-13, snes_type=snes_type), name="lip",
        # axial friction of a stroking rod shears the lip as a whole: only the radial
        # motion, which the stiff contact law drives, is held to half an element
        max_step=None if fp.speed == 0.0 or params.motion == "rotary" else 0.2 * width,
    )  # fmt: skip
    prob.spring_fraction = 1.0
    rough = inst.rough_scale if axial and inst.rough_state is not None else 1.0
    prob.w.x.array[:] = dry.w.x.array if rough == 1.0 else inst.rough_state[0]
    prob.w.x.scatter_forward()
    prob.roughness_scale.value = rough
    prob.set_fraction(1.0)
    film.set_edge_pressures(0.0, 0.0)  # start from zero sealed pressures
    film.restrict_to_gap(params.zone_gap * gap_scale, [prob.solver])
    if film.has_transport:  # pressurise at a slow start speed; solve_speed walks up from it
        film.set_speed(start_speed(params.film.speed))
    out = LubricatedLip(prob, inst, faces, rough_start=rough, z_installed=z_installed)
    if not params.feedback:
        out.film_only = film.make_solver(
            with_snes_type(prob.solver.options, snes_type), name="lip film"
        )
    dry.solver.destroy()
    return out


def set_sealed_pressures(lub: LubricatedLip, oil: float, air: float) -> None:
    """Set the sealed oil and air pressures [Pa] (film edges and, when on, faces)."""
    lub.problem.film.set_edge_pressures(oil, air)
    if lub.face_pressures is not None:
        lub.face_pressures[0].value = oil
        lub.face_pressures[1].value = air


def apply_pressures(lub: LubricatedLip, params: LipParameters, t: float) -> None:
    """Set the sealed pressures to the fraction ``t`` of those of ``params``."""
    set_sealed_pressures(lub, t * params.oil_pressure, t * params.air_pressure)


def move_oil_pressure(lub: LubricatedLip, params: LipParameters) -> dict[str, Any]:
    """Move the sealed pressures from their current values to those of ``params``
    and solve: one film solve on the frozen lip (``feedback = false``), else the
    coupled problem with adaptive steps from the last converged state (a failed
    step is cut and retried, :meth:`SolidContactProblem.ramp`)."""
    prob = lub.problem
    t0 = time.perf_counter()
    (oil0, air0), target = lub.sealed_pressures, (params.oil_pressure, params.air_pressure)
    where = f"lip at oil pressure {target[0]:g} Pa"
    if lub.film_only is not None:
        set_sealed_pressures(lub, *target)
        hist = lub.film_only.solve(where=f"{where} (frozen lip)")
        return {"newton_iterations": hist.newton_iterations, "pressure_steps": 1,
                "solve_time_s": time.perf_counter() - t0}  # fmt: skip
    prob.pressure_ramp = lambda t: set_sealed_pressures(
        lub, oil0 + t * (target[0] - oil0), air0 + t * (target[1] - air0)
    )
    try:
        n0 = len(prob.steps)
        prob.ramp(SteppingOptions(first=1.0, grow=2.0, easy=8, max_steps=60, predictor=False))
        steps = prob.steps[n0:]
    except SolverError as e:  # say it in the user's terms: the pressure reached
        t = float(e.partial.get("fraction", 0.0)) if isinstance(e.partial, dict) else 0.0
        reached = oil0 + t * (target[0] - oil0)
        # how far the oil pressure on the oil-side flank has pushed the band
        _, z_c = moment_width(prob)
        shift = z_c - lub.z_installed
        raise SolverError(
            f"the sealed oil pressure could not be raised beyond {reached:.4g} Pa on the "
            f"way from {oil0:.4g} to {target[0]:.4g} Pa (the band had moved "
            f"{shift * 1e3:+.3g} mm axially from its installed place): {e.what}",
            where=where,
            history=e.history,
            partial={"oil_pressure": reached, "fraction": t},
        ) from e
    finally:
        prob.pressure_ramp = None
    return {
        "newton_iterations": int(sum(s.newton_iterations for s in steps)),
        "pressure_steps": len(steps),
        "solve_time_s": time.perf_counter() - t0,
    }


solve_pressures = move_oil_pressure  # from the zero pressures of a fresh build


def solve_speed(lub: LubricatedLip, params: LipParameters) -> dict[str, Any]:
    """Reciprocating: walk the rod speed from a slow start to ``film.speed``
    (speed continuation of one sign).  Rotary or zero speed: nothing to solve."""
    prob = lub.problem
    target = params.film.speed
    if params.motion == "rotary" or target == 0.0:
        return {"newton_iterations": 0, "continuation_steps": 0}
    film = prob.film
    v0 = start_speed(target)
    film.set_speed(v0)
    t0 = time.perf_counter()
    its, steps = 0, 0
    if v0 != target:
        recs = speed_sweep(prob, [target], lambda *_: None, dict, params.stepping)
        if not recs[-1].converged:
            raise SolverError(
                f"the lip film did not reach film.speed = {target:g} m/s: {recs[-1].error}",
                where="lip speed continuation",
                partial={"speed": float(film.speed.value)},
            )
        its += recs[-1].newton_iterations
        steps += recs[-1].steps
    if lub.rough_start != 1.0 and float(prob.roughness_scale.value) != 1.0:
        its += prob.walk_roughness(lub.rough_start)  # at speed: the film keeps the lip off
    return {"newton_iterations": its, "continuation_steps": steps,
            "speed_time_s": time.perf_counter() - t0}  # fmt: skip


def start_speed(speed: float) -> float:
    """The rod speed [m/s] a reciprocating lip is pressurised at before it walks to
    ``speed``: ``START_SPEED`` with the sign of ``speed`` (or ``speed`` if slower)."""
    return math.copysign(min(abs(speed), START_SPEED), speed)


START_SPEED = 1e-4  # m/s: the Couette flux is then a small part of the static film's


# ---------------------------------------------------------------- results
def results(lub: LubricatedLip, params: LipParameters) -> dict[str, Any]:
    """Scalars of a solved point (SI; keys of the results contract)."""
    prob, film = lub.problem, lub.problem.film
    R_s = params.lip.shaft_radius
    ds = prob.ds_c
    speed = float(film.speed.value) if film.has_couette else 0.0
    load_fluid = prob.integrate(film.normal_force_integrand(), ds)
    fn = prob.asperity_force_integrand()
    load_contact = prob.integrate(fn, ds)
    normal = load_fluid + load_contact
    q_oil, q_air = film.edge_flows()  # outflows through the oil and the air end [m^3/s]
    leak = q_air
    flow = max(abs(q_oil), abs(q_air))
    vals = _by_z(film.film_values())
    z, gap, p, theta = vals["x"][:, 1], vals["gap"], vals["p"], vals["theta"]
    Xs, pc = _surface_by_z(prob, prob.p_cont)
    width, z_c = moment_width(prob)
    # the pressure that carries the lip: asperities and fluid (the peak and the band
    # of a full film, where the asperity pressure vanishes)
    band, z_band = moment_width(prob, fn + film.normal_force_integrand())
    _, p_total = _surface_by_z(prob, prob.p_cont + film.p)
    i_peak = int(np.argmax(p_total))
    z_peak = float(np.interp(Xs[i_peak, 1], vals["X"][:, 1], z))
    A = area_fraction(prob.p_cont, film.e_star, film.rms_slope)
    real = prob.integrate(A * film.da, ds)
    out: dict[str, Any] = {
        "motion": params.motion,
        "speed": float(params.film.speed),
        "oil_pressure": params.oil_pressure,
        "air_pressure": params.air_pressure,
        "leakage_rate": leak,
        "leakage_ml_per_h": leak * ML_PER_H,
        "oil_side_inflow": -q_oil,
        "mass_balance_error": abs(q_oil + q_air) / flow if flow > 0 else 0.0,
        "mass_imbalance": abs(q_oil + q_air),
        "radial_load": normal / (2.0 * math.pi * R_s),
        "normal_load": normal,
        "load_fluid": load_fluid,
        "load_contact": load_contact,
        "fluid_load_fraction": load_fluid / normal,
        "contact_width": width,
        "load_band_width": band,
        "z_load_centre": z_band,
        "z_peak_pressure": z_peak,
        "h_min": float(gap.min()),
        "h_central": float(np.interp(z_peak, z, gap)),
        "max_fluid_pressure": float(p.max()),
        "max_contact_pressure": float(pc.max()),
        "real_contact_area": real,
        # real over nominal area of the asperity band (0: no asperity contact)
        "contact_area_fraction": real / (2.0 * math.pi * R_s * width) if width > 0 else 0.0,
        "dofs": prob.dofs,
        "dof_counts": prob.dof_counts(),
        "ranks": world().size,
        **complementarity_of(prob),
    }
    # a key of every point (a sweep's rows share one header)
    out["film_below_continuum"] = bool(out["h_min"] < CONTINUUM_FILM)
    if out["film_below_continuum"]:
        get_logger().warning(
            "lip: the film is thinner than a continuum film (h_min %.3g m < %.0e m): the "
            "seal is in (near) full asperity contact; the Couette shear eta U / u and "
            "the friction it gives are outside the model",
            out["h_min"],
            CONTINUUM_FILM,
        )
    out["z_contact_centre"] = z_c if width > 0 else z_band  # the load's centre in full film
    if film.has_theta:
        cav = theta < 1.0 - 1e-8
        dz = np.gradient(z)
        out["cavitation_fraction"] = float(dz[cav].sum() / dz.sum())
    # friction on the shaft: hoop (rotary) or axial (reciprocating) shear integrated
    if params.motion == "rotary":  # hoop shear: asperities and Couette, no pressure gradient
        parts = {
            "asperity": prob.integrate(film.asperity_shear() * film.da, ds),
            "couette": prob.integrate(_couette_shear(film, params.film.speed), ds),
        }
        force = sum(parts.values())
        out["friction_torque"] = force * R_s
        out["friction_torque_couette"] = parts["couette"] * R_s
        out["friction_torque_asperity"] = parts["asperity"] * R_s
        out["power_loss"] = force * params.film.speed
        out["mu"] = force / normal
    else:  # axial shear on the rod, positive along +z; the drag opposes the rod's motion
        parts = {k: prob.integrate(v, ds) for k, v in film.friction_parts().items()}
        force = math.copysign(1.0, speed) * sum(parts.values()) if speed else parts["asperity"]
        out["friction_force"] = force
        for k, v in parts.items():
            out[f"friction_{k}"] = v
        out["mu"] = force / normal
        if speed:
            # oil left on the rod per unit area on the way out (or carried back on the
            # way in): the flow through the air end over the rod's sweep rate [m]
            out["transport_film_thickness"] = leak / (2.0 * math.pi * R_s * speed)
    reaction, hoop = radial_balance(prob, lub.install.mesh.tag("clamped"))
    f_spring = lub.install.spring.get("spring_force", 0.0)
    # sealed pressures on the free faces do radial work the balance does not count
    if not (params.face_pressure and params.feedback):
        out["radial_balance_error"] = (normal - f_spring + reaction - hoop) / normal
    return out


def _by_z(vals: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Film nodal values ordered by their reference axial coordinate (oil to air;
    monotone along the band, and so is the current one)."""
    order = np.argsort(vals["X"][:, 1], kind="stable")
    return {k: v[order] for k, v in vals.items()}


def _surface_by_z(prob: SolidContactProblem, expr: Any) -> tuple[np.ndarray, np.ndarray]:
    """Lumped P1 surface values of ``expr`` on the band, ordered by reference z."""
    X, v = prob.surface_values(expr, average=True)
    order = np.argsort(X[:, 1], kind="stable")
    return X[order], v[order]


def band_nodes(lub: LubricatedLip) -> dict[str, np.ndarray]:
    """The P2 nodes of the contact band ordered along it (oil to air): current
    radius ``r`` and axial position ``z``, and the separation ``u`` [m]; vertex,
    mid-side node, vertex, ... (the FEM's own gap field, for
    :func:`~dolfinx_seal.verification.seal_leakage.static_leakage`)."""
    prob = lub.problem
    X, r = prob.surface_values(prob.x[0])
    _, z = prob.surface_values(prob.x[1])
    _, u = prob.surface_values(prob.gap)
    order = np.argsort(X[:, 1], kind="stable")
    return {"r": r[order], "z": z[order], "u": u[order]}


def _couette_shear(film: SurfaceFilm, speed: float) -> Any:
    """Hoop Couette shear ``eta U theta / u`` times ``da/dA`` [Pa] at shaft speed U."""
    return film.params.viscosity * speed * film.theta / film.g * film.da


def write_film(out: Path, lub: LubricatedLip, params: LipParameters) -> None:
    """``film.csv`` (z from oil to air, SI) and ``film.png`` on rank 0."""
    prob, film = lub.problem, lub.problem.film
    vals = _by_z(film.film_values())
    Xs, pc = _surface_by_z(prob, prob.p_cont)
    A = area_fraction(prob.p_cont, film.e_star, film.rms_slope)
    _, af = _surface_by_z(prob, A)
    shear_expr = film.asperity_shear()
    if params.motion == "rotary":
        shear_expr = shear_expr + _couette_shear(film, params.film.speed) / film.da
    else:
        shear_expr = film.shear_on_rubber()
    _, tau = _surface_by_z(prob, shear_expr)
    z = vals["x"][:, 1]

    def on_film(v: np.ndarray) -> np.ndarray:  # P1 surface values -> film nodes
        return np.interp(vals["X"][:, 1], Xs[:, 1], v)

    cols = {
        "z": z,
        "contact_pressure": on_film(pc),
        "fluid_pressure": vals["p"],
        "separation": vals["gap"],
        "film_fraction": vals["theta"],
        "area_fraction": on_film(af),
        "shear": on_film(tau),
    }
    if world().rank != 0:
        return
    out.mkdir(parents=True, exist_ok=True)
    np.savetxt(out / "film.csv", np.column_stack(list(cols.values())), delimiter=",",
               header=",".join(cols), comments="")  # fmt: skip
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(6.4, 6.0), sharex=True)
    zz = z * 1e3
    ax1.plot(zz, cols["contact_pressure"] / 1e6, "r-", lw=2, label="asperity contact")
    ax1.plot(zz, cols["fluid_pressure"] / 1e6, "b-", lw=2, label="fluid")
    ax1.set_ylabel("pressure [MPa]")
    ax1.legend(frameon=False)
    ax1.set_title(_title(params))
    ax2.semilogy(zz, cols["separation"] * 1e6, "g-", lw=2, label="separation u")
    ax2.set_ylabel("separation [um]")
    ax2.set_xlabel("axial position z [mm] (oil side left, air side right)")
    lo = max(float(cols["separation"].min()) * 1e6 / 3, 1e-4)
    ax2.set_ylim(lo, 30 * lo * 10)
    fig.tight_layout()
    fig.savefig(out / "film.png", dpi=120)
    plt.close(fig)


def _title(params: LipParameters) -> str:
    what = "shaft" if params.motion == "rotary" else "rod"
    return (f"lip seal, {params.motion}: {what} {params.film.speed:.3g} m/s, oil "
            f"{params.oil_pressure / 1e6:.3g} MPa, h_rms {params.roughness.h_rms * 1e6:g} um")  # fmt: skip


# ---------------------------------------------------------------- run, sweep
def run(params: LipParameters, out: Path) -> dict[str, Any]:
    """Install, pressurise, bring the rod to speed (reciprocating); write the film
    and ``fields.xdmf``."""
    t0 = time.perf_counter()
    lub = build(params)
    try:
        info = {"install_steps": len(lub.install.problem.steps),
                "install_time_s": lub.install.solve_time_s}  # fmt: skip
        pr = solve_pressures(lub, params)
        sp = solve_speed(lub, params)
        res = results(lub, params)
        res.update(info)
        res.update(pressure_steps=pr["pressure_steps"],
                   newton_iterations=pr["newton_iterations"] + sp["newton_iterations"],
                   wall_time_s=time.perf_counter() - t0, converged=True)  # fmt: skip
        write_film(out, lub, params)
        write_fields(out, lub.problem)
    finally:
        lub.destroy()
    return res


SWEEPABLE = ("oil_pressure", "film.speed")


def sweep(
    params: LipParameters, out: Path, name: str, values: list[float], on_point: Any
) -> list[dict[str, Any]]:
    """Sweeps with one installation: over ``oil_pressure`` (each point from the
    last) or ``film.speed`` (rotary: one solve, the friction at each speed;
    reciprocating: a continuation chain per stroke direction from the static
    pressurised lip, slowest first)."""
    from dolfinx_seal.scenes import set_parameter

    if name == "speed":
        name = "film.speed"
    if name not in SWEEPABLE:
        raise ParameterError(f"lip sweeps run over {' or '.join(SWEEPABLE)} (got --over {name!r})")
    rows: list[dict[str, Any]] = []
    if name == "oil_pressure":
        vals = sorted(float(v) for v in values)
        lub = build(params)
        try:
            for v in vals:
                t0 = time.perf_counter()
                pv = set_parameter(params, "oil_pressure", v)
                info = move_oil_pressure(lub, pv)
                r = results(lub, pv)
                r.update(info, wall_time_s=time.perf_counter() - t0, converged=True)
                rows.append(r)
                if on_point(v, r):
                    write_film(out / f"oil_pressure_{v:.3e}", lub, pv)
        finally:
            lub.destroy()
        return rows
    # speed
    speeds = [float(v) for v in values]
    if params.motion == "rotary":
        if min(speeds) < 0:
            raise ParameterError("film.speed: rotary shaft speeds are >= 0")
        lub = build(set_parameter(params, "film.speed", max(speeds)))
        try:
            t0 = time.perf_counter()
            pr = solve_pressures(lub, params)
            for v in sorted(speeds):
                pv = set_parameter(params, "film.speed", v)
                r = results(lub, pv)
                r.update(newton_iterations=pr["newton_iterations"] if not rows else 0,
                         wall_time_s=time.perf_counter() - t0 if not rows else 0.0,
                         converged=True)  # fmt: skip
                rows.append(r)
                on_point(v, r)
            write_film(out, lub, params)
        finally:
            lub.destroy()
        return rows
    failed: list[dict[str, Any]] = []  # {"speed", "error"}: targets not reached
    for sign in (1.0, -1.0):
        chain = sorted((v for v in speeds if math.copysign(1.0, v) == sign and v != 0), key=abs)
        if not chain:
            continue
        if smooth_rod(params):  # start where the film is thickest, walk down
            chain.reverse()
        lub = build(set_parameter(params, "film.speed", chain[0]), max(map(abs, chain)))
        try:
            _stroke_chain(lub, params, chain, out, rows, on_point, failed)
        finally:
            lub.destroy()
    write_sweep_failures(out, failed)
    strokes = stroke_summary(rows, params.stroke_length)
    if strokes:
        write_strokes(out, strokes)
    return rows


def smooth_rod(params: LipParameters) -> bool:
    """A stroking rod smoother than the installation roughness
    (:data:`~dolfinx_seal.scenes.lip_install.INSTALL_H_RMS`): its chains start at
    their fastest speed, where the film is thickest and the walk from the rough
    scale to its own roughness is easy, and walk down.  (A rough rod's chains walk
    up from the slowest: its mixed start is the cheap one.)  Started at the
    slowest, the smooth rod's film formed a node-to-node wiggle at the outlet
    and continued on a film half as thick as the one started at speed."""
    from dolfinx_seal.scenes.lip_install import INSTALL_H_RMS

    return (params.motion == "reciprocating" and params.contact.model != "stiff"
            and params.roughness.build().h_rms() < INSTALL_H_RMS)  # fmt: skip


def _stroke_chain(
    lub: LubricatedLip, params: LipParameters, chain: list[float], out: Path,
    rows: list[dict[str, Any]], on_point: Any, failed: list[dict[str, Any]],
) -> None:  # fmt: skip
    """One stroke direction of a reciprocating sweep: pressurise, start at the first
    speed of ``chain``, continue through the others (rows appended as they converge;
    the targets not reached appended to ``failed`` with their reason)."""
    from dolfinx_seal.scenes import set_parameter

    t0 = time.perf_counter()
    pr = solve_pressures(lub, params)
    try:
        sp = solve_speed(lub, set_parameter(params, "film.speed", chain[0]))
    except SolverError as e:
        get_logger().error("lip sweep: the chain at %s m/s did not start: %s", chain[0], e)
        failed.append({"speed": chain[0], "error": str(e)})
        failed += [{"speed": v, "error": f"not attempted: the chain at {chain[0]:g} m/s did "
                    "not start"} for v in chain[1:]]  # fmt: skip
        return

    def point(v: float, r: dict[str, Any], lub: LubricatedLip = lub) -> None:
        pv = set_parameter(params, "film.speed", v)
        rr = results(lub, pv)
        rr.update(newton_iterations=r.get("newton_iterations", 0),
                  continuation_steps=r.get("continuation_steps", 1),
                  wall_time_s=r.get("wall_time_s", 0.0), converged=True)  # fmt: skip
        rows.append(rr)
        if on_point(v, rr):
            write_film(out / f"speed_{v:+.3e}", lub, pv)

    r0 = {"newton_iterations": pr["newton_iterations"] + sp["newton_iterations"],
          "wall_time_s": time.perf_counter() - t0}  # fmt: skip
    point(chain[0], r0)
    recs = speed_sweep(lub.problem, chain[1:], point, dict, params.stepping)
    failed += [{"speed": r.speed, "error": r.error} for r in recs if not r.converged]


def stroke_summary(rows: list[dict[str, Any]], stroke_length: float) -> list[dict[str, float]]:
    """Per-cycle oil transport of a reciprocating rod, for each |U| solved in both directions.

    A stroke of length ``L`` at speed ``U`` lasts ``L / |U|``; the oil carried out
    through the air end on the out-stroke is ``V_out = q(+U) L / U`` and the oil
    carried back on the in-stroke ``V_in = -q(-U) L / U`` (``q`` the
    ``leakage_rate``, positive from oil to air).  ``net_leakage_per_cycle = V_out -
    V_in`` [m^3] is the classic rod-seal leakage measure: positive, the seal
    loses oil; negative, it pumps back more than it lets out (steady strokes:
    the film of each stroke direction as if it had always run).
    """
    by_speed = {float(r["speed"]): r for r in rows if r.get("converged", True)}
    out = []
    for u in sorted({abs(v) for v in by_speed if v > 0 and -v in by_speed}):
        q_out, q_in = by_speed[u]["leakage_rate"], by_speed[-u]["leakage_rate"]
        v_out, v_in = q_out * stroke_length / u, -q_in * stroke_length / u
        out.append({
            "speed": u, "stroke_length": stroke_length,
            "out_stroke_volume": v_out, "in_stroke_volume": v_in,
            "net_leakage_per_cycle": v_out - v_in,
            "net_leakage_ml_per_1000_cycles": (v_out - v_in) * 1e6 * 1e3,
            "friction_work_per_cycle": (abs(by_speed[u]["friction_force"])
                                        + abs(by_speed[-u]["friction_force"])) * stroke_length,
        })  # fmt: skip
    return out


def write_strokes(out: Path, strokes: list[dict[str, float]]) -> None:
    """``strokes.csv`` (SI; written whole, on rank 0) beside ``sweep.csv``."""
    from dolfinx_seal.output import write_text_atomic

    keys = list(strokes[0])
    lines = [",".join(keys)] + [",".join(f"{s[k]:.10g}" for k in keys) for s in strokes]
    if world().rank == 0:
        write_text_atomic(Path(out) / "strokes.csv", "\n".join(lines) + "\n")
    world().barrier()


def plot_sweep(rows: list[dict[str, Any]], out_dir: Path, name: str) -> None:
    """``sweep.png``: leakage against oil pressure, or friction against speed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    if name == "oil_pressure":
        x = np.array([r["oil_pressure"] for r in rows]) / 1e6
        ax.plot(x, [r["leakage_ml_per_h"] for r in rows], "ko-", ms=4)
        ax.set_xlabel("oil pressure [MPa]")
        ax.set_ylabel("leakage [ml/h]")
    elif rows and rows[0]["motion"] == "rotary":
        x = np.array([r["speed"] for r in rows])
        ax.loglog(x, [r["friction_torque"] for r in rows], "ko-", ms=4, label="total")
        ax.loglog(x, [r["friction_torque_couette"] for r in rows], "b^--", ms=3, label="Couette")
        ax.loglog(x, [r["friction_torque_asperity"] for r in rows], "rs--", ms=3,
                  label="asperity")  # fmt: skip
        ax.set_xlabel("shaft surface speed [m/s]")
        ax.set_ylabel("friction torque [N m]")
        ax.legend(frameon=False)
    else:
        x = np.array([r["speed"] for r in rows])
        order = np.argsort(x)
        ax.semilogx(np.abs(x[order]), [rows[i]["friction_force"] for i in order], "ko", ms=4)
        ax.set_xlabel("|rod speed| [m/s]")
        ax.set_ylabel("friction force [N]")
    fig.tight_layout()
    fig.savefig(Path(out_dir) / "sweep.png", dpi=120)
    plt.close(fig)


SCENE = Scene(
    name="lip",
    summary="lubricated radial lip seal (axisymmetric): leakage, friction torque, rod strokes",
    parameters=LipParameters,
    run=run,
    sweep=lambda *a: sweep(*a),
    plot_sweep=lambda *a: plot_sweep(*a),
)

__all__ = [
    "SCENE",
    "LipParameters",
    "LubricatedLip",
    "build",
    "results",
    "run",
    "stroke_summary",
    "sweep",
]
