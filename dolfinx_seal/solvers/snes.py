"""The one PETSc SNES wrapper of dolfinx_seal.

:class:`NonlinearSolver` owns a SNES for a residual given as UFL form(s):

* single field (one :class:`dolfinx.fem.Function`, possibly in a mixed space) or
  blocked (lists of forms and functions, e.g. a field plus a real-space
  unknown), with Dirichlet conditions;
* optional lower/upper bounds per dof, which turn the problem into a
  variational inequality (VI) solved by ``vinewtonrsls``/``vinewtonssls``:
  find ``l <= x <= u`` with ``F_i >= 0`` where ``x_i = l_i``, ``F_i <= 0`` where
  ``x_i = u_i`` and ``F_i = 0`` in between;
* a unique options prefix per instance; PETSc command-line options given with
  that prefix override the defaults set here;
* rank-0 monitors and an explicit check of the converged reason: a failed solve
  raises :class:`~dolfinx_seal.errors.SolverError` carrying the iteration history;
* its own complementarity check after a VI solve, since a VI solver may report
  convergence on a zero step;
* an optional acceptance check of a converged state (``acceptance``: the owner's
  reason why the state is not a solution, e.g. outside a constitutive law's
  domain), raised as a failed solve;
* an assembly strategy (:mod:`dolfinx_seal.solvers.assembly`): plain DOLFINx
  assembly by default, or dolfinx_mpc assembly with multi-point constraints
  (periodicity, also with rotation of a vector field); the constraints' slave
  dofs are never bounded and their Newton update is zeroed;
* the reduced-space VI's linear solve on the full matrix's fixed pattern
  (``vi_linear_solve = "full_pattern"``): the inactive rows' system solved by
  one LU of the full Jacobian with identity rows at the active bounds, so MUMPS
  analyses the pattern once per solver instead of every Newton step;
* a kept factorisation as GMRES's preconditioner (``factor_reuse_its``), made
  afresh only after a slow linear solve, across Newton steps and solves: with
  ``newtonls``, with the fixed-pattern semismooth VI, and with the full
  pattern's LU of the reduced-space VI (the ball's default, issue 18);
* an opt-in fixed-pattern VI solver (``snes_type = "semismooth"``: identity rows
  at active bounds written into the matrix's own pattern);
* a penalty warm start for VIs (:meth:`NonlinearSolver.solve_penalty`): the
  bounds are first enforced by a dof-wise penalty ``kappa_i min(x_i - l_i, 0)``
  with ``kappa_i`` a multiple of the Jacobian diagonal, stepped up by decades
  with a semi-smooth Newton, after which the exact VI needs a few steps.

Defaults (docs/design.md, solver strategy): the ``basic`` line search (``bt`` fails
spuriously with the VI solvers because the active set changes as the step
shrinks) with an optional pre-check that limits the step; a direct LU solve
with MUMPS.
"""

from __future__ import annotations

import contextlib
import dataclasses
import itertools
import time
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import dolfinx
import numpy as np
import ufl
from petsc4py import PETSc

from dolfinx_seal import compat
from dolfinx_seal.errors import ParameterError, SolveHistory, SolverError
from dolfinx_seal.mpi import get_logger, print0
from dolfinx_seal.params import check_choice, check_int_range, check_positive
from dolfinx_seal.solvers.assembly import Assembly, PlainAssembly

#: ``-v`` shows one line per Newton step (debug records, rank 0)
_NEWTON_LOG = get_logger("dolfinx_seal.newton")

_counter = itertools.count()

_VI_TYPES = ("vinewtonrsls", "vinewtonssls")
#: the bounded types: PETSc's VI solvers and the wrapper's own fixed-pattern one
_BOUNDED_TYPES = (*_VI_TYPES, "semismooth")

#: a Newton step "stalls" when it lowers the residual norm by less than this fraction
#: (see :meth:`NonlinearSolver.newton_limit`)
STALL_REDUCTION = 0.01
#: the SNES reason a stalled solve ends with (PETSc has none of its own; the history
#: names it DIVERGED_STALLED)
_DIVERGED_STALLED = int(PETSc.SNES.ConvergedReason.DIVERGED_LOCAL_MIN)

#: how ``vinewtonrsls`` solves its reduced system (``SNESOptions.vi_linear_solve``)
_VI_LINEAR_SOLVES = ("submatrix", "full_pattern")

#: PETSc options (without prefix) given to every solver created inside
#: :func:`extra_petsc_options`; a solver's own ``petsc_options`` win over them
_SESSION_OPTIONS: list[dict[str, Any]] = []


@contextlib.contextmanager
def extra_petsc_options(options: Mapping[str, Any]) -> Iterator[None]:
    """Give PETSc ``options`` (keys without prefix, e.g. ``{"mat_mumps_icntl_7": 5}``
    for the METIS ordering) to every :class:`NonlinearSolver` created inside the block.

    The seam for solver studies (``bench/solver_levers.py``): the scenes build their
    solvers deep inside, each with its own unique prefix, so a global
    ``-mat_mumps_...`` option would not reach them.  The command line with a
    solver's prefix still wins; the solver's own ``petsc_options`` win over these.
    Nested blocks merge, the inner one winning.
    """
    _SESSION_OPTIONS.append(dict(options))
    try:
        yield
    finally:
        _SESSION_OPTIONS.pop()


#: :class:`SNESOptions` fields given to every solver created inside :func:`solver_session`
_SESSION_FIELDS: list[dict[str, Any]] = []


@contextlib.contextmanager
def solver_session(**fields: Any) -> Iterator[None]:
    """Override :class:`SNESOptions` fields of every :class:`NonlinearSolver` created
    inside the block, e.g. ``solver_session(snes_type="semismooth",
    factor_reuse_its=5)``: the fixed-pattern VI solver with a kept factorisation in
    every solver of a scene.

    The seam for solver studies (``bench/solver_levers.py``), the twin of
    :func:`extra_petsc_options` for the wrapper's own options.  A bounded solver
    that later switches to a reduced-space VI type (a fallback, the
    Reynolds-condition start) drops ``factor_reuse_its`` there (its matrix changes
    size every step).  Nested blocks merge, the inner one winning.
    """
    SNESOptions(**fields)  # the names and values checked before any solver is built
    _SESSION_FIELDS.append(dict(fields))
    try:
        yield
    finally:
        _SESSION_FIELDS.pop()


def with_snes_type(options: SNESOptions, snes_type: str) -> SNESOptions:
    """``options`` with another SNES type; a reduced-space or rescaling VI type
    (``vinewtonrsls``, ``vinewtonssls``) drops ``factor_reuse_its``, which needs a
    fixed matrix pattern."""
    return _replace(options, snes_type=snes_type)


@dataclass
class SNESOptions:
    """Options of :class:`NonlinearSolver` (the single source of their defaults).

    Attributes:
        snes_type: ``newtonls`` for equations; for problems with bounds the VI
            types ``vinewtonrsls`` (reduced space, default) or ``vinewtonssls``, or
            ``semismooth``: a semismooth Newton (PETSc ``newtonls``) on the natural
            residual ``x - clip(x - F, l, u)``, whose rows at an active bound become
            identity rows written into the matrix's own pattern, so the pattern never
            changes (the factorisation's analysis is done once, and the
            factorisation can be kept, see ``factor_reuse_its``).
        line_search: SNES line search (``basic`` is the safe choice with VIs).
        rtol: Relative residual tolerance, relative both to the first residual of a
            solve and to the forcing scale ``|F(0)|`` (see
            :meth:`NonlinearSolver.residual_scale`), so warm starts stop at the
            same accuracy as cold ones.
        atol: Absolute residual tolerance floor (in the scaled units of the residual).
        stol: Step tolerance ``|dx| < stol |x|``: a step at round-off level ends the
            solve (ill-conditioned problems stall there above ``rtol``).  For a VI a
            zero step can hide a wrong active set, which the complementarity check
            after the solve catches.
        max_it: Maximum Newton steps.
        ksp_type: Krylov solver (``preonly`` for a direct solve).
        pc_type: Preconditioner (``lu`` for a direct solve).
        factor_solver: Direct solver package (``mumps``, ``superlu_dist``, ``petsc``).
        floor_rtol: Round-off allowance: a solve that stagnates (step below ``stol``)
            is accepted only if its residual is below ``floor_rtol |F(0)|`` or its
            Jacobi-scaled residual (:meth:`NonlinearSolver.scaled_residual`, in
            solution units) is below ``floor_rtol max|x|``; a VI solution only if
            its natural residual ``|x - P(x - F)|`` passes the same test.
        dtol: Divergence tolerance: stop when ``|F| > dtol |F_first|`` (stiff contact
            laws may raise the residual by many decades on the way to convergence).
        factor_reuse_its: 0 (default): a new factorisation every Newton step
            (``ksp_type``/``pc_type`` as given).  ``k > 0``: the factorisation is
            kept as the right preconditioner of GMRES across Newton steps and
            solves (continuation points), and rebuilt at the next Newton step
            after a linear solve that took more than ``k`` iterations or failed.
            Needs a fixed matrix pattern: ``newtonls``, ``semismooth``, or
            ``vinewtonrsls`` with ``vi_linear_solve = "full_pattern"`` (GMRES on
            the reduced system, the kept LU of the full pattern, possibly of
            another active set, as its preconditioner).
        linear_rtol: GMRES relative tolerance when ``factor_reuse_its > 0``.
        vi_linear_solve: How ``vinewtonrsls`` solves its reduced system
            ``J_II dx_I = -F_I`` (I: the rows off an active bound) with a direct
            ``pc_type``: ``submatrix`` (PETSc's own: a new submatrix every Newton
            step, so the factorisation's analysis is redone every step) or
            ``full_pattern``: the full Jacobian with the active rows replaced by
            identity rows in its own sparsity pattern, ``[[J_II, J_IA], [0, I]]
            [dx_I; dx_A] = [-F_I; 0]``, whose ``dx_I`` is the same step; the pattern
            never changes, so the analysis is done once per solver and only the
            numeric factorisation is repeated.
        project_step: ``semismooth`` only: each Newton step is projected onto the
            bounds before the line search (``x - dx`` clipped to ``[lower,
            upper]``), so the iterates stay feasible.  Without it a node just off
            its bound (a film fraction of 0.99999 in a coupled JFO film) can be
            stepped far past it, where the natural residual ``x - u`` counts the
            overshoot: the active set then cycles (docs/scenes/lip-sector.md).
        monitor: Print the residual at every Newton step (rank 0).
        error_on_failure: Raise :class:`SolverError` when SNES does not converge.
    """

    snes_type: str = "newtonls"
    line_search: str = "basic"
    rtol: float = 1e-9
    atol: float = 1e-12
    stol: float = 1e-12
    max_it: int = 50
    ksp_type: str = "preonly"
    pc_type: str = "lu"
    factor_solver: str = "mumps"
    floor_rtol: float = 1e-6
    dtol: float = 1e4
    factor_reuse_its: int = 0
    linear_rtol: float = 1e-9
    vi_linear_solve: str = "full_pattern"
    project_step: bool = False
    monitor: bool = False
    error_on_failure: bool = True

    def __post_init__(self) -> None:
        check_choice("snes_type", self.snes_type, ("newtonls", *_BOUNDED_TYPES))
        check_int_range("factor_reuse_its", self.factor_reuse_its, 0)
        if self.factor_reuse_its and not _keeps_pattern(self.snes_type, self.vi_linear_solve):
            raise ParameterError(
                f"factor_reuse_its = {self.factor_reuse_its} needs a fixed matrix pattern: "
                "snes_type 'newtonls', 'semismooth', or 'vinewtonrsls' with vi_linear_solve "
                f"'full_pattern'; not '{self.snes_type}' with '{self.vi_linear_solve}' (its "
                "reduced or rescaled matrix changes every step)"
            )
        check_positive("linear_rtol", self.linear_rtol)
        check_choice("vi_linear_solve", self.vi_linear_solve, _VI_LINEAR_SOLVES)
        check_choice("line_search", self.line_search, ("basic", "bt", "l2", "cp", "nleqerr"))
        check_positive("rtol", self.rtol)
        check_positive("atol", self.atol)
        check_int_range("max_it", self.max_it, 1)
        check_positive("floor_rtol", self.floor_rtol)
        check_positive("dtol", self.dtol)


#: :class:`SNESOptions` fields that a solve reads from the solver's options each time
#: (its convergence test); the others are read when the SNES is built
SOLVE_TIME_FIELDS = ("rtol", "atol", "stol", "floor_rtol", "monitor", "error_on_failure")


def bounds_function(V: Any, value: float, sub: int | None = None) -> dolfinx.fem.Function:
    """A bound for :class:`NonlinearSolver`: ``value`` on the dofs of sub-space ``sub``.

    All dofs get ``value`` when ``sub`` is None.  Otherwise the other dofs get
    ``nan``, meaning "unbounded", which the solver turns into ``-inf`` (lower
    bound) or ``+inf`` (upper bound).  Example: ``bounds_function(W, 0.0, sub=1)``
    for ``p >= 0`` on the second field of a mixed space.
    """
    f = dolfinx.fem.Function(V)
    if sub is None:
        f.x.array[:] = value
    else:
        f.x.array[:] = np.nan
        _, dofs = V.sub(sub).collapse()
        f.x.array[np.asarray(dofs)] = value
    return f


class NonlinearSolver:
    """A PETSc SNES for ``F(u; v) = 0`` (or the VI with bounds) from UFL forms.

    Args:
        F: Residual form, or a list of residual forms (blocked problem).
        u: Unknown function, or a list of functions (one per block).
        bcs: Dirichlet conditions.
        J: Jacobian form(s); default ``ufl.derivative`` of ``F`` (the whole residual).
        lower: Lower bound(s): a Function (``nan`` = unbounded), a float, or None;
            for a blocked problem a list with one entry per block.
        upper: Upper bound(s), as ``lower``.
        options: :class:`SNESOptions`.
        prefix: PETSc options prefix (default unique ``dxs<N>_``); command-line
            options with this prefix override the defaults.
        name: Name used in messages and errors.
        step_limiter: Optional ``f(x, dx) -> s`` with ``0 < s <= 1`` on owned arrays:
            the Newton step is scaled by the global minimum of ``s`` (pre-check).
        assembly: Assembly strategy (:class:`~dolfinx_seal.solvers.assembly.Assembly`);
            default :class:`~dolfinx_seal.solvers.assembly.PlainAssembly` (DOLFINx).
            With :class:`~dolfinx_seal.solvers.assembly.MPCAssembly` the unknowns
            live on the constraints' spaces and bounds apply to the masters and
            free dofs (slaves are unbounded: they follow their masters).
        petsc_options: Extra PETSc options (without prefix) for this instance.
        form_compiler_options, jit_options: Passed to :func:`dolfinx.fem.form`.
    """

    def __init__(
        self,
        F: ufl.Form | Sequence[ufl.Form],
        u: dolfinx.fem.Function | Sequence[dolfinx.fem.Function],
        bcs: Sequence[dolfinx.fem.DirichletBC] = (),
        J: Any = None,
        lower: Any = None,
        upper: Any = None,
        options: SNESOptions | None = None,
        prefix: str | None = None,
        name: str = "problem",
        step_limiter: Callable[[np.ndarray, np.ndarray], float] | None = None,
        petsc_options: dict[str, Any] | None = None,
        form_compiler_options: dict | None = None,
        jit_options: dict | None = None,
        assembly: Assembly | None = None,
    ) -> None:
        self.blocked = isinstance(F, list | tuple)
        self.name = name
        self.options = _with_session(options or SNESOptions())
        self.prefix = prefix or f"dxs{next(_counter)}_"
        self.bcs = list(bcs)
        self.step_limiter = step_limiter
        self.history = SolveHistory()
        self.total_newton_iterations = 0
        # called after a converged solve: a reason why the state is not a solution
        # of the problem (e.g. outside a constitutive law's domain), or None
        self.acceptance: Callable[[], str | None] | None = None
        self._stall_steps = 0  # see newton_limit
        self._stalled = 0  # consecutive Newton steps of the solve under way that stalled
        self._stall_hit = False  # the solve under way ended stalled
        self._fnorm_last = 0.0
        self._penalty = 0.0
        fopts = {"form_compiler_options": form_compiler_options, "jit_options": jit_options}
        asm = assembly if assembly is not None else PlainAssembly()

        if self.blocked:
            if not isinstance(u, list | tuple) or len(u) != len(F):
                raise ParameterError("a blocked residual needs one unknown function per block")
            self.u = list(u)
            if J is None:
                J = [
                    [
                        ufl.derivative(Fi, uj, ufl.TrialFunction(asm.trial_space(Fj, uj)))
                        for Fj, uj in zip(F, self.u, strict=True)
                    ]
                    for Fi in F
                ]
                J = [[None if _is_zero(a) else a for a in row] for row in J]
            for i, Fi in enumerate(F):
                compat.check_quadrature_rules(Fi, f"{name}: residual block {i}")
                for j, a in enumerate(J[i]):
                    if a is not None:
                        compat.check_quadrature_rules(a, f"{name}: Jacobian block ({i}, {j})")
            self._L = [dolfinx.fem.form(Fi, **fopts) for Fi in F]
            self._a = [
                [None if a is None else dolfinx.fem.form(a, **fopts) for a in row] for row in J
            ]
        else:
            self.u = u
            if J is None:
                J = ufl.derivative(F, u, ufl.TrialFunction(asm.trial_space(F, u)))
            compat.check_quadrature_rules(F, f"{name}: residual")
            compat.check_quadrature_rules(J, f"{name}: Jacobian")
            self._L = dolfinx.fem.form(F, **fopts)
            self._a = dolfinx.fem.form(J, **fopts)
        self.assembly = asm
        self.assembly.setup(self._L, self._a, self.u, self.bcs)
        self.comm = self.assembly.comm
        self.b = self.assembly.create_vector()
        self.A = self.assembly.create_matrix()
        self.x = self.b.duplicate()
        self._constrained = self.assembly.constrained_dofs()
        self._homogenize = self.comm.allreduce(int(self._constrained.size)) > 0

        self.has_bounds = lower is not None or upper is not None
        self.xl = self.xu = None
        if self.has_bounds:
            self.xl = self._bound_vector(lower, PETSc.NINFINITY)
            self.xu = self._bound_vector(upper, PETSc.INFINITY)
            if self.options.snes_type not in _BOUNDED_TYPES:
                self.options = _replace(self.options, snes_type="vinewtonrsls")
        self._ssn = self.has_bounds and self.options.snes_type == "semismooth"
        self._ssn_on = False  # the natural-residual rows, only inside the main SNES solve
        self._main_solve = False  # inside SNESSolve of the main SNES
        self._ssn_point: np.ndarray | None = None  # where the active rows were found
        self._ssn_rows = np.zeros(0, dtype=np.int32)  # owned rows at an active bound
        #: the largest :meth:`factor_memory_mb` at the end of a solve [MB] (largest
        #: rank, all ranks; (0, 0) before the first): what the solver needed at most,
        #: where :meth:`factor_memory_mb` is what it holds now
        self.peak_factor_memory_mb: tuple[float, float] = (0.0, 0.0)
        self.factor_rebuilds = 0  # factorisations kept (factor_reuse_its > 0): rebuilds
        if self._ssn:  # identity rows written into the assembled pattern
            self.A.setOption(PETSc.Mat.Option.KEEP_NONZERO_PATTERN, True)
        self._diag = self.b.duplicate()
        # an algebraic term ``M x`` added to the residual (``M`` to the Jacobian), in
        # the solver's layout, its pattern within the Jacobian's (e.g. the film's
        # discrete upwinding, :mod:`dolfinx_seal.film.upwinding`); destroyed with
        # the solver
        self.linear_term: PETSc.Mat | None = None
        self._extra_options = {k: v for d in _SESSION_OPTIONS for k, v in d.items()}
        self._extra_options.update(petsc_options or {})
        # global PETSc options entries this solver set: key -> the SNES's prefix
        self._own_options: dict[str, str] = {}
        self._full_lu: _FullPatternLU | None = None  # vi_linear_solve = "full_pattern"
        self._lu_in_pc = False  # the main SNES's preconditioner is self._full_lu
        self._snes = self._make_snes(self.options, self.prefix, bounded=self.has_bounds)
        self._snes_penalty: PETSc.SNES | None = None
        self._tangent_ksp: PETSc.KSP | None = None
        # the unknowns of the last converged solve, while the factorisation is its own
        self._converged_x: PETSc.Vec | None = None
        self._factor_is_converged = False
        self._converged_snes: PETSc.SNES | None = None
        self._converged_fx: PETSc.Vec | None = None  # _converged_x as the functions hold it
        self._residual_scale: float | None = None

    # ---------------------------------------------------------------- set-up
    def _bound_vector(self, spec: Any, fill: float) -> PETSc.Vec:
        v = self.b.duplicate()
        v.set(fill)
        if spec is None:
            return v
        if self.blocked:
            specs = list(spec) if isinstance(spec, list | tuple) else [spec] * len(self.u)
            funcs = []
            for s, ui in zip(specs, self.u, strict=True):
                f = dolfinx.fem.Function(ui.function_space)
                f.x.array[:] = fill if s is None else (s if np.isscalar(s) else 0.0)
                if s is not None and not np.isscalar(s):
                    f.x.array[:] = s.x.array
                funcs.append(f)
            for f in funcs:
                f.x.array[np.isnan(f.x.array)] = fill
            compat.functions_to_block(funcs, v)
        else:
            arr = v.getArray(readonly=False)
            n = arr.shape[0]
            if np.isscalar(spec):
                arr[:] = spec
            else:
                vals = spec.x.array[:n].copy()
                vals[np.isnan(vals)] = fill
                arr[:] = vals
            del arr
        if self._constrained.size:  # slaves follow their masters: never bounded
            arr = v.getArray(readonly=False)
            arr[self._constrained] = fill
            del arr
        return v

    def _make_snes(self, o: SNESOptions, prefix: str, bounded: bool) -> PETSc.SNES:
        snes = PETSc.SNES().create(self.comm)
        snes.setOptionsPrefix(prefix)
        opts = PETSc.Options()
        defaults = {
            "snes_type": "newtonls" if o.snes_type == "semismooth" else o.snes_type,
            "snes_linesearch_type": o.line_search,
            "snes_rtol": o.rtol,
            "snes_atol": o.atol,
            "snes_stol": o.stol,
            "snes_max_it": o.max_it,
            "ksp_type": o.ksp_type,
            "pc_type": o.pc_type,
        }
        if o.pc_type in ("lu", "cholesky"):
            defaults["pc_factor_mat_solver_type"] = o.factor_solver
        full_pattern = (
            bounded
            and o.snes_type == "vinewtonrsls"
            and o.vi_linear_solve == "full_pattern"
            and o.ksp_type == "preonly"
            and o.pc_type == "lu"
        )
        if o.factor_reuse_its:  # GMRES, preconditioned by a kept factorisation
            defaults.update({
                "ksp_type": "gmres", "ksp_pc_side": "right", "ksp_rtol": o.linear_rtol,
                "ksp_gmres_restart": 2 * o.factor_reuse_its + 10,
                "ksp_max_it": 2 * o.factor_reuse_its + 10,
                # a failed linear solve still gives a step (the line search judges it);
                # the factorisation is rebuilt at the next Newton step
                "snes_max_linear_solve_fail": o.max_it + 1,
            })  # fmt: skip
            if not full_pattern:
                # built once (-2: at the first Jacobian, then never), kept across steps
                # and solves; _jacobian resets it after a slow linear solve.  (The full
                # pattern's LU decides itself: PETSc resets a reduced-space VI's
                # preconditioner every step, so no SNES lag applies there.)
                defaults.update({"snes_lag_preconditioner": -2,
                                 "snes_lag_preconditioner_persists": True})  # fmt: skip
        if full_pattern:  # the reduced system through the full pattern's LU
            defaults["pc_type"] = "python"  # its inner LU is given the factor package
            defaults.pop("pc_factor_mat_solver_type", None)
        defaults.update(self._extra_options)
        # the entries an earlier SNES of this prefix set (e.g. before set_snes_type)
        # are this solver's, not the command line's: they give way to the new defaults
        for key in [key for key, pre in self._own_options.items() if pre == prefix]:
            opts.delValue(key)
            del self._own_options[key]
        for k, v in defaults.items():
            if not opts.hasName(prefix + k):  # the command line wins
                opts[prefix + k] = v
                self._own_options[prefix + k] = prefix  # removed again by destroy()
        snes.setFunction(self._residual, self.b)
        snes.setJacobian(self._jacobian, self.A)
        if bounded and o.snes_type in _VI_TYPES:
            snes.setVariableBounds(self.xl, self.xu)
        snes.setMonitor(self._monitor)
        projected = bounded and o.snes_type == "semismooth" and o.project_step
        if self.step_limiter is not None or self._homogenize or projected:
            snes.setLineSearchPreCheck(self._precheck)
        snes.setFromOptions()
        snes.getKSP().setFromOptions()
        pc = snes.getKSP().getPC()
        # the kept factorisation is the full pattern's (not the SNES's lag)
        self._lu_in_pc = full_pattern and pc.getType() == "python"
        if self._lu_in_pc:  # not overridden on the command line
            if self._full_lu is None:  # its work objects are freed with the old SNES's PC
                self._full_lu = _FullPatternLU(self, prefix)
            self._full_lu.reuse_its = o.factor_reuse_its
            pc.setPythonContext(self._full_lu)
        if not opts.hasName(prefix + "snes_divergence_tolerance"):
            snes.setDivergenceTolerance(o.dtol)
        # after setFromOptions: setting the VI type installs PETSc's own test
        snes.setConvergenceTest(self._converged)
        return snes

    # ------------------------------------------------------------- callbacks
    def _to_functions(self, x: PETSc.Vec) -> None:
        """``x`` into the unknowns (with an MPC: slaves recomputed from the masters)."""
        self.assembly.to_functions(x)

    def _from_functions(self, x: PETSc.Vec) -> None:
        self.assembly.from_functions(x)

    def _residual(self, snes: PETSc.SNES, x: PETSc.Vec, b: PETSc.Vec) -> None:
        self._to_functions(x)
        self.assembly.residual(x, b)
        if self.linear_term is not None:
            self.linear_term.multAdd(x, b, b)
        if self._penalty > 0.0:
            self._add_penalty_residual(x, b)
        elif self._ssn_on:
            self._natural_rows(x, b)

    def _natural_rows(self, x: PETSc.Vec, b: PETSc.Vec) -> None:
        """Semismooth residual: ``F`` where ``l < x - F < u``, ``x - l`` (``x - u``)
        where ``x - F`` is below (above) the bound; remembers those active rows."""
        xa = x.getArray(readonly=True)
        fa = b.getArray(readonly=False)
        lo = self.xl.getArray(readonly=True)
        hi = self.xu.getArray(readonly=True)
        trial = xa - fa
        below = trial <= lo
        above = trial >= hi
        fa[below] = xa[below] - lo[below]
        fa[above] = xa[above] - hi[above]
        del fa
        self._ssn_rows = np.flatnonzero(below | above).astype(np.int32)
        self._ssn_point = xa.copy()

    def _jacobian(self, snes: PETSc.SNES, x: PETSc.Vec, A: PETSc.Mat, P: PETSc.Mat) -> None:
        self._to_functions(x)
        self.assembly.jacobian(A)
        if self.linear_term is not None:
            A.axpy(1.0, self.linear_term, structure=PETSc.Mat.Structure.SUBSET_NONZERO_PATTERN)
        if self._penalty > 0.0:
            self._add_penalty_jacobian(x, A)
        elif self._ssn_on:
            if self._ssn_point is None or not np.array_equal(
                self._ssn_point, x.getArray(readonly=True)
            ):  # the active rows of this point
                work = self.b.duplicate()
                self._residual(snes, x, work)
                work.destroy()
            start = A.getOwnershipRange()[0]
            A.zeroRows(self._ssn_rows + start, diag=1.0)  # collective; keeps the pattern
        if self.options.factor_reuse_its and self._main_solve and not self._lu_in_pc:
            self._maybe_rebuild_factorisation(snes)

    def _maybe_rebuild_factorisation(self, snes: PETSc.SNES) -> None:
        """Rebuild the kept factorisation after a slow or failed linear solve."""
        ksp = snes.getKSP()
        reason = int(ksp.getConvergedReason())  # 0 before the first linear solve
        slow = ksp.getIterationNumber() > self.options.factor_reuse_its
        rebuild = reason != 0 and (slow or reason < 0)
        if rebuild:  # the SNES lags the preconditioner forever (-1): start it afresh
            ksp.getPC().reset()
            self.factor_rebuilds += 1

    def _monitor(self, snes: PETSc.SNES, it: int, fnorm: float) -> None:
        self.history.residual_norms.append(float(fnorm))
        if it > 0:
            self.history.linear_iterations.append(snes.getKSP().getIterationNumber())
        if self.options.monitor:
            print0(f"  {self.name} [{self.prefix}] Newton {it:3d}  |F| = {fnorm:.6e}")
        _NEWTON_LOG.debug("%s Newton %d: |F| = %.3e", self.name, it, fnorm)  # -v: one line each

    def _converged(self, snes: PETSc.SNES, it: int, norms: tuple[float, float, float]) -> int:
        """Convergence test with mesh-independent step criterion.

        Residual: ``|F| < atol_eff`` or ``|F| < rtol |F_first|`` (2-norms).  Step:
        ``max|dx| <= stol max|x|`` (infinity norms, which do not grow with the
        number of dofs, unlike the 2-norm round-off floor of the residual), and
        only if ``|F|`` is within the round-off allowance ``floor_rtol |F(0)|``.
        """
        _xnorm, _ynorm, fnorm = norms
        R = PETSc.SNES.ConvergedReason
        # a VI solver's fnorm is the norm over the free set, 0 for an all-NaN residual:
        # check the residual itself too
        if not (np.isfinite(fnorm) and np.isfinite(snes.getFunction()[0].norm())):
            return R.DIVERGED_FNORM_NAN
        if it == 0:
            self._fnorm0 = fnorm
            self._stalled = 0
            self._fnorm_last = fnorm
            return R.CONVERGED_FNORM_ABS if fnorm <= self._atol_eff else R.ITERATING
        if fnorm <= self._atol_eff:
            return R.CONVERGED_FNORM_ABS
        if fnorm <= self.options.rtol * self._fnorm0:
            return R.CONVERGED_FNORM_RELATIVE
        if self.options.stol > 0:
            dx = snes.getSolutionUpdate().norm(PETSc.NormType.NORM_INFINITY)
            x = snes.getSolution().norm(PETSc.NormType.NORM_INFINITY)
            if dx <= self.options.stol * max(x, 1e-300) and (
                fnorm <= self._floor
                or self.scaled_residual(snes.getFunction()[0])
                <= self.options.floor_rtol * max(x, 1e-300)
            ):
                return R.CONVERGED_SNORM_RELATIVE
        if self._stall_steps:
            slow = fnorm > (1.0 - STALL_REDUCTION) * self._fnorm_last
            self._stalled = self._stalled + 1 if slow else 0
            self._fnorm_last = fnorm
            if self._stalled >= self._stall_steps:
                self._stall_hit = True
                return _DIVERGED_STALLED
        if it >= snes.getTolerances()[3]:
            return R.DIVERGED_MAX_IT
        dtol = snes.getDivergenceTolerance()
        if dtol > 0 and fnorm > dtol * self._fnorm0:
            return R.DIVERGED_DTOL
        return R.ITERATING

    def _precheck(self, x: PETSc.Vec, y: PETSc.Vec) -> bool:
        changed = False
        if self._homogenize and self._constrained.size:
            arr = y.getArray(readonly=False)
            changed = bool(np.any(arr[self._constrained] != 0.0))
            self.assembly.homogenize(arr)  # the slaves follow the masters, not the step
            del arr
        if self._ssn and self.options.project_step:  # x - y onto the bounds
            xa = x.getArray(readonly=True)
            ya = y.getArray(readonly=False)
            trial = xa - ya
            inside = np.clip(
                trial, self.xl.getArray(readonly=True), self.xu.getArray(readonly=True)
            )
            moved = trial != inside
            if np.any(moved):
                ya[moved] = xa[moved] - inside[moved]
                changed = True
            del ya
        if self.step_limiter is not None:
            s = float(self.step_limiter(x.getArray(readonly=True), y.getArray(readonly=True)))
            s = self.comm.allreduce(min(max(s, 1e-12), 1.0), op=_mpi_min())
            if s < 1.0:
                y.scale(s)
                changed = True
        return changed

    # ---------------------------------------------------------------- penalty
    def _active_violation(self, x: PETSc.Vec) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        xa = x.getArray(readonly=True)
        lo = self.xl.getArray(readonly=True)
        hi = self.xu.getArray(readonly=True)
        below = np.minimum(xa - lo, 0.0)
        above = np.maximum(xa - hi, 0.0)
        below[~np.isfinite(below)] = 0.0
        above[~np.isfinite(above)] = 0.0
        return below, above, xa

    def _add_penalty_residual(self, x: PETSc.Vec, b: PETSc.Vec) -> None:
        below, above, _ = self._active_violation(x)
        k = self._kappa
        arr = b.getArray(readonly=False)
        arr += k * (below + above)
        del arr

    def _add_penalty_jacobian(self, x: PETSc.Vec, A: PETSc.Mat) -> None:
        below, above, _ = self._active_violation(x)
        d = self._diag
        d.setArray(self._kappa * ((below < 0) | (above > 0)))
        A.setDiagonal(d, addv=PETSc.InsertMode.ADD_VALUES)
        A.assemble()

    # ------------------------------------------------------------------ solve
    def solve(self, where: str = "") -> SolveHistory:
        """Solve from the current value of the unknown(s); return the history.

        Raises:
            SolverError: SNES diverged, or it reported convergence but the
                complementarity check failed (VI).
        """
        return self._solve(self._snes, where)

    def _type_name(self, snes: PETSc.SNES) -> str:
        """The Newton's name in messages: ``semismooth`` for this project's own (a
        PETSc ``newtonls`` underneath), PETSc's type otherwise."""
        return "semismooth" if self._ssn else snes.getType()

    def _rebuild_after_petsc_error(self, snes: PETSc.SNES) -> None:
        """A PETSc error inside ``SNESSolve`` leaves vectors locked and the SNES in an
        undefined state: replace the work vector and the SNES object."""
        self.x = self.b.duplicate()
        if snes is self._snes:
            self._snes.destroy()
            self._snes = self._make_snes(self.options, self.prefix, bounded=self.has_bounds)
        else:
            self._snes_penalty.destroy()
            pen = _replace(self.options, snes_type="newtonls")
            self._snes_penalty = self._make_snes(pen, self.prefix + "penalty_", bounded=False)
            self._snes_penalty.setDivergenceTolerance(1e300)

    def set_bcs(self, bcs: Sequence[dolfinx.fem.DirichletBC]) -> None:
        """Replace the Dirichlet conditions (on the same spaces; e.g. a film zone cut
        shorter): the solver's list (in place) and its assembly's."""
        self.bcs[:] = list(bcs)
        self.assembly.set_bcs(self.bcs)

    def set_snes_type(self, snes_type: str) -> None:
        """Switch the SNES type (e.g. ``vinewtonrsls`` <-> ``vinewtonssls``) in place."""
        check_choice("snes_type", snes_type, ("newtonls", *_BOUNDED_TYPES))
        self.options = _replace(self.options, snes_type=snes_type)
        # a new SNES: the KSP of a reduced-space VI keeps the reduced operator's size
        PETSc.Options()[self.prefix + "snes_type"] = (
            "newtonls" if snes_type == "semismooth" else snes_type
        )
        self._ssn = self.has_bounds and snes_type == "semismooth"
        if self._ssn:
            self.A.setOption(PETSc.Mat.Option.KEEP_NONZERO_PATTERN, True)
        self._snes.destroy()
        self._snes = self._make_snes(self.options, self.prefix, bounded=self.has_bounds)

    def residual_scale(self) -> float:
        """Norm of the residual at zero unknowns, ``|F(0)|``: the scale of the forcing.

        Tolerances are relative to it (``atol_eff = max(atol, rtol |F(0)|)``), so a
        warm start that is already converged takes zero steps and a nested or
        continued solve stops at the same accuracy as a cold one.
        """
        if self._residual_scale is None:
            self._from_functions(self.x)
            saved = self.x.copy()
            zero = self.x.duplicate()
            zero.set(0.0)
            self._residual(self._snes, zero, self.b)
            scale = self.b.norm()
            self._to_functions(saved)
            self.x.array[:] = saved.array
            saved.destroy()
            zero.destroy()
            self._residual_scale = scale if scale > 0 and np.isfinite(scale) else 1.0
        return self._residual_scale

    def _solve(self, snes: PETSc.SNES, where: str) -> SolveHistory:
        self.history = SolveHistory()
        self._atol_eff = max(self.options.atol, self.options.rtol * self.residual_scale())
        self._floor = max(self._atol_eff, self.options.floor_rtol * self.residual_scale())
        self._fnorm0 = 0.0
        self._stall_hit = False
        self._factor_is_converged = False  # until this solve converges
        self._from_functions(self.x)
        if self.has_bounds and self._penalty == 0.0:
            # project the start onto the bounds: VI solvers require a feasible start
            arr = self.x.getArray(readonly=False)
            np.clip(arr, self.xl.getArray(readonly=True), self.xu.getArray(readonly=True), out=arr)
            del arr
        t0 = time.perf_counter()
        self._main_solve = snes is self._snes
        self._ssn_on = self._ssn and self._penalty == 0.0 and self._main_solve
        self._ssn_point = None
        try:
            snes.solve(None, self.x)
        except PETSc.Error as e:  # e.g. a factorisation failing on a non-finite matrix
            self.wall_time = time.perf_counter() - t0
            what = (
                f"SNES '{snes.getOptionsPrefix()}' ({self._type_name(snes)}): PETSc error {e.ierr} in the "
                f"linear solve after {snes.getIterationNumber()} Newton steps"
            )
            self._rebuild_after_petsc_error(snes)  # destroys ``snes``: read it before
            raise SolverError(what, where=where, history=self.history) from e
        finally:
            self._ssn_on = self._main_solve = False
        self.wall_time = time.perf_counter() - t0
        held = self.factor_memory_mb()
        if held is not None:
            self.peak_factor_memory_mb = tuple(map(max, self.peak_factor_memory_mb, held))
        self._to_functions(self.x)
        reason = snes.getConvergedReason()
        self.history.reason = int(reason)
        self.history.reason_name = _reason_name(reason)
        if self._stall_hit:
            self.history.reason_name = (
                f"DIVERGED_STALLED (the residual fell by less than {STALL_REDUCTION:.0%} "
                f"in each of the last {self._stall_steps} Newton steps)"
            )
        its = snes.getIterationNumber()
        self.total_newton_iterations += its
        where = where or self.name
        if reason <= 0:
            what = (
                f"SNES '{snes.getOptionsPrefix()}' ({self._type_name(snes)}) {self.history.reason_name} "
                f"after {its} Newton steps"
            )
            if reason == PETSc.SNES.ConvergedReason.DIVERGED_LINEAR_SOLVE:
                what += f" ({_linear_failure(snes)})"
                # a failed factorisation leaves the preconditioner failed for later solves
                self._rebuild_after_petsc_error(snes)  # destroys ``snes``: read it before
            if self.options.error_on_failure:
                raise SolverError(what, where=where, history=self.history)
            return self.history
        if self.has_bounds and self._penalty == 0.0:
            self.history.complementarity = self.complementarity()
            tol = self._floor
            xinf = self.x.norm(PETSc.NormType.NORM_INFINITY)
            ok = self.history.complementarity <= tol
            if not ok:  # the round-off allowance, with the diagonal at the solution
                self._jacobian(snes, self.x, self.A, self.A)
                F = self.residual()
                ok = self.scaled_residual(F) <= self.options.floor_rtol * max(xinf, 1e-300)
                F.destroy()  # a parallel Vec is not freed by Python alone (bench/soak.py)
            if not np.isfinite(self.history.complementarity) or not ok:
                raise SolverError(
                    f"SNES '{self.prefix}' reported {self.history.reason_name} but the "
                    f"complementarity residual is {self.history.complementarity:.3e} > {tol:.3e}",
                    where=where,
                    history=self.history,
                )
        why = self.acceptance() if self.acceptance is not None else None
        if why:
            self.history.reason_name = "CONVERGED_TO_INADMISSIBLE_STATE"
            raise SolverError(
                f"SNES '{self.prefix}' reported {_reason_name(reason)} after {its} Newton "
                f"steps, but {why}",
                where=where,
                history=self.history,
            )
        if snes is self._snes:  # the factorisation of its last Newton step is kept
            if self._converged_x is None:
                self._converged_x = self.x.duplicate()
            self.x.copy(self._converged_x)
            self._factor_is_converged = True
            self._converged_snes = snes  # a switch of type or options builds a new one
            # the unknowns as the functions hold them (with a periodic constraint the
            # slave entries of ``x`` differ from them: _at_converged_solve)
            if self._converged_fx is None:
                self._converged_fx = self.x.duplicate()
            self._from_functions(self._converged_fx)
        return self.history

    def solve_penalty(
        self,
        kappas: Sequence[float] = (1e0, 1e2, 1e4, 1e6, 1e8),
        weights: PETSc.Vec | None = None,
        where: str = "",
    ) -> list[SolveHistory]:
        """Penalty-continuation warm start, then the exact VI.

        For each ``k`` in ``kappas`` the bounds are enforced by the penalty
        ``k w_i (min(x_i - l_i, 0) + max(x_i - u_i, 0))`` added to the residual,
        solved by a semi-smooth Newton (``newtonls``, no bounds); the last
        solution starts the exact VI.  ``w_i`` defaults to the lumped mass
        ``int phi_i dx`` of the unknown's space, so ``k`` is the coefficient of
        the continuous penalty ``int k min(x, 0) v dx`` and its effect does not
        change with the mesh.  Returns the histories of all passes (the last one
        is the VI).
        """
        if not self.has_bounds:
            raise ParameterError("solve_penalty needs a problem with bounds")
        if self._snes_penalty is None:
            pen = _replace(self.options, snes_type="newtonls")
            self._snes_penalty = self._make_snes(pen, self.prefix + "penalty_", bounded=False)
            self._snes_penalty.setDivergenceTolerance(1e300)  # raising kappa raises |F| at first
        w = self._lumped_mass() if weights is None else weights.getArray(readonly=True).copy()
        hist = []
        try:
            for k in kappas:
                self._kappa = k * w
                self._penalty = k
                hist.append(self._solve(self._snes_penalty, f"{where or self.name}: penalty {k:g}"))
        finally:
            self._penalty = 0.0
        hist.append(self.solve(where=f"{where or self.name}: exact VI"))
        return hist

    def _lumped_mass(self) -> np.ndarray:
        """Owned values of ``int sum_c v_c dx`` for the test functions of the unknown(s)."""
        us = self.u if self.blocked else [self.u]
        forms = []
        for ui in us:
            V = ui.function_space
            v = ufl.TestFunction(V)
            vs = sum(v[i] for i in range(v.ufl_shape[0])) if v.ufl_shape else v
            forms.append(dolfinx.fem.form(vs * ufl.dx(domain=V.mesh)))
        vec = self.b.duplicate()
        self.assembly.assemble_linear(forms if self.blocked else forms[0], vec)
        out = np.abs(vec.getArray(readonly=True)).copy()
        vec.destroy()
        return out

    # ------------------------------------------------------------ continuation
    def tangent(self, dF: PETSc.Vec, reuse_factorisation: bool = True) -> PETSc.Vec:
        """The tangent ``t`` of the solution path at the current (converged) unknowns:
        ``J t = -dF`` with ``dF`` the residual's derivative with respect to the
        continuation parameter (a vector of this solver's layout), on the rows off
        an active bound; ``t = 0`` on the active rows, so the bounded unknowns there
        stay put.  A new vector (the caller destroys it).

        With ``reuse_factorisation``, a reduced-space VI solve through the full
        pattern (``vi_linear_solve = "full_pattern"``), and the unknowns still those
        its last solve converged to, the tangent reuses the factorisation of that
        solve's last Newton step (its active set; the Jacobian one step before
        convergence; with ``factor_reuse_its``, the kept one, possibly of an
        earlier step or solve, so the tangent is approximate: on the ball's sweep
        the continuation points still took 3 Newton steps each): two triangular
        solves, no assembly, no factorisation.  After
        a failed solve, or with other unknowns, the factorisation is not theirs.
        Otherwise one direct solve with the Jacobian at the current unknowns, by
        its own KSP (``<prefix>tangent_``: LU by ``factor_solver``) with the
        semismooth active set (``x - F`` beyond a bound), the solver's own
        factorisation left as it is.

        A plain Newton (``newtonls``, LU, no kept factorisation) at the unknowns of
        its last converged solve factorises the Jacobian there with its SNES's own
        LU, in the pattern it has analysed (one assembly and one numeric
        factorisation, no analysis, no copy).  It does not reuse a factorisation
        of that solve: on the lip sector's roughness path the Jacobian one Newton
        step before convergence gave tangents whose next step failed (15 Newton
        steps), where the Jacobian at the solution gave steps that start
        converged."""
        if reuse_factorisation and self._plain_lu_at_converged():
            rhs = dF.copy()
            rhs.scale(-1.0)
            t = rhs.duplicate()
            try:
                # the Jacobian here, factorised by the solve in the SNES's pattern
                self._jacobian(self._snes, self.x, self.A, self.A)
                ksp = self._snes.getKSP()
                ksp.solve(rhs, t)
                reason = ksp.getConvergedReason()
            finally:
                rhs.destroy()
            if reason < 0 or not np.isfinite(t.norm()):
                t.destroy()
                raise SolverError(
                    "the tangent's solve with the Newton's own LU failed "
                    f"({_named(PETSc.KSP.ConvergedReason, reason)})",
                    where=f"{self.name} tangent predictor",
                )
            return t
        lagged = self._full_lu if reuse_factorisation and self._at_converged_solve() else None
        if (
            lagged is not None
            and lagged.factor() is not None
            and lagged.factored_inactive is not None
        ):
            t = lagged.solve_full(dF)
            t.scale(-1.0)
            if not np.isfinite(t.norm()):
                t.destroy()
                raise SolverError(
                    "the tangent's solve with the last factorisation gave a non-finite vector",
                    where=f"{self.name} tangent predictor",
                )
            return t
        F = self.residual()
        self._jacobian(self._snes, self.x, self.A, self.A)
        rhs = dF.copy()
        rhs.scale(-1.0)
        A = self.A.copy()
        if self.has_bounds:
            trial = self.x.getArray(readonly=True) - F.getArray(readonly=True)
            active = np.flatnonzero(
                (trial < self.xl.getArray(readonly=True))
                | (trial > self.xu.getArray(readonly=True))
            ).astype(np.int32)
            rhs.array[active] = 0.0
            A.zeroRows(active + A.getOwnershipRange()[0], diag=1.0)  # collective
        F.destroy()
        if self._tangent_ksp is None:
            ksp = PETSc.KSP().create(self.comm)
            ksp.setOptionsPrefix(self.prefix + "tangent_")
            ksp.setType("preonly")
            ksp.getPC().setType("lu")
            ksp.getPC().setFactorSolverType(self.options.factor_solver)
            ksp.setFromOptions()
            self._tangent_ksp = ksp
        self._tangent_ksp.setOperators(A)
        t = rhs.duplicate()
        try:
            self._tangent_ksp.solve(rhs, t)
            reason = self._tangent_ksp.getConvergedReason()
            if reason < 0 or not np.isfinite(t.norm()):
                t.destroy()
                raise SolverError(
                    f"the tangent's linear solve failed ({_named(PETSc.KSP.ConvergedReason, reason)})",
                    where=f"{self.name} tangent predictor",
                )
        finally:
            self._tangent_ksp.reset()
            A.destroy()
            rhs.destroy()
        return t

    def _plain_lu_at_converged(self) -> bool:
        """Whether the unknowns are those of the last converged solve of a plain
        Newton (no bounds enforced) with a direct solve by its SNES's own LU."""
        o = self.options
        return (
            o.snes_type == "newtonls"
            and not self._ssn
            and o.ksp_type == "preonly"
            and o.pc_type == "lu"
            and not o.factor_reuse_its
            and not self._lu_in_pc
            and self._converged_snes is self._snes
            and self._factor_is_converged
            and self._same_unknowns(self._converged_fx)
        )

    def _same_unknowns(self, ref: PETSc.Vec | None) -> bool:
        """Whether the unknowns, as the functions hold them, equal ``ref`` (to 1e-14)."""
        if ref is None:
            return False
        self._from_functions(self.x)
        diff = self.x.copy()
        diff.axpy(-1.0, ref)
        same = diff.norm(PETSc.NormType.NORM_INFINITY) <= 1e-14 * max(
            ref.norm(PETSc.NormType.NORM_INFINITY), 1e-300
        )
        diff.destroy()
        return same

    def _at_converged_solve(self) -> bool:
        """Whether the unknowns are those of the last converged solve and no solve
        has run since (so the kept factorisation is that solve's last one).

        Compared with the SNES's own solution vector: with a periodic constraint
        its slave entries differ from the functions' after a solve of one Newton
        step or more (seen on the lip sector), so this is false there and the
        tangent gets its own Jacobian and LU (the coupled lip sector's walk from
        the tangent; the plain Newton's tangent compares with the functions'
        values instead)."""
        return self._factor_is_converged and self._same_unknowns(self._converged_x)

    def add_to_unknowns(self, step: PETSc.Vec, factor: float) -> None:
        """Unknowns ``+= factor * step`` (``step`` in this solver's layout; with a
        constraint, the slaves follow their masters)."""
        x = self.x.copy()
        self.assembly.from_functions(x)
        x.axpy(factor, step)
        self.assembly.to_functions(x)
        x.destroy()

    # ------------------------------------------------------------ diagnostics
    def residual(self) -> PETSc.Vec:
        """The residual vector at the current unknowns (a copy: the caller destroys it)."""
        self._from_functions(self.x)
        self._residual(self._snes, self.x, self.b)
        return self.b.copy()

    def jacobian(self, with_linear_term: bool = True) -> PETSc.Mat:
        """The Jacobian at the current unknowns, assembled into the solver's matrix
        (plain rows, no semismooth identity rows; :attr:`linear_term` added unless
        ``with_linear_term`` is false).  The next solve assembles it afresh."""
        term = self.linear_term
        if not with_linear_term:
            self.linear_term = None
        try:
            self._from_functions(self.x)
            self._jacobian(self._snes, self.x, self.A, self.A)
        finally:
            self.linear_term = term
        return self.A

    def scaled_residual(self, F: PETSc.Vec) -> float:
        """``max_i |x_i - clip(x_i - F_i / J_ii, l_i, u_i)|``: the residual in solution units.

        Dividing each row by the Jacobian diagonal (the last one assembled) turns
        the residual into a Jacobi correction, whose round-off level is about
        ``eps |x|`` whatever the mesh size (the 2-norm of the raw residual grows
        with the number of dofs and the conditioning).  Rows with a zero diagonal
        (saddle-point pressure rows with ``1/K = 0``) are left out.
        """
        self.A.getDiagonal(self._diag)
        d = np.abs(self._diag.getArray(readonly=True))
        xa = self.x.getArray(readonly=True)
        fa = F.getArray(readonly=True)
        keep = d > 0
        step = np.zeros_like(xa)
        step[keep] = fa[keep] / d[keep]
        if self.has_bounds:
            r = xa - np.clip(
                xa - step, self.xl.getArray(readonly=True), self.xu.getArray(readonly=True)
            )
        else:
            r = step
        local = float(np.abs(r).max(initial=0.0))
        return float(self.comm.allreduce(local, op=_mpi_max()))

    def complementarity(self) -> float:
        """2-norm of the natural residual ``x - clip(x - F(x), lower, upper)``.

        Zero exactly at a solution of the VI; it catches both a false
        "converged" on a zero step and wrong-signed multipliers on the active set.
        """
        F = self.residual()
        xa = self.x.getArray(readonly=True)
        r = xa - np.clip(
            xa - F.getArray(readonly=True),
            self.xl.getArray(readonly=True),
            self.xu.getArray(readonly=True),
        )
        F.destroy()
        return float(np.sqrt(self.comm.allreduce(float(r @ r))))

    def factor_memory_mb(self) -> tuple[float, float] | None:
        """Memory of the last MUMPS factorisation this solver holds [MB]: (the
        largest on one rank, INFOG(21); the sum over the ranks, INFOG(22)), in
        MUMPS's whole millions of bytes (0 below 1 MB).

        The factor is the SNES's own LU, or with ``vi_linear_solve =
        'full_pattern'`` the work matrix's (:class:`_FullPatternLU`).  None when
        the solver has not factorised yet or its factor is not MUMPS's
        (collective).
        """
        factors = [self._full_lu.factor()] if self._full_lu is not None else []
        pc = self._snes.getKSP().getPC()
        if pc.getType() in ("lu", "cholesky"):
            try:
                factors.append(pc.getFactorMatrix())
            except PETSc.Error:  # not set up yet
                pass
        for F in factors:
            # INFOG(29), the factor's entries, is 0 before the first factorisation
            if F is not None and F.getType() == "mumps" and F.getMumpsInfog(29) != 0:
                return float(F.getMumpsInfog(21)), float(F.getMumpsInfog(22))
        return None

    @property
    def snes(self) -> PETSc.SNES:
        """The underlying PETSc SNES."""
        return self._snes

    @contextlib.contextmanager
    def switched(self, snes_type: str | None = None, **fields: Any) -> Iterator[None]:
        """Another SNES type and other :class:`SNESOptions` fields inside the block;
        the solver's own options (and SNES type) are restored on leaving it, also
        when the block raises.

        Fields read at each solve (:data:`SOLVE_TIME_FIELDS`: the tolerances of the
        convergence test) change nothing else.  Any other change (the type, the
        line search, ``max_it``, ``dtol``, the linear solver) builds a new SNES on
        entry and again on exit, since the SNES reads them when it is built: its
        first factorisation then redoes the analysis (about 0.3 s a switch on the
        coarse lip sector)."""
        saved = self.options
        if snes_type is not None:
            fields["snes_type"] = snes_type
        new = _replace(saved, **fields)
        rebuild = any(
            getattr(new, f.name) != getattr(saved, f.name)
            for f in dataclasses.fields(SNESOptions)
            if f.name not in SOLVE_TIME_FIELDS
        )
        self.options = new
        if rebuild:
            self.set_snes_type(new.snes_type)
        try:
            yield
        finally:
            self.options = saved
            if rebuild:
                self.set_snes_type(saved.snes_type)

    @contextlib.contextmanager
    def newton_limit(self, max_newton: int, stall_steps: int = 0) -> Iterator[None]:
        """At most ``max_newton`` Newton steps a solve inside the block (0: the
        solver's own limit).  Set on the SNES itself: ``options.max_it`` is read
        only when the SNES is built.  ``stall_steps > 0``: a solve also fails
        (``DIVERGED_STALLED``) once that many consecutive Newton steps have each
        lowered the residual norm by less than :data:`STALL_REDUCTION`."""
        stall = self._stall_steps
        self._stall_steps = stall_steps
        max_it = self._snes.getTolerances()[3]
        if max_newton:
            self._snes.setTolerances(max_it=min(max_newton, max_it))
        try:
            yield
        finally:
            self._stall_steps = stall
            if max_newton:
                self._snes.setTolerances(max_it=max_it)  # the SNES may be a new one

    def destroy(self) -> None:
        """Free the PETSc objects and the options entries it set (collective)."""
        opts = PETSc.Options()
        for key in self._own_options:
            opts.delValue(key)
        self._own_options.clear()
        for obj in (
            self._snes,
            self._snes_penalty,
            self._tangent_ksp,
            self._converged_x,
            self._converged_fx,
            self.linear_term,
            self.A,
            self.b,
            self.x,
            self._diag,
            self.xl,
            self.xu,
        ):
            if obj is not None:
                obj.destroy()
        if self._full_lu is not None:
            self._full_lu.destroy()
            self._full_lu = None
        self.assembly.destroy()


class _FullPatternLU:
    """Python preconditioner of ``vinewtonrsls``'s KSP (``vi_linear_solve =
    "full_pattern"``): an exact solve of the reduced system ``J_II y_I = r_I``.

    PETSc's reduced-space VI extracts the submatrix ``J_II`` of the rows and
    columns off an active bound at every Newton step; a new matrix object makes
    the direct solver redo its analysis (ordering, symbolic factorisation), which
    is sequential in MUMPS.  Here the owner's full Jacobian (the matrix the SNES
    assembled) is copied into a work matrix of the same pattern, whose active rows
    become identity rows (the pattern is kept), and factorised: ``[[J_II, J_IA],
    [0, I]] [y_I; y_A] = [r_I; 0]`` gives ``y_A = 0`` and ``J_II y_I = r_I``.  The
    work matrix is one object with one pattern, so only the numeric factorisation
    is repeated.  The inner solver has the owner's options prefix, so
    ``-<prefix>mat_mumps_*`` options reach it.

    With ``reuse_its = k > 0`` (``SNESOptions.factor_reuse_its``) the outer KSP is
    GMRES (right preconditioned) on ``J_II`` and the factorisation is kept across
    Newton steps and solves: it is made afresh only at a set-up that follows a
    linear solve of more than ``k`` GMRES iterations (or a failed one).  A kept
    factorisation may hold another active set than the step's; the padded solve
    is then an approximate inverse of ``J_II``, which GMRES corrects."""

    def __init__(self, owner: NonlinearSolver, prefix: str) -> None:
        self.owner = owner
        self.prefix = prefix
        self.W: PETSc.Mat | None = None
        self.ksp: PETSc.KSP | None = None
        self.xf: PETSc.Vec | None = None
        self.yf: PETSc.Vec | None = None
        self.nz = 0.0  # nonzeros of the Jacobian the work matrix was copied from
        self.factored_inactive: PETSc.IS | None = None  # the factorisation's inactive set
        self.reuse_its = 0  # > 0: the factorisation is kept (see the class docstring)
        self.applies = 0  # preconditioner applications since the last set-up
        self.factorisations = 0  # numeric factorisations made (kept ones not counted)

    def _inactive(self) -> PETSc.IS:
        return self.owner._snes.getVIInactiveSet()

    def setUp(self, pc: PETSc.PC) -> None:  # petsc4py's name
        A = self.owner.A
        nz = A.getInfo(PETSc.Mat.InfoType.GLOBAL_SUM)["nz_used"]
        if self.W is not None and nz != self.nz:  # the Jacobian's pattern changed
            self.destroy()
        # right-preconditioned GMRES applies the preconditioner once per iteration
        # and once more for the solution (k iterations: k + 1)
        applies, self.applies = self.applies, 0
        if (
            self.reuse_its
            and self.ksp is not None
            and 0 < applies <= self.reuse_its + 1
            and self.owner._snes.getKSP().getConvergedReason() >= 0
        ):
            return
        self._factorise(pc, nz)

    def _factorise(self, pc: PETSc.PC, nz: float) -> None:
        """Copy the owner's Jacobian (``nz`` nonzeros) into the work matrix, identity
        rows at the step's active bounds, and factorise it."""
        A = self.owner.A
        if self.W is None:
            self.W = A.duplicate(copy=True)
            self.W.setOption(PETSc.Mat.Option.KEEP_NONZERO_PATTERN, True)
            self.xf, self.yf = self.W.createVecs()
            self.nz = nz
        else:
            A.copy(self.W, structure=PETSc.Mat.Structure.SAME_NONZERO_PATTERN)
        rstart, rend = self.W.getOwnershipRange()
        inactive = self._inactive()
        active = inactive.complement(rstart, rend)
        self.W.zeroRows(active, diag=1.0)  # collective; keeps the pattern
        active.destroy()
        if self.factored_inactive is not None:
            self.factored_inactive.destroy()
        # a copy for solve_full: the SNES's own set belongs to the SNES, which may
        # free or replace it once the step is over
        self.factored_inactive = inactive.duplicate()
        if self.ksp is None:
            ksp = PETSc.KSP().create(self.W.getComm())
            ksp.setType("preonly")
            inner = ksp.getPC()
            inner.setOptionsPrefix(self.prefix)  # the factor reads -<prefix>mat_mumps_*
            inner.setType("lu")
            inner.setFactorSolverType(self.owner.options.factor_solver)
            ksp.setOperators(self.W)
            self.ksp = ksp
        # the first set-up analyses and factorises; after it PETSc refactorises
        # (numerically only: one object, one pattern) inside the next solve, as the
        # work matrix has changed, and apply() passes on a failure found there
        self.ksp.setUp()
        self.factorisations += 1
        failed = self.ksp.getPC().getFailedReason()
        if failed:
            pc.setFailedReason(failed)

    def _solve_padded(self, inact: PETSc.IS, r: PETSc.Vec) -> bool:
        """Solve ``W yf = [r; 0]``: ``r`` (a vector of the rows in ``inact``) padded
        with zeros on the other rows.  Whether the solve succeeded."""
        self.xf.zeroEntries()
        sub = self.xf.getSubVector(inact)
        r.copy(sub)
        self.xf.restoreSubVector(inact, sub)
        self.ksp.solve(self.xf, self.yf)
        return self.ksp.getConvergedReason() >= 0

    def apply(self, pc: PETSc.PC, x: PETSc.Vec, y: PETSc.Vec) -> None:
        self.applies += 1
        inact = self._inactive()
        if not self._solve_padded(inact, x):
            pc.setFailedReason(self.ksp.getPC().getFailedReason() or 1)
        sub = self.yf.getSubVector(inact)
        sub.copy(y)
        self.yf.restoreSubVector(inact, sub)

    def solve_full(self, b: PETSc.Vec) -> PETSc.Vec:
        """``y`` with ``W y = b`` off the last set-up's active rows and ``y = 0`` on
        them, by the current factorisation (a new vector: the caller destroys it).
        The inactive set is the one the factorisation was made with."""
        inact = self.factored_inactive
        r = b.getSubVector(inact)
        ok = self._solve_padded(inact, r)
        b.restoreSubVector(inact, r)
        if not ok:
            raise SolverError(
                "the tangent's triangular solves failed "
                f"({_named(PETSc.KSP.ConvergedReason, self.ksp.getConvergedReason())})",
                where=f"{self.owner.name} tangent predictor",
            )
        y = b.duplicate()
        self.yf.copy(y)
        return y

    def factor(self) -> PETSc.Mat | None:
        """The inner factor matrix (for failure reports), or None."""
        if self.ksp is None:
            return None
        try:
            return self.ksp.getPC().getFactorMatrix()
        except PETSc.Error:
            return None

    def discard_factor(self) -> None:
        """Drop the factorisation (the next set-up analyses afresh)."""
        if self.ksp is not None:
            self.ksp.destroy()
            self.ksp = None

    def destroy(self, pc: PETSc.PC | None = None) -> None:
        """Free the work matrix, vectors and factorisation (PETSc calls it when the
        SNES's preconditioner is destroyed; they are built again at the next set-up)."""
        self.discard_factor()
        for obj in (self.W, self.xf, self.yf, self.factored_inactive):
            if obj is not None:
                obj.destroy()
        self.W = self.xf = self.yf = self.factored_inactive = None


# ------------------------------------------------------------------ helpers
def _is_zero(form: Any) -> bool:
    from ufl.algorithms import expand_derivatives

    try:
        return expand_derivatives(form).empty()
    except Exception:
        return False


def _keeps_pattern(snes_type: str, vi_linear_solve: str) -> bool:
    """Whether the linear systems of this SNES type keep one matrix pattern (so a
    factorisation can be kept across Newton steps, ``factor_reuse_its``)."""
    if snes_type == "vinewtonrsls":
        return vi_linear_solve == "full_pattern"
    return snes_type not in _VI_TYPES


def _replace(o: SNESOptions, **kw: Any) -> SNESOptions:
    from dataclasses import replace

    if not _keeps_pattern(
        kw.get("snes_type", o.snes_type), kw.get("vi_linear_solve", o.vi_linear_solve)
    ):
        kw.setdefault("factor_reuse_its", 0)
    return replace(o, **kw)


def _with_session(o: SNESOptions) -> SNESOptions:
    """``o`` with the fields of the enclosing :func:`solver_session` blocks."""
    fields = {k: v for d in _SESSION_FIELDS for k, v in d.items()}
    if not _keeps_pattern(
        fields.get("snes_type", o.snes_type), fields.get("vi_linear_solve", o.vi_linear_solve)
    ):
        fields.pop("factor_reuse_its", None)
    return _replace(o, **fields) if fields else o


def _mpi_min() -> Any:
    from mpi4py import MPI

    return MPI.MIN


def _mpi_max() -> Any:
    from mpi4py import MPI

    return MPI.MAX


def _named(enum: Any, value: int) -> str:
    for k, v in vars(enum).items():
        if not k.startswith("_") and v == value:
            return k
    return str(value)


def _linear_failure(snes: PETSc.SNES) -> str:
    """What failed in the last linear solve: the KSP reason, the preconditioner's
    failure and, for MUMPS, INFOG(1) and INFOG(2) (the MUMPS error code and its
    detail: -9 or -8 too little workspace, -10 a numerically singular matrix;
    the same on every rank)."""
    parts = []
    with contextlib.suppress(Exception):
        ksp = snes.getKSP()
        parts.append("KSP " + _named(PETSc.KSP.ConvergedReason, int(ksp.getConvergedReason())))
        pc = ksp.getPC()
        with contextlib.suppress(Exception):
            parts.append("PC " + _named(PETSc.PC.FailedReason, int(pc.getFailedReason())))
        with contextlib.suppress(Exception):
            if pc.getType() == "python":  # vi_linear_solve = "full_pattern"
                F = pc.getPythonContext().factor()
            else:
                F = pc.getFactorMatrix()
            if F.getType() == "mumps":
                parts.append(
                    f"MUMPS INFOG(1) = {F.getMumpsInfog(1)}, INFOG(2) = {F.getMumpsInfog(2)}"
                )
    return "; ".join(parts) or "no detail from the linear solver"


def _reason_name(reason: int) -> str:
    for k, v in vars(PETSc.SNES.ConvergedReason).items():
        if not k.startswith("_") and v == reason:
            return k
    return str(reason)


__all__ = ["NonlinearSolver", "SNESOptions", "bounds_function", "extra_petsc_options"]
