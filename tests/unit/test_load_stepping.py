"""Load stepping's Newton rules (no FEM): ``SteppingOptions.max_newton`` and
``stall_steps`` reach every solve of a ramp and are restored after it."""

from __future__ import annotations

import pytest

from dolfinx_seal.errors import ParameterError, SolveHistory, SolverError
from dolfinx_seal.solid.problem import SolidContactProblem, SteppingOptions
from dolfinx_seal.solvers import NonlinearSolver


class _SNES:
    def __init__(self) -> None:
        self.max_it = 25

    def getTolerances(self) -> tuple[float, float, float, int]:
        return (1e-9, 1e-12, 1e-12, self.max_it)

    def setTolerances(self, max_it: int) -> None:
        self.max_it = max_it


class _Solver:
    """Records the Newton rules each solve runs under; a step longer than ``reach``
    from the last converged fraction fails (as a stall, when one is asked for)."""

    newton_limit = NonlinearSolver.newton_limit  # the real one, on the fake SNES

    def __init__(self, prob: _Problem, reach: float) -> None:
        self.prob, self.reach = prob, reach
        self._snes = _SNES()
        self._stall_steps = 0
        self.seen: list[tuple[int, int]] = []  # (max_it, stall_steps) of every solve
        self.spent = 0  # Newton steps of the failed solves

    def solve(self, where: str = "") -> SolveHistory:
        p = self.prob
        self.seen.append((self._snes.max_it, self._stall_steps))
        if p.t - p.sol > self.reach:
            # a stuck step: 1 % less residual a step, until the stall rule or the limit
            self.spent += self._stall_steps or self._snes.max_it
            raise SolverError("DIVERGED", where=where)
        p.sol = p.t
        h = SolveHistory()
        h.residual_norms = [1.0, 1e-3, 1e-10]
        return h


class _Problem:
    name = "fake"
    ramp = SolidContactProblem.ramp
    _drop_load_tangent = SolidContactProblem._drop_load_tangent
    _load_tangent = None

    def __init__(self, reach: float) -> None:
        self.t = self.sol = 0.0
        self.steps: list = []
        self.solver = _Solver(self, reach)

    def set_fraction(self, t: float) -> None:
        self.t = t

    def state(self) -> list[float]:
        return [self.sol]

    def restore(self, state: list[float]) -> None:
        self.sol = state[0]


def test_a_ramp_solves_under_its_stall_rule_and_restores_it():
    prob = _Problem(reach=0.3)
    prob.ramp(SteppingOptions(first=0.5, max_newton=12, stall_steps=3))
    assert prob.sol == 1.0
    assert prob.solver.seen and all(s == (12, 3) for s in prob.solver.seen)
    # 0.5 fails, then 0.25 ...: every failed try stopped at the stall rule's 3 steps
    failed = len(prob.solver.seen) - len(prob.steps)
    assert failed > 0 and prob.solver.spent == 3 * failed
    assert (prob.solver._snes.max_it, prob.solver._stall_steps) == (25, 0)


def test_without_the_rules_a_failed_step_runs_to_the_solver_limit():
    prob = _Problem(reach=0.3)
    prob.ramp(SteppingOptions(first=0.5))
    failed = len(prob.solver.seen) - len(prob.steps)
    assert failed > 0 and prob.solver.spent == 25 * failed
    assert all(s == (25, 0) for s in prob.solver.seen)


def test_bad_stall_steps_names_the_parameter():
    with pytest.raises(ParameterError, match="stall_steps"):
        SteppingOptions(stall_steps=-1)
