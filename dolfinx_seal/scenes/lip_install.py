"""Scene ``lip-install``: a radial lip seal mounted on its shaft (S0 section 3.1, static).

Axisymmetric (r, z) lip of :mod:`geometry.lip` (an 80 mm shaft seal by
default), bonded to its metal case along ``clamped``.  The undeformed tip lies
``interference`` inside the shaft; installation is modelled by growing the
rigid shaft radius from the tip radius to its nominal value (position control
with adaptive stepping: strains well above 30 % at the tip), optionally with
the garter spring load on the spring groove.  No film: the static contact.

Reports the radial load per unit circumference ``radial_load`` (the total
radial contact force divided by ``2 pi R_shaft``) [N/m], the contact width
(where the contact pressure exceeds ``width_threshold`` times its peak),
the peak and mean contact pressure, and the contact pressure profile along z
(``pressure.csv``, ``pressure.png``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import ufl

from dolfinx_seal.meshing import create_mesh
from dolfinx_seal.mpi import COMM_WORLD
from dolfinx_seal.params import check_int_range, check_nonnegative, check_range
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
        width_threshold: Contact width = extent where ``p > width_threshold * p_max``.
        degree: Displacement degree.
    """

    lip: LipSealParams = field(default_factory=LipSealParams)
    material: MaterialParams = field(
        default_factory=lambda: MaterialParams(model="mooney-rivlin", E=8e6, nu=0.5)
    )
    roughness: RoughnessParams = field(default_factory=RoughnessParams)
    contact: ContactLawParams = field(default_factory=ContactLawParams)
    spring_load: float = 0.0
    width_threshold: float = 0.01
    degree: int = 2

    def __post_init__(self) -> None:
        check_nonnegative("spring_load", self.spring_load, "N/m")
        check_range("width_threshold", self.width_threshold, 0.0, 0.5, lo_open=True)
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
    fr = prob.contact_force()  # total radial force [N] (2 pi r weighted)
    radial_load = fr / (2.0 * math.pi * lp.shaft_radius)
    _, p = prob.surface_values(prob.p_cont, average=True)
    _, xr = prob.surface_values(prob.x[0], average=True)
    _, xz = prob.surface_values(prob.x[1], average=True)
    z = xz  # current axial position of the surface points
    order = np.argsort(z)
    z, p, xr = z[order], p[order], xr[order]
    pmax = float(p.max())
    width = _width(z, p, params.width_threshold * pmax)
    res = {
        "radial_load": radial_load,
        "normal_load": fr,
        "load_contact": fr,
        "contact_width": width,
        "max_contact_pressure": pmax,
        "mean_contact_pressure": radial_load / width if width > 0 else 0.0,
        "z_peak_pressure": float(z[np.argmax(p)]),
        "load_steps": len(prob.steps),
        "newton_iterations": int(sum(s.newton_iterations for s in prob.steps)),
        "solve_time_s": solve_time,
        "max_principal_strain": _max_strain(prob),
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


def _width(z: np.ndarray, p: np.ndarray, level: float) -> float:
    """Length of the z-range where ``p >= level`` (ends interpolated linearly)."""
    above = np.nonzero(p >= level)[0]
    if above.size == 0:
        return 0.0
    i0, i1 = above[0], above[-1]

    def cross(i: int, j: int) -> float:
        if j < 0 or j >= len(z):
            return float(z[i])
        return float(z[j] + (level - p[j]) * (z[i] - z[j]) / (p[i] - p[j]))

    return cross(i1, i1 + 1) - cross(i0, i0 - 1)


def _max_strain(prob: SolidContactProblem) -> float:
    """Largest principal logarithmic (Hencky) strain magnitude on the contact surface.

    In axisymmetry ``C = F^T F`` is block diagonal: the (r, z) block has the
    eigenvalues ``(tr +- sqrt(tr^2 - 4 det)) / 2`` and the hoop one is ``C_tt``.
    """
    C = prob.F.T * prob.F
    tr = C[0, 0] + C[1, 1]
    det = C[0, 0] * C[1, 1] - C[0, 1] * C[1, 0]
    disc = ufl.sqrt(ufl.max_value(tr * tr - 4.0 * det, 0.0))
    worst = 0.0
    for lam2 in ((tr + disc) / 2.0, (tr - disc) / 2.0, C[2, 2]):
        _, v = prob.surface_values(lam2)
        worst = max(worst, float(np.abs(0.5 * np.log(v)).max()))
    return worst


SCENE = Scene(
    name="lip-install",
    summary="radial lip seal pushed onto its shaft (axisymmetric, Mooney-Rivlin, large strain)",
    parameters=LipInstallParameters,
    run=run,
)

__all__ = ["SCENE", "LipInstallParameters"]
