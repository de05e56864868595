"""The lubricating film on the deformed contact surface of the rubber.

Reynolds equation (S1 eq 20, S0 eqs 9-11) on the *current* contact surface,
written on the reference surface with the mapping of the deformation
(S0 eqs 12-13 and A.1-A.3 are the 2D version)::

    div_s( phi_p(g) g^3 / (12 eta) grad_s p ) = div_s( U_m g theta )

* ``g``: local gap (mean separation) between the rubber surface and the
  counter-surface [m]; ``phi_p(g)`` the pressure flow factor of the
  homogenised roughness (:func:`pressure_flow_factor`).
* ``grad_s``: tangential gradient on the current surface.  For a field ``f``
  on the reference surface (normal ``N``) with reference tangential gradient
  ``G = (I - N N) Grad f``, the current one is ``(I - n n) F^-T G`` (it
  reproduces ``df`` along every deformed tangent ``F T``; ``n`` is the
  current normal from Nanson's formula).  The current area element is
  ``da = J |F^-T N| dA``.  The Jacobian of the coupled problem contains the
  derivatives of all these geometric terms (``ufl.derivative`` of the whole
  residual).
* ``U_m``: mean surface velocity, ``U/2`` for a counter-surface sliding at
  ``U`` under a rubber body at rest, projected on the current tangent plane.

Cavitation models (:attr:`FilmParams.cavitation`):

* ``"none"``: full Sommerfeld, negative pressures allowed.
* ``"reynolds"``: the Reynolds condition ``p >= 0`` as a variational
  inequality (bounds for SNES VI); mass is not conserved where the film re-forms.
* ``"jfo"``: mass-conserving Jakobsson-Floberg-Olsson (S0 eqs 10-11) with
  the film fraction ``theta``: ``p >= 0``, ``0 <= theta <= 1``,
  ``p (1 - theta) = 0``.  Written as a mixed complementarity problem for
  SNES VI: the Reynolds (mass balance) rows hold as equalities everywhere,
  and ``theta`` in ``[0, 1]`` is complementary to ``-p`` (lumped nodal rows),
  i.e. ``theta = 1 => p >= 0`` and ``theta < 1 => p = 0``; ``p < 0`` is only
  possible at ``theta = 0`` (total starvation).  The Couette term of
  ``theta`` is pure transport in cavitated zones; it is fully upwinded
  (one-point quadrature plus the streamline diffusion ``h / (2 |U_m|)``,
  which turns the element flux into ``U_m g theta_upwind`` in 1D).  Both
  terms are fluxes in conservative form, so the discrete mass balance holds
  node by node across reformation fronts.

Boundary of the lubricated zone: ambient pressure (0) and a flooded inlet
(``theta = 1``) on its edges, except on ``no_flux_tags`` (symmetry planes),
where the zero-flux condition is natural.

Unknowns are scaled: the solver sees ``P = p / p_ref``, and the film rows are
weighted so that a unit error in them is comparable to a nodal force error of
the solid rows (docs/design.md, solver strategy: unscaled, the Reynolds rows are ~1e-9 of
the elastic ones and SNES ignores them).

Tractions on the rubber (S1 eq 29; S0 eq A.5): ``-(p + p_cont) n`` and the
shear along the sliding direction ``tau = sigma_1 A/A0 + eta U theta / g -
(g/2) dp/ds`` (the fluid shear on the surface at rest; ``theta = 1`` unless
JFO).  The friction force on the sliding counter-surface is
``int sigma_1 A/A0 + eta U theta / g + (g/2) dp/ds da`` (:meth:`friction_parts`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import dolfinx
import numpy as np
import ufl
from mpi4py import MPI
from ufl.algorithms import extract_coefficients

from dolfinx_seal.compat import interpolation_points
from dolfinx_seal.compiled import CompiledCache
from dolfinx_seal.errors import ParameterError
from dolfinx_seal.params import check_bool, check_choice, check_positive, check_range
from dolfinx_seal.surface import tractions
from dolfinx_seal.surface.asperity import area_fraction
from dolfinx_seal.surface.state import SurfaceState

CAVITATION_MODELS = ("none", "reynolds", "jfo")
FLOW_FACTORS = ("none", "patir-cheng", "persson")
UPWIND = ("fraction", "film", "none")
ACTIVE_TOLERANCE = 1e-8  # scaled pressure at or below which a film node is on its bound (PETSc VI)
#: Thinnest film [m] a continuum Reynolds film describes: about three to five
#: molecular layers of a mineral oil.  Below it the viscous (Couette) shear
#: ``eta U / u`` and the flow ``u^3`` are outside the model (boundary lubrication):
#: a converged film thinner than this is reported (``film_below_continuum``) and
#: a stability study marks the point ``suspect``.
CONTINUUM_FILM = 2e-9


@dataclass(frozen=True)
class FilmParams:
    """The lubricant film (SI units; the single source of its defaults).

    Attributes:
        viscosity: Dynamic viscosity eta [Pa s] (S1: 0.1).
        speed: Sliding speed U of the counter-surface under the rubber at rest
            [m/s], signed along the sliding direction (negative: the counter-surface
            moves the other way, e.g. the in-stroke of a rod); the mean surface
            velocity is U/2.  0: no Couette term.
        cavitation: ``none``, ``reynolds`` (p >= 0) or ``jfo`` (mass-conserving).
        flow_factor: Pressure flow factor of the homogenised roughness:
            ``none`` (phi_p = 1), ``patir-cheng`` or ``persson`` (the
            Persson/Bruggeman effective-medium factor of the roughness spectrum,
            :class:`~dolfinx_seal.contact.flow_factors.BruggemanFlowFactor`).
        upstream: Extent of the lubricated zone upstream of the contact centre,
            in contact half-widths (radii) [-] (flooded inlet: 7-10 for Moes M <= 20).
        downstream: Extent downstream, in contact half-widths [-].
        asperity_shear: Frictional shear stress sigma_1 of the real contact
            area [Pa] (S1 eq 29: tau = sigma_1 A/A0).
        inlet_pressure: Pressure on the upstream edge of the lubricated zone
            (gauge, relative to the cavitation pressure) [Pa].
        outlet_pressure: Pressure on the downstream edge [Pa].
        upwind: What the streamline diffusion of the Couette transport upwinds:
            ``fraction`` (the film fraction theta only, a central film gap) or
            ``film`` (the transported film g theta as a whole: a first-order
            upwind scheme of the Couette term, S0's "forward difference for the
            Couette term in order to get a stable scheme").  A very soft contact
            (a seal, deformed hundreds of times its film) is in the inverse-
            hydrodynamic limit where the Couette term fixes the film: a central
            gap then decouples odd and even nodes (a node-to-node wiggle of the
            film and the pressure).  ``none``: no streamline diffusion, the
            one-point Galerkin transport, only with ``discrete_upwinding``
            (which then is the whole upwinding).
        gap_floor: Smallest gap used in the film coefficients, in units of
            h_rms [-] (keeps g^3 and eta U / g finite for Newton iterates).  A
            smooth surface's converged film stays above it; resolved crests
            (the two-scale lip sector) can sit below it, where the floor, not
            the gap, sets the film: ``floored_area_fraction`` and
            ``floored_fluid_load_fraction`` say how much (docs/scenes/lip-sector.md).
        discrete_upwinding: On the lip sector (``lip-dynamic``; other scenes
            refuse it), add Kuzmin's discrete
            upwinding to the JFO film's Couette transport (:mod:`dolfinx_seal.film.upwinding`): the least
            symmetric numerical diffusion that makes the transport rows an
            M-matrix, conserving the oil.  On an unstructured band the
            streamline-diffusion scheme alone is not monotone, and its
            semismooth Newton can wander without converging
            (docs/scenes/lip-sector.md).  A convergence aid: its diffusion
            also acts across the sliding and biases the leakage at speed
            (16-29 % low at 0.1 m/s, the wrong sign at 1 m/s on a rigid
            rough band against a finite-volume reference, where the
            default is within 1.2 % and 17 %; docs/verification.md).
            Without it, the frozen lip sector still takes it as the last
            fallback of a film solve that the default scheme cannot finish,
            and releases it (the film reported is then the default scheme's,
            or the weight ``discrete_upwinding_weight`` says).
        release_upwinding: With ``discrete_upwinding``: once the monotone film
            has converged, walk the discrete upwinding's weight down to 0, each
            weight solved from the last film (on the lip sector a failed weight
            step tried again by pseudo-time steps,
            :func:`~dolfinx_seal.film.upwinding.release_discrete_upwinding`),
            so that the film reported is the default scheme's (its leakage)
            and the discrete upwinding only the path to it; where a weight
            step below 1/256 fails, the film keeps the last weight solved
            (the result ``discrete_upwinding_weight``, 0 when released).
    """

    viscosity: float = 0.1
    speed: float = 0.0
    cavitation: str = "reynolds"
    flow_factor: str = "none"
    upstream: float = 10.0
    downstream: float = 6.0
    asperity_shear: float = 1.0e6
    gap_floor: float = 0.01
    inlet_pressure: float = 0.0
    outlet_pressure: float = 0.0
    upwind: str = "fraction"
    discrete_upwinding: bool = False
    release_upwinding: bool = False

    def __post_init__(self) -> None:
        check_positive("film.viscosity", self.viscosity, "Pa s")
        check_range("film.speed", self.speed, -1e3, 1e3, unit="m/s")
        check_choice("film.cavitation", self.cavitation, CAVITATION_MODELS)
        check_choice("film.flow_factor", self.flow_factor, FLOW_FACTORS)
        check_choice("film.upwind", self.upwind, UPWIND)
        check_range("film.upstream", self.upstream, 1.0, 100.0)
        check_range("film.downstream", self.downstream, 1.0, 100.0)
        check_range("film.asperity_shear", self.asperity_shear, 0.0, 1e9, unit="Pa")
        check_range("film.gap_floor", self.gap_floor, 0.0, 1.0, lo_open=True)
        check_range("film.inlet_pressure", self.inlet_pressure, 0.0, 1e9, unit="Pa")
        check_range("film.outlet_pressure", self.outlet_pressure, 0.0, 1e9, unit="Pa")
        check_bool("film.discrete_upwinding", self.discrete_upwinding)
        check_bool("film.release_upwinding", self.release_upwinding)
        if self.release_upwinding and not self.discrete_upwinding:
            raise ParameterError(
                "film.release_upwinding = True releases the discrete upwinding: it "
                "needs film.discrete_upwinding = True",
                "film.release_upwinding",
            )
        if self.release_upwinding and self.upwind == "none":
            raise ParameterError(
                "film.release_upwinding = True with film.upwind = 'none' would end on "
                "the central transport, which is unstable; allowed here: 'fraction' "
                "or 'film'",
                "film.release_upwinding",
            )
        if self.upwind == "none" and not self.discrete_upwinding:
            raise ParameterError(
                "film.upwind = 'none' (a central Couette transport) needs "
                "film.discrete_upwinding = True to be stable; allowed here: "
                "'fraction' or 'film'",
                "film.upwind",
            )


@dataclass(frozen=True)
class FilmScales:
    """Scales of the film unknowns and rows.

    Attributes:
        pressure: Pressure scale p_ref [Pa] (e.g. the Hertz peak).
        length: Contact half-width (radius) [m].
        gap: Gap scale [m] (e.g. h_rms).
        element: Element size on the contact [m].
    """

    pressure: float
    length: float
    gap: float
    element: float


def pressure_flow_factor(
    model: str, gap: Any, h_rms: Any, table: Any = None, scale: Any = 1.0
) -> Any:
    """Pressure flow factor ``phi_p`` of the averaged Reynolds equation (UFL).

    ``scale``: amplitude scale of the roughness the ``table`` was made for (its
    factor at scale ``s`` is ``phi(u / s)``).

    ``patir-cheng``: ``1 - 0.90 exp(-0.56 g / h_rms)`` (Patir & Cheng 1978,
    isotropic roughness; the same fit as
    :class:`dolfinx_seal.contact.flow_factors.PatirCheng`).  ``persson``: the
    :class:`~dolfinx_seal.contact.flow_factors.LogHermiteTable` ``table`` of the
    Bruggeman factor, a chain of conditionals over its intervals in ``ln(g/h_rms)``.
    """
    if model == "none":
        return 1.0
    if model == "patir-cheng":
        return 1.0 - 0.90 * ufl.exp(-0.56 * gap / h_rms)
    if model == "persson":
        if table is None:
            raise ParameterError("film.flow_factor = 'persson' needs the roughness spectrum")
        H = gap / (table.h_rms * scale)
        s = ufl.ln(H)
        expr = 1.0 - table.c_tail / (H * H)
        for j in range(table.s.size - 2, -1, -1):
            expr = ufl.conditional(ufl.lt(s, float(table.s[j + 1])), table.segment(j, s), expr)
        low = float(table.phi[0]) * ufl.exp(float(table.k_low) * (s - float(table.s[0])))
        return ufl.conditional(ufl.lt(s, float(table.s[0])), low, expr)
    raise ParameterError(f"film.flow_factor = {model!r} must be one of {FLOW_FACTORS}")


class SurfaceFilm:
    """Film unknowns, residuals, bounds and tractions on a lubricated surface.

    Args:
        params: :class:`FilmParams`.
        scales: :class:`FilmScales`.
        h_rms: Rms roughness of the homogenised scales [m] (flow factor, gap floor).
        rms_slope: Rms slope of the roughness (real contact area for the
            asperity shear); ``nan``: no asperity shear.
        e_star: Effective modulus ``E*`` [Pa] (real contact area).
        no_flux_tags: Facet tags where the film boundary is a symmetry plane.
        psd: Roughness spectrum (``flow_factor = "persson"`` only).
        allow_discrete_upwinding: The scene supports ``film.discrete_upwinding``
            (the lip sector; the others refuse it).

    After :meth:`attach`, :attr:`blocks` lists ``(residual, function, lower,
    upper)`` per film unknown (pressure, and the film fraction for JFO),
    :attr:`bcs` their Dirichlet conditions, :attr:`p` the fluid pressure [Pa]
    (UFL) and :meth:`traction_work` the virtual work on the rubber.
    """

    def __init__(
        self,
        params: FilmParams,
        scales: FilmScales,
        h_rms: float,
        rms_slope: float = math.nan,
        e_star: float = math.nan,
        no_flux_tags: Sequence[int] = (),
        psd: Any = None,
        allow_discrete_upwinding: bool = False,
    ) -> None:
        self.params, self.scales = params, scales
        if params.discrete_upwinding and not (
            allow_discrete_upwinding and params.cavitation == "jfo" and params.speed != 0.0
        ):
            raise ParameterError(
                "film.discrete_upwinding = True: allowed only for a sliding JFO film "
                "(film.cavitation = 'jfo', film.speed != 0) of the lip sector "
                "(lip-dynamic); set it to false here",
                "film.discrete_upwinding",
            )
        self.flow_table = None
        if params.flow_factor == "persson":
            from dolfinx_seal.contact.flow_factors import BruggemanFlowFactor

            if psd is None or not math.isfinite(e_star):
                raise ParameterError(
                    "film.flow_factor = 'persson' needs the roughness spectrum and E*"
                )
            self.flow_table = BruggemanFlowFactor(psd, e_star).hermite_table()
        self.h_rms = check_positive("h_rms", h_rms, "m")
        self.rms_slope, self.e_star = rms_slope, e_star
        self.no_flux_tags = tuple(no_flux_tags)
        self.has_couette = params.speed != 0.0
        self.has_theta = params.cavitation == "jfo"
        self.has_transport = self.has_couette  # set from the context in attach

    # ------------------------------------------------------------------ set-up
    def attach(self, ctx: SurfaceState, p_cont: Any = None) -> None:
        """Create the film unknowns and forms on ``ctx`` (``p_cont``: asperity pressure)."""
        pr, sc = self.params, self.scales
        mesh = ctx.mesh
        self.ctx = ctx
        self.has_transport = self.has_couette and ctx.transport
        S = dolfinx.fem.functionspace(mesh, ("Lagrange", 1))
        self.S = S
        self.compiled = CompiledCache()  # the outputs' interpolations (film_values)
        # off the lubricated surface and on its edges the pressure is prescribed
        fixed, edge = self._fixed_dofs(ctx)
        pinned = np.union1d(fixed, edge).astype(np.int32)
        self.bcs = [dolfinx.fem.dirichletbc(self._boundary_pressure(ctx, edge), pinned)]
        self._issued_bcs: list[Any] = []  # earlier film conditions (restrict_to_gap)
        self.constraints: list[Any] = []  # periodic: one constraint per film unknown
        self.P = self._unknown(S, self.bcs[:1], "fluid_pressure_scaled")
        q = ufl.TestFunction(S)
        self.p = sc.pressure * self.P  # [Pa]
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=ctx.facet_tags)
        meta = {} if ctx.quadrature_degree is None else {"quadrature_degree": ctx.quadrature_degree}
        self.ds = ds(ctx.contact_tag, metadata=meta)
        self.ds1 = ds(ctx.contact_tag, metadata={"quadrature_degree": 1})
        self.ds_vertex = ds(
            ctx.contact_tag, metadata={"quadrature_rule": "vertex", "quadrature_degree": 1}
        )
        dx = ufl.Measure("dx", domain=mesh)

        nanson = tractions.nanson_normal(ctx.F, ctx.N3)
        self.da = ufl.sqrt(ufl.dot(nanson, nanson)) * ctx.weight  # da / dA
        self.n = nanson / ufl.sqrt(ufl.dot(nanson, nanson))
        self.scale = ctx.roughness_scale  # homogenised roughness amplitude (homotopy)
        self.floor = pr.gap_floor * self.h_rms * self.scale  # [m]
        self.g = ufl.max_value(ctx.gap, self.floor)
        phi_p = pressure_flow_factor(
            pr.flow_factor, self.g, self.h_rms * self.scale, self.flow_table, self.scale
        )
        # homotopy weight of the flow factor (1: phi_p; 0: smooth walls), for starts
        self.flow_factor_weight = dolfinx.fem.Constant(mesh, 1.0)
        if pr.flow_factor != "none":
            phi_p = 1.0 - self.flow_factor_weight * (1.0 - phi_p)
        self.conductivity = phi_p * self.g**3 / (12.0 * pr.viscosity)  # m^3/(Pa s)
        self.speed = dolfinx.fem.Constant(mesh, float(pr.speed))
        # +1 / -1: the counter-surface slides along / against ``sliding`` (asperity drag)
        self.direction = dolfinx.fem.Constant(mesh, 1.0 if pr.speed >= 0.0 else -1.0)
        t = ctx.sliding - ufl.dot(ctx.sliding, self.n) * self.n
        self.t = t / ufl.sqrt(ufl.dot(t, t))  # current tangent along the sliding direction
        self.U_m = 0.5 * self.speed * self.t  # projected mean velocity [m/s]

        # row weight: flux residual [m^2/s] -> nodal force scale [N/m]
        u_ref = max(abs(pr.speed), 1e-300) if self.has_transport else 1e-300
        q_ref = sc.gap**3 * sc.pressure / (12.0 * pr.viscosity * sc.length) + 0.5 * u_ref * sc.gap
        self.row_weight = dolfinx.fem.Constant(mesh, sc.pressure * sc.element / q_ref)
        self._q_ref_parts = (sc.gap**3 * sc.pressure / (12.0 * pr.viscosity * sc.length), sc.gap)

        if self.has_theta:
            # a space of its own: blocked assembly matches Dirichlet conditions to
            # blocks by function space, so theta must not share the pressure's
            self.S_theta = dolfinx.fem.functionspace(mesh, ("Lagrange", 1))
            one = dolfinx.fem.Function(self.S_theta)
            one.x.array[:] = 1.0
            self.bcs.append(dolfinx.fem.dirichletbc(one, pinned))
            self.theta_fn = self._unknown(self.S_theta, self.bcs[-1:], "film_fraction")
            self.theta_fn.x.array[:] = 1.0
            self.theta: Any = self.theta_fn
        else:
            self.theta_fn = None
            self.theta = 1.0

        grad_q = self.surface_grad(q)
        R = self.conductivity * sc.pressure * ufl.dot(self.surface_grad(self.P), grad_q) * self.da
        # With transport the whole film row is one-point.  The transport terms must
        # be (upwinding), and FFCx 0.9 integrates a facet group whose one-point
        # integral follows one of another degree wholly one-point
        # (compat.check_quadrature_rules): the residual was one-point already while the pressure-pressure Jacobian kept
        # the flow term's own degree (0.26 % off finite differences on the cylinder,
        # Newton linear: 7 steps a continuation point, 4 with the row one-point; the
        # same converged values).  Without transport (zero speed) the row keeps it.
        one_point = self.has_transport
        R = R * (self.ds1 if one_point else self.ds)
        if self.has_transport:
            # one-point quadrature + streamline diffusion h/(2|U_m|): full upwinding of
            # theta (upwind = "fraction") or of the transported film g theta ("film")
            R += -self.g * self.theta * ufl.dot(self.U_m, grad_q) * self.da * self.ds1
            upwinded = None
            if pr.upwind == "film":
                upwinded = self.surface_grad(self.g * self.theta)
            elif self.has_theta and pr.upwind == "fraction":
                upwinded = self.g * self.surface_grad(self.theta_fn)
            if upwinded is not None:
                h_e = self._element_size(mesh, ctx.facet_tags.find(ctx.contact_tag))
                Um_abs = 0.5 * abs(self.speed)
                R += (
                    h_e
                    / (2.0 * Um_abs)
                    * ufl.dot(self.U_m, upwinded)
                    * ufl.dot(self.U_m, grad_q)
                    * self.da
                    * self.ds1
                )
            if self.has_theta:
                # film storage d(g theta da/dA)/dt (the oil volume per reference
                # area), by implicit Euler in a pseudo-time (pseudo_transient_solve);
                # 1/dt = 0: the steady film.  The old volume is the same form on
                # copies of its functions (displacement, position): on a moving lip
                # it holds the squeeze and stretch of the film, on a frozen one only
                # the change of theta
                self.inv_dt = dolfinx.fem.Constant(mesh, 0.0)  # 1/s
                self.theta_old = dolfinx.fem.Function(self.theta_fn.function_space)
                self.theta_old.x.array[:] = 1.0
                volume = self.g * self.da  # m: film volume per reference area
                self._old_functions = [
                    (c, c.copy())
                    for c in extract_coefficients(volume)
                    if isinstance(c, dolfinx.fem.Function)
                ]
                volume_old = ufl.replace(volume, dict(self._old_functions))
                self.film_volume = volume * self.theta_fn * self.ds1  # m^3 (times weight)
                R += (
                    self.inv_dt * (volume * self.theta_fn - volume_old * self.theta_old) * q
                    * self.ds1
                )  # fmt: skip
        self.R_P = self.row_weight * R + dolfinx.fem.Constant(mesh, 0.0) * self.P * q * dx

        bound_lo = 0.0 if pr.cavitation == "reynolds" else None
        self.blocks: list[tuple[Any, dolfinx.fem.Function, Any, Any]] = [
            (self.R_P, self.P, bound_lo, None)
        ]
        self.film_dofs_local = np.setdiff1d(
            np.arange(S.dofmap.index_map.size_local, dtype=np.int32), pinned
        )
        if self.has_theta:
            psi = ufl.TestFunction(self.S_theta)
            R_t = -sc.pressure * self.P * psi * self.ds_vertex
            R_t += dolfinx.fem.Constant(mesh, 0.0) * self.theta_fn * psi * dx
            self.blocks.append((R_t, self.theta_fn, 0.0, 1.0))
        self.p_cont = p_cont

    def _unknown(self, V: Any, bcs: Sequence[Any], name: str) -> dolfinx.fem.Function:
        """A film unknown on ``V``, or, on a periodic surface, on the space of its
        periodic constraint (appended to :attr:`constraints`; ``bcs`` are never slaves)."""
        periodic = self.ctx.periodic
        if periodic is None:
            return dolfinx.fem.Function(V, name=name)
        mpc = periodic.scalar(V, bcs)
        self.constraints.append(mpc)
        return dolfinx.fem.Function(mpc.function_space, name=name)

    def _boundary_pressure(self, ctx: SurfaceState, edge: np.ndarray) -> dolfinx.fem.Function:
        """Scaled boundary pressure: inlet value on upstream edge dofs, outlet downstream, 0 off the film."""
        f = dolfinx.fem.Function(self.S)
        self.boundary_values = f
        self._edges = self._split_edges(ctx, edge)
        self.set_edge_pressures(self.params.inlet_pressure, self.params.outlet_pressure)
        return f

    def _split_edges(self, ctx: SurfaceState, edge: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Edge dofs (owned and ghost) at the low and at the high end of the zone
        along :attr:`SurfaceState.edge_axis` (default the sliding direction)."""
        gdim = ctx.mesh.geometry.dim
        axis = ctx.sliding if ctx.edge_axis is None else ctx.edge_axis
        e = np.array([float(axis[i]) for i in range(gdim)])
        s = self.S.tabulate_dof_coordinates()[:, :gdim] @ e
        comm = ctx.mesh.comm
        lo = comm.allreduce(float(s[edge].min(initial=np.inf)), op=MPI.MIN)
        hi = comm.allreduce(float(s[edge].max(initial=-np.inf)), op=MPI.MAX)
        mid = 0.5 * (lo + hi)
        return edge[s[edge] < mid], edge[s[edge] >= mid]

    def set_edge_pressures(self, low: float, high: float) -> None:
        """Pressures [Pa] on the low (inlet) and high (outlet) edges of the zone."""
        f, (up, down) = self.boundary_values, self._edges
        self._edge_values = (float(low), float(high))
        f.x.array[:] = 0.0
        f.x.array[up] = low / self.scales.pressure
        f.x.array[down] = high / self.scales.pressure
        f.x.scatter_forward()  # the Dirichlet condition reads f at the next solve

    def accept_step(self) -> None:
        """Make the current film the old state of the next pseudo-time step
        (``theta_old``, and the old gap and area through copies of their functions)."""
        self.theta_old.x.array[:] = self.theta_fn.x.array
        for current, old in self._old_functions:
            old.x.array[:] = current.x.array

    def restrict_to_gap(self, max_gap: float, solvers: Sequence[Any] = ()) -> int:
        """End the lubricated zone where the current gap exceeds ``max_gap`` [m].

        The free film nodes are those between the lowest and the highest node
        (along the edge axis) whose gap is at most ``max_gap``; the nodes beyond
        are pinned to the edge pressure of their side (and a flooded film
        fraction).  Where the gap is wide the film carries no pressure drop (its
        conductance goes as ``g^3``), but its rows would dwarf those of the
        narrow constrictions by that factor and leave them at round-off:
        ``(300 um / 20 nm)^3`` on a lip seal's band.  The Dirichlet conditions
        are replaced in :attr:`bcs` and in each of ``solvers`` (their matrices
        keep their pattern).  Returns the number of free nodes (global).
        """
        ctx, S = self.ctx, self.S
        check_positive("max_gap", max_gap, "m")
        gdim = ctx.mesh.geometry.dim
        axis = ctx.sliding if ctx.edge_axis is None else ctx.edge_axis
        e = np.array([float(axis[i]) for i in range(gdim)])
        coord = S.tabulate_dof_coordinates()[:, :gdim] @ e
        g = dolfinx.fem.Function(S)
        g.interpolate(dolfinx.fem.Expression(ctx.gap, interpolation_points(S.element)))
        g.x.scatter_forward()
        film = np.zeros(coord.size, dtype=bool)
        film[self.film_dofs_local] = True
        film[np.concatenate(self._edges)] = True
        film = self._marked(np.flatnonzero(film))  # film nodes, ghosts included
        narrow = film & (g.x.array <= max_gap)
        comm = ctx.mesh.comm
        lo = comm.allreduce(float(coord[narrow].min(initial=np.inf)), op=MPI.MIN)
        hi = comm.allreduce(float(coord[narrow].max(initial=-np.inf)), op=MPI.MAX)
        if not np.isfinite(lo):
            raise ParameterError(
                f"max_gap = {max_gap!r} m: no film node has a gap that narrow (the "
                "lubricated zone would be empty)"
            )
        # a round-off margin: the two nodes of a periodic seam lie at one axial place up
        # to the rounding of their coordinates, and must be pinned together
        tol = 1e-9 * max(hi - lo, abs(lo), abs(hi))
        low = np.flatnonzero(film & (coord < lo - tol)).astype(np.int32)
        high = np.flatnonzero(film & (coord > hi + tol)).astype(np.int32)
        # nothing beyond the zone on one side, on any rank (a rank may hold one side alone)
        if (
            comm.allreduce(int(low.size), op=MPI.SUM) == 0
            or comm.allreduce(int(high.size), op=MPI.SUM) == 0
        ):
            self.release(solvers)  # nothing to cut: the film's own conditions (after pin)
            return comm.allreduce(int(self.film_dofs_local.size), op=MPI.SUM)
        old = list(self.bcs)
        fixed = np.flatnonzero(~film).astype(np.int32)
        pinned = np.union1d(np.union1d(fixed, low), high).astype(np.int32)
        self._edges = (low, high)
        self.set_edge_pressures(*self._edge_values)
        self.bcs = [dolfinx.fem.dirichletbc(self.boundary_values, pinned)]
        if self.has_theta:
            one = dolfinx.fem.Function(self.S_theta)
            one.x.array[:] = 1.0
            self.bcs.append(dolfinx.fem.dirichletbc(one, pinned))
        n_own = S.dofmap.index_map.size_local
        self.film_dofs_local = np.setdiff1d(np.arange(n_own, dtype=np.int32), pinned)
        self._issued_bcs.extend(old)
        for solver in solvers:  # the solver's other conditions, and the film's new ones
            kept = [b for b in solver.bcs if all(b is not o for o in self._issued_bcs)]
            solver.set_bcs(kept + self.bcs)
        return comm.allreduce(int(self.film_dofs_local.size), op=MPI.SUM)

    def pin(self, solvers: Sequence[Any] = ()) -> None:
        """Pin every film node: the pressure at the edge pressures (0 inside the zone)
        and, with JFO, a full film (``theta = 1``); a dry solve of the body with the
        film's unknowns riding along as identity rows.  The conditions replace the
        film's in each of ``solvers``; :meth:`restrict_to_gap` (or
        :meth:`release`) replaces them in turn.

        Why: a sliding film carried through a dry solve lives on the whole band,
        before :meth:`restrict_to_gap` cuts it to the narrow zone; on the two-scale
        lip sector its free nodes spanned gaps from 40 nm to 105 um (conductances
        ``g^3`` over ten decades), the constriction's pressures sat at the
        round-off of the wide gap's rows (``|p| ~ 2 kPa`` of either sign, half the
        nodes negative at ``theta ~ 1``), and the coupled JFO Newton crept and
        diverged."""
        S = self.S
        n = S.dofmap.index_map.size_local + S.dofmap.index_map.num_ghosts
        every = np.arange(n, dtype=np.int32)
        pins = [dolfinx.fem.dirichletbc(self.boundary_values, every)]
        if self.has_theta:
            one = dolfinx.fem.Function(self.S_theta)
            one.x.array[:] = 1.0
            pins.append(dolfinx.fem.dirichletbc(one, every))
        # On a periodic surface P lives on the constraint's space, whose index map
        # appends the constraint's ghosts to S's: copy S's entries, then refresh.
        own = self.boundary_values.x.array
        self.P.x.array[: own.size] = own
        self.P.x.scatter_forward()
        if self.has_theta:
            self.theta_fn.x.array[:] = 1.0
        self._pins = pins
        self._issued_bcs.extend(pins)
        for solver in solvers:
            kept = [b for b in solver.bcs if all(b is not o for o in self._issued_bcs + self.bcs)]
            solver.set_bcs(kept + pins)

    def release(self, solvers: Sequence[Any] = ()) -> None:
        """Undo :meth:`pin`: the film's own conditions again in each of ``solvers``."""
        for solver in solvers:
            kept = [b for b in solver.bcs if all(b is not o for o in self._issued_bcs + self.bcs)]
            solver.set_bcs(kept + self.bcs)

    def edge_flows(self) -> tuple[float, float]:
        """Volumetric flows [m^3/s, totals over the kinematics weight] out of the
        lubricated zone through its low and its high edge (positive outwards).

        The Reynolds row of an edge node, assembled without its Dirichlet
        condition and unweighted, is minus the flux leaving through that node
        (the boundary term of the weak form); the sums over each edge are the
        two outflows, and their sum is the net mass balance of the zone.
        """
        R = dolfinx.fem.assemble_vector(self._flux_form())
        R.scatter_reverse(dolfinx.la.InsertMode.add)
        n = self.S.dofmap.index_map.size_local
        w = float(self.row_weight.value)
        comm = self.ctx.mesh.comm
        out = []
        for dofs in self._edges:
            mine = dofs[dofs < n]
            out.append(-comm.allreduce(float(R.array[mine].sum()), op=MPI.SUM) / w)
        return out[0], out[1]

    def _flux_form(self) -> Any:
        if getattr(self, "_flux_compiled", None) is None:
            self._flux_compiled = dolfinx.fem.form(self.R_P)
        return self._flux_compiled

    def make_solver(
        self,
        options: Any,
        extra_blocks: Sequence[Any] = (),
        name: str = "film",
        *,
        reynolds_condition: bool = False,
    ) -> Any:
        """A :class:`~dolfinx_seal.solvers.NonlinearSolver` on the film unknowns alone
        (geometry frozen), optionally with further ``(residual, unknown, lower, upper)``
        blocks (e.g. the counter position).

        ``reynolds_condition``: solve the pressure under ``p >= 0`` whatever the
        cavitation model, the film fraction (JFO) left out, so frozen at its
        current value (set it to 1 first): the start of a JFO or full-Sommerfeld
        film (:func:`~dolfinx_seal.coupled.continuation.film_presolve`)."""
        from dolfinx_seal.solvers import NonlinearSolver, ProjectedMPCAssembly

        own = list(self.blocks)
        bcs = self.bcs
        if reynolds_condition:
            own = [(self.R_P, self.P, 0.0, None)]
            bcs = self.bcs[:1]
        fb = own + list(extra_blocks)
        lower = [b[2] for b in fb]
        upper = [b[3] for b in fb]
        bounded = any(v is not None for v in lower + upper)
        assembly = None
        if self.constraints:  # periodic: extra blocks (a real unknown) have none
            cons = self.constraints[: len(own)] + [None] * len(extra_blocks)
            assembly = ProjectedMPCAssembly(cons[0] if len(fb) == 1 else cons)
        if len(fb) == 1:
            return NonlinearSolver(
                fb[0][0], fb[0][1], bcs, options=options, name=name,
                lower=lower[0] if bounded else None, upper=upper[0] if bounded else None,
                assembly=assembly,
            )  # fmt: skip
        return NonlinearSolver(
            [b[0] for b in fb], [b[1] for b in fb], bcs, options=options, name=name,
            lower=lower if bounded else None, upper=upper if bounded else None,
            assembly=assembly,
        )  # fmt: skip

    @staticmethod
    def _element_size(mesh: dolfinx.mesh.Mesh, facets: np.ndarray, *,
                      from_vertices: bool = False) -> Any:  # fmt: skip
        """The size [m] of the film's elements (facets of ``mesh``): the facet's length
        in 2D, ``sqrt(2 area)`` in 3D.  On an affine mesh UFL's ``FacetArea``; on a
        curved one (``mesh_order = 2``, which FFCx 0.9 cannot integrate ``FacetArea``
        on: "Not handled: FacetArea") the same of the straight facet through its
        vertices, held by a cell function on each facet's one cell
        (``from_vertices`` forces that way, for tests)."""
        tdim = mesh.topology.dim
        if mesh.geometry.cmap.degree == 1 and not from_vertices:
            fa = ufl.FacetArea(mesh)
            return fa if tdim == 2 else ufl.sqrt(2.0 * fa)
        fdim = tdim - 1
        mesh.topology.create_connectivity(fdim, tdim)
        mesh.topology.create_connectivity(fdim, 0)
        f2c = mesh.topology.connectivity(fdim, tdim)
        h = dolfinx.fem.Function(dolfinx.fem.functionspace(mesh, ("DG", 0)))
        if len(facets) == 0:  # a rank without film facets (entities_to_geometry: SIGFPE)
            h.x.scatter_forward()
            return h
        x = mesh.geometry.x
        vertex_nodes = dolfinx.mesh.entities_to_geometry(mesh, fdim, facets, False)
        # the vertices are the first nodes of a Lagrange facet, in either degree
        corners = x[vertex_nodes[:, : fdim + 1]]
        if tdim == 2:
            size = np.linalg.norm(corners[:, 1] - corners[:, 0], axis=1)
        else:
            area = 0.5 * np.linalg.norm(
                np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1
            )
            size = np.sqrt(2.0 * area)
        for f, v in zip(facets, size, strict=True):
            h.x.array[f2c.links(f)[0]] = v
        h.x.scatter_forward()
        return h

    def _fixed_dofs(self, ctx: SurfaceState) -> tuple[np.ndarray, np.ndarray]:
        """Dofs (owned and ghost) off the lubricated surface, and on its edges.

        Marked through a scattered indicator so that every rank agrees on the
        dofs it shares.
        """
        mesh, S = ctx.mesh, self.S
        fdim = mesh.topology.dim - 1
        mesh.topology.create_connectivity(fdim, mesh.topology.dim)
        contact = ctx.facet_tags.find(ctx.contact_tag)
        ext = dolfinx.mesh.exterior_facet_indices(mesh.topology)
        skip = np.concatenate([contact] + [ctx.facet_tags.find(t) for t in self.no_flux_tags])
        others = np.setdiff1d(ext, skip)
        on = self._marked(dolfinx.fem.locate_dofs_topological(S, fdim, contact))
        near = self._marked(dolfinx.fem.locate_dofs_topological(S, fdim, others))
        fixed = np.flatnonzero(~on).astype(np.int32)
        edge = np.flatnonzero(on & near).astype(np.int32)
        return fixed, edge

    def _marked(self, dofs: np.ndarray) -> np.ndarray:
        """Boolean array over owned + ghost dofs, true where any rank marked the dof."""
        f = dolfinx.fem.Function(self.S)
        f.x.array[dofs] = 1.0
        f.x.scatter_reverse(dolfinx.la.InsertMode.add)
        f.x.scatter_forward()
        return f.x.array > 0.5

    def surface_grad(self, f: Any) -> Any:
        """Tangential gradient of ``f`` on the current surface (3-vector) [1/m]."""
        G = self.ctx.vector3(ufl.grad(f))
        N = self.ctx.N3
        G = G - ufl.dot(G, N) * N
        g = ufl.inv(self.ctx.F).T * G
        return g - ufl.dot(g, self.n) * self.n

    def set_speed(self, speed: float) -> None:
        """Change the sliding speed U [m/s], signed (the film must have been built
        with U != 0; the sign may change only where the sliding transports no
        fluid or the zone is long enough both ways)."""
        if not self.has_couette:
            raise ParameterError(
                "film.speed: this film was built at zero speed (no Couette term); "
                "build it with film.speed != 0 to sweep the speed"
            )
        if speed == 0.0 or not math.isfinite(speed):
            raise ParameterError(f"film.speed = {speed!r} m/s: must be finite and non-zero here")
        check_range("film.speed", speed, -1e3, 1e3, unit="m/s")
        self.speed.value = float(speed)
        self.direction.value = 1.0 if speed > 0.0 else -1.0
        poi, gap = self._q_ref_parts
        couette = 0.5 * abs(speed) * gap if self.has_transport else 0.0
        self.row_weight.value = self.scales.pressure * self.scales.element / (poi + couette)

    def set_pressure(self, pressure: Any) -> None:
        """Set the fluid pressure to a UFL expression [Pa] on the free film dofs
        (a Newton start; the boundary values stay)."""
        f = dolfinx.fem.Function(self.S)
        f.interpolate(dolfinx.fem.Expression(pressure, interpolation_points(self.S.element)))
        free = self.film_dofs_local
        self.P.x.array[free] = f.x.array[free] / self.scales.pressure
        self.P.x.scatter_forward()

    # ---------------------------------------------------------------- physics
    def shear_on_rubber(self) -> Any:
        """Shear stress on the rubber along :attr:`t` [Pa] (fluid + asperities)."""
        pr = self.params
        tau = -0.5 * self.g * ufl.dot(self.t, self.surface_grad(self.p))
        if self.has_couette:
            tau += pr.viscosity * self.speed * self.theta / self.g
        tau += self.asperity_shear()
        return tau

    def asperity_shear(self) -> Any:
        """``sigma_1 A/A0`` [Pa] along the sliding of the counter-surface (signed with
        it; 0 without contact pressure or rms slope)."""
        if (
            self.p_cont is None
            or not math.isfinite(self.rms_slope)
            or self.params.asperity_shear == 0
        ):
            return 0.0
        A = area_fraction(self.p_cont, self.e_star, self.rms_slope, self.scale)
        return self.direction * self.params.asperity_shear * A

    def friction_parts(self) -> dict[str, Any]:
        """Integrands (per reference area) of the friction force on the counter-surface [Pa].

        Keys ``couette``, ``poiseuille``, ``asperity``; each multiplies ``da/dA``.
        """
        pr = self.params
        out = {
            "poiseuille": 0.5 * self.g * ufl.dot(self.t, self.surface_grad(self.p)) * self.da,
            "asperity": self.asperity_shear() * self.da,
        }
        if self.has_couette:
            out["couette"] = pr.viscosity * self.speed * self.theta / self.g * self.da
        return out

    def traction_work(self, v3: Any) -> Any:
        """Virtual work of the fluid pressure and of the shear on the rubber (a residual term)."""
        ctx = self.ctx
        w = tractions.pressure_work(self.p, ctx.F, ctx.N3, v3, ctx.weight, self.ds)
        tau = self.shear_on_rubber()
        w += tau * ufl.dot(self.t, v3) * self.da * self.ds
        return -w

    def floored(self) -> Any:
        """1 where the gap is at or below its floor (``film.gap_floor h_rms``), else 0
        (UFL): where the film's coefficients are the floor's, not the gap's."""
        return ufl.conditional(ufl.le(self.ctx.gap, self.floor), 1.0, 0.0)

    def normal_force_integrand(self, part: str = "all") -> Any:
        """Fluid force on the body along the counter normal, per reference area [Pa].

        ``part``: ``"all"``, or the force of the pressures above (``"push"``) or
        below (``"suction"``) the cavitation pressure 0 alone.
        """
        check_choice("part", part, ("all", "push", "suction"))
        nanson = tractions.nanson_normal(self.ctx.F, self.ctx.N3)
        p = {"all": self.p, "push": ufl.max_value(self.p, 0.0),
             "suction": ufl.min_value(self.p, 0.0)}[part]  # fmt: skip
        return -p * ufl.dot(nanson, self.ctx.e_n) * self.ctx.weight

    # ---------------------------------------------------------------- outputs
    def _owned_surface_dofs(self) -> np.ndarray:
        """The owned dofs of :attr:`S` on the lubricated surface (found once)."""
        if getattr(self, "_surface_dofs", None) is None:
            ctx, S = self.ctx, self.S
            fdim = ctx.mesh.topology.dim - 1
            dofs = dolfinx.fem.locate_dofs_topological(
                S, fdim, ctx.facet_tags.find(ctx.contact_tag)
            )
            self._surface_dofs = dofs[dofs < S.dofmap.index_map.size_local]
        return self._surface_dofs

    def owned_gaps(self) -> np.ndarray:
        """Gap [m] at the owned dofs of the lubricated surface (no communication)."""
        dofs = self._owned_surface_dofs()
        return self.compiled.interpolate(self.ctx.gap, self.S).x.array[dofs].copy()

    def film_values(self) -> dict[str, np.ndarray]:
        """Nodal values on the lubricated surface, gathered and sorted by reference x.

        Keys: ``X`` (reference coordinates), ``x`` (current), ``p`` [Pa],
        ``theta``, ``gap`` [m]; only the dofs of the lubricated surface.
        """
        ctx, S = self.ctx, self.S
        dofs = self._owned_surface_dofs()
        vals = {}
        gdim = ctx.mesh.geometry.dim
        for name, expr in [("gap", ctx.gap), *((f"x{i}", ctx.x[i]) for i in range(gdim))]:
            vals[name] = self.compiled.interpolate(expr, S).x.array[dofs]
        X = S.tabulate_dof_coordinates()[dofs][:, :gdim]
        out = {
            "X": X,
            "x": np.column_stack([vals[f"x{i}"] for i in range(gdim)]),
            "p": self.scales.pressure * self.P.x.array[dofs],
            "theta": self.theta_fn.x.array[dofs] if self.has_theta else np.ones(dofs.size),
            "gap": vals["gap"],
        }
        comm = ctx.mesh.comm
        if comm.size > 1:
            out = {k: np.concatenate(comm.allgather(v)) for k, v in out.items()}
        order = np.lexsort(out["X"].T[::-1])
        return {k: v[order] for k, v in out.items()}

    def mass_balance_error(self) -> float:
        """Largest nodal mass imbalance of the film, relative to the inflow.

        The Reynolds rows (unweighted, SI) at the free film nodes are nodal net
        fluxes [m^2/s]; on the edges of the lubricated zone they are the
        boundary in/outflows.  Returns ``max |R_i|`` over free nodes where the
        film is not cavitated under the Reynolds condition (there mass is not
        conserved by construction), divided by the total inflow.  0 without
        flow (no transport and equal edge pressures).
        """
        edge_p = np.abs(self.boundary_values.x.array[np.concatenate(self._edges)])
        no_drive = edge_p.size == 0 or np.ptp(edge_p) == 0.0
        if not self.has_transport and self.ctx.mesh.comm.allreduce(no_drive, op=MPI.LAND):
            return 0.0
        R = dolfinx.fem.assemble_vector(self._flux_form())
        R.scatter_reverse(dolfinx.la.InsertMode.add)
        w = float(self.row_weight.value)
        r = R.array[: self.S.dofmap.index_map.size_local] / w
        free = self.film_dofs_local
        if self.params.cavitation == "reynolds":
            # on the bound as the VI solver sees it: PETSc's reduced-space VI keeps a
            # node with positive residual in the active set while x <= lower + 1e-8
            # (SNESVIGetInactiveSet, src/snes/impls/vi); such nodes, left at tiny
            # positive P = p/p_scale, are cavitated, not free
            free = free[self.P.x.array[free] > ACTIVE_TOLERANCE]
        interior = float(np.abs(r[free]).max(initial=0.0))
        comm = self.ctx.mesh.comm
        interior = comm.allreduce(interior, op=MPI.MAX)
        # the inflow: sum of the negative nodal fluxes on the edges
        edge = np.concatenate(self._edges)
        edge = edge[edge < self.S.dofmap.index_map.size_local]
        inflow = comm.allreduce(float(np.abs(r[edge]).sum()), op=MPI.SUM) / 2.0
        return interior / inflow if inflow > 0 else 0.0


__all__ = [
    "CAVITATION_MODELS",
    "FLOW_FACTORS",
    "FilmParams",
    "FilmScales",
    "SurfaceFilm",
    "pressure_flow_factor",
]
