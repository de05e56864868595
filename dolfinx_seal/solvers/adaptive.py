"""One adaptive continuation loop: load stepping, speed continuation, homotopies.

A parameter (a load fraction, a sliding speed, a homotopy weight) is walked from
its current value to a target in steps measured in a *coordinate* of the
parameter (the value itself, or log10 |speed|).  After each step:

* accepted: the step grows by :attr:`StepControl.grow` if it took at most
  :attr:`StepControl.easy` Newton steps (always, if ``easy`` is None), capped at
  :attr:`StepControl.max_step`;
* failed (a :class:`~dolfinx_seal.errors.SolverError`): the state and the
  parameter are restored to the last accepted step and the step is multiplied by
  :attr:`StepControl.cut`; below :attr:`StepControl.min_step` the walk stops.

A predictor (e.g. :func:`secant`) sets the starting state of each step from the
last two accepted states.  Every attempt is recorded (:class:`Attempt`), so a
failed walk says where it stalled and what was tried.  The walker keeps its step
and its history between walks (a sweep of several targets continues where the
last one ended).

The loop knows nothing of forms or meshes: the caller gives it ``apply`` (set
the parameter), ``solve`` (Newton from the current state, returns its steps or
raises), ``save`` and ``restore`` (copies of the unknowns).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from dolfinx_seal.errors import SolverError
from dolfinx_seal.mpi import get_logger
from dolfinx_seal.params import check_int_range, check_positive, check_range

#: A saved state: copies of the arrays of the unknowns.
State = Any
#: The last accepted (coordinate, state) pairs, oldest first (at most two).
History = list[tuple[float, State]]


@dataclass(frozen=True)
class StepControl:
    """How the step of an adaptive walk grows and shrinks (in the walk's coordinate).

    Attributes:
        first: First step.
        grow: Factor on the step after an easy accepted step (>= 1).
        easy: Newton steps counted as an easy step (None: every accepted step is easy).
        cut: Factor on the step after a failed step (0 < cut < 1).
        min_step: Smallest step: below it the walk stops.
        max_step: Largest step (None: no cap).
        max_attempts: Largest number of attempts, accepted and failed, in one walk
            (None: no limit).
        reset_step: Step after a walk that stopped (None: keep the last one).
        tolerance: Distance to the target below which it counts as reached.
    """

    first: float
    grow: float = 2.0
    easy: int | None = 6
    cut: float = 0.5
    min_step: float = 1e-4
    max_step: float | None = None
    max_attempts: int | None = None
    reset_step: float | None = None
    tolerance: float = 1e-12

    def __post_init__(self) -> None:
        check_positive("first", self.first)
        check_range("grow", self.grow, 1.0, 10.0)
        check_range("cut", self.cut, 0.0, 1.0, lo_open=True, hi_open=True)
        check_positive("min_step", self.min_step)
        if self.easy is not None:
            check_int_range("easy", self.easy, 1)
        if self.max_step is not None:
            check_positive("max_step", self.max_step)
        if self.max_attempts is not None:
            check_int_range("max_attempts", self.max_attempts, 1)


@dataclass
class Attempt:
    """One step of a walk: the parameter value tried and what came of it."""

    value: float
    accepted: bool
    newton_iterations: int = 0
    wall_time_s: float = 0.0
    error: str = ""


@dataclass
class WalkResult:
    """The outcome of one walk to a target.

    Attributes:
        target: The value aimed at.
        reached: The last accepted value (the state is left there).
        converged: Whether ``reached`` is the target.
        attempts: Every step tried, in order.
        error: Why the walk stopped (empty when converged).
        last_error: The :class:`SolverError` of the last failed attempt, if any.
        stopped: Whether the walk's ``stop`` hook ended it (``error`` says why).
    """

    target: float
    reached: float
    converged: bool
    attempts: list[Attempt] = field(default_factory=list)
    error: str = ""
    last_error: SolverError | None = None
    stopped: bool = False

    @property
    def accepted(self) -> list[Attempt]:
        return [a for a in self.attempts if a.accepted]

    @property
    def newton_iterations(self) -> int:
        """Newton steps of the accepted attempts."""
        return sum(a.newton_iterations for a in self.accepted)

    @property
    def steps(self) -> int:
        """Number of accepted steps."""
        return len(self.accepted)


def linear(value: float) -> float:
    """The identity coordinate (load fractions, homotopy weights)."""
    return float(value)


def log10_abs(value: float) -> float:
    """log10 |value|: the coordinate of a speed continuation (one sign per walk)."""
    return math.log10(abs(value))


def secant(history: History, coordinate: float) -> list[Any]:
    """The linear extrapolation, in the walk's coordinate, of the two states of
    ``history`` to ``coordinate`` (arrays combined element by element)."""
    (ca, sa), (cb, sb) = history
    r = (coordinate - cb) / (cb - ca)
    return [b + r * (b - a) for a, b in zip(sa, sb, strict=True)]


class TimeBudget:
    """A wall-time budget, started when made: :meth:`spent` gives the reason once it
    is spent (a ``stop`` hook of :meth:`AdaptiveWalk.walk`), decided on rank 0 of
    ``comm`` so that every rank takes the same branch.

    Args:
        seconds: The budget [s]; 0: none (never spent, ``comm`` not used).
        comm: The communicator of the ranks that must agree (None when ``seconds`` is 0).
    """

    def __init__(self, seconds: float, comm: Any = None) -> None:
        self.seconds = float(seconds or 0.0)
        self.comm = comm
        self.t0 = time.perf_counter()

    def spent(self) -> str:
        """``"the time budget of T s was spent"``, or ``""`` while it is not."""
        if not self.seconds:
            return ""
        late = self.comm.bcast(time.perf_counter() - self.t0 > self.seconds, root=0)
        return f"the time budget of {self.seconds:g} s was spent" if late else ""


class AdaptiveWalk:
    """An adaptive continuation in one parameter, kept between walks.

    Args:
        control: Step sizes.
        apply: Sets the parameter (``apply(value)``).
        solve: Solves from the current state at the applied value; returns the
            Newton steps or raises :class:`SolverError`.
        save, restore: Copy and reinstate the unknowns.
        coordinate: The coordinate the steps are measured in and its inverse
            (``(linear, linear)`` or ``(log10_abs, signed power of ten)``): see
            :meth:`log_speed`.
        predictor: ``predictor(history, coordinate)`` sets the start of a step
            from the last accepted states (one at the first step, then two; the
            current state is the last of them); None: start from the last one.
        on_accept: Called with the value and the Newton steps of each accepted step.
        name: Named in the log lines and errors.
    """

    def __init__(
        self,
        control: StepControl,
        apply: Callable[[float], None],
        solve: Callable[[float], int],
        save: Callable[[], State],
        restore: Callable[[State], None],
        *,
        coordinate: tuple[Callable[[float], float], Callable[[float], float]] = (linear, linear),
        predictor: Callable[[History, float], None] | None = None,
        on_accept: Callable[[float, int], None] | None = None,
        name: str = "continuation",
    ) -> None:
        self.control = control
        self.apply, self.solve, self.save, self.restore = apply, solve, save, restore
        self.to_coord, self.from_coord = coordinate
        self.predictor = predictor
        self.on_accept = on_accept
        self.name = name
        self.step = control.first
        self.history: History = []

    @staticmethod
    def log_speed(sign: float) -> tuple[Callable[[float], float], Callable[[float], float]]:
        """The coordinate log10 |v| of speeds of one ``sign``, with its inverse."""
        return log10_abs, lambda c: math.copysign(10.0**c, sign)

    def walk(
        self, start: float, target: float, stop: Callable[[], str] | None = None
    ) -> WalkResult:
        """Walk the parameter from ``start`` (the current, converged state) to ``target``.

        Returns the outcome; on a stop the state and the parameter are those of
        the last accepted step (``result.reached``).  Never raises for a failed
        step: the caller decides what a stop means (an error, a failed sweep point).
        ``stop``, asked before every step, ends the walk when it returns a reason
        (a spent time budget); it must give the same answer on every rank.
        """
        c = self.control
        log = get_logger()
        current = float(start)
        res = WalkResult(target=float(target), reached=current, converged=False)
        if not self.history or self.history[-1][0] != self.to_coord(current):
            self.history = [(self.to_coord(current), self.save())]
        goal = self.to_coord(target)
        while True:
            here = self.to_coord(current)
            dist = goal - here
            if abs(dist) < c.tolerance:
                res.converged = True
                return res
            if c.max_attempts is not None and len(res.attempts) >= c.max_attempts:
                res.error = f"more than {c.max_attempts} steps"
                return res
            why = stop() if stop is not None else ""
            if why:
                res.error, res.stopped = why, True
                return res
            c_try = goal if abs(dist) <= self.step else here + math.copysign(self.step, dist)
            v_try = float(target) if c_try == goal else self.from_coord(c_try)
            saved = self.save()
            t0 = time.perf_counter()
            self.apply(v_try)
            if self.predictor is not None:
                self.predictor(self.history, c_try)
            try:
                its = self.solve(v_try)
            except SolverError as e:
                self.restore(saved)
                self.apply(current)
                # cut the step that was tried: one capped at the target (shorter than
                # ``self.step``) cut from ``self.step`` could land on the same target
                # again and repeat the same failed solve
                self.step = min(self.step, abs(c_try - here)) * c.cut
                res.attempts.append(
                    Attempt(v_try, False, e.history.newton_iterations,
                            time.perf_counter() - t0, f"{e.what} ({e.where})")
                )  # fmt: skip
                res.last_error = e
                log.info("%s: step to %.6g failed (%s); step %.3g", self.name, v_try, e.what,
                         self.step)  # fmt: skip
                if self.step < c.min_step:
                    res.error = (
                        f"step {self.step:.2e} below {c.min_step:.1e} on the way from "
                        f"{current:.6g} to {target:.6g}: {e.what}"
                    )
                    if c.reset_step is not None:
                        self.step = c.reset_step
                    return res
                continue
            res.attempts.append(Attempt(v_try, True, its, time.perf_counter() - t0))
            current = v_try
            res.reached = current
            self.history = [self.history[-1], (c_try, self.save())]
            if self.on_accept is not None:
                self.on_accept(current, its)
            if c.easy is None or its <= c.easy:
                self.step *= c.grow
                if c.max_step is not None:
                    self.step = min(self.step, c.max_step)


def restore_arrays(functions: Sequence[Any], state: Sequence[Any]) -> None:
    """Copy the arrays of ``state`` into the ``x.array`` of ``functions``."""
    for f, arr in zip(functions, state, strict=True):
        f.x.array[:] = arr


__all__ = [
    "AdaptiveWalk",
    "Attempt",
    "StepControl",
    "TimeBudget",
    "WalkResult",
    "linear",
    "log10_abs",
    "restore_arrays",
    "secant",
]
