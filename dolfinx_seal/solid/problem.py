"""The rubber body in contact with a rigid counter-surface: forms, control, stepping.

:class:`SolidContactProblem` assembles, from named pieces,

    R(w; v) = int d psi(F(u), p_mix) w dx                (strain energy, kinematics weight w)
            + int p_cont(gap) J F^-T N . v w dA           (asperity pressure, Nanson follower load)
            [+ further boundary terms added by a scene, e.g. the fluid film]

with the unknowns

* ``u`` (vector P2 by default) and, for the mixed (nearly incompressible)
  formulation, the pressure ``p_mix`` (P1): Taylor-Hood;
* under force control, the rigid position of the counter-surface (a global real
  unknown, scifem) with the equation ``contact force = F_N``; under
  displacement control that position is a prescribed constant.

It is solved by :class:`~dolfinx_seal.solvers.NonlinearSolver` (blocked when
force-controlled) with adaptive load stepping (:meth:`SolidContactProblem.ramp`):
the load (or position) fraction grows after easy steps and is cut after a
failed one, restoring the last converged state.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import basix.ufl
import dolfinx
import numpy as np
import scifem
import ufl
from mpi4py import MPI

from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.mpi import get_logger
from dolfinx_seal.params import check_choice, check_int_range, check_positive, check_range
from dolfinx_seal.solid.materials import LinearElastic
from dolfinx_seal.solvers import NonlinearSolver, SNESOptions
from dolfinx_seal.surface import tractions
from dolfinx_seal.surface.asperity import contact_pressure
from dolfinx_seal.surface.state import SurfaceState


@dataclass
class Dirichlet:
    """A displacement condition on a tagged boundary.

    Attributes:
        tag: Facet tag.
        component: Displacement component (``None``: all components).
        value: Prescribed displacement [m].
    """

    tag: int
    component: int | None = None
    value: float = 0.0


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
    """

    first: float = 0.25
    grow: float = 2.0
    easy: int = 6
    cut: float = 0.5
    min_increment: float = 1e-4
    max_steps: int = 200
    predictor: bool = False

    def __post_init__(self) -> None:
        check_range("first", self.first, 0.0, 1.0, lo_open=True)
        check_range("grow", self.grow, 1.0, 10.0)
        check_range("cut", self.cut, 0.0, 1.0, lo_open=True, hi_open=True)
        check_positive("min_increment", self.min_increment)
        check_int_range("easy", self.easy, 1)
        check_int_range("max_steps", self.max_steps, 1)


@dataclass
class StepRecord:
    """One accepted load step."""

    fraction: float
    newton_iterations: int
    wall_time_s: float


class SolidContactProblem:
    """Rubber body + rigid counter-surface (+ optional extra boundary terms).

    Args:
        mesh, facet_tags: The body and its tagged boundary.
        kinematics: :mod:`~dolfinx_seal.solid.kinematics` object.
        material: :mod:`~dolfinx_seal.solid.materials` object.
        counter: :class:`~dolfinx_seal.solid.counter_surface.Flat` or ``Shaft``.
        law: Contact law with a UFL form (see :func:`~dolfinx_seal.surface.asperity.contact_pressure`).
        contact_tag: Facet tag of the surface that may touch.
        dirichlet: Displacement conditions.
        control: ``"force"`` (counter position unknown, ``target`` = normal force
            [N, or N/m in plane strain]) or ``"position"`` (``target`` = final
            counter position [m]).
        target: See ``control``.
        position0: Counter position at zero load [m] (the touching position).
        degree: Displacement degree (the mixed pressure is one lower).
        snes: Newton options.
        extra_residual: Optional ``f(problem) -> ufl.Form`` added to the displacement residual.
        max_step: Largest displacement change of one Newton step [m] (a pre-check
            scales longer steps down), so that a step driven by the stiff contact
            law cannot invert elements; None: no limit.
        max_normal_step: Largest change of the displacement component along the
            counter-surface normal in one Newton step [m] (with a larger
            ``max_step``): the normal motion is what the stiff contact law drives
            and what can invert the thin contact elements, while friction shears a
            lubricated body sideways as a whole (the S1 cylinder by 14 um at its
            start), a smooth motion that a mesh-sized ``max_step`` would spread over
            more steps the finer the mesh; None: no separate limit.
        max_gap_step: Largest change of the gap at a contact node in one Newton step
            [m] (normal displacement minus counter-surface motion).  A few decay
            lengths of the contact law keep Newton on an exponential law from
            overshooting by decades of pressure (docs/design.md, solver strategy); None: no limit.
        max_gap_closure: Largest fraction f (0-1) of its current value by which a
            contact gap may close in one Newton step; it may open by at most the
            factor 1/(1 - f).  For films, whose conductance goes as g^3: it keeps a
            step from a poor start from closing (or blowing open) the film, without
            slowing the far, wide gaps (which a fixed ``max_gap_step`` does).  With
            both, a gap may always change by ``max_gap_step`` (near asperity
            contact, where the gap is a small part of h_rms and the contact law
            limits the step); None: no limit.
        film: Optional :class:`~dolfinx_seal.film.surface.SurfaceFilm` on the
            contact surface: its unknowns join the Newton system, its pressure and
            shear act on the body and count in the force equation.
        bulk: False for a rigid body: no displacement unknowns (``material``,
            ``dirichlet`` and the step limits are then unused).
        sliding_axis: Coordinate axis of the counter-surface's sliding direction.
        quadrature_degree: Quadrature degree of the strain energy (default
            ``2 * degree``).  UFL's estimate for the neo-Hookean Jacobian is 13
            (the ``J^(-2/3)`` factors count as polynomials of high degree), which
            made 3D assembly ~10x slower for no accuracy gain measurable against
            Hertz; ``2 * degree`` integrates the linearised stiffness of affine
            cells exactly.
        surface_quadrature_degree: Quadrature degree of the contact-surface
            integrals (asperity pressure, film), the same for the residual and its
            Jacobian (UFL estimates the two separately).  Default ``4 * degree + 2``
            on lines (2D: 10 for P2; mu and h_min of the 10 um cylinder at 1e-3 m/s
            are unchanged to 1e-15, and 6 made its start diverge) and ``2 *
            degree + 2`` on triangles (3D, where the estimate for ``g^3`` and the
            exponential laws asked for rules of 1e5 points).
    """

    def __init__(
        self,
        mesh: dolfinx.mesh.Mesh,
        facet_tags: dolfinx.mesh.MeshTags,
        kinematics: Any,
        material: Any,
        counter: Any,
        law: Any,
        contact_tag: int,
        dirichlet: Sequence[Dirichlet],
        control: str = "force",
        target: float = 1.0,
        position0: float = 0.0,
        degree: int = 2,
        snes: SNESOptions | None = None,
        extra_residual: Callable[[SolidContactProblem], Any] | None = None,
        max_step: float | None = None,
        max_gap_step: float | None = None,
        max_gap_closure: float | None = None,
        name: str = "solid",
        max_normal_step: float | None = None,
        film: Any = None,
        bulk: bool = True,
        sliding_axis: int = 0,
        quadrature_degree: int | None = None,
        surface_quadrature_degree: int | None = None,
    ) -> None:
        check_choice("control", control, ("force", "position"))
        check_int_range("degree", degree, 1, 3)
        if control == "force":
            check_positive("target (normal load)", target)
        self.bulk = bool(bulk)
        if self.bulk and material.mixed and degree < 2:
            raise ParameterError("the mixed formulation needs degree >= 2 (Taylor-Hood)")
        if law is None and film is None:
            raise ParameterError("law: a problem without a film needs a contact law")
        self.mesh, self.facet_tags = mesh, facet_tags
        self.kin, self.material, self.counter, self.law = kinematics, material, counter, law
        self.control, self.target, self.name = control, float(target), name
        self.contact_tag = contact_tag
        gdim = mesh.geometry.dim
        cell = mesh.basix_cell()
        self.mixed = self.bulk and material.mixed
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
            self.w = dolfinx.fem.Function(self.W, name="state")
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
        self.e_n = counter.normal(gdim)
        self.dx = ufl.Measure("dx", domain=mesh)
        qd = 2 * degree if quadrature_degree is None else quadrature_degree
        check_int_range("quadrature_degree", qd, 1, 20)
        self.dx_energy = ufl.Measure("dx", domain=mesh, metadata={"quadrature_degree": qd})
        sqd = surface_quadrature_degree
        if sqd is None:
            sqd = 4 * degree + 2 if gdim == 2 else 2 * degree + 2
        check_int_range("surface_quadrature_degree", sqd, 1, 30)
        meta = {"quadrature_degree": sqd}
        self.ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags)
        self.ds_c = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags, metadata=meta)(
            contact_tag
        )

        # counter-surface position: a real unknown (force control) or a constant
        self.position0 = float(position0)
        if control == "force":
            self.R = scifem.create_real_functionspace(mesh)
            self.position = dolfinx.fem.Function(self.R, name="position")
            self.position.x.array[:] = position0
            self.load = dolfinx.fem.Constant(mesh, 0.0)
            self._owns_position = self.R.dofmap.index_map.size_local > 0
            self._pos_root = mesh.comm.allreduce(
                mesh.comm.rank if self._owns_position else mesh.comm.size, op=MPI.MIN
            )
        else:
            self.position = dolfinx.fem.Constant(mesh, float(position0))
            self.load = None

        self.extra = None
        self.gap = counter.gap(self.x, self.position)
        self.p_cont = contact_pressure(law, self.gap) if law is not None else None

        # the lubricating film (optional): its unknowns, residuals and tractions
        self.film = film
        if film is not None:
            # the counter-surface says how it slides (a shaft: along the hoop or the axis)
            if hasattr(counter, "sliding_direction"):
                sliding = counter.sliding_direction()
            else:
                sliding = _unit(gdim, sliding_axis)
            film.attach(
                SurfaceState(
                    mesh, facet_tags, contact_tag, self.x, self.F, self.N3, self.weight,
                    self.gap, kinematics.vector3, self.e_n, sliding, sqd,
                    edge_axis=getattr(counter, "edge_axis", lambda: None)(),
                    transport=getattr(counter, "transports", True),
                ),
                p_cont=self.p_cont,
            )  # fmt: skip

        # residual of the body
        blocks: list[tuple[Any, Any, Any, Any]] = []  # (residual, unknown, lower, upper)
        self.bcs: list[dolfinx.fem.DirichletBC] = []
        if self.bulk:
            if isinstance(material, LinearElastic):
                energy = material.small_strain_energy(kinematics.eps(self.u), self.p_mix)
            else:
                energy = material.strain_energy(self.F, self.p_mix)
            R_w = ufl.derivative(energy * self.weight * self.dx_energy, self.w, vw)
            if self.mixed:  # keep the (zero for nu = 0.5) diagonal of the mixed pressure in
                # the sparsity: semismooth VI solvers scale and shift the diagonal
                q_mix = ufl.split(vw)[1]
                R_w += dolfinx.fem.Constant(mesh, 0.0) * self.p_mix * q_mix * self.dx
            if self.p_cont is not None:
                R_w += -tractions.pressure_work(
                    self.p_cont, self.F, self.N3, self.v3, self.weight, self.ds_c
                )
            if film is not None:
                R_w += film.traction_work(self.v3)
            self.extra = extra_residual(self) if extra_residual is not None else None
            if self.extra is not None:
                R_w += self.extra
            blocks.append((R_w, self.w, None, None))
            self._dirichlet_bcs = self._dirichlet(dirichlet)
            self.bcs += self._dirichlet_bcs
        if film is not None:
            blocks += film.blocks
            self.bcs += film.bcs
        # force on the body along the counter normal (N, or N/m): asperities + fluid
        f_n = 0.0
        if self.p_cont is not None:
            f_n = -self.p_cont * ufl.dot(tractions.nanson_normal(self.F, self.N3), self.e_n)
            f_n = f_n * self.weight
        if film is not None:
            f_n = f_n + film.normal_force_integrand()
        self.force_form = f_n * self.ds_c
        opts = snes or SNESOptions(max_it=30)
        if control == "force":
            mu = ufl.TestFunction(self.R)
            vol = mesh.comm.allreduce(
                dolfinx.fem.assemble_scalar(dolfinx.fem.form(1.0 * self.dx)), op=MPI.SUM
            )
            R_r = f_n * mu * self.ds_c - self.load / vol * mu * self.dx
            blocks.append((R_r, self.position, None, None))
        self.blocks = blocks
        self.max_step, self.max_gap_step = max_step, max_gap_step
        self.max_normal_step = max_normal_step
        if max_normal_step is not None:
            check_positive("max_normal_step", max_normal_step, "m")
        self.max_gap_closure = max_gap_closure
        if max_gap_closure is not None:
            check_range("max_gap_closure", max_gap_closure, 0.0, 1.0, lo_open=True, hi_open=True)
        bulk_limits = self.bulk and (max_step or max_gap_step or max_gap_closure)
        limiter = (
            self._step_limiter(max_step, max_gap_step, closure=max_gap_closure)
            if bulk_limits
            else None
        )
        if not self.bulk and control == "force":
            limiter = self._rigid_gap_limiter()
        self._max_step_limiter = (
            self._step_limiter(max_step, None) if (max_step and self.bulk) else None
        )
        has_bounds = any(b[2] is not None or b[3] is not None for b in blocks)
        lower = [b[2] for b in blocks] if has_bounds else None
        upper = [b[3] for b in blocks] if has_bounds else None
        if len(blocks) == 1:
            lower = lower[0] if lower else None
            upper = upper[0] if upper else None
            self.solver = NonlinearSolver(
                blocks[0][0], blocks[0][1], self.bcs, lower=lower, upper=upper, options=opts,
                name=name, step_limiter=limiter,
            )  # fmt: skip
        else:
            self.solver = NonlinearSolver(
                [b[0] for b in blocks], [b[1] for b in blocks], self.bcs, lower=lower,
                upper=upper, options=opts, name=name, step_limiter=limiter,
            )  # fmt: skip
        self.steps: list[StepRecord] = []
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
                value = np.full(self.mesh.geometry.dim, c.value, dtype=dolfinx.default_scalar_type)
                bcs.append(dolfinx.fem.dirichletbc(value, dofs, Vu))
                continue
            sub = Vu if c.component is None else Vu.sub(c.component)
            collapsed, _ = sub.collapse()
            dofs = dolfinx.fem.locate_dofs_topological((sub, collapsed), fdim, facets)
            g = dolfinx.fem.Function(collapsed)
            g.x.array[:] = c.value
            bcs.append(dolfinx.fem.dirichletbc(g, dofs, sub))
        return bcs

    def _step_limiter(
        self,
        max_step: float | None,
        max_gap_step: float | None,
        blocks: Sequence[Any] | None = None,
        closure: float | None = None,
    ) -> Callable[[np.ndarray, np.ndarray], float]:
        """Pre-check scaling a Newton step so that no displacement dof moves more than
        ``max_step``, no contact gap changes by more than ``max_gap_step`` and none
        closes by more than the fraction ``closure`` of itself.

        ``blocks``: the block layout of the solver it serves (default the
        problem's); the counter position counts when it is the last block.

        The displacement dofs come first in the (block) vector, so their local
        indices are those of the collapsed displacement sub-space (owned part);
        the counter position (force control) follows the field block.
        """
        Vu = self.W.sub(0) if self.material.mixed else self.W
        n_own = self.W.dofmap.index_map.size_local * self.W.dofmap.index_map_bs
        if self.material.mixed:
            _, dofs = Vu.collapse()
            dofs = np.asarray(dofs)
        else:
            dofs = np.arange(n_own)
        dofs = dofs[dofs < n_own]
        axis = getattr(self.counter, "axis", 0)
        normal_dofs = np.asarray(Vu.sub(axis).collapse()[1])
        normal_dofs = normal_dofs[normal_dofs < n_own]
        max_normal = self.max_normal_step
        fdim = self.mesh.topology.dim - 1
        sub = Vu.sub(axis)
        collapsed, _ = sub.collapse()
        ndofs, cdofs = dolfinx.fem.locate_dofs_topological(
            (sub, collapsed), fdim, self.facet_tags.find(self.contact_tag)
        )
        owned = ndofs < n_own
        ndofs = ndofs[owned]
        # reference coordinate normal to the counter-surface of those dofs [m]
        Xn = collapsed.tabulate_dof_coordinates()[cdofs[owned], axis]
        if max_step:
            check_positive("max_step", max_step, "m")
        if max_gap_step:
            check_positive("max_gap_step", max_gap_step, "m")
        comm = self.mesh.comm
        blocks = self.blocks if blocks is None else blocks
        position_free = self.control == "force" and blocks[-1][1] is self.position
        pos_index = sum(
            b[1].function_space.dofmap.index_map.size_local
            * b[1].function_space.dofmap.index_map_bs
            for b in blocks[:-1]
        )

        def limit(x: np.ndarray, dx: np.ndarray) -> float:
            s = 1.0
            if max_step:
                big = float(np.abs(dx[dofs]).max(initial=0.0))
                if big > max_step:
                    s = min(s, max_step / big)
            if max_step and max_normal:
                big = float(np.abs(dx[normal_dofs]).max(initial=0.0))
                if big > max_normal:
                    s = min(s, max_normal / big)
            if max_gap_step or closure:
                # PETSc steps x -> x - dx: the gap changes by -(dx_n - dx_position)
                dpos = 0.0
                if position_free:  # the position dof is the last block
                    mine = (
                        (float(x[pos_index]), float(dx[pos_index])) if self._owns_position else None
                    )
                    pos, dpos = comm.bcast(mine, root=self._pos_root)
                elif closure:
                    pos = self.counter_position()
                dg = dpos - dx[ndofs]
            if max_gap_step and not closure:
                dgap = np.abs(dg).max(initial=0.0)
                if dgap > max_gap_step:
                    s = min(s, max_gap_step / dgap)
            if closure:  # g_new / g in [1 - closure, 1 / (1 - closure)], or |dg| <= max_gap_step
                gap = np.maximum(Xn + x[ndofs] - pos, 0.0)
                floor = max_gap_step or 0.0
                allowed = np.where(dg < 0.0, closure, closure / (1.0 - closure)) * gap
                allowed = np.maximum(allowed, floor)
                moving = np.abs(dg) > allowed
                if moving.any():
                    s = min(s, float((allowed[moving] / np.abs(dg[moving])).min()))
            return s

        return limit

    def _rigid_gap_limiter(self) -> Callable[[np.ndarray, np.ndarray], float]:
        """Pre-check for a rigid body under force control: one Newton step may change
        the smallest gap by at most half of itself (the film conductance ~ g^3
        makes a full step from a poor guess overshoot by decades)."""
        _, xn = self.surface_values(self.counter.gap(self.X, 0.0))
        lowest = float(xn.min())
        comm = self.mesh.comm
        pos_index = sum(
            b[1].function_space.dofmap.index_map.size_local
            * b[1].function_space.dofmap.index_map_bs
            for b in self.blocks[:-1]
        )

        def limit(x: np.ndarray, dx: np.ndarray) -> float:
            mine = (float(x[pos_index]), float(dx[pos_index])) if self._owns_position else None
            pos, dpos = comm.bcast(mine, root=self._pos_root)
            gap0 = lowest - pos
            # the gap changes by dpos: at most half of itself per step, either way
            if gap0 > 0 and abs(dpos) > 0.5 * gap0:
                return 0.5 * gap0 / abs(dpos)
            return 1.0

        return limit

    @property
    def dofs(self) -> int:
        """Global number of unknowns (film dofs off the lubricated surface excluded)."""
        return sum(self.dof_counts().values())

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

    def _state(self) -> list[np.ndarray]:
        """Copies of the arrays of all unknowns."""
        return [b[1].x.array.copy() for b in self.blocks]

    def _restore(self, state: Sequence[np.ndarray]) -> None:
        for b, arr in zip(self.blocks, state, strict=True):
            b[1].x.array[:] = arr

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
    ) -> list[StepRecord]:
        """Adaptive stepping of the load fraction from ``t_start`` to ``t_end``.

        Raises:
            SolverError: the increment fell below ``min_increment``; ``partial``
                holds the last converged fraction (the state is left there).
        """
        st = stepping or SteppingOptions()
        log = get_logger()
        t = t_start
        dt = min(st.first, t_end - t_start)
        last: list[tuple[float, list[np.ndarray]]] = [(t, self._state())]
        for _ in range(st.max_steps):
            if t >= t_end - 1e-14:
                return self.steps
            t_try = min(t + dt, t_end)
            saved = self._state()
            if st.predictor and len(last) == 2:  # secant predictor
                (ta, sa), (tb, sb) = last
                r = (t_try - tb) / (tb - ta)
                self._restore([b + r * (b - a) for a, b in zip(sa, sb, strict=True)])
            t0 = time.perf_counter()
            try:
                its = self.solve_at(t_try)
            except SolverError as e:
                self._restore(saved)
                dt *= st.cut
                log.info(
                    "%s: step to %.4g failed (%s); increment cut to %.3g",
                    self.name,
                    t_try,
                    e.what,
                    dt,
                )
                if dt < st.min_increment:
                    self.set_fraction(t)
                    raise SolverError(
                        f"load stepping stalled: increment {dt:.2e} below {st.min_increment:.1e}",
                        where=f"{self.name}, from load fraction {t:.6g}",
                        history=e.history,
                        partial={"fraction": t, "steps": list(self.steps)},
                    ) from e
                continue
            self.steps.append(StepRecord(t_try, its, time.perf_counter() - t0))
            t = t_try
            last = [last[-1], (t, self._state())]
            if on_step is not None:
                on_step(t)
            if its <= st.easy:
                dt *= st.grow
        raise SolverError(f"more than {st.max_steps} load steps", where=self.name)

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
        if isinstance(self.material, LinearElastic):
            energy = self.material.small_strain_energy(self.kin.eps(self.u), self.p_mix)
        else:
            energy = self.material.strain_energy(self.F, self.p_mix)
        R = ufl.derivative(energy * self.weight * self.dx_energy, self.w, vw)
        R += -tractions.pressure_work(pressure_guess, self.F, self.N3, v3, self.weight, self.ds_c)
        pre = NonlinearSolver(
            R, self.w, self._dirichlet_bcs, name=f"{self.name} warm start",
            options=dataclasses.replace(self.solver.options, snes_type="newtonls"),
            # the displacement-only (penalty) form of nearly incompressible rubber has a
            # huge volumetric stiffness and needs damped steps from the undeformed state;
            # the mixed form converges in 3-4 full steps at any mesh size
            step_limiter=None if self.material.mixed else self._max_step_limiter,
        )  # fmt: skip
        hist = pre.solve()
        pre.destroy()
        xn = self.counter.gap(self.x, 0.0)  # coordinate of the current surface along the normal
        _, vals = self.surface_values(xn)
        lowest = float(vals.min())
        if self.control == "force":
            self.position.x.array[:] = lowest - peak_separation
        return hist.newton_iterations

    # ---------------------------------------------------------------- results
    def contact_force(self) -> float:
        """Total contact force on the body along the counter normal [N or N/m]."""
        return self.mesh.comm.allreduce(
            dolfinx.fem.assemble_scalar(self._force_compiled), op=MPI.SUM
        )

    def integrate(self, expr: Any, measure: Any) -> float:
        """Global integral of a UFL expression."""
        return self.mesh.comm.allreduce(
            dolfinx.fem.assemble_scalar(dolfinx.fem.form(expr * measure)), op=MPI.SUM
        )

    def counter_position(self) -> float:
        """Current counter-surface position [m]."""
        if self.control == "force":
            return float(self.mesh.comm.allreduce(
                float(self.position.x.array[0]) if self.position.x.array.size else -np.inf, op=MPI.MAX))  # fmt: skip
        return float(self.position.value)

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
            S = dolfinx.fem.functionspace(self.mesh, ("Lagrange", deg))
            f = dolfinx.fem.Function(S)
            f.interpolate(dolfinx.fem.Expression(expr, _interp_points(S)))
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
    S = dolfinx.fem.functionspace(prob.mesh, ("Lagrange", 1))
    q = ufl.TestFunction(S)
    ds = prob.ds(tag, metadata=prob.ds_c.metadata())
    b = dolfinx.fem.assemble_vector(dolfinx.fem.form(expr * q * ds))
    m = dolfinx.fem.assemble_vector(dolfinx.fem.form(q * ds))
    b.scatter_reverse(dolfinx.la.InsertMode.add)
    m.scatter_reverse(dolfinx.la.InsertMode.add)
    f = dolfinx.fem.Function(S)
    on = m.array > 0
    f.x.array[on] = b.array[on] / m.array[on]
    f.x.scatter_forward()
    return f


def _interp_points(V: Any) -> Any:
    from dolfinx_seal.compat import interpolation_points

    return interpolation_points(V.element)


__all__ = ["Dirichlet", "SolidContactProblem", "StepRecord", "SteppingOptions"]


def _unit(gdim: int, axis: int) -> Any:
    """Unit 3-vector along coordinate ``axis``."""
    check_int_range("sliding_axis", axis, 0, gdim - 1)
    return ufl.as_vector([1.0 if i == axis else 0.0 for i in range(3)])
