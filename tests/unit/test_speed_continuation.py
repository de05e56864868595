"""Speed continuation bookkeeping (no FEM): failed targets are recorded, the sweep goes
on from the last good state, finished points are never lost."""

from __future__ import annotations

import math

import pytest

from dolfinx_seal.coupled.continuation import SpeedStepping, order_speeds, speed_sweep
from dolfinx_seal.errors import ParameterError, SolveHistory, SolverError
from dolfinx_seal.solvers import NonlinearSolver


class _Speed:
    def __init__(self, v: float) -> None:
        self.value = v


class _Film:
    def __init__(self, v: float) -> None:
        self.speed = _Speed(v)

    def set_speed(self, v: float) -> None:
        self.speed.value = v


class _SNES:
    """The Newton limit of the fake solver (PETSc's getTolerances/setTolerances)."""

    def __init__(self) -> None:
        self.max_it = 60

    def getTolerances(self) -> tuple[float, float, float, int]:
        return (1e-11, 1e-50, 1e-8, self.max_it)

    def setTolerances(self, max_it: int) -> None:
        self.max_it = max_it


class _Solver:
    """Converges (in 2 + 2 jump steps, jump in decades) unless the speed lies in a
    forbidden band, jumps too far, or the Newton limit is lower."""

    newton_limit = NonlinearSolver.newton_limit  # the real one, on the fake SNES

    def __init__(self, prob: _Problem) -> None:
        self.prob = prob
        self.snes = self._snes = _SNES()
        self._stall_steps = 0  # newton_limit's stall rule (only recorded here)
        self.limits: list[int] = []  # the Newton limit of every solve

    def solve(self, where: str = "") -> SolveHistory:
        p = self.prob
        v = p.film.speed.value
        jump = abs(math.log10(v / p.sol[0]))
        self.limits.append(self.snes.max_it)
        if 2 + 2 * jump > self.snes.max_it:
            p.sol = [float("nan")]
            raise SolverError("DIVERGED_MAX_IT", where=where)
        if p.bad[0] <= v <= p.bad[1] or jump > p.max_jump:
            p.sol = [float("nan")]  # a failed solve leaves garbage behind
            raise SolverError("diverged", where=where)
        p.sol = [v]
        h = SolveHistory()
        h.residual_norms = [1.0, 0.1, 1e-5, 1e-12]
        return h


class _Problem:
    name = "fake"

    def __init__(self, v0: float, bad: tuple[float, float], max_jump: float = 10.0) -> None:
        self.film = _Film(v0)
        self.sol = [v0]  # the "solution" remembers the speed it was solved at
        self.bad, self.max_jump = bad, max_jump
        self.solver = _Solver(self)

    def state(self) -> list[float]:
        return list(self.sol)

    def restore(self, s: list[float]) -> None:
        self.sol = list(s)


def test_unreachable_target_is_recorded_and_the_sweep_goes_on():
    prob = _Problem(1e-4, bad=(0.9e-2, 1.1e-2))
    done = []
    recs = speed_sweep(prob, [1e-3, 1e-2, 1e-1], lambda v, r: done.append(v), lambda: {},
                       SpeedStepping(predictor=False, film_presolve=False))  # fmt: skip
    assert [r.converged for r in recs] == [True, False, True]
    assert done == [1e-3, 1e-1]  # the finished points, in order
    assert "diverged" in recs[1].error
    assert prob.sol == [1e-1]  # restored after each failure, then went on


def test_large_jumps_are_cut_into_steps():
    prob = _Problem(1e-6, bad=(1.0, 1.0), max_jump=0.3)
    recs = speed_sweep(
        prob,
        [1e-2],
        lambda v, r: None,
        lambda: {},
        SpeedStepping(predictor=False, film_presolve=False),
    )
    assert recs[0].converged and recs[0].steps >= math.ceil(4 / 0.3)  # <= 0.3 decades a step
    assert all(0 < s < 1e-2 for s in recs[0].intermediate)


def test_a_continuation_step_stops_at_its_own_newton_limit():
    # 2 steps plus 2 per decade: with max_newton = 3 only steps of half a decade or less
    # decade converge (the walk cuts the others); the solver's own limit is restored
    prob = _Problem(1e-4, bad=(1.0, 1.0))
    st = SpeedStepping(predictor=False, film_presolve=False, max_newton=3, max_decades=1.0)
    recs = speed_sweep(prob, [1e-2], lambda v, r: None, lambda: {}, st)
    assert recs[0].converged and recs[0].steps > 2  # 2 steps of a decade would do without it
    assert set(prob.solver.limits) == {3} and prob.solver.snes.max_it == 60
    prob = _Problem(1e-4, bad=(1.0, 1.0))
    st = SpeedStepping(predictor=False, film_presolve=False, max_decades=1.0)
    recs = speed_sweep(prob, [1e-2], lambda v, r: None, lambda: {}, st)
    assert recs[0].converged and recs[0].steps == 2 and set(prob.solver.limits) == {60}
    with pytest.raises(ParameterError, match="max_newton"):
        SpeedStepping(max_newton=-1)


def test_order_and_bad_speed():
    assert order_speeds([3, 1, 2], "up") == [1, 2, 3]
    assert order_speeds([3, 1, 2], "up-down") == [1, 2, 3, 2, 1]
    assert order_speeds([3, 1, 2], "down") == [3, 2, 1]
    with pytest.raises(ParameterError, match="speed"):
        speed_sweep(_Problem(1.0, (0, 0)), [-1.0], lambda v, r: None, dict)
    with pytest.raises(ParameterError, match="max_decades"):
        SpeedStepping(max_decades=0.0)


def test_sweep_stops_after_consecutive_failures_and_keeps_its_points():
    # walking down into an unreachable band: 1e-2 converges, 1e-3 and 1e-4 fail, 1e-5
    # and 1e-6 are not attempted after max_failures = 2
    prob = _Problem(1.0, bad=(1e-7, 5e-3))
    done = []
    calls = []
    solve = prob.solver.solve

    def counted(where: str = "") -> SolveHistory:
        calls.append(prob.film.speed.value)
        return solve(where)

    prob.solver.solve = counted
    targets = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6]
    recs = speed_sweep(prob, targets, lambda v, r: done.append(v), dict,
                       SpeedStepping(predictor=False, max_failures=2, film_presolve=False))  # fmt: skip
    assert [r.converged for r in recs] == [True, False, False, False, False]
    assert [r.speed for r in recs] == targets
    assert done == [1e-2]
    assert all("not attempted" in r.error for r in recs[3:])
    assert min(calls) > 1e-5  # nothing below the second failed target was solved
    # the last good (intermediate) state is kept
    assert prob.sol == [prob.film.speed.value] and 5e-3 < prob.sol[0] < 1e-2
    with pytest.raises(ParameterError, match="max_failures"):
        SpeedStepping(max_failures=-1)


class _SpoilingPresolver:
    """A film presolve that leaves a state the coupled solve cannot start from
    (as on the S1 ball): the fake solver fails on the far jump it makes."""

    def __init__(self, prob: _Problem) -> None:
        self.prob, self.calls, self.destroyed = prob, 0, False

    def solve(self, where: str) -> int:
        self.calls += 1
        self.prob.sol = [1e-30]
        return 7

    def destroy(self) -> None:
        self.destroyed = True


def test_a_step_spoiled_by_the_film_presolve_is_retried_without_it(monkeypatch):
    from dolfinx_seal.coupled import continuation

    made = []
    monkeypatch.setattr(
        continuation, "FilmPresolver", lambda p: made.append(_SpoilingPresolver(p)) or made[-1]
    )
    prob = _Problem(1e-3, bad=(1.0, 1.0), max_jump=1.0)
    recs = speed_sweep(prob, [1e-2, 1e-1], lambda v, r: None, dict, SpeedStepping(predictor=False))
    assert [r.converged for r in recs] == [True, True]
    # two half-decade steps per decade and none halved: every retry succeeded
    assert [r.steps for r in recs] == [2, 2]
    assert [r.film_iterations for r in recs] == [14, 14]
    assert made[0].calls == 4 and made[0].destroyed
    assert prob.sol == [1e-1]


def test_a_spent_time_budget_stops_the_walk_before_its_next_step(monkeypatch):
    """``stepping.time_budget``: checked before every continuation step, not only
    before each target, so a walk that creeps (the ball's failed steps cost 60
    Newton steps, minutes each) stops once the budget is spent: the target under
    way is recorded as stopped where it got to, the later ones as not attempted.
    A clock that moves 1 s per solve, a budget of 2.5 s: three steps of half a
    decade from 1e-4 m/s, then the stop."""
    from mpi4py import MPI

    from dolfinx_seal.coupled import continuation

    clock = [0.0]
    monkeypatch.setattr(continuation.time, "perf_counter", lambda: clock[0])
    prob = _Problem(1e-4, bad=(1.0, 1.0))
    prob.mesh = type("Mesh", (), {"comm": MPI.COMM_SELF})()
    solve = prob.solver.solve

    def timed(where: str = "") -> SolveHistory:
        clock[0] += 1.0
        return solve(where)

    prob.solver.solve = timed
    done: list[float] = []
    st = SpeedStepping(predictor=False, film_presolve=False, max_decades=0.5, grow=1.0,
                       time_budget=2.5)  # fmt: skip
    recs = speed_sweep(prob, [1e-1, 1.0], lambda v, r: done.append(v), dict, st)
    assert [r.converged for r in recs] == [False, False] and done == []
    reached = 10 ** (-4 + 3 * 0.5)
    assert prob.film.speed.value == pytest.approx(reached) and prob.sol == [prob.film.speed.value]
    assert recs[0].error == f"stopped at {reached:.4g} m/s: the time budget of 2.5 s was spent"
    assert recs[1].error == "not attempted: the time budget of 2.5 s was spent"
    assert clock[0] == 3.0  # no solve after the budget was spent
