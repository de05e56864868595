"""Scene ``lip-install``: a radial lip seal mounted on its shaft (S0 section 3.1, static).

Axisymmetric (r, z) lip of :mod:`geometry.lip` (an 80 mm shaft seal by
default), bonded to its metal case along ``clamped``.  The undeformed tip lies
``interference`` inside the shaft; installation is modelled by growing the
rigid shaft radius from the tip radius to its nominal value (position control
with adaptive stepping), optionally with the garter spring load on the spring
groove.  No film: the static contact.  The default lip mostly bends (largest
principal strain about 5 %, under the tip); a sharp edge (``tip_radius`` 20 um)
under a strong spring (450 N/m) is strained by 33 % inside the tip arc.

Reports the radial load per unit circumference ``radial_load`` (the total
radial contact force divided by ``2 pi R_shaft``) [N/m], the contact width
(the width of the uniform band with the same force and second moment),
the peak and mean contact pressure, the largest principal (Hencky) strain and
where it is (reference position: ``max_strain_r_above_tip``, ``max_strain_z``),
and the contact pressure profile along z (``pressure.csv``, ``pressure.png``).

The radial balance of the section is reported too (totals over the
revolution, N, positive outwards on the lip): contact force ``normal_load``,
spring force ``spring_force`` (inwards), case reaction ``case_radial_reaction``
and the hoop force ``hoop_force`` (``2 pi int P_tt dA``: in axisymmetry a
uniform radial displacement stretches the hoop fibres, so the contact force is
not the case reaction); ``radial_balance_error`` is
``(contact - spring + reaction - hoop) / contact``, zero at convergence up to
quadrature.  ``min_gap_outside_band`` is the smallest gap between the shaft and
the lip surface outside the contact band (negative: the band is too narrow for
this interference).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import dolfinx
import numpy as np
import ufl
from mpi4py import MPI

from dolfinx_seal.compat import interpolation_points
from dolfinx_seal.coupled.results import write_fields
from dolfinx_seal.meshing import create_mesh
from dolfinx_seal.mpi import world
from dolfinx_seal.params import check_int_range, check_nonnegative, check_types
from dolfinx_seal.roughness.psd import RoughnessParams
from dolfinx_seal.scenes import Scene
from dolfinx_seal.scenes.common import ContactLawParams, MaterialParams, write_profile
from dolfinx_seal.solid.body import Body, Dirichlet, PositionControl
from dolfinx_seal.solid.counter_surface import Shaft
from dolfinx_seal.solid.kinematics import Axisymmetric
from dolfinx_seal.solid.materials import LinearElastic
from dolfinx_seal.solid.problem import SolidContactProblem, SteppingOptions
from dolfinx_seal.solid.step_limits import StepLimits
from dolfinx_seal.solvers import SNESOptions
from geometry.lip import LipSealParams

#: The default seal: an 80 x 100 x 10 mm radial shaft seal (ISO 6194-1 / DIN 3760
#: type A nominal size, the section of :mod:`geometry.lip`) with a moulded edge of
#: 0.1 mm radius, oil-side angle 45 deg and air-side angle 15 deg, 0.3 mm radial
#: interference and a garter spring of 170 N/m.  The spring was chosen so that the
#: installed lip lands in the bands handbooks give for such seals (H. K. Muller and
#: B. S. Nau, *Fluid Sealing Technology*, 1998, rotary lip seals; radial force per
#: unit circumference as defined by SAE J1901): radial force 0.1-0.2 N/mm, sealing
#: band 0.1-0.3 mm, peak pressure 0.5-2 MPa nearer the oil side.
SEAL_GEOMETRY = {"tip_radius": 0.1e-3, "air_angle": 15.0}
SEAL_SPRING_LOAD = 170.0  # N/m of groove circumference

#: Combined roughness of a ground shaft (Ra 0.2-0.4 um) and a moulded lip: h_rms
#: 0.5 um, Hurst 0.8, wavelengths from 21 um (q0) down to 63 nm (q1).  The longest
#: wavelength is a fifth of the sealing band: the homogenised laws need scale
#: separation, which S1's q0 = 1e4 1/m (630 um, wider than the band) lacks.
SEAL_ROUGHNESS = {"h_rms": 0.5e-6, "q0": 3.0e5, "q1": 1.0e8}


@dataclass(frozen=True)
class LipInstallParameters:
    """Lip seal installed on its shaft (SI units); defaults: :data:`SEAL_GEOMETRY`.

    Attributes:
        lip: Lip geometry and mesh (:class:`geometry.lip.LipSealParams`: shaft radius,
            interference, angles, spring groove, ...; the seal's edge radius and
            air-side angle by default, :data:`SEAL_GEOMETRY`).
        material: Rubber (NBR-like Mooney-Rivlin, E = 8 MPa, nearly incompressible).
        roughness: Combined lip/shaft roughness of the Persson law
            (:data:`SEAL_ROUGHNESS`: h_rms 0.5 um between 21 um and 63 nm).
        contact: Asperity contact law (``persson`` or ``stiff`` for a smooth contact).
        spring_load: Garter spring radial force per unit circumference of the groove
            [N/m] (0: no spring; default 170): a ring of hoop tension
            ``T = spring_load * r_g`` (``r_g`` the mean radius of the undeformed groove
            surface) pulling the groove bottom radially inwards with ``2 pi T`` in
            all, a dead load ramped with the shaft radius (the spring's own
            stiffness is neglected).
        degree: Displacement degree.
    """

    lip: LipSealParams = field(default_factory=lambda: LipSealParams(**SEAL_GEOMETRY))
    material: MaterialParams = field(
        default_factory=lambda: MaterialParams(model="mooney-rivlin", E=8e6, nu=0.5)
    )
    roughness: RoughnessParams = field(default_factory=lambda: RoughnessParams(**SEAL_ROUGHNESS))
    contact: ContactLawParams = field(default_factory=ContactLawParams)
    spring_load: float = SEAL_SPRING_LOAD
    degree: int = 2

    def __post_init__(self) -> None:
        check_types(self)
        check_nonnegative("spring_load", self.spring_load, "N/m")
        check_int_range("degree", self.degree, 1, 3)


class _LipProblem(SolidContactProblem):
    """The lip problem whose load fraction also ramps the garter spring."""

    spring_scale: dolfinx.fem.Constant | None = None
    spring_fraction: float | None = None  # None: the spring follows the load fraction
    #: when set, the load fraction ramps what it is given (e.g. the sealed pressures of
    #: the lubricated lip) with the shaft at its nominal radius and the spring in full
    pressure_ramp: Callable[[float], None] | None = None

    def set_fraction(self, t: float) -> None:
        if self.pressure_ramp is not None:
            super().set_fraction(1.0)
            if self.spring_scale is not None:
                self.spring_scale.value = 1.0
            self.pressure_ramp(t)
            return
        super().set_fraction(t)
        if self.spring_scale is not None:
            self.spring_scale.value = t if self.spring_fraction is None else self.spring_fraction


@dataclass
class Installation:
    """The lip installed on its shaft (what :func:`install` returns).

    Attributes:
        problem: The solved problem at load fraction 1 (shaft at its nominal radius,
            spring at its full load).  Its ``spring_fraction`` (``None``: the spring
            follows the load fraction) scales the spring load in later solves.
        mesh: The tagged lip mesh.
        law_info: What the contact law reports about itself.
        spring: ``spring_hoop_tension`` T [N], ``spring_force`` 2 pi T [N] and
            ``spring_radius`` r_g [m] (empty without a spring).
        solve_time_s: Wall time of the load stepping.
        rough_scale: The roughness scale the lip was installed at before its
            roughness was walked to its own (1: installed at its own roughness).
        rough_state: The unknowns at ``rough_scale`` (None when it is 1): where a
            lubricated start that needs a rough surface begins.
    """

    problem: _LipProblem
    mesh: Any
    law_info: dict[str, Any]
    spring: dict[str, float]
    solve_time_s: float
    rough_scale: float = 1.0
    rough_state: Any = None


#: A lip smoother than this [m] is installed with its roughness scaled up to it,
#: then the scale is walked down to 1 (:meth:`SolidContactProblem.walk_roughness`):
#: the law of a smooth surface is so stiff that growing the shaft under it took
#: 518 Newton steps at h_rms 0.1 um and stalled at 0.05 um.
INSTALL_H_RMS = 0.5e-6

#: adaptive steps of the shaft radius from the tip to its nominal value.  Increments of
#: at most 0.06: the walk grew its steps to about 0.1 and each failed after the
#: solver's 25 Newton steps (12 failures on the `lip-static` installation, 28.6 s on
#: one rank against 16.0-17.0 s capped, the radial load the same to 3e-10).  No cap on a
#: step's Newton steps: a cut after 12 stalled the coarse (h_rms 10 um) lip at its
#: first step, whose damped Newton takes more.  A step fails instead once three
#: Newton steps in a row each lower the residual by less than 1 %: where the tip
#: first touches, the secant predictor puts it into the shaft, and from there each
#: Newton step was scaled to under 1 % by the step limit (a direction of 0.29 mm at
#: the tip) and ran on to 25 steps, five times on the default lip (125 of its 219
#: Newton steps); they now stop after 3, with the same accepted steps and loads.
INSTALL_STEPS = SteppingOptions(
    first=0.02,
    grow=1.5,
    easy=8,
    max_steps=400,
    predictor=True,
    max_increment=0.06,
    stall_steps=3,
)


def install(params: LipInstallParameters) -> Installation:
    """Build the lip problem and grow the shaft radius to its nominal value (a
    smooth lip: at the roughness of :data:`INSTALL_H_RMS`, then walked to its own)."""
    lp = params.lip
    # the Hertz-like approach scale of the stiff law: the interference itself
    law, law_info = params.contact.build(
        params.roughness, params.material.E_star, approach=lp.interference
    )
    tm = create_mesh("lip", lp, comm=world())
    spring_info: dict[str, float] = {}
    # shaft radius grows from just inside the tip to its nominal value
    start = lp.shaft_radius - lp.interference - 0.02 * lp.interference
    prob = build_problem(params, tm, law, spring_info, position0=start)
    t1 = time.perf_counter()
    h_rms = getattr(law, "h_rms", 0.0)
    scale0 = INSTALL_H_RMS / h_rms if params.contact.model != "stiff" and h_rms else 1.0
    if scale0 > 1.0:
        prob.roughness_scale.value = scale0
    prob.ramp(INSTALL_STEPS)
    rough_state = None
    if scale0 > 1.0:
        rough_state = prob.state()
        its = prob.walk_roughness(scale0)
        law_info.update(install_roughness_scale=scale0, roughness_walk_newton_iterations=its)
    return Installation(prob, tm, law_info, spring_info, time.perf_counter() - t1,
                        max(scale0, 1.0), rough_state)  # fmt: skip


def build_problem(
    params: LipInstallParameters,
    tm: Any,
    law: Any,
    spring_info: dict[str, float],
    *,
    position0: float,
    film: Any = None,
    counter: Shaft | None = None,
    extra_terms: Sequence[Callable[[SolidContactProblem], Any]] = (),
    snes: SNESOptions | None = None,
    name: str = "lip-install",
    max_step: float | None = None,
) -> _LipProblem:
    """The lip on its shaft under position control (the shaft radius ramps from
    ``position0`` to its nominal value with the load fraction), with the garter
    spring (:func:`spring_work`), an optional film on the contact band and
    further named boundary terms ``extra_terms`` (each ``f(problem) -> ufl.Form``,
    added to the displacement residual).  ``spring_info`` receives the spring's
    tension, force and radius.  A Newton step moves no node more than ``max_step``
    [m] (default half a contact element) and none radially (towards the shaft)
    more than half a contact element."""
    lp = params.lip
    spring_scale = dolfinx.fem.Constant(tm.mesh, 0.0)
    terms = list(extra_terms)
    if params.spring_load > 0.0:
        terms.insert(0, lambda prob: spring_work(prob, tm, params.spring_load, spring_scale,
                                                 spring_info))  # fmt: skip

    def extra(prob: SolidContactProblem) -> Any:
        forms = [t(prob) for t in terms]
        return sum(forms[1:], forms[0]) if forms else None

    body = Body(Axisymmetric(), params.material.build(), [Dirichlet(tm.tag("clamped"))],
                degree=params.degree)  # fmt: skip
    limits = StepLimits(max_step=max_step or 0.5 * lp.h_contact, max_normal_step=0.5 * lp.h_contact)
    prob = _LipProblem(
        tm.mesh, tm.facet_tags, body, counter or Shaft(),
        PositionControl(lp.shaft_radius, position0), tm.tag("contact"), law=law, film=film,
        limits=limits, snes=snes or SNESOptions(max_it=25), name=name,
        extra_residual=extra if terms else None,
    )  # fmt: skip
    prob.spring_scale = spring_scale
    return prob


def spring_work(
    prob: SolidContactProblem,
    tm: Any,
    spring_load: float,
    scale: dolfinx.fem.Constant,
    info: dict[str, float],
) -> Any:
    """Virtual work of the garter spring on the groove (a residual term) [J per unit test].

    A ring of hoop tension ``T`` pulls inwards with ``T / r`` per unit of its
    circumference: ``2 pi T`` in all, whatever its radius.  ``T = spring_load *
    r_g``, ``r_g`` the mean radius of the undeformed groove; the load is spread
    over the groove as the radial part of a uniform pressure on its undeformed
    surface (``N_r > 0``: the groove bottom), a dead load scaled by ``scale``.
    """
    ds_g = prob.ds(tm.tag("spring_groove"))
    nr = ufl.max_value(prob.N3[0], 0.0)
    area_r = prob.integrate(nr * prob.weight, ds_g)
    r_g = prob.integrate(prob.X[0] * prob.weight, ds_g) / prob.integrate(prob.weight, ds_g)
    tension = spring_load * r_g
    info.update(
        spring_hoop_tension=tension, spring_force=2.0 * math.pi * tension, spring_radius=r_g
    )
    q = scale * (2.0 * math.pi * tension / area_r) * nr  # inward, per reference area
    return q * prob.v3[0] * prob.weight * ds_g


def run(params: LipInstallParameters, out: Path) -> dict[str, Any]:
    """Install the lip; write the pressure profile; return the results."""
    t0 = time.perf_counter()
    lp = params.lip
    inst = install(params)
    prob, tm, spring_info = inst.problem, inst.mesh, inst.spring
    strain_body, strain_surface, (r_strain, z_strain) = _max_strain(prob)
    fr = prob.contact_force()  # total radial force [N] (2 pi r weighted)
    reaction, hoop = radial_balance(prob, tm.tag("clamped"))
    f_spring = spring_info.get("spring_force", 0.0)
    radial_load = fr / (2.0 * math.pi * lp.shaft_radius)
    _, p = prob.surface_values(prob.p_cont, average=True)
    _, xr = prob.surface_values(prob.x[0], average=True)
    _, xz = prob.surface_values(prob.x[1], average=True)
    z = xz  # current axial position of the surface points
    order = np.argsort(z)
    z, p, xr = z[order], p[order], xr[order]
    pmax = float(p.max())
    width, z_mean = moment_width(prob)
    # the lip outside the contact band must stay off the shaft (no contact law there)
    min_gap = min(
        float(prob.surface_values(prob.gap, tag=tm.tag(side))[1].min())
        for side in ("oil_side", "air_side")
    )
    res = {
        "radial_load": radial_load,
        "normal_load": fr,
        "load_contact": fr,
        "contact_width": width,
        "max_contact_pressure": pmax,
        "mean_contact_pressure": radial_load / width if width > 0 else 0.0,
        "z_peak_pressure": float(z[np.argmax(p)]),
        "z_contact_centre": z_mean,
        "min_gap_outside_band": min_gap,
        "load_steps": len(prob.steps),
        "newton_iterations": int(sum(s.newton_iterations for s in prob.steps))
        + int(inst.law_info.get("roughness_walk_newton_iterations", 0)),
        "solve_time_s": inst.solve_time_s,
        "max_principal_strain": strain_body,
        "max_principal_strain_contact": strain_surface,
        "max_strain_r_above_tip": r_strain - lp.tip_r,
        "max_strain_z": z_strain,
        "dofs": prob.dofs,
        "ranks": world().size,
        "wall_time_s": time.perf_counter() - t0,
        "converged": True,
        "spring_hoop_tension": spring_info.get("spring_hoop_tension", 0.0),
        "spring_force": f_spring,
        "spring_radial_load": f_spring / (2.0 * math.pi * lp.shaft_radius),
        "case_radial_reaction": reaction,
        "hoop_force": hoop,
        "radial_balance_error": (fr - f_spring + reaction - hoop) / fr,
        "contact_law": prob.law.name,
        **inst.law_info,
    }
    write_profile(
        out, "pressure", {"z_m": z, "r_m": xr, "p_contact_Pa": p},
        title=f"installed lip: radial load {radial_load:.1f} N/m, width {width * 1e3:.3f} mm",
        xlabel="axial position z [mm] (oil side < 0)", ylabel="contact pressure [MPa]",
        curves={"contact pressure": (z * 1e3, p / 1e6)},
    )  # fmt: skip
    write_section(out, prob, f"installed lip: {radial_load:.0f} N/m, band {width * 1e3:.3f} mm, "
                  f"peak {pmax / 1e6:.2f} MPa")  # fmt: skip
    write_fields(out, prob, extra={"max_principal_strain": principal_strain(prob),
                                   "contact_pressure": prob.p_cont, "gap": prob.gap})  # fmt: skip
    prob.destroy()
    return res


def principal_strain(prob: SolidContactProblem) -> Any:
    """Largest principal logarithmic (Hencky) strain magnitude (UFL) [-]: in
    axisymmetry ``C = F^T F`` has the (r, z) eigenvalues ``(tr +- sqrt(tr^2 - 4
    det)) / 2`` and the hoop one ``C_tt``."""
    C = prob.F.T * prob.F
    tr = C[0, 0] + C[1, 1]
    det = C[0, 0] * C[1, 1] - C[0, 1] * C[1, 0]
    disc = ufl.sqrt(ufl.max_value(tr * tr - 4.0 * det, 0.0))
    e = [abs(0.5 * ufl.ln(lam2)) for lam2 in ((tr + disc) / 2.0, (tr - disc) / 2.0, C[2, 2])]
    return ufl.max_value(ufl.max_value(e[0], e[1]), e[2])


def write_section(out: Path, prob: SolidContactProblem, title: str) -> None:
    """``section.png``: the deformed section coloured by the largest principal
    strain, the whole lip and its tip, with the shaft line (rank 0 writes;
    every rank contributes its cells)."""
    S = dolfinx.fem.functionspace(prob.mesh, ("Lagrange", 1))
    V = dolfinx.fem.functionspace(prob.mesh, ("Lagrange", 1, (2,)))
    e = dolfinx.fem.Function(S)
    e.interpolate(dolfinx.fem.Expression(principal_strain(prob), interpolation_points(S.element)))
    u = dolfinx.fem.Function(V)
    u.interpolate(dolfinx.fem.Expression(prob.u, interpolation_points(V.element)))
    n_cells = prob.mesh.topology.index_map(prob.mesh.topology.dim).size_local
    cells = np.array([S.dofmap.cell_dofs(c) for c in range(n_cells)], dtype=np.int64)
    X = S.tabulate_dof_coordinates()[:, :2]
    xy = X + u.x.array.reshape(-1, 2)
    tri_xy = xy[cells]  # (cells, 3, 2) current positions
    tri_e = e.x.array[cells]
    comm = prob.mesh.comm
    parts = comm.gather((tri_xy, tri_e), root=0)
    if comm.rank != 0:
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.tri import Triangulation

    txy = np.concatenate([a for a, _ in parts]).reshape(-1, 2)
    te = np.concatenate([b for _, b in parts]).ravel()
    tri = Triangulation(txy[:, 1] * 1e3, txy[:, 0] * 1e3, np.arange(txy.shape[0]).reshape(-1, 3))
    R = float(prob.counter_position())
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6), gridspec_kw={"width_ratios": [1.3, 1]})
    for ax, zoom in zip(axes, (None, 0.6), strict=True):
        m = ax.tripcolor(tri, te, shading="gouraud", cmap="viridis", vmin=0.0)
        ax.axhline(R * 1e3, color="k", lw=1.5)
        ax.set_aspect("equal")
        ax.set_xlabel("z [mm] (oil side left)")
        ax.set_ylabel("r [mm]")
        if zoom:
            i = int(np.argmin(txy[:, 0]))
            zc, rc = txy[i, 1] * 1e3, txy[i, 0] * 1e3
            ax.set_xlim(zc - zoom, zc + zoom)
            ax.set_ylim(rc - 0.15, rc + 2 * zoom - 0.15)
            ax.set_title("tip (shaft: black line)")
        else:
            ax.set_ylim(R * 1e3 - 0.5, float(txy[:, 0].max()) * 1e3 + 0.3)
            ax.set_title(title, fontsize=9)
    fig.colorbar(m, ax=axes, label="largest principal (Hencky) strain", shrink=0.85)
    Path(out).mkdir(parents=True, exist_ok=True)
    fig.savefig(Path(out) / "section.png", dpi=130)
    plt.close(fig)


def radial_balance(prob: SolidContactProblem, clamped: int) -> tuple[float, float]:
    """Radial reaction of the case on the lip and the hoop force, both totals [N].

    The reaction is the residual of the body at the radial dofs of the clamped
    face (the virtual work of the stresses for a unit radial displacement of that
    face alone); the hoop force ``2 pi int P_tt dA`` is the work of the stresses
    for a uniform radial displacement of the whole section, which in axisymmetry
    is no rigid motion (it stretches every hoop fibre by ``1 / r``).  Equilibrium
    for that displacement: contact force - spring force + reaction = hoop force.
    """
    Vu = prob.W.sub(0) if prob.material.mixed else prob.W
    sub = Vu.sub(0)
    collapsed, dofs_r = sub.collapse()
    fdim = prob.mesh.topology.dim - 1
    on_case = dolfinx.fem.locate_dofs_topological(
        (sub, collapsed), fdim, prob.facet_tags.find(clamped)
    )[0]
    if isinstance(prob.material, LinearElastic):
        energy = prob.material.small_strain_energy(prob.kin.eps(prob.u), prob.p_mix)
    else:
        energy = prob.material.strain_energy(prob.F, prob.p_mix)
    v = dolfinx.fem.Function(prob.W)
    out = []
    for dofs in (on_case, dofs_r):
        v.x.array[:] = 0.0
        v.x.array[np.asarray(dofs)] = 1.0
        v.x.scatter_forward()
        work = dolfinx.fem.form(ufl.derivative(energy * prob.weight * prob.dx, prob.w, v))
        out.append(prob.mesh.comm.allreduce(dolfinx.fem.assemble_scalar(work), op=MPI.SUM))
    return out[0], out[1]


def moment_width(prob: SolidContactProblem, fn: Any = None) -> tuple[float, float]:
    """Contact width and centre [m] from the moments of the radial contact force density.

    ``w = sqrt(12 <(z - <z>)^2>)``: the width of the uniform pressure band with the
    same force, centre and second moment (exact for a uniform band; a Hertz
    ellipse of half-width a gives ``w = 1.73 a``).  An integral, it converges with
    the mesh where a threshold on nodal pressures does not.  ``fn``: another force
    density (e.g. fluid + asperity); default the asperity contact's.  A band that
    carries no force has width 0 and no centre (``nan``).
    """
    fn = prob.asperity_force_integrand() if fn is None else fn
    z = prob.x[1]
    m0 = prob.integrate(fn, prob.ds_c)
    if m0 <= 0.0:
        return 0.0, math.nan
    m1 = prob.integrate(fn * z, prob.ds_c) / m0
    centre = prob.compiled.constant(prob.mesh, "band centre", m1)  # not a literal: one kernel
    var = prob.integrate(fn * (z - centre) ** 2, prob.ds_c) / m0  # centred: no cancellation
    return math.sqrt(12.0 * var), m1


def _max_strain(prob: SolidContactProblem) -> tuple[float, float, tuple[float, float]]:
    """Largest principal logarithmic (Hencky) strain magnitude, in the body and on the
    contact surface, and the reference (r, z) position of the body value.

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
    X = S.tabulate_dof_coordinates()[:n]
    body, where, surface = 0.0, (math.nan, math.nan), 0.0
    for lam2 in ((tr + disc) / 2.0, (tr - disc) / 2.0, C[2, 2]):
        f.interpolate(dolfinx.fem.Expression(lam2, interpolation_points(S.element)))
        e = np.abs(0.5 * np.log(f.x.array[:n]))
        if n and e.max() > body:
            i = int(np.argmax(e))
            body, where = float(e[i]), (float(X[i, 0]), float(X[i, 1]))
        _, v = prob.surface_values(lam2)
        surface = max(surface, float(np.abs(0.5 * np.log(v)).max()))
    body, where = max(prob.mesh.comm.allgather((body, where)))
    return body, surface, where


SCENE = Scene(
    name="lip-install",
    summary="radial lip seal pushed onto its shaft (axisymmetric, Mooney-Rivlin, large strain)",
    parameters=LipInstallParameters,
    run=run,
)

__all__ = [
    "SCENE",
    "Installation",
    "LipInstallParameters",
    "build_problem",
    "install",
    "moment_width",
    "radial_balance",
    "spring_work",
]
