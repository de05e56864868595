"""The SNES wrapper: single field, blocked (with a global real unknown), VI bounds,
failure reporting, complementarity check, options pass-through, 1 vs 2 ranks."""

from __future__ import annotations

import dolfinx
import numpy as np
import pytest
import scifem
import ufl
from mpi4py import MPI
from petsc4py import PETSc

from dolfinx_seal.errors import ParameterError, SolverError
from dolfinx_seal.solid.problem import SolidContactProblem, SteppingOptions
from dolfinx_seal.solvers import (
    NonlinearSolver,
    SNESOptions,
    bounds_function,
    solver_session,
    with_snes_type,
)


def _nonlinear_poisson(comm, n=32, **kw):
    """-div((1 + u^2) grad u) = f on the unit square, manufactured u = x(1-x) y(1-y) * 4."""
    mesh = dolfinx.mesh.create_unit_square(comm, n, n)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 2))
    x = ufl.SpatialCoordinate(mesh)
    ue = 4 * x[0] * (1 - x[0]) * x[1] * (1 - x[1])
    f = -ufl.div((1 + ue**2) * ufl.grad(ue))
    u = dolfinx.fem.Function(V)
    v = ufl.TestFunction(V)
    F = ufl.inner((1 + u**2) * ufl.grad(u), ufl.grad(v)) * ufl.dx - f * v * ufl.dx
    mesh.topology.create_connectivity(1, 2)
    dofs = dolfinx.fem.locate_dofs_topological(
        V, 1, dolfinx.mesh.exterior_facet_indices(mesh.topology)
    )
    bc = dolfinx.fem.dirichletbc(0.0, dofs, V)
    return NonlinearSolver(F, u, [bc], **kw), u, ue


def test_newton_quadratic_convergence_and_accuracy():
    solver, u, ue = _nonlinear_poisson(MPI.COMM_WORLD)
    h = solver.solve()
    r = h.residual_norms
    assert h.reason > 0 and 3 <= h.newton_iterations <= 8
    # quadratic convergence: once in the asymptotic range, r_{k+1} <= C r_k^2
    rates = [
        np.log(r[k + 1]) / np.log(r[k])
        for k in range(1, len(r) - 1)
        if r[k] < 1e-2 and r[k + 1] > 1e-14
    ]
    assert all(q > 1.6 for q in rates), rates
    err = np.sqrt(
        MPI.COMM_WORLD.allreduce(
            dolfinx.fem.assemble_scalar(dolfinx.fem.form((u - ue) ** 2 * ufl.dx)), MPI.SUM
        )
    )
    assert err < 1e-5  # P2 on 32x32: O(h^3) ~ 3e-5 * const; observed 2e-7
    solver.destroy()


def test_failure_raises_typed_error_with_history():
    solver, _, _ = _nonlinear_poisson(MPI.COMM_WORLD, n=8, options=SNESOptions(max_it=1))
    with pytest.raises(SolverError) as info:
        solver.solve(where="unit test")
    e = info.value
    assert "DIVERGED_MAX_IT" in e.what and e.where == "unit test"
    assert len(e.history.residual_norms) == 2 and "last residual norms" in str(e)
    solver.destroy()


def test_a_converged_state_the_owner_refuses_is_a_failed_solve():
    """``acceptance`` runs after convergence; a reason makes the solve a failure
    that names it (the state is kept for the caller to restore from)."""
    solver, u, _ = _nonlinear_poisson(MPI.COMM_WORLD, n=8)
    calls = []

    def refuse():
        calls.append(float(MPI.COMM_WORLD.allreduce(np.max(np.abs(u.x.array)), MPI.MAX)))
        return "the state is outside the law's domain (injected)"

    solver.acceptance = refuse
    with pytest.raises(SolverError, match=r"CONVERGED_FNORM.*but the state is outside") as info:
        solver.solve(where="unit test")
    assert info.value.history.reason_name == "CONVERGED_TO_INADMISSIBLE_STATE"
    assert calls and calls[0] == pytest.approx(0.25, rel=1e-2)  # called on the solution
    solver.acceptance = lambda: None
    assert solver.solve().reason > 0
    solver.destroy()


def test_a_newton_limit_holds_inside_its_block_only():
    solver, _, _ = _nonlinear_poisson(MPI.COMM_WORLD, n=8, options=SNESOptions(max_it=40))
    with solver.newton_limit(1):
        with pytest.raises(SolverError, match="DIVERGED_MAX_IT after 1 Newton"):
            solver.solve()
    assert solver.snes.getTolerances()[3] == 40
    with solver.newton_limit(0):  # 0: the solver's own limit
        assert solver.snes.getTolerances()[3] == 40
    with solver.newton_limit(100):  # never above it
        assert solver.snes.getTolerances()[3] == 40
        assert solver.solve().reason > 0
    solver.destroy()


def test_a_stalled_solve_fails_after_its_stall_steps_inside_the_block_only():
    """Newton steps damped to 1/200 lower the residual by 0.5 % each: with
    ``stall_steps = 3`` the solve fails as DIVERGED_STALLED after 3 steps; outside
    the block it runs to the solver's limit; undamped, the stall rule never fires
    (quadratic convergence lowers the residual by decades a step)."""
    damped = {"snes_linesearch_damping": 0.005}
    solver, _, _ = _nonlinear_poisson(
        MPI.COMM_WORLD, n=8, options=SNESOptions(max_it=8), petsc_options=damped
    )
    with solver.newton_limit(0, stall_steps=3):
        with pytest.raises(
            SolverError,
            match=r"DIVERGED_STALLED \(the residual fell by less "
            r"than 1% in each of the last 3 Newton steps\) after 3 Newton",
        ) as e:
            solver.solve()
    norms = np.array(e.value.history.residual_norms)
    assert np.all(norms[1:] > 0.99 * norms[:-1])
    with pytest.raises(SolverError, match="DIVERGED_MAX_IT after 8 Newton"):
        solver.solve()
    solver.destroy()
    solver, _, _ = _nonlinear_poisson(MPI.COMM_WORLD, n=8)
    with solver.newton_limit(0, stall_steps=1):
        h = solver.solve()
    assert h.reason > 0 and h.newton_iterations <= 6
    solver.destroy()


def test_command_line_options_override_defaults():
    PETSc.Options()["cliprefix_snes_max_it"] = 1
    try:
        solver, _, _ = _nonlinear_poisson(MPI.COMM_WORLD, n=8, prefix="cliprefix_")
        with pytest.raises(SolverError, match="DIVERGED_MAX_IT after 1"):
            solver.solve()
        solver.destroy()
    finally:
        PETSc.Options().delValue("cliprefix_snes_max_it")


def test_blocked_problem_with_real_unknown():
    """Pure-Neumann Poisson with a global Lagrange multiplier fixing the mean (blocked).

    -u'' = pi^2 cos(pi x) on (0, 1), u'(0) = u'(1) = 0, int u = 0  ->  u = cos(pi x).
    """
    comm = MPI.COMM_WORLD
    mesh = dolfinx.mesh.create_unit_interval(comm, 200)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 2))
    R = scifem.create_real_functionspace(mesh)
    u, lam = dolfinx.fem.Function(V), dolfinx.fem.Function(R)
    v, mu = ufl.TestFunction(V), ufl.TestFunction(R)
    x = ufl.SpatialCoordinate(mesh)[0]
    f = np.pi**2 * ufl.cos(np.pi * x)
    F0 = ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx + lam * v * ufl.dx - f * v * ufl.dx
    F1 = u * mu * ufl.dx
    solver = NonlinearSolver([F0, F1], [u, lam])
    h = solver.solve()
    assert h.newton_iterations == 1  # linear problem
    err = np.sqrt(
        comm.allreduce(
            dolfinx.fem.assemble_scalar(dolfinx.fem.form((u - ufl.cos(np.pi * x)) ** 2 * ufl.dx)),
            MPI.SUM,
        )
    )
    assert err < 1e-7  # P2, h = 5e-3: O(h^3) ~ 1e-7 * pi^3 / 12...
    assert abs(comm.allreduce(float(lam.x.array[0]) if lam.x.array.size else 0.0, MPI.MAX)) < 1e-8
    solver.destroy()


def _string_on_obstacle(comm, n=200, **kw):
    """-u'' = 0 on (-1, 1), u(+-1) = 0, u >= 1/2 - x^2: contact on |x| <= 1 - sqrt(1/2)."""
    mesh = dolfinx.mesh.create_interval(comm, n, [-1.0, 1.0])
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1))
    u = dolfinx.fem.Function(V)
    v = ufl.TestFunction(V)
    F = ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx
    dofs = dolfinx.fem.locate_dofs_geometrical(V, lambda x: np.isclose(np.abs(x[0]), 1.0))
    bc = dolfinx.fem.dirichletbc(0.0, dofs, V)
    psi = dolfinx.fem.Function(V)
    psi.interpolate(lambda x: 0.5 - x[0] ** 2)
    return NonlinearSolver(F, u, [bc], lower=psi, **kw), u


def _string_exact(x):
    a = 1.0 - np.sqrt(0.5)
    return np.where(np.abs(x) <= a, 0.5 - x**2, (0.5 - a**2) * (1 - np.abs(x)) / (1 - a))


def test_vi_obstacle_1d_exact():
    solver, u = _string_on_obstacle(MPI.COMM_WORLD)
    h = solver.solve()
    assert h.complementarity <= 1e-9
    V = u.function_space
    n = V.dofmap.index_map.size_local
    x = V.tabulate_dof_coordinates()[:n, 0]
    err = MPI.COMM_WORLD.allreduce(
        float(np.abs(u.x.array[:n] - _string_exact(x)).max(initial=0)), MPI.MAX
    )
    # the contact point a = 0.2929 lies inside a cell: the nodal error is O(h^2) = 1e-4
    assert err < 2e-4
    solver.destroy()


def test_false_convergence_is_caught_by_complementarity():
    """SNES claiming convergence on a zero step (as PETSc's VI solvers may) is not trusted."""
    solver, _ = _string_on_obstacle(MPI.COMM_WORLD)
    solver.snes.setConvergenceTest(
        lambda snes, it, norms: PETSc.SNES.ConvergedReason.CONVERGED_SNORM_RELATIVE
    )
    with pytest.raises(SolverError, match="complementarity residual"):
        solver.solve()
    solver.destroy()


def test_stagnation_above_round_off_is_not_convergence():
    """A step tolerance of 0.99 would stop after one step; the residual check refuses it."""
    solver, _ = _string_on_obstacle(MPI.COMM_WORLD, options=SNESOptions(stol=0.99, max_it=100))
    h = solver.solve()
    assert h.reason_name != "CONVERGED_SNORM_RELATIVE" and h.complementarity < 1e-9
    solver.destroy()


def test_penalty_then_vi_matches_plain_vi():
    s1, u1 = _string_on_obstacle(MPI.COMM_WORLD)
    s1.solve()
    s2, u2 = _string_on_obstacle(MPI.COMM_WORLD)
    hist = s2.solve_penalty()
    assert hist[-1].newton_iterations <= 3
    assert np.allclose(u1.x.array, u2.x.array, atol=1e-10)
    s1.destroy()
    s2.destroy()


def _lu_count() -> int:
    return int(PETSc.Log.Event("MatLUFactorNum").getPerfInfo()["count"])


def test_semismooth_fixed_pattern_matches_the_reduced_space_vi():
    """The wrapper's own semismooth Newton (identity rows written into the fixed
    pattern) reaches the reduced-space VI's solution, which is the exact one to the
    discretisation error, with the same complementarity."""
    s1, u1 = _string_on_obstacle(MPI.COMM_WORLD)
    s1.solve()
    s2, u2 = _string_on_obstacle(MPI.COMM_WORLD, options=SNESOptions(snes_type="semismooth"))
    h = s2.solve()
    assert s2.snes.getType() == "newtonls"
    assert h.complementarity <= 1e-9
    assert np.allclose(u1.x.array, u2.x.array, atol=1e-10)
    s1.destroy()
    s2.destroy()


def _analysis_count() -> int:
    return int(PETSc.Log.Event("MatLUFactorSym").getPerfInfo()["count"])


def test_full_pattern_reduced_solve_takes_the_same_steps_with_one_analysis():
    """vi_linear_solve: the reduced system ``J_II dx_I = -F_I`` solved through the
    full matrix with identity rows at the active bounds is the same linear system,
    so the same Newton iterates (residuals to round-off) and the same solution; the
    pattern is fixed, so one analysis for every step of two solves, where PETSc's
    submatrix is analysed at every step (41 steps a solve here, 1 and 2 ranks)."""
    PETSc.Log.begin()
    runs = {}
    for mode in ("submatrix", "full_pattern"):
        solver, u = _string_on_obstacle(MPI.COMM_WORLD, options=SNESOptions(vi_linear_solve=mode))
        before = _analysis_count()
        h = solver.solve()
        u.x.array[:] = 0.0
        h2 = solver.solve()  # again from zero: the same work matrix
        runs[mode] = (h, h2, _analysis_count() - before, u.x.array.copy())
        assert solver.snes.getKSP().getPC().getType() == (
            "python" if mode == "full_pattern" else "lu"
        )
        solver.destroy()
    (h_s, h2_s, an_s, u_s), (h_f, h2_f, an_f, u_f) = runs["submatrix"], runs["full_pattern"]
    steps = h_s.newton_iterations
    assert steps >= 5  # the active set moves over several steps
    assert h_f.newton_iterations == steps and h2_f.newton_iterations == h2_s.newton_iterations
    r_s, r_f = np.array(h_s.residual_norms), np.array(h_f.residual_norms)
    assert np.all(np.abs(r_f - r_s) <= 1e-8 * r_s[0])
    assert np.allclose(u_f, u_s, rtol=0, atol=1e-12)
    assert h_f.complementarity <= 1e-9
    assert an_s == steps + h2_s.newton_iterations  # a new submatrix object every step
    assert an_f == 1


def _loaded_string_on_obstacle(comm, load_value, n=200, **kw):
    """-u'' = -load on (-1, 1), u(+-1) = 0, u >= 1/2 - x^2: the load presses the
    string onto the obstacle; the solution is affine in ``load`` for a fixed
    contact set."""
    mesh = dolfinx.mesh.create_interval(comm, n, [-1.0, 1.0])
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 1))
    load = dolfinx.fem.Constant(mesh, load_value)
    u = dolfinx.fem.Function(V)
    v = ufl.TestFunction(V)
    F = ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx + load * v * ufl.dx
    dofs = dolfinx.fem.locate_dofs_geometrical(V, lambda x: np.isclose(np.abs(x[0]), 1.0))
    bc = dolfinx.fem.dirichletbc(0.0, dofs, V)
    psi = dolfinx.fem.Function(V)
    psi.interpolate(lambda x: 0.5 - x[0] ** 2)
    return NonlinearSolver(F, u, [bc], lower=psi, **kw), u, psi, load


def _numeric_factorisations() -> int:
    return int(PETSc.Log.Event("MatLUFactorNum").getPerfInfo()["count"])


def test_path_tangent_with_the_last_factorisation_equals_the_difference_quotient():
    """``NonlinearSolver.tangent``: ``du/dload`` of the obstacle problem above.  With a
    fixed contact set the discrete solution is affine in the load, so the
    difference quotient of two converged solutions (load 2 and 2.002, the same
    contact set) is the exact tangent up to the solves' tolerance.  The tangent
    from the full-pattern solve's last factorisation and the one from a fresh
    Jacobian and LU both equal it; the first factorises nothing (1 and 2 ranks)."""
    PETSc.Log.begin()
    comm = MPI.COMM_WORLD
    solver, u, psi, load = _loaded_string_on_obstacle(comm, 2.0)
    solver.solve()
    n = u.function_space.dofmap.index_map.size_local
    u1 = u.x.array[:n].copy()
    contact1 = np.abs(u1 - psi.x.array[:n]) < 1e-10
    # dF/dload = int v dx: the residual is affine in the load
    F0 = solver.residual()
    load.value = 3.0
    dF = solver.residual()
    dF.axpy(-1.0, F0)
    load.value = 2.0
    before = _numeric_factorisations()
    t_lagged = solver.tangent(dF)
    lagged_factorisations = _numeric_factorisations() - before
    t_fresh = solver.tangent(dF, reuse_factorisation=False)
    delta = 2e-3
    load.value = 2.0 + delta
    solver.solve()
    u2 = u.x.array[:n].copy()
    contact2 = np.abs(u2 - psi.x.array[:n]) < 1e-10
    assert comm.allreduce(int(np.sum(contact1 != contact2)), MPI.SUM) == 0
    assert comm.allreduce(int(np.sum(contact1)), MPI.SUM) > 10  # a real contact set
    quotient = (u2 - u1) / delta
    scale = comm.allreduce(float(np.abs(quotient).max()), MPI.MAX)
    for t in (t_lagged, t_fresh):
        err = comm.allreduce(float(np.abs(t.array[:n] - quotient).max()), MPI.MAX)
        # a linear problem on a fixed contact set: each solve ends exact to round-off
        assert err <= 1e-8 * scale, err
        t.destroy()
    assert lagged_factorisations == 0
    # back at load 2 after the solve at 2.002: the kept factorisation is not this
    # state's, so the tangent is made afresh (one factorisation) and is the same
    load.value = 2.0
    u.x.array[:n] = u1
    u.x.scatter_forward()
    before = _numeric_factorisations()
    t_again = solver.tangent(dF)
    assert _numeric_factorisations() - before == 1
    err = comm.allreduce(float(np.abs(t_again.array[:n] - quotient).max()), MPI.MAX)
    assert err <= 1e-8 * scale, err
    t_again.destroy()
    for vec in (F0, dF):
        vec.destroy()
    solver.destroy()


def _scaled_nonlinear_poisson(comm, n=24, mesh=None):
    """-div((1 + u^2) grad u) = s f on the unit square, ``f`` the manufactured one
    of :func:`_nonlinear_poisson` (u = 0 on the boundary): a nonlinear path ``u(s)``
    in the load scale ``s``, solved by a plain Newton."""
    mesh = mesh or dolfinx.mesh.create_unit_square(comm, n, n)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 2))
    x = ufl.SpatialCoordinate(mesh)
    ue = 4 * x[0] * (1 - x[0]) * x[1] * (1 - x[1])
    scale = dolfinx.fem.Constant(mesh, 1.0)
    u = dolfinx.fem.Function(V)
    v = ufl.TestFunction(V)
    F = (
        ufl.inner((1 + u**2) * ufl.grad(u), ufl.grad(v)) * ufl.dx
        + scale * ufl.div((1 + ue**2) * ufl.grad(ue)) * v * ufl.dx
    )
    mesh.topology.create_connectivity(1, 2)
    dofs = dolfinx.fem.locate_dofs_topological(
        V, 1, dolfinx.mesh.exterior_facet_indices(mesh.topology)
    )
    return NonlinearSolver(F, u, [dolfinx.fem.dirichletbc(0.0, dofs, V)]), u, scale


def _symbolic_factorisations() -> int:
    return int(PETSc.Log.Event("MatLUFactorSym").getPerfInfo()["count"])


def test_plain_newton_tangent_is_factorised_in_the_snes_pattern():
    """``NonlinearSolver.tangent`` after a converged ``newtonls`` solve: the
    Jacobian at the solution, factorised by the SNES's own LU in the pattern it
    has analysed (one numeric factorisation, no analysis); the tangent's own
    direct solve (``reuse_factorisation=False``) analyses afresh.  Both against
    the central difference quotient of converged solutions at s = 3 +- 1e-3,
    whose truncation error is O(1e-6) of the tangent (measured: 1e-7), to 1e-6
    (1 and 2 ranks)."""
    PETSc.Log.begin()
    comm = MPI.COMM_WORLD
    solver, u, scale = _scaled_nonlinear_poisson(comm)
    n = u.function_space.dofmap.index_map.size_local

    def solution(s: float) -> np.ndarray:
        scale.value = s
        assert solver.solve().newton_iterations > 0
        return u.x.array[:n].copy()

    lo, hi = solution(3.0 - 1e-3), solution(3.0 + 1e-3)
    solution(3.0)
    F0 = solver.residual()
    scale.value = 4.0
    dF = solver.residual()  # the residual is affine in s: dF/ds exactly
    dF.axpy(-1.0, F0)
    scale.value = 3.0
    num, sym = _numeric_factorisations(), _symbolic_factorisations()
    t_own = solver.tangent(dF)
    assert (_numeric_factorisations() - num, _symbolic_factorisations() - sym) == (1, 0)
    t_fresh = solver.tangent(dF, reuse_factorisation=False)
    assert (_numeric_factorisations() - num, _symbolic_factorisations() - sym) == (2, 1)
    quotient = (hi - lo) / 2e-3
    size = comm.allreduce(float(np.abs(quotient).max()), MPI.MAX)
    assert size > 0.1  # a real path: u grows with s
    for t in (t_own, t_fresh):
        err = comm.allreduce(float(np.abs(t.array[:n] - quotient).max()), MPI.MAX)
        assert err <= 1e-6 * size, err
        t.destroy()
    # the SNES solves on from its refactorised LU: the same solution at s = 3.001
    assert np.allclose(solution(3.0 + 1e-3), hi, rtol=0, atol=1e-12 * size)
    for vec in (F0, dF):
        vec.destroy()
    solver.destroy()


def test_load_ramp_from_the_tangent_takes_fewer_newton_steps_to_the_same_state():
    """``SteppingOptions(predictor=True, tangent=True)``: the ramp in the load
    scale of the nonlinear problem above, in quarter steps, reaches the state the
    ramp from the last state reaches at s = 3 (to the solver's tolerance), in
    fewer Newton steps than it and than the secant (1 and 2 ranks; measured 11,
    12 and 15)."""
    comm = MPI.COMM_WORLD
    mesh = dolfinx.mesh.create_unit_square(comm, 24, 24)  # one partition for the three

    class _Ramped:
        name = "ramp"
        ramp = SolidContactProblem.ramp
        _predict = SolidContactProblem._predict
        _predict_tangent = SolidContactProblem._predict_tangent
        path_tangent = SolidContactProblem.path_tangent
        _drop_load_tangent = SolidContactProblem._drop_load_tangent

        def __init__(self) -> None:
            self.solver, self.u, self.scale = _scaled_nonlinear_poisson(comm, mesh=mesh)
            self.steps: list = []
            self._load_tangent = None

        def set_fraction(self, t: float) -> None:
            self.scale.value = 3.0 * t

        def state(self) -> list[np.ndarray]:
            return [self.u.x.array.copy()]

        def restore(self, state) -> None:
            self.u.x.array[:] = state[0]

    n_steps, finals = {}, {}
    for label, kw in (("none", {}), ("secant", {"predictor": True}),
                      ("tangent", {"predictor": True, "tangent": True})):  # fmt: skip
        prob = _Ramped()
        steps = prob.ramp(SteppingOptions(first=0.25, grow=1.0, **kw))
        assert [round(s.fraction, 12) for s in steps] == [0.25, 0.5, 0.75, 1.0]
        assert prob._load_tangent is None  # freed after the ramp
        n_steps[label] = sum(s.newton_iterations for s in steps)
        finals[label] = prob.u.x.array.copy()
        prob.solver.destroy()
    ref = finals["none"]
    size = comm.allreduce(float(np.abs(ref).max()), MPI.MAX)
    for label in ("secant", "tangent"):
        err = comm.allreduce(float(np.abs(finals[label] - ref).max()), MPI.MAX)
        assert err <= 1e-7 * size, (label, err)
    assert n_steps["tangent"] < n_steps["secant"] <= n_steps["none"], n_steps


def test_switching_the_vi_type_resets_the_solvers_own_options():
    """The full-pattern solve's ``pc_type python`` is the solver's own entry, not a
    command-line one: switching to ``vinewtonssls`` (which solves the full system
    itself) gives its LU back, and switching back gives the preconditioner back;
    each type reaches the same solution."""
    solver, u = _string_on_obstacle(MPI.COMM_WORLD)
    solver.solve()
    ref = u.x.array.copy()
    for snes_type, pc_type in (("vinewtonssls", "lu"), ("vinewtonrsls", "python")):
        solver.set_snes_type(snes_type)
        u.x.array[:] = 0.0
        h = solver.solve()
        assert solver.snes.getKSP().getPC().getType() == pc_type
        assert h.complementarity <= 1e-9
        assert np.allclose(u.x.array, ref, rtol=0, atol=1e-10)
    solver.destroy()


def test_a_switched_block_restores_the_solvers_own_type_and_options():
    """``switched``: inside the block the other type, ``max_it`` and ``dtol`` are the
    SNES's own (a new SNES) and the block solves; after it, also after an error
    inside it, the options and the SNES type are the solver's again.  A field the
    convergence test reads at each solve (``rtol``) keeps the SNES."""
    solver, u = _string_on_obstacle(MPI.COMM_WORLD)
    own = solver.options
    solver.solve()
    ref = u.x.array.copy()
    with solver.switched(snes_type="semismooth", max_it=300, dtol=1e300):
        assert solver.options.snes_type == "semismooth"
        assert solver.snes.getType() == "newtonls"
        assert solver.snes.getTolerances()[3] == 300
        assert solver.snes.getDivergenceTolerance() == 1e300
        u.x.array[:] = 0.0
        h = solver.solve()
        assert h.complementarity <= 1e-9
        assert np.allclose(u.x.array, ref, rtol=0, atol=1e-10)
    assert solver.options == own
    assert solver.snes.getType() == own.snes_type
    assert solver.snes.getTolerances()[3] == own.max_it
    with pytest.raises(RuntimeError, match="inside"):
        with solver.switched(snes_type="vinewtonssls"):
            raise RuntimeError("inside")
    assert solver.options == own and solver.snes.getType() == own.snes_type
    snes = solver.snes
    with solver.switched(rtol=1e-3):
        assert solver.snes is snes and solver.options.rtol == 1e-3
    assert solver.snes is snes and solver.options == own
    solver.destroy()


def test_a_projected_semismooth_step_keeps_every_iterate_feasible():
    """``project_step``: from u = 1 - x^2 (above the obstacle, no bound active) the
    semismooth Newton's first step is the free string, u = 0, far below the
    obstacle; projected, every iterate is on or above it, and both reach the
    same solution."""
    comm = MPI.COMM_WORLD
    solutions, lowest = [], []
    for project in (False, True):
        solver, u = _string_on_obstacle(comm)
        u.interpolate(lambda x: 1.0 - x[0] ** 2)
        low = []

        def record(snes, it, fnorm, solver=solver, low=low):
            if it > 0:
                gap = snes.getSolution().getArray(readonly=True) - solver.xl.getArray(readonly=True)
                low.append(comm.allreduce(float(gap.min(initial=np.inf)), MPI.MIN))

        with solver.switched(snes_type="semismooth", project_step=project, max_it=300):
            solver.snes.setMonitor(record)
            h = solver.solve()
        assert h.complementarity <= 1e-9
        solutions.append(u.x.array.copy())
        lowest.append(min(low))
        solver.destroy()
    assert lowest[0] < -1e-3  # the test can fail: unprojected iterates go below
    assert lowest[1] >= -1e-14
    assert np.allclose(solutions[0], solutions[1], rtol=0, atol=1e-10)


def test_kept_factorisation_gives_the_same_solution_with_fewer_factorisations():
    """factor_reuse_its: GMRES preconditioned by the first factorisation across the
    Newton steps and into a second solve (a moved obstacle, as in continuation)."""
    PETSc.Log.begin()
    opts = SNESOptions(snes_type="semismooth", factor_reuse_its=20)
    s1, u1 = _string_on_obstacle(MPI.COMM_WORLD)
    s2, u2 = _string_on_obstacle(MPI.COMM_WORLD, options=opts)
    s1.solve()
    n0 = _lu_count()
    h = s2.solve()
    assert s2.snes.getKSP().getType() == "gmres"
    assert h.newton_iterations >= 2 and h.complementarity <= 1e-9
    assert np.allclose(u1.x.array, u2.x.array, atol=1e-10)
    # one factorisation, plus one per rebuild after a slow linear solve
    assert _lu_count() - n0 == 1 + s2.factor_rebuilds < h.newton_iterations + 1
    for s in (s1, s2):  # a higher obstacle: both solve again from their solution
        lower = s.xl.getArray(readonly=False)
        lower[np.isfinite(lower)] += 0.01
        del lower
    s1.solve()
    n1, r1 = _lu_count(), s2.factor_rebuilds
    h = s2.solve()
    assert h.complementarity <= 1e-9
    # the kept factorisation carries over: a new one only after a slow linear solve
    assert _lu_count() - n1 == s2.factor_rebuilds - r1 < h.newton_iterations
    assert np.allclose(u1.x.array, u2.x.array, atol=1e-10)
    s1.destroy()
    s2.destroy()


def test_kept_factorisation_is_refused_where_the_pattern_changes():
    for kind, solve in (("vinewtonrsls", "submatrix"), ("vinewtonssls", "full_pattern")):
        with pytest.raises(ParameterError, match="factor_reuse_its = 5 needs a fixed matrix pat"):
            SNESOptions(snes_type=kind, vi_linear_solve=solve, factor_reuse_its=5)
    SNESOptions(snes_type="vinewtonrsls", factor_reuse_its=5)  # the full pattern keeps one


def test_reduced_space_vi_keeps_the_full_pattern_factorisation_across_steps_and_solves():
    """``vinewtonrsls`` with ``vi_linear_solve = "full_pattern"`` and ``factor_reuse_its``:
    GMRES on the reduced system, preconditioned by a kept LU of the full pattern
    (possibly of another active set), made afresh only after a slow linear solve.
    On a continuation in the load of the loaded string (the contact set grows from
    solve to solve) it takes the same Newton steps to the same solutions as a
    factorisation every step, with far fewer factorisations (1 and 2 ranks)."""
    PETSc.Log.begin()
    comm = MPI.COMM_WORLD
    runs = {}
    for k in (0, 8):
        opts = SNESOptions(factor_reuse_its=k, rtol=1e-12)
        solver, u, _psi, load = _loaded_string_on_obstacle(comm, 2.0, options=opts)
        n0, steps, sols, its = _numeric_factorisations(), [], [], []
        for value in (2.0, 2.2, 2.4, 2.6, 3.0):
            load.value = value
            h = solver.solve()
            assert h.complementarity <= 1e-9
            steps.append(h.newton_iterations)
            its += h.linear_iterations
            sols.append(u.x.array.copy())
        runs[k] = (steps, sols, _numeric_factorisations() - n0, its)
        assert solver.snes.getKSP().getType() == ("gmres" if k else "preonly")
        assert solver._full_lu.factorisations == runs[k][2]
        solver.destroy()
    (steps0, sols0, lu0, _), (steps8, sols8, lu8, its8) = runs[0], runs[8]
    assert sum(steps0) >= 25  # the contact set moves over many steps
    assert steps8 == steps0
    for a, b in zip(sols0, sols8, strict=True):
        assert np.allclose(a, b, rtol=0, atol=1e-12)
    assert lu0 == sum(steps0)  # one factorisation per Newton step
    # a new factorisation only after a linear solve of more than 8 GMRES iterations
    assert lu8 == 1 + sum(1 for n in its8[:-1] if n > 8) < lu0 / 5


def test_solver_session_reaches_every_solver_built_inside_it():
    """The study seam: a solver built inside ``solver_session`` takes its fields
    (the fixed-pattern VI with a kept factorisation) and solves to the reduced-space
    VI's solution; outside the block solvers keep their own; a switch to a
    reduced-space type drops the kept factorisation; bad fields are refused."""
    ref, u_ref = _string_on_obstacle(MPI.COMM_WORLD)
    ref.solve()
    with solver_session(snes_type="semismooth", factor_reuse_its=20):
        s, u = _string_on_obstacle(MPI.COMM_WORLD)
    assert (s.options.snes_type, s.options.factor_reuse_its) == ("semismooth", 20)
    h = s.solve()
    assert s.snes.getKSP().getType() == "gmres" and h.complementarity <= 1e-9
    assert np.allclose(u.x.array, u_ref.x.array, atol=1e-10)
    assert with_snes_type(s.options, "vinewtonrsls").factor_reuse_its == 20  # full pattern
    assert with_snes_type(s.options, "vinewtonssls").factor_reuse_its == 0
    s.set_snes_type("vinewtonssls")
    assert s.options.factor_reuse_its == 0
    other, _ = _string_on_obstacle(MPI.COMM_WORLD)
    assert other.options.snes_type == "vinewtonrsls" and other.options.factor_reuse_its == 0
    with pytest.raises(ParameterError, match="factor_reuse_its"):
        with solver_session(factor_reuse_its=-1):
            pass
    for solver in (ref, s, other):
        solver.destroy()


def test_bounds_on_a_subspace_of_a_mixed_space():
    mesh = dolfinx.mesh.create_unit_interval(MPI.COMM_WORLD, 8)
    import basix.ufl

    el = basix.ufl.element("Lagrange", mesh.basix_cell(), 1)
    W = dolfinx.fem.functionspace(mesh, basix.ufl.mixed_element([el, el]))
    lo = bounds_function(W, 0.0, sub=1)
    _, d0 = W.sub(0).collapse()
    _, d1 = W.sub(1).collapse()
    assert np.all(np.isnan(lo.x.array[d0])) and np.all(lo.x.array[d1] == 0.0)


def test_same_solution_on_one_and_all_ranks():
    """The distributed solve equals a serial solve (to solver tolerance)."""
    sw, uw = _string_on_obstacle(MPI.COMM_WORLD, n=64)
    sw.solve()
    ss, us = _string_on_obstacle(MPI.COMM_SELF, n=64)
    ss.solve()
    Vw = uw.function_space
    n = Vw.dofmap.index_map.size_local
    xw = Vw.tabulate_dof_coordinates()[:n, 0]
    xs = us.function_space.tabulate_dof_coordinates()[:, 0]
    order = np.argsort(xs)
    vs = np.interp(xw, xs[order], us.x.array[order])
    assert np.allclose(uw.x.array[:n], vs, atol=1e-11)
    sw.destroy()
    ss.destroy()


def test_mpc_assembly_without_constraints_is_the_plain_assembly():
    """The dolfinx_mpc strategy with empty constraints assembles exactly the plain
    Jacobian and residual, single field and blocked (field + real unknown)."""
    import dolfinx_mpc

    from dolfinx_seal.errors import ParameterError
    from dolfinx_seal.solvers import MPCAssembly

    comm = MPI.COMM_WORLD
    mesh = dolfinx.mesh.create_unit_square(comm, 6, 6)
    V = dolfinx.fem.functionspace(mesh, ("Lagrange", 2))
    R = scifem.create_real_functionspace(mesh)
    x = ufl.SpatialCoordinate(mesh)
    dofs = dolfinx.fem.locate_dofs_geometrical(V, lambda x: np.isclose(x[0], 0.0))
    bc = dolfinx.fem.dirichletbc(0.25, dofs, V)

    def build(assembly, blocked):
        mpc = dolfinx_mpc.MultiPointConstraint(V)
        mpc.finalize()
        u = dolfinx.fem.Function(mpc.function_space if assembly else V)
        u.interpolate(lambda x: x[0] * x[1])
        v = ufl.TestFunction(V)
        F = (1 + u**2) * ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx - x[1] * v * ufl.dx
        if not blocked:
            asm = MPCAssembly(mpc) if assembly else None
            return NonlinearSolver(F, u, [bc], assembly=asm)
        lam, mu = dolfinx.fem.Function(R), ufl.TestFunction(R)
        lam.x.array[:] = 0.5
        asm = MPCAssembly([mpc, None]) if assembly else None
        F = F + lam * v * ufl.dx
        return NonlinearSolver([F, u * mu * ufl.dx], [u, lam], [bc], assembly=asm)

    for blocked in (False, True):
        s_plain, s_mpc = build(False, blocked), build(True, blocked)
        for s in (s_plain, s_mpc):
            s._from_functions(s.x)
            s._jacobian(s.snes, s.x, s.A, s.A)
            s._residual(s.snes, s.x, s.b)
        D = s_mpc.A.copy()
        D.axpy(-1.0, s_plain.A, structure=PETSc.Mat.Structure.DIFFERENT)
        assert D.norm() <= 1e-14 * s_plain.A.norm()
        assert (s_mpc.b - s_plain.b).norm() <= 1e-14 * s_plain.b.norm()
        assert np.array_equal(s_mpc.x.array, s_plain.x.array)
        D.destroy()
        s_plain.destroy()
        s_mpc.destroy()
    mpc = dolfinx_mpc.MultiPointConstraint(V)
    mpc.finalize()
    u, lam = dolfinx.fem.Function(mpc.function_space), dolfinx.fem.Function(R)
    v, mu = ufl.TestFunction(V), ufl.TestFunction(R)
    with pytest.raises(ParameterError, match="one constraint"):
        NonlinearSolver([u * v * ufl.dx, lam * mu * ufl.dx], [u, lam], assembly=MPCAssembly(mpc))


def test_verbose_logs_one_line_per_newton_step(caplog):
    """``-v`` (debug logging) shows each Newton step with its residual norm."""
    solver, _, _ = _nonlinear_poisson(MPI.COMM_WORLD, n=8)
    with caplog.at_level("DEBUG", logger="dolfinx_seal.newton"):
        h = solver.solve()
    lines = [r.getMessage() for r in caplog.records if r.name == "dolfinx_seal.newton"]
    assert len(lines) == len(h.residual_norms) >= 3
    assert lines[0].endswith(f"Newton 0: |F| = {h.residual_norms[0]:.3e}")
    solver.destroy()


def test_destroy_removes_the_options_it_set():
    """A solver's default options live under its own prefix in PETSc's global options
    database; destroy() takes them out again (a sweep that builds a solver per point
    would otherwise grow the database without bound, bench/soak.py)."""
    before = set(PETSc.Options().getAll())
    solver, _ = _string_on_obstacle(MPI.COMM_WORLD, n=20)
    solver.solve()
    added = set(PETSc.Options().getAll()) - before
    assert any(k.startswith(solver.prefix) for k in added)
    solver.destroy()
    assert set(PETSc.Options().getAll()) == before


def test_factor_memory_is_the_mumps_factorisation_the_solver_holds():
    """``factor_memory_mb`` reads the factor the solver holds (and
    ``peak_factor_memory_mb`` keeps it): none before a solve; after one, MUMPS's
    largest rank <= total <= ranks x largest (INFOG(22) sums the ranks' whole MB,
    INFOG(21) is their largest), at least the factor's own entries (INFOG(29), 8
    bytes each), larger on a finer mesh; and the same through the full-pattern work
    matrix of a VI as through PETSc's LU."""
    comm = MPI.COMM_WORLD
    sizes = {}
    for n in (24, 96):
        solver, _, _ = _nonlinear_poisson(comm, n=n)
        assert solver.factor_memory_mb() is None
        assert solver.peak_factor_memory_mb == (0.0, 0.0)
        solver.solve()
        biggest, total = solver.factor_memory_mb()
        assert solver.peak_factor_memory_mb == (biggest, total)
        F = solver.snes.getKSP().getPC().getFactorMatrix()
        entries = F.getMumpsInfog(29)  # negative: millions of entries
        entries = -1e6 * entries if entries < 0 else entries
        assert 0 < biggest <= total <= comm.size * biggest
        assert total + 1.0 >= 8.0 * entries / 1e6  # whole MB
        sizes[n] = total
        solver.destroy()
    assert sizes[96] > sizes[24]
    for mode in ("submatrix", "full_pattern"):
        solver, _ = _string_on_obstacle(comm, options=SNESOptions(vi_linear_solve=mode))
        solver.solve()
        held = solver.factor_memory_mb()
        assert held is not None and 0 <= held[0] <= held[1]  # 200 unknowns: below 1 MB
        solver.destroy()
