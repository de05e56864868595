"""Scene ``cylinder``: a rubber cylinder pressed on a rigid flat (S1 section 2), dry.

2D plane strain, the S1 figure-4 system by default (R = 1 cm, F/L = 100 N/m,
E = 10 MPa, nu = 0.5, h_rms = 1 um, D_f = 2.2), Persson asperity contact as a
nonlinear traction on the deformed surface, force control (the flat's position
is a global unknown), neo-Hookean mixed u-p bulk.  No film unknowns: this
scene is dry (the lubricated cylinder adds the film on top of it).

Reports the normal load, contact half-width (from the second moment of the
pressure, ``a = 2 <x^2>^(1/2)``, exact for a Hertz ellipse), peak pressure, the
Hertz references, the real contact area per unit length, and the pressure
profile (``pressure.csv``, ``pressure.png``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import ufl

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.meshing import create_mesh
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.params import check_int_range, check_positive, check_range
from dolfinx_seal.roughness.psd import RoughnessParams
from dolfinx_seal.scenes import Scene
from dolfinx_seal.scenes.common import (
    ContactLawParams,
    MaterialParams,
    hertz_line,
    solve_dry,
    write_profile,
)
from dolfinx_seal.solid import tractions
from dolfinx_seal.solid.asperity import area_fraction
from dolfinx_seal.solid.counter_surface import Flat
from dolfinx_seal.solid.kinematics import PlaneStrain
from dolfinx_seal.solid.problem import Dirichlet, SolidContactProblem
from dolfinx_seal.solvers import SNESOptions


@dataclass(frozen=True)
class CylinderParameters:
    """Dry cylinder on a flat (SI units).

    Attributes:
        radius: Cylinder radius R [m].
        load: Normal load per unit length F/L [N/m].
        material: Rubber bulk.
        roughness: Roughness of the combined surfaces (S1: h_rms 1 um, D_f 2.2).
        contact: Asperity contact law.
        h_contact: Element size at the contact [m] (at most a_Hertz / 4).
        degree: Displacement degree (2; the mixed pressure is one lower).
    """

    radius: float = 0.01
    load: float = 100.0
    material: MaterialParams = field(default_factory=MaterialParams)
    roughness: RoughnessParams = field(default_factory=RoughnessParams)
    contact: ContactLawParams = field(default_factory=ContactLawParams)
    h_contact: float = 10e-6
    degree: int = 2

    def __post_init__(self) -> None:
        check_positive("radius", self.radius, "m")
        check_positive("load", self.load, "N/m")
        check_int_range("degree", self.degree, 1, 3)
        a, _ = hertz_line(self.load, self.radius, self.material.E_star)
        check_range(
            "h_contact", self.h_contact, 0.0, a / 4.0, lo_open=True, unit="m (<= a_Hertz/4)"
        )
        if a > 0.3 * self.radius:
            raise ParameterError(
                f"load = {self.load!r} N/m gives a Hertz half-width {a:.3g} m > 0.3 R: "
                "outside the small-contact regime of this scene"
            )


def run(params: CylinderParameters, out: Path) -> dict[str, Any]:
    """Solve the dry cylinder; write the pressure profile; return the results."""
    t0 = time.perf_counter()
    mat = params.material.build()
    e_star = params.material.E_star
    a_h, p_h = hertz_line(params.load, params.radius, e_star)
    law, law_info = params.contact.build(params.roughness, e_star, approach=a_h**2 / params.radius)
    tm = create_mesh(
        "cylinder", comm=COMM_WORLD, radius=params.radius, contact_half_width=a_h,
        h_contact=params.h_contact, h_arc=max(4 * params.h_contact, min(60e-6, a_h)),
    )  # fmt: skip
    prob = SolidContactProblem(
        tm.mesh, tm.facet_tags, PlaneStrain(), mat, Flat(axis=1), law, tm.tag("contact"),
        [Dirichlet(tm.tag("load"))], control="force", target=params.load, degree=params.degree,
        snes=SNESOptions(max_it=40, dtol=1e12), name="cylinder", max_step=0.5 * params.h_contact,
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
    summary="dry rubber cylinder on a flat (S1 sec 2): Persson contact, Hertz check",
    parameters=CylinderParameters,
    run=run,
)

__all__ = ["SCENE", "CylinderParameters", "dry_results", "run"]
