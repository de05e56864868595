"""The rubber body in contact with a rigid counter-surface: forms, control, stepping.

:class:`SolidContactProblem` assembles, from named pieces,

    R(w; v) = int d psi(F(u), p_mix) w dx                (strain energy, kinematics weight w)
            + int p_cont(gap) J F^-T N . v w dA           (asperity pressure, Nanson follower load)
            [+ further boundary terms added by a scene, e.g. the fluid film]

with the unknowns

* ``u`` (vector P2 by default) and, for the mixed (nearly incompressible)
  formulation, the pressure ``p_mix`` (P1): Taylor-Hood;
* under force control, the rigid position of the counter-surface (a global real
  unknown, :func:`~dolfinx_seal.compat.real_functionspace`) with the equation ``contact force = F_N``; under
  displacement control that position is a prescribed constant.

It is solved by :class:`~dolfinx_seal.solvers.NonlinearSolver` (blocked when
force-controlled) with adaptive load stepping (:meth:`SolidContactProblem.ramp`):
the load (or position) fraction grows after easy steps and is cut after a
failed one, restoring the last converged state.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import basix.ufl
import dolfinx
import numpy as np
import ufl
from mpi4py import MPI

from dolfinx_seal.compat import real_functionspace
from dolfinx_seal.compiled import CompiledCache
from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.output import progress_step
from dolfinx_seal.params import check_int_range, check_positive, check_range
from dolfinx_seal.solid.body import (
    Body,
    Dirichlet,
    ForceControl,
    PositionControl,
    energy_quadrature,
)
from dolfinx_seal.solid.counter_surface import CounterSurface
from dolfinx_seal.solid.materials import LinearElastic
from dolfinx_seal.solid.step_limits import StepLimits, displacement_limiter, rigid_gap_limiter
from dolfinx_seal.solvers import NonlinearSolver, ProjectedMPCAssembly, SNESOptions
from dolfinx_seal.solvers.adaptive import AdaptiveWalk, StepControl, restore_arrays, secant
from dolfinx_seal.surface import tractions
from dolfinx_seal.surface.asperity import contact_pressure
from dolfinx_seal.surface.state import SurfaceState

#: relative size of the pulling part of the asperity force that makes a state
#: inadmissible (:meth:`SolidContactProblem.folded_contact`)
FOLD_TOLERANCE = 1e-3
#: load-fraction step of the one-sided difference of the residual in
#: :meth:`SolidContactProblem.path_tangent` (fractions run from 0 to 1)
LOAD_TANGENT_DELTA = 1e-6


@dataclass
class SteppingOptions:
    """Adaptive load stepping (the single source of its defaults).

    Attributes:
        first: First load fraction.
        grow: Factor on the increment after a step of at most ``easy`` Newton steps.
        easy: Newton steps counted as an easy step.
        cut: Factor on the increment after a failed step.
        min_increment: Smallest increment before giving up.
        max_steps: Largest number of load steps.
        predictor: Start each step from the linear extrapolation of the last two
            converged states (useful under position control, where the contact
            zone must follow the moving counter-surface).
        tangent: With ``predictor``, extrapolate along the tangent of the load
            path at the last converged state instead (``J dx/dt = -dF/dt``,
            :meth:`SolidContactProblem.path_tangent`; also at the first step),
            with the Jacobian at that state.
        max_increment: Largest increment (None: no cap).
        max_newton: Newton steps allowed to one step before it counts as failed and
            is cut (0: the solver's own limit).  A step that needs many more than
            an accepted step does usually ends in a NaN or the limit anyway.
        stall_steps: A step also fails once this many consecutive Newton steps
            have each lowered the residual by less than 1 % (0: never;
            :meth:`~dolfinx_seal.solvers.NonlinearSolver.newton_limit`), the
            continuation's rule (:class:`~dolfinx_seal.coupled.continuation.SpeedStepping`).
    """

    first: float = 0.25
    grow: float = 2.0
    easy: int = 6
    cut: float = 0.5
    min_increment: float = 1e-4
    max_steps: int = 200
    predictor: bool = False
    tangent: bool = False
    max_increment: float | None = None
    max_newton: int = 0
    stall_steps: int = 0

    def __post_init__(self) -> None:
        check_range("first", self.first, 0.0, 1.0, lo_open=True)
        check_range("grow", self.grow, 1.0, 10.0)
        check_range("cut", self.cut, 0.0, 1.0, lo_open=True, hi_open=True)
        check_positive("min_increment", self.min_increment)
        check_int_range("easy", self.easy, 1)
        check_int_range("max_steps", self.max_steps, 1)
        check_int_range("max_newton", self.max_newton, 0)
        check_int_range("stall_steps", self.stall_steps, 0)
        if self.max_increment is not None:
            check_positive("max_increment", self.max_increment)

    def control(self, span: float) -> StepControl:
        """The step control of a walk over a load-fraction interval of length ``span``."""
        return StepControl(
            first=min(self.first, span), grow=self.grow, easy=self.easy, cut=self.cut,
            min_step=self.min_increment, max_step=self.max_increment,
            max_attempts=self.max_steps, tolerance=1e-14,
        )  # fmt: skip


@dataclass
class StepRecord:
    """One accepted load step (``wall_time_s``: since the previous accepted step,
    failed tries included)."""

    fraction: float
    newton_iterations: int
    wall_time_s: float


class SolidContactProblem:
    """A rubber body against a rigid counter-surface, composed from named parts.

    Args:
        mesh, facet_tags: The body and its tagged boundary.
        body: :class:`~dolfinx_seal.solid.body.Body` (kinematics, material,
            displacement conditions, degree, quadrature); a body without a
            material is rigid (no displacement unknowns).
        counter: :class:`~dolfinx_seal.solid.counter_surface.CounterSurface`
            (``Flat``, ``Shaft``): gap, normal and sliding direction.
        control: :class:`~dolfinx_seal.solid.body.ForceControl` (the counter
            position is a global unknown with the equation ``contact force =
            load``) or :class:`~dolfinx_seal.solid.body.PositionControl`.
        contact_tag: Facet tag of the surface that may touch.
        law: Contact law with a UFL form (see
            :func:`~dolfinx_seal.surface.asperity.contact_pressure`); None: no
            asperity contact (a film is then required).
        film: Optional :class:`~dolfinx_seal.film.surface.SurfaceFilm` on the
            contact surface: its unknowns join the Newton system, its pressure and
            shear act on the body and count in the force equation.
        limits: Newton step limits (:class:`~dolfinx_seal.solid.step_limits.StepLimits`).
        snes: Newton options.
        extra_residual: Optional ``f(problem) -> ufl.Form`` added to the
            displacement residual (a scene's own term, e.g. a garter spring).
        periodic: Optional periodicity of a sector (e.g.
            :class:`~dolfinx_seal.solvers.periodic.RotationalPeriodicity`): the
            displacement (and mixed pressure) and the film's unknowns are
            constrained periodic (dolfinx_mpc), and the Newton system is assembled
            with :class:`~dolfinx_seal.solvers.assembly.ProjectedMPCAssembly`; the unknowns
            then live on the constraints' spaces (:attr:`constraints`, one per block).
        name: Named in logs and errors.

    The residual is the sum of the named terms :meth:`_bulk_residual`,
    :meth:`_asperity_residual`, :meth:`_film_residual`, the scene's extra term,
    the film's own rows and, under force control, :meth:`_force_equation`.
    """

    def __init__(
        self,
        mesh: dolfinx.mesh.Mesh,
        facet_tags: dolfinx.mesh.MeshTags,
        body: Body,
        counter: CounterSurface,
        control: ForceControl | PositionControl,
        contact_tag: int,
        *,
        law: Any = None,
        film: Any = None,
        limits: StepLimits | None = None,
        snes: SNESOptions | None = None,
        extra_residual: Callable[[SolidContactProblem], Any] | None = None,
        periodic: Any = None,
        name: str = "solid",
    ) -> None:
        if law is None and film is None:
            raise ParameterError("law: a problem without a film needs a contact law")
        kinematics, material, degree = body.kinematics, body.material, body.degree
        self.body = body
        self.bulk = body.deformable
        self.mesh, self.facet_tags = mesh, facet_tags
        self.kin, self.material, self.counter, self.law = kinematics, material, counter, law
        self.control, self.target, self.name = control.kind, float(control.target), name
        self.contact_tag = contact_tag
        limits = limits or StepLimits()
        max_step = limits.max_step
        quadrature_degree = body.quadrature_degree
        surface_quadrature_degree = body.surface_quadrature_degree
        position0 = control.position0
        gdim = mesh.geometry.dim
        cell = mesh.basix_cell()
        self.mixed = self.bulk and material.mixed
        self.periodic = periodic
        self._body_constraint: Any = None
        self.W: Any = None
        self.w: Any = None
        vw: Any = None
        if self.bulk:
            Ve = basix.ufl.element("Lagrange", cell, degree, shape=(gdim,))
            if material.mixed:
                Qe = basix.ufl.element("Lagrange", cell, degree - 1)
                self.W = dolfinx.fem.functionspace(mesh, basix.ufl.mixed_element([Ve, Qe]))
            else:
                self.W = dolfinx.fem.functionspace(mesh, Ve)
            # a periodic body: its unknowns live on the constraint's space (more ghosts)
            space = self.W
            if periodic is not None:
                self._dirichlet_bcs = self._dirichlet(body.dirichlet)
                self._body_constraint = periodic.body(self.W, material.mixed, self._dirichlet_bcs)
                space = self._body_constraint.function_space
            self.w = dolfinx.fem.Function(space, name="state")
            vw = ufl.TestFunction(self.W)
            if material.mixed:
                self.u, self.p_mix = ufl.split(self.w)
                v, _ = ufl.split(vw)
            else:
                self.u, self.p_mix = self.w, None
                v = vw
        else:  # rigid body: no displacement unknowns
            self.u, self.p_mix, v = ufl.as_vector([0.0] * gdim), None, None
        X = ufl.SpatialCoordinate(mesh)
        self.X = X
        self.x = X + self.u  # current position
        self.weight = kinematics.weight(X)
        self.F = kinematics.F(self.u) if self.bulk else ufl.Identity(3)
        self.N3 = kinematics.vector3(ufl.FacetNormal(mesh))
        self.v3 = kinematics.vector3(v) if self.bulk else None
        self.e_n = counter.normal(self.x)
        self.dx = ufl.Measure("dx", domain=mesh)
        #: the outputs' compiled forms and interpolations (:meth:`integrate`,
        #: :meth:`surface_values`), kept from one point to the next
        self.compiled = CompiledCache()
        self._scalar_spaces: dict[int, Any] = {}
        self.dx_energy = ufl.Measure(
            "dx", domain=mesh, metadata=energy_quadrature(degree, cell.name, quadrature_degree)
        )
        sqd = surface_quadrature_degree
        if sqd is None:
            sqd = 4 * degree + 2 if gdim == 2 else 2 * degree + 2
        meta = {"quadrature_degree": sqd}
        self.ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags)
        self.ds_c = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags, metadata=meta)(
            contact_tag
        )

        # counter-surface position: a real unknown (force control) or a constant
        self.position0 = float(position0)
        if self.control == "force":
            self.R = real_functionspace(mesh)
            self.position = dolfinx.fem.Function(self.R, name="position")
            self.position.x.array[:] = position0
            self.load = dolfinx.fem.Constant(mesh, 0.0)
            # 1: the position held at position0 (ForceControl.held), 0: force control
            self.held = dolfinx.fem.Constant(mesh, 1.0 if getattr(control, "held", False) else 0.0)
            self._owns_position = self.R.dofmap.index_map.size_local > 0
            self._pos_root = mesh.comm.allreduce(
                mesh.comm.rank if self._owns_position else mesh.comm.size, op=MPI.MIN
            )
        else:
            self.position = dolfinx.fem.Constant(mesh, float(position0))
            self.load = None

        self.extra = None
        self.gap = counter.gap(self.x, self.position)
        # amplitude scale of the roughness in the asperity law (1: the law as given;
        # walk_roughness walks it, the homotopy that installs a smooth surface)
        self.roughness_scale = dolfinx.fem.Constant(mesh, 1.0)
        self.p_cont = (
            contact_pressure(law, self.gap, scale=self.roughness_scale) if law is not None else None
        )

        # the lubricating film (optional): its unknowns, residuals and tractions
        self.film = film
        if film is not None:
            film.attach(
                SurfaceState(
                    mesh, facet_tags, contact_tag, self.x, self.F, self.N3, self.weight,
                    self.gap, kinematics.vector3, self.e_n, counter.sliding_direction(self.x), sqd,
                    edge_axis=counter.edge_axis(), transport=counter.transports,
                    roughness_scale=self.roughness_scale,
                    periodic=periodic,
                ),
                p_cont=self.p_cont,
            )  # fmt: skip

        # the residual: a sum of named terms (bulk, asperity, film, force equation)
        blocks: list[tuple[Any, Any, Any, Any]] = []  # (residual, unknown, lower, upper)
        self.bcs: list[dolfinx.fem.DirichletBC] = []
        if self.bulk:
            R_w = self._bulk_residual(vw)
            if self.p_cont is not None:
                R_w += self._asperity_residual()
            if film is not None:
                R_w += self._film_residual()
            self.extra = extra_residual(self) if extra_residual is not None else None
            if self.extra is not None:
                R_w += self.extra
            blocks.append((R_w, self.w, None, None))
            if periodic is None:
                self._dirichlet_bcs = self._dirichlet(body.dirichlet)
            self.bcs += self._dirichlet_bcs
        if film is not None:
            blocks += film.blocks
            self.bcs += film.bcs
        self.force_form = self.normal_force_integrand() * self.ds_c
        if self.control == "force":
            blocks.append((self._force_equation(), self.position, None, None))
        self.blocks = blocks
        self.limits = limits
        if self.bulk and self.limits.any:
            limiter = self.step_limiter()
        elif not self.bulk and self.control == "force":
            limiter = rigid_gap_limiter(self)
        else:
            limiter = None
        self._max_step_limiter = (
            displacement_limiter(self, max_step, None) if (max_step and self.bulk) else None
        )
        self.solver = self._make_solver(snes or SNESOptions(max_it=30), limiter)
        self._fold_forms: list[Any] | None = None  # built by folded_contact when first called
        if self.bulk and film is not None and law is not None:
            self.solver.acceptance = self.folded_contact
        self.steps: list[StepRecord] = []
        self._load_tangent: tuple[float, Any] | None = None  # (fraction, dx/dt) of ramp()
        self._force_compiled = dolfinx.fem.form(self.force_form)

    # ---------------------------------------------------------------- set-up
    def _dirichlet(self, conds: Sequence[Dirichlet]) -> list[dolfinx.fem.DirichletBC]:
        fdim = self.mesh.topology.dim - 1
        Vu = self.W.sub(0) if self.material.mixed else self.W
        bcs = []
        for c in conds:
            facets = self.facet_tags.find(c.tag)
            if c.component is None and not self.material.mixed:  # the whole space
                dofs = dolfinx.fem.locate_dofs_topological(Vu, fdim, facets)
                if callable(c.value):  # a field
                    g = dolfinx.fem.Function(Vu)
                    g.interpolate(c.value)
                    bcs.append(dolfinx.fem.dirichletbc(g, dofs))
                    continue
                value = np.full(self.mesh.geometry.dim, c.value, dtype=dolfinx.default_scalar_type)
                bcs.append(dolfinx.fem.dirichletbc(value, dofs, Vu))
                continue
            sub = Vu if c.component is None else Vu.sub(c.component)
            collapsed, _ = sub.collapse()
            dofs = dolfinx.fem.locate_dofs_topological((sub, collapsed), fdim, facets)
            g = dolfinx.fem.Function(collapsed)
            if callable(c.value):  # a field
                g.interpolate(c.value)
            else:
                g.x.array[:] = c.value
            bcs.append(dolfinx.fem.dirichletbc(g, dofs, sub))
        return bcs

    # ------------------------------------------------ the terms of the residual
    def strain_energy(self) -> Any:
        """Strain energy density of the bulk per reference volume [J/m^3] (UFL):
        the small-strain energy of a linear material, else ``psi(F, p_mix)``."""
        if isinstance(self.material, LinearElastic):
            return self.material.small_strain_energy(self.kin.eps(self.u), self.p_mix)
        return self.material.strain_energy(self.F, self.p_mix)

    def _bulk_residual(self, vw: Any) -> Any:
        """``int d psi w dx``: the first variation of the strain energy (kinematic weight w)."""
        R = ufl.derivative(self.strain_energy() * self.weight * self.dx_energy, self.w, vw)
        if self.mixed:  # keep the (zero for nu = 0.5) diagonal of the mixed pressure in
            # the sparsity: semismooth VI solvers scale and shift the diagonal.  The
            # energy's rule: one group of cell integrals, one rule (compat)
            q_mix = ufl.split(vw)[1]
            R += dolfinx.fem.Constant(self.mesh, 0.0) * self.p_mix * q_mix * self.dx_energy
        return R

    def _asperity_residual(self) -> Any:
        """``int p_cont(gap) J F^-T N . v w dA``: the asperity pressure as a follower load."""
        return -tractions.pressure_work(self.p_cont, self.F, self.N3, self.v3, self.weight,
                                        self.ds_c)  # fmt: skip

    def _film_residual(self) -> Any:
        """The fluid pressure and shear of the film on the body
        (:meth:`~dolfinx_seal.film.surface.SurfaceFilm.traction_work`)."""
        return self.film.traction_work(self.v3)

    def asperity_force_integrand(self) -> Any:
        """Asperity force on the body along the counter normal per reference area
        [Pa, times the kinematic weight]: ``-p_cont J F^-T N . e_n w`` (0 without a law)."""
        if self.p_cont is None:
            return 0.0
        return (
            -self.p_cont * ufl.dot(tractions.nanson_normal(self.F, self.N3), self.e_n) * self.weight
        )

    def normal_force_integrand(self) -> Any:
        """Normal force on the body per reference area: asperities plus fluid."""
        f_n = self.asperity_force_integrand()
        if self.film is not None:
            f_n = f_n + self.film.normal_force_integrand()
        return f_n

    def _force_equation(self) -> Any:
        """Force control: ``int f_n mu dA - F_N / |body| int mu dx = 0`` for the position
        unknown (the load spread over the body volume, so the form is a plain integral).

        While :attr:`held` is 1 the row is ``F_N (position - position0) / |position0|
        = 0`` instead (the position held, the row of the size of the load at zero
        unknowns, so the residual scale ``|F(0)|`` stays that of force control);
        :meth:`release_position` switches to the load equation."""
        mu = ufl.TestFunction(self.R)
        vol = self.mesh.comm.allreduce(
            dolfinx.fem.assemble_scalar(dolfinx.fem.form(1.0 * self.dx)), op=MPI.SUM
        )
        force = self.normal_force_integrand() * mu * self.ds_c - self.load / vol * mu * self.dx
        if not float(self.held.value):
            return force
        hold = self.target / (abs(self.position0) or 1.0) * (self.position - self.position0)
        return (1.0 - self.held) * force + self.held * hold / vol * mu * self.dx

    def release_position(self) -> float:
        """Free a held counter-surface (:attr:`ForceControl.held`) at the normal force
        it carries now (asperities and film, [N or N/m]): from here the problem is
        force-controlled at that load, and the current state still solves it.
        Returns the load."""
        if self.control != "force":
            raise ParameterError("release_position: the problem is not force-controlled")
        load = self.contact_force()
        self.target = load  # what set_fraction(1) sets
        self.load.value = load
        self.held.value = 0.0
        return load

    @property
    def constraints(self) -> list[Any] | None:
        """The multi-point constraint of each block (None for a block without one:
        the counter position), or None for a problem that is not periodic."""
        if self.periodic is None:
            return None
        out: list[Any] = [self._body_constraint] if self.bulk else []
        if self.film is not None:
            out += list(self.film.constraints)
        if self.control == "force":
            out.append(None)
        return out

    def _assembly(self) -> Any:
        """The assembly strategy of the solvers: plain, or with the periodic constraints."""
        cons = self.constraints
        if cons is None:
            return None
        return ProjectedMPCAssembly(cons[0] if len(cons) == 1 else cons)

    def _make_solver(self, opts: SNESOptions, limiter: Any) -> NonlinearSolver:
        blocks = self.blocks
        has_bounds = any(b[2] is not None or b[3] is not None for b in blocks)
        lower = [b[2] for b in blocks] if has_bounds else None
        upper = [b[3] for b in blocks] if has_bounds else None
        if len(blocks) == 1:
            return NonlinearSolver(
                blocks[0][0], blocks[0][1], self.bcs, lower=lower[0] if lower else None,
                upper=upper[0] if upper else None, options=opts, name=self.name,
                step_limiter=limiter, assembly=self._assembly(),
            )  # fmt: skip
        return NonlinearSolver(
            [b[0] for b in blocks], [b[1] for b in blocks], self.bcs, lower=lower, upper=upper,
            options=opts, name=self.name, step_limiter=limiter, assembly=self._assembly(),
        )  # fmt: skip

    def step_limiter(self, blocks: Sequence[Any] | None = None) -> Any:
        """The problem's displacement and gap step limits for a solver with the block
        layout ``blocks`` (default the problem's own)
        (:func:`~dolfinx_seal.solid.step_limits.displacement_limiter`)."""
        lim = self.limits
        return displacement_limiter(self, lim.max_step, lim.max_gap_step, blocks=blocks,
                                    closure=lim.max_gap_closure)  # fmt: skip

    @property
    def dofs(self) -> int:
        """Global number of unknowns (film dofs off the lubricated surface excluded)."""
        return sum(self.dof_counts().values())

    def destroy(self) -> None:
        """Free the solver's PETSc objects (collective: call it on every rank; under MPI
        petsc4py cannot free a parallel object on its own)."""
        self.solver.destroy()

    def dof_counts(self) -> dict[str, int]:
        """Global number of unknowns per field.

        Keys ``displacement`` (with the mixed pressure, when the bulk is on),
        ``fluid_pressure`` and ``film_fraction`` (free dofs on the lubricated
        surface, when a film is on) and ``position`` (force control).  A field
        the problem does not have is absent.
        """
        out: dict[str, int] = {}
        if self.bulk:
            im = self.W.dofmap.index_map
            out["displacement"] = int(im.size_global * self.W.dofmap.index_map_bs)
        if self.film is not None:
            n = self.mesh.comm.allreduce(int(self.film.film_dofs_local.size), op=MPI.SUM)
            out["fluid_pressure"] = n
            if self.film.has_theta:
                out["film_fraction"] = n
        if self.control == "force":
            out["position"] = 1
        return out

    # ---------------------------------------------------------------- solving
    def set_fraction(self, t: float) -> None:
        """Set the load (force control) or the counter position (position control) fraction."""
        if self.control == "force":
            self.load.value = t * self.target
        else:
            self.position.value = self.position0 + t * (self.target - self.position0)

    def state(self) -> list[np.ndarray]:
        """Copies of the arrays of all unknowns (block order)."""
        return [b[1].x.array.copy() for b in self.blocks]

    def restore(self, state: Sequence[np.ndarray]) -> None:
        """Reinstate a :meth:`state`."""
        restore_arrays([b[1] for b in self.blocks], state)

    def solve_at(self, t: float, where: str = "") -> int:
        """Newton solve at load fraction ``t`` from the current state; returns Newton steps."""
        self.set_fraction(t)
        hist = self.solver.solve(where=where or f"{self.name} at load fraction {t:.4g}")
        return hist.newton_iterations

    def ramp(
        self,
        stepping: SteppingOptions | None = None,
        t_start: float = 0.0,
        t_end: float = 1.0,
        on_step: Callable[[float], None] | None = None,
        stop: Callable[[], str] | None = None,
    ) -> list[StepRecord]:
        """Adaptive stepping of the load fraction from ``t_start`` to ``t_end``.

        ``stop``, asked before every step, ends the stepping with its reason (a
        spent time budget; the same answer on every rank).

        Raises:
            SolverError: the increment fell below ``min_increment``, or ``stop``
                ended it; ``partial`` holds the last converged fraction (the state
                is left there).
        """
        st = stepping or SteppingOptions()
        t0 = time.perf_counter()

        def record(t: float, its: int) -> None:
            nonlocal t0
            self.steps.append(StepRecord(t, its, time.perf_counter() - t0))
            t0 = time.perf_counter()
            progress_step(f"{self.name} load fraction", t)
            if on_step is not None:
                on_step(t)

        predictor = None
        if st.predictor:
            predictor = self._predict_tangent if st.tangent else self._predict
        walk = AdaptiveWalk(
            st.control(t_end - t_start), self.set_fraction,
            lambda t: self.solver.solve(where=f"{self.name} at load fraction {t:.4g}").newton_iterations,
            self.state, self.restore, predictor=predictor,
            on_accept=record, name=f"{self.name} load stepping",
        )  # fmt: skip
        try:
            with self.solver.newton_limit(st.max_newton, st.stall_steps):
                res = walk.walk(t_start, t_end, stop=stop)
        finally:
            self._drop_load_tangent()
        if res.converged:
            return self.steps
        t = res.reached
        self.set_fraction(t)
        if res.stopped:
            raise SolverError(f"load stepping stopped: {res.error}", where=f"{self.name}, at "
                              f"load fraction {t:.6g}",
                              partial={"fraction": t, "steps": list(self.steps)})  # fmt: skip
        if res.last_error is None or walk.step >= st.min_increment:
            raise SolverError(f"more than {st.max_steps} load steps", where=self.name,
                              partial={"fraction": t, "steps": list(self.steps)})  # fmt: skip
        raise SolverError(
            f"load stepping stalled: increment {walk.step:.2e} below {st.min_increment:.1e}",
            where=f"{self.name}, from load fraction {t:.6g}",
            history=res.last_error.history,
            partial={"fraction": t, "steps": list(self.steps)},
        ) from res.last_error

    def walk_roughness(self, start: float, stepping: SteppingOptions | None = None) -> int:
        """Walk the roughness amplitude scale of the asperity law from ``start`` to 1.

        The current state must be converged with ``roughness_scale = start``.  A
        smooth surface's law is stiff (its pressure changes by decades over a
        fraction of a small ``h_rms``), so loading it from the unloaded body takes
        hundreds of Newton steps or stalls; loaded at a rougher scale, the body is
        already where the smooth one will be to within a few ``h_rms``, and the walk
        in ``log s`` closes that last gap in a few steps.  Returns the Newton steps.

        Raises:
            SolverError: the walk stalled; ``partial`` holds the scale reached.
        """
        st = stepping or SteppingOptions(first=0.5, grow=2.0, easy=8, max_steps=60)
        walk = AdaptiveWalk(
            StepControl(first=min(st.first, abs(math.log10(start)) or 1.0), grow=st.grow,
                        easy=st.easy, cut=st.cut, min_step=1e-3, max_attempts=st.max_steps),
            lambda c: setattr(self.roughness_scale, "value", c),
            lambda c: self.solver.solve(
                where=f"{self.name} at roughness scale {c:.4g}").newton_iterations,
            self.state, self.restore, coordinate=(math.log10, lambda c: 10.0**c),
            on_accept=lambda c, its: progress_step(f"{self.name} roughness scale", c),
            name=f"{self.name} roughness walk",
        )  # fmt: skip
        self.roughness_scale.value = start
        res = walk.walk(start, 1.0)
        if not res.converged:
            self.roughness_scale.value = res.reached
            raise SolverError(
                f"roughness walk stalled: {res.error}",
                where=f"{self.name}, from roughness scale {res.reached:.6g} towards 1",
                history=res.last_error.history if res.last_error else None,
                partial={"roughness_scale": res.reached},
            )
        self.roughness_scale.value = 1.0
        return res.newton_iterations

    def _predict(self, history: Any, t: float) -> None:
        """Secant predictor in the load fraction (from the second step on)."""
        if len(history) == 2:
            self.restore(secant(history, t))

    def _predict_tangent(self, history: Any, t: float) -> None:
        """Tangent predictor in the load fraction: ``x(t) = x(t0) + (t - t0) dx/dt``
        from the last converged state at ``t0`` (its tangent made once, kept for
        the retries of a cut step); the load fraction is left at ``t``."""
        t0 = float(history[-1][0])
        if self._load_tangent is None or self._load_tangent[0] != t0:
            self._drop_load_tangent()
            self._load_tangent = (t0, self.path_tangent(t0))
            self.set_fraction(t)
        self.solver.add_to_unknowns(self._load_tangent[1], t - t0)

    def path_tangent(self, t: float) -> Any:
        """The tangent ``dx/dt`` of the load path at the current state, converged
        at load fraction ``t``: ``J dx/dt = -dF/dt`` (:meth:`NonlinearSolver.tangent
        <dolfinx_seal.solvers.NonlinearSolver.tangent>`; a plain Newton factorises
        the Jacobian at the state in its own pattern), with ``dF/dt`` a one-sided
        difference of the residual over :data:`LOAD_TANGENT_DELTA`.  A vector of
        the solver's layout (the caller destroys it); the fraction is left at ``t``."""
        solver = self.solver
        self.set_fraction(t)
        F0 = solver.residual()
        self.set_fraction(t + LOAD_TANGENT_DELTA)
        dF = solver.residual()
        self.set_fraction(t)
        dF.axpy(-1.0, F0)
        dF.scale(1.0 / LOAD_TANGENT_DELTA)
        F0.destroy()
        try:
            return solver.tangent(dF)
        finally:
            dF.destroy()

    def _drop_load_tangent(self) -> None:
        if self._load_tangent is not None:
            self._load_tangent[1].destroy()
            self._load_tangent = None

    def warm_start(self, pressure_guess: Any, peak_separation: float) -> int:
        """Start from the deformation under a guessed contact pressure (e.g. Hertz).

        Solves the body with the contact term replaced by the prescribed pressure
        ``pressure_guess`` (a UFL expression of the reference coordinates, acting
        on the current surface), then places the counter-surface so that the
        lowest surface point has the gap ``peak_separation`` (the law's
        separation at the guessed peak pressure).  A
        stiff contact law then starts within a fraction of ``h_rms`` of its
        solution instead of from a point contact.  Returns the Newton steps.
        """
        if not self.bulk:
            raise ParameterError("warm_start needs the bulk (bulk=True)")
        vw = ufl.TestFunction(self.W)
        v = ufl.split(vw)[0] if self.material.mixed else vw
        v3 = self.kin.vector3(v)
        R = ufl.derivative(self.strain_energy() * self.weight * self.dx_energy, self.w, vw)
        R += -tractions.pressure_work(pressure_guess, self.F, self.N3, v3, self.weight, self.ds_c)
        pre = NonlinearSolver(
            R, self.w, self._dirichlet_bcs, name=f"{self.name} warm start",
            options=dataclasses.replace(self.solver.options, snes_type="newtonls"),
            # the displacement-only (penalty) form of nearly incompressible rubber has a
            # huge volumetric stiffness and needs damped steps from the undeformed state;
            # the mixed form converges in 3-4 full steps at any mesh size
            step_limiter=None if self.material.mixed else self._max_step_limiter,
            assembly=self._body_assembly(),
        )  # fmt: skip
        hist = pre.solve()
        pre.destroy()
        xn = self.counter.gap(self.x, 0.0)  # coordinate of the current surface along the normal
        _, vals = self.surface_values(xn)
        lowest = float(vals.min())
        if self.control == "force":
            self.position.x.array[:] = lowest - peak_separation
        return hist.newton_iterations

    def _body_assembly(self) -> Any:
        """The assembly of a solver on the body's unknowns alone."""
        if self._body_constraint is None:
            return None
        return ProjectedMPCAssembly(self._body_constraint)

    # ---------------------------------------------------------------- results
    def _scalar_space(self, degree: int) -> Any:
        """The scalar Lagrange space of ``degree`` on the mesh (made once)."""
        if degree not in self._scalar_spaces:
            self._scalar_spaces[degree] = dolfinx.fem.functionspace(self.mesh, ("Lagrange", degree))
        return self._scalar_spaces[degree]

    def contact_force(self) -> float:
        """Total contact force on the body along the counter normal [N or N/m]."""
        return self.mesh.comm.allreduce(
            dolfinx.fem.assemble_scalar(self._force_compiled), op=MPI.SUM
        )

    def integrate(self, expr: Any, measure: Any) -> float:
        """Global integral of a UFL expression (compiled once, :attr:`compiled`)."""
        return self.mesh.comm.allreduce(
            dolfinx.fem.assemble_scalar(self.compiled.form(expr, measure)), op=MPI.SUM
        )

    def counter_position(self) -> float:
        """Current counter-surface position [m]."""
        if self.control == "force":
            return float(self.mesh.comm.allreduce(
                float(self.position.x.array[0]) if self.position.x.array.size else -np.inf, op=MPI.MAX))  # fmt: skip
        return float(self.position.value)

    def folded_contact(self) -> str | None:
        """Why the current state of a lubricated rough contact is not a solution, or
        None: the asperity pressure pulls the body towards the counter-surface.

        Pressure pushes, so on every part of the surface that faces the
        counter-surface the asperity force ``-p_cont J F^-T N . e_n`` is positive;
        a negative part larger than :data:`FOLD_TOLERANCE` of the positive asperity
        and the fluid normal forces means the surface is folded over (its deformed
        normal turned away from the counter-surface) where the asperities press
        (the case that showed it: docs/design.md, "Starts and their fallback
        chain").  The solver calls this after convergence
        (:attr:`~dolfinx_seal.solvers.snes.NonlinearSolver.acceptance`) and treats
        a reason as a failed solve, so continuation cuts its step and a start
        takes its fallback chain."""
        if self._fold_forms is None:
            f = self.asperity_force_integrand()
            parts = (
                ufl.min_value(f, 0.0),
                ufl.max_value(f, 0.0),
                self.film.normal_force_integrand(),
            )
            self._fold_forms = [dolfinx.fem.form(g * self.ds_c) for g in parts]
        neg, pos, fluid = (
            self.mesh.comm.allreduce(dolfinx.fem.assemble_scalar(a), op=MPI.SUM)
            for a in self._fold_forms
        )
        if not neg < -FOLD_TOLERANCE * (pos + abs(fluid)):
            return None
        return (f"the asperity pressure pulls: its normal force has a part of {neg:.4g} "
                f"against {pos:.4g} pushing (fluid {fluid:.4g}; N, or N/m in 2D): the "
                "contact surface is folded over")  # fmt: skip

    def surface_values(
        self, expr: Any, tag: int | None = None, average: bool = False
    ) -> tuple[np.ndarray, np.ndarray]:
        """Reference coordinates and values of ``expr`` at the dofs of the (contact) surface.

        Gathered on every rank, sorted by the coordinates.  By default the
        expression is interpolated into the scalar Lagrange space of the
        displacement degree; with ``average=True`` it is the lumped L2
        projection onto P1 of the surface (use it for pressures of stiff laws,
        whose nodal samples oscillate on coarse meshes).
        """
        tag = self.contact_tag if tag is None else tag
        if average:
            f = _lumped_projection(self, expr, tag)
            S = f.function_space
        else:
            if not self.bulk:
                deg = 1
            elif self.mixed:
                deg = self.W.sub(0).ufl_element().degree
            else:
                deg = self.W.ufl_element().degree
            S = self._scalar_space(deg)
            f = self.compiled.interpolate(expr, S)
        fdim = self.mesh.topology.dim - 1
        dofs = dolfinx.fem.locate_dofs_topological(S, fdim, self.facet_tags.find(tag))
        nown = S.dofmap.index_map.size_local
        dofs = dofs[dofs < nown]
        X = S.tabulate_dof_coordinates()[dofs]
        vals = f.x.array[dofs]
        comm = self.mesh.comm
        Xa = np.concatenate(comm.allgather(X)) if comm.size > 1 else X
        va = np.concatenate(comm.allgather(vals)) if comm.size > 1 else vals
        order = np.lexsort(Xa.T[::-1])
        return Xa[order], va[order]


def _lumped_projection(prob: SolidContactProblem, expr: Any, tag: int) -> dolfinx.fem.Function:
    """P1 function with nodal values ``int expr phi_i ds / int phi_i ds`` on surface ``tag``.

    The lumped L2 projection of a boundary quantity: a local, positive weighted
    average that converges with the mesh and does not oscillate between vertex
    and mid-edge nodes as nodal samples of a stiff contact law do.
    """
    S = prob._scalar_space(1)
    q = ufl.TestFunction(S)
    ds = prob.ds(tag, metadata=prob.ds_c.metadata())
    b = dolfinx.fem.assemble_vector(prob.compiled.form(expr * q, ds))
    m = dolfinx.fem.assemble_vector(prob.compiled.form(q, ds))
    b.scatter_reverse(dolfinx.la.InsertMode.add)
    m.scatter_reverse(dolfinx.la.InsertMode.add)
    f = dolfinx.fem.Function(S)
    on = m.array > 0
    f.x.array[on] = b.array[on] / m.array[on]
    f.x.scatter_forward()
    return f


__all__ = ["SolidContactProblem", "StepRecord", "SteppingOptions"]
