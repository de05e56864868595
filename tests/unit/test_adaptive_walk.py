"""The one adaptive continuation loop (solvers/adaptive.py) on scalar problems.

A continuation of the root of ``x**3 + x = lam`` by a Newton that gives up
after a few steps: the walk must cut its step where Newton fails from the last
state, grow it where Newton is easy, end on the exact root, and report every
attempt.  A solve that can never succeed must stop with the state of the last
accepted step.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from dolfinx_seal.errors import ParameterError, SolveHistory, SolverError
from dolfinx_seal.solvers.adaptive import AdaptiveWalk, StepControl, secant


class CubicRoot:
    """Newton for ``x**3 + x = lam`` from the current ``x``, at most ``max_it`` steps."""

    def __init__(self, max_it: int) -> None:
        self.x = np.zeros(1)
        self.lam = 0.0
        self.max_it = max_it
        self.solves: list[float] = []

    def apply(self, lam: float) -> None:
        self.lam = lam

    def solve(self, lam: float) -> int:
        self.solves.append(lam)
        x = float(self.x[0])
        for it in range(1, self.max_it + 1):
            r = x**3 + x - self.lam
            x -= r / (3 * x * x + 1)
            if abs(x**3 + x - self.lam) < 1e-12 * max(1.0, abs(self.lam)):
                self.x[0] = x
                return it
        self.x[0] = np.nan  # a failed solve leaves garbage: the walk must restore
        raise SolverError("Newton did not converge", where=f"lam = {lam:g}",
                          history=SolveHistory())  # fmt: skip

    def save(self) -> list[np.ndarray]:
        return [self.x.copy()]

    def restore(self, state: list[np.ndarray]) -> None:
        self.x[:] = state[0]


def _walker(prob: CubicRoot, control: StepControl, **kw) -> AdaptiveWalk:
    return AdaptiveWalk(control, prob.apply, prob.solve, prob.save, prob.restore, **kw)


def test_walk_reaches_the_root_and_adapts_its_step():
    prob = CubicRoot(max_it=4)
    control = StepControl(first=50.0, grow=2.0, easy=3, cut=0.5, min_step=1e-3)
    walk = _walker(prob, control)
    res = walk.walk(0.0, 1000.0)
    assert res.converged and res.reached == 1000.0
    x = prob.x[0]
    assert x**3 + x == pytest.approx(1000.0, rel=1e-12)
    failed = [a for a in res.attempts if not a.accepted]
    assert failed, "a first step of 50 from x = 0 needs more than 4 Newton steps"
    # after each failure the next try is half as far from the same start
    for i, a in enumerate(res.attempts[:-1]):
        if not a.accepted:
            start = max([0.0] + [b.value for b in res.attempts[:i] if b.accepted])
            nxt = res.attempts[i + 1]
            assert nxt.value - start == pytest.approx(0.5 * (a.value - start), rel=1e-12)
    assert res.steps == len(res.accepted) and res.newton_iterations == sum(
        a.newton_iterations for a in res.accepted
    )
    assert all(math.isfinite(v) for v in prob.x)


def test_growth_is_capped_and_every_step_counts_as_easy_without_easy():
    prob = CubicRoot(max_it=50)
    walk = _walker(prob, StepControl(first=0.1, grow=2.0, easy=None, max_step=0.4))
    res = walk.walk(0.0, 2.0)
    steps = np.diff([0.0] + [a.value for a in res.accepted])
    assert steps[:3] == pytest.approx([0.1, 0.2, 0.4], rel=1e-12)
    assert np.all(steps <= 0.4 + 1e-12)


def test_load_stepping_options_cap_the_increment():
    """``SteppingOptions.max_increment`` is the walk's ``max_step`` (the load
    stepping of :meth:`~dolfinx_seal.solid.problem.SolidContactProblem.ramp`)."""
    from dolfinx_seal.solid.problem import SteppingOptions

    prob = CubicRoot(max_it=50)
    control = SteppingOptions(first=0.1, grow=2.0, easy=50, max_increment=0.25).control(2.0)
    res = _walker(prob, control).walk(0.0, 2.0)
    steps = np.diff([0.0] + [a.value for a in res.accepted])
    assert res.converged and steps[:3] == pytest.approx([0.1, 0.2, 0.25], rel=1e-12)
    assert np.all(steps <= 0.25 + 1e-12) and len(steps) == 9
    assert SteppingOptions().control(1.0).max_step is None
    with pytest.raises(ParameterError, match="max_increment"):
        SteppingOptions(max_increment=0.0)


def test_a_stall_keeps_the_last_accepted_state_and_resets_the_step():
    prob = CubicRoot(max_it=30)
    control = StepControl(first=0.5, cut=0.5, min_step=0.05, reset_step=0.5)
    walk = _walker(prob, control)

    def solve(lam: float) -> int:
        if lam > 1.0:  # a wall: nothing beyond lam = 1 converges
            raise SolverError("wall", where=f"lam = {lam:g}", history=SolveHistory())
        return CubicRoot.solve(prob, lam)

    walk.solve = solve
    res = walk.walk(0.0, 2.0)
    assert not res.converged
    assert res.reached == pytest.approx(1.0, abs=0.05)
    x = prob.x[0]
    assert x**3 + x == pytest.approx(res.reached, rel=1e-12)  # restored, not garbage
    assert prob.lam == res.reached
    assert "below" in res.error and res.last_error is not None
    assert walk.step == 0.5  # reset for the next walk


def test_a_failed_step_capped_at_the_target_is_never_tried_again():
    """A step shorter than the walk's step (the target is closer) that fails is cut
    from its own length: cutting the walk's step instead left it longer than the
    distance, so the same target was solved again, as the same failure (the S1 ball
    walking 5.6 -> 3.2 mm/s: a 0.24-decade step to the target after a 0.5-decade
    step, failed twice at 0.0032 m/s before a shorter step was tried)."""
    prob = CubicRoot(max_it=30)
    walk = _walker(prob, StepControl(first=0.5, cut=0.5, min_step=0.01))

    def solve(lam: float) -> int:
        if lam - prob.lam_accepted > 0.1:  # only steps of at most 0.1 converge
            raise SolverError("too far", where=f"lam = {lam:g}", history=SolveHistory())
        its = CubicRoot.solve(prob, lam)
        prob.lam_accepted = lam
        return its

    prob.lam_accepted = 0.0
    walk.solve = solve
    res = walk.walk(0.0, 0.3)  # 0.3 < 0.5: the first try is the target itself
    assert res.converged
    tried = [a.value for a in res.attempts]
    assert tried[0] == 0.3 and tried[1] == pytest.approx(0.15, rel=1e-12)
    failed = [a.value for a in res.attempts if not a.accepted]
    assert len(failed) == len(set(failed)), tried  # no failed value is tried twice


def test_max_attempts_stops_the_walk():
    prob = CubicRoot(max_it=30)
    walk = _walker(prob, StepControl(first=0.01, grow=1.0, max_attempts=5))
    res = walk.walk(0.0, 1.0)
    assert not res.converged and len(res.attempts) == 5 and "more than 5" in res.error


def test_secant_predictor_and_log_coordinate():
    """In log10 |v|, negative speeds walk by decades too; the predictor gets the
    last accepted states (the start alone at the first step, then two) and the
    coordinate of the step."""
    seen: list[tuple[float, ...]] = []
    state = [np.array([0.0])]

    def predictor(history, c):
        seen.append((*(ci for ci, _ in history), c))
        if len(history) == 2:
            state[0][:] = secant(history, c)[0]

    def solve(v: float) -> int:
        state[0][:] = math.log10(abs(v))  # the "solution" is linear in the coordinate
        return 1

    walk = AdaptiveWalk(
        StepControl(first=1.0, grow=1.0), lambda v: None, solve,
        lambda: [state[0].copy()], lambda s: state[0].__setitem__(slice(None), s[0]),
        coordinate=AdaptiveWalk.log_speed(-1.0), predictor=predictor,
    )  # fmt: skip
    state[0][:] = 0.0
    res = walk.walk(-1.0, -1000.0)
    assert res.converged and [a.value for a in res.accepted] == pytest.approx(
        [-10.0, -100.0, -1000.0], rel=1e-12
    )
    # the first step from the start alone, 0 -> 1; then (0, 1) -> 2 and (1, 2) -> 3
    assert seen == [(0.0, 1.0), (0.0, 1.0, 2.0), (1.0, 2.0, 3.0)]


def test_bad_step_control_is_refused_with_its_name():
    with pytest.raises(ParameterError, match="cut"):
        StepControl(first=1.0, cut=1.0)
    with pytest.raises(ParameterError, match="first"):
        StepControl(first=0.0)


def test_a_stop_hook_ends_the_walk_at_the_last_accepted_state():
    """``walk(..., stop=...)`` (a spent time budget) is asked before every step:
    once it gives a reason the walk ends there, kept at its last accepted step,
    with the reason and ``stopped``; a walk whose hook never fires is unchanged."""
    prob = CubicRoot(max_it=50)
    control = StepControl(first=0.25, grow=1.0, easy=None)
    asked: list[int] = []

    def stop() -> str:
        asked.append(len(prob.solves))
        return "the time budget of 1 s was spent" if len(prob.solves) >= 2 else ""

    res = _walker(prob, control).walk(0.0, 1.0, stop=stop)
    assert not res.converged and res.stopped
    assert res.error == "the time budget of 1 s was spent"
    assert res.reached == pytest.approx(0.5, rel=1e-12) and len(prob.solves) == 2
    assert prob.x[0] ** 3 + prob.x[0] == pytest.approx(0.5, rel=1e-12)
    assert asked == [0, 1, 2]
    free = _walker(CubicRoot(max_it=50), control).walk(0.0, 1.0, stop=lambda: "")
    assert free.converged and not free.stopped and free.steps == 4
