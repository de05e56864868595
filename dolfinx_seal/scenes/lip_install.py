"""Scene ``lip-install``: a radial lip seal mounted on its shaft (S0 section 3.1, static).

Axisymmetric (r, z) lip of :mod:`geometry.lip` (an 80 mm shaft seal by
default), bonded to its metal case along ``clamped``.  The undeformed tip lies
``interference`` inside the shaft; installation is modelled by growing the
rigid shaft radius from the tip radius to its nominal value (position control
with adaptive stepping: strains well above 30 % at the tip), optionally with
the garter spring load on the spring groove.  No film: the static contact.

Reports the radial load per unit circumference ``radial_load`` (the total
radial contact force divided by ``2 pi R_shaft``) [N/m], the contact width
(the width of the uniform band with the same force and second moment),
the peak and mean contact pressure, and the contact pressure profile along z
(``pressure.csv``, ``pressure.png``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import dolfinx
import numpy as np
import ufl
from mpi4py import MPI

from dolfinx_seal.compat import interpolation_points
from dolfinx_seal.meshing import create_mesh
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.params import check_int_range, check_nonnegative
from dolfinx_seal.roughness.psd import RoughnessParams
from dolfinx_seal.scenes import Scene
from dolfinx_seal.scenes.common import ContactLawParams, MaterialParams, write_profile
from dolfinx_seal.solid import tractions
from dolfinx_seal.solid.counter_surface import Shaft
from dolfinx_seal.solid.kinematics import Axisymmetric
from dolfinx_seal.solid.problem import Dirichlet, SolidContactProblem, SteppingOptions
from dolfinx_seal.solvers import SNESOptions
from geometry.lip import LipSealParams


@dataclass(frozen=True)
class LipInstallParameters:
    """Lip seal installed on its shaft (SI units).

    Attributes:
        lip: Lip geometry and mesh (:class:`geometry.lip.LipSealParams`: shaft radius,
            interference, angles, spring groove, ...).
        material: Rubber (NBR-like Mooney-Rivlin, E = 8 MPa, nearly incompressible).
        roughness: Lip/shaft roughness for the Persson law (S0: h_rms 10 um is the
            lip; a ground shaft is much smoother; default 1 um combined).
        contact: Asperity contact law (``persson`` or ``stiff`` for a smooth contact).
        spring_load: Garter spring radial force per unit circumference of the groove
            [N/m] (0: no spring).
        degree: Displacement degree.
    """

    lip: LipSealParams = field(default_factory=LipSealParams)
    material: MaterialParams = field(
        default_factory=lambda: MaterialParams(model="mooney-rivlin", E=8e6, nu=0.5)
    )
    roughness: RoughnessParams = field(default_factory=RoughnessParams)
    contact: ContactLawParams = field(default_factory=ContactLawParams)
    spring_load: float = 0.0
    degree: int = 2

    def __post_init__(self) -> None:
        check_nonnegative("spring_load", self.spring_load, "N/m")
        check_int_range("degree", self.degree, 1, 3)


def run(params: LipInstallParameters, out: Path) -> dict[str, Any]:
    """Install the lip; write the pressure profile; return the results."""
    t0 = time.perf_counter()
    lp = params.lip
    mat = params.material.build()
    e_star = params.material.E_star
    # the Hertz-like approach scale of the stiff law: the interference itself
    law, law_info = params.contact.build(params.roughness, e_star, approach=lp.interference)
    tm = create_mesh("lip", lp, comm=COMM_WORLD)
    r_tip = lp.shaft_radius - lp.interference

    def spring(prob: SolidContactProblem) -> Any:
        if params.spring_load == 0.0:
            return None
        ds_g = prob.ds(tm.tag("spring_groove"))
        # uniform pressure on the groove with a net radial force spring_load * 2 pi r_groove
        nr = -prob.N3[0]  # inward radial component of the outward normal
        area_r = prob.integrate(nr * prob.weight, ds_g)
        r_g = prob.integrate(prob.X[0] * prob.weight, ds_g) / prob.integrate(prob.weight, ds_g)
        p_s = params.spring_load * 2.0 * math.pi * r_g / area_r
        return -tractions.pressure_work(p_s, prob.F, prob.N3, prob.v3, prob.weight, ds_g)

    # shaft radius grows from just inside the tip to its nominal value
    start = r_tip - 0.02 * lp.interference
    prob = SolidContactProblem(
        tm.mesh, tm.facet_tags, Axisymmetric(), mat, Shaft(), law, tm.tag("contact"),
        [Dirichlet(tm.tag("clamped"))], control="position", target=lp.shaft_radius,
        position0=start, degree=params.degree, snes=SNESOptions(max_it=25), name="lip-install",
        extra_residual=spring if params.spring_load > 0.0 else None,
        max_step=0.5 * lp.h_contact,  # a Newton step moves no node more than half a contact element
    )  # fmt: skip
    t1 = time.perf_counter()
    prob.ramp(SteppingOptions(first=0.02, grow=1.5, easy=8, max_steps=400, predictor=True))
    solve_time = time.perf_counter() - t1
    strain_body, strain_surface = _max_strain(prob)
    fr = prob.contact_force()  # total radial force [N] (2 pi r weighted)
    radial_load = fr / (2.0 * math.pi * lp.shaft_radius)
    _, p = prob.surface_values(prob.p_cont, average=True)
    _, xr = prob.surface_values(prob.x[0], average=True)
    _, xz = prob.surface_values(prob.x[1], average=True)
    z = xz  # current axial position of the surface points
    order = np.argsort(z)
    z, p, xr = z[order], p[order], xr[order]
    pmax = float(p.max())
    width, z_mean = _moment_width(prob)
    res = {
        "radial_load": radial_load,
        "normal_load": fr,
        "load_contact": fr,
        "contact_width": width,
        "max_contact_pressure": pmax,
        "mean_contact_pressure": radial_load / width if width > 0 else 0.0,
        "z_peak_pressure": float(z[np.argmax(p)]),
        "z_contact_centre": z_mean,
        "load_steps": len(prob.steps),
        "newton_iterations": int(sum(s.newton_iterations for s in prob.steps)),
        "solve_time_s": solve_time,
        "max_principal_strain": strain_body,
        "max_principal_strain_contact": strain_surface,
        "dofs": prob.dofs,
        "ranks": COMM_WORLD.size,
        "wall_time_s": time.perf_counter() - t0,
        "converged": True,
        "contact_law": law.name,
        **law_info,
    }
    write_profile(
        out, "pressure", {"z_m": z, "r_m": xr, "p_contact_Pa": p},
        title=f"installed lip: radial load {radial_load:.1f} N/m, width {width * 1e3:.3f} mm",
        xlabel="axial position z [mm] (oil side < 0)", ylabel="contact pressure [MPa]",
        curves={"contact pressure": (z * 1e3, p / 1e6)},
    )  # fmt: skip
    return res


def _moment_width(prob: SolidContactProblem) -> tuple[float, float]:
    """Contact width and centre from the moments of the radial contact force density.

    ``w = sqrt(12 <(z - <z>)^2>)``: the width of the uniform pressure band with the
    same force, centre and second moment (exact for a uniform band; a Hertz
    ellipse of half-width a gives ``w = 1.73 a``).  An integral, it converges with
    the mesh where a threshold on nodal pressures does not.
    """
    fn = -prob.p_cont * ufl.dot(tractions.nanson_normal(prob.F, prob.N3), prob.e_n) * prob.weight
    z = prob.x[1]
    m0 = prob.integrate(fn, prob.ds_c)
    m1 = prob.integrate(fn * z, prob.ds_c) / m0
    var = prob.integrate(fn * (z - m1) ** 2, prob.ds_c) / m0  # centred: no cancellation
    return math.sqrt(12.0 * var), m1


def _max_strain(prob: SolidContactProblem) -> tuple[float, float]:
    """Largest principal logarithmic (Hencky) strain magnitude, in the body and on the
    contact surface.

    In axisymmetry ``C = F^T F`` is block diagonal: the (r, z) block has the
    eigenvalues ``(tr +- sqrt(tr^2 - 4 det)) / 2`` and the hoop one is ``C_tt``.
    The body value is taken at the vertices (P1 interpolation).
    """
    C = prob.F.T * prob.F
    tr = C[0, 0] + C[1, 1]
    det = C[0, 0] * C[1, 1] - C[0, 1] * C[1, 0]
    disc = ufl.sqrt(ufl.max_value(tr * tr - 4.0 * det, 0.0))
    S = dolfinx.fem.functionspace(prob.mesh, ("Lagrange", 1))
    f = dolfinx.fem.Function(S)
    n = S.dofmap.index_map.size_local
    body = surface = 0.0
    for lam2 in ((tr + disc) / 2.0, (tr - disc) / 2.0, C[2, 2]):
        f.interpolate(dolfinx.fem.Expression(lam2, interpolation_points(S.element)))
        body = max(body, float(np.abs(0.5 * np.log(f.x.array[:n])).max(initial=0.0)))
        _, v = prob.surface_values(lam2)
        surface = max(surface, float(np.abs(0.5 * np.log(v)).max()))
    body = prob.mesh.comm.allreduce(body, op=MPI.MAX)
    return body, surface


SCENE = Scene(
    name="lip-install",
    summary="radial lip seal pushed onto its shaft (axisymmetric, Mooney-Rivlin, large strain)",
    parameters=LipInstallParameters,
    run=run,
)

__all__ = ["SCENE", "LipInstallParameters"]
