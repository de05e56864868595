"""Scene ``ball``: a rubber ball pressed on a rigid flat (S1 section 3), dry.

3D half ball (symmetry plane ``y = 0``, which contains the sliding direction x)
or the full ball; the S1 figure-18 system by default (R = 1 cm, F = 1.3 N,
E* = 1.6 MPa, nu = 0.5, h_rms = 1 um, D_f = 2.2).  Persson asperity contact as a
nonlinear traction on the deformed surface, force control, mixed u-p
neo-Hookean bulk.  Dry: no film unknowns.

Reports the total normal load (twice the half model's), the contact radius
from the second moment of the pressure (``a = (5 <r^2> / 2)^(1/2)``, exact for a
Hertz distribution), peak pressure, the Hertz references, and the pressure
along the x axis (``pressure.csv``, ``pressure.png``).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import ufl

from dolfinx_seal.errors import ParameterError
from dolfinx_seal.meshing import create_mesh
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.params import check_choice, check_int_range, check_positive, check_range
from dolfinx_seal.roughness.psd import RoughnessParams
from dolfinx_seal.scenes import Scene
from dolfinx_seal.scenes.common import (
    ContactLawParams,
    MaterialParams,
    hertz_point,
    solve_dry,
    write_profile,
)
from dolfinx_seal.scenes.cylinder import dry_results
from dolfinx_seal.solid.counter_surface import Flat
from dolfinx_seal.solid.kinematics import Solid3D
from dolfinx_seal.solid.problem import Dirichlet, SolidContactProblem
from dolfinx_seal.solvers import SNESOptions


@dataclass(frozen=True)
class BallParameters:
    """Dry ball on a flat (SI units).

    Attributes:
        radius: Ball radius R [m].
        load: Total normal load F [N] (the half model carries F/2).
        material: Rubber bulk (S1 fig 18: E* = 1.6 MPa, i.e. E = 1.2 MPa at nu = 0.5).
        roughness: Roughness (S1: h_rms 1 um, D_f 2.2).
        contact: Asperity contact law.
        shape: ``half`` (symmetry plane y = 0) or ``full``.
        h_contact: Element size at the contact [m] (at most a_Hertz / 4).
        degree: Displacement degree.
    """

    radius: float = 0.01
    load: float = 1.3
    material: MaterialParams = field(default_factory=lambda: MaterialParams(E=1.2e6))
    roughness: RoughnessParams = field(default_factory=RoughnessParams)
    contact: ContactLawParams = field(default_factory=ContactLawParams)
    shape: str = "half"
    h_contact: float = 0.25e-3
    degree: int = 2

    def __post_init__(self) -> None:
        check_positive("radius", self.radius, "m")
        check_positive("load", self.load, "N")
        check_choice("shape", self.shape, ("half", "full"))
        check_int_range("degree", self.degree, 1, 3)
        a, _ = hertz_point(self.load, self.radius, self.material.E_star)
        check_range(
            "h_contact", self.h_contact, 0.0, a / 4.0, lo_open=True, unit="m (<= a_Hertz/4)"
        )
        if a > 0.4 * self.radius:
            raise ParameterError(
                f"load = {self.load!r} N gives a Hertz radius {a:.3g} m > 0.4 R: outside the "
                "small-contact regime of this scene"
            )


def run(params: BallParameters, out: Path) -> dict[str, Any]:
    """Solve the dry ball; write the pressure profile along x; return the results."""
    t0 = time.perf_counter()
    mat = params.material.build()
    e_star = params.material.E_star
    a_h, p_h = hertz_point(params.load, params.radius, e_star)
    law, law_info = params.contact.build(params.roughness, e_star, approach=a_h**2 / params.radius)
    tm = create_mesh(
        "ball", comm=COMM_WORLD, radius=params.radius, shape=params.shape, contact_radius=a_h,
        h_contact=params.h_contact, h_cap=max(2 * params.h_contact, min(0.3e-3, a_h / 2)),
    )  # fmt: skip
    half = params.shape == "half"
    factor = 2.0 if half else 1.0
    bcs = [Dirichlet(tm.tag("load"))]
    if half:
        bcs.append(Dirichlet(tm.tag("symmetry"), component=1))
    prob = SolidContactProblem(
        tm.mesh, tm.facet_tags, Solid3D(), mat, Flat(axis=2), law, tm.tag("contact"), bcs,
        control="force", target=params.load / factor, degree=params.degree,
        snes=SNESOptions(max_it=60, dtol=1e12), name="ball", max_step=0.5 * params.h_contact,
        max_gap_step=3.0 * _decay_length(law),
    )  # fmt: skip
    X = prob.X
    guess = p_h * ufl.sqrt(ufl.max_value(1.0 - (X[0] ** 2 + X[1] ** 2) / a_h**2, 0.0))
    info = solve_dry(prob, guess, p_h)
    res = dry_results(prob, params.load / factor, line=False, symmetry_factor=factor)
    res.update(info)
    res.update(
        hertz_contact_radius=a_h, hertz_peak_pressure=p_h, dofs=prob.dofs, ranks=COMM_WORLD.size,
        wall_time_s=time.perf_counter() - t0, converged=True, contact_law=law.name, **law_info,
    )  # fmt: skip
    Xs, p = prob.surface_values(prob.p_cont, average=True)
    on_axis = np.abs(Xs[:, 1]) < 1e-9 * params.radius
    x, pa = Xs[on_axis, 0], p[on_axis]
    order = np.argsort(x)
    x, pa = x[order], pa[order]
    hz = p_h * (1.0 - (x / a_h) ** 2).clip(min=0.0) ** 0.5
    write_profile(
        out, "pressure", {"x_m": x, "p_contact_Pa": pa, "p_hertz_Pa": hz},
        title=f"dry ball, F = {params.load:g} N, law: {law.name} (y = 0)",
        xlabel="x [mm]", ylabel="contact pressure [MPa]",
        curves={"FEM": (x * 1e3, pa / 1e6), "Hertz": (x * 1e3, hz / 1e6)},
    )  # fmt: skip
    return res


def _decay_length(law: Any) -> float:
    """Gap over which the contact pressure changes by a factor e (at large gaps) [m]."""
    return law.h_rms / law.alpha


SCENE = Scene(
    name="ball",
    summary="dry rubber ball on a flat (S1 sec 3): 3D half ball, Persson contact, Hertz check",
    parameters=BallParameters,
    run=run,
)
